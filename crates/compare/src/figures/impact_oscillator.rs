//! The impact oscillator's bifurcation diagram: the simulator's impact velocities against
//! frequency, sweeping up and down, with the closed-form period-1 branch on top.

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::gallery::OscillatorStudy;
use plotters::coord::Shift;
use plotters::prelude::*;

impl Figure for OscillatorStudy {
    fn name(&self) -> &str {
        "impact-oscillator"
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let (wmin, wmax) = self.omega_range;
        let all = || {
            self.up
                .iter()
                .chain(&self.down)
                .copied()
                .chain(self.branch.iter().map(|p| (p.omega, p.velocity_before)))
                .filter(|p| p.0 >= wmin && p.0 <= wmax)
        };
        let vmax = all().map(|p| p.1).fold(0.0, f64::max) * 1.08;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Impact velocity against frequency, scene '{}': simulated sweeps and the closed-form period-1 branch",
                    self.scene_name
                ),
                text(20),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d(wmin..wmax, 0.0..vmax.max(1e-3))
            .map_err(err)?;
        axes(
            &mut chart,
            "forcing frequency ω (rad/s)",
            "velocity just before impact ẋ⁻ (m/s)",
            18,
        )?;
        let up_colour = RGBColor(30, 90, 220);
        let down_colour = RGBColor(220, 60, 30);
        chart
            .draw_series(
                self.up
                    .iter()
                    .map(|&p| Circle::new(p, 2, up_colour.filled())),
            )
            .map_err(err)?
            .label("simulated, sweeping up")
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, up_colour.filled()));
        chart
            .draw_series(
                self.down
                    .iter()
                    .map(|&p| Cross::new(p, 3, down_colour.stroke_width(1))),
            )
            .map_err(err)?
            .label("simulated, sweeping down")
            .legend(move |(x, y)| Cross::new((x + 10, y), 4, down_colour.stroke_width(2)));
        for (stable, colour, label) in [
            (true, BLACK, "closed form, period 1, stable"),
            (
                false,
                RGBColor(130, 130, 130),
                "closed form, period 1, unstable",
            ),
        ] {
            chart
                .draw_series(
                    self.branch
                        .iter()
                        .filter(|p| p.stable == stable)
                        .map(|p| Circle::new((p.omega, p.velocity_before), 1, colour.filled())),
                )
                .map_err(err)?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3))
                });
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight, 15)?;
        Ok(())
    }
}
