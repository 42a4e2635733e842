//! Isotropic linear elasticity in the two planar idealisations (paper eqs. 9, 18).
//!
//! The tangent matrix `D` relates (σx, σy, τxy) to (εx, εy, γxy) (engineering shear strain,
//! eq. 10). Plasticity (Prandtl–Reuss, eq. 11 and Appendix A) will add an elastoplastic tangent
//! `D_ep = D − (D a)(D a)ᵀ / (H' + aᵀ D a)` per element on top of this; the driver already asks
//! each element for its tangent, so the yield event plugs into the same loop.

use crate::bail;
use crate::error::Result;
use nalgebra::Matrix3;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    Strain,
    Stress,
}

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

    /// Reject values no solid can have, naming the material and the fix.
    pub fn validate(&self, index: usize) -> Result<()> {
        let (e, nu) = (self.young, self.poisson);
        if !e.is_finite() || e <= 0.0 {
            bail!("material {index}: E = {e} is not allowed: Young's modulus must be a finite positive number");
        }
        if !nu.is_finite() || nu <= -1.0 || nu >= 0.5 {
            bail!("material {index}: nu = {nu} is not allowed: Poisson's ratio must satisfy -1 < nu < 0.5 (use 0.499 for a near-incompressible solid)");
        }
        if self.yield_stress.is_nan() || self.yield_stress <= 0.0 {
            bail!("material {index}: Sy = {} is not allowed: the yield stress must be positive (omit it for an elastic body)", self.yield_stress);
        }
        if !self.hardening.is_finite() || self.hardening < 0.0 {
            bail!("material {index}: H = {} is not allowed: the plastic modulus H' must be >= 0 (0 = perfectly plastic)", self.hardening);
        }
        Ok(())
    }

    /// Elastic stiffness D (plane strain or plane stress).
    pub fn elastic_tangent(&self, plane: Plane) -> Matrix3<f64> {
        let (e, nu) = (self.young, self.poisson);
        match plane {
            Plane::Strain => {
                let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
                Matrix3::new(
                    c * (1.0 - nu), c * nu, 0.0,
                    c * nu, c * (1.0 - nu), 0.0,
                    0.0, 0.0, c * (1.0 - 2.0 * nu) / 2.0,
                )
            }
            Plane::Stress => {
                let c = e / (1.0 - nu * nu);
                Matrix3::new(
                    c, c * nu, 0.0,
                    c * nu, c, 0.0,
                    0.0, 0.0, c * (1.0 - nu) / 2.0,
                )
            }
        }
    }

    /// Out-of-plane stress increment of an elastic element: σz = ν(σx + σy) in plane strain,
    /// 0 in plane stress.
    pub fn sigma_z(&self, plane: Plane, sx: f64, sy: f64) -> f64 {
        match plane {
            Plane::Strain => self.poisson * (sx + sy),
            Plane::Stress => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_strain_tangent_inverts_hooke() {
        // Plane strain: εz = 0 ⇒ εx = ((1-ν²)σx − ν(1+ν)σy)/E. Check D against this compliance.
        let m = Material::elastic(70_000.0, 0.3);
        let d = m.elastic_tangent(Plane::Strain);
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
        // σ = (1,0,0) ⇒ ε = (1/E, −ν/E, 0)
        let eps = nalgebra::Vector3::new(1.0 / 200.0, -0.25 / 200.0, 0.0);
        let s = d * eps;
        assert!((s - nalgebra::Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-14);
    }

    #[test]
    fn bad_values_are_named() {
        assert!(Material::elastic(-1.0, 0.3).validate(0).unwrap_err().0.contains("E = -1"));
        assert!(Material::elastic(1.0, 0.5).validate(2).unwrap_err().0.contains("material 2: nu = 0.5"));
    }
}
