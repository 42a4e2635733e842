//! The constant-strain triangle (CST): strain–displacement matrix B (eq. 10), stiffness
//! K_e = t·A·Bᵀ D B (the element part of K in eq. 36) and internal force t·A·Bᵀ σ (eq. 42).

use crate::mesh::Mesh;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

pub type BMatrix = SMatrix<f64, 3, 6>;
pub type ElementVector = SVector<f64, 6>;

#[derive(Debug, Clone)]
pub struct Cst {
    pub nodes: [usize; 3],
    pub area: f64,
    pub b: BMatrix,
}

impl Cst {
    pub fn new(mesh: &Mesh, e: usize) -> Self {
        let nodes = mesh.triangles[e];
        let [p1, p2, p3] = nodes.map(|i| mesh.nodes[i]);
        let area2 = mesh.signed_area2(e);
        let (b1, b2, b3) = (p2[1] - p3[1], p3[1] - p1[1], p1[1] - p2[1]);
        let (c1, c2, c3) = (p3[0] - p2[0], p1[0] - p3[0], p2[0] - p1[0]);
        #[rustfmt::skip]
        let b = BMatrix::from_row_slice(&[
            b1, 0.0, b2, 0.0, b3, 0.0,
            0.0, c1, 0.0, c2, 0.0, c3,
            c1, b1, c2, b2, c3, b3,
        ]) / area2;
        Cst { nodes, area: area2 / 2.0, b }
    }

    /// Global DOF numbers of the element (2 per node: x then y).
    pub fn dofs(&self) -> [usize; 6] {
        let [a, b, c] = self.nodes;
        [2 * a, 2 * a + 1, 2 * b, 2 * b + 1, 2 * c, 2 * c + 1]
    }

    pub fn gather(&self, u: &[f64]) -> ElementVector {
        ElementVector::from_iterator(self.dofs().iter().map(|&d| u[d]))
    }

    /// Strain (εx, εy, γxy) of the element for the global displacement vector `u`.
    pub fn strain(&self, u: &[f64]) -> Vector3<f64> {
        self.b * self.gather(u)
    }

    pub fn stiffness(&self, d: &Matrix3<f64>, thickness: f64) -> SMatrix<f64, 6, 6> {
        self.b.transpose() * d * self.b * (self.area * thickness)
    }

    /// Nodal internal forces t·A·Bᵀ σ for the in-plane stress (σx, σy, τxy).
    pub fn internal_force(&self, stress: &Vector3<f64>, thickness: f64) -> ElementVector {
        self.b.transpose() * stress * (self.area * thickness)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, Plane};

    fn tri() -> Mesh {
        Mesh { nodes: vec![[0.1, 0.2], [1.3, 0.1], [0.4, 0.9]], triangles: vec![[0, 1, 2]] }
    }

    #[test]
    fn linear_field_gives_its_exact_strain() {
        // Patch test at element level: u = (a x + b y, c x + d y) ⇒ ε = (a, d, b + c).
        let m = tri();
        let e = Cst::new(&m, 0);
        let (a, b, c, d) = (1e-3, -2e-3, 5e-4, 3e-3);
        let mut u = vec![0.0; 6];
        for (i, p) in m.nodes.iter().enumerate() {
            u[2 * i] = a * p[0] + b * p[1] + 0.7;
            u[2 * i + 1] = c * p[0] + d * p[1] - 0.2;
        }
        let eps = e.strain(&u);
        assert!((eps - Vector3::new(a, d, b + c)).norm() < 1e-15);
    }

    #[test]
    fn rigid_body_modes_have_zero_energy() {
        let m = tri();
        let e = Cst::new(&m, 0);
        let k = e.stiffness(&Material::elastic(70e3, 0.3).elastic_tangent(Plane::Strain), 1.0);
        let modes: [[f64; 6]; 3] = {
            let r = |p: [f64; 2]| [-p[1], p[0]];
            let (r0, r1, r2) = (r(m.nodes[0]), r(m.nodes[1]), r(m.nodes[2]));
            [[1., 0., 1., 0., 1., 0.], [0., 1., 0., 1., 0., 1.], [r0[0], r0[1], r1[0], r1[1], r2[0], r2[1]]]
        };
        for mode in modes {
            let f = k * ElementVector::from_row_slice(&mode);
            assert!(f.norm() < 1e-9 * k.norm(), "rigid mode loads the element: {f}");
        }
        assert!((k - k.transpose()).norm() < 1e-12 * k.norm());
    }
}
