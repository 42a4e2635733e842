"""The command line's errors: bad input gives one clear line on stderr naming the place and the
fix, exit code 2, no traceback and no panic (issue #2 acceptance list); only SlipstepError is
caught that way, a bug shows its traceback; runs go through run_case (--set reaches the engine,
an early engine stop still writes its results)."""

import csv
import json
import os
import subprocess
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
HERTZ = ROOT / "cases" / "hertz_cylinder.toml"


def slipstep(*args, cwd=None):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run(
        [sys.executable, "-m", "slipstep", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=300,
    )


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
    assert_clear_error(
        slipstep("run", case, "--out", tmp_path / "o"), "free to move", "translation in y"
    )


def test_inverted_triangle_in_a_mesh_file(tmp_path):
    # A 2x1 block of four triangles read from XDMF; element 2 is listed clockwise.
    pts = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], float)
    tris = np.array([[0, 1, 4], [0, 4, 3], [1, 5, 2], [1, 5, 4]])  # [1,5,2] is clockwise
    lines = np.array([[0, 1], [1, 2], [5, 4], [4, 3]])
    meshio.write(tmp_path / "m.xdmf", meshio.Mesh(pts, [("triangle", tris)]))
    meshio.write(
        tmp_path / "e.xdmf",
        meshio.Mesh(pts, [("line", lines)], cell_data={"tags": [np.array([1, 1, 2, 2])]}),
    )
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


# --------------------------------------------------------------------------- what the CLI catches
def test_a_slipstep_error_is_one_line_and_exit_2(monkeypatch, capsys):
    from slipstep import cli
    from slipstep.errors import FreeBodyError

    def free(*args, **kwargs):
        raise FreeBodyError("body 'b' is free to move (translation in x):\nadd a support")

    monkeypatch.delenv("SLIPSTEP_TRACEBACK", raising=False)
    monkeypatch.setattr(cli, "run_case", free)
    assert cli.main(["run", "--quiet"]) == 2
    err = capsys.readouterr().err
    # the newline inside the message is written as an escape: still one line
    assert (
        err == "slipstep: error: body 'b' is free to move (translation in x):\\nadd a " "support\n"
    )


@pytest.mark.parametrize("error", [RuntimeError("a bug"), ValueError("a bug")])
def test_other_exceptions_are_not_swallowed(monkeypatch, error):
    """A bug of the front (any exception that is not a SlipstepError nor the engine's
    InternalError) reaches the caller with its traceback instead of an error line."""
    from slipstep import cli

    def broken(*args, **kwargs):
        raise error

    monkeypatch.setattr(cli, "run_case", broken)
    with pytest.raises(type(error)):
        cli.main(["run", "--quiet"])


def test_an_engine_bug_is_one_line(monkeypatch, capsys):
    """The engine's InternalError (a broken invariant or a panic in it, which names itself and
    asks for a report) is one line, as every stop of a run is."""
    from slipstep import cli
    from slipstep.errors import InternalError

    def broken(*args, **kwargs):
        raise InternalError("an invariant broke; please report it with the case")

    monkeypatch.setattr(cli, "run_case", broken)
    assert cli.main(["run", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err == "slipstep: error: an invariant broke; please report it with the case\n", err


def test_a_bug_in_a_subprocess_shows_its_traceback(tmp_path):
    # the same through the real entry point: an exception from inside run_case
    code = (
        "import sys, slipstep.cli as c\n"
        "def boom(*a, **k):\n    raise RuntimeError('a bug')\n"
        "c.run_case = boom\nsys.exit(c.main(['run', '--quiet']))\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=120,
        env=dict(os.environ, MPLBACKEND="Agg"),
    )
    assert proc.returncode == 1
    assert "Traceback" in proc.stderr and "RuntimeError: a bug" in proc.stderr
    assert "slipstep: error" not in proc.stderr


# --------------------------------------------------------------------------- runs through run_case
COARSE = [
    "--set",
    "mesh.h_contact=0.2",
    "--set",
    "output.xdmf=false",
    "--set",
    "output.figures=false",
    "--set",
    "output.snapshots=[1.0]",
]


def test_set_reaches_the_engine(tmp_path):
    """--set contact.mu=0.3 on the (frictionless) built-in case: the written profile shows
    Coulomb friction with exactly that mu, |tangential stress| = 0.3 x pressure at every
    slipping pair (to round-off, 1e-9 relative) and below it where pairs stick."""
    proc = slipstep("run", "--quiet", "--out", tmp_path, *COARSE, "--set", "contact.mu=0.3")
    assert proc.returncode == 0, proc.stderr
    with open(tmp_path / "contact_profile.csv") as fh:
        rows = list(csv.DictReader(fh))
    slip = [r for r in rows if r["status"] == "slip"]
    stick = [r for r in rows if r["status"] == "stick"]
    assert slip and stick
    for r in slip:
        p, t = float(r["pressure"]), float(r["tangential_stress"])
        assert abs(abs(t) - 0.3 * p) <= 1e-9 * p
    assert all(abs(float(r["tangential_stress"])) <= 0.3 * float(r["pressure"]) for r in stick)


def test_an_event_bound_stop_writes_results_and_exits_2(tmp_path):
    out = tmp_path / "o"
    proc = slipstep("run", "--quiet", "--out", out, *COARSE, "--set", "solver.max_events=3")
    assert_clear_error(proc, "max_events = 3", f"(partial results in {out})")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["stop"]["kind"] == "event_bound" and summary["final_load_fraction"] < 1.0
    assert summary["stop"]["message"] in proc.stderr


def test_ctrl_c_while_writing_keeps_the_old_results(tmp_path, monkeypatch, capsys):
    from slipstep import cli, runner

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    out = tmp_path / "o"
    monkeypatch.setattr(runner, "write_results", interrupted)
    assert cli.main(["run", "--quiet", "--out", str(out), *COARSE]) == 130
    assert capsys.readouterr().err == (
        f"slipstep: interrupted while writing results; nothing " f"was replaced in {out}\n"
    )


def test_ctrl_c_before_the_run_says_interrupted(monkeypatch, capsys):
    from slipstep import cli

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "load_case", interrupted)
    assert cli.main(["run", "--quiet"]) == 130
    assert capsys.readouterr().err == "slipstep: interrupted\n"
