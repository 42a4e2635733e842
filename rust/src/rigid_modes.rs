//! Rigid-body modes that the supports leave free.
//!
//! In 2D each body has three rigid modes (two translations, one rotation), in 3D six (three
//! translations, three rotations). A mode survives the supports when it vanishes on every
//! fixed DOF of the body. An axisymmetric body (rings about the axis x = 0) has one:
//! translation along the axis (y); moving rings radially or tilting them strains the hoop
//! direction, so neither is a zero-energy mode. Surviving modes span the null space N of the
//! reduced stiffness; they must be held by contact, which the driver checks (a body free to
//! move is an error, not a singular factorization). For each mode one DOF is "pinned" so that
//! the rest of K is SPD (see `linalg`).

use crate::dim::Dim;
use crate::mesh::Mesh;
use nalgebra::{DMatrix, Matrix3, Matrix6};

/// An eigenvalue of AᵀA (A: the supports' rows of the rigid modes) below this × the rows counts
/// as zero: that combination of modes survives the supports.
const MODE_EIGENVALUE: f64 = 1e-10;
/// A mode weight above this is named in `describe`.
const NAMED_WEIGHT: f64 = 0.3;
/// A candidate pinned DOF must improve the distance by more than this.
const PIN_IMPROVEMENT: f64 = 1e-12;

/// A free rigid-body mode: its displacement vector over all DOFs (zero on fixed DOFs).
#[derive(Debug, Clone)]
pub struct RigidMode {
    pub body: usize,
    pub vector: Vec<f64>,
    pub description: String,
    /// Weights of the elementary motions (`elementary_modes`) that make up this mode.
    pub weights: Vec<f64>,
}

/// Free rigid modes of every body, plus the pinned DOFs (one per mode); `axisymmetric`: a
/// model of rings about the axis, whose only rigid motion is the axial translation.
pub fn free_modes<D: Dim>(
    mesh: &Mesh<D>,
    body_of_node: &[usize],
    n_bodies: usize,
    fixed: &[bool],
    axisymmetric: bool,
) -> (Vec<RigidMode>, Vec<usize>) {
    let dim = D::N;
    let mut modes = Vec::new();
    let mut pinned = Vec::new();
    for body in 0..n_bodies {
        let members: Vec<usize> =
            (0..mesh.n_nodes()).filter(|&i| body_of_node[i] == body).collect();
        let frame = BodyFrame::of(mesh, &members);
        let mut body_vectors: Vec<Vec<f64>> = Vec::new();
        for coef in surviving_combinations(
            &frame.supports_gram(&members, fixed),
            frame.threshold(&members, fixed),
            axisymmetric,
        ) {
            let mut v = vec![0.0; fixed.len()];
            for &i in &members {
                for c in 0..dim {
                    let dof = dim * i + c;
                    if !fixed[dof] {
                        v[dof] = (0..coef.len()).map(|l| coef[l] * frame.mode_value(dof, l)).sum();
                    }
                }
            }
            let description = describe(&coef);
            body_vectors.push(v.clone());
            modes.push(RigidMode { body, vector: v, description, weights: coef });
        }
        pinned.extend(match axisymmetric {
            true => pin_on_the_largest_ring(mesh, &members, &body_vectors),
            false => pick_pinned_dofs(&members, dim, &body_vectors),
        });
    }
    (modes, pinned)
}

/// A body's centroid and size, so that its rotation modes have O(1) entries.
struct BodyFrame<'n, D: Dim> {
    mesh: &'n Mesh<D>,
    dim: usize,
    centre: [f64; 3],
    size: f64,
}

impl<'n, D: Dim> BodyFrame<'n, D> {
    fn of(mesh: &'n Mesh<D>, members: &[usize]) -> Self {
        let (m, dim) = (members.len() as f64, D::N);
        let centre = members.iter().fold([0.0; 3], |s, &i| {
            let p = mesh.point(i);
            std::array::from_fn(|k| s[k] + p[k] / m)
        });
        let radius = |i: usize| {
            let p = mesh.point(i);
            (0..dim).map(|k| (p[k] - centre[k]).powi(2)).fold(0.0, |a, v| a + v).sqrt()
        };
        let size = members.iter().map(|&i| radius(i)).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
        BodyFrame { mesh, dim, centre, size }
    }

    /// Entry `dof` of elementary rigid mode k: the translations along the axes, then the
    /// rotations about the centre (2D: about z; 3D: about x, y, z, u = ω × (x − centre)).
    fn mode_value(&self, dof: usize, k: usize) -> f64 {
        let (i, c) = (dof / self.dim, dof % self.dim);
        if k < self.dim {
            return (c == k) as i32 as f64;
        }
        let p = self.mesh.point(i);
        let r: [f64; 3] = std::array::from_fn(|a| (p[a] - self.centre[a]) / self.size);
        let axis = k + 3 - D::RIGID_MODES; // 2D: about z; 3D: x, y, z
                                           // (e_axis × r)_c
        let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
        match c {
            _ if c == a1 => -r[a2],
            _ if c == a2 => r[a1],
            _ => 0.0,
        }
    }

    /// The DOFs of the body's nodes.
    fn dofs<'a>(&'a self, members: &'a [usize]) -> impl Iterator<Item = usize> + 'a {
        members.iter().flat_map(move |&i| (0..self.dim).map(move |c| self.dim * i + c))
    }

    /// AᵀA of the rigid modes' rows at the body's fixed DOFs: its null space is the
    /// combinations the supports leave free.
    fn supports_gram(&self, members: &[usize], fixed: &[bool]) -> DMatrix<f64> {
        let n = D::RIGID_MODES;
        let mut ata = DMatrix::<f64>::zeros(n, n);
        for dof in self.dofs(members).filter(|&d| fixed[d]) {
            for k in 0..n {
                for l in 0..n {
                    ata[(k, l)] += self.mode_value(dof, k) * self.mode_value(dof, l);
                }
            }
        }
        ata
    }

    /// The eigenvalue of AᵀA below which a combination survives: `MODE_EIGENVALUE` × its rows.
    fn threshold(&self, members: &[usize], fixed: &[bool]) -> f64 {
        let n_rows = self.dofs(members).filter(|&d| fixed[d]).count();
        MODE_EIGENVALUE * (n_rows.max(1) as f64)
    }
}

/// The axial translation of a ring body, pinned at the axial DOF of its node of largest radius.
/// Solving with K# puts the body's whole unbalanced load on the pinned DOF, and the contact
/// forces take it off again: a point load on the axis would raise stresses ~P/h² that cancel
/// to round-off, a ring load on the largest ring only ~P/(2π r h). (Measured on the Hertz
/// sphere: the relative residual of a snapshot 4e-10 pinned at the contact point, where the
/// plane's greedy choice lands, against 1e-11 of the full path.)
fn pin_on_the_largest_ring<D: Dim>(
    mesh: &Mesh<D>,
    members: &[usize],
    vectors: &[Vec<f64>],
) -> Vec<usize> {
    let r = |i: usize| mesh.nodes[i].as_ref()[0];
    let outer =
        members.iter().copied().fold(members[0], |best, i| if r(i) > r(best) { i } else { best });
    vectors.iter().map(|_| 2 * outer + 1).collect()
}

/// The combinations (weights of the elementary motions) of a body's zero-energy modes that
/// the supports leave free, from AᵀA of the supports' rows: its null space; in axisymmetry the
/// axial translation alone, free when no support holds a y DOF of the body (its diagonal entry
/// AᵀA[1][1] counts them).
fn surviving_combinations(ata: &DMatrix<f64>, threshold: f64, axisymmetric: bool) -> Vec<Vec<f64>> {
    if axisymmetric {
        return if ata[(1, 1)] <= threshold { vec![vec![0.0, 1.0, 0.0]] } else { vec![] };
    }
    let null = |values: &[f64], column: &dyn Fn(usize) -> Vec<f64>| -> Vec<Vec<f64>> {
        (0..values.len()).filter(|&k| values[k] <= threshold).map(column).collect()
    };
    if ata.nrows() == 3 {
        let eig = Matrix3::from_fn(|i, j| ata[(i, j)]).symmetric_eigen();
        return null(eig.eigenvalues.as_slice(), &|k| {
            eig.eigenvectors.column(k).iter().copied().collect()
        });
    }
    let eig = Matrix6::from_fn(|i, j| ata[(i, j)]).symmetric_eigen();
    null(eig.eigenvalues.as_slice(), &|k| eig.eigenvectors.column(k).iter().copied().collect())
}

/// Words for a rigid motion with weights of the elementary motions (3: 2D, 6: 3D).
pub fn describe(weights: &[f64]) -> String {
    let names: &[&str] = match weights.len() {
        3 => &["translation in x", "translation in y", "rotation"],
        _ => &[
            "translation in x",
            "translation in y",
            "translation in z",
            "rotation about x",
            "rotation about y",
            "rotation about z",
        ],
    };
    let parts: Vec<&str> = weights
        .iter()
        .zip(names)
        .filter(|(c, _)| c.abs() > NAMED_WEIGHT)
        .map(|(_, &s)| s)
        .collect();
    parts.join(" + ")
}

/// Greedy pivoting: pick, for each mode, the DOF whose row of N is farthest from the span of
/// the rows already picked; the picked r×r block of N is then well conditioned.
fn pick_pinned_dofs(members: &[usize], dim: usize, vectors: &[Vec<f64>]) -> Vec<usize> {
    let r = vectors.len();
    if r == 0 {
        return vec![];
    }
    let dofs: Vec<usize> =
        members.iter().flat_map(|&i| (0..dim).map(move |c| dim * i + c)).collect();
    let mut rows = DMatrix::<f64>::zeros(dofs.len(), r);
    for (j, &d) in dofs.iter().enumerate() {
        for k in 0..r {
            rows[(j, k)] = vectors[k][d];
        }
    }
    let mut chosen = Vec::new();
    let mut basis: Vec<nalgebra::DVector<f64>> = Vec::new();
    for _ in 0..r {
        let mut best = (0usize, -1.0);
        for j in 0..dofs.len() {
            let mut v = rows.row(j).transpose().into_owned();
            for q in &basis {
                let p = v.dot(q);
                v -= q * p;
            }
            let n = v.norm();
            if n > best.1 + PIN_IMPROVEMENT {
                best = (j, n);
            }
        }
        let mut v = rows.row(best.0).transpose().into_owned();
        for q in &basis {
            let p = v.dot(q);
            v -= q * p;
        }
        basis.push(v.normalize());
        chosen.push(dofs[best.0]);
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{Planar, Spatial};

    fn square_nodes() -> Mesh<Planar> {
        Mesh::<Planar>::new(
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    /// The unit cube's corners in 3D (five tetrahedra are not needed: modes read the nodes).
    fn cube() -> Mesh<Spatial> {
        let points = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        Mesh::<Spatial>::new(points, vec![[0, 1, 2, 4]])
    }

    #[test]
    fn a_free_solid_has_six_modes_and_symmetry_planes_leave_what_they_should() {
        // Free: 3 translations + 3 rotations. Held in x on the face x = 0 and in y on y = 0
        // (the eighth of a sphere's symmetry planes): only the translation in z survives.
        let m = cube();
        let (modes, pinned) = free_modes(&m, &[0; 8], 1, &vec![false; 24], false);
        assert_eq!(modes.len(), 6);
        let mut p = pinned.clone();
        p.sort();
        p.dedup();
        assert_eq!(p.len(), 6);
        let mut fixed = vec![false; 24];
        for i in 0..8 {
            fixed[3 * i] |= i & 1 == 0; // x = 0: u_x
            fixed[3 * i + 1] |= (i >> 1) & 1 == 0; // y = 0: u_y
        }
        let (modes, pinned) = free_modes(&m, &[0; 8], 1, &fixed, false);
        assert_eq!(modes.len(), 1);
        assert_eq!(modes[0].description, "translation in z");
        assert_eq!(pinned[0] % 3, 2);
        // One face held in z as well: a body on rollers in z, x and y: no mode left.
        (0..4).for_each(|i| fixed[3 * i + 2] = true);
        assert!(free_modes(&m, &[0; 8], 1, &fixed, false).0.is_empty());
        // Held only in z on the face z = 0: x, y translations and the rotation about z remain.
        let mut z_only = vec![false; 24];
        (0..4).for_each(|i| z_only[3 * i + 2] = true);
        let (modes, _) = free_modes(&m, &[0; 8], 1, &z_only, false);
        assert_eq!(modes.len(), 3);
        let words: Vec<&str> = modes.iter().map(|md| md.description.as_str()).collect();
        assert!(
            words.iter().all(|w| !w.contains("translation in z")
                && !w.contains("rotation about x")
                && !w.contains("rotation about y")),
            "{words:?}"
        );
    }

    #[test]
    fn symmetry_line_leaves_only_vertical_translation() {
        // u_x = 0 on the line x = 0 (nodes 0 and 3): translation x and rotation are held.
        let nodes = square_nodes();
        let mut fixed = vec![false; 8];
        fixed[0] = true;
        fixed[6] = true;
        let (modes, pinned) = free_modes(&nodes, &[0; 4], 1, &fixed, false);
        assert_eq!(modes.len(), 1);
        assert_eq!(modes[0].description, "translation in y");
        assert_eq!(pinned.len(), 1);
        assert_eq!(pinned[0] % 2, 1);
    }

    #[test]
    fn free_body_has_three_modes_and_three_pins() {
        let nodes = square_nodes();
        let (modes, pinned) = free_modes(&nodes, &[0; 4], 1, &vec![false; 8], false);
        assert_eq!(modes.len(), 3);
        let mut p = pinned.clone();
        p.sort();
        p.dedup();
        assert_eq!(p.len(), 3);
    }

    #[test]
    fn clamped_body_has_no_mode() {
        let nodes = square_nodes();
        let mut fixed = vec![false; 8];
        fixed[0] = true;
        fixed[1] = true;
        fixed[3] = true;
        let (modes, _) = free_modes(&nodes, &[0; 4], 1, &fixed, false);
        assert!(modes.is_empty());
    }

    #[test]
    fn axisymmetric_body_keeps_only_the_axial_translation() {
        // Rings: a free body has one zero-energy mode (translation along the axis y), pinned
        // at a y DOF; holding one y DOF removes it, holding x DOFs does not.
        let nodes = square_nodes();
        let (modes, pinned) = free_modes(&nodes, &[0; 4], 1, &vec![false; 8], true);
        assert_eq!(modes.len(), 1);
        assert_eq!(modes[0].description, "translation in y");
        assert_eq!(modes[0].vector, vec![0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0]);
        assert_eq!(pinned, vec![3]); // u_y of node 1, the first at the largest radius x = 1
        let mut fixed = vec![false; 8];
        fixed[0] = true;
        fixed[6] = true;
        assert_eq!(free_modes(&nodes, &[0; 4], 1, &fixed, true).0.len(), 1);
        fixed[3] = true;
        assert!(free_modes(&nodes, &[0; 4], 1, &fixed, true).0.is_empty());
    }
}
