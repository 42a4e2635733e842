"""Check that .venv is usable: `.venv/bin/python ci/check-env.py [--built]`.

numpy must be Debian's 1.24.2 (ci/constraints.txt) and h5py Debian's (same HDF5 as dolfinx); with
--built, the extension `slipstep._engine` must import too.
"""

import pathlib
import re
import sys

import numpy, dolfinx, meshio, h5py, gmsh, matplotlib, tqdm  # noqa: E401,F401  (the imports are the test)
import jupytext, nbclient, ipykernel, ipywidgets  # noqa: E401,F401  (the examples as notebooks)

root = pathlib.Path(__file__).resolve().parent.parent
want = re.search(r"^numpy==(\S+)", (root / "ci/constraints.txt").read_text(), re.M).group(1)
errors = []
if numpy.__version__ != want:
    errors.append(
        f"numpy {numpy.__version__} from {numpy.__file__}, expected {want}: something was "
        "pip-installed without -c ci/constraints.txt; rm -rf .venv and re-run make"
    )
if not h5py.__file__.startswith("/usr/lib/python3/"):
    errors.append(
        f"h5py {h5py.__version__} from {h5py.__file__}, expected Debian's python3-h5py: "
        "pip installed a PyPI h5py (own HDF5); rm -rf .venv and re-run make"
    )
if "--built" in sys.argv:
    try:
        import slipstep._engine  # noqa: F401
    except ImportError as e:
        errors.append(f"slipstep._engine does not import: {e}")
if errors:
    sys.exit("check-env: " + "\n check-env: ".join(errors))
print(
    f"check-env: ok: numpy {numpy.__version__}, dolfinx {dolfinx.__version__}, "
    f"meshio {meshio.__version__}, h5py {h5py.__version__} (HDF5 {h5py.version.hdf5_version}), "
    f"gmsh {getattr(gmsh, '__version__', '?')}, matplotlib {matplotlib.__version__}, "
    f"tqdm {tqdm.__version__}, jupytext {jupytext.__version__}, nbclient {nbclient.__version__}"
    + (", slipstep._engine" if "--built" in sys.argv else "")
)
