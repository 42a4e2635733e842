"""FEniCSx (dolfinx 0.5 to 0.11) co-simulation: identical meshes over XDMF/HDF5, bulk
cross-checks, contact replay and a hybrid mode.

Everything here is optional: the core package never imports this subpackage, and importing
it does not import dolfinx either; only the functions that need dolfinx import it (through
:mod:`.dolfinx_api`), and then raise :class:`DolfinxMissing` with the fix if it is absent.

Modules
-------
``dolfinx_api`` every dolfinx, UFL, petsc4py and mpi4py call of the package, with the
                version branches (0.5 ... 0.11) and the release notes they follow.
``forms``       the bulk weak form: one strain, one measure, per section (plane strain, plane
                stress, or the r-weighted axisymmetric ring section).
``exchange``    slipstep scene <-> XDMF/HDF5 <-> dolfinx mesh, with the explicit node, dof and
                cell maps (dolfinx reorders both nodes and cells).  Writing needs only h5py.
``plasticity``  small-strain von Mises return mapping with linear hardening (numpy, per cell),
                plane strain (sigma_z tracked), plane stress (sigma_z = 0, condensed) and
                axisymmetry (the hoop stress a fourth component).
``bulk``        dolfinx solvers on the exchanged mesh, driven by the same case with contact
                removed: linear elasticity and elastoplasticity (Newton, load in steps).
``radial``      the thick-walled cylinder's exact von Mises answer at any nu (a converged 1D
                radial model, numpy only): Hill's closed form (:mod:`slipstep.measures.references`) is
                exact at nu = 1/2 only.
``replay``      a slipstep contact state replayed in dolfinx as boundary conditions.
``hybrid``      slipstep's event loop on a user's dolfinx model (P1, isotropic elastic, plane).
``crosscheck``  the ``slipstep crosscheck`` report.

A 3D scene (tetrahedra) is exchanged and solved by the same modules: XYZ points and face tags
in the exchange, the six strains of ``forms.SpaceSection``, the six-component return of
``plasticity``, ``bulk`` on P1 vectors of three components (the contact replay, the hybrid mode
and the ``slipstep crosscheck`` report stay 2D).

Serial only (one MPI process): the maps are built from process-local numbering.
"""

from __future__ import annotations

from .dolfinx_api import DolfinxMissing, require_dolfinx

__all__ = ["DolfinxMissing", "require_dolfinx"]
