"""Grouped plastic increments, the speed-accuracy knob delta = solver.group_tol (issues 6, 16).

With delta > 0 (0.03 by default) an increment of a plastic run goes on past the first yield it
predicts by delta of the load fraction reached; every element that yields inside it gets the
exact split of its strain increment (elastic part, then Prandtl-Reuss flow integrated with
error control), and the increment is re-integrated from its start until it is balanced.
Contact events inside it are taken as contact sub-steps (the engine's `substeps`: the small
system with K held, no full-space solve) when snapshots are requested at given times, but for
closures next to plastic elements, which end it; with a snapshot at every event each ends an
increment. delta = 0 is the paper, event by event.
What must hold, whatever delta:
* the first yield load moves by less than the window;
* every event state is in equilibrium, recomputed from the snapshot arrays (tests/physics.py);
* contact closes exactly: no standoff, no tension (closures taken early and held at their
  remaining gap raised the Hertz peak pressure by 8.6 % at h = 0.03 and 61 % at h = 0.011,
  delta = 0.1, in an earlier engine that grouped them);
* the plastic path stays close to the event-by-event one (issue 16: within 0.5 % at the
  default on the thick cylinder, H' = 0, where no contact event bounds the increments);
* fewer increments (the point of the knob) -- asserted first wherever a grouped run is compared
  with the exact one: a scene where grouping groups nothing would make every comparison pass
  trivially.  The scenes here are elastoplastic: many yields between events.
"""

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, worst_equilibrium

from slipstep import prepare, solve
from slipstep.errors import InputError
from slipstep.output.summary import summarize

PLASTIC = ["material.Sy=200", "material.H=700", "contact.mu=0.3", "mesh.h_contact=0.1"]
P_HALF = 500.0  # the default case carries P = 1000 N/mm on the half model: half of it here


def run(overrides, delta, snapshots="[1.0]"):
    scene = prepare(
        None, overrides=[*overrides, f"solver.group_tol={delta}", f"output.snapshots={snapshots}"]
    )
    result = solve(scene)
    return scene, result, summarize(scene, result)


@pytest.fixture(scope="module")
def plastic():
    # the grouped run keeps every event state, for the equilibrium check
    return {0.0: run(PLASTIC, 0.0), 1e-2: run(PLASTIC, 1e-2, "events")}


def assert_contact_states(scene, snapshots, h):
    """At every snapshot: closed pairs touch (|gap| <= 1e-6 h: round-off of the solves against
    the mesh size), carry no tension (-1e-9 of the load: round-off), satisfy Coulomb (1e-9
    relative: the cone is hit exactly), and the state is in equilibrium, recomputed."""
    mu = np.asarray(scene.model["pairs"]["mu"])
    for k, snap in enumerate(snapshots):
        closed = np.asarray(snap["status"]) != 0
        ln, lt = np.asarray(snap["lambda_n"]), np.asarray(snap["lambda_t"])
        assert np.all(np.abs(np.asarray(snap["gap"])[closed]) < 1e-6 * h), k
        assert np.all(ln[closed] >= -1e-9 * P_HALF), k
        assert np.all(np.abs(lt) <= mu * ln * (1 + 1e-9) + 1e-9 * P_HALF), k
    worst, k, f = worst_equilibrium(scene.model, snapshots)
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)


def first_yield_fraction(result):
    ev = result["events"]
    return min(f for f, k in zip(ev["load_fraction"], ev["kind"]) if k == "yield")


def test_grouping_keeps_the_exact_first_yield_load(plastic):
    # Up to the first yield the path is elastic and the contact events are the exact run's (a
    # snapshot at every event: no contact sub-steps), so the trial's predicted first yield is
    # the exact run's onset and the grouped run records it there, to round-off (1e-9: the
    # solves' relative round-off is ~1e-13 over ~100 increments), not where the straight
    # strain path of its plastically flowing window puts it (as it was recorded before: the
    # thick cylinder's first yield 0.7 % early at delta = 0.01, 2.1 % at 0.03).
    f0, f1 = first_yield_fraction(plastic[0.0][1]), first_yield_fraction(plastic[1e-2][1])
    assert abs(f1 / f0 - 1) < 1e-9


def test_grouping_takes_fewer_increments_in_equilibrium(plastic):
    exact, grouped = plastic[0.0][1], plastic[1e-2][1]
    # Measured 630 -> 93 increments on this mesh; a factor 3 is a safe floor for delta = 1e-2.
    assert len(grouped["steps"]["load_fraction"]) * 3 < len(exact["steps"]["load_fraction"])
    scene = plastic[1e-2][0]
    worst, k, f = worst_equilibrium(scene.model, grouped["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
    # Sum of normal forces = the applied load on the half model (equilibrium of the cylinder).
    snap = grouped["snapshots"][-1]
    assert np.sum(snap["lambda_n"]) == pytest.approx(P_HALF, rel=1e-9)


def test_grouped_plastic_result_stays_within_the_window(plastic):
    # Events up to 1 % early in load: the contact half-width (~ sqrt(load)) and the peak
    # pressure may move by about delta/2 = 0.5 %; 1 % allows for the plastic zone's share
    # (measured: a -0.26 %... +0.12 %, p0 -0.2 % on the meshes tried).
    s0, s1 = plastic[0.0][2], plastic[1e-2][2]
    assert s1["contact_half_width"] == pytest.approx(s0["contact_half_width"], rel=1e-2)
    assert s1["peak_pressure"] == pytest.approx(s0["peak_pressure"], rel=1e-2)
    assert s1["n_plastic_elements"] == pytest.approx(s0["n_plastic_elements"], rel=0.05)


def test_grouping_closes_contacts_exactly():
    """delta = 0.1 (the coarsest setting of the bench) on the elastoplastic cylinder, mu = 0.3,
    h = 0.15 mm: yields are grouped, closures and slips never.

    First: grouping must group (fewer increments), or nothing below could fail.  Then at every
    event state of the grouped run: closed pairs touch (|gap| <= 1e-6 h: round-off of the
    solves against the mesh size; a pair closed early and held at its remaining gap would be
    off by a fraction of h), carry no tension (-1e-9 of the load: round-off), satisfy Coulomb
    (1e-9 relative: the cone is hit exactly), and the state is in equilibrium (recomputed).
    The contact width and peak pressure: grouped plasticity runs at most a factor (1 + delta)
    ahead in load, closures are exact, so a and p0 (both ~ sqrt(load) in Hertz contact) move
    by at most sqrt(1 + delta) - 1 = 4.9 % of delta = 0's."""
    h, delta = 0.15, 0.1
    base = ["material.Sy=200", "material.H=700", "contact.mu=0.3", f"mesh.h_contact={h}"]
    _, r0, s0 = run(base, 0.0)
    scene, r1, s1 = run(base, delta, "events")
    n0, n1 = len(r0["steps"]["load_fraction"]), len(r1["steps"]["load_fraction"])
    assert n1 < n0, (n1, n0)
    assert "yield" in r1["events"]["kind"]
    assert_contact_states(scene, r1["snapshots"], h)
    window = math.sqrt(1 + delta) - 1
    assert s1["contact_half_width"] == pytest.approx(s0["contact_half_width"], rel=window)
    assert s1["peak_pressure"] == pytest.approx(s0["peak_pressure"], rel=window)
    assert np.sum(r1["snapshots"][-1]["lambda_n"]) == pytest.approx(P_HALF, rel=1e-9)


def test_friction_events_inside_grouped_increments_keep_the_contact_history(plastic):
    """delta = 1e-2 with snapshots at given times: stick<->slip events inside a grouped
    increment are contact sub-steps, with K held over the increment's window.  First: they
    happen, and the full-space increments are fewer.  Then against the event-by-event run: every
    pair closes and first slips at the same load within the window, delta x the load reached
    (the grouping contract: K is held for at most that much load); the history is in load
    order with its steps; and at the snapshots (the ends of integrated, balanced increments)
    equilibrium recomputed from the arrays, closed pairs touching without tension, Coulomb."""
    delta, h = 1e-2, 0.1
    scene, grouped, summary = run(PLASTIC, delta, "[0.5, 1.0]")
    exact = plastic[0.0][1]
    substeps = summary["n_contact_substeps"]
    assert substeps > 0
    assert (
        len(grouped["steps"]["load_fraction"]) - substeps < len(exact["steps"]["load_fraction"]) / 3
    )

    def first(result, kind):
        ev, out = result["events"], {}
        for f, k, e in zip(ev["load_fraction"], ev["kind"], ev["entity"]):
            if k == kind:
                out.setdefault(int(e), float(f))
        return out

    for kind in ("close", "stick_to_slip"):
        at0, at1 = first(exact, kind), first(grouped, kind)
        assert at0.keys() == at1.keys(), kind
        for p, f in at0.items():
            assert abs(at1[p] - f) <= delta * f, (kind, p, f, at1[p])
    ev = grouped["events"]
    assert np.all(np.diff(np.asarray(ev["load_fraction"])) >= 0)
    assert np.all(np.diff(np.asarray(ev["step"])) >= 0)
    assert_contact_states(scene, grouped["snapshots"], h)


@pytest.mark.parametrize("bad", ["-0.1", "1.0", "nan"])
def test_group_tol_out_of_range_is_refused(bad):
    with pytest.raises(InputError, match="group_tol"):
        prepare(None, overrides=[f"solver.group_tol={bad}"])


@needs_gmsh
def test_default_grouping_keeps_the_plastic_path_of_the_thick_cylinder():
    """The thick cylinder (H' = 0, p = 175 MPa, Hill's c = 14.42 mm) at the case mesh: no
    contact event bounds the increments, so only the plastic window does. The default grouped
    run against the event-by-event one: the largest difference of any element's plastic strain
    (relative to the largest) and of its stresses within 0.5 % (issue 16's bound for the
    default; measured 0.47 % and 0.07 %), in under a tenth of the increments (measured 48 vs
    1607), and the same plastic front (largest plastic centroid radius) within one ring of
    elements (h = 0.25 mm at the bore: measured 14.488 vs 14.494 mm)."""
    runs = {}
    for delta in (0.0, None):
        extra = [] if delta is None else [f"solver.group_tol={delta}"]
        scene = prepare(CASES / "thick_cylinder.toml", ["output.snapshots=[1.0]", *extra])
        runs[delta] = scene, solve(scene)
    (scene, exact), (_, grouped) = runs[0.0], runs[None]
    assert len(grouped["steps"]["load_fraction"]) * 10 < len(exact["steps"]["load_fraction"])
    a, b = exact["snapshots"][-1], grouped["snapshots"][-1]
    rel = lambda x, y: np.abs(np.asarray(x) - y).max() / np.abs(np.asarray(y)).max()
    assert rel(b["plastic_strain"], a["plastic_strain"]) <= 5e-3
    assert rel(b["stress"], a["stress"]) <= 5e-3
    worst, k, f = worst_equilibrium(scene.model, grouped["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
    centroid_r = np.linalg.norm(scene.nodes[scene.triangles].mean(axis=1), axis=1)
    front = [centroid_r[np.asarray(s["plastic"]) > 0].max() for s in (a, b)]
    assert abs(front[1] - front[0]) <= 0.25, front
