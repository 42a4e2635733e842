//! The trial increment for the remaining load (eqs. 43–44 in residual form).
//!
//! With K# the generalized inverse of the reduced stiffness and N the free rigid-body modes,
//!   Δu = K#(r + E Δλ) + N α,
//! r = φ_target P − P_σ + (current contact forces) the out-of-balance force (eqs. 36, 42). The
//! columns of E are the force directions of the closed pairs (w_n, w_t for stick; w_n − dμ w_t
//! for slip, eq. 41, which makes the small system nonsymmetric), the rows of C their
//! constraints (w_n·Δu = −gap, eq. 38; w_t·Δu = 0 for stick, eq. 39). Δλ and α solve
//!   [Cᵀ K# E   Cᵀ N] [Δλ]   [h − Cᵀ K# r]
//!   [Nᵀ E       0  ] [α ] = [  −Nᵀ r    ]
//! whose second row is the equilibrium of each free body. Every Cᵀ K# E entry is a lookup in
//! the flexibility; a trial is one forward sweep of r, this small solve, and one backward sweep
//! of r + E Δλ (the contact DOFs are last in the factor).

use super::engine::{since, Engine};
use super::space::{Full, LoadSweep, Space};
use super::state::{State, TrialIncrement};
use crate::bail;
use crate::contact::{SparseVec, Status};
use crate::element::Element;
use crate::error::Result;
use nalgebra::{DMatrix, DVector, Vector4};
use rayon::prelude::*;
use std::time::Instant;

/// A pivot of the small system's LU below this × the largest one means "singular".
const SINGULAR_PIVOT: f64 = 1e-13;
/// Element loops run on the cores in chunks of at least this many elements (below it the
/// threads' start costs more than the loop).
pub(super) const PARALLEL_CHUNK: usize = 1024;
/// Displacement noise floor: × max |Δu| of the trial.
const DISPLACEMENT_NOISE: f64 = 1e-11;
/// An out-of-balance force within this of c ΔP (relative, 2-norms) is c ΔP (`forward_sweep`):
/// a state balanced to round-off. Corrected states are balanced to ~1e-13 of the load
/// (`max_equilibrium_residual` of the runs), the loop accepts 1e-9 (`equilibrium_tol`).
const BALANCED: f64 = 1e-12;

/// A row of the small system: pair p's normal or tangential constraint.
#[derive(Clone, Copy)]
pub(super) enum Row {
    Normal(usize),
    Tangent(usize),
}

/// K# r at the contact slots and the rigid-body rows −Nᵀ r for the out-of-balance force r; in
/// the full space also r's forward sweep, whose backward sweep waits for the contact forces.
pub(super) struct OutOfBalance {
    pub z0: Vec<f64>,
    pub mode_rhs: Vec<f64>,
    forward_sweep: Vec<f64>,
    /// The prescribed displacement increments ū(target) − u (full space).
    prescribed: Vec<(usize, f64)>,
    /// The obstacle shift increments (c_n, c_t)(target) − (c_n, c_t) per pair.
    pub dshift: Vec<[f64; 2]>,
    /// C⁻¹ Zᵀ r of the low-rank terms (`low_rank`; empty without them).
    low_rank_coefficients: Vec<f64>,
}

/// What a full-space trial for the remaining fraction c solved, kept for the contact sub-steps
/// of its increment (`substeps`): from a state the increment reached linearly the remaining
/// load is (c'/c) r, so its K# r at the contact slots, rigid-body rows and low-rank
/// coefficients are these scaled, and no solve is needed.
#[derive(Clone)]
pub(super) struct TrialBase {
    pub c: f64,
    z0: Vec<f64>,
    mode_rhs: Vec<f64>,
    forward_sweep: Vec<f64>,
    low_rank_coefficients: Vec<f64>,
}

impl TrialBase {
    fn of(oob: &OutOfBalance, c: f64) -> Self {
        TrialBase { c, z0: oob.z0.clone(), mode_rhs: oob.mode_rhs.clone(), forward_sweep: oob.forward_sweep.clone(), low_rank_coefficients: oob.low_rank_coefficients.clone() }
    }

    /// The out-of-balance force of the remaining fraction c' (contact slots only).
    fn scaled(&self, c: f64, dshift: Vec<[f64; 2]>) -> OutOfBalance {
        let k = if self.c > 0.0 { c / self.c } else { 0.0 };
        let times = |v: &[f64]| v.iter().map(|x| k * x).collect();
        OutOfBalance { z0: times(&self.z0), mode_rhs: times(&self.mode_rhs), forward_sweep: vec![], prescribed: vec![], dshift, low_rank_coefficients: vec![] }
    }
}

/// The closed pairs' constraint rows with their right-hand sides h, force directions E and
/// K# E at the contact slots.
pub(super) struct ContactSystem {
    pub rows: Vec<Row>,
    pub h: Vec<f64>,
    pub columns: Vec<Vec<(usize, f64)>>,
    pub flex_columns: Vec<Vec<f64>>,
}

impl Engine<'_> {
    /// The trial increment that takes the state to load fraction `target`: 1 for the remaining
    /// load, the current fraction for an equilibrium correction. `internal`: the internal
    /// force P_σ of the state's stresses if the caller has it.
    pub fn trial(&mut self, state: &State, target: f64, internal: Option<Vec<f64>>) -> Result<TrialIncrement> {
        let oob = self.out_of_balance(state, target, internal);
        if target == 1.0 && self.substep.is_none() && self.plastic_events_inside() {
            self.trial_base = Some(TrialBase::of(&oob, 1.0 - state.load_fraction));
        }
        let sys = self.contact_system(state, &oob.dshift);
        let sol = self.solve_small_system(state, &sys, &oob)?;
        Ok(self.increment(state, target, &sys, oob, &sol))
    }

    /// The stage's remaining load from the state to `target` (forces, prescribed displacement
    /// increments and obstacle motion), in residual form.
    pub fn out_of_balance(&mut self, state: &State, target: f64, internal: Option<Vec<f64>>) -> OutOfBalance {
        let dshift = self.shift_increment(state, target);
        if let Some(base) = &self.substep {
            return base.scaled(target - state.load_fraction, dshift); // a contact sub-step
        }
        if let Space::Reduced(r) = &self.space {
            // Elastic and in equilibrium: the out-of-balance force is (target − s)(ΔP − K_fp Δū) exactly.
            let c = target - state.load_fraction;
            let mode_rhs = self.mode_force.iter().map(|v| -c * v[1]).collect();
            return OutOfBalance { z0: r.u_load_reduced.iter().map(|v| c * v).collect(), mode_rhs, forward_sweep: vec![], prescribed: vec![], dshift, low_rank_coefficients: vec![] };
        }
        let internal = internal.unwrap_or_else(|| self.internal_force(&state.stress));
        let mut r = self.residual_from(&internal, state, target);
        let prescribed = self.prescribed_increment(state, target);
        if let Some(f) = self.prescribed_force(&prescribed) {
            r.iter_mut().zip(&f).for_each(|(a, b)| *a += b);
        }
        let r_eq = self.map.to_equations(&r);
        let w = self.forward_sweep(&r_eq, target - state.load_fraction, state.stage);
        let mut z0 = self.solver.trailing_solution(&w);
        let mut low_rank_coefficients = vec![];
        if !self.low_rank.is_empty() {
            // K⁻¹ r = K_f⁻¹ r − Z C⁻¹ Zᵀ r (`low_rank`), at the contact slots here.
            low_rank_coefficients = self.low_rank.coefficients(&r_eq);
            self.low_rank.subtract_trailing(&mut z0, &low_rank_coefficients);
        }
        let mode_rhs = self.mode_vectors.iter().map(|m| -m.iter().zip(&r).map(|(a, b)| a * b).sum::<f64>()).collect();
        OutOfBalance { z0, mode_rhs, forward_sweep: w, prescribed, dshift, low_rank_coefficients }
    }

    /// The forward sweep L⁻¹ r of an out-of-balance force r over the equations. From a balanced
    /// state r is c ΔP (c the stage fraction left, ΔP the stage's load change) up to round-off:
    /// then it is c × the stage load's sweep, kept per factorization (low-rank terms leave L
    /// as it is), and the trial costs one backward sweep. A rest above `BALANCED` × c‖ΔP‖
    /// (an integrated increment not yet corrected, prescribed displacements) is swept whole.
    fn forward_sweep(&mut self, r_eq: &[f64], c: f64, stage: usize) -> Vec<f64> {
        if c > 0.0 {
            self.sweep_stage_load(stage);
            if let Space::Full(Full { load_sweep: Some(ls), .. }) = &self.space {
                let (mut rest, mut load) = (0.0, 0.0);
                for (r, p) in r_eq.iter().zip(&ls.load) {
                    rest += (r - c * p) * (r - c * p);
                    load += c * c * p * p;
                }
                if rest <= BALANCED * BALANCED * load {
                    return ls.sweep.iter().map(|w| c * w).collect();
                }
            }
        }
        self.solver.forward(r_eq)
    }

    /// The current stage load's forward sweep, unless the cache holds it for this factor.
    fn sweep_stage_load(&mut self, stage: usize) {
        let factorization = self.solver.n_factorizations;
        if let Space::Full(Full { load_sweep: Some(ls), .. }) = &self.space {
            if ls.stage == stage && ls.factorization == factorization {
                return;
            }
        }
        let change = self.stage.force_change();
        let load: Vec<f64> = self.map.dof_of_equation.iter().map(|&d| if self.fixed[d] { 0.0 } else { change[d] }).collect();
        let sweep = self.solver.forward(&load);
        if let Space::Full(full) = &mut self.space {
            full.load_sweep = Some(LoadSweep { stage, factorization, load, sweep });
        }
    }

    /// Rows of the closed pairs: normal (h = −gap − Δc_n) and, for frictional stick, tangential
    /// (h = RTD at sticking − RTD − Δc_t), with Δc the obstacle's motion over the trial.
    pub fn contact_system(&self, state: &State, dshift: &[[f64; 2]]) -> ContactSystem {
        let (mut rows, mut h) = (Vec::new(), Vec::new());
        for (p, st) in state.status.iter().enumerate() {
            if !st.is_closed() {
                continue;
            }
            rows.push(Row::Normal(p));
            h.push(-self.gap(state, p) - dshift[p][0]);
            if *st == Status::Stick && self.pairs[p].frictional() {
                rows.push(Row::Tangent(p));
                h.push(state.rtd_stick[p] - self.rtd(state, p) - dshift[p][1]);
            }
        }
        let columns: Vec<Vec<(usize, f64)>> = rows.iter().map(|row| self.force_direction(*row, &state.status)).collect();
        let flex_columns = columns.iter().map(|e| self.flexibility_times(e)).collect();
        ContactSystem { rows, h, columns, flex_columns }
    }

    /// Column e_j: w_n (+ τ w_t for a slipping pair, τ = −dμ, eq. 41) or w_t.
    fn force_direction(&self, row: Row, status: &[Status]) -> Vec<(usize, f64)> {
        match row {
            Row::Normal(p) => {
                let pair = &self.pairs[p];
                let tau = pair.slip_ratio(status[p]);
                let mut e = pair.w_n.entries.clone();
                if tau != 0.0 {
                    e.extend(pair.w_t.entries.iter().map(|&(d, v)| (d, tau * v)));
                }
                e
            }
            Row::Tangent(p) => self.pairs[p].w_t.entries.clone(),
        }
    }

    pub fn constraint(&self, row: Row) -> &SparseVec {
        match row {
            Row::Normal(p) => &self.pairs[p].w_n,
            Row::Tangent(p) => &self.pairs[p].w_t,
        }
    }

    /// Assemble and solve the small system for (Δλ, α).
    fn solve_small_system(&mut self, state: &State, sys: &ContactSystem, oob: &OutOfBalance) -> Result<DVector<f64>> {
        let (m, nm) = (sys.rows.len(), self.modes.len());
        let mut a = DMatrix::<f64>::zeros(m + nm, m + nm);
        let mut rhs = DVector::<f64>::zeros(m + nm);
        for j in 0..m {
            for i in 0..m {
                a[(i, j)] = self.dot_slots(self.constraint(sys.rows[i]), &sys.flex_columns[j]);
            }
            for (k, mode) in self.mode_vectors.iter().enumerate() {
                a[(m + k, j)] = sys.columns[j].iter().map(|&(d, v)| v * mode[d]).sum();
            }
        }
        for (k, mode) in self.mode_vectors.iter().enumerate() {
            for i in 0..m {
                a[(i, m + k)] = self.constraint(sys.rows[i]).dot(mode);
            }
            rhs[m + k] = oob.mode_rhs[k];
        }
        for i in 0..m {
            rhs[i] = sys.h[i] - self.dot_slots(self.constraint(sys.rows[i]), &oob.z0);
        }
        self.check_restrained(state, &a, &sys.rows, oob)?;
        let t = Instant::now();
        let s = unit_free(&mut a, &mut rhs, m);
        let sol = solve_dense(&a, &rhs);
        self.timings.dense += since(t);
        match sol {
            Some(mut x) => {
                x.rows_mut(m, nm).iter_mut().for_each(|v| *v *= s);
                Ok(x)
            }
            None => {
                let closed: Vec<String> = sys.rows.iter().filter_map(|r| if let Row::Normal(p) = r { Some(p.to_string()) } else { None }).collect();
                bail!(Singular, "the contact system is singular at load fraction {:.6}: the closed pairs [{}] are redundant (two pairs on one node along the same direction?) — remove duplicate pairs", state.load_fraction, closed.join(", "))
            }
        }
    }

    /// Δλ, Δu = K#(r + E Δλ) + N α, and the element stress increments.
    fn increment(&mut self, state: &State, target: f64, sys: &ContactSystem, mut oob: OutOfBalance, sol: &DVector<f64>) -> TrialIncrement {
        let (m, n_pairs) = (sys.rows.len(), self.pairs.len());
        let (mut dlambda_n, mut dlambda_t) = (vec![0.0; n_pairs], vec![0.0; n_pairs]);
        for j in 0..m {
            match sys.rows[j] {
                Row::Normal(p) => {
                    dlambda_n[p] = sol[j];
                    dlambda_t[p] = self.pairs[p].slip_ratio(state.status[p]) * sol[j];
                }
                Row::Tangent(p) => dlambda_t[p] = sol[j],
            }
        }
        let dshift = std::mem::take(&mut oob.dshift);
        let prescribed = std::mem::take(&mut oob.prescribed);
        let mut du = self.displacement(sys, oob, sol);
        prescribed.iter().for_each(|&(d, v)| du[d] = v);
        let dalpha: Vec<f64> = (0..self.modes.len()).map(|k| sol[m + k]).collect();
        for (mode, s) in self.mode_vectors.iter().zip(&dalpha) {
            du.iter_mut().zip(mode).for_each(|(d, v)| *d += s * v);
        }
        if self.is_reduced() || self.substep.is_some() {
            if self.substep.is_none() {
                self.noise.displacement = DISPLACEMENT_NOISE * self.largest_increment(&du, target - state.load_fraction);
            }
            return TrialIncrement { du, dstress: vec![], dplastic: vec![], dstrain: vec![], dlambda_n, dlambda_t, dalpha, dshift };
        }
        let (dstress, dplastic, dstrain) = self.stress_increment(&du);
        let umax = self.largest_increment(&du, target - state.load_fraction);
        self.noise.displacement = DISPLACEMENT_NOISE * umax;
        TrialIncrement { du, dstress, dplastic, dstrain, dlambda_n, dlambda_t, dalpha, dshift }
    }

    /// K#(r + E Δλ): in the reduced space only at the contact DOFs, Σ_j Δλ_j K# e_j (reduced
    /// index = slot); in the full space the forces E Δλ on contact DOFs touch only the
    /// trailing rows of the forward sweep, then one backward sweep.
    fn displacement(&mut self, sys: &ContactSystem, oob: OutOfBalance, sol: &DVector<f64>) -> Vec<f64> {
        let m = sys.rows.len();
        if self.is_reduced() || self.substep.is_some() {
            let mut du = oob.z0;
            for j in 0..m {
                du.iter_mut().zip(&sys.flex_columns[j]).for_each(|(x, g)| *x += sol[j] * g);
            }
            return if self.is_reduced() { du } else { self.slots_to_dofs(&du) };
        }
        let mut w = oob.forward_sweep;
        let mut force_slots = vec![0.0; self.flexibility.nrows()];
        for j in 0..m {
            for &(d, v) in &sys.columns[j] {
                if self.contact_slot[d] != usize::MAX {
                    force_slots[self.contact_slot[d]] += sol[j] * v;
                }
            }
        }
        if m > 0 {
            self.solver.add_trailing_force(&mut w, &force_slots);
        }
        let mut x = self.solver.backward(w);
        if !self.low_rank.is_empty() {
            // K⁻¹(r + EΔλ) = K_f⁻¹(r + EΔλ) − Z C⁻¹ Zᵀ (r + EΔλ)
            let mut c = oob.low_rank_coefficients;
            let from_forces = self.low_rank.trailing_coefficients(&force_slots);
            c.iter_mut().zip(&from_forces).for_each(|(a, b)| *a += b);
            self.low_rank.subtract(&mut x, &c);
            self.count_low_rank_solve();
        }
        self.map.from_equations(&x)
    }

    /// A vector over all DOFs from its values at the contact slots (0 elsewhere).
    fn slots_to_dofs(&self, at_slots: &[f64]) -> Vec<f64> {
        let mut v = vec![0.0; self.map.role.len()];
        for (d, &slot) in self.contact_slot.iter().enumerate() {
            if slot != usize::MAX {
                v[d] = at_slots[slot];
            }
        }
        v
    }

    /// Δu = K⁻¹(f r + E Δλ) over all DOFs, from a trial's kept out-of-balance force r (its
    /// forward sweep) and the forces `force_slots` at the contact slots: one backward sweep.
    pub fn displacement_from(&mut self, base: &TrialBase, f: f64, force_slots: &[f64]) -> Vec<f64> {
        let mut w: Vec<f64> = base.forward_sweep.iter().map(|v| f * v).collect();
        self.solver.add_trailing_force(&mut w, force_slots);
        let mut x = self.solver.backward(w);
        if !self.low_rank.is_empty() {
            let mut c: Vec<f64> = base.low_rank_coefficients.iter().map(|v| f * v).collect();
            let from_forces = self.low_rank.trailing_coefficients(force_slots);
            c.iter_mut().zip(&from_forces).for_each(|(a, b)| *a += b);
            self.low_rank.subtract(&mut x, &c);
            self.count_low_rank_solve();
        }
        self.map.from_equations(&x)
    }

    /// max |u| of a state at stage fraction s (for round-off tolerances). The reduced space
    /// carries u at the contact DOFs only: the loads' share elsewhere is bounded by
    /// max |Σ u_stage of completed stages| + s × max |u_stage|.
    pub fn largest_displacement(&self, u: &[f64], s: f64) -> f64 {
        let carried = u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        match &self.space {
            Space::Reduced(r) => carried.max(r.u_done_max + s.abs() * r.u_load_max),
            Space::Full(_) => carried,
        }
    }

    /// max |Δu| of an increment over a stage fraction c (as `largest_displacement`).
    fn largest_increment(&self, du: &[f64], c: f64) -> f64 {
        let carried = du.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        match &self.space {
            Space::Reduced(r) => carried.max(c.abs() * r.u_load_max),
            Space::Full(_) => carried,
        }
    }

    /// Δσ, Δεp and Δε of every element for a displacement increment (eqs. 10, 11, 18), with
    /// the tangents K holds.
    pub fn stress_increment(&self, du: &[f64]) -> (Vec<Vector4<f64>>, Vec<f64>, Vec<Vector4<f64>>) {
        let per_element: Vec<(Vector4<f64>, f64, Vector4<f64>)> = self.elements.par_iter().with_min_len(PARALLEL_CHUNK).zip(&self.tangents).zip(&self.sections).map(|((el, t), section)| {
            let e = el.strain(du);
            (section.stress_increment(t, &e), section.plastic_multiplier(t, &e), e)
        }).collect();
        let n = per_element.len();
        let (mut dstress, mut dplastic, mut dstrain) = (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        for (s, p, e) in per_element {
            dstress.push(s);
            dplastic.push(p);
            dstrain.push(e);
        }
        (dstress, dplastic, dstrain)
    }

    /// Internal nodal forces P_σ = Σ w Bᵀ σ (eq. 42; w = t A, or 2π r̄ A in axisymmetry).
    pub fn internal_force(&self, stress: &[Vector4<f64>]) -> Vec<f64> {
        let mut f = vec![0.0; self.map.role.len()];
        for (el, s) in self.elements.iter().zip(stress) {
            let fe = el.internal_force(s);
            for (k, d) in el.dofs().iter().enumerate() {
                f[*d] += fe[k];
            }
        }
        f
    }

    /// Out-of-balance force at stage fraction `phi`: P(φ) − P_σ + contact forces over the free
    /// DOFs (the right-hand side of eq. 43), from the internal force P_σ of the stresses.
    pub fn residual_from(&self, internal: &[f64], state: &State, phi: f64) -> Vec<f64> {
        let mut r = internal.to_vec();
        for (d, v) in r.iter_mut().enumerate() {
            *v = if self.fixed[d] { 0.0 } else { self.stage.force(d, phi) - *v };
        }
        for (p, pair) in self.global_pairs().iter().enumerate() {
            pair.w_n.add_to(state.lambda_n[p], &mut r);
            pair.w_t.add_to(state.lambda_t[p], &mut r);
        }
        r
    }
}

/// Give the rigid-body columns and rows of the small system (the last ones, after the `m`
/// contact rows) the units of its flexibility block: Cᵀ N and Nᵀ E are ratios and −Nᵀ r a
/// force, where Cᵀ K# E is a compliance, so × the flexibility's size s (its largest diagonal
/// entry, rounded to a power of two: the scaling is exact) they are compliances and lengths
/// like the rest, and the pivot test of `solve_dense` is the same in any unit system
/// (unscaled, stresses in units 1e9 times smaller made the Hertz cylinder's system "singular").
/// Returns s: the rigid amplitudes solved are α / s.
fn unit_free(a: &mut DMatrix<f64>, rhs: &mut DVector<f64>, m: usize) -> f64 {
    let n = rhs.len();
    let s = (0..m).fold(0.0f64, |x, i| x.max(a[(i, i)].abs())).log2().round().exp2();
    if m == n || !(s > 0.0 && s.is_finite()) {
        return 1.0;
    }
    for k in m..n {
        a.column_mut(k).scale_mut(s);
        a.row_mut(k).scale_mut(s);
        rhs[k] *= s;
    }
    s
}

/// Solve the small dense system by LU with partial pivoting (faer's blocked kernel); None when
/// it is singular to working precision.
pub(super) fn solve_dense(a: &DMatrix<f64>, rhs: &DVector<f64>) -> Option<DVector<f64>> {
    let n = rhs.len();
    if n == 0 {
        return Some(DVector::zeros(0));
    }
    let mat = faer::MatRef::from_column_major_slice(a.as_slice(), n, n);
    let lu = faer::linalg::solvers::PartialPivLu::new(mat);
    let u = lu.U();
    let pivots: Vec<f64> = (0..n).map(|i| u[(i, i)].abs()).collect();
    let largest = pivots.iter().fold(0.0f64, |m, v| m.max(*v));
    if !(largest > 0.0) || pivots.iter().any(|&p| p <= SINGULAR_PIVOT * largest) {
        return None;
    }
    let mut x = faer::Mat::<f64>::from_fn(n, 1, |i, _| rhs[i]);
    use faer::linalg::solvers::SolveCore;
    lu.solve_in_place_with_conj(faer::Conj::No, x.as_mut());
    let x = DVector::from_fn(n, |i, _| x[(i, 0)]);
    x.iter().all(|v| v.is_finite()).then_some(x)
}
