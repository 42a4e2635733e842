"""Shared by the 3D tests (tests/*/test_*3d*.py): small 3D cases and the check of an engine
model against docs/engine_api.md's "3D models" section, written from the contract's text (not
from the code that builds the model)."""

from __future__ import annotations

import numpy as np

BOX = """
[case]
name = "box3"
[analysis]
dimension = 3
[[body]]
name = "b"
[body.mesh]
generator = "box"
width = 2.0
depth = 1.0
height = 1.0
nx = 4
ny = 2
nz = 2
[body.material]
E = 1000.0
nu = 0.25
[[bc]]
name = "base"
body = "b"
face = "bottom"
fix = ["x", "y", "z"]
"""


SPHERE = """
[case]
name = "sphere3"
units = "mm, N, MPa"
[analysis]
dimension = 3
[load]
P = 30.0
[[body]]
name = "sphere"
[body.mesh]
generator = "sphere"
R = 10.0
h_contact = 0.3
contact_zone = 1.0
h_max = 3.0
growth = 0.5
[body.material]
E = 70000.0
nu = 0.3
[[bc]]
body = "sphere"
face = "symmetry_x"
symmetry = true
[[bc]]
body = "sphere"
face = "symmetry_y"
symmetry = true
[[contact]]
kind = "rigid_plane"
body = "sphere"
face = "surface"
z_max = 0.1
"""


def assert_contract(model: dict) -> None:
    """The 3D model as docs/engine_api.md states it, key by key."""
    assert model["dimension"] == 3
    assert "triangles" not in model and "plane" not in model and "thickness" not in model
    nodes, tets = model["nodes"], model["tetrahedra"]
    n = len(nodes)
    assert nodes.dtype == np.float64 and nodes.shape == (n, 3)
    assert tets.dtype == np.int64 and tets.shape[1] == 4
    p = nodes[tets]
    assert (np.linalg.det(p[:, 1:] - p[:, :1]) > 0).all()  # positively oriented
    assert model["element_material"].shape == (len(tets),)
    fixed = model["fixed_dofs"]
    assert fixed.dtype == np.int64 and (fixed >= 0).all() and (fixed < 3 * n).all()
    assert model["load"].shape == (3 * n,)
    for pattern in model.get("patterns", []):
        if "force" in pattern:
            assert pattern["force"].shape == (3 * n,)
        if "motion" in pattern:
            assert pattern["motion"].shape[1] == 3
        if "displacement_dofs" in pattern:
            assert not np.isin(pattern["displacement_dofs"], fixed).any()
    pairs = model["pairs"]
    P = len(pairs["node_a"])
    normal, tangent = pairs["normal"], pairs["tangent"]
    assert normal.shape == (P, 3) and tangent.shape == (P, 2, 3)
    assert np.allclose(np.linalg.norm(normal, axis=1), 1.0, atol=1e-12)
    t1, t2 = tangent[:, 0], tangent[:, 1]
    assert np.allclose(np.einsum("pi,pi->p", t1, t2), 0.0, atol=1e-12)
    assert np.allclose(np.linalg.norm(t1, axis=1), 1.0) and np.allclose(
        np.linalg.norm(t2, axis=1), 1.0)
    assert np.allclose(np.cross(t1, t2), normal, atol=1e-12)  # t1 x t2 = n
    assert (pairs["gap"] >= 0).all() and (pairs["mu"] >= 0).all()
    if "weight_ptr" in pairs:
        ptr, node, value = pairs["weight_ptr"], pairs["weight_node"], pairs["weight_value"]
        for k in range(P):
            row = slice(ptr[k], ptr[k + 1])
            if ptr[k + 1] > ptr[k]:  # they cancel: contactor +1, target -1
                assert abs(value[row].sum()) <= 1e-9 and abs(value[row][value[row] > 0].sum()
                                                             - 1.0) <= 1e-9
