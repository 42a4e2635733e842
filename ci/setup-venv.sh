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

# Debian registers its h5py as the distribution "h5py._debian_h5py_serial", which pip does not
# recognise as "h5py". Without help, the pip run inside `maturin develop` (slipstep depends on h5py)
# pulls PyPI's h5py, with its own bundled HDF5, into the venv over Debian's (the HDF5 that dolfinx
# uses). Register Debian's h5py under its real name in the venv, metadata only, so pip sees the
# requirement as satisfied.
site=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
deb_info=$(compgen -G '/usr/lib/python3/dist-packages/h5py._debian_h5py_*.dist-info' | head -n1 || true)
if [[ -n $deb_info ]]; then
    if [[ -d $site/h5py ]]; then
        echo "setup-venv: removing PyPI h5py from $VENV (Debian's is used)"
        "$VENV/bin/python" -m pip uninstall -y -q h5py
    fi
    h5ver=${deb_info%.dist-info}; h5ver=${h5ver##*-}
    shim=$site/h5py-$h5ver.dist-info
    if [[ ! -f $shim/METADATA ]]; then
        mkdir -p "$shim"
        printf 'Metadata-Version: 2.1\nName: h5py\nVersion: %s\nSummary: Debian python3-h5py (%s), registered for pip by ci/setup-venv.sh\n' \
            "$h5ver" "$deb_info" > "$shim/METADATA"
        echo "slipstep-ci" > "$shim/INSTALLER"
        printf 'h5py-%s.dist-info/METADATA,,\nh5py-%s.dist-info/INSTALLER,,\nh5py-%s.dist-info/RECORD,,\n' \
            "$h5ver" "$h5ver" "$h5ver" > "$shim/RECORD"
    fi
fi

"$VENV/bin/python" -m pip install --progress-bar off -c "$CONSTRAINTS" -r ci/requirements.txt

"$VENV/bin/python" ci/check-env.py
