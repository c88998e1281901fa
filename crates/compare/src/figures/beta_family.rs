//! The two-impact family: the gap `Δ*(β)/u_g` that admits side-2 impacts `βT` after side-1
//! impacts, for a few frequencies, by verdict; Nigm and Shabana's non-viable band shaded; and
//! simulated confirmations (gap set to `Δ*(β)`, impact spacing measured).

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::plots::BetaFamily;
use plotters::coord::Shift;
use plotters::prelude::*;

const PALETTE: [RGBColor; 5] = [
    RGBColor(30, 90, 220),
    RGBColor(220, 60, 30),
    RGBColor(20, 150, 60),
    RGBColor(150, 40, 170),
    RGBColor(200, 140, 0),
];

impl Figure for BetaFamily {
    fn name(&self) -> &str {
        "beta-family"
    }

    fn size(&self) -> (u32, u32) {
        (1400, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let ymax = self
            .curves
            .iter()
            .flat_map(|(_, m)| m.iter().filter(|m| m.viable).map(|m| m.gap_ratio))
            .fold(1.0f64, f64::max)
            * 1.3;
        let ymax = ymax.min(20.0);
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Two-impact family Δ*(β)/u_g, scene '{}', e = {}",
                    self.scene_name, self.restitution
                ),
                text(28),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d(0.0..1.0, 0.0..ymax)
            .map_err(err)?;
        axes(
            &mut chart,
            "β: side-2 impact time / period",
            "gap Δ*(β) / u_g",
            18,
        )?;
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(0.0, 0.0), (self.non_viable_bound, ymax)],
                RGBColor(200, 200, 200).mix(0.4).filled(),
            )))
            .map_err(err)?
            .label(format!(
                "Nigm–Shabana: non-viable for 0 ≤ β ≤ {}",
                self.non_viable_bound
            ))
            .legend(|(x, y)| {
                Rectangle::new(
                    [(x, y - 6), (x + 20, y + 6)],
                    RGBColor(200, 200, 200).filled(),
                )
            });
        for (i, (omega, members)) in self.curves.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            // Faint line through every member; heavy where viable; markers say stable.
            let all: Vec<(f64, f64)> = members
                .iter()
                .filter(|m| m.gap_ratio.is_finite() && m.gap_ratio <= ymax)
                .map(|m| (m.beta, m.gap_ratio))
                .collect();
            chart
                .draw_series(LineSeries::new(all, colour.mix(0.35).stroke_width(1)))
                .map_err(err)?
                .label(format!("ω = {omega} rad/s (faint: not viable)"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3))
                });
            for w in members.windows(2) {
                if w[0].viable && w[1].viable && w[0].gap_ratio <= ymax && w[1].gap_ratio <= ymax {
                    let seg = vec![(w[0].beta, w[0].gap_ratio), (w[1].beta, w[1].gap_ratio)];
                    if w[0].stable && w[1].stable {
                        chart
                            .draw_series(LineSeries::new(seg, colour.stroke_width(4)))
                            .map_err(err)?;
                    } else {
                        chart
                            .draw_series(DashedLineSeries::new(seg, 5, 4, colour.stroke_width(3)))
                            .map_err(err)?;
                    }
                }
            }
        }
        let mut labelled = false;
        for c in &self.confirmations {
            let ok = c.measured_beta.is_some_and(|b| (b - c.beta).abs() < 1e-6);
            let style = if ok {
                BLACK.filled()
            } else {
                RED.stroke_width(2)
            };
            let s = chart
                .draw_series(std::iter::once(Cross::new((c.beta, c.gap_ratio), 7, style)))
                .map_err(err)?;
            if !labelled {
                labelled = true;
                s.label("simulated with gap Δ*(β): black ✕ impact spacing = βT, red ✕ it is not")
                    .legend(|(x, y)| Cross::new((x + 10, y), 6, BLACK.filled()));
            }
        }
        chart
            .draw_series(std::iter::once(Text::new(
                "heavy solid: viable and stable; heavy dashed: viable, unstable",
                (0.2, ymax * 0.97),
                text(16),
            )))
            .map_err(err)?;
        legend(&mut chart, SeriesLabelPosition::UpperRight, 15)?;
        Ok(())
    }
}
