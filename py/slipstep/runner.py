"""One run: case -> scene -> engine -> summary (and files)."""

from __future__ import annotations

import time
from pathlib import Path

from .case import Case, load_case
from .errors import EngineMissing
from .model import Scene, build_scene
from .results import write_results
from .summary import summarize

__all__ = ["EngineMissing", "engine", "prepare", "run_case", "solve"]


def engine():
    """The compiled engine module (docs/engine_api.md)."""
    try:
        from . import _engine
    except ImportError as exc:
        raise EngineMissing(f"the compiled engine slipstep._engine is not available ({exc}): "
                            f"build it with `make build` (maturin develop --release)") from None
    return _engine


def prepare(case_or_path: Case | str | Path | None = None, overrides=(), meshes=None) -> Scene:
    """Load (unless given a Case) and assemble a case into a Scene; ``meshes`` (body name ->
    Mesh) replaces the meshing of those bodies (:func:`slipstep.model.build_scene`)."""
    if isinstance(case_or_path, Case):
        if overrides:
            raise ValueError("overrides apply when loading: pass a path, not a Case")
        case = case_or_path
    else:
        case = load_case(case_or_path, overrides)
    return build_scene(case, meshes)


def solve(scene: Scene, progress: bool = False) -> dict:
    """Run the engine on a prepared scene."""
    return engine().solve(scene.model, progress)


def run_case(case_or_path: Case | str | Path | None = None, out: str | Path | None = None,
             overrides=(), progress: bool = False) -> tuple[dict, dict]:
    """Run a case (a path, a Case, or None for the built-in Hertz cylinder); write results to
    ``out`` if given.  Returns ``(result, summary)``.

    A run the engine stops early (Ctrl-C, limit load, event bound: ``result["stop"]``) is
    written like a complete one.  Ctrl-C while the files are being written raises
    KeyboardInterrupt with the message that nothing was replaced in ``out``.
    """
    start = time.perf_counter()
    scene = prepare(case_or_path, overrides)
    result = solve(scene, progress)
    summary = summarize(scene, result, wall_time_s=time.perf_counter() - start)
    if out is not None:
        try:
            write_results(out, scene, result, summary)
        except KeyboardInterrupt:
            raise KeyboardInterrupt(f"interrupted while writing results; nothing was replaced "
                                    f"in {out}") from None
    return result, summary
