//! Coulomb's law of friction on one pair (paper eqs. 1–3, 41, 52–55), in the plane and in space.
//!
//! In space the cone |λ_t| ≤ μ λ_n is round. A pair that has never slipped since it closed
//! sticks inside the round cone and starts to slip exactly where its force leaves it (a
//! quadratic in S: `slip_onset_scale`), on the facet tangent there. From that onset on, until
//! it opens, the pair's cone is the regular polygon of N sides circumscribed about the round
//! cone with that facet as one side (Klarbring's faceted cone, laid at the pair's own onset):
//! its sides' outward normals are e₀ turned by multiples of 2θ, θ = π/N ≤ `slip_turn` (N even, so
//! that a slip reversed is a side too). Every later switch is linear in S, and none moves the
//! force (no jump, hence no correction at fixed load and no chattering of the pairs such a
//! correction would move):
//! - on a *facet* e the pair slips along −e (normality) with μ λ_n along e and its cross force
//!   λ_⊥ = e⊥·λ_t free within ± tan θ μ λ_n (the facet's band, `contact`'s cross row);
//! - where λ_⊥ reaches the band's edge the force is at a *vertex* m = e turned by θ, where two
//!   sides meet: there its force is μ λ_n / cos θ along m and it slips in the vertex's normal
//!   cone (within θ of −m); a slip beyond that cone on one side goes onto that side's facet
//!   (eq. 55: at S = 0);
//! - a slip that turns against the force sticks (eqs. 54–55), and the stuck pair slips again
//!   where its force reaches a side of its polygon (eq. 53 side by side).
//! The force is thus never beyond the round cone by more than 1/cos θ − 1 (0.5 % at θ ≈ 0.1)
//! and lags its slip by at most θ. In the plane the cone is the two sides ± (eq. 41).

/// Coulomb's law with friction coefficient μ and, in space, the polygon's half-angle θ.
#[derive(Debug, Clone, Copy)]
pub struct Coulomb {
    pub mu: f64,
    /// θ = π/N: half the angle between adjacent sides of the polygon.
    pub turn: f64,
}

/// How a pair slipping at a vertex leaves it (`Coulomb::vertex_exit`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VertexExit {
    Stick,
    /// Onto the facet on this side (±1) of the vertex.
    Facet(f64),
}

impl Coulomb {
    /// The law with friction coefficient μ, its polygon's sides at most 2 `slip_turn` apart.
    pub fn new(mu: f64, slip_turn: f64) -> Self {
        Coulomb { mu, turn: polygon_half_angle(slip_turn) }
    }

    /// Whether there is friction at all (μ > 0); μ = 0 is frictionless sliding.
    pub fn acts(&self) -> bool {
        self.mu > 0.0
    }

    /// μ λ_n: the largest friction force of the round cone (eq. 1); 0 without compression.
    pub fn capacity(&self, lambda_n: f64) -> f64 {
        self.mu * lambda_n.max(0.0)
    }

    /// μ Δλ_n: the rate of the capacity along an increment of normal force rate Δλ_n (that
    /// keeps the pair pressed).
    pub fn capacity_rate(&self, dlambda_n: f64) -> f64 {
        self.mu * dlambda_n
    }

    /// tan θ μ λ_n: the largest cross force on a facet.
    pub fn cross_bound(&self, lambda_n: f64) -> f64 {
        self.turn.tan() * self.capacity(lambda_n)
    }

    /// μ λ_n / cos θ: the largest friction force the polygon admits (at its vertices).
    pub fn polygon_capacity(&self, lambda_n: f64) -> f64 {
        self.capacity(lambda_n) / self.turn.cos()
    }

    /// λ_t of a pair slipping on the facet at e (along t1, t2): μ λ_n along e, the cross part of
    /// `lambda_t` kept within the band (eq. 62 in space; `cross`: false for a facet with no
    /// cross row, whose force is μ λ_n e).
    pub fn on_facet(
        &self,
        lambda_n: f64,
        e: [f64; 2],
        lambda_t: [f64; 2],
        cross: bool,
    ) -> [f64; 2] {
        let along = self.capacity(lambda_n);
        let across = if cross {
            let most = self.cross_bound(lambda_n);
            (e[0] * lambda_t[1] - e[1] * lambda_t[0]).clamp(-most, most)
        } else {
            0.0
        };
        [along * e[0] - across * e[1], along * e[1] + across * e[0]]
    }

    /// λ_t of a pair slipping at the vertex m: μ λ_n / cos θ along m, where both sides hold.
    pub fn vertex_force(&self, lambda_n: f64, m: [f64; 2]) -> [f64; 2] {
        let size = self.polygon_capacity(lambda_n);
        [size * m[0], size * m[1]]
    }

    /// τ = λ_t / λ_n of a pair slipping in the plane in direction d = ±1 (eq. 41): −d μ.
    pub fn planar_slip_ratio(&self, direction: i8) -> f64 {
        -(direction as f64) * self.mu
    }

    /// τ = λ_t / λ_n (along t1, t2) of a pair slipping on the facet at e (μ e, no cross force)
    /// or, `vertex`, at the vertex e (μ e / cos θ).
    pub fn slip_ratio(&self, e: [f64; 2], vertex: bool) -> [f64; 2] {
        if vertex {
            self.vertex_force(1.0, e)
        } else {
            self.on_facet(1.0, e, [0.0; 2], false)
        }
    }

    /// The vertex a facet's band ends at on side `side` (±1): m = e turned by θ.
    pub fn vertex_of(&self, e: [f64; 2], side: f64) -> [f64; 2] {
        rotated(e, side.signum() * self.turn)
    }

    /// The facet of a vertex m on side `side`: e = m turned by θ that way.
    pub fn facet_of(&self, m: [f64; 2], side: f64) -> [f64; 2] {
        rotated(m, side.signum() * self.turn)
    }

    /// Where a pair slipping at the vertex m leaves it, from its slip rate (along t1, t2; a
    /// dissipative slip is against the force): within θ of −m its slip is in the vertex's normal
    /// cone (−a e₊ − b e₋, a, b ≥ 0) and it stays; beyond θ on one side it goes onto that side's
    /// facet; along the force (m·rate > 0) it sticks. `noise`: a rate below it is no slip.
    pub fn vertex_exit(&self, m: [f64; 2], rate: [f64; 2], noise: f64) -> Option<VertexExit> {
        let along = -(m[0] * rate[0] + m[1] * rate[1]);
        let across = -(m[0] * rate[1] - m[1] * rate[0]);
        if -along > noise {
            return Some(VertexExit::Stick);
        }
        let beyond = across.abs() - self.turn.tan() * along.max(0.0);
        (beyond > noise).then(|| VertexExit::Facet(across.signum()))
    }

    /// The outward normals of the polygon that has `e` as a side (or, `vertex`, as a vertex).
    pub fn polygon(&self, e: [f64; 2], vertex: bool) -> impl Iterator<Item = [f64; 2]> {
        let first = if vertex { rotated(e, self.turn) } else { e };
        let (turn, sides) = (self.turn, (std::f64::consts::PI / self.turn).round() as usize);
        (0..sides).map(move |k| rotated(first, 2.0 * turn * k as f64))
    }

    /// How fast a force moves out through the side with outward normal d at rates (Δλ_n, Δλ_t):
    /// d·Δλ_t − μ Δλ_n (the rate of that side's excess; eq. 53's denominator).
    pub fn outward_rate(&self, d: [f64; 2], (dln, dlt): (f64, [f64; 2])) -> f64 {
        d[0] * dlt[0] + d[1] * dlt[1] - self.capacity_rate(dln)
    }

    /// Where the force of a pair stuck inside its polygon (sides about e: `polygon`) reaches a
    /// side: the smallest S ≥ 0 with e_j·(λ_t0 + S Δλ_t) = μ (λ_n0 + S Δλ_n) crossed outwards
    /// (eq. 53 side by side). A force on a side (or beyond it by round-off) moving out leaves at
    /// S = 0. None: it stays inside (or its rates are noise).
    pub fn polygon_exit_scale(
        &self,
        e: [f64; 2],
        vertex: bool,
        (ln, lt): (f64, [f64; 2]),
        (dln, dlt): (f64, [f64; 2]),
        noise: f64,
    ) -> Option<f64> {
        let mu = self.mu;
        self.polygon(e, vertex)
            .filter_map(|d| {
                let rate = self.outward_rate(d, (dln, dlt));
                let slack = mu * ln - (d[0] * lt[0] + d[1] * lt[1]);
                (rate > noise).then(|| (slack / rate).max(0.0))
            })
            .fold(None, |best: Option<f64>, s| Some(best.map_or(s, |b| b.min(s))))
    }

    /// Where on its polygon (sides about e) a force λ_t lies: the side it is on, or the vertex
    /// (within `tol` of two sides). (unit direction, at a vertex).
    pub fn place_on_polygon(
        &self,
        e: [f64; 2],
        vertex: bool,
        lambda_n: f64,
        lambda_t: [f64; 2],
        tol: f64,
    ) -> ([f64; 2], bool) {
        let cap = self.capacity(lambda_n);
        let excess = |d: [f64; 2]| d[0] * lambda_t[0] + d[1] * lambda_t[1] - cap;
        let mut sides: Vec<[f64; 2]> = self.polygon(e, vertex).collect();
        sides.sort_by(|a, b| excess(*b).total_cmp(&excess(*a)));
        let (first, second) = (sides[0], sides[1]);
        let adjacent = first[0] * second[0] + first[1] * second[1] > (2.0 * self.turn).cos() - 1e-9;
        if adjacent && excess(second) >= excess(first) - tol {
            let m = [first[0] + second[0], first[1] + second[1]];
            let size = m[0].hypot(m[1]);
            return ([m[0] / size, m[1] / size], true);
        }
        (first, false)
    }

    /// The largest amount by which a force exceeds its cone: the round one, or its polygon.
    pub fn excess(
        &self,
        polygon: Option<([f64; 2], bool)>,
        lambda_n: f64,
        lambda_t: [f64; 2],
    ) -> f64 {
        match polygon {
            None => lambda_t[0].hypot(lambda_t[1]) - self.capacity(lambda_n),
            Some((e, vertex)) => {
                self.polygon(e, vertex)
                    .map(|d| d[0] * lambda_t[0] + d[1] * lambda_t[1])
                    .fold(f64::NEG_INFINITY, f64::max)
                    - self.capacity(lambda_n)
            }
        }
    }

    /// Stick → slip on the round cone (3D, a pair that has not slipped since it closed): the
    /// smallest S ≥ 0 where the friction force leaves the cone, g(S) = |λ_t0 + S Δλ_t| −
    /// μ (λ_n0 + S Δλ_n) crossing zero upwards. g is convex; its zeros with λ_n(S) > 0 are roots
    /// of the quadratic a S² + b S + c = 0, a = |Δλ_t|² − μ²Δλ_n², b = 2(λ_t0·Δλ_t − μ² λ_n0 Δλ_n),
    /// c = |λ_t0|² − μ² λ_n0² (the squared cone, whose other roots are on its mirror image
    /// through the apex, λ_n < 0). A pair on the cone or outside it by round-off (g(0) ≥ 0: also
    /// one whose λ_n is a round-off below zero just after it closed, where the squared cone's c
    /// and b describe the mirror image) slips at S = 0 when g grows there, also one at zero force
    /// sheared with no normal force rate to hold it (if it is pulled off, its separation at S = 0
    /// comes first); one that moves inwards first slips where it leaves again. None: the
    /// increment stays inside (or its rates are noise).
    pub fn slip_onset_scale(
        &self,
        (ln, lt): (f64, [f64; 2]),
        (dln, dlt): (f64, [f64; 2]),
        noise: f64,
    ) -> Option<f64> {
        let mu = self.mu;
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
        let roots = if disc < 0.0 {
            [f64::INFINITY; 2]
        } else {
            [
                if a != 0.0 { q / a } else { f64::INFINITY },
                if q != 0.0 { c / q } else { f64::INFINITY },
            ]
        };
        // where the cone itself (λ_n(S) > 0) is crossed outwards (g' = 2aS + b > 0); a pair on
        // the cone is not leaving at the point it starts from
        let leaving = |s: f64| {
            s.is_finite()
                && (s > 0.0 || (s == 0.0 && inside))
                && 2.0 * a * s + b > 0.0
                && ln + s * dln > 0.0
        };
        let exit = roots
            .into_iter()
            .filter(|&s| leaving(s))
            .fold(None, |best: Option<f64>, s| Some(best.map_or(s, |b| b.min(s))));
        if inside {
            return exit;
        }
        // on or outside the cone: g's slope at S = 0 (along λ_t0, or from the apex)
        let slope = if size > 0.0 { (lt[0] * dlt[0] + lt[1] * dlt[1]) / size } else { shear_rate }
            - mu * dln;
        if slope > 0.0 {
            return Some(0.0);
        }
        // moving inwards first: it leaves again where it crosses outwards; with no such crossing
        // it either stays inside (pressed more than sheared: g falls for good) or never enters
        exit.or((shear_rate > mu * dln).then_some(0.0))
    }

    /// Stick → slip in the plane (eqs. 52–53), on either side of the cone: λ_t reaching +μ λ_n
    /// slips along −t (d = −1), −μ λ_n along +t (d = 1); (d, S) of each side the increment
    /// moves towards.
    pub fn planar_onset_scales(
        &self,
        (ln, lt): (f64, f64),
        (dln, dlt): (f64, f64),
        noise: f64,
    ) -> Vec<(i8, f64)> {
        let mu = self.mu;
        [(-1i8, 1.0), (1, -1.0)]
            .into_iter()
            .filter_map(|(direction, side)| {
                let den = side * dlt - mu * dln;
                (den > noise).then(|| (direction, (mu * ln - side * lt) / den))
            })
            .collect()
    }

    /// A pair slipping on the facet with cross direction e⊥ = `cross`: where its cross force
    /// λ_⊥ = e⊥·λ_t reaches ± tan θ μ λ_n (the vertex on that side), linear in S on either side
    /// as eqs. 52–53 in the plane: (side ±1, S) of each side the increment reaches.
    pub fn facet_turn_scales(
        &self,
        cross: [f64; 2],
        (ln, lt): (f64, [f64; 2]),
        (dln, dlt): (f64, [f64; 2]),
        noise: f64,
    ) -> Vec<(i8, f64)> {
        let k = self.turn.tan() * self.mu;
        let across = cross[0] * lt[0] + cross[1] * lt[1];
        let rate = cross[0] * dlt[0] + cross[1] * dlt[1];
        [1i8, -1]
            .into_iter()
            .filter_map(|side| {
                let den = side as f64 * rate - k * dln;
                (den > noise).then(|| (side, ((k * ln - side as f64 * across) / den).max(0.0)))
            })
            .collect()
    }
}

/// The friction of a body's closed pairs taken together, for its check of gross sliding
/// (`driver::restraint`): their mean coefficient μ̄, each pair counted once. Its capacity μ̄ N
/// under the body's normal load N is the pairs' Σ μ λ_n when they share μ (Σ λ_n = N); with
/// different coefficients it weights each pair alike, not by its λ_n: an estimate.
#[derive(Debug, Clone, Copy)]
pub struct MeanCoulomb {
    pub mu: f64,
}

impl MeanCoulomb {
    /// μ̄ of `laws` (0 with none).
    pub fn of<'a>(laws: impl ExactSizeIterator<Item = &'a Coulomb>) -> Self {
        let n = laws.len();
        MeanCoulomb { mu: laws.map(|law| law.mu).sum::<f64>() / n.max(1) as f64 }
    }

    /// μ̄ N: the tangential load the pairs hold together under the normal load N ≥ 0.
    pub fn capacity(&self, normal_load: f64) -> f64 {
        self.mu * normal_load
    }
}

/// θ = π/N for the smallest even N ≥ 4 with π/N ≤ `slip_turn` (0: the plane, no polygon).
fn polygon_half_angle(slip_turn: f64) -> f64 {
    if slip_turn <= 0.0 {
        return 0.0;
    }
    let half_sides = (std::f64::consts::FRAC_PI_2 / slip_turn).ceil().max(2.0); // a square at least
    std::f64::consts::FRAC_PI_2 / half_sides
}

/// `v` turned by `angle` (counter-clockwise in the (t1, t2) plane).
fn rotated(v: [f64; 2], angle: f64) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    const ROUND_OFF: f64 = 1e-12;

    fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
        a[0] * b[0] + a[1] * b[1]
    }

    /// No compression, no friction: λ_n ≤ 0 gives zero capacity, a zero band and a zero force
    /// on any facet (the panic of a slipping pair at λ_n = −round-off was a negative band).
    #[test]
    fn without_compression_the_law_carries_nothing() {
        let law = Coulomb::new(0.3, 0.1);
        for ln in [0.0, -1.46e-13, -2.0] {
            assert_eq!(law.capacity(ln), 0.0);
            assert_eq!(law.cross_bound(ln), 0.0);
            assert_eq!(law.on_facet(ln, [0.6, 0.8], [0.2, -0.4], true), [0.0, 0.0]);
            assert_eq!(law.vertex_force(ln, [0.6, 0.8]), [0.0, 0.0]);
        }
    }

    /// The pairs' mean law: μ̄ N is Σ μ λ_n when they share μ (normal forces summing to N),
    /// the mean of their μ otherwise, and nothing without pairs.
    #[test]
    fn the_mean_law_holds_what_its_pairs_hold_together() {
        let same = [Coulomb::new(0.3, 0.1); 3];
        let lambda_n = [1.0, 2.5, 0.5];
        let together: f64 = same.iter().zip(lambda_n).map(|(law, ln)| law.capacity(ln)).sum();
        let n: f64 = lambda_n.iter().sum();
        assert!((MeanCoulomb::of(same.iter()).capacity(n) - together).abs() < ROUND_OFF * n);
        let mixed = [Coulomb::new(0.2, 0.1), Coulomb::new(0.6, 0.1)];
        assert!((MeanCoulomb::of(mixed.iter()).mu - 0.4).abs() < ROUND_OFF);
        assert_eq!(MeanCoulomb::of([].iter()).capacity(5.0), 0.0);
    }

    /// The polygon: N even sides, θ = π/N ≤ slip_turn, so that a reversed side is a side.
    #[test]
    fn the_polygon_has_an_even_number_of_sides_within_the_turn() {
        for slip_turn in [0.1, 0.05, 0.3, 1.0, std::f64::consts::FRAC_PI_2] {
            let law = Coulomb::new(0.3, slip_turn);
            let sides: Vec<[f64; 2]> = law.polygon([0.6, 0.8], false).collect();
            assert!(law.turn <= slip_turn + ROUND_OFF && sides.len() % 2 == 0 && sides.len() >= 2);
            assert!((sides.len() as f64 * law.turn - std::f64::consts::PI).abs() < ROUND_OFF);
            assert!(sides
                .iter()
                .any(|d| (d[0] + 0.6).abs() < ROUND_OFF && (d[1] + 0.8).abs() < ROUND_OFF));
        }
    }

    /// The projection onto a facet: on it, μ λ_n along e and the cross part kept; inside the
    /// band and outside it (clamped to ± tan θ μ λ_n); without a cross row, μ λ_n e.
    #[test]
    fn the_projection_puts_the_force_on_the_facet_within_its_band() {
        let (law, ln, e) = (Coulomb::new(0.5, 0.1), 4.0, [0.6, 0.8]);
        let perp = [-e[1], e[0]];
        let bound = law.turn.tan() * 0.5 * ln;
        for (across, kept) in
            [(0.0, 0.0), (0.5 * bound, 0.5 * bound), (3.0 * bound, bound), (-3.0 * bound, -bound)]
        {
            let f = [1.7 * e[0] + across * perp[0], 1.7 * e[1] + across * perp[1]];
            let on = law.on_facet(ln, e, f, true);
            assert!(
                (dot(on, e) - 0.5 * ln).abs() < ROUND_OFF
                    && (dot(on, perp) - kept).abs() < ROUND_OFF
            );
        }
        let on = law.on_facet(ln, e, [5.0, -3.0], false);
        assert!((on[0] - 2.0 * e[0]).abs() < ROUND_OFF && (on[1] - 2.0 * e[1]).abs() < ROUND_OFF);
    }

    /// The projection of a slipping pair's force onto its facet, for a force without compression
    /// (λ_n ≤ 0: nothing), inside the round cone, on it and outside it, in every direction about
    /// e: the result is on the facet (μ λ_n along e), within the polygon, beyond the round cone
    /// by at most 1/cos θ − 1, and keeps a cross force already within the band.
    #[test]
    fn the_projection_onto_the_cone_holds_wherever_the_force_is() {
        let (law, e) = (Coulomb::new(0.8, 0.1), [0.28, -0.96]);
        let perp = [-e[1], e[0]];
        for ln in [-1.0, -1e-14, 0.0, 2.5] {
            let cap = law.capacity(ln);
            for size in [0.0, 0.5, 1.0, 3.0] {
                for k in 0..16 {
                    // |λ_t| = size × the cone's radius at λ_n = 2.5, turned k π/8 from e
                    let d = rotated(e, k as f64 * std::f64::consts::PI / 8.0);
                    let f = d.map(|v| size * law.capacity(2.5) * v);
                    let on = law.on_facet(ln, e, f, true);
                    if ln <= 0.0 {
                        assert_eq!(on, [0.0; 2], "λ_n = {ln}");
                        continue;
                    }
                    assert!((dot(on, e) - cap).abs() < ROUND_OFF * cap);
                    assert!(law.excess(Some((e, false)), ln, on) < ROUND_OFF * cap);
                    assert!(dot(on, on).sqrt() <= cap / law.turn.cos() * (1.0 + ROUND_OFF));
                    let across = dot(f, perp);
                    if across.abs() <= law.cross_bound(ln) {
                        assert!((dot(on, perp) - across).abs() < ROUND_OFF * cap);
                    }
                }
            }
        }
    }

    /// τ = λ_t / λ_n of a slipping pair: −d μ in the plane; μ e on a facet and μ e / cos θ at a
    /// vertex in space, the forces `on_facet` and `vertex_force` give per unit λ_n.
    #[test]
    fn the_slip_ratio_is_the_force_per_unit_normal_force() {
        let law = Coulomb::new(0.4, 0.1);
        assert_eq!((law.planar_slip_ratio(1), law.planar_slip_ratio(-1)), (-0.4, 0.4));
        let e = [0.6, 0.8];
        let on = law.slip_ratio(e, false);
        assert!((on[0] - 0.24).abs() < ROUND_OFF && (on[1] - 0.32).abs() < ROUND_OFF);
        let at = law.slip_ratio(e, true);
        let size = 0.4 / law.turn.cos();
        assert!((at[0] - size * 0.6).abs() < ROUND_OFF && (at[1] - size * 0.8).abs() < ROUND_OFF);
    }

    /// A facet's band ends at a vertex: the force at the band's edge (θ off e) is the vertex's
    /// force (μ λ_n / cos θ along m = e turned by θ), on the next side too, at the opposite edge
    /// of its band; the vertex's facets are m ∓ θ; the force is on the polygon there.
    #[test]
    fn a_facets_edge_is_the_vertex_of_it_and_the_next_facet() {
        let (law, ln) = (Coulomb::new(0.3, 0.1), 10.0);
        let e = [0.6, 0.8];
        let perp = [-e[1], e[0]];
        for side in [1.0, -1.0] {
            let edge = [
                law.capacity(ln) * e[0] + side * law.cross_bound(ln) * perp[0],
                law.capacity(ln) * e[1] + side * law.cross_bound(ln) * perp[1],
            ];
            let m = law.vertex_of(e, side);
            let at_vertex = law.vertex_force(ln, m);
            assert!(
                (at_vertex[0] - edge[0]).abs() < ROUND_OFF
                    && (at_vertex[1] - edge[1]).abs() < ROUND_OFF,
                "{at_vertex:?} {edge:?}"
            );
            let back = law.facet_of(m, -side);
            assert!((back[0] - e[0]).abs() < ROUND_OFF && (back[1] - e[1]).abs() < ROUND_OFF);
            let next = law.facet_of(m, side);
            assert!(
                (dot(next, e) - (2.0 * law.turn).cos()).abs() < ROUND_OFF
                    && (dot(next, edge) - law.capacity(ln)).abs() < ROUND_OFF * ln
            );
            assert!(law.excess(Some((e, false)), ln, edge).abs() < ROUND_OFF * ln);
            let (placed, vertex) = law.place_on_polygon(e, false, ln, edge, 1e-9);
            assert!(vertex && (placed[0] - m[0]).abs() < 1e-9 && (placed[1] - m[1]).abs() < 1e-9);
        }
    }

    /// A pair at a vertex m stays while its slip is within θ of −m (the vertex's normal cone),
    /// goes onto the facet on the side its slip left it, and sticks when it slips along its force.
    #[test]
    fn a_vertex_is_left_where_the_slip_leaves_its_normal_cone() {
        let law = Coulomb::new(0.3, 0.1);
        let m = [0.6, 0.8];
        let m_perp = [-m[1], m[0]];
        let slip = |angle: f64| {
            let (s, c) = angle.sin_cos();
            [-(c * m[0] + s * m_perp[0]), -(c * m[1] + s * m_perp[1])] // the rate: against the force, turned
        };
        assert_eq!(law.vertex_exit(m, slip(0.0), 1e-14), None);
        assert_eq!(law.vertex_exit(m, slip(0.09), 1e-14), None);
        assert_eq!(law.vertex_exit(m, slip(0.11), 1e-14), Some(VertexExit::Facet(1.0)));
        assert_eq!(law.vertex_exit(m, slip(-0.5), 1e-14), Some(VertexExit::Facet(-1.0)));
        assert_eq!(law.vertex_exit(m, slip(3.0), 1e-14), Some(VertexExit::Stick));
        assert_eq!(law.vertex_exit(m, [1e-16, 0.0], 1e-14), None);
    }

    /// A stuck pair's force reaches its polygon where a side's equation holds (checked on it),
    /// on the side it moves to (here the reversed one), and nowhere before; a force shrinking
    /// inwards never does.
    #[test]
    fn a_stuck_force_leaves_its_polygon_on_a_side() {
        let (law, ln) = (Coulomb::new(0.4, 0.1), 5.0);
        let e = [1.0, 0.0];
        let lt = [1.9, 0.1];
        let dlt = [-2.0, 0.3];
        let s = law.polygon_exit_scale(e, false, (ln, lt), (0.0, dlt), 1e-14).expect("it leaves");
        let at = [lt[0] + s * dlt[0], lt[1] + s * dlt[1]];
        assert!(law.excess(Some((e, false)), ln, at).abs() < ROUND_OFF, "{s}");
        assert!((1..100).all(|k| law.excess(
            Some((e, false)),
            ln,
            [lt[0] + s * k as f64 / 100.0 * dlt[0], lt[1] + s * k as f64 / 100.0 * dlt[1]]
        ) < 0.0));
        assert!(at[0] < 0.0, "out on the reversed side: {at:?}");
        assert_eq!(law.polygon_exit_scale(e, false, (ln, lt), (1.0, [-0.1, 0.0]), 1e-14), None);
    }

    /// In the plane (eqs. 52–53): λ_n = 10, λ_t = 1, μ = 0.3, Δλ_n = 10, Δλ_t = 5 reaches
    /// +μλ_n at 1 + 5S = 0.3(10 + 10S), S = 1, slipping along −t; turned round it reaches −μλ_n
    /// at the same S; a rate into the cone reaches neither.
    #[test]
    fn in_the_plane_the_onset_is_where_the_force_reaches_a_side() {
        let law = Coulomb::new(0.3, 0.0);
        assert_eq!(law.planar_onset_scales((10.0, 1.0), (10.0, 5.0), 1e-14), vec![(-1, 1.0)]);
        assert_eq!(law.planar_onset_scales((10.0, -1.0), (10.0, -5.0), 1e-14), vec![(1, 1.0)]);
        assert!(law.planar_onset_scales((10.0, 1.0), (10.0, 1.0), 1e-14).is_empty());
    }

    /// The round cone (3D): the root lands on |λ_t| = μ λ_n (a pair inside going out; one on
    /// the cone moving inwards first, which leaves it at the later root; one moving inwards for
    /// good, which never slips), checked on the cone's own equation.
    #[test]
    fn round_cone_scale_lands_on_the_cone() {
        let (mu, noise) = (0.3, 1e-14);
        let law = Coulomb::new(mu, 0.1);
        let on_cone = |ln: f64, lt: [f64; 2], dln: f64, dlt: [f64; 2], s: f64| {
            (lt[0] + s * dlt[0]).hypot(lt[1] + s * dlt[1]) - mu * (ln + s * dln)
        };
        let cases = [
            (10.0, [1.0, -0.5], 2.0, [3.0, 4.0]),
            (10.0, [0.0, 0.0], 1.0, [-0.2, 2.5]),
            (5.0, [0.6, 0.0], -1.0, [0.0, 1.0]),
        ];
        for (ln, lt, dln, dlt) in cases {
            let s = law.slip_onset_scale((ln, lt), (dln, dlt), noise).expect("it slips");
            assert!(s > 0.0 && on_cone(ln, lt, dln, dlt, s).abs() < 1e-12 * ln, "{s}");
            assert!((1..100)
                .map(|k| s * k as f64 / 100.0)
                .all(|x| on_cone(ln, lt, dln, dlt, x) < 0.0));
        }
        // on the cone (λ_t = μλ_n (0.6, 0.8)), turning inwards first: the later crossing
        let (ln, lt) = (10.0, [1.8, 2.4]);
        let s = law.slip_onset_scale((ln, lt), (0.0, [-2.0, 0.5]), noise).expect("it leaves again");
        assert!(s > 0.5 && on_cone(ln, lt, 0.0, [-2.0, 0.5], s).abs() < 1e-12 * ln, "{s}");
        // just closed (λ = 0) and sheared more than pressed: at once; pressed more: never
        assert_eq!(law.slip_onset_scale((0.0, [0.0; 2]), (0.44, [0.04, -0.17]), noise), Some(0.0));
        assert_eq!(law.slip_onset_scale((0.0, [0.0; 2]), (1.0, [0.04, -0.17]), noise), None);
        // on it, its force shrinking straight back: through zero, out on the opposite side where
        // |λ_t| = |3 − S| = 3 again (S = 6); pressed harder than it is sheared: no slip
        let s = law.slip_onset_scale((ln, lt), (0.0, [-0.6, -0.8]), noise).expect("reversed");
        assert!((s - 6.0).abs() < 1e-12, "{s}");
        assert_eq!(law.slip_onset_scale((ln, [0.5, 0.0]), (10.0, [1.0, 0.0]), noise), None);
        // on it and moving out: at once
        assert_eq!(law.slip_onset_scale((ln, lt), (0.0, [0.6, 0.8]), noise), Some(0.0));
        // at zero force, sheared with no normal force rate (or one pulling by round-off): at once
        assert_eq!(law.slip_onset_scale((0.0, [0.0; 2]), (0.0, [0.04, -0.17]), noise), Some(0.0));
        assert_eq!(
            law.slip_onset_scale((0.0, [0.0; 2]), (-0.5 * noise, [0.04, -0.17]), noise),
            Some(0.0)
        );
        // just closed, λ_n a round-off below zero (as a correction at fixed load leaves it), so
        // outside the cone by round-off, where the squared cone describes its mirror image:
        // sheared more than pressed, at once, whether the round-off λ_t points along the shear
        // or against it; pressed more than sheared, never
        let (ln, lt) = (-4.66e-8, [-2.06e-9, 8.37e-8]);
        assert_eq!(law.slip_onset_scale((ln, lt), (0.171, [-0.2076, 0.0405]), noise), Some(0.0));
        assert_eq!(law.slip_onset_scale((ln, lt), (0.171, [0.0405, -0.2076]), noise), Some(0.0));
        assert_eq!(law.slip_onset_scale((ln, lt), (0.171, [-0.02, 0.004]), noise), None);
    }

    /// A facet's turn: the cross force λ_⊥ = e⊥·λ_t reaches ± tan θ μ λ_n where the friction
    /// force has turned by θ off e, on the side it turns to, and nowhere before; a force turning
    /// slower than its bound grows reaches neither side.
    #[test]
    fn a_facet_turns_where_the_force_has_turned_by_the_angle() {
        let (mu, noise) = (0.3, 1e-14);
        let law = Coulomb::new(mu, 0.1);
        let turn = law.turn;
        let k = turn.tan() * mu;
        let e = [0.6, 0.8];
        let cross = [-e[1], e[0]];
        let (ln, dln) = (10.0, 2.0);
        let lt = [mu * ln * e[0], mu * ln * e[1]];
        for side in [1.0, -1.0] {
            let dlt =
                [mu * dln * e[0] + side * 1.5 * cross[0], mu * dln * e[1] + side * 1.5 * cross[1]];
            let turns = law.facet_turn_scales(cross, (ln, lt), (dln, dlt), noise);
            assert_eq!(turns.len(), 1);
            let (s_side, s) = turns[0];
            assert_eq!(s_side as f64, side);
            let force = [lt[0] + s * dlt[0], lt[1] + s * dlt[1]];
            let along = e[0] * force[0] + e[1] * force[1];
            assert!(
                ((side * (cross[0] * force[0] + cross[1] * force[1])) / along - turn.tan()).abs()
                    < 1e-12,
                "{s}"
            );
        }
        let slow = [
            mu * dln * e[0] + 0.5 * k * dln * cross[0],
            mu * dln * e[1] + 0.5 * k * dln * cross[1],
        ];
        assert!(law.facet_turn_scales(cross, (ln, lt), (dln, slow), noise).is_empty());
    }
}
