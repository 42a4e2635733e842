"""slipstep vs dolfinx in axisymmetry (issue 15, test 5), identical meshes: the ring forms of
:class:`slipstep.fenicsx.forms.RingSection` (strain (u_r,r, u_z,z, u_r/r, gamma_rz), measure
2 pi r dx, axis held u_r = 0) against slipstep's ring element.

Elastic: the one-point (centroid) rule is slipstep's element, so the two solutions agree to
round-off (thick sphere, bulk; Hertz sphere, its contact state replayed).  A higher quadrature
is another consistent ring element: it differs at the discretization level and the difference
vanishes with the mesh.  Elastoplastic (the thick sphere, H' = 0): dolfinx in N equal load
steps (backward-Euler return, Newton) against slipstep's event path; the difference is the
step error of the return mapping and vanishes at first order in 1/N.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from conftest import CASES, needs_gmsh
from slipstep import build_scene, load_case, parse_case
from slipstep.measures import references
from slipstep.fenicsx.crosscheck import bulk_differences, engine_result, plastic_bulk

pytest.importorskip("dolfinx")
from slipstep.fenicsx.bulk import BulkProblem  # noqa: E402
from slipstep.fenicsx.replay import replay_elastic  # noqa: E402

THICK = CASES / "thick_sphere.toml"
ELASTIC = ["material.Sy=1e9", "output.snapshots=[0.5]"]
#: cases/thick_sphere.toml's mesh doubled (h = 0.5 at the bore, 1.6 outside)
COARSE = ["mesh.h=0.5", "mesh.h_outer=1.6"]

#: Round-off of two direct solvers (faer Cholesky, MUMPS LU) on the same matrix: eps 2.2e-16
#: times the condition number of the ring stiffness (~1e4 on these meshes: element sizes
#: 0.25..0.8 mm, r from 0 to 20 mm) with a margin of 100.
ROUND_OFF = 1e-10


@pytest.fixture(scope="module")
def thick_elastic():
    scene = build_scene(load_case(THICK, ELASTIC))
    return scene, BulkProblem(scene)


def test_ring_supports_and_loads_are_slipsteps(thick_elastic):
    """dolfinx finds the same held dofs (the case's symmetry edge and, by its own dof
    coordinates, u_r = 0 on the axis) and assembles the same ring load 2 pi int N r p n ds."""
    scene, bulk = thick_elastic
    assert np.array_equal(bulk.fixed_dofs, scene.model["fixed_dofs"])
    axis = np.flatnonzero(scene.nodes[:, 0] == 0.0)
    assert len(axis) > 10 and set(2 * axis) <= set(bulk.fixed_dofs.tolist())
    f = scene.model["load"]
    assert np.abs(bulk.load - f).max() <= 1e-13 * np.abs(f).max()


def test_ring_point_load_is_a_ring_total():
    """A [[point_load]] in axisymmetry is the total force on its ring (no thickness, no
    2 pi): the same vector as slipstep's."""
    text = (
        (CASES / "thick_sphere.toml").read_text()
        + """
[[point_load]]
body = "sphere"
at = [0.0, 20.0]
force = [0.0, -500.0]
"""
    )
    scene = build_scene(parse_case(text))
    bulk = BulkProblem(scene)
    f = scene.model["load"]
    assert np.abs(bulk.load - f).max() <= 1e-13 * np.abs(f).max()
    top = int(np.argmin(np.linalg.norm(scene.nodes - [0.0, 20.0], axis=1)))
    assert bulk.load[2 * top + 1] == -500.0  # on the unloaded outer surface: the force alone


def test_elastic_thick_sphere_agrees_to_round_off(thick_elastic):
    """Measured: u 1.9e-14, stress 6.1e-14.  The reactions vanish on free dofs, and the
    Newton path of the plastic solver (one step, DG0 tangent = D) gives the same answer."""
    scene, bulk = thick_elastic
    snap = engine_result(scene)[0]["snapshots"][-1]
    res = bulk.solve_elastic()
    d = bulk_differences(snap, res)
    assert d["u"] < ROUND_OFF and d["stress"] < ROUND_OFF, d
    free = np.setdiff1d(np.arange(2 * len(scene.nodes)), scene.model["fixed_dofs"])
    assert np.abs(res.reaction[free]).max() < ROUND_OFF * np.abs(scene.model["load"]).max()
    d1 = bulk_differences(snap, bulk.solve_plastic(n_steps=1))
    assert d1["u"] < ROUND_OFF and d1["stress"] < ROUND_OFF, d1


@needs_gmsh
def test_higher_quadrature_is_another_consistent_ring():
    """quadrature_degree = 2 integrates the u_r v_r / r term of the stiffness (almost) exactly
    instead of at the centroid: a different element, off slipstep's by far more than round-off,
    converging to it with the mesh: displacements at second order (the element energies differ
    by O(h^2); measured 1.7e-3, 4.5e-4, 1.2e-4 for h = 0.5, 0.25, 0.125: order 1.9), stresses
    (element values, largest difference at the bore) decreasing."""
    rows = []
    for k in (2.0, 1.0, 0.5):
        scene = build_scene(
            load_case(THICK, ELASTIC + [f"mesh.h={0.25 * k}", f"mesh.h_outer={0.8 * k}"])
        )
        snap = engine_result(scene)[0]["snapshots"][-1]
        d = bulk_differences(snap, BulkProblem(scene, quadrature_degree=2).solve_elastic())
        rows.append((d["u"], d["stress"]))
    u, s = np.array(rows).T
    assert u.min() > 1e4 * ROUND_OFF
    order = np.polyfit(np.log([2.0, 1.0, 0.5]), np.log(u), 1)[0]
    assert order >= 1.7, (order, rows)
    assert s[2] < s[1] < s[0], rows


@needs_gmsh
def test_hertz_sphere_contact_replay_to_round_off():
    """cases/hertz_sphere.toml: every snapshot's contact state (closed nodes held at the flat)
    replayed in dolfinx: displacements, stresses and the reactions at the closed nodes
    (slipstep's lambda_n, ring totals) to round-off.  The slipstep state is the sum of ~20
    increments on a mesh from 0.012 to 3 mm (condition number ~1e6): 1e-9 allows for that;
    measured u 2.4e-11, stress 1.5e-11, lambda_n 7.6e-11."""
    scene = build_scene(load_case(CASES / "hertz_sphere.toml"))
    result, _ = engine_result(scene, events=True)
    rows, _ = replay_elastic(scene, result)
    assert len(rows) >= 15 and rows[-1]["n_closed"] >= 20
    for r in rows:
        assert r["u"] < 1e-9 and r["stress"] < 1e-9 and r.get("lambda_n", 0.0) < 1e-9, r


# --------------------------------------------------------------------------- plasticity
@needs_gmsh
def test_hertz_sphere_elastoplastic_replay_within_path_tolerance():
    """The Hertz sphere past first yield (Sy = 130 MPa, P = 45 N, h_contact = 0.03 mm): its
    contact states replayed in order, one dolfinx step per event interval.  The replay steps
    by backward Euler while the engine takes drift-controlled tangent increments, so the two
    paths differ by the first-order integration error of either, the tolerances of the plane
    replay test (tests/fenicsx/test_fenicsx_replay.py); measured: u 6.2e-5, stress 3.6e-4, lambda_n
    1.1e-4, plastic strain 1.3e-3.  Before first yield the replay is exact (1.7e-12).  The
    first states, two nodes in contact under 3e-5 of the load, need Newton's round-off stop
    (bulk.ROUND_OFF_STEP): their relative residual floors at ~1e-10."""
    from slipstep.fenicsx.crosscheck import contact_replay

    scene = build_scene(
        load_case(
            CASES / "hertz_sphere.toml",
            ["material.Sy=130", "load.P=45", "mesh.h_contact=0.03", "solver.group_tol=0"],
        )
    )  # the replay steps through its events
    rows = contact_replay(scene)["rows"]
    elastic = [r for r in rows if "plastic_strain" not in r]
    plastic = [r for r in rows if "plastic_strain" in r]
    assert len(elastic) >= 5 and len(plastic) >= 50
    assert max(r["u"] for r in elastic) < 1e-9
    assert max(r["u"] for r in plastic) < 1e-4
    assert max(r["stress"] for r in plastic) < 2e-3
    assert max(r.get("lambda_n", 0) for r in plastic) < 2e-3
    assert max(r["plastic_strain"] for r in plastic) < 1e-2
    assert rows[-1]["load_fraction"] == 1.0


@pytest.fixture(scope="module")
def thick_plastic():
    """cases/thick_sphere.toml (p = 280 MPa, between p_e and the limit) on the coarse mesh
    (648 elements): dolfinx with N = 10, 20, 40 load steps, against slipstep event by event
    with every plastic tangent renewed at every increment (group_tol = 0, tangent_turn = 0:
    the path the load-stepped one converges to; held tangents, the default 0.05 rad, leave
    slipstep's own path ~5e-4 of the largest stress off it on this mesh)."""
    scene = build_scene(load_case(THICK, [*COARSE, "solver.group_tol=0", "solver.tangent_turn=0"]))
    return scene, plastic_bulk(scene, steps=(10, 20, 40))


@needs_gmsh
def test_thick_sphere_difference_vanishes_with_the_load_step(thick_plastic):
    """The difference to slipstep's event path halves with each halving of the step (the
    backward-Euler return is first order in the step for a non-proportional local path; the
    event path is exact): the fitted order is within 0.8..1.2, and the Richardson limit
    2 d(40) - d(20) is below a fifth of d(20), i.e. the two codes converge to one solution.
    Measured, N = 10, 20, 40: u 8.1e-4, 4.0e-4, 1.9e-4; stress 2.8e-3, 1.5e-3, 8.5e-4;
    plastic strain 6.9e-3, 3.4e-3, 1.9e-3; 394 plastic elements in both."""
    _, out = thick_plastic
    for key in ("u", "stress", "plastic_strain"):
        d = np.array([r[key] for r in out["rows"]])
        order = -np.polyfit(np.log([10, 20, 40]), np.log(d), 1)[0]
        assert 0.8 <= order <= 1.2, (key, d)
        assert abs(2 * d[2] - d[1]) <= 0.2 * d[1], (key, d)
    last = out["rows"][-1]
    assert abs(last["n_plastic_slipstep"] - last["n_plastic_dolfinx"]) <= 1


@needs_gmsh
def test_thick_sphere_both_codes_against_hill(thick_plastic):
    """Both codes' plastic zone against Hill's elastic-plastic radius c (p = 2Y ln(c/a) +
    (2Y/3)(1 - c^3/b^3)), measured by the plastic elements' ring volume 2 pi/3 (c^3 - a^3):
    within a quarter of the local element size (as tests/physics/test_thick_sphere.py on the case
    mesh; here ~1 mm at c)."""
    scene, out = thick_plastic
    data = scene.case.data
    mesh, mat = data["body"][0]["mesh"], data["body"][0]["material"]
    a, b, Y = mesh["a"], mesh["b"], mat["Sy"]
    p = next(bc["pressure"] for bc in data["bc"] if bc["edge"] == "inner")
    c = references.thick_sphere_radius(p, a, b, Y)
    h_at_c = mesh["h"] + (mesh["h_outer"] - mesh["h"]) * (c - a) / (b - a)
    pts = scene.nodes[scene.triangles]
    d1, d2 = pts[:, 1] - pts[:, 0], pts[:, 2] - pts[:, 0]
    volume = math.pi * pts[:, :, 0].mean(axis=1) * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    for plastic_strain in (out["snapshot"]["plastic_strain"], out["dolfinx"].plastic_strain):
        yielded = np.asarray(plastic_strain) > 0
        c_fe = (a**3 + 1.5 * volume[yielded].sum() / math.pi) ** (1 / 3)
        assert abs(c_fe - c) <= h_at_c / 4, (c_fe, c)


@needs_gmsh
def test_crosscheck_command_on_an_axisymmetric_case(tmp_path):
    """`slipstep crosscheck cases/hertz_sphere.toml`: the replay report, its contact pressures
    over the ring areas (scene.pair_area): the centre node's reads p0 = 239.5 MPa within the
    case's measured profile error (0.9 % rms within 0.9 a, part A)."""
    from slipstep.cli import main

    out = tmp_path / "cc"
    assert main(["crosscheck", str(CASES / "hertz_sphere.toml"), "--out", str(out)]) == 0
    report = json.loads((out / "crosscheck.json").read_text())
    assert report["plane"] == "axisymmetric" and report["mode"] == "contact replay"
    assert report["max"]["lambda_n"] < 1e-9 and report["max"]["u"] < 1e-9
    assert (out / "crosscheck.png").stat().st_size > 10_000
    scene = build_scene(load_case(CASES / "hertz_sphere.toml"))
    snap = engine_result(scene)[0]["snapshots"][-1]
    centre = int(np.argmin(scene.pair_xy[:, 0]))
    p0 = references.hertz_sphere(30.0, 50.0, 70000.0, 0.3)[1]
    assert snap["lambda_n"][centre] / scene.pair_area[centre] == pytest.approx(p0, rel=0.02)
