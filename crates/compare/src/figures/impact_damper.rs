//! What an impact damper buys: the primary's amplitude against frequency with the free body
//! (simulated, sweeping up and down) and without it (the primary alone, linear), one panel per gallery
//! damper, with the one-body damper's closed-form symmetric two-impact motion on top.

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::damper::{DamperPanel, DamperStudy};
use plotters::coord::Shift;
use plotters::prelude::*;

impl Figure for DamperStudy {
    fn name(&self) -> &str {
        "impact-damper"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 700)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let areas = root.split_evenly((1, self.panels.len().max(1)));
        for (area, panel) in areas.iter().zip(&self.panels) {
            draw_panel(area, panel, self.omega_range)?;
        }
        Ok(())
    }
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &DamperPanel,
    (wmin, wmax): (f64, f64),
) -> Result<(), String> {
    let top = panel
        .alone
        .iter()
        .chain(&panel.up)
        .chain(&panel.down)
        .chain(&panel.irregular)
        .map(|p| p.1)
        .chain(panel.branch.iter().map(|p| p.amplitude))
        .filter(|a| a.is_finite())
        .fold(0.0, f64::max)
        * 1.08;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!(
                "Scene '{}': amplitude of '{}' with and without the damper",
                panel.scene_name, panel.observed
            ),
            text(18),
        )
        .margin(18)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(wmin..wmax, 0.0..top.max(1e-3))
        .map_err(err)?;
    axes(
        &mut chart,
        "forcing frequency ω (rad/s)",
        &format!("amplitude of '{}' (m)", panel.observed),
        16,
    )?;
    let alone_colour = RGBColor(120, 120, 120);
    chart
        .draw_series(LineSeries::new(
            panel.alone.iter().copied(),
            alone_colour.stroke_width(2),
        ))
        .map_err(err)?
        .label("primary alone (no free body), linear")
        .legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 20, y)], alone_colour.stroke_width(2))
        });
    let up_colour = RGBColor(30, 90, 220);
    chart
        .draw_series(
            panel
                .up
                .iter()
                .map(|&p| Circle::new(p, 3, up_colour.filled())),
        )
        .map_err(err)?
        .label("with the damper: simulated, periodic, sweeping up")
        .legend(move |(x, y)| Circle::new((x + 10, y), 4, up_colour.filled()));
    let down_colour = RGBColor(20, 160, 90);
    chart
        .draw_series(
            panel
                .down
                .iter()
                .map(|&p| TriangleMarker::new(p, 4, down_colour.filled())),
        )
        .map_err(err)?
        .label("with the damper: simulated, periodic, sweeping down")
        .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 4, down_colour.filled()));
    let irregular_colour = RGBColor(220, 60, 30);
    chart
        .draw_series(
            panel
                .irregular
                .iter()
                .map(|&p| Cross::new(p, 4, irregular_colour.stroke_width(1))),
        )
        .map_err(err)?
        .label("with the damper: simulated, not periodic (last cycle)")
        .legend(move |(x, y)| Cross::new((x + 10, y), 4, irregular_colour.stroke_width(2)));
    if !panel.branch.is_empty() {
        for (stable, colour, label) in [
            (true, BLACK, "closed form, two impacts per period, stable"),
            (
                false,
                RGBColor(170, 170, 170),
                "closed form, two impacts per period, unstable",
            ),
        ] {
            chart
                .draw_series(
                    panel
                        .branch
                        .iter()
                        .filter(|p| p.stable == stable)
                        .map(|p| Circle::new((p.omega, p.amplitude), 1, colour.filled())),
                )
                .map_err(err)?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3))
                });
        }
    }
    legend(&mut chart, SeriesLabelPosition::UpperRight, 13)?;
    Ok(())
}
