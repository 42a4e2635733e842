"""The notebook-style examples (examples/*.py, percent format) run as scripts from a scratch
folder, and what they print is checked against closed forms and against slipstep's own
arrays read another way.  examples/hybrid_hertz.py has its own test (test_fenicsx_hybrid)."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = ROOT / "examples"
A_HERTZ = math.sqrt(4 * 1000.0 * 125.0 / (math.pi * 70000.0 / (1 - 0.3 ** 2)))
P0_HERTZ = 2 * 1000.0 / (math.pi * A_HERTZ)


def run_example(name: str, cwd, *args, python=sys.executable) -> str:
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT / "py"))
    proc = subprocess.run([python, str(EXAMPLES / name), *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return proc.stdout


def number(pattern: str, text: str) -> float:
    found = re.search(pattern, text)
    assert found, (pattern, text)
    return float(found.group(1))


def test_every_example_is_percent_format_and_tested():
    """Each example opens as a notebook (jupytext's percent format: `# %%` cells) and has a
    test here (hybrid_hertz.py: tests/test_fenicsx_hybrid.py; paraview_time.py, which runs
    under pvpython: tests/test_paraview_time.py)."""
    tested = {"hertz_in_ten_lines.py", "own_gmsh_mesh.py", "load_unload.py",
              "dolfinx_crosscheck.py", "paraview_time.py"}
    for path in EXAMPLES.glob("*.py"):
        if path.name == "hybrid_hertz.py":
            continue
        assert path.name in tested, path
        assert path.read_text().startswith("# %% [markdown]\n"), path


def _hertz_checks(out: str, h: float) -> None:
    """a within one node spacing h of Hertz and p0 within 1 % (tests/test_hertz.py: the edge
    is located by the nodes, first order in h; p0 is held to the 1 % acceptance)."""
    assert abs(number(r"a  = ([\d.]+) mm", out) - A_HERTZ) <= h
    assert number(r"p0 = ([\d.]+) MPa", out) == pytest.approx(P0_HERTZ, rel=0.01)


def test_hertz_in_ten_lines(tmp_path):
    out = run_example("hertz_in_ten_lines.py", tmp_path)
    _hertz_checks(out, h=0.05)
    # the contact force carries the load on the quarter model, P/2 x t (printed to 1e-3)
    assert "t = 0.5: total normal force 250.000 N/mm" in out
    assert "t = 1.0: total normal force 500.000 N/mm" in out
    code = [line for line in (EXAMPLES / "hertz_in_ten_lines.py").read_text().splitlines()
            if line.strip() and not line.startswith("#")]
    assert len(code) <= 10, code


def test_own_gmsh_mesh(tmp_path):
    out = run_example("own_gmsh_mesh.py", tmp_path)
    assert "edges ['arc', 'symmetry', 'top']" in out
    _hertz_checks(out, h=0.05)


def test_load_unload(tmp_path):
    out = run_example("load_unload.py", tmp_path)
    peak = re.search(r"t = 1.0: total normal force ([\d.-]+) N/mm, (\d+) elements on the yield "
                     r"surface, (\d+) with plastic strain", out)
    end = re.search(r"t = 2.0: total normal force ([\d.-]+) N/mm, (\d+) elements on the yield "
                    r"surface, (\d+) with plastic strain", out)
    assert peak and end, out
    assert float(peak.group(1)) == pytest.approx(500.0, abs=1e-3)  # P/2 at the peak
    assert abs(float(end.group(1))) <= 1e-3  # no load, no contact force (printed to 1e-3)
    assert int(peak.group(2)) > 0 and int(end.group(2)) == 0  # all unloaded elastically
    assert int(end.group(3)) == int(peak.group(3)) > 0  # plastic strain stays
    assert re.search(r"stage 1: .*\d+ yield", out) and re.search(r"stage 2: .*\d+ unload", out)
    # a load path with contact: its extent against t (no prescribed displacements: no
    # force-displacement figure)
    assert (tmp_path / "results" / "hertz_load_unload" / "contact_extent.png").exists()


def test_dolfinx_crosscheck(tmp_path):
    pytest.importorskip("dolfinx")
    out = run_example("dolfinx_crosscheck.py", tmp_path)
    rows = [float(x) for x in re.findall(r"N = \d+: relative difference u ([\d.e+-]+)", out)]
    # dolfinx's load steps converge to slipstep's exact path: 10 steps closer than 5
    assert len(rows) == 2 and rows[1] < rows[0]
    radius = re.search(r"plastic radius: slipstep ([\d.]+) mm, dolfinx ([\d.]+) mm, "
                       r"Hill ([\d.]+) mm", out)
    # Hill's c within one element (h = 1 mm at the bore, the mesh of the example)
    assert abs(float(radius.group(1)) - float(radius.group(3))) <= 1.0
    assert (tmp_path / "results" / "thick_cylinder_crosscheck" / "crosscheck.md").exists()
