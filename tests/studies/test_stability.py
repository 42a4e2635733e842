"""`slipstep study stability --quick`: the report exists and shows the physics, checked on the
runs' own arrays (equilibrium recomputed from the stresses, loads and contact forces,
tests/physics.py; Coulomb's inequality; the closure events; Hill's plastic radius), not on the
study's residual column or flags.

Tolerances: equilibrium EQUILIBRIUM_TOL (the engine's contract); Coulomb 1e-9 relative to the
pair's λ_n (round-off of the slip condition |λ_t| = μ λ_n); Hill's radius and limit 2 % (the
radius is read at the outermost plastic centroid, half an element of 0.5 mm off at most:
0.25/14.4 = 1.7 %; the limit stop is detected on the stiffness, past the limit by the last
increment)."""

from __future__ import annotations

import csv
import math
import re

import numpy as np
import pytest

pytest.importorskip("slipstep._engine")

from physics import EQUILIBRIUM_TOL, worst_equilibrium  # noqa: E402
from slipstep.measures.references import thick_cylinder_radius  # noqa: E402

from slipstep import stability  # noqa: E402
from slipstep.cli import main  # noqa: E402

A, B, SY = 10.0, 20.0, 250.0
P_LIM = 2 * SY / math.sqrt(3.0) * math.log(B / A)  # Hill's limit pressure 2k ln(b/a)


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """The study through the command line; its rows (with each run's scene and result) taken
    from the report ``stability.run`` returns to it."""
    out = tmp_path_factory.mktemp("stability")
    reports = []
    original = stability.run
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(
            stability, "run", lambda *a, **k: reports.append(original(*a, **k)) or reports[-1]
        )
        assert main(["study", "stability", "--quick", "--out", str(out)]) == 0
    rows = {r["scenario"]: r for r in reports[0]["rows"]}
    return out, rows


def test_every_documented_stop_has_a_row_status():
    """Each ``stop.kind`` docs/engine_api.md lists (the engine's contract) maps to a status,
    so that no run the study makes ends in a KeyError."""
    from conftest import ROOT

    doc = (ROOT / "docs" / "engine_api.md").read_text()
    row = next(line for line in doc.splitlines() if line.startswith("| `stop` |"))
    listed = row.split("`kind` in", 1)[1].split("; `message`", 1)[0].strip()
    kinds = re.findall(r"(?:^|, )`(\w+)`", listed)
    assert {"completed", "limit_load", "support_lost", "interrupted"} <= set(kinds), kinds
    assert set(kinds) <= set(stability.STATUS_OF_STOP), set(kinds) - set(stability.STATUS_OF_STOP)


def run_of(row):
    scene, result = row["_run"]
    assert result is not None, row["error"]
    return scene, result


def test_report_chart_table(study):
    out, rows = study
    text = (out / "report.md").read_text()
    assert "| scenario |" in text and "stability.png" in text
    assert (out / "stability.png").stat().st_size > 10_000
    with open(out / "stability.csv") as fh:
        assert {r["scenario"] for r in csv.DictReader(fh)} == set(rows)
    assert len(rows) >= 14


def test_every_run_completes_or_stops_at_the_limit_load(study):
    """Every scene loaded below collapse completes: the elastic ones (friction, ties,
    receding contact, grading) and the plastic ones below their limit (the thick cylinder at
    175 < 200.1 MPa, the Hertz cylinder).  Only the thick cylinders loaded to 1.1 x Hill's
    limit may stop at a limit load, and with nu = 0.3 they must, at Hill's limit within 2 %;
    at nu = 0.499 a locking CST mesh carries the load on (the study's point)."""
    _, rows = study
    for name, r in rows.items():
        if r["group"] != "incompressible":
            assert r["status"] == "completed", (name, r["error"])
            continue
        assert r["status"] in ("completed", "limit load"), (name, r["error"])
        if r["nu"] == 0.3:
            _, result = run_of(r)
            carried = result["stop"]["load_fraction"] * 1.1 * P_LIM
            assert r["status"] == "limit load" and carried == pytest.approx(P_LIM, rel=0.02)


def test_every_run_is_in_equilibrium(study):
    """Recomputed on every snapshot of every run, the limit-load stops included."""
    _, rows = study
    for name, r in rows.items():
        scene, result = run_of(r)
        worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
        assert worst <= EQUILIBRIUM_TOL, (name, k, f, worst)


def test_perfect_plasticity(study):
    """H' = 0 runs far into the plastic range: the thick cylinder's plastic radius (the
    outermost plastic centroid) against Hill's c = 14.4 mm at p = 175, within 2 %; the Hertz
    cylinder yields under the surface and completes."""
    _, rows = study
    scene, result = run_of(rows["H'=0 thick cylinder p=175"])
    last = result["snapshots"][-1]
    assert len(result["events"]["kind"]) > 100
    centroid = scene.nodes[scene.triangles].mean(axis=1)
    plastic = np.asarray(last["plastic_strain"]) > 0
    c = float(np.linalg.norm(centroid[plastic], axis=1).max())
    assert c / thick_cylinder_radius(175.0, A, B, SY / math.sqrt(3.0)) == pytest.approx(
        1.0, abs=0.02
    )
    scene, result = run_of(rows["H'=0 Hertz Sy=200 h_c=0.15"])
    assert len(result["events"]["kind"]) > 100
    assert (np.asarray(result["snapshots"][-1]["plastic_strain"]) > 0).any()


def test_high_friction_full_stick_and_coulomb(study):
    """Coulomb on every snapshot (|λ_t| <= μ λ_n); with μ = 0.5 some pairs slip, beyond the
    critical μ (1 and 2) every closed pair sticks."""
    _, rows = study
    for mu in (0.5, 1.0, 2.0):
        scene, result = run_of(rows[f"Hertz elastic mu={mu}"])
        for snap in result["snapshots"]:
            ln, lt = np.asarray(snap["lambda_n"]), np.asarray(snap["lambda_t"])
            assert np.all(np.abs(lt) <= mu * ln * (1 + 1e-9)), mu
        status = np.asarray(result["snapshots"][-1]["status"])
        if mu == 0.5:
            assert (status == 2).any()
        else:
            assert (status == 1).any() and not (status == 2).any(), mu


def test_equal_gaps_close_in_one_increment(study):
    """The flat block pulled onto the rigid flat with equal gaps (half the uniaxial-strain
    displacement at full load): every pair closes in one increment, at exactly f = 0.5
    (1e-12: round-off of the scale factor)."""
    _, rows = study
    scene, result = run_of(rows["flat block on rigid flat, equal gaps"])
    ev = result["events"]
    close = np.asarray(ev["kind"]) == "close"
    assert close.sum() == len(scene.model["pairs"]["node_a"])
    assert len(np.unique(np.asarray(ev["step"])[close])) == 1
    assert np.asarray(ev["load_fraction"])[close] == pytest.approx(0.5, rel=1e-12)


def test_extreme_grading(study):
    """The Hertz cylinder meshed from h = 0.001 to 10: edges 1e4 apart, run complete (its
    equilibrium: test_every_run_is_in_equilibrium)."""
    _, rows = study
    scene, result = run_of(rows["Hertz, h_contact=0.001, h_max=10"])
    tri = scene.nodes[scene.triangles]
    edge = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2)
    assert edge.max() / edge.min() >= 1e4
    assert result["stop"]["kind"] == "completed"


def test_locking_and_crossed_mesh(study):
    _, rows = study

    def p_full(name):  # p(all elements plastic) / Hill's limit - 1 (nan: never)
        v = rows[name]["p_full"]
        return float(v) / stability_limit() - 1 if v not in ("", "nan") else float("nan")

    # nu = 0.3: no locking, the whole cylinder is plastic at Hill's limit pressure (2 %)
    assert abs(p_full("nu=0.3 gmsh CST p=1.1 p_lim")) < 0.02
    # nu = 0.499: the CST mesh locks (not fully plastic even at 1.1 p_lim); the crossed
    # (union jack) mesh is fully plastic at the limit pressure
    assert not abs(p_full("nu=0.499 gmsh CST p=1.1 p_lim")) < 0.02
    assert abs(p_full("nu=0.499 union jack p=1.1 p_lim")) < 0.02


def stability_limit():
    import math

    return 2 * 250.0 / math.sqrt(3.0) * math.log(2.0)


def test_union_jack_mesh():
    m = stability.structured_annulus(10.0, 20.0, 4, 6, crossed=True)
    assert len(m.triangles) == 4 * 4 * 6 and len(m.nodes) == 5 * 7 + 4 * 6
    assert set(m.edges) == {"inner", "outer", "x_axis", "y_axis"}
