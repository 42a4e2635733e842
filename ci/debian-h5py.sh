#!/usr/bin/env bash
# Usage: ci/debian-h5py.sh VENV
#
# Make a venv made with --system-site-packages use Debian's h5py (python3-h5py), the one built
# on the HDF5 that Debian's dolfinx uses, and keep pip from installing PyPI's over it.
#
# Why: Debian registers its h5py as the distribution "h5py._debian_h5py_serial", which pip does
# not recognise as "h5py", so installing slipstep (which needs h5py) pulls PyPI's h5py with its
# own, newer HDF5 into the venv. Two HDF5 libraries then meet in one process, and dolfinx 0.5
# leaves the dlopen flags at RTLD_GLOBAL after its import: an h5py imported after dolfinx binds
# to Debian's HDF5 and dies ("ValueError: Not a datatype"). With one HDF5 the import order does
# not matter. This registers Debian's h5py under its real name in the venv (metadata only) and
# removes a PyPI h5py already there. Without Debian's python3-h5py it does nothing.
set -euo pipefail
venv=${1:?usage: ci/debian-h5py.sh VENV}
deb_info=$(compgen -G '/usr/lib/python3/dist-packages/h5py._debian_h5py_*.dist-info' | head -n1 || true)
[[ -n $deb_info ]] || exit 0

site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
if [[ -d $site/h5py ]]; then
    echo "debian-h5py: removing PyPI h5py from $venv (Debian's is used)"
    "$venv/bin/python" -m pip uninstall -y -q h5py
fi
h5ver=${deb_info%.dist-info}; h5ver=${h5ver##*-}
shim=$site/h5py-$h5ver.dist-info
if [[ ! -f $shim/METADATA ]]; then
    mkdir -p "$shim"
    printf 'Metadata-Version: 2.1\nName: h5py\nVersion: %s\nSummary: Debian python3-h5py (%s), registered for pip by ci/debian-h5py.sh\n' \
        "$h5ver" "$deb_info" > "$shim/METADATA"
    echo "slipstep-ci" > "$shim/INSTALLER"
    printf 'h5py-%s.dist-info/METADATA,,\nh5py-%s.dist-info/INSTALLER,,\nh5py-%s.dist-info/RECORD,,\n' \
        "$h5ver" "$h5ver" "$h5ver" > "$shim/RECORD"
fi
