//! The constant-strain triangle (CST) and its axisymmetric ring: strain–displacement matrix B
//! (eq. 10), stiffness K_e = w Bᵀ D B (the element part of K in eq. 36) and internal force
//! w Bᵀ σ (eq. 42), with w the element's volume: t·A in plane strain and plane stress, the
//! full ring 2π r̄ A in axisymmetry (r̄ the centroid radius; forces are totals over the ring).
//!
//! B has four rows (εx, εy, εz, γxy) for every plane, matching the four stress components
//! of `material`: the z row is zero in plane strain and plane stress (εz is 0, or follows from
//! σz = 0 in the material), and in axisymmetry it is the hoop strain εθ = u_r/r taken at the
//! centroid, (u_r1 + u_r2 + u_r3)/(3 r̄): one-point quadrature at the centroid, which gives the
//! exact εθ there for every linear displacement field and stays finite on elements that touch
//! the axis (r̄ > 0 for any element of positive area in r >= 0). The rows εr, εz, γrz are
//! constant and r A r̄ = ∫ r dA, so w Bᵀ σ is the exact virtual work of a uniform stress.

use crate::mesh::Mesh;
use nalgebra::{SMatrix, SVector};
use std::f64::consts::PI;

/// An element's kinematics, the seam between the mesh and the constitutive law: the nodes it
/// joins, its DOFs, its strain operator B (S rows: the components of its stress state; N
/// columns: its DOFs; nalgebra's fixed dimensions) and the measure w it integrates over. K_e,
/// the strain and the internal force follow from those. The CST of plane strain, plane stress
/// and axisymmetry is `Element<4, 6>`; a linear tetrahedron would be `Element<6, 12>`.
pub trait Element<const S: usize, const N: usize>: Send + Sync {
    /// The mesh nodes of the element.
    fn nodes(&self) -> &[usize];

    /// Global DOF numbers of the element, node after node.
    fn dofs(&self) -> [usize; N];

    /// Strain operator B: ε = B u_e.
    fn b(&self) -> &SMatrix<f64, S, N>;

    /// The measure w the element integrates over (its volume).
    fn measure(&self) -> f64;

    /// The element's entries of a vector over all DOFs.
    fn gather(&self, u: &[f64]) -> SVector<f64, N> {
        SVector::from_iterator(self.dofs().iter().map(|&d| u[d]))
    }

    /// Strain B u_e for the global displacement vector `u`.
    fn strain(&self, u: &[f64]) -> SVector<f64, S> {
        self.b() * self.gather(u)
    }

    /// w Bᵀ D B for the D the stress state pairs with B (`Section::element_matrix`).
    fn stiffness(&self, d: &SMatrix<f64, S, S>) -> SMatrix<f64, N, N> {
        self.b().transpose() * d * self.b() * self.measure()
    }

    /// Nodal internal forces w Bᵀ σ.
    fn internal_force(&self, stress: &SVector<f64, S>) -> SVector<f64, N> {
        self.b().transpose() * stress * self.measure()
    }
}

/// Rows εx, εy, εz (hoop εθ in axisymmetry), γxy; columns u_x, u_y of the three nodes.
pub type BMatrix = SMatrix<f64, 4, 6>;
pub type ElementVector = SVector<f64, 6>;

/// The row of the out-of-plane (hoop) strain in B and in the stress vector.
pub const HOOP: usize = 2;

#[derive(Debug, Clone)]
pub struct Cst {
    nodes: [usize; 3],
    /// The volume w the element integrates over: t·A (planar) or 2π r̄ A (axisymmetric).
    volume: f64,
    b: BMatrix,
}

impl Cst {
    /// Element `e` of `mesh` in plane strain or plane stress, of out-of-plane `thickness`:
    /// the z row of B is zero (εz is 0, or follows from σz = 0 in the material).
    pub fn planar(mesh: &Mesh, e: usize, thickness: f64) -> Self {
        let (nodes, area, b) = Cst::in_plane(mesh, e);
        Cst { nodes, volume: area * thickness, b }
    }

    /// Element `e` of `mesh` as a ring about the axis x = 0: the hoop row of B at the centroid
    /// and the volume 2π r̄ A.
    pub fn ring(mesh: &Mesh, e: usize) -> Self {
        let (nodes, area, mut b) = Cst::in_plane(mesh, e);
        let [p1, p2, p3] = nodes.map(|i| mesh.nodes[i]);
        let r = (p1[0] + p2[0] + p3[0]) / 3.0;
        for k in 0..3 {
            b[(HOOP, 2 * k)] = 1.0 / (3.0 * r); // εθ = Σ N_k(centroid) u_rk / r̄
        }
        Cst { nodes, volume: 2.0 * PI * r * area, b }
    }

    /// The nodes, the area and the in-plane rows of B (the z row zero).
    fn in_plane(mesh: &Mesh, e: usize) -> ([usize; 3], f64, BMatrix) {
        let nodes = mesh.triangles[e];
        let [p1, p2, p3] = nodes.map(|i| mesh.nodes[i]);
        let area2 = mesh.signed_area2(e);
        let (b1, b2, b3) = (p2[1] - p3[1], p3[1] - p1[1], p1[1] - p2[1]);
        let (c1, c2, c3) = (p3[0] - p2[0], p1[0] - p3[0], p2[0] - p1[0]);
        #[rustfmt::skip]
        let b = BMatrix::from_row_slice(&[
            b1, 0.0, b2, 0.0, b3, 0.0,
            0.0, c1, 0.0, c2, 0.0, c3,
            0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
            c1, b1, c2, b2, c3, b3,
        ]) / area2;
        (nodes, area2 / 2.0, b)
    }
}

impl Element<4, 6> for Cst {
    fn nodes(&self) -> &[usize] {
        &self.nodes
    }

    /// 2 per node: x then y.
    fn dofs(&self) -> [usize; 6] {
        let [a, b, c] = self.nodes;
        [2 * a, 2 * a + 1, 2 * b, 2 * b + 1, 2 * c, 2 * c + 1]
    }

    fn b(&self) -> &BMatrix {
        &self.b
    }

    fn measure(&self) -> f64 {
        self.volume
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, Plane};
    use crate::section::Section;
    use nalgebra::{Matrix4, Vector4};

    fn element(m: &Mesh, e: usize, plane: Plane, thickness: f64) -> Cst {
        plane.stress_state().element(m, e, thickness)
    }

    /// D of the material as the plane's element pairs it with B.
    fn elastic_d(material: Material, plane: Plane) -> Matrix4<f64> {
        Section::new(material, plane.stress_state()).elastic_matrix()
    }

    /// One element away from the axis and one touching it (node 3 at r = 0).
    fn mesh() -> Mesh {
        Mesh { nodes: vec![[0.1, 0.2], [1.3, 0.1], [0.4, 0.9], [0.0, 0.6]], triangles: vec![[0, 1, 2], [0, 2, 3]] }
    }

    /// Nodal values of a linear field u = (a0 + a1 x + a2 y, b0 + b1 x + b2 y).
    fn linear_field(m: &Mesh, a: [f64; 3], b: [f64; 3]) -> Vec<f64> {
        m.nodes.iter().flat_map(|p| [a[0] + a[1] * p[0] + a[2] * p[1], b[0] + b[1] * p[0] + b[2] * p[1]]).collect()
    }

    // Round-off bound of the strain tests: strains O(1e-3) from nodal values up to O(1) (the
    // rigid offsets) over coordinate differences O(0.1..1): cancellation leaves ~1e-16 × O(10).
    const STRAIN_ROUND_OFF: f64 = 1e-14;

    #[test]
    fn linear_field_gives_its_exact_strain() {
        // Patch test at element level: u = (a x + b y, c x + d y) + rigid ⇒ ε = (a, d, 0, b + c).
        let m = mesh();
        let (a, b, c, d) = (1e-3, -2e-3, 5e-4, 3e-3);
        let u = linear_field(&m, [0.7, a, b], [-0.2, c, d]);
        for plane in [Plane::Strain, Plane::Stress] {
            let eps = element(&m, 0, plane, 1.0).strain(&u);
            assert!((eps - Vector4::new(a, d, 0.0, b + c)).norm() < STRAIN_ROUND_OFF, "{plane:?}: {eps}");
        }
    }

    #[test]
    fn ring_reproduces_the_radial_and_axial_strain_states_exactly() {
        // u_r = A r, u_z = D r + E z + F: εr = εθ = A, εz = E, γrz = D everywhere (the centroid
        // rule is exact for u_r ∝ r), on the element off the axis and on the one touching it.
        let m = mesh();
        let (a, d, e) = (1e-3, -4e-4, 2.5e-3);
        let u = linear_field(&m, [0.0, a, 0.0], [0.3, d, e]);
        for k in 0..2 {
            let eps = element(&m, k, Plane::Axisymmetric, 1.0).strain(&u);
            assert!((eps - Vector4::new(a, e, a, d)).norm() < STRAIN_ROUND_OFF, "element {k}: {eps}");
        }
        // Any linear u_r = A r + B z + C: εθ is the exact u_r/r at the centroid.
        let (b, c) = (7e-4, -3e-4);
        let u = linear_field(&m, [c, a, b], [0.0, 0.0, 0.0]);
        for k in 0..2 {
            let el = element(&m, k, Plane::Axisymmetric, 1.0);
            let centre = m.triangles[k].map(|i| m.nodes[i]).iter().fold([0.0; 2], |s, p| [s[0] + p[0] / 3.0, s[1] + p[1] / 3.0]);
            let exact = (c + a * centre[0] + b * centre[1]) / centre[0];
            assert!((el.strain(&u)[HOOP] - exact).abs() < STRAIN_ROUND_OFF, "element {k}");
        }
    }

    #[test]
    fn ring_volume_is_pappus() {
        // 2π r̄ A: the volume swept by the triangle about the axis (Pappus), e.g. for the
        // element touching the axis, computed from its coordinates here.
        let m = mesh();
        let el = element(&m, 1, Plane::Axisymmetric, 7.0); // thickness does not apply
        let r = (0.1 + 0.4 + 0.0) / 3.0;
        assert!((el.measure() - 2.0 * PI * r * m.signed_area2(1) / 2.0).abs() < 1e-15);
        assert!((element(&m, 1, Plane::Strain, 7.0).measure() - 7.0 * m.signed_area2(1) / 2.0).abs() < 1e-15);
    }

    /// Rigid modes of an element: translation x, translation y, rotation about the origin.
    fn rigid_modes(m: &Mesh, e: usize) -> [ElementVector; 3] {
        let p = m.triangles[e].map(|i| m.nodes[i]);
        let rot = |k: usize| [-p[k][1], p[k][0]];
        [
            ElementVector::from_row_slice(&[1., 0., 1., 0., 1., 0.]),
            ElementVector::from_row_slice(&[0., 1., 0., 1., 0., 1.]),
            ElementVector::from_row_slice(&[rot(0)[0], rot(0)[1], rot(1)[0], rot(1)[1], rot(2)[0], rot(2)[1]]),
        ]
    }

    #[test]
    fn rigid_body_modes_have_zero_energy() {
        let m = mesh();
        let material = Material::elastic(70e3, 0.3);
        for plane in [Plane::Strain, Plane::Stress] {
            let k = element(&m, 0, plane, 1.0).stiffness(&elastic_d(material, plane));
            for mode in rigid_modes(&m, 0) {
                let f = k * mode;
                assert!(f.norm() < 1e-9 * k.norm(), "rigid mode loads the element: {f}");
            }
            assert!((k - k.transpose()).norm() < 1e-12 * k.norm());
        }
    }

    #[test]
    fn ring_has_only_the_axial_translation_as_zero_energy_mode() {
        // Axial translation: zero strain and force. Radial translation and rotation strain the
        // hoop direction: εθ = u_r/r̄ ≠ 0, so they carry energy uᵀ K u = w εᵀ D ε > 0.
        let m = mesh();
        let d = elastic_d(Material::elastic(70e3, 0.3), Plane::Axisymmetric);
        for e in 0..2 {
            let el = element(&m, e, Plane::Axisymmetric, 1.0);
            let k = el.stiffness(&d);
            let [tx, ty, rot] = rigid_modes(&m, e);
            assert!((el.b() * ty).norm() < STRAIN_ROUND_OFF && (k * ty).norm() < 1e-12 * k.norm(), "element {e}");
            for mode in [tx, rot] {
                let strain = el.b() * mode;
                assert!(strain[HOOP].abs() > 0.1, "element {e}: {strain}");
                let energy = (mode.transpose() * k * mode)[0];
                assert!((energy - el.measure() * (strain.transpose() * d * strain)[0]).abs() < 1e-10 * energy && energy > 0.0);
            }
            assert!((k - k.transpose()).norm() < 1e-12 * k.norm());
        }
    }
}
