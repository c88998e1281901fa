//! The chain figures: `chain-transmission` (the last cell's transmittance of chains of 1, 2,
//! 4 and 8 cells, linear and impacting, over the lattice's stop bands) and `chain-wave` (each
//! cell's outer amplitude along an 8-cell chain, in a pass band and in a stop band).

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::chain::ChainStudy;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Colour of the chain with `index` in the study's list of lengths.
fn colour(index: usize) -> RGBColor {
    const COLOURS: [RGBColor; 4] = [
        RGBColor(40, 40, 40),
        RGBColor(30, 110, 200),
        RGBColor(230, 130, 20),
        RGBColor(200, 40, 60),
    ];
    COLOURS[index % COLOURS.len()]
}

/// The stop-band shade.
const BAND: RGBColor = RGBColor(150, 200, 150);

/// `chain-transmission`.
#[derive(Debug, Clone)]
pub struct ChainTransmission<'a>(pub &'a ChainStudy);

/// `chain-wave`.
#[derive(Debug, Clone)]
pub struct ChainWave<'a>(pub &'a ChainStudy);

impl Figure for ChainTransmission<'_> {
    fn name(&self) -> &str {
        "chain-transmission"
    }

    fn size(&self) -> (u32, u32) {
        (1400, 1100)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let s = self.0;
        let (w0, w1) = s
            .curves
            .iter()
            .flat_map(|c| c.linear.iter().map(|p| p.0))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), w| {
                (a.min(w), b.max(w))
            });
        let (w0, w1) = if w1 > w0 { (w0, w1) } else { (0.0, 1.0) };
        let (t0, t1) = (-120.0, 40.0);
        let clip = |t: f64| t.clamp(t0, t1);
        let (top, bottom) = root.split_vertically(550);
        for (area, impacting) in [(&top, false), (&bottom, true)] {
            let title = if impacting {
                "impacting chains from rest (simulated)"
            } else {
                "linear chains (stops ignored, closed form)"
            };
            let mut chart = ChartBuilder::on(area)
                .caption(
                    format!(
                        "Last cell's transmittance of chains of N cells, scene '{}': {title}",
                        s.scene_name
                    ),
                    text(19),
                )
                .margin(18)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(w0..w1, t0..t1)
                .map_err(err)?;
            axes(
                &mut chart,
                "base frequency ω (rad/s)",
                "T = 20 log10(X_N/u_g) (dB)",
                16,
            )?;
            chart
                .draw_series(s.stop_bands.iter().map(|b| {
                    Rectangle::new(
                        [(b.lower.max(w0), t0), (b.upper.min(w1), t1)],
                        BAND.mix(0.35).filled(),
                    )
                }))
                .map_err(err)?
                .label("stop bands of the infinite lattice (undamped)")
                .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 16, y + 6)], BAND.filled()));
            chart
                .draw_series(LineSeries::new(
                    [(w0, 0.0), (w1, 0.0)],
                    BLACK.mix(0.4).stroke_width(1),
                ))
                .map_err(err)?;
            for (k, curve) in s.curves.iter().enumerate() {
                let c = colour(k);
                let label = format!("N = {}", curve.cells);
                if impacting {
                    chart
                        .draw_series(LineSeries::new(
                            curve.linear.iter().map(|&(w, t)| (w, clip(t))),
                            c.mix(0.25).stroke_width(1),
                        ))
                        .map_err(err)?;
                    chart
                        .draw_series(curve.impacting.iter().filter_map(|p| {
                            p.transmittance_db
                                .map(|t| Circle::new((p.omega, clip(t)), 3, c.filled()))
                        }))
                        .map_err(err)?
                        .label(format!("{label} (faint: its linear curve)"))
                        .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
                } else {
                    chart
                        .draw_series(LineSeries::new(
                            curve.linear.iter().map(|&(w, t)| (w, clip(t))),
                            c.stroke_width(2),
                        ))
                        .map_err(err)?
                        .label(label)
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2))
                        });
                }
            }
            legend(&mut chart, SeriesLabelPosition::LowerLeft, 14)?;
        }
        Ok(())
    }
}

impl Figure for ChainWave<'_> {
    fn name(&self) -> &str {
        "chain-wave"
    }

    fn size(&self) -> (u32, u32) {
        (1400, 650)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let s = self.0;
        let panels = root.split_evenly((1, s.waves.len().max(1)));
        for (area, wave) in panels.iter().zip(&s.waves) {
            let cells = wave.linear.len().max(wave.impacting.len()).max(1);
            let values = wave.linear.iter().chain(&wave.impacting).copied();
            let (lo, hi) = values
                .filter(|v| v.is_finite() && *v > 0.0)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(v), b.max(v))
                });
            let (lo, hi) = if hi > lo {
                (lo / 2.0, hi * 2.0)
            } else {
                (1e-3, 10.0)
            };
            let mut chart = ChartBuilder::on(area)
                .caption(
                    format!(
                        "ω = {} rad/s: lattice attenuation {:.3} per cell; from rest: {}",
                        wave.omega,
                        wave.lattice_attenuation,
                        wave.regime.unwrap_or("failed")
                    ),
                    text(16),
                )
                .margin(18)
                .x_label_area_size(45)
                .y_label_area_size(75)
                .build_cartesian_2d(0.5..cells as f64 + 0.5, (lo..hi).log_scale())
                .map_err(err)?;
            chart
                .configure_mesh()
                .x_labels(cells)
                .x_label_formatter(&|x| format!("{x:.0}"))
                .x_desc("cell j (from the base)")
                .y_desc("outer amplitude X_o,j (m)")
                .label_style(text(14))
                .axis_desc_style(text(16))
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(err)?;
            let at = |v: &[f64]| -> Vec<(f64, f64)> {
                v.iter()
                    .enumerate()
                    .filter(|(_, a)| a.is_finite() && **a > 0.0)
                    .map(|(j, &a)| (j as f64 + 1.0, a))
                    .collect()
            };
            let linear_colour = RGBColor(30, 110, 200);
            let impacting_colour = RGBColor(200, 40, 60);
            chart
                .draw_series(LineSeries::new(
                    at(&wave.linear),
                    linear_colour.stroke_width(2),
                ))
                .map_err(err)?
                .label("linear chain |U_o,j|")
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], linear_colour.stroke_width(2))
                });
            chart
                .draw_series(
                    at(&wave.impacting)
                        .into_iter()
                        .map(|p| Circle::new(p, 5, impacting_colour.filled())),
                )
                .map_err(err)?
                .label("impacting chain max|u_o,j|")
                .legend(move |(x, y)| Circle::new((x + 8, y), 4, impacting_colour.filled()));
            let decay: Vec<(f64, f64)> = at(&wave.lattice_decay)
                .into_iter()
                .filter(|p| p.1 > lo)
                .collect();
            chart
                .draw_series(DashedLineSeries::new(
                    decay,
                    6,
                    4,
                    BLACK.mix(0.6).stroke_width(1),
                ))
                .map_err(err)?
                .label("lattice: X_1 e^(−|Im q|(j − 1))")
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], BLACK.mix(0.6).stroke_width(1))
                });
            legend(&mut chart, SeriesLabelPosition::LowerLeft, 13)?;
        }
        Ok(())
    }
}
