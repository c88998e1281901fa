//! The tangent flow: flight propagators, impact saltation matrices, the stuck phase's reduced
//! propagator.

use super::*;

/// The tangent flow along a run: the Jacobian of the current state with respect to the start
/// state, as the product of the flights' propagators and the impacts' saltation matrices.
pub(crate) struct Tangent {
    /// `∂y/∂y(0)`.
    pub(crate) jacobian: DMatrix<f64>,
    /// The impacts in time order: pair, side and time since the start.
    pub(crate) impacts: Vec<(usize, i8, f64)>,
    /// The time since the start of the first sticking, if any: the Jacobian then maps onto the
    /// held pair's constrained tangent space (rank `2n − 2`), no longer a smooth map of the
    /// start state.
    pub(crate) sticking: Option<f64>,
    /// Whether [`Self::product`] holds the Jacobian just before the impact of the contact being
    /// resolved: a stick that follows it replaces both by one plastic saltation from the state
    /// before.
    pub(super) before_impact: bool,
    /// Sticks (plastic holds on a stop) so far.
    pub(crate) sticks: u64,
    /// Which pairs have stuck so far (each collapses two tangent directions).
    pub(crate) stuck_pairs: Vec<bool>,
    /// Time spent held on a stop so far.
    pub(crate) stuck_time: f64,
    /// The compliant contacts so far, in time order of their entries.
    pub(crate) contacts: Vec<TangentContact>,
    /// Storage for a flight's propagator and the product, reused by every flight (the product
    /// also keeps the Jacobian before an impact, see [`Self::before_impact`]).
    pub(super) propagator: DMatrix<f64>,
    pub(super) product: DMatrix<f64>,
}

impl Tangent {
    /// The identity tangent of a `2n`-dimensional state, for `pairs` contact pairs.
    pub(super) fn new(n: usize, pairs: usize) -> Self {
        Tangent {
            jacobian: DMatrix::identity(2 * n, 2 * n),
            impacts: Vec::new(),
            sticking: None,
            before_impact: false,
            sticks: 0,
            stuck_pairs: vec![false; pairs],
            stuck_time: 0.0,
            contacts: Vec::new(),
            propagator: DMatrix::zeros(0, 0),
            product: DMatrix::zeros(0, 0),
        }
    }
}

impl Engine<'_> {
    /// Applies the saltation matrix of an impact of pair `p` to the tangent `t`, in place:
    /// `S = Ĝ + (f⁺ − Ĝ f⁻) h_xᵀ / (h_x · f⁻)`, with the contact function `h = d·u ∓ gap`
    /// (`h_x = (d, 0)`, `h_x · f⁻ = ṙ⁻`), `Ĝ` the identity on positions and the restitution
    /// map `G = I − (1 + e) M⁻¹d dᵀ/w` (`w = dᵀM⁻¹d`) on velocities, `f` the vector field.
    /// The jump of the field is closed form: with `v⁺ − v⁻ = −(1 + e) ṙ⁻ M⁻¹d / w`,
    /// `(f⁺ − Ĝ f⁻)/ṙ⁻ = ((1 + e)/w) (−M⁻¹d, M⁻¹CM⁻¹d + M⁻¹d r̈⁻/ṙ⁻)`, `r̈⁻` the free
    /// relative acceleration just before. So `S J` is `J` with its velocity rows corrected
    /// along `M⁻¹d` and a rank-one term in `dᵀ J_u`: no matrix is formed. `det S = e²`.
    pub(super) fn apply_saltation(
        &self,
        t: &mut Tangent,
        p: &Pair,
        before: &DVector<f64>,
        tau: f64,
    ) {
        let n = self.n;
        let factor = (1.0 + p.spec.restitution) / p.compliance;
        let rdot = p.direction.dot(&before.rows(n, n));
        let rddot = self.free_relative_acceleration(p, before, tau);
        let ratio = rddot / rdot;
        let j = &mut t.jacobian;
        for col in 0..j.ncols() {
            let mut a = 0.0; // dᵀ δu
            let mut b = 0.0; // dᵀ δu̇
            for i in 0..n {
                a += p.direction[i] * j[(i, col)];
                b += p.direction[i] * j[(n + i, col)];
            }
            for i in 0..n {
                j[(i, col)] -= factor * p.mobility[i] * a;
                j[(n + i, col)] +=
                    factor * (-p.mobility[i] * b + (p.drag[i] + p.mobility[i] * ratio) * a);
            }
        }
    }

    /// Runs `periods` periods from state `y` at the section `t = 0` with the tangent flow: the
    /// state at `t = periods·T` and the tangent record (Jacobian, impacts, sticking).
    ///
    /// # Errors
    /// As [`Engine::next_iter`].
    pub(crate) fn tangent_run(
        &mut self,
        y: &DVector<f64>,
        periods: u32,
    ) -> Result<(DVector<f64>, Tangent), SimulationError> {
        let identity = DMatrix::identity(y.len(), y.len());
        self.tangent_periods(y, identity, periods as u64, |_| Ok(()))
    }

    /// [`Engine::tangent_run`] over `periods` periods with the tangent flow applied to `frame`
    /// (`2n` rows; the identity gives the Jacobian), calling `at_section` with the tangent at
    /// each section `t = kT`, `k ≥ 1` (it may replace the Jacobian, e.g. by an orthonormal
    /// frame, or stop the run with an error).
    ///
    /// # Errors
    /// As [`Engine::next_iter`], and those of `at_section`.
    pub(crate) fn tangent_periods<F>(
        &mut self,
        y: &DVector<f64>,
        frame: DMatrix<f64>,
        periods: u64,
        mut at_section: F,
    ) -> Result<(DVector<f64>, Tangent), SimulationError>
    where
        F: FnMut(&mut Tangent) -> Result<(), SimulationError>,
    {
        let n = self.n;
        let plan = Plan::fixed(periods);
        let mut state = self.init(
            &Start {
                state: y.clone(),
                time: 0.0,
            },
            &plan,
        )?;
        let mut tangent = Tangent::new(n, self.pairs.len());
        tangent.jacobian = frame;
        while state.k < periods {
            state.tangent = Some(tangent);
            let at_section_reached = self.next_iter(&mut state, &plan);
            tangent = state
                .tangent
                .take()
                .ok_or_else(|| SimulationError::Option("tangent flow lost".into()))?;
            if at_section_reached? {
                at_section(&mut tangent)?;
            }
        }
        Ok((state.y, tangent))
    }

    /// The restitution of [`Self::impact`] with the tangent flow's saltation matrix (kept out of
    /// line: ordinary runs never come here).
    #[cold]
    #[inline(never)]
    pub(super) fn impact_with_tangent(&self, state: &mut RunState, c: Contact) {
        if let Some(t) = state.tangent.as_mut() {
            let time = state.k as f64 * self.period + state.tau;
            // `product` keeps the Jacobian before the impact.
            if t.product.shape() != t.jacobian.shape() {
                t.product = t.jacobian.clone();
            } else {
                t.product.copy_from(&t.jacobian);
            }
            t.before_impact = true;
            self.apply_saltation(t, &self.pairs[c.pair], &state.y, state.tau);
            t.impacts.push((c.pair, c.side, time));
        }
        let mode = state.mode;
        self.restitute(c.pair, &mut state.y, None, mode);
    }

    /// The tangent flow through a flight of duration `span` (out of line, as above).
    #[cold]
    #[inline(never)]
    pub(super) fn propagate_tangent(&self, tangent: &mut Tangent, span: f64) {
        Self::propagate_flow_tangent(&self.free, tangent, span);
    }

    /// The tangent flow through a flight of duration `span` of `flow` (the free flow, or a
    /// compliant contact's augmented flow): its homogeneous propagator times the tangent.
    #[cold]
    #[inline(never)]
    pub(super) fn propagate_flow_tangent(flow: &LinearFlow, tangent: &mut Tangent, span: f64) {
        flow.propagator_into(span, &mut tangent.propagator);
        if tangent.product.shape() != tangent.jacobian.shape() {
            tangent.product = tangent.jacobian.clone();
        }
        tangent
            .product
            .gemm(1.0, &tangent.propagator, &tangent.jacobian, 0.0);
        std::mem::swap(&mut tangent.product, &mut tangent.jacobian);
    }

    /// The tangent flow through a stick of pair `pair` at time `time` since the start (out of
    /// line): the plastic saltation matrix from the state before the contact (an impact
    /// resolved just before at the same contact is replaced by it, since the plastic map
    /// absorbs any restitution: `G₀ G_e = G₀`).
    ///
    /// A plastic reset `v⁺ = G₀ v⁻` (`G₀ = I − M⁻¹d dᵀ/w`, `w = dᵀM⁻¹d`) on the surface
    /// `h = d·u ∓ gap = 0`, onto the constrained flow `f_s`, has the saltation matrix
    /// `S = Ĝ₀ + (f_s⁺ − Ĝ₀ f⁻) h_xᵀ / ṙ⁻`. The constrained acceleration is the free one
    /// projected, `a_s = G₀ a`, so `f_s⁺ − Ĝ₀ f⁻ = ṙ⁻ (−M⁻¹d/w, G₀ M⁻¹ C M⁻¹d/w)`: the
    /// division cancels, and `S = Ĝ₀ + c h_xᵀ` with `c = (−M⁻¹d, G₀ M⁻¹C M⁻¹d)/w`, a
    /// constant of the pair, valid down to a contact at zero relative velocity. `S` maps every
    /// perturbation onto the constrained tangent space `d·δu = d·δu̇ = 0` (rank `2n − 2`).
    #[cold]
    #[inline(never)]
    pub(super) fn stick_tangent(&self, t: &mut Tangent, pair: usize, time: f64) {
        let n = self.n;
        let p = &self.pairs[pair];
        let w = p.compliance;
        let mut s = DMatrix::<f64>::identity(2 * n, 2 * n);
        let projection = &p.mobility * p.direction.transpose() / w;
        let mut block = s.view_mut((n, n), (n, n));
        block -= &projection;
        let mut c = DVector::zeros(2 * n);
        c.rows_mut(0, n).copy_from(&(-&p.mobility / w));
        if self.model.has_damping() {
            let drag = &p.drag / w;
            let projected = &drag - &projection * &drag;
            c.rows_mut(n, n).copy_from(&projected);
        }
        let mut h_x = DVector::zeros(2 * n);
        h_x.rows_mut(0, n).copy_from(&p.direction);
        s += c * h_x.transpose();
        t.jacobian = if std::mem::take(&mut t.before_impact) {
            s * &t.product
        } else {
            s * &t.jacobian
        };
        t.sticking.get_or_insert(time);
        t.sticks += 1;
        if let Some(stuck) = t.stuck_pairs.get_mut(pair) {
            *stuck = true;
        }
    }

    /// The tangent flow through a stuck phase of duration `span` (out of line): the reduced
    /// flow's propagator `P_r` in the reduced coordinates, `δy ← E P_r Eᵀ δy` with
    /// `E = diag(T, T)` (`T` the orthonormal basis of `d⊥`). The tangent is already in the
    /// constrained space (the stick's saltation put it there), where `Eᵀ` is exact.
    ///
    /// The release that ends the phase needs no saltation: it happens where the contact force
    /// is zero, so the free and constrained vector fields agree there (`S = I`).
    #[cold]
    #[inline(never)]
    pub(super) fn propagate_stuck_tangent(st: &Stuck, t: &mut Tangent, span: f64) {
        let n = st.basis.nrows();
        let nr = st.basis.ncols();
        let mut e = DMatrix::zeros(2 * n, 2 * nr);
        e.view_mut((0, 0), (n, nr)).copy_from(&st.basis);
        e.view_mut((n, nr), (n, nr)).copy_from(&st.basis);
        let reduced = st.flow.propagator(span);
        t.jacobian = &e * (reduced * (e.transpose() * &t.jacobian));
        t.stuck_time += span;
    }
}
