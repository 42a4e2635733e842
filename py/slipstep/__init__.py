"""slipstep: event-driven ("adaptive incremental") frictional contact in 2D.

After Abdalla, Ali-Eldin & Ghazy: every increment is scaled to the next change of contact
status (close, separate, stick -> slip, slip -> stick), so there are no load steps to tune and
no penalty parameters.  The event loop is the compiled engine ``slipstep._engine``; this
package describes scenes (``case``), meshes them (``mesh``), builds the engine model
(``model``) and writes results (``summary``, ``output``, ``figures``, ``results``); errors
are the classes of ``errors``.

    >>> from slipstep import run_case
    >>> result, summary = run_case("cases/hertz_cylinder.toml", out="results/hertz",
    ...                            overrides=["contact.mu=0.1"])
"""

from .case import Case, CaseError, load_case, parse_case
from .errors import InputError, SlipstepError
from .mesh import Mesh, MeshError
from .model import Scene, build_scene
from .runner import prepare, run_case, solve

__all__ = ["Case", "CaseError", "InputError", "Mesh", "MeshError", "Scene", "SlipstepError",
           "build_scene", "load_case", "parse_case", "prepare", "run_case", "solve"]
