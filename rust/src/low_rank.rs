//! The stiffness between refactorizations: the factored K_f plus a few signed rank-one terms,
//!   K = K_f + W S Wᵀ,   S = diag(±1),
//! solved by the Sherman–Morrison–Woodbury identity
//!   K⁻¹ y = K_f⁻¹ y − Z C⁻¹ Zᵀ y,   Z = K_f⁻¹ W,   C = S⁻¹ + Wᵀ Z.
//!
//! A CST that yields changes its stiffness by a term of rank one (eq. 11: D_ep − D =
//! −(Da)(Da)ᵀ / (H' + aᵀDa)); one that unloads, or whose flow direction turned, by one or two.
//! Each new column costs one solve with K_f (many are solved together), every later solve
//! O(n k) more than with K_f alone; when that has cost as much as a factorization would have,
//! the caller refactorizes (`Cost`).
//!
//! The columns live on the equations of K_f (`DofMap`); Z is kept whole (n × k), so that a
//! trial's split solve (forward sweep, contact block, backward sweep) stays one solve.

use crate::factor::{Factor, FactorWork};
use nalgebra::DMatrix;

/// One signed rank-one term s w wᵀ of an element.
#[derive(Debug, Clone)]
pub struct Column {
    /// Sparse w over the equations of K_f.
    pub entries: Vec<(usize, f64)>,
    pub sign: f64,
    /// The element the term belongs to.
    pub owner: usize,
}

#[derive(Default)]
pub struct LowRank {
    columns: Vec<Column>,
    /// Z = K_f⁻¹ W, one vector of n per column.
    z: Vec<Vec<f64>>,
    /// C⁻¹, k × k.
    capacitance_inverse: DMatrix<f64>,
}

impl LowRank {
    pub fn rank(&self) -> usize {
        self.columns.len()
    }

    pub fn is_empty(&self) -> bool {
        self.columns.is_empty()
    }

    /// Forget every term (after a refactorization took them into K_f).
    pub fn clear(&mut self) {
        *self = LowRank::default();
    }

    /// Drop the terms of `owners` and add `added` (each solved with K_f, all at once).
    pub fn update(&mut self, solver: &mut Factor, n: usize, owners: &[usize], added: Vec<Column>) {
        if !owners.is_empty() {
            let drop: std::collections::HashSet<usize> = owners.iter().copied().collect();
            let mut j = 0;
            while j < self.columns.len() {
                if drop.contains(&self.columns[j].owner) {
                    self.columns.swap_remove(j);
                    self.z.swap_remove(j);
                } else {
                    j += 1;
                }
            }
        }
        let r = added.len();
        if r > 0 {
            let mut b = vec![0.0; n * r];
            for (c, col) in added.iter().enumerate() {
                col.entries.iter().for_each(|&(i, v)| b[c * n + i] += v);
            }
            solver.solve_in_place(&mut b, r);
            self.z.extend(b.chunks_exact(n).map(<[f64]>::to_vec));
            self.columns.extend(added);
        }
        self.rebuild_capacitance();
    }

    /// C = S⁻¹ + Wᵀ Z and its inverse.
    fn rebuild_capacitance(&mut self) {
        let k = self.columns.len();
        let mut c = DMatrix::<f64>::zeros(k, k);
        for (i, col) in self.columns.iter().enumerate() {
            for (j, zj) in self.z.iter().enumerate() {
                c[(i, j)] = col.entries.iter().map(|&(e, v)| v * zj[e]).sum::<f64>();
            }
            c[(i, i)] += 1.0 / col.sign;
        }
        // Symmetric in exact arithmetic (Wᵀ K_f⁻¹ W); average the round-off away.
        let c = (&c + c.transpose()) * 0.5;
        self.capacitance_inverse =
            c.try_inverse().unwrap_or_else(|| DMatrix::from_element(k, k, f64::NAN));
    }

    /// C⁻¹ Zᵀ y for y over the equations: the coefficients whose −Z combination corrects
    /// K_f⁻¹ y to K⁻¹ y.
    pub fn coefficients(&self, y: &[f64]) -> Vec<f64> {
        let zty: Vec<f64> =
            self.z.iter().map(|zj| zj.iter().zip(y).map(|(a, b)| a * b).sum()).collect();
        self.solve_capacitance(&zty)
    }

    /// C⁻¹ Zᵀ f for a force f on the last `t` equations only (given there, in order).
    pub fn trailing_coefficients(&self, f: &[f64]) -> Vec<f64> {
        let zty: Vec<f64> = self
            .z
            .iter()
            .map(|zj| zj[zj.len() - f.len()..].iter().zip(f).map(|(a, b)| a * b).sum())
            .collect();
        self.solve_capacitance(&zty)
    }

    fn solve_capacitance(&self, s: &[f64]) -> Vec<f64> {
        let k = self.rank();
        (0..k).map(|i| (0..k).map(|j| self.capacitance_inverse[(i, j)] * s[j]).sum()).collect()
    }

    /// x −= Z c over all equations.
    pub fn subtract(&self, x: &mut [f64], c: &[f64]) {
        for (zj, &cj) in self.z.iter().zip(c) {
            if cj != 0.0 {
                x.iter_mut().zip(zj).for_each(|(a, b)| *a -= cj * b);
            }
        }
    }

    /// x −= Z_t c over the last x.len() equations (the contact block).
    pub fn subtract_trailing(&self, x: &mut [f64], c: &[f64]) {
        let t = x.len();
        for (zj, &cj) in self.z.iter().zip(c) {
            if cj != 0.0 {
                x.iter_mut().zip(&zj[zj.len() - t..]).for_each(|(a, b)| *a -= cj * b);
            }
        }
    }

    /// The change of K⁻¹ on the last `t` equations: −Z_t C⁻¹ Z_tᵀ (t × t), added to the
    /// flexibility read from K_f.
    pub fn trailing_correction(&self, t: usize) -> faer::Mat<f64> {
        let k = self.rank();
        let zt = DMatrix::from_fn(t, k, |i, j| self.z[j][self.z[j].len() - t + i]);
        let m = &zt * &self.capacitance_inverse * zt.transpose();
        faer::Mat::from_fn(t, t, |i, j| -m[(i, j)])
    }
}

/// The cost of the solver's work, from the supernodal structure of the factor: what a
/// refactorization, a solve pair and a low-rank term cost, in floating-point operations of a
/// solve (memory-bound); a factorization's flops (dense blocks) count `FACTOR_FLOP_WEIGHT`.
#[derive(Debug, Clone, Copy, Default)]
pub struct Cost {
    pub factorization: f64,
    pub solve_pair: f64,
    pub equations: f64,
}

/// A factorization runs this much fewer seconds per flop than a solve pair (its dense
/// supernodal blocks run at matrix-matrix speed). Measured on this machine at 8.6k DOFs:
/// 61.6 Mflop in ~3.6 ms (17 Gflop/s) against 2.08 Mflop in ~0.5 ms (4 Gflop/s).
pub const FACTOR_FLOP_WEIGHT: f64 = 0.25;

impl Cost {
    /// The costs of a factor of this structure.
    pub fn of(work: FactorWork) -> Self {
        Cost {
            factorization: FACTOR_FLOP_WEIGHT * work.factorization_flops,
            solve_pair: work.solve_pair_flops,
            equations: work.equations,
        }
    }

    /// The extra work of `rank` terms for one solve (Zᵀy and Z c: 4 n k) .
    pub fn per_solve(&self, rank: usize) -> f64 {
        4.0 * self.equations * rank as f64
    }

    /// Adding `r` columns to `k`: r solves with K_f (blocked: `BLOCKED_SOLVE` of a solve
    /// pair each) and a new capacitance inverse (k³).
    pub fn update(&self, k: usize, r: usize) -> f64 {
        let k = (k + r) as f64;
        BLOCKED_SOLVE * self.solve_pair * r as f64 + 2.0 * self.equations * k * r as f64 + k * k * k
    }
}

/// A column of a blocked multi-right-hand-side solve costs this fraction of a single solve
/// pair (the substitutions become matrix products).
const BLOCKED_SOLVE: f64 = 0.5;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::{Cst, Element};
    use crate::linalg::{DofMap, StiffnessPattern};
    use crate::material::{Material, Plane};
    use crate::options::Factorization;
    use crate::section::Section;

    /// A supported 6 × 4-cell block: K_f, and K = K_f with some elements softened (plastic
    /// tangents) and one stiffened back, applied through the low-rank terms, must solve like a
    /// fresh factorization of K (to round-off), contact block included.
    #[test]
    fn woodbury_solves_like_a_refactorization() {
        let (nx, ny) = (7, 5);
        let mesh = crate::mesh::test_grid(nx, ny, 0.5, 0.4);
        let els: Vec<Cst> = (0..mesh.elements.len()).map(|e| Cst::planar(&mesh, e, 1.0)).collect();
        let n_dofs = 2 * mesh.nodes.len();
        let mut fixed = vec![false; n_dofs];
        (0..nx).for_each(|i| (fixed[2 * i], fixed[2 * i + 1]) = (true, true));
        let trailing: Vec<usize> =
            (0..nx).flat_map(|i| [2 * (nx * (ny - 1) + i), 2 * (nx * (ny - 1) + i) + 1]).collect();
        let map = DofMap::ordered(&els, n_dofs, &fixed, &[], &trailing).unwrap();
        let pattern = StiffnessPattern::new(&els, &map).unwrap();
        let mut m = Material::elastic(1000.0, 0.3);
        m.yield_stress = 1.0;
        m.hardening = 50.0;
        let stress = crate::material::from_planar([0.8, -0.4, 0.1, 0.5]);
        let section = Section::new(m, Plane::Strain.stress_state());
        let elastic = section.element_matrix(&section.tangent(&stress, false));
        let plastic = section.element_matrix(&section.tangent(&stress, true));
        let softened = [3, 4, 17, 30];
        let mut d_f = vec![elastic; els.len()];
        d_f[40] = plastic; // factored plastic, stiffened back below
        let mut d = d_f.clone();
        softened.iter().for_each(|&e| d[e] = plastic);
        d[40] = elastic;
        let mut solver = Factor::new(
            Factorization::Faer,
            &pattern.assemble(&els, &d_f, &map).unwrap(),
            &map,
            trailing.len(),
        )
        .unwrap();
        let n = map.n_equations;
        let column = |e: usize, delta: nalgebra::Matrix6<f64>| {
            let delta = Cst::rows_of(&delta);
            // delta = s c cᵀ (rank one): c from its largest diagonal entry.
            let j = (0..4)
                .max_by(|&a, &b| delta[(a, a)].abs().total_cmp(&delta[(b, b)].abs()))
                .unwrap();
            let c = delta.column(j) / delta[(j, j)].abs().sqrt();
            let w = els[e].b().transpose() * c * els[e].measure().sqrt();
            let entries = els[e]
                .dofs()
                .iter()
                .zip(w.iter())
                .filter_map(|(&g, &v)| map.equation(g).map(|q| (q, v)))
                .collect();
            Column { entries, sign: delta[(j, j)].signum(), owner: e }
        };
        let mut lr = LowRank::default();
        let added: Vec<Column> = softened
            .iter()
            .map(|&e| column(e, plastic - elastic))
            .chain([column(40, elastic - plastic)])
            .collect();
        lr.update(&mut solver, n, &[], added);
        let y: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let mut x = y.clone();
        solver.solve_in_place(&mut x, 1);
        let c = lr.coefficients(&y);
        lr.subtract(&mut x, &c);
        let mut fresh = Factor::new(
            Factorization::Faer,
            &pattern.assemble(&els, &d, &map).unwrap(),
            &map,
            trailing.len(),
        )
        .unwrap();
        let mut exact = y.clone();
        fresh.solve_in_place(&mut exact, 1);
        let big = exact.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for i in 0..n {
            assert!((x[i] - exact[i]).abs() < 1e-10 * big, "x[{i}] = {} vs {}", x[i], exact[i]);
        }
        // The contact block: K⁻¹ on the trailing equations.
        let t = trailing.len();
        let mut g = solver.trailing_inverse();
        let corr = lr.trailing_correction(t);
        let g_fresh = fresh.trailing_inverse();
        for i in 0..t {
            for j in 0..t {
                g[(i, j)] += corr[(i, j)];
                assert!(
                    (g[(i, j)] - g_fresh[(i, j)]).abs()
                        < 1e-10 * g_fresh[(i, i)].abs().max(g_fresh[(j, j)].abs())
                );
            }
        }
        // Dropping the terms of an element and adding them again changes nothing.
        let again = column(17, plastic - elastic);
        lr.update(&mut solver, n, &[17], vec![again]);
        let mut x2 = y.clone();
        solver.solve_in_place(&mut x2, 1);
        let c = lr.coefficients(&y);
        lr.subtract(&mut x2, &c);
        for i in 0..n {
            assert!((x2[i] - exact[i]).abs() < 1e-10 * big);
        }
    }
}
