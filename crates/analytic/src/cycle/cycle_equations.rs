//! The cycle equations of an impact sequence, one implementation for every model: generic over
//! the dimension `D` of the augmented state `z = (u, u̇, p)`, so that the unit runs them on
//! stack matrices (`D = 6`) and a chain on heap matrices (`D` dynamic). The phase states `p`
//! are `(cos θ, sin θ)` of a purely harmonic forcing, or `(cos kθ, sin kθ)` for each order `k`
//! of a forcing with harmonics ([`crate::problem::forcing`], [`CycleEquations::with_forcing_orders`]);
//! below, `P` is their number.
//!
//! A cycle of `p` forcing periods (`pT`) has `m` impacts at `0 = t₁ < t₂ < … < t_m < pT`,
//! impact `j` with the augmented impact map `Ĝ_j` and the contact functional `h_j` (its pair's
//! coordinate), which must equal `c_j` (the stop, `s_j gap`). For fixed `x = (α, t₂ … t_m)`
//! everything else is linear: with the augmented flow `Φ_j = exp(Â τ_j)` of flight `j` the maps
//! `Pre_j = Φ_j Ĝ_j Pre_{j−1}` (`Pre_0 = Φ_0`) carry `z₁ = (y₁, p₀)`, the state just after the
//! first impact and `p₀ = (cos α, sin α)` (with harmonics `(cos kα, sin kα)` for each order),
//! to the state just before impact `j + 1`.
//! Periodicity `(I − Ψ_xx) y₁ = Ψ_xp p₀`, `Ψ = Ĝ_0 Pre_{m−1}`, fixes `y₁`; it is solved in the
//! augmented dimension as `P z₁ = (0, p₀)`, `P` being `I − Ψ` with its last `P` rows replaced
//! by `(0, I_P)` (partial pivoting then eliminates exactly as on `I − Ψ_xx`). The `m` contact
//! conditions `h_jᵀ z(t_j⁻) = c_j` are the residuals.
//!
//! Derivatives are exact: `∂Φ_j/∂τ_j = Â Φ_j`, `∂p₀/∂α = (−sin α, cos α)` (with harmonics
//! `k (−sin kα, cos kα)` for each order), and the periodicity solve differentiated implicitly,
//! `P dz₁ = (dΨ z₁ restricted to the state rows, dp₀)`.
//!
//! **Rigid modes.** When the model has rigid modes `Φ` (`n × r`, `KΦ = 0`, see
//! [`crate::problem::rigid`]), every flight and impact map keeps the translations `(Φa, 0)`:
//! `Ψ_xx (Φa, 0) = (Φa, 0)`, so `I − Ψ_xx` is singular (rank `2n − r` when nothing else is
//! neutral) and periodicity alone leaves the offset `a` free while asking one solvability
//! condition per rigid mode of the impact times (that the free bodies come back where they
//! were: no drift over the cycle). The contact conditions fix the offsets: the first `r` impacts (in sequence
//! order) whose pair directions `w` have independent projections `Φᵀw` (the *anchors* `J`)
//! are moved into the periodicity solve, and the solvability conditions out of it, by the
//! bordered system
//!
//! ```text
//! [ P    L̂ ] [ z₁ ]   [ (0, p₀) ]
//! [ Rᵀ   0 ] [ μ  ] = [ c_J     ]
//! ```
//!
//! `P` as above, `L̂ = (Φ, 0, 0)` (a shift `Φμ` of the positions along the rigid modes at the
//! end of the cycle, `μ ∈ ℝʳ`: the free bodies' drift over one cycle), and row `i` of `Rᵀ` the
//! anchor `j_i`'s contact functional carried to the state after the first impact,
//! `h_jᵀ Pre_{j−1}` (`h₀ᵀ` for the first impact). A translation is kept and changes no other
//! coordinate: in coordinates `u = Φa + Φ⊥b` the `a`-columns of `Ψ_xx` are those of the
//! identity, so `I − Ψ_xx = [[0, −D], [0, I − Ψ']]`, where `I − Ψ'` acts on `(b, u̇)` (the
//! cycle map *modulo translations*) and the `a`-rows `D(b, u̇)` are the free bodies' drift
//! over the cycle, which periodicity asks to vanish. The bordered system is regular exactly
//! when `I − Ψ'` is (the cycle map at fixed impact times has no neutral direction but the
//! translations) and the anchors' `wᵀΦ` form a regular `r × r` matrix (`Rᵀ(Φ, 0)`, which the
//! choice of anchors ensures): then the drift is the dependent part of periodicity, and the
//! shifts `Φμ` are exactly what it lacks. A solution with `μ = 0`
//! is a periodic motion meeting the anchors' contact conditions, so the residuals are the
//! drifts `μ_i` (displacements, in the units of the contact residuals) in place of the
//! anchors' contact residuals, and the other contact residuals as before: `m` equations in
//! `m` unknowns whose zeros are the orbits. (A kick on the free bodies' velocities instead
//! fails where a body's velocity scale is neutral at fixed impact times, e.g. a free mass
//! between a stop on the frame and one on a primary at the orbit's own impact phase
//! `e/(1 + e)`.) Where `I − Ψ'` is singular the solve is reported singular, as a singular `P`
//! is without rigid modes. A model without rigid modes has no border and runs the unbordered
//! system above, unchanged.
//!
//! Differentiating the bordered system: `B (dz₁, dμ) = (dΨ z₁ on the state rows, dp₀,
//! −h_jᵀ dPre_{j−1} z₁ on anchor rows)`, the same carried products `dPre_f z₁` as without
//! border.

mod contact_flights;
mod in_omega;

pub(crate) use contact_flights::{balanced_exp, velocity_balance};

use crate::cycle::unit_flights::{product, remembered_flow, to_unit, unit_modes};
use crate::cycle::unit_modes::{ModalForcing, UnitModes};
use crate::orbit::wrap;
use crate::problem::forcing::phase_state;
use crate::problem::forcing::PhaseRows;
use nalgebra::allocator::Allocator;
use nalgebra::{
    Const, DMatrix, DVector, DefaultAllocator, Dim, DimMin, Dyn, Matrix6, OMatrix, OVector, LU,
};
use std::sync::Arc;

/// A flight shorter than this fraction of the cycle is two impacts merging: a grazing limit,
/// not an orbit of the sequence. Far below any grid spacing, far above rounding of the times.
pub(crate) const MIN_FLIGHT: f64 = 1e-9;

/// What one impact of the sequence contributes to the cycle equations.
#[derive(Debug, Clone)]
pub struct ImpactCondition<D: Dim>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// `Ĝ_j = diag(I_n, G, I_P)`: the augmented impact map of its pair.
    pub impact_map: OMatrix<f64, D, D>,
    /// `h_j = (w, 0, 0)`: its pair's coordinate as a functional of the augmented state.
    pub contact: OVector<f64, D>,
    /// `c_j = s_j gap`: where that coordinate must be at the impact.
    pub stop: f64,
}

/// The cycle equations of one impact sequence at one frequency, in augmented dimension `D`.
#[derive(Debug, Clone)]
pub struct CycleEquations<D: Dim>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    omega: f64,
    augmented: OMatrix<f64, D, D>,
    /// `Ĝ_j` of each impact, in sequence order. The per-impact lists are shared (not
    /// copied) by the equations at other frequencies ([`Self::at_frequency`], once per
    /// evaluation in continuation).
    g_hats: Arc<[OMatrix<f64, D, D>]>,
    /// `h_j`: the augmented gradient of impact `j`'s pair coordinate.
    contacts: Arc<[OVector<f64, D>]>,
    /// `c_j = s_j gap` of each impact: where its pair coordinate must be.
    stops: Arc<[f64]>,
    /// The rotations of the cycle that map the sequence onto itself.
    symmetries: Arc<[usize]>,
    /// The order of each pair of phase states (`[1]` for a purely harmonic forcing).
    orders: Arc<[u32]>,
    cycle: f64,
    /// The unit's modal decomposition of `A` (augmented dimension 6 only, and only where it
    /// is well-conditioned): the fast flow of every flight; `None`: Padé.
    modes: Option<(Arc<UnitModes>, ModalForcing)>,
    /// Whether the modal flights are looked up among those this thread computed last
    /// ([`remembered_flow`]): for callers that evaluate the cycle at points sharing flights.
    remember: bool,
    /// The border of a model with rigid modes (see the module's documentation); `None`:
    /// the unbordered periodicity solve.
    border: Option<Arc<RigidBorder>>,
    /// Per flight, its contact phase's own flow (`None` entries: free flights); `None`: no
    /// contact phase ([`Self::with_contact_flights`]).
    contact_flights: Option<Arc<[Option<contact_flights::ContactFlight<D>>]>>,
}

/// The border of the periodicity solve of a model with `r` rigid modes.
#[derive(Debug, Clone)]
pub(crate) struct RigidBorder {
    /// `L̂` (augmented size × `r`): shifts of the positions along the rigid modes.
    pub(crate) shifts: DMatrix<f64>,
    /// The anchor impacts `j_1 < … < j_r`, whose contact conditions fix the offsets.
    pub(crate) anchors: Vec<usize>,
}

/// The factored periodicity solve of one cycle: the unbordered `P`, or the bordered system of
/// a model with rigid modes.
enum Periodic<'a, D: DimMin<D, Output = D>>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// `P`'s LU factors.
    Plain(&'a LU<f64, D, D>),
    /// The bordered system's LU factors (size `D + r`).
    Bordered(&'a LU<f64, Dyn, Dyn>),
}

/// An owned [`Periodic`].
enum PeriodicFactors<D: DimMin<D, Output = D>>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    Plain(LU<f64, D, D>),
    Bordered(LU<f64, Dyn, Dyn>),
}

impl<D: DimMin<D, Output = D>> PeriodicFactors<D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    fn view(&self) -> Periodic<'_, D> {
        match self {
            Self::Plain(lu) => Periodic::Plain(lu),
            Self::Bordered(lu) => Periodic::Bordered(lu),
        }
    }
}

/// The cycle evaluated at one `x = (α, φ₂ … φ_m)`.
#[derive(Debug, Clone)]
pub struct CycleEvaluation<D: Dim>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// `Φ_j` of each flight.
    pub flights: Vec<OMatrix<f64, D, D>>,
    /// `Pre_j`: from `z₁` to the augmented state just before impact `j + 1` (impact `m`
    /// being the first impact of the next cycle).
    pub pre: Vec<OMatrix<f64, D, D>>,
    /// `z₁ = (y₁, p₀)`: the state just after the first impact and the forcing phase there.
    pub z1: OVector<f64, D>,
    /// Contact residuals `h_jᵀ z(t_j⁻) − c_j`, in sequence order.
    pub residual: DVector<f64>,
    /// `∂ residual / ∂ (α, φ₂ … φ_m)`, `φ` the impact times as fractions of the cycle; empty
    /// when evaluated without derivatives.
    pub jacobian: DMatrix<f64>,
}

impl<D: Dim> CycleEvaluation<D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// The augmented state just before each impact, in sequence order (impact 0's closes the
    /// cycle).
    pub fn before_impacts(&self) -> Vec<OVector<f64, D>> {
        let m = self.pre.len();
        (0..m)
            .map(|j| &self.pre[if j == 0 { m - 1 } else { j - 1 }] * &self.z1)
            .collect()
    }
}

impl<D: DimMin<D, Output = D>> CycleEquations<D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// The equations from their parts: the augmented system matrix `Â` at `omega`, and per
    /// impact (in sequence order) its augmented impact map `Ĝ_j`, contact functional `h_j` and
    /// stop `c_j`; `symmetries` the rotations of the cycle that keep the sequence, `cycle` its
    /// length `pT`.
    ///
    /// # Panics
    /// If the per-impact lists are empty or differ in length.
    pub fn new(
        omega: f64,
        augmented: OMatrix<f64, D, D>,
        impacts: Vec<ImpactCondition<D>>,
        symmetries: Vec<usize>,
        cycle: f64,
    ) -> Self {
        assert!(!impacts.is_empty(), "a cycle has at least one impact");
        let mut g_hats = Vec::with_capacity(impacts.len());
        let mut contacts = Vec::with_capacity(impacts.len());
        let mut stops = Vec::with_capacity(impacts.len());
        for impact in impacts {
            g_hats.push(impact.impact_map);
            contacts.push(impact.contact);
            stops.push(impact.stop);
        }
        Self {
            omega,
            augmented,
            g_hats: g_hats.into(),
            contacts: contacts.into(),
            stops: stops.into(),
            symmetries: symmetries.into(),
            orders: Arc::new([1]),
            cycle,
            modes: None,
            remember: false,
            border: None,
            contact_flights: None,
        }
    }

    /// The same equations bordered for a model with rigid modes (see the module's
    /// documentation): `shifts` the columns `L̂` (augmented size × `r`), `anchors` the `r`
    /// impacts whose contact conditions fix the offsets.
    pub(crate) fn with_rigid_border(self, shifts: DMatrix<f64>, anchors: Vec<usize>) -> Self {
        Self {
            border: Some(Arc::new(RigidBorder { shifts, anchors })),
            ..self
        }
    }

    /// The same equations for a forcing whose phase states are the pairs
    /// `(cos kθ, sin kθ)` of the orders `orders`, in the order of the augmented state's last
    /// `2 · orders.len()` rows (`[1]`, the default: `(cos θ, sin θ)` alone; a forcing with
    /// harmonics: [`crate::HarmonicForcing::orders`]). The phase at the first impact is then
    /// `(cos kα, sin kα)` for each order, its derivative in `α` `k (−sin kα, cos kα)`.
    ///
    /// # Panics
    /// If `orders` is empty or leaves no mechanical state (`2 · orders.len()` not below the
    /// augmented dimension).
    pub fn with_forcing_orders(self, orders: &[u32]) -> Self {
        assert!(
            !orders.is_empty() && 2 * orders.len() < self.augmented.nrows(),
            "one to (augmented dimension − 1)/2 pairs of phase states"
        );
        Self {
            orders: orders.into(),
            ..self
        }
    }

    /// The order of each pair of phase states (`[1]` for a purely harmonic forcing).
    pub fn forcing_orders(&self) -> &[u32] {
        &self.orders
    }

    /// Number `P` of phase states: two per order.
    pub fn phase_states(&self) -> usize {
        2 * self.orders.len()
    }

    /// Whether the periodicity solve is bordered (a model with rigid modes).
    pub fn is_bordered(&self) -> bool {
        self.border.is_some()
    }

    /// The same equations with the unit's modal flow (augmented dimension 6 only; elsewhere,
    /// or where `A` has no well-conditioned eigenbasis, they are returned unchanged): every
    /// flight's `exp(Â τ)` and its `ω` derivative from one eigen-decomposition of `A`, kept
    /// across [`Self::at_frequency`] (see `unit_modes`). One evaluation of the paper unit's
    /// `++--` cycle with the Jacobian in `(x, ω)` took 6.5 µs against Padé's 26.4 µs, the
    /// residuals alone 2.3 µs against 4.7 µs (`benches/cycle_flow.rs`, shared machine). Its
    /// rounding differs from Padé's by about 1e-15 of the flow's size (against a 40-digit
    /// reference: 3.6e-16 to 9.1e-16 on the paper unit at τ ≤ 7.9, Padé 2.6e-16 to 9.3e-16),
    /// so it serves continuation, which follows branches, while the orbit solvers whose
    /// results the tests compare with the closed form to 1e-12 (Floquet multipliers of
    /// non-normal monodromy matrices amplify that difference about a thousandfold) keep Padé.
    pub fn with_modal_flow(self) -> Self {
        if self.contact_flights.is_some() {
            return self;
        }
        let modes = unit_modes(&self.augmented);
        Self { modes, ..self }
    }

    /// The same equations, their modal flights looked up among the last 32 this thread
    /// computed (the same bits as computing them again): for a caller whose evaluations share
    /// flights, as a boundary curve's difference steps do (the flights that a step leaves
    /// unchanged are not recomputed). A continuation in `ω`, whose evaluations share none,
    /// would only pay for the look-up (it cost the study's continuation from 115 seeds 6 %
    /// more CPU), so it is off by default.
    pub fn with_remembered_flights(self) -> Self {
        Self {
            remember: true,
            ..self
        }
    }

    /// The same impacts at another frequency: `omega`, its augmented matrix `augmented` and
    /// cycle length `cycle` (what continuation in `ω` evaluates at each point).
    pub fn at_frequency(&self, omega: f64, augmented: OMatrix<f64, D, D>, cycle: f64) -> Self {
        let modes = self.modes.as_ref().and_then(|(previous, _)| {
            let unit = to_unit(&augmented);
            if previous.fits(&unit) {
                let forcing = previous.forcing(&unit);
                Some((Arc::clone(previous), forcing))
            } else {
                unit_modes(&augmented)
            }
        });
        let moved = Self {
            omega,
            augmented,
            cycle,
            modes,
            ..self.clone()
        };
        Self {
            contact_flights: moved.contact_flights_at_frequency(),
            ..moved
        }
    }

    /// `‖K‖∞ ‖K⁻¹‖∞` of the periodicity matrix `K = I − Ψ_xx` of the maps `pre` of one cycle
    /// (infinite when `K` is singular): the contact residuals carry rounding of about this
    /// many units of the motion's size.
    ///
    /// With a rigid border, the same of the bordered system without its phase rows and
    /// columns.
    pub fn conditioning(&self, pre: &[OMatrix<f64, D, D>]) -> f64 {
        let Some(last) = pre.last() else {
            return f64::INFINITY;
        };
        if let Some(border) = &self.border {
            let full = self.bordered_matrix(border, pre);
            let (size, s) = (self.augmented.nrows(), self.states());
            let keep: Vec<usize> = (0..s).chain(size..full.nrows()).collect();
            let k = DMatrix::from_fn(keep.len(), keep.len(), |i, j| full[(keep[i], keep[j])]);
            let inverse = k.clone().lu().try_inverse();
            return inf_norm(&k) * inverse.map_or(f64::INFINITY, |i| inf_norm(&i));
        }
        let psi = &self.g_hats[0] * last;
        let s = self.states();
        let k = DMatrix::from_fn(s, s, |i, j| f64::from(u8::from(i == j)) - psi[(i, j)]);
        // The inverse from the LU factors (partial pivoting), not the cofactor formula that
        // `try_inverse` uses up to 4×4, which loses accuracy where `K` is ill-conditioned.
        let inverse = k.clone().lu().try_inverse();
        inf_norm(&k) * inverse.map_or(f64::INFINITY, |i| inf_norm(&i))
    }

    /// The forcing frequency.
    pub fn omega(&self) -> f64 {
        self.omega
    }

    /// Length of the cycle, `pT`.
    pub fn cycle(&self) -> f64 {
        self.cycle
    }

    /// The augmented system matrix `Â`.
    pub fn augmented_matrix(&self) -> &OMatrix<f64, D, D> {
        &self.augmented
    }

    /// Number of impacts `m`, also the number of unknowns.
    pub fn impacts(&self) -> usize {
        self.stops.len()
    }

    /// Dimension of the mechanical state `(u, u̇)`: the augmented dimension less the phase
    /// states.
    pub fn states(&self) -> usize {
        self.augmented.nrows() - self.phase_states()
    }

    /// `c_j` of each impact.
    pub fn stops(&self) -> &[f64] {
        &self.stops
    }

    /// `h_j` of impact `j`: the augmented functional its condition sets to `c_j`.
    pub(crate) fn contact_functional(&self, j: usize) -> &OVector<f64, D> {
        &self.contacts[j]
    }

    /// The impact phases `(0, φ₂ … φ_m)` of the unknowns `x = (α, φ₂ … φ_m)`.
    pub fn phases(x: &[f64]) -> Vec<f64> {
        let mut p = x.to_vec();
        if let Some(first) = p.first_mut() {
            *first = 0.0;
        }
        p
    }

    /// Whether the unknowns keep every flight longer than `MIN_FLIGHT = 1e-9` of the cycle.
    pub fn ordered(&self, x: &[f64]) -> bool {
        let m = self.impacts();
        (1..m).all(|i| {
            let prev = if i == 1 { 0.0 } else { x[i - 1] };
            x[i] - prev > MIN_FLIGHT
        }) && (m == 1 || 1.0 - x[m - 1] > MIN_FLIGHT)
    }

    /// Size of the motion against which residuals are measured: the largest stop the sequence
    /// hits and the largest displacement just after the first impact.
    pub fn scale(&self, z1: &OVector<f64, D>) -> f64 {
        let dofs = self.states() / 2;
        let gaps = self.stops.iter().fold(0.0, |a: f64, s| a.max(s.abs()));
        z1.rows(0, dofs).iter().fold(gaps, |a, v| a.max(v.abs()))
    }

    /// Among the rotations of the cycle that keep the sequence, the representation of the
    /// unknowns `x` with the smallest wrapped `α`: returns `(α, phases)`.
    pub fn canonical(&self, x: &[f64]) -> (f64, Vec<f64>) {
        smallest_rotation(
            x[0],
            Self::phases(x),
            &self.symmetries,
            self.omega * self.cycle,
        )
    }

    /// `exp(Â τ)`: in the unit's modal basis where it has one (see `unit_modes`), otherwise
    /// by Padé.
    pub fn flow(&self, tau: f64) -> OMatrix<f64, D, D> {
        if let Some((modes, forcing)) = &self.modes {
            let size = self.augmented.nrows();
            let d = D::from_usize(size);
            let fast = if self.remember {
                remembered_flow(modes, forcing, tau)
            } else {
                modes.flow(forcing, tau)
            };
            return OMatrix::<f64, D, D>::from_fn_generic(d, d, |i, j| fast[(i, j)]);
        }
        (&self.augmented * tau).exp()
    }

    /// [`Self::flow`] of each of the durations `taus`: the modal flows (unless remembered)
    /// two at a time ([`UnitModes::flow_pair`]), bit for bit one at a time.
    fn flows(&self, taus: &[f64]) -> Vec<OMatrix<f64, D, D>> {
        if self.contact_flights.is_some() {
            return (0..taus.len())
                .map(|f| self.flight_flow(f, taus[f]))
                .collect();
        }
        let Some((modes, forcing)) = self.modes.as_ref().filter(|_| !self.remember) else {
            return taus.iter().map(|&tau| self.flow(tau)).collect();
        };
        let d = D::from_usize(self.augmented.nrows());
        let augmented =
            |fast: &Matrix6<f64>| OMatrix::<f64, D, D>::from_fn_generic(d, d, |i, j| fast[(i, j)]);
        let mut out = Vec::with_capacity(taus.len());
        for pair in taus.chunks(2) {
            if let [a, b] = *pair {
                out.extend(modes.flow_pair(forcing, [a, b]).iter().map(augmented));
            } else {
                out.push(augmented(&modes.flow(forcing, pair[0])));
            }
        }
        out
    }

    /// `Pre_j` of the flights `flights`, in order.
    pub fn pre_maps(&self, flights: &[&OMatrix<f64, D, D>]) -> Vec<OMatrix<f64, D, D>> {
        let mut pre: Vec<OMatrix<f64, D, D>> = Vec::with_capacity(flights.len());
        pre.push(flights[0].clone());
        for f in 1..flights.len() {
            let next = product(flights[f], &product(&self.g_hats[f], &pre[f - 1]));
            pre.push(next);
        }
        pre
    }

    /// The LU factors of the periodicity matrix `P` (`I − Ψ` with its last `P` rows, the
    /// phase states', `(0, I_P)`), `pre` the maps of one cycle; `None` when it is singular.
    pub fn periodicity(&self, pre: &[OMatrix<f64, D, D>]) -> Option<LU<f64, D, D>> {
        let last = pre.last()?;
        let psi = &self.g_hats[0] * last;
        let size = psi.nrows();
        let d = D::from_usize(size);
        let mut p = OMatrix::<f64, D, D>::identity_generic(d, d) - psi;
        let phases = self.phase_states();
        if phases == 2 {
            // A purely harmonic forcing: two phase rows, written as constants.
            p.rows_mut(size - 2, 2).fill(0.0);
            p[(size - 2, size - 2)] = 1.0;
            p[(size - 1, size - 1)] = 1.0;
        } else {
            p.rows_mut(size - phases, phases).fill(0.0);
            for i in size - phases..size {
                p[(i, i)] = 1.0;
            }
        }
        let lu = p.lu();
        lu.is_invertible().then_some(lu)
    }

    /// The bordered system of the maps `pre` (see the module's documentation): `P`, the shifts
    /// `L̂`, and the anchors' contact functionals carried to the state after the first impact.
    fn bordered_matrix(&self, border: &RigidBorder, pre: &[OMatrix<f64, D, D>]) -> DMatrix<f64> {
        let size = self.augmented.nrows();
        let r = border.anchors.len();
        let psi = pre.last().map(|last| &self.g_hats[0] * last);
        let mut b = DMatrix::zeros(size + r, size + r);
        let states = self.states();
        for i in 0..states {
            for j in 0..size {
                let identity = f64::from(u8::from(i == j));
                b[(i, j)] = identity - psi.as_ref().map_or(0.0, |p| p[(i, j)]);
            }
        }
        for i in states..size {
            b[(i, i)] = 1.0;
        }
        b.view_mut((0, size), (size, r)).copy_from(&border.shifts);
        for (i, &j) in border.anchors.iter().enumerate() {
            let row = if j == 0 {
                self.contacts[0].clone()
            } else {
                pre[j - 1].tr_mul(&self.contacts[j])
            };
            for k in 0..size {
                b[(size + i, k)] = row[k];
            }
        }
        b
    }

    /// The factored periodicity solve of the maps `pre`: bordered when the equations have a
    /// rigid border, otherwise [`Self::periodicity`]; `None` when singular.
    fn periodic_factors(&self, pre: &[OMatrix<f64, D, D>]) -> Option<PeriodicFactors<D>> {
        let Some(border) = &self.border else {
            return self.periodicity(pre).map(PeriodicFactors::Plain);
        };
        let lu = self.bordered_matrix(border, pre).lu();
        lu.is_invertible().then_some(PeriodicFactors::Bordered(lu))
    }

    /// Solves the periodicity system `solver` for the state rows `state` (zero when `None`),
    /// phase rows `p` (`P` entries) and, when bordered, anchor rows `anchor_rows`: `(z₁, μ)`
    /// (`μ` empty without border).
    fn periodic_solve(
        &self,
        solver: &Periodic<'_, D>,
        state: Option<&OVector<f64, D>>,
        p: PhaseRows<'_>,
        anchor_rows: impl Fn(usize) -> f64,
    ) -> Option<(OVector<f64, D>, Vec<f64>)> {
        let rhs = self.augmented_vector(state, p);
        match solver {
            Periodic::Plain(lu) => lu.solve(&rhs).map(|z| (z, Vec::new())),
            Periodic::Bordered(lu) => {
                let size = self.augmented.nrows();
                let r = lu.l().nrows() - size;
                let full = DVector::from_fn(size + r, |i, _| {
                    if i < size {
                        rhs[i]
                    } else {
                        anchor_rows(i - size)
                    }
                });
                let solution = lu.solve(&full)?;
                let d = D::from_usize(size);
                let z = OVector::<f64, D>::from_fn_generic(d, Const::<1>, |i, _| solution[i]);
                Some((z, solution.iter().skip(size).copied().collect()))
            }
        }
    }

    /// The bordered residuals: the contact residuals (less the stops when `with_stops`) with
    /// the drift `μ_i` in place of each anchor's.
    fn bordered_residuals(
        &self,
        pre: &[OMatrix<f64, D, D>],
        z1: &OVector<f64, D>,
        mu: &[f64],
        with_stops: bool,
    ) -> DVector<f64> {
        let values = self.contact_values(pre, z1);
        let mut residual = DVector::from_fn(values.len(), |j, _| {
            values[j] - if with_stops { self.stops[j] } else { 0.0 }
        });
        if let Some(border) = &self.border {
            for (i, &j) in border.anchors.iter().enumerate() {
                residual[j] = mu[i];
            }
        }
        residual
    }

    /// For fixed impact times (the maps `pre`), the residuals as the affine function
    /// `r₀ + Σ_i r_i p_i` of the phase states `p` at the first impact (`r₀ + r_c cos α +
    /// r_s sin α` for a purely harmonic forcing): `(r₀, [r_1 … r_P])`. Without border `r₀` is
    /// `−c_j`; `None` when the periodicity solve is singular.
    pub(crate) fn affine_residuals(
        &self,
        pre: &[OMatrix<f64, D, D>],
    ) -> Option<(DVector<f64>, Vec<DVector<f64>>)> {
        let factors = self.periodic_factors(pre)?;
        let solver = factors.view();
        let stops_at = |i: usize| {
            self.border
                .as_ref()
                .map_or(0.0, |b| self.stops[b.anchors[i]])
        };
        let phases = self.phase_states();
        let mut p = vec![0.0; phases];
        let (z0, mu0) = self.periodic_solve(&solver, None, PhaseRows::Still, stops_at)?;
        let constant = self.bordered_residuals(pre, &z0, &mu0, true);
        let mut linear = Vec::with_capacity(phases);
        for i in 0..phases {
            p[i] = 1.0;
            let (z, mu) = self.periodic_solve(&solver, None, PhaseRows::Given(&p), |_| 0.0)?;
            p[i] = 0.0;
            linear.push(self.bordered_residuals(pre, &z, &mu, false));
        }
        Some((constant, linear))
    }

    /// The phase states at the first impact for the base phase `alpha`: `(cos kα, sin kα)`
    /// for each order ([`Self::forcing_orders`]).
    pub fn phase_at(&self, alpha: f64) -> Vec<f64> {
        phase_state(&self.orders, alpha)
    }

    /// The augmented vector with the state rows `state` (zero when `None`) and the phase rows
    /// (the last `P`) `p`.
    pub(crate) fn augmented_vector(
        &self,
        state: Option<&OVector<f64, D>>,
        p: PhaseRows<'_>,
    ) -> OVector<f64, D> {
        let size = self.augmented.nrows();
        let mut v = match state {
            Some(s) => s.clone(),
            None => OVector::<f64, D>::zeros_generic(D::from_usize(size), Const::<1>),
        };
        let states = self.states();
        p.write(&self.orders, &mut v.as_mut_slice()[states..]);
        v
    }

    /// `h_jᵀ z(t_j⁻)` of each impact, the cycle starting from `z1` through the maps `pre`.
    pub fn contact_values(&self, pre: &[OMatrix<f64, D, D>], z1: &OVector<f64, D>) -> Vec<f64> {
        (0..self.impacts())
            .map(|j| {
                if j == 0 {
                    self.contacts[0].dot(z1)
                } else {
                    self.contacts[j].dot(&(&pre[j - 1] * z1))
                }
            })
            .collect()
    }

    /// The contact residuals `h_jᵀ z(t_j⁻) − c_j` of the cycle from `z1` through `pre`.
    pub fn residuals(&self, pre: &[OMatrix<f64, D, D>], z1: &OVector<f64, D>) -> DVector<f64> {
        let values = self.contact_values(pre, z1);
        DVector::from_fn(values.len(), |j, _| values[j] - self.stops[j])
    }

    /// The cycle at `x = (α, φ₂ … φ_m)`, with the exact Jacobian when `with_jacobian`.
    /// `None` when the periodicity solve is singular.
    ///
    /// # Panics
    /// If `x` does not have one entry per impact.
    pub fn evaluate_with(&self, x: &[f64], with_jacobian: bool) -> Option<CycleEvaluation<D>> {
        let m = self.impacts();
        assert_eq!(x.len(), m, "one unknown per impact");
        let phases = Self::phases(x);
        let taus: Vec<f64> = (0..m)
            .map(|f| {
                let end = if f + 1 < m { phases[f + 1] } else { 1.0 };
                (end - phases[f]) * self.cycle
            })
            .collect();
        let flights = self.flows(&taus);
        let pre = self.pre_maps(&flights.iter().collect::<Vec<_>>());
        if self.border.is_some() {
            return self.evaluate_bordered(x, flights, pre, with_jacobian);
        }
        let lu = self.periodicity(&pre)?;
        let alpha = x[0];
        let z1 = lu.solve(&self.augmented_vector(None, PhaseRows::At(alpha)))?;
        let residual = self.residuals(&pre, &z1);
        let mut evaluation = CycleEvaluation {
            flights,
            pre,
            z1,
            residual,
            jacobian: DMatrix::zeros(0, 0),
        };
        if with_jacobian {
            evaluation.jacobian = self.jacobian(&evaluation, &lu, alpha)?;
        }
        Some(evaluation)
    }

    /// [`Self::evaluate_with`] of bordered equations, from the flights and maps at `x`.
    fn evaluate_bordered(
        &self,
        x: &[f64],
        flights: Vec<OMatrix<f64, D, D>>,
        pre: Vec<OMatrix<f64, D, D>>,
        with_jacobian: bool,
    ) -> Option<CycleEvaluation<D>> {
        let border = self.border.as_ref()?;
        let factors = self.periodic_factors(&pre)?;
        let solver = factors.view();
        let alpha = x[0];
        let (z1, mu) = self.periodic_solve(&solver, None, PhaseRows::At(alpha), |i| {
            self.stops[border.anchors[i]]
        })?;
        let residual = self.bordered_residuals(&pre, &z1, &mu, true);
        let mut evaluation = CycleEvaluation {
            flights,
            pre,
            z1,
            residual,
            jacobian: DMatrix::zeros(0, 0),
        };
        if with_jacobian {
            evaluation.jacobian = self.jacobian_in(&evaluation, &solver, alpha)?;
        }
        Some(evaluation)
    }

    /// `∂ residual / ∂ (α, φ₂ … φ_m)` at an evaluation.
    fn jacobian(
        &self,
        e: &CycleEvaluation<D>,
        lu: &LU<f64, D, D>,
        alpha: f64,
    ) -> Option<DMatrix<f64>> {
        self.jacobian_in(e, &Periodic::Plain(lu), alpha)
    }

    /// `∂ residual / ∂ (α, φ₂ … φ_m)` at an evaluation, with the periodicity solve `solver`.
    fn jacobian_in(
        &self,
        e: &CycleEvaluation<D>,
        solver: &Periodic<'_, D>,
        alpha: f64,
    ) -> Option<DMatrix<f64>> {
        let m = self.impacts();
        let mut jacobian = DMatrix::zeros(m, m);
        // α: only p₀ moves.
        let alpha_column = self.column_in(e, solver, |_| None, PhaseRows::Slope(alpha))?;
        jacobian.set_column(0, &alpha_column);
        // t_i (impact i ≥ 1): flight i − 1 grows, flight i shrinks, so the own term of
        // ∂Pre_f is c_f Â Pre_f with c_{i−1} = 1, c_i = −1.
        for i in 1..m {
            let own = |f: usize| {
                let c = (f + 1 == i) as i32 as f64 - (f == i) as i32 as f64;
                (c != 0.0).then(|| product(self.flight_matrix(f), &e.pre[f]) * (c * self.cycle))
            };
            jacobian.set_column(i, &self.column_in(e, solver, own, PhaseRows::Still)?);
        }
        Some(jacobian)
    }

    /// The derivative of the residuals along one direction in which flight `f` contributes
    /// `own(f) = ∂Φ_f Ĝ_f Pre_{f−1}` (`∂Φ_0` for the first; `None`: the flight is unchanged)
    /// and the phase states `p₀` move by `dp0` (`P` entries): `∂Pre_f = Φ_f Ĝ_f ∂Pre_{f−1} +
    /// own(f)`, and the periodicity solve differentiated. For equations without a rigid
    /// border (`lu` factors `P`).
    ///
    /// # Panics
    /// If `dp0` has more entries than the phase states.
    pub fn column(
        &self,
        e: &CycleEvaluation<D>,
        lu: &LU<f64, D, D>,
        own: impl Fn(usize) -> Option<OMatrix<f64, D, D>>,
        dp0: &[f64],
    ) -> Option<DVector<f64>> {
        self.column_in(e, &Periodic::Plain(lu), own, PhaseRows::Given(dp0))
    }

    /// [`Self::column`] with the periodicity solve `solver`, bordered or not.
    fn column_in(
        &self,
        e: &CycleEvaluation<D>,
        solver: &Periodic<'_, D>,
        own: impl Fn(usize) -> Option<OMatrix<f64, D, D>>,
        dp0: PhaseRows<'_>,
    ) -> Option<DVector<f64>> {
        let m = self.impacts();
        // `∂Pre_f` is carried from flight to flight; only `∂Pre_f z₁` is kept (the same
        // product, taken as soon as `∂Pre_f` is known).
        let mut carried: Option<OMatrix<f64, D, D>> = None;
        let mut moved_z1: Vec<Option<OVector<f64, D>>> = Vec::with_capacity(m);
        for f in 0..m {
            let through = carried
                .as_ref()
                .map(|previous| product(&e.flights[f], &product(&self.g_hats[f], previous)));
            carried = match (through, own(f)) {
                (Some(d), Some(o)) => Some(d + o),
                (d, o) => d.or(o),
            };
            moved_z1.push(carried.as_ref().map(|d| d * &e.z1));
        }
        let moved_psi = moved_z1[m - 1].as_ref().map(|last| &self.g_hats[0] * last);
        let lu = match solver {
            Periodic::Plain(lu) => lu,
            Periodic::Bordered(_) => {
                return self.bordered_column(e, solver, &moved_z1, moved_psi.as_ref(), dp0)
            }
        };
        let dz1 = lu.solve(&self.augmented_vector(moved_psi.as_ref(), dp0))?;
        Some(DVector::from_fn(m, |j, _| {
            if j == 0 {
                return self.contacts[0].dot(&dz1);
            }
            let moved = &e.pre[j - 1] * &dz1;
            let total = match moved_z1[j - 1].as_ref() {
                Some(d) => d + moved,
                None => moved,
            };
            self.contacts[j].dot(&total)
        }))
    }
}

impl<D: DimMin<D, Output = D>> CycleEquations<D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// The bordered counterpart of the last step of [`Self::column`]: the bordered solve with
    /// `−h_jᵀ dPre_{j−1} z₁` on the anchor rows, then the residuals' derivatives (`dμ_i` for
    /// the anchors).
    fn bordered_column(
        &self,
        e: &CycleEvaluation<D>,
        solver: &Periodic<'_, D>,
        moved_z1: &[Option<OVector<f64, D>>],
        moved_psi: Option<&OVector<f64, D>>,
        dp0: PhaseRows<'_>,
    ) -> Option<DVector<f64>> {
        let border = self.border.as_ref()?;
        let anchor_rows = |i: usize| {
            let j = border.anchors[i];
            if j == 0 {
                return 0.0;
            }
            moved_z1[j - 1]
                .as_ref()
                .map_or(0.0, |d| -self.contacts[j].dot(d))
        };
        let (dz1, dmu) = self.periodic_solve(solver, moved_psi, dp0, anchor_rows)?;
        let m = self.impacts();
        let mut column = DVector::from_fn(m, |j, _| {
            if j == 0 {
                return self.contacts[0].dot(&dz1);
            }
            let moved = &e.pre[j - 1] * &dz1;
            let total = match moved_z1[j - 1].as_ref() {
                Some(d) => d + moved,
                None => moved,
            };
            self.contacts[j].dot(&total)
        });
        for (i, &j) in border.anchors.iter().enumerate() {
            column[j] = dmu[i];
        }
        Some(column)
    }
}

/// `‖m‖∞`, the largest row sum of moduli.
fn inf_norm(m: &DMatrix<f64>) -> f64 {
    m.row_iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Among the rotations `symmetries` of a cycle (start at impact `k` instead of 0) that keep
/// its canonical sequence, the representation of `(α, phases)` with the smallest wrapped `α`;
/// `omega_cycle` is `ω` times the cycle's length.
pub(crate) fn smallest_rotation(
    alpha: f64,
    phases: Vec<f64>,
    symmetries: &[usize],
    omega_cycle: f64,
) -> (f64, Vec<f64>) {
    let m = phases.len();
    symmetries
        .iter()
        .map(|&k| {
            let shifted: Vec<f64> = (0..m)
                .map(|j| (phases[(j + k) % m] - phases[k]).rem_euclid(1.0))
                .collect();
            (wrap(alpha + omega_cycle * phases[k]), shifted)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or((wrap(alpha), phases))
}
