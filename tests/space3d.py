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


# A Vickers pyramid (tip `tip`, a list) pressed by its `motion` (along -z) into the quarter of a
# block held by two symmetry planes, mu = 0.3: fill with str.format(tip=..., h_contact=..., motion=...).
VICKERS_QUARTER = """
[analysis]
dimension = 3
[output]
snapshots = [0.5, 1.0]
[[body]]
name = "block"
[body.mesh]
generator = "box"
z0 = -3.0
width = 3.0
depth = 3.0
height = 3.0
h_contact = {h_contact}
contact_zone = 0.6
h_max = 1.0
growth = 0.3
focus = [0.0, 0.0, 0.0]
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
body = "block"
face = "bottom"
fix = ["x", "y", "z"]
[[bc]]
body = "block"
face = "left"
symmetry = true
[[bc]]
body = "block"
face = "front"
symmetry = true
[[contact]]
kind = "rigid_surface"
indenter = "vickers"
tip = {tip}
size = 1.0
body = "block"
face = "top"
x_max = 1.0
y_max = 1.0
mu = 0.3
motion = [0.0, 0.0, {motion}]
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
        np.linalg.norm(t2, axis=1), 1.0
    )
    assert np.allclose(np.cross(t1, t2), normal, atol=1e-12)  # t1 x t2 = n
    assert (pairs["gap"] >= 0).all() and (pairs["mu"] >= 0).all()
    if "weight_ptr" in pairs:
        ptr, node, value = pairs["weight_ptr"], pairs["weight_node"], pairs["weight_value"]
        for k in range(P):
            row = slice(ptr[k], ptr[k + 1])
            if ptr[k + 1] > ptr[k]:  # they cancel: contactor +1, target -1
                assert (
                    abs(value[row].sum()) <= 1e-9
                    and abs(value[row][value[row] > 0].sum() - 1.0) <= 1e-9
                )


#: A quarter sphere (y >= 0: the plane y = 0 its mirror) on a rigid flat, for the Mindlin
#: stand-in below: a shear along x is symmetric about y = 0.
QUARTER = SPHERE.replace(
    'generator = "sphere"', 'generator = "sphere"\nportion = "quarter"'
).replace(
    '[[bc]]\nbody = "sphere"\nface = "symmetry_x"\nsymmetry = true\n',
    '[[bc]]\nbody = "sphere"\nface = "top"\nfix = ["x"]\n',
)


def mindlin_stand_in(scene, a: float, c: float, p0: float, mu: float, stress=None) -> dict:
    """NOT a solver: a 3D result in the engine's layout (docs/engine_api.md) whose contact is
    Hertz's pressure p0 sqrt(1 - r^2/a^2) inside r < a with Mindlin's tangential traction along
    +x (mu p, less mu p0 (c/a) sqrt(1 - r^2/c^2) in the stick disc r < c), r measured from the
    origin; its nodal forces are traction x each pair's area, split into the pair's (t1, t2).
    ``stress``: one (6,) Voigt row for every element (default zeros)."""
    x = scene.pair_xy
    r = np.hypot(x[:, 0], x[:, 1])
    p = p0 * np.sqrt(np.clip(1 - (r / a) ** 2, 0, None))
    q = mu * p - mu * p0 * (c / a) * np.sqrt(np.clip(1 - (r / c) ** 2, 0, None))
    traction = q[:, None] * np.array([1.0, 0.0, 0.0])
    area = scene.pair_area
    lam_t = np.einsum("pd,ptd->pt", traction, scene.pair_tangent) * area[:, None]
    status = np.where(r < c, 1, np.where(r < a, 2, 0)).astype(np.int8)
    n, m, P = len(scene.nodes), len(scene.tetrahedra), len(x)
    row = np.zeros(6) if stress is None else np.asarray(stress, dtype=float)
    snap = {
        "t": 1.0,
        "stage": 0,
        "load_fraction": 1.0,
        "u": np.zeros((n, 3)),
        "reaction": np.zeros((n, 3)),
        "stress": np.tile(row, (m, 1)),
        "plastic_strain": np.zeros(m),
        "plastic": np.zeros(m, np.int8),
        "lambda_n": p * area,
        "lambda_t": lam_t,
        "status": status,
        "gap": np.where(status > 0, 0.0, scene.model["pairs"]["gap"]),
        "rtd": np.zeros((P, 2)),
    }
    return {
        "events": {
            "step": np.zeros(0, np.int64),
            "load_fraction": np.zeros(0),
            "t": np.zeros(0),
            "stage": np.zeros(0, np.int64),
            "kind": [],
            "entity": np.zeros(0, np.int64),
        },
        "steps": {
            "load_fraction": np.array([1.0]),
            "t": np.array([1.0]),
            "stage": np.zeros(1, np.int64),
        },
        "snapshots": [snap],
        "closure_fraction": np.zeros(P),
        "predicted_closure": np.full(P, np.inf),
        "n_stages": 1,
        "stage_names": ["stage 1"],
        "max_drift": 0.0,
        "max_equilibrium_residual": 1e-14,
        "n_factorizations": 1,
        "n_solves": 1,
        "n_rate_problems": 0,
        "interrupted": False,
        "stop_reason": None,
        "stop": {"kind": "completed", "message": None, "load_fraction": 1.0, "t": 1.0},
        "timings": {},
    }


def displacement_at(
    nodes: np.ndarray, tets: np.ndarray, u: np.ndarray, points: np.ndarray
) -> np.ndarray:
    """The displacement of linear tetrahedra at ``points`` (K, 3): in each point's element (the
    one whose smallest barycentric coordinate is largest, >= -1e-9: a point on a shared face or
    edge reads the same value from every element there), u interpolated linearly.  Raises if a
    point lies outside the mesh."""
    nodes, u = np.asarray(nodes, dtype=float), np.asarray(u, dtype=float).reshape(-1, 3)
    x = nodes[tets]  # (M, 4, 3)
    jac = np.transpose(x[:, 1:] - x[:, :1], (0, 2, 1))  # columns x_k - x_0
    out = []
    for p in np.atleast_2d(points):
        lam = np.linalg.solve(jac, (p - x[:, 0])[:, :, None])[:, :, 0]  # (M, 3)
        bary = np.column_stack([1.0 - lam.sum(axis=1), lam])  # (M, 4)
        e = int(np.argmax(bary.min(axis=1)))
        if bary[e].min() < -1e-9:
            raise ValueError(f"point {p} lies outside the mesh")
        out.append(bary[e] @ u[tets[e]])
    return np.array(out)


def hertz_approach_errors(
    nodes, tets, u, P: float, R: float, E: float, nu: float, origin, inward, depths
) -> list[float]:
    """Relative errors of the approach of a sphere (radius R, E, nu) pressed by P onto a rigid
    flat, measured as in tests/physics/test_axisymmetric_hertz.py but in space: the shortening
    of the axis from the contact point ``origin`` to the depth d a along ``inward`` (the unit
    normal into the sphere), (u(origin) - u(origin + d a inward)) . inward, interpolated in the
    tetrahedra, plus Huber's half-space shortening below d a
    (``references.sphere_axis_compression``), against Hertz's delta = a^2/R, for each d in
    ``depths``.  The mesh need not have nodes on the axis."""
    from slipstep.measures import references

    a, p0, delta = references.hertz_sphere(P, R, E, nu)
    origin, inward = np.asarray(origin, dtype=float), np.asarray(inward, dtype=float)
    points = origin + np.outer([0.0, *depths], inward) * a
    w = displacement_at(nodes, tets, u, points) @ inward
    return [
        float(
            (w[0] - w[k + 1] + references.sphere_axis_compression(d, nu) * p0 * a / E) / delta - 1.0
        )
        for k, d in enumerate(depths)
    ]
