"""The examples (examples/*.py, percent format) run as notebooks, the way Jupyter runs them:
jupytext reads each into a notebook and nbclient executes it in an IPython kernel, from a scratch
folder; what its cells show is checked against closed forms and against slipstep's own arrays
read another way.  examples/paraview_time.py runs in ParaView's pvpython instead (its test:
tests/output/test_paraview_time.py); examples/hybrid_hertz.py also runs as a script (its command line).

In a kernel stderr is no terminal and sys.argv is the kernel's: the progress display is a
widget (ipywidgets, the `notebook` extra) or a start and an end line, never tqdm's text frames,
and no example reads the command line there."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = ROOT / "examples"
A_HERTZ = math.sqrt(4 * 1000.0 * 125.0 / (math.pi * 70000.0 / (1 - 0.3**2)))
P0_HERTZ = 2 * 1000.0 / (math.pi * A_HERTZ)
WIDGET = "application/vnd.jupyter.widget-view+json"


def run_example(name: str, cwd, *args, python=sys.executable) -> str:
    """The example as a script (stdout)."""
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT / "py"))
    proc = subprocess.run(
        [python, str(EXAMPLES / name), *map(str, args)],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return proc.stdout


def run_notebook(nb, cwd) -> dict:
    """Execute a notebook in a fresh IPython kernel with ``cwd`` as its folder and this
    checkout's package on its path (matplotlib's backend left to the kernel: inline).  Returns
    its shown text (stdout streams and cell results), its stderr text and the MIME types of
    the displays; a cell that raises fails the test with its traceback."""
    nbclient = pytest.importorskip("nbclient")
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    env["PYTHONPATH"] = str(ROOT / "py")
    client = nbclient.NotebookClient(
        nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(cwd)}}
    )
    client.execute(env=env)
    shown = {"stdout": "", "stderr": "", "displays": []}
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            if out["output_type"] == "stream":
                shown[out["name"]] += out["text"]
            elif out["output_type"] == "execute_result":
                shown["stdout"] += out["data"].get("text/plain", "") + "\n"
            elif out["output_type"] == "display_data":
                shown["displays"].append(sorted(out["data"]))
    return shown


def run_example_notebook(name: str, cwd) -> str:
    """examples/<name> as a notebook (jupytext's percent format); its shown text.  Progress
    never leaves tqdm's text frames or ipywidgets' warning on stderr."""
    jupytext = pytest.importorskip("jupytext")
    shown = run_notebook(jupytext.read(EXAMPLES / name), cwd)
    assert "IProgress" not in shown["stderr"] and "\r" not in shown["stderr"], shown["stderr"]
    return shown["stdout"]


def number(pattern: str, text: str) -> float:
    found = re.search(pattern, text)
    assert found, (pattern, text)
    return float(found.group(1))


def test_every_example_is_percent_format_and_tested():
    """Each example opens as a notebook (jupytext's percent format: `# %%` cells) and has a
    test here."""
    tested = {
        "hertz_in_ten_lines.py",
        "own_gmsh_mesh.py",
        "load_unload.py",
        "dolfinx_crosscheck.py",
        "hybrid_hertz.py",
        "paraview_time.py",
    }
    assert {p.name for p in EXAMPLES.glob("*.py")} == tested
    for path in EXAMPLES.glob("*.py"):
        assert path.read_text().startswith("# %% [markdown]\n"), path


def _hertz_checks(out: str, h: float) -> None:
    """a within one node spacing h of Hertz and p0 within 1 % (tests/physics/test_hertz.py: the edge
    is located by the nodes, first order in h; p0 is held to the 1 % acceptance)."""
    assert abs(number(r"a  = ([\d.]+) mm", out) - A_HERTZ) <= h
    assert number(r"p0 = ([\d.]+) MPa", out) == pytest.approx(P0_HERTZ, rel=0.01)


def test_hertz_in_ten_lines(tmp_path):
    out = run_example_notebook("hertz_in_ten_lines.py", tmp_path)
    _hertz_checks(out, h=0.05)
    # the contact force carries the load on the quarter model, P/2 x t (printed to 1e-3)
    assert "t = 0.5: total normal force 250.000 N/mm" in out
    assert "t = 1.0: total normal force 500.000 N/mm" in out
    code = [
        line
        for line in (EXAMPLES / "hertz_in_ten_lines.py").read_text().splitlines()
        if line.strip() and not line.startswith("#")
    ]
    assert len(code) <= 10, code


def test_own_gmsh_mesh(tmp_path):
    out = run_example_notebook("own_gmsh_mesh.py", tmp_path)
    assert "edges ['arc', 'symmetry', 'top']" in out
    _hertz_checks(out, h=0.05)


def test_load_unload(tmp_path):
    out = run_example_notebook("load_unload.py", tmp_path)
    peak = re.search(
        r"t = 1.0: total normal force ([\d.-]+) N/mm, (\d+) elements on the yield "
        r"surface, (\d+) with plastic strain",
        out,
    )
    end = re.search(
        r"t = 2.0: total normal force ([\d.-]+) N/mm, (\d+) elements on the yield "
        r"surface, (\d+) with plastic strain",
        out,
    )
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
    out = run_example_notebook("dolfinx_crosscheck.py", tmp_path)
    rows = [float(x) for x in re.findall(r"N = \d+: relative difference u ([\d.e+-]+)", out)]
    # dolfinx's load steps converge to slipstep's exact path: 10 steps closer than 5
    assert len(rows) == 2 and rows[1] < rows[0]
    radius = re.search(
        r"plastic radius: slipstep ([\d.]+) mm, dolfinx ([\d.]+) mm, " r"Hill ([\d.]+) mm", out
    )
    # Hill's c within one element (h = 1 mm at the bore, the mesh of the example)
    assert abs(float(radius.group(1)) - float(radius.group(3))) <= 1.0
    assert (tmp_path / "results" / "thick_cylinder_crosscheck" / "crosscheck.md").exists()


HYBRID = re.compile(
    r"outermost closed node x = ([\d.]+) mm \(Hertz a = ([\d.]+)\), .*"
    r"integral of the pressure ([\d.]+) N/mm \(P/2 = 500\)"
)


def _hybrid_checks(out: str, h: float) -> None:
    """The contact force is P/2 on the quarter (equilibrium; printed to 6 digits) and the
    outermost closed node within 2 h of Hertz's a: one spacing for locating the edge by the
    nodes, one for the P1 discretisation (tests/physics/test_hertz.py: within h on the case meshes)."""
    found = HYBRID.search(out)
    assert found, out
    x, a, force = map(float, found.groups())
    assert force == 500.0 and a == pytest.approx(A_HERTZ, abs=1e-4)
    assert abs(x - A_HERTZ) <= 2 * h


def test_hybrid_hertz(tmp_path):
    """As a notebook: the kernel's command line is not read (argparse would refuse it), the
    parameters cell is used (h_contact = 0.05)."""
    pytest.importorskip("dolfinx")
    _hybrid_checks(run_example_notebook("hybrid_hertz.py", tmp_path), h=0.05)
    assert (tmp_path / "results" / "hybrid_hertz" / "hybrid_hertz.xdmf").exists()


def test_hybrid_hertz_as_a_script(tmp_path):
    """As a script its options come from the command line."""
    pytest.importorskip("dolfinx")
    out = run_example("hybrid_hertz.py", tmp_path, "--h-contact", "0.2", "--out", "hh")
    _hybrid_checks(out, h=0.2)
    assert (tmp_path / "hh" / "hybrid_hertz.xdmf").exists()


# --------------------------------------------------------------------------- progress in a kernel
PROGRESS_CELL = """
import sys
{setup}
from slipstep.progress import Reporter
reporter = Reporter(True, "demo", 2)
reporter.report(10, 5, 0.5)
reporter.finish({{"events": {{"step": [0] * 12}}, "steps": {{"load_fraction": [0.0] * 6}},
                  "stop": {{"kind": "completed", "t": 2.0}}}})
"""


def _progress_notebook(setup: str = ""):
    nbformat = pytest.importorskip("nbformat")
    return nbformat.v4.new_notebook(
        cells=[nbformat.v4.new_code_cell(PROGRESS_CELL.format(setup=setup))]
    )


def test_progress_in_a_kernel_is_a_widget(tmp_path):
    """progress=True in a Jupyter kernel with ipywidgets: a tqdm widget (a widget display), and
    nothing on stderr.  The engine's reports are driven here by hand (two of them), so the
    test does not depend on how long a run takes."""
    pytest.importorskip("ipywidgets")
    shown = run_notebook(_progress_notebook(), tmp_path)
    assert any(WIDGET in d for d in shown["displays"]), shown
    assert shown["stderr"] == ""


def test_progress_in_a_kernel_without_ipywidgets_is_two_lines(tmp_path):
    """Without ipywidgets (hidden from the kernel): no "IProgress not found" warning and no
    text frames, but a start line naming the fix and an end line."""
    shown = run_notebook(_progress_notebook('sys.modules["ipywidgets"] = None'), tmp_path)
    assert not any(WIDGET in d for d in shown["displays"])
    start, end = shown["stderr"].splitlines()
    assert start == (
        "demo: running, t = 0.5 of 2 after 10 events (a progress bar needs "
        "ipywidgets: pip install ipywidgets)"
    )
    assert re.fullmatch(r"demo: completed at t = 2 of 2: 12 events, 6 increments, [\d.]+ s", end)
