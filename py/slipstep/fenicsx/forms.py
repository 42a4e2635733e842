"""The bulk problem's weak form on the 2D section, in Voigt notation: one strain, one measure.

    strain(w) = (eps_x, eps_y, gamma_xy)                       (CST: constant per cell)
    dOmega    = t dx,   dGamma(tag) = t ds(tag)                t: the thickness
    internal force      r(v)    = int  s . strain(v) dOmega    s: DG0 stress (x, y, xy)
    tangent stiffness   J(u, v) = int (C strain(u)) . strain(v) dOmega,  C: DG0 tangent
    edge load           f(v)    = int (traction - q n) . v dGamma(tag)

Plane strain and plane stress differ only in C and s (condensed on sigma_z = 0 by
:mod:`.plasticity`), not here.  Axisymmetry (:class:`RingSection`; r = x, z = y) changes the
two definitions and nothing else of the weak form: the strain gains the hoop strain
eps_theta = u_r / r, four components in the engine's (x, y, z, xy) order with z = theta (so the
DG0 spaces sized by ``STRAIN`` grow to 4), and the weight of both measures becomes 2 pi r
(forces are totals over the full ring, as in slipstep).

The bulk integrals of the ring use the one-point (centroid) rule by default: r and u_r / r are
then taken at the centroid, r_bar and (u_r1 + u_r2 + u_r3) / (3 r_bar), which is slipstep's
ring element (rust/src/element.rs), so the two stiffness matrices agree to round-off.  A higher
``quadrature_degree`` integrates the non-polynomial u_r u_r / r term of the stiffness more
accurately: a different ring element, consistent too (the two converge to each other with the
mesh).  Boundary integrals keep UFL's estimated degree (2: linear traction, test function and
r), which is exact, like slipstep's ring loads (:func:`slipstep.section.boundary_shares`).

In space (:class:`SpaceSection`, ``plane = "space"``: a 3D scene's tetrahedra) there is no
section: the strain has the six Voigt components of docs/engine_api.md (x, y, z, yz, xz, xy,
engineering shears), dOmega = dx and dGamma(tag) = ds(tag), forces are forces.
"""

from __future__ import annotations

import math

from . import dolfinx_api as api

#: The bulk quadrature of :class:`RingSection` that reproduces slipstep's ring element.
CENTROID_RULE = 1


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
        self.dGamma = WeightedMeasure(
            weight, ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
        )

    def strain(self, w):
        """(eps_x, eps_y, gamma_xy) of a displacement w."""
        return api.ufl().as_vector([w[0].dx(0), w[1].dx(1), w[0].dx(1) + w[1].dx(0)])

    def point_force(self, force):
        """The nodal force of a ``[[point_load]]`` (given per unit thickness)."""
        return force * self.thickness


class RingSection:
    """The axisymmetric section: x = r >= 0, y = z, every quantity a total over the ring."""

    STRAIN = ("r", "z", "theta", "rz")  # the engine's (x, y, z, xy), engineering shear

    def __init__(self, mesh, facet_tags=None, quadrature_degree: int = CENTROID_RULE):
        ufl = api.ufl()
        self.r = ufl.SpatialCoordinate(mesh)[0]
        weight = 2.0 * math.pi * self.r
        self.quadrature_degree = int(quadrature_degree)
        self.dOmega = WeightedMeasure(
            weight,
            ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": self.quadrature_degree}),
        )
        self.dGamma = WeightedMeasure(
            weight, ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
        )

    def strain(self, w):
        """(eps_r, eps_z, eps_theta = u_r / r, gamma_rz) of a displacement w."""
        return api.ufl().as_vector([w[0].dx(0), w[1].dx(1), w[0] / self.r, w[0].dx(1) + w[1].dx(0)])

    @staticmethod
    def point_force(force):
        """The nodal force of a ``[[point_load]]``: a ring total already."""
        return force


class SpaceSection:
    """Bodies in space: no section, the six strains of a tetrahedron."""

    STRAIN = ("x", "y", "z", "yz", "xz", "xy")  # docs/engine_api.md's Voigt order

    def __init__(self, mesh, facet_tags=None):
        ufl = api.ufl()
        weight = api.constant(mesh, 1.0)
        self.dOmega = WeightedMeasure(weight, ufl.dx)
        self.dGamma = WeightedMeasure(
            weight, ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
        )

    def strain(self, w):
        """(eps_x, eps_y, eps_z, gamma_yz, gamma_xz, gamma_xy) of a displacement w."""
        return api.ufl().as_vector(
            [
                w[0].dx(0),
                w[1].dx(1),
                w[2].dx(2),
                w[1].dx(2) + w[2].dx(1),
                w[0].dx(2) + w[2].dx(0),
                w[0].dx(1) + w[1].dx(0),
            ]
        )

    @staticmethod
    def point_force(force):
        """The nodal force of a ``[[point_load]]``: a force already."""
        return force


def section(
    mesh, plane: str, thickness: float, facet_tags=None, quadrature_degree: int = CENTROID_RULE
):
    """The section of the engine's ``plane`` ('strain', 'stress' or 'axisymmetric'; 'space'
    for a 3D scene); ``quadrature_degree`` applies to the ring's bulk integrals only."""
    if plane == "space":
        return SpaceSection(mesh, facet_tags)
    if plane == "axisymmetric":
        return RingSection(mesh, facet_tags, quadrature_degree)
    return Section(mesh, thickness, facet_tags)
