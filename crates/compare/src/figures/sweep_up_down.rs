//! `sweep-up-down`: the single cell swept slowly up and down the paper's axis, the envelope of
//! its outer displacement per forcing cycle against the instantaneous frequency, up and down in
//! two colours and each sweep's jump marked, beside the steady states of the same cell (the
//! linear curve in closed form and the simulated motions from rest of the chain study's
//! one-cell chain).

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::chain::ChainCurve;
use crate::study::signals::{SweepStudy, JUMP_DROP_DB};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Colour of the sweep up.
const UP: RGBColor = RGBColor(0, 114, 178);
/// Colour of the sweep down.
const DOWN: RGBColor = RGBColor(213, 94, 0);
/// Colour of the linear curve.
const LINEAR: RGBColor = RGBColor(120, 120, 120);

/// `sweep-up-down`: the sweeps and, when the chain study has it, its one-cell curve.
#[derive(Debug, Clone)]
pub struct SweepUpDown<'a> {
    /// The sweeps.
    pub study: &'a SweepStudy,
    /// The chain study's curve of one cell (the same damped unit): its steady states.
    pub steady: Option<&'a ChainCurve>,
}

impl Figure for SweepUpDown<'_> {
    fn name(&self) -> &str {
        "sweep-up-down"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let s = self.study;
        let (w0, w1) = (s.up.from.min(s.up.to), s.up.from.max(s.up.to));
        let values = s.up.envelope.iter().chain(&s.down.envelope).map(|p| p.1);
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(t), b.max(t))
        });
        let (t0, t1) = if hi > lo {
            ((lo - 5.0).floor(), (hi + 5.0).ceil())
        } else {
            (-40.0, 40.0)
        };
        let clip = |t: f64| t.clamp(t0, t1);
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Linear sine sweep up and down, scene '{}': {w0}–{w1} rad/s at R = {} rad/s² \
                     ({:.0} s each way), A = {} m, from rest",
                    s.scene_name, s.rate, s.sweep_duration, s.amplitude
                ),
                text(21),
            )
            .margin(18)
            .x_label_area_size(50)
            .y_label_area_size(75)
            .build_cartesian_2d(w0..w1, t0..t1)
            .map_err(err)?;
        axes(
            &mut chart,
            "instantaneous frequency ω(t) (rad/s)",
            "T = 20 log10(max|u_o|/A) per forcing cycle (dB)",
            16,
        )?;
        if let Some(curve) = self.steady {
            chart
                .draw_series(LineSeries::new(
                    curve.linear.iter().map(|&(w, t)| (w, clip(t))),
                    LINEAR.stroke_width(2),
                ))
                .map_err(err)?
                .label("steady: linear (no stops, closed form)")
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], LINEAR.stroke_width(2))
                });
            chart
                .draw_series(curve.impacting.iter().filter_map(|p| {
                    p.transmittance_db
                        .map(|t| Cross::new((p.omega, clip(t)), 5, BLACK.stroke_width(2)))
                }))
                .map_err(err)?
                .label("steady: simulated from rest at fixed ω (chain study, 1 cell)")
                .legend(|(x, y)| Cross::new((x + 9, y), 5, BLACK.stroke_width(2)));
        }
        for (run, colour, name) in [(&s.up, UP, "up"), (&s.down, DOWN, "down")] {
            chart
                .draw_series(LineSeries::new(
                    run.envelope.iter().map(|&(w, t)| (w, clip(t))),
                    colour.stroke_width(2),
                ))
                .map_err(err)?
                .label(format!(
                    "sweep {name}, {} → {} rad/s ({} impacts)",
                    run.from, run.to, run.impacts
                ))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(3))
                });
            if let Some(jump) = run.jump {
                chart
                    .draw_series(DashedLineSeries::new(
                        [(jump, t0), (jump, t1)],
                        7,
                        5,
                        colour.stroke_width(1),
                    ))
                    .map_err(err)?
                    .label(format!(
                        "sweep {name} jumps at {jump:.3} rad/s ({JUMP_DROP_DB} dB below its peak)"
                    ))
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(1))
                    });
            }
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight, 14)
    }
}
