"""`slipstep study stability --quick` (issue 7.4): the report exists and shows the physics."""

from __future__ import annotations

import csv

import pytest

pytest.importorskip("slipstep._engine")

from slipstep import stability  # noqa: E402
from slipstep.cli import main  # noqa: E402


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("stability")
    assert main(["study", "stability", "--quick", "--out", str(out)]) == 0
    rows = {r["scenario"]: r for r in csv.DictReader(open(out / "stability.csv"))}
    return out, rows


def test_report_chart_table(study):
    out, rows = study
    text = (out / "report.md").read_text()
    assert "| scenario |" in text and "stability.png" in text
    assert (out / "stability.png").stat().st_size > 10_000
    assert len(rows) >= 14
    # runs loaded beyond Hill's limit end at the limit load (engine stop), the others complete
    assert all(r["status"] in ("completed", "limit load") for r in rows.values()), \
        [(k, r["error"]) for k, r in rows.items() if r["status"] not in ("completed", "limit load")]


def test_perfect_plasticity_in_equilibrium(study):
    _, rows = study
    for name in ("H'=0 thick cylinder p=175", "H'=0 Hertz Sy=200 h_c=0.15"):
        r = rows[name]
        assert r["status"] == "completed" and float(r["final_load_fraction"]) == 1.0
        assert float(r["max_residual"]) <= 1e-9
        assert int(r["n_events"]) > 100
    # plastic radius vs Hill's c = 14.4 mm within 2 %
    assert abs(float(rows["H'=0 thick cylinder p=175"]["rel_error"])) < 0.02


def test_high_friction_full_stick_and_coulomb():
    rows = stability.scenario_friction(quick=True)
    by_mu = {r["scenario"]: r["_summary"] for r in rows}
    for mu in (0.5, 1.0, 2.0):
        s = by_mu[f"Hertz elastic mu={mu}"]
        assert s["max_equilibrium_residual"] <= 1e-9
        assert s["coulomb_excess"] <= 1e-12       # |lambda_t| <= mu lambda_n
    assert by_mu["Hertz elastic mu=0.5"]["n_slip"] > 0
    for mu in (1.0, 2.0):                          # beyond the critical mu: full stick
        s = by_mu[f"Hertz elastic mu={mu}"]
        assert s["n_slip"] == 0 and s["n_stick"] > 0


def test_equal_gaps_close_in_one_increment():
    rows = stability.scenario_ties(quick=True)
    s = rows[1]["_summary"]
    assert s["closed_in_one_increment"]
    assert abs(rows[1]["rel_error"]) < 1e-12      # at exactly f = 0.5
    assert s["max_equilibrium_residual"] <= 1e-9


def test_extreme_grading():
    s = stability.scenario_grading(quick=True)[0]["_summary"]
    assert s["size_ratio"] >= 1e4
    assert s["final_load_fraction"] == 1.0 and s["max_equilibrium_residual"] <= 1e-9


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
