//! The contact statuses at a fixed load, as a linear complementarity problem (LCP).
//!
//! A zero-length increment means the trial with the current statuses is inadmissible at once
//! (S = 0). Switching one violated status at a time (the paper's rule) may cycle. Instead, the
//! statuses of the *critical* pairs (zero gap and zero force, or on the Coulomb cone) are
//! found together: with Λ = λ + Δλ the contact forces at the end of the trial and
//!   Δu = K#(r + Σ w ΔΛ) + N α,   g' = gap + w_nᵀΔu,   v = w_tᵀΔu − (RTD at sticking − RTD),
//! the conditions of eqs. 22–24, 2–3 and 41 on each pair are
//!   strictly closed:         g' = 0 (Λn free);            stick inside the cone: v = 0 (Λt free)
//!   zero gap and force:      0 ≤ Λn ⊥ g' ≥ 0, and with friction Λt = β⁺ − β⁻,
//!                            0 ≤ β⁺ ⊥ γ + v ≥ 0,  0 ≤ β⁻ ⊥ γ − v ≥ 0,  0 ≤ γ ⊥ μΛn − β⁺ − β⁻ ≥ 0
//!                            (γ = |v|: slip opposes the friction force)
//!   on the cone, force sign σ: Λt = σ(μΛn − s),  0 ≤ s ⊥ −σ v ≥ 0   (stick, or slip along −σ)
//!   each free rigid mode:    Σ (Nᵀw) ΔΛ = −Nᵀ r   (α free)
//! A free variable x with its equation R = 0 becomes x = x⁺ − x⁻ with 0 ≤ x⁺ ⊥ R ≥ 0 and
//! 0 ≤ x⁻ ⊥ −R ≥ 0; pairing α with −R keeps M positive semidefinite without friction, so
//! Lemke's method (module `lcp`) solves it whenever a solution exists, and it terminates in
//! every case. The statuses follow from the solution.

use super::engine::Engine;
use super::state::State;
use crate::contact::Status;
use crate::lcp::lemke;
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
    /// Closed with positive force on the cone, force sign σ.
    Cone { sigma: f64 },
    /// Zero gap and zero force: open or closed is decided, with friction its tangential state.
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
        Affine { coef: vec![], constant: c }
    }
    fn var(i: usize) -> Self {
        Affine { coef: vec![(i, 1.0)], constant: 0.0 }
    }
    fn scaled_add(mut self, s: f64, other: &Affine) -> Self {
        self.coef.extend(other.coef.iter().map(|&(i, c)| (i, s * c)));
        self.constant += s * other.constant;
        self
    }
    fn eval(&self, y: &[f64]) -> f64 {
        self.constant + self.coef.iter().map(|&(i, c)| c * y[i]).sum::<f64>()
    }
}

/// The unknowns and their complementary rows, built up pair by pair.
#[derive(Default)]
struct Problem {
    /// Per unknown: may it be negative?
    free: Vec<bool>,
    /// Per unknown: its complementary row (an equation R = 0 for a free unknown).
    rows: Vec<Option<Affine>>,
}

impl Problem {
    fn unknown(&mut self, free: bool) -> usize {
        self.free.push(free);
        self.rows.push(None);
        self.free.len() - 1
    }
}

/// The statuses that satisfy every contact condition at the current load, or None when Lemke
/// finds no solution (the caller falls back to freezing).
impl Engine<'_> {
    pub fn solve_rate_problem(&mut self, state: &State) -> Option<Vec<Status>> {
        let q: Vec<usize> = (0..self.pairs.len()).filter(|&p| self.in_rate_problem(state, p)).collect();
        let roles: Vec<Role> = q.iter().map(|&p| self.role(state, p)).collect();
        let oob = self.out_of_balance(state, 1.0, None);
        let mut prob = Problem::default();
        // Λn, Λt of every pair in q, and α, as affine forms of the unknowns.
        let forces: Vec<(Affine, Affine)> = q.iter().zip(&roles).map(|(&p, &role)| self.force_unknowns(&mut prob, p, role)).collect();
        let alpha: Vec<usize> = (0..self.modes.len()).map(|_| prob.unknown(true)).collect();
        let (kin_n, kin_t) = self.kinematics(state, &q, &forces, &alpha, &oob.z0);
        for (i, (&p, &role)) in q.iter().zip(&roles).enumerate() {
            let g = kin_n[i].clone().scaled_add(1.0, &Affine::constant(self.pairs[p].gap(&state.u)));
            let h_t = if state.status[p] == Status::Stick { state.rtd_stick[p] - self.pairs[p].rtd(&state.u) } else { 0.0 };
            let v = kin_t[i].clone().scaled_add(-1.0, &Affine::constant(h_t));
            self.pair_rows(&mut prob, p, role, &forces[i], g, v);
        }
        for (k, &a) in alpha.iter().enumerate() {
            // −e_k = −(Σ (Nᵀw) ΔΛ + Nᵀ r), with −Nᵀ r = mode_rhs.
            let mut e = Affine::constant(-oob.mode_rhs[k]);
            for (i, &p) in q.iter().enumerate() {
                let (wn, wt) = (self.pairs[p].w_n.dot(&self.mode_vectors[k]), self.pairs[p].w_t.dot(&self.mode_vectors[k]));
                e = e.scaled_add(wn, &forces[i].0).scaled_add(-wn, &Affine::constant(state.lambda_n[p]));
                e = e.scaled_add(wt, &forces[i].1).scaled_add(-wt, &Affine::constant(state.lambda_t[p]));
            }
            prob.rows[a] = Some(Affine::constant(0.0).scaled_add(-1.0, &e));
        }
        let y = solve(&prob)?;
        let scale = kin_n.iter().chain(&kin_t).map(|a| a.eval(&y).abs()).fold(self.largest_displacement(&state.u, state.load_fraction), f64::max);
        let touching: Vec<bool> = q.iter().zip(&kin_n).map(|(&p, g)| self.pairs[p].gap(&state.u) + g.eval(&y) <= CRITICAL_GAP * scale).collect();
        Some(self.statuses(state, &q, &roles, &forces, (&kin_t, &touching), &y, scale))
    }

    /// Closed pairs, and open ones at zero gap.
    fn in_rate_problem(&self, state: &State, p: usize) -> bool {
        let umax = self.largest_displacement(&state.u, state.load_fraction);
        state.status[p].is_closed() || self.pairs[p].gap(&state.u) <= CRITICAL_GAP * umax + GAP_ROUND_OFF * self.scales.length
    }

    fn role(&self, state: &State, p: usize) -> Role {
        let tol = CRITICAL_FORCE * self.scales.force;
        let (pair, ln, lt) = (&self.pairs[p], state.lambda_n[p], state.lambda_t[p]);
        if !state.status[p].is_closed() || ln <= tol {
            Role::Critical
        } else if !pair.frictional() {
            Role::Normal
        } else if pair.mu * ln - lt.abs() <= tol {
            Role::Cone { sigma: if lt >= 0.0 { 1.0 } else { -1.0 } }
        } else {
            Role::Stick
        }
    }

    /// The unknowns of one pair and its forces (Λn, Λt) in terms of them.
    fn force_unknowns(&self, prob: &mut Problem, p: usize, role: Role) -> (Affine, Affine) {
        let mu = self.pairs[p].mu;
        match role {
            Role::Normal => (Affine::var(prob.unknown(true)), Affine::constant(0.0)),
            Role::Stick => (Affine::var(prob.unknown(true)), Affine::var(prob.unknown(true))),
            Role::Cone { sigma } => {
                let (n, s) = (prob.unknown(true), prob.unknown(false));
                (Affine::var(n), Affine { coef: vec![(n, sigma * mu), (s, -sigma)], constant: 0.0 })
            }
            Role::Critical if !self.pairs[p].frictional() => (Affine::var(prob.unknown(false)), Affine::constant(0.0)),
            Role::Critical => {
                let n = prob.unknown(false);
                let (bp, bm, _gamma) = (prob.unknown(false), prob.unknown(false), prob.unknown(false));
                (Affine::var(n), Affine { coef: vec![(bp, 1.0), (bm, -1.0)], constant: 0.0 })
            }
        }
    }

    /// w_nᵀΔu and w_tᵀΔu of every pair in q as affine forms: the flexibility (Cᵀ K# E) applied
    /// to ΔΛ = Λ − λ, plus K# r and the rigid modes.
    fn kinematics(&self, state: &State, q: &[usize], forces: &[(Affine, Affine)], alpha: &[usize], z0: &[f64]) -> (Vec<Affine>, Vec<Affine>) {
        let vecs: Vec<_> = q.iter().flat_map(|&p| [&self.pairs[p].w_n, &self.pairs[p].w_t]).collect();
        let deltas: Vec<Affine> = q.iter().zip(forces).flat_map(|(&p, (n, t))| [n.clone().scaled_add(-1.0, &Affine::constant(state.lambda_n[p])), t.clone().scaled_add(-1.0, &Affine::constant(state.lambda_t[p]))]).collect();
        let flex: Vec<Vec<f64>> = vecs.iter().map(|w| self.flexibility_times(&w.entries)).collect();
        let forms: Vec<Affine> = vecs
            .iter()
            .map(|a| {
                let mut f = Affine::constant(self.dot_slots(a, z0));
                for (b, delta) in deltas.iter().enumerate() {
                    f = f.scaled_add(self.dot_slots(a, &flex[b]), delta);
                }
                for (k, &ak) in alpha.iter().enumerate() {
                    f = f.scaled_add(a.dot(&self.mode_vectors[k]), &Affine::var(ak));
                }
                f
            })
            .collect();
        forms.chunks(2).map(|c| (c[0].clone(), c[1].clone())).unzip()
    }

    /// The complementary rows of one pair's unknowns (see the module documentation).
    fn pair_rows(&self, prob: &mut Problem, p: usize, role: Role, forces: &(Affine, Affine), g: Affine, v: Affine) {
        let n = forces.0.coef[0].0;
        prob.rows[n] = Some(g);
        match role {
            Role::Normal => {}
            Role::Stick => prob.rows[forces.1.coef[0].0] = Some(v),
            Role::Cone { sigma } => prob.rows[forces.1.coef[1].0] = Some(Affine::constant(0.0).scaled_add(-sigma, &v)),
            Role::Critical if !self.pairs[p].frictional() => {}
            Role::Critical => {
                let (bp, bm, gamma) = (n + 1, n + 2, n + 3);
                prob.rows[bp] = Some(Affine::var(gamma).scaled_add(1.0, &v));
                prob.rows[bm] = Some(Affine::var(gamma).scaled_add(-1.0, &v));
                let mu = self.pairs[p].mu;
                prob.rows[gamma] = Some(Affine { coef: vec![(n, mu), (bp, -1.0), (bm, -1.0)], constant: 0.0 });
            }
        }
    }

    /// The status of every pair after the solution y (pairs outside q keep theirs). A pair
    /// with zero force that ends the trial touching (g' = 0) stays closed: it may be what
    /// holds a rigid mode.
    fn statuses(&self, state: &State, q: &[usize], roles: &[Role], forces: &[(Affine, Affine)], (kin_t, touching): (&[Affine], &[bool]), y: &[f64], scale: f64) -> Vec<Status> {
        let tol = CRITICAL_FORCE * self.scales.force;
        let mut status = state.status.clone();
        for (i, (&p, &role)) in q.iter().zip(roles).enumerate() {
            let pair = &self.pairs[p];
            let slip = kin_t[i].eval(y) - if state.status[p] == Status::Stick { state.rtd_stick[p] - pair.rtd(&state.u) } else { 0.0 };
            let slipping = slip.abs() > SLIP_RATE * scale;
            status[p] = match role {
                Role::Normal | Role::Stick => state.status[p],
                Role::Cone { sigma } if slipping && -sigma * slip > 0.0 => Status::Slip { direction: (-sigma) as i8 },
                Role::Cone { .. } => Status::Stick,
                Role::Critical if forces[i].0.eval(y) <= tol && !touching[i] => Status::Open,
                Role::Critical if pair.frictional() && slipping => Status::Slip { direction: if slip > 0.0 { 1 } else { -1 } },
                Role::Critical => pair.closed_status(),
            };
        }
        status
    }
}

/// Convert to the standard LCP w = M z + q (free unknowns split in two) and solve it by
/// Lemke's method; y from z.
fn solve(prob: &Problem) -> Option<Vec<f64>> {
    // Column of z for each unknown (free: +col and +col+1 for x⁺, x⁻).
    let mut col = Vec::with_capacity(prob.free.len());
    let mut n = 0;
    for &f in &prob.free {
        col.push(n);
        n += if f { 2 } else { 1 };
    }
    let (mut m, mut qv) = (DMatrix::<f64>::zeros(n, n), DVector::<f64>::zeros(n));
    for (i, row) in prob.rows.iter().enumerate() {
        let row = row.as_ref()?;
        let copies: &[f64] = if prob.free[i] { &[1.0, -1.0] } else { &[1.0] };
        for (c, &sign) in copies.iter().enumerate() {
            let r = col[i] + c;
            qv[r] = sign * row.constant;
            for &(j, a) in &row.coef {
                m[(r, col[j])] += sign * a;
                if prob.free[j] {
                    m[(r, col[j] + 1)] -= sign * a;
                }
            }
        }
    }
    let sol = lemke(&m, &qv, PIVOTS_PER_VARIABLE * n + 100).ok()?;
    Some(prob.free.iter().enumerate().map(|(i, &f)| if f { sol.z[col[i]] - sol.z[col[i] + 1] } else { sol.z[col[i]] }).collect())
}
