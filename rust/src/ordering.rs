//! Fill-reducing orderings of the mesh's node graph for the Cholesky factor
//! (`linalg::DofMap::ordered`): approximate minimum degree (faer's AMD), and a geometric nested
//! dissection for meshes in space.
//!
//! Nested dissection: cut the nodes by a plane into two shares; the smallest set of nodes that
//! meets every edge across the plane (a minimum vertex cover of the cut, `smallest_cover`)
//! separates the rest into two parts with no edge between them; order each part the same way,
//! then the separator. The plane is the best of several (normals along the axes and the cube's
//! diagonals, 40, 50 or 60 % of the nodes below it), and a curved cut, a level set of the
//! graph distance from a peripheral node, competes with them (it follows a graded mesh's
//! shells): the one with the fewest separator nodes per 4 f (1 - f), f the share below.
//! Eliminating a part never fills into the other, so the fill is that of the separators'
//! dense blocks: for a 3D mesh of n nodes separators of O(n^{2/3}) nodes give O(n^{4/3})
//! entries in the factor and O(n²) flops, where minimum degree, which looks one elimination
//! ahead only, grows faster (measured in `DofMap::ordered`'s comment). Parts of at most `LEAF`
//! nodes are ordered by minimum degree.
//!
//! Measured on the Hertz sphere meshes' node graphs (`examples/ordering_work.rs`), METIS's
//! multilevel nested dissection (a yardstick, not a dependency) needs 0.75–0.78 of these flops
//! and 0.85 of these entries: its separators are refined where these are plane cuts.

use crate::error::Result;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::{Pair, SymbolicSparseColMat};

/// Parts of at most this many nodes are ordered by minimum degree.
const LEAF: usize = 128;

/// The shares of the nodes below the planes tried.
const SHARES: [f64; 3] = [0.4, 0.5, 0.6];

/// The normals of the planes tried: the axes and the diagonals of the cube.
const DIRECTIONS: [[f64; 3]; 7] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
    [1.0, 1.0, -1.0],
    [1.0, -1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// An undirected graph on nodes 0..m, its neighbour lists in compressed rows (no self loops).
pub struct NodeGraph {
    start: Vec<usize>,
    neighbours: Vec<usize>,
}

impl NodeGraph {
    /// The graph of the edges (a, b) (either direction; repeats allowed) on m nodes.
    pub fn new(m: usize, edges: &[(usize, usize)]) -> Self {
        let mut start = vec![0usize; m + 1];
        for &(a, b) in edges {
            if a != b {
                start[a + 1] += 1;
                start[b + 1] += 1;
            }
        }
        for i in 0..m {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut neighbours = vec![0usize; start[m]];
        for &(a, b) in edges.iter().filter(|(a, b)| a != b) {
            neighbours[fill[a]] = b;
            fill[a] += 1;
            neighbours[fill[b]] = a;
            fill[b] += 1;
        }
        // Each row sorted, its repeats dropped.
        let mut rows = Vec::with_capacity(neighbours.len() / 2);
        let mut row_start = Vec::with_capacity(m + 1);
        row_start.push(0);
        for i in 0..m {
            let row = &mut neighbours[start[i]..start[i + 1]];
            row.sort_unstable();
            let first = rows.len();
            for &v in row.iter() {
                if rows.len() == first || rows[rows.len() - 1] != v {
                    rows.push(v);
                }
            }
            row_start.push(rows.len());
        }
        let (start, neighbours) = (row_start, rows);
        NodeGraph { start, neighbours }
    }

    pub fn len(&self) -> usize {
        self.start.len() - 1
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn neighbours(&self, i: usize) -> &[usize] {
        &self.neighbours[self.start[i]..self.start[i + 1]]
    }
}

/// The minimum-degree (AMD) order of `graph`: `order[k]` is the k-th node to eliminate.
pub fn minimum_degree(graph: &NodeGraph) -> Result<Vec<usize>> {
    let m = graph.len();
    let mut entries: Vec<Pair<usize, usize>> = (0..m).map(|i| Pair::new(i, i)).collect();
    for a in 0..m {
        entries.extend(graph.neighbours(a).iter().filter(|&&b| b < a).map(|&b| Pair::new(a, b)));
    }
    let (pattern, _) = SymbolicSparseColMat::try_new_from_indices(m, m, &entries)
        .map_err(|e| crate::fail!(Internal, "could not analyse the mesh graph: {e:?}"))?;
    let (mut order, mut inverse) = (vec![0usize; m], vec![0usize; m]);
    let mut mem =
        MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(m, pattern.compute_nnz()))
            .map_err(|_| crate::fail!(Internal, "out of memory for the AMD ordering"))?;
    amd::order_maybe_unsorted(
        &mut order,
        &mut inverse,
        pattern.as_ref(),
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| crate::fail!(Internal, "the AMD ordering failed: {e:?}"))?;
    Ok(order)
}

/// The nested-dissection order of `graph` whose node i sits at `points[i]`: `order[k]` is the
/// k-th node to eliminate (see the module's documentation).
pub fn nested_dissection(graph: &NodeGraph, points: &[[f64; 3]]) -> Result<Vec<usize>> {
    let m = graph.len();
    let mut dissection = Dissection {
        graph,
        points,
        label: vec![0; m],
        next_label: 1,
        distance: vec![u32::MAX; m],
        local: vec![usize::MAX; m],
        order: Vec::with_capacity(m),
    };
    let mut nodes: Vec<usize> = (0..m).collect();
    dissection.dissect(&mut nodes)?;
    Ok(dissection.order)
}

/// The state of one nested dissection.
struct Dissection<'g> {
    graph: &'g NodeGraph,
    points: &'g [[f64; 3]],
    /// The part of the current split each node was put in (a fresh pair of labels per split).
    label: Vec<u32>,
    next_label: u32,
    /// Graph distances within the part being split (`measure_distance`).
    distance: Vec<u32>,
    /// A leaf's local numbering (usize::MAX elsewhere).
    local: Vec<usize>,
    order: Vec<usize>,
}

impl Dissection<'_> {
    /// Order `part` (its nodes permuted in place on the way): its two halves, then their
    /// separator.
    fn dissect(&mut self, part: &mut [usize]) -> Result<()> {
        if part.len() <= LEAF {
            return self.order_leaf(part);
        }
        // The cut of the fewest separator nodes per 4 f (1 - f) (see the module's documentation).
        let tries = (0..DIRECTIONS.len() + 1).flat_map(|key| SHARES.map(|share| (key, share)));
        let mut cost = |(key, share): (usize, f64)| {
            self.split(part, key, share).1.len() as f64 / (4.0 * share * (1.0 - share))
        };
        let best = tries
            .map(|t| (t, cost(t)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(t, _)| t)
            .unwrap_or((0, 0.5));
        let (low, cut) = self.split(part, best.0, best.1);
        let label = &self.label;
        part.sort_unstable_by_key(|&v| label[v]); // low half, high half, separator
        let n_low = part.iter().take_while(|&&v| label[v] == low).count();
        let (halves, _) = part.split_at_mut(part.len() - cut.len());
        let (first, second) = halves.split_at_mut(n_low);
        self.dissect(first)?;
        self.dissect(second)?;
        self.order.extend_from_slice(&cut);
        Ok(())
    }

    /// Split `part` with the `share` of its nodes lowest in `key` (k < 7: the coordinate along
    /// `DIRECTIONS[k]`; 7: the graph distance, `measure_distance`) below the cut, its nodes
    /// permuted: label the two sides, then the separator (a fresh increasing triple of labels),
    /// and return the low side's label and the separator.
    fn split(&mut self, part: &mut [usize], key: usize, share: f64) -> (u32, Vec<usize>) {
        let mid = (part.len() as f64 * share) as usize;
        if key == DIRECTIONS.len() {
            self.measure_distance(part);
            let distance = &self.distance;
            part.select_nth_unstable_by_key(mid, |&v| distance[v]);
        } else {
            let points = self.points;
            let along = |v: usize| (0..3).map(|c| DIRECTIONS[key][c] * points[v][c]).sum::<f64>();
            part.select_nth_unstable_by(mid, |&a, &b| along(a).total_cmp(&along(b)));
        }
        let (low, high, separator) = (self.next_label, self.next_label + 1, self.next_label + 2);
        self.next_label += 3;
        part[..mid].iter().for_each(|&v| self.label[v] = low);
        part[mid..].iter().for_each(|&v| self.label[v] = high);
        let low_boundary = self.touching(&part[..mid], high);
        let high_boundary = self.touching(&part[mid..], low);
        let cut = self.smallest_cover(&low_boundary, &high_boundary, high);
        cut.iter().for_each(|&v| self.label[v] = separator);
        (low, cut)
    }

    /// `distance` over `part`: the number of edges from a peripheral node of `part` (the
    /// farthest from the farthest from its first node) within `part`; a node not reached
    /// (another component) gets u32::MAX.
    fn measure_distance(&mut self, part: &[usize]) {
        let member = self.next_label;
        self.next_label += 1;
        part.iter().for_each(|&v| self.label[v] = member);
        let mut start = part[0];
        for _ in 0..2 {
            part.iter().for_each(|&v| self.distance[v] = u32::MAX);
            self.distance[start] = 0;
            let mut queue = vec![start];
            let mut head = 0;
            while head < queue.len() {
                let v = queue[head];
                head += 1;
                for &w in self.graph.neighbours(v) {
                    if self.label[w] == member && self.distance[w] == u32::MAX {
                        self.distance[w] = self.distance[v] + 1;
                        queue.push(w);
                    }
                }
            }
            start = queue[queue.len() - 1];
        }
    }

    /// The nodes of `side` with a neighbour labelled `other`.
    fn touching(&self, side: &[usize], other: u32) -> Vec<usize> {
        side.iter()
            .copied()
            .filter(|&v| self.graph.neighbours(v).iter().any(|&w| self.label[w] == other))
            .collect()
    }

    /// A smallest set of nodes that meets every edge between `a` and `b` (the nodes of the two
    /// halves that touch the other half, `b`'s labelled `b_label`): a minimum vertex cover of
    /// that bipartite graph, by König's theorem from a maximum matching (augmenting paths,
    /// breadth first): the nodes of `a` not reachable from an unmatched node of `a` by
    /// alternating paths, and those of `b` that are.
    fn smallest_cover(&mut self, a: &[usize], b: &[usize], b_label: u32) -> Vec<usize> {
        b.iter().enumerate().for_each(|(k, &v)| self.local[v] = k);
        let (graph, label, local) = (self.graph, &self.label, &self.local);
        let edges: Vec<Vec<usize>> = a
            .iter()
            .map(|&v| {
                graph
                    .neighbours(v)
                    .iter()
                    .filter(|&&w| label[w] == b_label)
                    .map(|&w| local[w])
                    .collect()
            })
            .collect();
        b.iter().for_each(|&v| self.local[v] = usize::MAX);
        let (mut mate_of_a, mut mate_of_b) = (vec![usize::MAX; a.len()], vec![usize::MAX; b.len()]);
        let mut reached_by = vec![usize::MAX; b.len()]; // the node of `a` a search reached it from
        let mut seen = vec![usize::MAX; b.len()]; // the search that reached it
        let mut queue = Vec::new();
        for root in 0..a.len() {
            queue.clear();
            queue.push(root);
            let mut head = 0;
            let mut free = None;
            'search: while head < queue.len() {
                let x = queue[head];
                head += 1;
                for &y in &edges[x] {
                    if seen[y] == root {
                        continue;
                    }
                    (seen[y], reached_by[y]) = (root, x);
                    if mate_of_b[y] == usize::MAX {
                        free = Some(y);
                        break 'search;
                    }
                    queue.push(mate_of_b[y]);
                }
            }
            // Augment along the path root → … → free.
            let mut y = free;
            while let Some(j) = y {
                let x = reached_by[j];
                let previous = mate_of_a[x];
                (mate_of_a[x], mate_of_b[j]) = (j, x);
                y = (previous != usize::MAX).then_some(previous);
            }
        }
        // The alternating paths from the unmatched nodes of `a`.
        let (mut in_a, mut in_b) = (vec![false; a.len()], vec![false; b.len()]);
        let mut stack: Vec<usize> = (0..a.len()).filter(|&x| mate_of_a[x] == usize::MAX).collect();
        stack.iter().for_each(|&x| in_a[x] = true);
        while let Some(x) = stack.pop() {
            for &y in &edges[x] {
                if !in_b[y] {
                    in_b[y] = true;
                    let z = mate_of_b[y];
                    if z != usize::MAX && !in_a[z] {
                        in_a[z] = true;
                        stack.push(z);
                    }
                }
            }
        }
        let from_a = a.iter().zip(&in_a).filter(|(_, &r)| !r).map(|(&v, _)| v);
        from_a.chain(b.iter().zip(&in_b).filter(|(_, &r)| r).map(|(&v, _)| v)).collect()
    }

    /// A small part in its minimum-degree order.
    fn order_leaf(&mut self, part: &[usize]) -> Result<()> {
        if part.is_empty() {
            return Ok(()); // (a side the separator took whole)
        }
        part.iter().enumerate().for_each(|(k, &v)| self.local[v] = k);
        let mut edges = Vec::new();
        for (k, &v) in part.iter().enumerate() {
            edges.extend(
                self.graph
                    .neighbours(v)
                    .iter()
                    .map(|&w| self.local[w])
                    .filter(|&l| l != usize::MAX && l < k)
                    .map(|l| (k, l)),
            );
        }
        let order = minimum_degree(&NodeGraph::new(part.len(), &edges))?;
        self.order.extend(order.iter().map(|&k| part[k]));
        part.iter().for_each(|&v| self.local[v] = usize::MAX);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::dim::Spatial;
    use crate::element::Tet4;
    use crate::factor::faer_llt::{symbolic_analysis, work_of};
    use crate::linalg::{DofMap, DofRole, NodeOrder, StiffnessPattern};
    use crate::mesh::Mesh;

    /// The unit cube cut into k³ cubes of 6 tetrahedra each (Freudenthal's split along the
    /// diagonal (0,0,0)-(1,1,1)): (k + 1)³ nodes.
    fn cube(k: usize) -> Mesh<Spatial> {
        let id = |i: usize, j: usize, l: usize| (l * (k + 1) + j) * (k + 1) + i;
        let h = 1.0 / k as f64;
        let points = (0..(k + 1).pow(3))
            .map(|n| {
                [
                    (n % (k + 1)) as f64 * h,
                    (n / (k + 1) % (k + 1)) as f64 * h,
                    (n / (k + 1).pow(2)) as f64 * h,
                ]
            })
            .collect();
        let mut tets = Vec::new();
        for (i, j, l) in
            (0..k).flat_map(|l| (0..k).flat_map(move |j| (0..k).map(move |i| (i, j, l))))
        {
            let corner = |d: [usize; 3]| id(i + d[0], j + d[1], l + d[2]);
            // The six monotone paths from (0,0,0) to (1,1,1), one per order of the axes.
            for axes in [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
                let mut d = [0; 3];
                let mut tet = [corner(d); 4];
                for (s, &a) in axes.iter().enumerate() {
                    d[a] = 1;
                    tet[s + 1] = corner(d);
                }
                tets.push(tet);
            }
        }
        Mesh::<Spatial>::new(points, tets)
    }

    fn map_of(
        mesh: &Mesh<Spatial>,
        fixed: &[bool],
        trailing: &[usize],
        how: NodeOrder,
    ) -> (Vec<Tet4>, DofMap) {
        let elements: Vec<Tet4> = (0..mesh.n_elements()).map(|e| Tet4::new(mesh, e)).collect();
        let map =
            DofMap::ordered_by(&elements, 3 * mesh.n_nodes(), fixed, &[], trailing, how).unwrap();
        (elements, map)
    }

    /// The factorization flops of K_reg's pattern in the map's order (symbolic analysis only).
    fn flops(elements: &[Tet4], map: &DofMap) -> f64 {
        let pattern = StiffnessPattern::new(elements, map).unwrap();
        work_of(&symbolic_analysis(&pattern.with_values(vec![0.0; pattern.nnz()])).unwrap())
            .factorization_flops
    }

    /// Nested dissection numbers every equation once, fixed DOFs none, and ends with the
    /// trailing DOFs in their given order (the factor's trailing block reads G from them).
    #[test]
    fn nested_dissection_is_a_permutation_with_the_trailing_dofs_last() {
        let mesh = cube(8);
        let n_dofs = 3 * mesh.n_nodes();
        // The face z = 0 held; the face z = 1 in contact: its normal DOFs trailing, listed
        // against the nodes' order, and the x DOFs of its first row too (a frictional pair's).
        let fixed: Vec<bool> = (0..n_dofs).map(|d| mesh.nodes[d / 3][2] == 0.0).collect();
        let top: Vec<usize> =
            (0..mesh.n_nodes()).rev().filter(|&n| mesh.nodes[n][2] == 1.0).collect();
        let trailing: Vec<usize> = top
            .iter()
            .map(|&n| 3 * n + 2)
            .chain(top.iter().filter(|&&n| mesh.nodes[n][1] == 0.0).map(|&n| 3 * n))
            .collect();
        let (_, map) = map_of(&mesh, &fixed, &trailing, NodeOrder::NestedDissection(&mesh.nodes));
        let n_free = fixed.iter().filter(|&&f| !f).count();
        assert_eq!(map.n_equations, n_free);
        let mut seen = vec![false; n_free];
        for (d, role) in map.role.iter().enumerate() {
            match *role {
                DofRole::Equation(e) => {
                    assert!(!fixed[d] && !seen[e], "DOF {d}: equation {e} fixed or given twice");
                    seen[e] = true;
                }
                _ => assert!(fixed[d], "free DOF {d} has no equation"),
            }
        }
        let first = n_free - trailing.len();
        for (k, &d) in trailing.iter().enumerate() {
            assert_eq!(map.equation(d), Some(first + k), "trailing DOF {d}");
        }
    }

    /// On a cube of 16³ cells, nested dissection's factorization takes at most 0.75 of the
    /// flops of minimum degree, with no trailing DOFs and with a face's normal DOFs trailing.
    /// Theory for a k³ grid: the separators' dense blocks give O(n²) flops (n = k³ nodes);
    /// minimum degree, which looks one elimination ahead, has no such bound in 3D. Measured
    /// here: 0.59 (no trailing) and 0.58 (trailing), and the gap grows with k (0.51 on the
    /// 88k-equation sphere mesh, `DofMap::ordered`). 0.75 leaves room for another AMD
    /// tie-break and still fails a dissection that lost a third of its advantage (separators
    /// two grid layers thick would double the top block and its flops eightfold).
    #[test]
    fn nested_dissection_factors_a_cube_with_fewer_flops_than_minimum_degree() {
        let mesh = cube(16);
        let n_dofs = 3 * mesh.n_nodes();
        let fixed: Vec<bool> = (0..n_dofs).map(|d| mesh.nodes[d / 3][2] == 0.0).collect();
        let top: Vec<usize> =
            (0..mesh.n_nodes()).filter(|&n| mesh.nodes[n][2] == 1.0).map(|n| 3 * n + 2).collect();
        for trailing in [vec![], top] {
            let (elements, amd) = map_of(&mesh, &fixed, &trailing, NodeOrder::MinimumDegree);
            let (_, nd) =
                map_of(&mesh, &fixed, &trailing, NodeOrder::NestedDissection(&mesh.nodes));
            let ratio = flops(&elements, &nd) / flops(&elements, &amd);
            assert!(
                ratio < 0.75,
                "{} trailing DOFs: nested dissection / minimum degree flops = {ratio:.3}",
                trailing.len()
            );
        }
    }
}
