"""Determinism (issue 7, part 3): the same case run twice gives bit-identical results.

Two scenes: the Hertz cylinder with friction (mu = 0.35) on a coarse mesh, and the same cylinder
elastoplastic (Sy = 200, H' = 700).  Each is meshed and solved twice in this process and once
in a fresh subprocess (and once more there with one rayon thread, in case a parallel reduction
depended on the number of threads); the mesh, the event list, the step records and every field
of every snapshot must agree bit for bit (float arrays compared as bytes, so even -0.0 against
0.0 or two NaN payloads would count as a difference).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import CASES, needs_gmsh

from slipstep.runner import prepare, solve

HERTZ = CASES / "hertz_cylinder.toml"
SCENES = {
    "hertz_friction": ["contact.mu=0.35", "mesh.h_contact=0.15"],
    "hertz_plastic": ["material.Sy=200", "material.H=700", "mesh.h_contact=0.15"],
}


def flatten(scene, result: dict) -> dict[str, np.ndarray]:
    """Every array of a run (the mesh and model included), keyed by a path."""
    out = {
        "model.nodes": scene.model["nodes"],
        "model.triangles": scene.model["triangles"],
        "model.load": scene.model["load"],
        "model.fixed_dofs": scene.model["fixed_dofs"],
    }
    for k, v in scene.model["pairs"].items():
        out[f"model.pairs.{k}"] = np.asarray(v)
    ev = result["events"]
    out["events.kind"] = np.asarray(ev["kind"], dtype="U16")
    for k in ("step", "load_fraction", "entity"):
        out[f"events.{k}"] = np.asarray(ev[k])
    for k, v in result["steps"].items():
        out[f"steps.{k}"] = np.asarray(v)
    for i, snap in enumerate(result["snapshots"]):
        for k, v in snap.items():
            out[f"snapshots.{i}.{k}"] = np.asarray(v)
    for k in ("closure_fraction", "predicted_closure"):
        out[k] = np.asarray(result[k])
    for k in ("max_equilibrium_residual", "max_drift", "n_factorizations", "n_solves"):
        out[k] = np.asarray(result[k])
    return out


def run(name: str) -> dict[str, np.ndarray]:
    scene = prepare(HERTZ, SCENES[name])
    return flatten(scene, solve(scene))


def assert_bit_identical(a: dict, b: dict, what: str) -> None:
    assert a.keys() == b.keys(), f"{what}: different outputs {set(a) ^ set(b)}"
    for k in a:
        x, y = a[k], b[k]
        assert x.dtype == y.dtype and x.shape == y.shape, (
            f"{what}: {k} {x.dtype}{x.shape} vs " f"{y.dtype}{y.shape}"
        )
        assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), f"{what}: {k} differs"
        assert x.tobytes() == y.tobytes(), f"{what}: {k} differs in its bits"


CHILD = """
import sys
import numpy as np
sys.path[:0] = [{here!r}, {tests!r}]  # this file, and conftest.py beside the folders
from test_determinism import run
np.savez({out!r}, **run({name!r}))
"""


def run_in_subprocess(name: str, out: Path, threads: str | None = None) -> dict:
    env = dict(os.environ)
    if threads is not None:
        env["RAYON_NUM_THREADS"] = threads
    here = Path(__file__).resolve().parent
    code = CHILD.format(here=str(here), tests=str(here.parent), out=str(out), name=name)
    proc = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr
    with np.load(out) as data:
        return {k: data[k] for k in data.files}


@needs_gmsh
@pytest.mark.parametrize("name", list(SCENES))
def test_runs_are_bit_identical(name, tmp_path):
    first = run(name)
    assert len(first["events.kind"]) > 0
    if name == "hertz_plastic":
        assert "yield" in set(first["events.kind"]), "the plastic scene should yield"
    else:
        assert {"stick_to_slip"} & set(first["events.kind"]), "the friction scene should slip"
    assert_bit_identical(first, run(name), f"{name}: second run in the same process")
    assert_bit_identical(
        first, run_in_subprocess(name, tmp_path / "fresh.npz"), f"{name}: run in a fresh process"
    )
    assert_bit_identical(
        first,
        run_in_subprocess(name, tmp_path / "one_thread.npz", "1"),
        f"{name}: run in a fresh process with RAYON_NUM_THREADS=1",
    )
