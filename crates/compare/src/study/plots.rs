//! The data of every figure, computed here; [`crate::figures`] only draws it.

use crate::runs::map::{Bandwidth, Map, MapGrid, MapPoint};
use crate::scene::analytic::{linear_displacements, orbit_state, AnalyticPoint};
use crate::scene::simulator::{Regime, SimulatedPoint};
use crate::verdict::{Class, ComparedPoint};
use rattle_event_driven::Regime as LyapunovRegime;

/// Samples `(t, u_o, u_i)` of a motion.
pub type Samples = Vec<(f64, f64, f64)>;

/// Samples per two forcing periods in the time-response figures: 400 resolve the fastest mode
/// of the paper's unit (ω₂/ω ≤ 5 on its figures) with 40 samples per oscillation.
pub const TIME_SAMPLES: usize = 400;

/// The paper's Figure 2: the linear steady state at a few frequencies.
#[derive(Debug, Clone)]
pub struct LinearTimeResponse {
    /// Scene name, for the title.
    pub scene_name: String,
    /// Gap `Δ` for the walls (0 without stops).
    pub gap: f64,
    /// One panel per frequency.
    pub panels: Vec<LinearPanel>,
}

/// One panel of [`LinearTimeResponse`].
#[derive(Debug, Clone)]
pub struct LinearPanel {
    /// Frequency, rad/s.
    pub omega: f64,
    /// Two forcing periods of `(t, u_o, u_i)`.
    pub samples: Samples,
    /// `X_o`.
    pub outer_amplitude: f64,
    /// `X_i`.
    pub inner_amplitude: f64,
}

/// Two forcing periods `[0, 2T]` of the linear steady state of `point`.
pub fn linear_samples(point: &AnalyticPoint) -> Samples {
    let period = std::f64::consts::TAU / point.omega;
    (0..=TIME_SAMPLES)
        .map(|k| {
            let t = 2.0 * period * k as f64 / TIME_SAMPLES as f64;
            let (uo, ui) = linear_displacements(&point.linear, point.omega, t);
            (t, uo, ui)
        })
        .collect()
}

/// Two forcing periods `[0, 2T]` of a two-impact orbit, from its side-1 impact.
pub fn orbit_samples(scene: &crate::scene::Scene, orbit: &rattle_analytic::Orbit) -> Samples {
    let period = std::f64::consts::TAU / orbit.omega;
    (0..=TIME_SAMPLES)
        .map(|k| {
            let t = 2.0 * period * k as f64 / TIME_SAMPLES as f64;
            let x = orbit_state(scene, orbit, t.rem_euclid(period));
            (t, x[0], x[1])
        })
        .collect()
}

/// One row of the paper's Figure 4.
#[derive(Debug, Clone)]
pub struct ImpactRow {
    /// Frequency, rad/s.
    pub omega: f64,
    /// Linear response over two periods.
    pub linear: Samples,
    /// Analytic viable orbit over two periods (time from a side-1 impact), if any.
    pub orbit: Option<Samples>,
    /// Simulated steady motion over two periods, on the same clock as `orbit` when there is
    /// one.
    pub simulated: Samples,
    /// What the right panel shows, in words.
    pub note: String,
}

/// The paper's Figure 4: the linear response beside the impacting steady state.
#[derive(Debug, Clone)]
pub struct ImpactTimeResponse {
    /// Scene name, for the title.
    pub scene_name: String,
    /// Gap `Δ` for the walls.
    pub gap: f64,
    /// One row per frequency.
    pub rows: Vec<ImpactRow>,
}

/// The paper's Figure 5 with the workbench's evidence.
#[derive(Debug, Clone)]
pub struct Transmittance {
    /// Scene name, for the title.
    pub scene_name: String,
    /// Analytic picture on a fine grid (linear and symmetric orbits).
    pub analytic: Vec<AnalyticPoint>,
    /// Simulated steady states from rest.
    pub simulated: Vec<SimulatedPoint>,
    /// The paper's claimed attenuation bands: `(from, to, label)`.
    pub claimed_bands: Vec<(f64, f64, String)>,
    /// The paper's claimed peaks and valleys: `(ω, label)`.
    pub claimed_marks: Vec<(f64, String)>,
}

/// Agreement of the two solvers against frequency.
#[derive(Debug, Clone)]
pub struct Agreement {
    /// Scene name, for the title.
    pub scene_name: String,
    /// Every frequency of the compared sweep.
    pub points: Vec<AgreementPoint>,
    /// The match tolerance, drawn as a line.
    pub tolerance: f64,
}

/// The paper's Figure 5 done completely: the linear curve, every continued branch (viable
/// stretches, stable or not) coloured by signature, the bifurcation events, and the simulated
/// points from rest.
#[derive(Debug, Clone)]
pub struct FrequencyResponse {
    /// Scene name, for the title.
    pub scene_name: String,
    /// `(ω, T)` of the linear steady state.
    pub linear: Vec<(f64, f64)>,
    /// Every viable stretch of every branch.
    pub stretches: Vec<Stretch>,
    /// Every event on a viable point: `(ω, T, kind)`.
    pub events: Vec<(f64, f64, &'static str)>,
    /// The simulated steady states from rest: `(ω, T, signature)` (`None` when not periodic
    /// with impacts).
    pub simulated: Vec<(f64, f64, Option<String>)>,
}

/// Consecutive viable points of one branch with one stability.
#[derive(Debug, Clone, PartialEq)]
pub struct Stretch {
    /// The branch's canonical signature.
    pub signature: String,
    /// Whether every point of the stretch is stable.
    pub stable: bool,
    /// `(ω, T)`.
    pub points: Vec<(f64, f64)>,
}

impl FrequencyResponse {
    /// The figure's data from the study's branches, analytic grid and compared sweep.
    pub fn new(
        scene_name: &str,
        analytic: &[AnalyticPoint],
        branches: &crate::runs::continuation::Branches,
        compared: &[ComparedPoint],
    ) -> Self {
        let mut stretches: Vec<Stretch> = Vec::new();
        for b in &branches.branches {
            let signature = b.signature.to_string();
            let mut current: Option<Stretch> = None;
            for p in &b.points {
                let keep = p.viable && p.transmittance_db.is_finite();
                match (&mut current, keep) {
                    (Some(s), true) if s.stable == p.stable => {
                        s.points.push((p.omega, p.transmittance_db))
                    }
                    (_, true) => {
                        // A change of stability: the new stretch starts where the old ends.
                        let mut points = Vec::new();
                        if let Some(s) = current.take() {
                            points.extend(s.points.last().copied());
                            stretches.push(s);
                        }
                        points.push((p.omega, p.transmittance_db));
                        current = Some(Stretch {
                            signature: signature.clone(),
                            stable: p.stable,
                            points,
                        });
                    }
                    (_, false) => stretches.extend(current.take()),
                }
            }
            stretches.extend(current);
        }
        Self {
            scene_name: scene_name.to_owned(),
            linear: analytic
                .iter()
                .filter(|p| p.linear.transmittance_db.is_finite())
                .map(|p| (p.omega, p.linear.transmittance_db))
                .collect(),
            stretches,
            events: branches
                .events
                .iter()
                .filter(|e| e.point.viable && e.point.transmittance_db.is_finite())
                .map(|e| (e.omega, e.point.transmittance_db, e.kind.name()))
                .collect(),
            simulated: compared
                .iter()
                .filter_map(|p| {
                    let t = p.from_rest.transmittance_db?;
                    Some((
                        p.analytic.omega,
                        t,
                        p.cross.signature.as_ref().map(|s| s.to_string()),
                    ))
                })
                .collect(),
        }
    }
}

/// One frequency of [`Agreement`].
#[derive(Debug, Clone, PartialEq)]
pub struct AgreementPoint {
    /// Frequency, rad/s.
    pub omega: f64,
    /// The verdict.
    pub class: Class,
    /// The simulated cycle's canonical signature, when periodic with impacts.
    pub signature: Option<String>,
    /// Largest relative difference from the analytic orbit of that signature.
    pub relative_difference: Option<f64>,
    /// Largest distance between the two solvers' Floquet multipliers.
    pub multiplier_difference: Option<f64>,
}

impl AgreementPoint {
    /// The point of `p`.
    pub fn of(p: &ComparedPoint) -> Self {
        Self {
            omega: p.analytic.omega,
            class: p.class.clone(),
            signature: p.cross.signature.as_ref().map(|s| s.to_string()),
            relative_difference: p.difference,
            multiplier_difference: p.cross.multiplier_difference,
        }
    }
}

/// One member of the two-impact family as drawn.
#[derive(Debug, Clone, Copy)]
pub struct Member {
    /// Fraction of the period between the impacts.
    pub beta: f64,
    /// `Δ*(β)/u_g`.
    pub gap_ratio: f64,
    /// No penetration, impacts from inside.
    pub viable: bool,
    /// Floquet multipliers inside the unit circle.
    pub stable: bool,
}

/// A simulated check of one family member.
#[derive(Debug, Clone, Copy)]
pub struct Confirmation {
    /// Frequency, rad/s.
    pub omega: f64,
    /// `Δ*(β)/u_g` used as the gap.
    pub gap_ratio: f64,
    /// `β` of the analytic member.
    pub beta: f64,
    /// Spacing of the simulated impacts over the period, if the simulation settled on two
    /// impacts per period.
    pub measured_beta: Option<f64>,
}

/// The two-impact family `Δ*(β)` for a few frequencies.
#[derive(Debug, Clone)]
pub struct BetaFamily {
    /// Scene name, for the title.
    pub scene_name: String,
    /// Restitution used.
    pub restitution: f64,
    /// Per frequency, the members on a grid of `β`.
    pub curves: Vec<(f64, Vec<Member>)>,
    /// Simulated confirmations.
    pub confirmations: Vec<Confirmation>,
    /// Nigm and Shabana's non-viable band `0 ≤ β ≤ bound`.
    pub non_viable_bound: f64,
}

/// Stroboscopic outer displacement against frequency, up and down, and the analytic orbits'.
#[derive(Debug, Clone)]
pub struct Bifurcation {
    /// Scene name, for the title.
    pub scene_name: String,
    /// Frequency range swept, rad/s.
    pub omega_range: (f64, f64),
    /// `(ω, u_o(kT))` of the upward sweep.
    pub up: Vec<(f64, f64)>,
    /// `(ω, u_o(kT))` of the downward sweep.
    pub down: Vec<(f64, f64)>,
    /// `(ω, u_o(kT), stable)` of the viable analytic orbits.
    pub analytic: Vec<(f64, f64, bool)>,
}

/// The frame of one panel of the bifurcation figure: a frequency range and a symmetric
/// displacement range `[-half_height, half_height]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BifurcationFrame {
    /// Frequency range shown, rad/s.
    pub omega_range: (f64, f64),
    /// Half the height of the displacement axis, m.
    pub half_height: f64,
}

/// Frequencies between the largest |u_o(kT)| of the sweeps (the primary resonance) and the
/// start of the detail panel, rad/s: far enough that the resonance's flanks, which rise as
/// 1/|ω − ω_r|, do not set the detail's scale.
const DETAIL_PAST_RESONANCE: f64 = 0.3;

impl Bifurcation {
    fn magnitudes(&self, omega: impl Fn(f64) -> bool) -> Vec<f64> {
        let mut mags: Vec<f64> = self
            .up
            .iter()
            .chain(&self.down)
            .map(|&(w, u)| (w, u))
            .chain(self.analytic.iter().map(|&(w, u, _)| (w, u)))
            .filter(|&(w, u)| omega(w) && u.is_finite())
            .map(|(_, u)| u.abs())
            .collect();
        mags.sort_by(f64::total_cmp);
        mags
    }

    /// The whole sweep, scaled to the bulk of its points (98th percentile of |u_o(kT)|): a few
    /// huge excursions at resonance would otherwise flatten everything else; they are clipped
    /// at the frame.
    pub fn whole_frame(&self) -> BifurcationFrame {
        let mags = self.magnitudes(|_| true);
        let bulk = mags.get(mags.len() * 98 / 100).copied().unwrap_or(1.0);
        BifurcationFrame {
            omega_range: self.omega_range,
            half_height: bulk.max(1e-3) * 1.2,
        }
    }

    /// The detail above the primary resonance, where the impacting orbits bifurcate: from
    /// `DETAIL_PAST_RESONANCE` (0.3 rad/s) above the frequency of the sweeps' largest |u_o(kT)| to the
    /// sweep's end, scaled to the largest |u_o(kT)| there. `None` when that leaves less than a
    /// tenth of the sweep.
    pub fn detail_frame(&self) -> Option<BifurcationFrame> {
        let (wmin, wmax) = self.omega_range;
        let peak = self
            .up
            .iter()
            .chain(&self.down)
            .filter(|p| p.1.is_finite())
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?
            .0;
        let start = peak + DETAIL_PAST_RESONANCE;
        if wmax - start < 0.1 * (wmax - wmin) {
            return None;
        }
        let top = self.magnitudes(|w| w >= start).last().copied()?;
        Some(BifurcationFrame {
            omega_range: (start, wmax),
            half_height: top.max(1e-3) * 1.1,
        })
    }
}

/// `u_o(kT)` (base phase 0) of a two-impact orbit.
pub fn stroboscopic_outer(scene: &crate::scene::Scene, orbit: &rattle_analytic::Orbit) -> f64 {
    let period = std::f64::consts::TAU / orbit.omega;
    // Time since the side-1 impact at which ω t + α ≡ 0.
    let t = (-orbit.alpha / orbit.omega).rem_euclid(period);
    orbit_state(scene, orbit, t)[0]
}

/// The attenuation of one `(e, Δ/u_g)` cell of the bandwidth map.
#[derive(Debug, Clone)]
pub struct BandwidthCell {
    /// Restitution.
    pub restitution: f64,
    /// `Δ/u_g`.
    pub gap_over_base_amplitude: f64,
    /// Simulated.
    pub simulated: Bandwidth,
    /// As the analytic candidates predict.
    pub analytic: Bandwidth,
}

/// The attenuation bandwidth over restitution and gap.
#[derive(Debug, Clone)]
pub struct BandwidthMap {
    /// Scene name, for the title.
    pub scene_name: String,
    /// The grid.
    pub grid: MapGrid,
    /// One cell per line of the map.
    pub cells: Vec<BandwidthCell>,
}

impl BandwidthMap {
    /// The figure's data from `map`.
    pub fn of(map: &Map) -> BandwidthMap {
        let step = map.grid.omega.step();
        BandwidthMap {
            scene_name: map.scene.name.clone(),
            grid: map.grid,
            cells: map
                .lines
                .iter()
                .map(|l| BandwidthCell {
                    restitution: l.x,
                    gap_over_base_amplitude: l.y,
                    simulated: l.simulated_bandwidth(step),
                    analytic: l.analytic_bandwidth(step),
                })
                .collect(),
        }
    }
}

/// The classes of the regime map, in legend order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RegimeClass {
    /// Periodic, no impact.
    NoImpact,
    /// Two impacts per period, period 1, and it is an attracting analytic candidate.
    TwoImpactAgreeing,
    /// Two impacts per period, period 1, but no attracting symmetric analytic orbit matches
    /// it (an asymmetric orbit, or one not yet within the match tolerance).
    TwoImpactOnly,
    /// Period 1 with another number or pattern of impacts.
    MoreImpacts,
    /// Periodic with period `p > 1`.
    Subharmonic,
    /// Not periodic within the cap, no exponents computed (or their run failed).
    Irregular,
    /// Not periodic, largest Lyapunov exponent positive beyond its uncertainty.
    Chaotic,
    /// Not periodic, largest exponent zero within its uncertainty.
    QuasiPeriodic,
    /// Not periodic within the cap, yet converging (largest exponent negative).
    Unsettled,
    /// Sticking on a stop in the final cycle.
    Sticking,
    /// Undamped and elastic: no steady state.
    NoDissipation,
    /// A solver failed.
    Failed,
}

impl RegimeClass {
    /// Every class, in legend order.
    pub const ALL: [RegimeClass; 12] = [
        RegimeClass::NoImpact,
        RegimeClass::TwoImpactAgreeing,
        RegimeClass::TwoImpactOnly,
        RegimeClass::MoreImpacts,
        RegimeClass::Subharmonic,
        RegimeClass::Irregular,
        RegimeClass::Chaotic,
        RegimeClass::QuasiPeriodic,
        RegimeClass::Unsettled,
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
            Some(Regime::Irregular) => match point.lyapunov_regime {
                Some(LyapunovRegime::Chaotic) => RegimeClass::Chaotic,
                Some(LyapunovRegime::QuasiPeriodic) => RegimeClass::QuasiPeriodic,
                Some(LyapunovRegime::Unsettled) => RegimeClass::Unsettled,
                None => RegimeClass::Irregular,
            },
            Some(Regime::Sticking) => RegimeClass::Sticking,
            Some(Regime::NoDissipation) => RegimeClass::NoDissipation,
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
            RegimeClass::Chaotic => "chaotic (largest Lyapunov exponent > 0)",
            RegimeClass::QuasiPeriodic => "quasi-periodic (largest exponent ≈ 0)",
            RegimeClass::Unsettled => "not periodic yet converging (exponent < 0)",
            RegimeClass::Sticking => "sticking",
            RegimeClass::NoDissipation => "no dissipation",
            RegimeClass::Failed => "solver failed",
        }
    }
}

/// One point of the regime map.
#[derive(Debug, Clone, Copy)]
pub struct RegimeCell {
    /// Frequency, rad/s.
    pub omega: f64,
    /// `Δ/u_g`.
    pub gap_over_base_amplitude: f64,
    /// Its class.
    pub class: RegimeClass,
}

/// The simulated regime over frequency and gap, at one restitution.
#[derive(Debug, Clone)]
pub struct RegimeMap {
    /// Scene name, for the title.
    pub scene_name: String,
    /// The grid.
    pub grid: MapGrid,
    /// The restitution of the map.
    pub restitution: f64,
    /// Every point.
    pub cells: Vec<RegimeCell>,
    /// Each class of [`RegimeClass::ALL`] with its share of the points, in `[0, 1]`.
    pub shares: Vec<(RegimeClass, f64)>,
}

impl RegimeMap {
    /// The figure's data from `map`.
    pub fn of(map: &Map) -> RegimeMap {
        let cells: Vec<RegimeCell> = map
            .lines
            .iter()
            .flat_map(|l| {
                l.points.iter().map(move |p| RegimeCell {
                    omega: p.omega,
                    gap_over_base_amplitude: l.y,
                    class: RegimeClass::of(p),
                })
            })
            .collect();
        let total = cells.len().max(1) as f64;
        let shares = RegimeClass::ALL
            .iter()
            .map(|&class| {
                let n = cells.iter().filter(|c| c.class == class).count();
                (class, n as f64 / total)
            })
            .collect();
        RegimeMap {
            scene_name: map.scene.name.clone(),
            grid: map.grid,
            restitution: map.lines.first().map_or(f64::NAN, |l| l.x),
            cells,
            shares,
        }
    }
}

/// Every figure's data.
#[derive(Debug, Clone)]
pub struct Plots {
    /// Figure 2.
    pub linear_time_response: LinearTimeResponse,
    /// Figure 4.
    pub impact_time_response: ImpactTimeResponse,
    /// Figure 5.
    pub transmittance: Transmittance,
    /// Agreement.
    pub agreement: Agreement,
    /// The complete frequency response (continued branches).
    pub frequency_response: FrequencyResponse,
    /// The β family.
    pub beta_family: BetaFamily,
    /// Bifurcation sweeps.
    pub bifurcation: Bifurcation,
    /// The maps, when the scene has stops.
    pub maps: Option<(BandwidthMap, RegimeMap)>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep(points: &[(f64, f64)]) -> Bifurcation {
        Bifurcation {
            scene_name: "test".into(),
            omega_range: (0.5, 4.0),
            up: points.to_vec(),
            down: Vec::new(),
            analytic: vec![(3.0, -0.25, true)],
        }
    }

    /// The detail panel starts `DETAIL_PAST_RESONANCE` above the sweep's largest |u_o(kT)| and
    /// is scaled to the largest |u_o(kT)| beyond that, the analytic points included (the last
    /// stop's 200-point sweep put its frame at ±37 m, squashing the 1–2 m detail above 1.7 rad/s).
    #[test]
    fn the_detail_frame_starts_past_the_resonance_and_fits_what_is_beyond() {
        let b = sweep(&[
            (1.0, 2.0),
            (1.4, -40.0),
            (1.6, 9.0),
            (2.0, 1.5),
            (3.5, -0.5),
        ]);
        let detail = b
            .detail_frame()
            .expect("3.5 rad/s of sweep beyond the resonance");
        assert_eq!(detail.omega_range, (1.4 + DETAIL_PAST_RESONANCE, 4.0));
        assert!((detail.half_height - 1.5 * 1.1).abs() < 1e-15);
        let whole = b.whole_frame();
        assert_eq!(whole.omega_range, (0.5, 4.0));
        assert!((whole.half_height - 40.0 * 1.2).abs() < 1e-12);
    }

    #[test]
    fn no_detail_frame_when_the_resonance_is_at_the_sweep_end() {
        let b = sweep(&[(1.0, 2.0), (3.9, 40.0)]);
        assert_eq!(b.detail_frame(), None);
    }
}
