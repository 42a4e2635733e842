//! Rigid-body modes that the supports leave free.
//!
//! In 2D each body has three rigid modes (two translations, one rotation). A mode survives
//! the supports when it vanishes on every fixed DOF of the body. An axisymmetric body (rings
//! about the axis x = 0) has one: translation along the axis (y); moving rings radially or
//! tilting them strains the hoop direction, so neither is a zero-energy mode. Surviving modes span the
//! null space N of the reduced stiffness; they must be held by contact, which the driver
//! checks (a body free to move is an error, not a singular factorization). For each mode one
//! DOF is "pinned" so that the rest of K is SPD (see `linalg`).

use crate::material::Plane;
use nalgebra::{DMatrix, Matrix3};

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
    /// Weights of (translation x, translation y, rotation) that make up this mode.
    pub weights: [f64; 3],
}

/// Free rigid modes of every body, plus the pinned DOFs (one per mode).
pub fn free_modes(nodes: &[[f64; 2]], body_of_node: &[usize], n_bodies: usize, fixed: &[bool], plane: Plane) -> (Vec<RigidMode>, Vec<usize>) {
    let mut modes = Vec::new();
    let mut pinned = Vec::new();
    for body in 0..n_bodies {
        let members: Vec<usize> = (0..nodes.len()).filter(|&i| body_of_node[i] == body).collect();
        let frame = BodyFrame::of(nodes, &members);
        let mut body_vectors: Vec<Vec<f64>> = Vec::new();
        for coef in surviving_combinations(&frame.supports_gram(&members, fixed), frame.threshold(&members, fixed), plane) {
            let mut v = vec![0.0; fixed.len()];
            for &i in &members {
                for c in 0..2 {
                    let dof = 2 * i + c;
                    if !fixed[dof] {
                        v[dof] = (0..3).map(|l| coef[l] * frame.mode_value(dof, l)).sum();
                    }
                }
            }
            let description = describe(coef[0], coef[1], coef[2]);
            body_vectors.push(v.clone());
            modes.push(RigidMode { body, vector: v, description, weights: [coef[0], coef[1], coef[2]] });
        }
        pinned.extend(match plane {
            Plane::Axisymmetric => pin_on_the_largest_ring(nodes, &members, &body_vectors),
            Plane::Strain | Plane::Stress => pick_pinned_dofs(&members, &body_vectors),
        });
    }
    (modes, pinned)
}

/// A body's centroid and size, so that its rotation mode has O(1) entries.
struct BodyFrame<'n> {
    nodes: &'n [[f64; 2]],
    centre: (f64, f64),
    size: f64,
}

impl<'n> BodyFrame<'n> {
    fn of(nodes: &'n [[f64; 2]], members: &[usize]) -> Self {
        let m = members.len() as f64;
        let (cx, cy) = members.iter().fold((0.0, 0.0), |s, &i| (s.0 + nodes[i][0] / m, s.1 + nodes[i][1] / m));
        let size = members.iter().map(|&i| ((nodes[i][0] - cx).powi(2) + (nodes[i][1] - cy).powi(2)).sqrt()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
        BodyFrame { nodes, centre: (cx, cy), size }
    }

    /// Entry `dof` of rigid mode k: translation x, translation y, rotation about the centre.
    fn mode_value(&self, dof: usize, k: usize) -> f64 {
        let (i, c) = (dof / 2, dof % 2);
        let (cx, cy) = self.centre;
        match k {
            0 => (c == 0) as i32 as f64,
            1 => (c == 1) as i32 as f64,
            _ => {
                if c == 0 {
                    -(self.nodes[i][1] - cy) / self.size
                } else {
                    (self.nodes[i][0] - cx) / self.size
                }
            }
        }
    }

    /// AᵀA of the rigid modes' rows at the body's fixed DOFs: its null space is the
    /// combinations the supports leave free.
    fn supports_gram(&self, members: &[usize], fixed: &[bool]) -> Matrix3<f64> {
        let mut ata = Matrix3::<f64>::zeros();
        for dof in members.iter().flat_map(|&i| [2 * i, 2 * i + 1]).filter(|&d| fixed[d]) {
            for k in 0..3 {
                for l in 0..3 {
                    ata[(k, l)] += self.mode_value(dof, k) * self.mode_value(dof, l);
                }
            }
        }
        ata
    }

    /// The eigenvalue of AᵀA below which a combination survives: `MODE_EIGENVALUE` × its rows.
    fn threshold(&self, members: &[usize], fixed: &[bool]) -> f64 {
        let n_rows = members.iter().flat_map(|&i| [2 * i, 2 * i + 1]).filter(|&d| fixed[d]).count();
        MODE_EIGENVALUE * (n_rows.max(1) as f64)
    }
}

/// The axial translation of a ring body, pinned at the axial DOF of its node of largest radius.
/// Solving with K# puts the body's whole unbalanced load on the pinned DOF, and the contact
/// forces take it off again: a point load on the axis would raise stresses ~P/h² that cancel
/// to round-off, a ring load on the largest ring only ~P/(2π r h). (Measured on the Hertz
/// sphere: the relative residual of a snapshot 4e-10 pinned at the contact point, where the
/// plane's greedy choice lands, against 1e-11 of the full path.)
fn pin_on_the_largest_ring(nodes: &[[f64; 2]], members: &[usize], vectors: &[Vec<f64>]) -> Vec<usize> {
    let outer = members.iter().copied().fold(members[0], |best, i| if nodes[i][0] > nodes[best][0] { i } else { best });
    vectors.iter().map(|_| 2 * outer + 1).collect()
}

/// The combinations (weights of translation x, translation y, rotation) of a body's zero-energy
/// modes that the supports leave free, from AᵀA of the supports' rows: its null space in the
/// plane; in axisymmetry the axial translation alone, free when no support holds a y DOF of the
/// body (its diagonal entry AᵀA[1][1] counts them).
fn surviving_combinations(ata: &Matrix3<f64>, threshold: f64, plane: Plane) -> Vec<[f64; 3]> {
    if plane == Plane::Axisymmetric {
        return if ata[(1, 1)] <= threshold { vec![[0.0, 1.0, 0.0]] } else { vec![] };
    }
    let eig = ata.symmetric_eigen();
    (0..3).filter(|&k| eig.eigenvalues[k] <= threshold).map(|k| {
        let c = eig.eigenvectors.column(k);
        [c[0], c[1], c[2]]
    }).collect()
}

/// Words for a rigid motion with weights (translation x, translation y, rotation).
pub fn describe(tx: f64, ty: f64, rot: f64) -> String {
    let parts: Vec<&str> = [(tx, "translation in x"), (ty, "translation in y"), (rot, "rotation")]
        .iter()
        .filter(|(c, _)| c.abs() > NAMED_WEIGHT)
        .map(|&(_, s)| s)
        .collect();
    parts.join(" + ")
}

/// Greedy pivoting: pick, for each mode, the DOF whose row of N is farthest from the span of
/// the rows already picked; the picked r×r block of N is then well conditioned.
fn pick_pinned_dofs(members: &[usize], vectors: &[Vec<f64>]) -> Vec<usize> {
    let r = vectors.len();
    if r == 0 {
        return vec![];
    }
    let dofs: Vec<usize> = members.iter().flat_map(|&i| [2 * i, 2 * i + 1]).collect();
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

    fn square_nodes() -> Vec<[f64; 2]> {
        vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    }

    #[test]
    fn symmetry_line_leaves_only_vertical_translation() {
        // u_x = 0 on the line x = 0 (nodes 0 and 3): translation x and rotation are held.
        let nodes = square_nodes();
        let mut fixed = vec![false; 8];
        fixed[0] = true;
        fixed[6] = true;
        let (modes, pinned) = free_modes(&nodes, &[0; 4], 1, &fixed, Plane::Strain);
        assert_eq!(modes.len(), 1);
        assert_eq!(modes[0].description, "translation in y");
        assert_eq!(pinned.len(), 1);
        assert_eq!(pinned[0] % 2, 1);
    }

    #[test]
    fn free_body_has_three_modes_and_three_pins() {
        let nodes = square_nodes();
        let (modes, pinned) = free_modes(&nodes, &[0; 4], 1, &vec![false; 8], Plane::Strain);
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
        let (modes, _) = free_modes(&nodes, &[0; 4], 1, &fixed, Plane::Strain);
        assert!(modes.is_empty());
    }

    #[test]
    fn axisymmetric_body_keeps_only_the_axial_translation() {
        // Rings: a free body has one zero-energy mode (translation along the axis y), pinned
        // at a y DOF; holding one y DOF removes it, holding x DOFs does not.
        let nodes = square_nodes();
        let (modes, pinned) = free_modes(&nodes, &[0; 4], 1, &vec![false; 8], Plane::Axisymmetric);
        assert_eq!(modes.len(), 1);
        assert_eq!(modes[0].description, "translation in y");
        assert_eq!(modes[0].vector, vec![0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0]);
        assert_eq!(pinned, vec![3]); // u_y of node 1, the first at the largest radius x = 1
        let mut fixed = vec![false; 8];
        fixed[0] = true;
        fixed[6] = true;
        assert_eq!(free_modes(&nodes, &[0; 4], 1, &fixed, Plane::Axisymmetric).0.len(), 1);
        fixed[3] = true;
        assert!(free_modes(&nodes, &[0; 4], 1, &fixed, Plane::Axisymmetric).0.is_empty());
    }
}
