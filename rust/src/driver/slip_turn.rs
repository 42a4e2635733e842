//! Friction in space: a slipping pair's held direction and its turn (rust/src/contact.rs's
//! module text).
//!
//! In 3D a slipping pair carries λ_t = μ λ_n e with e held along an increment, so the trial
//! stays linear. Within one linear increment the slip rate's direction is constant; between
//! increments it may turn. At an increment's start, a slipping pair whose trial slip rate
//! differs from −e by more than `slip_turn` has e turned to it at zero length (λ_t rotates at
//! fixed size, a force jump the equilibrium correction at fixed load rebalances) and the trial
//! is solved again; each turn is a zero-length switch of the pair for the anti-cycling rule, so
//! a run of turns ends. A slip rate that points against −e (more than a right angle) is the
//! slip → stick event's (`events`), not a turn.

use super::anticycling::AntiCycling;
use super::checks::Correction;
use super::engine::Engine;
use super::plasticity::correct_at_fixed_load;
use super::recording::Recorder;
use super::state::{State, TrialIncrement};
use super::selection::trial_of;
use crate::contact::Status;
use crate::events::slip_rate;
use crate::error::Result;

/// Turn the held direction of every slipping pair whose trial slip rate has turned by more
/// than `slip_turn` from −e (3D), and rebalance the state at its load. Returns whether any
/// turned: the caller solves the trial again. `correction`: the size of the last equilibrium
/// correction, which the contact checks allow for.
pub(super) fn turn_slip_directions(eng: &mut Engine, state: &mut State, trial: &TrialIncrement, cycles: &mut AntiCycling, rec: &mut Recorder, correction: &mut Correction) -> Result<bool> {
    let problem = &eng.problem;
    if problem.dim != 3 {
        return Ok(false);
    }
    let cos_limit = problem.model.options.slip_turn.cos();
    let mut turned = false;
    for p in 0..problem.pairs.len() {
        if !matches!(state.status[p], Status::Slip { direction } if direction != 0) {
            continue;
        }
        let pair = &problem.pairs[p];
        let rate = slip_rate(pair, &trial_of(trial), p);
        let size = rate[0].hypot(rate[1]);
        if size <= trial.noise.displacement {
            continue;
        }
        let e = state.slip_dir[p];
        let cos = -(e[0] * rate[0] + e[1] * rate[1]) / size;
        if cos < 0.0 || cos >= cos_limit || !cycles.turn(p) {
            continue; // a reversal (slip → stick), aligned, or out of turns
        }
        let e = rate.map(|r| -r / size);
        state.slip_dir[p] = e;
        let ln = state.lambda_n[p];
        (state.lambda_t[p], state.lambda_t2[p]) = (pair.mu * ln * e[0], pair.mu * ln * e[1]);
        turned = true;
    }

    if turned {
        let phi = state.load_fraction;
        let c = correct_at_fixed_load(eng, state, phi, None)?;
        c.events.iter().for_each(|e| rec.correction_event(e, phi));
        *correction = c.size;
    }
    Ok(turned)
}
