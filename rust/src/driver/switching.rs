//! Switching the statuses of the events that happen (paper §4 step 6), under the anti-cycling
//! rule, with the rate problem where the one-at-a-time rule cycles or a body rests on friction
//! alone; and the status change one event makes.

use super::anticycling::{Admission, AntiCycling};
use super::engine::Engine;
use super::problem::Problem;
use super::rate_problem::{hold_slip_directions, solve_rate_problem};
use super::recording::Recorder;
use super::restraint::{hold, Hold};
use super::selection::Selection;
use super::state::State;
use super::trial::Solve;
use crate::contact::Status;
use crate::dim::Dim;
use crate::events::Candidate;
use crate::model::EventKind;

/// Switch the statuses of the selected events under the anti-cycling rule: when the
/// one-at-a-time rule cycles, the rate problem (for the load `what` solves for) sets the
/// critical pairs' statuses together. It does too when the switches leave a body on friction
/// alone, every closed pair slipping (`restraint`: where its slip changes sense, a pair
/// sticks). Returns the largest force jump a switch made (see `switch`; in the reduced space
/// it is kept to be rebalanced: `keep_jumps`).
pub(super) fn switch_statuses<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    sel: &Selection,
    cycles: &mut AntiCycling,
    rec: &mut Recorder,
    what: Solve,
) -> f64 {
    let before = jumps_kept(eng, state).then(|| contact_forces(state));
    let jump = switch_group(eng, state, sel, cycles, rec, what);
    if let Some(before) = before {
        keep_jumps(state, &before);
    }
    jump
}

fn switch_group<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    sel: &Selection,
    cycles: &mut AntiCycling,
    rec: &mut Recorder,
    what: Solve,
) -> f64 {
    let mut jump: f64 = 0.0;
    let zero_length = sel.zero_length();
    cycles.increment_selected();
    if !zero_length {
        cycles.load_advanced();
    }
    if zero_length && cycles.wants_rate_problem(&sel.group) {
        crate::trace!(
            "rate problem at phi {}: cycling one at a time ({} events in the group)",
            sel.phi,
            sel.group.len()
        );
        if let Some(jump) = switch_by_rate_problem(eng, state, cycles, rec, sel.phi, what) {
            return jump;
        }
    }
    let mut seen = vec![false; cycles.n_entities()];
    for c in &sel.group {
        match cycles.admit(c, zero_length, &mut seen) {
            Admission::Skip => {}
            Admission::Freeze => rec.event(
                c,
                if c.kind.is_element_event() {
                    EventKind::FrozenElement
                } else {
                    EventKind::Frozen
                },
                sel.phi,
            ),
            Admission::Apply => {
                jump = jump.max(switch(&eng.problem, state, c));
                rec.event(c, c.kind, sel.phi);
            }
        }
    }
    let slip_or_separation =
        sel.group.iter().any(|c| matches!(c.kind, EventKind::StickToSlip | EventKind::Separate));
    if slip_or_separation
        && cycles.may_solve_rate_problem()
        && matches!(hold(&eng.problem, &eng.loads, state, &rec.events), Hold::OnFriction)
    {
        crate::trace!("rate problem at phi {}: a body rests on friction alone", sel.phi);
        jump =
            jump.max(switch_by_rate_problem(eng, state, cycles, rec, sel.phi, what).unwrap_or(0.0));
    }
    jump
}

/// Unit directions whose dot product is within this of 1 are the same (round-off of Lemke's
/// solution and of a sine and cosine).
const SAME_DIRECTION: f64 = 1e-9;

/// The statuses of the rate problem's solution, switched and recorded at φ; None when it has
/// none or changes nothing.
fn switch_by_rate_problem<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    cycles: &mut AntiCycling,
    rec: &mut Recorder,
    phi: f64,
    what: Solve,
) -> Option<f64> {
    let sol = solve_rate_problem(eng, state, what)?;
    let mut changes: Vec<_> = (0..sol.status.len())
        .flat_map(|p| transitions(p, state.status[p], sol.status[p]))
        .collect();
    // a pair that keeps slipping, elsewhere than on its own facet or vertex, turns to the rate
    // problem's (one that keeps its own is no event)
    let moved = |p: usize| {
        sol.slip_dir[p].is_some_and(|(e, vertex)| {
            vertex != state.at_vertex(p)
                || e[0] * state.slip_dir(p)[0] + e[1] * state.slip_dir(p)[1] < 1.0 - SAME_DIRECTION
        })
    };
    changes.extend(
        (0..sol.status.len()).filter(|&p| state.status[p] == sol.status[p] && moved(p)).map(|p| {
            Candidate {
                scale: 0.0,
                entity: p,
                kind: EventKind::SlipTurn,
                direction: 0,
                toward: [0.0; 2],
            }
        }),
    );
    if changes.is_empty() {
        return None;
    }
    cycles.rate_problem_solved();
    let mut jump: f64 = 0.0;
    for c in &changes {
        cycles.count(c, true);
        if c.kind != EventKind::SlipTurn {
            jump = jump.max(switch(&eng.problem, state, c)); // a turn's is the hand-back's
        }
        rec.event(c, c.kind, phi);
    }
    Some(jump.max(hold_slip_directions(&eng.problem, state, &sol)))
}

/// Apply one event's status change and the forces it sets. Returns the force it moved: the
/// change of λ_t of a slip (a pair the equilibrium correction moved off the cone is put back
/// on it) or of a facet's turn (its radial jump), the forces a separation drops (one applied
/// with a tie, before its own scale, still carries λ_n up to tie_tol × its rate): a force jump
/// that the caller rebalances.
pub(super) fn switch<D: Dim>(problem: &Problem<D>, state: &mut State<D>, c: &Candidate) -> f64 {
    let p = c.entity;
    if let Some(space) =
        state.space_mut().filter(|_| !c.kind.is_element_event() && c.kind != EventKind::SlipTurn)
    {
        space.facet_laid[p] = false;
    }
    let before = if c.kind.is_element_event() { [0.0; 2] } else { state.lambda_t_of(p) };
    let dropped = if c.kind == EventKind::Separate {
        state.lambda_n[p].abs().max(state.lambda_t[p].abs()).max(state.lambda_t_of(p)[1].abs())
    } else {
        0.0
    };
    match c.kind {
        EventKind::Close => {
            state.status[p] = problem.pairs[p].closed_status();
            state.set_facet(p, [0.0; 2], false); // the round cone until it slips
            state.stick_at(p, [problem.rtd(state, p), problem.rtd2(state, p)]);
        }
        EventKind::Separate => {
            state.status[p] = Status::Open;
            state.set_facet(p, [0.0; 2], false);
            state.lambda_n[p] = 0.0;
            state.set_lambda_t(p, [0.0; 2]);
        }
        EventKind::StickToSlip => {
            state.status[p] = Status::Slip { direction: c.direction };
            let now = state.lambda_t_of(p);
            if D::SLIP_TURNS {
                let (e, vertex) = onset_facet(problem, state, p, now, c.toward);
                state.set_facet(p, e, vertex);
            }
            state.set_lambda_t(p, problem.slip_force(state, p, now));
        }
        EventKind::SlipToStick => {
            // stuck where it is (in space, on its facet's band: no force jump)
            state.status[p] = Status::Stick;
            state.stick_at(p, [problem.rtd(state, p), problem.rtd2(state, p)]);
        }
        EventKind::SlipTurn => turn_facet(problem, state, p, c.direction),
        EventKind::Yield => state.plastic[p] = true,
        EventKind::Unload => state.plastic[p] = false,
        EventKind::Frozen | EventKind::FrozenElement => {}
    }
    match c.kind {
        EventKind::StickToSlip | EventKind::SlipTurn | EventKind::SlipToStick
            if state.space().is_some() =>
        {
            (state.lambda_t[p] - before[0]).hypot(state.lambda_t_of(p)[1] - before[1])
        }
        EventKind::StickToSlip => (state.lambda_t[p] - before[0]).abs(),
        _ => dropped,
    }
}

/// The facet (or vertex) a 3D pair starts to slip on, from its force there: the side of its
/// polygon it reached (`coulomb`), or on the round cone the facet tangent at its force's direction,
/// which lays its polygon; at zero force the direction its stuck force was growing in
/// (`toward`; if none either, the next trial's slip rate sets it: `slip_turn`).
fn onset_facet<D: Dim>(
    problem: &Problem<D>,
    state: &State<D>,
    p: usize,
    force: [f64; 2],
    toward: [f64; 2],
) -> ([f64; 2], bool) {
    let ln = state.lambda_n[p];
    if let Some((e, vertex)) = problem.polygon_of(state, p) {
        let law = problem.pairs[p].friction;
        return law.place_on_polygon(e, vertex, ln, force, PLACE_TOL * law.capacity(ln));
    }
    let size = force[0].hypot(force[1]);
    (if toward != [0.0; 2] || size == 0.0 { toward } else { force.map(|v| v / size) }, false)
}

/// A force within this × its capacity μ λ_n of two sides of its polygon is at their vertex.
const PLACE_TOL: f64 = 1e-9;

/// A facet's turn (3D, `coulomb`): a pair whose cross force reached the edge of its facet's
/// band goes to the vertex there, with the next facet (m = e turned by slip_turn towards the
/// force); one at a vertex whose slip left its normal cone on side `side` goes onto that side's
/// facet. Either way the force does not move (round-off aside): the band's edge is the vertex.
fn turn_facet<D: Dim>(problem: &Problem<D>, state: &mut State<D>, p: usize, side: i8) {
    let (law, now, e) = (problem.pairs[p].friction, state.lambda_t_of(p), state.slip_dir(p));
    if state.at_vertex(p) {
        state.set_facet(p, law.facet_of(e, side as f64), false);
    } else {
        let across = e[0] * now[1] - e[1] * now[0];
        state.set_facet(p, law.vertex_of(e, across), true);
    }
    state.set_lambda_t(p, problem.slip_force(state, p, now));
}

/// `switch`, its force jump kept in the reduced space (`keep_jumps`).
pub(super) fn switch_keeping<D: Dim>(eng: &Engine<D>, state: &mut State<D>, c: &Candidate) -> f64 {
    let before = jumps_kept(eng, state).then(|| contact_forces(state));
    let jump = switch(&eng.problem, state, c);
    if let Some(before) = before {
        keep_jumps(state, &before);
    }
    jump
}

/// Whether force jumps are kept apart to be rebalanced (`PairsInSpace::jumps`): in the reduced
/// space, for pairs in space, where a facet's turn is one (in the plane the only jumps are ties',
/// and its histories are kept as they were).
pub(super) fn jumps_kept<D: Dim>(eng: &Engine<D>, state: &State<D>) -> bool {
    eng.problem.is_reduced() && state.space().is_some()
}

/// Every pair's contact forces (λ_n, λ_t1, λ_t2), to tell what switches change.
pub(super) fn contact_forces<D: Dim>(state: &State<D>) -> Vec<[f64; 3]> {
    (0..state.lambda_n.len()).map(|p| state.contact_force(p)).collect()
}

/// The force jumps switches made since `before`, added to the state's unbalanced ones
/// (`State::jumps`), which the next trial rebalances.
pub(super) fn keep_jumps<D: Dim>(state: &mut State<D>, before: &[[f64; 3]]) {
    let now = contact_forces(state);
    if let Some(space) = state.space_mut() {
        for (p, jump) in space.jumps.iter_mut().enumerate() {
            (0..3).for_each(|k| jump[k] += now[p][k] - before[p][k]);
        }
    }
}

/// The events that take pair p from status `from` to `to` (for the rate problem's statuses).
pub(super) fn transitions(p: usize, from: Status, to: Status) -> Vec<Candidate> {
    let event =
        |kind, direction| Candidate { scale: 0.0, entity: p, kind, direction, toward: [0.0; 2] };
    match (from, to) {
        (a, b) if a == b => vec![],
        (_, Status::Open) => vec![event(EventKind::Separate, 0)],
        (Status::Open, Status::Slip { direction }) if direction != 0 => {
            vec![event(EventKind::Close, 0), event(EventKind::StickToSlip, direction)]
        }
        (Status::Open, _) => vec![event(EventKind::Close, 0)],
        (Status::Slip { .. }, Status::Stick) => vec![event(EventKind::SlipToStick, 0)],
        (Status::Stick, Status::Slip { direction }) => {
            vec![event(EventKind::StickToSlip, direction)]
        }
        (Status::Slip { .. }, Status::Slip { direction }) => {
            vec![event(EventKind::SlipToStick, 0), event(EventKind::StickToSlip, direction)]
        }
        (Status::Stick, Status::Stick) => vec![],
    }
}
