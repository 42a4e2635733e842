"""Stops inside an increment: Ctrl-C in a zero-length burst at t = 0, and an engine failure
(a panic: a bug), each ending the process with the results so far written and one line.

The scene is a square plate laid on a rigid flat at zero gap and pressed at a corner
(tests/engine/test_rate_problem_3d.py's, mu = 0.5): every candidate pair starts closed at zero
force, the statuses at t = 0 cycle one at a time, and the rate problem's LCP (~1400 unknowns,
~500 Lemke pivots) settles them; nothing happens at t > 0 until the run's last increment. The
SIGINT is a real signal raised by the engine's bindings at the 20th pivot of that LCP
(``SLIPSTEP_TEST_INTERRUPT=lcp_pivot:20``), the panic likewise (``SLIPSTEP_TEST_PANIC``), so
where the run stops does not depend on the machine's speed."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from engine.test_rate_problem_3d import PLATE

import slipstep
from slipstep.errors import InternalError


def _case(tmp_path: Path) -> Path:
    case = tmp_path / "plate.toml"
    case.write_text('[case]\nname = "plate"\n' + PLATE.format(mu=0.5))
    return case


def _run(tmp_path: Path, **env) -> tuple[subprocess.CompletedProcess, Path]:
    out = tmp_path / "o"
    proc = subprocess.run(
        [sys.executable, "-m", "slipstep", "run", str(_case(tmp_path)), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
        env=dict(os.environ, MPLBACKEND="Agg", **env),
    )
    return proc, out


def test_ctrl_c_inside_the_rate_problem_at_t0_stops_there_with_the_results(tmp_path):
    proc, out = _run(tmp_path, SLIPSTEP_TEST_INTERRUPT="lcp_pivot:20")
    assert proc.returncode == 130, proc.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] is True and summary["final_t"] == 0.0, summary["stop"]
    # the events of the burst before the LCP are kept (the first increment's, at least)
    assert summary["n_events"] > 0 and (out / "events.csv").exists()
    assert "interrupted at load fraction 0" in proc.stderr


def test_a_panic_is_one_line_and_keeps_the_results(tmp_path):
    proc, out = _run(tmp_path, SLIPSTEP_TEST_PANIC="lcp_pivot:20")
    assert proc.returncode == 2, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if "running" not in line]
    assert (
        len(lines) == 1 and "Traceback" not in proc.stderr and "panicked" not in proc.stderr
    ), proc.stderr
    # the case, the path time and the bug are named, and where the results are
    assert lines[0].startswith(
        "slipstep: error: plate: an engine bug stopped the run at t = 0"
    ), lines
    assert f"in {out}" in lines[0]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["stop"]["kind"] == "failed" and summary["n_events"] > 0


def test_from_python_a_failure_raises_with_the_partial_result(tmp_path, monkeypatch):
    monkeypatch.setenv("SLIPSTEP_TEST_PANIC", "lcp_pivot:20")
    with pytest.raises(InternalError, match="engine bug") as failed:
        slipstep.run(_case(tmp_path), progress=False)
    partial = failed.value.result
    assert partial.stop["kind"] == "failed" and len(partial.raw["events"]["kind"]) > 0
