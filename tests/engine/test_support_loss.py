"""A body held by contact alone that loses its hold along the path: it tips, lifts off or slides
as a whole.  The run stops there like at a limit load (``stop.kind == "support_lost"``), writes
what it computed, and says at which t, about which point and why; a body not held before any
load is applied stays an error.

The scene: a 5.14 x 4.38 block (plane stress) resting on a rigid flat, every bottom node a pair
at gap 0, held by nothing else; stage ``press`` applies the pressure q = 45.67 on its top, stage
``shear`` adds the traction -tau = -59.37 along x.  Rigid statics gives where each stop must
be, independently of the mesh and the material:

* tipping about the corner (0, 0): the last pair but one separates when the contact resultant
  reaches the corner, i.e. when the moment of the loads about it vanishes,
  tau s w h = q w (w/2) (friction acts at y = 0), so t = 1 + q w / (2 h tau) = 1.45136;
* sliding (mu = 0.3 < the tau/q = 0.59 at tipping): the last sticking pair slips when the
  friction needed reaches mu times the normal force, tau s w = mu q w, t = 1 + mu q / tau.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import write_case

import slipstep
from slipstep.errors import FreeBodyError

W, H, Q, TAU = 5.14, 4.38, 45.67, 59.37
T_TIP = 1.0 + Q * W / (2.0 * H * TAU)

BLOCK = f"""
[case]
name = "tipping_block"

[analysis]
plane = "stress"

[output]
figures = false
xdmf = false

[[body]]
name = "block"
[body.mesh]
generator = "block"
width = {W}
height = {H}
nx = 8
ny = 6
[body.material]
E = 1000.0
nu = 0.3

[[bc]]
name = "press"
body = "block"
edge = "top"
pressure = {Q}

[[bc]]
name = "shear"
body = "block"
edge = "top"
traction = [{-TAU}, 0.0]

[[contact]]
name = "base"
kind = "rigid_line"
body = "block"
edge = "bottom"
mu = 2.686

[[stage]]
name = "press"
factors = {{press = 1.0}}

[[stage]]
name = "shear"
factors = {{shear = 1.0}}
"""

#: The stop's path time comes from an event's scale, a linear solve: round-off is ~1e-12.
T_TOL = 1e-9
#: Equilibrium of the whole block from the arrays: the engine holds it to equilibrium_tol = 1e-9
#: of the load (the elastoplastic runs balance their corrections to that too).
FORCE_TOL = 1e-9 * Q * W


def contact_resultant(result) -> tuple[float, float]:
    """(Σ contact force along x, along y) on the block at the last snapshot, from λ_n, λ_t and
    the pairs' normals (t = (-n_y, n_x))."""
    snap = result.raw["snapshots"][-1]
    n = np.asarray(result.scene.model["pairs"]["normal"], dtype=float)
    t = np.column_stack([-n[:, 1], n[:, 0]])
    f = np.asarray(snap["lambda_n"])[:, None] * n + np.asarray(snap["lambda_t"])[:, None] * t
    return float(f[:, 0].sum()), float(f[:, 1].sum())


@pytest.mark.parametrize(
    "overrides",
    [
        [],
        ["material.Sy=30", "material.H=100"],
        ["material.Sy=30", "material.H=100", "output.snapshots=[1.0, 2.0]"],
    ],
    ids=["elastic", "elastoplastic", "elastoplastic_grouped"],
)
def test_a_block_sheared_until_it_tips_stops_there_and_keeps_its_results(tmp_path, overrides):
    # Elastic, then yielding at the corners (every event a snapshot: increments event by event
    # in the contact space; with time snapshots: grouped increments with contact sub-steps). The
    # tipping load is the same: it is statics.
    case = write_case(tmp_path, BLOCK)
    result = slipstep.run(case, tmp_path / "out", overrides, progress=False)
    stop = result.stop
    assert stop["kind"] == "support_lost", stop
    assert abs(stop["t"] - T_TIP) < T_TOL, (stop["t"], T_TIP)
    assert stop["message"].startswith(
        f"support lost at t = {T_TIP:.6f} (stage 'shear'): body 'block' tips about contact "
        f"'base' pair 0 (node 0 at (0.000000, 0.000000)), its last closed pair"
    ), stop["message"]
    # The results up to there are written, the last snapshot at the stop.
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["stop"]["kind"] == "support_lost" and summary["final_t"] == stop["t"]
    assert (tmp_path / "out" / "events.csv").read_text().count("\n") == len(result.events) + 1
    assert (tmp_path / "out" / "contact_profile.csv").is_file()
    assert result.times[-1] == stop["t"]
    # Equilibrium at the stop: the contact carries the pressure and the shear reached there.
    fx, fy = contact_resultant(result)
    assert abs(fy - Q * W) < FORCE_TOL and abs(fx - TAU * W * (stop["t"] - 1.0)) < FORCE_TOL


def test_a_block_sheared_beyond_friction_slides_as_a_whole_at_the_friction_limit(tmp_path):
    mu = 0.3
    result = slipstep.run(
        write_case(tmp_path, BLOCK), tmp_path / "out", [f"contact.mu={mu}"], progress=False
    )
    stop = result.stop
    assert stop["kind"] == "support_lost", stop
    assert abs(stop["t"] - (1.0 + mu * Q / TAU)) < T_TOL, stop["t"]
    assert "body 'block' slides as a whole (−translation in x)" in stop["message"], stop["message"]
    assert "raise mu" in stop["message"]
    fx, fy = contact_resultant(result)
    assert abs(fy - Q * W) < FORCE_TOL and abs(fx - mu * Q * W) < FORCE_TOL


def test_a_block_pressed_then_pulled_lifts_off_where_the_pressure_changes_sign(tmp_path):
    # press to q, then to -q: every contact force is (1 - 2s) times its value at t = 1.
    result = slipstep.run(
        write_case(tmp_path, BLOCK), None, ["stage.shear.factors={press = -1.0}"], progress=False
    )
    assert result.stop["kind"] == "support_lost"
    assert abs(result.stop["t"] - 1.5) < T_TOL
    assert (
        "body 'block' lifts off: its last closed pair (contact 'base' pair"
        in result.stop["message"]
    ), result.stop["message"]


def test_a_body_held_by_nothing_before_any_load_is_still_an_error(tmp_path):
    # The flat 0.1 below the block: no pair starts closed, nothing holds the block at t = 0.
    with pytest.raises(FreeBodyError, match="body 'block' is free to move"):
        slipstep.run(
            write_case(tmp_path, BLOCK), None, ["contact.point=[0.0, -0.1]"], progress=False
        )


def test_a_body_pulled_off_its_contact_at_the_first_instant_is_told_so(tmp_path):
    # The base starts closed (gap 0) and the first stage pulls the block up: it leaves the base
    # before any load is applied, an input error that names the contact and the pull (the
    # load's resultant, (0, q w), along +y), not a suggestion to start a contact closed.
    with pytest.raises(FreeBodyError) as err:
        slipstep.run(
            write_case(tmp_path, BLOCK),
            None,
            ["stage.press.factors={press = -1.0}"],
            progress=False,
        )
    assert str(err.value).startswith(
        "body 'block' lifts off at the first instant (t = 0): contact 'base' starts closed "
        "(gap 0), but the load pulls the body away from it along (0.000, 1.000)"
    ), str(err.value)
    assert "start a contact closed" not in str(err.value)
