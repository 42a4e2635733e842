//! Isotropic elasticity and von Mises plasticity with linear isotropic hardening
//! (paper §2.2, eqs. 4–11, 18 and Appendix A).
//!
//! Stresses and strains carry four components (x, y, z, xy) with engineering shear strain
//! (eq. 10), z the out-of-plane direction: plane strain (εz = 0, σz tracked), plane stress
//! (σz = 0) and axisymmetry (x = r, y = the axis z, and the z component is the hoop direction
//! θ: εθ = u_r/r) share one code path. The 4×4 tangent is built once; the element's strain
//! operator has four rows for every plane (element.rs), and `Tangent::element_matrix` gives the
//! D it pairs with: restricted (plane strain), statically condensed (plane stress) or whole
//! (axisymmetry).
//!
//! Prandtl–Reuss (eqs. 5–7) with the flow vector a = ∂σe/∂σ gives the elastoplastic tangent in
//! *stiffness* form,   D_ep = D − (D a)(D a)ᵀ / (H' + aᵀ D a)   (eq. 11),
//! which stays finite for perfect plasticity H' = 0; the paper's compliance form (A.2–A.6)
//! divides by H' (the tests check that both agree for H' > 0). D_ep − D is rank one.

use crate::bail;
use crate::error::Result;
use nalgebra::{Matrix3, Matrix4, RowVector3, Vector3, Vector4};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    Strain,
    Stress,
    /// Rings about the axis x = 0 (x = r >= 0, y = z); the z component is the hoop θ.
    Axisymmetric,
}

/// The magnitudes E, Sy and H (unless 0) may have, in the case's stress unit. Stresses reach
/// E × the nominal strain of the loads (between 1e-100 and 1: `Model::validate`), and the
/// yield scale (eqs. 12–16) multiplies two squared stresses: within 1e±50 those products stay
/// below 1e200 and the smallest stress a load may make still squares to a normal f64 (1e-300).
pub const MAGNITUDES: (f64, f64) = (1e-50, 1e50);

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E
    pub young: f64,
    /// Poisson's ratio ν
    pub poisson: f64,
    /// Yield stress Sy (∞ = elastic); used by the plasticity extension.
    pub yield_stress: f64,
    /// Plastic modulus H' (slope of the uniaxial stress–plastic strain curve).
    pub hardening: f64,
}

impl Material {
    pub fn elastic(young: f64, poisson: f64) -> Self {
        Material { young, poisson, yield_stress: f64::INFINITY, hardening: 0.0 }
    }

    /// Reject values no solid can have, and magnitudes whose squares leave f64's range
    /// (`MAGNITUDES`), naming the material (`name`, e.g. "body 'block' material") and the fix.
    pub fn validate(&self, name: &str) -> Result<()> {
        let (e, nu, sy, h) = (self.young, self.poisson, self.yield_stress, self.hardening);
        let (low, high) = MAGNITUDES;
        let beyond = |v: f64| v != 0.0 && v.is_finite() && !(low..=high).contains(&v);
        let unit = format!("must lie within [{low:e}, {high:e}] in the case's stress unit (beyond, squared stresses leave the range of f64): give stresses in another unit (steel: E = 2e5 in MPa, 2e11 in Pa)");
        if !e.is_finite() || e <= 0.0 {
            bail!(Input, "{name}: E = {e:?} is not allowed: Young's modulus must be a finite positive number");
        }
        if beyond(e) {
            bail!(Input, "{name}: E = {e:?} is not allowed: Young's modulus {unit}");
        }
        if !nu.is_finite() || nu <= -1.0 || nu >= 0.5 {
            bail!(Input, "{name}: nu = {nu:?} is not allowed: Poisson's ratio must satisfy -1 < nu < 0.5 (use 0.499 for a near-incompressible solid)");
        }
        if sy.is_nan() || sy <= 0.0 {
            bail!(Input, "{name}: Sy = {sy:?} is not allowed: the yield stress must be positive (omit it for an elastic body)");
        }
        if beyond(sy) {
            bail!(Input, "{name}: Sy = {sy:?} is not allowed: the yield stress {unit}");
        }
        // A yield strain below 1e-12 means wrong units; it would also overflow the relative
        // drift |σe − σy|/σy (found by tests/test_fuzz.py with Sy = 5e-324).
        if sy.is_finite() && sy < 1e-12 * e {
            bail!(Input, "{name}: Sy = {sy:?} is not allowed: the yield strain Sy/E = {:.3e} is below 1e-12; check the units of Sy and E", sy / e);
        }
        if !h.is_finite() || h < 0.0 {
            bail!(Input, "{name}: H = {h:?} is not allowed: the plastic modulus H' must be >= 0 (0 = perfectly plastic)");
        }
        if beyond(h) {
            bail!(Input, "{name}: H = {h:?} is not allowed: the plastic modulus H' (unless 0) {unit}");
        }
        Ok(())
    }

    pub fn is_plastic(&self) -> bool {
        self.yield_stress.is_finite()
    }

    /// Current yield stress σy(εp) = Sy + H' εp (linear isotropic hardening, eq. 6).
    pub fn current_yield(&self, plastic_strain: f64) -> f64 {
        self.yield_stress + self.hardening * plastic_strain
    }

    /// Isotropic D over (x, y, z, xy), engineering shear.
    pub fn elastic_d4(&self) -> Matrix4<f64> {
        let (e, nu) = (self.young, self.poisson);
        let lame = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let g = e / (2.0 * (1.0 + nu));
        let d = lame + 2.0 * g;
        Matrix4::new(
            d, lame, lame, 0.0,
            lame, d, lame, 0.0,
            lame, lame, d, 0.0,
            0.0, 0.0, 0.0, g,
        )
    }

    /// Tangent at stress σ: elastic, or elastoplastic (eq. 11) for an element that is plastic.
    pub fn tangent(&self, stress: &Vector4<f64>, plastic: bool) -> Tangent {
        let d4 = self.elastic_d4();
        if !plastic {
            return Tangent { d4, flow: None };
        }
        let a = flow_vector(stress);
        let da = d4 * a;
        let denom = self.hardening + a.dot(&da);
        Tangent { d4: d4 - da * da.transpose() / denom, flow: Some(Flow { da, denom }) }
    }

    /// D_ep Δε (eq. 11) at a stress on the yield surface and the plastic multiplier
    /// Δεp = (D a)ᵀ Δε / (H' + aᵀ D a), unclamped (negative: unloading), given D Δε. In plane
    /// strain and axisymmetry Δε is the whole strain, and von Mises gives the closed forms
    /// D a = (3G/σe) (sx, sy, sz, τxy) and aᵀ D a = 3G (s the deviator), so no tangent is built;
    /// plane stress goes through the condensed tangent.
    pub fn plastic_increment(&self, plane: Plane, stress: &Vector4<f64>, e: &Vector4<f64>, d_elastic: &Vector4<f64>) -> (Vector4<f64>, f64) {
        if plane == Plane::Stress {
            let t = self.tangent(stress, true);
            return (t.stress_increment(plane, e), t.plastic_multiplier(plane, e));
        }
        let g = self.young / (2.0 * (1.0 + self.poisson));
        let p = (stress[0] + stress[1] + stress[2]) / 3.0;
        let da = Vector4::new(stress[0] - p, stress[1] - p, stress[2] - p, stress[3]) * (3.0 * g / von_mises(stress));
        let multiplier = da.dot(e) / (self.hardening + 3.0 * g);
        (d_elastic - da * multiplier, multiplier)
    }

    /// Elastic D over (x, y, z, xy) as the element pairs it with its strain operator: the
    /// plane strain or plane stress 3×3 matrix embedded with a zero z row and column, the
    /// whole D in axisymmetry. (The planar forms are the classical closed forms; `element_matrix`
    /// of an elastic tangent agrees with them to round-off.)
    pub fn elastic_tangent(&self, plane: Plane) -> Matrix4<f64> {
        let (e, nu) = (self.young, self.poisson);
        match plane {
            Plane::Strain => {
                let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
                embed_in_plane(&Matrix3::new(
                    c * (1.0 - nu), c * nu, 0.0,
                    c * nu, c * (1.0 - nu), 0.0,
                    0.0, 0.0, c * (1.0 - 2.0 * nu) / 2.0,
                ))
            }
            Plane::Stress => {
                let c = e / (1.0 - nu * nu);
                embed_in_plane(&Matrix3::new(
                    c, c * nu, 0.0,
                    c * nu, c, 0.0,
                    0.0, 0.0, c * (1.0 - nu) / 2.0,
                ))
            }
            Plane::Axisymmetric => self.elastic_d4(),
        }
    }
}

/// σe = sqrt(3/2 s:s) (eq. 6) of (σx, σy, σz, τxy).
pub fn von_mises(s: &Vector4<f64>) -> f64 {
    von_mises_squared(s).max(0.0).sqrt()
}

/// σe² as the quadratic form σᵀ P σ of eqs. 12–13.
pub fn von_mises_squared(s: &Vector4<f64>) -> f64 {
    s[0] * s[0] + s[1] * s[1] + s[2] * s[2] - s[0] * s[1] - s[1] * s[2] - s[2] * s[0] + 3.0 * s[3] * s[3]
}

fn von_mises_bilinear(s: &Vector4<f64>, t: &Vector4<f64>) -> f64 {
    s[0] * t[0] + s[1] * t[1] + s[2] * t[2] - 0.5 * (s[0] * t[1] + s[1] * t[0] + s[1] * t[2] + s[2] * t[1] + s[2] * t[0] + s[0] * t[2])
        + 3.0 * s[3] * t[3]
}

/// a = ∂σe/∂σ = 3/(2σe) (sx, sy, sz, 2τxy) (engineering shear pairing).
pub fn flow_vector(s: &Vector4<f64>) -> Vector4<f64> {
    let se = von_mises(s);
    let p = (s[0] + s[1] + s[2]) / 3.0;
    Vector4::new(s[0] - p, s[1] - p, s[2] - p, 2.0 * s[3]) * (1.5 / se)
}

/// Yield scale factor S_p (eqs. 12–16): the smallest S ≥ 0 with σe(σ + S Δσ) = σy.
/// Returns None if the increment never reaches the yield surface.
pub fn yield_scale(stress: &Vector4<f64>, dstress: &Vector4<f64>, yield_stress: f64) -> Option<f64> {
    let a2 = von_mises_squared(dstress); // Δσe of eq. 12/13
    let a1 = 2.0 * von_mises_bilinear(stress, dstress); // D of eq. 12/13
    let a0 = von_mises_squared(stress) - yield_stress * yield_stress; // σ̄e − Sy²
    if a0 >= 0.0 {
        return if a1 > 0.0 { Some(0.0) } else { None };
    }
    if a2 <= 0.0 {
        return None;
    }
    let disc = (a1 * a1 - 4.0 * a2 * a0).sqrt(); // a0 < 0 ⇒ one positive root
    Some(if a1 >= 0.0 { -2.0 * a0 / (a1 + disc) } else { (-a1 + disc) / (2.0 * a2) })
}

/// The plastic part of a tangent: D a and H' + aᵀ D a (both at the increment's start).
#[derive(Debug, Clone, Copy)]
pub struct Flow {
    pub da: Vector4<f64>,
    pub denom: f64,
}

/// A material tangent over (x, y, z, xy), and how it reduces to the plane.
#[derive(Debug, Clone, Copy)]
pub struct Tangent {
    pub d4: Matrix4<f64>,
    pub flow: Option<Flow>,
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

impl Tangent {
    /// Out-of-plane strain per unit in-plane strain in plane stress, from σz = 0 (static
    /// condensation).
    fn condensed_strain_z(&self) -> RowVector3<f64> {
        let dz = self.d4[(2, 2)];
        RowVector3::from_fn(|_, j| -self.d4[(2, IN_PLANE[j])] / dz)
    }

    /// The full strain (εx, εy, εz, γxy) of an element strain (its operator's four rows, z
    /// zero in plane strain and plane stress, εθ in axisymmetry): εz from σz = 0 in plane
    /// stress, as it is otherwise.
    pub fn full_strain(&self, plane: Plane, e: &Vector4<f64>) -> Vector4<f64> {
        match plane {
            Plane::Stress => {
                let in_plane = Vector3::new(e[0], e[1], e[3]);
                Vector4::new(e[0], e[1], (self.condensed_strain_z() * in_plane)[0], e[3])
            }
            Plane::Strain | Plane::Axisymmetric => *e,
        }
    }

    /// In-plane 3×3 tangent (x, y, xy): restricted (εz = 0) or condensed (σz = 0).
    fn in_plane(&self, plane: Plane) -> Matrix3<f64> {
        let mut d = Matrix3::from_fn(|i, j| self.d4[(IN_PLANE[i], IN_PLANE[j])]);
        if plane == Plane::Stress {
            let col_z = Vector3::from_fn(|i, _| self.d4[(IN_PLANE[i], 2)]);
            let row_z = RowVector3::from_fn(|_, j| self.d4[(2, IN_PLANE[j])]);
            d -= col_z * row_z / self.d4[(2, 2)];
        }
        d
    }

    /// The D the element pairs with its four-row strain operator B (K_e = w Bᵀ D B, eq. 36):
    /// the plane strain restriction or the plane stress condensation with a zero z row and
    /// column, the whole 4×4 tangent in axisymmetry (the hoop row of B is live there).
    pub fn element_matrix(&self, plane: Plane) -> Matrix4<f64> {
        match plane {
            Plane::Strain | Plane::Stress => embed_in_plane(&self.in_plane(plane)),
            Plane::Axisymmetric => self.d4,
        }
    }

    /// Δσ (4 components) for an element strain increment (eq. 10 with D or D_ep).
    pub fn stress_increment(&self, plane: Plane, e: &Vector4<f64>) -> Vector4<f64> {
        self.d4 * self.full_strain(plane, e)
    }

    /// Equivalent plastic strain increment Δεp = (D a)ᵀ Δε / (H' + aᵀ D a) (Prandtl–Reuss);
    /// negative means elastic unloading. 0 for an elastic tangent.
    pub fn plastic_multiplier(&self, plane: Plane, e: &Vector4<f64>) -> f64 {
        match self.flow {
            None => 0.0,
            Some(f) => f.da.dot(&self.full_strain(plane, e)) / f.denom,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subnormal_moduli_and_vanishing_yield_strains_are_refused() {
        let mut m = Material::elastic(5e-324, 0.3);
        assert!(m.validate("material 0").unwrap_err().message.contains("E = 5e-324"));
        m = Material::elastic(70_000.0, 0.3);
        m.yield_stress = 1e-9;
        assert!(m.validate("material 0").unwrap_err().message.contains("yield strain"));
        m.yield_stress = 200.0;
        assert!(m.validate("material 0").is_ok());
    }

    #[test]
    fn plane_strain_tangent_inverts_hooke() {
        // Plane strain: εz = 0 ⇒ εx = ((1-ν²)σx − ν(1+ν)σy)/E. Check D against this compliance.
        let m = Material::elastic(70_000.0, 0.3);
        let d = Matrix3::from_fn(|i, j| m.elastic_tangent(Plane::Strain)[(IN_PLANE[i], IN_PLANE[j])]);
        let (e, nu) = (m.young, m.poisson);
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
        let d = m.elastic_tangent(Plane::Stress);
        // σ = (1,0,0) ⇒ ε = (1/E, −ν/E, 0); the z row and column are zero
        let eps = Vector4::new(1.0 / 200.0, -0.25 / 200.0, 0.0, 0.0);
        let s = d * eps;
        assert!((s - Vector4::new(1.0, 0.0, 0.0, 0.0)).norm() < 1e-14);
        // and the condensed elastic tangent agrees with it (to round-off)
        let t = m.tangent(&Vector4::zeros(), false);
        assert!((t.element_matrix(Plane::Stress) - d).norm() < 1e-13 * d.norm());
    }

    #[test]
    fn axisymmetric_tangent_is_the_whole_d_and_inverts_hooke() {
        // Rings: D over (εr, εz, εθ, γrz) is the 3D isotropic D; it inverts the compliance
        // ε = ((1+ν)σ − ν tr σ)/E (normal) and γ = 2(1+ν)τ/E (round-off of a 4×4 product).
        let m = Material::elastic(70_000.0, 0.3);
        let d = m.elastic_tangent(Plane::Axisymmetric);
        let (e, nu) = (m.young, m.poisson);
        let c = Matrix4::from_fn(|i, j| match (i, j) {
            (3, 3) => 2.0 * (1.0 + nu) / e,
            (3, _) | (_, 3) => 0.0,
            _ if i == j => 1.0 / e,
            _ => -nu / e,
        });
        assert!((d * c - Matrix4::identity()).norm() < 1e-12);
        assert_eq!(m.tangent(&Vector4::zeros(), false).element_matrix(Plane::Axisymmetric), d);
        // the hoop strain is live: Δσ of a pure hoop strain has σθ = (λ + 2G) εθ
        let s = m.tangent(&Vector4::zeros(), false).stress_increment(Plane::Axisymmetric, &Vector4::new(0.0, 0.0, 1e-3, 0.0));
        assert!((s[2] - d[(2, 2)] * 1e-3).abs() < 1e-12 && s[0] == s[1]);
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
        let ci = c.try_inverse().unwrap();
        let d_strain = Matrix3::from_fn(|i, j| ci[(IN_PLANE[i], IN_PLANE[j])]);
        assert!((t.in_plane(Plane::Strain) - d_strain).norm() < 1e-9 * d_strain.norm());
        // Plane stress (A.3): σz = 0, the in-plane compliance is the 3×3 block of A.2.
        let s = Vector4::new(120.0, -90.0, 0.0, 40.0);
        let t = m.tangent(&s, true);
        let c = compliance_a2(&m, &s);
        let c3 = Matrix3::from_fn(|i, j| c[(IN_PLANE[i], IN_PLANE[j])]);
        assert!((t.in_plane(Plane::Stress) * c3 - Matrix3::identity()).norm() < 1e-10);
    }

    #[test]
    fn plastic_tangent_is_a_rank_one_update_that_survives_h_zero() {
        let mut m = Material::elastic(70_000.0, 0.3);
        m.yield_stress = 200.0;
        m.hardening = 0.0; // perfect plasticity: A.2 would divide by zero
        let s = Vector4::new(100.0, -100.0, 0.0, 20.0);
        for plane in [Plane::Strain, Plane::Stress, Plane::Axisymmetric] {
            let diff = m.tangent(&s, true).element_matrix(plane) - m.tangent(&s, false).element_matrix(plane);
            let sv = diff.singular_values();
            let mut v: Vec<f64> = sv.iter().copied().collect();
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
            let (ds, multiplier) = m.plastic_increment(plane, &s, &e, &d_elastic);
            let expected = compliance_a2(&m, &s).try_inverse().unwrap() * e;
            assert!((ds - expected).norm() < 1e-9 * expected.norm(), "{plane:?}: {ds} vs {expected}");
            let a = flow_vector(&s);
            assert!((multiplier - a.dot(&ds) / m.hardening).abs() < 1e-9 * multiplier.abs());
        }
    }

    #[test]
    fn yield_scale_lands_on_the_surface() {
        let s = Vector4::new(50.0, -20.0, 9.0, 30.0);
        let ds = Vector4::new(100.0, -40.0, 18.0, 10.0);
        let sp = yield_scale(&s, &ds, 200.0).unwrap();
        assert!((von_mises(&(s + ds * sp)) - 200.0).abs() < 1e-10);
        // Unloading towards the origin reaches the surface only after reversing (S > 2).
        assert!(yield_scale(&s, &(-s * 0.5), 200.0).unwrap() > 2.0);
        assert!(yield_scale(&s, &Vector4::zeros(), 200.0).is_none());
    }

    #[test]
    fn bad_values_are_named() {
        assert!(Material::elastic(-1.0, 0.3).validate("material 0").unwrap_err().message.contains("E = -1"));
        assert!(Material::elastic(1.0, 0.5).validate("material 2").unwrap_err().message.contains("material 2: nu = 0.5"));
    }

    /// Moduli whose squared stresses leave f64's range are refused by key, at the bounds and
    /// beyond them, in both directions; H = 0 and an infinite Sy (elastic) are not magnitudes.
    #[test]
    fn magnitudes_beyond_f64s_squares_are_refused() {
        let (low, high) = MAGNITUDES;
        let steel = Material { young: 2e5, poisson: 0.3, yield_stress: 250.0, hardening: 0.0 };
        assert!(steel.validate("m").is_ok());
        assert!(Material { young: high, yield_stress: 1e-3 * high, hardening: high, ..steel }.validate("m").is_ok());
        assert!(Material { young: low, yield_stress: 1e3 * low, hardening: low, ..steel }.validate("m").is_ok());
        for (bad, key) in [(Material { young: 1e200, ..steel }, "E = 1e200"), (Material { young: 1e-60, yield_stress: f64::INFINITY, ..steel }, "E = 1e-60"),
            (Material { yield_stress: 1e51, ..steel }, "Sy = 1e51"), (Material { hardening: 1e300, ..steel }, "H = 1e300"), (Material { hardening: 1e-51, ..steel }, "H = 1e-51")] {
            let msg = bad.validate("body 'b' material").unwrap_err().message;
            assert!(msg.starts_with(&format!("body 'b' material: {key} is not allowed")) && msg.contains("another unit"), "{msg}");
        }
    }
}
