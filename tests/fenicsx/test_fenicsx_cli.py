"""`slipstep crosscheck CASE.toml --out DIR`: report (markdown table + figure + JSON)."""

from __future__ import annotations

import json

import pytest

from conftest import CASES, needs_gmsh, write_case
from slipstep.cli import main

pytest.importorskip("dolfinx")


def _files(out):
    return {p.name for p in out.iterdir()}


@needs_gmsh
def test_crosscheck_elastoplastic_bulk_with_hill(tmp_path):
    out = tmp_path / "tc"
    code = main(
        [
            "crosscheck",
            str(CASES / "thick_cylinder.toml"),
            "--out",
            str(out),
            "--set",
            "mesh.h=1.0",
            "--set",
            "mesh.h_outer=2.0",
            "--steps",
            "5,20",
        ]
    )
    assert code == 0
    assert {
        "crosscheck.md",
        "crosscheck.json",
        "crosscheck.png",
        "mesh.xdmf",
        "mesh.h5",
        "mesh_edges.xdmf",
        "mesh_edges.h5",
        "dolfinx.xdmf",
        "dolfinx.h5",
    } <= _files(out)
    report = json.loads((out / "crosscheck.json").read_text())
    assert report["mode"] == "elastoplastic bulk (no contact)"
    assert [r["steps"] for r in report["rows"]] == [5, 20]
    assert report["rows"][1]["u"] < report["rows"][0]["u"] < 1e-2
    assert abs(report["hill"]["dolfinx"]["u_outer"]) < 0.05
    md = (out / "crosscheck.md").read_text()
    assert "| elastoplastic, dolfinx N = 20 |" in md and "Hill" in md


@needs_gmsh
def test_crosscheck_contact_replay(tmp_path, capsys):
    out = tmp_path / "hz"
    code = main(
        ["crosscheck", "--out", str(out), "--set", "contact.mu=0.2", "--set", "mesh.h_contact=0.3"]
    )
    assert code == 0
    assert "contact replay" in capsys.readouterr().out
    report = json.loads((out / "crosscheck.json").read_text())
    assert report["max"]["u"] < 1e-8 and report["max"]["stress"] < 1e-8
    assert report["max"]["lambda_n"] < 1e-8
    assert (out / "crosscheck.png").stat().st_size > 10_000


def test_crosscheck_elastic_bulk(tmp_path):
    case = write_case(
        tmp_path,
        """
[case]
name = "plate"
[[body]]
name = "p"
[body.mesh]
generator = "block"
width = 4.0
height = 2.0
h = 0.25
[body.material]
E = 1000.0
nu = 0.2
[[bc]]
body = "p"
edge = "left"
fix = ["x", "y"]
[[bc]]
body = "p"
edge = "right"
traction = [1.0, 0.5]
""",
    )
    out = tmp_path / "out"
    assert main(["crosscheck", str(case), "--out", str(out)]) == 0
    report = json.loads((out / "crosscheck.json").read_text())
    assert report["mode"] == "elastic bulk (no contact)"
    assert report["rows"][0]["u"] < 1e-8 and report["rows"][0]["stress"] < 1e-8


@needs_gmsh
def test_node_to_node_contact_is_an_error_naming_the_limit(tmp_path, capsys):
    code = main(
        [
            "crosscheck",
            str(CASES / "two_blocks.toml"),
            "--out",
            str(tmp_path / "tb"),
            "--set",
            "body.punch.mesh.h=1.0",
            "--set",
            "body.foundation.mesh.h=1.0",
        ]
    )
    assert code == 2
    assert "node-to-node" in capsys.readouterr().err
    assert not (tmp_path / "tb").exists()  # issue 38: the exchanged mesh was left behind


def test_a_refused_case_leaves_an_existing_folder_as_it_was(tmp_path, capsys):
    out = tmp_path / "tb"
    out.mkdir()
    (out / "mine.txt").write_text("kept")
    code = main(
        [
            "crosscheck",
            str(CASES / "two_blocks.toml"),
            "--out",
            str(out),
            "--set",
            "body.punch.mesh.h=1.0",
            "--set",
            "body.foundation.mesh.h=1.0",
        ]
    )
    assert code == 2 and sorted(p.name for p in out.iterdir()) == ["mine.txt"]


def test_the_form_compiler_s_log_lines_are_not_printed(capsys):
    """dolfinx compiles a form through distutils, which sets the root logger to INFO and logs
    each compiler call: on a first run (an empty JIT cache) the terminal filled with
    ``INFO:root`` lines.  Here those calls are made as distutils makes them, inside the seam
    every form compilation goes through."""
    import logging

    from slipstep.fenicsx.dolfinx_api import quiet_compiler

    root = logging.getLogger()
    level = root.level
    handler = logging.StreamHandler()  # what logging.basicConfig (ffcx's) adds
    root.addHandler(handler)
    try:
        with quiet_compiler():
            root.setLevel(logging.INFO)  # distutils' set_verbosity(1)
            logging.info("gcc -pthread -c _cffi_form.c")
            logging.warning("a warning still shows")
        assert root.level == level
        logging.info("after compiling: the root logger's own level again")
    finally:
        root.removeHandler(handler)
    err = capsys.readouterr().err
    assert "gcc" not in err and "a warning still shows" in err


def test_bad_steps_are_an_error(capsys):
    assert main(["crosscheck", "--steps", "five"]) == 2
    assert "--steps" in capsys.readouterr().err
