//! A plastic window: a grouped increment (δ = `group_tol`, `stepping`) that runs past the first
//! predicted yield by δ of the load, its whole lifecycle.
//!
//! 1. It opens where the selection bounds it (`selection::select`, the window's end); what it
//!    changes outside the element arrays is kept (`Window::open`).
//! 2. Contact events inside it are contact sub-steps (`contact_events`): K is held from its
//!    trial to its end and its stresses are integrated and balanced once, at that end, so over
//!    that stretch the path is linear in K, as in an elastic run, and a contact event (stick↔
//!    slip, a separation, a closure away from plastic elements) needs only the paper's small
//!    system (eqs. 43–44) at the contact DOFs: from a state the increment reached linearly the
//!    remaining load is (c'/c) r of the trial's (`TrialBase`), so K# r at the contact slots is
//!    the trial's scaled and the flexibility gives the rest. The events switch one after
//!    another in load order, exactly as between full trials (with the anti-cycling rule), each
//!    with its step record; the increment then ends at its window, or at a closure next to a
//!    plastic element, with one backward sweep for Δu = K⁻¹(f r + W Δλ) + N Δα over all DOFs.
//!    (The full-space loop would solve, integrate and correct at every one of them: on the
//!    elastoplastic Hertz at 24.5k DOFs 297 increments become 64, with 183 sub-steps.) Not with
//!    prescribed displacements changing in the stage (their DOFs' increments follow the full
//!    state), nor when every event is a snapshot (each would need the full fields).
//! 3. Every element that yields inside gets the exact split of its strain increment (`advance`,
//!    `plasticity`), and the window is re-integrated from its start until it is balanced to 1e-4
//!    of the load (`plasticity::restore_equilibrium`).
//! 4. It closes with the yields and unloads inside it recorded in load order (`inside_events`);
//!    or, when its rounds stall (past a limit load there is no equilibrium with the stresses on
//!    their yield surfaces; near it they converge too slowly), it is taken back and retaken
//!    event by event, the paper's procedure, up to the load where it ended (`Window::retake`).
//!    Keeping the last linear stresses there (in equilibrium, but beyond the surfaces) put the
//!    thick sphere's limit-load stop 0.9 % above the exact run's at δ = 0.01; event by event,
//!    the procedure meets the limit where it is.

use super::advance::project_onto_cone;
use super::anticycling::AntiCycling;
use super::checks::Correction;
use super::engine::Engine;
use super::problem::Problem;
use super::recording::{Balance, InsideEvent, Recorder};
use super::restraint::{hold, Hold};
use super::selection::{select_contact, Selection};
use super::slip_direction::direct_new_slips;
use super::state::{IncrementStart, PairsInSpace, State, TrialIncrement};
use super::stepping::Stepping;
use super::switching::{contact_forces, switch_statuses};
use super::trial::{self, Solve, TrialBase};
use crate::contact::{Shift, Status};
use crate::dim::Dim;
use crate::error::Result;
use crate::events::Candidate;
use crate::model::EventKind;

/// At most this many contact sub-steps per increment (zero-length cycles are broken by the
/// anti-cycling rule; past it the increment simply ends there).
const MAX_SUBSTEPS: usize = 10_000;
/// The whole increment reproduces the sub-steps' contact path to this, relative to its largest
/// displacement. Measured: 1e-13 on the elastoplastic Hertz; up to 2.2e-6 at the two DOFs of
/// one slipping pair of the paper's block (quick mesh, μ = 0.2), a punch held by contact alone.
/// That is round-off, amplified: K# of a free body is its compliance relative to the pinned
/// DOF, there ~1e4 per unit force at the contact slots (a row sums to 2.2e5), and the pair's
/// displacement increment, 8e-4 per unit load, is the difference of K#r ≈ 1.372 and K#WΔλ ≈
/// −1.371. The whole takes Δλ as the difference of the end and start forces (~50 each: 4e-14
/// apart from the sub-steps' sum of increments), which K# turns into 4.6e-9. An error in the
/// algebra would be of order one.
const PATH_CHECK: f64 = 1e-3;

/// An open window: what it changes outside the element arrays (those come back from its
/// `IncrementStart`), the contact state, and what was recorded since it began.
pub(super) struct Window {
    stage: usize,
    load_fraction: f64,
    lambda_n: Vec<f64>,
    lambda_t: Vec<f64>,
    alpha: Vec<f64>,
    status: Vec<Status>,
    rtd_stick: Vec<f64>,
    /// 3D: λ_t2, the stuck RTD along t2 and the slip directions.
    space: Option<PairsInSpace>,
    shift: Vec<Shift>,
    recorded: Recorded,
    correction: Correction,
}

/// How far the record had come when a window opened.
struct Recorded {
    events: usize,
    steps: usize,
    substeps: usize,
    closure_fraction: Vec<f64>,
    balance: Balance,
}

impl Window {
    /// The window of a selection that groups plastic events inside (`Selection::plastic_inside`);
    /// None for an increment taken event by event.
    pub fn open<D: Dim>(
        sel: &Selection,
        state: &State<D>,
        rec: &Recorder,
        correction: Correction,
    ) -> Option<Self> {
        let recorded = || Recorded {
            events: rec.events.len(),
            steps: rec.steps.len(),
            substeps: rec.n_substeps,
            closure_fraction: rec.closure_fraction.clone(),
            balance: rec.balance,
        };
        sel.plastic_inside.then(|| Window {
            stage: state.stage,
            load_fraction: state.load_fraction,
            lambda_n: state.lambda_n.clone(),
            lambda_t: state.lambda_t.clone(),
            alpha: state.alpha.clone(),
            status: state.status.clone(),
            rtd_stick: state.rtd_stick.clone(),
            space: state.space().cloned(),
            shift: state.shift.clone(),
            recorded: recorded(),
            correction,
        })
    }

    /// Back to the window's start (its element arrays from `start`), and event by event until
    /// the path time where it ended (the returned stepping). (The anti-cycling switch counts
    /// keep the window's switches: they only name the busiest entities when the event bound
    /// stops a run.)
    pub fn retake<D: Dim>(
        self,
        state: &mut State<D>,
        start: IncrementStart,
        rec: &mut Recorder,
        correction: &mut Correction,
        stepping: Stepping,
    ) -> Stepping {
        let ended = state.time();
        (state.stress, state.plastic_strain, state.plastic, state.u) =
            (start.stress, start.plastic_strain, start.plastic, start.u);
        (state.stage, state.load_fraction) = (self.stage, self.load_fraction);
        (state.lambda_n, state.lambda_t, state.alpha) = (self.lambda_n, self.lambda_t, self.alpha);
        (state.status, state.rtd_stick, state.shift) = (self.status, self.rtd_stick, self.shift);
        if let (Some(now), Some(then)) = (state.space_mut(), &self.space) {
            // (the laid facets and the unbalanced jumps stay as they are)
            now.lambda_t2.clone_from(&then.lambda_t2);
            now.rtd_stick2.clone_from(&then.rtd_stick2);
            now.slip_dir.clone_from(&then.slip_dir);
            now.vertex.clone_from(&then.vertex);
        }
        let recorded = self.recorded;
        rec.events.truncate(recorded.events);
        rec.steps.truncate(recorded.steps);
        (rec.n_substeps, rec.closure_fraction) = (recorded.substeps, recorded.closure_fraction);
        rec.balance = recorded.balance;
        rec.n_retaken += 1;
        *correction = self.correction;
        stepping.retake_until(ended)
    }
}

/// The contact events of a window's selection taken as contact sub-steps (when
/// `takes_substeps`, with the trial's `base`): the increment from `state` as one trial
/// increment (scaled to the remaining load) and its selection, for `advance`, and the largest
/// force jump of a switch. Otherwise the trial and selection as they are.
pub(super) fn contact_events<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    trial: TrialIncrement,
    sel: Selection,
    base: Option<TrialBase>,
    cycles: &mut AntiCycling,
    rec: &mut Recorder,
) -> Result<(TrialIncrement, Selection, f64)> {
    match base.filter(|_| takes_substeps(eng, &sel, rec.every_event(), state)) {
        Some(base) => contact_substeps(eng, state, trial, sel, &base, cycles, rec),
        None => Ok((trial, sel, 0.0)),
    }
}

/// The yields and unloads inside the increment just settled, in order: the elements whose
/// status differs from the increment's `start`, but for the events that ended it (`group`).
pub(super) fn inside_events<D: Dim>(
    state: &State<D>,
    sel: &Selection,
    start: Option<IncrementStart>,
) -> Vec<InsideEvent> {
    let Some(start) = start else { return vec![] };
    let ended: std::collections::HashSet<usize> =
        sel.group.iter().filter(|c| c.kind.is_element_event()).map(|c| c.entity).collect();
    let mut inside: Vec<InsideEvent> = (0..state.plastic.len())
        .filter(|&e| state.plastic[e] != start.plastic[e] && !ended.contains(&e))
        .map(|e| match state.plastic[e] {
            true => InsideEvent {
                element: e,
                kind: EventKind::Yield,
                at: start.yielded_at.get(&e).copied().unwrap_or(1.0),
            },
            false => InsideEvent { element: e, kind: EventKind::Unload, at: 0.0 },
        })
        .collect();
    inside.sort_by(|a, b| a.at.total_cmp(&b.at));
    inside
}

/// Whether the selection's events are taken as contact sub-steps: a plastic window ended early
/// by contact events only.
fn takes_substeps<D: Dim>(
    eng: &Engine<D>,
    sel: &Selection,
    every_event: bool,
    state: &State<D>,
) -> bool {
    sel.plastic_inside
        && !sel.last
        && !every_event
        && !sel.group.is_empty()
        && sel.phi < sel.bound_phi
        && sel.group.iter().all(|c| inside_substeps(&eng.problem, c, state))
        && eng.loads.load.prescribed_changes().iter().all(|&(_, v)| v == 0.0)
}

/// Stick↔slip and separation are taken as sub-steps, and a closure whose nodes' elements are
/// all elastic; a closure next to a plastic element ends the increment, as an element event
/// does: a new contact at the edge of a plastic zone concentrates stress where the held
/// tangent is furthest from the material's. Measured: on the sphere on a flat (H' = 0,
/// 50 ω_c) every closure as a sub-step moved a contact-edge element's stress path from
/// 0.085 % to 1.5 % of the peak stress (with this rule: 0.086 %); on the elastoplastic
/// Hertz at 24.5k DOFs, whose contact edge stays elastic, the rule takes every closure and
/// the engine goes 2.77 → 2.61 s (δ = 0.01), 2.24 → 1.78 s (δ = 0.03).
fn inside_substeps<D: Dim>(problem: &Problem<D>, c: &Candidate, state: &State<D>) -> bool {
    match c.kind {
        EventKind::StickToSlip | EventKind::SlipToStick | EventKind::Separate => true,
        EventKind::Close => problem.pairs[c.entity]
            .w_n
            .entries
            .iter()
            .all(|&(d, _)| problem.node_elements[d / D::N].iter().all(|&e| !state.plastic[e])),
        _ => false,
    }
}

/// Switch the selection's contact events and go on event by event in the contact space up to
/// the increment's bound; then the whole increment from `state` as one trial increment (scaled
/// to the remaining load) and its selection, for `advance`, and the largest force jump of a
/// switch (a jump ends the sub-steps: the correction must rebalance it).
fn contact_substeps<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    sub: TrialIncrement,
    sel: Selection,
    base: &TrialBase,
    cycles: &mut AntiCycling,
    rec: &mut Recorder,
) -> Result<(TrialIncrement, Selection, f64)> {
    // The trial's first yield is the exact onset only if no contact event switches before
    // it (else the yields keep where the integration puts them).
    let first_yield = sel.first_yield.filter(|&(_, phi)| phi <= sel.phi);
    let start = state.clone();
    let mut jumped = vec![[0.0; 3]; state.lambda_n.len()];
    let (sel, jump) = walk_contact_events(eng, state, sub, sel, base, cycles, rec, &mut jumped)?;
    let whole = whole_increment(eng, &start, state, base);
    check_contact_path(eng, &start, state, &whole, &jumped)?;
    let (phi, bound_phi) = (state.load_fraction, sel.bound_phi);
    let scale = scale_between(&start, state);
    let (status, rtd_stick) =
        (std::mem::take(&mut state.status), std::mem::take(&mut state.rtd_stick));
    let kept = state.space_mut().map(|s| {
        (
            std::mem::take(&mut s.rtd_stick2),
            std::mem::take(&mut s.slip_dir),
            std::mem::take(&mut s.vertex),
        )
    });
    *state = State { status, rtd_stick, ..start };
    if let (Some(s), Some(kept)) = (state.space_mut(), kept) {
        (s.rtd_stick2, s.slip_dir, s.vertex) = kept;
    }
    let rebalance = jump > eng.problem.scales.force_noise;
    let last = sel.last && !rebalance;
    let ending = if rebalance || sel.group.iter().all(|c| inside_substeps(&eng.problem, c, state)) {
        vec![]
    } else {
        sel.group
    };
    let predicted_closures = if last { sel.predicted_closures } else { vec![] };
    Ok((
        whole,
        Selection {
            scale,
            last,
            phi,
            group: ending,
            predicted_closures,
            plastic_inside: true,
            bound_phi,
            first_yield,
        },
        jump,
    ))
}

/// The sub-steps themselves: the contact state advanced to each selection, its events switched
/// and recorded, the next contact-space trial and selection, until the bound, the stage's end,
/// a closure (left for the increment's end) or a force jump. Returns the last selection (its
/// bound the increment's) and the jump.
/// `jumped`: the contact forces the switches and projections moved with no sub-step of their
/// own, added up per pair (λ_n, λ_t1, λ_t2).
#[allow(clippy::too_many_arguments)]
fn walk_contact_events<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    mut sub: TrialIncrement,
    mut sel: Selection,
    base: &TrialBase,
    cycles: &mut AntiCycling,
    rec: &mut Recorder,
    jumped: &mut [[f64; 3]],
) -> Result<(Selection, f64)> {
    let bound_phi = sel.bound_phi;
    for _ in 0..MAX_SUBSTEPS {
        let projected = advance_contact(&eng.problem, state, &sub, &sel, jumped);
        let before = contact_forces(state);
        let jump =
            switch_statuses(eng, state, &sel, cycles, rec, Solve::SubStep(base)).max(projected);
        add_moved(state, &before, jumped);
        if jump > eng.problem.scales.force_noise {
            return Ok((sel, jump));
        }
        rec.substep(state, sel.scale);
        if rec.at_event_bound()
            || matches!(hold(&eng.problem, &eng.loads, state, &rec.events), Hold::Lost(_))
        {
            break; // the loop's event bound (or `support_lost`) stops the run at its next increment
        }
        let (next, jump) = substep_trial(eng, state, base, jumped)?;
        if jump > eng.problem.scales.force_noise {
            return Ok((sel, jump)); // a slip begun at zero force that carried λ_n already
        }
        sub = next;
        let remaining = 1.0 - state.load_fraction;
        let bound = if bound_phi >= 1.0 {
            f64::INFINITY
        } else if remaining > 0.0 {
            ((bound_phi - state.load_fraction) / remaining).max(0.0)
        } else {
            0.0
        };
        sel = select_contact(&eng.problem, state, &sub, cycles, bound);
        if sel.group.is_empty()
            || sel.last
            || !sel.group.iter().all(|c| inside_substeps(&eng.problem, c, state))
        {
            let projected = advance_contact(&eng.problem, state, &sub, &sel, jumped);
            return Ok((sel, projected));
        }
    }
    Ok((Selection { group: vec![], ..sel }, 0.0))
}

/// The next sub-step's trial; 3D: a slip begun at zero force that it presses takes its
/// direction from it, and it is solved again (`slip_direction::direct_new_slips`). Returns the trial
/// and the force that moved (added to `jumped`).
fn substep_trial<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    base: &TrialBase,
    jumped: &mut [[f64; 3]],
) -> Result<(TrialIncrement, f64)> {
    let sub = trial::solve(eng, state, Solve::SubStep(base), None)?;
    let before = contact_forces(state);
    let (directed, jump) = direct_new_slips(eng, state, &sub);
    add_moved(state, &before, jumped);
    match directed && jump <= eng.problem.scales.force_noise {
        true => Ok((trial::solve(eng, state, Solve::SubStep(base), None)?, jump)),
        false => Ok((sub, jump)),
    }
}

/// The whole increment must reproduce the sub-steps' path at the contact slots (the same
/// linear problem, solved once in full) to `PATH_CHECK` of the increment's largest
/// displacement; anything larger is an error in this module, not round-off. The forces the
/// switches moved below the force noise (`jumped`: a stuck pair outside its cone by round-off
/// put on it as it slips) are in the whole's end forces but moved no sub-step: the whole is
/// compared without them, K# W Δλ_jumped taken off at the contact slots with the flexibility
/// (no second solve: measured on the elastoplastic Hertz at 24.5k DOFs, every one of its 29
/// windows with sub-steps had such forces, and a whole increment without them cost a backward
/// sweep and the stress increments of every element each).
fn check_contact_path<D: Dim>(
    eng: &Engine<D>,
    start: &State<D>,
    end: &State<D>,
    whole: &TrialIncrement,
    jumped: &[[f64; 3]],
) -> Result<()> {
    let problem = &eng.problem;
    let scale = scale_between(start, end);
    if scale <= 0.0 {
        return Ok(()); // sub-steps of zero length: no path, and the whole is zero (`whole_increment`)
    }
    let moved = match jumped.iter().any(|j| *j != [0.0; 3]) {
        true => {
            eng.stiffness.flexibility.as_ref()
                * faer::ColRef::from_slice(&slot_forces(
                    problem,
                    jumped,
                    eng.stiffness.flexibility.nrows(),
                ))
        }
        false => faer::Col::zeros(eng.stiffness.flexibility.nrows()),
    };
    let mut worst = 0.0f64;
    for (d, &slot) in
        problem.dofs.contact_slot.iter().enumerate().filter(|(_, &slot)| slot != usize::MAX)
    {
        worst = worst.max((scale * whole.du[d] - moved[slot] - (end.u[d] - start.u[d])).abs());
    }
    let largest = scale * whole.du.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    // (an increment that moves nothing, 1e-15 of displacements of order one, is measured
    // against the round-off of the state's own displacements)
    let state_round_off =
        super::checks::GAP_ROUND_OFF * end.u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    if worst > PATH_CHECK * largest + state_round_off {
        crate::bail!(Internal, "contact sub-steps: the increment's displacement differs from its sub-steps' by {:.1e} (of {largest:.1e}) at load fraction {:.6}", worst, end.load_fraction);
    }
    Ok(())
}

/// Σ_p W_p (Δλ_n, Δλ_t1, Δλ_t2)_p at the contact slots (`n_slots` long).
fn slot_forces<D: Dim>(problem: &Problem<D>, dlambda: &[[f64; 3]], n_slots: usize) -> Vec<f64> {
    let contact_slot = &problem.dofs.contact_slot;
    let mut force_slots = vec![0.0; n_slots];
    for (pair, dl) in problem.pairs.iter().zip(dlambda) {
        for (w, v) in pair.columns().zip(*dl) {
            for &(d, c) in &w.entries {
                if contact_slot[d] != usize::MAX {
                    force_slots[contact_slot[d]] += v * c;
                }
            }
        }
    }
    force_slots
}

/// The contact state along a sub-step: u (exact at the contact DOFs, where a sub-step's
/// increment lives), λ, α and the obstacle shifts; the rest follows at the increment's end.
/// Returns the force jump of putting slipping pairs back on their cones (`project_onto_cone`):
/// the sub-steps' scaled load does not hold it, so a jump ends them; it is added to `jumped`.
fn advance_contact<D: Dim>(
    problem: &Problem<D>,
    state: &mut State<D>,
    inc: &TrialIncrement,
    sel: &Selection,
    jumped: &mut [[f64; 3]],
) -> f64 {
    let s = sel.scale;
    state.u.iter_mut().zip(&inc.du).for_each(|(u, d)| *u += s * d);
    state.advance_forces(inc, s);
    state.load_fraction = sel.phi;
    let before = contact_forces(state);
    let jump = project_onto_cone(problem, state);
    add_moved(state, &before, jumped);
    jump
}

/// The contact forces moved since `before`, added to `jumped`.
fn add_moved<D: Dim>(state: &State<D>, before: &[[f64; 3]], jumped: &mut [[f64; 3]]) {
    for (p, (j, b)) in jumped.iter_mut().zip(before).enumerate() {
        let now = state.contact_force(p);
        (0..3).for_each(|k| j[k] += now[k] - b[k]);
    }
}

/// The increment from `start` to the contact state `end` over all DOFs, as a trial increment
/// for the remaining load of `start` (so that its scale takes `start` to `end`):
/// Δu = K⁻¹(f r + W Δλ) + N Δα with f = 1 − c_end / c, then the stresses with K's tangents.
fn whole_increment<D: Dim>(
    eng: &mut Engine<D>,
    start: &State<D>,
    end: &State<D>,
    base: &TrialBase,
) -> TrialIncrement {
    let scale = scale_between(start, end);
    let per = |v: f64| if scale > 0.0 { v / scale } else { 0.0 };
    let dlambda_n: Vec<f64> =
        end.lambda_n.iter().zip(&start.lambda_n).map(|(a, b)| a - b).collect();
    let dlambda_t: Vec<f64> =
        end.lambda_t.iter().zip(&start.lambda_t).map(|(a, b)| a - b).collect();
    let dlambda_t2: Vec<f64> =
        (0..dlambda_n.len()).map(|p| end.lambda_t_of(p)[1] - start.lambda_t_of(p)[1]).collect();
    let dlambda: Vec<[f64; 3]> =
        (0..dlambda_n.len()).map(|p| [dlambda_n[p], dlambda_t[p], dlambda_t2[p]]).collect();
    let force_slots = slot_forces(&eng.problem, &dlambda, eng.stiffness.flexibility.nrows());
    let mut du = trial::displacement_from(eng, base, scale, &force_slots);
    let dalpha: Vec<f64> = end.alpha.iter().zip(&start.alpha).map(|(a, b)| a - b).collect();
    for (mode, a) in eng.problem.bodies.mode_vectors.iter().zip(&dalpha) {
        du.iter_mut().zip(mode).for_each(|(x, v)| *x += a * v);
    }
    du.iter_mut().for_each(|x| *x = per(*x));
    let (dstress, dplastic) = eng.stiffness.tangents.stress_increment(&eng.problem, &du);
    TrialIncrement {
        du,
        dstress,
        dplastic,
        dlambda_n: dlambda_n.into_iter().map(per).collect(),
        dlambda_t: dlambda_t.into_iter().map(per).collect(),
        dlambda_t2: if end.space().is_some() {
            dlambda_t2.into_iter().map(per).collect()
        } else {
            vec![]
        },
        dalpha: dalpha.into_iter().map(per).collect(),
        dshift: end
            .shift
            .iter()
            .zip(&start.shift)
            .map(|(a, b)| [per(a[0] - b[0]), per(a[1] - b[1]), per(a[2] - b[2])])
            .collect(),
        noise: base.noise,
    }
}

/// The scale of `start`'s trial for the remaining load that takes it to `end` (0 at a stage's end).
fn scale_between<D: Dim>(start: &State<D>, end: &State<D>) -> f64 {
    let c = 1.0 - start.load_fraction;
    if c > 0.0 {
        (end.load_fraction - start.load_fraction) / c
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::advance;
    use super::super::checks::LimitLoad;
    use super::super::clock::Clock;
    use super::super::scenes::*;
    use super::super::selection::select;
    use super::super::trial::remaining_load;
    use super::super::{increment, Outcome, StageLoop};
    use super::*;

    /// Round-off of a few operations on O(1) numbers (~1e-15 each).
    const ROUND_OFF: f64 = 1e-12;

    /// A window taken back returns to its start exactly (every array of the state, the
    /// record), and the loop goes event by event up to where it ended, grouped again from there.
    #[test]
    fn a_retaken_window_returns_to_its_start() {
        let (b, sy, delta) = (300.0, 250.0, 0.1);
        let m = square_on_rollers(0.0, -b, plastic(sy, 500.0));
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let mut rec = Recorder::new(&mut eng, &state).unwrap();
        let grouped = Stepping::Grouped { delta };
        let cycles = AntiCycling::new(0, 2, 4);
        let (trial, _) = remaining_load(&mut eng, &state, None, grouped).unwrap();
        let sel = select(&eng.problem, &state, &trial, &cycles, f64::INFINITY, grouped);
        let before = state.clone();
        let window =
            Window::open(&sel, &state, &rec, Correction::default()).expect("a plastic window");
        let start =
            advance::to_event(&eng, &mut state, &trial, &sel).expect("its yields are integrated");
        assert!(state.plastic.iter().all(|&p| p) && state.plastic_strain.iter().all(|&e| e > 0.0));
        rec.substep(&state, sel.scale);
        let mut correction = Correction { displacement: 1.0, force: 1.0 };
        let retaking = window.retake(&mut state, start, &mut rec, &mut correction, grouped);
        assert_eq!(retaking, Stepping::Retaking { until: sel.phi, delta });
        assert_eq!(
            (retaking.at(sel.phi * (1.0 - 1e-9)).window(), retaking.at(sel.phi)),
            (None, grouped)
        );
        assert_eq!(
            (&state.u, &state.stress, &state.plastic_strain, &state.plastic),
            (&before.u, &before.stress, &before.plastic_strain, &before.plastic)
        );
        assert_eq!(
            (state.load_fraction, &state.lambda_n, &state.status),
            (before.load_fraction, &before.lambda_n, &before.status)
        );
        assert_eq!((rec.steps.len(), rec.n_substeps, rec.n_retaken), (0, 0, 1));
        assert_eq!((correction.displacement, correction.force), (0.0, 0.0));
    }

    /// Two elements of the pressed square yielding at different loads (Sy 200 and 240 under
    /// σy = −b s, b = 300, so at s = 2/3 and 0.8 while the stress is uniform): one window
    /// (δ = 0.3) holds both; the first yields exactly where the trial predicts (eq. 16), the
    /// second after it and inside the window, recorded in load order in the window's one step.
    /// Its load is where the window's straight strain path crosses its surface: within 1 % of
    /// 0.8, since after the first yield that element's tangent, E H/(E + H), is only 2 % below
    /// E (H = 50E), so little stress moves over (measured 0.798; a stronger hardening drop
    /// moves it down to the onset, where it would be clamped).
    #[test]
    fn a_window_records_its_yields_in_load_order() {
        let (b, delta) = (300.0, 0.3);
        let mut m = square_on_rollers(0.0, -b, plastic(200.0, 50.0 * E));
        m.materials.push(plastic(240.0, 50.0 * E));
        m.element_material = vec![0, 1];
        m.options.group_tol = delta;
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let mut rec = Recorder::new(&mut eng, &state).unwrap();
        let mut cycles = AntiCycling::new(0, 2, 4);
        let stepping = Stepping::new(&m.options, eng.problem.is_reduced());
        let mut stage =
            StageLoop { stepping, limit: LimitLoad::default(), correction: Correction::default() };
        let outcome =
            increment(&mut eng, &mut state, &mut rec, &mut cycles, &mut stage, &mut None).unwrap();
        assert!(matches!(outcome, Outcome::Advanced));
        let onset = 200.0 / b;
        let end = onset * (1.0 + delta);
        assert!((state.load_fraction - end).abs() < ROUND_OFF && rec.steps.len() == 1);
        let yields: Vec<(usize, f64, usize)> = rec
            .events
            .iter()
            .filter(|e| e.kind == EventKind::Yield)
            .map(|e| (e.entity, e.load_fraction, e.step))
            .collect();
        assert_eq!(yields.len(), 2, "{yields:?}");
        assert_eq!((yields[0].0, yields[1].0), (0, 1));
        assert!(
            (yields[0].1 - onset).abs() < ROUND_OFF,
            "first yield at {} vs {onset}",
            yields[0].1
        );
        assert!(
            yields[1].1 > yields[0].1 && yields[1].1 <= end && (yields[1].1 - 0.8).abs() < 0.01,
            "{yields:?}"
        );
        assert!(yields.iter().all(|y| y.2 == 0));
    }
}
