//! The paper's Figure 5 done completely: the linear curve, every branch found by continuation
//! (viable stretches: stable solid, unstable dashed), coloured by impact signature, the
//! bifurcation events marked, the simulated points from rest on top.

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::plots::FrequencyResponse;
use plotters::coord::Shift;
use plotters::prelude::*;

const T_MIN: f64 = -45.0;
const T_MAX: f64 = 35.0;

/// Colours of the signatures, in order of first appearance (colour-blind safe first).
const SIGNATURE_COLOURS: [RGBColor; 10] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
    RGBColor(120, 60, 160),
    RGBColor(160, 120, 40),
    RGBColor(40, 40, 160),
    RGBColor(90, 90, 90),
];

impl Figure for FrequencyResponse {
    fn name(&self) -> &str {
        "frequency-response"
    }

    fn size(&self) -> (u32, u32) {
        (1600, 950)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let wmin = self.linear.first().map_or(0.0, |p| p.0);
        let wmax = self.linear.last().map_or(4.0, |p| p.0);
        let clamp = |t: f64| t.clamp(T_MIN, T_MAX);
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Frequency response by continuation, scene '{}' (viable orbits: stable solid, unstable dashed)",
                    self.scene_name
                ),
                text(26),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d(wmin..wmax, T_MIN..T_MAX)
            .map_err(err)?;
        axes(
            &mut chart,
            "base frequency ω (rad/s)",
            "transmittance T (dB)",
            18,
        )?;
        let grey = RGBColor(110, 110, 110);
        chart
            .draw_series(LineSeries::new(
                self.linear.iter().map(|&(w, t)| (w, clamp(t))),
                grey.stroke_width(2),
            ))
            .map_err(err)?
            .label("linear (no stops)")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(2))
            });
        // The signatures with the most viable points get their own colour; the rest share grey.
        let mut counts: Vec<(&str, usize)> = Vec::new();
        for s in &self.stretches {
            match counts.iter_mut().find(|(k, _)| *k == s.signature) {
                Some((_, n)) => *n += s.points.len(),
                None => counts.push((&s.signature, s.points.len())),
            }
        }
        counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        let named = SIGNATURE_COLOURS.len() - 1;
        let signatures: Vec<&str> = counts.iter().take(named).map(|c| c.0).collect();
        let other = SIGNATURE_COLOURS[named];
        let colour = |sig: &str| {
            signatures
                .iter()
                .position(|s| *s == sig)
                .map_or(other, |k| SIGNATURE_COLOURS[k])
        };
        for s in &self.stretches {
            let c = colour(&s.signature);
            let points: Vec<(f64, f64)> = s.points.iter().map(|&(w, t)| (w, clamp(t))).collect();
            if s.stable {
                chart
                    .draw_series(LineSeries::new(points, c.stroke_width(3)))
                    .map_err(err)?;
            } else {
                chart
                    .draw_series(DashedLineSeries::new(points, 6, 5, c.stroke_width(2)))
                    .map_err(err)?;
            }
        }
        for sig in &signatures {
            let c = colour(sig);
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(err)?
                .label(format!("branch {sig}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(3))
                });
        }
        if counts.len() > signatures.len() {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(err)?
                .label(format!(
                    "{} other signatures",
                    counts.len() - signatures.len()
                ))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], other.stroke_width(3))
                });
        }
        let kinds = [
            ("fold", RGBColor(0, 0, 0)),
            ("branch-point", RGBColor(200, 0, 0)),
            ("period-doubling", RGBColor(150, 0, 150)),
            ("neimark-sacker", RGBColor(0, 120, 0)),
            ("grazing", RGBColor(220, 140, 0)),
            ("vanishing-impact", RGBColor(0, 150, 200)),
        ];
        for (kind, c) in kinds {
            let marks: Vec<(f64, f64)> = self
                .events
                .iter()
                .filter(|e| e.2 == kind)
                .map(|e| (e.0, clamp(e.1)))
                .collect();
            if marks.is_empty() {
                continue;
            }
            chart
                .draw_series(marks.iter().map(|&p| TriangleMarker::new(p, 5, c.filled())))
                .map_err(err)?
                .label(format!("{kind} ({})", marks.len()))
                .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 6, c.filled()));
        }
        chart
            .draw_series(
                self.simulated
                    .iter()
                    .map(|&(w, t, _)| Cross::new((w, clamp(t)), 4, BLACK.stroke_width(1))),
            )
            .map_err(err)?
            .label("simulated from rest (any motion)")
            .legend(|(x, y)| Cross::new((x + 10, y), 4, BLACK.stroke_width(1)));
        legend(&mut chart, SeriesLabelPosition::LowerLeft, 15)?;
        Ok(())
    }
}
