//! The stress state of a model and the section that binds it to a material (paper §2.2,
//! eqs. 10–11, Appendix A.3–A.6).
//!
//! A material's law is three-dimensional (`material`: the six Voigt components); a 2D
//! element's strain operator has a row for each of x, y, z, xy (`element`), z the out-of-plane
//! direction, the other two shears zero. What z is makes the stress state, and each is an
//! implementation of `StressState`:
//! - `PlaneStrain`: εz = 0 (its row of B is zero), σz tracked; K pairs B with D restricted to
//!   (x, y, xy);
//! - `PlaneStress`: σz = 0, εz follows from it (static condensation of the tangent, A.3);
//! - `Axisymmetric`: rings about the axis x = 0 (x = r, y = the axis), z the hoop direction θ
//!   with εθ = u_r/r: every component is live and D is whole.
//!
//! - `Solid`: a three-dimensional body (linear tetrahedra): all six components are live, D is
//!   whole, and nothing is condensed.
//!
//! A `Section` binds a material to the model's stress state once; the driver asks it for
//! tangents, stress increments and returns to the yield surface and never names the plane or
//! the dimension.

use crate::material::{deviator, voigt_dot, von_mises, Material, Plane, Tangent, Voigt};
use nalgebra::{Matrix3, Matrix6, RowVector3, Vector3};
use std::fmt::Debug;

/// What the model's stress state is (see the module text).
pub trait StressState: Debug + Send + Sync {
    /// The elastic D over the six components as the element pairs it with its B: the
    /// classical closed forms. (`element_matrix` of an elastic tangent agrees with them to
    /// round-off.)
    fn elastic_matrix(&self, m: &Material) -> Matrix6<f64>;

    /// The D the element pairs with its strain operator B (K_e = w Bᵀ D B, eq. 36) for a
    /// material tangent `d` (the element takes the rows of its B from it).
    fn element_matrix(&self, d: &Matrix6<f64>) -> Matrix6<f64>;

    /// The full strain of an element strain (the rows of its B, the others 0) under the
    /// tangent `d`: the element strain itself where the kinematics give every component.
    fn full_strain(&self, _d: &Matrix6<f64>, e: &Voigt) -> Voigt {
        *e
    }

    /// Whether an element strain is the whole strain (εz given by the kinematics), so that a
    /// plastic increment has von Mises's closed form; false: εz follows from the tangent.
    fn strain_is_whole(&self) -> bool {
        true
    }

    /// σ with the part the yield function sees scaled by `factor`: the deviator at fixed mean
    /// stress.
    fn scale_onto_surface(&self, stress: &Voigt, factor: f64) -> Voigt {
        let p = (stress[0] + stress[1] + stress[2]) / 3.0;
        let mean = Voigt::from_fn(|i, _| if i < 3 { p } else { 0.0 });
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

/// A three-dimensional body: every component live.
#[derive(Debug, Clone, Copy)]
pub struct Solid;

impl StressState for Solid {
    fn elastic_matrix(&self, m: &Material) -> Matrix6<f64> {
        m.elastic_d()
    }

    fn element_matrix(&self, d: &Matrix6<f64>) -> Matrix6<f64> {
        *d
    }
}

impl StressState for PlaneStrain {
    fn elastic_matrix(&self, m: &Material) -> Matrix6<f64> {
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

    fn element_matrix(&self, d: &Matrix6<f64>) -> Matrix6<f64> {
        embed_in_plane(&restricted(d))
    }
}

impl StressState for PlaneStress {
    fn elastic_matrix(&self, m: &Material) -> Matrix6<f64> {
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

    fn element_matrix(&self, d: &Matrix6<f64>) -> Matrix6<f64> {
        embed_in_plane(&condensed(d))
    }

    fn full_strain(&self, d: &Matrix6<f64>, e: &Voigt) -> Voigt {
        let in_plane = Vector3::new(e[0], e[1], e[XY]);
        let mut full = *e;
        full[2] = (condensed_strain_z(d) * in_plane)[0];
        full
    }

    fn strain_is_whole(&self) -> bool {
        false
    }

    /// Radially: the in-plane stress scaled keeps σz = 0.
    fn scale_onto_surface(&self, stress: &Voigt, factor: f64) -> Voigt {
        stress * factor
    }
}

impl StressState for Axisymmetric {
    fn elastic_matrix(&self, m: &Material) -> Matrix6<f64> {
        m.elastic_d()
    }

    /// The whole tangent: the hoop row of B is live (the element takes x, y, z, xy).
    fn element_matrix(&self, d: &Matrix6<f64>) -> Matrix6<f64> {
        *d
    }
}

impl Plane {
    /// The stress state this plane names (a solid's is `Solid`).
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
    pub fn tangent(&self, stress: &Voigt, plastic: bool) -> Tangent {
        self.material.tangent(stress, plastic)
    }

    /// Elastic D as the element pairs it with its B (closed form).
    pub fn elastic_matrix(&self) -> Matrix6<f64> {
        self.state.elastic_matrix(&self.material)
    }

    /// The D the element pairs with its B for a tangent of this section.
    pub fn element_matrix(&self, t: &Tangent) -> Matrix6<f64> {
        self.state.element_matrix(&t.d)
    }

    /// Δσ for an element strain increment (eq. 10 with D or D_ep).
    pub fn stress_increment(&self, t: &Tangent, e: &Voigt) -> Voigt {
        t.d * self.state.full_strain(&t.d, e)
    }

    /// Equivalent plastic strain increment Δεp = (D a)ᵀ Δε / (H' + aᵀ D a) (Prandtl–Reuss);
    /// negative means elastic unloading. 0 for an elastic tangent.
    pub fn plastic_multiplier(&self, t: &Tangent, e: &Voigt) -> f64 {
        match t.flow {
            None => 0.0,
            Some(f) => voigt_dot(&f.da, &self.state.full_strain(&t.d, e)) / f.denom,
        }
    }

    /// D_ep Δε (eq. 11) at a stress on the yield surface and the plastic multiplier
    /// Δεp = (D a)ᵀ Δε / (H' + aᵀ D a), unclamped (negative: unloading), given D Δε. Where the
    /// element strain is the whole strain, von Mises gives the closed forms
    /// D a = (3G/σe) s (s the deviator, its shears the τ's) and aᵀ D a = 3G, so no tangent is
    /// built; otherwise (plane stress) it goes through the condensed tangent.
    pub fn plastic_increment(&self, stress: &Voigt, e: &Voigt, d_elastic: &Voigt) -> (Voigt, f64) {
        if !self.state.strain_is_whole() {
            let t = self.tangent(stress, true);
            return (self.stress_increment(&t, e), self.plastic_multiplier(&t, e));
        }
        let m = &self.material;
        let g = m.shear_modulus();
        let da = deviator(stress) * (3.0 * g / von_mises(stress));
        let multiplier = voigt_dot(&da, e) / (m.hardening + 3.0 * g);
        (d_elastic - da * multiplier, multiplier)
    }

    /// The stress scaled back onto the yield surface σe = σy (`StressState::scale_onto_surface`).
    pub fn onto_yield_surface(&self, stress: &Voigt, sy: f64) -> Voigt {
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
    pub fn not_beyond_surface(&self, stress: &Voigt, sy: f64) -> Voigt {
        if von_mises(stress) > sy {
            self.onto_yield_surface(stress, sy)
        } else {
            *stress
        }
    }
}

/// The xy shear among the six components.
const XY: usize = 5;
/// The in-plane components (x, y, xy) among the six.
const IN_PLANE: [usize; 3] = [0, 1, XY];

/// A 3×3 matrix over (x, y, xy) as a 6×6 one with zero rows and columns elsewhere.
fn embed_in_plane(m: &Matrix3<f64>) -> Matrix6<f64> {
    let mut d = Matrix6::zeros();
    for i in 0..3 {
        for j in 0..3 {
            d[(IN_PLANE[i], IN_PLANE[j])] = m[(i, j)];
        }
    }
    d
}

/// The in-plane 3×3 block of a tangent (εz = 0).
fn restricted(d: &Matrix6<f64>) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| d[(IN_PLANE[i], IN_PLANE[j])])
}

/// The in-plane 3×3 tangent with σz = 0 (static condensation).
fn condensed(d6: &Matrix6<f64>) -> Matrix3<f64> {
    let mut d = restricted(d6);
    let col_z = Vector3::from_fn(|i, _| d6[(IN_PLANE[i], 2)]);
    let row_z = RowVector3::from_fn(|_, j| d6[(2, IN_PLANE[j])]);
    d -= col_z * row_z / d6[(2, 2)];
    d
}

/// Out-of-plane strain per unit in-plane strain in plane stress, from σz = 0.
fn condensed_strain_z(d: &Matrix6<f64>) -> RowVector3<f64> {
    let dz = d[(2, 2)];
    RowVector3::from_fn(|_, j| -d[(2, IN_PLANE[j])] / dz)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{flow_vector, from_planar, von_mises_squared};

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
        let eps = from_planar([1.0 / 200.0, -0.25 / 200.0, 0.0, 0.0]);
        assert!((d * eps - from_planar([1.0, 0.0, 0.0, 0.0])).norm() < 1e-14);
        // and the condensed elastic tangent agrees with it (to round-off)
        let t = s.tangent(&Voigt::zeros(), false);
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
        let c = Matrix6::from_fn(|i, j| match (i < 3, j < 3) {
            (false, false) if i == j => 2.0 * (1.0 + nu) / e,
            (true, true) if i == j => 1.0 / e,
            (true, true) => -nu / e,
            _ => 0.0,
        });
        assert!((d * c - Matrix6::identity()).norm() < 1e-12);
        let t = s.tangent(&Voigt::zeros(), false);
        assert_eq!(s.element_matrix(&t), d);
        // the hoop strain is live: Δσ of a pure hoop strain has σθ = (λ + 2G) εθ
        let ds = s.stress_increment(&t, &from_planar([0.0, 0.0, 1e-3, 0.0]));
        assert!((ds[2] - d[(2, 2)] * 1e-3).abs() < 1e-12 && ds[0] == ds[1]);
    }

    /// Al with linear hardening (E = 70 GPa, ν = 0.3, Sy = 200 MPa, H' = 700 MPa).
    fn hardening_aluminium() -> Material {
        Material { yield_stress: 200.0, hardening: 700.0, ..Material::elastic(70_000.0, 0.3) }
    }

    /// The paper's compliance form (A.2): C_ep = C + a aᵀ / H' (a = ∂σe/∂σ).
    fn compliance_a2(m: &Material, s: &Voigt) -> Matrix6<f64> {
        let a = flow_vector(s);
        m.elastic_d().try_inverse().unwrap() + a * a.transpose() / m.hardening
    }

    #[test]
    fn stiffness_form_agrees_with_compliance_form_a2_a3_a6() {
        let m = hardening_aluminium();
        // Plane strain (A.6): the 4×4 forms are inverse to each other, hence also their
        // εz = 0 restrictions (A.5–A.6 condense the compliance, we restrict the stiffness).
        let s = from_planar([-150.0, -320.0, -141.0, 60.0]);
        let t = m.tangent(&s, true);
        let c = compliance_a2(&m, &s);
        assert!((t.d * c - Matrix6::identity()).norm() < 1e-10);
        let d_strain = restricted(&c.try_inverse().unwrap());
        assert!((restricted(&t.d) - d_strain).norm() < 1e-9 * d_strain.norm());
        // Plane stress (A.3): σz = 0, the in-plane compliance is the 3×3 block of A.2.
        let s = from_planar([120.0, -90.0, 0.0, 40.0]);
        let t = m.tangent(&s, true);
        let c3 = restricted(&compliance_a2(&m, &s));
        assert!((condensed(&t.d) * c3 - Matrix3::identity()).norm() < 1e-10);
    }

    #[test]
    fn plastic_tangent_is_a_rank_one_update_that_survives_h_zero() {
        let mut m = Material::elastic(70_000.0, 0.3);
        m.yield_stress = 200.0;
        m.hardening = 0.0; // perfect plasticity: A.2 would divide by zero
        let s = from_planar([100.0, -100.0, 0.0, 20.0]);
        for plane in [Plane::Strain, Plane::Stress, Plane::Axisymmetric] {
            let sec = section(m, plane);
            let diff = sec.element_matrix(&sec.tangent(&s, true))
                - sec.element_matrix(&sec.tangent(&s, false));
            let mut v: Vec<f64> = diff.singular_values().iter().copied().collect();
            v.sort_by(|a, b| b.partial_cmp(a).unwrap());
            assert!(v[0] > 0.0 && v[1] < 1e-9 * v[0], "{plane:?}: {v:?}");
        }
        // H' = 0: a plastic increment along the flow leaves σe unchanged (aᵀ D_ep = 0).
        let t = m.tangent(&s, true);
        let a = flow_vector(&s);
        assert!((a.transpose() * t.d).norm() < 1e-9 * t.d.norm());
    }

    /// The closed-form plastic step of plane strain and axisymmetry is the inverse of the
    /// paper's compliance (A.2) applied to the strain, and its multiplier is Prandtl–Reuss's
    /// dεp = a·Δσ / H' (eqs. 7–9) of that stress increment.
    #[test]
    fn closed_form_plastic_step_inverts_the_compliance_a2() {
        let m = hardening_aluminium();
        let s = from_planar([-150.0, -320.0, -141.0, 60.0]);
        let e = from_planar([-2e-4, 3e-4, 0.5e-4, 1e-4]);
        for plane in [Plane::Strain, Plane::Axisymmetric] {
            let d_elastic = m.elastic_d() * e;
            let (ds, multiplier) = section(m, plane).plastic_increment(&s, &e, &d_elastic);
            let expected = compliance_a2(&m, &s).try_inverse().unwrap() * e;
            assert!(
                (ds - expected).norm() < 1e-9 * expected.norm(),
                "{plane:?}: {ds} vs {expected}"
            );
            let a = flow_vector(&s);
            assert!((multiplier - a.dot(&ds) / m.hardening).abs() < 1e-9 * multiplier.abs());
        }
    }

    /// Back onto the surface: the deviator scaled at fixed mean stress (plane strain), the
    /// whole stress keeping σz = 0 (plane stress); a stress inside is kept.
    #[test]
    fn returns_onto_the_surface_keep_what_the_state_holds() {
        let m = hardening_aluminium();
        let s = from_planar([300.0, -100.0, 60.0, 80.0]);
        let strain = section(m, Plane::Strain).onto_yield_surface(&s, 200.0);
        assert!((von_mises(&strain) - 200.0).abs() < 1e-12 * 200.0);
        assert!(((strain[0] + strain[1] + strain[2]) - (s[0] + s[1] + s[2])).abs() < 1e-12 * 300.0);
        let flat = from_planar([300.0, -100.0, 0.0, 80.0]);
        let stress = section(m, Plane::Stress).onto_yield_surface(&flat, 200.0);
        assert!((von_mises(&stress) - 200.0).abs() < 1e-12 * 200.0 && stress[2] == 0.0);
        let inside = s * (100.0 / von_mises(&s));
        assert_eq!(section(m, Plane::Strain).not_beyond_surface(&inside, 200.0), inside);
    }

    /// In space (`Solid`): the closed-form plastic step is the inverse of the compliance A.2
    /// over all six components, with D a = (3G/σe) s and aᵀ D a = 3G (Prandtl–Reuss), and the
    /// tangent is whole.
    #[test]
    fn solid_plastic_step_inverts_the_compliance_a2_in_six_components() {
        let m = hardening_aluminium();
        let sec = Section::new(m, &Solid);
        let s = Voigt::from_row_slice(&[-150.0, -320.0, -141.0, 45.0, -30.0, 60.0]);
        let e = Voigt::from_row_slice(&[-2e-4, 3e-4, 0.5e-4, -0.7e-4, 1.2e-4, 1e-4]);
        let (ds, multiplier) = sec.plastic_increment(&s, &e, &(m.elastic_d() * e));
        let expected = compliance_a2(&m, &s).try_inverse().unwrap() * e;
        assert!((ds - expected).norm() < 1e-9 * expected.norm(), "{ds} vs {expected}");
        assert!(
            (multiplier - flow_vector(&s).dot(&ds) / m.hardening).abs() < 1e-9 * multiplier.abs()
        );
        let t = sec.tangent(&s, true);
        let (a, g) = (flow_vector(&s), m.shear_modulus());
        let se = von_mises(&s);
        let dev = crate::material::deviator(&s);
        assert!((m.elastic_d() * a - dev * (3.0 * g / se)).norm() < 1e-9 * g, "D a = (3G/σe) s");
        assert!((a.dot(&(m.elastic_d() * a)) - 3.0 * g).abs() < 1e-9 * g, "aᵀ D a = 3G");
        assert_eq!(sec.element_matrix(&t), t.d);
        assert_eq!(sec.elastic_matrix(), m.elastic_d());
    }

    /// The von Mises quadratic form in space: σe² = ½[(σx−σy)² + (σy−σz)² + (σz−σx)²]
    /// + 3(τyz² + τxz² + τxy²), here from its definition sqrt(3/2 s:s) with the tensor's nine
    /// entries; scaling onto the surface keeps the mean stress.
    #[test]
    fn von_mises_in_space_is_the_quadratic_form() {
        let s = Voigt::from_row_slice(&[120.0, -80.0, 30.0, 15.0, -25.0, 40.0]);
        let t = [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]];
        let p = (s[0] + s[1] + s[2]) / 3.0;
        let ss: f64 = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| {
                let d = t[i][j] - if i == j { p } else { 0.0 };
                d * d
            })
            .sum();
        assert!((von_mises_squared(&s) - 1.5 * ss).abs() < 1e-10 * ss);
        let on = Section::new(hardening_aluminium(), &Solid).onto_yield_surface(&s, 50.0);
        assert!(
            (von_mises(&on) - 50.0).abs() < 1e-12 * 50.0
                && ((on[0] + on[1] + on[2]) - 3.0 * p).abs() < 1e-12 * 100.0
        );
    }
}
