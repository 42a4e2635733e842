//! The factorization of K_reg behind one seam: what the event loop needs of it, and two
//! backends.
//!
//! The loop solves with K_reg (supports and pinned DOFs removed, SPD, `linalg`) in four ways:
//! blocked solves (low-rank columns, loads), the contact flexibility G = K⁻¹ restricted to the
//! trailing equations (the contact DOFs, last in the equations' order), and the split solve of
//! a trial, whose contact forces are found between a forward and a backward part. [`Backend`]
//! is that contract; [`Factor`] holds one backend and counts what the loop asked of it.
//!
//! - [`faer_llt::FaerLlt`] (the default, `factorization = "faer"`): faer's supernodal Cholesky
//!   in-process; G from the factor's trailing block, one substitution pair per trial.
//! - [`mumps::Mumps`] (`factorization = "mumps"`): PETSc's MUMPS Cholesky, the matrix rows
//!   distributed over the MPI ranks of `mpirun` (or one rank without it), for factors that
//!   outgrow one process. Every rank runs the same event loop on replicated small systems;
//!   the factor's calls are collective and their solutions gathered to every rank. G costs t
//!   blocked solves, and a trial's split solve two full solves (`mumps`).
//! - [`condensed::Condensed`] (`factorization = "condensed"`): faer's Cholesky of the far field
//!   kept with its condensed interface coupling, and only the Schur complement of the region
//!   near the contact refactorized; the region grows where K changes outside it.

pub mod condensed;
pub mod faer_llt;
pub mod mumps;
mod petsc;

use crate::error::Result;
use crate::linalg::DofMap;
use crate::options::{Factorization, Options};
use faer::sparse::SparseColMat;
use faer::Mat;

/// The work of a factor's operations in floating-point operations, from its structure
/// (`Backend::work`): a numeric factorization, a solve pair (one forward + backward
/// substitution), and the number of equations. The cost model of the low-rank terms
/// (`low_rank::Cost`) reads it, so both backends report the supernodal Cholesky's structure of
/// the same pattern and take the same refactorization decisions.
#[derive(Debug, Clone, Copy, Default)]
pub struct FactorWork {
    pub factorization_flops: f64,
    pub solve_pair_flops: f64,
    pub equations: f64,
}

/// A factorization of K_reg (lower triangle given, equations in the factor's order with the
/// last `n_trailing` ones the trailing block, `linalg::DofMap::ordered`).
///
/// A split solve K⁻¹(b + E f), f on the trailing equations, runs as `forward(b)` → w,
/// `trailing_solution(&w)` = (K⁻¹b) on the trailing equations, `add_trailing_force(&mut w, f)`,
/// `backward(w)` = K⁻¹(b + E f). What w holds is the backend's; the loop only scales it
/// (w of c b is c w: every backend's sweep is linear in b) and passes it on.
pub trait Backend {
    /// Factor `lower` again (same pattern, new values). A matrix that is not positive definite
    /// is a mechanism: a `FreeBody` error naming, where the backend knows it, the DOF.
    fn factor(&mut self, lower: &SparseColMat<usize, f64>, map: &DofMap) -> Result<()>;
    /// The work of a factorization and of a solve pair (`FactorWork`).
    fn work(&self) -> FactorWork;
    /// Solve K X = B in place for `columns` right-hand sides stored column after column.
    fn solve_in_place(&mut self, b: &mut [f64], columns: usize);
    /// G = K⁻¹ restricted to the trailing equations (t × t).
    fn trailing_inverse(&mut self) -> Mat<f64>;
    /// The forward part of a split solve of b (over the equations).
    fn forward(&mut self, b: &[f64]) -> Vec<f64>;
    /// (K⁻¹b) on the trailing equations, from the forward part w of b.
    fn trailing_solution(&self, w: &[f64]) -> Vec<f64>;
    /// Add a force f on the trailing equations (in their order) to a forward part.
    fn add_trailing_force(&self, w: &mut [f64], f: &[f64]);
    /// The backward part: K⁻¹(b + E f) over the equations.
    fn backward(&mut self, w: Vec<f64>) -> Vec<f64>;
    /// How many times the factor was built from a new structure (`Factor::n_builds`).
    fn n_builds(&self) -> usize {
        1
    }
}

/// The factor the loop holds: a backend and the count of its work.
pub struct Factor {
    backend: Box<dyn Backend>,
    pub n_factorizations: usize,
    /// Solves counted by right-hand side (a split solve is one, whatever the backend does).
    pub n_solves: usize,
}

impl Factor {
    /// The factor of `lower` by the chosen backend, whose last `n_trailing` equations form the
    /// trailing block (the symbolic analysis, kept for every refactorization, and the first
    /// numeric factorization).
    pub fn new(
        kind: Factorization,
        lower: &SparseColMat<usize, f64>,
        map: &DofMap,
        n_trailing: usize,
    ) -> Result<Self> {
        let backend: Box<dyn Backend> = match kind {
            Factorization::Faer => Box::new(faer_llt::FaerLlt::new(lower, map, n_trailing)?),
            Factorization::Mumps => Box::new(mumps::Mumps::new(lower, map, n_trailing)?),
            Factorization::Condensed => Box::new(condensed::Condensed::new(
                lower,
                map,
                n_trailing,
                crate::options::DEFAULT_NEAR_HOPS,
            )?),
        };
        Ok(Factor::of(backend))
    }

    /// The factor of `lower` by the backend and settings of a run's options (`Factor::new`).
    pub fn of_options(
        options: &Options,
        lower: &SparseColMat<usize, f64>,
        map: &DofMap,
        n_trailing: usize,
    ) -> Result<Self> {
        match options.factorization {
            Factorization::Condensed => Ok(Factor::of(Box::new(condensed::Condensed::new(
                lower,
                map,
                n_trailing,
                options.near_hops,
            )?))),
            kind => Factor::new(kind, lower, map, n_trailing),
        }
    }

    /// The factor a backend holds (its first factorization done).
    fn of(backend: Box<dyn Backend>) -> Self {
        Factor { backend, n_factorizations: 1, n_solves: 0 }
    }

    /// How many times the backend built its factor from a new structure (the condensed one's
    /// far factor: once, and again at every growth of its near region).
    pub fn n_builds(&self) -> usize {
        self.backend.n_builds()
    }

    /// Factor `lower` again (same pattern, new values).
    pub fn factor(&mut self, lower: &SparseColMat<usize, f64>, map: &DofMap) -> Result<()> {
        self.backend.factor(lower, map)?;
        self.n_factorizations += 1;
        Ok(())
    }

    pub fn work(&self) -> FactorWork {
        self.backend.work()
    }

    /// Solve K X = B in place for `columns` right-hand sides stored column after column.
    pub fn solve_in_place(&mut self, b: &mut [f64], columns: usize) {
        self.backend.solve_in_place(b, columns);
        self.n_solves += columns;
    }

    /// G = K⁻¹ restricted to the trailing equations.
    pub fn trailing_inverse(&mut self) -> Mat<f64> {
        self.backend.trailing_inverse()
    }

    /// The forward part of a split solve of b.
    pub fn forward(&mut self, b: &[f64]) -> Vec<f64> {
        self.backend.forward(b)
    }

    /// (K⁻¹b) on the trailing equations from the forward part of b.
    pub fn trailing_solution(&self, w: &[f64]) -> Vec<f64> {
        self.backend.trailing_solution(w)
    }

    /// w += the forward part of a force f on the trailing equations.
    pub fn add_trailing_force(&self, w: &mut [f64], f: &[f64]) {
        self.backend.add_trailing_force(w, f)
    }

    /// The backward part: K⁻¹(b + E f). Counts the split solve.
    pub fn backward(&mut self, w: Vec<f64>) -> Vec<f64> {
        self.n_solves += 1;
        self.backend.backward(w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::Cst;
    use crate::linalg::StiffnessPattern;
    use crate::material::{Material, Plane};
    use crate::section::Section;

    /// A 9 × 6-node cantilever fixed on x = 0, its free end's DOFs trailing (scrambled order).
    pub(super) fn cantilever() -> (SparseColMat<usize, f64>, DofMap, usize) {
        let (nx, ny) = (9, 6);
        let mesh = crate::mesh::test_grid(nx, ny, 0.5, 0.4);
        let els: Vec<Cst> = (0..mesh.elements.len()).map(|e| Cst::planar(&mesh, e, 1.0)).collect();
        let d = Section::new(Material::elastic(1000.0, 0.3), Plane::Strain.stress_state())
            .elastic_matrix();
        let n_dofs = 2 * mesh.nodes.len();
        let fixed: Vec<bool> = (0..n_dofs).map(|g| (g / 2) % nx == 0).collect();
        let trailing: Vec<usize> = [3, 0, 5, 2, 1, 4]
            .iter()
            .flat_map(|&j| [2 * (nx * j + nx - 1) + 1, 2 * (nx * j + nx - 1)])
            .collect();
        let map = DofMap::ordered(&els, n_dofs, &fixed, &[], &trailing).unwrap();
        let k = StiffnessPattern::new(&els, &map)
            .unwrap()
            .assemble(&els, &vec![d; els.len()], &map)
            .unwrap();
        (k, map, trailing.len())
    }

    /// K x from the stored lower triangle.
    pub(super) fn times(k: &SparseColMat<usize, f64>, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        let (ptr, rows, vals) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
        for c in 0..x.len() {
            for p in ptr[c]..ptr[c + 1] {
                let r = rows[p];
                y[r] += vals[p] * x[c];
                if r != c {
                    y[c] += vals[p] * x[r];
                }
            }
        }
        y
    }

    /// A backend honours the contract (`Backend`): every solve satisfies K x = b (the residual
    /// to round-off, K applied from its entries, not through the factor), G's column j is the
    /// solution for a unit load on trailing equation j read there, the split solve with a force
    /// f on the trailing equations satisfies K x = b + E f, and a refactorization takes the new
    /// values.
    fn check_contract(kind: Factorization) {
        check_contract_of(&format!("{kind:?}"), |k, map, t| Factor::new(kind, k, map, t).unwrap());
    }

    /// The contract for the factor `make` builds (`kind` names it in the messages).
    pub(super) fn check_contract_of(
        kind: &str,
        make: impl Fn(&SparseColMat<usize, f64>, &DofMap, usize) -> Factor,
    ) {
        let (k, map, t) = cantilever();
        let n = map.n_equations;
        let mut f = make(&k, &map, t);
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let big = b.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let residual = |x: &[f64], b: &[f64]| {
            times(&k, x).iter().zip(b).fold(0.0f64, |a, (kx, bi)| a.max((kx - bi).abs()))
        };
        // One and several right-hand sides (the second column is 2b: its solution is 2x).
        let mut x = b.clone();
        f.solve_in_place(&mut x, 1);
        assert!(residual(&x, &b) < 1e-10 * big, "{kind}: residual {}", residual(&x, &b));
        let mut two: Vec<f64> = b
            .iter()
            .chain(b.iter())
            .enumerate()
            .map(|(i, v)| if i < n { *v } else { 2.0 * v })
            .collect();
        f.solve_in_place(&mut two, 2);
        let xbig = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for i in 0..n {
            assert!(
                (two[i] - x[i]).abs() < 1e-12 * xbig
                    && (two[n + i] - 2.0 * x[i]).abs() < 2e-12 * xbig,
                "{kind}: blocked solve, row {i}"
            );
        }
        // G: column j is K⁻¹ e_j on the trailing equations, symmetric.
        let g = f.trailing_inverse();
        let first = n - t;
        for j in 0..t {
            let mut e = vec![0.0; n];
            e[first + j] = 1.0;
            let mut col = e.clone();
            f.solve_in_place(&mut col, 1);
            assert!(residual(&col, &e) < 1e-10);
            let scale = g[(j, j)];
            for i in 0..t {
                assert!(
                    (g[(i, j)] - col[first + i]).abs() < 1e-10 * scale,
                    "{kind}: G[{i},{j}] = {} vs {}",
                    g[(i, j)],
                    col[first + i]
                );
                assert!((g[(i, j)] - g[(j, i)]).abs() < 1e-12 * scale);
            }
        }
        // The split solve around a force on the trailing equations.
        let force: Vec<f64> = (0..t).map(|c| 1.0 + c as f64).collect();
        let mut w = f.forward(&b);
        let at_trailing = f.trailing_solution(&w);
        for i in 0..t {
            assert!(
                (at_trailing[i] - x[first + i]).abs() < 1e-10 * xbig,
                "{kind}: trailing part {i}"
            );
        }
        f.add_trailing_force(&mut w, &force);
        let split = f.backward(w);
        let mut with_force = b.clone();
        (0..t).for_each(|i| with_force[first + i] += force[i]);
        assert!(
            residual(&split, &with_force) < 1e-10 * big,
            "{kind}: split solve residual {}",
            residual(&split, &with_force)
        );
        // Refactorized with K doubled: the solution halves.
        let mut doubled = k.clone();
        doubled.val_mut().iter_mut().for_each(|v| *v *= 2.0);
        f.factor(&doubled, &map).unwrap();
        let mut half = b.clone();
        f.solve_in_place(&mut half, 1);
        (0..n).for_each(|i| {
            assert!((2.0 * half[i] - x[i]).abs() < 1e-10 * xbig, "{kind}: refactorized, row {i}")
        });
        assert_eq!(f.n_factorizations, 2);
        // Not positive definite (a diagonal entry negated): the mechanism error.
        let mut indefinite = k.clone();
        let (ptr, rows) = (k.symbolic().col_ptr().to_vec(), k.symbolic().row_idx().to_vec());
        let diagonal = (ptr[3]..ptr[4]).find(|&p| rows[p] == 3).unwrap();
        indefinite.val_mut()[diagonal] *= -1.0;
        let err = f.factor(&indefinite, &map).unwrap_err();
        assert_eq!(err.kind, crate::error::ErrorKind::FreeBody, "{kind}: {}", err.message);
    }

    #[test]
    fn the_faer_backend_honours_the_contract() {
        check_contract(Factorization::Faer);
    }

    /// MUMPS on one rank (PETSc started here): the same contract. Where PETSc is not
    /// installed the test says so and checks nothing (the Python test of the MUMPS runs is
    /// skipped there too).
    #[test]
    fn the_mumps_backend_honours_the_contract() {
        if let Err(e) = petsc::api() {
            eprintln!("skipped: {}", e.message);
            return;
        }
        check_contract(Factorization::Mumps);
    }
}
