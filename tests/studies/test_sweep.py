"""The sweep runner (slipstep.sweep): studies, per-case atomic results, resume, the CSV table,
and MPI (mpi4py.futures) giving the same results as local processes."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, needs_gmsh
from slipstep import sweep
from slipstep.cli import main as cli_main

TINY = """
[study]
name = "tiny"
base = "default"
set = ["material.Sy=200", "material.H=700", "mesh.h_contact=0.2", "output.snapshots=[1.0]"]

[vary]
"contact.mu" = [0.0, 0.3, 0.5]

[output]
stop_at_first_yield = true
"""

# Fields that legitimately differ between two runs of the same case.
VOLATILE = {"wall_time_s", "engine_timings_s"}


def write(tmp_path: Path, text: str = TINY, name: str = "tiny.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


# --------------------------------------------------------------------------- study files
def test_cartesian_product_first_key_slowest(tmp_path):
    study = sweep.parse_study(
        {
            "study": {"base": "default"},
            "vary": {"contact.mu": [0.0, 0.1], "load.P": [500.0, 1000.0, 2000.0]},
        }
    )
    tasks = study.tasks()
    assert [t["params"] for t in tasks][:3] == [
        {"contact.mu": 0.0, "load.P": p} for p in (500.0, 1000.0, 2000.0)
    ]
    assert len(tasks) == 6 and len({t["case_id"] for t in tasks}) == 6
    assert tasks[4]["case_id"] == "004-contact.mu=0.1_load.P=1000.0"
    assert tasks[4]["overrides"] == ["contact.mu=0.1", "load.P=1000.0"]


def test_toml_literals():
    assert [sweep.toml_literal(v) for v in (0.1, 3, True, "stress", [0.5, 1.0])] == [
        "0.1",
        "3",
        "true",
        '"stress"',
        "[0.5, 1.0]",
    ]


@pytest.mark.parametrize(
    "text, message",
    [
        ("[study]\nbase = 'nope.toml'\n", "no such case file"),
        ("[study]\nbogus = 1\n", "study.bogus is not a study key"),
        ("[vary]\n'contact.mu' = 0.1\n", "vary.contact.mu must be a non-empty list"),
        ("[output]\nfields = 'yes'\n", "output.fields must be true or false"),
        ("[output]\nsnapshots = true\n", "output.snapshots is not an output option"),
        ("[vary]\n'contact.nu' = [0.1]\n", "contact.nu"),
        ("[whatever]\n", "unknown table [whatever]"),
    ],
)
def test_bad_study_is_one_line_error(tmp_path, text, message):
    with pytest.raises(sweep.StudyError, match=message.replace("[", r"\[").replace(".", r"\.")):
        sweep.load_study(write(tmp_path, text, "bad.toml"))


@pytest.mark.parametrize("path", sorted((ROOT / "studies").glob("*.toml")), ids=lambda p: p.name)
def test_shipped_studies_validate(path):
    study = sweep.load_study(path)  # checks the first and the last case against the schema
    assert study.tasks() and study.description


def test_fig10_study_file():
    study = sweep.load_study(ROOT / "studies" / "fig10_onset_of_yield.toml")
    mus = study.vary["contact.mu"]
    assert len(mus) >= 11 and mus[0] == 0.0 and mus[-1] == 0.5 and mus == sorted(mus)
    assert study.output["stop_at_first_yield"]
    assert "material.Sy=200" in study.set


# --------------------------------------------------------------------------- running
@needs_gmsh
def test_sweep_writes_each_case_and_resumes(tmp_path):
    study = sweep.load_study(write(tmp_path))
    out = tmp_path / "out"
    (out / ".partial-000-contact.mu=0.0").mkdir(parents=True)  # debris of a killed sweep
    rep = sweep.run_sweep(study, out, workers=2, log=None)
    assert rep.complete and sorted(rep.done) == [t["case_id"] for t in study.tasks()]
    assert not list(out.glob(".partial-*"))
    fy = []
    for t in study.tasks():
        s = sweep.load_summary(out, t["case_id"])
        a = sweep.load_arrays(out, t["case_id"])
        assert s["sweep"]["params"] == t["params"] and s["sweep"]["overrides"] == t["overrides"]
        assert s["final_load_fraction"] == s["first_yield_load_fraction"]  # stopped there
        assert list(a["events_kind"]).count("yield") >= 1 and a["events_kind"][-1] == "yield"
        assert a["profile_pressure"].shape == (1, len(a["profile_x"]))
        fy.append(s["first_yield_load_fraction"])
    assert fy[2] < fy[0], "friction lowers the onset of yield"
    table = (out / "summaries.csv").read_text().splitlines()
    assert len(table) == 4 and table[0].startswith("case_id,contact.mu,")

    # resume: nothing to do
    stamp = {
        t["case_id"]: (out / t["case_id"] / "summary.json").stat().st_mtime_ns
        for t in study.tasks()
    }
    rep = sweep.run_sweep(study, out, workers=2, log=None)
    assert rep.done == [] and len(rep.skipped) == 3
    # an interrupted sweep: only the missing case runs again
    shutil.rmtree(out / "001-contact.mu=0.3")
    rep = sweep.run_sweep(study, out, workers=2, log=None)
    assert rep.done == ["001-contact.mu=0.3"]
    for cid in ("000-contact.mu=0.0", "002-contact.mu=0.5"):
        assert (out / cid / "summary.json").stat().st_mtime_ns == stamp[cid]
    # a changed study (other overrides) is not mistaken for a finished one
    changed = sweep.load_study(write(tmp_path), extra_set=["mesh.h_contact=0.25"])
    rep = sweep.run_sweep(changed, out, workers=1, log=None)
    assert len(rep.done) == 3


@needs_gmsh
def test_a_failing_case_is_reported_and_the_others_finish(tmp_path, capsys):
    # the middle value is invalid; the first and last are checked when the study loads
    text = TINY.replace("[0.0, 0.3, 0.5]", "[0.0, -1.0, 0.5]")
    path = write(tmp_path, text)
    out = tmp_path / "out"
    code = cli_main(["sweep", str(path), "--out", str(out), "--workers", "2", "--quiet"])
    assert code == 1
    err = capsys.readouterr().err
    assert "case 001-contact.mu=-1.0" in err and "mu" in err
    assert (out / "000-contact.mu=0.0" / "summary.json").exists()
    assert (out / "002-contact.mu=0.5" / "summary.json").exists()
    assert not (out / "001-contact.mu=-1.0").exists()


def test_cli_rejects_a_bad_study(tmp_path, capsys):
    code = cli_main(["sweep", str(write(tmp_path, "[study]\nbogus = 1\n")), "--quiet"])
    assert code == 2
    assert "study.bogus" in capsys.readouterr().err


# --------------------------------------------------------------------------- MPI
def _comparable(summary: dict) -> dict:
    s = {k: v for k, v in summary.items() if k not in VOLATILE}
    s["sweep"] = {k: v for k, v in s["sweep"].items() if k != "host"}
    return s


@needs_gmsh
@pytest.mark.skipif(
    shutil.which("mpirun") is None,
    reason="mpirun is not installed (Debian's openmpi-bin comes with dolfinx)",
)
def test_mpi_sweep_matches_local(tmp_path):
    pytest.importorskip("mpi4py.futures")
    path = write(tmp_path)
    local, mpi = tmp_path / "local", tmp_path / "mpi"
    assert cli_main(["sweep", str(path), "--out", str(local), "--quiet"]) == 0
    env = dict(
        os.environ,
        OMPI_ALLOW_RUN_AS_ROOT="1",
        OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
        OMPI_MCA_rmaps_base_oversubscribe="1",
        MPLBACKEND="Agg",
        PYTHONPATH=os.pathsep.join([str(ROOT / "py"), os.environ.get("PYTHONPATH", "")]),
    )
    cmd = [
        "mpirun",
        "-n",
        "2",
        "--oversubscribe",
        sys.executable,
        "-m",
        "mpi4py.futures",
        "-m",
        "slipstep",
        "sweep",
        str(path),
        "--out",
        str(mpi),
        "--mpi",
    ]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "(MPI)" in proc.stdout
    study = sweep.load_study(path)
    for t in study.tasks():
        cid = t["case_id"]
        assert _comparable(sweep.load_summary(mpi, cid)) == _comparable(
            sweep.load_summary(local, cid)
        ), cid
        a, b = sweep.load_arrays(mpi, cid), sweep.load_arrays(local, cid)
        assert sorted(a) == sorted(b)
        for key in a:
            np.testing.assert_array_equal(a[key], b[key], err_msg=f"{cid}: {key}")
    assert (
        json.loads((mpi / "study.json").read_text())["tasks"]
        == json.loads((local / "study.json").read_text())["tasks"]
    )


@needs_gmsh
def test_ctrl_c_keeps_finished_cases_and_the_rerun_resumes(tmp_path):
    """Ctrl-C after the second of six cases: the sweep (the parent process) gets a real SIGINT
    once that case is written (SLIPSTEP_TEST_INTERRUPT=case=2, raised from inside the run, so
    the point of interruption does not depend on the machine's speed). Exactly the two written
    cases stay, no partial folder is left, the exit code is 130, and a rerun does the rest."""
    text = TINY.replace("[0.0, 0.3, 0.5]", "[0.0, 0.1, 0.2, 0.3, 0.4, 0.5]")
    path = write(tmp_path, text)
    out = tmp_path / "out"
    env = dict(os.environ, MPLBACKEND="Agg", SLIPSTEP_TEST_INTERRUPT="case=2")
    proc = subprocess.run(
        [sys.executable, "-m", "slipstep", "sweep", str(path), "--out", str(out), "--workers", "1"],
        capture_output=True,
        env=env,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 130, proc.stderr
    assert "run the same command again to resume" in proc.stderr
    done = sorted(p.name for p in out.iterdir() if p.is_dir())
    assert len(done) == 2 and not list(out.glob(".partial-*")), done
    rep = sweep.run_sweep(sweep.load_study(path), out, workers=2, log=None)
    assert sorted(rep.skipped) == done and len(rep.done) == 6 - len(done)
