//! The paper's Figure 2: steady linear response of both masses with the two walls of the outer
//! mass (`u_o ± Δ`), at a few frequencies.

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::plots::LinearTimeResponse;
use plotters::coord::Shift;
use plotters::prelude::*;

impl Figure for LinearTimeResponse {
    fn name(&self) -> &str {
        "linear-time-response"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 560)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let gap = self.gap;
        let (title, body) = root.split_vertically(50);
        title
            .draw_text(
                &format!(
                    "Linear steady state (stops ignored), scene '{}', walls at u_o ± Δ, Δ = {gap} m",
                    self.scene_name
                ),
                &text(24),
                (20, 12),
            )
            .map_err(err)?;
        let panels = body.split_evenly((1, self.panels.len().max(1)));
        for (area, panel) in panels.iter().zip(&self.panels) {
            let omega = panel.omega;
            let period = std::f64::consts::TAU / omega;
            let uo: Vec<(f64, f64)> = panel.samples.iter().map(|&(t, u, _)| (t, u)).collect();
            let ui: Vec<(f64, f64)> = panel.samples.iter().map(|&(t, _, u)| (t, u)).collect();
            let ymax = panel
                .outer_amplitude
                .max(panel.inner_amplitude)
                .max(panel.outer_amplitude + gap)
                * 1.15;
            let mut chart = ChartBuilder::on(area)
                .caption(format!("ω = {omega} rad/s"), text(22))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(60)
                .build_cartesian_2d(0.0..2.0 * period, -ymax..ymax)
                .map_err(err)?;
            axes(&mut chart, "time t (s)", "displacement (m)", 16)?;
            let blue = BLUE.stroke_width(2);
            let red = RED.stroke_width(2);
            chart
                .draw_series(LineSeries::new(uo.iter().copied(), blue))
                .map_err(err)?
                .label("outer mass u_o")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], blue));
            chart
                .draw_series(LineSeries::new(ui.iter().copied(), red))
                .map_err(err)?
                .label("inner mass u_i")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], red));
            if gap > 0.0 {
                for (sign, label, colour) in [
                    (1.0, "side 1: u_o + Δ", BLACK),
                    (-1.0, "side 2: u_o − Δ", RGBColor(120, 120, 120)),
                ] {
                    let style = colour.stroke_width(1);
                    chart
                        .draw_series(DashedLineSeries::new(
                            uo.iter().map(|&(t, u)| (t, u + sign * gap)),
                            6,
                            4,
                            style,
                        ))
                        .map_err(err)?
                        .label(label)
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
                }
            }
            legend(&mut chart, SeriesLabelPosition::LowerRight, 14)?;
        }
        Ok(())
    }
}
