"""The bulk problem's weak form on the 2D section, in Voigt notation: one strain, one measure.

    strain(w) = (eps_x, eps_y, gamma_xy)                       (CST: constant per cell)
    dOmega    = t dx,   dGamma(tag) = t ds(tag)                t: the thickness
    internal force      r(v)    = int  s . strain(v) dOmega    s: DG0 stress (x, y, xy)
    tangent stiffness   J(u, v) = int (C strain(u)) . strain(v) dOmega,  C: DG0 tangent
    edge load           f(v)    = int (traction - q n) . v dGamma(tag)

Plane strain and plane stress differ only in C and s (condensed on sigma_z = 0 by
:mod:`.plasticity`), not here.  Axisymmetry (issue 15; r = x, z = y) changes the two
definitions of :class:`Section` and nothing else of the weak form: the strain gains
eps_theta = u_r / r (four components, the engine's (x, y, z, xy) order with z = theta, so
``STRAIN`` and the DG0 spaces sized by it grow to 4) and the weight of both measures becomes
2 pi r; the constitutive update then takes the four strain increments.
"""

from __future__ import annotations

from . import dolfinx_api as api


class WeightedMeasure:
    """A UFL measure times the section's weight: ``integrand * dOmega`` is
    ``integrand * weight * dx``; ``dGamma(tag)`` restricts a boundary measure to a tag."""

    def __init__(self, weight, measure):
        self.weight, self.measure = weight, measure

    def __rmul__(self, integrand):
        return integrand * self.weight * self.measure

    def __call__(self, subdomain_id):
        return WeightedMeasure(self.weight, self.measure(subdomain_id))


class Section:
    """A plane section of the given thickness (plane strain or plane stress)."""

    STRAIN = ("x", "y", "xy")  # the components of strain(w), engineering shear

    def __init__(self, mesh, thickness: float, facet_tags=None):
        ufl = api.ufl()
        self.thickness = float(thickness)
        weight = api.constant(mesh, self.thickness)
        self.dOmega = WeightedMeasure(weight, ufl.dx)
        self.dGamma = WeightedMeasure(weight, ufl.Measure("ds", domain=mesh,
                                                         subdomain_data=facet_tags))

    @staticmethod
    def strain(w):
        """(eps_x, eps_y, gamma_xy) of a displacement w."""
        return api.ufl().as_vector([w[0].dx(0), w[1].dx(1), w[0].dx(1) + w[1].dx(0)])
