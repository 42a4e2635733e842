"""Loads of any magnitude: within small strain and f64's range the results scale with them (the
elastic problem is linear, and a change of stress units is exact); beyond, one input error that
names the stage, the load and the bound, never an internal error or a message that blames mu
or duplicate pairs.

The bound (docs/engine_api.md, Magnitudes): at every stage end, the loads' nominal strains (a
force over the smallest E times the scene's section, a prescribed displacement or an obstacle's
motion over the scene's size), times the factors they reach, add up to at most 1, and each
nonzero one is at least 1e-100.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from conftest import CASES, needs_gmsh, write_case

import slipstep
from slipstep.case import CaseError
from slipstep.errors import InputError

# A 2 x 1 block on a rigid flat (pairs at gap 0, mu = 0.3: stick holds it in x), its top pushed
# down by 0.01 ("push"), a pressure on its right side ("side"), the flat moved up by "lid".
BLOCK = """
[case]
name = "magnitudes"

[output]
figures = false
xdmf = false

[[body]]
name = "block"
[body.mesh]
generator = "block"
width = 2.0
height = 1.0
nx = 8
ny = 4
[body.material]
E = 1000.0
nu = 0.3

[[bc]]
name = "push"
body = "block"
edge = "top"
displacement = {y = -0.01}

[[bc]]
name = "side"
body = "block"
edge = "right"
pressure = 1.0

[[contact]]
name = "lid"
kind = "rigid_line"
body = "block"
edge = "bottom"
mu = 0.3
motion = [0.0, 0.001]

[[stage]]
name = "press"
factors = {push = 1.0, side = 1.0, lid = 1.0}
"""

#: Nominal strains at factor 1: push 0.01 / L, side 1 x 1 / (E x 1 x L), lid 0.001 / L, with
#: L = the mesh's diagonal sqrt(5) (every pair starts closed: no gap adds to it).
L = math.sqrt(5.0)
STRAIN = {"push": 0.01 / L, "side": 1.0 / (1000.0 * L), "lid": 0.001 / L}

HUGE = [1e20, 1e100, 1e200, 1e300, 1e308]
TINY = [1e-300]


def run(tmp_path, *overrides, text=BLOCK):
    return slipstep.run(write_case(tmp_path, text), None, list(overrides), progress=False)


def input_error(tmp_path, *overrides) -> str:
    with pytest.raises(InputError) as info:
        run(tmp_path, *overrides)
    message = str(info.value)
    assert "\n" not in message, message
    for blamed in ("mu", "redundant", "duplicate", "ill-posed", "bug"):
        assert not re.search(rf"\b{blamed}\b", message), message
    return message


@pytest.mark.parametrize("load", ["push", "side", "lid"])
@pytest.mark.parametrize("factor", HUGE + [-f for f in HUGE] + TINY)
def test_a_stage_factor_beyond_the_bound_is_one_input_error(tmp_path, load, factor):
    message = input_error(tmp_path, f"stage.press.factors.{load}={factor!r}")
    head = f"stage 'press': load '{load}' at factor "
    assert message.startswith(head), message
    assert float(message[len(head) :].split()[0]) == factor, message
    assert " reaches a nominal strain of " in message, message
    if abs(factor) > 1:
        # The factor that would reach the bound: 1 minus the other loads' share, here < 1e-2.
        assert "at most 1 is meaningful" in message and "|factor| <= " in message, message
        allowed = float(message.rsplit("|factor| <= ", 1)[1].split()[0])
        assert 0.9 / STRAIN[load] < allowed <= 1.0 / STRAIN[load], message
    else:
        assert "at least 1e-100 is needed" in message and "|factor| >= " in message, message


@pytest.mark.parametrize("value", HUGE + TINY)
def test_a_prescribed_displacement_beyond_the_bound_is_one_input_error(tmp_path, value):
    # Without [[stage]] the loads are at factor 1: the message speaks of their values.
    text = BLOCK.split("[[stage]]")[0]
    with pytest.raises(InputError) as info:
        run(tmp_path, f"bc.push.displacement.y={-value!r}", text=text)
    message = str(info.value)
    assert message.startswith("load 'push' reaches a nominal strain of"), message
    assert ("lower its values" if value > 1 else "raise its values") in message, message


@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
@pytest.mark.parametrize(
    "key", ["stage.factors.push", "bc.push.displacement.y", "bc.side.pressure"]
)
def test_nan_and_inf_are_refused_by_key(tmp_path, key, value):
    # (The only stage is spelled without its name, as --set may.)
    with pytest.raises(CaseError, match=rf"{key} = {value} is not allowed: expected a "):
        run(tmp_path, f"{key}={value}")


@pytest.mark.parametrize("factor", [1e-95, 1e-40, 1e-3, 30.0])
def test_within_the_bound_the_results_scale_with_the_loads(tmp_path, factor):
    # Every pair starts closed, so the elastic problem is homogeneous of degree one in its loads
    # (displacements, forces and the flat's motion together): the same events at the same load
    # fractions, u and the contact forces scaled. 1e-12: round-off of the solves, relative.
    scaled = [f"stage.press.factors.{k}={factor!r}" for k in STRAIN]
    one, other = run(tmp_path), run(tmp_path, *scaled)
    assert one.stop["kind"] == other.stop["kind"] == "completed"
    assert np.array_equal(one.events["kind"], other.events["kind"])
    assert np.array_equal(one.events["entity"], other.events["entity"])
    assert np.allclose(
        one.events["load_fraction"], other.events["load_fraction"], rtol=0, atol=1e-12
    )
    a, b = one.raw["snapshots"][-1], other.raw["snapshots"][-1]
    for key in ("u", "lambda_n", "lambda_t"):
        x, y = np.asarray(a[key]) * factor, np.asarray(b[key])
        assert np.allclose(x, y, rtol=0, atol=1e-12 * np.abs(x).max()), key


@needs_gmsh
@pytest.mark.filterwarnings("error")  # no overflow in the summary's von Mises either
@pytest.mark.parametrize("units", [1e-45, 1e9, 1e45])
def test_a_change_of_stress_units_is_exact(tmp_path, units):
    # The Hertz cylinder with E and P in other units (E = 7e4 x 1e±45: near the bound 1e±50 on
    # the material's magnitudes): the contact grows through its gaps in the same events, p0 and
    # the stresses scale by the units, u does not (E/P fixed). Before, stresses in units 1e9
    # smaller made the contact system "singular: remove duplicate pairs".
    base = ["mesh.h_contact=0.4", "output.figures=false", "output.xdmf=false"]
    one = slipstep.run(CASES / "hertz_cylinder.toml", None, base, progress=False)
    other = slipstep.run(
        CASES / "hertz_cylinder.toml",
        None,
        base + [f"load.P={1000.0 * units!r}", f"material.E={70000.0 * units!r}"],
        progress=False,
    )
    assert np.array_equal(one.events["kind"], other.events["kind"])
    assert np.array_equal(one.events["entity"], other.events["entity"])
    a, b = one.raw["snapshots"][-1], other.raw["snapshots"][-1]
    # 1e-9: the event scales come from solves of systems scaled by 1e±45 (round-off ~1e-13
    # measured); u and the forces through them.
    assert np.allclose(
        one.events["load_fraction"], other.events["load_fraction"], rtol=0, atol=1e-9
    )
    assert np.allclose(
        np.asarray(b["u"]), np.asarray(a["u"]), rtol=0, atol=1e-9 * np.abs(a["u"]).max()
    )
    assert np.allclose(
        np.asarray(b["lambda_n"]) / units,
        np.asarray(a["lambda_n"]),
        rtol=0,
        atol=1e-9 * np.abs(a["lambda_n"]).max(),
    )


@pytest.mark.parametrize("units", [1e-45, 1e45])
def test_a_change_of_stress_units_is_exact_where_every_pair_slips(tmp_path, units):
    # The block's top pushed down onto the flat, nothing else holding it in x: its pairs all
    # slip (mu = 0.1, no node on its axis) and the rate problem decides where one sticks.
    text = BLOCK.replace("nx = 8", "nx = 9").replace("mu = 0.3", "mu = 0.1")
    text = text.replace("motion = [0.0, 0.001]", "").split("[[stage]]")[0]
    text = text.replace(
        '[[bc]]\nname = "side"\nbody = "block"\nedge = "right"\npressure = 1.0\n', ""
    )
    overrides = ["bc.push.displacement.y=-0.001"]
    one = run(tmp_path, *overrides, text=text)
    other = run(tmp_path, *overrides, f"body.block.material.E={1000.0 * units!r}", text=text)
    assert one.raw["n_rate_problems"] == other.raw["n_rate_problems"] == 1
    assert np.array_equal(one.events["kind"], other.events["kind"])
    a, b = one.raw["snapshots"][-1], other.raw["snapshots"][-1]
    assert np.allclose(
        np.asarray(b["lambda_n"]) / units,
        np.asarray(a["lambda_n"]),
        rtol=0,
        atol=1e-9 * np.abs(a["lambda_n"]).max(),
    )
    assert np.array_equal(a["status"], b["status"]) and list(a["status"]).count(1) == 1


@pytest.mark.parametrize(
    "key, value, loads",
    [
        ("E", 1e200, ["bc.push.displacement.y=-0.001"]),
        ("E", 1e-60, []),
        ("E", 1e51, []),
        ("Sy", 1e60, []),
        ("Sy", 1e-300, []),
        ("H", 1e300, []),
        ("H", 1e-55, []),
    ],
)
def test_material_magnitudes_whose_squared_stresses_leave_f64_are_one_input_error(
    tmp_path, key, value, loads
):
    # Stresses reach E x the nominal strain (up to 1) and are squared, and the yield check
    # multiplies squares: beyond 1e±50 (E = 1e200 with its loads scaled alike used to complete,
    # then the summary's von Mises overflowed) the case is refused by key, with the fix.
    plastic = [] if key == "E" else ["body.block.material.Sy=20.0", "body.block.material.H=100.0"]
    if key == "Sy" and value < 1:
        plastic = ["body.block.material.E=1e-40"]  # so that the yield strain is not the error
    msg = input_error(tmp_path, *plastic, *loads, f"body.block.material.{key}={value!r}")
    shown = repr(value).replace("e+", "e")  # as the engine writes it
    assert msg.startswith(f"body 'block' material: {key} = {shown} is not allowed"), msg
    assert "[1e-50, 1e50]" in msg and "another unit" in msg
