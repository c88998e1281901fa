//! Accuracy against cost: error against the analytic orbit versus time per solve for the
//! event-driven simulator (over its root tolerance) and the Runge–Kutta baseline (over its
//! `rtol`), with the analytic solve as one point, and Siconos's event-driven and Moreau–Jean
//! schemes when their results are attached (`work-precision`); and the cost of reaching a
//! steady state and of sweeps (`steady-state-cost`).

use crate::figures::plot::{err, legend, text, Figure};
use crate::peers::siconos::{SiconosRun, SiconosWorkPrecision};
use crate::peers::work_precision::{PrecisionPoint, WorkPrecision, FAILURE_ERROR};
use crate::runs::sweep::Solver;
use plotters::coord::combinators::LogCoord;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Errors below this are drawn on it (the plot's floor).
const FLOOR: f64 = 1e-16;
/// Failed solves are drawn at this error, above the failure threshold.
const FAILED: f64 = 0.5;

const EVENT: RGBColor = RGBColor(30, 90, 220);
const BASELINE: RGBColor = RGBColor(220, 60, 30);
const SICONOS_EVENT: RGBColor = RGBColor(20, 150, 70);
const SICONOS_MOREAU_JEAN: RGBColor = RGBColor(150, 60, 170);

/// The work-precision chart's coordinates: log time against log error.
type LogLog = Cartesian2d<LogCoord<f64>, LogCoord<f64>>;

/// The polyline through `(time, error, knob)` points in `colour`, with its legend entry.
fn draw_line<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, LogLog>,
    points: &[(f64, f64, f64)],
    colour: RGBColor,
    label: String,
) -> Result<(), String> {
    chart
        .draw_series(LineSeries::new(
            points.iter().map(|&(t, e, _)| (t, e)),
            colour.stroke_width(2),
        ))
        .map_err(err)?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
    Ok(())
}

/// A Siconos run's point: (seconds, error of the outer amplitude), failures at [`FAILED`].
fn siconos_plotted(run: &SiconosRun, reference: f64) -> Option<(f64, f64)> {
    let seconds = run.seconds.filter(|t| t.is_finite() && *t > 0.0)?;
    Some(match run.relative_error(reference) {
        Some(e) if e <= FAILURE_ERROR => (seconds, e.max(FLOOR)),
        _ => (seconds, FAILED),
    })
}

/// Siconos's two schemes: each a line over its knob (squares), labelled with the knob,
/// failures as crosses at the top. Their error is the outer amplitude's alone.
fn draw_siconos<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, LogLog>,
    siconos: &SiconosWorkPrecision,
    reference: f64,
) -> Result<(), String> {
    let schemes = [
        (
            &siconos.event_driven,
            SICONOS_EVENT,
            "Siconos 4.4 event-driven (Lsodar, LCP), tolerance",
            "",
        ),
        (
            &siconos.moreau_jean,
            SICONOS_MOREAU_JEAN,
            "Siconos 4.4 Moreau–Jean (θ = 0.5, LCP), time step",
            " s",
        ),
    ];
    for (runs, colour, label, unit) in schemes {
        let ok: Vec<(f64, f64, f64)> = runs
            .iter()
            .filter_map(|r| siconos_plotted(r, reference).map(|(t, e)| (t, e, r.knob)))
            .filter(|p| p.1 < FAILED)
            .collect();
        let label = format!(
            "{label} {:.0e} … {:.0e}{unit} (error of X_o only; CPU time of its loop)",
            runs.first().map_or(f64::NAN, |r| r.knob),
            runs.last().map_or(f64::NAN, |r| r.knob)
        );
        draw_line(chart, &ok, colour, label)?;
        chart
            .draw_series(ok.iter().map(|&(t, e, _)| {
                Rectangle::new([(t / 1.08, e / 1.6), (t * 1.08, e * 1.6)], colour.filled())
            }))
            .map_err(err)?;
        chart
            .draw_series(ok.iter().map(|&(t, e, knob)| {
                Text::new(
                    format!("{knob:.0e}"),
                    (t * 1.1, e / 3.0),
                    text(13).color(&colour),
                )
            }))
            .map_err(err)?;
        chart
            .draw_series(
                runs.iter()
                    .filter_map(|r| siconos_plotted(r, reference))
                    .filter(|p| p.1 >= FAILED)
                    .map(|p| Cross::new(p, 7, colour.stroke_width(3))),
            )
            .map_err(err)?;
    }
    Ok(())
}

/// The work-precision figure.
pub struct WorkPrecisionFigure {
    /// The study.
    pub study: WorkPrecision,
}

fn plotted(p: &PrecisionPoint) -> (f64, f64) {
    match (p.failure.as_ref(), p.error()) {
        (None, Some(e)) => (p.seconds, e.max(FLOOR)),
        _ => (p.seconds, FAILED),
    }
}

fn time_range(points: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = points
        .filter(|t| t.is_finite() && *t > 0.0)
        .fold((f64::INFINITY, 0.0_f64), |(lo, hi), t| {
            (lo.min(t), hi.max(t))
        });
    if lo.is_finite() {
        (
            10f64.powf(lo.log10().floor()),
            10f64.powf(hi.log10().ceil()),
        )
    } else {
        (1e-6, 1.0)
    }
}

/// A log range around positive values, padded by a factor 1.5 each side.
fn padded_range(points: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = points
        .filter(|t| t.is_finite() && *t > 0.0)
        .fold((f64::INFINITY, 0.0_f64), |(lo, hi), t| {
            (lo.min(t), hi.max(t))
        });
    if lo.is_finite() {
        (lo / 1.5, hi * 1.5)
    } else {
        (1e-6, 1.0)
    }
}

/// The figure's title and the three lines that say what is measured.
fn draw_titles<DB: DrawingBackend>(
    title: &DrawingArea<DB, Shift>,
    s: &WorkPrecision,
) -> Result<(), String> {
    title
        .draw(&Text::new(
            format!(
                "Work–precision, scene '{}', ω = {} rad/s (stable two-impact orbit, max|μ| = {:.3})",
                s.scene_name,
                s.omega,
                s.orbit
                    .floquet_multipliers
                    .iter()
                    .map(|m| m.norm())
                    .fold(0.0, f64::max)
            ),
            (20, 10),
            text(24),
        ))
        .map_err(err)?;
    title
        .draw(&Text::new(
            format!(
                "Both integrators start from rest and run {} periods. Error: the largest relative difference from the analytic orbit over the last",
                s.periods
            ),
            (20, 45),
            text(15),
        ))
        .map_err(err)?;
    title
        .draw(&Text::new(
            "period (outer amplitude X_o, state just before the side-1 impact, impact phase/π). Times: minimum of repeated runs, one thread.",
            (20, 67),
            text(15),
        ))
        .map_err(err)?;
    title
        .draw(&Text::new(
            format!(
                "Failed solves (missed impact, other motion, error > {FAILURE_ERROR}) are drawn as crosses at the top."
            ),
            (20, 89),
            text(15),
        ))
        .map_err(err)?;
    Ok(())
}

/// Our two integrators: each a line over its knob (circles), labelled with the knob (one
/// stacked list where the points crowd), failures as crosses.
fn draw_ours<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, LogLog>,
    s: &WorkPrecision,
) -> Result<(), String> {
    let series = [
        (
            &s.event_driven,
            EVENT,
            "event-driven simulator, root tolerance",
        ),
        (
            &s.baseline,
            BASELINE,
            "Dormand–Prince 5(4) + event location on dense output, rtol",
        ),
    ];
    for (points, colour, label) in series {
        let ok: Vec<(f64, f64, f64)> = points
            .iter()
            .filter(|p| p.failure.is_none())
            .map(|p| {
                let (t, e) = plotted(p);
                (t, e, p.tolerance)
            })
            .collect();
        let label = format!(
            "{label} {:.0e} … {:.0e}",
            points.first().map_or(f64::NAN, |p| p.tolerance),
            points.last().map_or(f64::NAN, |p| p.tolerance)
        );
        draw_line(chart, &ok, colour, label)?;
        chart
            .draw_series(
                ok.iter()
                    .map(|&(t, e, _)| Circle::new((t, e), 5, colour.filled())),
            )
            .map_err(err)?;
        // Labels: the knob at each point; when the points crowd (the event-driven errors all
        // sit at rounding level), one stacked list to their left, where the plot is empty
        // (to their right it ran under the legend).
        let (t_lo, t_hi) = ok.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), p| {
            (lo.min(p.0), hi.max(p.0))
        });
        let crowded = (t_hi / t_lo).log10() < 0.5;
        let e_lo = ok.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let right_aligned = Pos::new(HPos::Right, VPos::Center);
        chart
            .draw_series(ok.iter().enumerate().map(|(k, &(t, e, tol))| {
                let (at, words, style) = if crowded {
                    (
                        (t_lo / 1.3, e_lo * 10f64.powf(1.0 + 0.4 * k as f64)),
                        format!("{tol:.0e}: error {e:.1e}"),
                        text(13).color(&colour).pos(right_aligned),
                    )
                } else {
                    ((t, e * 2.2), format!("{tol:.0e}"), text(13).color(&colour))
                };
                Text::new(words, at, style)
            }))
            .map_err(err)?;
        chart
            .draw_series(
                points
                    .iter()
                    .filter(|p| p.failure.is_some())
                    .map(|p| Cross::new(plotted(p), 7, colour.stroke_width(3))),
            )
            .map_err(err)?;
    }
    Ok(())
}

/// The analytic solve, and the legend entry of a failed solve.
fn draw_analytic<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, LogLog>,
    s: &WorkPrecision,
) -> Result<(), String> {
    // The analytic solve: one point, drawn at its difference from the most accurate
    // simulation (a bound on both).
    let floor = s
        .event_driven
        .iter()
        .filter_map(PrecisionPoint::error)
        .fold(f64::INFINITY, f64::min);
    let floor = if floor.is_finite() {
        floor.max(FLOOR)
    } else {
        FLOOR
    };
    chart
        .draw_series(std::iter::once(TriangleMarker::new(
            (s.analytic_seconds, floor),
            9,
            BLACK.filled(),
        )))
        .map_err(err)?
        .label(format!(
            "analytic orbit solve (the reference), {:.1} µs; drawn at its difference from the simulator",
            s.analytic_seconds * 1e6
        ))
        .legend(|(x, y)| TriangleMarker::new((x + 10, y), 7, BLACK.filled()));
    chart
        .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
        .map_err(err)?
        .label("failed solve (no two-impact motion in the last period, or error > 0.1)")
        .legend(|(x, y)| Cross::new((x + 10, y), 6, BLACK.stroke_width(2)));
    Ok(())
}

impl Figure for WorkPrecisionFigure {
    fn name(&self) -> &str {
        "work-precision"
    }

    fn size(&self) -> (u32, u32) {
        (1400, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let s = &self.study;
        let siconos_seconds = s.siconos.iter().flat_map(|wp| {
            wp.event_driven
                .iter()
                .chain(&wp.moreau_jean)
                .filter_map(|r| r.seconds)
        });
        let (tmin, tmax) = time_range(
            s.event_driven
                .iter()
                .chain(&s.baseline)
                .map(|p| p.seconds)
                .chain([s.analytic_seconds])
                .chain(siconos_seconds),
        );
        let (title, body) = root.split_vertically(112);
        draw_titles(&title, s)?;
        let mut chart = ChartBuilder::on(&body)
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(90)
            .build_cartesian_2d((tmin..tmax).log_scale(), (FLOOR..1.0).log_scale())
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("time per solve (s)")
            .y_desc("relative error against the analytic orbit")
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(text(18))
            .axis_desc_style(text(20))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(DashedLineSeries::new(
                vec![(tmin, FAILURE_ERROR), (tmax, FAILURE_ERROR)],
                8,
                5,
                RGBColor(150, 150, 150).stroke_width(1),
            ))
            .map_err(err)?;
        draw_ours(&mut chart, s)?;
        if let Some(siconos) = &s.siconos {
            draw_siconos(&mut chart, siconos, s.orbit.outer_amplitude)?;
        }
        draw_analytic(&mut chart, s)?;
        // Lower right (slow and accurate) is empty; Siconos's points sit top right.
        legend(&mut chart, SeriesLabelPosition::LowerRight, 15)?;
        Ok(())
    }
}

/// The steady-state and sweep cost figure.
pub struct SteadyStateCost {
    /// The study.
    pub study: WorkPrecision,
}

impl Figure for SteadyStateCost {
    fn name(&self) -> &str {
        "steady-state-cost"
    }

    fn size(&self) -> (u32, u32) {
        (1600, 800)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let s = &self.study;
        let (left, right) = root.split_horizontally(800);
        // Left: from rest to a steady state, against the periodicity tolerance.
        let tols: Vec<f64> = s.steady.iter().map(|c| c.periodicity_tolerance).collect();
        let lo = tols.iter().copied().fold(f64::INFINITY, f64::min) / 3.0;
        let hi = tols.iter().copied().fold(0.0, f64::max) * 3.0;
        let tmax = s
            .steady
            .iter()
            .map(|c| c.seconds * 1e3)
            .filter(|t| t.is_finite())
            .fold(0.0, f64::max)
            * 1.25;
        let tmax = if tmax > 0.0 { tmax } else { 1.0 };
        let mut chart = ChartBuilder::on(&left)
            .caption(
                format!(
                    "From rest to steady state, '{}', ω = {} rad/s (event-driven)",
                    s.scene_name, s.omega
                ),
                text(19),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(90)
            .build_cartesian_2d((lo..hi).log_scale(), 0.0..tmax)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("periodicity tolerance (stroboscopic repeat)")
            .y_desc("time (ms), minimum of repeats")
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.2}"))
            .label_style(text(16))
            .axis_desc_style(text(18))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        let pts: Vec<(f64, f64, String)> = s
            .steady
            .iter()
            .map(|c| {
                let periods = c
                    .periods_run
                    .map_or("not settled".to_owned(), |p| format!("{p} periods"));
                let error = c.error.map_or(String::new(), |e| format!(", err {e:.0e}"));
                (
                    c.periodicity_tolerance,
                    c.seconds * 1e3,
                    format!("{periods}{error}"),
                )
            })
            .collect();
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|p| (p.0, p.1)),
                EVENT.stroke_width(2),
            ))
            .map_err(err)?
            .label("time to settle from rest (labels: periods run, error vs analytic)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], EVENT.stroke_width(2)));
        chart
            .draw_series(
                pts.iter()
                    .map(|p| Circle::new((p.0, p.1), 5, EVENT.filled())),
            )
            .map_err(err)?;
        chart
            .draw_series(
                pts.iter()
                    .map(|p| Text::new(p.2.clone(), (p.0, p.1 + 0.04 * tmax), text(13))),
            )
            .map_err(err)?;
        legend(&mut chart, SeriesLabelPosition::LowerLeft, 14)?;

        // Right: sweep time against points.
        let max_points = s.sweeps.iter().map(|c| c.points).max().unwrap_or(10) as f64;
        let min_points = s.sweeps.iter().map(|c| c.points).min().unwrap_or(1) as f64;
        let (tmin, tmax) = padded_range(s.sweeps.iter().map(|c| c.seconds));
        let mut chart = ChartBuilder::on(&right)
            .caption(
                format!(
                    "Sweep cost, ω ∈ [{}, {}] rad/s, all threads (minimum of repeats)",
                    s.sweep_range.0, s.sweep_range.1
                ),
                text(19),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(90)
            .build_cartesian_2d(
                (min_points / 1.5..max_points * 1.5).log_scale(),
                (tmin..tmax).log_scale(),
            )
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("frequencies in the sweep")
            .y_desc("wall time (s)")
            .x_label_formatter(&|v| {
                let n = v.round() as i64;
                if [10, 20, 50, 100, 200, 500, 1000].contains(&n) {
                    format!("{n}")
                } else {
                    String::new()
                }
            })
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(text(16))
            .axis_desc_style(text(18))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        for (solver, colour, label) in [
            (
                Solver::Analytic,
                BLACK,
                "analytic (linear + symmetric orbits, viability, Floquet)",
            ),
            (
                Solver::Event,
                EVENT,
                "event-driven from rest to steady state (cap 4000 periods)",
            ),
        ] {
            let pts: Vec<(f64, f64)> = s
                .sweeps
                .iter()
                .filter(|c| c.solver == solver)
                .map(|c| (c.points as f64, c.seconds))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                .map_err(err)?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 5, colour.filled())))
                .map_err(err)?;
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft, 14)?;
        Ok(())
    }
}
