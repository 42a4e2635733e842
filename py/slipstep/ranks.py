"""The MPI ranks of a run whose stiffness is factorized by MUMPS (``[solver] factorization =
"mumps"``), started as ``mpirun -n N slipstep run CASE``.

Every rank runs the whole scene (the same mesh, the same event loop); the engine hands the
factorization to PETSc's MUMPS with the matrix rows spread over the ranks and gathers every
solution back, so all ranks compute the same history.  Rank 0 alone writes the results and
prints.  PETSc (and MPI) are started here, through petsc4py, before the engine reaches them;
without ``mpirun`` the run is one rank.
"""

from __future__ import annotations

from .errors import InputError

MUMPS = "mumps"


def uses_mumps(case) -> bool:
    """Whether the case's stiffness is factorized by MUMPS."""
    return case.record.solver.factorization == MUMPS


def start(case) -> int:
    """This process's rank, PETSc started through petsc4py (0 for a case that does not use
    MUMPS: nothing is started)."""
    if not uses_mumps(case):
        return 0
    from .fenicsx.dolfinx_api import (
        start_petsc,
    )  # (the adapter of the dolfinx stack; not at import)

    try:
        PETSc = start_petsc()
    except ImportError as exc:
        raise InputError(
            f"{case.source}: solver.factorization = \"mumps\" needs petsc4py with "
            f"PETSc's MUMPS (Debian: apt install python3-petsc4py; {exc}): install "
            f"it or use factorization = \"faer\""
        ) from None
    if not PETSc.Sys.hasExternalPackage("mumps"):
        raise InputError(
            f"{case.source}: solver.factorization = \"mumps\": this PETSc has no "
            f"MUMPS; use factorization = \"faer\""
        )
    return PETSc.COMM_WORLD.rank


def rank() -> int:
    """This process's rank once PETSc runs (0 otherwise)."""
    import sys

    petsc = sys.modules.get("petsc4py.PETSc")
    return petsc.COMM_WORLD.rank if petsc is not None else 0
