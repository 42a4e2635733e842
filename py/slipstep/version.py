"""``slipstep.__version__``: one version, the Cargo workspace's (``[workspace.package]
version`` in Cargo.toml; pyproject.toml takes it from there through maturin).

From a source checkout it is read from that Cargo.toml, so a checkout on the path never reports
the version of another installed copy; an installed wheel has no Cargo.toml beside it and
reports its distribution's version.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

CARGO_TOML = Path(__file__).resolve().parents[2] / "Cargo.toml"  # py/slipstep/ -> checkout


def version() -> str:
    if CARGO_TOML.is_file():
        return tomllib.loads(CARGO_TOML.read_text())["workspace"]["package"]["version"]
    from importlib import metadata  # (not at import: it costs more than the rest of it)

    try:
        return metadata.version("slipstep")
    except metadata.PackageNotFoundError:  # neither a checkout nor installed: a copied folder
        return "unknown"


__version__ = version()


def versions() -> dict[str, str | None]:
    """What a run was made with: slipstep, its compiled engine (the bindings crate's version),
    numpy, gmsh and Python (None for one that is not there)."""
    import platform
    from importlib import metadata

    import numpy

    try:
        from . import _engine

        engine = getattr(_engine, "__version__", None)
    except ImportError:
        engine = None
    try:
        gmsh = metadata.version("gmsh")
    except metadata.PackageNotFoundError:
        gmsh = None
    return {
        "slipstep": __version__,
        "engine": engine,
        "numpy": numpy.__version__,
        "gmsh": gmsh,
        "python": platform.python_version(),
    }
