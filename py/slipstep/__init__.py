"""slipstep: event-driven ("adaptive incremental") frictional contact in 2D sections (plane or
axisymmetric) and 3D solids.

After Abdalla, Ali-Eldin & Ghazy: every increment is scaled to the next change of contact
status (close, separate, stick -> slip, slip -> stick) or plastic state, so there are no load
steps to tune and no penalty parameters.  The event loop is the compiled engine
``slipstep._engine``; this package describes scenes (``case``), meshes them (``mesh``), builds
the engine model (``build``, from ``contact`` and ``loads``), runs it (``runner``,
``progress``), gives the result as an object and writes its files (``output``, ``figures``),
measures it (``measures``); errors are the
classes of ``errors``; the shipped cases and studies are in ``shipped``.

    >>> import slipstep
    >>> r = slipstep.run("hertz_cylinder", overrides=["contact.mu=0.1"], out="results/hertz")
    >>> r                                   # a one-line summary (a table in a notebook)
    >>> r.fields(1.0)["u"], r.profile()["pressure"], r.to_meshio(0.5), r.events
    >>> slipstep.load("results/hertz")     # the same Result, read back from its folder
"""

from .version import __version__
from .case import Case, CaseError, load_case, parse_case
from .errors import InputError, SlipstepError
from .mesh import Mesh, MeshError, TetMesh, TriangleMesh, from_arrays, from_meshio, from_tetrahedra
from .build import build_scene
from .scene import Scene
from .progress import Progress
from .output.result import Result
from .runner import as_case, prepare, run, run_case, solve
from .output.saved import load

__all__ = [
    "__version__",
    "Case",
    "CaseError",
    "InputError",
    "Mesh",
    "MeshError",
    "Progress",
    "Result",
    "Scene",
    "SlipstepError",
    "TetMesh",
    "TriangleMesh",
    "as_case",
    "build_scene",
    "from_arrays",
    "from_meshio",
    "from_tetrahedra",
    "load",
    "load_case",
    "parse_case",
    "prepare",
    "run",
    "run_case",
    "solve",
]
