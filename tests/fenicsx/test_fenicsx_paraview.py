"""The XDMF written by either side opens in ParaView's Xdmf3 reader (pvpython from Debian's
python3-paraview, installed by `make test`, skipped with the reason without it; Debian's
python3-vtk9 9.1 is built without the Xdmf readers, so ParaView is the one that can check)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT, needs_gmsh
from slipstep import build_scene, parse_case, run_case

PVPYTHON = shutil.which("pvpython")
needs_pvpython = pytest.mark.skipif(
    PVPYTHON is None,
    reason="pvpython is not installed " "(Debian: apt-get install python3-paraview)",
)

CASE = """
[case]
name = "pv"
[output]
snapshots = [0.5, 1.0]
figures = false
[[body]]
name = "a"
[body.mesh]
generator = "block"
width = 4.0
height = 2.0
h = 0.5
[body.material]
E = 1000.0
nu = 0.3
Sy = 2.0
H = 100.0
[[body]]
name = "b"
[body.mesh]
generator = "block"
x0 = 5.0
width = 2.0
height = 2.0
h = 0.5
[body.material]
E = 2000.0
nu = 0.25
[[bc]]
body = "a"
edge = "left"
fix = ["x", "y"]
[[bc]]
body = "a"
edge = "right"
traction = [1.5, 0.0]
[[bc]]
body = "b"
edge = "bottom"
fix = ["x", "y"]
[[bc]]
body = "b"
edge = "top"
pressure = 1.0
"""


def _pvread(*paths):
    script = ROOT / "py" / "slipstep" / "fenicsx" / "pvread.py"
    out = subprocess.run(
        [PVPYTHON, "--force-offscreen-rendering", str(script), *map(str, paths)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@needs_gmsh
@needs_pvpython
def test_paraview_opens_every_xdmf_of_both_sides(tmp_path):
    pytest.importorskip("dolfinx")
    from slipstep.fenicsx.bulk import BulkProblem
    from slipstep.fenicsx.exchange import write_dolfinx_xdmf, write_scene_xdmf

    case = tmp_path / "pv.toml"
    case.write_text(CASE)
    scene = build_scene(parse_case(CASE))
    N, M = len(scene.nodes), len(scene.triangles)
    xdmf, edges, _ = write_scene_xdmf(scene, tmp_path / "mesh.xdmf")
    bulk = BulkProblem(scene, workdir=tmp_path / "work")
    res = bulk.solve_plastic(n_steps=4)
    dolfinx_results = bulk.write_xdmf(tmp_path / "dolfinx.xdmf", [res])
    dolfinx_mesh = write_dolfinx_xdmf(bulk.dm, tmp_path / "dolfinx_mesh.xdmf")
    run_case(case, out=tmp_path / "run")  # slipstep's own results.xdmf
    seen = _pvread(xdmf, edges, dolfinx_results, dolfinx_mesh, tmp_path / "run" / "results.xdmf")

    m = seen[str(xdmf)]
    assert (m["points"], m["cells"], m["cell_data"]) == ([N], [M], ["body"])
    e = seen[str(edges)]
    n_segments = sum(len(s) for mesh in scene.meshes.values() for s in mesh.edges.values())
    assert e["cells"] == [n_segments] and e["cell_data"] == ["edge"]
    d = seen[str(dolfinx_results)]
    assert set(d["points"]) == {N} and set(d["cells"]) == {M} and d["times"] == [1.0]
    assert d["point_data"] == ["u"]
    assert {"sigma_x", "sigma_y", "sigma_z", "tau_xy", "plastic_strain"} <= set(d["cell_data"])
    dm = seen[str(dolfinx_mesh)]
    assert M in dm["cells"] and N in dm["points"]
    r = seen[str(tmp_path / "run" / "results.xdmf")]
    assert r["points"] == [N] and r["cells"] == [M] and r["times"] == [0.5, 1.0]
    assert {"u", "nodal_stress", "nodal_von_mises"} <= set(r["point_data"])  # no contact here
    assert {"sigma_x", "stress", "von_mises"} <= set(r["cell_data"])


def test_pvread_is_not_imported_by_slipstep():
    assert "slipstep.fenicsx.pvread" not in sys.modules
