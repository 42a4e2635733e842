"""Guaranteed termination on adversarial scenes (issue 7, part 5).

The driver's rule (rust/src/driver.rs, "Termination"): positive-length increments advance the
load; within one run of zero-length increments each pair (and element) may switch status at
most ``max_zero_length_switches`` = 4 times and is then frozen (a ``frozen`` /
``frozen_element`` event) until the load advances, so a zero-length run has at most
(4 + 1) x (pairs + elements) increments; the whole run is bounded by ``max_events``
(automatic: 50 x (pairs + plastic elements + 1) + 1000 increments).  A frozen pair that then
violates a contact condition is an error naming it.

Every scene here must stop quickly, inside those bounds, and either complete (load fraction 1)
or raise a one-line ValueError naming a pair or an element.
"""

from __future__ import annotations

import copy
import re
from collections import Counter

import numpy as np
import pytest
from conftest import time_limit

from slipstep import _engine
from slipstep.case import parse_case
from slipstep.model import build_scene

MAX_ZERO_LENGTH_SWITCHES = 4  # Options::default() in rust/src/model.rs
ZERO_SCALE = 1e-12            # driver.rs: scale factors at or below this are zero-length




def longest_zero_length_run(scale) -> int:
    best = current = 0
    for s in scale:
        current = current + 1 if s <= ZERO_SCALE else 0
        best = max(best, current)
    return best


def run_bounded(model: dict) -> tuple[dict | None, str | None]:
    """Solve; check the documented bounds; return (result, None) or (None, error message)."""
    n_pairs = len(model["pairs"]["node_a"])
    n_elements = len(model["triangles"])
    plastic = any(m.get("Sy") is not None for m in model["materials"])
    try:
        with time_limit(60):
            result = _engine.solve(model, False)
    except ValueError as exc:
        msg = str(exc)
        assert "\n" not in msg
        assert re.search(r"\b(pair|element) \d+", msg), f"the error names no pair: {msg}"
        return None, msg
    assert not result["interrupted"]
    steps = result["steps"]
    n_steps = len(steps["scale"])
    max_steps = 50 * (n_pairs + (n_elements if plastic else 0) + 1) + 1000
    assert n_steps <= max_steps
    entities = n_pairs + (n_elements if plastic else 0)
    assert longest_zero_length_run(steps["scale"]) <= (MAX_ZERO_LENGTH_SWITCHES + 1) * entities
    if result["stop_reason"] is None:
        assert steps["load_fraction"][-1] == 1.0
    elif result["stop_reason"].startswith("limit load reached"):
        assert plastic, "only a plastic mechanism can make the tangent lose its stiffness"
    else:
        assert n_steps == max_steps and "max_events" in result["stop_reason"]
    for i, snap in enumerate(result["snapshots"]):
        for key in ("u", "stress", "lambda_n", "lambda_t", "gap"):
            assert np.isfinite(snap[key]).all(), (i, key)
    return result, None


BLOCK = """
[output]
snapshots = [1.0]
[[body]]
name = "b"
[body.mesh]
generator = "block"
x0 = {x0}
y0 = {y0}
width = {width}
height = {height}
nx = {nx}
ny = {ny}
[body.material]
E = 1000.0
nu = {nu}
[[contact]]
kind = "rigid_line"
body = "b"
edge = "bottom"
mu = {mu}
"""


def block_model(extra: str, **kw) -> dict:
    p = {"x0": 0.0, "y0": 0.0, "width": 2.0, "height": 1.0, "nx": 8, "ny": 4, "nu": 0.3,
         "mu": 0.3}
    p.update(kw)
    return build_scene(parse_case(BLOCK.format(**p) + extra)).model


# --------------------------------------------------------------------------- many at once
HANGING = """
[[bc]]
body = "b"
edge = "top"
fix = ["y"]
[[bc]]
body = "b"
edge = "left"
symmetry = true
[[bc]]
body = "b"
edge = "bottom"
traction = [0.0, -50.0]
"""


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.49])
def test_a_flat_face_closes_all_at_once_in_one_increment(nu):
    """A block hanging from its top (u_y = 0 there), pulled down by a traction on its bottom
    face: the stress is uniaxial and uniform, so all 201 bottom nodes reach the rigid flat
    0.01 below at the same load fraction.  They close together in ONE increment (a tie within
    tie_tol), and one more increment finishes the load."""
    model = block_model(HANGING, y0=0.01, width=20.0, nx=200, ny=2, nu=nu)
    result, error = run_bounded(model)
    assert error is None, error
    ev = result["events"]
    n_pairs = len(model["pairs"]["node_a"])
    assert n_pairs == 201
    assert list(ev["kind"]) == ["close"] * n_pairs
    assert set(ev["step"].tolist()) == {0}
    assert sorted(ev["entity"].tolist()) == list(range(n_pairs))
    # closes at u = 0.01 = f * 50 (1 - nu^2) / 1000 (plane strain, uniaxial stress, height 1)
    assert np.allclose(ev["load_fraction"], 0.01 * 1000 / (50 * (1 - nu ** 2)), rtol=1e-9,
                       atol=0)
    assert len(result["steps"]["scale"]) == 2


def test_a_flat_punch_closes_on_its_foundation_in_one_increment():
    """The same with two bodies: a hanging punch 0.01 above a fixed foundation, node-to-node
    pairs with equal gaps.  (A case file cannot say this: node_to_node pairs nodes within
    `tolerance` and counts gaps within `tolerance` as 0; so the scene is built touching and
    the punch is lifted in the engine model.)"""
    text = BLOCK.format(x0=0.0, y0=1.0, width=5.0, height=1.0, nx=50, ny=2, nu=0.3, mu=0.5)
    text = text.replace('kind = "rigid_line"\nbody = "b"\nedge = "bottom"',
                        'kind = "node_to_node"\nbody_a = "b"\nedge_a = "bottom"\n'
                        'body_b = "f"\nedge_b = "top"')
    text += HANGING + """
[[body]]
name = "f"
[body.mesh]
generator = "block"
width = 5.0
height = 1.0
nx = 50
ny = 2
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
body = "f"
edge = "bottom"
fix = ["x", "y"]
"""
    scene = build_scene(parse_case(text))
    model = scene.model
    punch = np.arange(scene.meshes["b"].n_nodes) + scene.offsets["b"]
    model["nodes"][punch, 1] += 0.01
    model["pairs"]["gap"][:] = 0.01
    result, error = run_bounded(model)
    assert error is None, error
    ev = result["events"]
    close = np.asarray(ev["kind"]) == "close"
    assert close.sum() == 51 and set(ev["step"][close].tolist()) == {0}
    assert sorted(ev["entity"][close].tolist()) == list(range(51))
    # after closing, the foundation's edge makes the outer pairs slip (a few more events)
    assert not (np.asarray(ev["step"])[~close] == 0).any()


# --------------------------------------------------------------------------- zero-length cycles
def shear_model(mu: float, ratio: float) -> dict:
    """A block on the flat (all pairs closed, gap 0), pressed and sheared on its top by a
    traction at ``ratio`` x mu of the pressure; held in x at one top corner only."""
    return block_model(f"""
[[bc]]
body = "b"
edge = "top"
traction = [{ratio * mu}, -1.0]
[[bc]]
body = "b"
nodes = "corner_top_left"
fix = ["x"]
""", mu=mu)


@pytest.mark.parametrize("mu", [0.5, 1.0, 2.0])
@pytest.mark.parametrize("ratio", [0.5, 0.999, 1.0, 1.001, 2.0])
def test_shear_at_the_friction_limit_terminates(mu, ratio):
    run_bounded(shear_model(mu, ratio))


RECEDING = """
[[point_load]]
at = [0.0, 0.5]
force = [0.0, -1.0]
"""


@pytest.mark.parametrize("mu", [0.0, 0.3, 1.0, 2.0])
@pytest.mark.parametrize("symmetric", [True, False], ids=["full", "half"])
def test_receding_contact_from_zero_gaps_terminates(mu, symmetric):
    """A thin plate lying on the flat (all gaps 0) under a central point load: most of it
    lifts off at zero load (receding contact).  The full plate is perfectly symmetric about
    x = 0, so every event comes in a tie with its mirror image."""
    if symmetric:
        extra = RECEDING + '[[bc]]\nbody = "b"\nnodes = "corner_top_left"\nfix = ["x"]\n'
        model = block_model(extra, x0=-5.0, width=10.0, height=0.5, nx=40, ny=2, mu=mu)
    else:
        extra = RECEDING + '[[bc]]\nbody = "b"\nedge = "left"\nsymmetry = true\n'
        model = block_model(extra, width=5.0, height=0.5, nx=20, ny=2, mu=mu)
    result, _ = run_bounded(model)
    if result is not None:
        kinds = Counter(result["events"]["kind"])
        assert kinds["separate"] > 0  # the plate lifts off its ends


def test_a_tangential_push_without_normal_load_is_frozen_and_named():
    """A block resting on the flat (gap 0, no pressure) pushed sideways at one bottom node:
    every pair has lambda_n = 0, so stick/slip/separate switch back and forth at zero load.
    The anti-cycling rule freezes them; the run stops with an error naming a frozen pair, or
    completes."""
    model = block_model("""
[[bc]]
body = "b"
edge = "left"
symmetry = true
[[point_load]]
at = [1.0, 0.0]
force = [-0.5, 0.0]
""", width=3.0, height=3.0, nx=3, ny=3, nu=0.49, mu=1.0)
    result, error = run_bounded(model)
    if error is not None:
        assert "frozen by the anti-cycling rule" in error
    else:
        assert "frozen" in set(result["events"]["kind"])


def test_perfect_plasticity_cycles_are_frozen():
    """One square of two perfectly plastic CST (nu = 0.499) pressed far beyond yield on a
    frictional flat: yield/unload and stick/slip alternate at zero load increment until the
    rule freezes the pair and both elements; then the run completes.  (Found by the fuzzer.)
    The load is beyond collapse, so by default the engine stops at the limit load; the
    limit-load stop is switched off here to exercise the anti-cycling rule itself."""
    model = {
        "nodes": np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]),
        "triangles": np.array([[0, 1, 3], [0, 3, 2]], dtype=np.int64),
        "element_material": np.zeros(2, dtype=np.int64),
        "materials": [{"E": 1000.0, "nu": 0.499, "Sy": 5.0, "H": 0.0}],
        "plane": "strain", "thickness": 1.0,
        "fixed_dofs": np.array([0, 4], dtype=np.int64),
        "load": np.array([0, 0, 0, 0, 0, -10.0, 0, -10.0]),
        "pairs": {"node_a": np.array([0, 1], dtype=np.int64),
                  "node_b": np.array([-1, -1], dtype=np.int64),
                  "normal": np.array([[0.0, 1.0], [0.0, 1.0]]), "gap": np.zeros(2),
                  "mu": np.full(2, 0.1)},
        "options": {"output": "events", "tie_tol": 1e-3, "drift_control": False},
    }
    default, error = run_bounded(copy.deepcopy(model))
    assert error is None and default["stop_reason"].startswith("limit load reached"), error
    model["options"]["limit_stiffness"] = 0.0
    result, error = run_bounded(model)
    assert error is None, error
    kinds = Counter(result["events"]["kind"])
    assert kinds["frozen"] >= 1 and kinds["frozen_element"] >= 1, kinds
    assert result["steps"]["load_fraction"][-1] == 1.0
