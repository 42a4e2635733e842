"""The MUMPS factorization (``[solver] factorization = "mumps"``) on two MPI ranks gives the
history of the default in-process factorization (faer) to round-off.

Both backends solve the same SPD systems with backward-stable Cholesky factorizations, in
different orders of elimination; two such solutions differ by about kappa(K) * eps relative.
For these coarse meshes kappa(K) ~ (body size / smallest element)^2 (P1 elements, one
material): hertz_cylinder at h = 0.15 on R = 125, (125 / 0.15)^2 ~ 7e5; the sphere R = 50 on
a block meshed at h = 0.09 near the contact, (50 / 0.09)^2 ~ 3e5; times eps = 2.2e-16: < 2e-10. An event's
load fraction is a ratio of such solutions. So: the same events (kind and entity, in order), load
fractions within 1e-9 and every snapshot's displacements within 1e-9 of the largest, a factor
5 above that bound. A wrong solve (a rank's rows lost, a stale factor after a tangent change, a
G from the wrong equations) moves them by far more, or changes the events.

The 2D scene is elastoplastic and frictional, so it also runs through refactorizations and the
low-rank terms' blocked solves; the 3D one is frictional (mu = 0.3, pressed then sheared: its
pairs close, stick, slip and turn their facets).
Skipped where ``mpirun`` or petsc4py (Debian's python3-petsc4py) is missing: the MUMPS
backend needs both.
"""

from __future__ import annotations

import csv
import importlib.util
import json
import os
import shutil
import subprocess
import sys

import meshio
import numpy as np
import pytest
from conftest import CASES, needs_gmsh

needs_mumps = pytest.mark.skipif(
    shutil.which("mpirun") is None or importlib.util.find_spec("petsc4py") is None,
    reason="mpirun or petsc4py (Debian: python3-petsc4py) is not installed: the MUMPS "
    "factorization runs through PETSc under mpirun",
)

#: See the module's docstring: kappa(K) eps < 2e-10 for both meshes.
ROUND_OFF = 1e-9

SCENES = {
    "hertz_plastic_friction": (
        CASES / "hertz_cylinder.toml",
        ["contact.mu=0.35", "material.Sy=200", "material.H=700", "mesh.h_contact=0.15"],
    ),
    "mindlin_sphere_3d": (
        CASES / "mindlin_sphere_3d.toml",
        ["body.sphere.mesh.h_contact=0.12", "body.block.mesh.h_contact=0.09"],
    ),
}


def run(case, overrides, out, ranks: int | None):
    """``slipstep run`` (under ``mpirun -n ranks`` with MUMPS, or alone with faer)."""
    args = [sys.executable, "-m", "slipstep", "run", str(case), "--out", str(out)]
    for item in [*overrides, "output.figures=false"]:
        args += ["--set", item]
    env = dict(
        os.environ,
        MPLBACKEND="Agg",
        OMPI_ALLOW_RUN_AS_ROOT="1",
        OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
        OMPI_MCA_rmaps_base_oversubscribe="1",
    )
    if ranks is not None:
        args = ["mpirun", "-n", str(ranks), *args, "--set", "solver.factorization=mumps"]
    proc = subprocess.run(args, capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return proc


def events(out):
    with open(out / "events.csv") as f:
        rows = list(csv.DictReader(f))
    return [(r["kind"], r["entity"]) for r in rows], np.array(
        [float(r["load_fraction"]) for r in rows]
    )


def summary(out) -> dict:
    return json.loads((out / "summary.json").read_text())


def displacements(out) -> np.ndarray:
    with meshio.xdmf.TimeSeriesReader(str(out / "results.xdmf")) as reader:
        reader.read_points_cells()
        return np.array([reader.read_data(k)[1]["u"] for k in range(reader.num_steps)])


@needs_gmsh
@needs_mumps
@pytest.mark.parametrize("name", SCENES)
def test_two_mumps_ranks_give_the_faer_history_to_round_off(name, tmp_path):
    case, overrides = SCENES[name]
    run(case, overrides, tmp_path / "faer", None)
    proc = run(case, overrides, tmp_path / "mumps", 2)
    # Rank 0 alone reports (and writes): one summary line.
    assert sum("->" in line for line in proc.stdout.splitlines()) == 1, proc.stdout

    kinds_faer, fractions_faer = events(tmp_path / "faer")
    kinds_mumps, fractions_mumps = events(tmp_path / "mumps")
    assert len(kinds_faer) > 10
    assert kinds_mumps == kinds_faer
    assert np.abs(fractions_mumps - fractions_faer).max() <= ROUND_OFF

    # The 2D scene's plastic tangent changes refactorize (and add low-rank terms in between)
    # in both runs. (The counts of solves may differ by a correction whose acceptance is
    # decided at round-off level: MUMPS on several ranks is not even bit-reproducible from run
    # to run, its contribution blocks being summed in the order the messages arrive.)
    if name == "hertz_plastic_friction":
        assert summary(tmp_path / "faer")["n_factorizations"] > 1
        assert summary(tmp_path / "mumps")["n_factorizations"] > 1

    u_faer, u_mumps = displacements(tmp_path / "faer"), displacements(tmp_path / "mumps")
    assert u_mumps.shape == u_faer.shape
    scale = np.abs(u_faer).max()
    assert scale > 0
    assert np.abs(u_mumps - u_faer).max() <= ROUND_OFF * scale


def test_an_unknown_factorization_is_one_clear_line(tmp_path):
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "slipstep",
            "run",
            str(CASES / "hertz_cylinder.toml"),
            "--out",
            str(tmp_path),
            "--set",
            "solver.factorization=cholmod",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "factorization" in lines[0] and "mumps" in lines[0], proc.stderr


def test_mumps_without_petsc4py_is_one_clear_line(tmp_path):
    """Where petsc4py cannot be imported (hidden here), a MUMPS run stops before the engine with
    one line naming the key, what to install and the alternative; nothing is written."""
    code = (
        "import sys; sys.modules['petsc4py'] = None; from slipstep.cli import main; "
        f"raise SystemExit(main(['run', {str(CASES / 'hertz_cylinder.toml')!r}, '--out', "
        f"{str(tmp_path / 'out')!r}, '--set', 'solver.factorization=mumps']))"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=120,
        env=dict(os.environ, MPLBACKEND="Agg"),
    )
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert all(w in lines[0] for w in ("factorization", "petsc4py", '"faer"')), lines[0]
    assert not (tmp_path / "out").exists()
