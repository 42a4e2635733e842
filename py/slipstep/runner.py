"""One run: case -> scene -> engine -> summary (and files).

:func:`run` is the entry for scripts and notebooks (a :class:`~slipstep.output.result.Result`);
:func:`run_case` is the older form, returning the two dicts.
"""

from __future__ import annotations

import signal
import sys
import threading
import time
from pathlib import Path

from . import ranks, shipped
from .case import Case, load_case
from .errors import EngineMissing, InputError
from .build import build_scene
from .scene import Scene
from . import progress as reporting
from .progress import Reporter
from .output.result import Result
from .output.results import write_results
from .output.summary import summarize

__all__ = ["EngineMissing", "as_case", "engine", "prepare", "run", "run_case", "solve"]


def engine():
    """The compiled engine module (docs/engine_api.md)."""
    try:
        from . import _engine
    except ImportError as exc:
        raise EngineMissing(
            f"the compiled engine slipstep._engine is not available ({exc}): "
            f"build it with `make build` (maturin develop --release)"
        ) from None
    return _engine


def as_case(case: Case | dict | str | Path | None = None, overrides=(), meshes=None) -> Case:
    """A :class:`Case` from a Case, a dict shaped like a case file (:meth:`Case.from_dict`;
    a body whose mesh ``meshes`` gives may leave out its mesh table), a case file, the name of
    a shipped case (:mod:`slipstep.shipped`), or None (the built-in Hertz cylinder)."""
    if isinstance(case, Case):
        if overrides:
            raise InputError(
                f"{case.source}: overrides apply when a case is read: pass its "
                f"path, text (Case.from_toml) or dict (Case.from_dict)"
            )
        return case
    if isinstance(case, dict):
        return Case.from_dict(_given_meshes(case, meshes or {}), overrides=overrides)
    return load_case(shipped.resolve(case), overrides)


def _given_meshes(data: dict, meshes: dict) -> dict:
    """``data`` with ``[body.mesh] generator = "given"`` for the bodies that have no mesh table
    and whose mesh ``meshes`` gives."""
    bodies = data.get("body")
    if not isinstance(bodies, list) or not meshes:
        return data
    fill = [
        {**b, "mesh": {"generator": "given"}}
        if isinstance(b, dict) and "mesh" not in b and b.get("name") in meshes
        else b
        for b in bodies
    ]
    return {**data, "body": fill}


def prepare(case: Case | dict | str | Path | None = None, overrides=(), meshes=None) -> Scene:
    """The assembled Scene of a case (:func:`as_case`); ``meshes`` (body name ->
    :class:`slipstep.mesh.Mesh`, e.g. from ``slipstep.mesh.from_meshio``) replaces the meshing
    of those bodies (:func:`slipstep.build.build_scene`)."""
    return build_scene(as_case(case, overrides, meshes), meshes)


def solve(scene: Scene, progress=False) -> dict:
    """Run the engine on a prepared scene; ``progress`` as for :func:`run`."""
    reporter = Reporter(progress, scene.case.name, scene.n_stages)
    result = None
    try:
        result = engine().solve(scene.model, reporter.callback, reporting.REPORT_INTERVAL_S)
    finally:
        reporter.finish(result)
    return result


def run(
    case: Case | dict | Scene | str | Path | None = None,
    out: str | Path | None = None,
    overrides=(),
    progress=True,
    *,
    meshes=None,
    figures: bool | None = None,
    xdmf: bool | None = None,
) -> Result:
    """Solve a case and return its :class:`~slipstep.output.result.Result`; write its files into
    ``out`` when given (``figures`` and ``xdmf`` default to the case's ``[output]``).

    ``case``: a Case, a dict, a case file, a shipped case name, None (the built-in Hertz
    cylinder; :func:`as_case`), or a prepared Scene.  ``progress``: True (a tqdm bar), False,
    or a callable ``f(slipstep.progress.Progress)`` that may return False to stop the run.

    Ctrl-C (a notebook's interrupt too) stops the engine within its current phase and the
    partial result is returned, like a run that ended early otherwise (``result.stop["kind"]``:
    interrupted, limit_load, event_bound, support_lost); its files are written like a complete
    run's.  A run that fails inside its event loop (an error of :mod:`slipstep.errors`, an
    engine bug as ``InternalError``) writes its results up to its last completed increment the
    same way, then raises the error, its message naming the case and where the results are,
    with that partial :class:`Result` as the exception's ``result``.

    A case with ``[solver] factorization = "mumps"`` run under ``mpirun -n N`` runs on every
    rank (:mod:`slipstep.ranks`); only rank 0 writes ``out``.
    """
    start = time.perf_counter()
    if isinstance(case, Scene):
        if overrides or meshes:
            raise InputError(
                f"{case.case.source}: a prepared Scene takes no overrides or "
                f"meshes: pass the case instead"
            )
        scene = case
    else:
        scene = prepare(case, overrides, meshes)
    if ranks.start(scene.case) != 0:  # MUMPS under mpirun: rank 0 writes and reports
        out, progress = None, False
    writers = _load_writers(scene, out, figures, xdmf)
    try:
        raw = solve(scene, progress)
    except BaseException as exc:
        # A daemon thread still inside an extension's import when the interpreter exits is
        # stopped in C code, which can abort the process instead of the error's clean exit.
        writers.join()
        partial = getattr(exc, "result", None)
        if not isinstance(partial, dict):
            raise
        raise _failed(exc, scene, partial, out, figures, xdmf, start) from None
    with _WritingFirst() as ctrl_c:
        result = Result(scene, raw, summarize(scene, raw, wall_time_s=time.perf_counter() - start))
        if out is not None:
            writers.join()
            try:
                write_results(out, scene, raw, result.summary, figures, xdmf)
                result.out = Path(out)
            except KeyboardInterrupt:
                raise KeyboardInterrupt(
                    f"interrupted while writing results; nothing was " f"replaced in {out}"
                ) from None
    if ctrl_c.received:
        raw["stop"]["late_interrupt"] = True
    return result


def _failed(exc: BaseException, scene: Scene, raw: dict, out, figures, xdmf, start: float):
    """The engine's failure inside its loop, its results so far (``raw``) written to ``out``
    like an early stop's: the same exception, its message naming the case, the path time of
    the last completed increment and the folder, with the partial Result as ``result``."""
    result = Result(scene, raw, summarize(scene, raw, wall_time_s=time.perf_counter() - start))
    where = f"results up to t = {raw['stop']['t']:.6g}"
    if out is not None:
        write_results(out, scene, raw, result.summary, figures, xdmf)
        result.out = Path(out)
        where += f" in {out}"
    failure = type(exc)(f"{scene.case.name}: {exc} ({where})")
    failure.result = result
    return failure


class _WritingFirst:
    """Once the engine has returned, a first Ctrl-C is held until the summary and the files are
    written (``received``; the run's stop then says ``late_interrupt``, as for a Ctrl-C during
    the engine's last increment), so a finished computation is not lost to a keystroke; a
    second Ctrl-C aborts. Only where Python's default handler is in place, on the main thread."""

    def __enter__(self):
        self.received, self.previous = False, None
        if (
            threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGINT) is signal.default_int_handler
        ):
            self.previous = signal.signal(signal.SIGINT, self._hold)
        return self

    def _hold(self, signum, frame):
        if self.received:
            raise KeyboardInterrupt
        self.received = True
        print("slipstep: writing the results first (Ctrl-C again to abort)", file=sys.stderr)

    def __exit__(self, *exc):
        if self.previous is not None:
            signal.signal(signal.SIGINT, self.previous)
        return False


def _load_writers(scene: Scene, out, figures: bool | None, xdmf: bool | None):
    """A started thread that imports what writing ``out`` will need (matplotlib and its font
    for the figures, meshio for the XDMF: ~0.4 s together) while the engine runs, which
    releases the GIL; a no-op thread without ``out``."""
    options = scene.case.record.output
    wanted = []
    if out is not None and (options.figures if figures is None else figures):
        from .figures.frame import preload

        wanted.append(preload)
    if out is not None and (options.xdmf if xdmf is None else xdmf):
        wanted.append(lambda: __import__("meshio"))

    def load():
        try:
            for step in wanted:
                step()
        except Exception:  # noqa: BLE001 - only a head start: the writer meets the error itself
            pass

    thread = threading.Thread(target=load, name="slipstep-load-writers", daemon=True)
    thread.start()
    return thread


def run_case(
    case_or_path: Case | str | Path | None = None,
    out: str | Path | None = None,
    overrides=(),
    progress: bool = False,
) -> tuple[dict, dict]:
    """:func:`run` returning ``(result dict, summary)`` (docs/engine_api.md), no progress by
    default: the form before :class:`~slipstep.output.result.Result`, kept for existing callers."""
    result = run(case_or_path, out, overrides, progress)
    return result.raw, result.summary
