//! The paper's Figure 5: transmittance against frequency — linear, analytic two-impact orbits
//! by verdict, and the simulated steady state from rest by regime; the paper's claims marked.

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::scene::simulator::Regime;
use crate::study::plots::Transmittance;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

const T_MIN: f64 = -45.0;
const T_MAX: f64 = 35.0;

fn clamp(t: f64) -> f64 {
    t.clamp(T_MIN, T_MAX)
}

/// Marker colour of a simulated regime.
pub fn regime_colour(regime: Regime) -> RGBColor {
    match regime {
        Regime::NoImpact => RGBColor(0, 130, 0),
        Regime::TwoImpact => RGBColor(0, 0, 0),
        Regime::MoreImpacts => RGBColor(230, 120, 0),
        Regime::Subharmonic => RGBColor(160, 0, 160),
        Regime::Irregular => RGBColor(200, 0, 0),
        Regime::Sticking => RGBColor(0, 150, 200),
        Regime::NoDissipation => RGBColor(150, 150, 150),
    }
}

impl Figure for Transmittance {
    fn name(&self) -> &str {
        "transmittance"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let wmin = self.analytic.first().map_or(0.0, |p| p.omega);
        let wmax = self.analytic.last().map_or(4.0, |p| p.omega);
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Transmittance T = 20 log10(X_o/u_g), scene '{}'",
                    self.scene_name
                ),
                text(28),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d(wmin..wmax, T_MIN..T_MAX)
            .map_err(err)?;
        axes(
            &mut chart,
            "base frequency ω (rad/s)",
            "transmittance T (dB)",
            18,
        )?;
        self.draw_claims(&mut chart, wmax)?;
        self.draw_linear(&mut chart, wmin, wmax)?;
        self.draw_orbits(&mut chart)?;
        self.draw_simulated(&mut chart)?;
        legend(&mut chart, SeriesLabelPosition::LowerLeft, 15)?;
        Ok(())
    }
}

/// The chart of the figure: frequency against transmittance.
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

impl Transmittance {
    /// The paper's claimed attenuation bands and its marked frequencies.
    fn draw_claims<DB: DrawingBackend>(
        &self,
        chart: &mut Chart<'_, DB>,
        wmax: f64,
    ) -> Result<(), String> {
        // The paper's claimed attenuation bands.
        for (i, (from, to, label)) in self.claimed_bands.iter().enumerate() {
            let (y0, y1) = (T_MAX - 4.0 - 3.0 * i as f64, T_MAX - 1.5 - 3.0 * i as f64);
            let colour = if label.contains("impact") {
                RGBColor(200, 60, 60)
            } else {
                RGBColor(60, 60, 200)
            };
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(*from, y0), (to.min(wmax), y1)],
                    colour.mix(0.35).filled(),
                )))
                .map_err(err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    label.clone(),
                    (*from + 0.02, y1 - 0.3),
                    text(14),
                )))
                .map_err(err)?;
        }
        for (w, label) in &self.claimed_marks {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(*w, T_MIN), (*w, T_MAX - 10.0)],
                    3,
                    5,
                    RGBColor(100, 100, 100).stroke_width(1),
                ))
                .map_err(err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    label.clone(),
                    (*w + 0.015, T_MIN + 2.0),
                    text(14),
                )))
                .map_err(err)?;
        }
        Ok(())
    }

    /// The 0 dB line and the linear unit, in contiguous runs of finite values.
    fn draw_linear<DB: DrawingBackend>(
        &self,
        chart: &mut Chart<'_, DB>,
        wmin: f64,
        wmax: f64,
    ) -> Result<(), String> {
        // 0 dB.
        chart
            .draw_series(LineSeries::new(
                vec![(wmin, 0.0), (wmax, 0.0)],
                BLACK.stroke_width(1),
            ))
            .map_err(err)?;
        // Linear unit: contiguous runs of finite values.
        let blue = RGBColor(30, 90, 220);
        let mut run: Vec<(f64, f64)> = Vec::new();
        let mut first = true;
        let mut flush = |run: &mut Vec<(f64, f64)>,
                         chart: &mut ChartContext<'_, DB, _>|
         -> Result<(), String> {
            if run.len() > 1 {
                let s = chart
                    .draw_series(LineSeries::new(run.clone(), blue.stroke_width(2)))
                    .map_err(err)?;
                if first {
                    s.label("linear unit (no stops)").legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], blue.stroke_width(2))
                    });
                    first = false;
                }
            }
            run.clear();
            Ok(())
        };
        for p in &self.analytic {
            if p.linear.transmittance_db.is_finite() {
                run.push((p.omega, clamp(p.linear.transmittance_db)));
            } else {
                flush(&mut run, chart)?;
            }
        }
        flush(&mut run, chart)?;
        Ok(())
    }

    /// The analytic symmetric two-impact orbits, segment by segment, by verdict.
    fn draw_orbits<DB: DrawingBackend>(&self, chart: &mut Chart<'_, DB>) -> Result<(), String> {
        // Analytic two-impact orbits: symmetric branches, segment by segment.
        let stable = RGBColor(0, 0, 0);
        let mut labelled = [false; 3];
        for branch in 0..2 {
            let pts: Vec<(f64, Option<&rattle_analytic::Orbit>)> = self
                .analytic
                .iter()
                .map(|p| {
                    (
                        p.omega,
                        p.orbits
                            .iter()
                            .find(|(b, o)| *b == branch && o.beta == 0.5)
                            .map(|(_, o)| o),
                    )
                })
                .collect();
            for w in pts.windows(2) {
                let (Some(a), Some(b)) = (w[0].1, w[1].1) else {
                    continue;
                };
                if (a.transmittance_db - b.transmittance_db).abs() > 3.0 {
                    continue;
                }
                let seg = vec![
                    (w[0].0, clamp(a.transmittance_db)),
                    (w[1].0, clamp(b.transmittance_db)),
                ];
                let kind = if !(a.viable && b.viable) {
                    2
                } else if a.stable && b.stable {
                    0
                } else {
                    1
                };
                let labels = [
                    "two-impact orbit: viable, stable",
                    "two-impact orbit: viable, unstable",
                    "two-impact orbit: not viable",
                ];
                let series = match kind {
                    0 => chart
                        .draw_series(LineSeries::new(seg, stable.stroke_width(3)))
                        .map_err(err)?,
                    1 => chart
                        .draw_series(DashedLineSeries::new(seg, 6, 5, stable.stroke_width(2)))
                        .map_err(err)?,
                    _ => chart
                        .draw_series(LineSeries::new(
                            seg,
                            RGBColor(160, 160, 160).mix(0.6).stroke_width(1),
                        ))
                        .map_err(err)?,
                };
                if !labelled[kind] {
                    labelled[kind] = true;
                    series.label(labels[kind]).legend(move |(x, y)| match kind {
                        0 => PathElement::new(vec![(x, y), (x + 20, y)], stable.stroke_width(3)),
                        1 => PathElement::new(vec![(x, y), (x + 8, y)], stable.stroke_width(2)),
                        _ => PathElement::new(
                            vec![(x, y), (x + 20, y)],
                            RGBColor(160, 160, 160).stroke_width(1),
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// The simulated steady states from rest, by regime.
    fn draw_simulated<DB: DrawingBackend>(&self, chart: &mut Chart<'_, DB>) -> Result<(), String> {
        // Simulated steady states from rest.
        let mut seen: Vec<Regime> = Vec::new();
        for p in &self.simulated {
            let Some(t) = p.transmittance_db.filter(|t| t.is_finite()) else {
                continue;
            };
            let colour = regime_colour(p.regime);
            let series = chart
                .draw_series(std::iter::once(Circle::new(
                    (p.omega, clamp(t)),
                    3,
                    colour.filled(),
                )))
                .map_err(err)?;
            if !seen.contains(&p.regime) {
                seen.push(p.regime);
                series
                    .label(format!("simulated from rest: {}", p.regime.words()))
                    .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
            }
        }
        Ok(())
    }
}
