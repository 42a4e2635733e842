//! Advancing the state to the event (paper §4 step 5, eqs. 58–62).

use super::clock::Phase;
use super::engine::Engine;
use super::plasticity::{integrate_stresses, place_integrated};
use super::problem::Problem;
use super::selection::Selection;
use super::state::{IncrementStart, State, TrialIncrement};
use crate::contact::Status;
use crate::model::EventKind;

/// u, σ, λ += S × trial (eqs. 58–61), the stresses of plastic elements (and, in a plastic
/// window, of those that yield inside) integrated (`plasticity`); slipping pairs on the
/// Coulomb cone (eq. 62). Returns the increment's start when stresses were integrated: it then
/// needs an equilibrium correction, and tells what yielded inside.
pub(super) fn to_event(eng: &Engine, state: &mut State, trial: &TrialIncrement, sel: &Selection) -> Option<IncrementStart> {
    let integrated = {
        let _t = eng.clock.time(Phase::Integration);
        integrate_stresses(&eng.problem, state, trial, sel)
    };
    let mut start = (!integrated.is_empty()).then(|| IncrementStart::of(state));
    state.advance(trial, sel.scale);
    state.load_fraction = sel.phi;
    if let Some(start) = &mut start {
        place_integrated(state, &integrated, start);
    }
    // Elements that reach their surface at this increment's end are plastic for the
    // correction already (their tangent then comes with the others: one update per step).
    for c in sel.group.iter().filter(|c| c.kind == EventKind::Yield) {
        state.plastic[c.entity] = true;
    }
    project_onto_cone(&eng.problem, state);
    start
}

/// λ_t = −d μ λ_n for slipping pairs (eq. 62; round-off removed). Returns the largest change:
/// more than round-off where the last correction left a slipping pair off its cone.
pub(super) fn project_onto_cone(problem: &Problem, state: &mut State) -> f64 {
    let mut largest: f64 = 0.0;
    for (p, st) in state.status.iter().enumerate() {
        if let Status::Slip { .. } = st {
            let on_cone = problem.pairs[p].slip_ratio(*st) * state.lambda_n[p];
            largest = largest.max((on_cone - state.lambda_t[p]).abs());
            state.lambda_t[p] = on_cone;
        }
    }
    largest
}
