"""Each idealisation (:mod:`slipstep.idealisation`) says the same thing in every name it gives: its
stresses, axes and moments agree with its dimension, its XDMF topologies are meshio's names of its
elements and boundary cells, and its boundary geometry (outward normals, points on the boundary)
is that of one element, checked against the element's own closed boundary."""

from __future__ import annotations

import meshio.xdmf.common
import numpy as np
import pytest

from slipstep.idealisation import Axisymmetric, Plane, Solid
from slipstep.validation.terms import terms_of

IDEALISATIONS = [Plane(), Axisymmetric(), Solid()]
#: meshio's cell type of a boundary cell, by the boundary's word
FACET_CELL = {"edge": "line", "face": "triangle"}


@pytest.mark.parametrize("ideal", IDEALISATIONS, ids=lambda i: type(i).__name__)
def test_an_idealisation_names_its_parts_consistently(ideal):
    d = ideal.dimension
    assert type(terms_of(d)) in type(ideal).__mro__  # the validator's terms are the scene's
    assert ideal.axes == ("x", "y", "z")[:d] and ideal.vector_type == f"vec{d}"
    # one stress name per component, all different: the symmetric tensor's, and a section's
    # out-of-plane normal stress
    assert len(set(ideal.stress_names)) == len(ideal.stress_names) == ideal.stress_width
    assert ideal.stress_width == d * (d + 1) // 2 + (d == 2)
    assert set(ideal.force_components) <= set(range(d))
    # the outputs name only moments the engine records
    assert set(ideal.moment_components) <= set(ideal.engine_moment_axes) <= {0, 1, 2}
    to_xdmf = meshio.xdmf.common.meshio_to_xdmf_type
    facet = FACET_CELL[ideal.boundary]
    assert ideal.xdmf_topology == (to_xdmf[ideal.cell_type][0], to_xdmf[facet][0])


#: One element of each idealisation and its boundary cells, outward (body on the left in 2D,
#: right-hand rule out of the body in 3D).
ELEMENTS = {
    2: (np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]]), np.array([[0, 1], [1, 2], [2, 0]])),
    3: (
        np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]]),
        np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]),
    ),
}


def _measures(nodes, cells) -> np.ndarray:
    """Each boundary cell's length (2D) or area (3D), from its corners."""
    p = nodes[cells]
    if cells.shape[1] == 2:
        return np.linalg.norm(p[:, 1] - p[:, 0], axis=1)
    return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)


@pytest.mark.parametrize("ideal", [Plane(), Solid()], ids=lambda i: type(i).__name__)
def test_boundary_normals_are_outward_and_close(ideal):
    nodes, cells = ELEMENTS[ideal.dimension]
    n = ideal.facet_normals(nodes, cells)
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0)
    centre = nodes.mean(axis=0)
    away = nodes[cells].mean(axis=1) - centre
    assert (np.einsum("ij,ij->i", n, away) > 0).all()  # out of the element
    # a closed boundary: sum of n dA vanishes (the divergence theorem for a constant field)
    assert np.abs((n * _measures(nodes, cells)[:, None]).sum(axis=0)).max() < 1e-12
    # at the corners, the surface normal points out of the element too
    corner = ideal.surface_normals(nodes, cells, np.arange(len(nodes)))
    assert (np.einsum("ij,ij->i", corner, nodes - centre) > 0).all()


@pytest.mark.parametrize("ideal", [Plane(), Solid()], ids=lambda i: type(i).__name__)
def test_points_on_the_boundary_are_found_off_its_corners(ideal):
    nodes, cells = ELEMENTS[ideal.dimension]
    on_first = nodes[cells[0]].mean(axis=0)  # the middle of a boundary cell
    inside = nodes.mean(axis=0)
    outside = 2.0 * on_first - inside  # as far beyond the cell as the centre is before it
    extra = np.vstack([nodes, on_first, inside, outside])
    k = len(nodes)
    found = ideal.on_boundary(extra, np.array([k, k + 1, k + 2, 0]), cells, 1e-9)
    assert found.tolist() == [True, False, False, False]  # node 0: a corner, not "on" a cell
