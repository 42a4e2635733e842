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
//! help (`lemke_restarted`). It terminates in every case. The statuses follow from the solution.

use super::engine::Engine;
use super::loads::StageLoads;
use super::problem::Problem;
use super::state::State;
use super::stiffness::Stiffness;
use super::trial::{self, Solve};
use crate::contact::Status;
use crate::lcp::{lemke_with_covering, LcpSolution};
use nalgebra::{DMatrix, DVector};

/// A force below this × Σ|load| counts as zero: the pair is critical (or open, in a solution).
const CRITICAL_FORCE: f64 = 1e-10;
/// An open pair within this × max|u| (+ round-off of the length scale) of its target is critical.
const CRITICAL_GAP: f64 = 1e-8;
const GAP_ROUND_OFF: f64 = 1e-12;
/// A slip rate above this × max|kinematic term| is slip, not stick.
const SLIP_RATE: f64 = 1e-9;
/// Lemke's pivot bound: this × (LCP size) + 100.
const PIVOTS_PER_VARIABLE: usize = 50;

/// How a pair enters the rate problem.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    /// Closed with positive force, frictionless (or tangent held): g' = 0.
    Normal,
    /// Closed, stick strictly inside the cone: g' = 0, v = 0.
    Stick,
    /// Frictional, on the cone or at zero force: its slip is decided; `closed`: with positive
    /// force (g' = 0), else 0 ≤ Λn ⊥ g' ≥ 0. `off_cone`: per side (+t, −t) the slack μλn ± λt
    /// of a side of the cone the pair is not on (None: on it).
    Friction { closed: bool, off_cone: [Option<f64>; 2] },
    /// Frictionless at zero gap and zero force: open or closed is decided.
    Critical,
}

/// An affine form in the unknowns y: coef · y + constant.
#[derive(Clone)]
struct Affine {
    coef: Vec<(usize, f64)>,
    constant: f64,
}

impl Affine {
    fn constant(c: f64) -> Self {
        Affine {
            coef: vec![],
            constant: c,
        }
    }
    fn var(i: usize) -> Self {
        Affine {
            coef: vec![(i, 1.0)],
            constant: 0.0,
        }
    }
    fn scaled_add(mut self, s: f64, other: &Affine) -> Self {
        self.coef
            .extend(other.coef.iter().map(|&(i, c)| (i, s * c)));
        self.constant += s * other.constant;
        self
    }
    fn eval(&self, y: &[f64]) -> f64 {
        self.constant + self.coef.iter().map(|&(i, c)| c * y[i]).sum::<f64>()
    }
}

/// A solved rate problem: its pairs, their roles and forces, which end touching, the unknowns,
/// and the displacement scale of its tolerances.
struct Solved {
    q: Vec<usize>,
    roles: Vec<Role>,
    forces: Vec<(Affine, Affine)>,
    touching: Vec<bool>,
    y: Vec<f64>,
    scale: f64,
}

/// The unknowns and their complementary rows, built up pair by pair.
#[derive(Default)]
struct Unknowns {
    /// Per unknown: may it be negative?
    free: Vec<bool>,
    /// Per unknown: its complementary row (an equation R = 0 for a free unknown).
    rows: Vec<Option<Affine>>,
    /// Per unknown: a length (slip rate, rigid amplitude; its row a force), else a force (its
    /// row a length).
    length: Vec<bool>,
}

impl Unknowns {
    fn unknown(&mut self, free: bool) -> usize {
        self.free.push(free);
        self.rows.push(None);
        self.length.push(false);
        self.free.len() - 1
    }

    fn length_unknown(&mut self, free: bool) -> usize {
        let i = self.unknown(free);
        self.length[i] = true;
        i
    }
}

/// The statuses that satisfy every contact condition at the current load, or None when Lemke
/// finds no solution (the caller falls back to freezing). `what`: the remaining load, or a
/// contact sub-step's (`trial::Solve`).
pub(super) fn solve_rate_problem(eng: &mut Engine, state: &State, what: Solve) -> Option<Vec<Status>> {
    if eng.problem.dim == 3 {
        return None; // (2D only: the faceted cone in space is not built; the last resort freezes)
    }
    let oob = trial::out_of_balance(eng, state, what, None);
    RateProblem { p: &eng.problem, stiffness: &eng.stiffness, loads: &eng.loads }.solve(state, &oob)
}

/// The problem's pairs, flexibility and stage loads the rate problem is built from.
struct RateProblem<'a> {
    p: &'a Problem<'a>,
    stiffness: &'a Stiffness,
    loads: &'a StageLoads,
}

impl RateProblem<'_> {
    fn solve(&self, state: &State, oob: &trial::OutOfBalance) -> Option<Vec<Status>> {
        let q: Vec<usize> = (0..self.p.pairs.len()).filter(|&p| self.in_rate_problem(state, p)).collect();
        let roles: Vec<Role> = q.iter().map(|&p| self.role(state, p)).collect();
        let mut prob = Unknowns::default();
        // Λn, Λt of every pair in q, and α, as affine forms of the unknowns.
        let forces: Vec<(Affine, Affine)> = roles.iter().map(|&role| self.force_unknowns(&mut prob, role)).collect();
        let alpha: Vec<usize> = (0..self.p.bodies.modes.len()).map(|_| prob.length_unknown(true)).collect();
        let (kin_n, kin_t) = self.kinematics(state, &q, &forces, &alpha, &oob.z0);
        for (i, (&p, &role)) in q.iter().zip(&roles).enumerate() {
            let g = kin_n[i].clone().scaled_add(1.0, &Affine::constant(self.p.gap(state, p) + oob.dshift[p][0]));
            let h_t = if state.status[p] == Status::Stick {
                state.rtd_stick[p] - self.p.rtd(state, p) - oob.dshift[p][1]
            } else {
                -oob.dshift[p][1]
            };
            let v = kin_t[i].clone().scaled_add(-1.0, &Affine::constant(h_t));
            self.pair_rows(&mut prob, p, role, &forces[i], g, v);
        }
        self.equilibrium_rows(&mut prob, state, &q, &forces, &alpha, oob);
        let y = solve(&prob)?;
        let scale = kin_n.iter().chain(&kin_t).map(|a| a.eval(&y).abs()).fold(self.loads.largest_displacement(self.p, &state.u, state.load_fraction), f64::max);
        let touching = q.iter().zip(&kin_n).map(|(&p, g)| self.p.gap(state, p) + oob.dshift[p][0] + g.eval(&y) <= CRITICAL_GAP * scale).collect();
        Some(self.statuses(state, &Solved { q, roles, forces, touching, y, scale }))
    }

    /// The row of each free rigid mode k: its body's equilibrium −e_k = 0 with
    /// e_k = Σ (Nᵀw) ΔΛ + Nᵀ r over the pairs `q` (−Nᵀ r = mode_rhs), paired with α_k.
    fn equilibrium_rows(&self, prob: &mut Unknowns, state: &State, q: &[usize], forces: &[(Affine, Affine)], alpha: &[usize], oob: &trial::OutOfBalance) {
        for (k, &a) in alpha.iter().enumerate() {
            let mode = &self.p.bodies.mode_vectors[k];
            let mut e = Affine::constant(-oob.mode_rhs[k]);
            for (i, &p) in q.iter().enumerate() {
                let (wn, wt) = (self.p.pairs[p].w_n.dot(mode), self.p.pairs[p].w_t.dot(mode));
                e = e.scaled_add(wn, &forces[i].0).scaled_add(-wn, &Affine::constant(state.lambda_n[p]));
                e = e.scaled_add(wt, &forces[i].1).scaled_add(-wt, &Affine::constant(state.lambda_t[p]));
            }
            prob.rows[a] = Some(Affine::constant(0.0).scaled_add(-1.0, &e));
        }
    }

    /// Closed pairs, and open ones at zero gap.
    fn in_rate_problem(&self, state: &State, p: usize) -> bool {
        let umax = self.loads.largest_displacement(self.p, &state.u, state.load_fraction);
        state.status[p].is_closed()
            || self.p.gap(state, p)
                <= CRITICAL_GAP * umax + GAP_ROUND_OFF * self.p.scales.length
    }

    fn role(&self, state: &State, p: usize) -> Role {
        let tol = CRITICAL_FORCE * self.p.scales.force;
        let (pair, ln, lt) = (&self.p.pairs[p], state.lambda_n[p], state.lambda_t[p]);
        let closed = state.status[p].is_closed() && ln > tol;
        match (pair.frictional(), closed) {
            (false, true) => Role::Normal,
            (false, false) => Role::Critical,
            (true, true) if pair.mu * ln - lt.abs() > tol => Role::Stick,
            (true, closed) => {
                let off = |slack: f64| (slack > tol).then_some(slack);
                Role::Friction { closed, off_cone: [off(pair.mu * ln + lt), off(pair.mu * ln - lt)] }
            }
        }
    }

    /// The unknowns of one pair and its forces (Λn, Λt) in terms of them.
    fn force_unknowns(&self, prob: &mut Unknowns, role: Role) -> (Affine, Affine) {
        match role {
            Role::Normal => (Affine::var(prob.unknown(true)), Affine::constant(0.0)),
            Role::Critical => (Affine::var(prob.unknown(false)), Affine::constant(0.0)),
            Role::Stick => (
                Affine::var(prob.unknown(true)),
                Affine::var(prob.unknown(true)),
            ),
            Role::Friction { closed, .. } => {
                let (n, t) = (prob.unknown(closed), prob.unknown(true));
                let (_slip_plus, _slip_minus) = (prob.length_unknown(false), prob.length_unknown(false));
                (Affine::var(n), Affine::var(t))
            }
        }
    }

    /// w_nᵀΔu and w_tᵀΔu of every pair in q as affine forms: the flexibility (Cᵀ K# E) applied
    /// to ΔΛ = Λ − λ, plus K# r and the rigid modes.
    fn kinematics(&self, state: &State, q: &[usize], forces: &[(Affine, Affine)], alpha: &[usize], z0: &[f64]) -> (Vec<Affine>, Vec<Affine>) {
        let vecs: Vec<_> = q.iter().flat_map(|&p| [&self.p.pairs[p].w_n, &self.p.pairs[p].w_t]).collect();
        let change = |f: &Affine, now: f64| f.clone().scaled_add(-1.0, &Affine::constant(now));
        let deltas: Vec<Affine> = q.iter().zip(forces).flat_map(|(&p, (n, t))| [change(n, state.lambda_n[p]), change(t, state.lambda_t[p])]).collect();
        let flex: Vec<Vec<f64>> = vecs.iter().map(|w| self.stiffness.flexibility_times(&self.p.dofs.contact_slot, &w.entries)).collect();
        let forms: Vec<Affine> = vecs
            .iter()
            .map(|a| {
                let mut f = Affine::constant(self.p.dot_slots(a, z0));
                for (b, delta) in deltas.iter().enumerate() {
                    f = f.scaled_add(self.p.dot_slots(a, &flex[b]), delta);
                }
                for (k, &ak) in alpha.iter().enumerate() {
                    f = f.scaled_add(a.dot(&self.p.bodies.mode_vectors[k]), &Affine::var(ak));
                }
                f
            })
            .collect();
        forms.chunks(2).map(|c| (c[0].clone(), c[1].clone())).unzip()
    }

    /// The complementary rows of one pair's unknowns (see the module documentation).
    fn pair_rows(
        &self,
        prob: &mut Unknowns,
        p: usize,
        role: Role,
        forces: &(Affine, Affine),
        g: Affine,
        v: Affine,
    ) {
        let n = forces.0.coef[0].0;
        prob.rows[n] = Some(g);
        match role {
            Role::Normal | Role::Critical => {}
            Role::Stick => prob.rows[n + 1] = Some(v),
            Role::Friction { off_cone, .. } => {
                let (t, vp, vm, mu) = (n + 1, n + 2, n + 3, self.p.pairs[p].mu);
                prob.rows[t] = Some(
                    v.scaled_add(-1.0, &Affine::var(vp))
                        .scaled_add(1.0, &Affine::var(vm)),
                );
                // A side of the cone the pair is not on cannot be reached at the increment's
                // start: its slip rate is 0 (its row the present slack), whatever the forces
                // would be after the whole remaining load with the statuses held.
                let side = |slack: Option<f64>, sign: f64| match slack {
                    Some(s) => Affine::constant(s),
                    None => Affine { coef: vec![(n, mu), (t, sign)], constant: 0.0 },
                };
                prob.rows[vp] = Some(side(off_cone[0], 1.0));
                prob.rows[vm] = Some(side(off_cone[1], -1.0));
            }
        }
    }

    /// The status of every pair after the solution y (pairs outside q keep theirs). A pair
    /// with zero force that ends the trial touching (g' = 0) stays closed: it may be what
    /// holds a rigid mode.
    fn statuses(&self, state: &State, sol: &Solved) -> Vec<Status> {
        let tol = CRITICAL_FORCE * self.p.scales.force;
        let (y, scale) = (&sol.y, sol.scale);
        let mut status = state.status.clone();
        for (i, (&p, &role)) in sol.q.iter().zip(&sol.roles).enumerate() {
            let n = sol.forces[i].0.coef[0].0;
            let opens = sol.forces[i].0.eval(y) <= tol && !sol.touching[i];
            status[p] = match role {
                Role::Normal | Role::Stick => state.status[p],
                Role::Critical if opens => Status::Open,
                Role::Critical => self.p.pairs[p].closed_status(),
                Role::Friction { closed: false, .. } if opens => Status::Open,
                Role::Friction { .. } => {
                    let (vp, vm) = (y[n + 2], y[n + 3]);
                    if vp.max(vm) <= SLIP_RATE * scale {
                        Status::Stick
                    } else {
                        Status::Slip {
                            direction: if vp >= vm { 1 } else { -1 },
                        }
                    }
                }
            };
        }
        status
    }
}

/// The mixed problem as a standard LCP, solved by Lemke's method. A free unknown without a
/// diagonal entry (a rigid amplitude: a saddle point) is split into x⁺ − x⁻ ≥ 0 with
/// 0 ≤ x⁺ ⊥ R ≥ 0 and 0 ≤ x⁻ ⊥ −R ≥ 0 (R = −e pairs α with its equilibrium equation with the
/// sign that keeps M positive semidefinite without friction); the other free unknowns are
/// eliminated with their equations (Schur complement M_cc − M_cf M_ff⁻¹ M_fc).
fn solve(prob: &Unknowns) -> Option<Vec<f64>> {
    let (mut m, mut q, split, col) = split_saddles(prob)?;
    let d = unit_free(prob, &split, &col, &mut m, &mut q);
    let free: Vec<usize> = (0..prob.free.len())
        .filter(|&i| prob.free[i] && !split[i])
        .map(|i| col[i])
        .collect();
    let bounded: Vec<usize> = (0..q.len()).filter(|r| !free.contains(r)).collect();
    let pick = |rows: &[usize], cols: &[usize]| {
        DMatrix::from_fn(rows.len(), cols.len(), |i, j| m[(rows[i], cols[j])])
    };
    let lu_ff = pick(&free, &free).lu();
    let (m_cf, m_fc) = (pick(&bounded, &free), pick(&free, &bounded));
    let q_f = DVector::from_fn(free.len(), |i, _| q[free[i]]);
    let (x_fc, x_q) = if free.is_empty() {
        (DMatrix::zeros(0, bounded.len()), DVector::zeros(0))
    } else {
        (lu_ff.solve(&m_fc)?, lu_ff.solve(&q_f)?)
    };
    let m_c = pick(&bounded, &bounded) - &m_cf * &x_fc;
    let q_c = DVector::from_fn(bounded.len(), |i, _| q[bounded[i]]) - &m_cf * &x_q;
    let z_c = lemke_restarted(&m_c, &q_c)?.z;
    let x_f = -(&x_fc * &z_c + &x_q);
    let mut z = DVector::<f64>::zeros(q.len());
    bounded.iter().zip(z_c.iter()).for_each(|(&r, &v)| z[r] = v);
    free.iter().zip(x_f.iter()).for_each(|(&r, &v)| z[r] = v);
    z.component_mul_assign(&d);
    Some(
        (0..prob.free.len())
            .map(|i| {
                if split[i] {
                    z[col[i]] - z[col[i] + 1]
                } else {
                    z[col[i]]
                }
            })
            .collect(),
    )
}

/// The length unknowns' columns and rows × the flexibility's size s (the largest diagonal entry
/// of a force unknown, rounded to a power of two: exact): the rows of force unknowns are lengths, their coefficients compliances
/// or ratios; of length unknowns forces, coefficients ratios. Scaled, every entry is a
/// compliance and every constant a length, so Lemke's pivots do not depend on the unit system
/// (a congruence D M D: positive semidefiniteness kept). Returns D's diagonal: z = D z̃.
fn unit_free(prob: &Unknowns, split: &[bool], col: &[usize], m: &mut DMatrix<f64>, q: &mut DVector<f64>) -> DVector<f64> {
    let n = q.len();
    let s = (0..prob.free.len()).filter(|&i| !prob.length[i]).fold(0.0f64, |x, i| x.max(m[(col[i], col[i])].abs())).log2().round().exp2();
    let mut d = DVector::<f64>::from_element(n, 1.0);
    if !(s > 0.0 && s.is_finite()) {
        return d;
    }
    for i in (0..prob.free.len()).filter(|&i| prob.length[i]) {
        d[col[i]] = s;
        if split[i] {
            d[col[i] + 1] = s;
        }
    }
    for r in 0..n {
        q[r] *= d[r];
        for c in 0..n {
            m[(r, c)] *= d[r] * d[c];
        }
    }
    d
}

/// Lemke's method with d = 1, then with up to `COVERING_RESTARTS` seeded positive covering
/// vectors: its path depends on d, and for M that is not copositive-plus (friction) a ray with
/// one d proves nothing. Every attempt terminates, so this does.
fn lemke_restarted(m: &DMatrix<f64>, q: &DVector<f64>) -> Option<LcpSolution> {
    let n = q.len();
    let max_pivots = PIVOTS_PER_VARIABLE * n + 100;
    let mut seed = COVERING_SEED;
    (0..=COVERING_RESTARTS).find_map(|attempt| {
        let d = DVector::from_fn(n, |_, _| if attempt == 0 { 1.0 } else { covering_entry(&mut seed) });
        lemke_with_covering(m, q, &d, max_pivots).ok()
    })
}

/// Covering vectors tried after d = 1, their seed and the range of their entries.
const COVERING_RESTARTS: usize = 32;
const COVERING_SEED: u64 = 0x2545_f491_4f6c_dd1d;
const COVERING_RANGE: (f64, f64) = (0.1, 10.0);

/// A pseudo-random entry in COVERING_RANGE (xorshift: deterministic runs).
fn covering_entry(seed: &mut u64) -> f64 {
    *seed ^= *seed << 13;
    *seed ^= *seed >> 7;
    *seed ^= *seed << 17;
    let u = (*seed >> 11) as f64 / (1u64 << 53) as f64;
    COVERING_RANGE.0 + u * (COVERING_RANGE.1 - COVERING_RANGE.0)
}

/// M y + q over the unknowns with every saddle unknown split in two; which were split, and the
/// column of each unknown.
#[allow(clippy::type_complexity)]
fn split_saddles(prob: &Unknowns) -> Option<(DMatrix<f64>, DVector<f64>, Vec<bool>, Vec<usize>)> {
    let split: Vec<bool> = (0..prob.free.len())
        .map(|i| {
            prob.free[i]
                && !prob.rows[i]
                    .as_ref()
                    .is_some_and(|r| r.coef.iter().any(|&(j, a)| j == i && a != 0.0))
        })
        .collect();
    let mut col = Vec::with_capacity(prob.free.len());
    let mut n = 0;
    for &sp in &split {
        col.push(n);
        n += if sp { 2 } else { 1 };
    }
    let (mut m, mut q) = (DMatrix::<f64>::zeros(n, n), DVector::<f64>::zeros(n));
    for (i, row) in prob.rows.iter().enumerate() {
        let row = row.as_ref()?;
        let copies: &[f64] = if split[i] { &[1.0, -1.0] } else { &[1.0] };
        for (c, &sign) in copies.iter().enumerate() {
            let r = col[i] + c;
            q[r] = sign * row.constant;
            for &(j, a) in &row.coef {
                m[(r, col[j])] += sign * a;
                if split[j] {
                    m[(r, col[j] + 1)] -= sign * a;
                }
            }
        }
    }
    Some((m, q, split, col))
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
            let (trial, _) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
            let sel = select(&eng.problem, &state, &trial, &cycles, f64::INFINITY, Stepping::EventByEvent);
            assert!(sel.zero_length() && !sel.group.is_empty(), "a zero-length switch, S = {}", sel.scale);
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
        state.status = solve_rate_problem(&mut eng, &state, Solve::RemainingLoad).expect("the rate problem has a solution");
        let (trial, _) = remaining_load(&mut eng, &state, None, Stepping::EventByEvent).unwrap();
        // Round-off: forces against the load (0.5), rates against the largest displacement rate;
        // ~1e-15 per operation on a six-node scene.
        let force = 1e-12 * 0.5;
        let rate = 1e-12 * trial.du.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (p, pair) in eng.problem.pairs.iter().enumerate() {
            let (gap_rate, slip_rate) = (pair.w_n.dot(&trial.du), pair.w_t.dot(&trial.du));
            match state.status[p] {
                Status::Open => assert!(gap_rate >= -rate, "pair {p} open but closing at {gap_rate}"),
                status => {
                    assert!(trial.dlambda_n[p] >= -force, "pair {p} {status:?} pulled: {}", trial.dlambda_n[p]);
                    if let Status::Slip { direction } = status {
                        assert!(direction as f64 * slip_rate >= -rate, "pair {p} slips against its friction: {slip_rate}");
                    }
                }
            }
        }
        assert!(state.status.iter().any(|s| s.is_closed()), "the strip rests on the flat");
        let cycles = AntiCycling::new(2, 0, 4);
        let sel = select(&eng.problem, &state, &trial, &cycles, f64::INFINITY, Stepping::EventByEvent);
        assert!(!sel.zero_length(), "the load advances: S = {}", sel.scale);
    }
}
