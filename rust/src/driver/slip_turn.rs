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
//! zero force, the pair would slip again at once, `Coulomb::slip_onset_scale`).
//!
//! Where a solve presses such a pair before an increment's trial comes, it takes e from that
//! solve (`slip_direction`).
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
use super::recording::Recorder;
use super::slip_direction::{hold_direction, slip_of, slipping};
use super::state::{State, TrialIncrement};
use super::switching::{contact_forces, jumps_kept, keep_jumps};
use crate::dim::Dim;
use crate::error::Result;

/// Direct every slipping 3D pair that has no normal force to hold its direction by (or no
/// direction yet) against its trial slip rate, where that turned by more than `slip_turn`
/// from −e. Returns whether any turned: the caller solves the trial again. A pair that had a
/// normal force but no direction (a slip rate at round-off when it began) gets its whole
/// friction force here, a jump rebalanced at its load; `correction`: the size of the last
/// equilibrium correction, which the contact checks allow for.
pub(super) fn direct_unloaded_slips<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    trial: &TrialIncrement,
    cycles: &mut AntiCycling,
    rec: &mut Recorder,
    correction: &mut Correction,
) -> Result<bool> {
    let problem = &eng.problem;
    if !D::SLIP_TURNS {
        return Ok(false); // a slip along a line has no direction to turn
    }
    let cos_limit = problem.model.options.slip_turn.cos();
    let before = jumps_kept(eng, state).then(|| contact_forces(state));
    let (mut turned, mut jump) = (false, 0.0f64);
    for p in 0..problem.pairs.len() {
        let e = state.slip_dir(p);
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
