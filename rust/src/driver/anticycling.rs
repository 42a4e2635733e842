//! Termination of zero-length runs, and of chains of ever shorter increments.
//!
//! Positive-length increments advance the load; zero-length increments (stick→slip at S = 0,
//! a pair that closes and reopens, ties) could cycle. So could a chain of positive increments
//! whose lengths shrink geometrically (a Zeno chain), each advancing the load but their sum
//! converging before it is applied, so that only round-off ends it. (Seen in 3D: a slipping
//! pair's turn (`slip_turn`) is a force jump whose correction opened a neighbour that had just
//! closed at zero force; it closed again a third as far on, and the turns shrank threefold.)
//! So a *run* is a sequence of increments that end within `SHORT_LOAD` of the stage fraction
//! where it began: zero-length ones and short ones alike. An increment that ends beyond ends
//! the run and begins the next where it ends. Within one run each pair and element may switch
//! status `max_zero_length_switches` times. A pair that would switch once more means the
//! one-at-a-time rule is cycling: the statuses of all critical pairs are then solved together
//! as a complementarity problem (`rate_problem`, Lemke), at most `MAX_RATE_PROBLEMS` times per
//! run (in 3D on a faceted cone, its statuses and slip directions handed back to the round
//! one). Only if that fails (no solution reachable: the scene may be ill-posed for its μ) is
//! the entity frozen in its status until the run ends (a `frozen` event names it): the last
//! resort.
//!
//! The bound: after the increment that begins it, every increment of a run that ends at an
//! event switches or freezes at least one entity, so a run has at most 1 + (switches + 1) ×
//! entities + MAX_RATE_PROBLEMS such increments; each run begins more than `SHORT_LOAD`
//! beyond the last one's start, so a stage has at most 1/SHORT_LOAD + 1 runs. Increments that
//! end at no event end at a bound: a requested snapshot time, a plastic window's end or the
//! drift bound. So the procedure always terminates.

use crate::events::Candidate;

/// Rate problems solved per run before the last resort (freezing) takes over.
pub(super) const MAX_RATE_PROBLEMS: usize = 3;
/// The span of a run, as a fraction of the stage's load (see the module text): a millionth,
/// finer than any result resolves (the XDMF series merges times within 1e-6 of the path) and
/// far above round-off.
pub(super) const SHORT_LOAD: f64 = 1e-6;

pub(super) struct AntiCycling {
    n_pairs: usize,
    max_switches: usize,
    /// Switches of each entity (pairs, then elements) in the current run.
    run_switches: Vec<usize>,
    frozen: Vec<bool>,
    /// The frozen flags the current increment was selected with (`load_advanced` clears
    /// `frozen` as the increment switches; its end is checked against these too).
    selected_frozen: Vec<bool>,
    /// Switches over the whole run (to name the busiest entities at the event bound).
    pub switch_count: Vec<usize>,
    rate_problems_in_run: usize,
    pub rate_problems: usize,
    /// The stage fraction where the current run began.
    run_start: f64,
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
        AntiCycling { n_pairs, max_switches, run_switches: vec![0; n], frozen: vec![false; n], selected_frozen: vec![false; n], switch_count: vec![0; n], rate_problems_in_run: 0, rate_problems: 0, run_start: 0.0 }
    }

    /// Frozen pairs and elements.
    pub fn frozen(&self) -> (&[bool], &[bool]) {
        self.frozen.split_at(self.n_pairs)
    }

    fn key(&self, c: &Candidate) -> usize {
        if c.kind.is_element_event() { self.n_pairs + c.entity } else { c.entity }
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

    /// Does the selected increment (`zero_length`; `last` of its stage; ending at stage
    /// fraction `phi`) continue the run: zero-length, or ending within `SHORT_LOAD` of where the
    /// run began? Else it begins a new run where it ends (the caller then calls
    /// `load_advanced`). A stage's first and last increments do not.
    pub fn in_run(&mut self, zero_length: bool, last: bool, phi: f64) -> bool {
        let advance = phi - self.run_start; // negative: a new stage's first increment
        let short = zero_length || (!last && (0.0..=SHORT_LOAD).contains(&advance));
        if !short {
            self.run_start = phi;
        }
        short
    }

    /// An increment that ends beyond the run's `SHORT_LOAD` ends the run.
    pub fn load_advanced(&mut self) {
        self.run_switches.iter_mut().for_each(|c| *c = 0);
        self.frozen.iter_mut().for_each(|f| *f = false);
        self.rate_problems_in_run = 0;
    }

    /// The one-at-a-time rule is cycling (a pair would exceed its switches) and the rate
    /// problem may still be tried in this run.
    pub fn wants_rate_problem(&self, group: &[Candidate]) -> bool {
        self.may_solve_rate_problem() && group.iter().any(|c| !c.kind.is_element_event() && self.run_switches[c.entity] >= self.max_switches)
    }

    /// The rate problem may still be tried in this run.
    pub fn may_solve_rate_problem(&self) -> bool {
        self.rate_problems_in_run < MAX_RATE_PROBLEMS
    }

    pub fn rate_problem_solved(&mut self) {
        self.rate_problems_in_run += 1;
        self.rate_problems += 1;
    }

    /// Decide one event; `seen` marks entities already switched in this increment.
    pub fn admit(&mut self, c: &Candidate, in_run: bool, seen: &mut [bool]) -> Admission {
        let key = self.key(c);
        if seen[key] {
            return Admission::Skip;
        }
        seen[key] = true;
        if in_run && self.run_switches[key] >= self.max_switches {
            self.frozen[key] = true;
            return Admission::Freeze;
        }
        self.count(c, in_run);
        Admission::Apply
    }

    /// Count a switch (also the rate problem's, which are never frozen); `in_run`: inside a run.
    pub fn count(&mut self, c: &Candidate, in_run: bool) {
        let key = self.key(c);
        if in_run {
            self.run_switches[key] += 1;
        }
        self.switch_count[key] += 1;
    }

    /// A slipping pair's held direction turns at an increment's start (3D, `slip_turn`): a
    /// switch of the pair in the run. False once the pair has used its switches in this run:
    /// it keeps its direction, so that a run of turns ends.
    pub fn turn(&mut self, p: usize) -> bool {
        if self.run_switches[p] >= self.max_switches {
            return false;
        }
        self.run_switches[p] += 1;
        self.switch_count[p] += 1;
        true
    }

    pub fn n_entities(&self) -> usize {
        self.frozen.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::EventKind;

    const MAX_SWITCHES: usize = 4;

    /// One closure of pair 0 per increment ending at each φ of `ends` (switched as
    /// `switch_statuses` does): the admission of each.
    fn closures(ends: &[f64]) -> Vec<&'static str> {
        let mut cycles = AntiCycling::new(1, 0, MAX_SWITCHES);
        let close = Candidate { scale: 1e-3, entity: 0, kind: EventKind::Close, direction: 0 };
        ends.iter()
            .map(|&phi| {
                let in_run = cycles.in_run(false, false, phi);
                if !in_run {
                    cycles.load_advanced();
                }
                match cycles.admit(&close, in_run, &mut [false]) {
                    Admission::Apply => "apply",
                    Admission::Freeze => "freeze",
                    Admission::Skip => "skip",
                }
            })
            .collect()
    }

    /// A Zeno chain as the 45° Mindlin sphere ran one (a pair closing again after increments
    /// shrinking threefold from 1.2e-5 of the stage, converging at φ*): every increment
    /// advances, but once the chain's whole remaining length L 3^-k is within SHORT_LOAD its
    /// increments are one run, and the pair is stopped after its switches there. The run
    /// begins at the first k = m with L 3^-m ≤ SHORT_LOAD (the increment before it, 2 L 3^-m,
    /// is longer than SHORT_LOAD for this L), so the closure at k = m + MAX_SWITCHES + 1 is
    /// frozen (counting zero-length increments only, none would be).
    #[test]
    fn a_chain_of_ever_shorter_increments_is_one_run() {
        let (phi_star, length) = (0.4, 1.8e-5);
        let ends: Vec<f64> = (0..40).map(|k| phi_star - length * 3f64.powi(-k)).collect();
        let m = (length / SHORT_LOAD).log(3.0).ceil() as i32;
        assert!(2.0 * length * 3f64.powi(-m) > SHORT_LOAD);
        let seen = closures(&ends);
        let frozen = seen.iter().position(|&a| a == "freeze").expect("the chain is stopped");
        assert_eq!(frozen, m as usize + MAX_SWITCHES + 1, "{seen:?}");
        assert!(seen[..frozen].iter().all(|&a| a == "apply"));
    }

    /// Increments longer than SHORT_LOAD each begin a run: a pair may switch at every one.
    #[test]
    fn increments_longer_than_the_span_each_begin_a_run() {
        let ends: Vec<f64> = (1..50).map(|k| k as f64 * 1.5 * SHORT_LOAD).collect();
        assert!(closures(&ends).iter().all(|&a| a == "apply"));
    }

    /// A run is measured from where it began, not increment by increment: short increments that
    /// add up to more than SHORT_LOAD end it.
    #[test]
    fn a_run_spans_at_most_its_load() {
        let mut cycles = AntiCycling::new(1, 0, MAX_SWITCHES);
        let step = 0.4 * SHORT_LOAD;
        let runs: Vec<bool> = (1..=6).map(|k| cycles.in_run(false, false, k as f64 * step)).collect();
        // begins at 0.4 (from the stage's start 0: in the first run), 0.8; 1.2 > 1 ends it and
        // begins one at 1.2: 1.6, 2.0 in it, 2.4 ends it.
        assert_eq!(runs, [true, true, false, true, true, false]);
        // a new stage's first increment begins a run; a stage's last increment ends one; a
        // zero-length increment continues it wherever it ends
        assert!(!cycles.in_run(false, false, 1e-9));
        assert!(cycles.in_run(true, false, 1e-9));
        assert!(!cycles.in_run(false, true, 1e-9 + 0.1 * SHORT_LOAD));
    }
}
