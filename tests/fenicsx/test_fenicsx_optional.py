"""dolfinx is optional: the core package, ``slipstep.fenicsx`` itself, the XDMF writer and
h5py reader work without it; ``slipstep crosscheck`` then fails with the fix."""

from __future__ import annotations

import subprocess
import sys

from conftest import ROOT

BLOCK_DOLFINX = """
import sys
class Block:
    def find_spec(self, name, path=None, target=None):
        if name == "dolfinx" or name.startswith("dolfinx."):
            raise ImportError("dolfinx blocked for this test")
sys.meta_path.insert(0, Block())
sys.path.insert(0, {py!r})
"""

SCRIPT = (
    BLOCK_DOLFINX
    + """
import numpy as np
import slipstep
from slipstep import build_scene, parse_case
from slipstep.fenicsx import exchange, plasticity, radial, DolfinxMissing
assert "dolfinx" not in sys.modules
scene = build_scene(parse_case('''
[[body]]
name = "a"
[body.mesh]
generator = "block"
width = 2.0
height = 1.0
h = 0.5
[body.material]
E = 1.0
nu = 0.3
[[bc]]
body = "a"
edge = "left"
fix = ["x", "y"]
'''))
xdmf, edges, h5 = exchange.write_scene_xdmf(scene, {tmp!r} + "/m.xdmf")
back = exchange.read_xdmf_h5(xdmf)
assert np.array_equal(back.nodes, scene.nodes)
try:
    exchange.read_dolfinx(xdmf)
except DolfinxMissing as exc:
    assert "python3-dolfinx" in str(exc)
else:
    raise AssertionError("read_dolfinx worked without dolfinx")
from slipstep.cli import main
code = main(["crosscheck", "--out", {tmp!r} + "/cc"])
assert code == 2, code
print("OK")
"""
)


def test_core_and_writer_work_without_dolfinx(tmp_path):
    script = SCRIPT.format(py=str(ROOT / "py"), tmp=str(tmp_path))
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=300
    )
    assert out.returncode == 0, out.stderr[-3000:]
    assert out.stdout.strip().endswith("OK")
    assert "dolfinx is not available" in out.stderr
