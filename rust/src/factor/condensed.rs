//! A factor that refactorizes only the region near the contact (`factorization =
//! "condensed"`): the far field's factor and its condensed interface operator are kept.
//!
//! The equations split into the near ones N (the contact DOFs, the trailing equations, and
//! every equation within `hops` graph hops of them in K's pattern) and the far ones F; I ⊂ N
//! are the near equations coupled to F (the interface). In the order [F, N] the Cholesky
//! factor of K is [L_FF 0; L_NF L_S], L_NF nonzero on the I rows only, L_S the factor of the
//! Schur complement S = K_NN − C, C = K_IF K_FF⁻¹ K_FI (dense, on I × I). While no entry of K
//! outside N × N changes (every element with a far node keeps its tangent), L_FF, L_IF and C
//! stay: a refactorization is the factor of S alone.
//!
//! - The far factor: the Cholesky of M = [K_FF K_FI; K_IF K_II] with I as its trailing block T,
//!   so C = K_II − T Tᵀ, and L_IF is M's; built once, and again when the region grows.
//! - The near factor: the Cholesky of S (K_NN's pattern with the I clique), its contact DOFs
//!   last: G = K⁻¹ on them is S⁻¹ there, read from its trailing block as before.
//! - A solve K x = b: the far forward sweep of [b_F, 0] gives z_F and w_I (L_IF z_F = −T w_I),
//!   the near solve of b_N with b_I + T w_I on I gives x_N, the far backward sweep of
//!   [z_F, Tᵀ x_I] gives x_F. A split solve nests the same way.
//! - Each factorization first compares K's entries outside N × N with those the far factor was
//!   built from (exactly): where any changed, their equations and `hops` around them join N
//!   and the far factor is rebuilt, so every factorization is exact whatever the plastic zone
//!   does.
//!
//! The equations keep the global order (`DofMap::ordered`); each factor orders its own part
//! (AMD with the I clique joined, I last in M, the contact DOFs last in S). Without contact
//! DOFs the region is the whole body.
//!
//! When it pays (measured on this 2-core machine, the same events as "faer" in every case):
//! only where the tangents that change stay in a region holding a small part of the equations.
//! On the shipped contact meshes the refined zone around the contact holds most equations and
//! the plastic zone fills it, so the region grows to most of the body and a refactorization of
//! S costs about what a full one does (S's interface block is dense): the 24.5k-DOF
//! elastoplastic Hertz refactorizes 4.0e8-flop regions at the end against 4.8e8 for all of K
//! (5 growths, factorization 1.32 s against 1.09 s); the 3D plastic sphere (7.1k DOFs) starts
//! at 2.4e8 flops (1 hop) against 1.09e9 but ends near the whole body, and at 14.9k DOFs
//! factorizes in 113-129 s against 114 s. Of the shipped 2D cases only the axisymmetric
//! plastic sphere (5.3k DOFs, 502 factorizations) gains: 0.95-1.03 s against 1.35-1.43 s.
//! Elastic runs factor once, and the condensed first factorization (two factors, two
//! orderings) costs about twice the plain one. Hence an option, not the default.

use super::faer_llt::FaerLlt;
use super::{Backend, FactorWork};
use crate::error::Result;
use crate::linalg::DofMap;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::sparse::linalg::amd;
use faer::sparse::{Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Accum, Mat, MatMut, Par};

/// A region that grows takes at least this factor more equations (besides `hops` layers
/// around the change): a plastic zone spreading layer by layer then costs a few far factors,
/// not one per layer. Measured on the 24.5k-DOF elastoplastic Hertz: 17 growths at 1 (layers
/// only), 5 at 1.5, 3 at 2 (its last region 2 % larger than at 1.5).
const GROWTH: f64 = 1.5;

/// Not in a restricted matrix.
const NONE: usize = usize::MAX;

pub struct Condensed {
    hops: usize,
    n_trailing: usize,
    graph: Graph,
    /// The near equations (by global equation).
    is_near: Vec<bool>,
    split: Split,
    far: Option<Far>,
    near: FaerLlt,
    /// How many times the far factor was built (the first included).
    n_far_builds: usize,
}

/// The equations of both factors and where K's entries go.
struct Split {
    /// M's equations (global): F, then I.
    far_eqs: Vec<usize>,
    n_interface: usize,
    /// S's equations (global), the trailing ones last in their global order.
    near_eqs: Vec<usize>,
    /// The position in S of each interface equation (in M's order of I).
    interface_in_near: Vec<usize>,
    /// S's pattern; the position in S of each of K's values (NONE outside N × N) and of each
    /// I-clique entry (a ≥ b in M's order of I, at a(a+1)/2 + b).
    near_pattern: SymbolicSparseColMat<usize>,
    near_of_k: Vec<usize>,
    clique_in_near: Vec<usize>,
}

/// The far factor, its trailing block T, C = K_II − T Tᵀ, and K's values outside N × N it was
/// built from (position in K, value).
struct Far {
    llt: FaerLlt,
    block: Mat<f64>,
    coupling: Mat<f64>,
    frozen: Vec<(usize, f64)>,
}

/// K's pattern as a symmetric adjacency (both triangles, no diagonal).
struct Graph {
    start: Vec<usize>,
    adjacent: Vec<usize>,
}

impl Graph {
    fn of(lower: &SparseColMat<usize, f64>) -> Self {
        let n = lower.nrows();
        let (ptr, rows) = (lower.symbolic().col_ptr(), lower.symbolic().row_idx());
        let mut degree = vec![0usize; n];
        for c in 0..n {
            for &r in rows[ptr[c]..ptr[c + 1]].iter().filter(|&&r| r != c) {
                degree[r] += 1;
                degree[c] += 1;
            }
        }
        let mut start = vec![0usize; n + 1];
        (0..n).for_each(|i| start[i + 1] = start[i] + degree[i]);
        let mut fill = start.clone();
        let mut adjacent = vec![0usize; start[n]];
        for c in 0..n {
            for &r in rows[ptr[c]..ptr[c + 1]].iter().filter(|&&r| r != c) {
                adjacent[fill[r]] = c;
                fill[r] += 1;
                adjacent[fill[c]] = r;
                fill[c] += 1;
            }
        }
        Graph { start, adjacent }
    }

    fn neighbours(&self, i: usize) -> &[usize] {
        &self.adjacent[self.start[i]..self.start[i + 1]]
    }

    /// Mark `seeds` and every equation within `hops` of them in `set`, and further layers
    /// around them until the set holds at least `at_least` equations (or no layer adds any).
    fn grow(&self, set: &mut [bool], seeds: &[usize], hops: usize, at_least: usize) {
        let mut front: Vec<usize> = seeds.iter().copied().filter(|&i| !set[i]).collect();
        front.iter().for_each(|&i| set[i] = true);
        let mut count = set.iter().filter(|&&x| x).count();
        let mut layer = 0;
        while (layer < hops || count < at_least) && !front.is_empty() {
            layer += 1;
            let mut next = Vec::new();
            for &i in &front {
                for &j in self.neighbours(i) {
                    if !set[j] {
                        set[j] = true;
                        count += 1;
                        next.push(j);
                    }
                }
            }
            front = next;
        }
    }
}

impl Condensed {
    /// The factor of `lower` whose last `n_trailing` equations are the contact DOFs, with the
    /// near region `hops` around them.
    pub fn new(
        lower: &SparseColMat<usize, f64>,
        map: &DofMap,
        n_trailing: usize,
        hops: usize,
    ) -> Result<Self> {
        let n = lower.nrows();
        let graph = Graph::of(lower);
        // (Without contact DOFs the region is the whole body: a plain Cholesky.)
        let mut is_near = vec![n_trailing == 0; n];
        let trailing: Vec<usize> = (n - n_trailing..n).collect();
        graph.grow(&mut is_near, &trailing, hops, 0);
        let (split, far, near) = build(lower, map, &graph, &is_near, n_trailing)?;
        Ok(Condensed { hops, n_trailing, graph, is_near, split, far, near, n_far_builds: 1 })
    }

    /// The equations of K's entries outside N × N that differ from the far factor's.
    fn changed_outside(&self, lower: &SparseColMat<usize, f64>) -> Vec<usize> {
        let Some(far) = &self.far else { return Vec::new() };
        let values = lower.val();
        let changed: Vec<usize> =
            far.frozen.iter().filter(|&&(p, v)| values[p] != v).map(|&(p, _)| p).collect();
        if changed.is_empty() {
            return changed;
        }
        let (ptr, rows) = (lower.symbolic().col_ptr(), lower.symbolic().row_idx());
        let mut eqs = Vec::new();
        for &p in &changed {
            let c = ptr.partition_point(|&q| q <= p) - 1;
            eqs.extend([rows[p], c]);
        }
        eqs
    }

    /// The far sweep of [b_F, 0] (M's equations × columns) and the near right-hand side b_N
    /// with b_I + T w_I on I (S's equations × columns).
    fn far_forward(&mut self, b: &[f64], columns: usize) -> (Vec<f64>, Vec<f64>) {
        let n = b.len() / columns.max(1);
        let split = &self.split;
        let mut near_rhs = gather(b, n, &split.near_eqs, columns);
        let Some(far) = &mut self.far else { return (Vec::new(), near_rhs) };
        let (m, n_i) = (split.far_eqs.len(), split.n_interface);
        let n_f = m - n_i;
        let mut sweep = gather(b, n, &split.far_eqs, columns);
        for col in 0..columns {
            sweep[col * m + n_f..(col + 1) * m].iter_mut().for_each(|v| *v = 0.0);
        }
        far.llt.forward_in_place(MatMut::from_column_major_slice_mut(&mut sweep, m, columns));
        let w_i = Mat::<f64>::from_fn(n_i, columns, |a, col| sweep[col * m + n_f + a]);
        let mut tw = Mat::<f64>::zeros(n_i, columns);
        matmul(tw.as_mut(), Accum::Replace, far.block.as_ref(), w_i.as_ref(), 1.0, Par::Seq);
        let n_near = split.near_eqs.len();
        for col in 0..columns {
            for (a, &q) in split.interface_in_near.iter().enumerate() {
                near_rhs[col * n_near + q] += tw[(a, col)];
            }
        }
        (sweep, near_rhs)
    }

    /// x over the equations from the near solution x_N and the far sweep (z_F in its F rows):
    /// the far backward sweep of [z_F, Tᵀ x_I].
    fn far_backward(&mut self, mut sweep: Vec<f64>, x_near: &[f64], columns: usize) -> Vec<f64> {
        let split = &self.split;
        let n = self.is_near.len();
        let mut x = vec![0.0; n * columns];
        scatter(&mut x, n, &split.near_eqs, x_near, columns);
        let Some(far) = &mut self.far else { return x };
        let (m, n_i) = (split.far_eqs.len(), split.n_interface);
        let n_f = m - n_i;
        let n_near = split.near_eqs.len();
        let x_i = Mat::<f64>::from_fn(n_i, columns, |a, col| {
            x_near[col * n_near + split.interface_in_near[a]]
        });
        let mut t_x = Mat::<f64>::zeros(n_i, columns);
        matmul(t_x.as_mut(), Accum::Replace, far.block.transpose(), x_i.as_ref(), 1.0, Par::Seq);
        for col in 0..columns {
            (0..n_i).for_each(|a| sweep[col * m + n_f + a] = t_x[(a, col)]);
        }
        far.llt.backward_in_place(MatMut::from_column_major_slice_mut(&mut sweep, m, columns));
        scatter(&mut x, n, &split.far_eqs[..n_f], &far_rows(&sweep, m, n_f, columns), columns);
        x
    }

    /// The number of F's equations: the head z_F of a split solve's w = [z_F, the near
    /// forward sweep].
    fn n_far_only(&self) -> usize {
        self.split.far_eqs.len() - self.split.n_interface
    }
}

/// The first `n_f` rows of each of `columns` columns of m rows.
fn far_rows(sweep: &[f64], m: usize, n_f: usize, columns: usize) -> Vec<f64> {
    (0..columns).flat_map(|col| sweep[col * m..col * m + n_f].iter().copied()).collect()
}

/// The rows `eqs` of `columns` columns of n rows.
fn gather(b: &[f64], n: usize, eqs: &[usize], columns: usize) -> Vec<f64> {
    (0..columns).flat_map(|col| eqs.iter().map(move |&e| b[col * n + e])).collect()
}

/// x's rows `eqs` (of `columns` columns of n rows) set from `part`.
fn scatter(x: &mut [f64], n: usize, eqs: &[usize], part: &[f64], columns: usize) {
    let m = eqs.len();
    for col in 0..columns {
        eqs.iter().enumerate().for_each(|(i, &e)| x[col * n + e] = part[col * m + i]);
    }
}

/// The split, the far factor (none when N is every equation) and the near factor of `lower`
/// for the near equations `is_near`.
fn build(
    lower: &SparseColMat<usize, f64>,
    map: &DofMap,
    graph: &Graph,
    is_near: &[bool],
    n_trailing: usize,
) -> Result<(Split, Option<Far>, FaerLlt)> {
    let n = lower.nrows();
    let first_trailing = n - n_trailing;
    // I: near equations with a far neighbour, in the global order.
    let interface: Vec<usize> = (0..n)
        .filter(|&i| is_near[i] && graph.neighbours(i).iter().any(|&j| !is_near[j]))
        .collect();
    let far_only: Vec<usize> = (0..n).filter(|&i| !is_near[i]).collect();
    let far_eqs: Vec<usize> = fill_reducing(graph, &far_only, &interface, &[])
        .into_iter()
        .chain(interface.iter().copied())
        .collect();
    let near_leading: Vec<usize> = (0..first_trailing).filter(|&i| is_near[i]).collect();
    let trailing: Vec<usize> = (first_trailing..n).collect();
    let near_eqs: Vec<usize> = fill_reducing(graph, &near_leading, &trailing, &[&interface])
        .into_iter()
        .chain(trailing.iter().copied())
        .collect();
    let near_local = local_of(&near_eqs, n);
    let interface_in_near: Vec<usize> = interface.iter().map(|&e| near_local[e]).collect();
    let (near_pattern, near_of_k, clique_in_near) =
        restricted(lower, &near_local, near_eqs.len(), &interface_in_near);
    let split = Split {
        far_eqs,
        n_interface: interface.len(),
        near_eqs,
        interface_in_near,
        near_pattern,
        near_of_k,
        clique_in_near,
    };
    let far = (!far_only.is_empty()).then(|| build_far(lower, map, &split)).transpose()?;
    let near = FaerLlt::new(
        &near_matrix(&split, far.as_ref(), lower),
        &sub_map(map, &split.near_eqs),
        n_trailing,
    )?;
    Ok((split, far, near))
}

/// The far factor of M = [K_FF K_FI; K_IF K_II] and C = K_II − T Tᵀ.
fn build_far(lower: &SparseColMat<usize, f64>, map: &DofMap, split: &Split) -> Result<Far> {
    let n = lower.nrows();
    let m = split.far_eqs.len();
    let far_local = local_of(&split.far_eqs, n);
    let (pattern, far_of_k, _) = restricted(lower, &far_local, m, &[]);
    let mut values = vec![0.0; pattern.row_idx().len()];
    let mut frozen = Vec::new();
    for (p, &v) in lower.val().iter().enumerate() {
        if far_of_k[p] != NONE {
            values[far_of_k[p]] = v;
        }
        if split.near_of_k[p] == NONE {
            frozen.push((p, v));
        }
    }
    let llt = FaerLlt::new(
        &SparseColMat::new(pattern.clone(), values.clone()),
        &sub_map(map, &split.far_eqs),
        split.n_interface,
    )?;
    let block = llt.trailing_block();
    let n_i = split.n_interface;
    let mut coupling = Mat::<f64>::zeros(n_i, n_i);
    matmul(coupling.as_mut(), Accum::Replace, block.as_ref(), block.transpose(), -1.0, Par::Seq);
    // + K_II, from M's trailing columns.
    let (ptr, rows) = (pattern.col_ptr(), pattern.row_idx());
    let n_f = m - n_i;
    for c in n_f..m {
        for p in ptr[c]..ptr[c + 1] {
            coupling[(rows[p] - n_f, c - n_f)] += values[p];
        }
    }
    Ok(Far { llt, block, coupling, frozen })
}

/// S = K_NN − C: K's entries in N × N, C's lower triangle subtracted on the I clique.
fn near_matrix(
    split: &Split,
    far: Option<&Far>,
    lower: &SparseColMat<usize, f64>,
) -> SparseColMat<usize, f64> {
    let mut values = vec![0.0; split.near_pattern.row_idx().len()];
    for (p, &v) in lower.val().iter().enumerate() {
        if split.near_of_k[p] != NONE {
            values[split.near_of_k[p]] += v;
        }
    }
    if let Some(far) = far {
        for a in 0..split.n_interface {
            for b in 0..=a {
                values[split.clique_in_near[a * (a + 1) / 2 + b]] -= far.coupling[(a, b)];
            }
        }
    }
    SparseColMat::new(split.near_pattern.clone(), values)
}

/// local[e] = i for e = eqs[i] (NONE for the other equations of n).
fn local_of(eqs: &[usize], n: usize) -> Vec<usize> {
    let mut local = vec![NONE; n];
    eqs.iter().enumerate().for_each(|(i, &e)| local[e] = i);
    local
}

/// The map of a factor's own equations `eqs` (for its messages: which DOF each is).
fn sub_map(map: &DofMap, eqs: &[usize]) -> DofMap {
    DofMap {
        role: Vec::new(),
        n_equations: eqs.len(),
        dof_of_equation: eqs.iter().map(|&e| map.dof_of_equation[e]).collect(),
        dim: map.dim,
        wide_separators: map.wide_separators,
    }
}

/// The lower triangle of K restricted to m equations (K's equation e is local[e], NONE where
/// left out), with every entry among the local equations `clique` added: its pattern, the
/// position of each of K's values in it (NONE outside), and of each clique entry (a ≥ b by
/// position in `clique`, at a(a+1)/2 + b).
fn restricted(
    lower: &SparseColMat<usize, f64>,
    local: &[usize],
    m: usize,
    clique: &[usize],
) -> (SymbolicSparseColMat<usize>, Vec<usize>, Vec<usize>) {
    let (ptr, rows) = (lower.symbolic().col_ptr(), lower.symbolic().row_idx());
    let nnz = rows.len();
    // (column, row, source): a source below nnz is K's value, above it a clique entry.
    let mut entries: Vec<(usize, usize, usize)> =
        Vec::with_capacity(nnz + clique.len() * (clique.len() + 1) / 2);
    for c in 0..lower.ncols() {
        for p in ptr[c]..ptr[c + 1] {
            let (lr, lc) = (local[rows[p]], local[c]);
            if lr != NONE && lc != NONE {
                entries.push((lr.min(lc), lr.max(lc), p));
            }
        }
    }
    for (a, &qa) in clique.iter().enumerate() {
        for (b, &qb) in clique[..=a].iter().enumerate() {
            entries.push((qa.min(qb), qa.max(qb), nnz + a * (a + 1) / 2 + b));
        }
    }
    entries.sort_unstable();
    let mut col_ptr = vec![0usize; m + 1];
    let mut row_idx = Vec::with_capacity(entries.len());
    let mut k_position = vec![NONE; nnz];
    let mut clique_position = vec![NONE; clique.len() * (clique.len() + 1) / 2];
    let mut last = (NONE, NONE);
    for &(c, r, source) in &entries {
        if (c, r) != last {
            row_idx.push(r);
            col_ptr[c + 1] += 1;
            last = (c, r);
        }
        let position = row_idx.len() - 1;
        if source < nnz {
            k_position[source] = position;
        } else {
            clique_position[source - nnz] = position;
        }
    }
    (0..m).for_each(|c| col_ptr[c + 1] += col_ptr[c]);
    (SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx), k_position, clique_position)
}

/// The equations `eqs` in a fill-reducing order: AMD on K's graph among them and the
/// equations `last` that will follow them, with `last` and each of `cliques` joined into a
/// clique (the dense blocks they become in the factor).
fn fill_reducing(graph: &Graph, eqs: &[usize], last: &[usize], cliques: &[&[usize]]) -> Vec<usize> {
    // Local numbering: eqs, then the equations only in the cliques (ordered after, dropped).
    let mut index: std::collections::HashMap<usize, usize> =
        eqs.iter().enumerate().map(|(i, &e)| (e, i)).collect();
    let mut all = eqs.to_vec();
    for &e in last.iter().chain(cliques.iter().flat_map(|c| c.iter())) {
        index.entry(e).or_insert_with(|| {
            all.push(e);
            all.len() - 1
        });
    }
    let m = all.len();
    let mut edges: Vec<Pair<usize, usize>> = (0..m).map(|i| Pair::new(i, i)).collect();
    for (i, &e) in all.iter().enumerate() {
        for j in graph.neighbours(e).iter().filter_map(|f| index.get(f)).filter(|&&j| j < i) {
            edges.push(Pair::new(i, *j));
        }
    }
    for clique in cliques.iter().copied().chain([last]) {
        let ids: Vec<usize> = clique.iter().map(|e| index[e]).collect();
        for (k, &a) in ids.iter().enumerate() {
            ids[..k].iter().for_each(|&b| edges.push(Pair::new(a.max(b), a.min(b))));
        }
    }
    let (pattern, _) = SymbolicSparseColMat::try_new_from_indices(m, m, &edges)
        .expect("indices within the local numbering");
    let (mut fwd, mut inv) = (vec![0usize; m], vec![0usize; m]);
    let mut mem =
        MemBuffer::new(amd::order_maybe_unsorted_scratch::<usize>(m, pattern.compute_nnz()));
    amd::order_maybe_unsorted(
        &mut fwd,
        &mut inv,
        pattern.as_ref(),
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .expect("AMD of a valid pattern");
    fwd.into_iter().filter(|&i| i < eqs.len()).map(|i| eqs[i]).collect()
}

impl Backend for Condensed {
    /// Factor S again, after growing the region and rebuilding the far factor where an entry
    /// of K outside N × N changed.
    fn factor(&mut self, lower: &SparseColMat<usize, f64>, map: &DofMap) -> Result<()> {
        let changed = self.changed_outside(lower);
        if !changed.is_empty() {
            let size = self.is_near.iter().filter(|&&x| x).count();
            self.graph.grow(
                &mut self.is_near,
                &changed,
                self.hops,
                (GROWTH * size as f64) as usize,
            );
            (self.split, self.far, self.near) =
                build(lower, map, &self.graph, &self.is_near, self.n_trailing)?;
            self.n_far_builds += 1;
            return Ok(());
        }
        let s = near_matrix(&self.split, self.far.as_ref(), lower);
        self.near.factor(&s, &sub_map(map, &self.split.near_eqs))
    }

    /// A refactorization is the near factor's; a solve pair runs both factors' sweeps and the
    /// two products with T.
    fn work(&self) -> FactorWork {
        let near = self.near.work();
        let far = self.far.as_ref().map(|f| f.llt.work()).unwrap_or_default();
        let n_i = self.split.n_interface as f64;
        FactorWork {
            factorization_flops: near.factorization_flops,
            solve_pair_flops: near.solve_pair_flops + far.solve_pair_flops + 4.0 * n_i * n_i,
            equations: self.is_near.len() as f64,
        }
    }

    fn solve_in_place(&mut self, b: &mut [f64], columns: usize) {
        let (sweep, mut near_rhs) = self.far_forward(b, columns);
        self.near.solve_in_place(&mut near_rhs, columns);
        let x = self.far_backward(sweep, &near_rhs, columns);
        b.copy_from_slice(&x);
    }

    fn trailing_inverse(&mut self) -> Mat<f64> {
        self.near.trailing_inverse()
    }

    /// w = [z_F, the near forward sweep].
    fn forward(&mut self, b: &[f64]) -> Vec<f64> {
        let (sweep, near_rhs) = self.far_forward(b, 1);
        let n_f = self.n_far_only();
        let mut w = far_rows(&sweep, self.split.far_eqs.len(), n_f, 1);
        w.extend(self.near.forward(&near_rhs));
        w
    }

    fn trailing_solution(&self, w: &[f64]) -> Vec<f64> {
        self.near.trailing_solution(&w[self.n_far_only()..])
    }

    fn add_trailing_force(&self, w: &mut [f64], f: &[f64]) {
        let n_f = self.n_far_only();
        self.near.add_trailing_force(&mut w[n_f..], f);
    }

    fn n_builds(&self) -> usize {
        self.n_far_builds
    }

    fn backward(&mut self, w: Vec<f64>) -> Vec<f64> {
        let n_f = self.n_far_only();
        let x_near = self.near.backward(w[n_f..].to_vec());
        let mut sweep = w[..n_f].to_vec();
        sweep.resize(self.split.far_eqs.len(), 0.0);
        self.far_backward(sweep, &x_near, 1)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{cantilever, check_contract_of, times};
    use super::super::Factor;
    use super::*;

    /// With 2 hops the cantilever's free-end region leaves a far field and an interface, so the
    /// contract's solves go through both factors.
    #[test]
    fn the_condensed_backend_honours_the_contract() {
        let (k, map, t) = cantilever();
        let c = Condensed::new(&k, &map, t, 2).unwrap();
        assert!(
            c.far.is_some() && c.split.n_interface > 0 && c.split.near_eqs.len() < map.n_equations
        );
        check_contract_of("condensed", |k, map, t| {
            Factor::of(Box::new(Condensed::new(k, map, t, 2).unwrap()))
        });
    }

    /// K + α w wᵀ with w = (1, −1) on the two equations of a node (both in the pattern; SPD kept).
    fn stiffened(k: &SparseColMat<usize, f64>, a: usize, alpha: f64) -> SparseColMat<usize, f64> {
        let b = a + 1;
        let mut out = k.clone();
        let (ptr, rows) = (k.symbolic().col_ptr().to_vec(), k.symbolic().row_idx().to_vec());
        for (r, c, v) in [(a, a, alpha), (b, b, alpha), (b, a, -alpha)] {
            let p =
                (ptr[c]..ptr[c + 1]).find(|&p| rows[p] == r).expect("a node's equations couple");
            out.val_mut()[p] += v;
        }
        out
    }

    /// A refactorization after a change inside the region keeps the far factor, one after a
    /// change in the far field grows the region and rebuilds it; after each, solves and the
    /// split solve satisfy K x = b with K's own entries (to round-off: 1e-10 of the load), and
    /// G equals a plain Cholesky's of the same K.
    #[test]
    fn refactorizations_are_exact_inside_and_outside_the_region() {
        let (k, map, t) = cantilever();
        let n = map.n_equations;
        let mut c = Condensed::new(&k, &map, t, 2).unwrap();
        let interface: Vec<usize> =
            c.split.far_eqs[c.split.far_eqs.len() - c.split.n_interface..].to_vec();
        // A node's first equation (its x DOF) by whether it lies inside N off the interface, or in F.
        let node_where = |inside: bool, c: &Condensed| {
            (0..n - t - 1)
                .find(|&e| {
                    map.dof_of_equation[e] % 2 == 0
                        && map.dof_of_equation[e + 1] == map.dof_of_equation[e] + 1
                        && [e, e + 1]
                            .iter()
                            .all(|&q| c.is_near[q] == inside && !interface.contains(&q))
                })
                .unwrap()
        };
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let big = b.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let inside = stiffened(&k, node_where(true, &c), 300.0);
        let outside = stiffened(&inside, node_where(false, &c), 300.0);
        for (kk, builds) in [(&inside, 1), (&outside, 2)] {
            c.factor(kk, &map).unwrap();
            assert_eq!(c.n_far_builds, builds);
            let residual = |x: &[f64], b: &[f64]| {
                times(kk, x).iter().zip(b).fold(0.0f64, |a, (kx, bi)| a.max((kx - bi).abs()))
            };
            let mut x = b.clone();
            c.solve_in_place(&mut x, 1);
            assert!(
                residual(&x, &b) < 1e-10 * big,
                "build {builds}: residual {}",
                residual(&x, &b)
            );
            let g = c.trailing_inverse();
            let g_plain = FaerLlt::new(kk, &map, t).unwrap().trailing_inverse();
            for i in 0..t {
                for j in 0..t {
                    assert!(
                        (g[(i, j)] - g_plain[(i, j)]).abs() < 1e-10 * g_plain[(i, i)],
                        "build {builds}: G[{i},{j}]"
                    );
                }
            }
            let force: Vec<f64> = (0..t).map(|i| 1.0 - i as f64).collect();
            let mut w = c.forward(&b);
            c.add_trailing_force(&mut w, &force);
            let split = c.backward(w);
            let mut with_force = b.clone();
            (0..t).for_each(|i| with_force[n - t + i] += force[i]);
            assert!(residual(&split, &with_force) < 1e-10 * big, "build {builds}: split residual");
        }
    }
}
