"""README.md states facts the repository holds: its pictures exist, its speed figures are the
ones the bench measured (bench/results.md, bench/dolfinx_side_by_side.md: a rerun bench with
other numbers fails here until README follows), and LICENSE is the license Cargo.toml
declares."""

from __future__ import annotations

import re
import tomllib

from conftest import ROOT

README = (ROOT / "README.md").read_text()


def test_the_pictures_exist_and_are_png():
    pictures = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", README)
    assert pictures and pictures[0].startswith("docs/")  # a result near the top
    assert README.index(pictures[0]) < README.index("## Quick start")
    for path in pictures:
        assert (ROOT / path).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", path


def _section(title: str) -> str:
    return README.split(f"## {title}\n", 1)[1].split("\n## ", 1)[0]


def test_the_speed_figures_are_the_bench_measurements():
    """Every 'N.NN s' and signed percentage in the comparison section is in a bench report."""
    bench = "".join(
        (ROOT / "bench" / name).read_text() for name in ("results.md", "dolfinx_side_by_side.md")
    )
    text = _section("When to choose it, and when not")
    quoted = re.findall(r"(\d+\.\d+) s\b", text) + re.findall(r"([+-]?\d+\.\d+) %", text)
    assert len(quoted) >= 8, quoted
    missing = [q for q in quoted if q not in bench]
    assert not missing, f"README quotes numbers the bench reports do not hold: {missing}"


def test_the_license_file_is_cargos_license():
    license_ = tomllib.loads((ROOT / "Cargo.toml").read_text())["workspace"]["package"]["license"]
    assert license_ == "MIT"
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License\n") and "WITHOUT WARRANTY OF ANY KIND" in text


def test_the_limits_and_the_reference_are_stated():
    limits = _section("Limits")
    for fact in (
        "3D",
        "Small strain",
        "Quasi-static",
        "3-node triangles",
        "4-node tetrahedra",
        "von Mises",
        "isotropic hardening",
        "axisymmetric",
        "slip_turn",
    ):
        assert fact in limits, fact
    reference = _section("Reference")
    assert "Abdalla" in reference and "A numerical incremental procedure" in reference
