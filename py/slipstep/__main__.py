"""``python -m slipstep`` = the ``slipstep`` command."""

from .cli import main

if __name__ == "__main__":  # mpi4py.futures workers re-import the main module
    raise SystemExit(main())
