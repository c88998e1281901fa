//! The regime of the simulated steady state over frequency and gap (at one restitution):
//! no impact, the two-impact period-1 motion (and whether it is the analytic orbit), other
//! period-1 motions, subharmonics, irregular motion, sticking.

use crate::figures::plot::{axes, err, text, Figure};
use crate::study::plots::{RegimeClass, RegimeMap};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Fill colour of a class.
pub fn colour(class: RegimeClass) -> RGBColor {
    match class {
        RegimeClass::NoImpact => RGBColor(215, 215, 215),
        RegimeClass::TwoImpactAgreeing => RGBColor(30, 150, 60),
        RegimeClass::TwoImpactOnly => RGBColor(160, 210, 100),
        RegimeClass::MoreImpacts => RGBColor(245, 165, 40),
        RegimeClass::Subharmonic => RGBColor(50, 100, 215),
        RegimeClass::Irregular => RGBColor(120, 120, 120),
        RegimeClass::Chaotic => RGBColor(205, 35, 35),
        RegimeClass::QuasiPeriodic => RGBColor(240, 120, 170),
        RegimeClass::Unsettled => RGBColor(120, 200, 220),
        RegimeClass::Sticking => RGBColor(140, 60, 170),
        RegimeClass::NoDissipation => RGBColor(250, 250, 250),
        RegimeClass::Failed => RGBColor(0, 0, 0),
    }
}

impl Figure for RegimeMap {
    fn name(&self) -> &str {
        "regime-map"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let grid = &self.grid;
        let (w0, w1) = (grid.omega.min, grid.omega.max);
        let (g0, g1) = (
            grid.gap_over_base_amplitude.min,
            grid.gap_over_base_amplitude.max,
        );
        // Each sample is drawn as the cell around it.
        let dw = 0.5 * grid.omega.step();
        let dg = 0.5 * grid.gap_over_base_amplitude.step();
        let (plot, side) = root.split_horizontally(1140);
        let restitution = self.restitution;
        let mut chart = ChartBuilder::on(&plot)
            .caption(
                format!(
                    "Simulated regime, scene '{}', e = {restitution} (each frequency continued from the previous one, up)",
                    self.scene_name
                ),
                text(20),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d((w0 - dw)..(w1 + dw), (g0 - dg)..(g1 + dg))
            .map_err(err)?;
        axes(
            &mut chart,
            "base frequency ω (rad/s)",
            "gap over base amplitude Δ/u_g",
            18,
        )?;
        chart
            .draw_series(self.cells.iter().map(|c| {
                let (w, g) = (c.omega, c.gap_over_base_amplitude);
                Rectangle::new(
                    [(w - dw, g - dg), (w + dw, g + dg)],
                    colour(c.class).filled(),
                )
            }))
            .map_err(err)?;
        // Legend: every class with its share of the map.
        let legend = side.margin(80, 20, 10, 10);
        for (i, &(class, share)) in self.shares.iter().enumerate() {
            let y = 30 * i as i32;
            legend
                .draw(&Rectangle::new(
                    [(0, y), (22, y + 20)],
                    colour(class).filled(),
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
                    format!("{} ({:.0}%)", class.words(), 100.0 * share),
                    (30, y + 3),
                    text(13),
                ))
                .map_err(err)?;
        }
        Ok(())
    }
}
