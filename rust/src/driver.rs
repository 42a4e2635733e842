//! The adaptive incremental procedure (paper §4).
//!
//! From the current state, one *trial* increment is solved for the whole remaining load in
//! residual form (eq. 43/44: right-hand side = total load − internal force + current contact
//! forces, so any drift is corrected by the next trial). Each candidate event gets its scale
//! factor (eqs. 48–55, module `events`); the state advances by the smallest one (eqs. 57–62),
//! the statuses of the pairs whose events fall at that scale change together, and the loop
//! repeats until the whole load is applied (S = 1).
//!
//! Linear algebra. With K# a generalized inverse of the reduced stiffness (SPD Cholesky factor
//! of K with supports and one pinned DOF per free rigid-body mode removed, `linalg`) and N the
//! free rigid-body modes, the trial increment of eq. 44 is
//!   Δu = K#(r + E Δλ) + N α,
//! where the columns of E are the contact force directions of the closed pairs (w_n, w_t for
//! stick; w_n − dμ w_t for slip, eq. 41: this makes the small system nonsymmetric) and the
//! rows of C their constraints (w_n·Δu = −gap, w_t·Δu = 0 for stick). The multipliers and
//! rigid amplitudes solve the small dense system
//!   [Cᵀ K# E   Cᵀ N] [Δλ]   [h − Cᵀ K# r]
//!   [Nᵀ E       0  ] [α ] = [  −Nᵀ r    ]
//! whose second row is the equilibrium of each free body. The contact DOFs are last in the
//! factor, so every Cᵀ K# E entry is read from their flexibility (`SpdSolver`), and a trial is
//! one forward sweep of r, the small dense solve, and one backward sweep of r + E Δλ. An elastic
//! run factors K once and carries only contact DOFs between events (the reduced mode).
//!
//! Simultaneous events: those whose scales agree within `tie_tol` (relative) are applied in
//! one increment (symmetric meshes, flat punches). At zero scale only the most urgent class is
//! applied per increment (`zero_length_priority`).
//!
//! Event grouping, the speed–accuracy knob δ = `group_tol` (0, the paper's procedure, is the
//! default): the state advances to the first event, at load fraction φ_min, and the friction
//! and plasticity events predicted at φ ≤ φ_min (1 + δ) switch with it (`may_be_taken_early`).
//! The window is relative to the load, not to the scale S of the remaining load: late in a run
//! S_min (1 + δ) would be a vanishing window. δ bounds how early an event is taken; an element
//! that yields early flows from just inside its yield surface (the drift control returns it),
//! a pair that slips early keeps its tangential force until the load brings it to the cone.
//!
//! Plasticity. Each element carries its tangent D or D_ep (eq. 11) built from the stress at
//! the start of the increment; the trial gives every element's stress and plastic-strain
//! increments, from which the yield scale S_p (eqs. 12–16) and plastic unloading (at S = 0)
//! follow. Any change of tangent refactorizes K: the paper re-evaluates D_ep of *every* plastic
//! element at each increment, so K changes by a term of rank ~2 × (plastic elements), not one
//! (no Sherman–Morrison–Woodbury), and a numeric refactorization costs only 5–10 solve pairs
//! here (measured, 8.6k–250k DOFs): an iteration on a stale factor needs at least two per
//! trial and gains nothing. What is kept: the symbolic analysis, the elastic K (only plastic
//! elements are re-added) and one solve per trial. Drift control (default on) bounds the
//! increment of plastic elements, returns them to the yield surface after the increment, and
//! restores equilibrium at fixed load with one correction solve, so that every event is in
//! equilibrium to round-off; `drift_control = false` is the paper without either.
//!
//! Termination (anti-cycling rule). Positive-length increments advance the load; the loop
//! stops when the trial reaches S = 1 and is bounded by `Options::max_steps`. Zero-length
//! increments (stick→slip at S = 0, a pair that closes and reopens, ties) could cycle: within
//! one run of zero-length increments each pair may change status at most
//! `max_zero_length_switches` times; a pair that would switch once more is frozen in its status
//! (a `frozen` event names it) and ignored until the load advances. Every zero-length increment
//! switches or freezes at least one pair, so a zero-length run has at most (switches + 1) × pairs
//! increments and the procedure always terminates. A frozen pair that then violates a contact
//! condition is reported as an error naming it.

use crate::bail;
use crate::contact::{Pair, Status};
use crate::element::Cst;
use crate::error::Result;
use crate::events::{self, Candidate, Noise};
use crate::linalg::{DofMap, ElementScatter, SpdSolver, StiffnessPattern};
use crate::material::{von_mises, Material, Plane, Tangent};
use crate::model::*;
use crate::rigid_modes::{free_modes, RigidMode};
use nalgebra::{DMatrix, DVector, Vector3, Vector4};
use std::time::Instant;

/// Scale factors at or below this are zero-length increments.
const ZERO_SCALE: f64 = 1e-12;

/// Order in which simultaneous zero-length events are applied (lowest first, one class per
/// increment): releasing a violated constraint (stick→slip, separation) before closing a gap,
/// and both before re-imposing stick. A slip reversal seen in a trial where a stuck pair
/// already exceeds its cone is an artefact of that trial; applying all of them at once makes
/// pairs chatter slip→stick→slip at every event.
fn zero_length_priority(kind: EventKind) -> u8 {
    match kind {
        EventKind::StickToSlip | EventKind::Separate => 0,
        EventKind::Close | EventKind::Yield => 1,
        EventKind::SlipToStick | EventKind::Unload | EventKind::Frozen | EventKind::FrozenElement => 2,
    }
}

/// Event grouping (`Options::group_tol`) may take these early: they change no contact
/// force at the switch. A pair that slips early keeps its tangential force, a yield changes
/// the tangent only. Contact changes are taken exactly: separating early would drop a
/// compressive force, and a pair closed early would have to be held at its remaining gap (pulling
/// it onto the target is a tensile force), a standoff that stays: measured, it raised the Hertz
/// peak pressure by 16 % (24.5k DOFs) to 61 % (106k DOFs) at δ = 0.1, growing under refinement.
fn may_be_taken_early(kind: EventKind) -> bool {
    matches!(kind, EventKind::StickToSlip | EventKind::SlipToStick | EventKind::Yield | EventKind::Unload)
}

/// The evolving state: accumulated displacement, stresses and contact forces (eqs. 59–62).
#[derive(Clone)]
struct State {
    load_fraction: f64,
    u: Vec<f64>,
    /// σx, σy, σz, τxy per element.
    stress: Vec<Vector4<f64>>,
    plastic_strain: Vec<f64>,
    lambda_n: Vec<f64>,
    lambda_t: Vec<f64>,
    /// Rigid-body amplitudes (only tracked in the reduced elastic mode).
    alpha: Vec<f64>,
}

/// One trial increment for the remaining load.
struct TrialIncrement {
    du: Vec<f64>,
    dstress: Vec<Vector4<f64>>,
    /// Equivalent plastic strain increment (negative: the element would unload).
    dplastic: Vec<f64>,
    dlambda_n: Vec<f64>,
    dlambda_t: Vec<f64>,
    dalpha: Vec<f64>,
}

/// A row of the small system: pair `pair`'s normal or tangential constraint.
#[derive(Clone, Copy)]
enum Row {
    Normal(usize),
    Tangent(usize),
}

struct Engine<'m> {
    model: &'m Model,
    elements: Vec<Cst>,
    /// Material of every element.
    material: Vec<Material>,
    tangents: Vec<Tangent>,
    /// The tangents changed since the last factorization.
    tangents_changed: bool,
    /// The pairs as the event loop sees them: over the global DOFs, or in the reduced elastic
    /// mode over the reduced DOFs (see `reduced`).
    pairs: Vec<Pair>,
    /// The pairs over the global DOFs (full fields, snapshots).
    global_pairs: Vec<Pair>,
    modes: Vec<RigidMode>,
    /// The rigid modes over the DOFs the event loop carries (all, or the reduced ones).
    mode_vectors: Vec<Vec<f64>>,
    /// Nᵀ P per mode (the reduced mode's rigid-body rows, without a full vector per event).
    mode_load: Vec<f64>,
    map: DofMap,
    pattern: StiffnessPattern,
    /// Plastic runs: K with every element elastic (the first assembly) and where each element's
    /// entries sit in it; a refactorization re-adds t A Bᵀ (D_ep − D) B of the plastic elements
    /// only.
    elastic_values: Vec<f64>,
    scatter: Option<ElementScatter>,
    fixed: Vec<bool>,
    solver: SpdSolver,
    /// Flexibility of the contact DOFs: K# restricted to them (t × t over the contact DOFs that
    /// are equations, indexed by `contact_slot`), read from the trailing block of the factor
    /// (`SpdSolver::trailing_inverse`) after every factorization. Every Cᵀ K# E entry of the
    /// small system comes from it: no triangular solve per contact pair.
    flexibility: faer::Mat<f64>,
    /// Slot in `flexibility` of each DOF of the loop's DOF space (usize::MAX: not a contact
    /// DOF, or fixed/pinned, where K# is zero). In the reduced mode slot = reduced index.
    contact_slot: Vec<usize>,
    /// Reduced elastic mode: no plastic material, so the state is fully described by the load
    /// fraction, the multipliers and the rigid amplitudes, u = φ K#P + K#(W λ) + N α, and an
    /// event needs only contact-DOF values: no triangular solve per event, one per requested
    /// snapshot. The loop then carries u only at the *reduced DOFs*: the contact DOFs that are
    /// equations (index = flexibility slot), then the pinned ones; no element arrays. An event
    /// costs O(contact DOFs²), independent of the mesh size.
    reduced: bool,
    max_snapshot_residual: f64,
    /// K#P (full load), for the reduced mode, over all DOFs and over the reduced DOFs.
    u_load: Vec<f64>,
    u_load_reduced: Vec<f64>,
    /// max |K#P|, for round-off tolerances (reduced mode).
    u_load_max: f64,
    /// Global DOF of each reduced DOF (reduced mode only).
    reduced_dofs: Vec<usize>,
    load_norm: f64,
    /// Σ|load|: the scale of forces, for tolerances.
    force_scale: f64,
    noise: Noise,
    length_scale: f64,
    timings: Timings,
}

pub fn run(model: &Model, mut progress: impl FnMut(Progress) -> bool) -> Result<RunResult> {
    let t_start = Instant::now();
    let mut eng = Engine::new(model)?;
    eng.timings.assembly = t_start.elapsed().as_secs_f64();
    eng.factor()?;
    let opts = &model.options;

    let n_pairs = eng.pairs.len();
    // The reduced elastic mode carries no element arrays between events.
    let n_el = if eng.reduced { 0 } else { eng.elements.len() };
    let mut state = State {
        load_fraction: 0.0,
        u: vec![0.0; eng.loop_dofs()],
        stress: vec![Vector4::zeros(); n_el],
        plastic_strain: vec![0.0; n_el],
        lambda_n: vec![0.0; n_pairs],
        lambda_t: vec![0.0; n_pairs],
        alpha: vec![0.0; eng.modes.len()],
    };
    // Initially closed pairs (zero gap: receding/conforming contact) start in stick (paper §4).
    let gap_tol = 1e-12 * eng.length_scale;
    let mut status: Vec<Status> = eng
        .pairs
        .iter()
        .map(|p| if p.gap0 <= gap_tol { p.closed_status() } else { Status::Open })
        .collect();
    let mut plastic = vec![false; n_el];
    let mut rtd_stick = vec![0.0; n_pairs];
    let mut closure_fraction: Vec<f64> =
        status.iter().map(|s| if s.is_closed() { 0.0 } else { f64::NAN }).collect();
    let mut predicted_closure = vec![f64::INFINITY; n_pairs];
    // Anti-cycling bookkeeping, pairs then elements (see the module documentation).
    let n_entities = n_pairs + n_el;
    let mut zero_switches = vec![0usize; n_entities];
    let mut frozen = vec![false; n_entities];
    let mut switch_count = vec![0usize; n_entities];

    let mut events_out: Vec<EventRecord> = Vec::new();
    let mut steps: Vec<StepRecord> = Vec::new();
    let mut snapshots: Vec<Snapshot> = Vec::new();
    let mut pending_fractions: Vec<f64> = match &opts.snapshots {
        SnapshotRequest::EveryEvent => {
            snapshots.push(eng.snapshot(&state, &status, &plastic)?);
            vec![]
        }
        SnapshotRequest::Fractions(f) => {
            let mut f = f.clone();
            f.sort_by(|a, b| a.total_cmp(b));
            f
        }
    };
    let n_plastic_capable = eng.material.iter().filter(|m| m.is_plastic()).count();
    let max_steps = if opts.max_steps > 0 { opts.max_steps } else { 50 * (n_pairs + n_plastic_capable + 1) + 1000 };
    let mut max_residual: f64 = 0.0;
    let mut max_drift: f64 = 0.0;
    let mut interrupted = false;
    let mut stop_reason = None;
    let mut initial_stiffness: Option<f64> = None;
    let mut internal_at_state: Option<Vec<f64>> = None;
    // Size of the last equilibrium correction (see the contact check below).
    let mut correction_size = (0.0, 0.0);

    loop {
        if steps.len() >= max_steps {
            let mut worst: Vec<usize> = (0..n_entities).collect();
            worst.sort_by_key(|&k| std::cmp::Reverse(switch_count[k]));
            let names: Vec<String> = worst.iter().take(5).filter(|&&k| switch_count[k] > 0)
                .map(|&k| if k < n_pairs { format!("pair {k} (node {}, {} switches)", eng.pairs[k].node_a, switch_count[k]) } else { format!("element {} ({} switches)", k - n_pairs, switch_count[k]) })
                .collect();
            stop_reason = Some(format!("the event loop reached max_events = {max_steps} increments at load fraction {:.6} (most switching: {}); the results up to there are kept: raise solver.max_events or coarsen the mesh", state.load_fraction, names.join(", ")));
            break;
        }
        if !eng.reduced {
            eng.refresh_tangents(&state, &plastic);
        }
        if eng.tangents_changed {
            eng.factor()?;
        }
        let (t0, dense0) = (Instant::now(), eng.timings.dense);
        let trial = eng.trial(&state, &status, &rtd_stick, 1.0, internal_at_state.take())?;
        // The small dense system is event bookkeeping, not a triangular solve.
        eng.timings.solves += t0.elapsed().as_secs_f64() - (eng.timings.dense - dense0);
        eng.timings.events += eng.timings.dense - dense0;
        // Limit load: with a plastic mechanism the tangent turns (nearly) singular and the trial
        // displacement explodes while the factorization still succeeds. Stop when the current
        // stiffness |R|²/(R·Δu) of the remaining load R falls below `limit_stiffness` of the
        // first increment's (a collapse, not a solution to report as complete).
        if !eng.reduced {
            let remaining: Vec<f64> = model.load.iter().enumerate().map(|(d, v)| if eng.fixed[d] { 0.0 } else { v * (1.0 - state.load_fraction) }).collect();
            let r2: f64 = remaining.iter().map(|v| v * v).sum();
            let work: f64 = remaining.iter().zip(&trial.du).map(|(a, b)| a * b).sum();
            if r2 > 0.0 {
                // Non-positive work of the remaining load: the tangent has lost positive
                // definiteness along the path (past the limit): zero stiffness.
                let stiffness = if work > 0.0 { r2 / work } else { 0.0 };
                let first = *initial_stiffness.get_or_insert(stiffness);
                if stiffness < opts.limit_stiffness * first {
                    stop_reason = Some(format!("limit load reached at load fraction {:.6}: the current stiffness fell to {:.1e} of the initial one (a plastic mechanism); the results up to there are kept: lower the load, or add hardening (H > 0)", state.load_fraction, stiffness / first));
                    break;
                }
            }
        }
        let t1 = Instant::now();

        let (frozen_pairs, frozen_elements) = frozen.split_at(n_pairs);
        let mut cands = events::candidates(
            &events::PairState { pairs: &eng.pairs, status: &status, lambda_n: &state.lambda_n, lambda_t: &state.lambda_t, u: &state.u, frozen: frozen_pairs },
            &events::Trial { du: &trial.du, dlambda_n: &trial.dlambda_n, dlambda_t: &trial.dlambda_t },
            eng.noise,
        );
        let elements = events::ElementState { material: &eng.material, stress: &state.stress, plastic_strain: &state.plastic_strain, plastic: &plastic, frozen: frozen_elements };
        cands.extend(events::element_candidates(&elements, &trial.dstress, &trial.dplastic));
        let drift_scale = if opts.drift_control { events::drift_bound(&elements, &trial.dstress, opts.max_stress_step) } else { f64::INFINITY };
        let s_min = cands.iter().map(|c| c.scale).fold(f64::INFINITY, f64::min);
        let scale = s_min.min(drift_scale).min(1.0);
        let last = s_min >= 1.0 && drift_scale >= 1.0;
        let phi0 = state.load_fraction;
        let remaining = 1.0 - phi0;
        if last {
            for c in &cands {
                if c.kind == EventKind::Close {
                    predicted_closure[c.entity] = phi0 + c.scale * remaining;
                }
            }
        }
        let tie_limit = s_min * (1.0 + opts.tie_tol) + 1e-14;
        // Grouping (δ = group_tol): friction and plasticity events up to φ_min (1 + δ) come along.
        let group_phi = (phi0 + s_min * remaining) * (1.0 + opts.group_tol);
        let early = |c: &Candidate| opts.group_tol > 0.0 && s_min > ZERO_SCALE && may_be_taken_early(c.kind) && c.scale <= 1.0 && phi0 + c.scale * remaining <= group_phi;
        let mut group: Vec<Candidate> = if scale < s_min || last { vec![] } else { cands.iter().copied().filter(|c| c.scale <= tie_limit || early(c)).collect() };
        if s_min <= ZERO_SCALE {
            // Zero-length events come from a trial that is itself inadmissible; apply first
            // the ones that release a violated constraint, and only then those that add one.
            let top = group.iter().map(|c| zero_length_priority(c.kind)).min().unwrap_or(0);
            group.retain(|c| zero_length_priority(c.kind) == top);
        }

        // Snapshots requested inside this increment (the path is linear in between).
        let phi1 = if last { 1.0 } else { phi0 + scale * remaining };
        while let Some(&f) = pending_fractions.first() {
            if f > phi1 + 1e-15 {
                break;
            }
            let s = if remaining > 0.0 { ((f - phi0) / remaining).clamp(0.0, scale) } else { 0.0 };
            let mut st = state.clone();
            eng.advance(&mut st, &trial, s, &plastic);
            st.load_fraction = f;
            snapshots.push(eng.snapshot(&st, &status, &plastic)?);
            pending_fractions.remove(0);
        }

        // Advance by S (eqs. 58–62), then check the state at the event.
        eng.advance(&mut state, &trial, scale, &plastic);
        state.load_fraction = phi1;
        for (p, st) in status.iter().enumerate() {
            if let Status::Slip { .. } = st {
                // On the cone (round-off removed); a pair that grouping let slip early slips
                // from below it and is only kept from crossing it.
                let cone = eng.pairs[p].slip_ratio(*st) * state.lambda_n[p];
                if opts.group_tol == 0.0 || state.lambda_t[p].abs() > cone.abs() {
                    state.lambda_t[p] = cone;
                }
            }
        }
        let drift = eng.drift(&state, &plastic);
        max_drift = max_drift.max(drift);
        // The equilibrium correction moves nodes and contact forces by a drift-sized amount that
        // no event of its own is computed for: an open pair pushed past its gap, or a stick pair
        // that has just reached its cone pushed over it, is switched by the next trial at S = 0;
        // the checks allow for that much. A zero-length increment of contact events only
        // changed no stress: the drift was corrected at the last event (whose allowance still
        // holds), and skipping it keeps the tangents, so K needs no refactorization.
        let stresses_kept = scale <= ZERO_SCALE && !group.iter().any(|c| c.kind.is_element_event());
        if !stresses_kept {
            correction_size = (0.0, 0.0);
        }
        if opts.drift_control && drift > 0.0 && !stresses_kept {
            eng.return_to_yield_surface(&mut state, &plastic);
            let correction = eng.trial(&state, &status, &rtd_stick, phi1, None)?;
            let largest = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            correction_size = (largest(&correction.du), largest(&correction.dlambda_n).max(largest(&correction.dlambda_t)));
            eng.advance(&mut state, &correction, 1.0, &plastic);
            state.load_fraction = phi1;
        }
        // (The internal force is reused by the next trial: status changes keep the stresses.)
        let (residual, internal) = eng.equilibrium_residual(&state);
        internal_at_state = internal;
        max_residual = max_residual.max(residual);
        if residual > opts.equilibrium_tol {
            bail!("equilibrium residual {residual:.3e} exceeds {:.1e} at load fraction {phi1:.6} (step {}): the linear system is ill-conditioned; check for nearly unsupported bodies or extreme element size ratios", opts.equilibrium_tol, steps.len());
        }
        eng.check_contact(&state, &status, frozen_pairs_of(&frozen, n_pairs), phi1, (2.0 * correction_size.0, 4.0 * correction_size.1))?;

        // Status changes of the events at this scale (with the anti-cycling rule).
        let zero_length = scale <= ZERO_SCALE;
        if !zero_length {
            zero_switches.iter_mut().for_each(|c| *c = 0);
            frozen.iter_mut().for_each(|f| *f = false);
        }
        let step_index = steps.len();
        let mut seen = vec![false; n_entities];
        for c in &group {
            let key = if c.kind.is_element_event() { n_pairs + c.entity } else { c.entity };
            if seen[key] {
                continue;
            }
            seen[key] = true;
            if zero_length && zero_switches[key] >= opts.max_zero_length_switches {
                frozen[key] = true;
                let kind = if c.kind.is_element_event() { EventKind::FrozenElement } else { EventKind::Frozen };
                events_out.push(EventRecord { step: step_index, load_fraction: phi1, kind, entity: c.entity });
                continue;
            }
            if zero_length {
                zero_switches[key] += 1;
            }
            switch_count[key] += 1;
            let p = c.entity;
            match c.kind {
                EventKind::Close => {
                    status[p] = eng.pairs[p].closed_status();
                    rtd_stick[p] = eng.pairs[p].rtd(&state.u);
                    closure_fraction[p] = phi1;
                }
                EventKind::Separate => {
                    status[p] = Status::Open;
                    state.lambda_n[p] = 0.0;
                    state.lambda_t[p] = 0.0;
                }
                EventKind::StickToSlip => {
                    status[p] = Status::Slip { direction: c.direction };
                    // On time the pair is on the cone; taken early it keeps its tangential force.
                    if c.scale <= tie_limit {
                        state.lambda_t[p] = eng.pairs[p].slip_ratio(status[p]) * state.lambda_n[p];
                    }
                }
                EventKind::SlipToStick => {
                    status[p] = Status::Stick;
                    rtd_stick[p] = eng.pairs[p].rtd(&state.u);
                }
                EventKind::Yield => plastic[c.entity] = true,
                EventKind::Unload => plastic[c.entity] = false,
                EventKind::Frozen | EventKind::FrozenElement => {}
            }
            events_out.push(EventRecord { step: step_index, load_fraction: phi1, kind: c.kind, entity: c.entity });
        }

        let n_closed = status.iter().filter(|s| s.is_closed()).count();
        let n_stick = status.iter().filter(|s| **s == Status::Stick).count();
        steps.push(StepRecord {
            load_fraction: phi1,
            scale,
            residual,
            n_closed,
            n_stick,
            n_slip: n_closed - n_stick,
            normal_force: state.lambda_n.iter().sum(),
            n_plastic: plastic.iter().filter(|&&p| p).count(),
            drift,
        });
        if let SnapshotRequest::EveryEvent = opts.snapshots {
            snapshots.push(eng.snapshot(&state, &status, &plastic)?);
        }
        eng.timings.events += t1.elapsed().as_secs_f64();
        if last || (opts.stop_at_first_yield && group.iter().any(|c| c.kind == EventKind::Yield)) {
            break;
        }
        if !progress(Progress { steps: steps.len(), events: events_out.len(), load_fraction: phi1 }) {
            interrupted = true;
            break;
        }
    }
    if interrupted || stop_reason.is_some() || matches!(opts.snapshots, SnapshotRequest::Fractions(_)) {
        if snapshots.last().map_or(true, |s| (s.load_fraction - state.load_fraction).abs() > 1e-14) {
            snapshots.push(eng.snapshot(&state, &status, &plastic)?);
        }
    }
    Ok(RunResult {
        events: events_out,
        steps,
        snapshots,
        closure_fraction,
        predicted_closure,
        max_equilibrium_residual: max_residual.max(eng.max_snapshot_residual),
        max_drift,
        n_factorizations: eng.solver.n_factorizations,
        n_solves: eng.solver.n_solves,
        interrupted,
        stop_reason,
        timings: eng.timings.clone(),
    })
}

fn frozen_pairs_of(frozen: &[bool], n_pairs: usize) -> &[bool] {
    &frozen[..n_pairs]
}

impl<'m> Engine<'m> {
    fn new(model: &'m Model) -> Result<Self> {
        let mesh = &model.mesh;
        mesh.validate()?;
        let n_nodes = mesh.n_nodes();
        let n_dofs = 2 * n_nodes;
        if !(model.thickness.is_finite() && model.thickness > 0.0) {
            bail!("thickness = {} is not allowed: give a positive out-of-plane thickness", model.thickness);
        }
        if model.materials.is_empty() {
            bail!("no material given: every body needs a material with E and nu");
        }
        for (i, m) in model.materials.iter().enumerate() {
            m.validate(i)?;
        }
        if model.element_material.len() != mesh.triangles.len() {
            bail!("element_material has {} entries for {} elements", model.element_material.len(), mesh.triangles.len());
        }
        if let Some((e, &m)) = model.element_material.iter().enumerate().find(|(_, &m)| m >= model.materials.len()) {
            bail!("element {e} uses material {m}, but only {} materials are given", model.materials.len());
        }
        if model.load.len() != n_dofs {
            bail!("the load vector has {} entries for {} DOFs (2 per node)", model.load.len(), n_dofs);
        }
        if let Some(d) = model.load.iter().position(|v| !v.is_finite()) {
            bail!("the load at node {} ({}) is not finite: check the pressure/traction values", d / 2, if d % 2 == 0 { "x" } else { "y" });
        }
        let mut fixed = vec![false; n_dofs];
        for &d in &model.fixed_dofs {
            if d >= n_dofs {
                bail!("fixed DOF {d} is out of range (the mesh has {n_dofs} DOFs)");
            }
            fixed[d] = true;
        }
        let load_norm = model.load.iter().enumerate().filter(|(d, _)| !fixed[*d]).map(|(_, v)| v * v).sum::<f64>().sqrt();
        // A tractionless scene is valid (its answer is zero); residuals are then absolute.
        let load_norm = if load_norm > 0.0 { load_norm } else { 1.0 };
        let (xmin, xmax, ymin, ymax) = mesh.nodes.iter().fold((f64::MAX, f64::MIN, f64::MAX, f64::MIN), |b, p| (b.0.min(p[0]), b.1.max(p[0]), b.2.min(p[1]), b.3.max(p[1])));
        let length_scale = ((xmax - xmin).powi(2) + (ymax - ymin).powi(2)).sqrt();
        let (body_of_node, n_bodies) = mesh.bodies();

        // Contact pairs.
        let mut pairs = Vec::with_capacity(model.pairs.len());
        let mut seen = std::collections::HashSet::new();
        for (k, p) in model.pairs.iter().enumerate() {
            let in_mesh = |i: usize| i < n_nodes && body_of_node[i] != usize::MAX;
            if !in_mesh(p.node_a) || p.node_b.map_or(false, |b| !in_mesh(b)) {
                let target = p.node_b.map_or(String::from("a rigid line"), |b| format!("node {b}"));
                bail!("contact pair {k} (node {} against {target}) refers to a node of no element: check the contact surface tags", p.node_a);
            }
            if p.node_b == Some(p.node_a) {
                bail!("contact pair {k} joins node {} to itself", p.node_a);
            }
            if !seen.insert((p.node_a, p.node_b)) {
                bail!("contact pair {k} repeats the pair of node {} (a node may face one target once): remove the duplicate", p.node_a);
            }
            if !(p.mu.is_finite() && p.mu >= 0.0) {
                bail!("contact pair {k}: mu = {} is not allowed: the friction coefficient must be >= 0", p.mu);
            }
            let nn = (p.normal[0].powi(2) + p.normal[1].powi(2)).sqrt();
            if !nn.is_finite() || (nn - 1.0).abs() > 1e-6 {
                bail!("contact pair {k}: the normal ({}, {}) is not a unit vector", p.normal[0], p.normal[1]);
            }
            if !p.gap.is_finite() {
                bail!("contact pair {k}: the initial gap is not finite");
            }
            if p.gap < -1e-9 * length_scale {
                bail!("initial penetration at contact pair {k} (node {}): gap {:.3e} < 0; move the bodies apart so that they at most touch", p.node_a, p.gap);
            }
            let normal = [p.normal[0] / nn, p.normal[1] / nn];
            let pair = Pair::new(p.node_a, p.node_b, normal, p.gap.max(0.0), p.mu, &fixed);
            if pair.w_n.norm() < 1e-12 {
                bail!("contact pair {k} (node {}): its normal direction is held by supports, so it can carry no contact force; remove the pair or the support", p.node_a);
            }
            pairs.push(pair);
        }

        let (modes, pinned) = free_modes(&mesh.nodes, &body_of_node, n_bodies, &fixed);
        // The contact DOFs that are equations (neither fixed nor pinned) go last in the factor:
        // their flexibility block (`SpdSolver`). Slot = their index there.
        let mut is_pinned = vec![false; n_dofs];
        pinned.iter().for_each(|&d| is_pinned[d] = true);
        let mut contact_slot = vec![usize::MAX; n_dofs];
        let mut slot_dofs = Vec::new();
        for pair in &pairs {
            for &(d, _) in pair.w_n.entries.iter().chain(&pair.w_t.entries) {
                if contact_slot[d] == usize::MAX && !fixed[d] && !is_pinned[d] {
                    contact_slot[d] = slot_dofs.len();
                    slot_dofs.push(d);
                }
            }
        }
        let elements: Vec<Cst> = (0..mesh.triangles.len()).map(|e| Cst::new(mesh, e)).collect();
        let map = DofMap::ordered(&elements, n_dofs, &fixed, &pinned, &slot_dofs)?;
        let pattern = StiffnessPattern::new(&elements, &map)?;
        let material: Vec<Material> = model.element_material.iter().map(|&m| model.materials[m]).collect();
        let tangents = material.iter().map(|m| m.tangent(&Vector4::zeros(), false)).collect();
        let reduced = model.options.reduced_elastic && !model.materials.iter().any(|m| m.is_plastic());
        let free_load: Vec<f64> = model.load.iter().enumerate().map(|(d, v)| if fixed[d] { 0.0 } else { *v }).collect();
        let mode_load: Vec<f64> = modes.iter().map(|m| m.vector.iter().zip(&free_load).map(|(a, b)| a * b).sum()).collect();
        let global_pairs = pairs.clone();
        let (pairs, contact_slot, mode_vectors, reduced_dofs) = if reduced {
            // Reduced DOFs: the slots, then the pinned contact DOFs (K# = 0 there, u = N α).
            let mut reduced_index = contact_slot.clone();
            let mut reduced_dofs = slot_dofs.clone();
            for pair in &pairs {
                for &(d, _) in pair.w_n.entries.iter().chain(&pair.w_t.entries) {
                    if reduced_index[d] == usize::MAX {
                        reduced_index[d] = reduced_dofs.len();
                        reduced_dofs.push(d);
                    }
                }
            }
            let remap = |w: &crate::contact::SparseVec| crate::contact::SparseVec { entries: w.entries.iter().map(|&(d, v)| (reduced_index[d], v)).collect() };
            let pairs = pairs.iter().map(|p| Pair { w_n: remap(&p.w_n), w_t: remap(&p.w_t), ..p.clone() }).collect();
            let slot = (0..reduced_dofs.len()).map(|r| if r < slot_dofs.len() { r } else { usize::MAX }).collect();
            let vectors = modes.iter().map(|m| reduced_dofs.iter().map(|&d| m.vector[d]).collect()).collect();
            (pairs, slot, vectors, reduced_dofs)
        } else {
            (pairs, contact_slot, modes.iter().map(|m| m.vector.clone()).collect(), vec![])
        };
        let load_total: f64 = model.load.iter().map(|v| v.abs()).sum::<f64>().max(f64::MIN_POSITIVE);
        Ok(Engine {
            model,
            elements,
            material,
            tangents,
            tangents_changed: true,
            pairs,
            global_pairs,
            modes,
            mode_vectors,
            mode_load,
            map,
            pattern,
            elastic_values: vec![],
            scatter: None,
            fixed,
            solver: SpdSolver::new(slot_dofs.len()),
            flexibility: faer::Mat::zeros(0, 0),
            contact_slot,
            reduced,
            u_load: vec![],
            u_load_reduced: vec![],
            u_load_max: 0.0,
            reduced_dofs,
            max_snapshot_residual: 0.0,
            load_norm,
            force_scale: load_total,
            noise: Noise { displacement: 0.0, force: 1e-12 * load_total },
            length_scale,
            timings: Timings::default(),
        })
    }

    fn factor(&mut self) -> Result<()> {
        let t0 = Instant::now();
        let (plane, thickness) = (self.model.plane, self.model.thickness);
        let k = if let Some(scatter) = &self.scatter {
            // The elastic K plus t A Bᵀ (D_ep − D) B of the elements that are plastic now.
            let mut values = self.elastic_values.clone();
            for (e, t) in self.tangents.iter().enumerate() {
                if t.flow.is_some() {
                    let softening = t.in_plane(plane) - self.material[e].elastic_tangent(plane);
                    scatter.add(e, &self.elements[e].stiffness(&softening, thickness), &mut values);
                }
            }
            self.pattern.with_values(values)
        } else {
            let in_plane: Vec<_> = self.tangents.iter().map(|t| t.in_plane(plane)).collect();
            let k = self.pattern.assemble(&self.elements, &in_plane, thickness, &self.map)?;
            if !self.reduced && self.tangents.iter().all(|t| t.flow.is_none()) && self.material.iter().any(|m| m.is_plastic()) {
                self.elastic_values = k.val().to_vec();
                self.scatter = Some(self.pattern.element_scatter(&self.elements, &self.map));
            }
            k
        };
        self.tangents_changed = false;
        let t1 = Instant::now();
        self.timings.assembly += (t1 - t0).as_secs_f64();
        self.solver.factor(&k, &self.map.dof_of_equation)?;
        self.timings.factorization += t1.elapsed().as_secs_f64();
        let t2 = Instant::now();
        self.flexibility = self.solver.trailing_inverse();
        self.timings.flexibility += t2.elapsed().as_secs_f64();
        if self.reduced {
            let load: Vec<f64> = self.model.load.iter().enumerate().map(|(d, v)| if self.fixed[d] { 0.0 } else { *v }).collect();
            let t3 = Instant::now();
            self.u_load = self.apply_ginv(std::slice::from_ref(&load)).pop().unwrap();
            self.u_load_reduced = self.reduced_dofs.iter().map(|&d| self.u_load[d]).collect();
            self.u_load_max = self.u_load.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            self.timings.solves += t3.elapsed().as_secs_f64();
        }
        if self.timings.solve_pair == 0.0 {
            // The best of three (one measurement is at the mercy of the machine's load).
            let mut best = f64::INFINITY;
            for _ in 0..3 {
                let mut b = vec![1.0; self.map.n_equations];
                let t4 = Instant::now();
                self.solver.solve_in_place(&mut b, 1);
                best = best.min(t4.elapsed().as_secs_f64());
                self.solver.n_solves -= 1;
            }
            self.timings.solve_pair = best;
        }
        Ok(())
    }

    /// x = K# y over all DOFs (fixed and pinned DOFs get 0), for each y in `ys`.
    fn apply_ginv(&mut self, ys: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let (n, k) = (self.map.n_equations, ys.len());
        let mut b: Vec<f64> = ys.iter().flat_map(|y| self.map.to_equations(y)).collect();
        if k > 0 {
            self.solver.solve_in_place(&mut b, k);
        }
        (0..k).map(|c| self.map.from_equations(&b[c * n..(c + 1) * n])).collect()
    }

    /// K# y at the contact slots for a force y = Σ v e_d on contact DOFs (a column of the
    /// flexibility matrix per entry).
    fn flexibility_times(&self, y: &[(usize, f64)]) -> Vec<f64> {
        let mut out = vec![0.0; self.flexibility.nrows()];
        for &(d, v) in y {
            let slot = self.contact_slot[d];
            if slot == usize::MAX || v == 0.0 {
                continue;
            }
            let col = self.flexibility.col(slot);
            out.iter_mut().zip(col.iter()).for_each(|(o, g)| *o += v * g);
        }
        out
    }

    /// cᵀ x for a constraint vector c and x given at the contact slots.
    fn dot_slots(&self, c: &crate::contact::SparseVec, x: &[f64]) -> f64 {
        c.entries.iter().map(|&(d, v)| match self.contact_slot[d] {
            usize::MAX => 0.0,
            slot => v * x[slot],
        }).sum()
    }

    /// Internal nodal forces Σ t A Bᵀ σ (eq. 42).
    fn internal_force(&self, stress: &[Vector4<f64>]) -> Vec<f64> {
        let mut f = vec![0.0; self.map.role.len()];
        for (el, s) in self.elements.iter().zip(stress) {
            let fe = el.internal_force(&Vector3::new(s[0], s[1], s[3]), self.model.thickness);
            for (k, d) in el.dofs().iter().enumerate() {
                f[*d] += fe[k];
            }
        }
        f
    }

    /// Out-of-balance force at load fraction `phi`, φ P − P_σ + contact forces over the free
    /// DOFs, from the internal force P_σ of the state's stresses.
    fn residual_from(&self, internal: &[f64], state: &State, phi: f64) -> Vec<f64> {
        let mut r = internal.to_vec();
        for (d, v) in r.iter_mut().enumerate() {
            *v = if self.fixed[d] { 0.0 } else { phi * self.model.load[d] - *v };
        }
        for (p, pair) in self.global_pairs.iter().enumerate() {
            pair.w_n.add_to(state.lambda_n[p], &mut r);
            pair.w_t.add_to(state.lambda_t[p], &mut r);
        }
        r
    }

    /// |φP − P_σ + Wλ| / |P|, and (full mode) the internal force P_σ it used, for the next
    /// trial from the same stresses.
    fn equilibrium_residual(&self, state: &State) -> (f64, Option<Vec<f64>>) {
        if self.reduced {
            // u = K#(φP + Wλ) + Nα is in equilibrium exactly when φP + Wλ is orthogonal to
            // the free rigid modes (K K# y = y for y ⊥ N); snapshots check the full residual.
            let r2: f64 = self
                .mode_vectors
                .iter()
                .zip(&self.mode_load)
                .map(|(mode, load)| {
                    let contact: f64 = self.pairs.iter().enumerate().map(|(p, pair)| state.lambda_n[p] * pair.w_n.dot(mode) + state.lambda_t[p] * pair.w_t.dot(mode)).sum();
                    (state.load_fraction * load + contact).powi(2)
                })
                .sum();
            return (r2.sqrt() / self.load_norm, None);
        }
        let internal = self.internal_force(&state.stress);
        let r = self.residual_from(&internal, state, state.load_fraction);
        (r.iter().map(|v| v * v).sum::<f64>().sqrt() / self.load_norm, Some(internal))
    }

    /// The trial increment that takes the state to load fraction `target` (eq. 44 in residual
    /// form): 1 for the remaining load; the current fraction for an equilibrium correction.
    ///
    /// `internal`: the internal force P_σ of `state`'s stresses if the caller has it.
    fn trial(&mut self, state: &State, status: &[Status], rtd_stick: &[f64], target: f64, internal: Option<Vec<f64>>) -> Result<TrialIncrement> {
        // z0 = K# r at the contact slots and the rigid-body rows −Nᵀ r for the out-of-balance
        // force r. In the full mode only the forward sweep of r is done here: the backward sweep
        // waits for the contact forces (`SpdSolver::forward`), one solve per trial.
        let (mode_rhs, z0, forward_sweep): (Vec<f64>, Vec<f64>, Vec<f64>) = if self.reduced {
            // Elastic and in equilibrium: the out-of-balance force is (target − φ) P exactly.
            let c = target - state.load_fraction;
            (self.mode_load.iter().map(|v| -c * v).collect(), self.u_load_reduced.iter().map(|v| c * v).collect(), vec![])
        } else {
            let internal = internal.unwrap_or_else(|| self.internal_force(&state.stress));
            let r = self.residual_from(&internal, state, target);
            let w = self.solver.forward(&self.map.to_equations(&r));
            let z0_slots = self.solver.trailing_solution(&w);
            (self.mode_vectors.iter().map(|m| -m.iter().zip(&r).map(|(a, b)| a * b).sum::<f64>()).collect(), z0_slots, w)
        };

        // Rows (constraints) and their right-hand sides h.
        let mut rows = Vec::new();
        let mut h = Vec::new();
        for (p, st) in status.iter().enumerate() {
            if !st.is_closed() {
                continue;
            }
            let pair = &self.pairs[p];
            rows.push(Row::Normal(p));
            h.push(-pair.gap(&state.u));
            if *st == Status::Stick && pair.frictional() {
                rows.push(Row::Tangent(p));
                h.push(rtd_stick[p] - pair.rtd(&state.u));
            }
        }
        let m = rows.len();
        let nm = self.modes.len();
        let size = m + nm;
        // Column j: force direction e_j (w_n − dμ w_t for a slipping pair, eq. 41) and K# e_j
        // at the contact DOFs, from the flexibility matrix.
        let columns: Vec<Vec<(usize, f64)>> = rows
            .iter()
            .map(|row| match *row {
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
            })
            .collect();
        let flex_columns: Vec<Vec<f64>> = columns.iter().map(|e| self.flexibility_times(e)).collect();
        let cvecs: Vec<&crate::contact::SparseVec> = rows
            .iter()
            .map(|row| match *row {
                Row::Normal(p) => &self.pairs[p].w_n,
                Row::Tangent(p) => &self.pairs[p].w_t,
            })
            .collect();
        let mut a = DMatrix::<f64>::zeros(size, size);
        let mut rhs = DVector::<f64>::zeros(size);
        for j in 0..m {
            for i in 0..m {
                a[(i, j)] = self.dot_slots(cvecs[i], &flex_columns[j]);
            }
            // Nᵀ e_j
            for (k, mode) in self.mode_vectors.iter().enumerate() {
                a[(m + k, j)] = columns[j].iter().map(|&(d, v)| v * mode[d]).sum();
            }
        }
        for (k, mode) in self.mode_vectors.iter().enumerate() {
            for i in 0..m {
                a[(i, m + k)] = cvecs[i].dot(mode);
            }
            rhs[m + k] = mode_rhs[k];
        }
        for i in 0..m {
            rhs[i] = h[i] - self.dot_slots(cvecs[i], &z0);
        }
        self.check_restrained(&a, m, &rows)?;
        let t_dense = Instant::now();
        let sol = match solve_dense(&a, &rhs) {
            Some(x) => x,
            None => {
                let closed: Vec<String> = rows.iter().filter_map(|r| if let Row::Normal(p) = r { Some(p.to_string()) } else { None }).collect();
                bail!("the contact system is singular at load fraction {:.6}: the closed pairs [{}] are redundant (two pairs on one node along the same direction?) — remove duplicate pairs", state.load_fraction, closed.join(", "));
            }
        };
        self.timings.dense += t_dense.elapsed().as_secs_f64();

        let mut dlambda_n = vec![0.0; self.pairs.len()];
        let mut dlambda_t = vec![0.0; self.pairs.len()];
        for j in 0..m {
            match rows[j] {
                Row::Normal(p) => {
                    dlambda_n[p] = sol[j];
                    dlambda_t[p] = self.pairs[p].slip_ratio(status[p]) * sol[j];
                }
                Row::Tangent(p) => dlambda_t[p] = sol[j],
            }
        }
        // Δu = K#(r + E Δλ) + N α.
        let mut du = if self.reduced {
            // Only the contact DOFs are needed (gaps, slips): Σ_j Δλ_j K# e_j there
            // (reduced index = slot).
            let mut du = z0;
            for j in 0..m {
                du.iter_mut().zip(&flex_columns[j]).for_each(|(x, g)| *x += sol[j] * g);
            }
            du
        } else {
            // The contact forces E Δλ sit on contact DOFs: their forward sweep only touches the
            // trailing rows. Then one backward sweep gives K#(r + E Δλ).
            let mut w = forward_sweep;
            if m > 0 {
                let mut force_slots = vec![0.0; self.flexibility.nrows()];
                for j in 0..m {
                    for &(d, v) in &columns[j] {
                        if self.contact_slot[d] != usize::MAX {
                            force_slots[self.contact_slot[d]] += sol[j] * v;
                        }
                    }
                }
                self.solver.add_trailing_force(&mut w, &force_slots);
            }
            self.map.from_equations(&self.solver.backward(w))
        };
        let dalpha: Vec<f64> = (0..self.modes.len()).map(|k| sol[m + k]).collect();
        for (k, mode) in self.mode_vectors.iter().enumerate() {
            let s = sol[m + k];
            du.iter_mut().zip(mode).for_each(|(d, v)| *d += s * v);
        }
        let (dstress, dplastic) = if self.reduced { (vec![], vec![]) } else { self.stress_increment(&du) };
        let umax = self.largest_displacement(&du, target - state.load_fraction);
        self.noise.displacement = 1e-11 * umax;
        Ok(TrialIncrement { du, dstress, dplastic, dlambda_n, dlambda_t, dalpha })
    }

    /// Length of the displacement vectors the event loop carries.
    fn loop_dofs(&self) -> usize {
        if self.reduced { self.reduced_dofs.len() } else { self.map.role.len() }
    }

    /// max |u| (for round-off tolerances). The reduced mode carries u at the contact DOFs only:
    /// the load's share elsewhere is bounded by `load_fraction` × max |K#P|.
    fn largest_displacement(&self, u: &[f64], load_fraction: f64) -> f64 {
        let carried = u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if self.reduced {
            carried.max(load_fraction.abs() * self.u_load_max)
        } else {
            carried
        }
    }

    /// A free rigid-body mode that no closed pair holds makes the small system singular:
    /// say which body and which motion.
    fn check_restrained(&self, a: &DMatrix<f64>, m: usize, rows: &[Row]) -> Result<()> {
        let nm = self.modes.len();
        if nm == 0 {
            return Ok(());
        }
        // Columns m.. of the constraint rows: Cᵀ N (m × nm) must have full column rank per body.
        let mut bodies: Vec<usize> = self.modes.iter().map(|md| md.body).collect();
        bodies.dedup();
        for body in bodies {
            let idx: Vec<usize> = (0..nm).filter(|&k| self.modes[k].body == body).collect();
            // Padded with zero rows so that the SVD returns the full right singular basis.
            let mut g = DMatrix::<f64>::zeros(m.max(idx.len()), idx.len());
            for i in 0..m {
                for (c, &k) in idx.iter().enumerate() {
                    g[(i, c)] = a[(i, m + k)];
                }
            }
            let svd = g.svd(false, true);
            let smax = svd.singular_values.iter().fold(0.0f64, |x, v| x.max(*v));
            let v_t = svd.v_t.as_ref().expect("requested");
            // Each (near-)zero singular value is a motion that no closed pair resists.
            let free: Vec<String> = (0..svd.singular_values.len())
                .filter(|&j| smax == 0.0 || svd.singular_values[j] <= 1e-9 * smax)
                .map(|j| {
                    let mut w = [0.0; 3];
                    for (c, &k) in idx.iter().enumerate() {
                        for (wl, ml) in w.iter_mut().zip(self.modes[k].weights) {
                            *wl += v_t[(j, c)] * ml;
                        }
                    }
                    crate::rigid_modes::describe(w[0], w[1], w[2])
                })
                .collect();
            if !free.is_empty() {
                let closed = rows.iter().filter(|r| matches!(r, Row::Normal(_))).count();
                bail!("body {body} is free to move ({}): it has no support in that direction and its {closed} closed contact pair(s) do not hold it; add a support (fix/symmetry) or start a contact closed (gap 0)", free.join("; "));
            }
        }
        Ok(())
    }

    /// Δσ and Δεp of every element for a displacement increment (eqs. 11, 18).
    fn stress_increment(&self, du: &[f64]) -> (Vec<Vector4<f64>>, Vec<f64>) {
        let plane = self.model.plane;
        self.elements
            .iter()
            .zip(&self.tangents)
            .map(|(el, t)| {
                let e = el.strain(du);
                (t.stress_increment(plane, &e), t.plastic_multiplier(plane, &e))
            })
            .unzip()
    }

    /// Rebuild the tangents of plastic elements at the current stress (the paper's D_ep at
    /// the increment's start) and of elements whose plastic flag changed; K is refactorized
    /// only if one of them differs (not after a zero-length increment without a yield/unload).
    fn refresh_tangents(&mut self, state: &State, plastic: &[bool]) {
        for e in 0..self.elements.len() {
            let was_plastic = self.tangents[e].flow.is_some();
            if plastic[e] || was_plastic {
                let tangent = self.material[e].tangent(&state.stress[e], plastic[e]);
                if tangent.d4 != self.tangents[e].d4 || plastic[e] != was_plastic {
                    self.tangents[e] = tangent;
                    self.tangents_changed = true;
                }
            }
        }
    }

    /// Yield-surface drift: max |σe − σy(εp)| / σy(εp) over plastic elements.
    fn drift(&self, state: &State, plastic: &[bool]) -> f64 {
        (0..plastic.len())
            .filter(|&e| plastic[e])
            .map(|e| {
                let sy = self.material[e].current_yield(state.plastic_strain[e]);
                (von_mises(&state.stress[e]) - sy).abs() / sy
            })
            .fold(0.0, f64::max)
    }

    /// Scale the stress of plastic elements back onto the yield surface: the deviator at fixed
    /// mean stress in plane strain, the in-plane stress (keeping σz = 0) in plane stress.
    fn return_to_yield_surface(&self, state: &mut State, plastic: &[bool]) {
        for e in 0..plastic.len() {
            if !plastic[e] {
                continue;
            }
            let sy = self.material[e].current_yield(state.plastic_strain[e]);
            let s = state.stress[e];
            let factor = sy / von_mises(&s);
            if factor > 1.0 && self.model.options.group_tol > 0.0 {
                // Yielded early by grouping and still inside the surface: flowing from there
                // is the O(δ) error grouping accepts; lifting it onto the surface would add
                // stress that no load put there.
                continue;
            }
            state.stress[e] = match self.model.plane {
                Plane::Stress => s * factor,
                Plane::Strain => {
                    let p = (s[0] + s[1] + s[2]) / 3.0;
                    let mean = Vector4::new(p, p, p, 0.0);
                    mean + (s - mean) * factor
                }
            };
        }
    }

    /// state += s × trial increment (eqs. 58–61).
    fn advance(&self, st: &mut State, trial: &TrialIncrement, s: f64, plastic: &[bool]) {
        st.u.iter_mut().zip(&trial.du).for_each(|(u, d)| *u += s * d);
        st.stress.iter_mut().zip(&trial.dstress).for_each(|(u, d)| *u += s * d);
        for e in 0..st.plastic_strain.len() {
            if plastic[e] {
                st.plastic_strain[e] += s * trial.dplastic[e].max(0.0);
            }
        }
        st.lambda_n.iter_mut().zip(&trial.dlambda_n).for_each(|(u, d)| *u += s * d);
        st.lambda_t.iter_mut().zip(&trial.dlambda_t).for_each(|(u, d)| *u += s * d);
        st.alpha.iter_mut().zip(&trial.dalpha).for_each(|(u, d)| *u += s * d);
    }

    /// Contact conditions at an event: no penetration, λ_n ≥ 0, Coulomb cone.
    fn check_contact(&self, state: &State, status: &[Status], frozen: &[bool], phi: f64, allowance: (f64, f64)) -> Result<()> {
        let umax = self.largest_displacement(&state.u, state.load_fraction);
        let gap_tol = 1e-8 * umax + 1e-12 * self.length_scale + allowance.0;
        let force_tol = 1e-9 * self.force_scale + allowance.1;
        let why = |p: usize| if frozen[p] { " (the pair was frozen by the anti-cycling rule: it cycled between statuses at zero load increment)" } else { "" };
        for (p, pair) in self.pairs.iter().enumerate() {
            let g = pair.gap(&state.u);
            if g < -gap_tol {
                bail!("contact pair {p} (node {}) penetrates by {:.3e} at load fraction {phi:.6}{}", pair.node_a, -g, why(p));
            }
            if status[p].is_closed() {
                let (ln, lt) = (state.lambda_n[p], state.lambda_t[p]);
                if ln < -force_tol {
                    bail!("contact pair {p} (node {}) carries a tensile force {ln:.3e} at load fraction {phi:.6}{}", pair.node_a, why(p));
                }
                if lt.abs() > pair.mu * ln + force_tol {
                    bail!("contact pair {p} (node {}) violates Coulomb's law (|λ_t| = {:.3e} > μλ_n = {:.3e}) at load fraction {phi:.6}{}", pair.node_a, lt.abs(), pair.mu * ln, why(p));
                }
            }
        }
        Ok(())
    }

    /// The full fields of a state; in the reduced mode they are rebuilt here (one solve) and
    /// their equilibrium is checked in full.
    fn snapshot(&mut self, state: &State, status: &[Status], plastic: &[bool]) -> Result<Snapshot> {
        let full;
        let state = if self.reduced {
            full = self.reconstruct(state)?;
            &full
        } else {
            state
        };
        Ok(Snapshot {
            load_fraction: state.load_fraction,
            u: state.u.clone(),
            stress: state.stress.iter().map(|s| [s[0], s[1], s[2], s[3]]).collect(),
            plastic_strain: state.plastic_strain.clone(),
            plastic: if plastic.is_empty() { vec![0; self.elements.len()] } else { plastic.iter().map(|&p| p as i8).collect() },
            lambda_n: state.lambda_n.clone(),
            lambda_t: state.lambda_t.clone(),
            status: status.iter().map(|s| s.code()).collect(),
            gap: self.global_pairs.iter().map(|p| p.gap(&state.u)).collect(),
            rtd: self.global_pairs.iter().map(|p| p.rtd(&state.u)).collect(),
        })
    }

    /// u = φ K#P + K#(W λ) + N α and its stresses, for the reduced elastic mode.
    fn reconstruct(&mut self, state: &State) -> Result<State> {
        let mut y = vec![0.0; self.map.role.len()];
        for (p, pair) in self.global_pairs.iter().enumerate() {
            pair.w_n.add_to(state.lambda_n[p], &mut y);
            pair.w_t.add_to(state.lambda_t[p], &mut y);
        }
        let mut u = self.apply_ginv(std::slice::from_ref(&y)).pop().unwrap();
        u.iter_mut().zip(&self.u_load).for_each(|(a, b)| *a += state.load_fraction * b);
        for (mode, a) in self.modes.iter().zip(&state.alpha) {
            u.iter_mut().zip(&mode.vector).for_each(|(x, v)| *x += a * v);
        }
        let (stress, _) = self.stress_increment(&u);
        let mut full = state.clone();
        full.u = u;
        full.stress = stress;
        full.plastic_strain = vec![0.0; self.elements.len()];
        let saved = std::mem::replace(&mut self.reduced, false);
        let (residual, _) = self.equilibrium_residual(&full);
        self.reduced = saved;
        self.max_snapshot_residual = self.max_snapshot_residual.max(residual);
        if residual > self.model.options.equilibrium_tol {
            bail!("equilibrium residual {residual:.3e} of the reconstructed fields exceeds {:.1e} at load fraction {:.6}: the linear system is ill-conditioned", self.model.options.equilibrium_tol, state.load_fraction);
        }
        Ok(full)
    }
}

/// Solve the small dense system by LU with partial pivoting (faer's blocked kernel); None when
/// it is singular to working precision (a pivot below 1e-13 of the largest).
fn solve_dense(a: &DMatrix<f64>, rhs: &DVector<f64>) -> Option<DVector<f64>> {
    let n = rhs.len();
    if n == 0 {
        return Some(DVector::zeros(0));
    }
    let mat = faer::MatRef::from_column_major_slice(a.as_slice(), n, n);
    let lu = faer::linalg::solvers::PartialPivLu::new(mat);
    let u = lu.U();
    let pivots: Vec<f64> = (0..n).map(|i| u[(i, i)].abs()).collect();
    let largest = pivots.iter().fold(0.0f64, |m, v| m.max(*v));
    if !(largest > 0.0) || pivots.iter().any(|&p| p <= 1e-13 * largest) {
        return None;
    }
    let mut x = faer::Mat::<f64>::from_fn(n, 1, |i, _| rhs[i]);
    use faer::linalg::solvers::SolveCore;
    lu.solve_in_place_with_conj(faer::Conj::No, x.as_mut());
    let x = DVector::from_fn(n, |i, _| x[(i, 0)]);
    x.iter().all(|v| v.is_finite()).then_some(x)
}
