"""A scene's idealisation: how its bodies are modelled, chosen once from the case when the
scene is built (:func:`of_case`) and carried on it (``scene.idealisation``), so that the rest
of the package asks it instead of testing the dimension.

``base``     the :class:`Idealisation` interface
``section``  :class:`Section`: 2D sections of triangles, two DOFs per node, contact on
             edges: :class:`Plane` (plane strain or stress) or :class:`Axisymmetric`
``solid``    :class:`Solid`: 3D solids of tetrahedra, three DOFs per node, contact on faces
"""

from __future__ import annotations

from .base import Idealisation
from .section import Axisymmetric, Plane, Section
from .solid import Solid

__all__ = ["Axisymmetric", "Idealisation", "Plane", "Section", "Solid", "of_case"]


def of_case(case) -> Idealisation:
    """The idealisation a case's ``[analysis]`` table asks for (``dimension``, and in 2D
    ``plane``): the one place they are read to choose an implementation."""
    analysis = case.data["analysis"]
    if case.dimension == 3:
        return Solid()
    return Axisymmetric() if analysis["plane"] == "axisymmetric" else Plane()
