//! The limit of planar sliding: a body held by frictional pairs on one plane (3D, `restraint::
//! friction_held`) carries a load in that plane, a force F and a moment M about the normal, only
//! while friction forces f_i with |f_i| ≤ c_i = μ_i λ_n,i balance it. At the limit it slides
//! rigidly with a planar motion q = (v, ω) (the velocity of a reference point, the rotation
//! about the normal: an instantaneous centre of rotation, at infinity for a translation), and
//! every pair's friction is c_i against its own velocity v + ω n × r_i. The set of loads the
//! pairs carry is convex with the support function (the dissipation)
//!
//!   D(q) = Σ c_i |A_i q|,   A_i q = v + ω J r_i,   J r = n × r,
//!
//! so a load w = (F, M) is carried iff w·q ≤ D(q) for every motion q (Goyal, Ruina and
//! Papadopoulos' limit surface: at the limit w = ∇D(q)).
//!
//! Along an increment the load and the normal forces are linear in its scale S (from the trial,
//! as the other events): w(S) = w₀ + S Δw, c_i(S) = c_i0 + S Δc_i. For one motion q the load
//! reaches q's supporting plane, w(S)·q = D_S(q), at the root of an affine function,
//!
//!   S(q) = (D₀(q) − w₀·q) / (Δw·q − ΔD(q)),
//!
//! and every S(q) bounds from above where the load leaves the set; with c_i ≥ 0 the set of S
//! whose load is carried is an interval (a max of affine functions of S is convex), so the
//! first S where the load reaches the limit is S* = min_q S(q). It is found by descent on the
//! unit sphere of motions: with R = w(S(q)) − ∇D_S(q) (the load the motion leaves unbalanced,
//! ⊥ q by Euler's identity), ∇S(q) = −R / (Δw·q − ΔD(q)), and the Newton step δq = H⁺R
//! (H = ∇²D_S, positive semidefinite with H q = 0, taken on q⊥) descends S; halved until S
//! falls. At S* the load is on the surface: R = 0 (a smooth point), or the centre is on a pair
//! (a kink of D: that pair's friction is anything within its capacity), which the descent
//! approaches and the end tests exactly, rotating about the pairs nearest its centre. Every
//! iterate is an upper bound of S*; the descent stops where |R| is round-off of Σ c_i
//! (`STATIONARY`), where S is exact to second order in R. With no moment (M = 0 about the
//! normal forces' centre) the minimizing motion is the translation along F and S* is the root
//! of |F(S)| = Σ c_i(S), Coulomb's T = μN for the body.
//!
//! Lengths are in units of the contact's size (positions about its centre), so that the three
//! components of q and of w are of one order.

use crate::contact::Frame;
use nalgebra::{Matrix2, Vector2};

/// |R| on q⊥ below this × Σ c_i: the motion balances the load (round-off of the sums).
const STATIONARY: f64 = 1e-13;
/// Newton steps of one descent (it converges in a few from the start it is given).
const MAX_STEPS: usize = 100;
/// Halvings of a step that does not lower S before the descent ends there.
const HALVINGS: usize = 40;
/// Pairs nearest the centre of rotation tried as the centre itself (a kink of D).
const NEAREST: usize = 3;
/// A centre beyond this × the contact's size is a translation (in words).
const FAR: f64 = 1e6;

/// A planar load: the force (along the plane's basis) and the moment about the normal through
/// the contact's centre, divided by its size.
pub(super) type Wrench = [f64; 3];

/// A body's frictional pairs on one plane, their capacities linear in the increment's scale.
pub(super) struct Contact {
    /// Each pair's position in the plane about the contact's centre, in units of its size.
    pub at: Vec<[f64; 2]>,
    /// Each pair's capacity c_i = μ_i λ_n,i at S = 0 and its rate.
    pub capacity: Vec<[f64; 2]>,
}

/// Where a load reaches the limit: the scale S and the unit motion q there.
#[derive(Debug, Clone, Copy)]
pub(super) struct Limit {
    pub scale: f64,
    pub motion: [f64; 3],
}

impl Limit {
    /// The instantaneous centre of the motion (about the contact's centre, in units of its
    /// size), None for a translation (a centre farther than `FAR`).
    pub fn centre(&self) -> Option<[f64; 2]> {
        let [vx, vy, w] = self.motion;
        // v + ω J p = 0  ⇒  p = J v / ω
        (w.abs() * FAR > vx.hypot(vy)).then(|| [-vy / w, vx / w])
    }
}

/// The first S in [0, 1] where the load w₀ + S Δw reaches the limit of `contact` (its
/// capacities c_i0 + S Δc_i), and the motion there. None when the load is carried up to S = 1,
/// or up to where a capacity falls to zero (a separation, which ends the increment first):
/// then at every S between (the carried S are an interval); or when it is zero there.
pub(super) fn first_reach(contact: &Contact, start: Wrench, rate: Wrench) -> Option<Limit> {
    let last = contact
        .capacity
        .iter()
        .filter(|c| c[1] < 0.0)
        .map(|c| (c[0] / -c[1]).max(0.0))
        .fold(1.0, f64::min);
    let end = add(start, rate, last);
    let at_end = Contact {
        at: contact.at.clone(),
        capacity: contact.capacity.iter().map(|c| [c[0] + last * c[1], 0.0]).collect(),
    };
    let end_limit = proportional(&at_end, end)?;
    if end_limit.scale > 1.0 {
        return None;
    }
    // the motion that leaves the end load outside reaches it inside the increment
    let path = Path { contact, start, rate };
    Some(path.descend(end_limit.motion))
}

/// The factor k at which k × `load` reaches the limit of `contact` (constant capacities):
/// 1/k is the load's share of what the pairs carry (its gauge). None for a zero load.
pub(super) fn proportional(contact: &Contact, load: Wrench) -> Option<Limit> {
    let size = norm(load);
    (size > 0.0)
        .then(|| Path { contact, start: [0.0; 3], rate: load }.descend(load.map(|x| x / size)))
}

/// A load linear in S on a contact whose capacities are.
struct Path<'a> {
    contact: &'a Contact,
    start: Wrench,
    rate: Wrench,
}

impl Path<'_> {
    /// S(q): where the load reaches the supporting plane of motion q (0 when it starts on or
    /// beyond it, ∞ when it never does).
    fn reach(&self, q: [f64; 3]) -> f64 {
        let (d0, dd) = self.contact.dissipation(q);
        let gap = d0 - dot(self.start, q);
        let closing = dot(self.rate, q) - dd;
        match () {
            _ if gap <= 0.0 => 0.0,
            _ if closing <= 0.0 => f64::INFINITY,
            _ => gap / closing,
        }
    }

    /// Descent of S(q) on the unit sphere from `q` (finite S), then the pairs nearest its
    /// centre as the centre itself.
    fn descend(&self, q: [f64; 3]) -> Limit {
        let mut best = Limit { scale: self.reach(q), motion: q };
        for _ in 0..MAX_STEPS {
            let Some(step) = self.newton_step(best) else { break };
            let mut lower = (0..HALVINGS).scan(1.0, |alpha, _| {
                let q = unit(add(best.motion, step, *alpha));
                *alpha *= 0.5;
                Some(Limit { scale: self.reach(q), motion: q })
            });
            match lower.find(|l| l.scale < best.scale) {
                Some(l) => best = l,
                None => break,
            }
        }
        for j in self.contact.nearest(best.motion) {
            let w = best.motion[2].signum();
            let jr = perp(self.contact.at[j]);
            let q = unit([-w * jr[0], -w * jr[1], w]);
            let s = self.reach(q);
            if s < best.scale {
                best = Limit { scale: s, motion: q };
            }
        }
        best
    }

    /// δq = H⁺R on q⊥ at S(q) (a gradient step where H is singular there: collinear pairs);
    /// None when R is round-off, or S is 0 or ∞.
    fn newton_step(&self, at: Limit) -> Option<[f64; 3]> {
        let (q, s) = (at.motion, at.scale);
        if !(s > 0.0 && s.is_finite()) {
            return None;
        }
        let load = add(self.start, self.rate, s);
        let (mut residual, mut hessian, mut total) = (load, [[0.0; 3]; 3], 0.0);
        for (i, c) in self.contact.capacity.iter().enumerate() {
            let c = c[0] + s * c[1];
            let jr = perp(self.contact.at[i]);
            let a = self.contact.velocity(i, q);
            let speed = a[0].hypot(a[1]);
            total += c.abs();
            if speed == 0.0 {
                continue; // the centre on the pair: a kink (`descend` tries it)
            }
            let u = [a[0] / speed, a[1] / speed];
            let lift = |x: [f64; 2]| [x[0], x[1], jr[0] * x[0] + jr[1] * x[1]]; // A_iᵀ x
            let pushed = lift(u);
            (0..3).for_each(|k| residual[k] -= c * pushed[k]);
            // A_iᵀ (I − u uᵀ) A_i c/|A_i q|: the unit normal of u, lifted, squared
            let across = lift([-u[1], u[0]]);
            for r in 0..3 {
                for k in 0..3 {
                    hessian[r][k] += c / speed * across[r] * across[k];
                }
            }
        }
        let [e1, e2] = Frame::in_space(q, None).tangents; // an orthonormal basis of q⊥
        let r2 = Vector2::new(dot(e1, residual), dot(e2, residual));
        if r2.norm() <= STATIONARY * total {
            return None;
        }
        let quad = |x: [f64; 3], y: [f64; 3]| {
            (0..3).map(|r| x[r] * (0..3).map(|k| hessian[r][k] * y[k]).sum::<f64>()).sum::<f64>()
        };
        let h2 = Matrix2::new(quad(e1, e1), quad(e1, e2), quad(e2, e1), quad(e2, e2));
        let d = h2.cholesky().map_or(r2 / total.max(f64::MIN_POSITIVE), |ch| ch.solve(&r2));
        Some(add(e1.map(|x| d[0] * x), e2, d[1]))
    }
}

impl Contact {
    /// A_i q: pair i's velocity under motion q.
    fn velocity(&self, i: usize, q: [f64; 3]) -> [f64; 2] {
        let jr = perp(self.at[i]);
        [q[0] + q[2] * jr[0], q[1] + q[2] * jr[1]]
    }

    /// D₀(q) and its rate ΔD(q).
    fn dissipation(&self, q: [f64; 3]) -> (f64, f64) {
        (0..self.at.len()).fold((0.0, 0.0), |(d0, dd), i| {
            let a = self.velocity(i, q);
            let speed = a[0].hypot(a[1]);
            (d0 + self.capacity[i][0] * speed, dd + self.capacity[i][1] * speed)
        })
    }

    /// The pairs nearest the centre of a turning motion (none for a translation).
    fn nearest(&self, q: [f64; 3]) -> Vec<usize> {
        if q[2] == 0.0 {
            return vec![];
        }
        let mut by_speed: Vec<(f64, usize)> = (0..self.at.len())
            .map(|i| (self.velocity(i, q).map(f64::abs).iter().sum(), i))
            .collect();
        by_speed.sort_by(|a, b| a.0.total_cmp(&b.0));
        by_speed.into_iter().take(NEAREST).map(|(_, i)| i).collect()
    }
}

/// J r = n × r in the plane.
fn perp(r: [f64; 2]) -> [f64; 2] {
    [-r[1], r[0]]
}

/// a + k b.
fn add(a: [f64; 3], b: [f64; 3], k: f64) -> [f64; 3] {
    [a[0] + k * b[0], a[1] + k * b[1], a[2] + k * b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    a.map(|x| x / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The limits below are closed forms of a few operations on O(1) numbers; the descent
    /// stops where the residual is 1e-13 of Σ c, so S is exact to round-off (second order).
    const ROUND_OFF: f64 = 1e-12;

    fn contact(points: &[[f64; 2]], capacity: &[f64]) -> Contact {
        Contact { at: points.to_vec(), capacity: capacity.iter().map(|&c| [c, 0.0]).collect() }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= ROUND_OFF * b.abs().max(1.0)
    }

    const SQUARE: [[f64; 2]; 4] = [[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]];

    /// A pure moment on four equal pairs at a square's corners turns it about its centre: the
    /// pairs carry M = Σ c |r| = 4 c √2.
    #[test]
    fn a_pure_moment_turns_the_square_about_its_centre() {
        let c = 0.3;
        let l = proportional(&contact(&SQUARE, &[c; 4]), [0.0, 0.0, 1.0]).unwrap();
        assert!(close(l.scale, 4.0 * c * 2f64.sqrt()), "{l:?}");
        let centre = l.centre().unwrap();
        assert!(centre[0].abs() < ROUND_OFF && centre[1].abs() < ROUND_OFF, "{centre:?}");
    }

    /// A force through the centre of a symmetric contact translates it at |F| = Σ c (Coulomb's
    /// T = μN), whatever its direction.
    #[test]
    fn a_force_through_the_centre_translates_at_mu_n() {
        let c = [0.1, 0.2, 0.1, 0.2]; // symmetric about the centre
        for angle in [0.0f64, 0.3, 2.0] {
            let l = proportional(&contact(&SQUARE, &c), [angle.cos(), angle.sin(), 0.0]).unwrap();
            assert!(close(l.scale, 0.6) && l.centre().is_none(), "{angle}: {l:?}");
        }
    }

    /// The centre on a pair (a kink of D): a pure moment on the square with a fifth pair at its
    /// centre turns it about that pair, which carries nothing: M = Σ_corners c |r|.
    #[test]
    fn a_centre_on_a_pair_is_found_exactly() {
        let mut points = SQUARE.to_vec();
        points.push([0.0, 0.0]);
        let l =
            proportional(&contact(&points, &[0.3, 0.3, 0.3, 0.3, 5.0]), [0.0, 0.0, -2.0]).unwrap();
        assert!(close(l.scale, 4.0 * 0.3 * 2f64.sqrt() / 2.0), "{l:?}");
    }

    /// Two pairs at (±1, 0) (collinear: D is flat across the line), a force F along y at x = d:
    /// the nearer pair saturates, F(1 + d)/2 = c, and the far one is the centre.
    #[test]
    fn an_off_centre_force_on_two_pairs_turns_about_the_far_one() {
        let (c, d) = (0.25, 0.4);
        let l = proportional(&contact(&[[-1.0, 0.0], [1.0, 0.0]], &[c, c]), [0.0, 1.0, d]).unwrap();
        assert!(close(l.scale, 2.0 * c / (1.0 + d)), "{l:?}");
        let centre = l.centre().unwrap();
        assert!((centre[0] + 1.0).abs() < 1e-9 && centre[1].abs() < 1e-9, "{centre:?}");
    }

    /// Along an increment: capacities c (1 + S) and a force F₀ + S ΔF through the centre reach
    /// Σ c (1 + S) = |F₀ + S ΔF| at the root of that linear equation; a load that stays inside
    /// has no limit.
    #[test]
    fn an_increment_reaches_the_limit_where_capacity_and_load_meet() {
        let c = 0.1;
        let k = Contact { at: SQUARE.to_vec(), capacity: vec![[c, c]; 4] };
        // 4c (1 + S) = 0.2 + 0.8 S  ⇒  S = (0.4 − 0.2) / (0.8 − 0.4) = 0.5
        let l = first_reach(&k, [0.2, 0.0, 0.0], [0.8, 0.0, 0.0]).unwrap();
        assert!(close(l.scale, 0.5), "{l:?}");
        assert!(first_reach(&k, [0.2, 0.0, 0.0], [0.3, 0.0, 0.0]).is_none());
    }

    /// Every motion's S(q) bounds the limit from above (the load reaches q's supporting plane
    /// there), so the descent's S is below S(q) of every motion sampled on the sphere, on
    /// irregular contacts and loads (a stalled descent would be above some).
    #[test]
    fn no_motion_reaches_the_limit_earlier() {
        let mut seed = 12345u64;
        let mut next = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20 {
            let n = 3 + (8.0 * next()) as usize;
            let at: Vec<[f64; 2]> =
                (0..n).map(|_| [2.0 * next() - 1.0, 2.0 * next() - 1.0]).collect();
            let capacity: Vec<f64> = (0..n).map(|_| next()).collect();
            let k = contact(&at, &capacity);
            let load = [2.0 * next() - 1.0, 2.0 * next() - 1.0, 2.0 * next() - 1.0];
            let l = proportional(&k, load).unwrap();
            let path = Path { contact: &k, start: [0.0; 3], rate: load };
            for i in 0..200 {
                for j in 0..100 {
                    let (theta, phi) = (
                        std::f64::consts::PI * (i as f64 + 0.5) / 200.0,
                        std::f64::consts::TAU * j as f64 / 100.0,
                    );
                    let q = [theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()];
                    assert!(
                        l.scale <= path.reach(q) * (1.0 + ROUND_OFF),
                        "{l:?} above S = {} at {q:?}",
                        path.reach(q)
                    );
                }
            }
        }
    }
}
