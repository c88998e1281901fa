//! Chains of cells in series and the linear chain's steady state in closed form.
//!
//! Cell `j` (`j = 1 … N`) is a mass-in-mass unit: its outer mass `m_o,j` is tied to outer mass
//! `j − 1` (the base for the first) by `k_o,j` and `c_o,j`, its inner mass `m_i,j` to its own
//! outer mass by `k_i,j` and `c_i,j`. The base moves as `u_g cos ωt`; the last outer mass is
//! free. A [`Cell`] is one unit without the base amplitude (a chain has one base); a chain of
//! cells with stops becomes a [`crate::LinearModel`] through
//! [`crate::LinearModel::graded_chain`].
//!
//! [`chain_response`] solves the linear chain (no stops) by transfer matrices. Eliminating the
//! inner mass (`U_i = s_i U_o / D`, `s_i = k_i + iωc_i`, `D = s_i − m_i ω²`) leaves each cell
//! as one outer mass of effective dynamic mass `m_eff(ω) = m_o + m_i s_i / D` on the coupling
//! `κ = k_o + iωc_o`. With the state `(U_j, F_{j+1})` (`F_j = κ_j (U_j − U_{j−1})`, the force in
//! spring `j`), Newton's law of outer mass `j`, `F_{j+1} − F_j = −ω² m_eff,j U_j`, and spring
//! `j` give the backward step
//!
//! `F_j = F_{j+1} + ω² m_eff,j U_j`, `U_{j−1} = U_j − F_j / κ_j`,
//!
//! started at the free end `(U_N, F_{N+1}) = (1, 0)` and scaled at the end so that
//! `U_0 = u_g`. Two things keep it accurate and finite:
//!
//! - each step is multiplied through by `D_j`, so the local resonance `D_j = 0` (where
//!   `m_eff,j` is infinite and outer mass `j` stands still) is an ordinary step: with
//!   `A_j = ω² m_eff,j D_j = ω² (m_o,j D_j + m_i,j s_i,j)`,
//!   `F̃_j = D_j F̃_{j+1} + A_j Ũ_j`, `Ũ_{j−1} = D_j Ũ_j − F̃_j / κ_j`, and then
//!   `U_j = u_g (∏_{k≤j} D_k) Ũ_j / Ũ_0`, `U_i,j = u_g s_i,j (∏_{k<j} D_k) Ũ_j / Ũ_0`;
//! - the sweep runs from the free end towards the base, the direction in which the physical
//!   solution grows inside a stop band (it decays away from the base), so nothing is computed
//!   as a small difference of large numbers; the states are kept normalised with their
//!   logarithmic scale carried apart, so 64 cells deep in a stop band neither overflow nor
//!   underflow before the final product.
//!
//! The finite chain has no bounded steady state where `Ũ_0 = 0` (an undamped resonance of the
//! chain on a fixed base); that is declared when `|Ũ_0|` is within rounding of the sizes of the
//! terms that form it (`CHAIN_RESONANCE_ULPS = 64.0`) and reported as `unbounded`, never NaN.

use nalgebra::{Complex, DMatrix, DVector};

use crate::model::{out_of_range, ContactPair, HarmonicForcing, LinearModel, ModelError};
use crate::unit::{Damping, Stops, Unit, UnitError};

/// The most cells a chain may have. Enough for the attenuation of a stop band to reach the
/// floor of double precision many times over (a stop band of the paper's cell attenuates by
/// `e^{−1}` per cell or more at its centre), and few enough that the `2N`-dimensional models
/// of the impacting chain stay cheap.
pub const MAX_CELLS: usize = 64;

/// A cell of a chain: a mass-in-mass unit without the base amplitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// Outer mass `m_o > 0`.
    pub outer_mass: f64,
    /// Inner mass `m_i > 0`.
    pub inner_mass: f64,
    /// Spring `k_o > 0` tying this cell's outer mass to the previous cell's (the first cell's
    /// to the base).
    pub outer_stiffness: f64,
    /// Outer-to-inner spring `k_i > 0`.
    pub inner_stiffness: f64,
    /// Dashpots: `outer` beside `k_o`, `inner` beside `k_i`; `None` means none.
    pub damping: Option<Damping>,
}

impl Cell {
    /// The cell of `unit`: its masses, springs and dashpots (its base amplitude is the
    /// chain's, not the cell's).
    pub fn of_unit(unit: &Unit) -> Self {
        Self {
            outer_mass: unit.outer_mass,
            inner_mass: unit.inner_mass,
            outer_stiffness: unit.outer_stiffness,
            inner_stiffness: unit.inner_stiffness,
            damping: unit.damping,
        }
    }

    /// The dashpots `(c_o, c_i)`, zero without damping.
    pub fn dashpots(&self) -> (f64, f64) {
        self.damping.map_or((0.0, 0.0), |d| (d.outer, d.inner))
    }

    /// Checks the cell as cell `index` of a chain: masses and stiffnesses finite and `> 0`,
    /// dashpots finite and `≥ 0`.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the first bad field as `chain[index].outer_mass`,
    /// `chain[index].inner_mass`, `chain[index].outer_stiffness`,
    /// `chain[index].inner_stiffness`, `chain[index].damping.outer` or
    /// `chain[index].damping.inner`.
    pub fn validate(&self, index: usize) -> Result<(), ModelError> {
        self.validate_as(&format!("chain[{index}]"))
    }

    /// [`Cell::validate`] with the fields named `{prefix}.outer_mass`, ….
    pub(crate) fn validate_as(&self, prefix: &str) -> Result<(), ModelError> {
        for (name, value) in [
            ("outer_mass", self.outer_mass),
            ("inner_mass", self.inner_mass),
            ("outer_stiffness", self.outer_stiffness),
            ("inner_stiffness", self.inner_stiffness),
        ] {
            check(format!("{prefix}.{name}"), value, value > 0.0, "> 0")?;
        }
        if let Some(d) = self.damping {
            for (name, value) in [("outer", d.outer), ("inner", d.inner)] {
                check(
                    format!("{prefix}.damping.{name}"),
                    value,
                    value >= 0.0,
                    ">= 0",
                )?;
            }
        }
        Ok(())
    }
}

pub(crate) fn check(
    field: String,
    value: f64,
    ok: bool,
    allowed: &'static str,
) -> Result<(), ModelError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(ModelError::OutOfRange {
            field,
            value,
            allowed,
        })
    }
}

/// Checks a chain: between 1 and [`MAX_CELLS`] cells, each valid, and the base amplitude
/// finite and `> 0`.
///
/// # Errors
/// [`ModelError::OutOfRange`] naming `chain` (with the number of cells as the value) when
/// there are none or more than [`MAX_CELLS`], then the first bad field of a cell (see
/// [`Cell::validate`]), then `base.amplitude`.
pub(crate) fn validate_chain(cells: &[Cell], base_amplitude: f64) -> Result<(), ModelError> {
    let count = cells.len();
    check(
        "chain".to_string(),
        count as f64,
        (1..=MAX_CELLS).contains(&count),
        "between 1 and 64 cells (MAX_CELLS)",
    )?;
    for (j, cell) in cells.iter().enumerate() {
        cell.validate(j)?;
    }
    check(
        "base.amplitude".to_string(),
        base_amplitude,
        base_amplitude > 0.0,
        "> 0",
    )
}

/// The matrices and contact pairs of a chain with stops, assembled in the order of
/// [`crate::LinearModel::chain`] so that identical cells give the same model bit for bit.
pub(crate) struct ChainMatrices {
    pub(crate) mass: DMatrix<f64>,
    pub(crate) damping: DMatrix<f64>,
    pub(crate) stiffness: DMatrix<f64>,
    pub(crate) forcing: HarmonicForcing,
    pub(crate) pairs: Vec<ContactPair>,
}

/// Checks and assembles a chain with stops (see [`crate::LinearModel::graded_chain`]).
pub(crate) fn assemble(
    cells: &[(Cell, Stops)],
    base_amplitude: f64,
) -> Result<ChainMatrices, ModelError> {
    let linear: Vec<Cell> = cells.iter().map(|(cell, _)| *cell).collect();
    validate_chain(&linear, base_amplitude)?;
    for (j, (_, stops)) in cells.iter().enumerate() {
        check(
            format!("chain[{j}].stops.gap"),
            stops.gap,
            stops.gap > 0.0,
            "> 0",
        )?;
        check(
            format!("chain[{j}].stops.restitution"),
            stops.restitution,
            (0.0..=1.0).contains(&stops.restitution),
            "in [0, 1]",
        )?;
    }
    let n = 2 * cells.len();
    let mut mass = DMatrix::zeros(n, n);
    let mut damping = DMatrix::zeros(n, n);
    let mut stiffness = DMatrix::zeros(n, n);
    // A spring (dashpot) of rate `k` between coordinates `a` and `b`.
    let link = |m: &mut DMatrix<f64>, a: usize, b: usize, k: f64| {
        m[(a, a)] += k;
        m[(b, b)] += k;
        m[(a, b)] -= k;
        m[(b, a)] -= k;
    };
    let mut pairs = Vec::with_capacity(cells.len());
    for (j, (cell, stops)) in cells.iter().enumerate() {
        let (o, i) = (2 * j, 2 * j + 1);
        let (ko, ki) = (cell.outer_stiffness, cell.inner_stiffness);
        let (co, ci) = cell.dashpots();
        mass[(o, o)] = cell.outer_mass;
        mass[(i, i)] = cell.inner_mass;
        if j == 0 {
            stiffness[(o, o)] += ko;
            damping[(o, o)] += co;
        } else {
            link(&mut stiffness, o, o - 2, ko);
            link(&mut damping, o, o - 2, co);
        }
        link(&mut stiffness, o, i, ki);
        link(&mut damping, o, i, ci);
        let mut direction = DVector::zeros(n);
        direction[o] = -1.0;
        direction[i] = 1.0;
        pairs.push(ContactPair {
            direction,
            gap_side1: stops.gap,
            gap_side2: stops.gap,
            restitution: stops.restitution,
        });
    }
    let (ko, co) = (cells[0].0.outer_stiffness, cells[0].0.dashpots().0);
    let mut cosine = DVector::zeros(n);
    cosine[0] = ko * base_amplitude;
    let mut sine_per_omega = DVector::zeros(n);
    sine_per_omega[0] = -co * base_amplitude;
    let forcing = HarmonicForcing {
        cosine,
        sine: DVector::zeros(n),
        sine_per_omega,
        harmonics: Vec::new(),
    };
    Ok(ChainMatrices {
        mass,
        damping,
        stiffness,
        forcing,
        pairs,
    })
}

/// Undamped resonance of a finite chain is declared when `|Ũ_0|` (see the module notes) is
/// within `CHAIN_RESONANCE_ULPS` ulps of its first-order rounding scale
/// `Σ_j |ℓ_j| S_j |x̃_j|`: `Ũ_0 = ℓ_j M_j x̃_j` for every `j`, with `ℓ_j = (1, 0) M_1 ⋯ M_{j−1}`
/// the forward product, `M_j` cell `j`'s scaled backward step and `S_j` its entries' term sizes
/// (`|k_i| + m_i ω² + ω c_i` for `D`, …), so a relative error `ε` in each term of each step moves
/// `Ũ_0` by at most `ε` times that sum. Reasoning (not a measurement): each entry is formed and
/// applied with a few complex roundings; 64 is the margin `RESONANCE_ULPS = 64.0`
/// leaves for the unit, whose determinant a one-cell chain's `Ũ_0` is (over `κ`).
pub(crate) const CHAIN_RESONANCE_ULPS: f64 = 64.0;

/// The linear chain's steady state `u(t) = Re{U e^{iωt}}` at one frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainResponse {
    /// The angular frequency `ω`.
    pub omega: f64,
    /// `U_o,j` of every cell, base side first (infinite when unbounded).
    pub outer: Vec<Complex<f64>>,
    /// `U_i,j` of every cell (infinite when unbounded).
    pub inner: Vec<Complex<f64>>,
    /// `|U_o,j|` of every cell: `max_t |u_o,j(t)|`.
    pub cell_outer_amplitudes: Vec<f64>,
    /// `|U_o,N|`, the last cell's outer amplitude; `+∞` when unbounded.
    pub outer_amplitude: f64,
    /// `T = 20 log10(|U_o,N| / u_g)`: `+∞` when unbounded, `−∞` when the last outer mass stands
    /// exactly still.
    pub transmittance_db: f64,
    /// True at an undamped resonance of the chain (see `CHAIN_RESONANCE_ULPS = 64.0`): no bounded
    /// steady state exists.
    pub unbounded: bool,
}

/// A complex number with a separate logarithmic scale: `value · e^{log_scale}`.
#[derive(Debug, Clone, Copy)]
struct Scaled {
    value: Complex<f64>,
    log_scale: f64,
}

/// One backward step's coefficients of cell `j` at `ω`.
struct Step {
    /// `s_i = k_i + iωc_i`.
    inner_coupling: Complex<f64>,
    /// `D = s_i − m_i ω²`.
    d: Complex<f64>,
    /// `A = ω² (m_o D + m_i s_i)`.
    a: Complex<f64>,
    /// `κ = k_o + iωc_o`.
    kappa: Complex<f64>,
    /// Sizes of the terms of `D` and `A` (sums of magnitudes).
    d_size: f64,
    a_size: f64,
}

impl Step {
    fn new(cell: &Cell, omega: f64) -> Self {
        let (co, ci) = cell.dashpots();
        let w2 = omega * omega;
        let inner_coupling = Complex::new(cell.inner_stiffness, omega * ci);
        let d = inner_coupling - cell.inner_mass * w2;
        let a = (d * cell.outer_mass + inner_coupling * cell.inner_mass) * w2;
        let d_size = cell.inner_stiffness + cell.inner_mass * w2 + omega * ci;
        let s_size = cell.inner_stiffness + omega * ci;
        Self {
            inner_coupling,
            d,
            a,
            kappa: Complex::new(cell.outer_stiffness, omega * co),
            d_size,
            a_size: w2 * (cell.outer_mass * d_size + cell.inner_mass * s_size),
        }
    }
}

/// The linear chain's steady state at `omega` by transfer matrices (see the module notes),
/// finite wherever a bounded steady state exists, damped or not.
///
/// # Errors
/// [`ModelError::OutOfRange`] from `validate_chain`, or naming `omega` if it is not finite
/// and `≥ 0`.
pub fn chain_response(
    cells: &[Cell],
    base_amplitude: f64,
    omega: f64,
) -> Result<ChainResponse, ModelError> {
    validate_chain(cells, base_amplitude)?;
    check("omega".to_string(), omega, omega >= 0.0, ">= 0")?;
    let n = cells.len();
    let steps: Vec<Step> = cells.iter().map(|c| Step::new(c, omega)).collect();
    // Backward sweep: x̃_j = (Ũ_j, F̃_{j+1}) kept normalised, `states[j]` its first entry and
    // `tails[j]` the whole state, both with the log scale `log_scale`.
    let zero = Complex::new(0.0, 0.0);
    let mut tails = vec![(zero, zero, 0.0); n + 1];
    let (mut u, mut f) = (Complex::new(1.0, 0.0), zero);
    let mut log_scale = 0.0;
    tails[n] = (u, f, log_scale);
    for j in (1..=n).rev() {
        let s = &steps[j - 1];
        let f_new = s.d * f + s.a * u;
        let u_new = s.d * u - f_new / s.kappa;
        let r = u_new.norm().max(f_new.norm());
        if r == 0.0 {
            // Both entries exactly zero: Ũ_0 = 0 below, a resonance.
            u = zero;
            break;
        }
        (u, f) = (u_new / r, f_new / r);
        log_scale += r.ln();
        tails[j - 1] = (u, f, log_scale);
    }
    let states: Vec<Scaled> = tails
        .iter()
        .map(|&(value, _, log_scale)| Scaled { value, log_scale })
        .collect();
    let resonance =
        u.norm() <= CHAIN_RESONANCE_ULPS * f64::EPSILON * rounding_scale(&steps, &tails);
    if resonance {
        let inf = Complex::new(f64::INFINITY, 0.0);
        return Ok(ChainResponse {
            omega,
            outer: vec![inf; n],
            inner: vec![inf; n],
            cell_outer_amplitudes: vec![f64::INFINITY; n],
            outer_amplitude: f64::INFINITY,
            transmittance_db: f64::INFINITY,
            unbounded: true,
        });
    }
    let base = states[0];
    // U_j = u_g (∏_{k≤j} D_k) Ũ_j / Ũ_0; `prefix` is ∏_{k<j} D_k, scaled.
    let mut prefix = Scaled {
        value: Complex::new(1.0, 0.0),
        log_scale: 0.0,
    };
    let mut outer = Vec::with_capacity(n);
    let mut inner = Vec::with_capacity(n);
    let amplitude = |factor: Complex<f64>, prefix: Scaled, state: Scaled| {
        if factor == Complex::new(0.0, 0.0)
            || prefix.value == Complex::new(0.0, 0.0)
            || state.value == Complex::new(0.0, 0.0)
        {
            return Complex::new(0.0, 0.0);
        }
        let ratio = factor * prefix.value * state.value / base.value;
        ratio * (prefix.log_scale + state.log_scale - base.log_scale).exp() * base_amplitude
    };
    for j in 1..=n {
        let s = &steps[j - 1];
        inner.push(amplitude(s.inner_coupling, prefix, states[j]));
        outer.push(amplitude(s.d, prefix, states[j]));
        let norm = s.d.norm();
        prefix = if norm == 0.0 {
            Scaled {
                value: Complex::new(0.0, 0.0),
                log_scale: 0.0,
            }
        } else {
            Scaled {
                value: prefix.value * (s.d / norm),
                log_scale: prefix.log_scale + norm.ln(),
            }
        };
    }
    let cell_outer_amplitudes: Vec<f64> = outer.iter().map(|u| u.norm()).collect();
    let last = cell_outer_amplitudes[n - 1];
    Ok(ChainResponse {
        omega,
        outer,
        inner,
        transmittance_db: crate::linear::transmittance_db(last, base_amplitude),
        cell_outer_amplitudes,
        outer_amplitude: last,
        unbounded: false,
    })
}

/// `Σ_j |ℓ_j| S_j |x̃_j|` of `CHAIN_RESONANCE_ULPS = 64.0`, relative to the scale of `x̃_0`:
/// `tails[j] = (Ũ_j, F̃_{j+1}, log scale)` normalised, `ℓ_j` carried forward normalised too.
fn rounding_scale(steps: &[Step], tails: &[(Complex<f64>, Complex<f64>, f64)]) -> f64 {
    let base_log = tails[0].2;
    let (mut l0, mut l1) = (Complex::new(1.0, 0.0), Complex::new(0.0, 0.0));
    let mut l_log = 0.0;
    let mut total = 0.0;
    for (j, s) in steps.iter().enumerate() {
        let (u, f, x_log) = tails[j + 1];
        let kappa = s.kappa.norm();
        // S = [[|D| + |A|/|κ|, |D|/|κ|], [|A|, |D|]] in term sizes.
        let s00 = s.d_size + s.a_size / kappa;
        let s01 = s.d_size / kappa;
        let term = l0.norm() * (s00 * u.norm() + s01 * f.norm())
            + l1.norm() * (s.a_size * u.norm() + s.d_size * f.norm());
        total += term * (l_log + x_log - base_log).exp();
        // ℓ ← ℓ M_j, M = [[D − A/κ, −D/κ], [A, D]].
        let m00 = s.d - s.a / s.kappa;
        let m01 = -s.d / s.kappa;
        let (n0, n1) = (l0 * m00 + l1 * s.a, l0 * m01 + l1 * s.d);
        let r = n0.norm().max(n1.norm());
        if r == 0.0 {
            break;
        }
        (l0, l1) = (n0 / r, n1 / r);
        l_log += r.ln();
    }
    total
}

/// The chain constructors of [`LinearModel`] (here, so that the model does not depend on
/// the chain: the chain builds models).
impl LinearModel {
    /// The unit as a model: `u = (u_o, u_i)`, the matrices of [`Unit`], the forcing
    /// `f_c = (k_o u_g, 0)`, `f_ω = (−c_o u_g, 0)`, and one pair `w = (−1, 1)` (`r = u_i − u_o`)
    /// with both gaps `Δ`.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] with the field of [`Unit::validate`] or [`Stops::validate`].
    pub fn unit(unit: &Unit, stops: &Stops) -> Result<Self, ModelError> {
        Self::chain(unit, stops, 1)
    }

    /// `cells` copies of the unit in series: outer mass `j` tied to outer mass `j − 1` by `k_o`
    /// and `c_o` (the first to the base), inner mass `j` inside outer mass `j` by `k_i` and
    /// `c_i`, and one contact pair per cell with the stops of `stops`. Coordinates
    /// `u = (u_o,1, u_i,1, u_o,2, u_i,2, …)`; pair `j` is cell `j`'s `r_j = u_i,j − u_o,j`.
    /// One cell is [`LinearModel::unit`]; any number is [`LinearModel::graded_chain`] of equal
    /// cells.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] with the field of [`Unit::validate`] or [`Stops::validate`],
    /// `chain.cells` if `cells` is 0, or `chain` if it is above [`MAX_CELLS`].
    pub fn chain(unit: &Unit, stops: &Stops, cells: usize) -> Result<Self, ModelError> {
        let from_unit = |e: UnitError| match e {
            UnitError::OutOfRange {
                field,
                value,
                allowed,
            } => out_of_range(field.to_string(), value, allowed),
        };
        unit.validate().map_err(from_unit)?;
        stops.validate().map_err(from_unit)?;
        if cells == 0 {
            return Err(out_of_range("chain.cells".to_string(), 0.0, ">= 1"));
        }
        let cell = Cell::of_unit(unit);
        Self::graded_chain(&vec![(cell, *stops); cells], unit.base_amplitude)
    }

    /// A graded chain: cell `j` with its own masses, springs, dashpots and stops, in series as
    /// in [`LinearModel::chain`] (cell `j`'s `k_o`, `c_o` tie its outer mass to cell `j − 1`'s,
    /// the first cell's to the base, which moves as `base_amplitude · cos ωt`). Identical cells
    /// give [`LinearModel::chain`] and one cell [`LinearModel::unit`], bit for bit.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming `chain` if there are no cells or more than
    /// [`MAX_CELLS`], else the first bad field as `chain[j].outer_mass`, …,
    /// `chain[j].damping.inner` (see [`crate::Cell::validate`]), then `base.amplitude`, then
    /// `chain[j].stops.gap` (`> 0`) or `chain[j].stops.restitution` (in `[0, 1]`).
    pub fn graded_chain(cells: &[(Cell, Stops)], base_amplitude: f64) -> Result<Self, ModelError> {
        let m = assemble(cells, base_amplitude)?;
        Self::new(m.mass, m.damping, m.stiffness, m.forcing, m.pairs)
    }
}
