"""The errors slipstep raises, one class per cause (the interface contract with the engine).

Every :class:`SlipstepError` is meant for the user: its message is one line that names the
place (case key, body, contact, element) and the fix; ``slipstep`` prints it as
``slipstep: error: <message>`` and exits with 2.  The compiled engine raises the classes of
this module too (``slipstep._engine.solve`` imports it), one per kind of core error.
:class:`InternalError` is not a SlipstepError: it is a bug, which the command line reports in
one line too.  An error inside the engine's event loop comes with the results up to there
(the exception's ``result``; ``slipstep run`` writes them).
"""

from __future__ import annotations


class SlipstepError(Exception):
    """A problem the user can fix; the message is one line naming the place and the fix."""

    def __init__(self, message: str = ""):
        # one line, whatever a key, a value or a file name holds (TOML keys and strings may
        # contain newlines): control characters are written as escapes
        super().__init__("".join(c if c.isprintable() else repr(c)[1:-1] for c in str(message)))


class InputError(SlipstepError, ValueError):
    """Bad input: a case key or override, a mesh, a study, a model value (index out of range,
    NaN, inverted element).  Fix the value the message names."""


class CaseError(InputError):
    """A problem in a case file or an override; the message is one line and names the fix."""


class FreeBodyError(SlipstepError):
    """A body is free to move (a rigid-body mode, or a mechanism) under the current contact
    state.  Add a support ([[bc]] fix/symmetry) or a contact that holds the named body."""


class GrossSlidingError(SlipstepError):
    """The tangential load exceeds what friction can carry: the named body slides away.
    Lower the tangential load, raise mu, or support the body tangentially."""


class SingularSystemError(SlipstepError):
    """The equations are singular: redundant constraints (a node held twice, a pair whose
    normal is fully supported) or a factorization failure.  Remove the redundant support."""


class EquilibriumError(SlipstepError):
    """The equilibrium residual rose above ``solver.equilibrium_tol``: the run is no longer
    trustworthy.  Refine the mesh, lower ``solver.max_stress_step``, or report the case."""


class IllPosedError(SlipstepError):
    """Statuses cycled at a fixed load, the complementarity (rate) problem found no admissible
    set, and the last-resort freeze left a contact or yield condition violated: the scene may
    be ill-posed for its friction coefficient.  Lower mu, add supports, or change the load."""


class EngineMissing(SlipstepError, RuntimeError):
    """The compiled engine ``slipstep._engine`` is not built (run ``make build``), or cannot
    solve the scene's dimension (a 3D scene before the engine's 3D)."""


class InternalError(RuntimeError):
    """A bug in slipstep (an invariant of the engine broke, or a panic in it).  Not a
    SlipstepError (no fix of the user's makes it go away): the command line prints its one line
    (``SLIPSTEP_TRACEBACK=1``: the traceback); please report it with the case."""


__all__ = [
    "CaseError",
    "EngineMissing",
    "EquilibriumError",
    "FreeBodyError",
    "GrossSlidingError",
    "IllPosedError",
    "InputError",
    "InternalError",
    "SingularSystemError",
    "SlipstepError",
]
