"""Elastoplastic Hertz cylinder (paper §5.1, Table 1, Fig. 5): Sy = 200 MPa, H' = 700 MPa.

Johnson: for a frictionless line contact (nu = 0.3) von Mises yield starts below the surface at
depth 0.70 a when p0 = 1.79 Sy, i.e. at the load fraction f = (1.79 Sy / p0)^2 = 0.654 of the
full load (p0 grows as sqrt(f)).
"""

import math

import numpy as np
import pytest
from physics import EQUILIBRIUM_TOL, equilibrium_residual

from slipstep import prepare, solve

SY, H = 200.0, 700.0
A_HERTZ, P0_HERTZ = 1.4384068, 442.58672
F_JOHNSON = (1.79 * SY / P0_HERTZ) ** 2
PLASTIC = [f"material.Sy={SY}", f"material.H={H}"]


def first_yield(h):
    """Load fraction and element centroid of the first yield event on a mesh of size h."""
    scene = prepare(None, overrides=[*PLASTIC, f"mesh.h_contact={h}", "output.snapshots=[1.0]"])
    scene.model["options"]["stop_at_first_yield"] = True
    result = solve(scene)
    ev = result["events"]
    k = ev["kind"].index("yield")
    centroid = scene.nodes[scene.triangles[ev["entity"][k]]].mean(axis=0)
    return float(ev["load_fraction"][k]), centroid


def test_johnson_reference():
    assert F_JOHNSON == pytest.approx(0.654, abs=5e-4)


def test_first_yield_load_and_depth_on_the_default_mesh():
    # Acceptance: 3 % on the load fraction; depth 0.70 a(f) within one element size (0.03 mm).
    f, c = first_yield(0.03)
    assert f == pytest.approx(F_JOHNSON, rel=0.03)
    a = A_HERTZ * math.sqrt(f)
    assert abs(c[1] - 0.70 * a) <= 0.03
    assert abs(c[0]) <= 0.25 * a, "first yield lies under the centre of the contact"


def test_first_yield_error_shrinks_under_refinement():
    errors = [abs(first_yield(h)[0] / F_JOHNSON - 1) for h in (0.12, 0.06, 0.03)]
    assert errors[0] > errors[1] > errors[2], errors


@pytest.fixture(scope="module")
def plastic_runs():
    """Full elastoplastic runs on a coarse mesh (h_contact = 0.15 mm: ~200-300 yield events
    each), a snapshot after every event."""
    runs = {}
    for mu in (0.0, 0.1, 0.35):
        scene = prepare(
            None,
            overrides=[
                *PLASTIC,
                "mesh.h_contact=0.15",
                f"contact.mu={mu}",
                "output.snapshots=events",
            ],
        )
        runs[mu] = scene, solve(scene)
    return runs


def plastic_zone(scene, result):
    last = result["snapshots"][-1]
    ever = np.flatnonzero(np.asarray(last["plastic_strain"]) > 0)
    tri = scene.nodes[scene.triangles[ever]]
    area = 0.5 * np.abs(
        (tri[:, 1, 0] - tri[:, 0, 0]) * (tri[:, 2, 1] - tri[:, 0, 1])
        - (tri[:, 2, 0] - tri[:, 0, 0]) * (tri[:, 1, 1] - tri[:, 0, 1])
    )
    closed = set(
        np.asarray(scene.model["pairs"]["node_a"])[np.asarray(last["status"]) > 0].tolist()
    )
    touches_surface = any(closed & set(scene.triangles[e].tolist()) for e in ever)
    return area.sum(), touches_surface


def test_runs_complete_in_equilibrium(plastic_runs):
    # Every event state in equilibrium, recomputed from its stresses, load and contact forces
    # (tests/physics.py; 1e-9: the equilibrium contract, round-off is far below).
    failures = []
    for mu, (scene, result) in plastic_runs.items():
        steps = result["steps"]
        assert steps["load_fraction"][-1] == 1.0 and not result["interrupted"]
        for k, snap in enumerate(result["snapshots"]):
            r = equilibrium_residual(scene.model, snap)
            if r > EQUILIBRIUM_TOL:
                failures.append((mu, k, float(snap["load_fraction"]), r))
        np.testing.assert_allclose(
            steps["normal_force"], np.asarray(steps["load_fraction"]) * 500.0, rtol=1e-9
        )
        assert "yield" in result["events"]["kind"]
        last = result["snapshots"][-1]
        assert np.all(
            np.abs(last["lambda_t"]) <= mu * np.asarray(last["lambda_n"]) * (1 + 1e-9) + 1e-12
        )
    assert not failures, f"(mu, snapshot, load fraction, residual) out of equilibrium: {failures}"


def test_plastic_zone_grows_with_friction_and_reaches_the_surface(plastic_runs):
    # Paper §5.1 / Fig. 5: friction enlarges the plastic zone; at mu = 0.35 it reaches the surface.
    zones = {mu: plastic_zone(*run) for mu, run in plastic_runs.items()}
    assert zones[0.0][0] < zones[0.1][0] < zones[0.35][0], zones
    assert not zones[0.0][1] and zones[0.35][1], zones


def test_drift_bounded_and_smaller_than_paper_exact(plastic_runs):
    # With the default drift control (stress step <= 0.05 Sy per increment) the departure from the
    # yield surface is second order in that step: bound 0.05^2 = 2.5e-3. The paper's procedure
    # (frozen tangent, no bound, no return) drifts more on the same scene.
    scene, result = plastic_runs[0.35]
    assert result["max_drift"] <= 0.05**2
    scene.model["options"]["drift_control"] = False
    exact = solve(scene)
    assert exact["max_drift"] > result["max_drift"]


@pytest.mark.parametrize("turn, tolerance", [(0.0, 1e-9), (None, 0.05 * 0.05**2)])
def test_unloading_is_elastic(turn, tolerance):
    # mu = 0.35 redistributes stress near the surface: some plastic elements unload. After its
    # `unload` event an element's plastic strain must stay frozen (elastic response) until it
    # yields again, and its von Mises stress stays at or below the current yield stress.
    # Tolerance: with the tangent renewed at every increment (tangent_turn = 0) the stresses
    # sit on the surface to round-off (1e-9 relative). With the default held tangent (up to
    # θ = 0.05 rad off the flow) the equilibrium correction leaves plastic elements up to
    # θ × its stress change off the surface, at most θ × max_stress_step² = 1.25e-4 (an
    # unloading element is put back on the surface, but the next correction may move it that
    # much again).
    # Event by event (group_tol = 0): the unload events and their states are the subject here
    # (grouped increments integrate unloading and re-yield inside an increment).
    extra = [] if turn is None else [f"solver.tangent_turn={turn}"]
    scene = prepare(
        None,
        overrides=[
            *PLASTIC,
            "mesh.h_contact=0.15",
            "contact.mu=0.35",
            "output.snapshots=events",
            "solver.group_tol=0",
            *extra,
        ],
    )
    result = solve(scene)
    ev = result["events"]
    unloads = [
        (int(s), int(e)) for s, k, e in zip(ev["step"], ev["kind"], ev["entity"]) if k == "unload"
    ]
    assert unloads, "this scene has unloading elements"
    snaps = result["snapshots"]  # snapshot k + 1 is the state after step k
    for step, e in unloads:
        later_yield = [
            int(s)
            for s, k, x in zip(ev["step"], ev["kind"], ev["entity"])
            if k == "yield" and x == e and s > step
        ]
        end = later_yield[0] if later_yield else len(snaps) - 2
        ep = [snaps[k + 1]["plastic_strain"][e] for k in range(step, end + 1)]
        assert max(ep) - min(ep) <= 1e-12 * max(ep[0], 1e-12), (e, ep[:3])
        for k in range(step, end + 1):
            s = np.asarray(snaps[k + 1]["stress"][e])
            se = np.sqrt(
                0.5 * ((s[0] - s[1]) ** 2 + (s[1] - s[2]) ** 2 + (s[2] - s[0]) ** 2) + 3 * s[3] ** 2
            )
            assert se <= (SY + H * ep[0]) * (1 + tolerance)


def test_yield_drift_field_matches_the_engine_measure(tmp_path):
    # The XDMF's per-element yield_drift is recomputed from stress and plastic strain; at every
    # snapshot it must stay below the engine's max_drift (which is measured before the return).
    import h5py

    from slipstep.output import writers as output

    scene = prepare(
        None, overrides=[*PLASTIC, "mesh.h_contact=0.15", "output.snapshots=[0.8, 1.0]"]
    )
    result = solve(scene)
    output.write_xdmf(tmp_path, scene, result)
    with h5py.File(tmp_path / "results.h5") as h5:
        drifts = [np.asarray(h5[k]) for k in h5 if k.startswith("data")]
    assert len(drifts) > 0
    per_element = [output.yield_drift(scene, s).max() for s in result["snapshots"]]
    assert max(per_element) <= result["max_drift"] + 1e-12
    assert max(per_element) > 0 or result["max_drift"] == 0
