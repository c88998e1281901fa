//! The regime boundaries: panel 1, the regime map over (ω, Δ/u_g) with every
//! boundary curve over the gap and the linear unit's attenuation band edges; panel 2, the
//! bandwidth map's regimes on its gap line nearest the scene's gap over (ω, e) with every
//! curve over the restitution. Colour by event kind, line style by signature.

use crate::figures::plot::{axes, err, text, Figure};
use crate::figures::regime_map::colour;
use crate::study::boundaries::{BoundariesFigure, CurveLine};
use crate::study::plots::RegimeClass;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

/// The event kinds drawn, in legend order, with their colours.
const KINDS: [(&str, RGBColor); 6] = [
    ("fold", RGBColor(0, 0, 0)),
    ("branch-point", RGBColor(230, 140, 0)),
    ("period-doubling", RGBColor(20, 40, 200)),
    ("neimark-sacker", RGBColor(200, 0, 200)),
    ("grazing", RGBColor(190, 0, 0)),
    ("vanishing-impact", RGBColor(0, 130, 130)),
];

/// The line styles, in legend order: `+-`, `++--`, other period-1 signatures, longer periods.
const STYLES: [&str; 4] = [
    "+- (solid)",
    "++-- (long dashes)",
    "other period 1 (short dashes)",
    "period > 1 (dots)",
];

/// Opacity of the maps beneath the curves.
const BACKGROUND_OPACITY: f64 = 0.4;

/// The colour of an event kind.
fn kind_colour(kind: &str) -> RGBColor {
    KINDS
        .iter()
        .find(|(k, _)| *k == kind)
        .map_or(RGBColor(90, 90, 90), |&(_, c)| c)
}

/// The style index (into [`STYLES`]) of a curve's signature.
fn style_of(curve: &CurveLine) -> usize {
    match (curve.signature.as_str(), curve.period) {
        ("+-", 1) => 0,
        ("++--", 1) => 1,
        (_, 1) => 2,
        _ => 3,
    }
}

/// `(dash, gap)` lengths in pixels of a style; `None` for solid.
fn dashes(style: usize) -> Option<(u32, u32)> {
    match style {
        0 => None,
        1 => Some((12, 5)),
        2 => Some((5, 4)),
        _ => Some((2, 4)),
    }
}

/// Draws `curves` on `chart`, clipped to its ranges by the chart.
fn draw_curves<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    curves: &[CurveLine],
) -> Result<(), String> {
    for c in curves {
        let style = kind_colour(c.kind).stroke_width(2);
        match dashes(style_of(c)) {
            None => chart
                .draw_series(LineSeries::new(c.points.iter().copied(), style))
                .map(|_| ())
                .map_err(err)?,
            Some((dash, gap)) => chart
                .draw_series(DashedLineSeries::new(
                    c.points.iter().copied(),
                    dash,
                    gap,
                    style,
                ))
                .map(|_| ())
                .map_err(err)?,
        }
    }
    Ok(())
}

/// Vertical dashed lines at the finite edges of `bands` within `[w0, w1]`, from `y0` to `y1`.
fn draw_band_edges<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    bands: &[(f64, f64)],
    (y0, y1): (f64, f64),
) -> Result<(), String> {
    let edges = bands
        .iter()
        .flat_map(|&(a, b)| [a, b])
        .filter(|w| w.is_finite());
    for w in edges {
        chart
            .draw_series(DashedLineSeries::new(
                [(w, y0), (w, y1)],
                10,
                6,
                RGBColor(60, 60, 60).stroke_width(3),
            ))
            .map_err(err)?;
    }
    Ok(())
}

impl BoundariesFigure {
    /// Panel 1: the regime map over (ω, Δ/u_g) and the curves over the gap.
    fn gap_panel<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let (w0, w1) = self.omega_range;
        let (g0, g1) = self.regime_map.as_ref().map_or((0.05, 1.0), |m| {
            let a = m.grid.gap_over_base_amplitude;
            (a.min - 0.5 * a.step(), a.max + 0.5 * a.step())
        });
        let map_words = self.regime_map.as_ref().map_or(String::new(), |m| {
            format!("; beneath: simulated regime of '{}'", m.scene_name)
        });
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!(
                    "Boundaries over the gap, scene '{}', e = {}{map_words}",
                    self.scene_name, self.restitution
                ),
                text(20),
            )
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(75)
            .build_cartesian_2d(w0..w1, g0..g1)
            .map_err(err)?;
        axes(
            &mut chart,
            "base frequency ω (rad/s)",
            "gap over base amplitude Δ/u_g",
            16,
        )?;
        if let Some(m) = &self.regime_map {
            let dw = 0.5 * m.grid.omega.step();
            let dg = 0.5 * m.grid.gap_over_base_amplitude.step();
            chart
                .draw_series(m.cells.iter().map(|c| {
                    let (w, g) = (c.omega, c.gap_over_base_amplitude);
                    Rectangle::new(
                        [(w - dw, g - dg), (w + dw, g + dg)],
                        colour(c.class).mix(BACKGROUND_OPACITY).filled(),
                    )
                }))
                .map_err(err)?;
        }
        draw_band_edges(&mut chart, &self.linear_bands, (g0, g1))?;
        draw_curves(&mut chart, &self.gap_curves)
    }

    /// Panel 2: the bandwidth map's regimes on one gap line over (ω, e) and the curves over
    /// the restitution.
    fn restitution_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), String> {
        let (w0, w1) = self.omega_range;
        let (e0, e1) = (0.0, 1.0);
        let line_words = self
            .restitution_background
            .as_ref()
            .map_or(String::new(), |b| {
                format!(
                    "; beneath: simulated regime of '{}' at Δ/u_g = {:.3}",
                    b.scene_name, b.gap_over_base_amplitude
                )
            });
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!(
                    "Boundaries over the restitution, scene '{}', Δ = {}{line_words}",
                    self.scene_name, self.gap
                ),
                text(20),
            )
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(75)
            .build_cartesian_2d(w0..w1, e0..e1)
            .map_err(err)?;
        axes(
            &mut chart,
            "base frequency ω (rad/s)",
            "coefficient of restitution e",
            16,
        )?;
        if let Some(b) = &self.restitution_background {
            let (dw, de) = (0.5 * b.omega_step, 0.5 * b.restitution_step);
            chart
                .draw_series(b.cells.iter().map(|c| {
                    let (w, e) = (c.omega, c.restitution);
                    Rectangle::new(
                        [(w - dw, (e - de).max(e0)), (w + dw, (e + de).min(e1))],
                        colour(c.class).mix(BACKGROUND_OPACITY).filled(),
                    )
                }))
                .map_err(err)?;
        }
        draw_band_edges(&mut chart, &self.linear_bands, (e0, e1))?;
        draw_curves(&mut chart, &self.restitution_curves)
    }

    /// The legend: event kinds, line styles, the band edges and the regimes beneath.
    fn legend<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let legend = area.margin(60, 10, 10, 10);
        let mut y = 0;
        let line = |words: String,
                    colour: RGBColor,
                    dash: Option<(u32, u32)>,
                    y: i32|
         -> Result<(), String> {
            let style = colour.stroke_width(3);
            match dash {
                None => legend
                    .draw(&PathElement::new([(0, y + 8), (40, y + 8)], style))
                    .map_err(err)?,
                Some((d, g)) => {
                    let mut x = 0;
                    while x < 40 {
                        let end = (x + d as i32).min(40);
                        legend
                            .draw(&PathElement::new([(x, y + 8), (end, y + 8)], style))
                            .map_err(err)?;
                        x = end + g as i32;
                    }
                }
            }
            legend
                .draw(&Text::new(words, (48, y), text(14)))
                .map_err(err)
        };
        for (kind, colour) in KINDS {
            line(kind.to_owned(), colour, None, y)?;
            y += 24;
        }
        y += 12;
        for (k, words) in STYLES.iter().enumerate() {
            line((*words).to_owned(), RGBColor(0, 0, 0), dashes(k), y)?;
            y += 24;
        }
        y += 12;
        line(
            "linear unit's attenuation band edges".into(),
            RGBColor(60, 60, 60),
            Some((10, 6)),
            y,
        )?;
        y += 36;
        for class in RegimeClass::ALL {
            legend
                .draw(&Rectangle::new(
                    [(0, y), (22, y + 18)],
                    colour(class).mix(BACKGROUND_OPACITY).filled(),
                ))
                .map_err(err)?;
            legend
                .draw(&Text::new(class.words(), (30, y + 2), text(13)))
                .map_err(err)?;
            y += 24;
        }
        Ok(())
    }
}

impl Figure for BoundariesFigure {
    fn name(&self) -> &str {
        "boundaries"
    }

    fn size(&self) -> (u32, u32) {
        (1700, 1500)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let (plots, side) = root.split_horizontally(1300);
        let (top, bottom) = plots.split_vertically(750);
        self.gap_panel(&top)?;
        self.restitution_panel(&bottom)?;
        self.legend(&side)
    }
}
