//! faer's supernodal Cholesky in-process: the default backend (`factorization = "faer"`).

use super::{Backend, FactorWork};
use crate::bail;
use crate::error::Result;
use crate::linalg::DofMap;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SparseColMat;
use faer::{Accum, Conj, Mat, MatMut, Par, Side};

/// One thread for the solves and the dense block, and for the factorization of plane and small
/// meshes. Measured on this 2-core machine, faer's parallel (rayon) supernodal factorization is
/// slower there, its supernodes small: 6.8 s → 10.0 s at 955k DOFs, and 0.36 s → 0.75 s for 88
/// factorizations at 8.6k DOFs.
const PAR: Par = Par::Seq;
/// A mesh in space ordered by nested dissection has large dense supernodes (its separators):
/// from this many flops its numeric factorization runs on every thread of the pool
/// (`factorization_par`). Measured on the 2 cores, quiet: the Hertz sphere's 280k equations,
/// 1.87e12 flops, 48.3 s → 31.9 s.
const PARALLEL_FACTORIZATION_FLOPS: f64 = 1e11;

/// The threads of the numeric factorization: all of the pool's for an order with wide
/// separators (a mesh in space, `DofMap::wide_separators`) whose factorization costs at least
/// `PARALLEL_FACTORIZATION_FLOPS`, else one.
fn factorization_par(symbolic: &SymbolicCholesky<usize>, map: &DofMap) -> Par {
    if map.wide_separators && work_of(symbolic).factorization_flops >= PARALLEL_FACTORIZATION_FLOPS
    {
        Par::rayon(0)
    } else {
        PAR
    }
}

/// Cholesky factor of K_reg with the symbolic analysis kept for refactorization.
///
/// The equations come numbered in the factor's order (`DofMap::ordered`: fill-reducing, with
/// a chosen set of *trailing* equations, the contact DOFs, last), so the factor is L Lᵀ = K
/// without a permutation. With the trailing equations in the last t positions, the forward substitution of a unit load at a trailing DOF only touches the last
/// t rows, and the trailing rows of the backward substitution only the last t columns: the
/// flexibility of the trailing DOFs (K⁻¹ restricted to them, the Delassus operator of the
/// contact problem) is G = T⁻ᵀ T⁻¹ with T the trailing t × t block of L. One dense inversion
/// then replaces one full solve per contact pair.
///
/// The same block splits a solve K x = b + f with f on the trailing equations into one
/// forward and one backward substitution (`forward`, `trailing_solution`,
/// `add_trailing_force`, `backward`): the trailing part of K⁻¹b is known after the forward
/// sweep, and the forward sweep of f only touches the trailing rows (w_t += T⁻¹ f_t). The
/// event loop uses it to find the contact forces between the sweeps: one solve per trial.
pub struct FaerLlt {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    /// The last `n_trailing` equations form the trailing block.
    n_trailing: usize,
    /// T⁻¹ for the trailing block T of the current factor (lower triangular, t × t).
    trailing_block_inverse: Mat<f64>,
    /// Work space of the numeric factorization and of one-column solves, kept between calls.
    factor_scratch: MemBuffer,
    /// The threads of the numeric factorization (`factorization_par`).
    factor_par: Par,
    solve_scratch: Option<MemBuffer>,
}

impl FaerLlt {
    /// The factor of `lower` (lower triangle of an SPD matrix) whose last `n_trailing`
    /// equations form the trailing block: the symbolic analysis of its pattern, kept for every
    /// refactorization, and the first numeric factorization (`factor`), so that a solver always
    /// holds a factor.
    pub fn new(lower: &SparseColMat<usize, f64>, map: &DofMap, n_trailing: usize) -> Result<Self> {
        let symbolic = symbolic_analysis(lower)?;
        let factor_par = factorization_par(&symbolic, map);
        let factor_scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<f64>(factor_par, Default::default()),
        )
        .map_err(|_| crate::fail!(Internal, "out of memory for the Cholesky factorization"))?;
        let mut solver = FaerLlt {
            values: vec![0.0; symbolic.len_val()],
            symbolic,
            n_trailing,
            trailing_block_inverse: Mat::zeros(0, 0),
            factor_scratch,
            factor_par,
            solve_scratch: None,
        };
        solver.factor(lower, map)?;
        Ok(solver)
    }

    fn supernodal(&self) -> SupernodalLltRef<'_, usize, f64> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(sup) => SupernodalLltRef::new(sup, &self.values),
            SymbolicCholeskyRaw::Simplicial(_) => unreachable!("the factor is always supernodal"),
        }
    }

    /// The trailing t × t block T of the factor L (lower triangular).
    pub(super) fn trailing_block(&self) -> Mat<f64> {
        let t = self.n_trailing;
        let first = self.symbolic.nrows() - t;
        let mut tb = Mat::<f64>::zeros(t, t);
        if let SymbolicCholeskyRaw::Supernodal(sup) = self.symbolic.raw() {
            let factor = SupernodalLltRef::new(sup, &self.values);
            for s in (0..sup.n_supernodes()).rev() {
                let node = factor.supernode(s);
                let val = node.val();
                let start = node.start();
                let ncols = val.ncols();
                if start + ncols <= first {
                    break; // supernodes are contiguous column ranges in increasing order
                }
                let row_of =
                    |i: usize| if i < ncols { start + i } else { node.pattern()[i - ncols] };
                for c in 0..ncols {
                    let j = start + c;
                    if j < first {
                        continue;
                    }
                    for i in c..val.nrows() {
                        tb[(row_of(i) - first, j - first)] = val[(i, c)];
                    }
                }
            }
        }
        tb
    }

    /// B ← L⁻¹ B (the forward sweep) for the columns of `b`.
    pub(super) fn forward_in_place(&mut self, b: MatMut<'_, f64>) {
        let mut mem = self.scratch(b.ncols());
        self.supernodal().l_solve_with_conj(Conj::No, b, PAR, MemStack::new(&mut mem));
        self.keep_scratch(mem);
    }

    /// B ← L⁻ᵀ B (the backward sweep) for the columns of `b`.
    pub(super) fn backward_in_place(&mut self, b: MatMut<'_, f64>) {
        let mut mem = self.scratch(b.ncols());
        self.supernodal().l_transpose_solve_with_conj(Conj::No, b, PAR, MemStack::new(&mut mem));
        self.keep_scratch(mem);
    }

    /// The work space of a sweep or solve with `columns` right-hand sides (the one-column one is
    /// kept between calls: `keep_scratch`).
    fn scratch(&mut self, columns: usize) -> MemBuffer {
        match (columns, self.solve_scratch.take()) {
            (1, Some(mem)) => mem,
            _ => MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(columns, PAR)),
        }
    }

    fn keep_scratch(&mut self, mem: MemBuffer) {
        if self.solve_scratch.is_none() {
            self.solve_scratch = Some(mem);
        }
    }
}

impl Backend for FaerLlt {
    /// Factor `lower` again (same pattern, new values). A non-positive pivot means a
    /// mechanism: the message names the global DOF through `dof_of_equation`.
    fn factor(&mut self, lower: &SparseColMat<usize, f64>, map: &DofMap) -> Result<()> {
        let result = self.symbolic.factorize_numeric_llt(
            &mut self.values,
            lower.as_ref(),
            Side::Lower,
            Default::default(),
            self.factor_par,
            MemStack::new(&mut self.factor_scratch),
            Default::default(),
        );
        match result {
            Ok(_) => Ok(()),
            Err(LltError::NonPositivePivot { index }) => {
                // (The equations are in the factor's order: no permutation to undo.)
                let dim = map.dim;
                let hint = map
                    .dof_of_equation
                    .get(index)
                    .map(|&d| format!(" near node {} ({})", d / dim, ["x", "y", "z"][d % dim]))
                    .unwrap_or_default();
                bail!(FreeBody, "the stiffness matrix is singular{hint}: the model has a mechanism (a part held by nothing, or elements joined at a single node); add supports or check the mesh connectivity")
            }
        }
    }

    /// The work from the supernodal structure (`work_of`).
    fn work(&self) -> FactorWork {
        work_of(&self.symbolic)
    }

    /// Solve K_reg X = B in place for `columns` right-hand sides stored column after column
    /// (one blocked forward/backward substitution for all of them).
    fn solve_in_place(&mut self, b: &mut [f64], columns: usize) {
        let n = b.len() / columns.max(1);
        let mut mem = self.scratch(columns);
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, n, columns),
            PAR,
            MemStack::new(&mut mem),
        );
        self.keep_scratch(mem);
    }

    /// G = K_reg⁻¹ restricted to the trailing equations (the last t),
    /// from the trailing block T of the factor: G = T⁻ᵀ T⁻¹ (see the type's documentation).
    fn trailing_inverse(&mut self) -> Mat<f64> {
        let t = self.n_trailing;
        // X = T⁻¹, G = Xᵀ X.
        let mut x = Mat::<f64>::identity(t, t);
        solve_lower_triangular_in_place(self.trailing_block().as_ref(), x.as_mut(), PAR);
        let mut g = Mat::<f64>::zeros(t, t);
        matmul(g.as_mut(), Accum::Replace, x.transpose(), x.as_ref(), 1.0, PAR);
        self.trailing_block_inverse = x;
        g
    }

    /// Forward sweep w = L⁻¹ b for b over the equations.
    fn forward(&mut self, b: &[f64]) -> Vec<f64> {
        let mut w = b.to_vec();
        let n = w.len();
        self.forward_in_place(MatMut::from_column_major_slice_mut(&mut w, n, 1));
        w
    }

    /// The trailing equations' part of K⁻¹b, from the forward sweep w of b: T⁻ᵀ w_t (in the order of the
    /// trailing equations).
    fn trailing_solution(&self, w: &[f64]) -> Vec<f64> {
        let t = self.n_trailing;
        let w_t = &w[w.len() - t..];
        let x = &self.trailing_block_inverse;
        // (T⁻ᵀ w_t)_i = Σ_j X_ji w_j, X lower triangular.
        (0..t).map(|i| (i..t).map(|j| x[(j, i)] * w_t[j]).sum()).collect()
    }

    /// Add a force f given on the trailing equations to a forward sweep:
    /// w_t += T⁻¹ f.
    fn add_trailing_force(&self, w: &mut [f64], f: &[f64]) {
        let t = self.n_trailing;
        let first = w.len() - t;
        let x = &self.trailing_block_inverse;
        for (j, &fj) in f.iter().enumerate() {
            if fj != 0.0 {
                for i in j..t {
                    w[first + i] += x[(i, j)] * fj;
                }
            }
        }
    }

    /// Backward sweep: x = L⁻ᵀ w, over the equations.
    fn backward(&mut self, mut w: Vec<f64>) -> Vec<f64> {
        let n = w.len();
        self.backward_in_place(MatMut::from_column_major_slice_mut(&mut w, n, 1));
        w
    }
}

/// The supernodal symbolic analysis of `lower`'s pattern in its own order (the equations are
/// numbered in the factor's order already, `DofMap::ordered`). Supernodal always: the trailing
/// block is read from the supernodes.
pub fn symbolic_analysis(lower: &SparseColMat<usize, f64>) -> Result<SymbolicCholesky<usize>> {
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    // (Without a permutation faer's analysis reads the upper triangle: hand it Lᵀ's.)
    let upper =
        lower.as_ref().transpose().to_col_major().map_err(|e| {
            crate::fail!(Internal, "could not transpose the stiffness pattern: {e:?}")
        })?;
    factorize_symbolic_cholesky(upper.symbolic(), Side::Upper, SymmetricOrdering::Identity, params)
        .map_err(|e| crate::fail!(Internal, "symbolic factorization failed: {e:?}"))
}

/// The work of a factorization and of a solve pair, from the supernodal structure: a
/// supernode of c columns with r rows below them costs c³/3 + c² r + c r² to factor (its
/// own block, the panel below it, the update of its ancestors) and holds c(c+1)/2 + c r
/// entries, each used twice by a solve pair (2 flops each way).
pub fn work_of(symbolic: &SymbolicCholesky<usize>) -> FactorWork {
    let (mut factorization, mut entries) = (0.0, 0.0);
    if let SymbolicCholeskyRaw::Supernodal(sup) = symbolic.raw() {
        let ptr = sup.col_ptr_for_row_idx();
        for s in 0..sup.n_supernodes() {
            let c = (sup.supernode_end()[s] - sup.supernode_begin()[s]) as f64;
            let r = (ptr[s + 1] - ptr[s]) as f64;
            factorization += c * c * c / 3.0 + c * c * r + c * r * r;
            entries += c * (c + 1.0) / 2.0 + c * r;
        }
    }
    FactorWork {
        factorization_flops: factorization,
        solve_pair_flops: 4.0 * entries,
        equations: symbolic.nrows() as f64,
    }
}
