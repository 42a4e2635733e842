#!/usr/bin/env bash
# Fails when a Rust or Python file is not as `make fmt` would write it (rustfmt.toml, pyproject's
# [tool.ruff]); prints which files and how to fix them. Run by `make test`.
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
cargo fmt --all --check >/dev/null 2>&1 || {
  echo "format: Rust files differ from rustfmt.toml's layout (run: make fmt):"
  cargo fmt --all --check -l 2>/dev/null | sed 's/^/  /' || true
  status=1
}
{ [ -x .venv/bin/ruff ] && PATH=$PWD/.venv/bin:$PATH; ruff format --check --quiet .; } || {
  echo "format: the Python files above differ from pyproject's [tool.ruff] layout (run: make fmt)"
  status=1
}
exit $status
