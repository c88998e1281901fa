//! The regime of the simulated steady state over frequency and gap (at one restitution):
//! no impact, the two-impact period-1 motion (and whether it is the analytic orbit), other
//! period-1 motions, subharmonics, irregular motion, sticking.

use crate::map::{Map, MapPoint};
use crate::plot::{axes, err, text, Figure};
use crate::simulation::Regime;
use plotters::coord::Shift;
use plotters::prelude::*;

/// The classes of the regime map, in legend order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RegimeClass {
    /// Periodic, no impact.
    NoImpact,
    /// Two impacts per period, period 1, and it is a stable viable symmetric analytic orbit.
    TwoImpactAgreeing,
    /// Two impacts per period, period 1, but no stable viable symmetric analytic orbit matches
    /// it (an asymmetric orbit, or one not yet within the match tolerance).
    TwoImpactOnly,
    /// Period 1 with another number or pattern of impacts.
    MoreImpacts,
    /// Periodic with period `p > 1`.
    Subharmonic,
    /// Not periodic within the cap.
    Irregular,
    /// Sticking on a stop in the final cycle.
    Sticking,
    /// Undamped and elastic: no steady state.
    NoDissipation,
    /// A solver failed.
    Failed,
}

impl RegimeClass {
    /// Every class, in legend order.
    pub const ALL: [RegimeClass; 9] = [
        RegimeClass::NoImpact,
        RegimeClass::TwoImpactAgreeing,
        RegimeClass::TwoImpactOnly,
        RegimeClass::MoreImpacts,
        RegimeClass::Subharmonic,
        RegimeClass::Irregular,
        RegimeClass::Sticking,
        RegimeClass::NoDissipation,
        RegimeClass::Failed,
    ];

    /// The class of a map point.
    pub fn of(point: &MapPoint) -> RegimeClass {
        match point.regime {
            None => RegimeClass::Failed,
            Some(Regime::NoImpact) => RegimeClass::NoImpact,
            Some(Regime::TwoImpact) if point.analytic_match => RegimeClass::TwoImpactAgreeing,
            Some(Regime::TwoImpact) => RegimeClass::TwoImpactOnly,
            Some(Regime::MoreImpacts) => RegimeClass::MoreImpacts,
            Some(Regime::Subharmonic) => RegimeClass::Subharmonic,
            Some(Regime::Irregular) => RegimeClass::Irregular,
            Some(Regime::Sticking) => RegimeClass::Sticking,
            Some(Regime::Undecided) => RegimeClass::NoDissipation,
        }
    }

    /// Legend words.
    pub fn words(self) -> &'static str {
        match self {
            RegimeClass::NoImpact => "no impact",
            RegimeClass::TwoImpactAgreeing => "two impacts, period 1 = symmetric analytic orbit",
            RegimeClass::TwoImpactOnly => "two impacts, period 1, not a symmetric orbit",
            RegimeClass::MoreImpacts => "other impacts, period 1",
            RegimeClass::Subharmonic => "period p > 1",
            RegimeClass::Irregular => "not periodic within the cap",
            RegimeClass::Sticking => "sticking",
            RegimeClass::NoDissipation => "no dissipation",
            RegimeClass::Failed => "solver failed",
        }
    }

    /// Fill colour.
    pub fn colour(self) -> RGBColor {
        match self {
            RegimeClass::NoImpact => RGBColor(215, 215, 215),
            RegimeClass::TwoImpactAgreeing => RGBColor(30, 150, 60),
            RegimeClass::TwoImpactOnly => RGBColor(160, 210, 100),
            RegimeClass::MoreImpacts => RGBColor(245, 165, 40),
            RegimeClass::Subharmonic => RGBColor(50, 100, 215),
            RegimeClass::Irregular => RGBColor(205, 35, 35),
            RegimeClass::Sticking => RGBColor(140, 60, 170),
            RegimeClass::NoDissipation => RGBColor(250, 250, 250),
            RegimeClass::Failed => RGBColor(0, 0, 0),
        }
    }
}

/// The figure's data: one map with a single restitution.
pub struct RegimeMap {
    /// Scene name, for the title.
    pub scene_name: String,
    /// The map (its lines: one per gap).
    pub map: Map,
}

impl Figure for RegimeMap {
    fn name(&self) -> &str {
        "regime-map"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let grid = &self.map.grid;
        let (w0, w1) = (grid.omega.min, grid.omega.max);
        let (g0, g1) = (
            grid.gap_over_base_amplitude.min,
            grid.gap_over_base_amplitude.max,
        );
        // Each sample is drawn as the cell around it.
        let dw = 0.5 * grid.omega.step();
        let dg = 0.5 * grid.gap_over_base_amplitude.step();
        let (plot, side) = root.split_horizontally(1140);
        let restitution = self.map.lines.first().map_or(f64::NAN, |l| l.restitution);
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
        let mut counts = [0usize; RegimeClass::ALL.len()];
        chart
            .draw_series(
                self.map
                    .lines
                    .iter()
                    .flat_map(|line| {
                        let g = line.gap_over_base_amplitude;
                        line.points.iter().map(move |p| (g, p))
                    })
                    .map(|(g, p)| {
                        let class = RegimeClass::of(p);
                        Rectangle::new(
                            [(p.omega - dw, g - dg), (p.omega + dw, g + dg)],
                            class.colour().filled(),
                        )
                    }),
            )
            .map_err(err)?;
        for line in &self.map.lines {
            for p in &line.points {
                let class = RegimeClass::of(p);
                if let Some(i) = RegimeClass::ALL.iter().position(|c| *c == class) {
                    counts[i] += 1;
                }
            }
        }
        // Legend: every class with its share of the map.
        let total = counts.iter().sum::<usize>().max(1);
        let legend = side.margin(80, 20, 10, 10);
        for (i, class) in RegimeClass::ALL.iter().enumerate() {
            let y = 30 * i as i32;
            legend
                .draw(&Rectangle::new(
                    [(0, y), (22, y + 20)],
                    class.colour().filled(),
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
                        "{} ({:.0}%)",
                        class.words(),
                        100.0 * counts[i] as f64 / total as f64
                    ),
                    (30, y + 3),
                    text(13),
                ))
                .map_err(err)?;
        }
        Ok(())
    }
}
