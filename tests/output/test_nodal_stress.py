"""The stresses as results.xdmf and Result.fields give them besides the engine's four element
columns: the full symmetric tensor (its out-of-plane component per idealisation) and the
nodal stresses recovered by area-weighted averaging (slipstep.output.fields.nodal_stress).

Patch tests: a uniform stress state, which linear triangles reproduce exactly, applied as the
tractions sigma . n on every edge of a block (plane strain, plane stress) or of a ring section
(axisymmetry, the state of tests/physics/test_axisymmetric_patch.py); the engine returns it to round-off
(stresses of order 1 from a solve of ~100 DOFs: 1e-11), so the element tensor and the
recovered nodal stresses must equal it at every element and node, boundary and corners too.
Convergence: the elastic thick cylinder against Lame's closed form.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh

from slipstep import Case, run
from slipstep.output.fields import centroids, stress_tensor

E, NU = 1000.0, 0.3
SX, SY, TXY = 2.0, -1.0, 0.5  # the uniform in-plane stress of the plane patches
ROUND_OFF = 1e-11

PLANE_PATCH = """
[analysis]
plane = "{plane}"
[output]
figures = false
xdmf = false
[[body]]
name = "patch"
[body.mesh]
generator = "block"
width = 2.0
height = 1.0
nx = 4
ny = 3
[body.material]
E = {E}
nu = {NU}
[[bc]]
body = "patch"
nodes = "corner_bottom_left"
fix = ["x", "y"]
[[bc]]
body = "patch"
nodes = "corner_bottom_right"
fix = ["y"]
[[bc]]
body = "patch"
edge = "right"
traction = [{SX}, {TXY}]
[[bc]]
body = "patch"
edge = "left"
traction = [{mSX}, {mTXY}]
[[bc]]
body = "patch"
edge = "top"
traction = [{TXY}, {SY}]
[[bc]]
body = "patch"
edge = "bottom"
traction = [{mTXY}, {mSY}]
"""


def plane_patch(plane: str):
    text = PLANE_PATCH.format(
        plane=plane, E=E, NU=NU, SX=SX, SY=SY, TXY=TXY, mSX=-SX, mSY=-SY, mTXY=-TXY
    )
    return run(Case.from_toml(text), progress=False)


@pytest.mark.parametrize("plane, sigma_z", [("strain", NU * (SX + SY)), ("stress", 0.0)])
def test_a_uniform_plane_stress_state_as_tensor_and_at_the_nodes(plane, sigma_z):
    """sigma_z = nu (sigma_x + sigma_y) in plane strain (eps_z = 0), 0 in plane stress."""
    r = plane_patch(plane)
    f = r.fields()
    exact = np.array([[SX, TXY, 0.0], [TXY, SY, 0.0], [0.0, 0.0, sigma_z]])
    tensor = r.to_meshio().cell_data["stress"][0].reshape(-1, 3, 3)
    assert np.abs(tensor - exact).max() <= ROUND_OFF
    nodal = f["nodal_stress"]
    assert nodal.shape == (len(r.nodes), 4)
    assert np.abs(nodal - [SX, SY, sigma_z, TXY]).max() <= ROUND_OFF
    on_nodes = r.to_meshio().point_data["nodal_stress"].reshape(-1, 3, 3)
    assert np.abs(on_nodes - exact).max() <= ROUND_OFF
    vm = math.sqrt(0.5 * ((SX - SY) ** 2 + (SY - sigma_z) ** 2 + (sigma_z - SX) ** 2) + 3 * TXY**2)
    assert np.abs(f["nodal_von_mises"] - vm).max() <= ROUND_OFF


def test_the_tensor_layout():
    """Row by row xx xy xz / yx yy yz / zx zy zz from the columns x, y, z, xy."""
    assert stress_tensor(np.array([1.0, 2.0, 3.0, 4.0])).tolist() == [
        [1.0, 4.0, 0.0, 4.0, 2.0, 0.0, 0.0, 0.0, 3.0]
    ]


# --------------------------------------------------------------------------- convergence
def lame_errors(h: float) -> tuple[float, float, float]:
    """(max, rms) over the nodes of the recovered (sigma_r, sigma_theta) against Lame, and
    the rms of the element (centroid) stresses against Lame at the centroids, for the elastic
    thick cylinder a = 10, b = 20, p = 100 MPa (below first yield, 108 MPa) at element size h:
    sigma_r = A - B/r^2, sigma_theta = A + B/r^2, A = p a^2/(b^2 - a^2), B = A b^2."""
    a, b, p = 10.0, 20.0, 100.0
    A = p * a * a / (b * b - a * a)
    B = A * b * b
    r = run(
        CASES / "thick_cylinder.toml",
        progress=False,
        overrides=[
            f"mesh.h={h}",
            f"mesh.h_outer={h}",
            f"bc.bore.pressure={p}",
            "output.snapshots=[1.0]",
            "output.figures=false",
        ],
    )
    f = r.fields()

    def polar_error(xy, s):
        rad = np.linalg.norm(xy, axis=1)
        c, n = xy[:, 0] / rad, xy[:, 1] / rad
        srr = c * c * s[:, 0] + n * n * s[:, 1] + 2 * c * n * s[:, 3]
        stt = n * n * s[:, 0] + c * c * s[:, 1] - 2 * c * n * s[:, 3]
        return np.maximum(np.abs(srr - (A - B / rad**2)), np.abs(stt - (A + B / rad**2)))

    nodal = polar_error(r.nodes, f["nodal_stress"])
    element = polar_error(centroids(r.nodes, r.triangles), f["stress"])
    return nodal.max(), math.sqrt((nodal**2).mean()), math.sqrt((element**2).mean())


@needs_gmsh
def test_recovered_stresses_converge_to_lame():
    """Averaging constant element stresses is first order in h at the boundary nodes (a
    one-sided average of a sloped field) and second order inside on smooth meshes: halving h
    at least halves the largest nodal error (ratio 2 for order 1; 1.7 allows for gmsh's sizes
    being targets) and more than halves its rms (the first-order nodes are a boundary layer
    O(h) thin: order 3/2), and the nodal rms is below that of the element stresses at their
    centroids (order 1), which the recovery is meant to improve on."""
    errors = [lame_errors(h) for h in (1.0, 0.5, 0.25)]
    for (max0, rms0, _), (max1, rms1, _) in zip(errors, errors[1:]):
        assert max0 / max1 >= 1.7 and rms0 / rms1 >= 2.0, errors
    assert all(rms < element for _, rms, element in errors), errors
