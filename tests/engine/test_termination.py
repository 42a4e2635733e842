"""Guaranteed termination, and well-posed scenes solved (issues 7 and 12).

The driver's rule (rust/src/driver/anticycling.rs): positive-length increments advance the
load; within one run of zero-length increments each pair (and element) may switch status
``max_zero_length_switches`` = 4 times. A pair that would switch once more means the
one-at-a-time rule is cycling: the statuses of all critical pairs are then solved together as a
complementarity problem (rust/src/driver/rate_problem.rs, Lemke's method), at most 3 times per
run; only if that fails is the entity frozen (the last resort), and a frozen pair that then
violates a contact condition is an ``IllPosedError``.  The whole run is bounded by
``max_events`` (automatic: 50 x (pairs + plastic elements + 1) + 1000 increments).

Every scene here has a solution, so each must *complete* (load fraction 1, stop "completed"),
and the result is checked from its arrays, not from the engine's own checks: equilibrium
recomputed from the stresses (tests/physics.py), no penetration, no tension, open pairs carry
no force, closed pairs touch, Coulomb's cone, and friction opposing the slip of every slipping
pair.  The one scene without a solution (a perfectly plastic square loaded past its collapse
load with the limit-load stop switched off) shows the last resort.
"""

from __future__ import annotations

import copy
from collections import Counter

import numpy as np
import pytest
from conftest import time_limit
from physics import equilibrium_residual

from slipstep import _engine
from slipstep.case import parse_case
from slipstep.errors import GrossSlidingError
from slipstep.build import build_scene

MAX_ZERO_LENGTH_SWITCHES = 4  # Options::default() in rust/src/model.rs
MAX_RATE_PROBLEMS = 3  # rust/src/driver/anticycling.rs
ZERO_SCALE = 1e-12  # rust/src/driver/selection.rs: zero-length increments
# Round-off tolerances, relative to the scene's scales: forces to Σ|load| (the engine's noise
# floor is 1e-12 of it; the checks allow 1e-9, the engine's own contact check), gaps to the
# largest displacement (1e-8: the triangular solves' round-off on these small meshes is ~1e-12).
FORCE_TOL = 1e-9
GAP_TOL = 1e-8
# Equilibrium recomputed from the stresses: round-off of the solves (the engine's own bound).
EQUILIBRIUM_TOL = 1e-9


def longest_zero_length_run(scale) -> int:
    best = current = 0
    for s in scale:
        current = current + 1 if s <= ZERO_SCALE else 0
        best = max(best, current)
    return best


def assert_contact_conditions(model: dict, result: dict) -> None:
    """Signorini and Coulomb on every snapshot, from the arrays alone."""
    mu = model["pairs"]["mu"]
    snaps = result["snapshots"]
    force = FORCE_TOL * np.abs(model["load"]).sum()
    gap = GAP_TOL * max(np.abs(s["u"]).max() for s in snaps)
    for k, s in enumerate(snaps):
        closed = s["status"] > 0
        ln, lt = s["lambda_n"], s["lambda_t"]
        assert (s["gap"] >= -gap).all(), (k, s["gap"].min())
        assert (np.abs(s["gap"][closed]) <= gap).all(), (k, "a closed pair does not touch")
        assert (ln[~closed] == 0).all() and (lt[~closed] == 0).all(), (
            k,
            "an open pair carries force",
        )
        assert (ln[closed] >= -force).all(), (k, ln.min())
        assert (np.abs(lt) <= mu * ln + force).all(), (k, "outside Coulomb's cone")
        assert equilibrium_residual(model, s) <= EQUILIBRIUM_TOL, (
            k,
            equilibrium_residual(model, s),
        )
        if k > 0:
            # Friction opposes the slip: λ_t · Δrtd ≤ 0 for pairs slipping at both ends of the
            # step (the dissipation −λ_t Δrtd is never negative).
            prev = snaps[k - 1]
            slipping = (s["status"] == 2) & (prev["status"] == 2) & (mu > 0)
            work = lt[slipping] * (s["rtd"] - prev["rtd"])[slipping]
            assert (work <= force * gap).all(), (k, work.max())


def run_complete(model: dict) -> dict:
    """Solve with a snapshot at every event; the run must complete inside the documented
    bounds and satisfy every contact condition."""
    model["options"] = {**model.get("options", {}), "output": "events"}
    n_pairs = len(model["pairs"]["node_a"])
    plastic = any(m.get("Sy") is not None for m in model["materials"])
    entities = n_pairs + (len(model["triangles"]) if plastic else 0)
    with time_limit(60):
        result = _engine.solve(model, False)
    assert result["stop"]["kind"] == "completed", result["stop"]
    steps = result["steps"]
    assert steps["load_fraction"][-1] == 1.0
    assert len(steps["scale"]) <= 50 * (entities + 1) + 1000
    assert (
        longest_zero_length_run(steps["scale"])
        <= (MAX_ZERO_LENGTH_SWITCHES + 1) * entities + MAX_RATE_PROBLEMS
    )
    assert "frozen" not in set(
        result["events"]["kind"]
    ), "the last resort fired on a scene with a solution"
    assert_contact_conditions(model, result)
    return result


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
    p = {"x0": 0.0, "y0": 0.0, "width": 2.0, "height": 1.0, "nx": 8, "ny": 4, "nu": 0.3, "mu": 0.3}
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
    result = run_complete(model)
    ev = result["events"]
    n_pairs = len(model["pairs"]["node_a"])
    assert n_pairs == 201
    assert list(ev["kind"]) == ["close"] * n_pairs
    assert set(ev["step"].tolist()) == {0}
    assert sorted(ev["entity"].tolist()) == list(range(n_pairs))
    # closes at u = 0.01 = f * 50 (1 - nu^2) / 1000 (plane strain, uniaxial stress, height 1)
    assert np.allclose(ev["load_fraction"], 0.01 * 1000 / (50 * (1 - nu**2)), rtol=1e-9, atol=0)
    assert len(result["steps"]["scale"]) == 2


def test_a_flat_punch_closes_on_its_foundation_in_one_increment():
    """The same with two bodies: a hanging punch 0.01 above a fixed foundation, node-to-node
    pairs with equal gaps.  (A case file cannot say this: node_to_node pairs nodes within
    `tolerance` and counts gaps within `tolerance` as 0; so the scene is built touching and
    the punch is lifted in the engine model.)"""
    text = BLOCK.format(x0=0.0, y0=1.0, width=5.0, height=1.0, nx=50, ny=2, nu=0.3, mu=0.5)
    text = text.replace(
        'kind = "rigid_line"\nbody = "b"\nedge = "bottom"',
        'kind = "node_to_node"\nbody_a = "b"\nedge_a = "bottom"\n' 'body_b = "f"\nedge_b = "top"',
    )
    text += (
        HANGING
        + """
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
    )
    scene = build_scene(parse_case(text))
    model = scene.model
    punch = np.arange(scene.meshes["b"].n_nodes) + scene.offsets["b"]
    model["nodes"][punch, 1] += 0.01
    model["pairs"]["gap"][:] = 0.01
    result = run_complete(model)
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
    return block_model(
        f"""
[[bc]]
body = "b"
edge = "top"
traction = [{ratio * mu}, -1.0]
[[bc]]
body = "b"
nodes = "corner_top_left"
fix = ["x"]
""",
        mu=mu,
    )


@pytest.mark.parametrize("mu", [0.5, 1.0, 2.0])
@pytest.mark.parametrize("ratio", [0.5, 0.999, 1.0, 1.001, 2.0])
def test_shear_at_and_beyond_the_friction_limit_completes(mu, ratio):
    """The corner support holds the block in x whatever the shear, so every ratio has a
    solution: beyond the friction limit the base slips and the corner takes the rest. (Before
    the rate problem, mu = 2 at ratio 0.5 and mu = 0.5 at ratio 2 ended frozen.)"""
    result = run_complete(shear_model(mu, ratio))
    if ratio > 1.0:
        last = result["snapshots"][-1]
        assert (last["status"] != 1).any() or (
            last["status"] == 0
        ).any(), "beyond the limit some pair slips or opens"


RECEDING = """
[[point_load]]
at = [0.0, 0.5]
force = [0.0, -1.0]
"""


def receding_plate(mu: float, symmetric: bool) -> dict:
    if symmetric:
        extra = RECEDING + '[[bc]]\nbody = "b"\nnodes = "corner_top_left"\nfix = ["x"]\n'
        return block_model(extra, x0=-5.0, width=10.0, height=0.5, nx=40, ny=2, mu=mu)
    extra = RECEDING + '[[bc]]\nbody = "b"\nedge = "left"\nsymmetry = true\n'
    return block_model(extra, width=5.0, height=0.5, nx=20, ny=2, mu=mu)


@pytest.mark.parametrize("mu", [0.0, 0.3, 1.0, 1.5, 2.0, 3.0])
@pytest.mark.parametrize("symmetric", [True, False], ids=["full", "half"])
def test_receding_contact_from_zero_gaps_completes(mu, symmetric):
    """A thin plate lying on the flat (all gaps 0) under a central point load: most of it lifts
    off at zero load (receding contact). The full plate's geometry and load are symmetric about
    x = 0, but its one x support (a top corner) carries Σλ_t once friction acts, so only the
    frictionless run is mirror-symmetric. (Before the rate problem, mu = 2 and 3 ended frozen
    with a tensile force.) The plate carries the whole load on the flat: Σλ_n = 1 in both
    models (the half model's point load sits on its symmetry line and is applied whole; the
    symmetry line takes no vertical force)."""
    result = run_complete(receding_plate(mu, symmetric))
    assert Counter(result["events"]["kind"])["separate"] > 0  # the plate lifts off its ends
    last = result["snapshots"][-1]
    assert abs(last["lambda_n"].sum() - 1.0) <= 1e-9
    if symmetric and mu == 0.0:
        # Frictionless, the full plate is mirror-symmetric (its one x support, at a top
        # corner, carries no force then; with friction it does, and breaks the symmetry): the
        # pairs at x and −x carry the same normal force (round-off of the solves).
        model = receding_plate(mu, symmetric)
        x = model["nodes"][model["pairs"]["node_a"], 0]
        mirror = np.array([np.argmin(np.abs(x + xi)) for xi in x])
        assert np.allclose(x[mirror], -x, atol=1e-12)
        assert np.allclose(last["lambda_n"], last["lambda_n"][mirror], rtol=0, atol=1e-9)


@pytest.mark.parametrize("mu", [1.2, 1.7, 3.0])
@pytest.mark.parametrize("nx, ny", [(40, 4), (80, 8)])
def test_receding_contact_on_finer_meshes_above_the_lift_off_threshold_completes(nx, ny, mu):
    """The half plate on finer meshes: above a threshold mu_c (about 1.0-1.2 on these meshes,
    found by an independent LCP solver and an exhaustive search of status patterns) the
    plate's unloaded overhang ends flat on the flat, touching with forces down to 1e-6; there
    the first Lemke solver ended on rays although a solution exists. Every run must complete
    with all conditions met (see assert_contact_conditions)."""
    extra = RECEDING + '[[bc]]\nbody = "b"\nedge = "left"\nsymmetry = true\n'
    result = run_complete(block_model(extra, width=5.0, height=0.5, nx=nx, ny=ny, mu=mu))
    assert abs(result["snapshots"][-1]["lambda_n"].sum() - 1.0) <= 1e-9


def test_a_tangential_push_without_normal_load_completes():
    """A block resting on the flat (gap 0, no pressure) pushed sideways at one bottom node,
    held in x by its symmetry edge: every pair starts at lambda_n = 0, and the one-at-a-time
    rule cycles stick/slip/separate at zero load (it used to freeze). The block touches the
    flat with zero force wherever it does not lift: nothing holds it vertically but contact,
    and no vertical load acts, so Σλ_n = 0 at the end."""
    model = block_model(
        """
[[bc]]
body = "b"
edge = "left"
symmetry = true
[[point_load]]
at = [1.0, 0.0]
force = [-0.5, 0.0]
""",
        width=3.0,
        height=3.0,
        nx=3,
        ny=3,
        nu=0.49,
        mu=1.0,
    )
    result = run_complete(model)
    assert abs(result["snapshots"][-1]["lambda_n"].sum()) <= 1e-9
    assert result["n_rate_problems"] >= 1


def test_gross_sliding_is_its_own_error_with_the_friction_capacity():
    """A block on the flat, nothing holding it in x, pressed by q = 1 and sheared by τ = 0.75
    with mu = 0.5: τ/q > mu at every load level, so friction cannot hold it (gross sliding).
    The error names the body and the direction, and under the full load (width 2) the
    tangential load T = 2τ = 1.5 against the capacity μN = 0.5 × 2q = 1 (printed to 4 digits)."""
    model = block_model(
        """
[[bc]]
body = "b"
edge = "top"
traction = [0.75, -1.0]
""",
        mu=0.5,
    )
    with pytest.raises(GrossSlidingError) as info:
        _engine.solve(model, False)
    msg = str(info.value)
    assert msg.startswith("body 'b' slides as a whole") and "translation in x" in msg, msg
    load, capacity = (
        float(msg.split(word)[1].split()[0]) for word in ("tangential load T = ", "μN = ")
    )
    assert abs(load - 1.5) <= 1e-3 and abs(capacity - 1.0) <= 1e-3, msg
    assert "\n" not in msg


def test_perfect_plasticity_beyond_collapse_reaches_the_last_resort():
    """One square of two perfectly plastic CST (nu = 0.499) pressed far beyond its collapse
    load on a frictional flat: by default the engine stops at the limit load. With the stop
    switched off there is no solution past collapse, and yield/unload alternate with
    stick/slip at zero load increment until the last-resort rule freezes the pair and both
    elements; the run then completes. (Found by the fuzzer.) This is the only scene in the
    suite that reaches the last resort."""
    model = {
        "nodes": np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]),
        "triangles": np.array([[0, 1, 3], [0, 3, 2]], dtype=np.int64),
        "element_material": np.zeros(2, dtype=np.int64),
        "materials": [{"E": 1000.0, "nu": 0.499, "Sy": 5.0, "H": 0.0}],
        "plane": "strain",
        "thickness": 1.0,
        "fixed_dofs": np.array([0, 4], dtype=np.int64),
        "load": np.array([0, 0, 0, 0, 0, -10.0, 0, -10.0]),
        "pairs": {
            "node_a": np.array([0, 1], dtype=np.int64),
            "node_b": np.array([-1, -1], dtype=np.int64),
            "normal": np.array([[0.0, 1.0], [0.0, 1.0]]),
            "gap": np.zeros(2),
            "mu": np.full(2, 0.1),
        },
        "options": {"output": "events", "tie_tol": 1e-3, "drift_control": False},
    }
    with time_limit(60):
        default = _engine.solve(copy.deepcopy(model), False)
    assert default["stop"]["kind"] == "limit_load", default["stop"]
    model["options"]["limit_stiffness"] = 0.0
    with time_limit(60):
        result = _engine.solve(model, False)
    kinds = Counter(result["events"]["kind"])
    assert kinds["frozen"] >= 1 and kinds["frozen_element"] >= 1, kinds
    assert result["stop"]["kind"] == "completed"
    assert (
        longest_zero_length_run(result["steps"]["scale"])
        <= (MAX_ZERO_LENGTH_SWITCHES + 1) * 4 + MAX_RATE_PROBLEMS
    )
