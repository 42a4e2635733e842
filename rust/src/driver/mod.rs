//! The adaptive incremental procedure (paper §4).
//!
//! From the current state one *trial* increment is solved for the whole remaining load in
//! residual form (eq. 44), each candidate event gets its scale factor (eqs. 48–56), the state
//! advances by the smallest (eqs. 57–62), the statuses of the events there switch, and the loop
//! repeats until the whole load is applied (S = 1). A load path of several stages (unloading,
//! displacement control, moving obstacles; module [`path`]) runs that loop once per stage from
//! the state the previous one left. [`run`] reads as that list; each phase is a module:
//!
//! | phase | module | paper |
//! |---|---|---|
//! | the assembled problem, K and its factor, flexibility | [`engine`], [`stiffness`], [`space`] | eqs. 36, 45–46 |
//! | state and trial increment records | [`state`] | eqs. 59–62 |
//! | the load path: patterns, stages, prescribed displacements, obstacle motion | [`path`], [`loads`] | |
//! | trial for the remaining load (small contact system) | [`trial`] | eqs. 43–44 |
//! | free bodies, gross sliding, loss of support along the path | [`restraint`] | |
//! | scale factors, S_min, ties, zero-length order, grouping | [`selection`] | eqs. 48–57 |
//! | advance and status switches | [`advance`] | eqs. 58–62 |
//! | contact events inside a grouped plastic increment, in the contact space | [`substeps`] | eqs. 43–44 |
//! | which tangent each element gives K; refactorization or low-rank terms | [`tangents`] | eq. 11 |
//! | integrated stresses, equilibrium correction (event by event), re-integration | [`plasticity`] | eqs. 5–11, 59 |
//! | a window the re-integration cannot balance, taken back and retaken event by event | [`retake`] | §4 |
//! | equilibrium, contact conditions, limit load | [`checks`] | eqs. 22–24, 1–2 |
//! | termination of zero-length runs | [`anticycling`], [`rate_problem`] | |
//! | event history, increments, snapshots | [`recording`] | |
//!
//! Linear algebra: K# is a generalized inverse of the stiffness with the supports and one
//! pinned DOF per free rigid-body mode removed; the contact DOFs are last in its SPD factor, so
//! their flexibility is read from the factor's trailing block and a trial costs one solve.
//!
//! Simultaneous events whose scales agree within `tie_tol` switch in one increment.
//!
//! Plasticity. The stresses of plastic elements are integrated along each increment
//! (`stress_integration`) and one correction at fixed load restores equilibrium, itself taken
//! event by event so that the corrected state is admissible. K holds, per element, D or a D_ep
//! renewed when the element yields, unloads, or its flow direction turned by more than
//! `tangent_turn`; those changes are low-rank terms on the last factor (`low_rank`) until they
//! cost a refactorization. Grouped increments (δ = `group_tol`, 0.03 by default; 0 = the paper,
//! event by event) run past the first predicted yield by δ of the load: every element that
//! yields inside gets the exact split of its strain increment, and the increment is
//! re-integrated from its start until it is balanced to 1e-4 of the load (one whose rounds stall
//! beyond 1e-3, as past a limit load, is retaken event by event). Contact events inside
//! it are contact sub-steps ([`substeps`]: the small system with K held, no full-space solve),
//! but for closures next to plastic elements, which end it, and unless every event is a snapshot.

mod advance;
mod anticycling;
mod checks;
mod engine;
mod loads;
mod path;
mod plasticity;
mod rate_problem;
mod recording;
mod restraint;
mod retake;
mod selection;
mod space;
mod state;
mod stiffness;
mod substeps;
mod tangents;
mod trial;

use crate::contact::Status;
use crate::error::Result;
use crate::events;
use crate::model::{EventKind, Model, Progress, RunResult, StopReason};
use anticycling::{Admission, AntiCycling};
use checks::LimitLoad;
use engine::{since, Engine};
use plasticity::{Correction, Restored};
use recording::Recorder;
use restraint::Hold;
use retake::WindowStart;
use selection::Selection;
use state::State;
use std::time::Instant;

/// Zero-gap pairs start closed: a gap within this × the length scale counts as zero.
pub(super) const INITIAL_CONTACT: f64 = 1e-12;

/// Run the procedure on a model, stage by stage along its load path (`path`); `progress` is
/// called after every increment and stops the run (keeping the results so far) when it returns
/// false.
pub fn run(model: &Model, mut progress: impl FnMut(Progress) -> bool) -> Result<RunResult> {
    model.validate()?;
    let started = Instant::now();
    let mut eng = Engine::new(model)?;
    eng.timings.assembly = since(started);
    eng.factored();
    let mut state = State::initial(&eng.pairs, eng.loop_dofs(), eng.loop_elements(), eng.modes.len(), INITIAL_CONTACT * eng.scales.length);
    eng.begin_stage(0, &mut state);
    let mut rec = Recorder::new(&mut eng, &state)?;
    let mut cycles = AntiCycling::new(eng.pairs.len(), eng.loop_elements(), model.options.max_zero_length_switches);
    let mut stop = StopReason::Completed;
    for k in 0..eng.path.n_stages() {
        if k > 0 {
            eng.begin_stage(k, &mut state); // the next stage's remaining load, from this state
            rec.stage = k;
            cycles.load_advanced();
        }
        stop = run_stage(&mut eng, &mut state, &mut rec, &mut cycles, &mut progress)?;
        if stop != StopReason::Completed {
            break;
        }
    }
    rec.finish(eng, &state, stop, cycles.rate_problems)
}

/// The procedure of §4 over one stage, s from 0 to 1: returns `Completed` at S = 1, or why it
/// stopped before.
fn run_stage(eng: &mut Engine, state: &mut State, rec: &mut Recorder, cycles: &mut AntiCycling, progress: &mut impl FnMut(Progress) -> bool) -> Result<StopReason> {
    let mut limit = LimitLoad::default();
    let mut correction = Correction::default();
    if let Some(stop) = support_lost(eng, state, rec, 0) {
        return Ok(stop); // the last stage's end let a body go
    }
    loop {
        if let Some(stop) = rec.event_bound(eng, state, cycles) {
            return Ok(stop);
        }
        if eng.retake_until.is_some_and(|t| state.time() >= t) {
            eng.retake_until = None; // the retaken window is behind: grouped again
        }
        eng.update_tangents(state)?; // D or D_ep at the increment's start (eq. 11)
        let trial = timed_trial(eng, state, rec.internal.take())?; // the remaining load (eq. 44)
        let t_events = Instant::now();
        let cut = rec.snapshot_cut(eng, state);
        let sel = eng.select(state, &trial, cycles, cut); // S = min(S_c, S_p, S_f, S_r, S_A) (eqs. 48–57)
        if let Some(stop) = limit.check(eng, state, &trial, &sel) {
            return Ok(stop);
        }
        rec.snapshots_inside(eng, state, &trial, &sel)?;
        let (phi0, first_event, first_step) = (state.load_fraction, rec.events.len(), rec.steps.len());
        let window = sel.plastic_inside.then(|| WindowStart::new(state, rec, correction));
        let (trial, sel, sub_jump) = match eng.takes_substeps(&sel, rec.every_event(), state) {
            true => eng.contact_substeps(state, trial, sel, cycles, rec)?, // contact events in the contact space
            false => (trial, sel, 0.0),
        };
        let integrated = eng.advance(state, &trial, &sel); // eqs. 58–62
        let jump = switch_statuses(eng, state, &sel, cycles, rec).max(sub_jump); // step 6
        let lost = support_lost(eng, state, rec, first_event);
        if lost.is_some() && (integrated || jump > eng.noise.force) {
            restore_hold(eng, state, rec, first_event); // the correction needs what held it
        }
        let Some(residual) = settle(eng, state, &sel, cycles, rec, &mut correction, integrated, jump)? else {
            window.expect("only a grouped window is unbalanced").retake(eng, state, rec, &mut correction);
            eng.timings.events += since(t_events);
            continue;
        };
        let inside = eng.inside_events(state, &sel);
        rec.events_inside(&inside, (phi0, sel.phi), sel.first_yield, first_event, first_step);
        rec.step(eng, state, sel.scale, residual)?;
        eng.timings.events += since(t_events);
        if sel.last {
            return Ok(StopReason::Completed); // S = 1 (step 8)
        }
        if let Some(stop) = lost.or_else(|| support_lost(eng, state, rec, first_event)) {
            return Ok(stop); // (or a separation of the correction's)
        }
        if eng.model.options.stop_at_first_yield && sel.group.iter().any(|c| c.kind == EventKind::Yield) {
            return Ok(StopReason::FirstYield);
        }
        if !progress(Progress { steps: rec.steps.len(), events: rec.events.len(), load_fraction: state.time() }) {
            return Ok(StopReason::Interrupted { load_fraction: state.time() });
        }
    }
}

/// A body that lost its hold along the path, where pairs separated or began to slip since the
/// event `first_event` (it lifts off, tips or slides as a whole: `restraint`), stops the run
/// there with its results; one unheld before any load is applied (t = 0) is the trial's error
/// (a missing support, a load beyond friction from the start).
fn support_lost(eng: &Engine, state: &State, rec: &Recorder, first_event: usize) -> Option<StopReason> {
    if state.time() == 0.0 {
        return None;
    }
    let loosened = rec.events[first_event..].iter().any(|e| matches!(e.kind, EventKind::Separate | EventKind::StickToSlip));
    match loosened.then(|| eng.hold(state, &rec.events)) {
        Some(Hold::Lost(stop)) => Some(stop),
        _ => None,
    }
}

/// Close again the pairs that separated since `first_event` (at zero force) and stick those
/// that began to slip (on the cone): where a body loses its hold the state is balanced (an
/// equilibrium correction) with the contacts that held it there, since beyond none do.
fn restore_hold(eng: &Engine, state: &mut State, rec: &Recorder, first_event: usize) {
    for e in &rec.events[first_event..] {
        let back = match (e.kind, state.status[e.entity]) {
            (EventKind::Separate, Status::Open) => EventKind::Close,
            (EventKind::StickToSlip, Status::Slip { .. }) => EventKind::SlipToStick,
            _ => continue,
        };
        eng.switch(state, &events::Candidate { scale: 0.0, entity: e.entity, kind: back, direction: 0 });
    }
}

/// The trial for the remaining load (eq. 44), its small dense system timed as event work.
fn timed_trial(eng: &mut Engine, state: &State, internal: Option<Vec<f64>>) -> Result<state::TrialIncrement> {
    let (t0, dense0) = (Instant::now(), eng.timings.dense);
    let trial = eng.trial(state, 1.0, internal)?;
    eng.timings.solves += since(t0) - (eng.timings.dense - dense0);
    eng.timings.events += eng.timings.dense - dense0;
    Ok(trial)
}

/// After the advance and the status switches (step 6): the equilibrium correction of
/// integrated stresses, with the tangents brought up to date and the new statuses, or of a
/// switch's force jump alone (a pair the last correction had moved off the Coulomb cone that
/// now slips is put back on it), taken event by event (`correct_at_fixed_load`); then the
/// checks at the event (equilibrium, contact conditions). Returns the residual, or None for a
/// grouped window its re-integration could not balance (the caller retakes it: `retake`).
#[allow(clippy::too_many_arguments)]
fn settle(eng: &mut Engine, state: &mut State, sel: &Selection, cycles: &AntiCycling, rec: &mut Recorder, correction: &mut Correction, integrated: bool, jump: f64) -> Result<Option<f64>> {
    let corrected = match eng.restore_equilibrium(state, sel, integrated)? {
        Restored::Unbalanced => return Ok(None),
        Restored::Corrected(c) => Some(c),
        Restored::Linear if jump > eng.noise.force => Some(eng.correct_at_fixed_load(state, sel.phi, None)?),
        Restored::Linear => None,
    };
    if let Some(c) = corrected {
        *correction = c.size;
        c.events.iter().for_each(|e| rec.correction_event(e, sel.phi));
    }
    let drift = eng.drift(state);
    rec.max_drift = rec.max_drift.max(drift);
    rec.drift = drift;
    let residual = checked_equilibrium(eng, state, sel.phi, rec)?;
    eng.check_contact(state, &cycles.frozen_pairs_of_increment(), *correction)?;
    Ok(Some(residual))
}

/// The state's equilibrium residual, recorded (with the internal force the next trial reuses)
/// and checked against `equilibrium_tol`.
fn checked_equilibrium(eng: &Engine, state: &State, phi: f64, rec: &mut Recorder) -> Result<f64> {
    let (residual, internal) = eng.equilibrium_residual(state);
    rec.internal = internal;
    rec.max_residual = rec.max_residual.max(residual);
    eng.check_equilibrium(residual, phi, rec.steps.len())?;
    Ok(residual)
}

/// Switch the statuses of the selected events (step 6) under the anti-cycling rule: when the
/// one-at-a-time rule cycles, the rate problem sets the critical pairs' statuses together. It
/// does too when the switches leave a body on friction alone, every closed pair slipping
/// (`restraint`: where its slip changes sense, a pair sticks). Returns the largest force jump
/// a switch made (see `rebalance`).
fn switch_statuses(eng: &mut Engine, state: &mut State, sel: &Selection, cycles: &mut AntiCycling, rec: &mut Recorder) -> f64 {
    let mut jump: f64 = 0.0;
    let zero_length = sel.zero_length();
    cycles.increment_selected();
    if !zero_length {
        cycles.load_advanced();
    }
    if zero_length && cycles.wants_rate_problem(&sel.group) {
        if let Some(jump) = switch_by_rate_problem(eng, state, cycles, rec, sel.phi) {
            return jump;
        }
    }
    let mut seen = vec![false; cycles.n_entities()];
    for c in &sel.group {
        match cycles.admit(c, zero_length, &mut seen) {
            Admission::Skip => {}
            Admission::Freeze => rec.event(c, if c.kind.is_element_event() { EventKind::FrozenElement } else { EventKind::Frozen }, sel.phi),
            Admission::Apply => {
                jump = jump.max(eng.switch(state, c));
                rec.event(c, c.kind, sel.phi);
            }
        }
    }
    let slip_or_separation = sel.group.iter().any(|c| matches!(c.kind, EventKind::StickToSlip | EventKind::Separate));
    if slip_or_separation && cycles.may_solve_rate_problem() && matches!(eng.hold(state, &rec.events), Hold::OnFriction) {
        jump = jump.max(switch_by_rate_problem(eng, state, cycles, rec, sel.phi).unwrap_or(0.0));
    }
    jump
}

/// The statuses of the rate problem's solution, switched and recorded at φ; None when it has
/// none or changes nothing.
fn switch_by_rate_problem(eng: &mut Engine, state: &mut State, cycles: &mut AntiCycling, rec: &mut Recorder, phi: f64) -> Option<f64> {
    let status = eng.solve_rate_problem(state)?;
    let changes: Vec<_> = (0..status.len()).flat_map(|p| advance::transitions(p, state.status[p], status[p])).collect();
    if changes.is_empty() {
        return None;
    }
    cycles.rate_problem_solved();
    let mut jump: f64 = 0.0;
    for c in &changes {
        cycles.count(c, true);
        jump = jump.max(eng.switch(state, c));
        rec.event(c, c.kind, phi);
    }
    Some(jump)
}
