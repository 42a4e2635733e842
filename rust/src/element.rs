//! The constant-strain elements: the triangle (CST) with its axisymmetric ring, and the linear
//! tetrahedron (Tet4). Strain–displacement matrix B (eq. 10), stiffness K_e = w Bᵀ D B (the
//! element part of K in eq. 36) and internal force w Bᵀ σ (eq. 42), with w the element's
//! volume: t·A in plane strain and plane stress, the full ring 2π r̄ A in axisymmetry (r̄ the
//! centroid radius; forces are totals over the ring), V for the tetrahedron.
//!
//! An element's B has the rows of the Voigt components its kinematics give (`Element::ROWS`);
//! strains and stresses meet the material in all six (`material::Voigt`), the others zero.
//!
//! B has four rows (εx, εy, εz, γxy) for every plane, matching the four stress components
//! of `material`: the z row is zero in plane strain and plane stress (εz is 0, or follows from
//! σz = 0 in the material), and in axisymmetry it is the hoop strain εθ = u_r/r taken at the
//! centroid, (u_r1 + u_r2 + u_r3)/(3 r̄): one-point quadrature at the centroid, which gives the
//! exact εθ there for every linear displacement field and stays finite on elements that touch
//! the axis (r̄ > 0 for any element of positive area in r >= 0). The rows εr, εz, γrz are
//! constant and r A r̄ = ∫ r dA, so w Bᵀ σ is the exact virtual work of a uniform stress.

use crate::dim::{Dim, Planar, PlaneSection, Spatial};
use crate::material::{Plane, Voigt, PLANAR};
use crate::mesh::Mesh;
use nalgebra::{Matrix6, SMatrix, SVector};
use std::f64::consts::PI;

/// An element's kinematics, the seam between the mesh and the constitutive law: the nodes it
/// joins, its DOFs, its strain operator B (S rows: the Voigt components `ROWS` of its stress
/// state; N columns: its DOFs, `DIM` per node; nalgebra's fixed dimensions) and the measure w
/// it integrates over. K_e, the strain and the internal force follow from those. The CST of
/// plane strain, plane stress and axisymmetry is `Element<4, 6>`, the linear tetrahedron
/// `Element<6, 12>`.
pub trait Element<const S: usize, const N: usize>: Send + Sync {
    /// The space the element is in (`dim`).
    type Space: Dim;
    /// DOFs per node (the space's dimension).
    const DIM: usize = <Self::Space as Dim>::N;
    /// The Voigt component (`material::Voigt`) of each row of B.
    const ROWS: [usize; S];

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

    /// Strain B u_e for the global displacement vector `u`, in the six components (those B
    /// has no row for are 0).
    fn strain(&self, u: &[f64]) -> Voigt {
        let e = self.b() * self.gather(u);
        let mut full = Voigt::zeros();
        Self::ROWS.iter().zip(e.iter()).for_each(|(&r, &v)| full[r] = v);
        full
    }

    /// The rows and columns of B's components of a six-component D.
    fn rows_of(d: &Matrix6<f64>) -> SMatrix<f64, S, S> {
        SMatrix::from_fn(|i, j| d[(Self::ROWS[i], Self::ROWS[j])])
    }

    /// w Bᵀ D B for the D the stress state pairs with B (`Section::element_matrix`).
    fn stiffness(&self, d: &Matrix6<f64>) -> SMatrix<f64, N, N> {
        self.b().transpose() * Self::rows_of(d) * self.b() * self.measure()
    }

    /// Nodal internal forces w Bᵀ σ.
    fn internal_force(&self, stress: &Voigt) -> SVector<f64, N> {
        let s = SVector::<f64, S>::from_fn(|i, _| stress[Self::ROWS[i]]);
        self.b().transpose() * s * self.measure()
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
    pub fn planar(mesh: &Mesh<Planar>, e: usize, thickness: f64) -> Self {
        let (nodes, area, b) = Cst::in_plane(mesh, e);
        Cst { nodes, volume: area * thickness, b }
    }

    /// Element `e` of `mesh` as a ring about the axis x = 0: the hoop row of B at the centroid
    /// and the volume 2π r̄ A.
    pub fn ring(mesh: &Mesh<Planar>, e: usize) -> Self {
        let (nodes, area, mut b) = Cst::in_plane(mesh, e);
        let [p1, p2, p3] = nodes.map(|i| mesh.nodes[i]);
        let r = (p1[0] + p2[0] + p3[0]) / 3.0;
        for k in 0..3 {
            b[(HOOP, 2 * k)] = 1.0 / (3.0 * r); // εθ = Σ N_k(centroid) u_rk / r̄
        }
        Cst { nodes, volume: 2.0 * PI * r * area, b }
    }

    /// Element `e` of `mesh` with the kinematics of `plane` (`thickness`: planar states only).
    pub fn of_plane(mesh: &Mesh<Planar>, e: usize, plane: Plane, thickness: f64) -> Self {
        match plane {
            Plane::Axisymmetric => Cst::ring(mesh, e),
            Plane::Strain | Plane::Stress => Cst::planar(mesh, e, thickness),
        }
    }

    /// The nodes, the area and the in-plane rows of B (the z row zero).
    fn in_plane(mesh: &Mesh<Planar>, e: usize) -> ([usize; 3], f64, BMatrix) {
        let nodes = mesh.elements[e];
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
    type Space = Planar;
    const ROWS: [usize; 4] = PLANAR;

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

/// The linear tetrahedron: constant strain over its volume V. Its nodes are positively
/// oriented, det[x1 − x0, x2 − x0, x3 − x0] = 6V > 0 (`Mesh::validate`).
#[derive(Debug, Clone)]
pub struct Tet4 {
    nodes: [usize; 4],
    volume: f64,
    b: SMatrix<f64, 6, 12>,
}

impl Tet4 {
    /// Tetrahedron `e` of `mesh`: B from the gradients of its linear shape functions,
    /// ∇N_k = (row k of the inverse of [1 x y z] at the nodes), rows εx, εy, εz, γyz, γxz, γxy.
    pub fn new(mesh: &Mesh<Spatial>, e: usize) -> Self {
        let nodes = mesh.elements[e];
        let p = nodes.map(|i| mesh.nodes[i]);
        let jac = nalgebra::Matrix3::from_fn(|r, c| p[c + 1][r] - p[0][r]); // columns x_k − x_0
        let det = jac.determinant();
        let inv = jac.try_inverse().unwrap_or_else(nalgebra::Matrix3::zeros); // validate refuses det ≤ 0
                                                                              // ∇N_k = rows of J⁻¹ (k = 1..3), ∇N_0 = −their sum.
        let mut grad = [[0.0; 3]; 4];
        for k in 0..3 {
            for c in 0..3 {
                grad[k + 1][c] = inv[(k, c)];
                grad[0][c] -= inv[(k, c)];
            }
        }
        let mut b = SMatrix::<f64, 6, 12>::zeros();
        for (k, [gx, gy, gz]) in grad.into_iter().enumerate() {
            let (x, y, z) = (3 * k, 3 * k + 1, 3 * k + 2);
            b[(0, x)] = gx;
            b[(1, y)] = gy;
            b[(2, z)] = gz;
            (b[(3, y)], b[(3, z)]) = (gz, gy); // γyz = ∂v/∂z + ∂w/∂y
            (b[(4, x)], b[(4, z)]) = (gz, gx); // γxz = ∂u/∂z + ∂w/∂x
            (b[(5, x)], b[(5, y)]) = (gy, gx); // γxy = ∂u/∂y + ∂v/∂x
        }
        Tet4 { nodes, volume: det / 6.0, b }
    }
}

impl Element<6, 12> for Tet4 {
    type Space = Spatial;
    const ROWS: [usize; 6] = [0, 1, 2, 3, 4, 5];

    fn nodes(&self) -> &[usize] {
        &self.nodes
    }

    /// 3 per node: x, y, z.
    fn dofs(&self) -> [usize; 12] {
        std::array::from_fn(|k| 3 * self.nodes[k / 3] + k % 3)
    }

    fn b(&self) -> &SMatrix<f64, 6, 12> {
        &self.b
    }

    fn measure(&self) -> f64 {
        self.volume
    }
}

/// The elements of a model, of one kind: triangles (2D) or tetrahedra (3D). Loops over them
/// are written once, generically over `Element`, and run on either (`on_elements!`).
#[derive(Debug, Clone)]
pub enum Elements {
    Plane(Vec<Cst>),
    Space(Vec<Tet4>),
}

/// The elements of a dimension (`dim`): the constant-strain triangle in the plane, with the
/// kinematics of its stress state, the linear tetrahedron in space.
pub trait Discretization: Dim {
    /// The elements of `mesh` under `section`.
    fn elements(mesh: &Mesh<Self>, section: &Self::Section) -> Elements;
}

impl Discretization for Planar {
    fn elements(mesh: &Mesh<Self>, section: &PlaneSection) -> Elements {
        let (plane, thickness) = (section.plane, section.thickness);
        Elements::Plane(
            (0..mesh.n_elements()).map(|e| Cst::of_plane(mesh, e, plane, thickness)).collect(),
        )
    }
}

impl Discretization for Spatial {
    fn elements(mesh: &Mesh<Self>, _: &()) -> Elements {
        Elements::Space((0..mesh.n_elements()).map(|e| Tet4::new(mesh, e)).collect())
    }
}

/// `on_elements!(elements, els => body)`: the body with `els` the `Elements`' vector, whichever
/// kind it holds.
#[macro_export]
macro_rules! on_elements {
    ($elements:expr, $els:ident => $body:expr) => {
        match $elements {
            $crate::element::Elements::Plane($els) => $body,
            $crate::element::Elements::Space($els) => $body,
        }
    };
}

impl Elements {
    pub fn len(&self) -> usize {
        on_elements!(self, els => els.len())
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The nodes of element e.
    pub fn nodes(&self, e: usize) -> &[usize] {
        on_elements!(self, els => els[e].nodes())
    }

    /// The global DOFs of element e.
    pub fn dofs(&self, e: usize) -> Vec<usize> {
        on_elements!(self, els => els[e].dofs().to_vec())
    }

    /// The strain of element e (six components) for the displacement `u`.
    pub fn strain(&self, e: usize, u: &[f64]) -> Voigt {
        on_elements!(self, els => els[e].strain(u))
    }

    /// f[d] += sign × (w Bᵀ σ)_d of element e at its DOFs d that `keep` accepts.
    pub fn add_internal_force(
        &self,
        e: usize,
        stress: &Voigt,
        sign: f64,
        keep: impl Fn(usize) -> bool,
        f: &mut [f64],
    ) {
        on_elements!(self, els => {
            let fe = els[e].internal_force(stress);
            for (k, d) in els[e].dofs().into_iter().enumerate() {
                if keep(d) {
                    f[d] += sign * fe[k];
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{Planar, Spatial};
    use crate::material::{from_planar, Material};
    use crate::section::Section;
    use nalgebra::Matrix6;

    fn element(m: &Mesh<Planar>, e: usize, plane: Plane, thickness: f64) -> Cst {
        Cst::of_plane(m, e, plane, thickness)
    }

    /// D of the material as the plane's element pairs it with B.
    fn elastic_d(material: Material, plane: Plane) -> Matrix6<f64> {
        Section::new(material, plane.stress_state()).elastic_matrix()
    }

    /// One element away from the axis and one touching it (node 3 at r = 0).
    fn mesh() -> Mesh<Planar> {
        Mesh::<Planar>::new(
            vec![[0.1, 0.2], [1.3, 0.1], [0.4, 0.9], [0.0, 0.6]],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    /// Nodal values of a linear field u = (a0 + a1 x + a2 y, b0 + b1 x + b2 y).
    fn linear_field(m: &Mesh<Planar>, a: [f64; 3], b: [f64; 3]) -> Vec<f64> {
        m.nodes
            .iter()
            .flat_map(|p| [a[0] + a[1] * p[0] + a[2] * p[1], b[0] + b[1] * p[0] + b[2] * p[1]])
            .collect()
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
            assert!(
                (eps - from_planar([a, d, 0.0, b + c])).norm() < STRAIN_ROUND_OFF,
                "{plane:?}: {eps}"
            );
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
            assert!(
                (eps - from_planar([a, e, a, d])).norm() < STRAIN_ROUND_OFF,
                "element {k}: {eps}"
            );
        }
        // Any linear u_r = A r + B z + C: εθ is the exact u_r/r at the centroid.
        let (b, c) = (7e-4, -3e-4);
        let u = linear_field(&m, [c, a, b], [0.0, 0.0, 0.0]);
        for k in 0..2 {
            let el = element(&m, k, Plane::Axisymmetric, 1.0);
            let centre = m.elements[k]
                .map(|i| m.nodes[i])
                .iter()
                .fold([0.0; 2], |s, p| [s[0] + p[0] / 3.0, s[1] + p[1] / 3.0]);
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
        assert!(
            (element(&m, 1, Plane::Strain, 7.0).measure() - 7.0 * m.signed_area2(1) / 2.0).abs()
                < 1e-15
        );
    }

    /// Rigid modes of an element: translation x, translation y, rotation about the origin.
    fn rigid_modes(m: &Mesh<Planar>, e: usize) -> [ElementVector; 3] {
        let p = m.elements[e].map(|i| m.nodes[i]);
        let rot = |k: usize| [-p[k][1], p[k][0]];
        [
            ElementVector::from_row_slice(&[1., 0., 1., 0., 1., 0.]),
            ElementVector::from_row_slice(&[0., 1., 0., 1., 0., 1.]),
            ElementVector::from_row_slice(&[
                rot(0)[0],
                rot(0)[1],
                rot(1)[0],
                rot(1)[1],
                rot(2)[0],
                rot(2)[1],
            ]),
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
            assert!(
                (el.b() * ty).norm() < STRAIN_ROUND_OFF && (k * ty).norm() < 1e-12 * k.norm(),
                "element {e}"
            );
            for mode in [tx, rot] {
                let strain = el.b() * mode;
                assert!(strain[HOOP].abs() > 0.1, "element {e}: {strain}");
                let energy = (mode.transpose() * k * mode)[0];
                assert!(
                    (energy - el.measure() * (strain.transpose() * Cst::rows_of(&d) * strain)[0])
                        .abs()
                        < 1e-10 * energy
                        && energy > 0.0
                );
            }
            assert!((k - k.transpose()).norm() < 1e-12 * k.norm());
        }
    }

    /// A tetrahedron of general shape (positively oriented) and one on the axes.
    fn tets() -> Mesh<Spatial> {
        Mesh::<Spatial>::new(
            vec![
                [0.1, 0.2, -0.1],
                [1.3, 0.1, 0.2],
                [0.4, 0.9, 0.0],
                [0.3, 0.4, 1.1],
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [0.0, 3.0, 0.0],
                [0.0, 0.0, 4.0],
            ],
            vec![[0, 1, 2, 3], [4, 5, 6, 7]],
        )
    }

    /// A linear field u = c + G x at every node of `m` (3 per node).
    fn linear_field_3d(m: &Mesh<Spatial>, c: [f64; 3], g: [[f64; 3]; 3]) -> Vec<f64> {
        m.nodes
            .iter()
            .flat_map(|p| (0..3).map(move |i| c[i] + (0..3).map(|j| g[i][j] * p[j]).sum::<f64>()))
            .collect()
    }

    #[test]
    fn tetrahedron_gives_a_linear_fields_exact_strain() {
        // ε = sym(G) with engineering shears: (G00, G11, G22, G12 + G21, G02 + G20, G01 + G10).
        let m = tets();
        let g = [[1e-3, -2e-3, 5e-4], [3e-4, 2e-3, -1e-3], [7e-4, 4e-4, -1.5e-3]];
        let u = linear_field_3d(&m, [0.7, -0.2, 0.4], g);
        let exact = Voigt::from_row_slice(&[
            g[0][0],
            g[1][1],
            g[2][2],
            g[1][2] + g[2][1],
            g[0][2] + g[2][0],
            g[0][1] + g[1][0],
        ]);
        for e in 0..2 {
            let eps = Tet4::new(&m, e).strain(&u);
            assert!((eps - exact).norm() < STRAIN_ROUND_OFF, "element {e}: {eps}");
        }
    }

    #[test]
    fn tetrahedron_volume_and_nodal_forces_are_the_face_formulas() {
        // V of the corner tetrahedron (2, 3, 4 on the axes) = 2·3·4/6 = 4; under a uniform σ
        // node k carries w Bᵀσ = −σ·(A n)_k/3, (A n)_k the outward area vector of the face
        // opposite node k (the divergence theorem on ∫σ ∇N_k).
        let m = tets();
        assert!((Tet4::new(&m, 1).measure() - 4.0).abs() < 1e-14);
        let sigma = Voigt::from_row_slice(&[120.0, -80.0, 30.0, 15.0, -25.0, 40.0]);
        let s = |i: usize, j: usize| sigma[[[0, 5, 4], [5, 1, 3], [4, 3, 2]][i][j]];
        for e in 0..2 {
            let el = Tet4::new(&m, e);
            let f = el.internal_force(&sigma);
            let p = m.elements[e].map(|i| m.nodes[i]);
            for k in 0..4 {
                let face: Vec<[f64; 3]> = (0..4).filter(|&j| j != k).map(|j| p[j]).collect();
                let (a, b) = (
                    [0, 1, 2].map(|c| face[1][c] - face[0][c]),
                    [0, 1, 2].map(|c| face[2][c] - face[0][c]),
                );
                let mut area = [
                    a[1] * b[2] - a[2] * b[1],
                    a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0],
                ]
                .map(|v| v / 2.0);
                let inward = (0..3).map(|c| area[c] * (p[k][c] - face[0][c])).sum::<f64>() > 0.0;
                if inward {
                    area = area.map(|v| -v);
                }
                for i in 0..3 {
                    let expected = -(0..3).map(|j| s(i, j) * area[j]).sum::<f64>() / 3.0;
                    assert!(
                        (f[3 * k + i] - expected).abs() < 1e-11 * 120.0,
                        "element {e} node {k} component {i}: {} vs {expected}",
                        f[3 * k + i]
                    );
                }
            }
        }
    }

    #[test]
    fn tetrahedron_has_exactly_the_six_rigid_modes_as_zero_energy() {
        // Translations and rotations (u = ω × x) strain nothing; K (12×12, symmetric) has rank 6.
        let m = tets();
        let d = Section::new(Material::elastic(70e3, 0.3), &crate::section::Solid).elastic_matrix();
        for e in 0..2 {
            let el = Tet4::new(&m, e);
            let k = el.stiffness(&d);
            assert!((k - k.transpose()).norm() < 1e-12 * k.norm());
            for mode in 0..6 {
                let u = m
                    .nodes
                    .iter()
                    .flat_map(|p| {
                        let (t, w) = if mode < 3 { (mode, None) } else { (0, Some(mode - 3)) };
                        (0..3).map(move |c| match w {
                            None => (c == t) as i32 as f64,
                            Some(a) => {
                                [[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]][a][c]
                            }
                        })
                    })
                    .collect::<Vec<f64>>();
                let ue = el.gather(&u);
                assert!((k * ue).norm() < 1e-9 * k.norm(), "element {e} mode {mode}");
            }
            let sv = k.singular_values();
            let rank = sv.iter().filter(|&&v| v > 1e-9 * sv.max()).count();
            assert_eq!(rank, 6, "element {e}: {sv}");
        }
    }

    #[test]
    fn flat_and_inverted_tetrahedra_are_named() {
        let mut m = tets();
        m.elements[1] = [4, 6, 5, 7];
        assert!(m
            .validate()
            .unwrap_err()
            .message
            .starts_with("element 1 is an inverted tetrahedron"));
        m.elements[1] = [4, 5, 6, 7];
        let (p0, p1, p2) = (m.nodes[0], m.nodes[1], m.nodes[2]);
        m.nodes[3] = std::array::from_fn(|c| (p0[c] + p1[c] + p2[c]) / 3.0); // in the plane of the others
        let err = m.validate().unwrap_err().message;
        assert!(err.starts_with("element 0 is a flat tetrahedron"), "{err}");
    }
}
