//! PETSc's MUMPS Cholesky, the matrix rows distributed over the MPI ranks
//! (`factorization = "mumps"`).
//!
//! Every rank runs the same event loop with the whole K assembled (it is sparse; the factor is
//! what outgrows a process) and hands PETSc the rows it owns, a contiguous block of the
//! equations. Every call here is collective: all ranks make it in the same order, which the
//! replicated, deterministic loop guarantees, and every solution is gathered whole to every
//! rank, so the ranks' loops see the same numbers bit for bit and take the same events.
//! (From one run to the next, on several ranks, the numbers may differ at round-off: MUMPS
//! sums contribution blocks in the order the ranks' messages arrive.)
//!
//! Against the faer backend: G = K⁻¹ on the trailing equations is MUMPS's computation of
//! selected entries of the inverse (t sparse right-hand sides, its solves pruned to the tree's
//! paths they touch) instead of the factor's trailing block, and a trial's split solve is two
//! full solves (the forward part solves for b, the backward part for b + E f) instead of one
//! substitution pair: MUMPS's sweeps are not reachable through PETSc. PETSc refuses the Schur
//! complement (which would give G directly) on more than one rank.

use super::faer_llt::{symbolic_analysis, work_of};
use super::petsc::{self, Api, FactorInfo, Handle, PetscInt};
use super::{Backend, FactorWork};
use crate::bail;
use crate::error::Result;
use crate::linalg::DofMap;
use faer::sparse::SparseColMat;
use faer::Mat;
use std::ptr::null_mut;

/// MUMPS's controls (ICNTL) the selected inverse sets and the solves need back.
const ICNTL_SOLUTION_DISTRIBUTED: PetscInt = 21;
const ICNTL_INVERSE_ENTRIES: PetscInt = 30;
/// MUMPS's INFOG(1) when ScaLAPACK meets a non-positive pivot in an SPD (SYM = 1) root front.
const MUMPS_NOT_POSITIVE_DEFINITE: PetscInt = -40;

pub struct Mumps {
    api: &'static Api,
    /// The upper triangle of K (PETSc's symmetric block format, one row per equation).
    matrix: Handle,
    factor: Handle,
    rhs: Handle,
    solution: Handle,
    /// Scatters a distributed vector to `whole` on every rank.
    gather: Handle,
    whole: Handle,
    info: FactorInfo,
    /// This rank's equations [first, end), and whether other ranks hold the rest.
    first: usize,
    end: usize,
    several_ranks: bool,
    n: usize,
    n_trailing: usize,
    /// The supernodal Cholesky's work for the same pattern (the cost model's, `FactorWork`).
    work: FactorWork,
}

impl Mumps {
    /// The distributed matrix of `lower`, MUMPS's analysis of it (once), and its first
    /// numeric factorization.
    pub fn new(lower: &SparseColMat<usize, f64>, map: &DofMap, n_trailing: usize) -> Result<Self> {
        let api = petsc::api()?;
        let n = lower.nrows();
        let (rank, size) = api.rank_and_size();
        let (first, end) = (n * rank / size, n * (rank + 1) / size);
        let work = work_of(&symbolic_analysis(lower)?);
        let mut m = Mumps {
            api,
            matrix: null_mut(),
            factor: null_mut(),
            rhs: null_mut(),
            solution: null_mut(),
            gather: null_mut(),
            whole: null_mut(),
            info: [0.0; 11],
            first,
            end,
            several_ranks: size > 1,
            n,
            n_trailing,
            work,
        };
        api.quietly(|| m.create(lower))?;
        m.factor(lower, map)?;
        Ok(m)
    }

    /// The matrix (preallocated from `lower`'s pattern), its factor object analysed once, and
    /// the vectors of the solves.
    fn create(&mut self, lower: &SparseColMat<usize, f64>) -> Result<()> {
        let (api, (first, end), n) = (self.api, (self.first, self.end), self.n as PetscInt);
        // Row c of the upper triangle is column c of `lower`: entries in this rank's columns
        // (the diagonal block) and beyond (the off-diagonal block).
        let col_ptr = lower.symbolic().col_ptr();
        let row_idx = lower.symbolic().row_idx();
        let (mut diagonal, mut beyond) =
            (Vec::with_capacity(end - first), Vec::with_capacity(end - first));
        for c in first..end {
            let in_block = row_idx[col_ptr[c]..col_ptr[c + 1]].iter().filter(|&&r| r < end).count();
            diagonal.push(in_block as PetscInt);
            beyond.push((col_ptr[c + 1] - col_ptr[c] - in_block) as PetscInt);
        }
        let local = (end - first) as PetscInt;
        unsafe {
            api.check(
                (api.MatCreateSBAIJ)(
                    api.comm(),
                    1,
                    local,
                    local,
                    n,
                    n,
                    0,
                    diagonal.as_ptr(),
                    0,
                    beyond.as_ptr(),
                    &mut self.matrix,
                ),
                "MatCreateSBAIJ",
            )?;
            self.set_values(lower)?;
            api.check(
                (api.MatSetOption)(self.matrix, petsc::MAT_SPD, petsc::PETSC_TRUE),
                "MatSetOption(MAT_SPD)",
            )?;
            api.check(
                (api.MatGetFactor)(
                    self.matrix,
                    c"mumps".as_ptr(),
                    petsc::MAT_FACTOR_CHOLESKY,
                    &mut self.factor,
                ),
                "MatGetFactor(mumps, Cholesky)",
            )?;
            api.check((api.MatFactorInfoInitialize)(&mut self.info), "MatFactorInfoInitialize")?;
            api.check(
                (api.MatCholeskyFactorSymbolic)(self.factor, self.matrix, null_mut(), &self.info),
                "MatCholeskyFactorSymbolic",
            )?;
            api.check(
                (api.MatCreateVecs)(self.matrix, &mut self.solution, &mut self.rhs),
                "MatCreateVecs",
            )?;
            api.check(
                (api.VecScatterCreateToAll)(self.solution, &mut self.gather, &mut self.whole),
                "VecScatterCreateToAll",
            )?;
        }
        Ok(())
    }

    /// This rank's rows of the upper triangle from `lower`'s columns, assembled.
    unsafe fn set_values(&mut self, lower: &SparseColMat<usize, f64>) -> Result<()> {
        let api = self.api;
        let (col_ptr, row_idx, values) =
            (lower.symbolic().col_ptr(), lower.symbolic().row_idx(), lower.val());
        let mut columns: Vec<PetscInt> = Vec::new();
        for c in self.first..self.end {
            let range = col_ptr[c]..col_ptr[c + 1];
            columns.clear();
            columns.extend(row_idx[range.clone()].iter().map(|&r| r as PetscInt));
            let row = c as PetscInt;
            api.check(
                (api.MatSetValues)(
                    self.matrix,
                    1,
                    &row,
                    columns.len() as PetscInt,
                    columns.as_ptr(),
                    values[range].as_ptr(),
                    petsc::INSERT_VALUES,
                ),
                "MatSetValues",
            )?;
        }
        api.check(
            (api.MatAssemblyBegin)(self.matrix, petsc::MAT_FINAL_ASSEMBLY),
            "MatAssemblyBegin",
        )?;
        api.check((api.MatAssemblyEnd)(self.matrix, petsc::MAT_FINAL_ASSEMBLY), "MatAssemblyEnd")
    }

    /// `whole` (every equation, on every rank) from the distributed vector `v`.
    unsafe fn gathered(&self, v: Handle, out: &mut [f64]) {
        let api = self.api;
        api.must(
            (api.VecScatterBegin)(
                self.gather,
                v,
                self.whole,
                petsc::INSERT_VALUES,
                petsc::SCATTER_FORWARD,
            ),
            "VecScatterBegin",
        );
        api.must(
            (api.VecScatterEnd)(
                self.gather,
                v,
                self.whole,
                petsc::INSERT_VALUES,
                petsc::SCATTER_FORWARD,
            ),
            "VecScatterEnd",
        );
        let mut p: *const f64 = std::ptr::null();
        api.must((api.VecGetArrayRead)(self.whole, &mut p), "VecGetArrayRead");
        out.copy_from_slice(std::slice::from_raw_parts(p, self.n));
        api.must((api.VecRestoreArrayRead)(self.whole, &mut p), "VecRestoreArrayRead");
    }

    /// `values` of rank 0 to every rank.
    unsafe fn broadcast(&self, values: &mut [f64], rank0: bool) {
        let api = self.api;
        let own = if rank0 { values.len() } else { 0 };
        let (mut v, mut to_all, mut all): (Handle, Handle, Handle) =
            (null_mut(), null_mut(), null_mut());
        api.must(
            (api.VecCreateMPI)(api.comm(), own as PetscInt, values.len() as PetscInt, &mut v),
            "VecCreateMPI",
        );
        let mut p: *mut f64 = null_mut();
        api.must((api.VecGetArray)(v, &mut p), "VecGetArray");
        std::slice::from_raw_parts_mut(p, own).copy_from_slice(&values[..own]);
        api.must((api.VecRestoreArray)(v, &mut p), "VecRestoreArray");
        api.must((api.VecScatterCreateToAll)(v, &mut to_all, &mut all), "VecScatterCreateToAll");
        api.must(
            (api.VecScatterBegin)(to_all, v, all, petsc::INSERT_VALUES, petsc::SCATTER_FORWARD),
            "VecScatterBegin",
        );
        api.must(
            (api.VecScatterEnd)(to_all, v, all, petsc::INSERT_VALUES, petsc::SCATTER_FORWARD),
            "VecScatterEnd",
        );
        let mut q: *const f64 = std::ptr::null();
        api.must((api.VecGetArrayRead)(all, &mut q), "VecGetArrayRead");
        values.copy_from_slice(std::slice::from_raw_parts(q, values.len()));
        api.must((api.VecRestoreArrayRead)(all, &mut q), "VecRestoreArrayRead");
        api.must((api.VecScatterDestroy)(&mut to_all), "VecScatterDestroy");
        api.must((api.VecDestroy)(&mut all), "VecDestroy");
        api.must((api.VecDestroy)(&mut v), "VecDestroy");
    }

    /// K⁻¹ b for one right-hand side over the equations.
    fn solve_one(&mut self, b: &mut [f64]) {
        let api = self.api;
        unsafe {
            let mut p: *mut f64 = null_mut();
            api.must((api.VecGetArray)(self.rhs, &mut p), "VecGetArray");
            std::slice::from_raw_parts_mut(p, self.end - self.first)
                .copy_from_slice(&b[self.first..self.end]);
            api.must((api.VecRestoreArray)(self.rhs, &mut p), "VecRestoreArray");
            api.must((api.MatSolve)(self.factor, self.rhs, self.solution), "MatSolve");
            self.gathered(self.solution, b);
        }
    }

    /// K⁻¹ B for `columns` right-hand sides stored column after column, in one MUMPS solve.
    fn solve_block(&mut self, b: &mut [f64], columns: usize) {
        let (api, n, local) = (self.api, self.n, self.end - self.first);
        unsafe {
            // A dense n × columns matrix in this rank's rows, holding `data`'s when given.
            let dense = |data: Option<&[f64]>| {
                let mut m: Handle = null_mut();
                api.must(
                    (api.MatCreateDense)(
                        api.comm(),
                        local as PetscInt,
                        petsc::PETSC_DECIDE,
                        n as PetscInt,
                        columns as PetscInt,
                        null_mut(),
                        &mut m,
                    ),
                    "MatCreateDense",
                );
                if let Some(data) = data {
                    let mut p: *mut f64 = null_mut();
                    api.must((api.MatDenseGetArray)(m, &mut p), "MatDenseGetArray");
                    let mine = std::slice::from_raw_parts_mut(p, local * columns);
                    for (c, column) in mine.chunks_exact_mut(local.max(1)).enumerate() {
                        column.copy_from_slice(&data[c * n + self.first..c * n + self.end]);
                    }
                    api.must((api.MatDenseRestoreArray)(m, &mut p), "MatDenseRestoreArray");
                }
                m
            };
            let mut rhs = dense(Some(b));
            let mut x = dense(None);
            api.must((api.MatMatSolve)(self.factor, rhs, x), "MatMatSolve");
            for (c, column) in b.chunks_exact_mut(n).enumerate() {
                let mut v: Handle = null_mut();
                api.must(
                    (api.MatDenseGetColumnVecRead)(x, c as PetscInt, &mut v),
                    "MatDenseGetColumnVecRead",
                );
                self.gathered(v, column);
                api.must(
                    (api.MatDenseRestoreColumnVecRead)(x, c as PetscInt, &mut v),
                    "MatDenseRestoreColumnVecRead",
                );
            }
            api.must((api.MatDestroy)(&mut rhs), "MatDestroy");
            api.must((api.MatDestroy)(&mut x), "MatDestroy");
        }
    }
}

impl Backend for Mumps {
    /// New values into the distributed matrix and MUMPS's numeric factorization. The matrix
    /// is declared SPD (MUMPS's SYM = 1, no pivoting): a negative or zero pivot, which MUMPS
    /// counts (INFOG(12)) or, on the root front ScaLAPACK factors on several ranks, refuses
    /// (INFOG(1) = -40), means a mechanism; MUMPS does not say where.
    fn factor(&mut self, lower: &SparseColMat<usize, f64>, _map: &DofMap) -> Result<()> {
        let api = self.api;
        let (mut failure, mut status, mut negative) = (0, 0, 0);
        // (MUMPS's status is read whether or not PETSc passes its failure on as an error.)
        let numeric = api.quietly(|| unsafe {
            self.set_values(lower)?;
            let numeric = (api.MatCholeskyFactorNumeric)(self.factor, self.matrix, &self.info);
            api.check((api.MatFactorGetError)(self.factor, &mut failure), "MatFactorGetError")?;
            api.check((api.MatMumpsGetInfog)(self.factor, 1, &mut status), "MatMumpsGetInfog")?;
            api.check((api.MatMumpsGetInfog)(self.factor, 12, &mut negative), "MatMumpsGetInfog")?;
            Ok(numeric)
        })?;
        if failure == petsc::MAT_FACTOR_NUMERIC_ZEROPIVOT
            || status == MUMPS_NOT_POSITIVE_DEFINITE
            || negative > 0
        {
            bail!(FreeBody, "the stiffness matrix is singular: the model has a mechanism (a part held by nothing, or elements joined at a single node); add supports or check the mesh connectivity");
        }
        if failure != 0 || status < 0 || numeric != 0 {
            bail!(Internal, "MUMPS could not factorize the stiffness (MUMPS INFOG(1) = {status}; -8, -9 and -13 are out of memory): use more ranks or factorization = \"faer\"");
        }
        Ok(())
    }

    fn work(&self) -> FactorWork {
        self.work
    }

    fn solve_in_place(&mut self, b: &mut [f64], columns: usize) {
        match columns {
            0 => {}
            1 => self.solve_one(b),
            _ => self.solve_block(b, columns),
        }
    }

    /// G = K⁻¹ restricted to the trailing equations: MUMPS's selected entries of the inverse
    /// (found on rank 0, then sent to every rank), symmetrized (K⁻¹ is symmetric; the
    /// entries (i, j) and (j, i) are computed apart, so they differ at round-off).
    fn trailing_inverse(&mut self) -> Mat<f64> {
        let (api, n, t) = (self.api, self.n, self.n_trailing);
        if t == 0 {
            return Mat::zeros(0, 0);
        }
        let rank0 = self.first == 0;
        let trailing: Vec<PetscInt> = (n - t..n).map(|i| i as PetscInt).collect();
        let mut entries = vec![0.0; t * t];
        unsafe {
            // The pattern of the wanted entries, as PETSc hands it to MUMPS: the transpose of
            // an n × n matrix whose row j lists the rows i of column j, all of it on rank 0.
            let local = if rank0 { n as PetscInt } else { 0 };
            let row_entries: Vec<PetscInt> =
                (0..local as usize).map(|j| if j >= n - t { t as PetscInt } else { 0 }).collect();
            let mut pattern: Handle = null_mut();
            api.must(
                (api.MatCreateAIJ)(
                    api.comm(),
                    local,
                    local,
                    n as PetscInt,
                    n as PetscInt,
                    0,
                    row_entries.as_ptr(),
                    0,
                    row_entries.as_ptr(),
                    &mut pattern,
                ),
                "MatCreateAIJ",
            );
            if rank0 {
                let ones = vec![1.0; t * t];
                api.must(
                    (api.MatSetValues)(
                        pattern,
                        t as PetscInt,
                        trailing.as_ptr(),
                        t as PetscInt,
                        trailing.as_ptr(),
                        ones.as_ptr(),
                        petsc::INSERT_VALUES,
                    ),
                    "MatSetValues",
                );
            }
            api.must(
                (api.MatAssemblyBegin)(pattern, petsc::MAT_FINAL_ASSEMBLY),
                "MatAssemblyBegin",
            );
            api.must((api.MatAssemblyEnd)(pattern, petsc::MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
            let mut wanted: Handle = null_mut();
            api.must((api.MatCreateTranspose)(pattern, &mut wanted), "MatCreateTranspose");
            api.must((api.MatMumpsGetInverse)(self.factor, wanted), "MatMumpsGetInverse");
            // Back to solving: no inverse entries, and (on several ranks) the solution left
            // distributed, as PETSc's solves expect it.
            api.must(
                (api.MatMumpsSetIcntl)(self.factor, ICNTL_INVERSE_ENTRIES, 0),
                "MatMumpsSetIcntl",
            );
            if self.several_ranks {
                api.must(
                    (api.MatMumpsSetIcntl)(self.factor, ICNTL_SOLUTION_DISTRIBUTED, 1),
                    "MatMumpsSetIcntl",
                );
            }
            if rank0 {
                // Row j of `pattern`, column i: K⁻¹(i, j).
                api.must(
                    (api.MatGetValues)(
                        pattern,
                        t as PetscInt,
                        trailing.as_ptr(),
                        t as PetscInt,
                        trailing.as_ptr(),
                        entries.as_mut_ptr(),
                    ),
                    "MatGetValues",
                );
            }
            api.must((api.MatDestroy)(&mut wanted), "MatDestroy");
            api.must((api.MatDestroy)(&mut pattern), "MatDestroy");
            self.broadcast(&mut entries, rank0);
        }
        Mat::from_fn(t, t, |i, j| 0.5 * (entries[j * t + i] + entries[i * t + j]))
    }

    /// w = [b, K⁻¹b]: one solve.
    fn forward(&mut self, b: &[f64]) -> Vec<f64> {
        let mut w = Vec::with_capacity(2 * b.len());
        w.extend_from_slice(b);
        w.extend_from_slice(b);
        self.solve_one(&mut w[b.len()..]);
        w
    }

    fn trailing_solution(&self, w: &[f64]) -> Vec<f64> {
        w[w.len() - self.n_trailing..].to_vec()
    }

    /// b += E f (the solution part is stale from here: `backward` solves again).
    fn add_trailing_force(&self, w: &mut [f64], f: &[f64]) {
        let n = w.len() / 2;
        w[n - f.len()..n].iter_mut().zip(f).for_each(|(a, b)| *a += b);
    }

    /// K⁻¹(b + E f): a second solve.
    fn backward(&mut self, mut w: Vec<f64>) -> Vec<f64> {
        w.truncate(w.len() / 2);
        self.solve_one(&mut w);
        w
    }
}

impl Drop for Mumps {
    fn drop(&mut self) {
        let api = self.api;
        unsafe {
            for m in [&mut self.factor, &mut self.matrix] {
                if !m.is_null() {
                    (api.MatDestroy)(m);
                }
            }
            for v in [&mut self.rhs, &mut self.solution, &mut self.whole] {
                if !v.is_null() {
                    (api.VecDestroy)(v);
                }
            }
            if !self.gather.is_null() {
                (api.VecScatterDestroy)(&mut self.gather);
            }
        }
    }
}
