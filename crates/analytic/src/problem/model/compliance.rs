//! Compliant (Kelvin–Voigt) contact pairs: a spring `k_c` and a dashpot `c_c` along the pair's
//! direction `w` while the pair penetrates its stop, in place of Newton restitution.
//!
//! While the penetration `δ = s r − gap_s > 0` (`r = wᵀu`, `s = ±1` the side), the generalised
//! force `−w (k_c (r − s gap_s) + c_c ṙ)` acts: the motion is the linear flow of
//! `M, C + c_c wwᵀ, K + k_c wwᵀ` with the constant force `k_c s gap_s w` and the same harmonic
//! forcing. The contact ends where `δ` returns to 0 (the spring may pull at its very end, which
//! keeps the flow piecewise linear and exact). The constant force rides on a constant phase
//! state: the pair `(cos 0θ, sin 0θ) = (1, 0)` of order 0 appended to the augmented state, so
//! that a contact phase is, like a free flight, the exponential of an augmented matrix.

use super::{out_of_range, LinearModel, ModelError};
use nalgebra::{DMatrix, DVector};

/// Largest ratio of a compliant pair's contact frequency `ω_c = √(k_c wᵀM⁻¹w)` to the
/// structure's fastest rate `ω_s` (the bound `½(c + √(c² + 4k))` on the moduli of the
/// eigenvalues of the system without contact, `k` and `c` the largest row sums of `|M⁻¹K|`
/// and `|M⁻¹C|`), i.e. a stiffness ratio of `1e12`.
///
/// The cycle's unknowns are event times as fractions of a cycle of the order of the
/// structure's period `2π/ω_s`, resolved to `ε ≈ 2.2e-16` of it. A contact lasts about
/// `π/ω_c`: at the ratio `1e6` its duration is still resolved to `2ε · 1e6 ≈ 4.4e-10` of
/// itself, and it fills `1/(2 · 1e6) = 5e-7` of such a cycle, 500 times the shortest flight
/// that is not two events merging (`MIN_FLIGHT = 1e-9` of the cycle). Beyond it the contact's
/// time scale sinks towards the rounding of the times themselves. The workbench's stiffest
/// contacts (`k_c` = `1e8` times the structure's, a ratio of `1e4`) stay two orders inside.
pub const MAX_CONTACT_FREQUENCY_RATIO: f64 = 1e6;

/// A compliant contact law of a pair (both its sides): a spring of stiffness `k_c` and a
/// dashpot `c_c` in parallel (Kelvin–Voigt) along the pair's direction while it penetrates a
/// stop.
///
/// For a pair of reduced mass `μ = 1/(wᵀM⁻¹w)` that no other force acts on during contact,
/// the exit velocity is `−e` times the entry velocity with `e = exp(−ζπ/√(1 − ζ²))`,
/// `ζ = c_c/(2√(k_c μ))`, after a contact of `π/ω_d`, `ω_d = √(k_c/μ) √(1 − ζ²)`
/// ([`Compliance::restitution`], [`Compliance::contact_duration`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compliance {
    /// The contact spring `k_c > 0` (force per unit of `r`).
    pub stiffness: f64,
    /// The contact dashpot `c_c ≥ 0` (force per unit of `ṙ`).
    pub damping: f64,
}

impl Compliance {
    /// The damping ratio `ζ = c_c/(2√(k_c μ))` of the contact on a pair of reduced mass `μ`.
    pub fn damping_ratio(&self, reduced_mass: f64) -> f64 {
        self.damping / (2.0 * (self.stiffness * reduced_mass).sqrt())
    }

    /// The isolated pair's coefficient of restitution `e = exp(−ζπ/√(1 − ζ²))` (0 when
    /// `ζ ≥ 1`: the overdamped contact does not end).
    pub fn restitution(&self, reduced_mass: f64) -> f64 {
        let zeta = self.damping_ratio(reduced_mass);
        if zeta >= 1.0 {
            0.0
        } else {
            (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp()
        }
    }

    /// The isolated pair's contact duration `π/ω_d`, `ω_d = √(k_c/μ) √(1 − ζ²)` (`+∞` when
    /// `ζ ≥ 1`).
    pub fn contact_duration(&self, reduced_mass: f64) -> f64 {
        let zeta = self.damping_ratio(reduced_mass);
        if zeta >= 1.0 {
            return f64::INFINITY;
        }
        std::f64::consts::PI / ((self.stiffness / reduced_mass).sqrt() * (1.0 - zeta * zeta).sqrt())
    }

    /// The law of stiffness `stiffness` whose isolated restitution on a pair of reduced mass
    /// `reduced_mass` is `restitution ∈ (0, 1]`: `ζ = −ln e/√(π² + ln² e)`,
    /// `c_c = 2ζ√(k_c μ)`.
    pub fn matched(stiffness: f64, restitution: f64, reduced_mass: f64) -> Self {
        let log = restitution.ln();
        let zeta = -log / (std::f64::consts::PI.powi(2) + log * log).sqrt();
        Self {
            stiffness,
            damping: 2.0 * zeta * (stiffness * reduced_mass).sqrt(),
        }
    }
}

/// `½(c + √(c² + 4k))` of the acceleration rows of a first-order system matrix `A` of `n`
/// degrees of freedom (`k`, `c` the largest row sums of `|A|` over the position and the velocity
/// columns): a bound on the moduli of its eigenvalues, the fastest rate of its flow.
pub(crate) fn fastest_rate(system: &DMatrix<f64>, n: usize) -> f64 {
    let row_norm = |col: usize| {
        (n..2 * n)
            .map(|i| (col..col + n).map(|j| system[(i, j)].abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    let (k, c) = (row_norm(0), row_norm(n));
    0.5 * (c + (c * c + 4.0 * k).sqrt())
}

impl LinearModel {
    /// The same model with the contact law of pair `pair` compliant: its impacts become
    /// contact phases (`0+c` in a sequence, [`crate::ImpactSequence`]), its restitution
    /// unused.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming `compliances[pair]` for a pair the model lacks,
    /// `compliances[pair].stiffness` when not finite and `> 0` or when the contact frequency
    /// `√(k_c wᵀM⁻¹w)` exceeds [`MAX_CONTACT_FREQUENCY_RATIO`] times the structure's fastest
    /// rate (models whose `K` and `C` are both zero have no such rate and no such bound), and
    /// `compliances[pair].damping` when not finite and `≥ 0`.
    pub fn with_compliance(
        mut self,
        pair: usize,
        compliance: Compliance,
    ) -> Result<LinearModel, ModelError> {
        if pair >= self.pairs.len() {
            return Err(out_of_range(
                format!("compliances[{pair}]"),
                pair as f64,
                "the index of one of the model's pairs",
            ));
        }
        let field = |name: &str| format!("compliances[{pair}].{name}");
        let k = compliance.stiffness;
        if !(k.is_finite() && k > 0.0) {
            return Err(out_of_range(field("stiffness"), k, "finite and > 0"));
        }
        let c = compliance.damping;
        if !(c.is_finite() && c >= 0.0) {
            return Err(out_of_range(field("damping"), c, "finite and >= 0"));
        }
        let structure = fastest_rate(&self.system_matrix(), self.dofs());
        let contact = (k / self.reduced_mass(pair)).sqrt();
        if structure > 0.0 && contact > MAX_CONTACT_FREQUENCY_RATIO * structure {
            return Err(out_of_range(
                field("stiffness"),
                k,
                "small enough that sqrt(k_c w'M^-1 w) is at most MAX_CONTACT_FREQUENCY_RATIO \
                 (1e6) times the structure's fastest rate (the contact's time scale above the \
                 rounding of the cycle's times)",
            ));
        }
        self.compliances[pair] = Some(compliance);
        Ok(self)
    }

    /// The contact law of pair `pair`: `Some` when compliant ([`LinearModel::with_compliance`]),
    /// `None` when rigid (restitution) or when the model has no such pair.
    pub fn compliance(&self, pair: usize) -> Option<Compliance> {
        self.compliances.get(pair).copied().flatten()
    }

    /// The reduced mass `μ = 1/(wᵀM⁻¹w)` of pair `pair` along its direction.
    ///
    /// # Panics
    /// If `pair` is not an index of [`LinearModel::pairs`].
    pub fn reduced_mass(&self, pair: usize) -> f64 {
        let w = &self.pairs[pair].direction;
        1.0 / w.dot(&(&self.mass_inverse * w))
    }

    /// The augmented matrix of a cycle with contact phases at `omega`: the model's
    /// [`LinearModel::augmented_matrix`] with the constant phase pair of order 0 appended
    /// (two more rows and columns, zero: `(1, 0)` stays constant and forces nothing in free
    /// flight).
    pub(crate) fn compliant_augmented(&self, omega: f64) -> DMatrix<f64> {
        let size = self.augmented_size();
        let mut m = DMatrix::zeros(size + 2, size + 2);
        m.view_mut((0, 0), (size, size))
            .copy_from(&self.augmented_matrix(omega));
        m
    }

    /// What a contact phase of compliant pair `pair` on side `side` adds to
    /// [`Self::compliant_augmented`] (independent of `ω`): `−M⁻¹k_c wwᵀ` and `−M⁻¹c_c wwᵀ` in
    /// the velocity rows of the position and velocity columns, and the constant force
    /// `M⁻¹w k_c s gap_s` in the column of the constant phase state.
    ///
    /// # Panics
    /// If `pair` is not a compliant pair of the model.
    pub(crate) fn contact_increment(&self, pair: usize, side: i8) -> DMatrix<f64> {
        let law = self.compliances[pair].expect("a compliant pair");
        let contact = &self.pairs[pair];
        let n = self.dofs();
        let size = self.augmented_size() + 2;
        let w = &contact.direction;
        let minv_w = &self.mass_inverse * w;
        let outer = &minv_w * w.transpose();
        let stop = if side == 1 {
            contact.gap_side1
        } else {
            -contact.gap_side2
        };
        let mut m = DMatrix::zeros(size, size);
        m.view_mut((n, 0), (n, n))
            .copy_from(&(&outer * -law.stiffness));
        m.view_mut((n, n), (n, n))
            .copy_from(&(&outer * -law.damping));
        m.view_mut((n, size - 2), (n, 1))
            .copy_from(&(&minv_w * (law.stiffness * stop)));
        m
    }
}

impl LinearModel {
    /// The rigid model whose every compliant pair impacts with the isolated pair's restitution
    /// of its contact law ([`Compliance::restitution`]): the limit the compliant orbits tend
    /// to as the contact stiffens at fixed restitution, and the multi-start's source of
    /// guesses for them.
    pub(crate) fn rigid_proxy(&self) -> LinearModel {
        let mut proxy = self.clone();
        for (p, law) in self.compliances.iter().enumerate() {
            if let Some(law) = law {
                proxy.pairs[p].restitution = law.restitution(self.reduced_mass(p));
            }
        }
        proxy.compliances = vec![None; self.pairs.len()];
        proxy
    }

    /// What holding pair `pair` on its stop changes in [`Self::compliant_augmented`] at
    /// `omega`: the accelerations projected onto `wᵀü = 0`, `ü = ΠM⁻¹(f − Cu̇ − Ku)`,
    /// `Π = I − M⁻¹w wᵀ/(wᵀM⁻¹w)` (the stop's force `w λ` takes the part along `w`): `−M⁻¹w wᵀ
    /// / (wᵀM⁻¹w)` times the velocity rows of the free flight's matrix, every column. It
    /// depends on `ω` through the forcing's columns.
    ///
    /// # Panics
    /// If `pair` is not an index of [`LinearModel::pairs`].
    pub(crate) fn stick_increment(&self, omega: f64, pair: usize) -> DMatrix<f64> {
        let n = self.dofs();
        let free = self.compliant_augmented(omega);
        let size = free.nrows();
        let w = &self.pairs[pair].direction;
        let minv_w = &self.mass_inverse * w;
        let projector = &minv_w * w.transpose() / -w.dot(&minv_w);
        let mut m = DMatrix::zeros(size, size);
        m.view_mut((n, 0), (n, size))
            .copy_from(&(projector * free.view((n, 0), (n, size))));
        m
    }

    /// The release condition of pair `pair` as an augmented functional at `omega`:
    /// `wᵀM⁻¹(f − Cu̇ − Ku) / ω²`, the pair's relative acceleration were it free, in units of
    /// displacement (per radian² of the forcing). It is `−λ/(μω²)`, `λ` the stop's force along
    /// `w` and `μ` the reduced mass: zero where the held pair is released.
    ///
    /// # Panics
    /// If `pair` is not an index of [`LinearModel::pairs`].
    pub(crate) fn release_functional(&self, omega: f64, pair: usize) -> DVector<f64> {
        let n = self.dofs();
        let free = self.compliant_augmented(omega);
        let w = &self.pairs[pair].direction;
        free.view((n, 0), (n, free.ncols())).tr_mul(w) / (omega * omega)
    }
}
