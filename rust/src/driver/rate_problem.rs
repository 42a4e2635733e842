//! The contact statuses at a fixed load, as a linear complementarity problem (LCP).
//!
//! A zero-length increment means the trial with the current statuses is inadmissible at once
//! (S = 0). Switching one violated status at a time (the paper's rule) may cycle. Instead, the
//! statuses of the *critical* pairs (zero gap and zero force, or on the Coulomb cone) are
//! found together: with Λ = λ + Δλ the contact forces at the end of the trial and
//!   Δu = K#(r + Σ w ΔΛ) + N α,   g' = gap + w_nᵀΔu,   v = w_tᵀΔu − (RTD at sticking − RTD),
//! the conditions of eqs. 22–24, 2–3 and 41 on each pair are (Klarbring's 2D form, with the
//! slip rates v⁺, v⁻ ≥ 0 as unknowns)
//!   strictly closed:          g' = 0 (Λn free);     stick strictly inside the cone: v = 0 (Λt free)
//!   zero gap and force:       0 ≤ Λn ⊥ g' ≥ 0
//!   frictional, on the cone or at zero force:
//!                             v − v⁺ + v⁻ = 0 (Λt free),
//!                             0 ≤ v⁺ ⊥ μΛn + Λt ≥ 0,   0 ≤ v⁻ ⊥ μΛn − Λt ≥ 0
//!                             (slip along +t only with Λt = −μΛn, eq. 41, and vice versa);
//!                             a pair on one side of the cone cannot reach the other at the
//!                             increment's start: that side's row is its present slack
//!                             μλn ∓ λt > 0, so its slip rate is 0 (held to the end of the
//!                             trial instead, it asks the statuses to last the whole remaining
//!                             load: often no set does, while one holds at the start)
//!   each free rigid mode:     Σ (Nᵀw) ΔΛ = −Nᵀ r   (α free)
//! This is a mixed LCP (free unknowns with equations, the rest complementary). The free
//! unknowns are eliminated (or split, for the rigid amplitudes), and Lemke's method (module
//! `lcp`) solves the rest: without friction it is the KKT system of a convex QP, solved
//! whenever a solution exists; with friction the condensed matrix is a P-matrix for small μ
//! (Klarbring), where Lemke always succeeds; otherwise restarts with other covering vectors
//! help (`mixed_lcp`). It terminates in every case. The statuses follow from the solution.
//!
//! # In space (3D): the round cone faceted
//!
//! In space the cone |Λt| ≤ μΛn is replaced, for this problem only, by a polygon of sides d_j
//! with a slip rate v_j ≥ 0 each: v + Σ_j v_j d_j = 0 (Λt free), 0 ≤ v_j ⊥ μΛn − d_jᵀΛt ≥ 0
//! (the plane's is this with d = −t, +t). Each pair's sides, their rows, and the status and
//! slip direction they give back are the cone's (`cone_rows`); the passes that lay facets
//! about stray slips are `solve_rate_problem`'s, and the hand-back to the facet design of
//! friction (`coulomb`) is `hold_slip_directions`.
//!
//! # A working set: the pairs presumed stuck
//!
//! Most pairs of a contact that closes at once stick, and Lemke's work grows as the cube of
//! its complementary unknowns. So in space the pairs at zero force are first presumed to
//! close and stick: their forces are free unknowns with a stuck pair's equations (g' = 0,
//! v = 0), eliminated with the others' free forces, and Lemke solves for the rest. A presumed
//! pair the solution leaves pulling or beyond its round cone joins the complementary ones, and
//! the problem is solved again (`RateProblem::solve`). A presumed pair that the final solution
//! keeps meets a stuck pair's conditions, so that solution solves the whole problem. The pad:
//! its first LCP 0 unknowns (all 258 presumed), 135 pairs then wrong, the next 675 unknowns,
//! 15 more, then 750; every LCP of its two rate problems 0.2–0.6 s (1.9–3.1 s with none
//! presumed), the same contact (a, c, p0) as without.

use super::cone_rows::{self, Facet, PairUnknowns};
use super::engine::Engine;
use super::loads::StageLoads;
use super::mixed_lcp::{self, Affine, Unknowns};
use super::problem::Problem;
use super::state::State;
use super::stiffness::Stiffness;
use super::trial::{self, Solve};
use crate::contact::{SparseVec, Status};
use crate::dim::Dim;
use nalgebra::DMatrix;

/// A force below this × Σ|load| counts as zero: the pair is critical (or open, in a solution).
const CRITICAL_FORCE: f64 = 1e-10;
/// An open pair within this × max|u| (+ round-off of the length scale) of its target is critical.
const CRITICAL_GAP: f64 = 1e-8;
const GAP_ROUND_OFF: f64 = 1e-12;
/// A slip rate above this × max|kinematic term| is slip, not stick.
const SLIP_RATE: f64 = 1e-9;
/// Rounds of the working set (`RateProblem::solve`) before it presumes nothing.
const WORKING_SET_ROUNDS: usize = 4;
/// Solves of the 3D rate problem, facets laid about stray slips between them.
const FACET_PASSES: usize = 4;

/// How a pair enters the rate problem.
#[derive(Clone, PartialEq)]
enum Role {
    /// Closed with positive force, frictionless (or tangent held): g' = 0.
    Normal,
    /// Closed, stick strictly inside the cone: g' = 0, v = 0.
    Stick,
    /// Frictional, on the cone or at zero force: its slip is decided; `closed`: with positive
    /// force (g' = 0), else 0 ≤ Λn ⊥ g' ≥ 0. `facets`: the cone's sides (2D: +t, −t).
    Friction { closed: bool, facets: Vec<Facet>, polygon: bool },
    /// Frictionless at zero gap and zero force: open or closed is decided.
    Critical,
}

/// One pair's forces as affine forms of the unknowns: Λn, Λt along its tangential
/// coordinates (`RateProblem::tangents`), and the unknowns of its normal force, tangential
/// forces and facets' slip rates.
struct PairForces {
    normal: Affine,
    tangential: Vec<Affine>,
    n: usize,
    t: Vec<usize>,
    slips: Vec<usize>,
}

/// A solved rate problem: its pairs, their roles and forces, which end touching, the unknowns,
/// and the displacement scale of its tolerances.
struct Solved {
    q: Vec<usize>,
    roles: Vec<Role>,
    forces: Vec<PairForces>,
    touching: Vec<bool>,
    y: Vec<f64>,
    scale: f64,
}

impl Solved {
    /// The solved force of the i-th pair of q: Λn, and Λt along its tangential coordinates.
    fn force(&self, i: usize) -> (f64, Vec<f64>) {
        let f = &self.forces[i];
        (f.normal.eval(&self.y), f.tangential.iter().map(|a| a.eval(&self.y)).collect())
    }
}

/// The rate problem's answer: every pair's status and, in 3D, where each pair it sets slipping
/// slips: its facet's direction e (along t1, t2), or a vertex m of its polygon (`coulomb`)
/// (None: keep the one it has).
pub(super) struct RateSolution {
    pub status: Vec<Status>,
    pub slip_dir: Vec<Option<([f64; 2], bool)>>,
}

/// The statuses that satisfy every contact condition at the current load, or None when Lemke
/// finds no solution (the caller falls back to freezing). `what`: the remaining load, or a
/// contact sub-step's (`trial::Solve`).
pub(super) fn solve_rate_problem<D: Dim>(
    eng: &mut Engine<D>,
    state: &State<D>,
    what: Solve,
) -> Option<RateSolution> {
    let oob = trial::out_of_balance(eng, state, what, None);
    // Facets laid about stray slips (`stray_slips`), pass after pass, until none is left.
    let mut laid = vec![vec![]; eng.problem.pairs.len()];
    let (mut presumed, mut compliance) = (None, std::cell::OnceCell::new());
    for pass in 1.. {
        crate::interrupt::checkpoint(crate::interrupt::Checkpoint::RateProblem).ok()?;
        let mut rp = RateProblem {
            p: &eng.problem,
            stiffness: &eng.stiffness,
            loads: &eng.loads,
            laid,
            presumed: vec![],
            compliance,
        };
        rp.presumed = presumed.take().unwrap_or_else(|| rp.zero_force_pairs(state));
        let solved = rp.solve(state, &oob)?;
        let sol = rp.statuses(state, &solved);
        let mut stray = rp.stray_slips(&solved, &sol);
        stray.extend(rp.stuck_beyond_round_cone(&solved, &sol));
        if stray.is_empty() || pass == FACET_PASSES {
            return Some(sol);
        }
        (laid, presumed, compliance) = (rp.laid, Some(rp.presumed), rp.compliance);
        for (p, e) in stray {
            laid[p].extend(cone_rows::facets_about(e, eng.problem.pairs[p].friction.turn));
        }
    }
    unreachable!("the passes end at FACET_PASSES")
}

/// Where the pairs the rate problem set slipping slip, handed back to the facet design of
/// friction (`coulomb`): each slips on the facet (or at the vertex) it picked, with the facet's
/// cross row from zero normal force on (`State::facet_laid`), as on the rate problem's polygon
/// side; its force goes onto it (a pair on its polygon already is there: no jump). Returns the
/// largest change of λ_t it made (a force jump the caller rebalances).
pub(super) fn hold_slip_directions<D: Dim>(
    problem: &Problem<D>,
    state: &mut State<D>,
    sol: &RateSolution,
) -> f64 {
    let mut jump: f64 = 0.0;
    for (p, placed) in sol.slip_dir.iter().enumerate() {
        if let (Some((e, vertex)), Status::Slip { .. }) = (placed, state.status[p]) {
            let space = state.space_mut().expect("a facet is laid in space only");
            (space.slip_dir[p], space.vertex[p], space.facet_laid[p]) = (*e, *vertex, true);
            let now = state.lambda_t_of(p);
            let [t1, t2] = problem.slip_force(state, p, now);
            jump = jump.max((t1 - now[0]).hypot(t2 - now[1]));
            state.set_lambda_t(p, [t1, t2]);
        }
    }
    jump
}

/// The problem's pairs, flexibility and stage loads the rate problem is built from, and per
/// pair the facet normals laid about its slip directions of earlier passes.
struct RateProblem<'a, D: Dim> {
    p: &'a Problem<'a, D>,
    stiffness: &'a Stiffness,
    loads: &'a StageLoads,
    laid: Vec<Vec<[f64; 2]>>,
    /// Per pair: presumed to close and stick (the working set's guess, 3D: see `solve`).
    presumed: Vec<bool>,
    /// wᵀ K# w' of every two of the pairs' w_n and free tangents, in the order of
    /// `kinematics`: the same in every round and pass of one rate problem (its pairs and their
    /// tangents are the state's).
    compliance: std::cell::OnceCell<DMatrix<f64>>,
}

impl<D: Dim> RateProblem<'_, D> {
    /// The problem solved on a working set (3D): the pairs at zero force are presumed to close
    /// and stick (`presumed`: their forces free unknowns, eliminated with g' = 0, v = 0, as a
    /// stuck pair's), and only the others are complementary unknowns of Lemke's. A presumed
    /// pair the solution leaves pulling (Λn < 0) or beyond its round cone joins the
    /// complementary ones and the problem is solved again: at most `WORKING_SET_ROUNDS` times,
    /// then with none presumed (as when Lemke finds no solution with some presumed). The
    /// solution it ends with solves the whole problem: a presumed pair's conditions hold as a
    /// stuck one's. Lemke's work grows as the cube of its unknowns, and most pairs of a
    /// contact that closes at once stick (the pad of issue 37: 258 pairs at zero gap and force,
    /// 144 of them stuck).
    fn solve(&mut self, state: &State<D>, oob: &trial::OutOfBalance) -> Option<Solved> {
        for round in 0.. {
            let solved = self.solve_presuming(state, oob);
            let any = self.presumed.contains(&true);
            let Some(solved) = solved else {
                if !any {
                    return None;
                }
                self.presumed.iter_mut().for_each(|x| *x = false);
                continue;
            };
            let wrong = self.wrongly_presumed(&solved);
            if wrong.is_empty() {
                return Some(solved);
            }
            crate::trace!("rate problem: {} of the pairs presumed stuck are not", wrong.len());
            match round < WORKING_SET_ROUNDS {
                true => wrong.into_iter().for_each(|p| self.presumed[p] = false),
                false => self.presumed.iter_mut().for_each(|x| *x = false),
            }
        }
        unreachable!("the rounds end with none presumed")
    }

    /// 3D: the pairs of the problem at zero force (the working set's first guess); none in 2D.
    fn zero_force_pairs(&self, state: &State<D>) -> Vec<bool> {
        let tol = CRITICAL_FORCE * self.p.scales.force;
        (0..self.p.pairs.len())
            .map(|p| {
                state.space().is_some()
                    && self.in_rate_problem(state, p)
                    && state.lambda_n[p].abs() <= tol
                    && state.lambda_t[p].hypot(state.lambda_t_of(p)[1]) <= tol
            })
            .collect()
    }

    /// The presumed pairs whose solved forces are not a stuck pair's: Λn < 0, or beyond the
    /// round cone |Λt| ≤ μ Λn (to the force noise).
    fn wrongly_presumed(&self, solved: &Solved) -> Vec<usize> {
        let tol = CRITICAL_FORCE * self.p.scales.force;
        solved
            .q
            .iter()
            .enumerate()
            .filter(|&(_, &p)| self.presumed[p])
            .filter(|&(i, &p)| {
                let f = &solved.forces[i];
                let ln = f.normal.eval(&solved.y);
                let lt: Vec<f64> = f.tangential.iter().map(|a| a.eval(&solved.y)).collect();
                ln < -tol || cone_rows::norm(&lt) > self.p.pairs[p].friction.capacity(ln) + tol
            })
            .map(|(_, &p)| p)
            .collect()
    }

    fn solve_presuming(&self, state: &State<D>, oob: &trial::OutOfBalance) -> Option<Solved> {
        let q: Vec<usize> =
            (0..self.p.pairs.len()).filter(|&p| self.in_rate_problem(state, p)).collect();
        let roles: Vec<Role> = q.iter().map(|&p| self.role(state, p)).collect();
        let mut prob = Unknowns::default();
        // Λn, Λt of every pair in q, and α, as affine forms of the unknowns.
        let forces: Vec<PairForces> = q
            .iter()
            .zip(&roles)
            .map(|(&p, role)| self.force_unknowns(&mut prob, p, role))
            .collect();
        let alpha: Vec<usize> =
            (0..self.p.bodies.modes.len()).map(|_| prob.length_unknown(true)).collect();
        let (kin_n, kin_t) = self.kinematics(state, &q, &forces, &alpha, &oob.z0);
        for (i, (&p, role)) in q.iter().zip(&roles).enumerate() {
            let g = kin_n[i]
                .clone()
                .scaled_add(1.0, &Affine::constant(self.p.gap(state, p) + oob.dshift[p][0]));
            let v: Vec<Affine> = self
                .tangents(p)
                .iter()
                .zip(&kin_t[i])
                .map(|(&k, kin)| {
                    let h_t = if state.status[p] == Status::Stick {
                        self.stuck_rtd(state, p, k) - self.rtd(state, p, k) - oob.dshift[p][k + 1]
                    } else {
                        -oob.dshift[p][k + 1]
                    };
                    kin.clone().scaled_add(-1.0, &Affine::constant(h_t))
                })
                .collect();
            self.pair_rows(&mut prob, p, role, &forces[i], g, v);
        }
        self.equilibrium_rows(&mut prob, state, &q, &forces, &alpha, oob);
        let y = mixed_lcp::solve(&prob)?;
        let scale = kin_n
            .iter()
            .chain(kin_t.iter().flatten())
            .map(|a| a.eval(&y).abs())
            .fold(self.loads.largest_displacement(self.p, &state.u, state.load_fraction), f64::max);
        let touching = q
            .iter()
            .zip(&kin_n)
            .map(|(&p, g)| {
                self.p.gap(state, p) + oob.dshift[p][0] + g.eval(&y) <= CRITICAL_GAP * scale
            })
            .collect();
        Some(Solved { q, roles, forces, touching, y, scale })
    }

    /// 3D: the pairs at zero force the solution sets slipping whose force across their slip
    /// direction e is beyond the facet design's band, tan θ μΛn (`coulomb`): the polygon's
    /// side they slip on is wider than the design's facet. Handed back, such a pair's facet
    /// would turn at once (at zero force the force is its rate), and the trial would leave the
    /// rate problem's solution; with facets laid about e it may not. With their e.
    fn stray_slips(&self, solved: &Solved, sol: &RateSolution) -> Vec<(usize, [f64; 2])> {
        let tol = CRITICAL_FORCE * self.p.scales.force;
        let mut stray = vec![];
        for (i, (&p, role)) in solved.q.iter().zip(&solved.roles).enumerate() {
            let (Some((e, _)), Role::Friction { closed: false, .. }) = (sol.slip_dir[p], role)
            else {
                continue;
            };
            if self.tangents(p).len() == 1 {
                continue; // one free tangent: its two sides are exact
            }
            let (ln, lt) = solved.force(i);
            if cone_rows::beyond_band(&self.p.pairs[p].friction, e, (ln, &lt), tol) {
                stray.push((p, e));
            }
        }
        stray
    }

    /// 3D: the pairs at zero force the solution sticks with a force beyond the round cone, in a
    /// corner of the polygon (by up to 1/cos(π/FACETS) − 1), with their force's direction d.
    /// Handed back, such a pair would slip at once at the next selection (the round cone's
    /// stick → slip from zero force), the rate problem would stick it again, and the run would
    /// cycle into the last resort (the frictional Hertz sphere: a pair stuck at 1.011 μΛn).
    /// Facets laid about d cut that corner, so the next pass sticks it inside the round cone
    /// or slips it on the facet at d.
    fn stuck_beyond_round_cone(
        &self,
        solved: &Solved,
        sol: &RateSolution,
    ) -> Vec<(usize, [f64; 2])> {
        let tol = CRITICAL_FORCE * self.p.scales.force;
        let mut beyond = vec![];
        for (i, (&p, role)) in solved.q.iter().zip(&solved.roles).enumerate() {
            let Role::Friction { closed: false, .. } = role else { continue };
            if self.tangents(p).len() == 1 || sol.status[p] != Status::Stick {
                continue; // one free tangent: its two sides are exact
            }
            let (ln, lt) = solved.force(i);
            let law = &self.p.pairs[p].friction;
            beyond.extend(cone_rows::beyond_round_cone(law, (ln, &lt), tol).map(|d| (p, d)));
        }
        beyond
    }

    /// The tangential coordinates of pair p (indices into t1, t2): in 2D its tangent always (a
    /// frictionless pair's Λt is 0); in 3D the tangents a frictional pair's supports leave free.
    fn tangents(&self, p: usize) -> Vec<usize> {
        let pair = &self.p.pairs[p];
        match pair.tangents.len() {
            1 => vec![0],
            _ if !pair.frictional() => vec![],
            _ => pair.free_tangents().map(|(k, _)| k).collect(),
        }
    }

    /// Tangent k's constraint vector, force, RTD and RTD at sticking of pair p.
    fn tangent_vec(&self, p: usize, k: usize) -> &SparseVec {
        &self.p.pairs[p].tangents[k].w
    }
    fn lambda_t(&self, state: &State<D>, p: usize, k: usize) -> f64 {
        state.lambda_t_of(p)[k]
    }
    fn rtd(&self, state: &State<D>, p: usize, k: usize) -> f64 {
        if k == 0 {
            self.p.rtd(state, p)
        } else {
            self.p.rtd2(state, p)
        }
    }
    fn stuck_rtd(&self, state: &State<D>, p: usize, k: usize) -> f64 {
        state.rtd_stick_of(p)[k]
    }

    /// The row of each free rigid mode k: its body's equilibrium −e_k = 0 with
    /// e_k = Σ (Nᵀw) ΔΛ + Nᵀ r over the pairs `q` (−Nᵀ r = mode_rhs), paired with α_k.
    fn equilibrium_rows(
        &self,
        prob: &mut Unknowns,
        state: &State<D>,
        q: &[usize],
        forces: &[PairForces],
        alpha: &[usize],
        oob: &trial::OutOfBalance,
    ) {
        for (k, &a) in alpha.iter().enumerate() {
            let mode = &self.p.bodies.mode_vectors[k];
            let mut e = Affine::constant(-oob.mode_rhs[k]);
            for (i, &p) in q.iter().enumerate() {
                let wn = self.p.pairs[p].w_n.dot(mode);
                e = e
                    .scaled_add(wn, &forces[i].normal)
                    .scaled_add(-wn, &Affine::constant(state.lambda_n[p]));
                for (&t, force) in self.tangents(p).iter().zip(&forces[i].tangential) {
                    let wt = self.tangent_vec(p, t).dot(mode);
                    e = e
                        .scaled_add(wt, force)
                        .scaled_add(-wt, &Affine::constant(self.lambda_t(state, p, t)));
                }
            }
            prob.rows[a] = Some(Affine::constant(0.0).scaled_add(-1.0, &e));
        }
    }

    /// Closed pairs, and open ones at zero gap.
    fn in_rate_problem(&self, state: &State<D>, p: usize) -> bool {
        let umax = self.loads.largest_displacement(self.p, &state.u, state.load_fraction);
        state.status[p].is_closed()
            || self.p.gap(state, p) <= CRITICAL_GAP * umax + GAP_ROUND_OFF * self.p.scales.length
    }

    fn role(&self, state: &State<D>, p: usize) -> Role {
        let tol = CRITICAL_FORCE * self.p.scales.force;
        let (pair, ln) = (&self.p.pairs[p], state.lambda_n[p]);
        if self.presumed[p] {
            return if pair.frictional() { Role::Stick } else { Role::Normal };
        }
        let lt: Vec<f64> = self.tangents(p).iter().map(|&k| self.lambda_t(state, p, k)).collect();
        let closed = state.status[p].is_closed() && ln > tol;
        // a pair with a force keeps the polygon it slipped on (`coulomb`); at zero force its
        // orientation holds nothing and the rate problem's own polygon is laid
        let polygon = self.p.polygon_of(state, p).filter(|_| closed);
        let margin = match polygon {
            Some(_) => -self.p.friction_excess(state, p),
            None => self.p.pairs[p].friction.capacity(ln) - cone_rows::norm(&lt),
        };
        match (pair.frictional(), closed) {
            (false, true) => Role::Normal,
            (false, false) => Role::Critical,
            (true, true) if margin > tol => Role::Stick,
            (true, closed) => {
                let held = Some(state.slip_dir(p)).filter(|e| {
                    matches!(state.status[p], Status::Slip { .. }) && e[0].hypot(e[1]) > 0.0
                });
                let sides =
                    cone_rows::directions(&pair.friction, &lt, polygon, held, &self.laid[p], tol);
                let facets = cone_rows::facets(&pair.friction, (ln, &lt), sides, tol);
                Role::Friction { closed, facets, polygon: polygon.is_some() }
            }
        }
    }

    /// The unknowns of one pair and its forces (Λn, Λt) in terms of them: Λn, then Λt along
    /// each tangential coordinate, then one slip rate per facet.
    fn force_unknowns(&self, prob: &mut Unknowns, p: usize, role: &Role) -> PairForces {
        let n_t = self.tangents(p).len();
        let n =
            prob.unknown(!matches!(role, Role::Critical | Role::Friction { closed: false, .. }));
        let t: Vec<usize> = match role {
            Role::Normal | Role::Critical => vec![],
            Role::Stick | Role::Friction { .. } => (0..n_t).map(|_| prob.unknown(true)).collect(),
        };
        let slips = match role {
            Role::Friction { facets, .. } => {
                facets.iter().map(|_| prob.length_unknown(false)).collect()
            }
            _ => vec![],
        };
        let tangential = match role {
            Role::Normal | Role::Critical => vec![Affine::constant(0.0); n_t],
            _ => t.iter().map(|&i| Affine::var(i)).collect(),
        };
        PairForces { normal: Affine::var(n), tangential, n, t, slips }
    }

    /// w_nᵀΔu and w_tᵀΔu (per tangential coordinate) of every pair in q as affine forms: the
    /// flexibility (Cᵀ K# E) applied to ΔΛ = Λ − λ, plus K# r and the rigid modes.
    fn kinematics(
        &self,
        state: &State<D>,
        q: &[usize],
        forces: &[PairForces],
        alpha: &[usize],
        z0: &[f64],
    ) -> (Vec<Affine>, Vec<Vec<Affine>>) {
        let vecs: Vec<_> = q
            .iter()
            .flat_map(|&p| {
                std::iter::once(&self.p.pairs[p].w_n)
                    .chain(self.tangents(p).into_iter().map(move |k| self.tangent_vec(p, k)))
            })
            .collect();
        let change = |f: &Affine, now: f64| f.clone().scaled_add(-1.0, &Affine::constant(now));
        let deltas: Vec<Affine> = q
            .iter()
            .zip(forces)
            .flat_map(|(&p, f)| {
                std::iter::once(change(&f.normal, state.lambda_n[p]))
                    .chain(
                        self.tangents(p)
                            .into_iter()
                            .zip(&f.tangential)
                            .map(|(k, t)| change(t, self.lambda_t(state, p, k))),
                    )
                    .collect::<Vec<_>>()
            })
            .collect();
        let compliance = self.compliance.get_or_init(|| {
            let flex: Vec<Vec<f64>> = vecs
                .iter()
                .map(|w| self.stiffness.flexibility_times(&self.p.dofs.contact_slot, &w.entries))
                .collect();
            DMatrix::from_fn(vecs.len(), vecs.len(), |a, b| self.p.dot_slots(vecs[a], &flex[b]))
        });
        let mut forms = vecs.iter().enumerate().map(|(i, a)| {
            let mut f = Affine::constant(self.p.dot_slots(a, z0));
            for (b, delta) in deltas.iter().enumerate() {
                f = f.scaled_add(compliance[(i, b)], delta);
            }
            for (k, &ak) in alpha.iter().enumerate() {
                f = f.scaled_add(a.dot(&self.p.bodies.mode_vectors[k]), &Affine::var(ak));
            }
            f
        });
        q.iter()
            .map(|&p| {
                (
                    forms.next().expect("a normal form"),
                    forms.by_ref().take(self.tangents(p).len()).collect(),
                )
            })
            .unzip()
    }

    /// The complementary rows of one pair's unknowns (see the module documentation): g' for Λn;
    /// for Λt the slip rate v = 0 (stick), or on the cone its slip and facets' rows
    /// (`cone_rows::slip_rows`).
    fn pair_rows(
        &self,
        prob: &mut Unknowns,
        p: usize,
        role: &Role,
        forces: &PairForces,
        g: Affine,
        v: Vec<Affine>,
    ) {
        prob.rows[forces.n] = Some(g);
        match role {
            Role::Normal | Role::Critical => {}
            Role::Stick => forces.t.iter().zip(v).for_each(|(&t, v)| prob.rows[t] = Some(v)),
            Role::Friction { facets, .. } => {
                let unknowns = PairUnknowns { n: forces.n, t: &forces.t, slips: &forces.slips };
                cone_rows::slip_rows(prob, self.p.pairs[p].friction.mu, facets, unknowns, v);
            }
        }
    }

    /// The status of every pair after the solution y (pairs outside q keep theirs), and the
    /// held direction of those it sets slipping in 3D. A pair with zero force that ends the
    /// trial touching (g' = 0) stays closed: it may be what holds a rigid mode.
    fn statuses(&self, state: &State<D>, sol: &Solved) -> RateSolution {
        let tol = CRITICAL_FORCE * self.p.scales.force;
        let (y, scale) = (&sol.y, sol.scale);
        let mut status = state.status.clone();
        let mut slip_dir = vec![None; status.len()];
        for (i, (&p, role)) in sol.q.iter().zip(&sol.roles).enumerate() {
            let f = &sol.forces[i];
            let opens = f.normal.eval(y) <= tol && !sol.touching[i];
            status[p] = match role {
                Role::Normal | Role::Stick if self.presumed[p] => self.p.pairs[p].closed_status(),
                Role::Normal | Role::Stick => state.status[p],
                Role::Critical if opens => Status::Open,
                Role::Critical => self.p.pairs[p].closed_status(),
                Role::Friction { closed: false, .. } if opens => Status::Open,
                Role::Friction { facets, polygon, .. } => {
                    let rates: Vec<f64> = f.slips.iter().map(|&s| y[s]).collect();
                    let pair = &self.p.pairs[p];
                    let (status, placed) = cone_rows::slip_status(
                        &pair.friction,
                        pair.slips_along_a_line(),
                        &self.tangents(p),
                        (facets, *polygon),
                        &rates,
                        SLIP_RATE * scale,
                    );
                    slip_dir[p] = placed;
                    status
                }
            };
        }
        RateSolution { status, slip_dir }
    }
}

#[cfg(test)]
mod tests {
    use super::super::anticycling::{Admission, AntiCycling};
    use super::super::clock::Clock;
    use super::super::scenes::*;
    use super::super::selection::select;
    use super::super::stepping::Stepping;
    use super::super::switching::switch;
    use super::super::trial::remaining_load;
    use super::*;

    /// The pushed strip's two pairs, switched one event at a time at zero load (the paper's
    /// rule, one switch per pair and increment, never frozen), come back to where they started
    /// after two switches: a cycle.
    #[test]
    fn one_at_a_time_the_pushed_strips_two_pairs_cycle() {
        let m = pushed_strip(0.5);
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let mut cycles = AntiCycling::new(2, 0, usize::MAX);
        let initial = state.status.clone();
        let mut seen = vec![initial.clone()];
        for _ in 0..4 {
            let (trial, _) =
                remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
            let sel = select(
                &eng.problem,
                &state,
                &trial,
                &cycles,
                f64::INFINITY,
                Stepping::EventByEvent,
            );
            assert!(
                sel.zero_length() && !sel.group.is_empty(),
                "a zero-length switch, S = {}",
                sel.scale
            );
            let mut switched = vec![false; 2];
            for c in &sel.group {
                if let Admission::Apply = cycles.admit(c, true, &mut switched) {
                    switch(&eng.problem, &mut state, c);
                }
            }
            seen.push(state.status.clone());
        }
        assert_ne!(seen[1], initial);
        assert_eq!((&seen[2], &seen[4]), (&initial, &initial), "{seen:?}");
    }

    /// The rate problem sets both pairs' statuses together, and the trial with them is
    /// admissible from its start (checked on the trial's own rates, not by the selection): a
    /// closed pair's normal force grows (λ_n = 0 now), a slipping pair slips the way its
    /// friction opposes, an open pair's gap does not close; so the load advances at once.
    #[test]
    fn the_rate_problem_settles_the_cycle_with_admissible_statuses() {
        let m = pushed_strip(0.5);
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        state.status = solve_rate_problem(&mut eng, &state, Solve::RemainingLoad)
            .expect("the rate problem has a solution")
            .status;
        let (trial, _) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
        // Round-off: forces against the load (0.5), rates against the largest displacement rate;
        // ~1e-15 per operation on a six-node scene.
        let force = 1e-12 * 0.5;
        let rate = 1e-12 * trial.du.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (p, pair) in eng.problem.pairs.iter().enumerate() {
            let (gap_rate, slip_rate) = (pair.w_n.dot(&trial.du), pair.w_t().dot(&trial.du));
            match state.status[p] {
                Status::Open => {
                    assert!(gap_rate >= -rate, "pair {p} open but closing at {gap_rate}")
                }
                status => {
                    assert!(
                        trial.dlambda_n[p] >= -force,
                        "pair {p} {status:?} pulled: {}",
                        trial.dlambda_n[p]
                    );
                    if let Status::Slip { direction } = status {
                        assert!(
                            direction as f64 * slip_rate >= -rate,
                            "pair {p} slips against its friction: {slip_rate}"
                        );
                    }
                }
            }
        }
        assert!(state.status.iter().any(|s| s.is_closed()), "the strip rests on the flat");
        let cycles = AntiCycling::new(2, 0, 4);
        let sel =
            select(&eng.problem, &state, &trial, &cycles, f64::INFINITY, Stepping::EventByEvent);
        assert!(!sel.zero_length(), "the load advances: S = {}", sel.scale);
    }

    /// A strip of cubes [0, n] × [0, 1] × [0, 1] (six tetrahedra each, ν = 0) resting on a
    /// rigid flat z = 0 with its bottom nodes at x < n (gap 0, friction μ), held in x on its
    /// left face (`planar`: and in y everywhere), pushed towards it by `push` (x, y) at the
    /// bottom nodes of its right face.
    pub(super) fn pushed_strip_3d(
        n: usize,
        mu: f64,
        push: [f64; 3],
        planar: bool,
    ) -> crate::model::Model<crate::dim::Spatial> {
        use crate::material::Material;
        let id = |i: usize, j: usize, k: usize| i + (n + 1) * (j + 2 * k);
        let mesh = cube_block([n, 1, 1], 1.0);
        let (n_points, n_tets) = (mesh.nodes.len(), mesh.elements.len());
        let mut fixed: Vec<usize> =
            (0..2).flat_map(|j| (0..2).map(move |k| 3 * id(0, j, k))).collect();
        if planar {
            fixed.extend((0..n_points).map(|v| 3 * v + 1));
        }
        fixed.sort();
        let mut load = vec![0.0; 3 * n_points];
        for j in 0..2 {
            load[3 * id(n, j, 0)] = push[0] / 2.0;
            load[3 * id(n, j, 0) + 1] = push[1] / 2.0;
            load[3 * id(n, j, 0) + 2] = push[2] / 2.0;
        }
        let pairs = (0..n)
            .flat_map(|i| (0..2).map(move |j| (i, j)))
            .map(|(i, j)| crate::model::PairInput {
                node_a: id(i, j, 0),
                node_b: None,
                normal: [0.0, 0.0, 1.0],
                tangents: None,
                gap: 0.0,
                mu,
                contact: 0,
                weights: vec![],
            })
            .collect();
        let mut m = model(mesh, fixed, load, pairs, Material::elastic(E, 0.0));
        m.element_material = vec![0; n_tets];
        m
    }

    /// Zero-length switches one at a time from the start: the statuses after each (None when
    /// the load advances first).
    fn one_at_a_time<D: crate::element::Discretization>(
        m: &crate::model::Model<D>,
        switches: usize,
    ) -> Vec<Vec<Status>> {
        let clock = Clock::new();
        let (mut eng, mut state) = start(m, &clock);
        let n = eng.problem.pairs.len();
        let mut cycles = AntiCycling::new(n, 0, usize::MAX);
        let mut seen = vec![state.status.clone()];
        for _ in 0..switches {
            let Ok((trial, _)) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent)
            else {
                break;
            };
            let sel = select(
                &eng.problem,
                &state,
                &trial,
                &cycles,
                f64::INFINITY,
                Stepping::EventByEvent,
            );
            if !sel.zero_length() || sel.group.is_empty() {
                break;
            }
            let mut switched = vec![false; n];
            for c in &sel.group {
                if let Admission::Apply = cycles.admit(c, true, &mut switched) {
                    switch(&eng.problem, &mut state, c);
                }
            }
            seen.push(state.status.clone());
        }
        seen
    }

    /// In space: the strip of two cubes held in y (its pairs' one free tangent along x) and in x
    /// on its left face, pushed towards it at the bottom of its right face, its four pairs at
    /// zero force: switched one event at a time at zero load (one switch per pair and
    /// increment, never frozen), its far pairs stick and slip again and again, as the planar
    /// strip's (found by a search over pushes and μ on strips of two and three cubes).
    #[test]
    fn in_space_one_at_a_time_the_pushed_strips_pairs_cycle() {
        let seen = one_at_a_time(&pushed_strip_3d(2, 0.5, PLANAR_PUSH, true), 6);
        assert_eq!(seen.len(), 7, "six zero-length switches: {seen:?}");
        assert_ne!(seen[2], seen[3]);
        assert_eq!((&seen[4], &seen[6]), (&seen[2], &seen[2]), "{seen:?}");
        assert_eq!(&seen[5], &seen[3], "{seen:?}");
    }

    /// The pushes of the 3D strips: held in y, towards the held face; free in y, across it
    /// and down, so that friction can hold it (|p_y| < μ|p_z|) and its far pairs slip in the
    /// plane.
    const PLANAR_PUSH: [f64; 3] = [-0.5, 0.0, 0.0];
    const SPACE_PUSH: [f64; 3] = [-0.3, 0.2, -1.0];

    /// The faceted rate problem sets the 3D strips' statuses and slip directions together (the
    /// cycling one's, and one whose far pairs slip across its axis), and
    /// the trial with them (on the round cone) is admissible from its start, checked on the
    /// trial's own rates: a closed pair's normal force grows, a slipping pair's friction μλn e
    /// opposes its slip (−e · slip rate ≥ 0), an open pair's gap does not close; and the load
    /// advances at once.
    #[test]
    fn in_space_the_faceted_rate_problem_sets_admissible_statuses() {
        settles(&pushed_strip_3d(2, 0.5, PLANAR_PUSH, true));
        settles(&pushed_strip_3d(2, 1.0, SPACE_PUSH, false));
    }

    fn settles<D: crate::element::Discretization>(m: &crate::model::Model<D>) {
        let clock = Clock::new();
        let (mut eng, mut state) = start(m, &clock);
        let sol = solve_rate_problem(&mut eng, &state, Solve::RemainingLoad)
            .expect("the rate problem has a solution");
        state.status.clone_from(&sol.status);
        hold_slip_directions(&eng.problem, &mut state, &sol);
        let (trial, _) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
        // Round-off, as in 2D: ~1e-15 per operation on a twelve-node scene.
        let force = 1e-12 * 0.5;
        let rate = 1e-12 * trial.du.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut slipping = 0;
        for (p, pair) in eng.problem.pairs.iter().enumerate() {
            let gap_rate = pair.w_n.dot(&trial.du);
            match state.status[p] {
                Status::Open => {
                    assert!(gap_rate >= -rate, "pair {p} open but closing at {gap_rate}")
                }
                status => {
                    assert!(
                        trial.dlambda_n[p] >= -force,
                        "pair {p} {status:?} pulled: {}",
                        trial.dlambda_n[p]
                    );
                    if let Some((e, _)) = sol.slip_dir[p] {
                        slipping += 1;
                        assert!(
                            (e[0].hypot(e[1]) - 1.0).abs() <= 1e-15 && state.slip_dir(p) == e,
                            "pair {p} holds the rate problem's unit direction"
                        );
                        let v = crate::events::slip_rate(
                            pair,
                            &super::super::selection::trial_of(&trial),
                            p,
                        );
                        assert!(
                            -(e[0] * v[0] + e[1] * v[1]) >= -rate,
                            "pair {p} slips against its friction: {v:?} along {e:?}"
                        );
                    }
                }
            }
        }
        assert!(slipping > 0 && state.status.iter().any(|s| s.is_closed()), "{:?}", state.status);
        let cycles = AntiCycling::new(4, 0, 4);
        let sel =
            select(&eng.problem, &state, &trial, &cycles, f64::INFINITY, Stepping::EventByEvent);
        assert!(!sel.zero_length(), "the load advances: S = {}", sel.scale);
    }

    /// The faceted cone of the 3D rate problem (module documentation): a pair on the round cone
    /// is on the first facet of the polygon circumscribed and turned to its force, whose normal
    /// is its friction force's direction, the only side it can slip on (the others have present
    /// slack, no unknowns); a pair strictly inside sticks; at zero force every facet is
    /// reachable, the first along t1; a pair on its own polygon (it slipped since it closed)
    /// at a vertex has the vertex's two sides; a pair whose supports hold one tangent has the
    /// two sides of the other.
    #[test]
    fn the_cone_is_faceted_about_the_pairs_friction_force() {
        let (mu, ln, angle) = (0.5, 2.0, 0.7f64);
        let m = pushed_strip_3d(2, mu, [-0.5, 0.0, 0.0], false);
        let clock = Clock::new();
        let (eng, mut state) = start(&m, &clock);
        let rp = RateProblem {
            p: &eng.problem,
            stiffness: &eng.stiffness,
            loads: &eng.loads,
            laid: vec![vec![]; eng.problem.pairs.len()],
            presumed: vec![false; eng.problem.pairs.len()],
            compliance: Default::default(),
        };
        let (free, held) = (2, 0); // at x = 1, and on the face x = 0 held in x (t2 = x there)
        assert!(eng.problem.pairs[held].held(1) && eng.problem.pairs[free].has_tangent_plane());
        state.lambda_n[free] = ln;
        state.set_lambda_t(free, [mu * ln * angle.cos(), mu * ln * angle.sin()]);
        let Role::Friction { closed: true, facets, polygon: false } = rp.role(&state, free) else {
            panic!("a closed pair on the cone")
        };
        // Round-off of a sine and cosine sum: a few ulps of the unit normal and of μλn.
        let tol = 1e-14;
        assert!(facets.len() == 1 && facets[0].off.is_none(), "only the first facet is reachable");
        assert!(
            (facets[0].dir[0] - angle.cos()).abs() <= tol
                && (facets[0].dir[1] - angle.sin()).abs() <= tol,
            "{:?}",
            facets[0].dir
        );
        // on its own polygon, at the vertex m: the two sides m ± θ
        let law = eng.problem.pairs[free].friction;
        let m = [angle.cos(), angle.sin()];
        state.status[free] = Status::Slip { direction: 1 };
        state.set_facet(free, m, true);
        state.set_lambda_t(free, law.vertex_force(ln, m));
        let Role::Friction { closed: true, facets, polygon: true } = rp.role(&state, free) else {
            panic!("a pair at its polygon's vertex")
        };
        let mut sides: Vec<f64> = facets.iter().map(|f| f.dir[1].atan2(f.dir[0]) - angle).collect();
        sides.sort_by(f64::total_cmp);
        assert!(
            sides.len() == 2
                && (sides[0] + law.turn).abs() <= 1e-12
                && (sides[1] - law.turn).abs() <= 1e-12,
            "{sides:?}"
        );
        state.status[free] = Status::Stick;
        state.set_facet(free, [0.0; 2], false);
        state.set_lambda_t(free, [0.9 * mu * ln * angle.cos(), 0.9 * mu * ln * angle.sin()]);
        assert!(rp.role(&state, free) == Role::Stick);
        state.lambda_n[free] = 0.0;
        state.set_lambda_t(free, [0.0; 2]);
        let Role::Friction { closed: false, facets, .. } = rp.role(&state, free) else {
            panic!("a pair at zero force")
        };
        assert!(facets.iter().all(|f| f.off.is_none()) && facets[0].dir == [1.0, 0.0]);
        (state.lambda_n[held], state.lambda_t[held]) = (ln, mu * ln);
        let Role::Friction { facets, .. } = rp.role(&state, held) else {
            panic!("a pair on the cone")
        };
        assert!(
            facets
                == [
                    Facet { dir: vec![-1.0], off: Some(2.0 * mu * ln) },
                    Facet { dir: vec![1.0], off: None }
                ]
        );
    }
}
