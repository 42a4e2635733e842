"""Hertz's sphere in 3D without symmetry planes, and rotated in space.

The scene: the whole lower hemisphere (the sphere generator's ``portion = "half"``: R = 50 mm,
E = 70 GPa, nu = 0.3), its cut z = R held by a ``fix`` of all three components (no [[bc]]
symmetry anywhere), pressed by a rigid flat moved into it by 1.2 um along its normal.  The
candidates are the sphere's surface triangles below z = 5 mm (a face tag of the mesh given
from Python: a window x_min .. z_max would not rotate with the scene); nodes there start at
gaps up to 5 mm, far beyond the approach, so they cannot close.

1. Frictionless, against Hertz for the contact's measured force P = sum lambda_n (the flat's
   motion prescribes the approach of the cut, which adds the whole sphere's compression to
   Hertz's): the approach delta = a^2/R measured on the axis as in test_hertz_sphere_3d.py
   (shortening from the contact point to d a, interpolated in the tetrahedra, plus Huber's
   half-space below) at d = 1 and 1.5, inside the fine zone (0.4 mm = 1.6 a), within (h/a)^2
   (second order: 1.0 % at h = 0.025, a/h = 10); the contact radius within one spacing h of
   a and the peak pressure within h/a of p0 (the node-spacing bounds of test_hertz_sphere_3d);
   the flat's force equal to the cut's reaction and every stress state balanced, to the
   equilibrium tolerance (1e-9).  The far field is coarse (growth 0.5 per mm, h_max 10 mm):
   it stiffens the sphere's bulk, which only changes P, and P is measured.  Measured: the
   approach +0.06 % and -0.29 % at a and 1.5 a; with every E x 1.05 or x 0.95
   (tests/mutate_3d.py) -0.84/-1.66 % and +1.03/+1.19 %, both rejected, the latter narrowly:
   the E check with margin is test_hertz_sphere_3d.py's, on its finer mesh.
2. The same scene with every coordinate rotated (mesh nodes, the flat's point, normal and
   motion) by a rotation about no coordinate axis: the discrete problem is the same, so the
   answers must be the rotated ones: u -> Q u, sigma -> Q sigma Q^T, and lambda_n, gaps,
   statuses, the events and their times unchanged, to ROUND_OFF = 1e-8 of each field's largest
   value (tests/engine/test_invariance.py's bound: the two runs differ by the rounding of
   their data, amplified by the condition number of the stiffness, ~10 N eps per solve).  On
   a coarse mesh (h = 0.1): the invariance holds on any mesh.
3. With friction (mu = 0.3, Spence's problem), the stick radius against slipstep's
   axisymmetric run (cases/hertz_sphere.toml) at the same force: within h + h_axi, as in
   test_spence_sphere_3d.py (h = 0.04 here).  (Before issue 37's polygon design of friction
   this scene at h = 0.025 panicked after 29 s, "min > max, or either was NaN"; it now
   completes in ~19 s, too long for CI: the mesh here is the coarser one.)
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, worst_equilibrium
from space3d import hertz_approach_errors

import slipstep
from slipstep.measures import references

R, E, NU, MOTION = 50.0, 70000.0, 0.3, 0.0012
H, H_COARSE, H_FRICTION, H_AXI = 0.025, 0.1, 0.04, 0.006
DEPTHS = (1.0, 1.5)
ROUND_OFF = 1e-8
#: A rotation about no coordinate axis (z, y, x angles 0.3, 0.7, -0.4 rad).
ANGLES = (0.3, 0.7, -0.4)


def rotation(a: float, b: float, c: float) -> np.ndarray:
    ca, sa, cb, sb, cc, sc = (
        math.cos(a),
        math.sin(a),
        math.cos(b),
        math.sin(b),
        math.cos(c),
        math.sin(c),
    )
    rz = np.array([[ca, -sa, 0], [sa, ca, 0], [0, 0, 1]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rx = np.array([[1, 0, 0], [0, cc, -sc], [0, sc, cc]])
    return rz @ ry @ rx


def hemisphere(h: float, Q: np.ndarray):
    """The half sphere's mesh (h_contact = h, fine within 0.4 mm), rotated by Q, with the
    face tags ``top`` (the cut) and ``cap`` (the surface triangles below z = 5 mm)."""
    from slipstep.mesh import tetrahedron_generators as generators
    from slipstep.mesh import TetMesh

    mesh = generators.sphere(R, h, 0.4, 10.0, 0.5, portion="half")
    surface = mesh.faces["surface"]
    cap = surface[(mesh.nodes[surface, 2] <= 5.0).all(axis=1)]
    return TetMesh(
        mesh.nodes @ Q.T, mesh.tetrahedra.copy(), {"top": mesh.faces["top"].copy(), "cap": cap}
    )


def run(h: float, Q: np.ndarray, mu: float = 0.0, snapshots=(0.5, 1.0)):
    case = {
        "case": {"name": "hemisphere"},
        "analysis": {"dimension": 3},
        "output": {"snapshots": snapshots if snapshots == "events" else list(snapshots)},
        "body": [{"name": "sphere", "material": {"E": E, "nu": NU}}],
        "bc": [{"name": "cut", "body": "sphere", "face": "top", "fix": ["x", "y", "z"]}],
        "contact": [
            {
                "name": "flat",
                "kind": "rigid_plane",
                "body": "sphere",
                "face": "cap",
                "point": [0.0, 0.0, 0.0],
                "normal": (Q @ [0.0, 0.0, 1.0]).tolist(),
                "motion": (Q @ [0.0, 0.0, MOTION]).tolist(),
                "mu": mu,
            }
        ],
    }
    return slipstep.run(case, meshes={"sphere": hemisphere(h, Q)}, progress=False)


@pytest.fixture(scope="module")
def plain():
    pytest.importorskip("gmsh")
    return run(H, np.eye(3))


@pytest.fixture(scope="module")
def pair():
    pytest.importorskip("gmsh")
    Q = rotation(*ANGLES)
    return run(H_COARSE, np.eye(3), snapshots="events"), run(H_COARSE, Q, snapshots="events"), Q


def contact_force(result) -> float:
    return float(np.sum(result.raw["snapshots"][-1]["lambda_n"]))


# --------------------------------------------------------------------------- 1. Hertz
@needs_gmsh
def test_balanced_without_symmetry_planes(plain):
    assert plain.completed
    model = plain.scene.model
    assert not any(bc["symmetry"] for bc in plain.case.data["bc"])
    worst, k, t = worst_equilibrium(model, plain.raw["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, t, worst)
    snap = plain.raw["snapshots"][-1]
    cut = np.unique(plain.scene.global_boundary("sphere", "top"))
    reaction = np.asarray(snap["reaction"])[cut].sum(axis=0)
    P = contact_force(plain)
    assert np.abs(reaction + [0.0, 0.0, P]).max() <= EQUILIBRIUM_TOL * P


@needs_gmsh
def test_approach_radius_and_peak_pressure_against_hertz(plain):
    P = contact_force(plain)
    a, p0, _ = references.hertz_sphere(P, R, E, NU)
    snap = plain.raw["snapshots"][-1]
    errors = hertz_approach_errors(
        plain.scene.nodes,
        plain.scene.tetrahedra,
        snap["u"],
        P,
        R,
        E,
        NU,
        origin=[0.0, 0.0, 0.0],
        inward=[0.0, 0.0, 1.0],
        depths=DEPTHS,
    )
    assert all(abs(e) <= (H / a) ** 2 for e in errors), (errors, (H / a) ** 2)
    s = plain.summary
    assert abs(s["contact_radius"] - a) <= H, (s["contact_radius"], a)
    assert abs(s["peak_pressure"] / p0 - 1) <= H / a, (s["peak_pressure"], p0)


# --------------------------------------------------------------------------- 2. rotated
def rel_diff(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.abs(a - b).max() / max(np.abs(a).max(), 1e-300))


@needs_gmsh
def test_rotated_in_space_the_answers_rotate(pair):
    base, turned, Q = pair
    assert base.completed and turned.completed
    eb, et = base.raw["events"], turned.raw["events"]
    assert list(eb["kind"]) == list(et["kind"]) and np.array_equal(eb["entity"], et["entity"])
    assert np.abs(np.asarray(eb["t"]) - np.asarray(et["t"])).max() <= ROUND_OFF
    assert len(eb["kind"]) > 10  # a contact grown through many closures
    for sb, st in zip(base.raw["snapshots"], turned.raw["snapshots"], strict=True):
        assert sb["t"] == pytest.approx(st["t"], abs=ROUND_OFF)
        assert np.array_equal(sb["status"], st["status"])
        for key in ("lambda_n", "gap"):
            assert rel_diff(sb[key], st[key]) <= ROUND_OFF, key
        assert rel_diff(np.asarray(sb["u"]) @ Q.T, st["u"]) <= ROUND_OFF
        sigma = np.asarray(sb["stress"])[:, [[0, 5, 4], [5, 1, 3], [4, 3, 2]]]
        turned_sigma = np.asarray(st["stress"])[:, [[0, 5, 4], [5, 1, 3], [4, 3, 2]]]
        assert rel_diff(Q @ sigma @ Q.T, turned_sigma) <= ROUND_OFF
    for key in ("total_normal_force", "contact_radius", "peak_pressure"):
        assert base.summary[key] == pytest.approx(turned.summary[key], rel=ROUND_OFF), key


# --------------------------------------------------------------------------- 3. friction
@needs_gmsh
def test_with_friction_the_stick_radius_of_the_axisymmetric_run():
    pytest.importorskip("gmsh")
    space = run(H_FRICTION, np.eye(3), mu=0.3, snapshots=(1.0,))
    assert space.completed, space.stop
    P = contact_force(space)
    axi = slipstep.run(
        CASES / "hertz_sphere.toml",
        progress=False,
        overrides=[
            f"mesh.h_contact={H_AXI}",
            "contact.mu=0.3",
            f"load.P={P}",
            "output.snapshots=[1.0]",
        ],
    )
    c3, c_axi = space.summary["stick_radius"], axi.summary["stick_half_width"]
    assert 0 < c3 and abs(c3 - c_axi) <= H_FRICTION + H_AXI, (c3, c_axi)
    worst, k, t = worst_equilibrium(space.scene.model, space.raw["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, t, worst)
