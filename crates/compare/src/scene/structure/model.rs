//! The checked structure: its matrices, its stops as contact pairs and its floating groups,
//! and each solver's model built from it ([`Structure::event_model`],
//! [`Structure::analytic_model`]).

use nalgebra::{Complex, DMatrix, DVector};

/// One stop, resolved: a contact pair `r = u[plus] − u[minus]` (`None`: the frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stop {
    /// The body counted positive in `r` (`None`: the frame).
    pub plus: Option<usize>,
    /// The body counted negative in `r` (`None`: the frame).
    pub minus: Option<usize>,
    /// Distance to side 1; `+∞`: no stop there.
    pub gap_plus: f64,
    /// Distance to side 2; `+∞`: no stop there.
    pub gap_minus: f64,
    /// What happens at the stop: a rigid impact or a compliant contact.
    pub law: ContactLaw,
}

/// The restitution a compliant stop's contact pair carries in each engine's model: never read
/// (the pair's compliance replaces the impact law), and within every engine's range `[0, 1]`.
const RESTITUTION_UNREAD: f64 = 1.0;

/// A stop's contact law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactLaw {
    /// A rigid stop: an instantaneous impact with Newton restitution `ṙ⁺ = −e ṙ⁻`.
    Rigid {
        /// `e ∈ [0, 1]`.
        restitution: f64,
    },
    /// A compliant (Kelvin–Voigt) stop: while the penetration `δ > 0`, a spring and a dashpot
    /// act between the pair; the contact ends where `δ` returns to 0.
    Compliant {
        /// `k_c`, N/m, `> 0`.
        stiffness: f64,
        /// `c_c`, N·s/m, `≥ 0`.
        damping: f64,
    },
}

impl ContactLaw {
    /// A rigid stop's restitution; `None` for a compliant one.
    pub fn restitution(&self) -> Option<f64> {
        match *self {
            ContactLaw::Rigid { restitution } => Some(restitution),
            ContactLaw::Compliant { .. } => None,
        }
    }
}

impl Stop {
    /// The stop's relative coordinate `r = u[plus] − u[minus]` of the displacements `u` (or
    /// its rate of the velocities), the frame's end counted as 0: the quantity each solver
    /// holds in `[−gap_minus, gap_plus]`.
    ///
    /// # Panics
    /// If `u` has no entry for one of the stop's bodies.
    pub fn relative(&self, u: &[f64]) -> f64 {
        let at = |end: Option<usize>| end.map_or(0.0, |j| u[j]);
        at(self.plus) - at(self.minus)
    }
}

/// One higher harmonic of a structure's forcing, of order `k`:
/// `f_c cos(kωt + φ) + (f_s + kω f_ω) sin(kωt + φ)`, the base's harmonic of that order and
/// the forces' summed. `φ` is the base harmonic's phase (0 when only forces have the order,
/// whose phases are then folded into `f_c` and `f_s`): with a dashpot to the base, the part
/// proportional to `kω` stays a sine of `kωt + φ`, so its derivative in `ω` stays exact.
#[derive(Debug, Clone, PartialEq)]
pub struct ForcingHarmonic {
    /// `k ≥ 2`.
    pub order: u32,
    /// `f_c`: the base's springs times `a_k`, plus each force's `F_k cos(φ_k − φ)`.
    pub cosine: DVector<f64>,
    /// `f_s`: each force's `−F_k sin(φ_k − φ)`.
    pub sine: DVector<f64>,
    /// `f_ω`: the base's dashpots times `−a_k`, per unit of the harmonic's frequency `kω`.
    pub sine_per_omega: DVector<f64>,
    /// `φ`, rad.
    pub phase: f64,
}

impl ForcingHarmonic {
    /// The force's amplitudes on `cos kωt` and `sin kωt` at `omega`: `f_c cos(x + φ) +
    /// s sin(x + φ)` expanded, `(f_c cos φ + s sin φ, s cos φ − f_c sin φ)`,
    /// `s = f_s + kω f_ω`.
    pub fn amplitudes_at(&self, omega: f64) -> (DVector<f64>, DVector<f64>) {
        let s = &self.sine + &self.sine_per_omega * (f64::from(self.order) * omega);
        let (sp, cp) = self.phase.sin_cos();
        (&self.cosine * cp + &s * sp, &s * cp - &self.cosine * sp)
    }
}

/// A checked structure with its matrices: `M ü + C u̇ + K u = f_c cos ωt + (f_s + ω f_ω) sin ωt`
/// plus the higher harmonics ([`ForcingHarmonic`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Structure {
    /// The bodies' names, in coordinate order.
    pub names: Vec<String>,
    /// `M` (diagonal: the bodies' masses).
    pub mass: DMatrix<f64>,
    /// `K`, assembled from the springs (those to the frame or base on the diagonal only).
    pub stiffness: DMatrix<f64>,
    /// `C`, assembled from the dashpots; `None` when every dashpot is zero (or there is none).
    pub damping: Option<DMatrix<f64>>,
    /// `f_c`: the base's springs times `u_g`, plus each force's `F cos φ`.
    pub forcing_cos: DVector<f64>,
    /// `f_s`: each force's `−F sin φ`.
    pub forcing_sin: DVector<f64>,
    /// `f_ω`: the base's dashpots times `−u_g` (the sine part per unit `ω`).
    pub forcing_sin_per_omega: DVector<f64>,
    /// The forcing's higher harmonics, by increasing order (empty: the fundamental alone).
    pub harmonics: Vec<ForcingHarmonic>,
    /// The force on each body per unit base displacement: the stiffness of the springs tied
    /// to the base (a base motion `u_g(t)` of any shape pushes with
    /// `base_stiffness · u_g + base_damping · u̇_g`).
    pub base_stiffness: DVector<f64>,
    /// The force on each body per unit base velocity: the damping of the dashpots tied to the
    /// base.
    pub base_damping: DVector<f64>,
    /// The contact pairs.
    pub stops: Vec<Stop>,
    /// `u_g` (the fundamental's amplitude), when the base moves.
    pub base_amplitude: Option<f64>,
    /// The observed body.
    pub observe: usize,
    /// Per body, the group it floats in when no chain of springs ties it to the frame or the
    /// base (an id shared by the bodies of one group), `None` when springs hold it. A floating
    /// group's position is not set by the linear dynamics (`K` is singular on its
    /// translation): its motion clear of the stops is a family, offset anywhere the stops
    /// allow.
    pub floating: Vec<Option<usize>>,
}

impl Structure {
    /// Whether the structure has floating bodies ([`Structure::floating`]).
    pub fn has_floating(&self) -> bool {
        self.floating.iter().any(Option::is_some)
    }

    /// Whether `stop`'s relative coordinate moves with a floating group's offset: its ends
    /// lie in different groups and one at least floats (the frame never does).
    pub fn floats(&self, stop: &Stop) -> bool {
        let group = |end: Option<usize>| end.and_then(|j| self.floating[j]);
        let (a, b) = (group(stop.minus), group(stop.plus));
        (a.is_some() || b.is_some()) && a != b
    }

    /// Whether a stop is compliant.
    pub fn has_compliant_stops(&self) -> bool {
        self.stops
            .iter()
            .any(|s| matches!(s.law, ContactLaw::Compliant { .. }))
    }

    /// Degrees of freedom (bodies).
    pub fn dofs(&self) -> usize {
        self.names.len()
    }

    /// `f_s + ω f_ω`: the sine part of the forcing at `omega`.
    pub fn forcing_sin_at(&self, omega: f64) -> DVector<f64> {
        &self.forcing_sin + &self.forcing_sin_per_omega * omega
    }

    /// The event-driven simulator's model at `omega`: the matrices as assembled, a contact
    /// pair per stop (a side without a stop has gap `+∞`) with its compliance where the stop
    /// is compliant, damping terms only where a dashpot is not zero, and the harmonics'
    /// amplitudes at `omega`.
    ///
    /// # Errors
    /// [`rattle_event_driven::ModelError`] for `omega` not finite and `> 0`, or a contact
    /// stiffness the simulator refuses (beyond its rounding floor).
    pub fn event_model(
        &self,
        omega: f64,
    ) -> Result<rattle_event_driven::Model, rattle_event_driven::ModelError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(rattle_event_driven::ModelError::OutOfRange {
                field: "omega".into(),
                value: omega,
                allowed: "> 0",
            });
        }
        let contacts = self
            .stops
            .iter()
            .map(|s| rattle_event_driven::ContactPair {
                plus_dof: s.plus,
                minus_dof: s.minus,
                gap_plus: s.gap_plus,
                gap_minus: s.gap_minus,
                restitution: s.law.restitution().unwrap_or(RESTITUTION_UNREAD),
            })
            .collect();
        let model = rattle_event_driven::Model::new(
            self.mass.clone(),
            self.stiffness.clone(),
            self.damping.clone(),
            self.forcing_cos.clone(),
            self.forcing_sin_at(omega),
            contacts,
        )?;
        let model =
            self.stops
                .iter()
                .enumerate()
                .try_fold(model, |model, (k, s)| match s.law {
                    ContactLaw::Rigid { .. } => Ok(model),
                    ContactLaw::Compliant { stiffness, damping } => model
                        .with_compliance(k, rattle_event_driven::Compliance { stiffness, damping }),
                })?;
        if self.harmonics.is_empty() {
            return Ok(model);
        }
        model.with_harmonics(
            self.harmonics
                .iter()
                .map(|h| {
                    let (cos, sin) = h.amplitudes_at(omega);
                    rattle_event_driven::Harmonic {
                        order: h.order,
                        cos,
                        sin,
                    }
                })
                .collect(),
        )
    }

    /// The analytic solver's model: the same matrices and harmonics, each stop a contact pair
    /// of direction `w = e_plus − e_minus` (the frame's entry left out), with its compliance
    /// where the stop is compliant.
    ///
    /// # Errors
    /// [`rattle_analytic::ModelError`] when the analytic model's own checks refuse it (they
    /// accept every checked structure but a contact stiffness beyond the solver's rounding
    /// floor).
    pub fn analytic_model(
        &self,
    ) -> Result<rattle_analytic::LinearModel, rattle_analytic::ModelError> {
        let n = self.dofs();
        let pairs = self
            .stops
            .iter()
            .map(|s| {
                let mut w = DVector::zeros(n);
                if let Some(i) = s.plus {
                    w[i] = 1.0;
                }
                if let Some(i) = s.minus {
                    w[i] = -1.0;
                }
                rattle_analytic::ContactPair {
                    direction: w,
                    gap_side1: s.gap_plus,
                    gap_side2: s.gap_minus,
                    restitution: s.law.restitution().unwrap_or(RESTITUTION_UNREAD),
                }
            })
            .collect();
        let model = rattle_analytic::LinearModel::new(
            self.mass.clone(),
            self.damping.clone().unwrap_or_else(|| DMatrix::zeros(n, n)),
            self.stiffness.clone(),
            rattle_analytic::HarmonicForcing {
                cosine: self.forcing_cos.clone(),
                sine: self.forcing_sin.clone(),
                sine_per_omega: self.forcing_sin_per_omega.clone(),
                harmonics: self
                    .harmonics
                    .iter()
                    .map(|h| rattle_analytic::Harmonic {
                        order: h.order,
                        cosine: h.cosine.clone(),
                        sine: h.sine.clone(),
                        sine_per_omega: h.sine_per_omega.clone(),
                        phase: h.phase,
                    })
                    .collect(),
            },
            pairs,
        )?;
        self.stops
            .iter()
            .enumerate()
            .try_fold(model, |model, (k, s)| match s.law {
                ContactLaw::Rigid { .. } => Ok(model),
                ContactLaw::Compliant { stiffness, damping } => {
                    model.with_compliance(k, rattle_analytic::Compliance { stiffness, damping })
                }
            })
    }

    /// The start at rest at `t = 0`: the `2n` state entries zero.
    pub fn rest(&self) -> rattle_event_driven::Start {
        rattle_event_driven::Start::rest(self.dofs())
    }

    /// The transmittance `20 log10(X / u_g)` of the observed body's amplitude `X`, when the
    /// base moves and the value is finite.
    pub fn transmittance_db(&self, amplitude: f64) -> Option<f64> {
        self.base_amplitude
            .map(|ug| rattle_analytic::transmittance_db(amplitude, ug))
            .filter(|t| t.is_finite())
    }

    /// The impact sequence of the stops `text` over `period` forcing periods: `<stop><side>`
    /// tokens (`0+ 1- 0- 1+`), or with one stop the side characters alone (`+-` reads as
    /// `0+ 0-`).
    ///
    /// # Errors
    /// [`rattle_analytic::SequenceError`] for a text that does not parse or a period out of
    /// range.
    pub fn sequence(
        &self,
        text: &str,
        period: u32,
    ) -> Result<rattle_analytic::ImpactSequence, rattle_analytic::SequenceError> {
        let bare = !text.is_empty() && text.chars().all(|c| matches!(c, '+' | '-'));
        let text = if self.stops.len() == 1 && bare {
            text.chars()
                .map(|c| format!("0{c}"))
                .collect::<Vec<_>>()
                .join(" ")
        } else {
            text.to_owned()
        };
        rattle_analytic::ImpactSequence::parse(&text, period)
    }

    /// Every body's displacement per unit base displacement at `omega` (rad/s) with the stops
    /// removed: `U(ω) = (K − ω²M + iωC)⁻¹ (k_b + iω c_b)`, `k_b` and `c_b` the springs' and
    /// dashpots' ties to the base ([`Structure::base_stiffness`],
    /// [`Structure::base_damping`]), for `u_g = Re(U_g e^{iωt})`, `u_j = Re(U_j U_g e^{iωt})`.
    /// `None` where `K − ω²M + iωC` is singular (an undamped natural frequency).
    pub fn base_responses(&self, omega: f64) -> Option<DVector<Complex<f64>>> {
        let n = self.dofs();
        let damping = |r: usize, c: usize| self.damping.as_ref().map_or(0.0, |d| d[(r, c)]);
        let dynamic = DMatrix::from_fn(n, n, |r, c| {
            Complex::new(
                self.stiffness[(r, c)] - omega * omega * self.mass[(r, c)],
                omega * damping(r, c),
            )
        });
        let force = DVector::from_fn(n, |r, _| {
            Complex::new(self.base_stiffness[r], omega * self.base_damping[r])
        });
        let u = dynamic.lu().solve(&force)?;
        u.iter()
            .all(|h| h.re.is_finite() && h.im.is_finite())
            .then_some(u)
    }

    /// The observed body's displacement per unit base displacement at `omega` (rad/s) with the
    /// stops removed: the observed entry of [`Structure::base_responses`],
    /// `H(ω) = e_obsᵀ (K − ω²M + iωC)⁻¹ (k_b + iω c_b)`. `None` where `K − ω²M + iωC` is
    /// singular (an undamped natural frequency).
    pub fn base_response(&self, omega: f64) -> Option<Complex<f64>> {
        self.base_responses(omega).map(|u| u[self.observe])
    }

    /// Whether some dashpot is not zero.
    pub fn is_damped(&self) -> bool {
        self.damping.is_some()
    }
}
