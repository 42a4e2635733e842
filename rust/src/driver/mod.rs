//! The adaptive incremental procedure (paper §4).
//!
//! From the current state one *trial* increment is solved for the whole remaining load in
//! residual form (eq. 44), each candidate event gets its scale factor (eqs. 48–56), the state
//! advances by the smallest (eqs. 57–62), the statuses of the events there switch, and the loop
//! repeats until the whole load is applied (S = 1). A load path of several stages (unloading,
//! displacement control, moving obstacles; module [`path`]) runs that loop once per stage from
//! the state the previous one left. [`run`] reads as that list, and one increment as the
//! paper's steps: trial → select → window → advance → switch → settle → record. The engine is
//! in three parts: the problem, fixed for the run; the stiffness; the evolving state. Each
//! phase is a module, and none imports one below it in this table:
//!
//! | part or phase | module | paper |
//! |---|---|---|
//! | where the time goes (scoped timers) | [`clock`] | |
//! | the evolving state, a trial increment, an increment's start | [`state`] | eqs. 59–62 |
//! | how increments are taken: event by event, grouped, retaking | [`stepping`] | §4 |
//! | the load path: patterns, stages, prescribed displacements, obstacle motion | [`path`] | |
//! | the DOF space the loop carries (full, or the reduced elastic one) | [`space`] | |
//! | the problem: elements, sections, pairs, bodies and rigid modes, DOF maps | [`problem`] | eqs. 10, 45–46 |
//! | the tangent each element gives K, and when it is renewed | [`tangents`] | eq. 11 |
//! | K, its factor, low-rank terms, flexibility, solves | [`stiffness`] | eq. 36 |
//! | the current stage's loads, out-of-balance force | [`loads`] | eq. 42 |
//! | the engine: problem, stiffness, stage loads | [`engine`] | |
//! | free bodies, gross sliding, loss of support along the path | [`restraint`] | |
//! | the limit of a body sliding on friction in one plane (force and moment) | [`planar_sliding`] | |
//! | trial for the remaining load (small contact system) | [`trial`] | eqs. 43–44 |
//! | scale factors, S_min, ties, zero-length order, a window's bound | [`selection`] | eqs. 48–57 |
//! | termination of zero-length runs: the statuses at a fixed load | [`anticycling`], [`rate_problem`] | |
//! | the rate problem as a mixed LCP, solved by Lemke's method | [`mixed_lcp`] | |
//! | the friction cone in the rate problem: its sides (±t; space's faceted cone), their rows, the statuses they give back | [`cone_rows`] | eqs. 2–3, 41 |
//! | equilibrium, contact conditions, limit load | [`checks`] | eqs. 22–24, 1–2 |
//! | event history, increments, snapshots | [`recording`] | |
//! | status switches (step 6) | [`switching`] | eqs. 41, 50–55 |
//! | 3D friction: the direction a slip begun at zero force takes from a solve that presses it | [`slip_direction`] | |
//! | integrated stresses, equilibrium correction, re-integration | [`plasticity`] | eqs. 5–11, 59 |
//! | advance to the event | [`advance`] | eqs. 58–62 |
//! | a plastic window: open, contact sub-steps, close or retake | [`window`] | eqs. 16, 43–44 |
//! | 3D friction: the direction of a pair slipping at zero force | [`slip_turn`] | |
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
//! event by event) are plastic windows ([`window`]): they run past the first predicted yield by
//! δ of the load, every element that yields inside gets the exact split of its strain
//! increment, and the window is re-integrated from its start until it is balanced to 1e-4 of
//! the load (one whose rounds stall beyond 1e-3, as past a limit load, is retaken event by
//! event). Contact events inside it are contact sub-steps (the small system with K held, no
//! full-space solve), but for closures next to plastic elements, which end it, and unless
//! every event is a snapshot.

mod advance;
mod anticycling;
mod checks;
mod clock;
mod cone_rows;
mod engine;
mod loads;
mod mixed_lcp;
mod path;
mod planar_sliding;
mod plasticity;
mod problem;
mod rate_problem;
mod recording;
mod restraint;
#[cfg(test)]
mod scenes;
mod selection;
mod slip_direction;
mod slip_turn;
mod space;
mod state;
mod stepping;
mod stiffness;
mod switching;
mod tangents;
mod trial;
mod window;

use crate::contact::Status;
use crate::dim::Dim;
use crate::element::Discretization;
use crate::error::{Error, ErrorKind, Result};
use crate::events::Candidate;
use crate::model::{EventKind, Model, Options, Progress, RunResult, StopReason};
use anticycling::AntiCycling;
use checks::{check_contact, check_equilibrium, equilibrium_residual, Correction, LimitLoad};
use clock::{Clock, Phase};
use engine::Engine;
use plasticity::{correct_at_fixed_load, drift, restore_equilibrium, Restored};
use recording::Recorder;
use restraint::{hold, Hold};
use selection::Selection;
use state::{IncrementStart, State, TrialIncrement};
use stepping::Stepping;
use switching::{switch_keeping, switch_statuses};
use tangents::Renewal;
use trial::Solve;
use window::Window;

/// Run the procedure on a model, stage by stage along its load path (`path`); `progress` is
/// called after every increment and stops the run (keeping the results so far) when it returns
/// false, as a request through `interrupt` does in any phase. A model or scene the engine
/// refuses before any load is applied (a free body, a load beyond friction at t = 0) is an
/// error; a later failure (and a panic: an engine bug) ends the run as a
/// `StopReason::Failed` with the results of the increments completed.
pub fn run<D: Discretization>(
    model: &Model<D>,
    mut progress: impl FnMut(Progress) -> bool,
) -> Result<RunResult> {
    model.validate()?;
    let clock = Clock::new();
    let mut eng = Engine::new(model, &clock)?;
    let mut state = eng.initial_state();
    let mut rec = Recorder::new(&mut eng, &state)?;
    let mut cycles = AntiCycling::new(
        eng.problem.pairs.len(),
        eng.problem.loop_elements(),
        model.options.max_zero_length_switches,
    );
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        run_path(&mut eng, &mut state, &mut rec, &mut cycles, &mut progress)
    }));
    let t = state.time();
    if let Ok(Err(e)) = &outcome {
        if t == 0.0 && e.kind != ErrorKind::Interrupted && !crate::interrupt::requested() {
            return Err(e.clone()); // refused before any load was applied: nothing to keep
        }
    }
    let (stop, settled) = match outcome {
        Ok(Ok(stop)) => (stop, true),
        // (a failure after a stop was requested is the request's doing: a rate problem cut
        // short freezes pairs)
        Ok(Err(e)) if e.kind == ErrorKind::Interrupted || crate::interrupt::requested() => {
            (StopReason::Interrupted { load_fraction: t }, false)
        }
        Ok(Err(error)) => (StopReason::Failed { load_fraction: t, error }, false),
        Err(panic) => {
            (StopReason::Failed { load_fraction: t, error: engine_bug(panic.as_ref(), t) }, false)
        }
    };
    rec.finish(eng, &state, stop, settled, cycles.rate_problems)
}

/// The stages of the load path in turn (`path`), each from the state the last one left.
fn run_path<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    rec: &mut Recorder,
    cycles: &mut AntiCycling,
    progress: &mut impl FnMut(Progress) -> bool,
) -> Result<StopReason> {
    // The internal force of the state's stresses, from its equilibrium check, for the next trial.
    let mut internal = None;
    for k in 0..eng.problem.path.n_stages() {
        if k > 0 {
            eng.begin_stage(k, state); // the next stage's remaining load, from this state
            rec.stage = k;
            cycles.load_advanced();
        }
        let stop = run_stage(eng, state, rec, cycles, &mut internal, progress)?;
        if stop != StopReason::Completed {
            return Ok(stop);
        }
    }
    Ok(StopReason::Completed)
}

/// A panic inside the loop as the failure it is: a broken invariant of the engine.
fn engine_bug(payload: &(dyn std::any::Any + Send), t: f64) -> Error {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".into());
    Error::new(
        ErrorKind::Internal,
        format!(
            "an engine bug stopped the run at t = {t:.6} ({what}); please report it with the case"
        ),
    )
}

/// What the loop carries from one increment of a stage to the next.
struct StageLoop {
    stepping: Stepping,
    limit: LimitLoad,
    /// The size of the last equilibrium correction (the contact checks allow for it).
    correction: Correction,
}

impl StageLoop {
    /// The tangents an update renews in this increment (`tangents`): fresh yields may wait
    /// inside a plastic window.
    fn renewal(&self, options: &Options) -> Renewal {
        Renewal::of_increment(options, self.stepping.window().is_some())
    }
}

/// How an increment ended.
enum Outcome {
    Advanced,
    /// Its window was taken back, to be retaken event by event.
    Retaken,
    Stop(StopReason),
}

/// The procedure of §4 over one stage, s from 0 to 1: returns `Completed` at S = 1, or why it
/// stopped before.
fn run_stage<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    rec: &mut Recorder,
    cycles: &mut AntiCycling,
    internal: &mut Option<Vec<f64>>,
    progress: &mut impl FnMut(Progress) -> bool,
) -> Result<StopReason> {
    let mut stage = StageLoop {
        stepping: Stepping::new(&eng.problem.model.options, eng.problem.is_reduced()),
        limit: LimitLoad::default(),
        correction: Correction::default(),
    };
    if let Some(stop) = support_lost(eng, state, rec, 0) {
        return Ok(stop); // the last stage's end let a body go
    }
    loop {
        if let Some(stop) = rec.event_bound(eng, state, cycles) {
            return Ok(stop);
        }
        match increment(eng, state, rec, cycles, &mut stage, internal)? {
            Outcome::Stop(stop) => return Ok(stop),
            Outcome::Retaken => continue,
            Outcome::Advanced => {}
        }
        if !progress(Progress { steps: rec.steps.len(), events: rec.events.len(), t: state.time() })
        {
            return Ok(StopReason::Interrupted { load_fraction: state.time() });
        }
    }
}

/// One increment of §4: trial → select → window → advance → switch → settle → record.
fn increment<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    rec: &mut Recorder,
    cycles: &mut AntiCycling,
    stage: &mut StageLoop,
    internal: &mut Option<Vec<f64>>,
) -> Result<Outcome> {
    stage.stepping = stage.stepping.at(state.time()); // a retaken window behind: grouped again
    let renewal = stage.renewal(&eng.problem.model.options);
    eng.stiffness.update(&eng.problem, state, renewal, eng.clock)?; // D or D_ep at the increment's start (eq. 11)
    let (mut trial, mut base) = {
        let _t = eng.clock.time(Phase::Solves);
        trial::remaining_load(eng, state, internal.take(), stage.stepping)? // eq. 44
    };
    while slip_turn::direct_unloaded_slips(eng, state, &trial, cycles, rec, &mut stage.correction)?
    {
        crate::interrupt::checkpoint(crate::interrupt::Checkpoint::UnloadedTurn)?;
        let _t = eng.clock.time(Phase::Solves);
        (trial, base) = trial::remaining_load(eng, state, None, stage.stepping)?;
        // 3D: a slip at zero force took its direction
    }
    let _events = eng.clock.time(Phase::Events);
    let cut = rec.snapshot_cut(eng, state).min(friction_cut(eng, state, &trial)); // (3D: a body held by friction alone meets its limit)
    let sel = selection::select(&eng.problem, state, &trial, cycles, cut, stage.stepping); // S = min(S_c, S_p, S_f, S_r, S_A) (eqs. 48–57)
    if let Some(stop) = stage.limit.check(eng, state, &trial, &sel) {
        return Ok(Outcome::Stop(stop));
    }
    rec.snapshots_inside(eng, state, &trial, &sel)?;
    let (phi0, first_event, first_step) = (state.load_fraction, rec.events.len(), rec.steps.len());
    let window = Window::open(&sel, state, rec, stage.correction);
    let (trial, sel, sub_jump) = window::contact_events(eng, state, trial, sel, base, cycles, rec)?;
    let start = advance::to_event(eng, state, &trial, &sel); // eqs. 58–62
    let jump = switch_statuses(eng, state, &sel, cycles, rec, Solve::RemainingLoad)
        .max(sub_jump)
        .max(unbalanced_jump(state)); // step 6
    let lost = support_lost(eng, state, rec, first_event);
    if lost.is_some() && (start.is_some() || jump > eng.problem.scales.force_noise) {
        restore_hold(eng, state, rec, first_event); // the correction needs what held it
    }
    let (residual, start) = match settle(eng, state, &sel, cycles, rec, stage, start, window, jump)?
    {
        Settled::Balanced { residual, internal: balanced, start } => {
            *internal = balanced;
            (residual, start)
        }
        Settled::Unbalanced(window, start) => {
            stage.stepping =
                window.retake(state, start, rec, &mut stage.correction, stage.stepping);
            return Ok(Outcome::Retaken);
        }
    };
    let inside = window::inside_events(state, &sel, start);
    rec.events_inside(&inside, (phi0, sel.phi), sel.first_yield, first_event, first_step);
    rec.step(eng, state, sel.scale, residual, internal.as_deref())?;
    drop(_events);
    if sel.last {
        return Ok(Outcome::Stop(StopReason::Completed)); // S = 1 (step 8)
    }
    if let Some(stop) = lost
        .or_else(|| support_lost(eng, state, rec, first_event))
        .or_else(|| restraint::friction_stop(&eng.problem, &eng.loads, state))
    {
        return Ok(Outcome::Stop(stop)); // (or a separation of the correction's)
    }
    if eng.problem.model.options.stop_at_first_yield
        && sel.group.iter().any(|c| c.kind == EventKind::Yield)
    {
        return Ok(Outcome::Stop(StopReason::FirstYield));
    }
    Ok(Outcome::Advanced)
}

/// The largest force jump the state keeps unbalanced (`State::jumps`; 0 outside the reduced 3D
/// space): the advance's and the switches' alike, the correction at fixed load releases them.
fn unbalanced_jump<D: Dim>(state: &State<D>) -> f64 {
    let jumps = state.space().map_or(&[][..], |s| &s.jumps);
    jumps.iter().map(|j| j[0].abs().max(j[1].hypot(j[2]))).fold(0.0, f64::max)
}

/// The trial's scale at which the load of a body held by friction alone meets the limit of its
/// pairs (∞ if none).
fn friction_cut<D: Dim>(eng: &Engine<D>, state: &State<D>, trial: &TrialIncrement) -> f64 {
    let remaining = 1.0 - state.load_fraction;
    match restraint::friction_limit(&eng.problem, &eng.loads, state, trial) {
        Some(s) if remaining > 0.0 => (s - state.load_fraction) / remaining,
        _ => f64::INFINITY,
    }
}

/// A body that lost its hold along the path, where pairs separated or began to slip since the
/// event `first_event` (it lifts off, tips or slides as a whole: `restraint`), stops the run
/// there with its results; one unheld before any load is applied (t = 0) is the trial's error
/// (a missing support, a load beyond friction from the start).
fn support_lost<D: Dim>(
    eng: &Engine<D>,
    state: &State<D>,
    rec: &Recorder,
    first_event: usize,
) -> Option<StopReason> {
    if state.time() == 0.0 {
        return None;
    }
    let loosened = rec.events[first_event..]
        .iter()
        .any(|e| matches!(e.kind, EventKind::Separate | EventKind::StickToSlip));
    match loosened.then(|| hold(&eng.problem, &eng.loads, state, &rec.events)) {
        Some(Hold::Lost(stop)) => Some(stop),
        _ => None,
    }
}

/// Close again the pairs that separated since `first_event` (at zero force) and stick those
/// that began to slip (on the cone): where a body loses its hold the state is balanced (an
/// equilibrium correction) with the contacts that held it there, since beyond none do.
fn restore_hold<D: Dim>(eng: &Engine<D>, state: &mut State<D>, rec: &Recorder, first_event: usize) {
    for e in &rec.events[first_event..] {
        let back = match (e.kind, state.status[e.entity]) {
            (EventKind::Separate, Status::Open) => EventKind::Close,
            (EventKind::StickToSlip, Status::Slip { .. }) => EventKind::SlipToStick,
            _ => continue,
        };
        switch_keeping(
            eng,
            state,
            &Candidate { scale: 0.0, entity: e.entity, kind: back, direction: 0, toward: [0.0; 2] },
        );
    }
}

/// What settling an increment left.
enum Settled {
    /// The state's equilibrium residual, the internal force of its stresses (full space), and
    /// the increment's start when its stresses were integrated.
    Balanced { residual: f64, internal: Option<Vec<f64>>, start: Option<IncrementStart> },
    /// A plastic window its re-integration could not balance, and its start: to be retaken.
    Unbalanced(Window, IncrementStart),
}

/// After the advance and the status switches (step 6): the equilibrium correction of
/// integrated stresses (`start`: the increment's), with the tangents brought up to date and the
/// new statuses, or of a switch's force jump alone (a pair the last correction had moved off
/// the Coulomb cone that now slips is put back on it), taken event by event
/// (`correct_at_fixed_load`); then the checks at the event (equilibrium, contact conditions).
#[allow(clippy::too_many_arguments)]
fn settle<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    sel: &Selection,
    cycles: &AntiCycling,
    rec: &mut Recorder,
    stage: &mut StageLoop,
    start: Option<IncrementStart>,
    window: Option<Window>,
    jump: f64,
) -> Result<Settled> {
    let renewal = stage.renewal(&eng.problem.model.options);
    let (corrected, start) = match restore_equilibrium(eng, state, sel, start, window, renewal)? {
        Restored::Unbalanced(window, start) => return Ok(Settled::Unbalanced(window, start)),
        Restored::Corrected(c, start) => (Some(c), Some(start)),
        Restored::Linear if jump > eng.problem.scales.force_noise => {
            (Some(correct_at_fixed_load(eng, state, sel.phi, None)?), None)
        }
        Restored::Linear => (None, None),
    };
    if let Some(c) = corrected {
        stage.correction = c.size;
        c.events.iter().for_each(|e| rec.correction_event(e, sel.phi));
    }
    let drift = drift(&eng.problem, state);
    rec.balance.max_drift = rec.balance.max_drift.max(drift);
    rec.balance.drift = drift;
    let (residual, internal) = equilibrium_residual(eng, state);
    rec.balance.max_residual = rec.balance.max_residual.max(residual);
    check_equilibrium(eng, residual, sel.phi, rec.steps.len())?;
    check_contact(eng, state, &cycles.frozen_pairs_of_increment(), stage.correction)?;
    Ok(Settled::Balanced { residual, internal, start })
}
