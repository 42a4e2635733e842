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

pub mod faer_llt;
pub mod mumps;
mod petsc;

use crate::error::Result;
use crate::linalg::DofMap;
use crate::options::Factorization;
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
    pub fn new(kind: Factorization, lower: &SparseColMat<usize, f64>, map: &DofMap, n_trailing: usize) -> Result<Self> {
        let backend: Box<dyn Backend> = match kind {
            Factorization::Faer => Box::new(faer_llt::FaerLlt::new(lower, map, n_trailing)?),
            Factorization::Mumps => Box::new(mumps::Mumps::new(lower, map, n_trailing)?),
        };
        Ok(Factor { backend, n_factorizations: 1, n_solves: 0 })
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
