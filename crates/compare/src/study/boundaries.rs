//! The regime boundaries of the study's scene: every event of the study's own
//! continuation in ω ([`Study::branches`], no second continuation) followed over the gap and
//! over the restitution by [`follow_events`], the data files they are written to
//! (`data/boundaries/`), and the data of the `boundaries` figure.
//!
//! The study's continuation is of the scene as given (the paper's unit is undamped); the maps
//! drawn beneath the curves are of [`map_scene`](super::map_scene), the same unit with light
//! damping when the scene has none. The figure and the report say so.

use super::report::study_bands;
use super::Study;
use crate::output::{write_table, Format, Header};
use crate::runs::boundaries::{follow_events, rows, BoundariesRecord, EventFilter};
use crate::runs::map::Map;
use crate::runs::parallel::Progress;
use crate::scene::parameter::{Field, SceneParameter};
use crate::study::plots::{RegimeClass, RegimeMap};
use rattle_analytic::BoundarySettings;
use std::path::{Path, PathBuf};

/// The gaps the curves are followed over, m: 0.1–1 on the paper's unit (`u_g = 1`).
pub const GAP_RANGE: (f64, f64) = (0.1, 1.0);

/// The restitutions the curves are followed over (the note asks for 0.3–1).
pub const RESTITUTION_RANGE: (f64, f64) = (0.3, 1.0);

/// Cap on the points of a curve in each direction: the study follows every event of its
/// continuation (about a hundred on the paper's unit), so a curve that wanders (a
/// Neimark–Sacker curve winding through resonances, a cascade's doubling) is cut there
/// (`point-cap`) rather than costing the figures run seconds each.
pub const CURVE_POINTS: usize = 300;

/// The stage follows the events of orbits with at most this many impacts per cycle (`+-`,
/// `++-`, `+-+-`, `++--`, …) that bound a stable motion ([`EventFilter::stable_only`]); the
/// others (the long orbits of the doubling cascades, which cost the most and lie in the
/// thinnest slivers of the maps, and events between unstable orbits, which border nothing
/// the maps can show) are listed as skipped: following every event of the paper unit's
/// continuation costs minutes of CPU.
pub const MAX_IMPACTS: usize = 4;

/// Cap of [`CURVE_POINTS`] for `cargo xtask figures --quick`.
pub const QUICK_CURVE_POINTS: usize = 40;

/// The boundaries of a study over one parameter.
#[derive(Debug, Clone)]
pub struct ParamBoundaries {
    /// The parameter.
    pub param: SceneParameter,
    /// The curves and skipped events, or why none could be followed.
    pub record: Result<BoundariesRecord, String>,
}

/// The boundaries of a study over the gap and over the restitution.
#[derive(Debug, Clone)]
pub struct StudyBoundaries {
    /// Over `stops.gap` within [`GAP_RANGE`].
    pub gap: ParamBoundaries,
    /// Over `stops.restitution` within [`RESTITUTION_RANGE`].
    pub restitution: ParamBoundaries,
}

/// The curves of every event of `study`'s continuation over the gap and the restitution,
/// both parameters at once (each curve on rayon's threads): the result does not depend on
/// the thread count. `quick` caps each curve at [`QUICK_CURVE_POINTS`] points per direction,
/// else [`CURVE_POINTS`].
pub fn study_boundaries(study: &Study, quick: bool) -> StudyBoundaries {
    let follow = |field: Field, (min, max): (f64, f64)| {
        let param = SceneParameter { cell: None, field };
        let settings = BoundarySettings {
            omega_min: study.size.omega_min,
            omega_max: study.size.omega_max,
            max_points: if quick {
                QUICK_CURVE_POINTS
            } else {
                CURVE_POINTS
            },
            ..BoundarySettings::new(min, max)
        };
        let record = follow_events(
            &study.scene,
            &study.branches,
            &param,
            &settings,
            EventFilter {
                max_impacts: Some(MAX_IMPACTS),
                stable_only: true,
            },
            &Progress::hidden(),
        )
        .map_err(|e| e.to_string());
        ParamBoundaries { param, record }
    };
    let (gap, restitution) = rayon::join(
        || follow(Field::Gap, GAP_RANGE),
        || follow(Field::Restitution, RESTITUTION_RANGE),
    );
    StudyBoundaries { gap, restitution }
}

impl ParamBoundaries {
    /// The file stem of this parameter's data: `gap` or `restitution` (the field's last
    /// word).
    pub fn stem(&self) -> &'static str {
        let path = self.param.field.path();
        path.rsplit('.').next().unwrap_or(path)
    }
}

impl StudyBoundaries {
    /// Writes `DIR/gap.json`, `DIR/gap.csv`, `DIR/restitution.json` and
    /// `DIR/restitution.csv`: each JSON the document `rattle boundaries --json` prints, each
    /// CSV its points (one row per point with the curve's index, as `rattle boundaries --out
    /// F.csv`). Returns the files written; a parameter without a record writes nothing.
    ///
    /// # Errors
    /// A file that cannot be written, with its path.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>, String> {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let mut written = Vec::new();
        for b in [&self.gap, &self.restitution] {
            let Ok(record) = &b.record else { continue };
            let json = dir.join(format!("{}.json", b.stem()));
            let text = serde_json::to_string_pretty(record).map_err(|e| e.to_string())? + "\n";
            std::fs::write(&json, text).map_err(|e| format!("{}: {e}", json.display()))?;
            let csv = dir.join(format!("{}.csv", b.stem()));
            write_table(&csv, Format::Csv, &Header::default(), rows(record))
                .map_err(|e| e.to_string())?;
            written.extend([json, csv]);
        }
        Ok(written)
    }

    /// The `boundaries` figure's data: the curves of `study` over both parameters, the
    /// regime map of `maps` under the gap's curves and the bandwidth map's regimes on its
    /// gap line nearest the scene's gap under the restitution's.
    pub fn figure(&self, study: &Study, maps: Option<&(Map, Map)>) -> BoundariesFigure {
        let scene = &study.scene;
        let base = scene.unit_model().base_amplitude;
        let gap = scene.gap().unwrap_or(f64::NAN);
        let line = maps.and_then(|(bandwidth, _)| {
            let nearest = nearest_gap_line(bandwidth, gap / base)?;
            Some(RestitutionBackground {
                gap_over_base_amplitude: nearest,
                cells: bandwidth
                    .lines
                    .iter()
                    .filter(|l| l.y == nearest)
                    .flat_map(|l| {
                        l.points.iter().map(move |p| RestitutionCell {
                            omega: p.omega,
                            restitution: l.x,
                            class: RegimeClass::of(p),
                        })
                    })
                    .collect(),
                omega_step: bandwidth.grid.omega.step(),
                restitution_step: bandwidth.grid.restitution.step(),
                scene_name: bandwidth.scene.name.clone(),
            })
        });
        BoundariesFigure {
            scene_name: scene.name.clone(),
            gap,
            restitution: scene.stops.map_or(f64::NAN, |s| s.rigid_restitution()),
            omega_range: (study.size.omega_min, study.size.omega_max),
            regime_map: maps.map(|(_, regimes)| RegimeMap::of(regimes)),
            restitution_background: line,
            gap_curves: curves(&self.gap, base),
            restitution_curves: curves(&self.restitution, 1.0),
            linear_bands: study_bands(study)[0].clone(),
        }
    }
}

/// The `Δ/u_g` of the line of `map` nearest `gap_over_base_amplitude`.
fn nearest_gap_line(map: &Map, gap_over_base_amplitude: f64) -> Option<f64> {
    map.lines.iter().map(|l| l.y).min_by(|a, b| {
        (a - gap_over_base_amplitude)
            .abs()
            .total_cmp(&(b - gap_over_base_amplitude).abs())
    })
}

/// The curves of `b` as lines in (ω, parameter / `scale`).
fn curves(b: &ParamBoundaries, scale: f64) -> Vec<CurveLine> {
    let Ok(record) = &b.record else {
        return Vec::new();
    };
    record
        .curves
        .iter()
        .map(|c| CurveLine {
            kind: c.boundary.event,
            signature: c.boundary.signature.clone(),
            period: c.boundary.period,
            points: c
                .boundary
                .points
                .iter()
                .map(|p| (p.omega, p.param_value / scale))
                .collect(),
        })
        .collect()
}

/// One boundary curve, as drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveLine {
    /// The event kind (`fold`, `period-doubling`, …).
    pub kind: &'static str,
    /// The orbits' canonical signature.
    pub signature: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// `(ω, parameter)` along the curve.
    pub points: Vec<(f64, f64)>,
}

/// One cell of the bandwidth map on one gap line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestitutionCell {
    /// Frequency, rad/s.
    pub omega: f64,
    /// Restitution.
    pub restitution: f64,
    /// Its regime.
    pub class: RegimeClass,
}

/// The bandwidth map's regimes on its gap line nearest the scene's gap.
#[derive(Debug, Clone, PartialEq)]
pub struct RestitutionBackground {
    /// The line's `Δ/u_g`.
    pub gap_over_base_amplitude: f64,
    /// Every point of the line's restitutions.
    pub cells: Vec<RestitutionCell>,
    /// The map's frequency step, rad/s.
    pub omega_step: f64,
    /// The map's restitution step.
    pub restitution_step: f64,
    /// The map's scene (with light damping when the study's has none).
    pub scene_name: String,
}

/// The `boundaries` figure's data.
#[derive(Debug, Clone)]
pub struct BoundariesFigure {
    /// The study's scene name.
    pub scene_name: String,
    /// The scene's gap, m.
    pub gap: f64,
    /// The scene's restitution.
    pub restitution: f64,
    /// The study's frequencies, rad/s.
    pub omega_range: (f64, f64),
    /// Panel 1's background: the regime map over (ω, Δ/u_g).
    pub regime_map: Option<RegimeMap>,
    /// Panel 2's background.
    pub restitution_background: Option<RestitutionBackground>,
    /// The curves over the gap, as `(ω, Δ/u_g)`.
    pub gap_curves: Vec<CurveLine>,
    /// The curves over the restitution, as `(ω, e)`.
    pub restitution_curves: Vec<CurveLine>,
    /// The linear unit's attenuation bands, rad/s (the last may end at infinity).
    pub linear_bands: Vec<(f64, f64)>,
}

/// Every crossing of `curve` with the parameter value `v`: `(ω, curve)` interpolated linearly
/// between the two points that bracket `v` (the points lie at most one curve step apart,
/// far below the maps' frequency step).
fn crossings(curve: &CurveLine, v: f64) -> Vec<f64> {
    curve
        .points
        .windows(2)
        .filter_map(|pair| {
            let ((w0, p0), (w1, p1)) = (pair[0], pair[1]);
            let inside = (p0 - v) * (p1 - v) <= 0.0 && p0 != p1;
            inside.then(|| w0 + (w1 - w0) * (v - p0) / (p1 - p0))
        })
        .collect()
}

/// The curve of `curves` whose crossing of `v` lies nearest `omega`: `(|Δω|, ω there, curve)`.
fn nearest_curve(curves: &[CurveLine], v: f64, omega: f64) -> Option<(f64, f64, &CurveLine)> {
    curves
        .iter()
        .flat_map(|c| {
            crossings(c, v)
                .into_iter()
                .map(move |w| ((w - omega).abs(), w, c))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// How a band edge at `omega` relates to the curves at `v`: the curve it follows within
/// `resolution`, or the nearest one.
fn edge_words(curves: &[CurveLine], v: f64, omega: f64, resolution: f64) -> (String, bool) {
    if !omega.is_finite() {
        return (
            "∞ (the band reaches the map's last frequency)".into(),
            false,
        );
    }
    match nearest_curve(curves, v, omega) {
        Some((d, w, c)) if d <= resolution => (
            format!(
                "{omega:.3}: follows the {} of `{}` (ω = {w:.3})",
                c.kind, c.signature
            ),
            true,
        ),
        Some((d, w, c)) => (
            format!(
                "{omega:.3}: none (nearest the {} of `{}` at ω = {w:.3}, {d:.3} away)",
                c.kind, c.signature
            ),
            false,
        ),
        None => (format!("{omega:.3}: none (no curve crosses here)"), false),
    }
}

/// The counts of curves by kind, e.g. `3 fold, 2 grazing`.
fn kind_counts(record: &BoundariesRecord) -> String {
    let mut kinds: Vec<(&str, usize)> = Vec::new();
    for c in &record.curves {
        match kinds.iter_mut().find(|(k, _)| *k == c.boundary.event) {
            Some(entry) => entry.1 += 1,
            None => kinds.push((c.boundary.event, 1)),
        }
    }
    kinds
        .iter()
        .map(|(k, n)| format!("{n} {k}"))
        .collect::<Vec<_>>()
        .join(", ")
}

impl StudyBoundaries {
    /// The report's section on the boundaries: the curves by kind over each parameter, and
    /// for the first attenuation band of each line of the bandwidth map of `maps` that a
    /// parameter's curves reach (the scene's restitution over the gap; the gap line nearest
    /// the scene's over the restitution), which curve each edge follows within the map's
    /// frequency step.
    pub fn section(&self, study: &Study, maps: Option<&(Map, Map)>) -> String {
        use std::fmt::Write as _;
        let mut out = String::from("\n## Regime boundaries (issue #23)\n\n");
        let _ = writeln!(
            out,
            "Every event of the study's continuation in ω (figures/frequency-response) followed \
             in (ω, gap) over Δ ∈ [{}, {}] m and in (ω, e) over e ∈ [{}, {}] (figures/boundaries, \
             data/boundaries/; each curve at most {CURVE_POINTS} points each way, `point-cap` \
             where cut). The curves are of the scene as given ('{}', undamped for the paper's \
             unit); the maps beneath them and below are of the same unit with light damping.\n",
            GAP_RANGE.0, GAP_RANGE.1, RESTITUTION_RANGE.0, RESTITUTION_RANGE.1, study.scene.name
        );
        for b in [&self.gap, &self.restitution] {
            match &b.record {
                Ok(r) => {
                    let filtered = r
                        .skipped
                        .iter()
                        .filter(|s| s.reason.contains("not followed"))
                        .count();
                    let _ = writeln!(
                        out,
                        "- over `{}`: {} events, {} curves ({}); {} events on a curve already \
                         listed; {} skipped ({} of orbits with more than {MAX_IMPACTS} impacts \
                         per cycle or bounding no stable motion: not followed by this stage; {} \
                         whose curve failed).",
                        r.param,
                        r.events,
                        r.curves.len(),
                        kind_counts(r),
                        r.curves
                            .iter()
                            .map(|c| c.same_as_events.len())
                            .sum::<usize>(),
                        r.skipped.len(),
                        filtered,
                        r.skipped.len() - filtered,
                    );
                }
                Err(e) => {
                    let _ = writeln!(out, "- over `{}`: none followed: {e}", b.param);
                }
            }
        }
        if let Some(maps) = maps {
            self.band_edges(&mut out, study, maps);
        }
        out
    }

    /// The table of the first attenuation band's edges against the curves.
    fn band_edges(&self, out: &mut String, study: &Study, (bandwidth, _): &(Map, Map)) {
        use std::fmt::Write as _;
        let figure = self.figure(study, None);
        let step = bandwidth.grid.omega.step();
        let base = study.scene.unit_model().base_amplitude;
        let e_scene = figure.restitution;
        let g_line = nearest_gap_line(bandwidth, figure.gap / base).unwrap_or(f64::NAN);
        let _ = writeln!(
            out,
            "\nThe first attenuation band (simulated from rest, T < 0 dB) of each line of the \
             bandwidth map the curves reach, its edges against the curves' ω at the line's \
             parameter value (\"follows\": within the map's frequency step {step:.3} rad/s). The \
             restitution curves are at Δ = {} m, the map's nearest line at Δ/u_g = {g_line:.4}.\n",
            figure.gap
        );
        let _ = writeln!(
            out,
            "| line | first band (rad/s) | lower edge | upper edge |\n| --- | --- | --- | --- |"
        );
        let (mut followed, mut edges) = (0, 0);
        // Lines whose first band opens above the paper's start, and those where it closes.
        let (mut late, mut closed, mut lines) = (0, 0, 0);
        let claimed = super::paper::IMPACTING_BAND;
        for line in &bandwidth.lines {
            let (g, e) = (line.y, line.x);
            let (curves, v, label) = if e == e_scene {
                (&figure.gap_curves, g, format!("e = {e}, Δ/u_g = {g:.4}"))
            } else if g == g_line && e >= RESTITUTION_RANGE.0 {
                (
                    &figure.restitution_curves,
                    e,
                    format!("Δ/u_g = {g:.4}, e = {e:.1}"),
                )
            } else {
                continue;
            };
            let Some(&(lo, hi)) = line.simulated_bandwidth(step).bands.first() else {
                let _ = writeln!(out, "| {label} | none | | |");
                continue;
            };
            let (low, a) = edge_words(curves, v, lo, step);
            let (high, b) = edge_words(curves, v, hi, step);
            followed += usize::from(a) + usize::from(b);
            lines += 1;
            late += usize::from(lo > claimed.0 + super::paper::read_off::BAND_START);
            closed += usize::from(hi.is_finite());
            edges += 1 + usize::from(hi.is_finite());
            let _ = writeln!(out, "| {label} | {lo:.3}–{hi:.3} | {low} | {high} |");
        }
        let _ = writeln!(
            out,
            "\n{followed} of the {edges} finite edges follow a curve within the map's step.\n"
        );
        if late + closed > 0 {
            let _ = writeln!(
                out,
                "**A finding against the paper** (\"attenuation from {} rad/s to ∞ with no \
                 transmission band inside\"): on {late} of these {lines} lines the first band opens \
                 later than {} rad/s, and on {closed} it closes at a finite frequency, the unit \
                 transmitting again above it.\n",
                claimed.0, claimed.0
            );
        }
    }
}
