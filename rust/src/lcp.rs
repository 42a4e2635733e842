//! Linear complementarity problems by Lemke's complementary pivoting method.
//!
//! LCP(M, q): find z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0 (M dense, any sign pattern, not
//! necessarily symmetric). Lemke's method adds an artificial variable z₀ with covering vector
//! d = 1, w = M z + q + d z₀, starts from the basis of all w with z₀ just large enough to make
//! q + d z₀ ≥ 0, and then pivots complementarily: the variable entering is always the
//! complement of the one that just left, the leaving one is found by the minimum-ratio test
//! (ties broken lexicographically with the rows of the basis inverse, so it cannot cycle). It
//! stops when z₀ leaves (a solution) or when no row limits the entering variable (a secondary
//! ray). It succeeds whenever M is a P-matrix, and for copositive-plus M (e.g. positive
//! semidefinite) whenever the LCP is feasible, so a ray then proves infeasibility. Each pivot
//! costs O(n²) on the dense tableau.
//!
//! Lemke's path depends on the covering vector d; for M that is not copositive-plus (friction)
//! a ray with one d proves nothing, so d = 1 is tried first and then `COVERING_RESTARTS` seeded
//! positive vectors. Each attempt terminates, so the call does.

use nalgebra::{DMatrix, DVector};

/// A pivot element must exceed this × the largest entry of its column.
const PIVOT_TOL: f64 = 1e-11;
/// Ratios within this (relative) are ties, broken lexicographically.
const TIE_TOL: f64 = 1e-12;

#[derive(Debug, Clone, PartialEq)]
pub enum LcpFailure {
    /// Lemke ended on a secondary ray: no solution is reachable (for copositive-plus M: none
    /// exists).
    Ray { pivots: usize },
    /// The pivot bound was reached (a guard: the lexicographic rule does not cycle).
    PivotLimit { pivots: usize },
    /// M or q contains NaN/inf, or the dimensions disagree.
    BadInput,
}

pub struct LcpSolution {
    pub z: DVector<f64>,
    pub w: DVector<f64>,
    pub pivots: usize,
}

/// The tableau [B⁻¹ | B⁻¹(−M) | B⁻¹(−d) | B⁻¹q] over the variables w (0..n), z (n..2n), z₀
/// (2n), with the basic variable of every row.
#[derive(Clone)]
struct Tableau {
    n: usize,
    t: DMatrix<f64>,
    basic: Vec<usize>,
}

impl Tableau {
    fn new(m: &DMatrix<f64>, q: &DVector<f64>) -> Self {
        let n = q.len();
        let mut t = DMatrix::<f64>::zeros(n, 2 * n + 2);
        for i in 0..n {
            t[(i, i)] = 1.0;
            for j in 0..n {
                t[(i, n + j)] = -m[(i, j)];
            }
            t[(i, 2 * n)] = -1.0;
            t[(i, 2 * n + 1)] = q[i];
        }
        Tableau {
            n,
            t,
            basic: (0..n).collect(),
        }
    }

    fn rhs(&self) -> usize {
        2 * self.n + 1
    }

    /// Make column `c` basic in row `r` (Gauss–Jordan).
    fn pivot(&mut self, r: usize, c: usize) {
        let p = self.t[(r, c)];
        let mut row = self.t.row(r).clone_owned();
        row /= p;
        for i in 0..self.n {
            if i != r {
                let f = self.t[(i, c)];
                if f != 0.0 {
                    for j in 0..self.t.ncols() {
                        self.t[(i, j)] -= f * row[j];
                    }
                }
            }
        }
        self.t.set_row(r, &row);
        self.basic[r] = c;
    }

    /// The lexicographic key of row i for entering column c: (rhs, B⁻¹ row) / pivot.
    fn key(&self, i: usize, c: usize) -> Vec<f64> {
        let p = self.t[(i, c)];
        std::iter::once(self.t[(i, self.rhs())] / p)
            .chain((0..self.n).map(|j| self.t[(i, j)] / p))
            .collect()
    }

    /// The leaving row for entering column c by the lexicographic minimum-ratio test; z₀'s row
    /// wins a tie (the method then ends). None: a ray.
    fn leaving_row(&self, c: usize) -> Option<usize> {
        let largest = (0..self.n)
            .map(|i| self.t[(i, c)].abs())
            .fold(0.0, f64::max);
        let mut best: Option<(usize, Vec<f64>)> = None;
        for i in (0..self.n).filter(|&i| self.t[(i, c)] > PIVOT_TOL * largest) {
            let key = self.key(i, c);
            let better = match &best {
                None => true,
                Some((b, bk)) => {
                    lex_less(&key, bk)
                        || (!lex_less(bk, &key)
                            && self.basic[i] == 2 * self.n
                            && self.basic[*b] != 2 * self.n)
                }
            };
            if better {
                best = Some((i, key));
            }
        }
        best.map(|(i, _)| i)
    }
}

/// a < b lexicographically, with entries within TIE_TOL (relative) counted equal.
fn lex_less(a: &[f64], b: &[f64]) -> bool {
    for (x, y) in a.iter().zip(b) {
        let scale = x.abs().max(y.abs()).max(f64::MIN_POSITIVE);
        if (x - y).abs() > TIE_TOL * scale {
            return x < y;
        }
    }
    false
}

/// Solve the LCP (M, q) by Lemke's method, restarting with other covering vectors after a
/// ray. `max_pivots` bounds the work of one attempt.
pub fn lemke(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    max_pivots: usize,
) -> Result<LcpSolution, LcpFailure> {
    let n = q.len();
    if m.nrows() != n || m.ncols() != n || m.iter().chain(q.iter()).any(|v| !v.is_finite()) {
        return Err(LcpFailure::BadInput);
    }
    if q.iter().all(|&v| v >= 0.0) {
        return Ok(LcpSolution {
            z: DVector::zeros(n),
            w: q.clone(),
            pivots: 0,
        });
    }
    let mut seed = COVERING_SEED;
    let mut failure = LcpFailure::Ray { pivots: 0 };
    for attempt in 0..=COVERING_RESTARTS {
        let covering: Vec<f64> = (0..n)
            .map(|_| {
                if attempt == 0 {
                    1.0
                } else {
                    covering_entry(&mut seed)
                }
            })
            .collect();
        match complementary_pivoting(m, q, &covering, max_pivots) {
            Ok(solution) => return Ok(solution),
            Err(f) => failure = f,
        }
    }
    Err(failure)
}

/// Covering vectors tried after d = 1, and their entries' range.
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

/// One run of Lemke's method with covering vector d.
fn complementary_pivoting(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    d: &[f64],
    max_pivots: usize,
) -> Result<LcpSolution, LcpFailure> {
    let n = q.len();
    let mut tab = Tableau::new(m, q);
    for i in 0..n {
        tab.t[(i, 2 * n)] = -d[i];
    }
    // z₀ enters where it is needed most: the smallest q_i / d_i.
    let first = (0..n).fold(0, |b, i| if q[i] / d[i] <= q[b] / d[b] { i } else { b });
    let mut leaving = tab.basic[first];
    tab.pivot(first, 2 * n);
    for pivots in 1..=max_pivots {
        let entering = if leaving < n {
            leaving + n
        } else {
            leaving - n
        };
        let Some(r) = tab.leaving_row(entering) else {
            return Err(LcpFailure::Ray { pivots });
        };
        leaving = tab.basic[r];
        tab.pivot(r, entering);
        if leaving == 2 * n {
            return Ok(polish(m, q, &tab.basic, pivots));
        }
    }
    Err(LcpFailure::PivotLimit { pivots: max_pivots })
}

/// The solution of the final basis recomputed from the original data (w − M z = q with the
/// nonbasic variables zero), so that z_i w_i = 0 holds exactly and round-off of the pivots is
/// not carried.
fn polish(m: &DMatrix<f64>, q: &DVector<f64>, basic: &[usize], pivots: usize) -> LcpSolution {
    let n = q.len();
    let mut b = DMatrix::<f64>::zeros(n, n);
    for (k, &v) in basic.iter().enumerate() {
        for i in 0..n {
            b[(i, k)] = if v < n {
                (i == v) as u8 as f64
            } else {
                -m[(i, v - n)]
            };
        }
    }
    let x = b.lu().solve(q).unwrap_or_else(|| DVector::zeros(n));
    let mut z = DVector::<f64>::zeros(n);
    for (k, &v) in basic.iter().enumerate() {
        if v >= n {
            z[v - n] = x[k].max(0.0);
        }
    }
    let w = m * &z + q;
    LcpSolution { z, w, pivots }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The LCP conditions checked from the definition, at a tolerance of `tol` × the data scale.
    fn assert_solves(m: &DMatrix<f64>, q: &DVector<f64>, z: &DVector<f64>, tol: f64) {
        let w = m * z + q;
        let scale = m.amax() * z.amax() + q.amax();
        for i in 0..q.len() {
            assert!(z[i] >= 0.0 && w[i] >= -tol * scale, "z = {z}, w = {w}");
            assert!(
                (z[i] * w[i]).abs() <= tol * scale * (1.0 + z.amax()),
                "z = {z}, w = {w}"
            );
        }
    }

    /// Every complementary basis tried: the solutions that exist (for a P-matrix exactly one).
    fn enumerate(m: &DMatrix<f64>, q: &DVector<f64>) -> Vec<DVector<f64>> {
        let n = q.len();
        let mut out = vec![];
        for mask in 0..(1usize << n) {
            let idx: Vec<usize> = (0..n).filter(|&i| mask >> i & 1 == 1).collect();
            let sub = DMatrix::from_fn(idx.len(), idx.len(), |a, b| m[(idx[a], idx[b])]);
            let rhs = DVector::from_fn(idx.len(), |a, _| -q[idx[a]]);
            let zs = if idx.is_empty() {
                DVector::zeros(0)
            } else if let Some(x) = sub.lu().solve(&rhs) {
                x
            } else {
                continue;
            };
            let mut z = DVector::zeros(n);
            idx.iter().zip(zs.iter()).for_each(|(&i, &v)| z[i] = v);
            let w = m * &z + q;
            if z.iter().chain(w.iter()).all(|&v| v >= -1e-12) {
                out.push(z);
            }
        }
        out
    }

    /// A seeded xorshift in [−1, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    #[test]
    fn nonnegative_q_is_solved_by_zero() {
        let s = lemke(
            &DMatrix::identity(3, 3),
            &DVector::from_vec(vec![1.0, 0.0, 2.0]),
            10,
        )
        .unwrap();
        assert_eq!(s.pivots, 0);
        assert!(s.z.iter().all(|&v| v == 0.0));
    }

    #[test]
    fn random_p_matrices_match_enumeration() {
        // S + K with S symmetric positive definite and K skew is a P-matrix: the solution is
        // unique, so Lemke's must equal the one found by trying all 2^n bases.
        let mut rng = Rng(0x9e3779b97f4a7c15);
        for trial in 0..200 {
            let n = 1 + trial % 8;
            let a = DMatrix::from_fn(n, n, |_, _| rng.next());
            let k = DMatrix::from_fn(n, n, |_, _| rng.next());
            let m = &a * a.transpose() + DMatrix::identity(n, n) * 0.1 + (&k - k.transpose());
            let q = DVector::from_fn(n, |_, _| rng.next());
            let s = lemke(&m, &q, 50 * n + 100).expect("a P-matrix LCP has a solution");
            assert_solves(&m, &q, &s.z, 1e-10);
            let all = enumerate(&m, &q);
            assert_eq!(all.len(), 1);
            assert!(
                (&all[0] - &s.z).amax() <= 1e-9 * (1.0 + s.z.amax()),
                "{} vs {}",
                all[0],
                s.z
            );
        }
    }

    #[test]
    fn degenerate_problems_terminate() {
        // Repeated rows and zeros in q: ties in every ratio test.
        let m = DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 0.0, 1.0, 2.0, 0.0, 0.0, 0.0, 1.0]);
        let q = DVector::from_vec(vec![-1.0, -1.0, 0.0]);
        let s = lemke(&m, &q, 1000).unwrap();
        assert_solves(&m, &q, &s.z, 1e-12);
    }

    #[test]
    fn an_infeasible_psd_problem_ends_on_a_ray() {
        // M = [[0, −1], [1, 0]] (skew: positive semidefinite), q = (−1, −1): w₁ = −z₂ − 1 ≥ 0
        // needs z₂ ≤ −1 < 0: no feasible point, so Lemke must end on a ray.
        let m = DMatrix::from_row_slice(2, 2, &[0.0, -1.0, 1.0, 0.0]);
        assert!(matches!(
            lemke(&m, &DVector::from_vec(vec![-1.0, -1.0]), 100),
            Err(LcpFailure::Ray { .. })
        ));
    }

    #[test]
    fn one_coulomb_pair_slips_with_the_hand_solution() {
        // One pair, flexibility [[1, 0], [0, 1]], pushed into the target (q_n = −1) and
        // sideways (q_t = −0.5), μ = 0.3; unknowns (Λn, β⁺, β⁻, γ), Λt = β⁺ − β⁻, rows
        // g = q_n + Λn ⊥ Λn, γ + v ⊥ β⁺, γ − v ⊥ β⁻, μΛn − β⁺ − β⁻ ⊥ γ with v = q_t + Λt.
        // Sticking would need |Λt| = 0.5 > μΛn = 0.3, so it slips: Λn = 1, Λt = 0.3, v = −0.2.
        let mu = 0.3;
        let m = DMatrix::from_row_slice(
            4,
            4,
            &[
                1.0, 0.0, 0.0, 0.0, 0.0, 1.0, -1.0, 1.0, 0.0, -1.0, 1.0, 1.0, mu, -1.0, -1.0, 0.0,
            ],
        );
        let q = DVector::from_vec(vec![-1.0, -0.5, 0.5, 0.0]);
        let s = lemke(&m, &q, 100).unwrap();
        assert_solves(&m, &q, &s.z, 1e-12);
        assert!(
            (s.z[0] - 1.0).abs() < 1e-12
                && (s.z[1] - s.z[2] - 0.3).abs() < 1e-12
                && (s.z[3] - 0.2).abs() < 1e-12,
            "{}",
            s.z
        );
    }

    #[test]
    fn nan_is_bad_input() {
        let m = DMatrix::from_row_slice(1, 1, &[f64::NAN]);
        assert_eq!(
            lemke(&m, &DVector::from_vec(vec![-1.0]), 10).err(),
            Some(LcpFailure::BadInput)
        );
    }
}
