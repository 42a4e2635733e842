//! What the run keeps: the event history, one record per increment, field snapshots (after
//! every event, or at requested path times on the piecewise-linear path), and per pair the
//! path time at which it closed. Path time t = stage + the fraction s of it (`path`).

use super::anticycling::AntiCycling;
use super::checks::full_residual;
use super::clock::Phase;
use super::engine::Engine;
use super::selection::Selection;
use super::space::Space;
use super::state::{State, TrialIncrement};
use crate::bail;
use crate::contact::Pair;
use crate::dim::Dim;
use crate::error::Result;
use crate::events::Candidate;
use crate::model::{
    EventKind, EventRecord, RunResult, Snapshot, SnapshotRequest, StepRecord, StopReason,
};
use crate::rigid_modes::RigidMode;

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
    /// The resultants every increment records (contact forces and moments, reactions, loads'
    /// work).
    resultants: Resultants,
}

impl Recorder {
    pub fn new<D: Dim>(eng: &mut Engine<D>, state: &State<D>) -> Result<Self> {
        let opts = &eng.problem.model.options;
        let n_pairs = eng.problem.pairs.len();
        let plastic_capable =
            eng.problem.sections.iter().filter(|s| s.material.is_plastic()).count();
        let mut rec = Recorder {
            events: vec![],
            steps: vec![],
            snapshots: vec![],
            pending: vec![],
            stage: 0,
            every_event: matches!(opts.snapshots, SnapshotRequest::EveryEvent),
            closure_fraction: state
                .status
                .iter()
                .map(|s| if s.is_closed() { 0.0 } else { f64::NAN })
                .collect(),
            predicted_closure: vec![f64::INFINITY; n_pairs],
            balance: Balance::default(),
            n_substeps: 0,
            n_retaken: 0,
            max_steps: if opts.max_events > 0 {
                opts.max_events
            } else {
                50 * (n_pairs + plastic_capable + 1) + 1000
            },
            resultants: Resultants::new(eng),
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
    pub fn event_bound<D: Dim>(
        &self,
        eng: &Engine<D>,
        state: &State<D>,
        cycles: &AntiCycling,
    ) -> Option<StopReason> {
        if !self.at_event_bound() {
            return None;
        }
        let n_pairs = eng.problem.pairs.len();
        let count = &cycles.switch_count;
        let mut worst: Vec<usize> = (0..cycles.n_entities()).collect();
        worst.sort_by_key(|&k| std::cmp::Reverse(count[k]));
        let name = |k: usize| {
            if k < n_pairs {
                format!("{}, {} switches", eng.problem.model.pair_name(k), count[k])
            } else {
                format!("element {} ({} switches)", k - n_pairs, count[k])
            }
        };
        let busiest: Vec<String> =
            worst.iter().take(BUSIEST_NAMED).filter(|&&k| count[k] > 0).map(|&k| name(k)).collect();
        Some(StopReason::EventBound {
            load_fraction: state.time(),
            max_steps: self.max_steps,
            busiest: busiest.join("; "),
        })
    }

    /// Every event a snapshot (the default output).
    pub fn every_event(&self) -> bool {
        self.every_event
    }

    /// The scale of the trial at which the next requested snapshot falls, in the full space:
    /// increments end there, so that the snapshot lies on the integrated path (∞ for none, or
    /// in the reduced space, where the path between events is linear and interpolated).
    pub fn snapshot_cut<D: Dim>(&self, eng: &Engine<D>, state: &State<D>) -> f64 {
        let (phi0, remaining) = (state.load_fraction, 1.0 - state.load_fraction);
        match self.pending.first() {
            Some(&t)
                if !eng.problem.is_reduced()
                    && remaining > 0.0
                    && t - (state.stage as f64) <= 1.0 =>
            {
                ((t - state.stage as f64 - phi0) / remaining).max(0.0)
            }
            _ => f64::INFINITY,
        }
    }

    /// Full space: the requested snapshots at the state's path time (where an increment was
    /// cut); `internal`: the internal force of its stresses if the caller has it.
    fn snapshots_at_end<D: Dim>(
        &mut self,
        eng: &mut Engine<D>,
        state: &State<D>,
        internal: Option<&[f64]>,
    ) -> Result<()> {
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
    pub fn snapshots_inside<D: Dim>(
        &mut self,
        eng: &mut Engine<D>,
        state: &State<D>,
        trial: &TrialIncrement,
        sel: &Selection,
    ) -> Result<()> {
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
            let s =
                if remaining > 0.0 { ((f - phi0) / remaining).clamp(0.0, sel.scale) } else { 0.0 };
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
    pub fn events_inside(
        &mut self,
        inside: &[InsideEvent],
        (phi0, phi1): (f64, f64),
        first_yield: Option<(usize, f64)>,
        first_event: usize,
        first_step: usize,
    ) {
        let ends: Vec<f64> = self.steps[first_step..].iter().map(|s| s.load_fraction).collect();
        let onset = first_yield.map(|(element, phi)| (element, phi.min(phi1)));
        let records = inside.iter().map(|ev| {
            let mut phi = phi0 + ev.at * (phi1 - phi0);
            if let (EventKind::Yield, Some((element, onset))) = (ev.kind, onset) {
                phi = if ev.element == element { onset } else { phi.max(onset) };
            }
            let step = first_step + ends.iter().filter(|&&end| end < phi).count();
            EventRecord {
                step,
                stage: self.stage,
                load_fraction: phi,
                time: self.stage as f64 + phi,
                kind: ev.kind,
                entity: ev.element,
            }
        });
        let mut merged: Vec<(bool, EventRecord)> = records
            .map(|r| (false, r))
            .chain(self.events.drain(first_event..).map(|r| (true, r)))
            .collect();
        merged.sort_by(|a, b| a.1.load_fraction.total_cmp(&b.1.load_fraction).then(a.0.cmp(&b.0)));
        self.events.extend(merged.into_iter().map(|(_, r)| r));
    }

    /// A contact sub-step's record (`substeps`): the contact state after its events, with the
    /// residual and drift of the increment's start, which its linear path keeps.
    pub fn substep<D: Dim>(&mut self, state: &State<D>, scale: f64) {
        self.n_substeps += 1;
        let residual = self.steps.last().map_or(0.0, |s| s.residual);
        let (n_closed, n_stick) = (state.n_closed(), state.n_stick());
        let (contact_force, contact_moment) = self.resultants.contacts(state);
        let (reaction, load_work) = self.resultants.unknown();
        self.steps.push(StepRecord {
            stage: state.stage,
            load_fraction: state.load_fraction,
            time: state.time(),
            scale,
            residual,
            n_closed,
            n_stick,
            n_slip: n_closed - n_stick,
            normal_force: state.lambda_n.iter().sum(),
            n_plastic: state.n_plastic(),
            drift: self.balance.drift,
            contact_force,
            contact_moment,
            reaction,
            load_work,
        });
    }

    /// An event of the equilibrium correction at φ. A pair the correction separates that closed
    /// in this increment was predicted to close too early (by the trial's tangent): its closure
    /// is withdrawn instead (it is predicted again from the corrected state).
    pub fn correction_event(&mut self, c: &Candidate, phi: f64) {
        let step = self.steps.len();
        if c.kind == EventKind::Separate {
            if let Some(i) = self
                .events
                .iter()
                .rposition(|e| e.step == step && e.kind == EventKind::Close && e.entity == c.entity)
            {
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
        self.events.push(EventRecord {
            step: self.steps.len(),
            stage: self.stage,
            load_fraction: phi,
            time,
            kind,
            entity: c.entity,
        });
    }

    /// One record per increment, and its snapshot when every event is requested; `internal`:
    /// the internal force of the state's stresses (from the equilibrium check).
    pub fn step<D: Dim>(
        &mut self,
        eng: &mut Engine<D>,
        state: &State<D>,
        scale: f64,
        residual: f64,
        internal: Option<&[f64]>,
    ) -> Result<()> {
        let drift = self.balance.drift;
        let (n_closed, n_stick) = (state.n_closed(), state.n_stick());
        let (contact_force, contact_moment) = self.resultants.contacts(state);
        let (reaction, load_work) = self.resultants.supports_and_loads(eng, state, internal);
        self.steps.push(StepRecord {
            stage: state.stage,
            load_fraction: state.load_fraction,
            time: state.time(),
            scale,
            residual,
            n_closed,
            n_stick,
            n_slip: n_closed - n_stick,
            normal_force: state.lambda_n.iter().sum(),
            n_plastic: state.n_plastic(),
            drift,
            contact_force,
            contact_moment,
            reaction,
            load_work,
        });
        if self.every_event {
            let snapshot = self.snapshot(eng, state, internal)?;
            self.snapshots.push(snapshot);
        }
        self.snapshots_at_end(eng, state, internal)
    }

    /// The final snapshot (for requested fractions, and for runs that stopped early) and the
    /// result; `settled`: the state is an increment's end (not one a failure or an interrupt
    /// inside an increment left), whose fields make that snapshot.
    pub fn finish<D: Dim>(
        mut self,
        mut eng: Engine<D>,
        state: &State<D>,
        stop: StopReason,
        settled: bool,
        rate_problems: usize,
    ) -> Result<RunResult> {
        let early = !matches!(stop, StopReason::Completed | StopReason::FirstYield);
        if settled && (early || !self.every_event) {
            if self.snapshots.last().map_or(true, |s| (s.time - state.time()).abs() > SAME_FRACTION)
            {
                let last = self.snapshot(&mut eng, state, None)?;
                self.snapshots.push(last);
            }
        }
        Ok(RunResult {
            dim: D::N,
            stage_names: eng.problem.path.stage_names.clone(),
            events: self.events,
            steps: self.steps,
            snapshots: self.snapshots,
            closure_fraction: self.closure_fraction,
            predicted_closure: self.predicted_closure,
            max_equilibrium_residual: self
                .balance
                .max_residual
                .max(self.balance.max_snapshot_residual),
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
    fn snapshot<D: Dim>(
        &mut self,
        eng: &mut Engine<D>,
        state: &State<D>,
        internal: Option<&[f64]>,
    ) -> Result<Snapshot> {
        let full;
        let (state, internal) = if eng.problem.is_reduced() {
            let (s, internal, residual) = reconstruct(eng, state)?;
            self.balance.max_snapshot_residual = self.balance.max_snapshot_residual.max(residual);
            full = s;
            (&full, internal)
        } else {
            (
                state,
                internal.map_or_else(|| eng.problem.internal_force(&state.stress), <[f64]>::to_vec),
            )
        };
        let (problem, loads) = (&eng.problem, &eng.loads);
        let pairs = problem.global_pairs();
        // P_σ − P − the contact forces at the held DOFs: the supports' force
        let mut contact = vec![0.0; internal.len()];
        for (p, pair) in pairs.iter().enumerate() {
            pair.add_support_force(state.lambda_n[p], state.lambda_t_of(p), &mut contact);
        }
        let reaction = (0..internal.len())
            .map(|d| {
                if problem.dofs.fixed[d] {
                    internal[d] - loads.load.force(d, state.load_fraction) - contact[d]
                } else {
                    0.0
                }
            })
            .collect();
        Ok(Snapshot {
            stage: state.stage,
            load_fraction: state.load_fraction,
            time: state.time(),
            dim: D::N,
            u: state.u.clone(),
            stress: state.stress.iter().map(|s| std::array::from_fn(|k| s[k])).collect(),
            plastic_strain: state.plastic_strain.clone(),
            plastic: if state.plastic.is_empty() {
                vec![0; problem.elements.len()]
            } else {
                state.plastic.iter().map(|&p| p as i8).collect()
            },
            lambda_n: state.lambda_n.clone(),
            lambda_t: state.lambda_t.clone(),
            status: state.status.iter().map(|s| s.code()).collect(),
            gap: pairs.iter().zip(&state.shift).map(|(p, c)| p.gap(&state.u) + c[0]).collect(),
            rtd: pairs.iter().zip(&state.shift).map(|(p, c)| p.rtd(&state.u) + c[1]).collect(),
            lambda_t2: state.space().map_or(vec![], |s| s.lambda_t2.clone()),
            rtd2: match state.space() {
                Some(_) => pairs
                    .iter()
                    .zip(&state.shift)
                    .map(|(p, c)| p.dots(&state.u)[2] + c[2])
                    .collect(),
                None => vec![],
            },
            reaction,
        })
    }
}

/// What every increment records beside its counts (issue 38): each contact's resultant force
/// and moment (O(pairs)), each support group's reaction and each force pattern's work P_j · u.
///
/// The reactions and works are linear in the state. The full space has u, and at every
/// increment's end the internal force P_σ of its equilibrium check: a group's reaction is
/// Σ (P_σ − P − contact forces) over its DOFs, a work P_j · u, O(group DOFs + pairs). The
/// reduced elastic space carries neither (only the contact DOFs between events): there each is
/// a functional a·u of u = Σ u_stage (completed) + s u_stage + ū(s) + K#(W λ) + N α, read from
/// the state's λ and α with z = K# a solved once at the start (`Functional`): one solve per
/// held component of each group (a = K s, s the group's DOFs along it, whose internal force
/// (K u)·s = a·u) and per force pattern, none per increment, O(pairs) per increment.
struct Resultants {
    /// Per pair: its contact, and its contactor point (node a, or Σ c_i x_i over the contactor
    /// nodes of a weighted row).
    contact: Vec<usize>,
    point: Vec<[f64; 3]>,
    /// Per pair: its frame (n, t1, t2; t2 unused in 2D).
    frame: Vec<[[f64; 3]; 3]>,
    n_contacts: usize,
    /// Per support group: its held components.
    supports: Vec<Vec<Held>>,
    /// Per force pattern (`load`, then `Model::patterns`): a = P_j.
    loads: Vec<Functional>,
}

/// The DOFs of a support group along one component.
struct Held {
    component: usize,
    dofs: Vec<usize>,
    /// The pairs' force straight onto these DOFs per unit (λ_n, λ_t1, λ_t2) (`Pair::on_supports`).
    direct: Vec<(usize, [f64; 3])>,
    /// Reduced space: their internal force (K u)·s as the functional a = K s.
    internal: Option<Functional>,
}

/// A linear functional a·u of the displacement. Full space: from u. Reduced space: a·u =
/// a·(Σ u_stage + s u_stage + ū(s)) + Σ_p (z·w_p) λ_p + Σ_k (a·N_k) α_k with z = K# a (K# is
/// symmetric: a·K#(W λ) = z·W λ), the first term affine in s within a stage.
struct Functional {
    /// a's nonzero entries over all DOFs.
    a: Vec<(usize, f64)>,
    /// Reduced space: per pair (z·w_n, z·w_t, z·w_t2), per free rigid mode a·N_k.
    pairs: Vec<[f64; 3]>,
    modes: Vec<f64>,
    /// Reduced space: (stage, a·(Σ u_stage + ū_start), a·(u_stage + Δū)) of the last stage seen.
    stage: Option<(usize, f64, f64)>,
}

impl Functional {
    fn new(a: &[f64]) -> Self {
        Functional {
            a: a.iter().enumerate().filter(|&(_, &v)| v != 0.0).map(|(d, &v)| (d, v)).collect(),
            pairs: vec![],
            modes: vec![],
            stage: None,
        }
    }

    fn dot(&self, u: &[f64]) -> f64 {
        if u.is_empty() {
            return 0.0; // (no completed stage yet)
        }
        self.a.iter().map(|&(d, v)| v * u[d]).sum()
    }

    /// Reduced space: the coefficients of λ and α from z = K# a.
    fn reduce(&mut self, z: &[f64], pairs: &[Pair], modes: &[RigidMode]) {
        self.pairs = pairs.iter().map(|p| p.dots(z)).collect();
        self.modes = modes.iter().map(|m| self.dot(&m.vector)).collect();
    }

    fn value<D: Dim>(&mut self, eng: &Engine<D>, state: &State<D>) -> f64 {
        if !eng.problem.is_reduced() {
            return self.dot(&state.u);
        }
        let (c0, c1) = match self.stage {
            Some((k, c0, c1)) if k == state.stage => (c0, c1),
            _ => {
                let (reduced, load) = (&eng.loads.reduced, &eng.loads.load);
                let mut start = vec![0.0; eng.problem.dofs.fixed.len()];
                let mut change = start.clone();
                load.prescribed.iter().for_each(|&(d, s0, ds)| (start[d], change[d]) = (s0, ds));
                let c = (
                    self.dot(&reduced.u_done) + self.dot(&start),
                    self.dot(&reduced.u_load) + self.dot(&change),
                );
                self.stage = Some((state.stage, c.0, c.1));
                c
            }
        };
        let lambda = (0..self.pairs.len()).filter(|&p| {
            state.lambda_n[p] != 0.0 || state.lambda_t[p] != 0.0 || state.lambda_t_of(p)[1] != 0.0
        });
        let contacts: f64 = lambda
            .map(|p| {
                self.pairs[p][0] * state.lambda_n[p]
                    + self.pairs[p][1] * state.lambda_t[p]
                    + self.pairs[p][2] * state.lambda_t_of(p)[1]
            })
            .sum();
        let modes: f64 = self.modes.iter().zip(&state.alpha).map(|(a, b)| a * b).sum();
        c0 + state.load_fraction * c1 + contacts + modes
    }
}

impl Resultants {
    fn new<D: Dim>(eng: &mut Engine<D>) -> Self {
        let problem = &eng.problem;
        let (model, dim) = (problem.model, D::N);
        let pairs = problem.global_pairs();
        let contact: Vec<usize> = model.pairs.iter().map(|p| p.contact).collect();
        let n_contacts =
            model.names.contacts.len().max(contact.iter().map(|&c| c + 1).max().unwrap_or(0));
        let point = model
            .pairs
            .iter()
            .map(|p| {
                let contactor: Vec<(usize, f64)> =
                    p.weights.iter().copied().filter(|&(_, c)| c > 0.0).collect();
                let total: f64 = contactor.iter().map(|&(_, c)| c).sum();
                match contactor.is_empty() {
                    true => model.mesh.point(p.node_a),
                    false => {
                        let mut x = [0.0; 3];
                        contactor.iter().for_each(|&(i, c)| {
                            x.iter_mut()
                                .zip(model.mesh.point(i))
                                .for_each(|(a, b)| *a += c / total * b)
                        });
                        x
                    }
                }
            })
            .collect();
        let fixed = &problem.dofs.fixed;
        let supports: Vec<Vec<Held>> = model
            .names
            .supports
            .iter()
            .map(|(_, dofs)| {
                (0..dim)
                    .filter_map(|c| {
                        let dofs: Vec<usize> =
                            dofs.iter().copied().filter(|&d| d % dim == c && fixed[d]).collect();
                        let mut mask = vec![false; fixed.len()];
                        dofs.iter().for_each(|&d| mask[d] = true);
                        let on = |w: &crate::contact::SparseVec| {
                            w.entries.iter().filter(|e| mask[e.0]).map(|e| e.1).sum::<f64>()
                        };
                        let direct = pairs
                            .iter()
                            .enumerate()
                            .map(|(p, pair)| {
                                let mut direct = [0.0; 3];
                                pair.on_supports().zip(&mut direct).for_each(|(w, v)| *v = on(w));
                                (p, direct)
                            })
                            .filter(|(_, v)| *v != [0.0; 3])
                            .collect();
                        (!dofs.is_empty()).then_some(Held {
                            component: c,
                            dofs,
                            direct,
                            internal: None,
                        })
                    })
                    .collect()
            })
            .collect();
        let loads: Vec<Functional> = std::iter::once(&model.load)
            .chain(model.patterns.iter().map(|p| &p.force))
            .map(|f| Functional::new(f))
            .collect();
        let frame = pairs
            .iter()
            .map(|p| {
                let t2 = p.tangents.get(1).map_or([0.0; 3], |t| t.direction);
                [p.normal, p.tangents[0].direction, t2]
            })
            .collect();
        let mut out = Resultants { contact, point, frame, n_contacts, supports, loads };
        if eng.problem.is_reduced() {
            out.reduce(eng);
        }
        out
    }

    /// Reduced space: every functional's z = K# a, in one solve of many right-hand sides.
    fn reduce<D: Dim>(&mut self, eng: &mut Engine<D>) {
        let _t = eng.clock.time(Phase::Solves);
        let n = eng.problem.dofs.fixed.len();
        for held in self.supports.iter_mut().flatten() {
            let mut s = vec![0.0; n];
            held.dofs.iter().for_each(|&d| s[d] = 1.0);
            let (stress, _) = eng.stiffness.tangents.stress_increment(&eng.problem, &s);
            held.internal = Some(Functional::new(&eng.problem.internal_force(&stress)));
        }
        let mut functionals: Vec<&mut Functional> = self
            .supports
            .iter_mut()
            .flatten()
            .filter_map(|h| h.internal.as_mut())
            .chain(self.loads.iter_mut())
            .filter(|f| !f.a.is_empty())
            .collect();
        let ys: Vec<Vec<f64>> = functionals
            .iter()
            .map(|f| {
                let mut y = vec![0.0; n];
                f.a.iter().for_each(|&(d, v)| y[d] = v);
                y
            })
            .collect();
        let zs = eng.stiffness.apply_ginv(&eng.problem.dofs.map, &ys);
        for (f, z) in functionals.iter_mut().zip(&zs) {
            f.reduce(z, eng.problem.global_pairs(), &eng.problem.bodies.modes);
        }
    }

    /// Per contact its resultant force on the contactor side and that force's moment about the
    /// origin (`StepRecord::contact_force`, `contact_moment`).
    fn contacts<D: Dim>(&self, state: &State<D>) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let mut force = vec![[0.0; 3]; self.n_contacts];
        let mut moment = vec![[0.0; 3]; self.n_contacts];
        for (p, [n, t1, t2]) in self.frame.iter().enumerate() {
            let lambda = [state.lambda_n[p], state.lambda_t[p], state.lambda_t_of(p)[1]];
            if lambda == [0.0; 3] {
                continue;
            }
            let f: [f64; 3] =
                std::array::from_fn(|k| n[k] * lambda[0] + t1[k] * lambda[1] + t2[k] * lambda[2]);
            let x = self.point[p];
            let m =
                [x[1] * f[2] - x[2] * f[1], x[2] * f[0] - x[0] * f[2], x[0] * f[1] - x[1] * f[0]];
            let c = self.contact[p];
            (0..3).for_each(|k| {
                (force[c][k], moment[c][k]) = (force[c][k] + f[k], moment[c][k] + m[k])
            });
        }
        (force, moment)
    }

    /// Per support group its reaction and per force pattern its work at the state
    /// (`StepRecord::reaction`, `load_work`); `internal`: the state's internal force (full space).
    fn supports_and_loads<D: Dim>(
        &mut self,
        eng: &Engine<D>,
        state: &State<D>,
        internal: Option<&[f64]>,
    ) -> (Vec<[f64; 3]>, Vec<f64>) {
        let reduced = eng.problem.is_reduced();
        let phi = state.load_fraction;
        let lambda = |p: usize| state.contact_force(p);
        let reaction = self
            .supports
            .iter_mut()
            .map(|group| {
                let mut r = [0.0; 3];
                for held in group.iter_mut() {
                    let inner = match (internal, held.internal.as_mut()) {
                        (Some(f), _) if !reduced => held.dofs.iter().map(|&d| f[d]).sum(),
                        (_, Some(functional)) if reduced => functional.value(eng, state),
                        _ => f64::NAN,
                    };
                    let load: f64 = held.dofs.iter().map(|&d| eng.loads.load.force(d, phi)).sum();
                    let direct: f64 = held
                        .direct
                        .iter()
                        .map(|&(p, c)| {
                            let l = lambda(p);
                            c[0] * l[0] + c[1] * l[1] + c[2] * l[2]
                        })
                        .sum();
                    r[held.component] = inner - load - direct;
                }
                r
            })
            .collect();
        let work = self
            .loads
            .iter_mut()
            .map(|f| if f.a.is_empty() { 0.0 } else { f.value(eng, state) })
            .collect();
        (reaction, work)
    }

    /// A contact sub-step's reactions and works: not known (NaN).
    fn unknown(&self) -> (Vec<[f64; 3]>, Vec<f64>) {
        (vec![[f64::NAN; 3]; self.supports.len()], vec![f64::NAN; self.loads.len()])
    }
}

/// u = Σ u_stage (completed) + s u_stage + K#(W λ) + N α, ū at the prescribed DOFs, and its
/// stresses, for the reduced space; also the internal force P_σ and the fields' equilibrium
/// residual, which must be within `equilibrium_tol`.
fn reconstruct<D: Dim>(eng: &mut Engine<D>, state: &State<D>) -> Result<(State<D>, Vec<f64>, f64)> {
    let Engine { problem, stiffness, loads, .. } = eng;
    let mut y = vec![0.0; problem.dofs.map.role.len()];
    for (p, pair) in problem.global_pairs().iter().enumerate() {
        pair.add_force(state.contact_force(p), &mut y);
    }
    let mut u =
        stiffness.apply_ginv(&problem.dofs.map, std::slice::from_ref(&y)).pop().unwrap_or_default();
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

#[cfg(test)]
mod tests {
    use super::super::run;
    use super::super::scenes::*;
    use crate::model::{LoadPattern, Model, RunResult, Stage};

    /// Round-off of the resultants relative to the load (a few sums of element forces).
    const ROUND_OFF: f64 = 1e-12;

    fn run_in<D: crate::element::Discretization>(mut m: Model<D>, reduced: bool) -> RunResult {
        m.options.reduced_elastic = reduced;
        m.validate().expect("a valid scene");
        run(&m, |_| true).expect("it runs")
    }

    /// The square on rollers pressed by q on its top against a wall to its right (node 2):
    /// every increment's reactions, the same in the reduced elastic space (functionals of the
    /// contact forces) as in the full one (the internal force), balance the load and the wall:
    /// the bottom rollers carry q, the left ones the wall's force; the wall's force is its
    /// pair's λ_n along its normal (−1, 0), at node 2 (1, 1) its moment about the origin
    /// M_z = x F_y − y F_x = λ_n; the pressure's work P·u = −(q/2)(u_y2 + u_y3).
    #[test]
    fn reactions_balance_in_both_spaces() {
        let q = 2.0;
        let mut records = vec![];
        for reduced in [true, false] {
            let mut m = poisson_wall(q, 1e-4);
            m.names.supports = vec![("left".into(), vec![0, 6]), ("bottom".into(), vec![1, 3])];
            let r = run_in(m, reduced);
            let last = r.steps.last().expect("steps");
            let (lambda, force, moment) = (
                r.snapshots.last().unwrap().lambda_n[0],
                last.contact_force[0],
                last.contact_moment[0],
            );
            assert!(lambda > 0.0, "the wall is reached");
            assert!(
                (force[0] + lambda).abs() <= ROUND_OFF * q && force[1] == 0.0 && force[2] == 0.0,
                "{force:?}"
            );
            assert!(
                (moment[2] - lambda).abs() <= ROUND_OFF * q && moment[0] == 0.0 && moment[1] == 0.0,
                "{moment:?}"
            );
            for s in &r.steps {
                let applied_y = -q * s.load_fraction;
                let [left, bottom] = [s.reaction[0], s.reaction[1]];
                assert!(
                    (left[0] + s.contact_force[0][0]).abs() <= ROUND_OFF * q,
                    "left {left:?} against the wall {:?}",
                    s.contact_force[0]
                );
                assert!((bottom[1] + applied_y).abs() <= ROUND_OFF * q, "bottom {bottom:?}");
                assert!(
                    left[1] == 0.0 && bottom[0] == 0.0,
                    "a group reacts only along what it holds"
                );
            }
            let u = &r.snapshots.last().unwrap().u;
            let work = -q / 2.0 * (u[5] + u[7]);
            assert!(
                (last.load_work[0] - work).abs() <= ROUND_OFF * work.abs(),
                "P·u {} against {work}",
                last.load_work[0]
            );
            records.push(r.steps);
        }
        let (reduced, full) = (&records[0], &records[1]);
        assert_eq!(reduced.len(), full.len());
        for (a, b) in reduced.iter().zip(full) {
            for g in 0..2 {
                (0..3).for_each(|c| {
                    assert!((a.reaction[g][c] - b.reaction[g][c]).abs() <= ROUND_OFF * q)
                });
            }
            assert!(
                (a.load_work[0] - b.load_work[0]).abs()
                    <= ROUND_OFF * b.load_work[0].abs().max(1e-300)
            );
        }
    }

    /// The square on rollers pulled by a prescribed u_x = d on its right edge (nodes 1, 2) in
    /// two stages (d, then back to d/2): the pulled edge's reaction is E d (plane stress,
    /// uniaxial, thickness 1), the left rollers' −E d, in both spaces (the reduced one reads
    /// the prescribed values and each stage's K#-load per stage).
    #[test]
    fn a_prescribed_displacement_reacts_with_its_stress() {
        let d = 1e-3;
        for reduced in [true, false] {
            let mut m = square_on_rollers(0.0, 0.0, crate::material::Material::elastic(E, NU));
            m.patterns = vec![LoadPattern {
                name: "pull".into(),
                displacement: vec![(2, d), (4, d)],
                ..Default::default()
            }];
            m.stages = vec![
                Stage { name: "out".into(), factors: vec![0.0, 1.0] },
                Stage { name: "back".into(), factors: vec![0.0, 0.5] },
            ];
            m.names.supports = vec![
                ("left".into(), vec![0, 6]),
                ("pulled".into(), vec![2, 4]),
                ("bottom".into(), vec![1, 3]),
            ];
            let r = run_in(m, reduced);
            assert_eq!(r.steps.len(), 2);
            for (s, factor) in r.steps.iter().zip([1.0, 0.5]) {
                let pull = E * d * factor;
                assert!(
                    (s.reaction[1][0] - pull).abs() <= ROUND_OFF * pull,
                    "pulled {:?} against {pull}",
                    s.reaction[1]
                );
                assert!(
                    (s.reaction[0][0] + pull).abs() <= ROUND_OFF * pull,
                    "left {:?}",
                    s.reaction[0]
                );
                assert!(s.reaction[2][1].abs() <= ROUND_OFF * pull, "bottom {:?}", s.reaction[2]);
            }
        }
    }
}
