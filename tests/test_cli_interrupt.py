"""Ctrl-C during a long run: the engine stops at the next event, the partial results are
written (summary says interrupted, at a load fraction < 1) and the exit code is 130."""

import json
import os
import signal
import subprocess
import sys
import time


def test_ctrl_c_keeps_the_partial_results(tmp_path):
    out = tmp_path / "o"
    env = dict(os.environ, MPLBACKEND="Agg")
    # A fine frictional mesh: several seconds of events, long enough to interrupt.
    proc = subprocess.Popen([sys.executable, "-m", "slipstep", "run", "--set", "mesh.h_contact=0.008",
                             "--set", "contact.mu=0.35", "--out", str(out)],
                            stderr=subprocess.PIPE, stdout=subprocess.PIPE, env=env)
    # Wait for the first progress line (the event loop is running), then press Ctrl-C.
    seen = b""
    deadline = time.time() + 120
    while b"events" not in seen and time.time() < deadline:
        seen += os.read(proc.stderr.fileno(), 256)
    assert b"events" in seen, seen
    proc.send_signal(signal.SIGINT)
    rest_out, rest_err = proc.communicate(timeout=120)
    assert proc.returncode == 130, rest_err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] is True
    assert 0 < summary["final_load_fraction"] < 1
    assert (out / "events.csv").exists()
