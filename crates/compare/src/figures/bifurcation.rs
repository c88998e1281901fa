//! Simulated stroboscopic outer displacement `u_o(kT)` against frequency, sweeping up and down
//! with the final state carried over, and the analytic symmetric orbits' stroboscopic points.

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::plots::Bifurcation;
use plotters::coord::Shift;
use plotters::prelude::*;

impl Figure for Bifurcation {
    fn name(&self) -> &str {
        "bifurcation"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let (wmin, wmax) = self.omega_range;
        // Scale to the bulk of the points (98th percentile): a few huge excursions near
        // resonance would otherwise flatten everything else; they are clipped at the frame.
        let mut mags: Vec<f64> = self
            .up
            .iter()
            .chain(&self.down)
            .map(|p| p.1.abs())
            .chain(self.analytic.iter().map(|p| p.1.abs()))
            .filter(|v| v.is_finite())
            .collect();
        mags.sort_by(f64::total_cmp);
        let bulk = mags.get(mags.len() * 98 / 100).copied().unwrap_or(1.0);
        let ymax = bulk.max(1e-3) * 1.2;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Stroboscopic u_o(kT), sweeping up and down, scene '{}' (outliers clipped to the frame)",
                    self.scene_name
                ),
                text(22),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d(wmin..wmax, -ymax..ymax)
            .map_err(err)?;
        axes(
            &mut chart,
            "base frequency ω (rad/s)",
            "u_o at t = kT (m)",
            18,
        )?;
        let up_colour = RGBColor(30, 90, 220);
        let down_colour = RGBColor(220, 60, 30);
        chart
            .draw_series(
                self.up
                    .iter()
                    .map(|&(w, u)| Circle::new((w, u), 2, up_colour.filled())),
            )
            .map_err(err)?
            .label("simulated, sweeping up")
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, up_colour.filled()));
        chart
            .draw_series(
                self.down
                    .iter()
                    .map(|&(w, u)| Cross::new((w, u), 3, down_colour.stroke_width(1))),
            )
            .map_err(err)?
            .label("simulated, sweeping down")
            .legend(move |(x, y)| Cross::new((x + 10, y), 4, down_colour.stroke_width(2)));
        chart
            .draw_series(
                self.analytic
                    .iter()
                    .filter(|p| p.2)
                    .map(|&(w, u, _)| Circle::new((w, u), 5, BLACK.stroke_width(1))),
            )
            .map_err(err)?
            .label("analytic symmetric orbit, viable and stable")
            .legend(|(x, y)| Circle::new((x + 10, y), 5, BLACK.stroke_width(1)));
        chart
            .draw_series(self.analytic.iter().filter(|p| !p.2).map(|&(w, u, _)| {
                TriangleMarker::new((w, u), 4, RGBColor(120, 120, 120).stroke_width(1))
            }))
            .map_err(err)?
            .label("analytic symmetric orbit, viable but unstable")
            .legend(|(x, y)| {
                TriangleMarker::new((x + 10, y), 4, RGBColor(120, 120, 120).stroke_width(1))
            });
        legend(&mut chart, SeriesLabelPosition::UpperRight, 15)?;
        Ok(())
    }
}
