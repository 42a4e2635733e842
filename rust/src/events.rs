//! Scale factors of the next events (paper §4, step 3, eqs. 48–57).
//!
//! From the current state (λ_n, λ_t, gaps) and a trial increment (Δu, Δλ_n, Δλ_t) computed
//! for the whole remaining load, each candidate event has a scale S ∈ [0, ∞): the fraction of
//! the trial increment at which it happens. The smallest S (capped at 1) is taken.

use crate::contact::{Pair, Shift, Status};
use crate::coulomb::VertexExit;
use crate::material::Voigt;
use crate::material::{von_mises, yield_scale};
use crate::model::EventKind;
use crate::section::Section;
use rayon::prelude::*;

#[derive(Debug, Clone, Copy)]
pub struct Candidate {
    pub scale: f64,
    /// Pair index for contact events, element index for `Yield` / `Unload`.
    pub entity: usize,
    pub kind: EventKind,
    /// For stick→slip: the slip direction d (λ_t = −d μ λ_n afterwards).
    pub direction: i8,
    /// 3D stick→slip at zero force: the direction its stuck force was growing in, which its
    /// friction force takes (it has none to take it from); 0 otherwise.
    pub toward: [f64; 2],
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
    /// Pairs slipping at a vertex of two facets (`coulomb`).
    pub vertex: &'a [bool],
    /// Per pair: e⊥ of a pair slipping on a facet with its cross row, else None.
    pub cross: Vec<Option<[f64; 2]>>,
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
            out.push(Candidate {
                scale: scale.max(0.0),
                entity: p,
                kind,
                direction,
                toward: [0.0; 2],
            })
        };
        let (ln, lt) = (state.lambda_n[p], state.lambda_t[p]);
        let (dln, dlt) = (trial.dlambda_n[p], trial.dlambda_t[p]);
        match state.status[p] {
            Status::Open => {
                // Contact, eqs. 48–49: the gap closes at S_c = g / (−Δg) (Δg with the
                // obstacle's motion).
                let dgap = pair.w_n.dot(trial.du) + trial.dshift[p][0];
                if dgap < -noise.displacement {
                    push(
                        &mut out,
                        (pair.gap(state.u) + state.shift[p][0]).max(0.0) / -dgap,
                        EventKind::Close,
                        0,
                    );
                }
            }
            status => {
                // Separation, eqs. 50–51: λ_n reaches zero at S_r = λ_n / (−Δλ_n).
                if dln < -noise.force {
                    push(&mut out, ln.max(0.0) / -dln, EventKind::Separate, 0);
                }
                match (status, &state.space) {
                    (Status::Stick, Some(space)) if pair.frictional() => {
                        // Stick → slip (3D, `coulomb`): on the round cone, or on its polygon for
                        // a pair that slipped since it closed; direction 1 marks a frictional
                        // slip, whose facet the switch takes from λ_t there.
                        let (law, lt, dlt) =
                            (pair.friction, [lt, space.lambda_t2[p]], [dlt, trial.dlambda_t2[p]]);
                        let e = space.slip_dir[p];
                        let onset = if e != [0.0; 2] && pair.has_tangent_plane() && ln > noise.force
                        {
                            law.polygon_exit_scale(
                                e,
                                space.vertex[p],
                                (ln, lt),
                                (dln, dlt),
                                noise.force,
                            )
                        } else {
                            law.slip_onset_scale((ln, lt), (dln, dlt), noise.force)
                        };
                        if let Some(s) = onset {
                            let growing = dlt[0].hypot(dlt[1]);
                            let unloaded =
                                lt[0].hypot(lt[1]) <= noise.force && growing > noise.force;
                            let toward = if unloaded { dlt.map(|v| v / growing) } else { [0.0; 2] };
                            out.push(Candidate {
                                scale: s.max(0.0),
                                entity: p,
                                kind: EventKind::StickToSlip,
                                direction: 1,
                                toward,
                            });
                        }
                    }
                    (Status::Slip { direction }, Some(space))
                        if direction != 0 && space.vertex[p] =>
                    {
                        // At a vertex: its slip leaves the vertex's normal cone onto a facet, or
                        // turns against the force (eq. 54): at S = 0.
                        let law = pair.friction;
                        match law.vertex_exit(
                            space.slip_dir[p],
                            slip_rate(pair, trial, p),
                            noise.displacement,
                        ) {
                            Some(VertexExit::Stick) => {
                                push(&mut out, 0.0, EventKind::SlipToStick, 0)
                            }
                            Some(VertexExit::Facet(side)) => {
                                push(&mut out, 0.0, EventKind::SlipTurn, side as i8)
                            }
                            None => {}
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
                            for (side, s) in pair.friction.facet_turn_scales(
                                cross,
                                (ln, lt),
                                (dln, dlt),
                                noise.force,
                            ) {
                                push(&mut out, s, EventKind::SlipTurn, side);
                            }
                        }
                    }
                    (Status::Stick, _) if pair.frictional() => {
                        // Stick → slip, eqs. 52–53, on either side of the Coulomb cone.
                        for (direction, s) in
                            pair.friction.planar_onset_scales((ln, lt), (dln, dlt), noise.force)
                        {
                            push(&mut out, s, EventKind::StickToSlip, direction);
                        }
                    }
                    (Status::Slip { direction }, _) if pair.friction.acts() => {
                        // Slip → stick, eqs. 54–55: the slip rate turns against the friction
                        // force's direction; this happens at zero scale.
                        let dslip = pair.w_t().dot(trial.du) + trial.dshift[p][1];
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
    let mut rate = [0.0; 2];
    for (k, t) in pair.free_tangents() {
        rate[k] = t.w.dot(trial.du) + trial.dshift[p][k + 1];
    }
    rate
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
pub fn element_candidates(
    state: &ElementState,
    dstress: &[Voigt],
    dplastic: &[f64],
    max_step: Option<f64>,
) -> (Vec<Candidate>, f64) {
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
fn element_candidate(
    state: &ElementState,
    e: usize,
    dstress: &Voigt,
    dplastic: f64,
    noise: f64,
    max_step: Option<f64>,
) -> (Option<Candidate>, f64) {
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
        let unload = (dplastic < -noise && !state.frozen[e]).then_some(Candidate {
            scale: 0.0,
            entity: e,
            kind: EventKind::Unload,
            direction: 0,
            toward: [0.0; 2],
        });
        return (unload, bound);
    }
    if state.frozen[e] {
        return (None, f64::INFINITY);
    }
    (
        yield_scale(&state.stress[e], dstress, sy).map(|s| Candidate {
            scale: s,
            entity: e,
            kind: EventKind::Yield,
            direction: 0,
            toward: [0.0; 2],
        }),
        f64::INFINITY,
    )
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
        let st = PairState {
            pairs: &pairs,
            status: &[Status::Open],
            lambda_n: &[0.0],
            lambda_t: &[0.0],
            u: &u,
            shift: &[[0.0; 3]],
            frozen: &[false],
            space: None,
        };
        let du = [0.0, -0.32];
        let c = candidates(
            &st,
            &Trial {
                du: &du,
                dlambda_n: &[0.0],
                dlambda_t: &[0.0],
                dshift: &[[0.0; 3]],
                dlambda_t2: &[],
            },
            Noise { displacement: 1e-14, force: 1e-14 },
        );
        assert_eq!(c.len(), 1);
        assert!((c[0].scale - 0.08 / 0.32).abs() < 1e-15);
    }

    #[test]
    fn stick_slip_scale_hits_the_cone() {
        // λ_n = 10, λ_t = 1, μ = 0.3; Δλ_n = 10, Δλ_t = 5: 1 + 5S = 0.3(10 + 10S) ⇒ S = 1.
        let pairs = one_pair(0.3);
        let st = PairState {
            pairs: &pairs,
            status: &[Status::Stick],
            lambda_n: &[10.0],
            lambda_t: &[1.0],
            u: &[0.0, 0.0],
            shift: &[[0.0; 3]],
            frozen: &[false],
            space: None,
        };
        let c = candidates(
            &st,
            &Trial {
                du: &[0.0, 0.0],
                dlambda_n: &[10.0],
                dlambda_t: &[5.0],
                dshift: &[[0.0; 3]],
                dlambda_t2: &[],
            },
            Noise { displacement: 1e-14, force: 1e-14 },
        );
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].kind, EventKind::StickToSlip);
        assert_eq!(c[0].direction, -1);
        assert!((c[0].scale - 1.0).abs() < 1e-14);
    }
}
