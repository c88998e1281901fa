//! Basins of attraction: each start at rest (outer and inner displacement) coloured by the
//! attractor it reaches.

use crate::figures::plot::{axes, err, text, Figure};
use crate::runs::basins::{Attractor, Basins};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Fill colours of the periodic attractors, in their order of appearance.
const PALETTE: [RGBColor; 8] = [
    RGBColor(30, 150, 60),
    RGBColor(50, 100, 215),
    RGBColor(245, 165, 40),
    RGBColor(140, 60, 170),
    RGBColor(160, 210, 100),
    RGBColor(120, 200, 220),
    RGBColor(240, 120, 170),
    RGBColor(120, 80, 40),
];

/// The basins figure of one frequency.
#[derive(Debug, Clone)]
pub struct BasinsFigure {
    /// Scene name, for the title.
    pub scene_name: String,
    /// The grid and its attractors.
    pub basins: Basins,
}

/// Fill colour of attractor `k` of `attractors`.
fn colour(attractors: &[Attractor], k: usize) -> RGBColor {
    match attractors[k] {
        Attractor::NotPeriodic => RGBColor(205, 35, 35),
        Attractor::NoDissipation => RGBColor(250, 250, 250),
        Attractor::Sticking => RGBColor(90, 30, 110),
        Attractor::Failed => RGBColor(0, 0, 0),
        Attractor::OutsideClearance => RGBColor(160, 160, 160),
        Attractor::Periodic { .. } | Attractor::Motion { .. } => {
            let periodic = attractors[..k].iter().filter(|a| a.is_periodic()).count();
            PALETTE[periodic % PALETTE.len()]
        }
    }
}

impl Figure for BasinsFigure {
    fn name(&self) -> &str {
        "basins"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 1000)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let b = &self.basins;
        let (o, i) = (b.grid.outer, b.grid.inner);
        let (dx, dy) = (0.5 * o.step(), 0.5 * i.step());
        let (plot, side) = root.split_horizontally(1000);
        let mut chart = ChartBuilder::on(&plot)
            .caption(
                format!(
                    "Basins of attraction, scene '{}', ω = {} rad/s (starts at rest, t = 0)",
                    self.scene_name, b.omega
                ),
                text(20),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d((o.min - dx)..(o.max + dx), (i.min - dy)..(i.max + dy))
            .map_err(err)?;
        axes(
            &mut chart,
            "outer displacement at the start u_o(0) (m)",
            "inner displacement at the start u_i(0) (m)",
            18,
        )?;
        chart
            .draw_series(b.cells.iter().map(|c| {
                Rectangle::new(
                    [(c.outer - dx, c.inner - dy), (c.outer + dx, c.inner + dy)],
                    colour(&b.attractors, c.attractor).filled(),
                )
            }))
            .map_err(err)?;
        let legend = side.margin(80, 20, 10, 10);
        let total = b.cells.len().max(1) as f64;
        for (k, (a, n)) in b.attractors.iter().zip(&b.counts).enumerate() {
            let y = 30 * k as i32;
            legend
                .draw(&Rectangle::new(
                    [(0, y), (22, y + 20)],
                    colour(&b.attractors, k).filled(),
                ))
                .map_err(err)?;
            legend
                .draw(&Rectangle::new(
                    [(0, y), (22, y + 20)],
                    BLACK.stroke_width(1),
                ))
                .map_err(err)?;
            legend
                .draw(&Text::new(
                    format!(
                        "{} ({n} starts, {:.2}%)",
                        a.words(),
                        100.0 * *n as f64 / total
                    ),
                    (30, y + 3),
                    text(13),
                ))
                .map_err(err)?;
        }
        Ok(())
    }
}
