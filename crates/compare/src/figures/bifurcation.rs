//! Simulated stroboscopic outer displacement `u_o(kT)` against frequency, sweeping up and down
//! with the final state carried over, and the analytic symmetric orbits' stroboscopic points.

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::plots::{Bifurcation, BifurcationFrame};
use plotters::coord::Shift;
use plotters::prelude::*;

impl Figure for Bifurcation {
    fn name(&self) -> &str {
        "bifurcation"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 1350)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let whole = self.whole_frame();
        let Some(detail) = self.detail_frame() else {
            return self.panel(root, whole, "outliers clipped to the frame");
        };
        let (top, bottom) = root.split_vertically(750);
        self.panel(&top, whole, "outliers clipped to the frame")?;
        self.panel(&bottom, detail, "detail above the primary resonance")
    }
}

impl Bifurcation {
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        frame: BifurcationFrame,
        what: &str,
    ) -> Result<(), String> {
        let (wmin, wmax) = frame.omega_range;
        let ymax = frame.half_height;
        let inside = |w: f64| (wmin..=wmax).contains(&w);
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!(
                    "Stroboscopic u_o(kT), sweeping up and down, scene '{}' ({what})",
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
                    .filter(|p| inside(p.0))
                    .map(|&(w, u)| Circle::new((w, u), 2, up_colour.filled())),
            )
            .map_err(err)?
            .label("simulated, sweeping up")
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, up_colour.filled()));
        chart
            .draw_series(
                self.down
                    .iter()
                    .filter(|p| inside(p.0))
                    .map(|&(w, u)| Cross::new((w, u), 3, down_colour.stroke_width(1))),
            )
            .map_err(err)?
            .label("simulated, sweeping down")
            .legend(move |(x, y)| Cross::new((x + 10, y), 4, down_colour.stroke_width(2)));
        chart
            .draw_series(
                self.analytic
                    .iter()
                    .filter(|p| p.2 && inside(p.0))
                    .map(|&(w, u, _)| Circle::new((w, u), 5, BLACK.stroke_width(1))),
            )
            .map_err(err)?
            .label("analytic symmetric orbit, viable and stable")
            .legend(|(x, y)| Circle::new((x + 10, y), 5, BLACK.stroke_width(1)));
        chart
            .draw_series(
                self.analytic
                    .iter()
                    .filter(|p| !p.2 && inside(p.0))
                    .map(|&(w, u, _)| {
                        TriangleMarker::new((w, u), 4, RGBColor(120, 120, 120).stroke_width(1))
                    }),
            )
            .map_err(err)?
            .label("analytic symmetric orbit, viable but unstable")
            .legend(|(x, y)| {
                TriangleMarker::new((x + 10, y), 4, RGBColor(120, 120, 120).stroke_width(1))
            });
        legend(&mut chart, SeriesLabelPosition::UpperRight, 15)?;
        Ok(())
    }
}
