//! The factor's work under each node ordering, from the symbolic analysis alone (no numeric
//! factorization): a tetrahedron mesh read from raw little-endian files, its DOFs on the
//! planes x = 0 and y = 0 held normal to them (the eighth of a body), the given contact nodes'
//! DOFs trailing (all three with friction, the normal one without).
//!
//!     cargo run --release --example ordering_work -- PREFIX [frictionless] [numeric]
//!
//! `numeric` also times faer's factorization (analysis, numeric factor) of a matrix of that
//! pattern (diagonally dominant values: the work of a Cholesky does not depend on them).
//!
//! PREFIX.points (f64 × 3 per node), PREFIX.tets (u64 × 4 per tetrahedron), PREFIX.contact
//! (u64 node ids); `bench/large_3d.py --dump-mesh PREFIX --size SIZE` writes them.

use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::sparse::{Pair, SymbolicSparseColMat};
use faer::Side;
use slipstep_core::dim::Spatial;
use slipstep_core::element::Tet4;
use slipstep_core::factor::faer_llt::{symbolic_analysis, work_of, FaerLlt};
use slipstep_core::linalg::{DofMap, NodeOrder, StiffnessPattern};
use slipstep_core::mesh::Mesh;
use slipstep_core::ordering::{minimum_degree, nested_dissection, NodeGraph};
use std::time::Instant;

/// The work of the scalar node graph's factor in each node order: the orderings compared
/// without DOFs, supports or trailing block (METIS's from PREFIX.metis when it exists).
fn node_graph_work(mesh: &Mesh<Spatial>, prefix: &str) {
    let n = mesh.n_nodes();
    let edges: Vec<(usize, usize)> = mesh
        .elements
        .iter()
        .flat_map(|t| (0..4).flat_map(move |i| (i + 1..4).map(move |j| (t[i], t[j]))))
        .collect();
    let graph = NodeGraph::new(n, &edges);
    let mut upper: Vec<Pair<usize, usize>> = (0..n).map(|i| Pair::new(i, i)).collect();
    for a in 0..n {
        upper.extend(graph.neighbours(a).iter().filter(|&&b| b > a).map(|&b| Pair::new(a, b)));
    }
    let (pattern, _) = SymbolicSparseColMat::try_new_from_indices(n, n, &upper).unwrap();
    let mut orders = vec![
        ("minimum degree", minimum_degree(&graph).unwrap()),
        ("nested dissection", nested_dissection(&graph, &mesh.nodes).unwrap()),
    ];
    if let Ok(bytes) = std::fs::read(format!("{prefix}.metis")) {
        orders.push((
            "METIS NodeND",
            bytes
                .chunks_exact(8)
                .map(|c| u64::from_le_bytes(c.try_into().unwrap()) as usize)
                .collect(),
        ));
    }
    for (name, order) in orders {
        let mut inverse = vec![0usize; n];
        order.iter().enumerate().for_each(|(k, &v)| inverse[v] = k);
        let perm = PermRef::new_checked(&order, &inverse, n);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold:
                faer::sparse::linalg::SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Upper,
            SymmetricOrdering::Custom(perm),
            params,
        )
        .unwrap();
        let work = work_of(&symbolic);
        println!(
            "node graph, {name:18} flops {:.3e}  nnz(L) {:.3e}",
            work.factorization_flops,
            work.solve_pair_flops / 4.0
        );
    }
}

/// A matrix of `pattern` with -1 off the diagonal and the row's entry count + 1 on it:
/// symmetric and strictly diagonally dominant, so SPD.
fn dominant(pattern: &StiffnessPattern) -> faer::sparse::SparseColMat<usize, f64> {
    let shape = pattern.with_values(vec![0.0; pattern.nnz()]);
    let (col_ptr, row_idx) = (shape.symbolic().col_ptr(), shape.symbolic().row_idx());
    let mut count = vec![0.0; shape.nrows()];
    for c in 0..shape.ncols() {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            count[r] += 1.0;
            count[c] += 1.0;
        }
    }
    let values = (0..shape.ncols())
        .flat_map(|c| row_idx[col_ptr[c]..col_ptr[c + 1]].iter().map(move |&r| (r, c)))
        .map(|(r, c)| if r == c { count[c] + 1.0 } else { -1.0 })
        .collect();
    pattern.with_values(values)
}

fn read_words(path: &str) -> Vec<[u8; 8]> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    bytes.chunks_exact(8).map(|c| c.try_into().unwrap()).collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let prefix = args.get(1).expect("usage: ordering_work PREFIX [frictionless]");
    let frictionless = args.iter().any(|a| a == "frictionless");
    let numeric = args.iter().any(|a| a == "numeric");
    let coords: Vec<f64> =
        read_words(&format!("{prefix}.points")).into_iter().map(f64::from_le_bytes).collect();
    let ids: Vec<usize> = read_words(&format!("{prefix}.tets"))
        .into_iter()
        .map(|w| u64::from_le_bytes(w) as usize)
        .collect();
    let contact: Vec<usize> = read_words(&format!("{prefix}.contact"))
        .into_iter()
        .map(|w| u64::from_le_bytes(w) as usize)
        .collect();
    let points: Vec<[f64; 3]> = coords.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    let tets: Vec<[usize; 4]> = ids.chunks_exact(4).map(|t| [t[0], t[1], t[2], t[3]]).collect();
    let mesh = Mesh::<Spatial>::new(points, tets);
    let elements: Vec<Tet4> = (0..mesh.n_elements()).map(|e| Tet4::new(&mesh, e)).collect();
    let n_dofs = 3 * mesh.n_nodes();
    let mut fixed = vec![false; n_dofs];
    for (i, p) in mesh.nodes.iter().enumerate() {
        fixed[3 * i] |= p[0] == 0.0;
        fixed[3 * i + 1] |= p[1] == 0.0;
    }
    let components = if frictionless { 2..3 } else { 0..3 };
    let trailing: Vec<usize> = contact
        .iter()
        .flat_map(|&n| components.clone().map(move |c| 3 * n + c))
        .filter(|&d| !fixed[d])
        .collect();
    println!("nodes {} tets {} trailing {}", mesh.n_nodes(), mesh.n_elements(), trailing.len());
    node_graph_work(&mesh, prefix);
    if std::env::var("NODE_GRAPH_ONLY").is_ok() {
        return;
    }
    for (name, how) in [
        ("minimum degree", NodeOrder::MinimumDegree),
        ("nested dissection", NodeOrder::NestedDissection(&mesh.nodes)),
    ] {
        let start = Instant::now();
        let map = DofMap::ordered_by(&elements, n_dofs, &fixed, &[], &trailing, how).unwrap();
        let ordering = start.elapsed().as_secs_f64();
        let pattern = StiffnessPattern::new(&elements, &map).unwrap();
        let lower = pattern.with_values(vec![0.0; pattern.nnz()]);
        let start = Instant::now();
        let symbolic = symbolic_analysis(&lower).unwrap();
        let analysis = start.elapsed().as_secs_f64();
        let work = work_of(&symbolic);
        drop(symbolic);
        if numeric {
            let start = Instant::now();
            FaerLlt::new(&dominant(&pattern), &map, trailing.len()).unwrap();
            println!("{name:18} factorization {:.2} s", start.elapsed().as_secs_f64());
        }
        println!(
            "{name:18} equations {} ordering {ordering:.2} s analysis {analysis:.2} s  flops {:.3e}  nnz(L) {:.3e}",
            map.n_equations,
            work.factorization_flops,
            work.solve_pair_flops / 4.0
        );
    }
}
