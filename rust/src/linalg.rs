//! Sparse linear algebra: the reduced stiffness and its Cholesky factor.
//!
//! Supports (u = 0) are eliminated. A body that is held only by contact (the paper's cylinder
//! on the flat, a block on a foundation) has rigid-body modes left in K; for those a few
//! "pinned" DOFs are removed as well, which turns K into an SPD matrix K_reg. Solving with
//! K_reg and setting the pinned DOFs to zero applies a generalized inverse K# (K K# K = K);
//! the rigid-body amplitudes are then found together with the contact multipliers
//! (see `driver`), so the big factor stays SPD and is never refactorized for a contact event.

use crate::bail;
use crate::element::Cst;
use crate::error::Result;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{MatMut, Side};
use faer::linalg::solvers::Solve;
use nalgebra::Matrix3;

/// Where a global DOF goes in the reduced system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DofRole {
    /// Prescribed zero displacement (support, symmetry).
    Fixed,
    /// Removed to make K_reg SPD; its value comes from the rigid-body amplitudes.
    Pinned,
    /// Equation number in K_reg.
    Equation(usize),
}

#[derive(Debug, Clone)]
pub struct DofMap {
    pub role: Vec<DofRole>,
    pub n_equations: usize,
}

impl DofMap {
    pub fn new(n_dofs: usize, fixed: &[bool], pinned: &[usize]) -> Self {
        let mut role = vec![DofRole::Fixed; n_dofs];
        let mut is_pinned = vec![false; n_dofs];
        for &d in pinned {
            is_pinned[d] = true;
        }
        let mut n = 0;
        for d in 0..n_dofs {
            if fixed[d] {
                continue;
            }
            role[d] = if is_pinned[d] {
                DofRole::Pinned
            } else {
                n += 1;
                DofRole::Equation(n - 1)
            };
        }
        DofMap { role, n_equations: n }
    }

    pub fn equation(&self, dof: usize) -> Option<usize> {
        match self.role[dof] {
            DofRole::Equation(i) => Some(i),
            _ => None,
        }
    }
}

/// The sparsity pattern of K_reg (lower triangle), analysed once: refilling it with new
/// element tangents skips the sort of the triplets (plastic runs reassemble at every event).
pub struct StiffnessPattern {
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
}

/// Visit every lower-triangle entry (row, col, element, i, j) of the assembly, in a fixed order.
fn for_each_entry(elements: &[Cst], map: &DofMap, mut f: impl FnMut(usize, usize, usize, usize, usize)) {
    for (e, el) in elements.iter().enumerate() {
        let eqs = el.dofs().map(|g| map.equation(g));
        for i in 0..6 {
            let Some(ri) = eqs[i] else { continue };
            for j in 0..6 {
                let Some(cj) = eqs[j] else { continue };
                if ri >= cj {
                    f(ri, cj, e, i, j);
                }
            }
        }
    }
}

impl StiffnessPattern {
    pub fn new(elements: &[Cst], map: &DofMap) -> Result<Self> {
        let mut idx = Vec::with_capacity(elements.len() * 21);
        for_each_entry(elements, map, |r, c, _, _, _| idx.push(Pair::new(r, c)));
        let n = map.n_equations;
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &idx)
            .map_err(|e| crate::error::Error(format!("could not analyse the stiffness pattern: {e:?}")))?;
        Ok(StiffnessPattern { symbolic, argsort })
    }

    /// Lower triangle of K_reg = Σ_e t A Bᵀ D_e B over the equation DOFs.
    pub fn assemble(&self, elements: &[Cst], tangents: &[Matrix3<f64>], thickness: f64, map: &DofMap) -> Result<SparseColMat<usize, f64>> {
        let ke: Vec<_> = elements.iter().zip(tangents).map(|(el, d)| el.stiffness(d, thickness)).collect();
        let mut values = Vec::with_capacity(elements.len() * 21);
        for_each_entry(elements, map, |_, _, e, i, j| values.push(ke[e][(i, j)]));
        SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, &values)
            .map_err(|e| crate::error::Error(format!("could not assemble the stiffness matrix: {e:?}")))
    }
}

/// Cholesky factor of K_reg with the symbolic analysis kept for refactorization.
pub struct SpdSolver {
    symbolic: Option<SymbolicLlt<usize>>,
    factor: Option<Llt<usize, f64>>,
    pub n_factorizations: usize,
    pub n_solves: usize,
}

impl SpdSolver {
    pub fn new() -> Self {
        SpdSolver { symbolic: None, factor: None, n_factorizations: 0, n_solves: 0 }
    }

    /// Factor `lower` (lower triangle of an SPD matrix). A non-positive pivot means a
    /// mechanism: the message names the global DOF through `dof_of_equation`.
    pub fn factor(&mut self, lower: &SparseColMat<usize, f64>, dof_of_equation: &[usize]) -> Result<()> {
        if self.symbolic.is_none() {
            let sym = SymbolicLlt::try_new(lower.symbolic(), Side::Lower)
                .map_err(|e| crate::error::Error(format!("symbolic factorization failed: {e:?}")))?;
            self.symbolic = Some(sym);
        }
        let sym = self.symbolic.clone().unwrap();
        match Llt::try_new_with_symbolic(sym, lower.as_ref(), Side::Lower) {
            Ok(f) => {
                self.factor = Some(f);
                self.n_factorizations += 1;
                Ok(())
            }
            Err(faer::sparse::linalg::LltError::Numeric(
                faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index },
            )) => {
                // The pivot index is in the fill-reducing ordering; name a DOF of the
                // original numbering only when it is in range, else stay generic.
                let hint = dof_of_equation
                    .get(index)
                    .map(|&d| format!(" near node {} ({})", d / 2, if d % 2 == 0 { "x" } else { "y" }))
                    .unwrap_or_default();
                bail!("the stiffness matrix is singular{hint}: the model has a mechanism (a part held by nothing, or elements joined at a single node); add supports or check the mesh connectivity")
            }
            Err(e) => bail!("the Cholesky factorization failed: {e:?}"),
        }
    }

    /// Solve K_reg X = B in place for `columns` right-hand sides stored column after column
    /// (one blocked forward/backward substitution for all of them).
    pub fn solve_in_place(&mut self, b: &mut [f64], columns: usize) {
        let n = b.len() / columns.max(1);
        let f = self.factor.as_ref().expect("factor() before solve");
        f.solve_in_place(MatMut::from_column_major_slice_mut(b, n, columns));
        self.n_solves += columns;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, Plane};
    use crate::mesh::Mesh;

    #[test]
    fn global_stiffness_is_symmetric_and_annihilates_rigid_modes() {
        // Unsupported 3x2-cell mesh: assembled K (dense, both triangles) is symmetric, its lower
        // triangle is what the sparse assembly stores, and K r = 0 for the three rigid modes.
        let mut nodes = vec![];
        for j in 0..3 {
            for i in 0..4 {
                nodes.push([i as f64 * 0.7, j as f64 * 0.4 + 0.1 * i as f64]);
            }
        }
        let mut triangles = vec![];
        for j in 0..2 {
            for i in 0..3 {
                let a = 4 * j + i;
                triangles.push([a, a + 1, a + 5]);
                triangles.push([a, a + 5, a + 4]);
            }
        }
        let mesh = Mesh { nodes, triangles };
        let els: Vec<Cst> = (0..mesh.triangles.len()).map(|e| Cst::new(&mesh, e)).collect();
        let d = Material::elastic(1000.0, 0.3).elastic_tangent(Plane::Strain);
        let n = 2 * mesh.nodes.len();
        let mut k = nalgebra::DMatrix::<f64>::zeros(n, n);
        for el in &els {
            let ke = el.stiffness(&d, 2.0);
            for (i, gi) in el.dofs().iter().enumerate() {
                for (j, gj) in el.dofs().iter().enumerate() {
                    k[(*gi, *gj)] += ke[(i, j)];
                }
            }
        }
        assert!((&k - k.transpose()).norm() < 1e-12 * k.norm());
        let map = DofMap::new(n, &vec![false; n], &[]);
        let lower = StiffnessPattern::new(&els, &map).unwrap().assemble(&els, &vec![d; els.len()], 2.0, &map).unwrap();
        let dense_lower = lower.to_dense();
        for i in 0..n {
            for j in 0..n {
                let expect = if i >= j { k[(i, j)] } else { 0.0 };
                assert!((dense_lower[(i, j)] - expect).abs() < 1e-12 * k.norm());
            }
        }
        for mode in 0..3 {
            let r = nalgebra::DVector::from_fn(n, |dof, _| {
                let p = mesh.nodes[dof / 2];
                match (mode, dof % 2) {
                    (0, 0) | (1, 1) => 1.0,
                    (2, 0) => -p[1],
                    (2, 1) => p[0],
                    _ => 0.0,
                }
            });
            assert!((&k * r).norm() < 1e-10 * k.norm());
        }
    }

    #[test]
    fn assembled_stiffness_is_symmetric_positive_with_supports() {
        // 2x2 squares of a cantilever, fixed on x = 0: K_reg must factor, and K x = b is solved.
        let mut nodes = vec![];
        for j in 0..3 {
            for i in 0..3 {
                nodes.push([i as f64, j as f64]);
            }
        }
        let mut triangles = vec![];
        for j in 0..2 {
            for i in 0..2 {
                let a = 3 * j + i;
                triangles.push([a, a + 1, a + 4]);
                triangles.push([a, a + 4, a + 3]);
            }
        }
        let mesh = Mesh { nodes, triangles };
        let els: Vec<Cst> = (0..mesh.triangles.len()).map(|e| Cst::new(&mesh, e)).collect();
        let d = Material::elastic(1000.0, 0.3).elastic_tangent(Plane::Stress);
        let tangents = vec![d; els.len()];
        let mut fixed = vec![false; 18];
        for j in 0..3 {
            fixed[2 * (3 * j)] = true;
            fixed[2 * (3 * j) + 1] = true;
        }
        let map = DofMap::new(18, &fixed, &[]);
        let k = StiffnessPattern::new(&els, &map).unwrap().assemble(&els, &tangents, 1.0, &map).unwrap();
        let mut s = SpdSolver::new();
        let dofs: Vec<usize> = (0..18).filter(|&d| !fixed[d]).collect();
        s.factor(&k, &dofs).unwrap();
        let mut b = vec![1.0; map.n_equations];
        s.solve_in_place(&mut b, 1);
        assert!(b.iter().all(|v| v.is_finite()));
    }
}
