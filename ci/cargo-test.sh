#!/usr/bin/env bash
# `cargo test --release --workspace` in the same build environment `maturin develop --release`
# uses, so that both share every artifact in target/release (nothing is compiled twice).
#
# Why --workspace and not `-p slipstep-core`: cargo unifies dependency features over the packages
# selected on the command line. bindings/ (pyo3, rust-numpy) turns on extra features of shared
# crates (num-traits/num-complex "default"), so a `-p slipstep-core` build has a different feature
# set and recompiles faer, nalgebra & co. a second time (measured: +2 min on a clean build, 2 cores)
# and slipstep-core itself after every change.
#
# Why the PYO3_* variables: pyo3-ffi's build script re-runs when PYO3_PYTHON, PYO3_CONFIG_FILE,
# PYO3_ENVIRONMENT_SIGNATURE, VIRTUAL_ENV or PATH differ from the previous build; maturin sets the
# first three, so plain cargo would rebuild pyo3 (and maturin would rebuild it back) each time.
set -euo pipefail
cd "$(dirname "$0")/.."

venv=${VIRTUAL_ENV:-$PWD/.venv}
py=$venv/bin/python
target=${CARGO_TARGET_DIR:-$PWD/target}

if [[ -x $py ]]; then
    export VIRTUAL_ENV=$venv PYO3_PYTHON=$py PYTHON_SYS_EXECUTABLE=$py PYO3_BUILD_EXTENSION_MODULE=1
    PYO3_ENVIRONMENT_SIGNATURE=$("$py" -c 'import struct, sys; v = sys.version_info
print("%s-%d.%d-%dbit" % (sys.implementation.name, v.major, v.minor, struct.calcsize("P") * 8))')
    export PYO3_ENVIRONMENT_SIGNATURE
    shopt -s nullglob
    configs=("$target"/maturin/pyo3-config-*.txt)
    if ((${#configs[@]} == 1)); then
        export PYO3_CONFIG_FILE=${configs[0]}
    else
        echo "cargo-test: expected one $target/maturin/pyo3-config-*.txt (found ${#configs[@]});" \
             "pyo3 may be rebuilt" >&2
    fi
fi

exec cargo test --release --workspace "$@"
