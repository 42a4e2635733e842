//! Termination of zero-length runs.
//!
//! Positive-length increments advance the load; zero-length increments (stick→slip at S = 0,
//! a pair that closes and reopens, ties) could cycle. Within one run of zero-length increments
//! each pair and element may switch status `max_zero_length_switches` times. A pair that would
//! switch once more means the one-at-a-time rule is cycling: the statuses of all critical pairs
//! are then solved together as a complementarity problem (`rate_problem`, Lemke), at most
//! `MAX_RATE_PROBLEMS` times per run (in 3D on a faceted cone, its statuses and slip
//! directions handed back to the facet design of friction). Only if that fails (no solution reachable: the scene may
//! be ill-posed for its μ) is the entity frozen in its status until the load advances (a
//! `frozen` event names it): the last resort. Every zero-length increment switches or freezes
//! at least one entity, so a run has at most (switches + 1) × entities + MAX_RATE_PROBLEMS
//! increments, and the procedure always terminates.

use crate::events::Candidate;

/// Rate problems solved per zero-length run before the last resort (freezing) takes over.
pub(super) const MAX_RATE_PROBLEMS: usize = 3;

pub(super) struct AntiCycling {
    n_pairs: usize,
    max_switches: usize,
    /// Switches of each entity (pairs, then elements) in the current zero-length run.
    zero_switches: Vec<usize>,
    /// Turns of each pair's held direction at zero force in the current zero-length run
    /// (`turn`): a budget of their own, as they are no status switches.
    zero_turns: Vec<usize>,
    frozen: Vec<bool>,
    /// The frozen flags the current increment was selected with (`load_advanced` clears
    /// `frozen` as the increment switches; its end is checked against these too).
    selected_frozen: Vec<bool>,
    /// Switches over the whole run (to name the busiest entities at the event bound).
    pub switch_count: Vec<usize>,
    rate_problems_in_run: usize,
    pub rate_problems: usize,
}

/// What happens to one event of the selected group.
pub(super) enum Admission {
    Apply,
    Freeze,
    /// The entity already switched in this increment.
    Skip,
}

impl AntiCycling {
    pub fn new(n_pairs: usize, n_elements: usize, max_switches: usize) -> Self {
        let n = n_pairs + n_elements;
        AntiCycling {
            n_pairs,
            max_switches,
            zero_switches: vec![0; n],
            zero_turns: vec![0; n_pairs],
            frozen: vec![false; n],
            selected_frozen: vec![false; n],
            switch_count: vec![0; n],
            rate_problems_in_run: 0,
            rate_problems: 0,
        }
    }

    /// Frozen pairs and elements.
    pub fn frozen(&self) -> (&[bool], &[bool]) {
        self.frozen.split_at(self.n_pairs)
    }

    fn key(&self, c: &Candidate) -> usize {
        if c.kind.is_element_event() {
            self.n_pairs + c.entity
        } else {
            c.entity
        }
    }

    /// Pairs frozen while the current increment was selected or since: a contact condition
    /// they violate at its end is the freeze's doing.
    pub fn frozen_pairs_of_increment(&self) -> Vec<bool> {
        (0..self.n_pairs).map(|p| self.frozen[p] || self.selected_frozen[p]).collect()
    }

    /// The increment selected with the current frozen flags starts switching.
    pub fn increment_selected(&mut self) {
        self.selected_frozen.clone_from(&self.frozen);
    }

    /// A positive-length increment ends the zero-length run.
    pub fn load_advanced(&mut self) {
        self.zero_switches.iter_mut().for_each(|c| *c = 0);
        self.zero_turns.iter_mut().for_each(|c| *c = 0);
        self.frozen.iter_mut().for_each(|f| *f = false);
        self.rate_problems_in_run = 0;
    }

    /// The one-at-a-time rule is cycling (a pair would exceed its switches) and the rate
    /// problem may still be tried in this run.
    pub fn wants_rate_problem(&self, group: &[Candidate]) -> bool {
        self.may_solve_rate_problem()
            && group.iter().any(|c| {
                !c.kind.is_element_event() && self.zero_switches[c.entity] >= self.max_switches
            })
    }

    /// The rate problem may still be tried in this zero-length run.
    pub fn may_solve_rate_problem(&self) -> bool {
        self.rate_problems_in_run < MAX_RATE_PROBLEMS
    }

    pub fn rate_problem_solved(&mut self) {
        self.rate_problems_in_run += 1;
        self.rate_problems += 1;
    }

    /// Decide one event; `seen` marks entities already switched in this increment.
    pub fn admit(&mut self, c: &Candidate, zero_length: bool, seen: &mut [bool]) -> Admission {
        let key = self.key(c);
        if seen[key] {
            return Admission::Skip;
        }
        seen[key] = true;
        if zero_length && self.zero_switches[key] >= self.max_switches {
            self.frozen[key] = true;
            return Admission::Freeze;
        }
        self.count(c, zero_length);
        Admission::Apply
    }

    /// Count a switch (also the rate problem's, which are never frozen).
    pub fn count(&mut self, c: &Candidate, zero_length: bool) {
        let key = self.key(c);
        if zero_length {
            self.zero_switches[key] += 1;
        }
        self.switch_count[key] += 1;
    }

    /// A slipping pair's held direction turns at an increment's start (3D, `slip_turn`): a
    /// zero-length switch of the pair. False once the pair has used its switches in this run:
    /// it keeps its direction, so that a run of turns ends.
    pub fn turn(&mut self, p: usize) -> bool {
        if self.zero_turns[p] >= self.max_switches {
            return false;
        }
        self.zero_turns[p] += 1;
        self.switch_count[p] += 1;
        true
    }

    pub fn n_entities(&self) -> usize {
        self.frozen.len()
    }
}
