//! The stress state of a 2D model and the section that binds it to a material (paper §2.2,
//! eqs. 10–11, Appendix A.3–A.6).
//!
//! A material's law is three-dimensional (`material`: four components x, y, z, xy here, z the
//! out-of-plane direction); an element's strain operator has a row for each of them
//! (`element`). What z is makes the stress state, and each is an implementation of
//! `StressState`:
//! - `PlaneStrain`: εz = 0 (its row of B is zero), σz tracked; K pairs B with D restricted to
//!   (x, y, xy);
//! - `PlaneStress`: σz = 0, εz follows from it (static condensation of the tangent, A.3);
//! - `Axisymmetric`: rings about the axis x = 0 (x = r, y = the axis), z the hoop direction θ
//!   with εθ = u_r/r: every component is live and D is whole.
//!
//! A `Section` binds a material to the model's stress state once; the driver asks it for
//! tangents, stress increments and returns to the yield surface and never names the plane. A
//! solid (six components) is a further implementation with its own element, not a branch.

use crate::element::Cst;
use crate::material::{von_mises, Material, Plane, Tangent};
use crate::mesh::Mesh;
use nalgebra::{Matrix3, Matrix4, RowVector3, Vector3, Vector4};
use std::fmt::Debug;

/// What the out-of-plane direction z of a 2D model is (see the module text).
pub trait StressState: Debug + Send + Sync {
    /// Element `e` of `mesh` with this state's kinematics (`thickness`: planar states only).
    fn element(&self, mesh: &Mesh, e: usize, thickness: f64) -> Cst;

    /// The elastic D over (x, y, z, xy) as the element pairs it with its B: the classical
    /// closed forms. (`element_matrix` of an elastic tangent agrees with them to round-off.)
    fn elastic_matrix(&self, m: &Material) -> Matrix4<f64>;

    /// The D the element pairs with its four-row strain operator B (K_e = w Bᵀ D B, eq. 36)
    /// for a material tangent `d4` over (x, y, z, xy).
    fn element_matrix(&self, d4: &Matrix4<f64>) -> Matrix4<f64>;

    /// The full strain (εx, εy, εz, γxy) of an element strain (the rows of its B) under the
    /// tangent `d4`: the element strain itself where the kinematics give εz.
    fn full_strain(&self, _d4: &Matrix4<f64>, e: &Vector4<f64>) -> Vector4<f64> {
        *e
    }

    /// Whether an element strain is the whole strain (εz given by the kinematics), so that a
    /// plastic increment has von Mises's closed form; false: εz follows from the tangent.
    fn strain_is_whole(&self) -> bool {
        true
    }

    /// σ with the part the yield function sees scaled by `factor`: the deviator at fixed mean
    /// stress.
    fn scale_onto_surface(&self, stress: &Vector4<f64>, factor: f64) -> Vector4<f64> {
        let p = (stress[0] + stress[1] + stress[2]) / 3.0;
        let mean = Vector4::new(p, p, p, 0.0);
        mean + (stress - mean) * factor
    }
}

/// εz = 0, σz tracked.
#[derive(Debug, Clone, Copy)]
pub struct PlaneStrain;

/// σz = 0, εz from it.
#[derive(Debug, Clone, Copy)]
pub struct PlaneStress;

/// Rings about the axis x = 0; z is the hoop direction θ (εθ = u_r/r).
#[derive(Debug, Clone, Copy)]
pub struct Axisymmetric;

impl StressState for PlaneStrain {
    fn element(&self, mesh: &Mesh, e: usize, thickness: f64) -> Cst {
        Cst::planar(mesh, e, thickness)
    }

    fn elastic_matrix(&self, m: &Material) -> Matrix4<f64> {
        let (e, nu) = (m.young, m.poisson);
        let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
        #[rustfmt::skip]
        let d = Matrix3::new(
            c * (1.0 - nu), c * nu, 0.0,
            c * nu, c * (1.0 - nu), 0.0,
            0.0, 0.0, c * (1.0 - 2.0 * nu) / 2.0,
        );
        embed_in_plane(&d)
    }

    fn element_matrix(&self, d4: &Matrix4<f64>) -> Matrix4<f64> {
        embed_in_plane(&restricted(d4))
    }
}

impl StressState for PlaneStress {
    fn element(&self, mesh: &Mesh, e: usize, thickness: f64) -> Cst {
        Cst::planar(mesh, e, thickness)
    }

    fn elastic_matrix(&self, m: &Material) -> Matrix4<f64> {
        let (e, nu) = (m.young, m.poisson);
        let c = e / (1.0 - nu * nu);
        #[rustfmt::skip]
        let d = Matrix3::new(
            c, c * nu, 0.0,
            c * nu, c, 0.0,
            0.0, 0.0, c * (1.0 - nu) / 2.0,
        );
        embed_in_plane(&d)
    }

    fn element_matrix(&self, d4: &Matrix4<f64>) -> Matrix4<f64> {
        embed_in_plane(&condensed(d4))
    }

    fn full_strain(&self, d4: &Matrix4<f64>, e: &Vector4<f64>) -> Vector4<f64> {
        let in_plane = Vector3::new(e[0], e[1], e[3]);
        Vector4::new(e[0], e[1], (condensed_strain_z(d4) * in_plane)[0], e[3])
    }

    fn strain_is_whole(&self) -> bool {
        false
    }

    /// Radially: the in-plane stress scaled keeps σz = 0.
    fn scale_onto_surface(&self, stress: &Vector4<f64>, factor: f64) -> Vector4<f64> {
        stress * factor
    }
}

impl StressState for Axisymmetric {
    fn element(&self, mesh: &Mesh, e: usize, _thickness: f64) -> Cst {
        Cst::ring(mesh, e)
    }

    fn elastic_matrix(&self, m: &Material) -> Matrix4<f64> {
        m.elastic_d4()
    }

    /// The whole 4×4 tangent: the hoop row of B is live.
    fn element_matrix(&self, d4: &Matrix4<f64>) -> Matrix4<f64> {
        *d4
    }
}

impl Plane {
    /// The stress state this plane names.
    pub fn stress_state(self) -> &'static dyn StressState {
        match self {
            Plane::Strain => &PlaneStrain,
            Plane::Stress => &PlaneStress,
            Plane::Axisymmetric => &Axisymmetric,
        }
    }
}

/// A material under the model's stress state: everything the loop asks of an element's
/// constitutive law, with the plane bound in once.
#[derive(Debug, Clone, Copy)]
pub struct Section {
    pub material: Material,
    state: &'static dyn StressState,
}

impl Section {
    pub fn new(material: Material, state: &'static dyn StressState) -> Self {
        Section { material, state }
    }

    /// The material tangent at stress σ: elastic, or elastoplastic (eq. 11) when plastic.
    pub fn tangent(&self, stress: &Vector4<f64>, plastic: bool) -> Tangent {
        self.material.tangent(stress, plastic)
    }

    /// Elastic D as the element pairs it with its B (closed form).
    pub fn elastic_matrix(&self) -> Matrix4<f64> {
        self.state.elastic_matrix(&self.material)
    }

    /// The D the element pairs with its B for a tangent of this section.
    pub fn element_matrix(&self, t: &Tangent) -> Matrix4<f64> {
        self.state.element_matrix(&t.d4)
    }

    /// Δσ (four components) for an element strain increment (eq. 10 with D or D_ep).
    pub fn stress_increment(&self, t: &Tangent, e: &Vector4<f64>) -> Vector4<f64> {
        t.d4 * self.state.full_strain(&t.d4, e)
    }

    /// Equivalent plastic strain increment Δεp = (D a)ᵀ Δε / (H' + aᵀ D a) (Prandtl–Reuss);
    /// negative means elastic unloading. 0 for an elastic tangent.
    pub fn plastic_multiplier(&self, t: &Tangent, e: &Vector4<f64>) -> f64 {
        match t.flow {
            None => 0.0,
            Some(f) => f.da.dot(&self.state.full_strain(&t.d4, e)) / f.denom,
        }
    }

    /// D_ep Δε (eq. 11) at a stress on the yield surface and the plastic multiplier
    /// Δεp = (D a)ᵀ Δε / (H' + aᵀ D a), unclamped (negative: unloading), given D Δε. Where the
    /// element strain is the whole strain, von Mises gives the closed forms
    /// D a = (3G/σe) (sx, sy, sz, τxy) and aᵀ D a = 3G (s the deviator), so no tangent is built;
    /// otherwise (plane stress) it goes through the condensed tangent.
    pub fn plastic_increment(&self, stress: &Vector4<f64>, e: &Vector4<f64>, d_elastic: &Vector4<f64>) -> (Vector4<f64>, f64) {
        if !self.state.strain_is_whole() {
            let t = self.tangent(stress, true);
            return (self.stress_increment(&t, e), self.plastic_multiplier(&t, e));
        }
        let m = &self.material;
        let g = m.young / (2.0 * (1.0 + m.poisson));
        let p = (stress[0] + stress[1] + stress[2]) / 3.0;
        let da = Vector4::new(stress[0] - p, stress[1] - p, stress[2] - p, stress[3]) * (3.0 * g / von_mises(stress));
        let multiplier = da.dot(e) / (m.hardening + 3.0 * g);
        (d_elastic - da * multiplier, multiplier)
    }

    /// The stress scaled back onto the yield surface σe = σy (`StressState::scale_onto_surface`).
    pub fn onto_yield_surface(&self, stress: &Vector4<f64>, sy: f64) -> Vector4<f64> {
        let se = von_mises(stress);
        if !(se > 0.0) {
            return *stress;
        }
        self.state.scale_onto_surface(stress, sy / se)
    }

    /// A plastic element's stress at an increment's start: beyond its yield surface (the drift
    /// of the last correction) scaled back onto it; inside it (a correction that unloaded it
    /// along D_ep) kept, since `stress_integration::integrate` takes it elastically up to the
    /// surface. (Scaling it out onto the surface instead is a stress change without a strain,
    /// an out-of-balance force that the next correction undoes along D_ep, leaving the same
    /// drift inside again: in plane stress, where the scaling is radial, the drift then never
    /// decays and the increments stall.)
    pub fn not_beyond_surface(&self, stress: &Vector4<f64>, sy: f64) -> Vector4<f64> {
        if von_mises(stress) > sy {
            self.onto_yield_surface(stress, sy)
        } else {
            *stress
        }
    }
}

/// The in-plane components (x, y, xy) among (x, y, z, xy).
const IN_PLANE: [usize; 3] = [0, 1, 3];

/// A 3×3 matrix over (x, y, xy) as a 4×4 one over (x, y, z, xy) with a zero z row and column.
fn embed_in_plane(m: &Matrix3<f64>) -> Matrix4<f64> {
    let mut d = Matrix4::zeros();
    for i in 0..3 {
        for j in 0..3 {
            d[(IN_PLANE[i], IN_PLANE[j])] = m[(i, j)];
        }
    }
    d
}

/// The in-plane 3×3 block of a tangent (εz = 0).
fn restricted(d4: &Matrix4<f64>) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| d4[(IN_PLANE[i], IN_PLANE[j])])
}

/// The in-plane 3×3 tangent with σz = 0 (static condensation).
fn condensed(d4: &Matrix4<f64>) -> Matrix3<f64> {
    let mut d = restricted(d4);
    let col_z = Vector3::from_fn(|i, _| d4[(IN_PLANE[i], 2)]);
    let row_z = RowVector3::from_fn(|_, j| d4[(2, IN_PLANE[j])]);
    d -= col_z * row_z / d4[(2, 2)];
    d
}

/// Out-of-plane strain per unit in-plane strain in plane stress, from σz = 0.
fn condensed_strain_z(d4: &Matrix4<f64>) -> RowVector3<f64> {
    let dz = d4[(2, 2)];
    RowVector3::from_fn(|_, j| -d4[(2, IN_PLANE[j])] / dz)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::flow_vector;

    fn section(m: Material, plane: Plane) -> Section {
        Section::new(m, plane.stress_state())
    }

    #[test]
    fn plane_strain_tangent_inverts_hooke() {
        // Plane strain: εz = 0 ⇒ εx = ((1-ν²)σx − ν(1+ν)σy)/E. Check D against this compliance.
        let m = Material::elastic(70_000.0, 0.3);
        let d = restricted(&section(m, Plane::Strain).elastic_matrix());
        let (e, nu) = (m.young, m.poisson);
        #[rustfmt::skip]
        let c = Matrix3::new(
            (1.0 - nu * nu) / e, -nu * (1.0 + nu) / e, 0.0,
            -nu * (1.0 + nu) / e, (1.0 - nu * nu) / e, 0.0,
            0.0, 0.0, 2.0 * (1.0 + nu) / e,
        );
        let id = d * c;
        assert!((id - Matrix3::identity()).norm() < 1e-12);
    }

    #[test]
    fn plane_stress_uniaxial() {
        let m = Material::elastic(200.0, 0.25);
        let s = section(m, Plane::Stress);
        let d = s.elastic_matrix();
        // σ = (1,0,0) ⇒ ε = (1/E, −ν/E, 0); the z row and column are zero
        let eps = Vector4::new(1.0 / 200.0, -0.25 / 200.0, 0.0, 0.0);
        assert!((d * eps - Vector4::new(1.0, 0.0, 0.0, 0.0)).norm() < 1e-14);
        // and the condensed elastic tangent agrees with it (to round-off)
        let t = s.tangent(&Vector4::zeros(), false);
        assert!((s.element_matrix(&t) - d).norm() < 1e-13 * d.norm());
    }

    #[test]
    fn axisymmetric_tangent_is_the_whole_d_and_inverts_hooke() {
        // Rings: D over (εr, εz, εθ, γrz) is the 3D isotropic D; it inverts the compliance
        // ε = ((1+ν)σ − ν tr σ)/E (normal) and γ = 2(1+ν)τ/E (round-off of a 4×4 product).
        let m = Material::elastic(70_000.0, 0.3);
        let s = section(m, Plane::Axisymmetric);
        let d = s.elastic_matrix();
        let (e, nu) = (m.young, m.poisson);
        let c = Matrix4::from_fn(|i, j| match (i, j) {
            (3, 3) => 2.0 * (1.0 + nu) / e,
            (3, _) | (_, 3) => 0.0,
            _ if i == j => 1.0 / e,
            _ => -nu / e,
        });
        assert!((d * c - Matrix4::identity()).norm() < 1e-12);
        let t = s.tangent(&Vector4::zeros(), false);
        assert_eq!(s.element_matrix(&t), d);
        // the hoop strain is live: Δσ of a pure hoop strain has σθ = (λ + 2G) εθ
        let ds = s.stress_increment(&t, &Vector4::new(0.0, 0.0, 1e-3, 0.0));
        assert!((ds[2] - d[(2, 2)] * 1e-3).abs() < 1e-12 && ds[0] == ds[1]);
    }

    /// Al with linear hardening (E = 70 GPa, ν = 0.3, Sy = 200 MPa, H' = 700 MPa).
    fn hardening_aluminium() -> Material {
        Material { yield_stress: 200.0, hardening: 700.0, ..Material::elastic(70_000.0, 0.3) }
    }

    /// The paper's compliance form (A.2): C_ep = C + a aᵀ / H' (a = ∂σe/∂σ).
    fn compliance_a2(m: &Material, s: &Vector4<f64>) -> Matrix4<f64> {
        let a = flow_vector(s);
        m.elastic_d4().try_inverse().unwrap() + a * a.transpose() / m.hardening
    }

    #[test]
    fn stiffness_form_agrees_with_compliance_form_a2_a3_a6() {
        let m = hardening_aluminium();
        // Plane strain (A.6): the 4×4 forms are inverse to each other, hence also their
        // εz = 0 restrictions (A.5–A.6 condense the compliance, we restrict the stiffness).
        let s = Vector4::new(-150.0, -320.0, -141.0, 60.0);
        let t = m.tangent(&s, true);
        let c = compliance_a2(&m, &s);
        assert!((t.d4 * c - Matrix4::identity()).norm() < 1e-10);
        let d_strain = restricted(&c.try_inverse().unwrap());
        assert!((restricted(&t.d4) - d_strain).norm() < 1e-9 * d_strain.norm());
        // Plane stress (A.3): σz = 0, the in-plane compliance is the 3×3 block of A.2.
        let s = Vector4::new(120.0, -90.0, 0.0, 40.0);
        let t = m.tangent(&s, true);
        let c3 = restricted(&compliance_a2(&m, &s));
        assert!((condensed(&t.d4) * c3 - Matrix3::identity()).norm() < 1e-10);
    }

    #[test]
    fn plastic_tangent_is_a_rank_one_update_that_survives_h_zero() {
        let mut m = Material::elastic(70_000.0, 0.3);
        m.yield_stress = 200.0;
        m.hardening = 0.0; // perfect plasticity: A.2 would divide by zero
        let s = Vector4::new(100.0, -100.0, 0.0, 20.0);
        for plane in [Plane::Strain, Plane::Stress, Plane::Axisymmetric] {
            let sec = section(m, plane);
            let diff = sec.element_matrix(&sec.tangent(&s, true)) - sec.element_matrix(&sec.tangent(&s, false));
            let mut v: Vec<f64> = diff.singular_values().iter().copied().collect();
            v.sort_by(|a, b| b.partial_cmp(a).unwrap());
            assert!(v[0] > 0.0 && v[1] < 1e-9 * v[0], "{plane:?}: {v:?}");
        }
        // H' = 0: a plastic increment along the flow leaves σe unchanged (aᵀ D_ep = 0).
        let t = m.tangent(&s, true);
        let a = flow_vector(&s);
        assert!((a.transpose() * t.d4).norm() < 1e-9 * t.d4.norm());
    }

    /// The closed-form plastic step of plane strain and axisymmetry is the inverse of the
    /// paper's compliance (A.2) applied to the strain, and its multiplier is Prandtl–Reuss's
    /// dεp = a·Δσ / H' (eqs. 7–9) of that stress increment.
    #[test]
    fn closed_form_plastic_step_inverts_the_compliance_a2() {
        let m = hardening_aluminium();
        let s = Vector4::new(-150.0, -320.0, -141.0, 60.0);
        let e = Vector4::new(-2e-4, 3e-4, 0.5e-4, 1e-4);
        for plane in [Plane::Strain, Plane::Axisymmetric] {
            let d_elastic = m.elastic_d4() * e;
            let (ds, multiplier) = section(m, plane).plastic_increment(&s, &e, &d_elastic);
            let expected = compliance_a2(&m, &s).try_inverse().unwrap() * e;
            assert!((ds - expected).norm() < 1e-9 * expected.norm(), "{plane:?}: {ds} vs {expected}");
            let a = flow_vector(&s);
            assert!((multiplier - a.dot(&ds) / m.hardening).abs() < 1e-9 * multiplier.abs());
        }
    }

    /// Back onto the surface: the deviator scaled at fixed mean stress (plane strain), the
    /// whole stress keeping σz = 0 (plane stress); a stress inside is kept.
    #[test]
    fn returns_onto_the_surface_keep_what_the_state_holds() {
        let m = hardening_aluminium();
        let s = Vector4::new(300.0, -100.0, 60.0, 80.0);
        let strain = section(m, Plane::Strain).onto_yield_surface(&s, 200.0);
        assert!((von_mises(&strain) - 200.0).abs() < 1e-12 * 200.0);
        assert!(((strain[0] + strain[1] + strain[2]) - (s[0] + s[1] + s[2])).abs() < 1e-12 * 300.0);
        let flat = Vector4::new(300.0, -100.0, 0.0, 80.0);
        let stress = section(m, Plane::Stress).onto_yield_surface(&flat, 200.0);
        assert!((von_mises(&stress) - 200.0).abs() < 1e-12 * 200.0 && stress[2] == 0.0);
        let inside = s * (100.0 / von_mises(&s));
        assert_eq!(section(m, Plane::Strain).not_beyond_surface(&inside, 200.0), inside);
    }
}
