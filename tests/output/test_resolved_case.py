"""Every result folder records its inputs: ``case.toml`` (the case as it ran: every default
filled in, the ``--set`` overrides applied) and the versions in ``summary.json``, so that
``slipstep run <folder>/case.toml`` reruns the run.

The reruns compare two runs made from different inputs, the original case with its overrides
and the written file; they fail if the file loses or misspells a value the run used (an
override, a default, a study's option).  Each has a negative control: the same case without
the override (or the option) gives other events, so identical events are not a given.
"""

from __future__ import annotations

import copy
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from conftest import CASES, MINIMAL, ROOT, needs_gmsh

import slipstep
from slipstep.builders.section import mesh_body
from slipstep.case import CaseError, load_case, parse_case
from slipstep.mesh.triangle_generators import block
from slipstep.mesh.triangle_files import write_msh
from slipstep.output.resolved_case import resolved_case_text

pytestmark = needs_gmsh

COARSE = "mesh.h_contact=0.2"  # the Hertz cylinder coarse enough for a 1-2 s run


def cli(*args: str) -> None:
    """``slipstep ARGS`` in a fresh process, as a user runs it."""
    env = dict(os.environ, PYTHONPATH=str(ROOT / "py"), MPLBACKEND="Agg")
    proc = subprocess.run(
        [sys.executable, "-m", "slipstep", *args],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr


def exactly_equal(a, b) -> bool:
    """Equal values of equal types all the way down (a float 1.0 is not the int 1)."""
    if isinstance(a, dict):
        return (
            isinstance(b, dict)
            and a.keys() == b.keys()
            and all(exactly_equal(a[k], b[k]) for k in a)
        )
    if isinstance(a, (list, tuple)):
        return (
            type(a) is type(b)
            and len(a) == len(b)
            and all(exactly_equal(x, y) for x, y in zip(a, b))
        )
    return type(a) is type(b) and a == b


# --------------------------------------------------------------------------- the file itself
@pytest.mark.parametrize("path", sorted(CASES.glob("*.toml")), ids=lambda p: p.stem)
def test_every_shipped_case_reads_back_as_it_was_validated(path):
    """The same document, but for the files it names: by their absolute paths (the results
    folder is elsewhere), mesh files and a rigid surface's alike."""
    case = load_case(path)
    again = parse_case(resolved_case_text(case), "case.toml", base_dir=path.parent)
    want = copy.deepcopy(case.data)
    for table in [b["mesh"] for b in want["body"]] + want["contact"]:
        for key in ("file", "edge_file", "face_file"):
            if table.get(key):
                table[key] = str((path.parent / table[key]).resolve())
    assert exactly_equal(again.data, want)


@pytest.mark.parametrize(
    "text, overrides",
    [
        # overrides of every kind of value: a float, a string, a list, an inline-table entry
        (
            MINIMAL,
            [
                "contact.mu=0.45",
                "analysis.plane=stress",
                "bc.fix=[\"y\"]",
                "output.snapshots=[0.5, 1.0]",
            ],
        ),
        # names TOML must quote and escape; a displacement (inline table) and stages
        (
            MINIMAL.replace('name = "mini"', 'name = "a \\"quoted\\" \\\\ näme\\ttab"').replace(
                'fix = ["x", "y"]', 'fix = ["x"]\nname = "push up"\ndisplacement = {y = 0.1}'
            )
            + '\n[[stage]]\nname = "out"\nfactors = {"push up" = 1.0}\n'
            '\n[[stage]]\nname = "back"\nfactors = {"push up" = 0.0}\n',
            [],
        ),
        # axisymmetric: thickness is filled in, inert and refused when given
        (MINIMAL.replace('[[body]]', '[analysis]\nplane = "axisymmetric"\n\n[[body]]'), []),
        # a refined block keeps h_max and growth, a graded one its focus
        (
            MINIMAL.replace(
                "nx = 4\nny = 2", "h = 0.25\nrefine_box = [0.0, 0.5, 1.0, 1.0]\n" "h_max = 0.5"
            ),
            ["mesh.growth=0.2"],
        ),
        (
            MINIMAL.replace(
                "nx = 4\nny = 2",
                "h_contact = 0.1\ncontact_zone = 0.3\nh_max = 0.5\n" "focus = [1.0, 1.0]",
            ),
            [],
        ),
    ],
    ids=["overrides", "quoted_names_and_stages", "axisymmetric", "refined_block", "graded_block"],
)
def test_the_resolved_case_validates_to_the_same_data(text, overrides):
    case = parse_case(text, overrides=overrides)
    again = parse_case(resolved_case_text(case), "case.toml")
    assert exactly_equal(again.data, case.data)


def test_a_mesh_file_is_written_by_its_absolute_path(tmp_path):
    """A relative ``file`` resolves against the case's folder; the result folder is another."""
    (tmp_path / "meshes").mkdir()
    mesh = slipstep.from_arrays(
        [[0, 0], [1, 0], [1, 1], [0, 1]],
        [[0, 1, 2], [0, 2, 3]],
        {"bottom": [[0, 1]], "top": [[2, 3]]},
    )
    write_msh(mesh, tmp_path / "meshes" / "block.msh")
    text = MINIMAL.replace(
        'generator = "block"\nwidth = 2.0\nheight = 1.0\nnx = 4\nny = 2',
        'file = "meshes/block.msh"',
    )
    case = parse_case(text, base_dir=tmp_path)
    written = resolved_case_text(case)
    assert f'file = "{(tmp_path / "meshes" / "block.msh").resolve()}"' in written
    elsewhere = tmp_path / "results"
    elsewhere.mkdir()
    again = parse_case(written, base_dir=elsewhere)
    assert np.array_equal(mesh_body(again, 0).nodes, mesh_body(case, 0).nodes)
    again.data["body"][0]["mesh"]["file"] = "meshes/block.msh"
    assert exactly_equal(again.data, case.data)


# --------------------------------------------------------------------------- reruns
def test_a_run_with_overrides_reruns_from_its_case_toml(tmp_path):
    cli(
        "run",
        "hertz_cylinder",
        "--set",
        COARSE,
        "--set",
        "contact.mu=0.3",
        "--set",
        "solver.group_tol=0",
        "--out",
        str(tmp_path / "first"),
        "--quiet",
    )
    cli("run", str(tmp_path / "first" / "case.toml"), "--out", str(tmp_path / "again"), "--quiet")
    first = (tmp_path / "first" / "events.csv").read_bytes()
    assert (tmp_path / "again" / "events.csv").read_bytes() == first
    # negative control: without the friction override the events differ (no stick/slip)
    cli(
        "run",
        "hertz_cylinder",
        "--set",
        COARSE,
        "--set",
        "solver.group_tol=0",
        "--out",
        str(tmp_path / "frictionless"),
        "--quiet",
    )
    assert (tmp_path / "frictionless" / "events.csv").read_bytes() != first
    text = (tmp_path / "first" / "case.toml").read_text()
    assert "--set contact.mu=0.3" in text.splitlines()[1]  # the header says where it came from
    assert "mu = 0.3" in text and "group_tol = 0.0" in text


def test_a_staged_case_reruns_from_its_case_toml(tmp_path):
    cli(
        "run",
        str(CASES / "hertz_load_unload.toml"),
        "--set",
        COARSE,
        "--set",
        "output.xdmf=false",
        "--set",
        "output.figures=false",
        "--out",
        str(tmp_path / "first"),
        "--quiet",
    )
    cli("run", str(tmp_path / "first" / "case.toml"), "--out", str(tmp_path / "again"), "--quiet")
    events = (tmp_path / "first" / "events.csv").read_text()
    assert (tmp_path / "again" / "events.csv").read_text() == events
    assert len({row.split(",")[-1] for row in events.splitlines()[1:]}) > 1, "several stages"


def test_a_study_case_reruns_from_its_case_toml(tmp_path):
    """The sweep's stop_at_first_yield option is part of the case it records."""
    study = tmp_path / "tiny.toml"
    study.write_text(f"""
[study]
name = "tiny"
base = "default"
set = ["material.Sy=200", "material.H=700", "{COARSE}", "output.figures=false",
       "output.xdmf=false"]

[vary]
"contact.mu" = [0.3]

[output]
stop_at_first_yield = true
results = true
""")
    cli("sweep", str(study), "--out", str(tmp_path / "sweep"), "--workers", "1", "--quiet")
    (folder,) = [p for p in (tmp_path / "sweep").iterdir() if p.is_dir()]
    assert "stop_at_first_yield = true" in (folder / "case.toml").read_text()
    cli("run", str(folder / "case.toml"), "--out", str(tmp_path / "again"), "--quiet")
    events = (folder / "events.csv").read_text()
    assert (tmp_path / "again" / "events.csv").read_text() == events
    assert events.splitlines()[-1].split(",")[2] == "yield", "the run stops at first yield"
    # negative control: the same case without the study's option runs past first yield
    (tmp_path / "free.toml").write_text(
        (folder / "case.toml")
        .read_text()
        .replace("stop_at_first_yield = true", "stop_at_first_yield = false")
    )
    cli("run", str(tmp_path / "free.toml"), "--out", str(tmp_path / "free"), "--quiet")
    assert (tmp_path / "free" / "events.csv").read_text() != events


def test_versions_are_in_the_summary(tmp_path):
    cli("run", "hertz_cylinder", "--set", COARSE, "--out", str(tmp_path), "--quiet")
    versions = json.loads((tmp_path / "summary.json").read_text())["versions"]
    assert versions["slipstep"] == slipstep.__version__
    assert versions["numpy"] == np.__version__
    assert versions["python"] == ".".join(map(str, sys.version_info[:3]))
    assert versions["engine"] and versions["gmsh"]
    assert f"slipstep {slipstep.__version__}" in (tmp_path / "case.toml").read_text()


def test_a_mesh_from_python_is_named_as_given(tmp_path):
    mesh = block(2.0, 1.0, 4, 2)
    case = parse_case(MINIMAL)
    result = slipstep.run(case, meshes={"b": mesh}, progress=False)
    result.write(tmp_path, figures=False, xdmf=False)
    text = (tmp_path / "case.toml").read_text()
    assert 'generator = "given"' in text and "came from Python" in text
    with pytest.raises(CaseError, match='generator = "given": pass its mesh from Python'):
        slipstep.build_scene(load_case(tmp_path / "case.toml"))
    rerun = slipstep.run(load_case(tmp_path / "case.toml"), meshes={"b": mesh}, progress=False)
    assert np.array_equal(
        rerun.raw["events"]["load_fraction"], result.raw["events"]["load_fraction"]
    )
