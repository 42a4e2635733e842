"""Bad input through the command line: one clear line on stderr naming the place and the fix,
exit code 2, no traceback and no panic (issue #2 acceptance list)."""

import os
import subprocess
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
HERTZ = ROOT / "cases" / "hertz_cylinder.toml"


def slipstep(*args, cwd=None):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, "-m", "slipstep", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=300)


def assert_clear_error(proc, *words):
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("slipstep: error:"), lines[0]
    assert "Traceback" not in proc.stderr and "panicked" not in proc.stderr
    for w in words:
        assert w in lines[0], (w, lines[0])


def without_section(text: str, header: str) -> str:
    """The case text with one [[header]] / [header] table removed."""
    out, skip = [], False
    for line in text.splitlines():
        s = line.split("#")[0].strip()
        if s.startswith("["):
            skip = s in (f"[[{header}]]", f"[{header}]")
        if not skip:
            out.append(line)
    return "\n".join(out) + "\n"


def test_missing_material_key(tmp_path):
    case = tmp_path / "c.toml"
    case.write_text(HERTZ.read_text().replace("E = 70000.0", ""))
    assert_clear_error(slipstep("run", case, "--out", tmp_path / "o"), "E")


def test_unknown_bc_tag(tmp_path):
    case = tmp_path / "c.toml"
    case.write_text(HERTZ.read_text().replace('edge = "symmetry"', 'edge = "symetry"'))
    assert_clear_error(slipstep("run", case, "--out", tmp_path / "o"), "symetry")


def test_negative_mu():
    assert_clear_error(slipstep("run", "--set", "contact.mu=-0.1", "--out", "/tmp/never"), "mu")


def test_nu_one_half():
    assert_clear_error(slipstep("run", "--set", "material.nu=0.5", "--out", "/tmp/never"), "nu")


def test_body_free_to_translate(tmp_path):
    # The cylinder without its flat: nothing holds it vertically.
    case = tmp_path / "c.toml"
    case.write_text(without_section(HERTZ.read_text(), "contact"))
    assert_clear_error(slipstep("run", case, "--out", tmp_path / "o"), "free to move", "translation in y")


def test_inverted_triangle_in_a_mesh_file(tmp_path):
    # A 2x1 block of four triangles read from XDMF; element 2 is listed clockwise.
    pts = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], float)
    tris = np.array([[0, 1, 4], [0, 4, 3], [1, 5, 2], [1, 5, 4]])  # [1,5,2] is clockwise
    lines = np.array([[0, 1], [1, 2], [5, 4], [4, 3]])
    meshio.write(tmp_path / "m.xdmf", meshio.Mesh(pts, [("triangle", tris)]))
    meshio.write(tmp_path / "e.xdmf", meshio.Mesh(pts, [("line", lines)],
                                                   cell_data={"tags": [np.array([1, 1, 2, 2])]}))
    case = tmp_path / "c.toml"
    case.write_text("""
[analysis]
plane = "strain"
[[body]]
name = "b"
[body.mesh]
file = "m.xdmf"
edge_file = "e.xdmf"
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
body = "b"
edge = "1"
fix = ["x", "y"]
[[bc]]
body = "b"
edge = "2"
pressure = 1.0
""")
    assert_clear_error(slipstep("run", case, "--out", tmp_path / "o"), "element 2")


def test_failed_run_leaves_earlier_results_alone(tmp_path):
    out = tmp_path / "o"
    out.mkdir()
    (out / "summary.json").write_text("{\"keep\": true}")
    slipstep("run", "--set", "material.nu=0.5", "--out", out)
    assert (out / "summary.json").read_text() == "{\"keep\": true}"
