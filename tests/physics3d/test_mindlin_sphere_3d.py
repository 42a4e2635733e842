"""Mindlin's sphere in 3D through ``slipstep.run``: cases/mindlin_sphere_3d.toml (the half
y >= 0, sheared along x) and cases/mindlin_sphere_45_3d.toml (no symmetry, sheared along the
diagonal of the mesh's axes), both coarsened, against Mindlin (1949; Johnson, Contact Mechanics
§7.2) for two bodies of the same material (no normal-tangential coupling):

    a = (3 P R / (4 E*))^(1/3), E* = E / (2 (1 - nu^2));  stick disc c = a (1 - Q/(mu P))^(1/3),
    friction traction on the sphere antiparallel to Q in the slip annulus c < r < a.

P is the contact's measured normal force (the approach is prescribed), Q the applied shear
(the traction on the cut times its meshed area), so Q/(mu P) is what the run was given.

CI mesh: the sphere's contact spacing HS = 0.04 mm (a/h = 7.7), the block's 0.06, both growing
by 0.5 per mm.  Tolerances:
- forces: the contact's resultants balance the applied shear and the cut's reaction to the
  engine's equilibrium tolerance (1e-9), on any mesh;
- contact radius (the equivalent radius of the closed sphere nodes' areas) within one
  contactor spacing HS of Hertz's a (the true edge lies between a closed and an open node);
- stick radius: within HS of the true stick edge likewise, and c is 0.794 a, itself known to
  HS: 3 HS on this mesh (the bench holds the bench mesh to two spacings);
- slip directions: within TURN of antiparallel to Q: the engine follows a slipping pair's
  direction exactly on the round cone, re-aligning it whenever the trial's slip rate turns by
  more than its slip_turn option within an increment (docs/engine_api.md): TURN = 2 slip_turn
  bounds the misalignment (one turn before a re-alignment, one within the increment after);
- the 45 degree run (whole sphere and block) against the run along x (the half): the stick and
  contact radii of the same sphere nodes within HS of each other, the stick zone's centroid
  within HS of the contact point, and its area's principal second moments within 2 HS/c of each
  other (a disc of nodal areas, each boundary node moving a radius by up to HS).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, equilibrium_residual

import slipstep

HS, HB = 0.04, 0.06
R, E, NU, MU = 50.0, 70000.0, 0.3, 0.3
E_STAR = E / (2 * (1 - NU ** 2))
COARSE = [f"body.sphere.mesh.h_contact={HS}", f"body.block.mesh.h_contact={HB}",
          "body.sphere.mesh.growth=0.5", "body.block.mesh.growth=0.5",
          "output.snapshots=[1.0, 2.0]"]


def angle_deg(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Angles in degrees between the rows of u and the direction v."""
    v = np.asarray(v, dtype=float) / np.linalg.norm(v)
    cos = (np.asarray(u, dtype=float) @ v) / np.linalg.norm(u, axis=1)
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def second_moments(points: np.ndarray, weights: np.ndarray):
    """(centroid (2,), principal values (2,) descending) of points in the plane x, y weighted
    by ``weights`` (areas)."""
    w, p = np.asarray(weights, dtype=float), np.asarray(points, dtype=float)[:, :2]
    c = (w[:, None] * p).sum(axis=0) / w.sum()
    d = p - c
    values = np.linalg.eigvalsh(np.einsum("p,pi,pj->ij", w, d, d) / w.sum())
    return c, values[::-1]


def applied_shear(result, mirror: float) -> np.ndarray:
    """The shear stage's force on the model (traction x the cut's meshed area), times the
    mirror factor of a half model (its y component then cancels with the mirror's)."""
    bc = next(b for b in result.case.data["bc"] if b["name"] == "shear")
    tri = result.scene.global_boundary("sphere", "top")
    x = result.scene.nodes[tri]
    area = 0.5 * np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1).sum()
    q = mirror * area * np.asarray(bc["traction"], dtype=float)
    if mirror == 2.0:
        q[1] = 0.0
    return q


def mindlin(result, mirror: float) -> dict:
    """Measured forces and Mindlin's a and c for them, the summary's radii, the profile."""
    s = result.summary
    P = s["total_normal_force"]
    Q = applied_shear(result, mirror)
    a = (3 * P * R / (4 * E_STAR)) ** (1 / 3)
    ratio = np.linalg.norm(Q) / (MU * P)
    return {"P": P, "Q": Q, "a": a, "c": a * (1 - ratio) ** (1 / 3), "ratio": ratio,
            "summary": s, "profile": result.profile()}


def slip_turn() -> float:
    from slipstep.schema import SOLVER_KEYS
    return float(SOLVER_KEYS["slip_turn"].default)


@pytest.fixture(scope="module")
def along_x():
    pytest.importorskip("gmsh")
    result = slipstep.run(CASES / "mindlin_sphere_3d.toml", overrides=COARSE, progress=False)
    return result, mindlin(result, 2.0)


@pytest.fixture(scope="module")
def diagonal():
    pytest.importorskip("gmsh")
    result = slipstep.run(CASES / "mindlin_sphere_45_3d.toml", overrides=COARSE, progress=False)
    return result, mindlin(result, 1.0)


def slipping_tractions(m: dict) -> np.ndarray:
    prof = m["profile"]
    t = prof["tangential_stress"][prof["status"] == 2]
    return t[np.linalg.norm(t, axis=1) > 0]


@needs_gmsh
def test_forces_balance_the_shear_and_the_cut(along_x):
    result, m = along_x
    assert result.completed
    s = m["summary"]
    assert math.isclose(m["ratio"], 0.5, rel_tol=0.05)  # the case's Q = 0.5 mu P, P measured
    assert math.isclose(s["total_tangential_force"], np.linalg.norm(m["Q"]),
                        rel_tol=EQUILIBRIUM_TOL)
    # the cut's reaction (the prescribed approach, both halves) carries P
    top = np.unique(result.scene.global_boundary("sphere", "top"))
    reaction = np.asarray(result.raw["snapshots"][-1]["reaction"])[top, 2].sum()
    assert math.isclose(-2 * reaction, m["P"], rel_tol=EQUILIBRIUM_TOL)
    for snap in result.raw["snapshots"]:
        assert equilibrium_residual(result.scene.model, snap) <= EQUILIBRIUM_TOL


@needs_gmsh
def test_contact_and_stick_radii_against_mindlin(along_x):
    _, m = along_x
    s = m["summary"]
    assert abs(s["contact_radius"] - m["a"]) <= HS, (s["contact_radius"], m["a"])
    assert abs(s["stick_radius"] - m["c"]) <= 3 * HS, (s["stick_radius"], m["c"])
    assert s["contacts"]["interface"]["n_slip"] > 0 and s["contacts"]["interface"]["n_stick"] > 0


@needs_gmsh
def test_slip_is_along_the_shear(along_x):
    _, m = along_x
    t = slipping_tractions(m)
    assert len(t) >= 5
    assert angle_deg(t, -m["Q"]).max() <= 2 * math.degrees(slip_turn())


@needs_gmsh
def test_sheared_at_45_degrees_the_forces_follow_the_load(diagonal):
    result, m = diagonal
    assert result.completed
    tangential = np.asarray(m["summary"]["tangential_force"])
    assert np.allclose(tangential, m["Q"], rtol=0, atol=EQUILIBRIUM_TOL * np.linalg.norm(m["Q"]))
    t = slipping_tractions(m)
    assert len(t) >= 10
    assert angle_deg(t, -m["Q"]).max() <= 2 * math.degrees(slip_turn())


@needs_gmsh
def test_sheared_at_45_degrees_the_stick_zone_is_the_same_disc(diagonal, along_x):
    _, m45 = diagonal
    _, m0 = along_x
    for key in ("stick_radius", "contact_radius"):
        assert abs(m45["summary"][key] - m0["summary"][key]) <= HS, key
    assert abs(m45["summary"]["stick_radius"] - m45["c"]) <= 3 * HS
    prof = m45["profile"]
    stick = prof["status"] == 1
    area = result_areas(diagonal[0], prof)[stick]
    centre, moments = second_moments(prof["x"][stick], area)
    assert np.linalg.norm(centre) <= HS
    c = m45["summary"]["stick_radius"]
    assert moments[0] / moments[1] - 1 <= 2 * 2 * HS / c  # moments go as c^2: twice HS/c each


def result_areas(result, prof) -> np.ndarray:
    """The profile's rows' tributary areas (the scene's pair areas, in the profile's order)."""
    return np.asarray(result.scene.pair_area)[prof["pair"]]
