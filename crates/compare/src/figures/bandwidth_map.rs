//! The attenuation bandwidth over restitution and gap: for every `(e, Δ/u_g)` the measure of
//! the frequencies with `T < 0 dB` and where the first such band starts, simulated and as the
//! analytic orbits predict.

use crate::figures::plot::{axes, err, text, Figure};
use crate::runs::map::MapGrid;
use crate::study::plots::{BandwidthCell, BandwidthMap};
use plotters::coord::Shift;
use plotters::prelude::*;

/// A perceptually ordered colour scale (viridis, by its anchors): `t ∈ [0, 1]`.
pub fn scale_colour(t: f64) -> RGBColor {
    const ANCHORS: [(f64, f64, f64); 6] = [
        (68.0, 1.0, 84.0),
        (65.0, 68.0, 135.0),
        (42.0, 120.0, 142.0),
        (34.0, 168.0, 132.0),
        (122.0, 209.0, 81.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (ANCHORS.len() - 1) as f64;
    let i = (x.floor() as usize).min(ANCHORS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (ANCHORS[i], ANCHORS[i + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A panel's value at a cell.
fn cell(c: &BandwidthCell, value: Option<f64>) -> (f64, f64, Option<f64>) {
    (c.restitution, c.gap_over_base_amplitude, value)
}

/// Colour of cells without a value (no attenuation band, or nothing predicted).
const EMPTY: RGBColor = RGBColor(200, 200, 200);

/// One panel: a value per `(e, Δ/u_g)` cell on a common scale `[0, top]`.
struct Panel<'a> {
    title: &'a str,
    values: Vec<(f64, f64, Option<f64>)>,
}

/// Draws one panel.
fn panel_of<DB: DrawingBackend>(
    grid: &MapGrid,
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    top: f64,
    unit: &str,
) -> Result<(), String> {
    let de = 0.5 * grid.restitution.step().max(1e-3);
    let dg = 0.5 * grid.gap_over_base_amplitude.step().max(1e-3);
    let (e0, e1) = (grid.restitution.min - de, grid.restitution.max + de);
    let (g0, g1) = (
        grid.gap_over_base_amplitude.min - dg,
        grid.gap_over_base_amplitude.max + dg,
    );
    let (plot, bar) = area.split_horizontally(area.dim_in_pixel().0 - 110);
    let mut chart = ChartBuilder::on(&plot)
        .caption(panel.title, text(17))
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(e0..e1, g0..g1)
        .map_err(err)?;
    axes(&mut chart, "restitution e", "gap Δ/u_g", 14)?;
    chart
        .draw_series(panel.values.iter().map(|&(e, g, v)| {
            let colour = v.map_or(EMPTY, |v| scale_colour(v / top));
            Rectangle::new([(e - de, g - dg), (e + de, g + dg)], colour.filled())
        }))
        .map_err(err)?;
    // Colour bar.
    let mut bar_chart = ChartBuilder::on(&bar)
        .margin_top(40)
        .margin_bottom(55)
        .margin_right(10)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..1.0, 0.0..top)
        .map_err(err)?;
    bar_chart
        .configure_mesh()
        .disable_x_mesh()
        .disable_x_axis()
        .y_desc(unit)
        .label_style(text(13))
        .axis_desc_style(text(14))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(err)?;
    let n = 100;
    bar_chart
        .draw_series((0..n).map(|i| {
            let a = top * i as f64 / n as f64;
            let b = top * (i + 1) as f64 / n as f64;
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                scale_colour((i as f64 + 0.5) / n as f64).filled(),
            )
        }))
        .map_err(err)?;
    Ok(())
}

impl Figure for BandwidthMap {
    fn name(&self) -> &str {
        "bandwidth-map"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 1100)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let grid = &self.grid;
        let (title, body) = root.split_vertically(50);
        title
            .draw(&Text::new(
                format!(
                    "Attenuation (T < 0 dB) over ω ∈ [{}, {}] rad/s by restitution and gap, scene '{}'; grey: none",
                    grid.omega.min, grid.omega.max, self.scene_name
                ),
                (20, 15),
                text(20),
            ))
            .map_err(err)?;
        let panels = body.split_evenly((2, 2));
        let range = grid.omega.max - grid.omega.min;
        let simulated_width = Panel {
            title: "simulated: attenuation bandwidth (rad/s)",
            values: self
                .cells
                .iter()
                .map(|c| cell(c, Some(c.simulated.bandwidth).filter(|b| *b > 0.0)))
                .collect(),
        };
        let analytic_width = Panel {
            title: "analytic prediction: attenuation bandwidth (rad/s)",
            values: self
                .cells
                .iter()
                .map(|c| cell(c, Some(c.analytic.bandwidth).filter(|b| *b > 0.0)))
                .collect(),
        };
        let simulated_start = Panel {
            title: "simulated: where the first band starts (rad/s)",
            values: self
                .cells
                .iter()
                .map(|c| cell(c, c.simulated.first_band_start))
                .collect(),
        };
        let analytic_start = Panel {
            title: "analytic prediction: where the first band starts (rad/s)",
            values: self
                .cells
                .iter()
                .map(|c| cell(c, c.analytic.first_band_start))
                .collect(),
        };
        panel_of(
            grid,
            &panels[0],
            &simulated_width,
            range,
            "bandwidth (rad/s)",
        )?;
        panel_of(
            grid,
            &panels[1],
            &analytic_width,
            range,
            "bandwidth (rad/s)",
        )?;
        panel_of(
            grid,
            &panels[2],
            &simulated_start,
            grid.omega.max,
            "ω (rad/s)",
        )?;
        panel_of(
            grid,
            &panels[3],
            &analytic_start,
            grid.omega.max,
            "ω (rad/s)",
        )?;
        Ok(())
    }
}
