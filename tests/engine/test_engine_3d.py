"""The engine in space (dimension = 3, linear tetrahedra), checked from outside its code on
small scenes built here or by the scene builder: the patch test (a uniform stress of all six
components under its consistent face loads is reproduced exactly), equilibrium recomputed from
the result arrays (tests/physics.py's tetrahedron forces and contact forces in each pair's
frame), invariance (the rotated scene gives the rotated solution), the engine half of the
node-to-surface patch test on non-matching faces (a uniform pressure crosses the interface as
lambda_j = p S_j, S_j the row's area), and the one-line refusals of bad 3D input."""

from __future__ import annotations

import numpy as np
import pytest
from physics import (
    EQUILIBRIUM_TOL,
    contact_force,
    equilibrium_residual,
    tangent_basis,
    tet_internal_force,
)
from space3d import BOX

from slipstep.build import build_scene
from slipstep.case import parse_case
from slipstep.errors import GrossSlidingError, InputError
from slipstep.runner import engine

# A uniform stress from loads of size |σ| on a mesh of O(1) condition: each stress is a few
# hundred operations on numbers of that size, so round-off is ~1e-13 of |σ|; an element
# kinematics or law error shows at order one.
ROUND_OFF = 1e-10


def box_scene():
    """The structured 2 x 1 x 1 box of tests/space3d.py (4 x 2 x 2 cells, 96 tetrahedra)."""
    return build_scene(parse_case(BOX, "box.toml"))


def no_pairs(model):
    model["pairs"] = {
        "node_a": np.zeros(0, np.int64),
        "node_b": np.zeros(0, np.int64),
        "normal": np.zeros((0, 3)),
        "gap": np.zeros(0),
        "mu": np.zeros(0),
    }
    return model


def faces_of(scene):
    """Every boundary triangle of the box with its outward normal: the six face tags."""
    out = []
    for face, normal in (
        ("bottom", (0, 0, -1)),
        ("top", (0, 0, 1)),
        ("left", (-1, 0, 0)),
        ("right", (1, 0, 0)),
        ("front", (0, -1, 0)),
        ("back", (0, 1, 0)),
    ):
        out.append((scene.global_boundary("b", face), np.array(normal, dtype=float)))
    return out


def consistent_load(scene, sigma):
    """The nodal forces of the traction σ n on every face: area/3 σ n to each corner of each
    boundary triangle (exact for a constant traction on linear triangles)."""
    tensor = sigma[[[0, 5, 4], [5, 1, 3], [4, 3, 2]]]
    f = np.zeros(3 * len(scene.nodes))
    for cells, normal in faces_of(scene):
        p = scene.nodes[cells]
        area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
        traction = tensor @ normal
        for corner in range(3):
            for c in range(3):
                np.add.at(f, 3 * cells[:, corner] + c, area / 3.0 * traction[c])
    return f


def three_two_one(nodes):
    """A statically determinate support: the corner at the origin held in x, y, z, the corner
    on the x axis in y and z, the corner on the y axis in z; no constraint on a balanced load."""
    at = lambda x, y, z: int(np.argmin(np.linalg.norm(nodes - [x, y, z], axis=1)))  # noqa: E731
    o, ex, ey = at(0, 0, 0), at(2, 0, 0), at(0, 1, 0)
    return np.array([3 * o, 3 * o + 1, 3 * o + 2, 3 * ex + 1, 3 * ex + 2, 3 * ey + 2], np.int64)


def test_a_uniform_stress_of_all_six_components_is_reproduced_exactly():
    scene = box_scene()
    sigma = np.array([120.0, -80.0, 30.0, 15.0, -25.0, 40.0])  # xx, yy, zz, yz, xz, xy
    model = no_pairs(dict(scene.model))
    model["load"] = consistent_load(scene, sigma)
    model["fixed_dofs"] = three_two_one(scene.nodes)
    result = engine().solve(model)
    stress = result["snapshots"][-1]["stress"]
    assert stress.shape == (len(model["tetrahedra"]), 6)
    assert np.abs(stress - sigma).max() <= ROUND_OFF * np.abs(sigma).max()
    # Hooke's compliance of that stress is the strain every element has: checked through the
    # displacement of the corner opposite the origin relative to it (u = ε x, rigid part held)
    E, nu = 1000.0, 0.25
    reaction = result["snapshots"][-1]["reaction"]
    assert np.abs(reaction).max() <= ROUND_OFF * np.abs(sigma).max()  # a balanced load
    eps_xx = (sigma[0] - nu * (sigma[1] + sigma[2])) / E
    u = result["snapshots"][-1]["u"]
    corner = int(np.argmin(np.linalg.norm(scene.nodes - [2, 0, 0], axis=1)))
    assert abs(u[corner, 0] - 2.0 * eps_xx) <= ROUND_OFF * abs(2.0 * eps_xx)


def pressed_box(rotation=np.eye(3)):
    """The box clamped on its bottom (x, y, z: the same support in every frame), its top pushed
    towards a rigid plane above it by forces that grow across it, the plane's pairs frictionless
    with a gap that closes; everything turned by ``rotation``."""
    scene = box_scene()
    model = dict(scene.model)
    nodes = scene.nodes
    top = np.flatnonzero(np.isclose(nodes[:, 2], 1.0))
    load = np.zeros((len(nodes), 3))
    load[top, 2] = 2.0 + nodes[top, 0] + 0.5 * nodes[top, 1] ** 2  # up, non-uniform
    load[top, 0] = 0.3  # and a shear
    model["nodes"] = nodes @ rotation.T
    model["load"] = (load @ rotation.T).ravel()
    normal = np.array([0.0, 0.0, -1.0]) @ rotation.T  # from the plane towards the body
    model["pairs"] = {
        "node_a": top.astype(np.int64),
        "node_b": -np.ones(len(top), np.int64),
        "normal": np.tile(normal, (len(top), 1)),
        "gap": 1e-3 * (1.0 + 0.1 * nodes[top, 0]),
        "mu": np.zeros(len(top)),
        "contact": np.zeros(len(top), np.int64),
    }
    model["contact_names"] = ["lid"]
    return model


def test_a_rotated_scene_gives_the_rotated_solution():
    """u' = R u, σ' = R σ Rᵀ, the same λ_n and the same events, for a rotation R off every axis
    (to the round-off of a well-conditioned solve: ~1e-12 relative; 1e-9 allows the event scales'
    amplification of it)."""
    angle = 0.7
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    plain, turned = engine().solve(pressed_box()), engine().solve(pressed_box(rotation))
    assert list(plain["events"]["kind"]) == list(turned["events"]["kind"])
    assert (plain["events"]["entity"] == turned["events"]["entity"]).all()
    assert np.allclose(
        plain["events"]["load_fraction"], turned["events"]["load_fraction"], rtol=1e-9
    )
    a, b = plain["snapshots"][-1], turned["snapshots"][-1]
    assert np.count_nonzero(a["status"]) > 0, "the plane carries load"
    scale_u = np.abs(a["u"]).max()
    assert np.abs(a["u"] @ rotation.T - b["u"]).max() <= 1e-9 * scale_u
    voigt = [[0, 5, 4], [5, 1, 3], [4, 3, 2]]
    sa, sb = a["stress"][:, voigt], b["stress"][:, voigt]
    assert np.abs(rotation @ sa @ rotation.T - sb).max() <= 1e-9 * np.abs(sa).max()
    assert np.allclose(a["lambda_n"], b["lambda_n"], rtol=1e-9, atol=1e-9 * a["lambda_n"].max())


@pytest.mark.parametrize("rotated", [False, True])
def test_equilibrium_recomputed_from_the_arrays_holds_at_every_snapshot(rotated):
    """Σ V Bᵀσ − load − (λ_n n + λ_t1 t1 + λ_t2 t2) vanishes at every free DOF of every
    snapshot (tests/physics.py, in space), and the supports' reaction the engine reports is
    that force at the held DOFs (to the documented equilibrium tolerance)."""
    rotation = np.eye(3)
    if rotated:
        c, s = np.cos(0.4), np.sin(0.4)
        rotation = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    model = pressed_box(rotation)
    model["options"] = {
        **model.get("options", {}),
        "output": "fractions",
        "fractions": np.array([0.3, 0.6, 1.0]),
    }
    result = engine().solve(model)
    assert len(result["snapshots"]) >= 3
    for snap in result["snapshots"]:
        assert equilibrium_residual(model, snap) <= EQUILIBRIUM_TOL
        internal = tet_internal_force(model["nodes"], model["tetrahedra"], snap["stress"])
        load = snap["t"] * model["load"]
        contact = contact_force(
            len(model["nodes"]), model["pairs"], snap["lambda_n"], snap["lambda_t"]
        )
        held = model["fixed_dofs"]
        recomputed = (internal - load - contact)[held]
        assert (
            np.abs(recomputed - snap["reaction"].ravel()[held]).max()
            <= EQUILIBRIUM_TOL * np.abs(load).sum()
        )
        assert snap["lambda_t"].shape == (len(model["pairs"]["node_a"]), 2)
        assert snap["rtd"].shape == (len(model["pairs"]["node_a"]), 2)


def test_the_node_to_surface_patch_test_carries_a_uniform_pressure_exactly():
    """Engine half of the 3D contact patch test: a lid on a block of the same material, meshed
    independently (non-matching faces), both on rollers, pressed by p on its top: the stress is
    σzz = −p everywhere and every node-to-surface row carries λ_j = p S_j (S_j its row area,
    the integral of its shape function), to round-off."""
    p = 2.5
    for nx, ny in ((3, 5), (5, 3)):
        scene = lid_scene(nx, ny, p)
        result = engine().solve(scene.model)
        snap = result["snapshots"][-1]
        assert (snap["status"] > 0).all()
        assert (
            np.abs(snap["lambda_n"] - p * scene.pair_area).max()
            <= ROUND_OFF * p * scene.pair_area.max()
        )
        expected = np.zeros(6)
        expected[2] = -p
        assert np.abs(snap["stress"] - expected).max() <= ROUND_OFF * p


def test_node_to_node_pairs_between_matching_faces_carry_a_uniform_pressure_exactly():
    """The same lid meshed like the block's top (4 x 2 cells: its nodes match), node-to-node
    pairs with friction (μ = 0.3; nothing pushes them sideways, so they stick with λt = 0): σzz =
    −p everywhere, every pair carries p times its node's tributary area, Σλn = p A, to
    round-off."""
    p = 2.5
    text = LID.format(nx=4, ny=2, p=p).replace('"node_to_surface"', '"node_to_node"')
    scene = build_scene(parse_case(text.replace("mu = 0.0", "mu = 0.3"), "lid.toml"))
    snap = engine().solve(scene.model)["snapshots"][-1]
    assert (snap["status"] == 1).all()
    assert (
        np.abs(snap["lambda_n"] - p * scene.pair_area).max()
        <= ROUND_OFF * p * scene.pair_area.max()
    )
    assert abs(snap["lambda_n"].sum() - p * 2.0 * 1.0) <= ROUND_OFF * p * 2.0
    assert np.abs(snap["lambda_t"]).max() <= ROUND_OFF * p * scene.pair_area.max()
    expected = np.zeros(6)
    expected[2] = -p
    assert np.abs(snap["stress"] - expected).max() <= ROUND_OFF * p


ROLLERS = """
[[bc]]
body = "{body}"
face = "left"
fix = ["x"]
[[bc]]
body = "{body}"
face = "front"
fix = ["y"]
"""

LID = (
    """
[case]
name = "lid"
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
body = "b"
face = "bottom"
fix = ["z"]
[[body]]
name = "lid"
[body.mesh]
generator = "box"
z0 = 1.0
width = 2.0
depth = 1.0
height = 0.5
nx = {nx}
ny = {ny}
nz = 1
[body.material]
E = 1000.0
nu = 0.25
[[bc]]
body = "lid"
face = "top"
pressure = {p}
[[contact]]
kind = "node_to_surface"
body_a = "lid"
face_a = "bottom"
body_b = "b"
face_b = "top"
mu = 0.0
"""
    + ROLLERS.format(body="b")
    + ROLLERS.format(body="lid")
)


def lid_scene(nx, ny, p):
    """A lid of nx x ny cells on the 4 x 2 block (non-matching faces), both on rollers (x on
    their left faces, y on their front ones, z on the block's bottom), p on the lid's top."""
    return build_scene(parse_case(LID.format(nx=nx, ny=ny, p=p), "lid.toml"))


def tetrahedron_model(**change):
    model = {
        "dimension": 3,
        "nodes": np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]),
        "tetrahedra": np.array([[0, 1, 2, 3]], dtype=np.int64),
        "element_material": np.zeros(1, dtype=np.int64),
        "materials": [{"E": 1.0, "nu": 0.3}],
        "fixed_dofs": np.arange(9, dtype=np.int64),
        "load": np.array([0.0] * 11 + [1e-3]),
    }
    return no_pairs(model) | change


@pytest.mark.parametrize(
    "change, words",
    [
        (
            {"tetrahedra": np.array([[0, 2, 1, 3]], dtype=np.int64)},
            "element 0 is an inverted tetrahedron",
        ),
        (
            {"nodes": np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0.3, 0.3, 0]])},
            "element 0 is a flat tetrahedron",
        ),
        ({"plane": "strain"}, "'plane' is a key of 2D models"),
        ({"thickness": 1.0}, "'thickness' is a key of 2D models"),
        ({"triangles": np.array([[0, 1, 2]], dtype=np.int64)}, "'triangles' is a key of 2D models"),
        ({"dimension": 4}, "dimension = 4: use 2 or 3"),
    ],
)
def test_bad_3d_input_is_one_line_naming_the_place(change, words):
    with pytest.raises(InputError) as err:
        engine().solve(tetrahedron_model(**change))
    message = str(err.value)
    assert words in message and "\n" not in message, message


def test_a_3d_key_in_a_2d_model_is_named():
    model = {
        "nodes": np.array([[0.0, 0], [1, 0], [0, 1]]),
        "triangles": np.array([[0, 1, 2]], dtype=np.int64),
        "tetrahedra": np.array([[0, 1, 2, 0]], dtype=np.int64),
        "plane": "strain",
        "thickness": 1.0,
        "element_material": np.zeros(1, dtype=np.int64),
        "materials": [{"E": 1.0, "nu": 0.3}],
        "fixed_dofs": np.arange(4, dtype=np.int64),
        "load": np.zeros(6),
    }
    with pytest.raises(InputError) as err:
        engine().solve(model)
    assert "'tetrahedra' is a key of 3D models" in str(err.value)


def block_on_a_frictional_plane(ratio, mu=0.3, p=2.0):
    """The box (ν = 0) standing on a rigid plane z = 0 (a frictional pair at every bottom node,
    closed at the start, nothing else holding it) under the uniform stress σzz = −p,
    τxz = τyz = ratio μ p/√2 (a shear at 45° to the mesh's axes, of size ratio μ p): the
    consistent loads of that stress on every face but the bottom, which the contact carries."""
    scene = box_scene()
    tau = ratio * mu * p / np.sqrt(2.0)
    sigma = np.array([0.0, 0.0, -p, tau, tau, 0.0])
    model = dict(scene.model)
    model["materials"] = [{"E": 1000.0, "nu": 0.0}]
    model["fixed_dofs"] = np.zeros(0, np.int64)
    cells = scene.global_boundary("b", "bottom")
    bottom = np.unique(cells)
    pts = scene.nodes[cells]
    area = 0.5 * np.linalg.norm(np.cross(pts[:, 1] - pts[:, 0], pts[:, 2] - pts[:, 0]), axis=1)
    tributary = np.zeros(len(scene.nodes))
    for corner in range(3):
        np.add.at(tributary, cells[:, corner], area / 3.0)
    model["load"] = consistent_load(scene, sigma) - consistent_load_on(scene, sigma, "bottom")
    n = len(bottom)
    model["pairs"] = {
        "node_a": bottom.astype(np.int64),
        "node_b": -np.ones(n, np.int64),
        "normal": np.tile([0.0, 0.0, 1.0], (n, 1)),
        "gap": np.zeros(n),
        "mu": np.full(n, mu),
        "contact": np.zeros(n, np.int64),
    }
    model["contact_names"] = ["plane"]
    return model, sigma, tributary[bottom]


def consistent_load_on(scene, sigma, face):
    """`consistent_load` of one face only."""
    normal = dict((("bottom", (0, 0, -1)), ("top", (0, 0, 1))))[face]
    tensor = sigma[[[0, 5, 4], [5, 1, 3], [4, 3, 2]]]
    cells = scene.global_boundary("b", face)
    p = scene.nodes[cells]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    traction = tensor @ np.array(normal, dtype=float)
    f = np.zeros(3 * len(scene.nodes))
    for corner in range(3):
        for c in range(3):
            np.add.at(f, 3 * cells[:, corner] + c, area / 3.0 * traction[c])
    return f


def test_a_shear_inside_the_round_cone_sticks_with_the_exact_forces():
    """At 0.95 of the cone's capacity along 45° every pair sticks and carries the uniform
    stress's nodal forces exactly: λ_n = p S_j and λ_t = τ S_j (S_j the node's tributary area),
    the stress uniform. (An inscribed four-facet pyramid with facets along the axes would have
    let these pairs slip: its capacity along 45° is μλ_n/√2.)"""
    model, sigma, area = block_on_a_frictional_plane(0.95)
    snap = engine().solve(model)["snapshots"][-1]
    assert (snap["status"] == 1).all(), snap["status"]
    p = -sigma[2]
    assert np.abs(snap["lambda_n"] - p * area).max() <= ROUND_OFF * p
    # the plane's tangential force on the body is its traction σ·(−e_z) = −(τxz, τyz) per area
    traction = -np.array([sigma[4], sigma[3], 0.0])
    b1, b2 = tangent_basis(np.asarray(model["pairs"]["normal"], dtype=float))
    along = snap["lambda_t"][:, :1] * b1 + snap["lambda_t"][:, 1:] * b2  # λ_t in x, y, z
    assert np.abs(along - traction * area[:, None]).max() <= ROUND_OFF * p
    assert np.abs(snap["stress"] - sigma).max() <= ROUND_OFF * p


def test_a_shear_beyond_the_round_cone_slides_the_block():
    """At 1.05 of the capacity along 45° every pair reaches the round cone at the first instant
    and slips, and the block, held by nothing else, slides: a one-line error naming the body
    and both translations of the 45° motion (the engine's gross-sliding error, as for a 2D load
    beyond friction from the start: its tangential load in the plane exceeds mu N)."""
    model, _, _ = block_on_a_frictional_plane(1.05)
    with pytest.raises(GrossSlidingError) as err:
        engine().solve(model)
    message = str(err.value)
    assert (
        "body 'b'" in message and "translation in x" in message and "translation in y" in message
    ), message
    assert "slip" in message and "\n" not in message, message
