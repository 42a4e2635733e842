//! Where the engine's time goes: scoped timers over the phases of `Timings`.
//!
//! `Clock::time` starts a phase and the returned guard ends it when it drops. A phase timed
//! inside another pauses it: each second counts once, in the innermost phase, so the phases
//! partition the time they cover (a refactorization inside an equilibrium correction counts
//! as factorization, not as correction). `timings` reports `events` with the phases of the
//! event work timed inside it (the small dense systems, stress integration, corrections).

use crate::records::Timings;
use std::cell::{Cell, RefCell};
use std::time::Instant;

/// A phase of the run, as `Timings` reports them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Phase {
    /// Set-up and every assembly of K.
    Assembly,
    Factorization,
    /// The contact flexibility read from a factor.
    Flexibility,
    /// The triangular solves of the trials for the remaining load and of the stage loads.
    Solves,
    /// The small dense contact systems.
    Dense,
    /// An increment's event work after its trial.
    Events,
    /// Low-rank updates of the factor.
    LowRank,
    /// Stress integration of plastic elements.
    Integration,
    /// Equilibrium corrections after integrated increments.
    Corrections,
}

const PHASES: usize = 9;

/// The seconds of every phase, and the phases running now (innermost last).
pub(super) struct Clock {
    own: [Cell<f64>; PHASES],
    running: RefCell<Vec<Phase>>,
    /// When the innermost running phase started or resumed.
    since: Cell<Instant>,
}

/// A running phase; it ends when this drops (guards drop in reverse order of their start).
#[must_use = "the phase ends when the timer drops"]
pub(super) struct Timer<'c> {
    clock: &'c Clock,
}

impl Clock {
    pub fn new() -> Self {
        Clock {
            own: Default::default(),
            running: RefCell::new(Vec::new()),
            since: Cell::new(Instant::now()),
        }
    }

    /// Time `phase` (pausing the phase it runs in) until the returned timer drops.
    pub fn time(&self, phase: Phase) -> Timer<'_> {
        self.charge_innermost();
        self.running.borrow_mut().push(phase);
        Timer { clock: self }
    }

    /// The time since the innermost phase started or resumed, to that phase.
    fn charge_innermost(&self) {
        let now = Instant::now();
        if let Some(&phase) = self.running.borrow().last() {
            let cell = &self.own[phase as usize];
            cell.set(cell.get() + (now - self.since.get()).as_secs_f64());
        }
        self.since.set(now);
    }

    fn seconds(&self, phase: Phase) -> f64 {
        self.own[phase as usize].get()
    }

    /// The record of the run's timings; `solve_pair` is the measured unit (`seconds`).
    pub fn timings(&self, solve_pair: f64) -> Timings {
        use Phase::*;
        let s = |p| self.seconds(p);
        Timings {
            assembly: s(Assembly),
            factorization: s(Factorization),
            flexibility: s(Flexibility),
            solves: s(Solves),
            dense: s(Dense),
            events: s(Events) + s(Dense) + s(Integration) + s(Corrections),
            low_rank: s(LowRank),
            integration: s(Integration),
            corrections: s(Corrections),
            solve_pair,
        }
    }
}

impl Drop for Timer<'_> {
    fn drop(&mut self) {
        self.clock.charge_innermost();
        self.clock.running.borrow_mut().pop();
    }
}

/// `f`'s result and the seconds it took: a measurement (the timing unit), not a phase.
pub(super) fn seconds<R>(f: impl FnOnce() -> R) -> (R, f64) {
    let start = Instant::now();
    let r = f();
    (r, start.elapsed().as_secs_f64())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nested phases partition the time: the outer phase's own time excludes the inner one's,
    /// and `events` adds the event work timed inside it. (Busy loops of a few ms; the test
    /// checks the bookkeeping, which holds for any durations, not the clock's resolution.)
    #[test]
    fn an_inner_phase_pauses_the_outer_one() {
        let clock = Clock::new();
        let spin = |ms: u64| {
            let t = Instant::now();
            while t.elapsed().as_millis() < ms as u128 {}
        };
        let (_, total) = seconds(|| {
            let _events = clock.time(Phase::Events);
            spin(2);
            {
                let _dense = clock.time(Phase::Dense);
                spin(3);
            }
            spin(1);
        });
        let (events, dense) = (clock.seconds(Phase::Events), clock.seconds(Phase::Dense));
        assert!(dense >= 0.003 && events >= 0.003, "dense {dense}, events' own {events}");
        assert!(
            events + dense <= total,
            "the parts exceed the whole: {events} + {dense} > {total}"
        );
        let t = clock.timings(0.0);
        assert_eq!((t.dense, t.events), (dense, events + dense));
    }
}
