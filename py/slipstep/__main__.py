"""``python -m slipstep`` = the ``slipstep`` command."""

from .cli import main

raise SystemExit(main())
