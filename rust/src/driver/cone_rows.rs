//! The friction cone's part of the rate problem (`rate_problem`): each frictional pair's sides
//! in its tangential coordinates, their rows among the unknowns, and the status and slip
//! direction its solved slip rates give back. In the plane the cone is its two sides ±t
//! (Klarbring's 2D form, eq. 41): 0 ≤ v⁺ ⊥ μΛn + Λt ≥ 0, 0 ≤ v⁻ ⊥ μΛn − Λt ≥ 0 with
//! v − v⁺ + v⁻ = 0 (Λt free), a side the force is not on keeping its unknown, its row its
//! present slack μλn ∓ λt > 0.
//!
//! # In space (3D): the round cone faceted for this problem only
//!
//! The same problem with Λt = (Λt1, Λt2) and the cone |Λt| ≤ μΛn replaced by a polygon of
//! `FACETS` sides (Klarbring's / Stewart and Trinkle's faceted cone): side j has the
//! outward normal d_j in the tangent plane, its condition μΛn − d_jᵀΛt ≥ 0, and its own slip
//! rate v_j ≥ 0, slip against its normal:
//!   v + Σ_j v_j d_j = 0 (Λt free),   0 ≤ v_j ⊥ μΛn − d_jᵀΛt ≥ 0
//! (2D is this with the two sides d = −t, +t). A pair with a force that has slipped since it
//! closed has its own polygon (`coulomb`), and the problem takes its sides. For the others the
//! polygon is *circumscribed* about the round cone and turned so that its first side's normal
//! is the pair's friction force (its held slip direction; t1 at zero force): a pair on the
//! round cone is on that side exactly, so a slipping pair keeps its direction. A side a force
//! is not on has present slack and is not reachable at the increment's start (its slip rate is
//! 0): in space it is no unknown (in the plane it keeps one, its row that slack, as the other
//! side there always did). Only a pair at zero force sees the polygon's other sides: a square,
//! 6 unknowns per zero-force pair (an inscribed one would put every pair on the round cone
//! outside it, infeasible at the start). Its corners over-estimate the round capacity by
//! 1/cos(π/4) − 1 = 41 %, and its sides are wider than the facet design's band, so a pair the
//! solution sticks beyond the round cone, or slips with a force across its slip beyond the
//! band, gets the sides of the polygon laid about its direction and the problem is solved
//! again (`rate_problem`'s `stuck_beyond_round_cone`, `stray_slips`): only where the
//! solution needs them. With twelve sides (3.5 % at the corners, 14 unknowns per pair) the pad of issue 37, 258 pairs at
//! zero gap and force at t = 0, made LCPs of 3354 unknowns (~40 s each on this machine); with
//! the square, 1290–1587 (2.4–4.2 s), the same statuses after the passes (144 stuck, 62
//! slipping against 143/63: one pair of the solution's 258 at its cone's edge).
//!
//! The hand-back to the facet design of friction (`coulomb`): the statuses the LCP picks
//! become the pairs' statuses, and a pair it sets slipping slips on the side it slips on, at the
//! vertex of two adjacent sides of a polygon, or (a corner of the wider twelve-gon) on the facet
//! at the direction e = Σ v_j d_j / |Σ v_j d_j| (against its slip), with the facet's cross row
//! from zero normal force on, its cross force free as on the polygon's side
//! (`rate_problem::hold_slip_directions`); its turns from there are the facet design's own.
//! The trial that follows is then the LCP's own conditions, but where a side is wider than
//! the design's facet: a pair at zero force (its force the rate problem's, from zero) that
//! slips on a side with a force across it beyond tan θ μΛn would turn its facet at
//! once, and its neighbours' forces with it (the receding plate at μ = 2: stuck pairs at
//! 0.75–0.88 of their cone slipped at once, and the last resort left one outside its cone).
//! So such a slip lays three facets about its e, the sides of the polygon laid at e (2θ apart,
//! whose corners are its vertices), and the problem is solved again (at most `rate_problem`'s
//! `FACET_PASSES` times). A pair slipping at a corner of two twelve-gon sides carries more than
//! μΛn along e there (by at most 1/cos(π/12) − 1) and μ λ_n handed back: its trial's force
//! differs from the LCP's by that, within what a stuck neighbour's margin absorbs.
//! A tangent the supports hold (a symmetry plane) is not a coordinate: the pair has the two
//! sides along its other tangent, as in 2D.

use super::mixed_lcp::{Affine, Unknowns};
use crate::contact::Status;
use crate::coulomb::Coulomb;

/// Sides of the polygon about the round Coulomb cone of a pair at zero force in the 3D rate
/// problem (see the module documentation): a square, refined where the solution needs it.
const FACETS: usize = 4;
/// Two sides' normals are adjacent on a polygon when their dot product is within this of
/// cos 2θ (round-off of a sine and cosine).
const SAME_SIDE: f64 = 1e-9;
/// A force on a facet of the design agrees with it to this (relative): round-off of Lemke's
/// solution.
const FACET_AGREEMENT: f64 = 1e-6;

/// One side of a pair's friction cone in its tangential coordinates: the outward normal d of
/// the facet μΛn − dᵀΛt ≥ 0 (unit), its slip rate along −d; `off`: the present slack of a
/// facet the pair is not on (None: on it). (In the plane such a side keeps its unknown, whose
/// row is that slack; in space a polygon's sides the force is not on are no unknowns.)
#[derive(Clone, PartialEq)]
pub(super) struct Facet {
    pub dir: Vec<f64>,
    pub off: Option<f64>,
}

/// A pair's unknowns in the rate problem: its normal force, its tangential forces (one per
/// tangential coordinate) and its facets' slip rates.
pub(super) struct PairUnknowns<'a> {
    pub n: usize,
    pub t: &'a [usize],
    pub slips: &'a [usize],
}

/// The sides of a pair's cone at the increment's start, its force (λn, λt) (`lt` along its
/// tangential coordinates), of outward normals `directions` (`directions`): only those the
/// force is on can slip at the start (the others' slip rates are 0: their present slack is
/// positive), so in space only those are unknowns; in the plane both sides are.
pub(super) fn facets(
    law: &Coulomb,
    (ln, lt): (f64, &[f64]),
    directions: Vec<Vec<f64>>,
    tol: f64,
) -> Vec<Facet> {
    let facet = |dir: Vec<f64>| {
        let slack = law.capacity(ln) - dir.iter().zip(lt).map(|(d, l)| d * l).sum::<f64>();
        Facet { dir, off: (slack > tol).then_some(slack) }
    };
    let space = lt.len() == 2;
    directions.into_iter().map(facet).filter(|f| !space || f.off.is_none()).collect()
}

/// The outward normals of a pair's cone facets in its tangential coordinates (friction force
/// `lt`): along one tangent its two sides −t, +t (exact); in its tangent plane the sides of
/// the polygon it slips on (`polygon`: `coulomb`), or for a pair on the round cone `FACETS`
/// sides of the polygon circumscribed about it, the first along its friction force (at zero
/// force along `held`, the held slip direction of a slipping pair, else t1), so that a pair on
/// the cone is on it, and the facets `laid` about its stray slips.
pub(super) fn directions(
    law: &Coulomb,
    lt: &[f64],
    polygon: Option<([f64; 2], bool)>,
    held: Option<[f64; 2]>,
    laid: &[[f64; 2]],
    tol: f64,
) -> Vec<Vec<f64>> {
    if lt.len() == 1 {
        return vec![vec![-1.0], vec![1.0]];
    }
    if let Some((e, vertex)) = polygon {
        return law.polygon(e, vertex).map(|d| d.to_vec()).collect();
    }
    let [c, s] = match norm(lt) {
        size if size > tol => [lt[0] / size, lt[1] / size],
        _ => held.unwrap_or([1.0, 0.0]),
    };
    (0..FACETS)
        .map(|j| {
            let (sin, cos) = (2.0 * std::f64::consts::PI * j as f64 / FACETS as f64).sin_cos();
            vec![cos * c - sin * s, sin * c + cos * s]
        })
        .chain(laid.iter().map(|d| d.to_vec()))
        .collect()
}

/// The facet normals laid about a slip direction e (along t1, t2): e itself and its neighbours
/// on the polygon laid at e (`coulomb`, sides 2θ apart), so that the facet at e reaches θ to
/// either side, the facet design's band, and its corners are the polygon's vertices.
pub(super) fn facets_about(e: [f64; 2], turn: f64) -> [[f64; 2]; 3] {
    let turned = |a: f64| {
        let (s, c) = a.sin_cos();
        [c * e[0] - s * e[1], s * e[0] + c * e[1]]
    };
    [e, turned(2.0 * turn), turned(-2.0 * turn)]
}

/// The rows of a pair on its cone (see the module documentation): for Λt along each tangential
/// coordinate its slip rate `v` + Σ v_j d_j = 0 (slip against the facets' normals); for each
/// facet's slip rate v_j its facet μΛn − d_jᵀΛt, or its present slack when the pair is not on
/// it.
pub(super) fn slip_rows(
    prob: &mut Unknowns,
    mu: f64,
    facets: &[Facet],
    unknowns: PairUnknowns,
    v: Vec<Affine>,
) {
    let PairUnknowns { n, t, slips } = unknowns;
    for (k, (&t, v)) in t.iter().zip(v).enumerate() {
        prob.rows[t] = Some(
            facets
                .iter()
                .zip(slips)
                .fold(v, |row, (f, &s)| row.scaled_add(f.dir[k], &Affine::var(s))),
        );
    }
    // A facet the pair is not on cannot be reached at the increment's start: its slip rate is 0
    // (its row the present slack), whatever the forces would be after the whole remaining load
    // with the statuses held.
    for (f, &s) in facets.iter().zip(slips) {
        prob.rows[s] = Some(match f.off {
            Some(slack) => Affine::constant(slack),
            None => Affine {
                coef: std::iter::once((n, mu))
                    .chain(t.iter().zip(&f.dir).map(|(&t, &d)| (t, -d)))
                    .collect(),
                constant: 0.0,
            },
        });
    }
}

/// The status of a pair on its cone from its facets' solved slip `rates` (at most `noise`: no
/// slip), and, slipping in space, where it slips (`placement`): along one tangent
/// (`along_a_line`) in the sense of the faster of its two sides.
pub(super) fn slip_status(
    law: &Coulomb,
    along_a_line: bool,
    tangents: &[usize],
    (facets, polygon): (&[Facet], bool),
    rates: &[f64],
    noise: f64,
) -> (Status, Option<([f64; 2], bool)>) {
    if rates.iter().fold(0.0f64, |a, &r| a.max(r)) <= noise {
        (Status::Stick, None)
    } else if along_a_line {
        (Status::Slip { direction: if rates[0] >= rates[1] { 1 } else { -1 } }, None)
    } else {
        let placed = placement(law, tangents, facets, rates, noise, polygon);
        (Status::Slip { direction: 1 }, Some(placed))
    }
}

/// 3D: where a pair slipping at the facets' `rates` slips in the facet design (`coulomb`): on
/// the one side with a slip rate above `noise`, or at the vertex of two adjacent sides of a
/// polygon (its own, `polygon`, or laid about a stray slip: 2θ apart); else (a corner of
/// the rate problem's wider polygon) on the facet at its slip direction (`held_direction`).
fn placement(
    law: &Coulomb,
    tangents: &[usize],
    facets: &[Facet],
    rates: &[f64],
    noise: f64,
    polygon: bool,
) -> ([f64; 2], bool) {
    if tangents.len() == 1 {
        return (held_direction(tangents, facets, rates), false); // along its one free tangent
    }
    let slipping: Vec<[f64; 2]> = facets
        .iter()
        .zip(rates)
        .filter(|(_, &r)| r > noise)
        .map(|(f, _)| [f.dir[0], f.dir[1]])
        .collect();
    let adjacent = |a: [f64; 2], b: [f64; 2]| {
        (a[0] * b[0] + a[1] * b[1] - (2.0 * law.turn).cos()).abs() < SAME_SIDE
    };
    match slipping[..] {
        [a] => (a, false),
        [a, b] if polygon || adjacent(a, b) => {
            let m = [a[0] + b[0], a[1] + b[1]];
            let size = m[0].hypot(m[1]);
            ([m[0] / size, m[1] / size], true)
        }
        _ => (held_direction(tangents, facets, rates), false),
    }
}

/// 3D: the direction e (along t1, t2) of the friction force of a pair slipping at the
/// facets' rates: against its slip −Σ v_j d_j, the round cone's maximal dissipation.
fn held_direction(tangents: &[usize], facets: &[Facet], rates: &[f64]) -> [f64; 2] {
    let mut e = [0.0; 2];
    for (f, &r) in facets.iter().zip(rates) {
        tangents.iter().zip(&f.dir).for_each(|(&k, &d)| e[k] += r * d);
    }
    let size = e[0].hypot(e[1]);
    e.map(|c| c / size)
}

/// 3D: whether a pair slipping at zero force on the side at e has a force across e beyond the
/// facet design's band, tan θ μΛn (`coulomb`): the side is wider than the design's facet
/// (`rate_problem`'s stray slips).
pub(super) fn beyond_band(law: &Coulomb, e: [f64; 2], (ln, lt): (f64, &[f64]), tol: f64) -> bool {
    let band = law.cross_bound(ln);
    let across = e[0] * lt[1] - e[1] * lt[0];
    across.abs() > band * (1.0 - FACET_AGREEMENT) + tol
}

/// 3D: the direction of a force (Λn, Λt) beyond the round cone, in a corner of the rate
/// problem's polygon (by up to 1/cos(π/FACETS) − 1); None within it.
pub(super) fn beyond_round_cone(
    law: &Coulomb,
    (ln, lt): (f64, &[f64]),
    tol: f64,
) -> Option<[f64; 2]> {
    let size = norm(lt);
    (size > law.capacity(ln) * (1.0 + FACET_AGREEMENT) + tol).then(|| [lt[0] / size, lt[1] / size])
}

/// The Euclidean norm of a pair's tangential components (|λt| along one).
pub(super) fn norm(v: &[f64]) -> f64 {
    match v {
        [x] => x.abs(),
        _ => v.iter().map(|x| x * x).sum::<f64>().sqrt(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ROUND_OFF: f64 = 1e-12;

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < ROUND_OFF && (a[1] - b[1]).abs() < ROUND_OFF
    }

    /// A force on the round cone (μλn = 1 along (0.6, 0.8)) is on the first side of the square
    /// turned to it, and in space that side alone is an unknown; in the plane, on the side −t,
    /// both sides are, the other with its slack μλn + λt = 2.
    #[test]
    fn only_the_sides_a_force_is_on_are_unknowns_in_space() {
        let (law, tol) = (Coulomb::new(0.5, 0.1), 1e-12);
        let lt = [0.6, 0.8];
        let sides = directions(&law, &lt, None, None, &[], tol);
        assert_eq!(sides.len(), FACETS);
        assert!(close([sides[0][0], sides[0][1]], lt));
        let on = facets(&law, (2.0, &lt), sides, tol);
        assert!(on.len() == 1 && on[0].off.is_none() && close([on[0].dir[0], on[0].dir[1]], lt));
        let line =
            facets(&law, (2.0, &[-1.0]), directions(&law, &[-1.0], None, None, &[], tol), tol);
        assert!(line[0] == Facet { dir: vec![-1.0], off: None });
        assert!(line[1].dir == [1.0] && (line[1].off.unwrap() - 2.0).abs() < ROUND_OFF);
    }

    /// The solved slip rates read back: no rate above the noise sticks; along a line the pair
    /// slips in the sense of its faster side; in the tangent plane on the one side that slips,
    /// at the vertex between two adjacent sides of its polygon (e turned by θ), and at a corner
    /// of the wider square along Σ v_j d_j (against its slip).
    #[test]
    fn the_solved_rates_give_the_status_and_where_the_pair_slips() {
        let (law, noise) = (Coulomb::new(0.3, 0.1), 1e-12);
        let line = [Facet { dir: vec![-1.0], off: None }, Facet { dir: vec![1.0], off: None }];
        let status = |rates: &[f64]| slip_status(&law, true, &[0], (&line, false), rates, noise);
        assert_eq!(status(&[0.0, 1e-13]), (Status::Stick, None));
        assert_eq!(status(&[0.0, 2.0]), (Status::Slip { direction: -1 }, None));
        assert_eq!(status(&[2.0, 1.0]), (Status::Slip { direction: 1 }, None));
        let e = [0.6, 0.8];
        let own: Vec<Facet> =
            law.polygon(e, false).map(|d| Facet { dir: d.to_vec(), off: None }).collect();
        let mut rates = vec![0.0; own.len()];
        rates[2] = 1.0;
        let (_, placed) = slip_status(&law, false, &[0, 1], (&own, true), &rates, noise);
        let (d, vertex) = placed.expect("it slips in its tangent plane");
        assert!(!vertex && close(d, [own[2].dir[0], own[2].dir[1]]));
        (rates[0], rates[1], rates[2]) = (1.0, 0.5, 0.0);
        let (d, vertex) = slip_status(&law, false, &[0, 1], (&own, true), &rates, noise).1.unwrap();
        assert!(vertex && close(d, law.vertex_of(e, 1.0)));
        let square: Vec<Facet> = directions(&law, &[1.0, 0.0], None, None, &[], noise)
            .into_iter()
            .map(|dir| Facet { dir, off: None })
            .collect();
        let (d, vertex) =
            slip_status(&law, false, &[0, 1], (&square, false), &[3.0, 4.0, 0.0, 0.0], noise)
                .1
                .unwrap();
        assert!(!vertex && close(d, [0.6, 0.8]), "{d:?}");
    }

    /// The checks of the facet passes: a force beyond the round cone (not one on it) gives its
    /// direction; a force across the slip direction beyond tan θ μΛn (not one within) is
    /// beyond the band.
    #[test]
    fn the_passes_find_forces_beyond_the_round_cone_and_the_band() {
        let (law, tol) = (Coulomb::new(0.5, 0.1), 1e-12);
        assert_eq!(beyond_round_cone(&law, (2.0, &[0.6, 0.8]), tol), None);
        let d = beyond_round_cone(&law, (2.0, &[0.606, 0.808]), tol).expect("beyond");
        assert!(close(d, [0.6, 0.8]));
        let band = law.cross_bound(2.0);
        let e = [1.0, 0.0];
        assert!(!beyond_band(&law, e, (2.0, &[1.0, 0.9 * band]), tol));
        assert!(beyond_band(&law, e, (2.0, &[1.0, -1.1 * band]), tol));
    }
}
