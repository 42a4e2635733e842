"""User-facing text carries no internal references ("issue 7", "the issue's list"): what a user
reads knows nothing of the project's tracker.  User-facing: every string in the package
(docstrings that help() shows, messages, report texts), the shipped cases and studies (copied
out by `slipstep new`, comments included), the examples (their comments are notebook text),
README.md and the documentation."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from conftest import ROOT

INTERNAL = re.compile(r"\bissues?\b", re.I)


def _strings(path: Path) -> str:
    """Every string constant of a Python module (comments are for maintainers)."""
    tree = ast.parse(path.read_text(), str(path))
    return "\n".join(
        node.value
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant) and isinstance(node.value, str)
    )


PACKAGE = sorted((ROOT / "py" / "slipstep").rglob("*.py"))
TEXTS = sorted(
    [
        *(ROOT / "cases").glob("*.toml"),
        *(ROOT / "studies").glob("*.toml"),
        *(p for p in (ROOT / "examples").iterdir() if p.is_file()),
        ROOT / "README.md",
        ROOT / "cases" / "README.md",
        *(ROOT / "docs").glob("*.md"),
    ]
)


def _where(path: Path, text: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if INTERNAL.search(line)]


def test_the_files_are_found():
    assert len(PACKAGE) > 20 and ROOT / "examples" / "README.md" in TEXTS


@pytest.mark.parametrize("path", PACKAGE, ids=lambda p: str(p.relative_to(ROOT)))
def test_package_strings(path):
    assert not _where(path, _strings(path))


@pytest.mark.parametrize("path", TEXTS, ids=lambda p: str(p.relative_to(ROOT)))
def test_documents_cases_and_examples(path):
    assert not _where(path, path.read_text())
