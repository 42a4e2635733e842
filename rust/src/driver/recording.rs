//! What the run keeps: the event history, one record per increment, field snapshots (after
//! every event, or at requested path times on the piecewise-linear path), and per pair the
//! path time at which it closed. Path time t = stage + the fraction s of it (`path`).

use super::anticycling::AntiCycling;
use super::checks::full_residual;
use super::engine::Engine;
use super::selection::Selection;
use super::space::Space;
use super::state::{State, TrialIncrement};
use crate::bail;
use crate::error::Result;
use crate::events::Candidate;
use crate::model::{EventKind, EventRecord, RunResult, Snapshot, SnapshotRequest, StepRecord, StopReason};

/// A requested snapshot time this close past the increment's end still falls inside it.
const FRACTION_SLACK: f64 = 1e-15;
/// The final state is added unless the last snapshot is this close to it (in path time).
const SAME_FRACTION: f64 = 1e-14;
/// How many of the most switching entities the event-bound message names.
const BUSIEST_NAMED: usize = 5;

/// A yield or unload inside an increment (a plastic window): the element and the fraction of
/// the increment.
pub(super) struct InsideEvent {
    pub element: usize,
    pub kind: EventKind,
    pub at: f64,
}

/// How well the recorded states hold.
#[derive(Clone, Copy, Default)]
pub(super) struct Balance {
    /// The largest equilibrium residual of the loop's states and of reconstructed snapshots
    /// (reduced space).
    pub max_residual: f64,
    pub max_snapshot_residual: f64,
    /// The largest yield-surface drift, and the current increment's (before its return).
    pub max_drift: f64,
    pub drift: f64,
}

pub(super) struct Recorder {
    pub events: Vec<EventRecord>,
    pub steps: Vec<StepRecord>,
    pub snapshots: Vec<Snapshot>,
    /// Requested snapshot times not reached yet (ascending).
    pending: Vec<f64>,
    /// The current stage (0-based).
    pub stage: usize,
    every_event: bool,
    pub closure_fraction: Vec<f64>,
    pub predicted_closure: Vec<f64>,
    pub balance: Balance,
    max_steps: usize,
    /// Steps that were contact sub-steps (`substeps`).
    pub n_substeps: usize,
    /// Windows taken back and retaken event by event (`retake`).
    pub n_retaken: usize,
}

impl Recorder {
    pub fn new(eng: &mut Engine, state: &State) -> Result<Self> {
        let opts = &eng.problem.model.options;
        let n_pairs = eng.problem.pairs.len();
        let plastic_capable = eng.problem.sections.iter().filter(|s| s.material.is_plastic()).count();
        let mut rec = Recorder {
            events: vec![],
            steps: vec![],
            snapshots: vec![],
            pending: vec![],
            stage: 0,
            every_event: matches!(opts.snapshots, SnapshotRequest::EveryEvent),
            closure_fraction: state.status.iter().map(|s| if s.is_closed() { 0.0 } else { f64::NAN }).collect(),
            predicted_closure: vec![f64::INFINITY; n_pairs],
            balance: Balance::default(),
            n_substeps: 0,
            n_retaken: 0,
            max_steps: if opts.max_events > 0 { opts.max_events } else { 50 * (n_pairs + plastic_capable + 1) + 1000 },
        };
        match &opts.snapshots {
            SnapshotRequest::EveryEvent => {
                let first = rec.snapshot(eng, state, None)?;
                rec.snapshots.push(first);
            }
            SnapshotRequest::Times(f) => {
                rec.pending = f.clone();
                rec.pending.sort_by(|a, b| a.total_cmp(b));
            }
        }
        Ok(rec)
    }

    /// The run has taken as many increments as it may (`Options::max_events`).
    pub fn at_event_bound(&self) -> bool {
        self.steps.len() >= self.max_steps
    }

    /// The event bound's stop, naming the entities that switched most.
    pub fn event_bound(&self, eng: &Engine, state: &State, cycles: &AntiCycling) -> Option<StopReason> {
        if !self.at_event_bound() {
            return None;
        }
        let n_pairs = eng.problem.pairs.len();
        let count = &cycles.switch_count;
        let mut worst: Vec<usize> = (0..cycles.n_entities()).collect();
        worst.sort_by_key(|&k| std::cmp::Reverse(count[k]));
        let name = |k: usize| if k < n_pairs { format!("{}, {} switches", eng.problem.model.pair_name(k), count[k]) } else { format!("element {} ({} switches)", k - n_pairs, count[k]) };
        let busiest: Vec<String> = worst.iter().take(BUSIEST_NAMED).filter(|&&k| count[k] > 0).map(|&k| name(k)).collect();
        Some(StopReason::EventBound { load_fraction: state.time(), max_steps: self.max_steps, busiest: busiest.join("; ") })
    }

    /// Every event a snapshot (the default output).
    pub fn every_event(&self) -> bool {
        self.every_event
    }

    /// The scale of the trial at which the next requested snapshot falls, in the full space:
    /// increments end there, so that the snapshot lies on the integrated path (∞ for none, or
    /// in the reduced space, where the path between events is linear and interpolated).
    pub fn snapshot_cut(&self, eng: &Engine, state: &State) -> f64 {
        let (phi0, remaining) = (state.load_fraction, 1.0 - state.load_fraction);
        match self.pending.first() {
            Some(&t) if !eng.problem.is_reduced() && remaining > 0.0 && t - (state.stage as f64) <= 1.0 => ((t - state.stage as f64 - phi0) / remaining).max(0.0),
            _ => f64::INFINITY,
        }
    }

    /// Full space: the requested snapshots at the state's path time (where an increment was
    /// cut); `internal`: the internal force of its stresses if the caller has it.
    fn snapshots_at_end(&mut self, eng: &mut Engine, state: &State, internal: Option<&[f64]>) -> Result<()> {
        while let Some(&t) = self.pending.first() {
            if eng.problem.is_reduced() || t > state.time() + FRACTION_SLACK {
                break;
            }
            let snapshot = self.snapshot(eng, state, internal)?;
            self.snapshots.push(snapshot);
            self.pending.remove(0);
        }
        Ok(())
    }

    /// Snapshots requested inside this increment (the path is linear in between; reduced space).
    pub fn snapshots_inside(&mut self, eng: &mut Engine, state: &State, trial: &TrialIncrement, sel: &Selection) -> Result<()> {
        let (phi0, remaining) = (state.load_fraction, 1.0 - state.load_fraction);
        let stage = state.stage as f64;
        while let Some(&t) = self.pending.first() {
            if !eng.problem.is_reduced() {
                break;
            }
            let f = t - stage;
            if f > sel.phi + FRACTION_SLACK {
                break;
            }
            let s = if remaining > 0.0 { ((f - phi0) / remaining).clamp(0.0, sel.scale) } else { 0.0 };
            let mut st = state.clone();
            st.advance(trial, s);
            st.load_fraction = f;
            let snapshot = self.snapshot(eng, &st, None)?;
            self.snapshots.push(snapshot);
            self.pending.remove(0);
        }
        for &(p, phi) in &sel.predicted_closures {
            self.predicted_closure[p] = stage + phi;
        }
        Ok(())
    }

    /// The yields and unloads inside the current increment (φ0 → φ1), merged in load order
    /// with the increment's events from `first_event` on (its contact sub-steps' and those that
    /// ended it), before them at the same load; each in the step (from `first_step`: the
    /// sub-steps', then this increment's) whose load it falls in. A yield's load is where the
    /// integration put it along the increment, but not before the trial's first predicted yield
    /// (`first_yield`: the path is linear up to it, so its element yields exactly there and no
    /// element earlier; without the bound the straight strain path of an increment that flowed
    /// plastically puts them early: the thick cylinder's first yield by 0.7 % at δ = 0.01, 2.1 % at
    /// 0.03).
    pub fn events_inside(&mut self, inside: &[InsideEvent], (phi0, phi1): (f64, f64), first_yield: Option<(usize, f64)>, first_event: usize, first_step: usize) {
        let ends: Vec<f64> = self.steps[first_step..].iter().map(|s| s.load_fraction).collect();
        let onset = first_yield.map(|(element, phi)| (element, phi.min(phi1)));
        let records = inside.iter().map(|ev| {
            let mut phi = phi0 + ev.at * (phi1 - phi0);
            if let (EventKind::Yield, Some((element, onset))) = (ev.kind, onset) {
                phi = if ev.element == element { onset } else { phi.max(onset) };
            }
            let step = first_step + ends.iter().filter(|&&end| end < phi).count();
            EventRecord { step, stage: self.stage, load_fraction: phi, time: self.stage as f64 + phi, kind: ev.kind, entity: ev.element }
        });
        let mut merged: Vec<(bool, EventRecord)> = records.map(|r| (false, r)).chain(self.events.drain(first_event..).map(|r| (true, r))).collect();
        merged.sort_by(|a, b| a.1.load_fraction.total_cmp(&b.1.load_fraction).then(a.0.cmp(&b.0)));
        self.events.extend(merged.into_iter().map(|(_, r)| r));
    }

    /// A contact sub-step's record (`substeps`): the contact state after its events, with the
    /// residual and drift of the increment's start, which its linear path keeps.
    pub fn substep(&mut self, state: &State, scale: f64) {
        self.n_substeps += 1;
        let residual = self.steps.last().map_or(0.0, |s| s.residual);
        let (n_closed, n_stick) = (state.n_closed(), state.n_stick());
        self.steps.push(StepRecord { stage: state.stage, load_fraction: state.load_fraction, time: state.time(), scale, residual, n_closed, n_stick, n_slip: n_closed - n_stick, normal_force: state.lambda_n.iter().sum(), n_plastic: state.n_plastic(), drift: self.balance.drift });
    }

    /// An event of the equilibrium correction at φ. A pair the correction separates that closed
    /// in this increment was predicted to close too early (by the trial's tangent): its closure
    /// is withdrawn instead (it is predicted again from the corrected state).
    pub fn correction_event(&mut self, c: &Candidate, phi: f64) {
        let step = self.steps.len();
        if c.kind == EventKind::Separate {
            if let Some(i) = self.events.iter().rposition(|e| e.step == step && e.kind == EventKind::Close && e.entity == c.entity) {
                self.events.remove(i);
                self.closure_fraction[c.entity] = f64::NAN;
                return;
            }
        }
        self.event(c, c.kind, phi);
    }

    pub fn event(&mut self, c: &Candidate, kind: EventKind, phi: f64) {
        let time = self.stage as f64 + phi;
        if kind == EventKind::Close {
            self.closure_fraction[c.entity] = time;
        }
        self.events.push(EventRecord { step: self.steps.len(), stage: self.stage, load_fraction: phi, time, kind, entity: c.entity });
    }

    /// One record per increment, and its snapshot when every event is requested; `internal`:
    /// the internal force of the state's stresses (from the equilibrium check).
    pub fn step(&mut self, eng: &mut Engine, state: &State, scale: f64, residual: f64, internal: Option<&[f64]>) -> Result<()> {
        let drift = self.balance.drift;
        let (n_closed, n_stick) = (state.n_closed(), state.n_stick());
        self.steps.push(StepRecord { stage: state.stage, load_fraction: state.load_fraction, time: state.time(), scale, residual, n_closed, n_stick, n_slip: n_closed - n_stick, normal_force: state.lambda_n.iter().sum(), n_plastic: state.n_plastic(), drift });
        if self.every_event {
            let snapshot = self.snapshot(eng, state, internal)?;
            self.snapshots.push(snapshot);
        }
        self.snapshots_at_end(eng, state, internal)
    }

    /// The final snapshot (for requested fractions, and for runs that stopped early) and the
    /// result; `settled`: the state is an increment's end (not one a failure or an interrupt
    /// inside an increment left), whose fields make that snapshot.
    pub fn finish(mut self, mut eng: Engine, state: &State, stop: StopReason, settled: bool, rate_problems: usize) -> Result<RunResult> {
        let early = !matches!(stop, StopReason::Completed | StopReason::FirstYield);
        if settled && (early || !self.every_event) {
            if self.snapshots.last().map_or(true, |s| (s.time - state.time()).abs() > SAME_FRACTION) {
                let last = self.snapshot(&mut eng, state, None)?;
                self.snapshots.push(last);
            }
        }
        Ok(RunResult {
            stage_names: eng.problem.path.stage_names.clone(),
            events: self.events,
            steps: self.steps,
            snapshots: self.snapshots,
            closure_fraction: self.closure_fraction,
            predicted_closure: self.predicted_closure,
            max_equilibrium_residual: self.balance.max_residual.max(self.balance.max_snapshot_residual),
            max_drift: self.balance.max_drift,
            n_factorizations: eng.stiffness.solver.n_factorizations,
            n_factor_builds: eng.stiffness.solver.n_builds(),
            n_low_rank_updates: eng.stiffness.n_low_rank_updates,
            n_contact_substeps: self.n_substeps,
            n_retaken_windows: self.n_retaken,
            n_solves: eng.stiffness.solver.n_solves,
            n_rate_problems: rate_problems,
            stop,
            timings: eng.clock.timings(eng.stiffness.solve_pair),
        })
    }

    /// The full fields of a state and its support reactions; in the reduced space they are
    /// rebuilt (one solve) and their equilibrium is checked in full. `internal`: the internal
    /// force of the state's stresses when the caller has it (full space).
    fn snapshot(&mut self, eng: &mut Engine, state: &State, internal: Option<&[f64]>) -> Result<Snapshot> {
        let full;
        let (state, internal) = if eng.problem.is_reduced() {
            let (s, internal, residual) = reconstruct(eng, state)?;
            self.balance.max_snapshot_residual = self.balance.max_snapshot_residual.max(residual);
            full = s;
            (&full, internal)
        } else {
            (state, internal.map_or_else(|| eng.problem.internal_force(&state.stress), <[f64]>::to_vec))
        };
        let (problem, loads) = (&eng.problem, &eng.loads);
        let pairs = problem.global_pairs();
        // P_σ − P − the contact forces at the held DOFs: the supports' force
        let mut contact = vec![0.0; internal.len()];
        for (p, pair) in pairs.iter().enumerate() {
            pair.add_support_force(state.lambda_n[p], [state.lambda_t[p], state.lambda_t2[p]], &mut contact);
        }
        let reaction = (0..internal.len()).map(|d| if problem.dofs.fixed[d] { internal[d] - loads.load.force(d, state.load_fraction) - contact[d] } else { 0.0 }).collect();
        Ok(Snapshot {
            stage: state.stage,
            load_fraction: state.load_fraction,
            time: state.time(),
            dim: problem.dim,
            u: state.u.clone(),
            stress: state.stress.iter().map(|s| std::array::from_fn(|k| s[k])).collect(),
            plastic_strain: state.plastic_strain.clone(),
            plastic: if state.plastic.is_empty() { vec![0; problem.elements.len()] } else { state.plastic.iter().map(|&p| p as i8).collect() },
            lambda_n: state.lambda_n.clone(),
            lambda_t: state.lambda_t.clone(),
            status: state.status.iter().map(|s| s.code()).collect(),
            gap: pairs.iter().zip(&state.shift).map(|(p, c)| p.gap(&state.u) + c[0]).collect(),
            rtd: pairs.iter().zip(&state.shift).map(|(p, c)| p.rtd(&state.u) + c[1]).collect(),
            lambda_t2: if problem.dim == 3 { state.lambda_t2.clone() } else { vec![] },
            rtd2: if problem.dim == 3 { pairs.iter().zip(&state.shift).map(|(p, c)| p.w_t2.dot(&state.u) + c[2]).collect() } else { vec![] },
            reaction,
        })
    }

}

/// u = Σ u_stage (completed) + s u_stage + K#(W λ) + N α, ū at the prescribed DOFs, and its
/// stresses, for the reduced space; also the internal force P_σ and the fields' equilibrium
/// residual, which must be within `equilibrium_tol`.
fn reconstruct(eng: &mut Engine, state: &State) -> Result<(State, Vec<f64>, f64)> {
    let Engine { problem, stiffness, loads, .. } = eng;
    let mut y = vec![0.0; problem.dofs.map.role.len()];
    for (p, pair) in problem.global_pairs().iter().enumerate() {
        pair.w_n.add_to(state.lambda_n[p], &mut y);
        pair.w_t.add_to(state.lambda_t[p], &mut y);
        pair.w_t2.add_to(state.lambda_t2[p], &mut y);
    }
    let mut u = stiffness.apply_ginv(&problem.dofs.map, std::slice::from_ref(&y)).pop().unwrap_or_default();
    if let Space::Reduced(_) = &problem.space {
        u.iter_mut().zip(&loads.reduced.u_load).for_each(|(a, b)| *a += state.load_fraction * b);
        u.iter_mut().zip(&loads.reduced.u_done).for_each(|(a, b)| *a += b);
    }
    loads.load.prescribed_at(state.load_fraction).for_each(|(d, v)| u[d] = v);
    for (mode, a) in problem.bodies.modes.iter().zip(&state.alpha) {
        u.iter_mut().zip(&mode.vector).for_each(|(x, v)| *x += a * v);
    }
    let (stress, _) = stiffness.tangents.stress_increment(problem, &u);
    let mut full = state.clone();
    full.u = u;
    full.stress = stress;
    full.plastic_strain = vec![0.0; problem.elements.len()];
    let (residual, internal) = full_residual(eng, &full);
    let tol = eng.problem.model.options.equilibrium_tol;
    if residual > tol {
        bail!(Equilibrium, "equilibrium residual {residual:.3e} of the reconstructed fields exceeds {tol:.1e} at load fraction {:.6}: the linear system is ill-conditioned", state.load_fraction);
    }
    Ok((full, internal, residual))
}
