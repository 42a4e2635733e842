"""Invariances the discrete problem has exactly, checked on the engine's answers.

* Rotation: a cantilever pressed by a pressure onto a rigid flat beneath it, and the same scene
  rotated by 0.5 rad about the origin (mesh nodes, the flat's point and normal: the case gives
  the flat by ``point`` and ``normal``, the rotated mesh is a file mesh, so the pressure and the
  pairs are built by the case machinery from rotated geometry).  The clamp holds both
  components of its nodes, a support that rotates with the body.  The answers must be the
  rotated ones: u → Q u, σ → Q σ Qᵀ, and every scalar (λ_n, λ_t, gap, RTD, σz, von Mises,
  plastic strain, statuses, events) unchanged.
* Mirror symmetry: the Hertz cylinder as a full half-disc (the quarter mesh mirrored about
  x = 0) against the half model of the default case, frictionless and μ = 0.3.  The full model
  has no symmetry support: u_x is held at two nodes on x = 0 only (no x-translation, no rotation
  about the contact point; both are symmetric constraints, so the symmetric answer is not
  forced, it must come out).  λ_n per pair must equal its mirror image's and the half model's
  (the node at x = 0 carries the tributary length of both sides: twice the half model's), λ_t
  and the RTD change sign in the mirror, statuses (contact and stick extents) are symmetric.

Round-off tolerance (ROUND_OFF = 1e-8, relative to each field's largest value over the run):
the two runs solve the same discrete problem with differently rounded data (rotated
coordinates; a different assembly and DOF order).  A linear solve loses about κ(K) ε, with
κ(K) ~ 10 N for a 2D stiffness of N nodes (smooth modes have Rayleigh quotient ~E/N, the
largest ~E) and ε = 2.2e-16; increments add their errors: ≤ 100 increments × 10 × 8600 nodes ×
ε = 2e-9 for the full cylinder, far less for the 205-node beam.  An error in the physics (a
tangent or a stress not rotated, a mirror-image force of the wrong sign) is O(1).
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from physics import EQUILIBRIUM_TOL, von_mises, worst_equilibrium

from slipstep import _engine, prepare, solve
from slipstep.mesh import triangle_generators as generators

ROUND_OFF = 1e-8


def rel_diff(a, b, scale):
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) / scale if np.size(a) else 0.0


# --------------------------------------------------------------------------- rotation
W, HEIGHT, NX, NY = 20.0, 2.0, 40, 4  # beam, h = 0.5 mm
GAP = 0.05  # the flat lies GAP below the beam
THETA = 0.5  # rad
TAGS = {"top": 3, "left": 4, "contact": 5}


def write_beam_case(folder, theta):
    """The cantilever (clamped left end, pressure 5 MPa on top) over a rigid flat, mesh and
    flat rotated by theta; elastoplastic (Sy = 100 MPa, H' = 2000 MPa), μ = 0.3."""
    import meshio

    b = generators.block(W, HEIGHT, NX, NY)
    c, s = math.cos(theta), math.sin(theta)
    Q = np.array([[c, -s], [s, c]])
    bottom = b.edges["bottom"]
    edges = {
        "top": b.edges["top"],
        "left": b.edges["left"],
        # the bottom without the clamped corner: its node cannot be a contact candidate
        "contact": bottom[~np.any(np.isin(bottom, b.edges["left"]), axis=1)],
    }
    segments = np.concatenate([edges[k] for k in TAGS])
    tags = np.concatenate([np.full(len(edges[k]), v, dtype=np.int64) for k, v in TAGS.items()])
    points = b.nodes @ Q.T
    mesh = meshio.Mesh(
        np.column_stack([points, np.zeros(len(points))]),
        [("triangle", b.triangles), ("line", segments)],
        cell_data={"tag": [np.zeros(len(b.triangles), np.int64), tags]},
    )
    name = f"beam_{theta:.3f}"
    meshio.xdmf.write(str(folder / f"{name}.xdmf"), mesh)
    normal, point = Q @ [0.0, 1.0], Q @ [0.0, -GAP]
    case = folder / f"{name}.toml"
    case.write_text(f"""
[output]
snapshots = "events"
[[body]]
name = "beam"
[body.mesh]
file = "{name}.xdmf"
[body.material]
E = 70000.0
nu = 0.3
Sy = 100.0
H = 2000.0
[[bc]]
body = "beam"
edge = "{TAGS['left']}"
fix = ["x", "y"]
[[bc]]
body = "beam"
edge = "{TAGS['top']}"
pressure = 5.0
[[contact]]
kind = "rigid_line"
body = "beam"
edge = "{TAGS['contact']}"
point = [{point[0]!r}, {point[1]!r}]
normal = [{normal[0]!r}, {normal[1]!r}]
mu = 0.3
""")
    return case, Q


@pytest.fixture(scope="module")
def beams(tmp_path_factory):
    folder = tmp_path_factory.mktemp("beams")
    runs = {}
    for theta in (0.0, THETA):
        case, Q = write_beam_case(folder, theta)
        scene = prepare(case)
        runs[theta] = scene, solve(scene), Q
    return runs


def test_rotated_scene_is_the_same_scene(beams):
    (s0, _, _), (s1, _, Q) = beams[0.0], beams[THETA]
    assert np.allclose(s0.nodes @ Q.T, s1.nodes, rtol=0, atol=1e-13 * W)  # same node order
    p0, p1 = s0.model["pairs"], s1.model["pairs"]
    assert np.array_equal(p0["node_a"], p1["node_a"])
    assert np.allclose(p0["gap"], p1["gap"], rtol=0, atol=1e-12 * W)
    assert np.allclose(np.asarray(p0["normal"]) @ Q.T, p1["normal"], rtol=0, atol=1e-15)
    assert np.array_equal(np.sort(s0.model["fixed_dofs"]), np.sort(s1.model["fixed_dofs"]))
    load0 = np.asarray(s0.model["load"]).reshape(-1, 2) @ Q.T
    assert np.allclose(
        load0, np.asarray(s1.model["load"]).reshape(-1, 2), rtol=0, atol=1e-13 * np.abs(load0).max()
    )


def test_the_scene_exercises_contact_friction_and_plasticity(beams):
    _, r0, _ = beams[0.0]
    kinds = set(r0["events"]["kind"])
    assert {"close", "stick_to_slip", "slip_to_stick", "yield"} <= kinds, kinds
    assert r0["stop"]["kind"] == "completed"


def test_rotation_gives_the_rotated_answer(beams):
    (s0, r0, _), (s1, r1, Q) = beams[0.0], beams[THETA]
    e0, e1 = r0["events"], r1["events"]
    assert list(e0["kind"]) == list(e1["kind"])
    assert np.array_equal(e0["entity"], e1["entity"])
    np.testing.assert_allclose(e1["load_fraction"], e0["load_fraction"], rtol=ROUND_OFF, atol=0)
    assert len(r0["snapshots"]) == len(r1["snapshots"])
    snaps = list(zip(r0["snapshots"], r1["snapshots"]))
    u_scale = max(np.abs(a["u"]).max() for a, _ in snaps)
    f_scale = max(np.abs(a["lambda_n"]).max() for a, _ in snaps)
    s_scale = max(np.abs(a["stress"]).max() for a, _ in snaps)
    g_scale = max(GAP, u_scale)
    ep_scale = max(max(a["plastic_strain"].max() for a, _ in snaps), 1e-300)
    for k, (a, b) in enumerate(snaps):
        assert a["load_fraction"] == pytest.approx(b["load_fraction"], rel=ROUND_OFF)
        assert rel_diff(np.asarray(a["u"]) @ Q.T, b["u"], u_scale) <= ROUND_OFF, k
        for key in ("lambda_n", "lambda_t"):
            assert rel_diff(a[key], b[key], f_scale) <= ROUND_OFF, (k, key)
        for key in ("gap", "rtd"):
            assert rel_diff(a[key], b[key], g_scale) <= ROUND_OFF, (k, key)
        assert np.array_equal(a["status"], b["status"]), k
        assert np.array_equal(a["plastic"], b["plastic"]), k
        assert rel_diff(a["plastic_strain"], b["plastic_strain"], ep_scale) <= ROUND_OFF, k
        sa, sb = np.asarray(a["stress"]), np.asarray(b["stress"])
        tensor = np.zeros((len(sa), 2, 2))
        tensor[:, 0, 0], tensor[:, 1, 1] = sa[:, 0], sa[:, 1]
        tensor[:, 0, 1] = tensor[:, 1, 0] = sa[:, 3]
        rotated = Q @ tensor @ Q.T
        for got, want in (
            (sb[:, 0], rotated[:, 0, 0]),
            (sb[:, 1], rotated[:, 1, 1]),
            (sb[:, 3], rotated[:, 0, 1]),
            (sb[:, 2], sa[:, 2]),
            (von_mises(sb), von_mises(sa)),
        ):
            assert rel_diff(got, want, s_scale) <= ROUND_OFF, k
    assert r0["snapshots"][-1]["plastic_strain"].max() > 0


def test_both_orientations_in_equilibrium(beams):
    for theta, (scene, result, _) in beams.items():
        worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
        assert worst <= EQUILIBRIUM_TOL, (theta, k, f, worst)


# --------------------------------------------------------------------------- mirror
H_CONTACT = 0.05


def full_model(half: dict):
    """The full half-disc from the quarter model: nodes on x = 0 shared, the others mirrored;
    mirrored triangles re-oriented counter-clockwise; the load (the pressure on the cut y = R)
    mirrored, so the shared nodes get both halves; a pair for every candidate node and its
    mirror image.  Supports: u_x of the top node (0, R) and of the axis node nearest (0, R/2).
    Returns (model, mirror: half node -> full node, number of half pairs)."""
    nodes = np.asarray(half["nodes"])
    n = len(nodes)
    on_axis = nodes[:, 0] == 0.0
    mirror = np.arange(n)
    mirror[~on_axis] = n + np.arange(np.count_nonzero(~on_axis))
    full_nodes = np.vstack([nodes, nodes[~on_axis] * [-1.0, 1.0]])
    triangles = np.asarray(half["triangles"])
    full_triangles = np.vstack([triangles, mirror[triangles][:, [0, 2, 1]]])
    load = np.asarray(half["load"]).reshape(-1, 2)
    full_load = np.zeros((len(full_nodes), 2))
    np.add.at(full_load, np.arange(n), load)
    np.add.at(full_load, mirror, load * [-1.0, 1.0])
    pairs = half["pairs"]
    a = np.asarray(pairs["node_a"])
    off = ~on_axis[a]
    top = int(np.flatnonzero(on_axis & (nodes[:, 1] == nodes[:, 1].max()))[0])
    axis = np.flatnonzero(on_axis)
    middle = int(axis[np.argmin(np.abs(nodes[axis, 1] - 0.5 * nodes[:, 1].max()))])
    model = copy.deepcopy(
        {k: v for k, v in half.items() if k not in ("body_names", "element_body", "contact_names")}
    )
    model.update(
        {
            "nodes": full_nodes,
            "triangles": full_triangles.astype(np.int64),
            "element_material": np.concatenate([half["element_material"]] * 2).astype(np.int64),
            "fixed_dofs": np.array(sorted([2 * top, 2 * middle]), dtype=np.int64),
            "load": full_load.ravel(),
            "pairs": {
                "node_a": np.concatenate([a, mirror[a[off]]]).astype(np.int64),
                "node_b": -np.ones(len(a) + np.count_nonzero(off), dtype=np.int64),
                "normal": np.vstack(
                    [pairs["normal"], np.asarray(pairs["normal"])[off] * [-1.0, 1.0]]
                ),
                "gap": np.concatenate([pairs["gap"], np.asarray(pairs["gap"])[off]]),
                "mu": np.concatenate([pairs["mu"], np.asarray(pairs["mu"])[off]]),
            },
        }
    )
    return model, mirror, len(a)


@pytest.fixture(scope="module", params=[0.0, 0.3])
def halves(request):
    mu = request.param
    scene = prepare(
        None,
        overrides=[f"contact.mu={mu}", f"mesh.h_contact={H_CONTACT}", "output.snapshots=events"],
    )
    model, mirror, n_half = full_model(scene.model)
    return mu, scene, solve(scene), model, _engine.solve(model, False), mirror, n_half


def test_full_model_is_the_half_model_built_right(halves):
    _, scene, _, model, _, mirror, n_half = halves
    p = model["nodes"][model["triangles"]]
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    assert np.all(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0)  # all counter-clockwise
    load = model["load"].reshape(-1, 2).sum(axis=0)
    # the full cylinder carries the whole P = 1000 N/mm; the x-loads cancel pairwise
    assert load[1] == pytest.approx(-1000.0, rel=1e-12) and abs(load[0]) <= 1e-12 * 1000.0
    assert len(model["pairs"]["node_a"]) == 2 * n_half - 1


def test_full_model_equals_mirrored_half_model(halves):
    mu, scene, rh, model, rf, mirror, n_half = halves
    assert rh["stop"]["kind"] == rf["stop"]["kind"] == "completed"
    # the same increments: mirror-image events fall at the same load and are applied together
    np.testing.assert_allclose(
        rf["steps"]["load_fraction"], rh["steps"]["load_fraction"], rtol=ROUND_OFF, atol=0
    )
    a = np.asarray(scene.model["pairs"]["node_a"])
    axis = scene.nodes[a, 0] == 0.0
    twin = n_half + np.cumsum(~axis) - 1  # full-model pair of each half pair's mirror
    f_scale = max(np.abs(s["lambda_n"]).max() for s in rh["snapshots"]) * 2
    u_scale = max(np.abs(s["u"]).max() for s in rh["snapshots"])
    n = len(scene.nodes)
    for k, (sh, sf) in enumerate(zip(rh["snapshots"], rf["snapshots"])):
        ln_half = np.where(axis, 2.0, 1.0) * np.asarray(sh["lambda_n"])
        ln, lt, st = (np.asarray(sf[key]) for key in ("lambda_n", "lambda_t", "status"))
        # right side = half model, left side = its mirror image
        assert rel_diff(ln[:n_half], ln_half, f_scale) <= ROUND_OFF, k
        assert rel_diff(ln[twin[~axis]], sh["lambda_n"][~axis], f_scale) <= ROUND_OFF, k
        assert rel_diff(lt[:n_half][~axis], sh["lambda_t"][~axis], f_scale) <= ROUND_OFF, k
        assert (
            rel_diff(lt[twin[~axis]], -np.asarray(sh["lambda_t"])[~axis], f_scale) <= ROUND_OFF
        ), k
        assert np.all(np.abs(lt[:n_half][axis]) <= ROUND_OFF * f_scale), k  # no shear on the axis
        # statuses: the closed (contact) and stick extents are symmetric and the half model's
        assert np.array_equal(st[:n_half], sh["status"]), k
        assert np.array_equal(st[twin[~axis]], np.asarray(sh["status"])[~axis]), k
        u = np.asarray(sf["u"])
        assert rel_diff(u[:n], sh["u"], u_scale) <= ROUND_OFF, k
        assert rel_diff(u[mirror] * [-1.0, 1.0], sh["u"], u_scale) <= ROUND_OFF, k
    last = rf["snapshots"][-1]
    closed = np.asarray(last["status"]) > 0
    assert 40 <= closed.sum() and np.sum(last["lambda_n"]) == pytest.approx(1000.0, rel=1e-9)
    if mu > 0:
        assert np.any(np.asarray(last["status"]) == 1) and np.any(np.asarray(last["status"]) == 2)


def test_full_and_half_models_in_equilibrium(halves):
    _, scene, rh, model, rf, _, _ = halves
    for m, r in ((scene.model, rh), (model, rf)):
        worst, k, f = worst_equilibrium(m, r["snapshots"])
        assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
