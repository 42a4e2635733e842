"""FEniCSx (dolfinx 0.5) co-simulation: identical meshes over XDMF/HDF5, bulk cross-checks,
contact replay and a hybrid mode (issue 4).

Everything here is optional: the core package never imports this subpackage, and importing
it does not import dolfinx either; only the functions that need dolfinx import it, and then
raise :class:`DolfinxMissing` with the fix if it is absent.

Modules
-------
``exchange``    slipstep scene <-> XDMF/HDF5 <-> dolfinx mesh, with the explicit node, dof and
                cell maps (dolfinx reorders both nodes and cells).  Writing needs only h5py.
``plasticity``  small-strain von Mises return mapping with linear hardening (numpy, per cell),
                plane strain (sigma_z tracked) and plane stress (sigma_z = 0, condensed).
``bulk``        dolfinx solvers on the exchanged mesh, driven by the same case with contact
                removed: linear elasticity and elastoplasticity (Newton, load in steps).
``hill``        Hill's closed form for the thick-walled cylinder under internal pressure.
``replay``      a slipstep contact state replayed in dolfinx as boundary conditions.
``hybrid``      slipstep's event loop on a user's dolfinx model (P1, isotropic elastic).
``crosscheck``  the ``slipstep crosscheck`` report.

Serial only (one MPI process): the maps are built from process-local numbering.
"""

from __future__ import annotations

from ..errors import SlipstepError


class DolfinxMissing(SlipstepError, ImportError):
    """dolfinx (FEniCSx 0.5) is not importable: install it (the message says how)."""


def require_dolfinx():
    """Import and return ``dolfinx``, or raise :class:`DolfinxMissing` naming the fix."""
    try:
        import dolfinx  # noqa: F401
        import dolfinx.fem.petsc  # noqa: F401
        import dolfinx.io  # noqa: F401
    except ImportError as exc:
        raise DolfinxMissing(f"dolfinx is not available ({exc}): install Debian's "
                             f"python3-dolfinx (make setup does) and use a venv made with "
                             f"--system-site-packages") from None
    from mpi4py import MPI
    if MPI.COMM_WORLD.size != 1:
        raise RuntimeError("slipstep.fenicsx runs in serial only (one MPI process)")
    return dolfinx


__all__ = ["DolfinxMissing", "require_dolfinx"]
