//! Friction in space: the direction a pair that began to slip at zero force takes from a solve
//! that presses it (rust/src/contact.rs's module text; `slip_turn` is the turn at an
//! increment's trial).
//!
//! A slipping 3D pair holds a direction e, taken from its friction force when it starts to
//! slip; one that starts at zero force (it slips as it closes) has none, and carries no
//! friction force until a solve gives it a slip rate. Where a solve presses such a pair before
//! an increment's trial comes (the equilibrium correction at fixed load, a plastic window's
//! contact sub-steps), it takes e against that solve's own slip rate and the solve is
//! repeated: else it would carry λ_n with no friction force until the next increment
//! (measured on an elastoplastic block under a Vickers pyramid, μ = 0.3: λ_n = 7.6e-3,
//! reactions ~40, with λ_t = 0).

use super::engine::Engine;
use super::problem::Problem;
use super::selection::trial_of;
use super::state::{State, TrialIncrement};
use super::switching::{contact_forces, jumps_kept, keep_jumps};
use crate::contact::Status;
use crate::dim::Dim;
use crate::events::slip_rate;

/// Every slipping 3D pair that has no direction yet (it began to slip at zero force) and that
/// `inc` presses (λ_n + Δλ_n above the force noise) takes the direction against its slip rate
/// in `inc`: the solve of an equilibrium correction or of a plastic window's contact sub-step,
/// where no increment's trial comes between the switch and the force the pair then carries
/// (`slip_turn::direct_unloaded_slips` is that trial's turn). One `inc` leaves unloaded waits for that
/// trial: a correction's slip rate there answers another pair's jump, not the load. A pair
/// takes its direction once, so it needs no anti-cycling turn. Returns whether any did (the
/// caller solves `inc` again) and the force that moved (μ λ_n of a pair already loaded), kept
/// as a switch's jump is (`keep_jumps`).
pub(super) fn direct_new_slips<D: Dim>(
    eng: &Engine<D>,
    state: &mut State<D>,
    inc: &TrialIncrement,
) -> (bool, f64) {
    let problem = &eng.problem;
    if !D::SLIP_TURNS {
        return (false, 0.0); // a slip along a line has its direction from its sense
    }
    let before = jumps_kept(eng, state).then(|| contact_forces(state));
    let (mut directed, mut jump) = (false, 0.0f64);
    for p in 0..problem.pairs.len() {
        let pressed = state.lambda_n[p] + inc.dlambda_n[p] > problem.scales.force_noise;
        if state.slip_dir(p) != [0.0; 2] || !slipping(state, p) || !pressed {
            continue;
        }
        if let Some((rate, size)) = slip_of(problem, inc, p) {
            jump = jump.max(hold_direction(problem, state, p, rate.map(|r| -r / size)));
            directed = true;
        }
    }
    if let Some(before) = before {
        keep_jumps(state, &before);
    }
    (directed, jump)
}

/// Whether pair p slips (with a sense: `Status::Slip`).
pub(super) fn slipping<D: Dim>(state: &State<D>, p: usize) -> bool {
    matches!(state.status[p], Status::Slip { direction } if direction != 0)
}

/// Pair p's slip rate in `inc` and its size; None while that is round-off.
pub(super) fn slip_of<D: Dim>(
    problem: &Problem<D>,
    inc: &TrialIncrement,
    p: usize,
) -> Option<([f64; 2], f64)> {
    let rate = slip_rate(&problem.pairs[p], &trial_of(inc), p);
    let size = rate[0].hypot(rate[1]);
    (size > inc.noise.displacement).then_some((rate, size))
}

/// Pair p slips along −e from here: its friction force is μ λ_n e. Returns how far it moved.
pub(super) fn hold_direction<D: Dim>(
    problem: &Problem<D>,
    state: &mut State<D>,
    p: usize,
    e: [f64; 2],
) -> f64 {
    state.set_facet(p, e, false);
    let mu_ln = problem.pairs[p].friction.capacity(state.lambda_n[p]);
    let moved = (mu_ln * e[0] - state.lambda_t[p]).hypot(mu_ln * e[1] - state.lambda_t_of(p)[1]);
    state.set_lambda_t(p, [mu_ln * e[0], mu_ln * e[1]]);
    moved
}
