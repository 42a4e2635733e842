//! Friction in space: the direction of a pair slipping at zero normal force (rust/src/contact.rs's
//! module text).
//!
//! A slipping 3D pair holds a direction e and slips on the facet of the round cone at e; its
//! facet turns with its friction force as an ordinary event (`EventKind::SlipTurn`). A pair
//! that slips at zero normal force (one that slips as it closes) has no force to take e from:
//! its first trial has no friction force (e = 0) and no cross row, and at an increment's start
//! it takes e against its trial's slip rate, when that differs from e by more than
//! `slip_turn`, and the trial is solved again. With λ_n at round-off this moves no force
//! (λ_t = μ λ_n e), so there is nothing to rebalance; each such turn is a zero-length switch of
//! the pair for the anti-cycling rule, so a run of them ends. A slip rate that points against
//! −e is a turn too: with no normal force there is no friction force to stick with (stuck at
//! zero force, the pair would slip again at once, `events::onto_round_cone`).
//!
//! Where a solve loads such a pair before any increment's trial comes (the equilibrium
//! correction at fixed load, a plastic window's contact sub-steps), it takes e against that
//! solve's own slip rate and the solve is repeated (`direct_new_slips`): else it would carry
//! λ_n with no friction force until the next increment (measured on an elastoplastic block
//! under a Vickers pyramid, μ = 0.3: λ_n = 7.6e-3, reactions ~40, with λ_t = 0).
//!
//! A body whose pairs all begin to slip at zero force (a block pressed on a plane at low μ,
//! its pairs slipping outwards from the first instant) has nothing that holds its turn about
//! the normal in that first trial: no pair has a direction, so none a cross row. Nothing
//! turns it either (no load, no friction force along it): the trial holds such an idle motion
//! still (`restraint::check_restrained`), and its slip rates give the pairs their directions.

use super::anticycling::AntiCycling;
use super::checks::Correction;
use super::engine::Engine;
use super::plasticity::correct_at_fixed_load;
use super::problem::Problem;
use super::recording::Recorder;
use super::selection::trial_of;
use super::state::{State, TrialIncrement};
use super::switching::{contact_forces, jumps_kept, keep_jumps};
use crate::contact::Status;
use crate::events::slip_rate;
use crate::error::Result;

/// Direct every slipping 3D pair that has no normal force to hold its direction by (or no
/// direction yet) against its trial slip rate, where that turned by more than `slip_turn`
/// from −e. Returns whether any turned: the caller solves the trial again. A pair that had a
/// normal force but no direction (a slip rate at round-off when it began) gets its whole
/// friction force here, a jump rebalanced at its load; `correction`: the size of the last
/// equilibrium correction, which the contact checks allow for.
pub(super) fn direct_unloaded_slips(eng: &mut Engine, state: &mut State, trial: &TrialIncrement, cycles: &mut AntiCycling, rec: &mut Recorder, correction: &mut Correction) -> Result<bool> {
    let problem = &eng.problem;
    if problem.dim != 3 {
        return Ok(false);
    }
    let cos_limit = problem.model.options.slip_turn.cos();
    let before = jumps_kept(eng).then(|| contact_forces(state));
    let (mut turned, mut jump) = (false, 0.0f64);
    for p in 0..problem.pairs.len() {
        let e = state.slip_dir[p];
        let unloaded = state.lambda_n[p] <= problem.scales.force_noise || e == [0.0; 2];
        if !unloaded || !slipping(state, p) {
            continue;
        }
        let Some((rate, size)) = slip_of(problem, trial, p) else { continue };
        let cos = -(e[0] * rate[0] + e[1] * rate[1]) / size;
        if cos >= cos_limit || !cycles.turn(p) {
            continue; // aligned, or out of turns
        }
        jump = jump.max(hold_direction(problem, state, p, rate.map(|r| -r / size)));
        turned = true;
    }
    if let Some(before) = before {
        keep_jumps(state, &before);
    }
    if jump > eng.problem.scales.force_noise {
        let phi = state.load_fraction;
        let c = correct_at_fixed_load(eng, state, phi, None)?;
        c.events.iter().for_each(|e| rec.correction_event(e, phi));
        *correction = c.size;
    }
    Ok(turned)
}

/// Every slipping 3D pair that has no direction yet (it began to slip at zero force) and that
/// `inc` presses (λ_n + Δλ_n above the force noise) takes the direction against its slip rate
/// in `inc`: the solve of an equilibrium correction or of a plastic window's contact sub-step,
/// where no increment's trial comes between the switch and the force the pair then carries
/// (`direct_unloaded_slips` is that trial's turn). One `inc` leaves unloaded waits for that
/// trial: a correction's slip rate there answers another pair's jump, not the load. A pair
/// takes its direction once, so it needs no anti-cycling turn. Returns whether any did (the
/// caller solves `inc` again) and the force that moved (μ λ_n of a pair already loaded), kept
/// as a switch's jump is (`keep_jumps`).
pub(super) fn direct_new_slips(eng: &Engine, state: &mut State, inc: &TrialIncrement) -> (bool, f64) {
    let problem = &eng.problem;
    if problem.dim != 3 {
        return (false, 0.0);
    }
    let before = jumps_kept(eng).then(|| contact_forces(state));
    let (mut directed, mut jump) = (false, 0.0f64);
    for p in 0..problem.pairs.len() {
        let pressed = state.lambda_n[p] + inc.dlambda_n[p] > problem.scales.force_noise;
        if state.slip_dir[p] != [0.0; 2] || !slipping(state, p) || !pressed {
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
fn slipping(state: &State, p: usize) -> bool {
    matches!(state.status[p], Status::Slip { direction } if direction != 0)
}

/// Pair p's slip rate in `inc` and its size; None while that is round-off.
fn slip_of(problem: &Problem, inc: &TrialIncrement, p: usize) -> Option<([f64; 2], f64)> {
    let rate = slip_rate(&problem.pairs[p], &trial_of(inc), p);
    let size = rate[0].hypot(rate[1]);
    (size > inc.noise.displacement).then_some((rate, size))
}

/// Pair p slips along −e from here: its friction force is μ λ_n e. Returns how far it moved.
fn hold_direction(problem: &Problem, state: &mut State, p: usize, e: [f64; 2]) -> f64 {
    state.slip_dir[p] = e;
    let mu_ln = problem.pairs[p].mu * state.lambda_n[p];
    let moved = (mu_ln * e[0] - state.lambda_t[p]).hypot(mu_ln * e[1] - state.lambda_t2[p]);
    (state.lambda_t[p], state.lambda_t2[p]) = (mu_ln * e[0], mu_ln * e[1]);
    moved
}
