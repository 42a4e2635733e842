"""A scene's idealisation: how its bodies are modelled, chosen once from the case when the
scene is built (:func:`of_case`) and carried on it (``scene.idealisation``), so that the rest
of the package asks it instead of testing the dimension.

``base``     the :class:`Idealisation` interface
``section``  :class:`Section`: 2D sections of triangles, two DOFs per node, contact on
             edges: :class:`Plane` (plane strain or stress) or :class:`Axisymmetric`
``solid``    :class:`Solid`: 3D solids of tetrahedra, three DOFs per node, contact on faces
"""

from __future__ import annotations

from ..validation.terms import SectionTerms, SolidTerms, terms_of
from .base import Idealisation
from .section import Axisymmetric, Plane, Section
from .solid import Solid

__all__ = ["Axisymmetric", "Idealisation", "Plane", "Section", "Solid", "of_case"]


def of_case(case) -> Idealisation:
    """The idealisation a case's ``[analysis]`` table asks for: the one of its dimension's terms
    (:func:`slipstep.validation.terms.terms_of`, the validator's), in 2D by ``plane``."""
    plane = case.record.analysis.plane
    section = Axisymmetric if plane == "axisymmetric" else Plane
    return {SectionTerms: section, SolidTerms: Solid}[type(terms_of(case.dimension))]()
