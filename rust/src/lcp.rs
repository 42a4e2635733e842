//! Linear complementarity problems by Lemke's complementary pivoting method.
//!
//! LCP(M, q): given M (n×n, dense, any sign pattern, not necessarily symmetric) and q, find
//! z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0, i.e. z_i = 0 or w_i = 0 for every i.
//!
//! Lemke's method adds an artificial variable z₀ ≥ 0 with a covering vector d > 0 (here d = 1):
//! w = M z + q + d z₀. It starts from the basis of all w with z₀ = max_i(−q_i / d_i), so that
//! every basic value is ≥ 0; every later basis is almost complementary (one pair (w_i, z_i)
//! has neither variable basic). The complementary pivot rule lets enter the complement of the
//! variable that just left; the minimum ratio test min_i b_i / a_i over the entering column's
//! positive entries a_i (b = basic values) picks the row that leaves, so b stays ≥ 0. Ties
//! (degeneracy) are broken lexicographically with the rows of the basis inverse,
//! (b_i, (B⁻¹)_i) / a_i, which keeps every row lexicographically positive: no basis repeats,
//! the method cannot cycle. It ends when z₀ leaves (a solution) or when the entering column
//! has no positive entry (a secondary ray).
//!
//! It is guaranteed to end on a solution when M is a P-matrix (all principal minors > 0, e.g.
//! S + K with S symmetric positive definite and K skew), and when M is copositive-plus (e.g.
//! positive semidefinite) and the LCP is feasible; for copositive-plus M a ray therefore
//! proves that no z ≥ 0 with M z + q ≥ 0 exists. For other M (Coulomb friction is copositive
//! but not copositive-plus) a ray proves nothing; [`lemke_with_covering`] lets a caller retry
//! with another d.
//!
//! Each pivot is a Gauss–Jordan step on the dense n × (2n + 2) tableau, O(n²). Numerics:
//! - the tableau is built for the symmetrically equilibrated problem (D M D, D q / s, by powers
//!   of two: exact), and the covering vector d is that problem's: d = 1 covers its rows alike,
//!   whatever the units of M's rows (the original problem's covering vector is D⁻¹ d / s);
//! - before each ratio test the basic values and the entering column get one step of
//!   iterative refinement against the original columns (O(n²)), so that ties which exact
//!   arithmetic would see (frequent in friction problems) are seen to round-off;
//! - ties use the tolerances below; the final basis is solved once more from the original
//!   M and q (LU), so the result is accurate to round-off and z_i w_i = 0 exactly.
//!
//! The accuracy is relative to the largest |q_i|: z₀ d adds ≈ max |q_i| to every row, so a
//! row whose q_i is 10⁻⁹ of that keeps only the digits left over.

use nalgebra::{DMatrix, DVector};

/// A pivot element a_i must exceed PIVOT_TOL × max_k |a_k| of its column (smaller: a zero
/// polluted by round-off).
const PIVOT_TOL: f64 = 1e-10;
/// Ratios (and lexicographic keys) within TIE_TOL, relative, are a tie.
const TIE_TOL: f64 = 1e-12;
/// A basic value below ZERO_TOL × max_k |b_k| is round-off of a degenerate zero (so its ratio
/// ties with the least one within ZERO_TOL max_k |b_k| / a_i).
const ZERO_TOL: f64 = 1e-13;
/// A ratio test decided by less than this (relative) is refined first (`Tableau::clear_choice`):
/// far above the round-off of the tableau's entries (~1e-16 per pivot, ~1e-13 after
/// thousands), far below a difference the problem's data make.
const NEAR: f64 = 1e-7;
/// An entering column's entry within this factor of the pivot threshold may be on either side
/// of it to round-off: the column is refined first.
const PIVOT_BAND: f64 = 1e3;
/// Sweeps of symmetric Ruiz equilibration of M (a few bring rows and columns near unit size).
const EQUILIBRATION_SWEEPS: usize = 8;

#[derive(Debug, Clone, PartialEq)]
pub enum LcpFailure {
    /// Lemke ended on a secondary ray: no solution is reachable (for copositive-plus M: none
    /// exists).
    Ray { pivots: usize },
    /// The pivot bound was reached (should not happen with the lexicographic rule; a guard).
    PivotLimit { pivots: usize },
    /// M or q contains NaN/inf, or the dimensions disagree.
    BadInput,
    /// A stop was requested (`interrupt`) while it pivoted.
    Interrupted { pivots: usize },
}

#[derive(Debug, Clone)]
pub struct LcpSolution {
    pub z: DVector<f64>,
    pub w: DVector<f64>,
    pub pivots: usize,
}

/// Solve the LCP (M, q) by Lemke's method. `max_pivots` bounds the work (callers pass e.g.
/// 50 n + 100).
pub fn lemke(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    max_pivots: usize,
) -> Result<LcpSolution, LcpFailure> {
    lemke_with_covering(m, q, &DVector::from_element(q.len(), 1.0), max_pivots)
}

/// Lemke's method with covering vector d of the equilibrated problem (see the module text;
/// every d_i > 0 and finite, else `BadInput`).
pub fn lemke_with_covering(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    d: &DVector<f64>,
    max_pivots: usize,
) -> Result<LcpSolution, LcpFailure> {
    let n = q.len();
    let finite = m.iter().chain(q.iter()).chain(d.iter()).all(|v| v.is_finite());
    if m.shape() != (n, n) || d.len() != n || !finite || d.iter().any(|&v| v <= 0.0) {
        return Err(LcpFailure::BadInput);
    }
    if q.iter().all(|&v| v >= 0.0) {
        let z = DVector::zeros(n);
        return Ok(LcpSolution { z, w: q.clone(), pivots: 0 });
    }
    let scaling = Scaling::new(m, q);
    let mut tab = Tableau::new(m, q, d, &scaling);
    let pivots = tab.run(max_pivots)?;
    Ok(polish(m, q, &tab, &scaling, pivots))
}

/// The symmetric scaling M' = D M D, q' = D q / s, d' = D d: then z = s D z', w = s D⁻¹ w'
/// (z_i w_i = s² z'_i w'_i, so complementarity, P-matrix and copositivity carry over).
struct Scaling {
    diag: DVector<f64>,
    s: f64,
}

impl Scaling {
    fn new(m: &DMatrix<f64>, q: &DVector<f64>) -> Self {
        let n = q.len();
        let mut d = DVector::from_element(n, 1.0);
        for _ in 0..EQUILIBRATION_SWEEPS {
            // D_i ← D_i / √(max |(D M D)_ij|, |(D M D)_ji| over j), rounded to a power of two.
            let f = DVector::from_fn(n, |i, _| {
                let big = (0..n)
                    .map(|j| (d[i] * m[(i, j)] * d[j]).abs().max((d[j] * m[(j, i)] * d[i]).abs()))
                    .fold(0.0, f64::max);
                if big > 0.0 {
                    power_of_two(1.0 / big.sqrt())
                } else {
                    1.0
                }
            });
            d.component_mul_assign(&f);
        }
        if d.iter().any(|v| !v.is_normal()) {
            d.fill(1.0);
        }
        let s = power_of_two(q.component_mul(&d).amax());
        Scaling { diag: d, s: if s.is_normal() { s } else { 1.0 } }
    }
}

/// 2^round(log₂ x) for x > 0: scaling by it is exact.
fn power_of_two(x: f64) -> f64 {
    x.log2().round().clamp(-1000.0, 1000.0).exp2()
}

/// The tableau B⁻¹ [I | −M | −d | q] of the scaled problem over the variables w (columns
/// 0..n), z (n..2n), z₀ (2n), right-hand side (2n + 1), with the basic variable of each row.
/// Columns 0..n hold B⁻¹ itself, which the lexicographic rule reads; `t0` is the initial
/// tableau [I | −M | −d | q], the original columns.
struct Tableau {
    n: usize,
    t: DMatrix<f64>,
    t0: DMatrix<f64>,
    basic: Vec<usize>,
}

impl Tableau {
    fn new(m: &DMatrix<f64>, q: &DVector<f64>, d: &DVector<f64>, sc: &Scaling) -> Self {
        let n = q.len();
        let mut t = DMatrix::zeros(n, 2 * n + 2);
        for i in 0..n {
            t[(i, i)] = 1.0;
            for j in 0..n {
                t[(i, n + j)] = -(sc.diag[i] * m[(i, j)] * sc.diag[j]);
            }
            t[(i, 2 * n)] = -d[i];
            t[(i, 2 * n + 1)] = sc.diag[i] * q[i] / sc.s;
        }
        Tableau { n, t0: t.clone(), t, basic: (0..n).collect() }
    }

    fn z0(&self) -> usize {
        2 * self.n
    }

    fn rhs(&self, i: usize) -> f64 {
        self.t[(i, 2 * self.n + 1)]
    }

    /// Complementary pivoting until z₀ leaves; the number of pivots.
    fn run(&mut self, max_pivots: usize) -> Result<usize, LcpFailure> {
        if max_pivots == 0 {
            return Err(LcpFailure::PivotLimit { pivots: 0 });
        }
        // z₀ enters in the row of the lexicographically least (q_i, e_iᵀ) / d_i (its column
        // holds −d): afterwards b_k = q_k − d_k q_r / d_r ≥ 0 for all k.
        let z0 = self.z0();
        let d = |i: usize| -self.t[(i, z0)];
        let all: Vec<usize> = (0..self.n).collect();
        let r =
            self.lex_min(&all, |i| self.rhs(i) / d(i), d).ok_or(LcpFailure::Ray { pivots: 0 })?;
        let mut leaving = self.basic[r];
        self.pivot(r, z0);
        let mut pivots = 1;
        while leaving != z0 {
            if pivots >= max_pivots {
                return Err(LcpFailure::PivotLimit { pivots });
            }
            if crate::interrupt::checkpoint(crate::interrupt::Checkpoint::LcpPivot).is_err() {
                return Err(LcpFailure::Interrupted { pivots });
            }
            let entering = if leaving < self.n { leaving + self.n } else { leaving - self.n };
            // refined only where the ratio test is close to a tie (or a pivot to the
            // threshold): elsewhere round-off cannot change its choice, and the refinement's
            // O(n²) reads cost as much as the pivot itself
            if !self.clear_choice(entering) {
                self.refine([2 * self.n + 1, entering]);
            }
            let r = self.leaving_row(entering).ok_or(LcpFailure::Ray { pivots })?;
            leaving = self.basic[r];
            self.pivot(r, entering);
            pivots += 1;
        }
        Ok(pivots)
    }

    /// Whether the ratio test for column c picks its row by a margin round-off cannot close:
    /// no entry within a factor `PIVOT_BAND` of the pivot threshold, and one row's ratio below every other's
    /// by `NEAR` (relative, with the floor `NEAR` β / a_i for degenerate rows).
    fn clear_choice(&self, c: usize) -> bool {
        let a = |i: usize| self.t[(i, c)];
        let largest = (0..self.n).map(|i| a(i).abs()).fold(0.0, f64::max);
        let (low, high) = (PIVOT_TOL * largest / PIVOT_BAND, PIVOT_TOL * largest * PIVOT_BAND);
        if (0..self.n).any(|i| (low..=high).contains(&a(i).abs())) {
            return false;
        }
        let beta = (0..self.n).map(|i| self.rhs(i).abs()).fold(0.0, f64::max);
        let rows = (0..self.n).filter(|&i| a(i) > PIVOT_TOL * largest);
        let ratio = |i: usize| self.rhs(i).max(0.0) / a(i);
        let theta_min = rows.clone().map(ratio).fold(f64::INFINITY, f64::min);
        rows.filter(|&i| ratio(i) <= theta_min + NEAR * (theta_min.abs() + beta / a(i))).count()
            == 1
    }

    /// The row leaving when column c enters (minimum ratio test, lexicographic ties); None
    /// when no entry of the column is positive: a ray.
    fn leaving_row(&self, c: usize) -> Option<usize> {
        let a = |i: usize| self.t[(i, c)];
        let largest = (0..self.n).map(|i| a(i).abs()).fold(0.0, f64::max);
        let rows: Vec<usize> = (0..self.n).filter(|&i| a(i) > PIVOT_TOL * largest).collect();
        // θ_i = b_i / a_i, a round-off negative b_i counted as the zero it is.
        self.lex_min(&rows, |i| self.rhs(i).max(0.0) / a(i), a)
    }

    /// Among `rows`, the least key (θ_i, (B⁻¹)_i / a_i) lexicographically, θ = `ratio` and
    /// a = `div` > 0. θ_i ties with θ_min when θ_i ≤ θ_min + TIE_TOL |θ_min| + ZERO_TOL β / a_i
    /// (β = max_k |b_k|); z₀'s row wins a tie (its leaving ends the method). Later keys tie
    /// alike, with the floor ZERO_TOL ρ, ρ the largest |key| of the tied rows.
    fn lex_min(
        &self,
        rows: &[usize],
        ratio: impl Fn(usize) -> f64,
        div: impl Fn(usize) -> f64,
    ) -> Option<usize> {
        let theta_min = rows.iter().map(|&i| ratio(i)).fold(f64::INFINITY, f64::min);
        let beta = (0..self.n).map(|i| self.rhs(i).abs()).fold(0.0, f64::max);
        let tied =
            |i: usize| ratio(i) <= theta_min + TIE_TOL * theta_min.abs() + ZERO_TOL * beta / div(i);
        let mut ties: Vec<usize> = rows.iter().copied().filter(|&i| tied(i)).collect();
        if let Some(&i) = ties.iter().find(|&&i| self.basic[i] == self.z0()) {
            return Some(i);
        }
        // ρ: the largest |(B⁻¹)_ij| / a_i of the tied rows, the scale of the keys' round-off.
        let key = |i: usize, j: usize| self.t[(i, j)] / div(i);
        let rho = ties
            .iter()
            .flat_map(|&i| (0..self.n).map(move |j| key(i, j).abs()))
            .fold(0.0, f64::max);
        for j in 0..self.n {
            if ties.len() <= 1 {
                break;
            }
            let least = ties.iter().map(|&i| key(i, j)).fold(f64::INFINITY, f64::min);
            ties.retain(|&i| key(i, j) <= least + TIE_TOL * least.abs() + ZERO_TOL * rho);
        }
        ties.first().copied()
    }

    /// Gauss–Jordan step making column c basic in row r: row_r /= t_rc, then
    /// row_i −= t_ic row_r for i ≠ r.
    fn pivot(&mut self, r: usize, c: usize) {
        let p = self.t[(r, c)];
        let col: Vec<f64> = self.t.column(c).iter().copied().collect();
        // column by column over the column-major storage: row_i −= t_ic f for every i, then
        // row r's entry set to f itself
        for column in self.t.as_mut_slice().chunks_exact_mut(self.n) {
            let f = column[r] / p;
            if f != 0.0 {
                column.iter_mut().zip(&col).for_each(|(x, &a)| *x -= a * f);
                column[r] = f;
            }
        }
        self.t.column_mut(c).fill(0.0);
        self.t[(r, c)] = 1.0;
        self.basic[r] = c;
    }

    /// One step of iterative refinement of tableau columns c = B⁻¹ x (x: their original
    /// columns), which pivoting alone lets drift: r = x − B (B⁻¹ x) from the original columns of
    /// the basis, then B⁻¹ x += B⁻¹ r. O(n²), so exact ties stay ties to round-off; the two
    /// columns of a pivot (the right-hand side, the entering one) in one pass over the basis
    /// and over B⁻¹, the tableau's memory traffic being its cost.
    fn refine(&mut self, columns: [usize; 2]) {
        let n = self.n;
        let mut r = columns.map(|c| self.t0.column(c).clone_owned());
        let x = columns.map(|c| self.t.column(c).clone_owned());
        for (k, &v) in self.basic.iter().enumerate() {
            if v < n {
                r.iter_mut().zip(&x).for_each(|(r, x)| r[v] -= x[k]); // w_v's original column is e_v
            } else {
                let original = self.t0.column(v);
                for (i, &m) in original.iter().enumerate() {
                    r[0][i] -= x[0][k] * m;
                    r[1][i] -= x[1][k] * m;
                }
            }
        }
        let mut correction = [vec![0.0; n], vec![0.0; n]];
        for (j, inverse) in self.t.as_slice()[..n * n].chunks_exact(n).enumerate() {
            let (a, b) = (r[0][j], r[1][j]);
            for (i, &v) in inverse.iter().enumerate() {
                correction[0][i] += a * v;
                correction[1][i] += b * v;
            }
        }
        for (c, dx) in columns.into_iter().zip(&correction) {
            for (i, d) in dx.iter().enumerate() {
                self.t[(i, c)] += d;
            }
        }
    }

    /// z read off the tableau (basic z_j = b_r, unscaled: z = s D z'), clamped at 0.
    fn z(&self, sc: &Scaling) -> DVector<f64> {
        let mut z = DVector::zeros(self.n);
        for (r, &v) in self.basic.iter().enumerate() {
            if (self.n..2 * self.n).contains(&v) {
                let j = v - self.n;
                z[j] = (sc.s * sc.diag[j] * self.rhs(r)).max(0.0);
            }
        }
        z
    }
}

/// The final complementary basis solved again from the original data: B x = q with column
/// e_i for a basic w_i and −M_j for a basic z_j. Of that z and the tableau's, the one with the
/// smaller violation is kept; w = M z + q, set to exactly 0 where z_i > 0 (w_i is nonbasic).
fn polish(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    tab: &Tableau,
    sc: &Scaling,
    pivots: usize,
) -> LcpSolution {
    let n = q.len();
    let b = DMatrix::from_fn(n, n, |i, k| match tab.basic[k] {
        v if v < n => f64::from(u8::from(i == v)),
        v => -m[(i, v - n)],
    });
    let mut z = tab.z(sc);
    if let Some(x) = b.lu().solve(q).filter(|x| x.iter().all(|v| v.is_finite())) {
        let mut z_lu = DVector::zeros(n);
        for (k, &v) in tab.basic.iter().enumerate() {
            if v >= n {
                z_lu[v - n] = x[k].max(0.0);
            }
        }
        if violation(m, q, &z_lu, sc) <= violation(m, q, &z, sc) {
            z = z_lu;
        }
    }
    let mut w = m * &z + q;
    for i in 0..n {
        if z[i] > 0.0 {
            w[i] = 0.0;
        }
    }
    LcpSolution { z, w, pivots }
}

/// max_i of the error of w_i = (M z + q)_i, |w_i| where z_i > 0 (complementarity) and
/// max(−w_i, 0) elsewhere (feasibility), relative to the size of its terms in the equilibrated
/// problem: |q_i| + Σ_j |M_ij| D_j ζ with ζ = max_k z_k / D_k (a degenerate z_k that is
/// round-off of 0 then does not set the scale).
fn violation(m: &DMatrix<f64>, q: &DVector<f64>, z: &DVector<f64>, sc: &Scaling) -> f64 {
    let w = m * z + q;
    let zeta = z.component_div(&sc.diag).amax();
    (0..q.len())
        .map(|i| {
            let terms = (0..q.len()).map(|j| m[(i, j)].abs() * sc.diag[j]).sum::<f64>();
            let err = if z[i] > 0.0 { w[i].abs() } else { (-w[i]).max(0.0) };
            if err > 0.0 {
                err / (q[i].abs() + terms * zeta)
            } else {
                0.0
            }
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seeded xorshift64 (no rand crate): uniform in [lo, hi).
    struct Rng(u64);

    impl Rng {
        fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
        }

        fn matrix(&mut self, n: usize) -> DMatrix<f64> {
            DMatrix::from_fn(n, n, |_, _| self.uniform(-1.0, 1.0))
        }
    }

    /// The LCP conditions from the definition, w recomputed here: z ≥ 0, w ≥ −tol·scale_i,
    /// |z_i w_i| ≤ tol·z_i·scale_i with scale_i = |q_i| + Σ_j |M_ij z_j| (the size of the terms
    /// of w_i); the returned w must be M z + q and exactly complementary to z.
    fn assert_solves(m: &DMatrix<f64>, q: &DVector<f64>, s: &LcpSolution, tol: f64) {
        let w = m * &s.z + q;
        for i in 0..q.len() {
            let scale = q[i].abs() + (0..q.len()).map(|j| (m[(i, j)] * s.z[j]).abs()).sum::<f64>();
            let ctx = format!("i = {i}, z = {}, w = {}", s.z, w);
            assert!(s.z[i] >= -1e-12 * s.z.amax(), "z ≥ 0 fails: {ctx}");
            assert!(w[i] >= -tol * scale, "w ≥ 0 fails: {ctx}");
            assert!((s.z[i] * w[i]).abs() <= tol * s.z[i].abs() * scale, "z w = 0 fails: {ctx}");
            assert!((s.w[i] - w[i]).abs() <= tol * scale, "returned w ≠ M z + q: {ctx}");
            assert!(s.z[i] * s.w[i] == 0.0, "returned pair not complementary: {ctx}");
        }
    }

    /// Every complementary basis (z_i basic for i in the mask, w_i otherwise) whose basic
    /// solution satisfies the LCP within `tol` (relative, as in `assert_solves`).
    fn enumerate(m: &DMatrix<f64>, q: &DVector<f64>, tol: f64) -> Vec<DVector<f64>> {
        let n = q.len();
        let mut out = vec![];
        for mask in 0..1usize << n {
            let idx: Vec<usize> = (0..n).filter(|&i| mask >> i & 1 == 1).collect();
            let m_bb = DMatrix::from_fn(idx.len(), idx.len(), |a, b| m[(idx[a], idx[b])]);
            let q_b = DVector::from_fn(idx.len(), |a, _| -q[idx[a]]);
            // (nalgebra's LU panics on 0 × 0.)
            let z_b = if idx.is_empty() { Some(q_b) } else { m_bb.lu().solve(&q_b) };
            let Some(z_b) = z_b else { continue };
            let mut z = DVector::zeros(n);
            idx.iter().zip(z_b.iter()).for_each(|(&i, &v)| z[i] = v);
            let w = m * &z + q;
            let ok = (0..n).all(|i| {
                let scale = q[i].abs() + (0..n).map(|j| (m[(i, j)] * z[j]).abs()).sum::<f64>();
                z[i] >= -tol * z.amax() && w[i] >= -tol * scale
            });
            if ok {
                out.push(z);
            }
        }
        out
    }

    #[test]
    fn nonnegative_q_is_solved_by_zero() {
        let m = DMatrix::from_row_slice(2, 2, &[-1.0, 3.0, 2.0, -5.0]);
        let q = DVector::from_vec(vec![0.0, 2.0]);
        let s = lemke(&m, &q, 10).unwrap();
        assert_eq!(s.pivots, 0);
        assert!(s.z.iter().all(|&v| v == 0.0) && s.w == q);
    }

    #[test]
    fn textbook_two_by_two() {
        // M = [[2, 1], [−1, 2]] is a P-matrix (minors 2, 2, 5). The four complementary bases,
        // q = (−3, 1): {} w = q ✗; {z₁}: z₁ = 3/2, w₂ = −1/2 ✗; {z₂}: z₂ = −1/2 ✗;
        // {z₁, z₂}: M z = (3, −1) ⇒ z = (7/5, 1/5) ✓, the unique solution.
        let m = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, -1.0, 2.0]);
        let q = DVector::from_vec(vec![-3.0, 1.0]);
        let all = enumerate(&m, &q, 1e-14);
        assert_eq!(all.len(), 1);
        assert!((&all[0] - DVector::from_vec(vec![1.4, 0.2])).amax() < 1e-15);
        let s = lemke(&m, &q, 100).unwrap();
        assert_solves(&m, &q, &s, 1e-14);
        assert!((&s.z - &all[0]).amax() < 1e-15, "z = {}", s.z);
    }

    /// A random P-matrix of one of three kinds: A Aᵀ + I; S + K (S SPD, K skew); D (S + K) D
    /// with D_i in 10^[−3, 3], so entries span 1e−6..1e6 (D M D stays a P-matrix).
    fn random_p_lcp(rng: &mut Rng, n: usize, kind: usize) -> (DMatrix<f64>, DVector<f64>) {
        let a = rng.matrix(n);
        let mut m = &a * a.transpose() + DMatrix::identity(n, n);
        let mut q = DVector::from_fn(n, |_, _| rng.uniform(-1.0, 1.0));
        if kind >= 1 {
            let k = rng.matrix(n) * 2.0;
            m = m * 0.2 + (&k - k.transpose());
        }
        if kind == 2 {
            let d = DVector::from_fn(n, |_, _| 10f64.powf(rng.uniform(-3.0, 3.0)));
            m = DMatrix::from_diagonal(&d) * m * DMatrix::from_diagonal(&d);
            q.component_mul_assign(&d);
        }
        (m, q)
    }

    #[test]
    fn random_p_matrices_solve_and_match_enumeration() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for trial in 0..200 {
            let n = if trial < 150 { 1 + trial % 10 } else { 11 + trial % 20 };
            let (m, q) = random_p_lcp(&mut rng, n, trial % 3);
            let s = lemke(&m, &q, 50 * n + 100).expect("a P-matrix LCP has a solution");
            assert_solves(&m, &q, &s, 1e-10);
            // Another covering vector takes another path to the same (unique) solution.
            let d = DVector::from_fn(n, |_, _| rng.uniform(0.1, 10.0));
            let s_d = lemke_with_covering(&m, &q, &d, 50 * n + 100).expect("solved");
            assert_solves(&m, &q, &s_d, 1e-10);
            for (&a, &b) in s.z.iter().zip(s_d.z.iter()) {
                assert!((a - b).abs() <= 1e-8 * a.abs().max(b.abs()), "trial {trial}: {a} vs {b}");
            }
            if n <= 10 {
                // P-matrix: exactly one complementary basis is feasible.
                let all = enumerate(&m, &q, 1e-10);
                assert_eq!(all.len(), 1, "trial {trial}");
                for (&a, &b) in all[0].iter().zip(s.z.iter()) {
                    assert!((a - b).abs() <= 1e-8 * a.abs(), "trial {trial}: {a} vs {b}");
                }
            }
        }
    }

    /// Not a check (Lemke's worst case is exponential): prints the pivot counts, run with
    /// `cargo test --release pivot_counts -- --nocapture`.
    #[test]
    fn pivot_counts_on_random_p_matrices() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for n in [10, 30] {
            for kind in 0..3 {
                let counts: Vec<usize> = (0..100)
                    .map(|_| {
                        let (m, q) = random_p_lcp(&mut rng, n, kind);
                        let s = lemke(&m, &q, 50 * n + 100).unwrap();
                        assert_solves(&m, &q, &s, 1e-10);
                        s.pivots
                    })
                    .collect();
                let mean = counts.iter().sum::<usize>() as f64 / counts.len() as f64;
                let max = counts.iter().max().unwrap();
                eprintln!("n = {n}, kind {kind}: pivots mean {mean:.1}, max {max}");
            }
        }
    }

    /// Lemke's method with ties broken by the smallest row index instead of lexicographically
    /// (and z₀'s row first); true if a basis repeats, i.e. it cycles.
    fn cycles_without_lexicographic_rule(m: &DMatrix<f64>, q: &DVector<f64>) -> bool {
        let n = q.len();
        let mut t = DMatrix::from_fn(n, 2 * n + 2, |i, j| match j {
            j if j < n => f64::from(u8::from(i == j)),
            j if j < 2 * n => -m[(i, j - n)],
            j if j == 2 * n => -1.0,
            _ => q[i],
        });
        let mut basic: Vec<usize> = (0..n).collect();
        let mut seen = std::collections::HashSet::new();
        let (mut r, mut c) = ((0..n).fold(0, |b, i| if q[i] < q[b] { i } else { b }), 2 * n);
        for _ in 0..100 {
            let row = t.row(r) / t[(r, c)];
            for i in 0..n {
                let f = t[(i, c)];
                t.set_row(i, &(if i == r { row.clone() } else { t.row(i) - row.clone() * f }));
            }
            let leaving = std::mem::replace(&mut basic[r], c);
            let mut key = basic.clone();
            key.sort_unstable();
            if leaving == 2 * n || !seen.insert((key, leaving)) {
                return leaving != 2 * n;
            }
            c = if leaving < n { leaving + n } else { leaving - n };
            let ratio = |i: usize| t[(i, 2 * n + 1)] / t[(i, c)];
            let rows: Vec<usize> = (0..n).filter(|&i| t[(i, c)] > 1e-9).collect();
            let least = rows.iter().map(|&i| ratio(i)).fold(f64::INFINITY, f64::min);
            let ties: Vec<usize> = rows.into_iter().filter(|&i| ratio(i) <= least + 1e-9).collect();
            let Some(&first) = ties.first() else {
                return false;
            };
            r = ties.iter().copied().find(|&i| basic[i] == 2 * n).unwrap_or(first);
        }
        false
    }

    #[test]
    fn degenerate_problem_that_cycles_under_a_naive_rule_terminates() {
        // Rows 1 and 2 of (M, q) repeat, q₃ = 0 and the other q_i tie: every ratio test
        // after the first pivot is degenerate. Smallest-row-index tie breaking revisits a
        // basis after 5 pivots; the lexicographic rule cannot.
        #[rustfmt::skip]
        let m = DMatrix::from_row_slice(5, 5, &[
            -1.0, 1.0, -1.0, 1.0, 2.0,
            -1.0, 1.0, -1.0, 1.0, 2.0,
            -1.0, 1.0, -1.0, 2.0, -2.0,
            0.0, 1.0, -1.0, 0.0, 2.0,
            -2.0, 0.0, 1.0, 0.0, 1.0,
        ]);
        let q = DVector::from_vec(vec![-1.0, -1.0, 0.0, -1.0, -1.0]);
        assert!(cycles_without_lexicographic_rule(&m, &q));
        let s = lemke(&m, &q, 1000).expect("terminates on a solution");
        assert_solves(&m, &q, &s, 1e-14);
        // Hand check: z = (0, 0, 1/3, 5/6, 2/3) gives w = (5/6, 5/6, 0, 0, 0).
        let hand = DVector::from_vec(vec![0.0, 0.0, 1.0 / 3.0, 5.0 / 6.0, 2.0 / 3.0]);
        assert!((&s.z - hand).amax() < 1e-15, "z = {}", s.z);
    }

    #[test]
    fn infeasible_copositive_plus_problems_end_on_a_ray() {
        // M = [[0, −1], [1, 0]] is skew, so zᵀM z = 0 and (M + Mᵀ) z = 0: copositive-plus.
        // With q = (−1, −1), w₁ = −z₂ − 1 ≤ −1 < 0 for every z ≥ 0: infeasible.
        let skew = DMatrix::from_row_slice(2, 2, &[0.0, -1.0, 1.0, 0.0]);
        // M = [[1, −1], [−1, 1]] is positive semidefinite (copositive-plus); with
        // q = (−1, −1), w₁ + w₂ = −2 < 0 for every z: infeasible.
        let psd = DMatrix::from_row_slice(2, 2, &[1.0, -1.0, -1.0, 1.0]);
        let q = DVector::from_vec(vec![-1.0, -1.0]);
        for m in [skew, psd] {
            let r = lemke(&m, &q, 100);
            assert!(matches!(r, Err(LcpFailure::Ray { .. })), "{r:?}");
        }
    }

    /// The 2D Coulomb-friction LCP of k contacts with flexibility C (SPD, rows ordered
    /// n₁, t₁, n₂, t₂, …): per contact the unknowns (λn, β⁺, β⁻, γ), λt = β⁺ − β⁻, with
    /// complements g = qn + (C λ)_n ⊥ λn, γ + v ⊥ β⁺, γ − v ⊥ β⁻, μ λn − β⁺ − β⁻ ⊥ γ, where
    /// v = qt + (C λ)_t is the slip rate.
    fn friction_lcp(
        c: &DMatrix<f64>,
        qn: &[f64],
        qt: &[f64],
        mu: f64,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let k = qn.len();
        let mut m = DMatrix::zeros(4 * k, 4 * k);
        let mut q = DVector::zeros(4 * k);
        for a in 0..k {
            for b in 0..k {
                // Columns λn_b, β⁺_b, β⁻_b of the rows g_a and v_a.
                for (row, sign_v, ca) in
                    [(0, 1.0, 2 * a), (1, 1.0, 2 * a + 1), (2, -1.0, 2 * a + 1)]
                {
                    m[(4 * a + row, 4 * b)] = sign_v * c[(ca, 2 * b)];
                    m[(4 * a + row, 4 * b + 1)] = sign_v * c[(ca, 2 * b + 1)];
                    m[(4 * a + row, 4 * b + 2)] = -sign_v * c[(ca, 2 * b + 1)];
                }
            }
            m[(4 * a + 1, 4 * a + 3)] = 1.0;
            m[(4 * a + 2, 4 * a + 3)] = 1.0;
            m[(4 * a + 3, 4 * a)] = mu;
            m[(4 * a + 3, 4 * a + 1)] = -1.0;
            m[(4 * a + 3, 4 * a + 2)] = -1.0;
            q[4 * a] = qn[a];
            (q[4 * a + 1], q[4 * a + 2]) = (qt[a], -qt[a]);
        }
        (m, q)
    }

    #[test]
    fn coulomb_friction_contacts() {
        #[rustfmt::skip]
        let c = DMatrix::from_row_slice(6, 6, &[
            2.0, 0.3, 0.5, 0.1, 0.2, 0.0,
            0.3, 1.0, 0.1, 0.4, 0.0, 0.1,
            0.5, 0.1, 2.0, 0.3, 0.5, 0.1,
            0.1, 0.4, 0.3, 1.0, 0.1, 0.4,
            0.2, 0.0, 0.5, 0.1, 2.0, 0.3,
            0.0, 0.1, 0.1, 0.4, 0.3, 1.0,
        ]);
        assert!(c.clone().cholesky().is_some(), "the flexibility is SPD");
        // Contacts 1, 2 pushed in, 3 pulled off; all driven sideways.
        let (qn, qt) = ([-1.0, -0.5, 0.3], [0.8, -0.3, 0.2]);
        for mu in [0.3, 2.0] {
            let (m, q) = friction_lcp(&c, &qn, &qt, mu);
            let s = lemke(&m, &q, 1000).expect("solved");
            assert_solves(&m, &q, &s, 1e-12);
            // Coulomb's law read back: |λt| ≤ μ λn, and slip v ≠ 0 only at λt = −μ λn sign v.
            let w = &m * &s.z + &q;
            for a in 0..qn.len() {
                let (lambda_n, lambda_t) = (s.z[4 * a], s.z[4 * a + 1] - s.z[4 * a + 2]);
                let slip = (w[4 * a + 1] - w[4 * a + 2]) / 2.0;
                assert!(lambda_t.abs() <= mu * lambda_n * (1.0 + 1e-12) + 1e-15, "μ = {mu}");
                if slip.abs() > 1e-12 {
                    assert!((lambda_t + mu * lambda_n * slip.signum()).abs() < 1e-12, "μ = {mu}");
                }
            }
        }
    }

    #[test]
    fn bad_input() {
        let q = DVector::from_vec(vec![-1.0, 1.0]);
        let mut m = DMatrix::identity(2, 2);
        m[(0, 1)] = f64::NAN;
        assert_eq!(lemke(&m, &q, 10).err(), Some(LcpFailure::BadInput));
        let inf_q = DVector::from_vec(vec![-1.0, f64::INFINITY]);
        assert_eq!(lemke(&DMatrix::identity(2, 2), &inf_q, 10).err(), Some(LcpFailure::BadInput));
        assert_eq!(lemke(&DMatrix::identity(3, 3), &q, 10).err(), Some(LcpFailure::BadInput));
        let zero_d = DVector::from_vec(vec![1.0, 0.0]);
        let r = lemke_with_covering(&DMatrix::identity(2, 2), &q, &zero_d, 10);
        assert_eq!(r.err(), Some(LcpFailure::BadInput));
    }

    #[test]
    fn edge_cases_are_refused_or_solved() {
        let empty = lemke(&DMatrix::zeros(0, 0), &DVector::zeros(0), 10).unwrap();
        assert_eq!((empty.z.len(), empty.pivots), (0, 0));
        let q = DVector::from_vec(vec![-1.0, 2.0]);
        let id = DMatrix::identity(2, 2);
        assert_eq!(lemke(&id, &q, 0).err(), Some(LcpFailure::PivotLimit { pivots: 0 }));
        // M = 0 with some q_i < 0: w = q is infeasible, the first column is zero: a ray.
        assert!(matches!(lemke(&DMatrix::zeros(2, 2), &q, 10), Err(LcpFailure::Ray { .. })));
    }

    #[test]
    fn extreme_magnitudes_give_the_scaled_solution() {
        // LCP(D M₀ D, D q₀) is solved by z = D⁻¹ z₀ (w = D w₀): with D a power of two the
        // scaled problem is exact, so its solution must be the textbook one, z₀ = (7/5, 1/5),
        // scaled, to round-off, however far D is from 1 (here 2^±330 ≈ 1e±99: z near 1e±100).
        let (m0, q0) = (
            DMatrix::from_row_slice(2, 2, &[2.0, 1.0, -1.0, 2.0]),
            DVector::from_vec(vec![-3.0, 1.0]),
        );
        for (a, b) in [(330, -330), (-330, 330), (300, 300), (-300, -300)] {
            let d = DVector::from_vec(vec![2f64.powi(a), 2f64.powi(b)]);
            let m = DMatrix::from_diagonal(&d) * &m0 * DMatrix::from_diagonal(&d);
            let q = q0.component_mul(&d);
            let s = lemke(&m, &q, 100).unwrap_or_else(|e| panic!("D = {d}: {e:?}"));

            assert_solves(&m, &q, &s, 1e-14);
            let z0 = s.z.component_mul(&d);
            assert!(
                (z0[0] - 1.4).abs() < 1e-14 && (z0[1] - 0.2).abs() < 1e-14,
                "D = {d}: z = {}",
                s.z
            );
        }
        // A uniform scale of M alone (a compliance in other units) scales z inversely.
        for c in [1e-80, 1e80] {
            let s = lemke(&(&m0 * c), &q0, 100).unwrap_or_else(|e| panic!("c = {c}: {e:?}"));
            assert!(
                (s.z[0] * c - 1.4).abs() < 1e-14 && (s.z[1] * c - 0.2).abs() < 1e-14,
                "c = {c}: z = {}",
                s.z
            );
        }
        // Beyond f64: M = diag(1e300, 1e-300), q = (−1e-300, −1e300) is solved only by
        // z = (1e-600, 1e600), which f64 cannot hold. No non-finite z may come back.
        let m = DMatrix::from_row_slice(2, 2, &[1e300, 0.0, 0.0, 1e-300]);
        let q = DVector::from_vec(vec![-1e-300, -1e300]);
        if let Ok(s) = lemke(&m, &q, 10) {
            assert!(
                s.z.iter().chain(s.w.iter()).all(|v| v.is_finite()),
                "z = {}, w = {}",
                s.z,
                s.w
            );
        }
    }
}
