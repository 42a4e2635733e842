//! The rate problem as a mixed linear complementarity problem (`rate_problem`): unknowns
//! (forces, slip rates, rigid amplitudes), each free (with an equation) or complementary to its
//! row, and their solution by Lemke's method (`lcp`) after the free unknowns are eliminated or,
//! for a saddle point's, split.

use super::trial;
use crate::lcp::{lemke_with_covering, LcpFailure, LcpSolution};
use nalgebra::{DMatrix, DVector};

/// Lemke's pivot bound: this × (LCP size) + 100.
const PIVOTS_PER_VARIABLE: usize = 50;

/// An affine form in the unknowns y: coef · y + constant.
#[derive(Clone)]
pub(super) struct Affine {
    pub coef: Vec<(usize, f64)>,
    pub constant: f64,
}

impl Affine {
    pub(super) fn constant(c: f64) -> Self {
        Affine { coef: vec![], constant: c }
    }
    pub(super) fn var(i: usize) -> Self {
        Affine { coef: vec![(i, 1.0)], constant: 0.0 }
    }
    pub(super) fn scaled_add(mut self, s: f64, other: &Affine) -> Self {
        self.coef.extend(other.coef.iter().map(|&(i, c)| (i, s * c)));
        self.constant += s * other.constant;
        self
    }
    pub(super) fn eval(&self, y: &[f64]) -> f64 {
        self.constant + self.coef.iter().map(|&(i, c)| c * y[i]).sum::<f64>()
    }
}

/// The unknowns and their complementary rows, built up pair by pair.
#[derive(Default)]
pub(super) struct Unknowns {
    /// Per unknown: may it be negative?
    pub free: Vec<bool>,
    /// Per unknown: its complementary row (an equation R = 0 for a free unknown).
    pub rows: Vec<Option<Affine>>,
    /// Per unknown: a length (slip rate, rigid amplitude; its row a force), else a force (its
    /// row a length).
    pub length: Vec<bool>,
}

impl Unknowns {
    pub(super) fn unknown(&mut self, free: bool) -> usize {
        self.free.push(free);
        self.rows.push(None);
        self.length.push(false);
        self.free.len() - 1
    }

    pub(super) fn length_unknown(&mut self, free: bool) -> usize {
        let i = self.unknown(free);
        self.length[i] = true;
        i
    }
}

/// The mixed problem as a standard LCP, solved by Lemke's method. A free unknown without a
/// diagonal entry (a rigid amplitude: a saddle point) is split into x⁺ − x⁻ ≥ 0 with
/// 0 ≤ x⁺ ⊥ R ≥ 0 and 0 ≤ x⁻ ⊥ −R ≥ 0 (R = −e pairs α with its equilibrium equation with the
/// sign that keeps M positive semidefinite without friction); the other free unknowns are
/// eliminated with their equations (Schur complement M_cc − M_cf M_ff⁻¹ M_fc).
pub(super) fn solve(prob: &Unknowns) -> Option<Vec<f64>> {
    let (mut m, mut q, split, col) = split_saddles(prob)?;
    let d = unit_free(prob, &split, &col, &mut m, &mut q);
    let free: Vec<usize> =
        (0..prob.free.len()).filter(|&i| prob.free[i] && !split[i]).map(|i| col[i]).collect();
    let bounded: Vec<usize> = (0..q.len()).filter(|r| !free.contains(r)).collect();
    let pick = |rows: &[usize], cols: &[usize]| {
        DMatrix::from_fn(rows.len(), cols.len(), |i, j| m[(rows[i], cols[j])])
    };
    let m_cf = pick(&bounded, &free);
    // [M_ff⁻¹ M_fc | M_ff⁻¹ q_f] in one solve
    let rhs = DMatrix::from_fn(free.len(), bounded.len() + 1, |i, j| {
        if j < bounded.len() {
            m[(free[i], bounded[j])]
        } else {
            q[free[i]]
        }
    });
    let x = trial::lu_solve(&pick(&free, &free), rhs, 0.0)?; // singular: an exact zero pivot
    let (x_fc, x_q) =
        (x.columns(0, bounded.len()).into_owned(), x.column(bounded.len()).into_owned());
    let m_c = pick(&bounded, &bounded) - &m_cf * &x_fc;
    let q_c = DVector::from_fn(bounded.len(), |i, _| q[bounded[i]]) - &m_cf * &x_q;
    let started = std::time::Instant::now();
    let lemke = lemke_restarted(&m_c, &q_c);
    crate::trace!(
        "rate problem: LCP of {} unknowns ({} free eliminated): {} in {:.2} s",
        q_c.len(),
        free.len(),
        lemke.as_ref().map_or("no solution".to_string(), |s| format!("{} pivots", s.pivots)),
        started.elapsed().as_secs_f64()
    );
    let z_c = lemke?.z;
    let x_f = -(&x_fc * &z_c + &x_q);
    let mut z = DVector::<f64>::zeros(q.len());
    bounded.iter().zip(z_c.iter()).for_each(|(&r, &v)| z[r] = v);
    free.iter().zip(x_f.iter()).for_each(|(&r, &v)| z[r] = v);
    z.component_mul_assign(&d);
    Some(
        (0..prob.free.len())
            .map(|i| if split[i] { z[col[i]] - z[col[i] + 1] } else { z[col[i]] })
            .collect(),
    )
}

/// The length unknowns' columns and rows × the flexibility's size s (the largest diagonal entry
/// of a force unknown, rounded to a power of two: exact): the rows of force unknowns are lengths, their coefficients compliances
/// or ratios; of length unknowns forces, coefficients ratios. Scaled, every entry is a
/// compliance and every constant a length, so Lemke's pivots do not depend on the unit system
/// (a congruence D M D: positive semidefiniteness kept). Returns D's diagonal: z = D z̃.
fn unit_free(
    prob: &Unknowns,
    split: &[bool],
    col: &[usize],
    m: &mut DMatrix<f64>,
    q: &mut DVector<f64>,
) -> DVector<f64> {
    let n = q.len();
    let s = (0..prob.free.len())
        .filter(|&i| !prob.length[i])
        .fold(0.0f64, |x, i| x.max(m[(col[i], col[i])].abs()))
        .log2()
        .round()
        .exp2();
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
    (0..=COVERING_RESTARTS)
        .find_map(|attempt| {
            let d = DVector::from_fn(
                n,
                |_, _| if attempt == 0 { 1.0 } else { covering_entry(&mut seed) },
            );
            match lemke_with_covering(m, q, &d, max_pivots) {
                Err(LcpFailure::Interrupted { .. }) => Some(None), // no restart: the run stops
                attempt => attempt.ok().map(Some),
            }
        })
        .flatten()
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

/// The free unknowns whose equations can eliminate them: among those with a diagonal entry,
/// a set on which M_ff is regular, picked by symmetric Gaussian elimination with diagonal
/// pivoting (each unknown by its own equation), a pivot below `DEPENDENT` × the largest
/// diagonal entry ending it. The others are split (saddles): a rigid amplitude (no diagonal
/// entry), and a force whose flexibility depends on the others' (the tangents of a floating
/// body's node that K# pins, turned off the axes: M_ff singular to round-off, its Schur
/// complement 10^33, Lemke's first pivot a ray).
fn independent_free(prob: &Unknowns) -> Option<Vec<bool>> {
    let diagonal = |i: usize| {
        prob.rows[i]
            .as_ref()
            .map_or(0.0, |r| r.coef.iter().filter(|&&(j, _)| j == i).map(|&(_, v)| v).sum())
    };
    let free: Vec<usize> =
        (0..prob.free.len()).filter(|&i| prob.free[i] && diagonal(i) != 0.0).collect();
    let mut slot = vec![usize::MAX; prob.free.len()];
    free.iter().enumerate().for_each(|(k, &i)| slot[i] = k);
    let n = free.len();
    let mut a = DMatrix::<f64>::zeros(n, n);
    for (r, &i) in free.iter().enumerate() {
        for &(j, v) in &prob.rows[i].as_ref()?.coef {
            if slot[j] != usize::MAX {
                a[(r, slot[j])] += v;
            }
        }
    }
    let largest = (0..n).map(|k| a[(k, k)].abs()).fold(0.0, f64::max);
    let mut chosen = vec![false; prob.free.len()];
    let mut order: Vec<usize> = (0..n).collect();
    for k in 0..n {
        let j = (k..n).max_by(|&x, &y| a[(x, x)].abs().total_cmp(&a[(y, y)].abs())).expect("k < n");
        let pivot = a[(j, j)];
        if !(pivot.abs() > DEPENDENT * largest) {
            break;
        }
        (a.swap_rows(k, j), a.swap_columns(k, j), order.swap(k, j));
        chosen[free[order[k]]] = true;
        let m = n - k - 1;
        let (column, row) = (
            a.view((k + 1, k), (m, 1)).column(0).clone_owned(),
            a.view((k, k + 1), (1, m)).row(0).transpose(),
        );
        a.view_mut((k + 1, k + 1), (m, m)).ger(-1.0 / pivot, &column, &row, 1.0);
    }
    Some(chosen)
}

/// A pivot of M_ff below this × its largest diagonal entry is round-off: that unknown depends.
const DEPENDENT: f64 = 1e-9;

/// M y + q over the unknowns with every saddle unknown split in two; which were split, and the
/// column of each unknown.
#[allow(clippy::type_complexity)]
fn split_saddles(prob: &Unknowns) -> Option<(DMatrix<f64>, DVector<f64>, Vec<bool>, Vec<usize>)> {
    let eliminable = independent_free(prob)?;
    let split: Vec<bool> = (0..prob.free.len()).map(|i| prob.free[i] && !eliminable[i]).collect();
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
    use super::*;

    /// Three free forces whose flexibilities are dependent to round-off (the second a multiple
    /// of the first, as a pinned node's two tangents turned off the axes) and a rigid
    /// amplitude: the first and the third are eliminated, the second and the amplitude split.
    #[test]
    fn dependent_free_unknowns_are_split_not_eliminated() {
        let mut prob = Unknowns::default();
        let ids: Vec<usize> = (0..3).map(|_| prob.unknown(true)).collect();
        let alpha = prob.length_unknown(true);
        let (k, eps) = (0.06, 1e-19);
        let flex = [[1.0, k, 0.3], [k, k * k + eps, 0.3 * k], [0.3, 0.3 * k, 2.0]];
        for (i, &u) in ids.iter().enumerate() {
            let coef = ids
                .iter()
                .zip(flex[i])
                .map(|(&j, v)| (j, v))
                .chain(std::iter::once((alpha, 1.0)))
                .collect();
            prob.rows[u] = Some(Affine { coef, constant: 0.1 });
        }
        prob.rows[alpha] =
            Some(Affine { coef: ids.iter().map(|&j| (j, -1.0)).collect(), constant: 1.0 });
        let chosen = independent_free(&prob).expect("every row given");
        assert_eq!(chosen, vec![true, false, true, false]);
    }
}
