//! Poincaré sections of a motion that never repeats: the stroboscopic section `(u_o, u̇_o)` at
//! `t = kT` beside the impact map (base phase of each impact, approach velocity), the
//! Lyapunov exponents in the title.

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::chaos::PoincareSections;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::collections::HashSet;

/// The figure's data.
#[derive(Debug, Clone)]
pub struct PoincareFigure {
    /// Scene name, for the title.
    pub scene_name: String,
    /// The sections and the exponents.
    pub sections: PoincareSections,
}

/// Radius of a point's dot, px.
const RADIUS: i32 = 1;
/// Side of the cells of [`dots`], px: less than a dot's diameter.
const CELL: i32 = 2;

/// Colour of the stroboscopic points.
const SECTION: RGBColor = RGBColor(30, 60, 150);
/// Colours of side-1 and side-2 impacts.
const SIDE_1: RGBColor = RGBColor(205, 35, 35);
const SIDE_2: RGBColor = RGBColor(30, 150, 60);

/// `[lo, hi]` of `values`, padded by 5 %; `(-1, 1)` without a spread.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if lo.is_finite() && hi > lo {
        let pad = 0.05 * (hi - lo);
        (lo - pad, hi + pad)
    } else if lo.is_finite() {
        (lo - 1.0, lo + 1.0)
    } else {
        (-1.0, 1.0)
    }
}

/// The exponents as `[a, b, …] ± u /s`, with the collapsed ones.
fn exponents_words(p: &PoincareSections) -> String {
    let list = p
        .exponents
        .iter()
        .map(|l| format!("{l:.3}"))
        .collect::<Vec<_>>()
        .join(", ");
    let collapsed = if p.collapsed > 0 {
        format!(" and {} × −∞ (sticking)", p.collapsed)
    } else {
        String::new()
    };
    format!("λ = [{list}] ± {:.3} /s{collapsed}", p.uncertainty)
}

/// Draws `points` as dots of [`RADIUS`] px, at most one per cell of [`CELL`] × [`CELL`] px: a
/// point whose dot would land in a cell already dotted would paint (nearly) the same pixels
/// again, and only swell the SVG.
/// `label`, when given, names the dots in the chart's legend.
fn dots<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    points: impl Iterator<Item = (f64, f64)>,
    colour: RGBColor,
    label: Option<&str>,
) -> Result<(), String> {
    let mut seen = HashSet::new();
    let unique: Vec<(f64, f64)> = points
        .filter(|&p| {
            let (x, y) = chart.backend_coord(&p);
            seen.insert((x.div_euclid(CELL), y.div_euclid(CELL)))
        })
        .collect();
    let series = chart
        .draw_series(
            unique
                .into_iter()
                .map(|p| Circle::new(p, RADIUS, colour.filled())),
        )
        .map_err(err)?;
    if let Some(label) = label {
        series
            .label(label)
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, colour.filled()));
    }
    Ok(())
}

impl Figure for PoincareFigure {
    fn name(&self) -> &str {
        "poincare"
    }

    fn size(&self) -> (u32, u32) {
        (1700, 850)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let p = &self.sections;
        let regime = p.regime.unwrap_or("periodic");
        let root = root.titled(
            &format!(
                "Scene '{}', ω = {} rad/s, the motion settled from rest: {regime}, {} over {} periods",
                self.scene_name,
                p.omega,
                exponents_words(p),
                p.lyapunov_periods
            ),
            text(22),
        )
        .map_err(err)?;
        let (left, right) = root.split_horizontally(850);

        let (u0, u1) = range(p.sections.iter().map(|s| s.0));
        let (v0, v1) = range(p.sections.iter().map(|s| s.1));
        let mut chart = ChartBuilder::on(&left)
            .caption(
                format!(
                    "Stroboscopic section t = kT (base at u_g cos ωt), {} points",
                    p.sections.len()
                ),
                text(18),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(80)
            .build_cartesian_2d(u0..u1, v0..v1)
            .map_err(err)?;
        axes(
            &mut chart,
            "outer displacement u_o (m)",
            "outer velocity u̇_o (m/s)",
            16,
        )?;
        dots(&mut chart, p.sections.iter().copied(), SECTION, None)?;

        let (r0, r1) = range(p.impacts.iter().map(|i| i.relative_velocity));
        let mut chart = ChartBuilder::on(&right)
            .caption(format!("Impact map, {} impacts", p.impacts.len()), text(18))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..std::f64::consts::TAU, r0..r1)
            .map_err(err)?;
        axes(
            &mut chart,
            "base phase of the impact ωt mod 2π (rad)",
            "relative velocity before the impact ṙ⁻ (m/s)",
            16,
        )?;
        for (side, colour, words) in [
            (1, SIDE_1, "impact on side 1 (r = +Δ)"),
            (-1, SIDE_2, "impact on side 2 (r = −Δ)"),
        ] {
            dots(
                &mut chart,
                p.impacts
                    .iter()
                    .filter(|i| i.side == side)
                    .map(|i| (i.phase, i.relative_velocity)),
                colour,
                Some(words),
            )?;
        }
        legend(&mut chart, SeriesLabelPosition::LowerLeft, 15)?;
        Ok(())
    }
}
