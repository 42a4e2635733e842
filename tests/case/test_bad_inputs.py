"""The bad-input catalogue (issue 7, part 1): every case in tests/case/bad_inputs/ through the CLI.

Each ``tests/case/bad_inputs/NN_name.toml`` starts with comment lines

    # bad: what is wrong with it
    # expect: word | word | ...        (all must appear in the error line)
    # args: --set KEY=VALUE ...        (optional: extra command-line arguments)
    # out: under-file | is-file        (optional: --out is below / is a regular file)
    # xfail: what slipstep does instead (optional: a known gap, strict: it fails once fixed,
    #        and then the line goes)

and may use mesh files beside it.  ``slipstep run CASE --out DIR`` must exit with 2 and print
exactly one stderr line ``slipstep: error: ...`` containing every expected word (the place and
the fix), with no traceback and no panic, and must leave what was already in the output folder
(a sentinel and an old summary.json) and the catalogue folder untouched.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

CATALOGUE = Path(__file__).resolve().parent / "bad_inputs"
CASES = sorted(CATALOGUE.glob("*.toml"))
#: The catalogue's size when last counted: an entry that goes missing fails (entries are added,
#: never dropped; raise this with them).
SIZE = 170
#: Of them in space (``dimension = 3``): the 3D front's own checks.
SIZE_3D = 56


def header(path: Path) -> dict:
    """The ``# key: value`` lines at the top of a catalogue case (bytes: a case may not be
    UTF-8 on purpose)."""
    meta = {}
    for raw in path.read_bytes().splitlines():
        line = raw.decode("utf-8", errors="replace").strip()
        if not line.startswith("#"):
            break
        key, sep, value = line[1:].partition(":")
        if sep and key.strip() in ("bad", "expect", "args", "out", "xfail"):
            meta[key.strip()] = value.strip()
    return meta


def tree(root: Path) -> dict:
    """Every file below ``root`` with its bytes (folders as None)."""
    out = {}
    for p in sorted(root.rglob("*")):
        out[str(p.relative_to(root))] = None if p.is_dir() else p.read_bytes()
    return out


def slipstep(*args, cwd: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k != "SLIPSTEP_TRACEBACK"}
    env["MPLBACKEND"] = "Agg"
    return subprocess.run(
        [sys.executable, "-m", "slipstep", *map(str, args)],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        errors="replace",
        timeout=120,
    )


def in_space(path: Path) -> bool:
    return re.search(rb"^dimension\s*=\s*3\b", path.read_bytes(), re.M) is not None


def test_the_catalogue_is_complete():
    assert len(CASES) >= SIZE, f"{SIZE - len(CASES)} catalogue entries went missing"
    assert sum(map(in_space, CASES)) >= SIZE_3D
    for case in CASES:
        meta = header(case)
        assert meta.get("bad"), f"{case.name}: no '# bad:' line"
        assert meta.get("expect"), f"{case.name}: no '# expect:' line"
        assert meta.get("out", "") in ("", "under-file", "is-file"), case.name


def entry(case: Path):
    known = header(case).get("xfail")
    marks = [pytest.mark.xfail(strict=True, reason=known)] if known else []
    return pytest.param(case, id=case.stem, marks=marks)


@pytest.mark.parametrize("case", [entry(c) for c in CASES])
def test_bad_input_gives_one_clear_line(case: Path, tmp_path: Path):
    meta = header(case)
    expect = [w.strip() for w in meta["expect"].split("|") if w.strip()]
    work = tmp_path / "work"
    work.mkdir()
    mode = meta.get("out", "")
    if mode:
        blocker = work / "blocker"
        blocker.write_text("a regular file that must stay as it is\n")
        out = blocker / "sub" if mode == "under-file" else blocker
    else:
        out = work / "out"
        out.mkdir()
        (out / "sentinel.txt").write_text("results of an earlier run\n")
        (out / "summary.json").write_text('{"earlier": true}\n')
    before, catalogue_before = tree(work), tree(CATALOGUE)

    proc = slipstep("run", case, "--out", out, *shlex.split(meta.get("args", "")), cwd=work)

    where = f"{case.name}: stderr was:\n{proc.stderr}"
    assert proc.returncode == 2, where
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, where
    line = lines[0]
    assert line.startswith("slipstep: error: "), where
    for bad in ("Traceback", "panicked", "PanicException", "RuntimeWarning"):
        assert bad not in proc.stderr + proc.stdout, where
    for word in expect:
        assert word in line, f"{case.name}: {word!r} not in the error line:\n{line}"
    assert tree(work) == before, f"{case.name}: the output folder changed"
    assert tree(CATALOGUE) == catalogue_before, f"{case.name}: the catalogue folder changed"
