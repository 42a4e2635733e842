"""One run: case -> scene -> engine -> summary (and files)."""

from __future__ import annotations

import time
from pathlib import Path

from .case import Case, load_case
from .model import Scene, build_scene
from .output import summarize, write_results


class EngineMissing(RuntimeError):
    """The compiled engine ``slipstep._engine`` is not built."""


def engine():
    """The compiled engine module (docs/engine_api.md)."""
    try:
        from . import _engine
    except ImportError as exc:
        raise EngineMissing(f"the compiled engine slipstep._engine is not available ({exc}): "
                            f"build it with `make build` (maturin develop --release)") from None
    return _engine


def prepare(case_or_path: Case | str | Path | None = None, overrides=()) -> Scene:
    """Load (unless given a Case) and assemble a case into a Scene."""
    if isinstance(case_or_path, Case):
        if overrides:
            raise ValueError("overrides apply when loading: pass a path, not a Case")
        case = case_or_path
    else:
        case = load_case(case_or_path, overrides)
    return build_scene(case)


def solve(scene: Scene, progress: bool = False) -> dict:
    """Run the engine on a prepared scene."""
    return engine().solve(scene.model, progress)


def run_case(case_or_path: Case | str | Path | None = None, out: str | Path | None = None,
             overrides=(), progress: bool = False) -> tuple[dict, dict]:
    """Run a case (a path, a Case, or None for the built-in Hertz cylinder); write results to
    ``out`` if given.  Returns ``(result, summary)``."""
    start = time.perf_counter()
    scene = prepare(case_or_path, overrides)
    result = solve(scene, progress)
    summary = summarize(scene, result, wall_time_s=time.perf_counter() - start)
    if out is not None:
        write_results(out, scene, result, summary)
    return result, summary
