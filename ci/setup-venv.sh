#!/usr/bin/env bash
# Create/refresh .venv: Debian's python (sees apt's dolfinx, meshio, h5py, scipy, numpy) plus the
# pip packages of ci/requirements.txt, every pip install constrained by ci/constraints.txt.
set -euo pipefail
cd "$(dirname "$0")/.."

SYS_PY=/usr/bin/python3
VENV=.venv
CONSTRAINTS=ci/constraints.txt
export PIP_DISABLE_PIP_VERSION_CHECK=1

# Recreate the venv if it is missing or was made by another interpreter / without system packages.
cfg=$VENV/pyvenv.cfg
if [[ ! -x $VENV/bin/python ]] || [[ ! -f $cfg ]] \
    || ! grep -qx 'include-system-site-packages = true' "$cfg" \
    || ! grep -qx 'home = /usr/bin' "$cfg"; then
    echo "setup-venv: creating $VENV with $SYS_PY --system-site-packages"
    rm -rf "$VENV"
    "$SYS_PY" -m venv --system-site-packages "$VENV"
fi

# Debian's h5py (same HDF5 as dolfinx) registered for pip, so no pip run here or inside
# `maturin develop` pulls PyPI's h5py over it (the reasons are in the script).
ci/debian-h5py.sh "$VENV"

"$VENV/bin/python" -m pip install --progress-bar off -c "$CONSTRAINTS" -r ci/requirements.txt

"$VENV/bin/python" ci/check-env.py
