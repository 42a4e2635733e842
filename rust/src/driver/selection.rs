//! Which events happen next (paper §4 steps 3–4): every candidate's scale factor (eqs. 48–56,
//! module `events`), the smallest S (eq. 57), the events that come with it (ties), the bound of
//! a plastic window (`stepping`), and the order of simultaneous zero-length events.

use super::anticycling::AntiCycling;
use super::problem::Problem;
use super::state::{State, TrialIncrement};
use super::stepping::Stepping;
use crate::dim::Dim;
use crate::events::{self, Candidate, ElementState, PairState, SpacePairs, Trial};
use crate::model::{EventKind, Options};

/// Scale factors at or below this are zero-length increments.
pub(super) const ZERO_SCALE: f64 = 1e-12;
/// Absolute slack added to the tie window S_min (1 + tie_tol).
const TIE_SLACK: f64 = 1e-14;
/// An event predicted within this of the stage's end (in stage fraction) ties with the end:
/// it belongs to the next stage, if that one keeps loading, and is no event of this one. (An
/// element reloaded to the stress it had on the yield surface reaches it again exactly at the
/// end: measured 1 − 5e-14 on the autofrettage reload; without the tie it would re-yield with
/// zero plastic flow.)
pub(super) const STAGE_END: f64 = 1e-12;
/// A stage that starts yielding at once still advances by this × δ of the stage per grouped
/// increment (the window is relative to the load fraction otherwise).
const WINDOW_FLOOR: f64 = 0.05;

/// The outcome of one selection.
pub(super) struct Selection {
    /// The scale the state advances by: min(S_min, drift bound, 1).
    pub scale: f64,
    /// S_min ≥ 1: the trial completes the load (step 8).
    pub last: bool,
    /// Load fraction after the advance.
    pub phi: f64,
    /// The events that switch at `phi` (empty when the drift bound cut the increment short).
    pub group: Vec<Candidate>,
    /// Last trial only: the load fraction at which each open pair would have closed.
    pub predicted_closures: Vec<(usize, f64)>,
    /// A plastic window: yields and unloads happen inside the increment (integrated), not at
    /// its end.
    pub plastic_inside: bool,
    /// The load fraction the increment may not pass whatever the contact events: the plastic
    /// window's end, the drift bound, a requested snapshot or the stage's end.
    pub bound_phi: f64,
    /// A plastic window: the first yield the trial predicts, (element, load fraction): the
    /// exact onset on the increment's linear path, as event by event, so no element yields
    /// before it (`Recorder::events_inside`); None after contact sub-steps that switched
    /// before it (the path changed).
    pub first_yield: Option<(usize, f64)>,
}

impl Selection {
    pub fn zero_length(&self) -> bool {
        self.scale <= ZERO_SCALE
    }
}

/// S = min(S_c, S_p, S_f, S_r, S_A) (eq. 57) and the events that switch with it. `cut`: a scale
/// the increment must not pass (a requested snapshot time; ∞ for none); `stepping`: a plastic
/// window runs past the first predicted yield (`plastic_window`).
pub(super) fn select<D: Dim>(
    problem: &Problem<D>,
    state: &State<D>,
    trial: &TrialIncrement,
    cycles: &AntiCycling,
    cut: f64,
    stepping: Stepping,
) -> Selection {
    let (mut cands, drift_scale) = candidates(problem, state, trial, cycles);
    let (window, first_yield) = match stepping.window() {
        Some(delta) => {
            plastic_window(&mut cands, state.load_fraction, 1.0 - state.load_fraction, delta)
        }
        None => (f64::INFINITY, None),
    };
    let plastic_inside = stepping.window().is_some();
    Selection {
        first_yield,
        ..choose(
            &problem.model.options,
            state,
            cands,
            drift_scale.min(window).min(cut),
            plastic_inside,
        )
    }
}

/// A contact sub-step (`substeps`): the next contact events of a contact-space trial, up to
/// `bound` (the scale where the increment ends for plasticity, a snapshot or the stage).
pub(super) fn select_contact<D: Dim>(
    problem: &Problem<D>,
    state: &State<D>,
    trial: &TrialIncrement,
    cycles: &AntiCycling,
    bound: f64,
) -> Selection {
    let cands = events::candidates(
        &pair_state(problem, state, cycles.frozen().0),
        &trial_of(trial),
        trial.noise,
    );
    choose(&problem.model.options, state, cands, bound, true)
}

/// The pairs' part of the state as `events` reads it; `frozen`: pairs the anti-cycling rule
/// holds.
pub(super) fn pair_state<'a, D: Dim>(
    problem: &'a Problem<D>,
    state: &'a State<D>,
    frozen: &'a [bool],
) -> PairState<'a> {
    let space = state.space().map(|space| SpacePairs {
        lambda_t2: &space.lambda_t2,
        slip_dir: &space.slip_dir,
        vertex: &space.vertex,
        cross: (0..problem.pairs.len()).map(|p| problem.cross_direction(state, p)).collect(),
    });
    PairState {
        pairs: &problem.pairs,
        status: &state.status,
        lambda_n: &state.lambda_n,
        lambda_t: &state.lambda_t,
        u: &state.u,
        shift: &state.shift,
        frozen,
        space,
    }
}

/// A trial's rates as `events` reads them.
pub(super) fn trial_of(trial: &TrialIncrement) -> Trial<'_> {
    Trial {
        du: &trial.du,
        dlambda_n: &trial.dlambda_n,
        dlambda_t: &trial.dlambda_t,
        dshift: &trial.dshift,
        dlambda_t2: &trial.dlambda_t2,
    }
}

/// Every candidate event of the trial (contacts, yields, unloads) and the drift bound.
fn candidates<D: Dim>(
    problem: &Problem<D>,
    state: &State<D>,
    trial: &TrialIncrement,
    cycles: &AntiCycling,
) -> (Vec<Candidate>, f64) {
    let (frozen_pairs, frozen_elements) = cycles.frozen();
    let mut cands = events::candidates(
        &pair_state(problem, state, frozen_pairs),
        &trial_of(trial),
        trial.noise,
    );
    let elements = ElementState {
        sections: &problem.sections,
        stress: &state.stress,
        plastic_strain: &state.plastic_strain,
        plastic: &state.plastic,
        frozen: frozen_elements,
    };
    let opts = &problem.model.options;
    let max_step = opts.drift_control.then_some(opts.max_stress_step);
    let (element_cands, drift_scale) =
        events::element_candidates(&elements, &trial.dstress, &trial.dplastic, max_step);
    cands.extend(element_cands);
    (cands, drift_scale)
}

/// The smallest scale among the candidates and `bound`, the events tied with it, and the
/// order of zero-length ones.
fn choose<D: Dim>(
    opts: &Options,
    state: &State<D>,
    mut cands: Vec<Candidate>,
    bound: f64,
    plastic_inside: bool,
) -> Selection {
    let (phi0, remaining) = (state.load_fraction, 1.0 - state.load_fraction);
    for c in
        cands.iter_mut().filter(|c| c.scale < 1.0 && phi0 + c.scale * remaining >= 1.0 - STAGE_END)
    {
        c.scale = 1.0; // ties with the stage's end (see STAGE_END)
    }
    let s_min = cands.iter().map(|c| c.scale).fold(f64::INFINITY, f64::min);
    let scale = s_min.min(bound).min(1.0);
    let last = s_min >= 1.0 && bound >= 1.0;
    let predicted_closures = if last {
        cands
            .iter()
            .filter(|c| c.kind == EventKind::Close)
            .map(|c| (c.entity, phi0 + c.scale * remaining))
            .collect()
    } else {
        vec![]
    };
    let tie_limit = s_min * (1.0 + opts.tie_tol) + TIE_SLACK;
    let mut group: Vec<Candidate> = if scale < s_min || last {
        vec![]
    } else {
        cands.iter().copied().filter(|c| c.scale <= tie_limit).collect()
    };
    if s_min <= ZERO_SCALE {
        // Zero-length events come from a trial that is itself inadmissible; apply first
        // the ones that release a violated constraint, and only then those that add one.
        let top = group.iter().map(|c| zero_length_priority(c.kind)).min().unwrap_or(0);
        group.retain(|c| zero_length_priority(c.kind) == top);
    }
    let phi = if last { 1.0 } else { phi0 + scale * remaining };
    let bound_phi = if bound >= 1.0 { 1.0 } else { phi0 + bound * remaining };
    Selection {
        scale,
        last,
        phi,
        group,
        predicted_closures,
        plastic_inside,
        bound_phi,
        first_yield: None,
    }
}

/// Order in which simultaneous zero-length events are applied (lowest first, one class per
/// increment): releasing a violated constraint (stick→slip, separation, a facet's turn) before
/// closing a gap, and both before re-imposing stick. A slip reversal seen in a trial where a stuck pair
/// already exceeds its cone is an artefact of that trial; applying all of them at once makes
/// pairs chatter slip→stick→slip at every event.
fn zero_length_priority(kind: EventKind) -> u8 {
    match kind {
        EventKind::StickToSlip | EventKind::Separate | EventKind::SlipTurn => 0,
        EventKind::Close | EventKind::Yield => 1,
        EventKind::SlipToStick
        | EventKind::Unload
        | EventKind::Frozen
        | EventKind::FrozenElement => 2,
    }
}

/// A plastic window: take the yields out of the candidates; the scale at which the grouped
/// increment ends for them: the first one's load fraction φ_p, then δ max(φ_p, floor) more; and
/// that first yield (element, φ_p). (Unloads stay events: they come at zero scale, and K must
/// hold the elastic tangent of an element that unloads.)
fn plastic_window(
    cands: &mut Vec<Candidate>,
    phi0: f64,
    remaining: f64,
    delta: f64,
) -> (f64, Option<(usize, f64)>) {
    let first = cands
        .iter()
        .filter(|c| c.kind == EventKind::Yield && c.scale.is_finite())
        .min_by(|a, b| a.scale.total_cmp(&b.scale))
        .map(|c| (c.entity, c.scale));
    cands.retain(|c| c.kind != EventKind::Yield);
    let Some((element, scale)) = first.filter(|_| remaining > 0.0) else {
        return (f64::INFINITY, None);
    };
    let phi = phi0 + scale * remaining;
    ((phi + delta * phi.max(WINDOW_FLOOR) - phi0) / remaining, Some((element, phi)))
}

#[cfg(test)]
mod tests {
    use super::super::clock::Clock;
    use super::super::engine::Engine;
    use super::super::scenes::*;
    use super::super::trial::remaining_load;
    use super::*;

    /// Scales on these scenes come from a few dozen operations on O(1) numbers (~1e-15 each);
    /// an error in the rule would be of order one.
    const ROUND_OFF: f64 = 1e-12;

    /// The trial for the remaining load and its selection from `state`.
    fn next<D: Dim>(eng: &mut Engine<D>, state: &State<D>, stepping: Stepping) -> Selection {
        let cycles = AntiCycling::new(eng.problem.pairs.len(), eng.problem.loop_elements(), 4);
        let (trial, _) = remaining_load(eng, state, None, stepping).unwrap();
        select(&eng.problem, state, &trial, &cycles, f64::INFINITY, stepping)
    }

    /// The square pressed by q spreads towards the wall at gap g by ν q/E at the full load, so
    /// the gap closes at S_c = g E / (ν q) (eq. 49), the increment's one event.
    #[test]
    fn a_gap_closes_at_the_closed_form_scale() {
        let (q, g) = (2.0, 1e-4);
        let m = poisson_wall(q, g);
        let clock = Clock::new();
        let (mut eng, state) = start(&m, &clock);
        let sel = next(&mut eng, &state, Stepping::EventByEvent);
        let s_c = g * E / (NU * q);
        assert!(
            (sel.scale - s_c).abs() < ROUND_OFF * s_c && !sel.last,
            "S = {} vs {s_c}",
            sel.scale
        );
        assert_eq!(
            sel.group.iter().map(|c| (c.kind, c.entity)).collect::<Vec<_>>(),
            [(EventKind::Close, 0)]
        );
        assert!((sel.phi - s_c).abs() < ROUND_OFF);
    }

    /// The pair pressed by N and stuck carries the growing shear T s by itself (λ_t = T s), so it
    /// reaches μ λ_n at S_f = μ N / T (eq. 53), sliding along −t, with +x (d = −1).
    #[test]
    fn a_stuck_pair_slips_at_the_closed_form_scale() {
        let (n, t, mu) = (3.0, 1.0, 0.2);
        let m = pressed_then_sheared(n, t, mu);
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let (press, _) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
        state.advance(&press, 1.0);
        eng.begin_stage(1, &mut state);
        let sel = next(&mut eng, &state, Stepping::EventByEvent);
        let s_f = mu * n / t;
        assert!((sel.scale - s_f).abs() < ROUND_OFF * s_f, "S = {} vs {s_f}", sel.scale);
        assert_eq!(
            sel.group.iter().map(|c| (c.kind, c.entity, c.direction)).collect::<Vec<_>>(),
            [(EventKind::StickToSlip, 0, -1)]
        );
    }

    /// Pulled to σx = a, then pressed by σy = −b s: plane stress σe² = a² + a b s + b² s², so
    /// both elements (the stress is uniform) reach Sy at the positive root of
    /// b² s² + a b s + a² − Sy² = 0 (eqs. 12–16), and yield together.
    #[test]
    fn an_element_yields_at_the_root_of_the_quadratic() {
        let (a, b, sy) = (100.0, 300.0, 250.0);
        let m = pulled_then_pressed(a, b, plastic(sy, 500.0));
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let (pull, _) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
        state.advance(&pull, 1.0);
        eng.begin_stage(1, &mut state);
        let sel = next(&mut eng, &state, Stepping::EventByEvent);
        let root =
            (-a * b + (a * a * b * b - 4.0 * b * b * (a * a - sy * sy)).sqrt()) / (2.0 * b * b);
        assert!((sel.scale - root).abs() < ROUND_OFF * root, "S = {} vs {root}", sel.scale);
        let mut yielded: Vec<(EventKind, usize)> =
            sel.group.iter().map(|c| (c.kind, c.entity)).collect();
        yielded.sort_by_key(|&(_, e)| e);
        assert_eq!(yielded, [(EventKind::Yield, 0), (EventKind::Yield, 1)]);
    }

    /// Grouped, the increment runs past the first yield (pressed by σy = −b s: at s_p = Sy/b)
    /// to s_p (1 + δ): the yields are no events of its end, the first one is kept as the
    /// window's exact onset.
    #[test]
    fn a_window_runs_past_the_first_yield_by_delta() {
        let (b, sy, delta) = (300.0, 250.0, 0.1);
        let m = square_on_rollers(0.0, -b, plastic(sy, 500.0));
        let clock = Clock::new();
        let (mut eng, state) = start(&m, &clock);
        let sel = next(&mut eng, &state, Stepping::Grouped { delta });
        let s_p = sy / b;
        let (_, onset) = sel.first_yield.expect("the window's first yield");
        assert!((onset - s_p).abs() < ROUND_OFF, "onset {onset} vs {s_p}");
        assert!((sel.phi - s_p * (1.0 + delta)).abs() < ROUND_OFF && sel.plastic_inside);
        assert!(
            sel.group.is_empty(),
            "the window ends at its bound: {:?}",
            sel.group.iter().map(|c| c.kind).collect::<Vec<_>>()
        );
    }
}
