"""Ctrl-C during a run: the engine stops at the next increment, the partial results are
written (summary says interrupted, at a load fraction < 1) and the exit code is 130.

The SIGINT is a real signal, raised inside the run at a known event
(``SLIPSTEP_TEST_INTERRUPT=event=N``, read by the engine's bindings), so where the run stops
does not depend on how fast the machine is."""

import csv
import json
import os
import subprocess
import sys

import pytest

# The frictional Hertz cylinder at its default mesh: 149 events (measured 2026-11-25), so 40 is
# well inside the run and 1 is its first increment.
OVERRIDES = ["--set", "contact.mu=0.35"]


def _run(tmp_path, trigger: str):
    out = tmp_path / "o"
    env = dict(os.environ, MPLBACKEND="Agg", SLIPSTEP_TEST_INTERRUPT=trigger)
    proc = subprocess.run(
        [sys.executable, "-m", "slipstep", "run", *OVERRIDES, "--out", str(out)],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    return proc, out


def _events(out) -> list[dict]:
    with open(out / "events.csv") as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


@pytest.mark.parametrize("at_event", [1, 40])
def test_ctrl_c_keeps_the_partial_results(tmp_path, at_event):
    """Stopped right after the increment that recorded event number ``at_event``: the run ends
    in equilibrium at that increment's t, which is the t of its last event."""
    proc, out = _run(tmp_path, f"event={at_event}")
    assert proc.returncode == 130, proc.stderr
    assert "interrupted at load fraction" in proc.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] is True
    events = _events(out)
    # stopped after the increment that reached at_event events (it may record several at once)
    last_step = max(int(e["step"]) for e in events)
    assert sum(int(e["step"]) < last_step for e in events) < at_event <= len(events)
    t_last = float(events[-1]["t"])
    assert 0 < summary["final_load_fraction"] < 1
    assert summary["final_load_fraction"] == pytest.approx(t_last, rel=1e-12)


def test_ctrl_c_as_the_run_completes_keeps_the_complete_results(tmp_path):
    """A SIGINT that arrives when the engine has nothing left to stop (raised after its last
    increment): the complete results are written, and the exit code still says interrupted."""
    proc, out = _run(tmp_path, "end")
    assert proc.returncode == 130, proc.stderr
    assert "complete results" in proc.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] is False and summary["final_load_fraction"] == 1.0
