//! Advancing the state to the event (paper §4 step 5, eqs. 58–62).

use super::clock::Phase;
use super::engine::Engine;
use super::plasticity::{integrate_stresses, place_integrated};
use super::problem::Problem;
use super::selection::Selection;
use super::state::{IncrementStart, State, TrialIncrement};
use super::switching::{contact_forces, jumps_kept, keep_jumps};
use crate::contact::Status;
use crate::dim::Dim;
use crate::model::EventKind;

/// u, σ, λ += S × trial (eqs. 58–61), the stresses of plastic elements (and, in a plastic
/// window, of those that yield inside) integrated (`plasticity`); slipping pairs on the
/// Coulomb cone (eq. 62). Returns the increment's start when stresses were integrated: it then
/// needs an equilibrium correction, and tells what yielded inside.
pub(super) fn to_event<D: Dim>(
    eng: &Engine<D>,
    state: &mut State<D>,
    trial: &TrialIncrement,
    sel: &Selection,
) -> Option<IncrementStart> {
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
    // Put back on its facet, a pair a correction left beyond it has a force jump; in the
    // reduced space it is kept to be rebalanced (`State::jumps`), as a switch's is.
    let before = jumps_kept(eng, state).then(|| contact_forces(state));
    project_onto_cone(&eng.problem, state);
    if let Some(before) = before {
        keep_jumps(state, &before);
    }
    start
}

/// Slipping pairs onto their friction force (eq. 62; `Problem::slip_force`: in space on their
/// facet, the cross force kept within its band), round-off removed. Returns the largest change:
/// more than round-off where the last correction left a slipping pair off its cone.
pub(super) fn project_onto_cone<D: Dim>(problem: &Problem<D>, state: &mut State<D>) -> f64 {
    let mut largest: f64 = 0.0;
    for p in 0..state.status.len() {
        if let Status::Slip { .. } = state.status[p] {
            let now = state.lambda_t_of(p);
            let on_cone = problem.slip_force(state, p, now);
            largest = largest.max((on_cone[0] - now[0]).hypot(on_cone[1] - now[1]));
            state.set_lambda_t(p, on_cone);
        }
    }
    largest
}

#[cfg(test)]
mod tests {
    use super::super::anticycling::AntiCycling;
    use super::super::clock::Clock;
    use super::super::scenes::*;
    use super::super::selection::select;
    use super::super::stepping::Stepping;
    use super::super::switching::switch;
    use super::super::trial::remaining_load;
    use super::*;

    /// Round-off of a few operations on O(1) numbers (~1e-15 each).
    const ROUND_OFF: f64 = 1e-12;

    /// Advanced to the closure of the wall's gap (S_c = g E / (ν q)): the gap is g − S Δu_x = 0
    /// (eq. 58), u = S Δu (eq. 59), the open pair carries nothing (eq. 60), and with nothing
    /// integrated (elastic) no correction is needed.
    #[test]
    fn advancing_to_a_closure_closes_the_gap() {
        let (q, g) = (2.0, 1e-4);
        let m = poisson_wall(q, g);
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let cycles = AntiCycling::new(1, 0, 4);
        let (trial, _) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
        let sel =
            select(&eng.problem, &state, &trial, &cycles, f64::INFINITY, Stepping::EventByEvent);
        assert!(to_event(&eng, &mut state, &trial, &sel).is_none());
        let s = g * E / (NU * q);
        assert!(
            eng.problem.gap(&state, 0).abs() < ROUND_OFF * g,
            "gap {}",
            eng.problem.gap(&state, 0)
        );
        // reduced space: u over the pair's DOFs (node 2: x, y)
        assert!(
            (state.u[0] - s * NU * q / E).abs() < ROUND_OFF * g
                && (state.u[1] + s * q / E).abs() < ROUND_OFF * g
        );
        assert!((state.load_fraction - s).abs() < ROUND_OFF && state.lambda_n[0] == 0.0);
        switch(&eng.problem, &mut state, &sel.group[0]);
        assert!(state.status[0].is_closed());
    }

    /// A stuck pair advanced to its slip: λ_n = N held, λ_t = S_f T = μ N on the cone (eqs.
    /// 60–61); switched, it slips along +x with λ_t = −d μ λ_n (eq. 62, d = −1), and a λ_t the
    /// last correction moved off the cone is put back on it, the jump reported.
    #[test]
    fn advancing_a_stuck_pair_to_its_slip_puts_it_on_the_cone() {
        let (n, t, mu) = (3.0, 1.0, 0.2);
        let m = pressed_then_sheared(n, t, mu);
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let cycles = AntiCycling::new(1, 0, 4);
        let (press, _) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
        state.advance(&press, 1.0);
        eng.begin_stage(1, &mut state);
        let (shear, _) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
        let sel =
            select(&eng.problem, &state, &shear, &cycles, f64::INFINITY, Stepping::EventByEvent);
        to_event(&eng, &mut state, &shear, &sel);
        assert!(
            (state.lambda_n[0] - n).abs() < ROUND_OFF * n
                && (state.lambda_t[0] - mu * n).abs() < ROUND_OFF * n
        );
        switch(&eng.problem, &mut state, &sel.group[0]);
        assert_eq!(state.status[0], Status::Slip { direction: -1 });
        assert!((state.lambda_t[0] - mu * n).abs() < ROUND_OFF * n);
        state.lambda_t[0] = 0.9 * mu * n;
        let jump = project_onto_cone(&eng.problem, &mut state);
        assert!(
            (jump - 0.1 * mu * n).abs() < ROUND_OFF * n
                && (state.lambda_t[0] - mu * n).abs() < ROUND_OFF * n
        );
    }
}
