//! Advancing the state to the event (paper §4 step 5, eqs. 58–62) and switching the statuses
//! of the events that happen there (step 6).

use super::engine::{since, Engine};
use std::time::Instant;
use super::plasticity::IncrementStart;
use super::selection::Selection;
use super::state::{State, TrialIncrement};
use crate::contact::Status;
use crate::events::Candidate;
use crate::model::EventKind;

impl Engine<'_> {
    /// u, σ, λ += S × trial (eqs. 58–61), the stresses of plastic elements (and, grouped, of
    /// those that yield inside) integrated (`plasticity`); slipping pairs on the Coulomb cone
    /// (eq. 62). Returns whether any stress was integrated (it then needs an equilibrium
    /// correction; `inside_events` tells what happened inside).
    pub fn advance(&mut self, state: &mut State, trial: &TrialIncrement, sel: &Selection) -> bool {
        let t0 = Instant::now();
        let integrated = self.integrate_stresses(state, trial, sel);
        self.timings.integration += since(t0);
        let mut start = (!integrated.is_empty())
            .then(|| IncrementStart { stress: state.stress.clone(), plastic_strain: state.plastic_strain.clone(), plastic: state.plastic.clone(), u: state.u.clone(), yielded_at: Default::default() });
        state.advance(trial, sel.scale);
        state.load_fraction = sel.phi;
        if let Some(start) = &mut start {
            self.place_integrated(state, &integrated, start);
        }
        self.increment_start = start;
        // Elements that reach their surface at this increment's end are plastic for the
        // correction already (their tangent then comes with the others: one update per step).
        for c in sel.group.iter().filter(|c| c.kind == EventKind::Yield) {
            state.plastic[c.entity] = true;
        }
        self.project_onto_cone(state);
        !integrated.is_empty()
    }

    /// λ_t = −d μ λ_n for slipping pairs (round-off removed). Returns the largest change:
    /// more than round-off where the last correction left a slipping pair off its cone.
    pub(super) fn project_onto_cone(&self, state: &mut State) -> f64 {
        let mut largest: f64 = 0.0;
        for (p, st) in state.status.iter().enumerate() {
            if let Status::Slip { .. } = st {
                let on_cone = self.pairs[p].slip_ratio(*st) * state.lambda_n[p];
                largest = largest.max((on_cone - state.lambda_t[p]).abs());
                state.lambda_t[p] = on_cone;
            }
        }
        largest
    }

    /// Apply one event's status change and the forces it sets. Returns the force it moved: the
    /// change of λ_t of a slip (a pair the equilibrium correction moved off the cone is put back
    /// on it), the forces a separation drops (one applied with a tie, before its own scale,
    /// still carries λ_n up to tie_tol × its rate): a force jump that the caller rebalances.
    pub fn switch(&self, state: &mut State, c: &Candidate) -> f64 {
        let p = c.entity;
        let before = if c.kind == EventKind::StickToSlip { state.lambda_t[p] } else { 0.0 };
        let dropped = if c.kind == EventKind::Separate { state.lambda_n[p].abs().max(state.lambda_t[p].abs()) } else { 0.0 };
        match c.kind {
            EventKind::Close => {
                state.status[p] = self.pairs[p].closed_status();
                state.rtd_stick[p] = self.rtd(state, p);
            }
            EventKind::Separate => {
                state.status[p] = Status::Open;
                state.lambda_n[p] = 0.0;
                state.lambda_t[p] = 0.0;
            }
            EventKind::StickToSlip => {
                state.status[p] = Status::Slip { direction: c.direction };
                state.lambda_t[p] = self.pairs[p].slip_ratio(state.status[p]) * state.lambda_n[p];
            }
            EventKind::SlipToStick => {
                state.status[p] = Status::Stick;
                state.rtd_stick[p] = self.rtd(state, p);
            }
            EventKind::Yield => state.plastic[p] = true,
            EventKind::Unload => state.plastic[p] = false,
            EventKind::Frozen | EventKind::FrozenElement => {}
        }
        if c.kind == EventKind::StickToSlip { (state.lambda_t[p] - before).abs() } else { dropped }
    }
}

/// The events that take pair p from status `from` to `to` (for the rate problem's statuses).
pub(super) fn transitions(p: usize, from: Status, to: Status) -> Vec<Candidate> {
    let event = |kind, direction| Candidate { scale: 0.0, entity: p, kind, direction };
    match (from, to) {
        (a, b) if a == b => vec![],
        (_, Status::Open) => vec![event(EventKind::Separate, 0)],
        (Status::Open, Status::Slip { direction }) if direction != 0 => vec![event(EventKind::Close, 0), event(EventKind::StickToSlip, direction)],
        (Status::Open, _) => vec![event(EventKind::Close, 0)],
        (Status::Slip { .. }, Status::Stick) => vec![event(EventKind::SlipToStick, 0)],
        (Status::Stick, Status::Slip { direction }) => vec![event(EventKind::StickToSlip, direction)],
        (Status::Slip { .. }, Status::Slip { direction }) => vec![event(EventKind::SlipToStick, 0), event(EventKind::StickToSlip, direction)],
        (Status::Stick, Status::Stick) => vec![],
    }
}
