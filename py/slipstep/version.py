"""``slipstep.__version__``: one version, the Cargo workspace's (``[workspace.package]
version`` in Cargo.toml; pyproject.toml takes it from there through maturin).

From a source checkout it is read from that Cargo.toml, so a checkout on the path never reports
the version of another installed copy; an installed wheel has no Cargo.toml beside it and
reports its distribution's version.
"""

from __future__ import annotations

import tomllib
from importlib import metadata
from pathlib import Path

CARGO_TOML = Path(__file__).resolve().parents[2] / "Cargo.toml"  # py/slipstep/ -> checkout


def version() -> str:
    if CARGO_TOML.is_file():
        return tomllib.loads(CARGO_TOML.read_text())["workspace"]["package"]["version"]
    try:
        return metadata.version("slipstep")
    except metadata.PackageNotFoundError:  # neither a checkout nor installed: a copied folder
        return "unknown"


__version__ = version()
