"""Zero-length runs in space settled by the rate problem on a faceted cone.

A thin square plate lying on a rigid frictional flat (every gap 0) under a point load at its
centre, modelled by its quarter (symmetry planes x = 0 and y = 0, the load on their common
edge): most of it lifts off at zero load (receding contact), and switched one event at a time
its pairs cycle through stick, slip and separation at zero load increment, the slip directions
turning in the plane.  Solving those statuses together in 3D is the rate problem's job (Lemke
on the cone faceted for that problem only, the statuses and slip directions handed back to the
round cone: rust/src/driver/rate_problem.rs); before it existed, mu = 1 and mu = 2 ended as an
ill-posed scene (a frozen pair left with a tensile force, or outside Coulomb's cone) and mu = 3
completed only by freezing pairs.

Each run must complete without the last resort, and its result is checked from the arrays
alone, pair by pair: Signorini (no penetration, closed pairs touch, open pairs carry nothing,
no tension), Coulomb's round cone |lambda_t| <= mu lambda_n, a slipping pair on the cone with its
friction opposing its slip (the dissipation -lambda_t . d(rtd) is never negative), equilibrium
recomputed from the stresses (tests/physics.py in space), and the plate carrying the whole load
on the flat.
"""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, equilibrium_residual, slipped_since_closing

import slipstep
from slipstep import _engine
from slipstep.build import build_scene
from slipstep.case import parse_case

PLATE = """
[analysis]
dimension = 3
[output]
snapshots = [1.0]
[[body]]
name = "plate"
[body.mesh]
generator = "box"
width = 5.0
depth = 5.0
height = 0.5
nx = 10
ny = 10
nz = 1
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
body = "plate"
face = "left"
symmetry = true
[[bc]]
body = "plate"
face = "front"
symmetry = true
[[point_load]]
at = [0.0, 0.0, 0.5]
force = [0.0, 0.0, -0.25]
[[contact]]
kind = "rigid_plane"
body = "plate"
face = "bottom"
mu = {mu}
"""

# Round-off tolerances relative to the scene's scales, as tests/engine/test_termination.py's:
# forces to the load (the engine's noise floor is 1e-12 of it, its own contact check 1e-9),
# gaps to the largest displacement (the solves' round-off on this small mesh is ~1e-12).
FORCE_TOL = 1e-9
GAP_TOL = 1e-8


def plate_model(mu: float) -> dict:
    model = build_scene(parse_case(PLATE.format(mu=mu), "plate.toml")).model
    model["options"] = {**model.get("options", {}), "output": "events"}
    return model


def assert_contact_conditions(model: dict, result: dict) -> None:
    """Signorini and Coulomb at every snapshot, from the arrays alone (and the event history,
    which tells a stuck pair on its polygon from one on the round cone)."""
    mu = model["pairs"]["mu"]
    snaps = result["snapshots"]
    force = FORCE_TOL * np.abs(model["load"]).sum()
    gap = GAP_TOL * max(np.abs(s["u"]).max() for s in snaps)
    for k, s in enumerate(snaps):
        closed, slipping = s["status"] > 0, s["status"] == 2
        ln, lt = s["lambda_n"], s["lambda_t"]
        size = np.linalg.norm(lt, axis=1)
        assert (s["gap"] >= -gap).all(), (k, s["gap"].min())
        assert (np.abs(s["gap"][closed]) <= gap).all(), (k, "a closed pair does not touch")
        assert (ln[~closed] == 0).all() and (lt[~closed] == 0).all(), (
            k,
            "an open pair carries force",
        )
        assert (ln[closed] >= -force).all(), (k, ln.min())
        # a stuck pair inside the round cone, or inside its polygon once it slipped (circumscribed
        # about the round cone, sides at most 2 slip_turn apart); a slipping one on the facet of
        # the cone at its direction: mu lambda_n along it, up to tan(slip_turn) mu lambda_n
        # across it (rust/src/coulomb.rs), so mu lambda_n <= |lambda_t| <= mu lambda_n /
        # cos(slip_turn)
        polygon = slipped_since_closing(result["events"], len(mu), float(s["t"]))
        capacity = (
            mu * ln / np.where(slipping | polygon, np.cos(model["options"]["slip_turn"]), 1.0)
        )
        assert (size <= capacity + force).all(), (
            k,
            "outside Coulomb's cone",
            (size - capacity).max(),
        )
        assert (size[slipping] >= (mu * ln)[slipping] - force).all(), (
            k,
            "a slipping pair inside the cone",
        )
        assert equilibrium_residual(model, s) <= EQUILIBRIUM_TOL, (
            k,
            equilibrium_residual(model, s),
        )
        if k > 0:
            # Friction opposes the slip of a pair slipping at both ends of the step: the
            # dissipation −λ_t · Δrtd is never negative (to force × length round-off).
            prev = snaps[k - 1]
            both = slipping & (prev["status"] == 2)
            work = np.einsum("ij,ij->i", lt[both], (s["rtd"] - prev["rtd"])[both])
            assert (work <= force * gap).all(), (k, work.max())


@pytest.mark.parametrize("mu", [0.5, 1.0, 1.5, 2.0, 2.5, 3.0])
def test_receding_plate_in_space_completes_through_the_rate_problem(mu):
    model = plate_model(mu)
    result = _engine.solve(model, False)
    assert result["stop"]["kind"] == "completed", result["stop"]
    kinds = Counter(result["events"]["kind"])
    assert "frozen" not in kinds, "the last resort fired on a scene with a solution"
    # (at mu = 3 the one-at-a-time rule settles the start alone since the polygon design of
    # rust/src/coulomb.rs: its onsets move no force)
    assert (
        result["n_rate_problems"] >= 1 or mu == 3.0
    ), "the scene no longer exercises the rate problem"
    assert_contact_conditions(model, result)
    # The flat carries the whole load (the symmetry planes take no vertical force).
    last = result["snapshots"][-1]
    load_z = -np.asarray(model["load"]).reshape(-1, 3)[:, 2].sum()
    assert abs(last["lambda_n"].sum() - load_z) <= FORCE_TOL * load_z
    # Receding contact: the pressure gathers under the load at the corner (0, 0) of the
    # quarter, so its centre lies nearer to it than the centre of the quarter's bottom face
    # (2.5, 2.5), where a uniform pressure would put it (the bottom nodes are symmetric about it).
    at = np.asarray(model["nodes"])[np.asarray(model["pairs"]["node_a"])]
    centre = last["lambda_n"] @ at[:, :2] / last["lambda_n"].sum()
    assert (centre < 2.5).all(), centre


# The frictional Hertz sphere (cases/hertz_sphere_3d.toml at mu = 0.3: the eighth of an elastic
# sphere pressed on a rigid flat, Spence's problem) on the coarsest mesh that ended on the last
# resort (11.8k DOFs, ~1 s): at t = 0.376 a pair that closed and slipped at once started a
# zero-length run; the rate problem set its neighbours slipping, the equilibrium correction of
# its hand-back's round-off force jump (5e-11 N) stuck them again on slip reversals of 1e-14 mm,
# the next trial slipped them at once, and after its three rate problems the run froze a pair
# on its cone, which the next increment pushed outside it. Monotonic loading of a frictional
# Hertz contact has a solution (every pair sticks once closed, slips near the edge at most).
SPHERE_H, SPHERE_MU, SPHERE_P = 0.03, 0.3, 30.0


@needs_gmsh
def test_frictional_hertz_sphere_in_space_completes_without_the_last_resort():
    snapshots = [round(0.025 * k, 3) for k in range(1, 41)]  # every 0.025 of the load
    result = slipstep.run(
        CASES / "hertz_sphere_3d.toml",
        progress=False,
        overrides=[
            f"mesh.h_contact={SPHERE_H}",
            f"contact.flat.mu={SPHERE_MU}",
            f"output.snapshots={snapshots}",
        ],
    )
    raw, model = result.raw, result.scene.model
    assert raw["stop"]["kind"] == "completed", raw["stop"]
    assert "frozen" not in Counter(
        raw["events"]["kind"]
    ), "the last resort fired on a scene with a solution"
    assert len(raw["snapshots"]) == len(snapshots)
    assert_contact_conditions(model, raw)
    # the eighth carries P/4 on the flat, from the arrays (the symmetry planes take no force along z)
    assert abs(4 * raw["snapshots"][-1]["lambda_n"].sum() - SPHERE_P) <= EQUILIBRIUM_TOL * SPHERE_P
