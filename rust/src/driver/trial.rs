//! The trial increment (eqs. 43–44 in residual form).
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
//!
//! What a trial solves for is a value (`Solve`): the stage's remaining load, equilibrium at the
//! current load (a correction), or a contact sub-step's remaining load, which is the base
//! trial's scaled (`TrialBase`, `substeps`).

use super::clock::Phase;
use super::engine::Engine;
use super::problem::Problem;
use super::restraint;
use super::state::{State, TrialIncrement};
use super::stepping::Stepping;
use crate::bail;
use crate::contact::{Shift, SparseVec, Status};
use crate::dim::Dim;
use crate::error::{ErrorKind, Result};
use crate::events::Noise;
use nalgebra::{DMatrix, DVector};
use std::borrow::Cow;

/// A pivot of the small system's LU below this × the largest one means "singular".
const SINGULAR_PIVOT: f64 = 1e-13;
/// Displacement noise floor: × max |Δu| of the trial.
const DISPLACEMENT_NOISE: f64 = 1e-11;

/// What a trial solves for.
#[derive(Clone, Copy)]
pub(super) enum Solve<'b> {
    /// The stage's remaining load: from the state to s = 1 (eq. 44).
    RemainingLoad,
    /// Equilibrium at stage fraction φ, the state's own (an equilibrium correction).
    Balance(f64),
    /// The remaining load from a state a grouped increment reached linearly: the base trial's,
    /// scaled (a contact sub-step; contact DOFs only).
    SubStep(&'b TrialBase),
}

impl Solve<'_> {
    /// The stage fraction the trial goes to.
    fn target(self) -> f64 {
        match self {
            Solve::RemainingLoad | Solve::SubStep(_) => 1.0,
            Solve::Balance(phi) => phi,
        }
    }
}

/// A row of the small system: pair p's normal or tangential constraint (3D: along t1, t2),
/// or (3D) a slipping pair's cross row along e⊥ = the direction given (`contact`).
#[derive(Clone, Copy)]
pub(super) enum Row {
    Normal(usize),
    Tangent(usize),
    Tangent2(usize),
    Cross(usize, [f64; 2]),
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
    pub dshift: Vec<Shift>,
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
    /// The trial's noise floors (a sub-step's are its base's).
    pub noise: Noise,
}

impl TrialBase {
    fn of(oob: &OutOfBalance, c: f64) -> Self {
        let noise = Noise { displacement: 0.0, force: 0.0 };
        TrialBase {
            c,
            z0: oob.z0.clone(),
            mode_rhs: oob.mode_rhs.clone(),
            forward_sweep: oob.forward_sweep.clone(),
            low_rank_coefficients: oob.low_rank_coefficients.clone(),
            noise,
        }
    }

    /// The out-of-balance force of the remaining fraction c' (contact slots only).
    fn scaled(&self, c: f64, dshift: Vec<Shift>) -> OutOfBalance {
        let k = if self.c > 0.0 { c / self.c } else { 0.0 };
        let times = |v: &[f64]| v.iter().map(|x| k * x).collect();
        OutOfBalance {
            z0: times(&self.z0),
            mode_rhs: times(&self.mode_rhs),
            forward_sweep: vec![],
            prescribed: vec![],
            dshift,
            low_rank_coefficients: vec![],
        }
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

/// The trial increment for `what`. `internal`: the internal force P_σ of the state's stresses
/// if the caller has it.
pub(super) fn solve<D: Dim>(
    eng: &mut Engine<D>,
    state: &State<D>,
    what: Solve,
    internal: Option<Vec<f64>>,
) -> Result<TrialIncrement> {
    Ok(solve_keeping(eng, state, what, internal, false)?.0)
}

/// The trial for the stage's remaining load (eq. 44), and in a plastic window (`stepping`) what
/// its contact sub-steps reuse (`TrialBase`).
pub(super) fn remaining_load<D: Dim>(
    eng: &mut Engine<D>,
    state: &State<D>,
    internal: Option<Vec<f64>>,
    stepping: Stepping,
) -> Result<(TrialIncrement, Option<TrialBase>)> {
    solve_keeping(eng, state, Solve::RemainingLoad, internal, stepping.window().is_some())
}

fn solve_keeping<D: Dim>(
    eng: &mut Engine<D>,
    state: &State<D>,
    what: Solve,
    internal: Option<Vec<f64>>,
    keep_base: bool,
) -> Result<(TrialIncrement, Option<TrialBase>)> {
    let oob = out_of_balance(eng, state, what, internal);
    let mut base = keep_base.then(|| TrialBase::of(&oob, 1.0 - state.load_fraction));
    let mut sys = contact_system(eng, state, &oob.dshift, false);
    let sol = match solve_small_system(eng, state, &sys, &oob) {
        Err(e)
            if matches!(e.kind, ErrorKind::FreeBody | ErrorKind::GrossSliding)
                && unloaded_facets(&eng.problem, state).next().is_some() =>
        {
            sys = contact_system(eng, state, &oob.dshift, true);
            solve_small_system(eng, state, &sys, &oob).map_err(|_| e)?
        }
        sol => sol?,
    };
    let inc = increment(eng, state, what, &sys, oob, &sol);
    if let Some(b) = &mut base {
        b.noise = inc.noise;
    }
    Ok((inc, base))
}

/// The stage's remaining load from the state to `what`'s target (forces, prescribed
/// displacement increments and obstacle motion), in residual form.
pub(super) fn out_of_balance<D: Dim>(
    eng: &mut Engine<D>,
    state: &State<D>,
    what: Solve,
    internal: Option<Vec<f64>>,
) -> OutOfBalance {
    let target = what.target();
    let Engine { problem, stiffness, loads, .. } = eng;
    let dshift = loads.shift_increment(state, target);
    if let Solve::SubStep(base) = what {
        return base.scaled(target - state.load_fraction, dshift);
    }
    if problem.is_reduced() {
        // Elastic and in equilibrium: the out-of-balance force is (target − s)(ΔP − K_fp Δū)
        // exactly, and the force jumps not yet rebalanced (3D: `State::jumps`) add W Δλ.
        let c = target - state.load_fraction;
        let mut z0: Vec<f64> = loads.reduced.u_load_reduced.iter().map(|v| c * v).collect();
        let jumps = jump_force(problem, state);
        if !jumps.is_empty() {
            let dz = stiffness.flexibility_times(&problem.dofs.contact_slot, &jumps);
            z0.iter_mut().zip(&dz).for_each(|(z, d)| *z += d); // reduced index = slot
        }
        let mode_rhs = (0..loads.mode_force.len())
            .map(|k| {
                -c * loads.mode_force[k][1]
                    - jumps.iter().map(|&(d, v)| v * problem.bodies.mode_vectors[k][d]).sum::<f64>()
            })
            .collect();
        return OutOfBalance {
            z0,
            mode_rhs,
            forward_sweep: vec![],
            prescribed: vec![],
            dshift,
            low_rank_coefficients: vec![],
        };
    }
    let internal = internal.unwrap_or_else(|| problem.internal_force(&state.stress));
    let mut r = loads.residual_from(problem, &internal, state, target);
    let prescribed = loads.prescribed_increment(problem, state, target);
    if let Some(f) = problem.prescribed_force(&stiffness.tangents.held, &prescribed) {
        r.iter_mut().zip(&f).for_each(|(a, b)| *a += b);
    }
    let r_eq = problem.dofs.map.to_equations(&r);
    let w = stiffness.forward_sweep(&r_eq, target - state.load_fraction, state.stage, || {
        loads.change_on_equations(problem)
    });
    let mut z0 = stiffness.solver.trailing_solution(&w);
    let mut low_rank_coefficients = vec![];
    if !stiffness.low_rank.is_empty() {
        // K⁻¹ r = K_f⁻¹ r − Z C⁻¹ Zᵀ r (`low_rank`), at the contact slots here.
        low_rank_coefficients = stiffness.low_rank.coefficients(&r_eq);
        stiffness.low_rank.subtract_trailing(&mut z0, &low_rank_coefficients);
    }
    let mode_rhs = problem
        .bodies
        .mode_vectors
        .iter()
        .map(|m| -m.iter().zip(&r).map(|(a, b)| a * b).sum::<f64>())
        .collect();
    OutOfBalance { z0, mode_rhs, forward_sweep: w, prescribed, dshift, low_rank_coefficients }
}

/// W Δλ of the state's unbalanced force jumps (`State::jumps`), as (DOF, force) entries.
fn jump_force<D: Dim>(problem: &Problem<D>, state: &State<D>) -> Vec<(usize, f64)> {
    let mut force = vec![];
    let jumps = state.space().map_or(&[][..], |s| &s.jumps);
    for (pair, jump) in problem.pairs.iter().zip(jumps).filter(|(_, j)| **j != [0.0; 3]) {
        for (w, v) in pair.columns().zip(jump) {
            force.extend(w.entries.iter().map(|&(d, c)| (d, v * c)));
        }
    }
    force
}

/// 3D: the slipping pairs at zero normal force that hold a direction e but no facet yet
/// (`Problem::cross_direction`), with their cross directions e⊥.
fn unloaded_facets<'a, D: Dim>(
    problem: &'a Problem<D>,
    state: &'a State<D>,
) -> impl Iterator<Item = (usize, [f64; 2])> + 'a {
    let unloaded = move |p: usize| (0.0..=problem.scales.force_noise).contains(&state.lambda_n[p]);
    (0..problem.pairs.len())
        .filter(move |&p| unloaded(p))
        .filter_map(move |p| problem.facet_cross(state, p).map(|cross| (p, cross)))
}

/// Rows of the closed pairs: normal (h = −gap − Δc_n); for frictional stick, tangential
/// (h = RTD at sticking − RTD − Δc_t); for a 3D pair slipping on a facet, the cross row (no
/// slip across its held direction: h = −e⊥·Δc_t), with Δc the obstacle's motion over the trial.
/// `unloaded`: also for the pairs slipping at zero force with a direction (`unloaded_facets`),
/// where without them a body is free or seems to slide as a whole (pressed, its pairs all
/// slipping from the first instant, a turn about the normal unresisted:
/// their normal forces grow with the trial; the advance bounds the cross forces they take,
/// `advance::project_onto_cone`, and the jump is rebalanced).
fn contact_system<D: Dim>(
    eng: &Engine<D>,
    state: &State<D>,
    dshift: &[Shift],
    unloaded: bool,
) -> ContactSystem {
    let problem = &eng.problem;
    let (mut rows, mut h) = (Vec::new(), Vec::new());
    let mut extra_cross = vec![None; problem.pairs.len()];
    if unloaded {
        unloaded_facets(problem, state).for_each(|(p, cross)| extra_cross[p] = Some(cross));
    }
    for (p, st) in state.status.iter().enumerate() {
        if !st.is_closed() {
            continue;
        }
        rows.push(Row::Normal(p));
        h.push(-problem.gap(state, p) - dshift[p][0]);
        let pair = &problem.pairs[p];
        if *st == Status::Stick && pair.frictional() {
            // (a frictional pair has a free tangent: in 2D its one, whose row it always has)
            if !pair.held(0) {
                rows.push(Row::Tangent(p));
                h.push(state.rtd_stick[p] - problem.rtd(state, p) - dshift[p][1]);
            }
            if !pair.held(1) {
                rows.push(Row::Tangent2(p));
                h.push(state.rtd_stick_of(p)[1] - problem.rtd2(state, p) - dshift[p][2]);
            }
        }
        if let Some(cross) = problem.cross_direction(state, p).or(extra_cross[p]) {
            rows.push(Row::Cross(p, cross));
            h.push(-(cross[0] * dshift[p][1] + cross[1] * dshift[p][2]));
        }
    }
    let columns: Vec<Vec<(usize, f64)>> =
        rows.iter().map(|row| force_direction(problem, state, *row)).collect();
    let flex_columns = columns
        .iter()
        .map(|e| eng.stiffness.flexibility_times(&problem.dofs.contact_slot, e))
        .collect();
    ContactSystem { rows, h, columns, flex_columns }
}

/// Column e_j: w_n (+ τ w_t for a slipping pair, τ = −dμ, eq. 41; in 3D + τ1 w_t + τ2 w_t2,
/// τ = μ e), or w_t (w_t2, the cross direction's e⊥₁ w_t + e⊥₂ w_t2).
fn force_direction<D: Dim>(problem: &Problem<D>, state: &State<D>, row: Row) -> Vec<(usize, f64)> {
    match row {
        Row::Normal(p) => {
            let pair = &problem.pairs[p];
            let [tau, tau2] = problem.slip_ratios(state, p);
            let mut e = pair.w_n.entries.clone();
            for (t, tau) in pair.tangents.iter().zip([tau, tau2]).filter(|(_, tau)| *tau != 0.0) {
                e.extend(t.w.entries.iter().map(|&(d, v)| (d, tau * v)));
            }
            e
        }
        Row::Tangent(p) => problem.pairs[p].tangents[0].w.entries.clone(),
        Row::Tangent2(p) => problem.pairs[p].tangents[1].w.entries.clone(),
        Row::Cross(p, cross) => problem.pairs[p].along_tangent(cross).entries,
    }
}

fn constraint<'a, D: Dim>(problem: &'a Problem<D>, row: Row) -> Cow<'a, SparseVec> {
    match row {
        Row::Normal(p) => Cow::Borrowed(&problem.pairs[p].w_n),
        Row::Tangent(p) => Cow::Borrowed(&problem.pairs[p].tangents[0].w),
        Row::Tangent2(p) => Cow::Borrowed(&problem.pairs[p].tangents[1].w),
        Row::Cross(p, cross) => Cow::Owned(problem.pairs[p].along_tangent(cross)),
    }
}

/// Assemble and solve the small system for (Δλ, α).
fn solve_small_system<D: Dim>(
    eng: &Engine<D>,
    state: &State<D>,
    sys: &ContactSystem,
    oob: &OutOfBalance,
) -> Result<DVector<f64>> {
    let problem = &eng.problem;
    let modes = &problem.bodies.mode_vectors;
    let (m, nm) = (sys.rows.len(), problem.bodies.modes.len());
    let mut a = DMatrix::<f64>::zeros(m + nm, m + nm);
    let mut rhs = DVector::<f64>::zeros(m + nm);
    let constraints: Vec<Cow<SparseVec>> =
        sys.rows.iter().map(|&row| constraint(problem, row)).collect();
    for j in 0..m {
        for i in 0..m {
            a[(i, j)] = problem.dot_slots(&constraints[i], &sys.flex_columns[j]);
        }
        for (k, mode) in modes.iter().enumerate() {
            a[(m + k, j)] = sys.columns[j].iter().map(|&(d, v)| v * mode[d]).sum();
        }
    }
    for (k, mode) in modes.iter().enumerate() {
        for i in 0..m {
            a[(i, m + k)] = constraints[i].dot(mode);
        }
        rhs[m + k] = oob.mode_rhs[k];
    }
    for i in 0..m {
        rhs[i] = sys.h[i] - problem.dot_slots(&constraints[i], &oob.z0);
    }
    let closed_normals = || {
        sys.rows
            .iter()
            .filter_map(|r| if let Row::Normal(p) = r { Some(*p) } else { None })
            .collect::<Vec<usize>>()
    };
    let idle = restraint::check_restrained(
        problem,
        &eng.loads,
        state,
        &a,
        m,
        &oob.mode_rhs,
        closed_normals,
    )?;
    let (s, sol) = {
        let _t = eng.clock.time(Phase::Dense);
        let s = unit_free(&mut a, &mut rhs, m);
        for v in &idle {
            // held still: + s v vᵀ on the rigid block (zero there; s: its units after
            // `unit_free`), whose row along v then reads v·α = 0
            for (k, vk) in v.iter().enumerate() {
                for (l, vl) in v.iter().enumerate() {
                    a[(m + k, m + l)] += s * vk * vl;
                }
            }
        }
        (s, solve_dense(&a, &rhs))
    };
    match sol {
        Some(mut x) => {
            x.rows_mut(m, nm).iter_mut().for_each(|v| *v *= s);
            Ok(x)
        }
        None => {
            let closed: Vec<String> = closed_normals().iter().map(|p| p.to_string()).collect();
            bail!(Singular, "the contact system is singular at load fraction {:.6}: the closed pairs [{}] are redundant (two pairs on one node along the same direction?) — remove duplicate pairs", state.load_fraction, closed.join(", "))
        }
    }
}

/// Δλ, Δu = K#(r + E Δλ) + N α, and the element stress increments (not for a sub-step, nor in
/// the reduced space).
fn increment<D: Dim>(
    eng: &mut Engine<D>,
    state: &State<D>,
    what: Solve,
    sys: &ContactSystem,
    mut oob: OutOfBalance,
    sol: &DVector<f64>,
) -> TrialIncrement {
    let problem = &eng.problem;
    let (m, n_pairs) = (sys.rows.len(), problem.pairs.len());
    let (mut dlambda_n, mut dlambda_t) = (vec![0.0; n_pairs], vec![0.0; n_pairs]);
    let mut dlambda_t2 = vec![0.0; if state.space().is_some() { n_pairs } else { 0 }];
    for j in 0..m {
        match sys.rows[j] {
            Row::Normal(p) => {
                dlambda_n[p] = sol[j];
                let [tau, tau2] = problem.slip_ratios(state, p);
                dlambda_t[p] = tau * sol[j];
                if let Some(d) = dlambda_t2.get_mut(p) {
                    *d = tau2 * sol[j];
                }
            }
            Row::Tangent(p) => dlambda_t[p] = sol[j],
            Row::Tangent2(p) => dlambda_t2[p] = sol[j],
            Row::Cross(p, cross) => {
                dlambda_t[p] += cross[0] * sol[j]; // after its normal row's μ e Δλ_n
                dlambda_t2[p] += cross[1] * sol[j];
            }
        }
    }
    let dshift = std::mem::take(&mut oob.dshift);
    let prescribed = std::mem::take(&mut oob.prescribed);
    let sub_step = matches!(what, Solve::SubStep(_));
    let mut du = displacement(eng, sys, oob, sol, sub_step);
    let problem = &eng.problem;
    prescribed.iter().for_each(|&(d, v)| du[d] = v);
    let dalpha: Vec<f64> = (0..problem.bodies.modes.len()).map(|k| sol[m + k]).collect();
    for (mode, s) in problem.bodies.mode_vectors.iter().zip(&dalpha) {
        du.iter_mut().zip(mode).for_each(|(d, v)| *d += s * v);
    }
    let noise = match what {
        Solve::SubStep(base) => base.noise,
        Solve::RemainingLoad | Solve::Balance(_) => {
            let largest =
                eng.loads.largest_increment(problem, &du, what.target() - state.load_fraction);
            Noise { displacement: DISPLACEMENT_NOISE * largest, force: problem.scales.force_noise }
        }
    };
    if problem.is_reduced() || sub_step {
        return TrialIncrement {
            du,
            dstress: vec![],
            dplastic: vec![],
            dlambda_n,
            dlambda_t,
            dlambda_t2,
            dalpha,
            dshift,
            noise,
        };
    }
    let (dstress, dplastic) = eng.stiffness.tangents.stress_increment(problem, &du);
    TrialIncrement {
        du,
        dstress,
        dplastic,
        dlambda_n,
        dlambda_t,
        dlambda_t2,
        dalpha,
        dshift,
        noise,
    }
}

/// K#(r + E Δλ): in the reduced space and for a sub-step only at the contact DOFs,
/// Σ_j Δλ_j K# e_j (reduced index = slot); in the full space the forces E Δλ on contact DOFs
/// touch only the trailing rows of the forward sweep, then one backward sweep.
fn displacement<D: Dim>(
    eng: &mut Engine<D>,
    sys: &ContactSystem,
    oob: OutOfBalance,
    sol: &DVector<f64>,
    sub_step: bool,
) -> Vec<f64> {
    let m = sys.rows.len();
    let Engine { problem, stiffness, .. } = eng;
    if problem.is_reduced() || sub_step {
        let mut du = oob.z0;
        for j in 0..m {
            du.iter_mut().zip(&sys.flex_columns[j]).for_each(|(x, g)| *x += sol[j] * g);
        }
        return if problem.is_reduced() { du } else { problem.slots_to_dofs(&du) };
    }
    let contact_slot = &problem.dofs.contact_slot;
    let mut force_slots = vec![0.0; stiffness.flexibility.nrows()];
    for j in 0..m {
        for &(d, v) in &sys.columns[j] {
            if contact_slot[d] != usize::MAX {
                force_slots[contact_slot[d]] += sol[j] * v;
            }
        }
    }
    let x = stiffness
        .backward_with_forces(oob.forward_sweep, &force_slots, || oob.low_rank_coefficients);
    problem.dofs.map.from_equations(&x)
}

/// Δu = K⁻¹(f r + E Δλ) over all DOFs, from a trial's kept out-of-balance force r (its
/// forward sweep) and the forces `force_slots` at the contact slots: one backward sweep.
pub(super) fn displacement_from<D: Dim>(
    eng: &mut Engine<D>,
    base: &TrialBase,
    f: f64,
    force_slots: &[f64],
) -> Vec<f64> {
    let w: Vec<f64> = base.forward_sweep.iter().map(|v| f * v).collect();
    let x = eng.stiffness.backward_with_forces(w, force_slots, || {
        base.low_rank_coefficients.iter().map(|v| f * v).collect()
    });
    eng.problem.dofs.map.from_equations(&x)
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

/// Solve the small dense system by LU with partial pivoting; None when it is singular to
/// working precision (a pivot ≤ `SINGULAR_PIVOT` × the largest).
fn solve_dense(a: &DMatrix<f64>, rhs: &DVector<f64>) -> Option<DVector<f64>> {
    let x = lu_solve(a, DMatrix::from_column_slice(rhs.len(), 1, rhs.as_slice()), SINGULAR_PIVOT)?;
    Some(x.column(0).into_owned())
}

/// X = A⁻¹ B by LU with partial pivoting (faer's blocked kernel); None when a pivot of U is
/// ≤ `singular` × the largest (0: an exact zero) or X is not finite.
pub(super) fn lu_solve(a: &DMatrix<f64>, b: DMatrix<f64>, singular: f64) -> Option<DMatrix<f64>> {
    let (n, k) = b.shape();
    if n == 0 {
        return Some(b);
    }
    let lu = faer::linalg::solvers::PartialPivLu::new(faer::MatRef::from_column_major_slice(
        a.as_slice(),
        n,
        n,
    ));
    let pivots: Vec<f64> = (0..n).map(|i| lu.U()[(i, i)].abs()).collect();
    let largest = pivots.iter().fold(0.0f64, |m, v| m.max(*v));
    if !(largest > 0.0) || pivots.iter().any(|&p| p <= singular * largest) {
        return None;
    }
    let mut x = b;
    use faer::linalg::solvers::SolveCore;
    lu.solve_in_place_with_conj(
        faer::Conj::No,
        faer::MatMut::from_column_major_slice_mut(x.as_mut_slice(), n, k),
    );
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::super::clock::Clock;
    use super::super::scenes::*;
    use super::super::space::Space;
    use super::*;
    use crate::model::Model;

    /// Round-off of the solves on these scenes of four nodes: each result is a few dozen
    /// operations on O(1) numbers, ~1e-15 each; 1e-12 leaves room and catches any error in the
    /// algebra, which would be of order one.
    const ROUND_OFF: f64 = 1e-12;

    /// The entry of DOF `dof` of a vector over the DOFs the loop carries.
    fn at<D: Dim>(eng: &Engine<D>, v: &[f64], dof: usize) -> f64 {
        match &eng.problem.space {
            Space::Reduced(r) => v[r.dofs.iter().position(|&d| d == dof).expect("a contact DOF")],
            Space::Full => v[dof],
        }
    }

    /// The square on rollers pressed by q: uniform σy = −q, so its free corner (node 2) moves by
    /// (ν q/E, −q/E) (plane stress), in the reduced elastic space (contact DOFs only) as in the
    /// full one; the open pair carries nothing.
    #[test]
    fn the_remaining_load_moves_the_corner_by_the_closed_form() {
        let q = 2.0;
        for reduced in [true, false] {
            let mut m = poisson_wall(q, 1.0); // the wall far away: the pair stays open
            m.options.reduced_elastic = reduced;
            let clock = Clock::new();
            let (mut eng, state) = start(&m, &clock);
            assert_eq!(eng.problem.is_reduced(), reduced);
            let (trial, base) =
                remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
            assert!(base.is_none(), "no window, no base kept");
            let (ux, uy) = (at(&eng, &trial.du, 4), at(&eng, &trial.du, 5));
            assert!((ux - NU * q / E).abs() < ROUND_OFF * q / E, "u_x = {ux}");
            assert!((uy + q / E).abs() < ROUND_OFF * q / E, "u_y = {uy}");
            assert_eq!((trial.dlambda_n[0], trial.dlambda_t[0]), (0.0, 0.0));
        }
    }

    /// A stuck pair holds its node in place, so it carries the load on it by the node's
    /// equilibrium: stage 1 presses by N (Δλ_n = N), stage 2 adds the tangential T
    /// (Δλ_t = T, t = (−1, 0)); the node does not move.
    #[test]
    fn a_stuck_pair_carries_the_load_on_its_node() {
        let (n, t) = (3.0, 1.0);
        let m = pressed_then_sheared(n, t, 0.5);
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let press = solve(&mut eng, &state, Solve::RemainingLoad, None).unwrap();
        assert!(
            (press.dlambda_n[0] - n).abs() < ROUND_OFF * n
                && press.dlambda_t[0].abs() < ROUND_OFF * n
        );
        assert!(press.du.iter().all(|v| v.abs() < ROUND_OFF * n / E));
        state.advance(&press, 1.0);
        eng.begin_stage(1, &mut state);
        let shear = solve(&mut eng, &state, Solve::RemainingLoad, None).unwrap();
        assert!(
            shear.dlambda_n[0].abs() < ROUND_OFF * n
                && (shear.dlambda_t[0] - t).abs() < ROUND_OFF * t
        );
        assert!(shear.du.iter().all(|v| v.abs() < ROUND_OFF * n / E));
    }

    /// In a plastic window the trial keeps its base, and a contact sub-step from a state the
    /// increment reached linearly (at s) solves the remaining load (1 − s) of it: the corner's
    /// displacement is (1 − s) (ν q/E, −q/E), with no full-space solve.
    #[test]
    fn a_sub_step_solves_the_remaining_load_from_its_base() {
        let q = 2.0;
        let m = poisson_wall(q, 1.0);
        let mut m = Model { materials: vec![plastic(1e6, 0.0)], ..m }; // plastic: the full space, never yielding
        m.options.group_tol = 0.1;
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let (trial, base) =
            remaining_load(&mut eng, &state, None, Stepping::Grouped { delta: 0.1 }).unwrap();
        let base = base.expect("a window keeps its trial's base");
        let s = 0.3;
        state.u.iter_mut().zip(&trial.du).for_each(|(u, d)| *u += s * d);
        state.load_fraction = s;
        let solves = eng.stiffness.solver.n_solves;
        let sub = solve(&mut eng, &state, Solve::SubStep(&base), None).unwrap();
        assert_eq!(eng.stiffness.solver.n_solves, solves, "a sub-step solves in the contact space");
        assert!((sub.du[4] - (1.0 - s) * NU * q / E).abs() < ROUND_OFF * q / E);
        assert!((sub.du[5] + (1.0 - s) * q / E).abs() < ROUND_OFF * q / E);
    }
}
