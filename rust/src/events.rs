//! Scale factors of the next events (paper §4, step 3, eqs. 48–57).
//!
//! From the current state (λ_n, λ_t, gaps) and a trial increment (Δu, Δλ_n, Δλ_t) computed
//! for the whole remaining load, each candidate event has a scale S ∈ [0, ∞): the fraction of
//! the trial increment at which it happens. The smallest S (capped at 1) is taken.

use crate::contact::{Pair, Shift, Status};
use crate::material::{von_mises, yield_scale};
use crate::section::Section;
use crate::model::EventKind;
use crate::material::Voigt;
use rayon::prelude::*;

#[derive(Debug, Clone, Copy)]
pub struct Candidate {
    pub scale: f64,
    /// Pair index for contact events, element index for `Yield` / `Unload`.
    pub entity: usize,
    pub kind: EventKind,
    /// For stick→slip: the slip direction d (λ_t = −d μ λ_n afterwards).
    pub direction: i8,
}

/// Noise floors below which a rate counts as zero (relative to the problem's scales).
#[derive(Debug, Clone, Copy)]
pub struct Noise {
    pub displacement: f64,
    pub force: f64,
}

pub struct PairState<'a> {
    pub pairs: &'a [Pair],
    pub status: &'a [Status],
    pub lambda_n: &'a [f64],
    pub lambda_t: &'a [f64],
    pub u: &'a [f64],
    /// Per pair: the gap and RTD shift of its obstacle's motion (c_n, c_t).
    pub shift: &'a [Shift],
    /// Pairs excluded by the anti-cycling rule until the load advances.
    pub frozen: &'a [bool],
    /// 3D (None in 2D).
    pub space: Option<SpacePairs<'a>>,
}

/// The pairs' state in space (3D): friction on the round cone, slipping on its facets
/// (`contact`'s module text).
pub struct SpacePairs<'a> {
    /// λ_t along t2.
    pub lambda_t2: &'a [f64],
    /// The held directions e of slipping pairs (along t1, t2).
    pub slip_dir: &'a [[f64; 2]],
    /// Per pair: e⊥ of a pair slipping on a facet with its cross row, else None.
    pub cross: Vec<Option<[f64; 2]>>,
    /// tan(`slip_turn`): a facet's cross force is bounded by this × μ λ_n.
    pub turn_bound: f64,
}

pub struct Trial<'a> {
    pub du: &'a [f64],
    pub dlambda_n: &'a [f64],
    pub dlambda_t: &'a [f64],
    /// Change of the obstacle shifts (c_n, c_t1, c_t2) over the trial.
    pub dshift: &'a [Shift],
    /// 3D: Δλ_t along t2 (empty in 2D).
    pub dlambda_t2: &'a [f64],
}

/// All candidate events of the trial increment, unsorted.
pub fn candidates(state: &PairState, trial: &Trial, noise: Noise) -> Vec<Candidate> {
    let mut out = Vec::new();
    for (p, pair) in state.pairs.iter().enumerate() {
        if state.frozen[p] {
            continue;
        }
        let push = |out: &mut Vec<Candidate>, scale: f64, kind, direction| {
            out.push(Candidate { scale: scale.max(0.0), entity: p, kind, direction })
        };
        let (ln, lt) = (state.lambda_n[p], state.lambda_t[p]);
        let (dln, dlt) = (trial.dlambda_n[p], trial.dlambda_t[p]);
        match state.status[p] {
            Status::Open => {
                // Contact, eqs. 48–49: the gap closes at S_c = g / (−Δg) (Δg with the
                // obstacle's motion).
                let dgap = pair.w_n.dot(trial.du) + trial.dshift[p][0];
                if dgap < -noise.displacement {
                    push(&mut out, (pair.gap(state.u) + state.shift[p][0]).max(0.0) / -dgap, EventKind::Close, 0);
                }
            }
            status => {
                // Separation, eqs. 50–51: λ_n reaches zero at S_r = λ_n / (−Δλ_n).
                if dln < -noise.force {
                    push(&mut out, ln.max(0.0) / -dln, EventKind::Separate, 0);
                }
                match (status, &state.space) {
                    (Status::Stick, Some(space)) if pair.frictional() => {
                        // Stick → slip on the round cone (3D, `contact`): direction 1 marks a
                        // frictional slip, whose held direction the switch takes from λ_t there.
                        let lt = [lt, space.lambda_t2[p]];
                        let dlt = [dlt, trial.dlambda_t2[p]];
                        if let Some(s) = onto_round_cone(pair.mu, (ln, lt), (dln, dlt), noise.force) {
                            push(&mut out, s, EventKind::StickToSlip, 1);
                        }
                    }
                    (Status::Slip { direction }, Some(space)) if direction != 0 => {
                        // Slip → stick (eq. 54 in the plane): the slip rate turns against −e.
                        let e = space.slip_dir[p];
                        let rate = slip_rate(pair, trial, p);
                        if e[0] * rate[0] + e[1] * rate[1] > noise.displacement {
                            push(&mut out, 0.0, EventKind::SlipToStick, 0);
                        }
                        if let Some(cross) = space.cross[p] {
                            let (lt, dlt) = ([lt, space.lambda_t2[p]], [dlt, trial.dlambda_t2[p]]);
                            for (side, s) in facet_turns(space.turn_bound * pair.mu, cross, (ln, lt), (dln, dlt), noise.force) {
                                push(&mut out, s, EventKind::SlipTurn, side);
                            }
                        }
                    }
                    (Status::Stick, _) if pair.frictional() => {
                        // Stick → slip, eqs. 52–53, on either side of the Coulomb cone.
                        // Reaching λ_t = +μλ_n means slip in −t (d = −1), and vice versa.
                        let mu = pair.mu;
                        let den_plus = dlt - mu * dln;
                        if den_plus > noise.force {
                            push(&mut out, (mu * ln - lt) / den_plus, EventKind::StickToSlip, -1);
                        }
                        let den_minus = -dlt - mu * dln;
                        if den_minus > noise.force {
                            push(&mut out, (mu * ln + lt) / den_minus, EventKind::StickToSlip, 1);
                        }
                    }
                    (Status::Slip { direction }, _) if pair.mu > 0.0 => {
                        // Slip → stick, eqs. 54–55: the slip rate turns against the friction
                        // force's direction; this happens at zero scale.
                        let dslip = pair.w_t.dot(trial.du) + trial.dshift[p][1];
                        if (direction as f64) * dslip < -noise.displacement {
                            push(&mut out, 0.0, EventKind::SlipToStick, 0);
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    out
}

/// 3D: a pair's relative tangential velocity (t1, t2) in a trial (0 along a direction the
/// supports hold).
pub fn slip_rate(pair: &Pair, trial: &Trial, p: usize) -> [f64; 2] {
    let along = |w: &crate::contact::SparseVec, k: usize| if pair.held[k - 1] { 0.0 } else { w.dot(trial.du) + trial.dshift[p][k] };
    [along(&pair.w_t, 1), along(&pair.w_t2, 2)]
}

/// Stick → slip on the round Coulomb cone (3D): the smallest S ≥ 0 where the friction force
/// leaves the cone, g(S) = |λ_t0 + S Δλ_t| − μ (λ_n0 + S Δλ_n) crossing zero upwards. g is
/// convex; its zeros with λ_n(S) > 0 are roots of the quadratic a S² + b S + c = 0,
/// a = |Δλ_t|² − μ²Δλ_n², b = 2(λ_t0·Δλ_t − μ² λ_n0 Δλ_n), c = |λ_t0|² − μ² λ_n0² (the squared
/// cone, whose other roots are on its mirror image through the apex, λ_n < 0). A pair on the
/// cone or outside it by round-off (g(0) ≥ 0: also one whose λ_n is a round-off below zero just
/// after it closed, where the squared cone's c and b describe the mirror image) slips at S = 0
/// when g grows there, also one at zero force sheared with no normal force rate to hold it (if
/// it is pulled off, its separation at S = 0 comes first), and one that stays outside; one that
/// moves inwards first slips where it leaves again. None: the increment stays inside (or its
/// rates are noise).
pub fn onto_round_cone(mu: f64, (ln, lt): (f64, [f64; 2]), (dln, dlt): (f64, [f64; 2]), noise: f64) -> Option<f64> {
    let shear_rate = dlt[0].hypot(dlt[1]);
    if shear_rate <= noise && mu * dln.abs() <= noise {
        return None;
    }
    let mu2 = mu * mu;
    let a = dlt[0] * dlt[0] + dlt[1] * dlt[1] - mu2 * dln * dln;
    let b = 2.0 * (lt[0] * dlt[0] + lt[1] * dlt[1] - mu2 * ln * dln);
    let c = lt[0] * lt[0] + lt[1] * lt[1] - mu2 * ln * ln;
    let size = lt[0].hypot(lt[1]);
    let inside = size < mu * ln;
    let disc = b * b - 4.0 * a * c;
    let q = -0.5 * (b + b.signum() * disc.max(0.0).sqrt()); // the roots q/a and c/q, without cancellation
    let roots = if disc < 0.0 { [f64::INFINITY; 2] } else { [if a != 0.0 { q / a } else { f64::INFINITY }, if q != 0.0 { c / q } else { f64::INFINITY }] };
    // where the cone itself (λ_n(S) > 0) is crossed outwards (f' = 2aS + b > 0); a pair on the
    // cone is not leaving at the point it starts from
    let leaving = |s: f64| s.is_finite() && (s > 0.0 || (s == 0.0 && inside)) && 2.0 * a * s + b > 0.0 && ln + s * dln > 0.0;
    let exit = roots.into_iter().filter(|&s| leaving(s)).fold(None, |best: Option<f64>, s| Some(best.map_or(s, |b| b.min(s))));
    if inside {
        return exit;
    }
    // on or outside the cone: g's slope at S = 0 (along λ_t0, or from the apex)
    let slope = if size > 0.0 { (lt[0] * dlt[0] + lt[1] * dlt[1]) / size } else { shear_rate } - mu * dln;
    if slope > 0.0 {
        return Some(0.0);
    }
    // moving inwards first: it leaves again where it crosses outwards; with no such crossing it
    // either stays inside (pressed more than sheared: g falls for good) or never enters
    exit.or((shear_rate > mu * dln).then_some(0.0))
}

/// A pair slipping on a facet (3D): where its friction force has turned off the held
/// direction e by `slip_turn`, its cross force λ_⊥ = e⊥·λ_t reaching ± k λ_n (k = tan(slip_turn)
/// μ), linear in S on either side as eqs. 52–53 in the plane: (side ±1, S) of each side the
/// increment reaches.
pub fn facet_turns(k: f64, cross: [f64; 2], (ln, lt): (f64, [f64; 2]), (dln, dlt): (f64, [f64; 2]), noise: f64) -> Vec<(i8, f64)> {
    let across = cross[0] * lt[0] + cross[1] * lt[1];
    let rate = cross[0] * dlt[0] + cross[1] * dlt[1];
    [1i8, -1]
        .into_iter()
        .filter_map(|side| {
            let den = side as f64 * rate - k * dln;
            (den > noise).then(|| (side, (k * ln - side as f64 * across) / den))
        })
        .collect()
}

/// A plastic multiplier below this × the largest of the trial counts as zero (no unloading).
const PLASTIC_NOISE: f64 = 1e-10;

pub struct ElementState<'a> {
    pub sections: &'a [Section],
    pub stress: &'a [Voigt],
    pub plastic_strain: &'a [f64],
    pub plastic: &'a [bool],
    pub frozen: &'a [bool],
}

/// Elastic → plastic at S_p (eqs. 12–16, 56), and plastic → elastic unloading at S = 0 when
/// the trial's plastic multiplier is negative (the event the paper leaves out); with drift
/// control also the drift bound: the largest scale at which no plastic element's stress
/// changes by more than `max_step` × σy (von Mises norm of the increment; with the tangent
/// frozen at the increment's start, the departure from the yield surface grows with the square
/// of this). `dstress` and `dplastic` are the trial's stress and plastic-strain increments.
pub fn element_candidates(state: &ElementState, dstress: &[Voigt], dplastic: &[f64], max_step: Option<f64>) -> (Vec<Candidate>, f64) {
    let noise = PLASTIC_NOISE * dplastic.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let per_element: Vec<(Option<Candidate>, f64)> = (0..state.stress.len())
        .into_par_iter()
        .with_min_len(ELEMENT_CHUNK)
        .map(|e| element_candidate(state, e, &dstress[e], dplastic[e], noise, max_step))
        .collect();
    let bound = per_element.iter().fold(f64::INFINITY, |b, (_, s)| b.min(*s));
    (per_element.into_iter().filter_map(|(c, _)| c).collect(), bound)
}

/// Element loops run in parallel chunks of at least this many elements.
const ELEMENT_CHUNK: usize = 1024;

/// One element's candidate event, and its drift bound (∞ unless it is plastic).
fn element_candidate(state: &ElementState, e: usize, dstress: &Voigt, dplastic: f64, noise: f64, max_step: Option<f64>) -> (Option<Candidate>, f64) {
    let m = &state.sections[e].material;
    if !m.is_plastic() {
        return (None, f64::INFINITY);
    }
    let sy = m.current_yield(state.plastic_strain[e]);
    if state.plastic[e] {
        let change = von_mises(dstress);
        let bound = match max_step {
            Some(step) if change > 0.0 => step * sy / change,
            _ => f64::INFINITY,
        };
        let unload = (dplastic < -noise && !state.frozen[e]).then_some(Candidate { scale: 0.0, entity: e, kind: EventKind::Unload, direction: 0 });
        return (unload, bound);
    }
    if state.frozen[e] {
        return (None, f64::INFINITY);
    }
    (yield_scale(&state.stress[e], dstress, sy).map(|s| Candidate { scale: s, entity: e, kind: EventKind::Yield, direction: 0 }), f64::INFINITY)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_pair(mu: f64) -> Vec<Pair> {
        vec![Pair::new(0, None, [0.0, 1.0], 0.1, mu, &[false, false])]
    }

    #[test]
    fn closing_scale_is_gap_over_closure() {
        let pairs = one_pair(0.0);
        let u = [0.0, -0.02];
        let st = PairState { pairs: &pairs, status: &[Status::Open], lambda_n: &[0.0], lambda_t: &[0.0], u: &u, shift: &[[0.0; 3]], frozen: &[false], space: None };
        let du = [0.0, -0.32];
        let c = candidates(&st, &Trial { du: &du, dlambda_n: &[0.0], dlambda_t: &[0.0], dshift: &[[0.0; 3]], dlambda_t2: &[] }, Noise { displacement: 1e-14, force: 1e-14 });
        assert_eq!(c.len(), 1);
        assert!((c[0].scale - 0.08 / 0.32).abs() < 1e-15);
    }

    /// The round cone (3D): the root lands on |λ_t| = μ λ_n (a pair inside going out; one on
    /// the cone moving inwards first, which leaves it at the later root; one moving inwards for
    /// good, which never slips), checked on the cone's own equation.
    #[test]
    fn round_cone_scale_lands_on_the_cone() {
        let (mu, noise) = (0.3, 1e-14);
        let on_cone = |ln: f64, lt: [f64; 2], dln: f64, dlt: [f64; 2], s: f64| (lt[0] + s * dlt[0]).hypot(lt[1] + s * dlt[1]) - mu * (ln + s * dln);
        let cases = [(10.0, [1.0, -0.5], 2.0, [3.0, 4.0]), (10.0, [0.0, 0.0], 1.0, [-0.2, 2.5]), (5.0, [0.6, 0.0], -1.0, [0.0, 1.0])];
        for (ln, lt, dln, dlt) in cases {
            let s = onto_round_cone(mu, (ln, lt), (dln, dlt), noise).expect("it slips");
            assert!(s > 0.0 && on_cone(ln, lt, dln, dlt, s).abs() < 1e-12 * ln, "{s}");
            // nowhere outside before it
            assert!((1..100).map(|k| s * k as f64 / 100.0).all(|x| on_cone(ln, lt, dln, dlt, x) < 0.0));
        }
        // on the cone (λ_t = μλ_n (0.6, 0.8)), turning inwards first: the later crossing
        let (ln, lt) = (10.0, [1.8, 2.4]);
        let s = onto_round_cone(mu, (ln, lt), (0.0, [-2.0, 0.5]), noise).expect("it leaves again");
        assert!(s > 0.5 && on_cone(ln, lt, 0.0, [-2.0, 0.5], s).abs() < 1e-12 * ln, "{s}");
        // just closed (λ = 0) and sheared more than pressed: at once; pressed more: never
        assert_eq!(onto_round_cone(mu, (0.0, [0.0; 2]), (0.44, [0.04, -0.17]), noise), Some(0.0));
        assert_eq!(onto_round_cone(mu, (0.0, [0.0; 2]), (1.0, [0.04, -0.17]), noise), None);
        // on it, its force shrinking straight back: through zero, out on the opposite side where
        // |λ_t| = |3 − S| = 3 again (S = 6); pressed harder than it is sheared: no slip
        let s = onto_round_cone(mu, (ln, lt), (0.0, [-0.6, -0.8]), noise).expect("reversed");
        assert!((s - 6.0).abs() < 1e-12, "{s}");
        assert_eq!(onto_round_cone(mu, (ln, [0.5, 0.0]), (10.0, [1.0, 0.0]), noise), None);
        // on it and moving out: at once
        assert_eq!(onto_round_cone(mu, (ln, lt), (0.0, [0.6, 0.8]), noise), Some(0.0));
        // at zero force, sheared with no normal force rate (or one pulling by round-off): at once
        assert_eq!(onto_round_cone(mu, (0.0, [0.0; 2]), (0.0, [0.04, -0.17]), noise), Some(0.0));
        assert_eq!(onto_round_cone(mu, (0.0, [0.0; 2]), (-0.5 * noise, [0.04, -0.17]), noise), Some(0.0));
        // just closed, λ_n a round-off below zero (as a correction at fixed load leaves it), so
        // outside the cone by round-off, where the squared cone describes its mirror image:
        // sheared more than pressed, at once, whether the round-off λ_t points along the shear
        // (the pyramid's edge: λ_t grows along it as the stick went on) or against it; pressed
        // more than sheared, never
        let (ln, lt) = (-4.66e-8, [-2.06e-9, 8.37e-8]);
        assert_eq!(onto_round_cone(mu, (ln, lt), (0.171, [-0.2076, 0.0405]), noise), Some(0.0));
        assert_eq!(onto_round_cone(mu, (ln, lt), (0.171, [0.0405, -0.2076]), noise), Some(0.0));
        assert_eq!(onto_round_cone(mu, (ln, lt), (0.171, [-0.02, 0.004]), noise), None);
    }

    /// A facet's turn: the cross force λ_⊥ = e⊥·λ_t reaches ± tan(slip_turn) μ λ_n where the
    /// friction force has turned by slip_turn off e, on the side it turns to, and nowhere
    /// before; a force turning slower than its bound grows reaches neither side.
    #[test]
    fn a_facet_turns_where_the_force_has_turned_by_the_angle() {
        let (mu, turn, noise) = (0.3, 0.1f64, 1e-14);
        let k = turn.tan() * mu;
        let e = [0.6, 0.8];
        let cross = [-e[1], e[0]];
        let (ln, dln) = (10.0, 2.0);
        let lt = [mu * ln * e[0], mu * ln * e[1]]; // on the facet's tangent point
        for side in [1.0, -1.0] {
            let dlt = [mu * dln * e[0] + side * 1.5 * cross[0], mu * dln * e[1] + side * 1.5 * cross[1]];
            let turns = facet_turns(k, cross, (ln, lt), (dln, dlt), noise);
            assert_eq!(turns.len(), 1);
            let (s_side, s) = turns[0];
            assert_eq!(s_side as f64, side);
            let force = [lt[0] + s * dlt[0], lt[1] + s * dlt[1]];
            let along = e[0] * force[0] + e[1] * force[1];
            assert!(((side * (cross[0] * force[0] + cross[1] * force[1])) / along - turn.tan()).abs() < 1e-12, "{s}");
        }
        let slow = [mu * dln * e[0] + 0.5 * k * dln * cross[0], mu * dln * e[1] + 0.5 * k * dln * cross[1]];
        assert!(facet_turns(k, cross, (ln, lt), (dln, slow), noise).is_empty());
    }

    #[test]
    fn stick_slip_scale_hits_the_cone() {
        // λ_n = 10, λ_t = 1, μ = 0.3; Δλ_n = 10, Δλ_t = 5: 1 + 5S = 0.3(10 + 10S) ⇒ S = 1.
        let pairs = one_pair(0.3);
        let st = PairState { pairs: &pairs, status: &[Status::Stick], lambda_n: &[10.0], lambda_t: &[1.0], u: &[0.0, 0.0], shift: &[[0.0; 3]], frozen: &[false], space: None };
        let c = candidates(&st, &Trial { du: &[0.0, 0.0], dlambda_n: &[10.0], dlambda_t: &[5.0], dshift: &[[0.0; 3]], dlambda_t2: &[] }, Noise { displacement: 1e-14, force: 1e-14 });
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].kind, EventKind::StickToSlip);
        assert_eq!(c[0].direction, -1);
        assert!((c[0].scale - 1.0).abs() < 1e-14);
    }
}
