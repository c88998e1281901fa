//! Frequency sweeps: one solver or both at every frequency, in parallel, in frequency order;
//! each point one [`SweepRow`].

use crate::output::{finite, number_list, table_row, Header};
use crate::runs::parallel::{for_each_ordered, parallel_map, Grain, Progress};
use crate::runs::shard::Shard;
use crate::scene::analytic::{analyse, AnalyticPoint, OrbitSearch};
use crate::scene::lyapunov::{chaos, SWEEP_LYAPUNOV_PERIODS};
use crate::scene::simulator::{run, SimulatedPoint};
use crate::scene::Scene;
use crate::verdict::chain::{chain_cross_check, ChainCheck};
use crate::verdict::{compare, Class, ComparedPoint, Starts};
use rattle_event_driven::SimulationOptions;

/// Which solver a sweep runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Solver {
    /// The closed-form solver: linear steady state and symmetric two-impact orbits (on a
    /// chain: the linear chain).
    Analytic,
    /// The event-driven simulator from rest.
    Event,
    /// Both: the simulator from rest beside the analytic orbit of its signature (any
    /// signature), the simulator also started on every viable symmetric orbit, and a verdict.
    /// On a chain: the linear chain, and the verdict of `rattle compare` on the chain.
    Both,
}

impl Solver {
    /// The solver's name as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Solver::Analytic => "analytic",
            Solver::Event => "event",
            Solver::Both => "both",
        }
    }

    pub(crate) fn grain(self) -> Grain {
        match self {
            Solver::Analytic => Grain::Even,
            Solver::Event | Solver::Both => Grain::Uneven,
        }
    }
}

/// The result at one frequency of a sweep.
#[derive(Debug, Clone)]
pub enum SweepPoint {
    /// Analytic only.
    Analytic(AnalyticPoint),
    /// Simulator only.
    Event(SimulatedPoint),
    /// Both and the verdict.
    Both(Box<ComparedPoint>),
    /// Both on a chain: the linear chain and the chain's verdict, as `rattle compare` gives it.
    Chain {
        /// The linear chain (no orbits: a chain's orbits are those of its simulated sequence).
        analytic: AnalyticPoint,
        /// The simulated cycle beside the analytic orbit of its impact sequence.
        check: Box<ChainCheck>,
    },
    /// This frequency failed; the message says why.
    Failed {
        /// The frequency.
        omega: f64,
        /// Why.
        message: String,
    },
}

/// One frequency with `solver`.
pub fn point(scene: &Scene, omega: f64, solver: Solver, options: &SimulationOptions) -> SweepPoint {
    let failed = |message: String| SweepPoint::Failed { omega, message };
    match solver {
        Solver::Analytic => analyse(scene, omega, OrbitSearch::Symmetric)
            .map(SweepPoint::Analytic)
            .unwrap_or_else(|e| failed(e.to_string())),
        Solver::Event => run(scene, omega, &crate::scene::simulator::rest(scene), options)
            .map(SweepPoint::Event)
            .unwrap_or_else(|e| failed(e.to_string())),
        Solver::Both if scene.is_chain() => chain_point(scene, omega, options),
        Solver::Both => compare(scene, omega, options, Starts::RestAndOrbits)
            .map(|c| SweepPoint::Both(Box::new(c)))
            .unwrap_or_else(|e| failed(e.to_string())),
    }
}

/// Both solvers on the chain `scene` at `omega`: the linear chain beside the verdict of
/// `rattle compare` ([`chain_cross_check`]).
fn chain_point(scene: &Scene, omega: f64, options: &SimulationOptions) -> SweepPoint {
    let analytic = match analyse(scene, omega, OrbitSearch::Symmetric) {
        Ok(a) => a,
        Err(e) => {
            return SweepPoint::Failed {
                omega,
                message: format!("analytic: {e}"),
            }
        }
    };
    match chain_cross_check(scene, omega, options) {
        Ok(check) => SweepPoint::Chain {
            analytic,
            check: Box::new(check),
        },
        Err(e) => SweepPoint::Failed {
            omega,
            message: e.to_string(),
        },
    }
}

/// `solver` on `scene` at every frequency of `omegas`, in parallel, in order.
pub fn sweep(
    scene: &Scene,
    omegas: &[f64],
    solver: Solver,
    options: &SimulationOptions,
    progress: &Progress,
) -> Vec<SweepPoint> {
    parallel_map(omegas, solver.grain(), progress, |&omega| {
        point(scene, omega, solver, options)
    })
}

/// [`sweep`], each point's row handed to `sink` in frequency order as soon as its block of
/// frequencies is done: memory holds one block, whatever the number of frequencies.
///
/// # Errors
/// The first error of `sink`.
pub fn sweep_rows<E>(
    scene: &Scene,
    omegas: &[f64],
    solver: Solver,
    options: &SimulationOptions,
    progress: &Progress,
    sink: impl FnMut(SweepRow) -> Result<(), E>,
) -> Result<(), E> {
    for_each_ordered(
        omegas,
        solver.grain(),
        progress,
        |&omega| {
            let p = point(scene, omega, solver, options);
            let mut row = SweepRow::new(scene, &p);
            row.set_chaos(scene, &p, options);
            row
        },
        sink,
    )
}

table_row! {
    /// One frequency of a sweep. A cell is empty (CSV) or `null` (JSON) where it does not
    /// apply to the solver, or is not finite.
    pub struct SweepRow {
        /// Angular frequency, rad/s.
        pub omega: Option<f64>,
        /// Linear `X_o`, m (`null` at an undamped resonance).
        pub linear_outer_amplitude: Option<f64>,
        /// Linear `T`, dB.
        pub linear_transmittance_db: Option<f64>,
        /// Whether the linear motion reaches the stops (of a chain: any cell's).
        pub linear_touches_stops: Option<bool>,
        /// Linear `max|u_o,j|` of every cell, from the base out, m: a list, `;`-separated
        /// ([`number_list`]; one element for a single unit).
        pub linear_cell_outer_amplitudes: Option<String>,
        /// Symmetric two-impact orbits found (0, 1 or 2).
        pub orbits: Option<usize>,
        /// Of which stable and viable.
        pub stable_viable_orbits: Option<usize>,
        /// Branch 0: base phase at the side-1 impact, rad.
        pub branch0_alpha: Option<f64>,
        /// Branch 0: `X_o`, m.
        pub branch0_outer_amplitude: Option<f64>,
        /// Branch 0: `T`, dB.
        pub branch0_transmittance_db: Option<f64>,
        /// Branch 0: viable.
        pub branch0_viable: Option<bool>,
        /// Branch 0: stable.
        pub branch0_stable: Option<bool>,
        /// Branch 1: base phase at the side-1 impact, rad.
        pub branch1_alpha: Option<f64>,
        /// Branch 1: `X_o`, m.
        pub branch1_outer_amplitude: Option<f64>,
        /// Branch 1: `T`, dB.
        pub branch1_transmittance_db: Option<f64>,
        /// Branch 1: viable.
        pub branch1_viable: Option<bool>,
        /// Branch 1: stable.
        pub branch1_stable: Option<bool>,
        /// Simulated regime from rest.
        pub simulated_regime: Option<&'static str>,
        /// Simulator status (`periodic`, `non-periodic`, `no-dissipation`, `, sticking`).
        pub simulated_status: Option<String>,
        /// Least period, forcing periods.
        pub simulated_period: Option<u32>,
        /// Impacts per forcing period over the final cycle (of a chain: all pairs').
        pub simulated_impacts_per_period: Option<f64>,
        /// Impacts per forcing period of each contact pair, from the base out: a list,
        /// `;`-separated ([`number_list`]; empty without stops).
        pub simulated_pair_impacts_per_period: Option<String>,
        /// Simulated `X_o`, m (of a chain: the last cell's).
        pub simulated_outer_amplitude: Option<f64>,
        /// Simulated `max|u_o,j|` of every cell, from the base out, m: a list, `;`-separated
        /// ([`number_list`]).
        pub simulated_cell_outer_amplitudes: Option<String>,
        /// Simulated `T`, dB.
        pub simulated_transmittance_db: Option<f64>,
        /// Whether the final cycle sticks.
        pub simulated_sticking: Option<bool>,
        /// The simulated cycle's canonical impact signature (periodic, polished by Newton).
        pub simulated_signature: Option<String>,
        /// The largest Lyapunov exponent of the simulated motion, 1/s ([`crate::scene::lyapunov::Chaos`]).
        pub largest_exponent: Option<f64>,
        /// Its uncertainty, 1/s.
        pub largest_exponent_uncertainty: Option<f64>,
        /// A non-periodic motion's regime: `chaotic`, `quasi-periodic` or `unsettled`.
        pub lyapunov_regime: Option<&'static str>,
        /// `X_o` of the analytic orbit of the simulated signature (`--solver both`; of a chain,
        /// of its impact sequence, the last cell's), m.
        pub analytic_outer_amplitude: Option<f64>,
        /// That orbit's `max|u_o,j|` of every cell, from the base out, m: a list,
        /// `;`-separated ([`number_list`]).
        pub analytic_cell_outer_amplitudes: Option<String>,
        /// Whether that analytic orbit is viable.
        pub analytic_viable: Option<bool>,
        /// Whether that analytic orbit is stable.
        pub analytic_stable: Option<bool>,
        /// Its energy balance residual, relative.
        pub analytic_energy_residual: Option<f64>,
        /// The verdict (`--solver both`).
        pub class: Option<&'static str>,
        /// Largest relative difference from the analytic motion of the simulated signature.
        pub relative_difference: Option<f64>,
        /// Largest distance between a simulated Floquet multiplier and the nearest analytic one.
        pub multiplier_difference: Option<f64>,
        /// The verdict in words (`beyond`, `contradiction`).
        pub class_detail: Option<String>,
        /// What the simulated motion matched, in words.
        pub matched: Option<String>,
        /// Why this frequency failed.
        pub error: Option<String>,
    }
}

/// Branch cells `(alpha, X_o, T, viable, stable)` of one symmetric branch.
type BranchCells = (
    Option<f64>,
    Option<f64>,
    Option<f64>,
    Option<bool>,
    Option<bool>,
);

impl SweepRow {
    fn empty(omega: f64) -> SweepRow {
        SweepRow {
            omega: finite(omega),
            linear_outer_amplitude: None,
            linear_transmittance_db: None,
            linear_touches_stops: None,
            linear_cell_outer_amplitudes: None,
            orbits: None,
            stable_viable_orbits: None,
            branch0_alpha: None,
            branch0_outer_amplitude: None,
            branch0_transmittance_db: None,
            branch0_viable: None,
            branch0_stable: None,
            branch1_alpha: None,
            branch1_outer_amplitude: None,
            branch1_transmittance_db: None,
            branch1_viable: None,
            branch1_stable: None,
            simulated_regime: None,
            simulated_status: None,
            simulated_period: None,
            simulated_impacts_per_period: None,
            simulated_pair_impacts_per_period: None,
            simulated_outer_amplitude: None,
            simulated_cell_outer_amplitudes: None,
            simulated_transmittance_db: None,
            simulated_sticking: None,
            simulated_signature: None,
            largest_exponent: None,
            largest_exponent_uncertainty: None,
            lyapunov_regime: None,
            analytic_outer_amplitude: None,
            analytic_cell_outer_amplitudes: None,
            analytic_viable: None,
            analytic_stable: None,
            analytic_energy_residual: None,
            class: None,
            relative_difference: None,
            multiplier_difference: None,
            class_detail: None,
            matched: None,
            error: None,
        }
    }

    /// The row of `point` on `scene`.
    pub fn new(scene: &Scene, point: &SweepPoint) -> SweepRow {
        let pairs = scene.pair_count();
        match point {
            SweepPoint::Analytic(p) => {
                let mut row = SweepRow::empty(p.omega);
                row.set_analytic(p);
                row
            }
            SweepPoint::Event(s) => {
                let mut row = SweepRow::empty(s.omega);
                row.set_simulated(s, pairs);
                row
            }
            SweepPoint::Both(c) => {
                let mut row = SweepRow::empty(c.analytic.omega);
                row.set_analytic(&c.analytic);
                row.set_simulated(&c.from_rest, pairs);
                row.class = Some(c.class.name());
                row.relative_difference = c.difference.and_then(finite);
                row.multiplier_difference = c.cross.multiplier_difference.and_then(finite);
                row.class_detail = Some(c.class.detail().to_owned());
                row.matched = c.matched.clone();
                if let Some(o) = &c.cross.analytic {
                    row.analytic_outer_amplitude = finite(o.outer_amplitude);
                    row.analytic_cell_outer_amplitudes = number_list(&[o.outer_amplitude]);
                    row.analytic_viable = Some(o.viable);
                    row.analytic_stable = Some(o.stable);
                    row.analytic_energy_residual = finite(o.energy_residual);
                }
                row
            }
            SweepPoint::Chain { analytic, check } => {
                let mut row = SweepRow::empty(check.omega);
                row.set_analytic(analytic);
                row.set_simulated(&check.simulated, pairs);
                row.class = Some(check.class.name());
                row.relative_difference = check.relative_difference.and_then(finite);
                row.multiplier_difference = check.multiplier_difference.and_then(finite);
                row.class_detail = Some(check.class.detail().to_owned());
                row.matched = (check.class == Class::Agreement).then(|| match &check.analytic {
                    Some(o) => format!("{} orbit over {} period(s)", o.sequence, o.period),
                    None => "linear chain clear of the stops".to_owned(),
                });
                if let Some(o) = &check.analytic {
                    row.analytic_outer_amplitude = finite(o.outer_amplitude);
                    row.analytic_cell_outer_amplitudes = number_list(&o.cell_outer_amplitudes);
                    row.analytic_viable = Some(o.viable);
                    row.analytic_stable = Some(o.stable);
                    row.analytic_energy_residual = finite(o.energy_residual);
                }
                row
            }
            SweepPoint::Failed { omega, message } => {
                let mut row = SweepRow::empty(*omega);
                row.error = Some(message.clone());
                row
            }
        }
    }

    fn set_analytic(&mut self, p: &AnalyticPoint) {
        self.linear_outer_amplitude = finite(p.linear.outer_amplitude);
        self.linear_transmittance_db = finite(p.linear.transmittance_db);
        self.linear_touches_stops = p.touches_stops;
        self.linear_cell_outer_amplitudes = number_list(&p.linear_cell_outer_amplitudes);
        if p.cells > 1 {
            // A chain's orbits are not searched by the sweep.
            return;
        }
        self.orbits = Some(p.orbits.len());
        self.stable_viable_orbits = Some(p.stable_viable_orbits().count());
        let branch = |b: usize| -> BranchCells {
            match p.orbits.iter().find(|(k, _)| *k == b) {
                Some((_, o)) => (
                    finite(o.alpha),
                    finite(o.outer_amplitude),
                    finite(o.transmittance_db),
                    Some(o.viable),
                    Some(o.stable),
                ),
                None => (None, None, None, None, None),
            }
        };
        (
            self.branch0_alpha,
            self.branch0_outer_amplitude,
            self.branch0_transmittance_db,
            self.branch0_viable,
            self.branch0_stable,
        ) = branch(0);
        (
            self.branch1_alpha,
            self.branch1_outer_amplitude,
            self.branch1_transmittance_db,
            self.branch1_viable,
            self.branch1_stable,
        ) = branch(1);
    }

    /// Fills the Lyapunov columns from the simulated motion of `point` on `scene` (an
    /// exponents' run of [`SWEEP_LYAPUNOV_PERIODS`] for a non-periodic one); a failure of that
    /// run goes to [`SweepRow::error`].
    pub fn set_chaos(&mut self, scene: &Scene, point: &SweepPoint, options: &SimulationOptions) {
        let sim = match point {
            SweepPoint::Event(s) => s,
            SweepPoint::Both(c) => &c.from_rest,
            SweepPoint::Chain { check, .. } => &check.simulated,
            SweepPoint::Analytic(_) | SweepPoint::Failed { .. } => return,
        };
        match chaos(scene, sim, SWEEP_LYAPUNOV_PERIODS, options) {
            Ok(c) => {
                self.largest_exponent = c.largest_exponent.and_then(finite);
                self.largest_exponent_uncertainty = c.uncertainty.and_then(finite);
                self.lyapunov_regime = c.regime.map(|r| r.name());
            }
            Err(e) => {
                let message = format!("lyapunov: {e}");
                self.error = Some(match self.error.take() {
                    Some(first) => format!("{first}; {message}"),
                    None => message,
                });
            }
        }
    }

    /// The simulated columns of `s` on a scene with `pairs` contact pairs.
    fn set_simulated(&mut self, s: &SimulatedPoint, pairs: usize) {
        self.simulated_regime = Some(s.regime.name());
        self.simulated_status = Some(s.status_name());
        self.simulated_period = s.steady.period;
        self.simulated_impacts_per_period = finite(s.steady.impacts_per_period);
        self.simulated_pair_impacts_per_period = number_list(&s.pair_impacts_per_period(pairs));
        self.simulated_outer_amplitude = finite(s.outer_amplitude);
        self.simulated_cell_outer_amplitudes = number_list(&s.cell_outer_amplitudes());
        self.simulated_transmittance_db = s.transmittance_db.and_then(finite);
        self.simulated_sticking = Some(s.steady.sticking);
        self.simulated_signature = s.signature().map(|sig| sig.to_string());
    }
}

/// The header of a sweep's JSON document: scene, solver, effects, the number of frequencies of
/// the whole sweep and, for a part, which shard it is.
pub fn header(scene: &Scene, solver: Solver, points: usize, shard: Option<Shard>) -> Header {
    let mut h = Header::default();
    h.push("scene", scene);
    h.push("solver", &solver.name());
    h.push("effects", &scene.effect_names());
    h.push("points", &points);
    if let Some(s) = shard {
        h.push("shard", &s);
    }
    h
}
