//! Agreement of the two solvers against frequency: where both solvers give the same periodic
//! motion, the relative difference of the orbits and the distance of their Floquet multipliers
//! (log scale), coloured by impact signature; below, the class of every frequency.

use crate::figures::plot::{err, legend, text, Figure};
use crate::study::plots::Agreement;
use crate::verdict::Class;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Differences below this are drawn at it (an exact zero has no place on a log axis).
const FLOOR: f64 = 1e-19;

fn class_colour(class: &Class) -> RGBColor {
    match class {
        Class::Agreement => RGBColor(0, 0, 0),
        Class::Coexistence => RGBColor(30, 90, 220),
        Class::Beyond(_) => RGBColor(230, 120, 0),
        Class::Contradiction(_) => RGBColor(220, 0, 0),
    }
}

fn class_row(class: &Class) -> f64 {
    match class {
        Class::Agreement => 3e-19,
        Class::Coexistence => 1e-18,
        Class::Beyond(_) => 3e-18,
        Class::Contradiction(_) => 1e-17,
    }
}

/// Colours of the signatures, in order of their first appearance.
const SIGNATURE_COLOURS: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
    RGBColor(120, 60, 160),
    RGBColor(90, 90, 90),
];

impl Figure for Agreement {
    fn name(&self) -> &str {
        "agreement"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 850)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let wmin = self.points.first().map_or(0.0, |p| p.omega);
        let wmax = self.points.last().map_or(1.0, |p| p.omega);
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Analytic vs event-driven steady state, scene '{}'",
                    self.scene_name
                ),
                text(28),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(90)
            .build_cartesian_2d(wmin..wmax, (FLOOR..1.0).log_scale())
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("base frequency ω (rad/s)")
            .y_desc("relative difference (orbit; Floquet multipliers)")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(text(18))
            .axis_desc_style(text(20))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(DashedLineSeries::new(
                vec![(wmin, self.tolerance), (wmax, self.tolerance)],
                8,
                5,
                RGBColor(120, 120, 120).stroke_width(2),
            ))
            .map_err(err)?
            .label(format!("match tolerance {:.0e}", self.tolerance))
            .legend(|(x, y)| {
                PathElement::new(
                    vec![(x, y), (x + 20, y)],
                    RGBColor(120, 120, 120).stroke_width(2),
                )
            });
        // The most frequent signatures get their own colour; the rest share the last.
        let mut counts: Vec<(String, usize)> = Vec::new();
        for p in self.points.iter().filter(|p| p.class == Class::Agreement) {
            let sig = p.signature.clone().unwrap_or_else(|| "linear".to_owned());
            match counts.iter_mut().find(|(k, _)| *k == sig) {
                Some((_, n)) => *n += 1,
                None => counts.push((sig, 1)),
            }
        }
        counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let named = SIGNATURE_COLOURS.len() - 1;
        let colour = |sig: &str| {
            counts
                .iter()
                .take(named)
                .position(|(s, _)| s == sig)
                .map_or(SIGNATURE_COLOURS[named], |k| SIGNATURE_COLOURS[k])
        };
        let agreeing: Vec<_> = self
            .points
            .iter()
            .filter(|p| p.class == Class::Agreement)
            .map(|p| (p, colour(p.signature.as_deref().unwrap_or("linear"))))
            .collect();
        chart
            .draw_series(agreeing.iter().filter_map(|(p, c)| {
                p.relative_difference
                    .map(|d| Circle::new((p.omega, d.max(FLOOR)), 4, c.filled()))
            }))
            .map_err(err)?
            .label("orbit difference (state, impact phases, base phase)")
            .legend(|(x, y)| Circle::new((x + 10, y), 4, BLACK.filled()));
        chart
            .draw_series(agreeing.iter().filter_map(|(p, c)| {
                p.multiplier_difference
                    .map(|d| TriangleMarker::new((p.omega, d.max(FLOOR)), 5, c.stroke_width(2)))
            }))
            .map_err(err)?
            .label("Floquet multiplier difference")
            .legend(|(x, y)| TriangleMarker::new((x + 10, y), 5, BLACK.stroke_width(2)));
        for (k, (sig, n)) in counts.iter().take(named).enumerate() {
            let c = SIGNATURE_COLOURS[k];
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(err)?
                .label(format!("signature {sig}: {n} points"))
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], c.filled()));
        }
        if counts.len() > named {
            let rest: usize = counts.iter().skip(named).map(|(_, n)| n).sum();
            let c = SIGNATURE_COLOURS[named];
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(err)?
                .label(format!(
                    "{} other signatures: {rest} points",
                    counts.len() - named
                ))
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], c.filled()));
        }
        let names = [
            (Class::Agreement, "class: agreement"),
            (
                Class::Coexistence,
                "class: coexistence (stable orbit holds; from rest elsewhere)",
            ),
            (
                Class::Beyond(String::new()),
                "class: beyond exact comparison (not periodic, sticking, no dissipation)",
            ),
            (Class::Contradiction(String::new()), "class: contradiction"),
        ];
        for (class, label) in names {
            let pts: Vec<(f64, f64)> = self
                .points
                .iter()
                .filter(|p| p.class.name() == class.name())
                .map(|p| (p.omega, class_row(&class)))
                .collect();
            let colour = class_colour(&class);
            chart
                .draw_series(pts.iter().map(|&(w, y)| {
                    Rectangle::new(
                        [(w - 0.004, y * 0.8), (w + 0.004, y * 1.25)],
                        colour.filled(),
                    )
                }))
                .map_err(err)?
                .label(format!("{label} ({})", pts.len()))
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 12, y + 5)], colour.filled())
                });
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight, 15)?;
        Ok(())
    }
}
