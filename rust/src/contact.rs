//! Contact candidate pairs and their constraint vectors (paper eqs. 21–28, 45–46).
//!
//! A pair joins a contactor node `a` to a target: another body's node `b` (node-to-node) or
//! a rigid obstacle (`b = None`). With the target's unit normal n (pointing towards `a`) and
//! tangent t = (−n_y, n_x) (in 3D the frame's t1, and a second row w_t2 along t2), in global
//! DOFs:
//!
//!   w_n = n at a, −n at b   ⇒ gap = gap₀ + w_nᵀ u ≥ 0        (eqs. 21–22, with C_n = −w_n)
//!   w_t = t at a, −t at b   ⇒ RTD = w_tᵀ u                   (eq. 25, C_t = w_t)
//!
//! and the contact force on the bodies is w_n λ_n + w_t λ_t with λ_n ≥ 0 compressive
//! (eqs. 23, 36). A weighted pair (node-to-segment, mortar-style) spreads the same column over
//! more nodes: w_n = Σ_i c_i n at node i (contactor weights c_i > 0 summing to 1, target
//! weights < 0 summing to −1), so its gap is a weighted mean over the interface; it is still
//! one row of the paper's C_n / C_t. Coulomb (eqs. 1–3): |λ_t| ≤ μ λ_n; a slipping pair carries
//! λ_t = −d μ λ_n where d = ±1 is the direction of its slip (eq. 41).
//!
//! # Friction in space (3D)
//!
//! The Coulomb cone is round: |λ_t| ≤ μ λ_n with λ_t = (λ_t1, λ_t2) in the pair's (t1, t2).
//! - A *stuck* pair has two tangential rows, w_t1ᵀΔu = h1 and w_t2ᵀΔu = h2 (none along a tangent
//!   its supports hold, as for a node on a symmetry plane: its force there goes to the support
//!   and the cone bounds the other component).
//! - A *slipping* pair slips on the facet of the round cone at a held unit direction e: the
//!   cone linearized at its force, e·λ_t ≤ μ λ_n (a circumscribed one-facet Klarbring cone,
//!   laid anew as the force turns). Its flow rule, normality to that facet, is slip along −e
//!   only. So it has two rows: the normal one, with λ_t·e = μ λ_n eliminated (column
//!   w_n + μ(e1 w_t1 + e2 w_t2), as a 2D slip pair), and the *cross row* along e⊥ = (−e2, e1),
//!   w_⊥ = −e2 w_t1 + e1 w_t2, held stuck (ΔRTD_⊥ = 0) by its own multiplier λ_⊥, which starts
//!   at 0 and varies continuously: λ_t = μ λ_n e + λ_⊥ e⊥. The trial stays one linear solve.
//! - The first stick → slip since the pair closed is exact on the round cone: the smallest S
//!   that leaves it, |λ_t0 + S Δλ_t| = μ (λ_n0 + S Δλ_n), a quadratic in S
//!   (`Coulomb::slip_onset_scale`); e is the force's direction there and λ_⊥ = 0: no force jump
//!   at the onset. That facet is one side of the polygon the pair's friction is on from then on
//!   until it opens (`coulomb`: N sides 2θ apart, θ = π/N ≤ slip_turn). Slip → stick is eq. 54's
//!   dissipation test along e: the slip rate along −e reverses; a stuck pair slips again where
//!   its force reaches a side of its polygon (linear in S).
//! - The facet turns (`EventKind::SlipTurn`): when the cross force reaches the bound
//!   |λ_⊥| = tan θ μ λ_n (linear in S on either side, like 2D stick → slip:
//!   `Coulomb::facet_turn_scales`), the force is at the polygon's vertex m = e turned by θ; there
//!   it is μ λ_n / cos θ along m, and the pair slips in the vertex's normal cone (within θ of
//!   −m, no cross row) until its slip leaves it on one side, onto that side's facet (at S = 0,
//!   also a `SlipTurn`). No switch moves the force, so none needs a correction at fixed load.
//!   The force lies on the polygon, up to 1/cos θ − 1 beyond the round cone
//!   (`Problem::friction_excess`), and lags the slip direction by at most θ. A slipping pair
//!   never produces work: its force along its slip is −μ λ_n and across it there is no slip.
//! - A pair that slips at zero normal force (one that slips as it closes) takes e from the
//!   direction its stuck force was growing in (`Candidate::toward`), or with none from its
//!   first trial's slip rate (`driver::slip_turn`); at zero force it has no cross row; a pair on
//!   a symmetry plane (one tangent held by its supports) slips along its free tangent as in 2D,
//!   with no cross row (the support holds it).
//!
//! Measured on the Mindlin sphere (cases/mindlin_sphere_3d.toml, P then Q = 0.5 μP, μ = 0.3),
//! before (the force held along an increment and turned at an increment's start: a jump of
//! its whole direction) and with the facets: c/a against Mindlin's (1 − Q/μP)^(1/3) for the
//! measured forces (0.810 coarse, 0.807 shipped); δ_x the cut's mean x displacement over the
//! shear; the work slipping pairs produce between snapshots at every event (λ_t·ΔRTD > 0,
//! trapezoid) over the work they dissipate; the angle of the slipping pairs' friction forces
//! off −Q at the end (median / max); wall time on two cores shared with other jobs (the
//! facets in the reduced elastic space, `space`; the full space at 0.1: 10.9 s coarse, the
//! same work to 1e-15). Coarse: sphere h_contact 0.06 mm, block 0.08 (17.4k DOFs, a/h ≈ 5);
//! shipped: 0.04 / 0.06 (25k DOFs).
//!
//! | mesh | slip_turn | engine | c/a | δ_x (µm) | events | wall (s) | produced / dissipated | angle off −Q |
//! |---|---|---|---|---|---|---|---|---|
//! | coarse | 0.05 | before | 0.705 | 0.2422 | 375 | 33.5 | 21 % | 5.5° / 53° |
//! | coarse | 0.05 | facets | 0.718 | 0.2428 | 642 | 6.9 | 4e-7 | 5.7° / 123° |
//! | coarse | 0.1  | before | 0.691 | 0.2395 | 433 | 28.4 | 53 % | 2.5° / 172° |
//! | coarse | 0.1  | facets | 0.728 | 0.2428 | 492 | 5.6 | 9e-8 | 5.3° / 35° |
//! | coarse | 0.4  | before | 0.736 | 0.2430 | 245 | 25.1 | 8.6 % | 7.9° / 69° |
//! | coarse | 0.4  | facets | 0.718 | 0.2424 | 383 | 4.1 | 2e-7 | 6.8° / 122° |
//! | shipped | 0.05 | before | 0.740 | 0.2456 | 623 | 142 | 19 % | 7.8° / 14° |
//! | shipped | 0.05 | facets | 0.753 | 0.2462 | 1223 | 33.6 | 5e-7 | 2.5° / 34° |
//! | shipped | 0.1  | before | 0.751 | 0.2456 | 503 | 83.0 | 17 % | 7.2° / 14° |
//! | shipped | 0.1  | facets | 0.753 | 0.2462 | 972 | 24.3 | 1e-7 | 2.9° / 34° |
//! | shipped | 0.4  | before | 0.746 | 0.2460 | 347 | 46.4 | 12 % | 4.5° / 21° |
//! | shipped | 0.4  | facets | 0.762 | 0.2458 | 786 | 16.1 | 2.5e-7 | 6.6° / 34° |
//!
//! (The facets' runs include main's basis of contact nodes on a symmetry plane, the before
//! runs not.) Slipping pairs produce no work to round-off; the stick radius moves by at most
//! one node with the angle and δ_x by 0.2 %, both far inside the mesh's error (c − Mindlin's
//! ≈ −0.4 h); mindlin_sphere_45_3d (coarse, whole bodies): 508 → 1222 events, 61 → 18 s,
//! produced / dissipated 10 % → 2e-7, the last resort fired 8 → 2 times. The events grow
//! because a slip that reverses inside a correction now sticks (it would produce work) and
//! slips again at the next increment. The angle off −Q is not the design's to bound: a pair
//! that starts to slip keeps its stuck force's direction (no jump at the onset), which near
//! the stick edge or for a row with a small normal force (the 123° one, near the centre of
//! the coarse mesh) can be far from −Q; the design bounds the force's lag behind the pair's
//! own slip (2 slip_turn over a step, tests/engine/test_friction_facets_3d.py).
//!
use crate::coulomb::Coulomb;

/// A pair's contact frame: the unit normal n of its target (towards the contactor) and a basis
/// of the tangent plane, `T` = `D` − 1 tangents in `D` dimensions: one in 2D, two in 3D. The
/// pair's constraint vectors are the frame's directions at its nodes (eqs. 45–46).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame<const D: usize, const T: usize> {
    pub normal: [f64; D],
    pub tangents: [[f64; D]; T],
}

impl Frame<2, 1> {
    /// The 2D frame of a normal: t = (−n_y, n_x), so that n × t = +1 (the sign of the RTD).
    pub fn planar(normal: [f64; 2]) -> Self {
        Frame { normal, tangents: [[-normal[1], normal[0]]] }
    }

    pub fn tangent(&self) -> [f64; 2] {
        self.tangents[0]
    }
}

impl Frame<3, 2> {
    /// A pair's frame in the plane, with three components: the planar frame (z = 0; t2 = z,
    /// which a planar pair has no row along: `Pair::tangents`).
    pub fn in_plane(normal: [f64; 3]) -> Self {
        let t = Frame::planar([normal[0], normal[1]]).tangent();
        Frame { normal, tangents: [[t[0], t[1], 0.0], [0.0, 0.0, 1.0]] }
    }

    /// A pair's frame in space: the `tangents` given, or the engine's own: t1 = (e × n)/|e × n|
    /// with e the coordinate axis least aligned with n, t2 = n × t1.
    pub fn in_space(normal: [f64; 3], tangents: Option<[[f64; 3]; 2]>) -> Self {
        let tangents = tangents.unwrap_or_else(|| {
            let least =
                (0..3).fold(0, |k, i| if normal[i].abs() < normal[k].abs() { i } else { k });
            let mut e = [0.0; 3];
            e[least] = 1.0;
            let t1 = normalized(cross(e, normal));
            [t1, cross(normal, t1)]
        });
        Frame { normal, tangents }
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn normalized(a: [f64; 3]) -> [f64; 3] {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    a.map(|v| v / n)
}

/// The constraint vector of a frame direction `dir` over the nodes of `weights` (c_i): Σ_i c_i
/// dir at node i, `dim` DOFs per node.
fn along(weights: &[(usize, f64)], dim: usize, dir: [f64; 3]) -> SparseVec {
    let entries =
        weights.iter().flat_map(|&(i, c)| (0..dim).map(move |k| (dim * i + k, c * dir[k])));
    SparseVec { entries: entries.filter(|&(_, c)| c != 0.0).collect() }
}

/// A pair's gap and RTD shifts by its obstacle's motion: (c_n, c_t1, c_t2) (c_t2 = 0 in 2D).
pub type Shift = [f64; 3];

/// A constraint vector shorter than this has all its DOFs held by supports (unit normals and
/// tangents: entries are 0 or of order 1).
pub const HELD_BY_SUPPORTS: f64 = 1e-12;

/// A sparse vector over global DOFs: at most 4 entries (two nodes × two components).
#[derive(Debug, Clone, Default)]
pub struct SparseVec {
    pub entries: Vec<(usize, f64)>,
}

impl SparseVec {
    pub fn dot(&self, u: &[f64]) -> f64 {
        self.entries.iter().map(|&(d, c)| c * u[d]).sum()
    }

    /// y += s · self
    pub fn add_to(&self, s: f64, y: &mut [f64]) {
        for &(d, c) in &self.entries {
            y[d] += s * c;
        }
    }

    /// Keep only the DOFs `keep` says are free.
    pub fn restricted(&self, keep: impl Fn(usize) -> bool) -> SparseVec {
        SparseVec { entries: self.entries.iter().copied().filter(|&(d, _)| keep(d)).collect() }
    }

    pub fn norm(&self) -> f64 {
        self.entries.iter().map(|&(_, c)| c * c).sum::<f64>().sqrt()
    }

    /// The part of this vector orthogonal to `other` (itself when `other` is zero).
    pub fn across(&self, other: &SparseVec) -> SparseVec {
        let at = |v: &SparseVec, d: usize| {
            v.entries.iter().filter(|e| e.0 == d).map(|e| e.1).sum::<f64>()
        };
        let nn = other.norm().powi(2);
        let s = if nn > 0.0 {
            self.entries.iter().map(|&(d, c)| c * at(other, d)).sum::<f64>() / nn
        } else {
            0.0
        };
        let mut out = self.clone();
        for &(d, c) in &other.entries {
            match out.entries.iter_mut().find(|e| e.0 == d) {
                Some(e) => e.1 -= s * c,
                None => out.entries.push((d, -s * c)),
            }
        }
        out
    }
}

/// The contact status of a pair (paper: C_nN open, C_ta stick, C_ts slip).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Open,
    /// Closed, no relative tangential motion. Also used for frictional pairs whose tangential
    /// DOFs are all held by supports (a node on a symmetry line): their tangential constraint
    /// would be redundant, so it is not imposed and λ_t stays 0.
    Stick,
    /// Closed and slipping with λ_t = −d μ λ_n. Frictionless closed pairs are Slip with μ = 0.
    Slip {
        direction: i8,
    },
}

impl Status {
    pub fn code(self) -> i8 {
        match self {
            Status::Open => 0,
            Status::Stick => 1,
            Status::Slip { .. } => 2,
        }
    }
    pub fn is_closed(self) -> bool {
        self != Status::Open
    }
}

/// One tangent of a pair's frame and its row (eqs. 25, 45–46).
#[derive(Debug, Clone)]
pub struct Tangent {
    /// The unit direction t (three components; z = 0 in the plane).
    pub direction: [f64; 3],
    /// The tangential constraint vector w_t over free DOFs (supports removed).
    pub w: SparseVec,
    /// The supports hold it (a node on a symmetry plane): no stick row along it, and its
    /// friction force goes to the support (Coulomb's cone bounds the other tangent's).
    pub held: bool,
    /// The column's entries at held DOFs: the force the pair puts straight onto the supports.
    pub on_supports: SparseVec,
}

#[derive(Debug, Clone)]
pub struct Pair {
    pub node_a: usize,
    pub node_b: Option<usize>,
    /// The unit normal n of the target, towards the contactor (three components; z = 0 in the
    /// plane).
    pub normal: [f64; 3],
    pub gap0: f64,
    /// Coulomb's law on this pair: μ, and in space its polygon (`coulomb`).
    pub friction: Coulomb,
    /// Normal constraint vector over free DOFs (supports removed).
    pub w_n: SparseVec,
    /// The normal column's entries at held DOFs (which a reaction excludes: they do not move).
    pub n_on_supports: SparseVec,
    /// The frame's tangents: t in the plane, (t1, t2) in space.
    pub tangents: Vec<Tangent>,
}

/// Where a pair is and what it is: its nodes, its frame, the space's dimension.
pub struct PairGeometry<'a> {
    pub node_a: usize,
    pub node_b: Option<usize>,
    /// Node-to-segment or node-to-surface weights (empty: 1 at a, −1 at b).
    pub weights: &'a [(usize, f64)],
    pub dim: usize,
    pub frame: Frame<3, 2>,
}

impl Pair {
    /// A 2D pair with the frame of its unit `normal`.
    pub fn new(
        node_a: usize,
        node_b: Option<usize>,
        normal: [f64; 2],
        gap0: f64,
        mu: f64,
        fixed: &[bool],
    ) -> Self {
        let frame = Frame::in_plane([normal[0], normal[1], 0.0]);
        let friction = Coulomb::new(mu, 0.0);
        Self::build(
            PairGeometry { node_a, node_b, weights: &[], dim: 2, frame },
            gap0,
            friction,
            fixed,
        )
    }

    /// A 2D pair whose constraint column is Σ_i c_i (n or t) at the nodes of `weights` (c_i).
    pub fn weighted(
        node_a: usize,
        node_b: Option<usize>,
        weights: &[(usize, f64)],
        normal: [f64; 2],
        gap0: f64,
        mu: f64,
        fixed: &[bool],
    ) -> Self {
        let frame = Frame::in_plane([normal[0], normal[1], 0.0]);
        let friction = Coulomb::new(mu, 0.0);
        Self::build(PairGeometry { node_a, node_b, weights, dim: 2, frame }, gap0, friction, fixed)
    }

    /// The pair of `g` (node to node, or weighted when `g.weights` is not empty) under the
    /// friction law `friction`.
    pub fn build(g: PairGeometry, gap0: f64, friction: Coulomb, fixed: &[bool]) -> Self {
        let PairGeometry { node_a, node_b, dim, frame, .. } = g;
        let weighted = !g.weights.is_empty();
        let mut own_weights = vec![(node_a, 1.0)];
        own_weights.extend(node_b.map(|b| (b, -1.0)));
        let weights = if weighted { g.weights } else { &own_weights };
        let vec_of = |dir: [f64; 3]| along(weights, dim, dir);
        let free = |d: usize| !fixed[d];
        let w_n = vec_of(frame.normal).restricted(free);
        // A tangential row is held when, on the free DOFs, it adds nothing to the normal row:
        // zero (every tangential DOF held), or parallel to it (a node on two symmetry planes
        // under a tilted normal: both rows act on its one free DOF). Node to node: over all
        // its DOFs; a weighted row (its force on node a alone): over node a's, since its
        // remaining entries would constrain the target only.
        let part =
            |w: &SparseVec| if weighted { w.restricted(|d| d / dim == node_a) } else { w.clone() };
        let tangents = frame.tangents[..dim - 1]
            .iter()
            .map(|&direction| {
                let w = vec_of(direction).restricted(free);
                Tangent {
                    direction,
                    held: part(&w).across(&part(&w_n)).norm() < HELD_BY_SUPPORTS,
                    on_supports: vec_of(direction).restricted(|d| fixed[d]),
                    w,
                }
            })
            .collect();
        Pair {
            node_a,
            node_b,
            normal: frame.normal,
            gap0,
            friction,
            n_on_supports: vec_of(frame.normal).restricted(|d| fixed[d]),
            w_n,
            tangents,
        }
    }

    /// w_t: the constraint vector along the first tangent (t in the plane, t1 in space).
    pub fn w_t(&self) -> &SparseVec {
        &self.tangents[0].w
    }

    /// w_t2: the constraint vector along t2 (in space; None in the plane).
    pub fn w_t2(&self) -> Option<&SparseVec> {
        self.tangents.get(1).map(|t| &t.w)
    }

    /// Whether the supports hold tangent k (a tangent the frame does not have, the plane's
    /// second, counts as held: nothing to constrain).
    pub fn held(&self, k: usize) -> bool {
        self.tangents.get(k).is_none_or(|t| t.held)
    }

    /// The tangents the supports leave free, with their indices (0: t / t1, 1: t2).
    pub fn free_tangents(&self) -> impl Iterator<Item = (usize, &Tangent)> {
        self.tangents.iter().enumerate().filter(|(_, t)| !t.held)
    }

    /// The pair's columns of W (eqs. 45–46): w_n, then w_t of each tangent.
    pub fn columns(&self) -> impl Iterator<Item = &SparseVec> {
        std::iter::once(&self.w_n).chain(self.tangents.iter().map(|t| &t.w))
    }

    /// Their entries at held DOFs, in the same order (`Tangent::on_supports`).
    pub fn on_supports(&self) -> impl Iterator<Item = &SparseVec> {
        std::iter::once(&self.n_on_supports).chain(self.tangents.iter().map(|t| &t.on_supports))
    }

    /// y += W λ, λ = (λ_n, λ_t1, λ_t2): the pair's force on the free DOFs (λ_t2 unused in the
    /// plane).
    pub fn add_force(&self, lambda: [f64; 3], y: &mut [f64]) {
        self.columns().zip(lambda).for_each(|(w, l)| w.add_to(l, y));
    }

    /// (w_n·v, w_t1·v, w_t2·v): each column against v (0 for a tangent the frame lacks).
    pub fn dots(&self, v: &[f64]) -> [f64; 3] {
        let mut out = [0.0; 3];
        self.columns().zip(&mut out).for_each(|(w, o)| *o = w.dot(v));
        out
    }

    /// Every tangential DOF is held by supports: no stick constraint.
    pub fn tangent_held(&self) -> bool {
        self.tangents.iter().all(|t| t.held)
    }

    /// The constraint vectors whose DOFs the contact system reads (its slots): the normal, and
    /// the tangential ones where friction can act. (A 2D pair lists its tangent always, as it
    /// always has, so that 2D runs keep their DOF order; in 3D the tangential DOFs of
    /// frictionless pairs would triple the dense trailing block of the factor for nothing.)
    pub fn slot_vectors(&self) -> Vec<&SparseVec> {
        let one_tangent = self.tangents.len() == 1;
        let rows = if one_tangent || self.friction.acts() { self.tangents.len() } else { 0 };
        std::iter::once(&self.w_n).chain(self.tangents[..rows].iter().map(|t| &t.w)).collect()
    }

    /// Its frame has one tangent (the plane): a slip is along ±t, its sense all there is to its
    /// direction (eq. 41).
    pub fn slips_along_a_line(&self) -> bool {
        self.tangents.len() == 1
    }

    /// Both tangents free (neither held by the supports): friction acts in the whole tangent
    /// plane, on the round cone and its facets. Never in 2D, whose frame has one tangent (the
    /// second counts as held).
    pub fn has_tangent_plane(&self) -> bool {
        self.tangents.len() == 2 && self.free_tangents().count() == 2
    }

    pub fn frictional(&self) -> bool {
        self.friction.acts() && !self.tangent_held()
    }

    /// The status a pair takes when it closes: stick with friction (held tangentially by
    /// its own constraint, or by the supports when `tangent_held`), frictionless sliding (μ = 0).
    pub fn closed_status(&self) -> Status {
        if self.friction.acts() {
            Status::Stick
        } else {
            Status::Slip { direction: 0 }
        }
    }

    pub fn gap(&self, u: &[f64]) -> f64 {
        self.gap0 + self.w_n.dot(u)
    }

    pub fn rtd(&self, u: &[f64]) -> f64 {
        self.w_t().dot(u)
    }

    /// 3D: the constraint vector along the tangent-plane direction `dir` (along t1, t2):
    /// dir₁ w_t1 + dir₂ w_t2.
    pub fn along_tangent(&self, dir: [f64; 2]) -> SparseVec {
        let scaled = self
            .tangents
            .iter()
            .zip(dir)
            .flat_map(|(t, c)| t.w.entries.iter().map(move |&(d, v)| (d, c * v)));
        SparseVec { entries: scaled.filter(|&(_, v)| v != 0.0).collect() }
    }

    /// y += the force λ_n, λ_t (along t1, t2) put on the held DOFs (global).
    pub fn add_support_force(&self, lambda_n: f64, lambda_t: [f64; 2], y: &mut [f64]) {
        self.on_supports()
            .zip([lambda_n, lambda_t[0], lambda_t[1]])
            .for_each(|(w, l)| w.add_to(l, y));
    }

    /// λ_t = τ λ_n for a pair slipping in the plane (eq. 41): τ = −d μ.
    pub fn slip_ratio(&self, status: Status) -> f64 {
        match status {
            Status::Slip { direction } => self.friction.planar_slip_ratio(direction),
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gap_and_rtd_follow_the_conventions() {
        // Node a (0) above node b (1), target normal +y: moving a up opens the gap,
        // moving a along t = (−1, 0) is positive RTD.
        let fixed = vec![false; 4];
        let p = Pair::new(0, Some(1), [0.0, 1.0], 0.5, 0.2, &fixed);
        let u = [-0.1, 0.2, 0.0, -0.3];
        assert!((p.gap(&u) - (0.5 + 0.2 + 0.3)).abs() < 1e-15);
        assert!((p.rtd(&u) - 0.1).abs() < 1e-15);
    }

    #[test]
    fn weighted_rows_spread_the_column_and_cancel() {
        // Contactor node 0 (weight 1), target nodes 1, 2 (−0.25, −0.75): moving everything by
        // the same vector keeps the gap; the gap is u0 − (0.25 u1 + 0.75 u2) along n.
        let fixed = vec![false; 6];
        let p = Pair::weighted(
            0,
            Some(2),
            &[(0, 1.0), (1, -0.25), (2, -0.75)],
            [0.0, 1.0],
            0.0,
            0.3,
            &fixed,
        );
        let shift = [0.3, -0.2, 0.3, -0.2, 0.3, -0.2];
        assert!(p.gap(&shift).abs() < 1e-15 && p.rtd(&shift).abs() < 1e-15);
        let u = [0.0, 0.1, 0.0, 0.4, 0.0, 0.0];
        assert!((p.gap(&u) - (0.1 - 0.25 * 0.4)).abs() < 1e-15);
        // Node 0 held in x on a symmetry line: no stick row, although the targets are free.
        let held = Pair::weighted(
            0,
            Some(2),
            &[(0, 1.0), (1, -0.25), (2, -0.75)],
            [0.0, 1.0],
            0.0,
            0.3,
            &[true, false, false, false, false, false],
        );
        assert!(held.tangent_held() && !p.tangent_held());
    }

    #[test]
    fn tangent_on_a_symmetry_line_is_held() {
        // Node 0 with u_x fixed on a rigid flat of normal +y: its tangential DOF is a support.
        let fixed = vec![true, false];
        let p = Pair::new(0, None, [0.0, 1.0], 0.0, 0.3, &fixed);
        assert!(p.tangent_held() && !p.frictional());
        assert_eq!(p.closed_status(), Status::Stick);
        // its tangential force goes straight to the support: x = 2 λ_t (t = (−1, 0)) at DOF 0
        let mut y = [0.0; 2];
        p.add_support_force(1.0, [-2.0, 0.0], &mut y);
        assert_eq!(y, [2.0, 0.0]);
    }
}
