//! Isotropic elasticity and von Mises plasticity with linear isotropic hardening
//! (paper §2.2, eqs. 4–11, 18 and Appendix A).
//!
//! Stresses and strains carry the six Voigt components (xx, yy, zz, yz, xz, xy) with
//! engineering shear strains (eq. 10). The law here is three-dimensional over them; a 2D model
//! uses (x, y, z, xy) with yz = xz = 0 and z the out-of-plane direction; what z is (plane
//! strain, plane stress, the hoop direction of axisymmetry, or a third coordinate of a solid)
//! and how an element's strain meets this law is the stress state's (`section`), bound to a
//! material by a `Section`. (The zero components add exact zeros to every sum here, so a 2D
//! history is the one of the former four-component law bit for bit.)
//!
//! Prandtl–Reuss (eqs. 5–7) with the flow vector a = ∂σe/∂σ gives the elastoplastic tangent in
//! *stiffness* form,   D_ep = D − (D a)(D a)ᵀ / (H' + aᵀ D a)   (eq. 11),
//! which stays finite for perfect plasticity H' = 0; the paper's compliance form (A.2–A.6)
//! divides by H' (the tests check that both agree for H' > 0). D_ep − D is rank one.

use crate::bail;
use crate::error::Result;
use nalgebra::{Matrix6, Vector6};

/// A stress or strain in Voigt order (xx, yy, zz, yz, xz, xy), engineering shear strains.
pub type Voigt = Vector6<f64>;
/// The shear components of `Voigt` (normal ones are 0..3).
pub const SHEARS: std::ops::Range<usize> = 3..6;
/// The 2D components (x, y, z, xy) of a plane or axisymmetric model among the six.
pub const PLANAR: [usize; 4] = [0, 1, 2, 5];

/// The stress state a model names (its implementation: `Plane::stress_state` in `section`).
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

/// The six components of a 2D stress or strain (x, y, z, xy).
pub fn from_planar(c: [f64; 4]) -> Voigt {
    let mut v = Voigt::zeros();
    PLANAR.iter().zip(c).for_each(|(&k, x)| v[k] = x);
    v
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
            bail!(
                Input,
                "{name}: H = {h:?} is not allowed: the plastic modulus H' (unless 0) {unit}"
            );
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

    /// Isotropic D over the six Voigt components, engineering shear.
    pub fn elastic_d(&self) -> Matrix6<f64> {
        let (e, nu) = (self.young, self.poisson);
        let lame = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let g = e / (2.0 * (1.0 + nu));
        let d = lame + 2.0 * g;
        Matrix6::from_fn(|i, j| match (i < 3, j < 3) {
            (true, true) if i == j => d,
            (true, true) => lame,
            (false, false) if i == j => g,
            _ => 0.0,
        })
    }

    /// The shear modulus G.
    pub fn shear_modulus(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// Tangent at stress σ: elastic, or elastoplastic (eq. 11) for an element that is plastic.
    pub fn tangent(&self, stress: &Voigt, plastic: bool) -> Tangent {
        let d = self.elastic_d();
        if !plastic {
            return Tangent { d, flow: None };
        }
        let a = flow_vector(stress);
        let da = d * a;
        let denom = self.hardening + voigt_dot(&a, &da);
        Tangent { d: d - da * da.transpose() / denom, flow: Some(Flow { da, denom }) }
    }
}

/// σe = sqrt(3/2 s:s) (eq. 6).
pub fn von_mises(s: &Voigt) -> f64 {
    von_mises_squared(s).max(0.0).sqrt()
}

/// σe² as the quadratic form σᵀ P σ of eqs. 12–13: ½[(σx−σy)² + (σy−σz)² + (σz−σx)²]
/// + 3(τyz² + τxz² + τxy²), in the form of the paper's P.
pub fn von_mises_squared(s: &Voigt) -> f64 {
    let normal = s[0] * s[0] + s[1] * s[1] + s[2] * s[2] - s[0] * s[1] - s[1] * s[2] - s[2] * s[0];
    SHEARS.fold(normal, |a, k| a + 3.0 * s[k] * s[k])
}

fn von_mises_bilinear(s: &Voigt, t: &Voigt) -> f64 {
    let normal = s[0] * t[0] + s[1] * t[1] + s[2] * t[2]
        - 0.5 * (s[0] * t[1] + s[1] * t[0] + s[1] * t[2] + s[2] * t[1] + s[2] * t[0] + s[0] * t[2]);
    SHEARS.fold(normal, |a, k| a + 3.0 * s[k] * t[k])
}

/// aᵀb of two six-component vectors, summed as (xx + zz + xz) + (yy + xy + yz): with the two
/// shears a 2D model does not have (yz, xz) last in each partial sum, a 2D product is the
/// one of the former four-component law bit for bit (nalgebra's 4-vector dot pairs (x + z) +
/// (y + xy)).
pub fn voigt_dot(a: &Voigt, b: &Voigt) -> f64 {
    (a[0] * b[0] + a[2] * b[2] + a[4] * b[4]) + (a[1] * b[1] + a[5] * b[5] + a[3] * b[3])
}

/// The deviator s of σ (its shear components are σ's).
pub fn deviator(s: &Voigt) -> Voigt {
    let p = (s[0] + s[1] + s[2]) / 3.0;
    Voigt::from_fn(|i, _| if i < 3 { s[i] - p } else { s[i] })
}

/// a = ∂σe/∂σ = 3/(2σe) (sx, sy, sz, 2τyz, 2τxz, 2τxy) (engineering shear pairing).
pub fn flow_vector(s: &Voigt) -> Voigt {
    let se = von_mises(s);
    let dev = deviator(s);
    Voigt::from_fn(|i, _| if i < 3 { dev[i] } else { 2.0 * dev[i] }) * (1.5 / se)
}

/// Yield scale factor S_p (eqs. 12–16): the smallest S ≥ 0 with σe(σ + S Δσ) = σy.
/// Returns None if the increment never reaches the yield surface.
pub fn yield_scale(stress: &Voigt, dstress: &Voigt, yield_stress: f64) -> Option<f64> {
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
    pub da: Voigt,
    pub denom: f64,
}

/// A material tangent over the six components: D or D_ep (eq. 11), and its plastic part. How
/// it acts on an element's strain is the section's (`section::Section`).
#[derive(Debug, Clone, Copy)]
pub struct Tangent {
    pub d: Matrix6<f64>,
    pub flow: Option<Flow>,
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
    fn yield_scale_lands_on_the_surface() {
        let s = Voigt::from_row_slice(&[50.0, -20.0, 9.0, -12.0, 7.0, 30.0]);
        let ds = Voigt::from_row_slice(&[100.0, -40.0, 18.0, 5.0, -3.0, 10.0]);
        let sp = yield_scale(&s, &ds, 200.0).unwrap();
        assert!((von_mises(&(s + ds * sp)) - 200.0).abs() < 1e-10);
        // Unloading towards the origin reaches the surface only after reversing (S > 2).
        assert!(yield_scale(&s, &(-s * 0.5), 200.0).unwrap() > 2.0);
        assert!(yield_scale(&s, &Voigt::zeros(), 200.0).is_none());
    }

    #[test]
    fn bad_values_are_named() {
        assert!(Material::elastic(-1.0, 0.3)
            .validate("material 0")
            .unwrap_err()
            .message
            .contains("E = -1"));
        assert!(Material::elastic(1.0, 0.5)
            .validate("material 2")
            .unwrap_err()
            .message
            .contains("material 2: nu = 0.5"));
    }

    /// Moduli whose squared stresses leave f64's range are refused by key, at the bounds and
    /// beyond them, in both directions; H = 0 and an infinite Sy (elastic) are not magnitudes.
    #[test]
    fn magnitudes_beyond_f64s_squares_are_refused() {
        let (low, high) = MAGNITUDES;
        let steel = Material { young: 2e5, poisson: 0.3, yield_stress: 250.0, hardening: 0.0 };
        assert!(steel.validate("m").is_ok());
        assert!(Material { young: high, yield_stress: 1e-3 * high, hardening: high, ..steel }
            .validate("m")
            .is_ok());
        assert!(Material { young: low, yield_stress: 1e3 * low, hardening: low, ..steel }
            .validate("m")
            .is_ok());
        for (bad, key) in [
            (Material { young: 1e200, ..steel }, "E = 1e200"),
            (Material { young: 1e-60, yield_stress: f64::INFINITY, ..steel }, "E = 1e-60"),
            (Material { yield_stress: 1e51, ..steel }, "Sy = 1e51"),
            (Material { hardening: 1e300, ..steel }, "H = 1e300"),
            (Material { hardening: 1e-51, ..steel }, "H = 1e-51"),
        ] {
            let msg = bad.validate("body 'b' material").unwrap_err().message;
            assert!(
                msg.starts_with(&format!("body 'b' material: {key} is not allowed"))
                    && msg.contains("another unit"),
                "{msg}"
            );
        }
    }
}
