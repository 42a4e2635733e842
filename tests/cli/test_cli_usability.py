"""What a user of the command line expects: ``--version``, a close name suggested for a
misspelt case, ``--set KEY VALUE`` answered with how to write it, ``--help`` pointing to a key
reference the wheel has (``slipstep keys``, tests/case/test_keys.py), ``slipstep new`` copying a
shipped case to edit, and every early stop reported through its own message."""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib

import pytest

from conftest import ROOT

import slipstep as package
from slipstep import cli, shipped
from slipstep.case import load_case

CARGO_VERSION = tomllib.loads((ROOT / "Cargo.toml").read_text())["workspace"]["package"]["version"]


def slipstep(*args, cwd=None):
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT / "py"))
    return subprocess.run(
        [sys.executable, "-m", "slipstep", *map(str, args)],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


def one_error_line(proc) -> str:
    assert proc.returncode == 2, (proc.stdout, proc.stderr)
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("slipstep: error: "), proc.stderr
    return lines[0].removeprefix("slipstep: error: ")


# --------------------------------------------------------------------------- version
def test_version_is_the_cargo_workspace_version():
    """One version: Cargo.toml's workspace version (pyproject.toml takes it from there), read
    here with tomllib, is what the package and the command say."""
    assert package.__version__ == CARGO_VERSION
    proc = slipstep("--version")
    assert proc.returncode == 0 and proc.stdout == f"slipstep {CARGO_VERSION}\n"


# --------------------------------------------------------------------------- names and --set
def test_a_misspelt_case_name_gets_the_close_shipped_names():
    line = one_error_line(slipstep("run", "hertz_cylnder"))
    assert line == (
        "hertz_cylnder: no such case file, and no shipped case of that name; did you "
        "mean hertz_cylinder? (`slipstep list` shows the shipped ones)"
    )


def test_a_name_like_no_shipped_case_points_to_the_list():
    line = one_error_line(slipstep("check", "zzz"))
    assert line == (
        "zzz: no such case file, and no shipped case of that name (`slipstep list` "
        "shows the shipped ones)"
    )


def test_a_misspelt_study_name_gets_the_close_shipped_names():
    line = one_error_line(slipstep("sweep", "fig10_onset_of_yeld"))
    assert "no such study file" in line and "did you mean fig10_onset_of_yield?" in line


@pytest.mark.parametrize(
    "argv, shown, fix",
    [
        (["run", "--set", "contact.mu", "0.2"], "--set contact.mu 0.2", "--set contact.mu=0.2"),
        (
            ["run", "two_blocks", "--set", "contact.mu", "0.2", "--quiet"],
            "--set contact.mu 0.2",
            "--set contact.mu=0.2",
        ),
        (["check", "--set", "contact.mu"], "--set contact.mu", "--set contact.mu=VALUE"),
        (["run", "--set=contact.mu", "0.2"], "--set contact.mu 0.2", "--set contact.mu=0.2"),
    ],
)
def test_set_with_a_space_says_to_write_key_equals_value(argv, shown, fix):
    line = one_error_line(slipstep(*argv))
    assert line == f"{shown}: write KEY=VALUE as one word, {fix} (the keys: `slipstep keys`)"


def test_help_points_to_the_key_reference_and_to_new():
    text = slipstep("--help").stdout
    assert "`slipstep keys [SECTION]`" in text and "`slipstep new NAME --from" in text
    assert "slipstep keys" in slipstep("run", "--help").stdout  # under --set
    assert "README" not in text + slipstep("run", "--help").stdout  # not in a wheel


# --------------------------------------------------------------------------- slipstep new
@pytest.mark.parametrize("source", shipped.names("cases"))
def test_new_copies_a_shipped_case_under_its_new_name(tmp_path, source):
    """The copy is the shipped case (same validated content) but for its name, which is the new
    one (so its results go to results/<NAME>); comments are kept."""
    proc = slipstep("new", "mine", "--from", source, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith(f"mine.toml: a copy of the shipped case {source}, named mine")
    copy, original = load_case(tmp_path / "mine.toml"), load_case(shipped.path(source))
    assert copy.name == "mine"
    assert {**copy.data, "case": {}} == {**original.data, "case": {}}
    assert {k: v for k, v in copy.data["case"].items() if k != "name"} == {
        k: v for k, v in original.data["case"].items() if k != "name"
    }
    text = (tmp_path / "mine.toml").read_text()
    assert text.count("#") == shipped.path(source).read_text().count("#")
    for rel in shipped.referenced_files(original.data):  # the meshes and surfaces it names
        assert (tmp_path / rel).read_bytes() == (shipped.path(source).parent / rel).read_bytes()


def test_a_new_case_that_names_a_surface_file_is_checked_where_it_was_written(tmp_path):
    """Issue 38: `new --from boussinesq_punch_3d` left its flat_punch_3d.stl behind, and the
    copy failed with "no such surface file"."""
    proc = slipstep("new", "vickers", "--from", "boussinesq_punch_3d", cwd=tmp_path)
    assert "(with flat_punch_3d.stl beside it)" in proc.stdout, proc.stderr
    proc = slipstep("check", "vickers.toml", cwd=tmp_path)
    assert proc.returncode == 0 and proc.stdout.startswith("vickers: "), proc.stderr


def test_new_keeps_a_different_file_of_the_same_name_and_names_the_fix(tmp_path):
    (tmp_path / "flat_punch_3d.stl").write_text("mine")
    line = one_error_line(slipstep("new", "vickers", "--from", "boussinesq_punch_3d", cwd=tmp_path))
    assert line.startswith("flat_punch_3d.stl exists and differs from the file")
    assert not (tmp_path / "vickers.toml").exists()
    assert (tmp_path / "flat_punch_3d.stl").read_text() == "mine"


def test_new_keeps_an_existing_file_and_names_the_fix(tmp_path):
    (tmp_path / "mine.toml").write_text("keep")
    line = one_error_line(slipstep("new", "mine", cwd=tmp_path))
    assert line == "mine.toml exists: give another NAME, or remove the file first"
    assert (tmp_path / "mine.toml").read_text() == "keep"


def test_new_from_a_misspelt_case_suggests_one(tmp_path):
    line = one_error_line(slipstep("new", "mine", "--from", "hertz_sfere", cwd=tmp_path))
    assert "did you mean hertz_sphere" in line and not (tmp_path / "mine.toml").exists()


@pytest.mark.parametrize(
    "text, want",
    [
        (
            '[case]\nname = "old"\n[solver]\nname = "x"\n',
            '[case]\nname = "new"\n[solver]\nname = "x"\n',
        ),
        (
            '# c\n[case]\ndescription = "d"\n\n[load]\nP = 1.0\n',
            '# c\n[case]\nname = "new"\ndescription = "d"\n\n[load]\nP = 1.0\n',
        ),
        ('[load]\nP = 1.0\n', '[case]\nname = "new"\n\n[load]\nP = 1.0\n'),
    ],
)
def test_renamed_sets_only_the_case_name(text, want):
    assert shipped.renamed(text, "new") == want
    assert tomllib.loads(shipped.renamed(text, "new"))["case"]["name"] == "new"


# --------------------------------------------------------------------------- early stops
def _stopped(kind: str, message):
    """run_case's answer for a run that stopped with ``kind`` (the engine's stop record)."""

    def run_case(case, out, overrides=(), progress=False):
        return {"stop": {"kind": kind, "message": message, "t": 0.5}}, {"final_t": 0.5}

    return run_case


@pytest.mark.parametrize(
    "kind, message, code",
    [
        ("completed", None, 0),
        ("first_yield", None, 0),  # asked for by solver.stop_at_first_yield: not an error
        ("limit_load", "limit load reached at load fraction 0.5: ...", 2),
        ("support_lost", "the body lifts off at t = 0.5 about (1, 0): ...", 2),  # a new kind
    ],
)
def test_an_early_stop_is_reported_by_its_message_whatever_its_kind(
    monkeypatch, capsys, tmp_path, kind, message, code
):
    monkeypatch.setattr(cli, "run_case", _stopped(kind, message))
    assert cli.main(["run", "--quiet", "--out", str(tmp_path)]) == code
    err = capsys.readouterr().err
    assert err == (
        f"slipstep: error: {message} (partial results in {tmp_path})\n" if message else ""
    )
