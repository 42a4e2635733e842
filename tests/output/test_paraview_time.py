"""examples/paraview_time.py under pvpython on every shipped case with stages: ParaView's
Xdmf3 reader finds data at every time step of results.xdmf (a repeated time used to read as an
empty frame), the steps are the distinct path times of the run, and what ParaView reads at
each equals the API's arrays at that t.

The cases run with a snapshot at every event (where several events share one t) on meshes
four times coarser than shipped (:func:`coarse`), so the file keeps its layout at a fraction
of the cost.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess

import numpy as np
import pytest

from conftest import ROOT

import slipstep
from slipstep import load_case, shipped

PVPYTHON = shutil.which("pvpython")
#: The shipped cases of several stages, planar, axisymmetric and 3D; mindlin_sphere_45_3d
#: writes what mindlin_sphere_3d writes (the same bodies and stages, 24k DOFs and 363 event
#: steps even coarsened: 90 s), so the 3D series is read once.
STAGED = [
    name
    for name in shipped.names()
    if len(load_case(shipped.path(name)).data.get("stage") or []) > 1
    and name != "mindlin_sphere_45_3d"
]
#: Element-size keys of the generators, coarsened by :data:`COARSER` (capped at h_max).
SIZE_KEYS = ("h_contact", "h", "h_outer")
COARSER = 4.0


def coarse(name: str) -> list[str]:
    """Overrides: a snapshot at every event, no figures, every body's element sizes x 4."""
    out = ['output.snapshots="events"', "output.figures=false"]
    for body in load_case(shipped.path(name)).data["body"]:
        mesh = body["mesh"]
        for key in SIZE_KEYS:
            if mesh.get(key):
                h = min(COARSER * mesh[key], mesh.get("h_max") or np.inf)
                out.append(f"body.{body['name']}.mesh.{key}={h!r}")
    return out


def paraview_reads(xdmf, cwd=None) -> dict:
    """The example's JSON line for ``xdmf`` (None: no argument, as in a notebook's kernel, so
    the example's own RESULT path, relative to ``cwd``)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # ParaView's own Python
    args = [] if xdmf is None else [str(xdmf)]
    proc = subprocess.run(
        [
            PVPYTHON,
            "--force-offscreen-rendering",
            str(ROOT / "examples" / "paraview_time.py"),
            *args,
        ],
        capture_output=True,
        text=True,
        timeout=600,
        env=env,
        cwd=cwd,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_the_shipped_cases_with_stages_are_found():
    # the three shipped load paths at the time of writing; a new one joins the test below
    assert {"autofrettage", "cattaneo_mindlin", "hertz_load_unload"} <= set(STAGED)


@pytest.mark.skipif(
    PVPYTHON is None,
    reason="pvpython is not installed (Debian: apt-get " "install python3-paraview)",
)
@pytest.mark.parametrize("name", STAGED)
def test_paraview_reads_every_time_step(name, tmp_path):
    """One XDMF step per distinct t, none empty in ParaView, and ParaView's largest |u|, von
    Mises stress and contact pressure at each equal the API's at that t (the state after the
    last event there; the same float64 data through another reader: equal to round-off,
    1e-12)."""
    r = slipstep.run(name, out=tmp_path, overrides=coarse(name), progress=False)
    seen = paraview_reads(tmp_path / "results.xdmf")
    # one step per time resolvable in single precision (ParaView drops a step closer than ~1e-8
    # relative to its neighbour): the last time of each run of times less than 1e-6 apart
    t = np.unique(r.times)
    distinct = t[np.append(np.diff(t) > 1e-6 * max(1.0, t.max()), True)]
    assert seen["empty"] == []
    assert seen["times"] == distinct.tolist()
    assert [step["t"] for step in seen["steps"]] == distinct.tolist()
    for step in seen["steps"]:
        f = r.fields(step["t"])
        assert step["max_u"] == pytest.approx(np.linalg.norm(f["u"], axis=1).max(), rel=1e-12)
        assert step["max_von_mises"] == pytest.approx(f["von_mises"].max(), rel=1e-12)
        if len(f["pressure"]):  # the contact fields are point data of the time series
            assert step["max_contact_pressure"] == pytest.approx(
                np.abs(f["pressure"]).max(), rel=1e-12
            )


def test_a_load_unload_has_several_events_at_one_time():
    """The case that showed the empty frames: with a snapshot at every event, some path times
    hold several snapshots (the stage end t = 1 with the unloading switches after it), so the
    check above covers the repeated times."""
    r = slipstep.run("hertz_load_unload", overrides=coarse("hertz_load_unload"), progress=False)
    assert len(np.unique(r.times)) < len(r.times)
    assert list(r.times).count(1.0) >= 2


@pytest.mark.skipif(
    PVPYTHON is None,
    reason="pvpython is not installed (Debian: apt-get " "install python3-paraview)",
)
def test_without_a_command_line_it_opens_its_own_result_path(tmp_path):
    """As a notebook cell runs it (no .xdmf argument): the example opens the path it names,
    results/hertz_load_unload/results.xdmf, and reads a step at every snapshot time."""
    out = tmp_path / "results" / "hertz_load_unload"
    r = slipstep.run(
        "hertz_load_unload",
        out=out,
        progress=False,
        overrides=[
            "mesh.h_contact=0.4",
            "output.snapshots=[0.5, 1.0, 2.0]",
            "output.figures=false",
        ],
    )
    seen = paraview_reads(None, cwd=tmp_path)
    assert seen["times"] == list(r.times) and not seen["empty"]
