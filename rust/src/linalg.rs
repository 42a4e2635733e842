//! Sparse linear algebra: the reduced stiffness, its equations and its pattern (the factor:
//! `factor`).
//!
//! Supports (u = 0) are eliminated. A body that is held only by contact (the paper's cylinder
//! on the flat, a block on a foundation) has rigid-body modes left in K; for those a few
//! "pinned" DOFs are removed as well, which turns K into an SPD matrix K_reg. Solving with
//! K_reg and setting the pinned DOFs to zero applies a generalized inverse K# (K K# K = K);
//! the rigid-body amplitudes are then found together with the contact multipliers
//! (see `driver`), so the big factor stays SPD and is never refactorized for a contact event.

use crate::bail;
use crate::dim::Dim;
use crate::element::Element;
use crate::error::Result;
use crate::mesh::Mesh;
use crate::ordering::{self, NodeGraph};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use nalgebra::{Matrix6, SMatrix};

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
    /// The global DOF of each equation.
    pub dof_of_equation: Vec<usize>,
    /// DOFs per node (messages name the node and component).
    pub dim: usize,
    /// The order's separators are surfaces (`Dim::WIDE_SEPARATORS`): its large dense
    /// supernodes make a large factorization pay for threads.
    pub wide_separators: bool,
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
        DofMap::with_roles(role, n)
    }

    fn with_roles(role: Vec<DofRole>, n_equations: usize) -> Self {
        let mut dof_of_equation = vec![0; n_equations];
        for (d, r) in role.iter().enumerate() {
            if let DofRole::Equation(i) = r {
                dof_of_equation[*i] = d;
            }
        }
        DofMap { role, n_equations, dof_of_equation, dim: 2, wide_separators: false }
    }

    pub fn equation(&self, dof: usize) -> Option<usize> {
        match self.role[dof] {
            DofRole::Equation(i) => Some(i),
            _ => None,
        }
    }

    /// The equations' entries of a vector over all DOFs.
    pub fn to_equations(&self, v: &[f64]) -> Vec<f64> {
        self.dof_of_equation.iter().map(|&d| v[d]).collect()
    }

    /// A vector over all DOFs from its equations' entries (0 at fixed and pinned DOFs).
    pub fn from_equations(&self, x: &[f64]) -> Vec<f64> {
        let mut v = vec![0.0; self.role.len()];
        self.dof_of_equation.iter().zip(x).for_each(|(&d, &xi)| v[d] = xi);
        v
    }

    /// Equations numbered in the order of the Cholesky factor, so that the factor needs no
    /// permutation: a fill-reducing order (AMD on the mesh's node graph, both DOFs of a node
    /// together, the nodes with a `trailing` DOF joined into a clique) of the nodes that carry
    /// no trailing DOF, then the other equations of those that do, then the `trailing` DOFs in
    /// the order given: they end the factor (`factor::Backend::trailing_inverse`). Measured on the Hertz meshes, the
    /// clique cuts the factorization flops by 5 % (8.6k DOFs) and 14 % (24k) against AMD on
    /// the graph without the trailing nodes; keeping them last still costs +42 % (8.6k) and
    /// +22 % (24k) flops against plain AMD: the price of reading the contact flexibility from
    /// the factor. (The clique has O(t²) entries, as the flexibility matrix itself.)
    ///
    /// In space the trailing DOFs are a frictionless pair's normal DOF alone, and moving their
    /// nodes' other DOFs last too would triple the dense last block: there AMD orders the node
    /// graph without the clique, the trailing DOFs alone are taken out of its order and put
    /// last, their nodes' other DOFs staying where AMD put them. Measured on hertz_sphere_3d at
    /// 57.4k equations and 982 pairs: 4.01e11 -> 2.66e11 factorization flops, nnz(L) 9.09e7 ->
    /// 7.48e7, the last supernode 8547 -> 6349 columns (plain AMD without trailing DOFs: 1.99e11).
    /// Every trailing DOF must be an equation (neither fixed nor pinned).
    ///
    /// This is the plane and axisymmetric order; meshes in space of `DISSECTION_FROM` nodes or
    /// more take nested dissection (`ordered_by`, `NodeOrder::of_mesh`, `ordering`). Measured on the Hertz sphere's eighth
    /// (`examples/ordering_work.rs`, symbolic analysis; minimum degree -> nested dissection),
    /// the contact nodes' normal DOFs trailing: 88.3k equations 6.65e11 -> 2.67e11 flops,
    /// nnz(L) 1.44e8 -> 9.34e7; 280k (a/h = 31) 4.37e12 -> 1.32e12, 6.14e8 -> 3.52e8; 937k
    /// (a/h = 40) 5.15e13 -> 1.52e13, 3.72e9 -> 1.93e9. With their three DOFs trailing
    /// (friction) 88.3k: 9.48e11 -> 4.85e11; 937k: 5.79e13 -> 1.78e13.
    pub fn ordered<E: Element<S, N>, const S: usize, const N: usize>(
        elements: &[E],
        n_dofs: usize,
        fixed: &[bool],
        pinned: &[usize],
        trailing: &[usize],
    ) -> Result<Self> {
        Self::ordered_by(elements, n_dofs, fixed, pinned, trailing, NodeOrder::MinimumDegree)
    }

    /// `ordered` with the nodes' order chosen by `how`. Nested dissection leaves out of its
    /// graph the nodes whose every equation is trailing: they end the factor anyway.
    pub fn ordered_by<E: Element<S, N>, const S: usize, const N: usize>(
        elements: &[E],
        n_dofs: usize,
        fixed: &[bool],
        pinned: &[usize],
        trailing: &[usize],
        how: NodeOrder,
    ) -> Result<Self> {
        let dim = E::DIM;
        let node_dofs = move |n: usize| (0..dim).map(move |c| dim * n + c);
        let mut is_pinned = vec![false; n_dofs];
        pinned.iter().for_each(|&d| is_pinned[d] = true);
        let is_equation = |d: usize| !fixed[d] && !is_pinned[d];
        let mut role: Vec<DofRole> = (0..n_dofs)
            .map(|d| if is_pinned[d] && !fixed[d] { DofRole::Pinned } else { DofRole::Fixed })
            .collect();
        let n_nodes = n_dofs / dim;
        let mut is_trailing = vec![false; n_dofs];
        trailing.iter().for_each(|&d| is_trailing[d] = true);
        let mut node_is_trailing = vec![false; n_nodes];
        trailing.iter().for_each(|&d| node_is_trailing[d / dim] = true);
        // (Plane and axisymmetric: the trailing nodes joined into a clique, their DOFs all last.)
        let clique = <E::Space as Dim>::TRAILING_CLIQUE;
        let dissected = matches!(how, NodeOrder::NestedDissection(_));
        let in_graph =
            |n: usize| node_dofs(n).any(|d| is_equation(d) && !(dissected && is_trailing[d]));
        // The node graph, renumbered 0..m.
        let mut index = vec![usize::MAX; n_nodes];
        let graph_nodes: Vec<usize> = (0..n_nodes).filter(|&n| in_graph(n)).collect();
        graph_nodes.iter().enumerate().for_each(|(i, &n)| index[n] = i);
        let ends: Vec<usize> = graph_nodes
            .iter()
            .filter(|&&n| clique && node_is_trailing[n])
            .map(|&n| index[n])
            .collect();
        let order =
            how.order(&node_graph(elements, &index, graph_nodes.len(), &ends), &graph_nodes)?;
        let leading_dofs = order
            .iter()
            .map(|&i| graph_nodes[i])
            .filter(|&n| !(clique && node_is_trailing[n]))
            .flat_map(node_dofs)
            .filter(|&d| !is_trailing[d]);
        // (A node left out of the dissection's graph has no equation but its trailing ones.)
        let rest = (0..n_nodes)
            .filter(|&n| clique && node_is_trailing[n])
            .flat_map(node_dofs)
            .filter(|&d| !is_trailing[d]);
        let mut n_equations = 0;
        for d in leading_dofs.chain(rest).chain(trailing.iter().copied()) {
            if is_equation(d) {
                role[d] = DofRole::Equation(n_equations);
                n_equations += 1;
            } else if is_trailing[d] {
                bail!(Internal, "internal: trailing DOF {d} is not an equation");
            }
        }
        let wide_separators = <E::Space as Dim>::WIDE_SEPARATORS;
        Ok(DofMap { dim, wide_separators, ..DofMap::with_roles(role, n_equations) })
    }
}

/// The node graph of `elements` over the nodes numbered by `index` (0..m; usize::MAX: left
/// out), two nodes joined where an element joins them, and the nodes `clique` all joined.
fn node_graph<E: Element<S, N>, const S: usize, const N: usize>(
    elements: &[E],
    index: &[usize],
    m: usize,
    clique: &[usize],
) -> NodeGraph {
    let mut edges = Vec::new();
    for el in elements {
        let ids: Vec<usize> =
            el.nodes().iter().map(|&n| index[n]).filter(|&i| i != usize::MAX).collect();
        for (k, &a) in ids.iter().enumerate() {
            edges.extend(ids[k + 1..].iter().map(|&b| (a, b)));
        }
    }
    for (k, &a) in clique.iter().enumerate() {
        edges.extend(clique[..k].iter().map(|&b| (a, b)));
    }
    NodeGraph::new(m, &edges)
}

/// How `DofMap::ordered_by` orders the nodes (`ordering`).
#[derive(Debug, Clone, Copy)]
pub enum NodeOrder<'a> {
    /// Approximate minimum degree on the node graph.
    MinimumDegree,
    /// Geometric nested dissection, the nodes at these points (a mesh in space).
    NestedDissection(&'a [[f64; 3]]),
}

/// Meshes in space of at least this many nodes are ordered by nested dissection. It already
/// saves 18 % of the flops at 7.5k nodes (hertz_sphere_3d, 20.7k equations; 35 % with
/// friction); below, a factorization takes a fraction of a second whichever the order, and
/// minimum degree keeps the round-off, hence the event histories, of small scenes as before.
const DISSECTION_FROM: usize = 3000;

impl<'a> NodeOrder<'a> {
    /// The order of `graph`, whose node i is the mesh's node `nodes[i]`.
    fn order(&self, graph: &NodeGraph, nodes: &[usize]) -> Result<Vec<usize>> {
        match *self {
            NodeOrder::MinimumDegree => ordering::minimum_degree(graph),
            NodeOrder::NestedDissection(points) => {
                let at: Vec<[f64; 3]> = nodes.iter().map(|&n| points[n]).collect();
                ordering::nested_dissection(graph, &at)
            }
        }
    }

    /// The order for `mesh` (`DISSECTION_FROM`; plane and axisymmetric meshes: minimum degree).
    pub fn of_mesh<D: Dim>(mesh: &'a Mesh<D>) -> Self {
        match D::in_space(&mesh.nodes) {
            Some(points) if points.len() >= DISSECTION_FROM => NodeOrder::NestedDissection(points),
            _ => NodeOrder::MinimumDegree,
        }
    }
}

/// The sparsity pattern of K_reg (lower triangle), built once from the mesh's node adjacency:
/// refilling it with new element tangents needs no sort (plastic runs refactorize often).
pub struct StiffnessPattern {
    symbolic: SymbolicSparseColMat<usize>,
}

/// Visit every lower-triangle entry (row, col, element, i, j) of the assembly, in a fixed order.
fn for_each_entry<const S: usize, const N: usize>(
    elements: &[impl Element<S, N>],
    map: &DofMap,
    mut f: impl FnMut(usize, usize, usize, usize, usize),
) {
    for (e, el) in elements.iter().enumerate() {
        let eqs = el.dofs().map(|g| map.equation(g));
        for i in 0..N {
            let Some(ri) = eqs[i] else { continue };
            for j in 0..N {
                let Some(cj) = eqs[j] else { continue };
                if ri >= cj {
                    f(ri, cj, e, i, j);
                }
            }
        }
    }
}

impl StiffnessPattern {
    /// Column by column from the node adjacency (two nodes couple when an element joins
    /// them; both DOFs of a node together): no sort of the 21 entries per element, which at
    /// 1M DOFs is ~40M index pairs and their argsort.
    pub fn new<E: Element<S, N>, const S: usize, const N: usize>(
        elements: &[E],
        map: &DofMap,
    ) -> Result<Self> {
        let n = map.n_equations;
        let dim = E::DIM;
        let n_nodes = map.role.len() / dim;
        // Neighbours of each node (itself included), compressed rows.
        let mut degree = vec![1usize; n_nodes + 1];
        for el in elements {
            el.nodes().iter().for_each(|&a| degree[a] += el.nodes().len() - 1);
        }
        let mut start = vec![0usize; n_nodes + 1];
        for a in 0..n_nodes {
            start[a + 1] = start[a] + degree[a];
        }
        let mut fill = start.clone();
        let mut neighbours = vec![0usize; start[n_nodes]];
        for a in 0..n_nodes {
            neighbours[fill[a]] = a;
            fill[a] += 1;
        }
        for el in elements {
            for (k, &a) in el.nodes().iter().enumerate() {
                for (l, &b) in el.nodes().iter().enumerate() {
                    if k != l {
                        neighbours[fill[a]] = b;
                        fill[a] += 1;
                    }
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(9 * n);
        col_ptr.push(0);
        let mut rows = Vec::new();
        for c in 0..n {
            let a = map.dof_of_equation[c] / dim;
            rows.clear();
            for &b in &neighbours[start[a]..fill[a]] {
                rows.extend((0..dim).filter_map(|k| map.equation(dim * b + k)).filter(|&r| r >= c));
            }
            rows.sort_unstable();
            rows.dedup();
            row_idx.extend_from_slice(&rows);
            col_ptr.push(row_idx.len());
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        Ok(StiffnessPattern { symbolic })
    }

    /// Position of entry (r, c), r ≥ c, among the values.
    fn position(&self, r: usize, c: usize) -> usize {
        let (col_ptr, row_idx) = (self.symbolic.col_ptr(), self.symbolic.row_idx());
        col_ptr[c]
            + row_idx[col_ptr[c]..col_ptr[c + 1]].binary_search(&r).expect("entry in the pattern")
    }

    /// Where each element's lower-triangle entries sit among the values of the assembled matrix
    /// (in the `assemble` order): the plastic loop re-adds only the elements whose tangent
    /// changed instead of reassembling all of them.
    pub fn element_scatter<const S: usize, const N: usize>(
        &self,
        elements: &[impl Element<S, N>],
        map: &DofMap,
    ) -> ElementScatter {
        let mut offsets = Vec::with_capacity(elements.len() + 1);
        let mut entries = Vec::with_capacity(elements.len() * 21);
        offsets.push(0);
        let mut current = 0;
        for_each_entry(elements, map, |r, c, e, i, j| {
            while current < e {
                offsets.push(entries.len());
                current += 1;
            }
            entries.push(ScatterEntry { position: self.position(r, c), local: (i as u8, j as u8) });
        });
        while offsets.len() <= elements.len() {
            offsets.push(entries.len());
        }
        ElementScatter { offsets, entries }
    }

    /// The number of stored entries (the lower triangle's).
    pub fn nnz(&self) -> usize {
        self.symbolic.compute_nnz()
    }

    /// The matrix with the pattern and the given values (in the pattern's storage order).
    pub fn with_values(&self, values: Vec<f64>) -> SparseColMat<usize, f64> {
        SparseColMat::new(self.symbolic.clone(), values)
    }

    /// Lower triangle of K_reg = Σ_e w Bᵀ D_e B over the equation DOFs (D_e: `Section::element_matrix`).
    pub fn assemble<const S: usize, const N: usize>(
        &self,
        elements: &[impl Element<S, N>],
        tangents: &[Matrix6<f64>],
        map: &DofMap,
    ) -> Result<SparseColMat<usize, f64>> {
        let mut values = vec![0.0; self.symbolic.row_idx().len()];
        // (for_each_entry visits the elements in turn: one element matrix at a time)
        let mut current: Option<(usize, SMatrix<f64, N, N>)> = None;
        for_each_entry(elements, map, |r, c, e, i, j| {
            if current.as_ref().map_or(true, |(k, _)| *k != e) {
                current = Some((e, elements[e].stiffness(&tangents[e])));
            }
            let ke = &current.as_ref().expect("set above").1;
            values[self.position(r, c)] += ke[(i, j)];
        });
        Ok(self.with_values(values))
    }
}

#[derive(Clone, Copy)]
struct ScatterEntry {
    position: usize,
    local: (u8, u8),
}

/// Positions of every element's stiffness entries in the assembled values (see
/// `StiffnessPattern::element_scatter`).
pub struct ElementScatter {
    offsets: Vec<usize>,
    entries: Vec<ScatterEntry>,
}

impl ElementScatter {
    /// values += the lower-triangle entries of element `e`'s 6 × 6 matrix `ke`.
    pub fn add<const N: usize>(&self, e: usize, ke: &SMatrix<f64, N, N>, values: &mut [f64]) {
        for entry in &self.entries[self.offsets[e]..self.offsets[e + 1]] {
            values[entry.position] += ke[(entry.local.0 as usize, entry.local.1 as usize)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{Planar, Spatial};
    use crate::element::Cst;
    use crate::factor::Factor;
    use crate::material::{Material, Plane};
    use crate::mesh::Mesh;
    use crate::options::Factorization;
    use crate::section::Section;

    /// Elastic D of E = 1000, ν = 0.3 as the plane's element pairs it with B.
    fn elastic_d(plane: Plane) -> nalgebra::Matrix6<f64> {
        Section::new(Material::elastic(1000.0, 0.3), plane.stress_state()).elastic_matrix()
    }

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
        let mesh = Mesh::<Planar>::new(nodes, triangles);
        let els: Vec<Cst> = (0..mesh.elements.len()).map(|e| Cst::planar(&mesh, e, 2.0)).collect();
        let d = elastic_d(Plane::Strain);
        let n = 2 * mesh.nodes.len();
        let mut k = nalgebra::DMatrix::<f64>::zeros(n, n);
        for el in &els {
            let ke = el.stiffness(&d);
            for (i, gi) in el.dofs().iter().enumerate() {
                for (j, gj) in el.dofs().iter().enumerate() {
                    k[(*gi, *gj)] += ke[(i, j)];
                }
            }
        }
        assert!((&k - k.transpose()).norm() < 1e-12 * k.norm());
        let map = DofMap::new(n, &vec![false; n], &[]);
        let lower = StiffnessPattern::new(&els, &map)
            .unwrap()
            .assemble(&els, &vec![d; els.len()], &map)
            .unwrap();
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
        let mesh = Mesh::<Planar>::new(nodes, triangles);
        let els: Vec<Cst> = (0..mesh.elements.len()).map(|e| Cst::planar(&mesh, e, 1.0)).collect();
        let d = elastic_d(Plane::Stress);
        let tangents = vec![d; els.len()];
        let mut fixed = vec![false; 18];
        for j in 0..3 {
            fixed[2 * (3 * j)] = true;
            fixed[2 * (3 * j) + 1] = true;
        }
        let map = DofMap::new(18, &fixed, &[]);
        let k = StiffnessPattern::new(&els, &map).unwrap().assemble(&els, &tangents, &map).unwrap();
        let mut s = Factor::new(Factorization::Faer, &k, &map, 0).unwrap();
        let rhs: Vec<f64> = (0..map.n_equations).map(|i| 1.0 + i as f64).collect();
        let mut x = rhs.clone();
        s.solve_in_place(&mut x, 1);
        // K x = b, with K applied from its stored lower triangle (round-off: 1e-10 of |b|).
        let dense = k.to_dense();
        let n = map.n_equations;
        for i in 0..n {
            let kx: f64 =
                (0..n).map(|j| if i >= j { dense[(i, j)] } else { dense[(j, i)] } * x[j]).sum();
            assert!((kx - rhs[i]).abs() < 1e-10 * n as f64, "row {i}: {kx} vs {}", rhs[i]);
        }
    }

    #[test]
    fn trailing_block_gives_the_flexibility_of_the_chosen_dofs() {
        // A 6x4-cell cantilever: G from the trailing block of the factor must equal K⁻¹
        // restricted to the chosen equations (here the free-end nodes, in scrambled order),
        // computed by full solves with unit loads, to round-off.
        let (nx, ny) = (7, 5);
        let mesh = crate::mesh::test_grid(nx, ny, 0.5, 0.4);
        let els: Vec<Cst> = (0..mesh.elements.len()).map(|e| Cst::planar(&mesh, e, 1.0)).collect();
        let d = elastic_d(Plane::Strain);
        let n_dofs = 2 * mesh.nodes.len();
        let mut fixed = vec![false; n_dofs];
        for j in 0..ny {
            fixed[2 * nx * j] = true;
            fixed[2 * nx * j + 1] = true;
        }
        let chosen_dofs: Vec<usize> = [3, 0, 4, 2, 1]
            .iter()
            .flat_map(|&j| [2 * (nx * j + nx - 1) + 1, 2 * (nx * j + nx - 1)])
            .collect();
        check_trailing_block(&els, n_dofs, &fixed, &chosen_dofs, d);
    }

    #[test]
    fn in_space_the_trailing_block_holds_the_chosen_dofs_alone() {
        // A 3x2x2-cube bar of tetrahedra (six per cube), fixed on x = 0; the chosen DOFs are the
        // z components of the free end's nodes, in scrambled order (as a frictionless pair's
        // normal DOF): they alone end the factor (their nodes' x and y DOFs come before), and
        // the flexibility and the split solve hold as in the plane.
        let (nx, ny, nz) = (4, 3, 3);
        let node = |i: usize, j: usize, k: usize| i + nx * (j + ny * k);
        let points = (0..nz)
            .flat_map(|k| {
                (0..ny).flat_map(move |j| {
                    (0..nx).map(move |i| [i as f64, 0.8 * j as f64, 0.6 * k as f64])
                })
            })
            .collect();
        let mut tetrahedra = vec![];
        for (i, j, k) in (0..nx - 1)
            .flat_map(|i| (0..ny - 1).flat_map(move |j| (0..nz - 1).map(move |k| (i, j, k))))
        {
            // Kuhn's six tetrahedra of a cube along its diagonal from corner 0 to corner 7.
            let c = |b: usize| node(i + (b & 1), j + ((b >> 1) & 1), k + (b >> 2));
            for path in [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]] {
                let t = [c(0), c(path[0]), c(path[1]), c(7)];
                tetrahedra.push(t);
            }
        }
        let mut mesh = Mesh::<Spatial>::new(points, tetrahedra);
        // Orient every tetrahedron positively (Kuhn's paths alternate in sign).
        for t in 0..mesh.elements.len() {
            let [a, b, c, d] = mesh.elements[t].map(|n| nalgebra::Vector3::from(mesh.nodes[n]));
            if (b - a).cross(&(c - a)).dot(&(d - a)) < 0.0 {
                mesh.elements[t].swap(1, 2);
            }
        }
        let els: Vec<crate::element::Tet4> =
            (0..mesh.elements.len()).map(|e| crate::element::Tet4::new(&mesh, e)).collect();
        let d =
            Section::new(Material::elastic(1000.0, 0.3), &crate::section::Solid).elastic_matrix();
        let n_dofs = 3 * mesh.nodes.len();
        let fixed: Vec<bool> = (0..n_dofs).map(|g| g / 3 % nx == 0).collect();
        let chosen_dofs: Vec<usize> = [(1, 2), (0, 0), (2, 1), (1, 0), (0, 2)]
            .iter()
            .map(|&(j, k)| 3 * node(nx - 1, j, k) + 2)
            .collect();
        let map = check_trailing_block(&els, n_dofs, &fixed, &chosen_dofs, d);
        let first_trailing = map.n_equations - chosen_dofs.len();
        assert!(chosen_dofs.iter().all(|&g| map.equation(g - 1).unwrap() < first_trailing
            && map.equation(g - 2).unwrap() < first_trailing));
    }

    /// The trailing block of the factor ordered with `chosen_dofs` last gives K⁻¹ restricted to
    /// them, and the split solve around forces on them is one full solve; returns the map.
    fn check_trailing_block<E: Element<S, N>, const S: usize, const N: usize>(
        els: &[E],
        n_dofs: usize,
        fixed: &[bool],
        chosen_dofs: &[usize],
        d: Matrix6<f64>,
    ) -> DofMap {
        let map = DofMap::ordered(els, n_dofs, fixed, &[], chosen_dofs).unwrap();
        let k = StiffnessPattern::new(els, &map)
            .unwrap()
            .assemble(els, &vec![d; els.len()], &map)
            .unwrap();
        let chosen: Vec<usize> = chosen_dofs.iter().map(|&g| map.equation(g).unwrap()).collect();
        // The chosen DOFs are the last equations, in the order given.
        let t = chosen.len();
        assert_eq!(chosen, (map.n_equations - t..map.n_equations).collect::<Vec<_>>());
        let mut s = Factor::new(Factorization::Faer, &k, &map, t).unwrap();
        let g = s.trailing_inverse();
        let n = map.n_equations;
        let mut b = vec![0.0; n * chosen.len()];
        for (c, &eq) in chosen.iter().enumerate() {
            b[c * n + eq] = 1.0;
        }
        s.solve_in_place(&mut b, chosen.len());
        let scale = (0..chosen.len()).map(|i| g[(i, i)]).fold(0.0, f64::max);
        for (c, _) in chosen.iter().enumerate() {
            for (r, &eq) in chosen.iter().enumerate() {
                assert!(
                    (g[(r, c)] - b[c * n + eq]).abs() < 1e-12 * scale,
                    "G[{r},{c}] = {} vs {}",
                    g[(r, c)],
                    b[c * n + eq]
                );
            }
        }

        // The split solve: forward sweep of a load y, the trailing part of K⁻¹y read from it,
        // a force f on the chosen DOFs added between the sweeps; the backward sweep must give
        // K⁻¹(y + f) as one full solve does (to round-off, relative to the largest entry).
        let y: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let f: Vec<f64> = (0..chosen.len()).map(|c| 1.0 + c as f64).collect();
        let mut full = y.clone();
        s.solve_in_place(&mut full, 1);
        let w = s.forward(&y);
        let at_chosen = s.trailing_solution(&w);
        let big = full.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (c, &eq) in chosen.iter().enumerate() {
            assert!(
                (at_chosen[c] - full[eq]).abs() < 1e-12 * big,
                "trailing part {c}: {} vs {}",
                at_chosen[c],
                full[eq]
            );
        }
        let mut with_force = y.clone();
        for (c, &eq) in chosen.iter().enumerate() {
            with_force[eq] += f[c];
        }
        s.solve_in_place(&mut with_force, 1);
        let mut w = w;
        s.add_trailing_force(&mut w, &f);
        let x = s.backward(w);
        let big = with_force.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for i in 0..n {
            assert!(
                (x[i] - with_force[i]).abs() < 1e-12 * big,
                "x[{i}] = {} vs {}",
                x[i],
                with_force[i]
            );
        }
        map
    }
}
