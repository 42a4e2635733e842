//! Plasticity in the loop (eqs. 5–11, 59): the elements' stresses over an increment, and the
//! equilibrium correction after it.
//!
//! The trial moves every element with the tangent K holds (`tangents`), which is exact for the
//! elastic ones. With `drift_control` (the default) the stress of every element that is plastic,
//! or (grouped increments) crosses its yield surface inside the increment, is integrated along
//! its strain instead (`stress_integration`: the elastic–plastic split, Prandtl–Reuss with error
//! control); one correction solve at fixed load, with the tangents brought up to date, then
//! restores equilibrium, so that every event is in equilibrium to round-off. (Keeping the
//! linear stresses while they stay within a tolerance of the surface saves corrections but
//! biases the path: measured on the elastoplastic Hertz at 8.6k DOFs, p0 −0.24 %, −0.05 % and
//! −0.03 % for tolerances 1e-3, 1e-4 and 1e-5 of σy.) `drift_control = false` is the paper
//! exactly: the tangent's linear increment, no correction.

use super::engine::{since, Engine};
use super::retake::{stalls, RETAKE_TOL};
use super::selection::{Selection, STAGE_END, ZERO_SCALE};
use super::trial::PARALLEL_CHUNK;
use super::state::{State, TrialIncrement};
use crate::error::Result;
use crate::material::{von_mises, yield_scale};
use crate::events::{self, Candidate, PairState, Trial};
use crate::model::EventKind;
use crate::element::Element;
use crate::stress_integration::{integrate, Integrated, PointState};
use nalgebra::Vector4;
use rayon::prelude::*;
use std::time::Instant;

/// The size of the last equilibrium correction (displacement, force): the correction moves
/// nodes and contact forces by that much with no event of its own, so the contact checks
/// allow for it (see `Engine::check_contact`).
#[derive(Clone, Copy, Default)]
pub(super) struct Correction {
    pub displacement: f64,
    pub force: f64,
}

/// What restoring equilibrium after an increment did.
pub(super) enum Restored {
    /// The increment kept the tangent's linear stresses: in equilibrium already, and the last
    /// correction's allowance for the contact checks still holds.
    Linear,
    Corrected(Corrected),
    /// A grouped window its re-integration could not balance: the caller retakes it (`retake`).
    Unbalanced,
}

/// A yield or unload inside an increment: the element and the fraction of the increment.
pub(super) struct InsideEvent {
    pub element: usize,
    pub kind: EventKind,
    pub at: f64,
}

impl Engine<'_> {
    /// Yield-surface drift: max |σe − σy(εp)| / σy(εp) over plastic elements.
    pub fn drift(&self, state: &State) -> f64 {
        (0..state.plastic.len())
            .filter(|&e| state.plastic[e])
            .map(|e| {
                let sy = self.sections[e].material.current_yield(state.plastic_strain[e]);
                (von_mises(&state.stress[e]) - sy).abs() / sy
            })
            .fold(0.0, f64::max)
    }

    /// The stress of each element that is plastic at the increment's start, or (grouped
    /// increments) whose elastic path crosses its yield surface inside the increment, integrated
    /// over the increment's strain from `state` (before the advance). An elastic path that meets
    /// the surface within `STAGE_END` of the stage's end ties with the end, as a yield event does
    /// (`selection`): it belongs to the next stage.
    pub fn integrate_stresses(&self, state: &State, trial: &TrialIncrement, sel: &Selection) -> Vec<(usize, Integrated)> {
        let scale = sel.scale;
        if !self.model.options.drift_control || scale <= ZERO_SCALE {
            return vec![]; // a zero-length increment changes no stress (and gets no correction)
        }
        let (phi0, phi1) = (state.load_fraction, sel.phi);
        let crosses = |e: usize, sy: f64| match yield_scale(&state.stress[e], &(trial.dstress[e] * scale), sy) {
            Some(r) => r < 1.0 && phi0 + r * (phi1 - phi0) < 1.0 - STAGE_END,
            None => false,
        };
        (0..state.stress.len())
            .into_par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .filter_map(|e| {
                let (section, plastic) = (&self.sections[e], state.plastic[e]);
                let m = &section.material;
                let sy = m.current_yield(state.plastic_strain[e]);
                if !m.is_plastic() || !(plastic || (sel.plastic_inside && crosses(e, sy))) {
                    return None;
                }
                // back onto the surface first if the last correction left it beyond
                let stress = if plastic { section.not_beyond_surface(&state.stress[e], sy) } else { state.stress[e] };
                let start = PointState { stress, plastic_strain: state.plastic_strain[e], plastic };
                Some((e, integrate(section, &start, &(trial.dstrain[e] * scale))))
            })
            .collect()
    }

    /// Put the integrated states in place and note where elements crossed their surfaces.
    pub fn place_integrated(&self, state: &mut State, integrated: &[(usize, Integrated)], start: &mut IncrementStart) {
        for (e, out) in integrated {
            state.stress[*e] = out.end.stress;
            state.plastic_strain[*e] = out.end.plastic_strain;
            state.plastic[*e] = out.end.plastic;
            if let Some(at) = out.yielded_at {
                start.yielded_at.insert(*e, at);
            }
        }
    }

    /// The yields and unloads inside the increment just settled, in order: the elements whose
    /// status differs from the increment's start, but for the events that ended it (`group`).
    pub fn inside_events(&mut self, state: &State, sel: &Selection) -> Vec<InsideEvent> {
        let Some(start) = self.increment_start.take() else { return vec![] };
        let ended: std::collections::HashSet<usize> = sel.group.iter().filter(|c| c.kind.is_element_event()).map(|c| c.entity).collect();
        let mut inside: Vec<InsideEvent> = (0..state.plastic.len())
            .filter(|&e| state.plastic[e] != start.plastic[e] && !ended.contains(&e))
            .map(|e| match state.plastic[e] {
                true => InsideEvent { element: e, kind: EventKind::Yield, at: start.yielded_at.get(&e).copied().unwrap_or(1.0) },
                false => InsideEvent { element: e, kind: EventKind::Unload, at: 0.0 },
            })
            .collect();
        inside.sort_by(|a, b| a.at.total_cmp(&b.at));
        inside
    }

    /// Equilibrium after an increment whose stresses were integrated: the tangents follow the
    /// state (`update_tangents`), then the correction at fixed load (`correct_at_fixed_load`).
    /// A correction that leaves plastic elements more than max_stress_step² off their yield
    /// surfaces (the second-order drift of a fresh tangent over a bounded stress step: only
    /// waiting yields, `tangents`, do that), and every stage's end, then settle on the surfaces
    /// (`settle_on_surfaces`).
    pub fn restore_equilibrium(&mut self, state: &mut State, sel: &Selection, integrated: bool) -> Result<Restored> {
        if !integrated {
            return Ok(Restored::Linear);
        }
        let t0 = Instant::now();
        self.update_tangents(state)?;
        let restored = match self.converge_increment(state, sel.phi, sel.plastic_inside)? {
            Some(mut corrected) => {
                let bound = self.model.options.max_stress_step.powi(2);
                if sel.last || self.drift(state) > bound {
                    corrected.absorb(self.settle_on_surfaces(state, sel.phi, sel.last)?);
                }
                Restored::Corrected(corrected)
            }
            None => Restored::Unbalanced,
        };
        self.timings.corrections += since(t0);
        Ok(restored)
    }

    /// A grouped increment's plastic path: the correction, then every element that was or
    /// became plastic, or is beyond its surface, integrated again from the increment's start over
    /// its whole strain (trial and corrections: `reintegrate`); while that state is out of balance
    /// by more than `REINTEGRATION_TOL` of the load, correct it again. The last linear stresses
    /// are kept (in equilibrium to round-off), with their plastic strains and flags; an elastic
    /// element they leave beyond its surface has yielded.
    /// Event by event, the one correction. None for a window whose rounds stall (`retake`).
    fn converge_increment(&mut self, state: &mut State, phi: f64, regrouped: bool) -> Result<Option<Corrected>> {
        let mut corrected = self.correct_at_fixed_load(state, phi, None)?;
        let Some(mut start) = self.increment_start.take() else { return Ok(Some(corrected)) };
        let mut previous = None;
        for round in 1..=if regrouped { MAX_ROUNDS } else { 0 } {
            let linear = (state.stress.clone(), state.plastic_strain.clone(), state.plastic.clone());
            self.reintegrate(state, &mut start);
            let (residual, internal) = self.full_residual(state);
            if residual <= REINTEGRATION_TOL {
                (state.stress, state.plastic_strain, state.plastic) = linear;
                break;
            }
            if residual > RETAKE_TOL && stalls(residual, previous, MAX_ROUNDS - round) {
                self.increment_start = Some(start); // the caller takes the window back from it
                return Ok(None);
            }
            corrected.absorb(self.correct_at_fixed_load(state, phi, Some(internal))?);
            if round >= MAX_REINTEGRATIONS && residual <= RETAKE_TOL {
                break;
            }
            previous = Some(residual);
        }
        self.flag_beyond_surfaces(state, &mut start);
        self.increment_start = Some(start);
        Ok(Some(corrected))
    }

    /// An elastic element the last correction left beyond its yield surface yielded in this
    /// increment (where the integration put its crossing, else at the end): plastic from here
    /// (its next increment starts on the surface).
    fn flag_beyond_surfaces(&self, state: &mut State, start: &mut IncrementStart) {
        for e in 0..state.plastic.len() {
            let m = &self.sections[e].material;
            if m.is_plastic() && !state.plastic[e] && von_mises(&state.stress[e]) > m.current_yield(state.plastic_strain[e]) {
                state.plastic[e] = true;
                start.yielded_at.entry(e).or_insert(1.0);
            }
        }
    }

    /// Every element that was plastic at the increment's start, is plastic now or is beyond its
    /// yield surface now: its start state integrated over the increment's whole strain so far.
    fn reintegrate(&self, state: &mut State, start: &mut IncrementStart) {
        let du: Vec<f64> = state.u.iter().zip(&start.u).map(|(a, b)| a - b).collect();
        let now: &State = state;
        let integrated: Vec<(usize, Integrated)> = (0..now.stress.len())
            .into_par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .filter_map(|e| {
                let section = &self.sections[e];
                let m = &section.material;
                let beyond = || von_mises(&now.stress[e]) > m.current_yield(now.plastic_strain[e]);
                if !m.is_plastic() || !(start.plastic[e] || now.plastic[e] || beyond()) {
                    return None;
                }
                let sy = m.current_yield(start.plastic_strain[e]);
                let stress = if start.plastic[e] { section.not_beyond_surface(&start.stress[e], sy) } else { start.stress[e] };
                let point = PointState { stress, plastic_strain: start.plastic_strain[e], plastic: start.plastic[e] };
                Some((e, integrate(section, &point, &self.elements[e].strain(&du))))
            })
            .collect();
        for (e, out) in integrated {
            match out.yielded_at {
                Some(at) => start.yielded_at.insert(e, at),
                None => start.yielded_at.remove(&e),
            };
            state.stress[e] = out.end.stress;
            state.plastic_strain[e] = out.end.plastic_strain;
            state.plastic[e] = out.end.plastic;
        }
    }

    /// Plastic elements back onto their yield surfaces (the drift a held tangent left), then a
    /// correction with
    /// every tangent renewed, which leaves only the square of that drift: a reload then retraces
    /// the stage's end (elastic shakedown stays elastic), and an unload starts on the surface.
    /// Repeated (at most `SETTLE_ROUNDS` times) until the drift is round-off at a stage's end.
    fn settle_on_surfaces(&mut self, state: &mut State, phi: f64, stage_end: bool) -> Result<Corrected> {
        let mut corrected = Corrected::default();
        for _ in 0..SETTLE_ROUNDS {
            for e in (0..state.plastic.len()).filter(|&e| state.plastic[e]) {
                let section = &self.sections[e];
                let sy = section.material.current_yield(state.plastic_strain[e]);
                state.stress[e] = section.onto_yield_surface(&state.stress[e], sy);
            }
            self.renew_all_tangents = true;
            let renewed = self.update_tangents(state);
            self.renew_all_tangents = false;
            renewed?;
            corrected.absorb(self.correct_at_fixed_load(state, phi, None)?);
            if !stage_end || self.drift(state) <= SETTLED_DRIFT {
                break;
            }
        }
        Ok(corrected)
    }

    /// Equilibrium at fixed load φ by the procedure itself: solve the correction for the
    /// out-of-balance force (eq. 44 with no load change), advance it to the first contact event
    /// that would make the state inadmissible (a gap closing, a pair separating, a stuck pair
    /// reaching its cone: eqs. 48–53), switch that, and solve the rest again, so that the
    /// corrected state is admissible. Returns the correction's size and its events, in order.
    /// `internal`: the internal force of the state's stresses if the caller has it.
    pub fn correct_at_fixed_load(&mut self, state: &mut State, phi: f64, mut internal: Option<Vec<f64>>) -> Result<Corrected> {
        let mut corrected = Corrected::default();
        for step in 0..MAX_CORRECTION_EVENTS {
            let c = self.trial(state, phi, internal.take())?;
            let frozen = vec![false; self.pairs.len()];
            let pairs = PairState { pairs: &self.pairs, status: &state.status, lambda_n: &state.lambda_n, lambda_t: &state.lambda_t, u: &state.u, shift: &state.shift, frozen: &frozen };
            let mut cands = events::candidates(&pairs, &Trial { du: &c.du, dlambda_n: &c.dlambda_n, dlambda_t: &c.dlambda_t, dshift: &c.dshift }, self.noise);
            // A slip that reverses inside the correction leaves its force on the cone: the state
            // stays admissible, and sticking it would only cycle with the next increment.
            cands.retain(|x| x.kind != EventKind::SlipToStick);
            let first = cands.iter().map(|x| x.scale).fold(f64::INFINITY, f64::min);
            // The last allowed step takes the rest whatever it violates (the contact checks then
            // allow for the correction's size).
            let s = if step + 1 == MAX_CORRECTION_EVENTS { 1.0 } else { first.min(1.0) };
            corrected.size.include(&c, s);
            state.advance(&c, s);
            state.load_fraction = phi;
            if s >= 1.0 {
                break;
            }
            let tie = first * (1.0 + CORRECTION_TIE) + CORRECTION_TIE_SLACK;
            for x in cands.into_iter().filter(|x| x.scale <= tie) {
                self.switch(state, &x);
                corrected.events.push(x);
            }
        }
        Ok(corrected)
    }
}

/// A grouped increment is re-integrated until its state is out of balance by at most this ×
/// the load (relative residual). Measured on the thick cylinder (H' = 0, δ = 0.01, 2.7k and
/// 4.9k DOFs), the largest difference of plastic strain to the event-by-event run: 1.75 % with
/// one linear correction, 1.45 % (tol 1e-3), 0.47 % (1e-4), 0.33 % (1e-5); on the
/// elastoplastic Hertz (24.5k DOFs) 1e-4 moves p0 by 0.003 %.
const REINTEGRATION_TOL: f64 = 1e-4;
/// After this many rounds a window within `RETAKE_TOL` is kept; one further out goes on while
/// its rounds converge fast enough to reach `RETAKE_TOL` within `MAX_ROUNDS` (`retake::stalls`),
/// else it is retaken.
const MAX_REINTEGRATIONS: usize = 4;
const MAX_ROUNDS: usize = 10;

/// A stage ends with its plastic elements this close to their yield surfaces (relative; a
/// reload of an elastic release then meets them at the stage's end: `selection::STAGE_END`),
/// settled in at most `SETTLE_ROUNDS` rounds (each leaves about the square of the last drift).
const SETTLED_DRIFT: f64 = 1e-12;
const SETTLE_ROUNDS: usize = 3;

/// The state of the elements and the displacement at the start of an increment whose stresses
/// were integrated.
pub(super) struct IncrementStart {
    pub stress: Vec<Vector4<f64>>,
    pub plastic_strain: Vec<f64>,
    pub plastic: Vec<bool>,
    pub u: Vec<f64>,
    /// Where in the increment each element that crossed its surface did so (the latest
    /// integration's elastic fraction).
    pub yielded_at: std::collections::HashMap<usize, f64>,
}

/// Contact events of one correction within this (relative, plus an absolute slack) of its
/// first switch together; at most this many sub-steps per correction (each switches at
/// least one pair; past it the rest is taken as one step).
const CORRECTION_TIE: f64 = 1e-9;
const CORRECTION_TIE_SLACK: f64 = 1e-14;
const MAX_CORRECTION_EVENTS: usize = 32;

/// What an equilibrium correction did: its size and the contact events it took, in order.
#[derive(Default)]
pub(super) struct Corrected {
    pub size: Correction,
    pub events: Vec<Candidate>,
}

impl Corrected {
    /// Grown by a further correction.
    fn absorb(&mut self, other: Corrected) {
        self.size.displacement = self.size.displacement.max(other.size.displacement);
        self.size.force = self.size.force.max(other.size.force);
        self.events.extend(other.events);
    }
}

impl Correction {
    /// Grow by `s` × a correction increment.
    fn include(&mut self, c: &TrialIncrement, s: f64) {
        let largest = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        self.displacement = self.displacement.max(s * largest(&c.du));
        self.force = self.force.max(s * largest(&c.dlambda_n).max(largest(&c.dlambda_t)));
    }
}
