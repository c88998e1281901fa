//! The largest Lyapunov exponent of the motion from rest against frequency, beside the
//! simulated transmittance: bands of chaos against the bands of attenuation.

use crate::figures::plot::{axes, err, text, Figure};
use crate::study::chaos::ChaosSample;
use plotters::coord::Shift;
use plotters::prelude::*;
use rattle_event_driven::Regime as LyapunovRegime;

/// The figure's data.
#[derive(Debug, Clone)]
pub struct LyapunovFigure {
    /// Scene name, for the title.
    pub scene_name: String,
    /// The samples, ascending frequency.
    pub samples: Vec<ChaosSample>,
}

/// Marker colour of a sample: by regime for a motion that does not repeat, grey for a
/// periodic one (exponent from its multipliers).
fn colour(regime: Option<LyapunovRegime>) -> RGBColor {
    match regime {
        Some(LyapunovRegime::Chaotic) => RGBColor(205, 35, 35),
        Some(LyapunovRegime::QuasiPeriodic) => RGBColor(240, 120, 170),
        Some(LyapunovRegime::Unsettled) => RGBColor(120, 200, 220),
        None => RGBColor(110, 110, 110),
    }
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if lo.is_finite() && hi > lo {
        let pad = 0.05 * (hi - lo);
        (lo - pad, hi + pad)
    } else {
        (-1.0, 1.0)
    }
}

impl Figure for LyapunovFigure {
    fn name(&self) -> &str {
        "lyapunov"
    }

    fn size(&self) -> (u32, u32) {
        (1400, 1000)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let s = &self.samples;
        let (w0, w1) = range(s.iter().map(|p| p.omega));
        let (top, bottom) = root.split_vertically(480);
        let (t0, t1) = range(s.iter().filter_map(|p| p.transmittance_db));
        let mut chart = ChartBuilder::on(&top)
            .caption(
                format!(
                    "Simulated transmittance and largest Lyapunov exponent from rest, scene '{}'",
                    self.scene_name
                ),
                text(20),
            )
            .margin(20)
            .x_label_area_size(45)
            .y_label_area_size(75)
            .build_cartesian_2d(w0..w1, t0..t1)
            .map_err(err)?;
        axes(
            &mut chart,
            "base frequency ω (rad/s)",
            "transmittance T (dB)",
            18,
        )?;
        chart
            .draw_series(LineSeries::new(
                [(w0, 0.0), (w1, 0.0)],
                BLACK.mix(0.4).stroke_width(1),
            ))
            .map_err(err)?;
        chart
            .draw_series(s.iter().filter_map(|p| {
                p.transmittance_db
                    .map(|t| Circle::new((p.omega, t), 3, colour(p.chaos.regime).filled()))
            }))
            .map_err(err)?;
        let (l0, l1) = range(s.iter().flat_map(|p| {
            let l = p.chaos.largest_exponent.unwrap_or(f64::NAN);
            let u = p.chaos.uncertainty.unwrap_or(0.0);
            [l - u, l + u]
        }));
        let mut chart = ChartBuilder::on(&bottom)
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d(w0..w1, l0..l1)
            .map_err(err)?;
        axes(
            &mut chart,
            "base frequency ω (rad/s)",
            "largest Lyapunov exponent λ₁ (1/s)",
            18,
        )?;
        chart
            .draw_series(LineSeries::new(
                [(w0, 0.0), (w1, 0.0)],
                BLACK.mix(0.4).stroke_width(1),
            ))
            .map_err(err)?;
        chart
            .draw_series(s.iter().filter_map(|p| {
                let l = p.chaos.largest_exponent?;
                let u = p.chaos.uncertainty.unwrap_or(0.0);
                Some(PathElement::new(
                    vec![(p.omega, l - u), (p.omega, l + u)],
                    colour(p.chaos.regime).stroke_width(1),
                ))
            }))
            .map_err(err)?;
        chart
            .draw_series(s.iter().filter_map(|p| {
                let l = p.chaos.largest_exponent?;
                Some(Circle::new(
                    (p.omega, l),
                    3,
                    colour(p.chaos.regime).filled(),
                ))
            }))
            .map_err(err)?;
        for (i, (regime, words)) in [
            (Some(LyapunovRegime::Chaotic), "chaotic"),
            (Some(LyapunovRegime::QuasiPeriodic), "quasi-periodic"),
            (Some(LyapunovRegime::Unsettled), "not periodic, converging"),
            (None, "periodic (from its Floquet multipliers)"),
        ]
        .into_iter()
        .enumerate()
        {
            let y = 30 + 22 * i as i32;
            bottom
                .draw(&Circle::new((110, y), 5, colour(regime).filled()))
                .map_err(err)?;
            bottom
                .draw(&Text::new(words, (122, y - 8), text(14)))
                .map_err(err)?;
        }
        Ok(())
    }
}
