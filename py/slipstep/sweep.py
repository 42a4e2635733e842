"""Parameter studies: ``slipstep sweep STUDY.toml [--out DIR] [--workers N] [--mpi]``.

A study is a TOML file::

    [study]
    name = "fig10_onset_of_yield"        # default: the file name without .toml
    description = "..."
    base = "default"                     # a case file (relative to the study file) or "default"
                                         # (the built-in Hertz cylinder)
    set = ["material.Sy=200", "material.H=700"]   # overrides applied to every case

    [vary]                               # case keys (spelled as --set spells them), each with a
    "contact.mu" = [0.0, 0.05, 0.1]      # list of values; the cases are the cartesian product,
                                         # the first key varying slowest

    [output]
    stop_at_first_yield = false          # end each run right after its first yield event
    results = false                      # also write each case's full results (XDMF, CSV, PNG)
                                         # as `slipstep run` does
    fields = false                       # store the final mesh fields in result.npz

Every case runs in its own process: local processes by default
(:class:`concurrent.futures.ProcessPoolExecutor`, all cores), or MPI ranks through mpi4py's pool
executor (``--mpi``; launch with ``mpirun -n N python -m mpi4py.futures -m slipstep sweep ...
--mpi``: rank 0 runs the sweep, the other N-1 ranks are workers).

Results: ``OUT/<case-id>/summary.json`` (the run's summary plus a ``sweep`` block: case id,
parameters, overrides), ``OUT/<case-id>/case.toml`` (the case as it ran, every default filled
in: ``slipstep run`` reruns it) and ``OUT/<case-id>/result.npz`` (event history, steps, contact
profiles at every snapshot, contact growth; mesh fields with ``fields = true``).  Workers send their
results back to rank 0 / the parent process, which writes each case as soon as it finishes:
staged in ``OUT/.partial-<case-id>`` and renamed into place, so a case folder exists only when
it is complete.  A sweep that is interrupted resumes (same command) without redoing the cases
whose folder holds a summary with the same overrides and options.  At the end
``OUT/summaries.csv`` tabulates every case (parameters + scalar summary values).
With ``results = true`` under MPI the workers write their files themselves: ``OUT`` must then be
on a filesystem that every rank sees.
"""

from __future__ import annotations

import concurrent.futures as cf
import csv
import hashlib
import itertools
import json
import os
import re
import shutil
import sys
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import shipped
from .errors import InputError
from .output.writers import json_safe, write_summary_json
from .output.summary import contact_text

STUDY_KEYS = {"name", "description", "base", "set"}
OUTPUT_KEYS = {"stop_at_first_yield": False, "results": False, "fields": False}


class StudyError(InputError):
    """A problem in a study file; one line naming the file, the key and the fix."""


@dataclass
class Study:
    """A parsed study: base case, fixed overrides, varied keys (ordered), output options."""

    name: str
    base: str | None  # case path (absolute) or None = built-in default
    set: list[str] = field(default_factory=list)
    vary: dict[str, list] = field(default_factory=dict)
    output: dict = field(default_factory=lambda: dict(OUTPUT_KEYS))
    description: str = ""
    source: str = "<study>"

    def tasks(self) -> list[dict]:
        """The cases: cartesian product of ``vary`` (first key slowest), one task dict each."""
        keys = list(self.vary)
        combos = list(itertools.product(*(self.vary[k] for k in keys))) if keys else [()]
        tasks = []
        for i, values in enumerate(combos):
            params = dict(zip(keys, values))
            overrides = list(self.set) + [f"{k}={toml_literal(v)}" for k, v in params.items()]
            tasks.append(
                {
                    "index": i,
                    "case_id": case_id(i, params),
                    "params": params,
                    "base": self.base,
                    "overrides": overrides,
                    "options": dict(self.output),
                }
            )
        return tasks


# --------------------------------------------------------------------------- study files
def toml_literal(value) -> str:
    """A Python value as the TOML literal ``--set`` expects."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_literal(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} as a TOML value")


def case_id(index: int, params: dict) -> str:
    """``003-contact.mu=0.15``: index plus the varied values, safe as a folder name."""
    parts = [f"{k}={toml_literal(v)}" for k, v in params.items()]
    text = re.sub(r"[^A-Za-z0-9._=+-]+", "_", "_".join(parts)).strip("_")
    if len(text) > 80:
        text = text[:60] + "-" + hashlib.sha1(text.encode()).hexdigest()[:10]
    return f"{index:03d}-{text}" if text else f"{index:03d}"


def load_study(path: str | Path, extra_set=()) -> Study:
    """Read and check a study file (``extra_set``: more overrides for every case)."""
    path = Path(path)
    source = str(path)
    try:
        raw = tomllib.loads(path.read_text())
    except FileNotFoundError:
        raise StudyError(f"{source}: no such study file") from None
    except tomllib.TOMLDecodeError as exc:
        raise StudyError(f"{source}: invalid TOML: {exc}") from None
    return parse_study(raw, source, path.parent, default_name=path.stem, extra_set=extra_set)


def parse_study(
    raw: dict,
    source: str = "<study>",
    base_dir: str | Path = ".",
    default_name: str = "study",
    extra_set=(),
) -> Study:
    """A study from its TOML document (a dict)."""
    unknown = set(raw) - {"study", "vary", "output"}
    if unknown:
        raise StudyError(
            f"{source}: unknown table [{sorted(unknown)[0]}]: use [study], [vary] " f"and [output]"
        )
    st = raw.get("study", {})
    bad = set(st) - STUDY_KEYS
    if bad:
        raise StudyError(
            f"{source}: study.{sorted(bad)[0]} is not a study key: use "
            f"{', '.join(sorted(STUDY_KEYS))}"
        )
    base = st.get("base", "default")
    if not isinstance(base, str) or not base:
        raise StudyError(f'{source}: study.base must be a case file path or "default"')
    if base == "default":
        base_path = None
    else:
        base_path = str((Path(base_dir) / base).resolve())
        if not Path(base_path).exists():
            raise StudyError(f"{source}: study.base = {base!r}: no such case file ({base_path})")
    fixed = st.get("set", [])
    if not isinstance(fixed, list) or any(not isinstance(s, str) or "=" not in s for s in fixed):
        raise StudyError(f'{source}: study.set must be a list of "KEY=VALUE" strings')
    vary = raw.get("vary", {})
    for key, values in vary.items():
        if not isinstance(values, list) or not values:
            raise StudyError(f"{source}: vary.{key} must be a non-empty list of values")
    out = dict(OUTPUT_KEYS)
    for key, value in raw.get("output", {}).items():
        if key not in OUTPUT_KEYS:
            raise StudyError(
                f"{source}: output.{key} is not an output option: use " f"{', '.join(OUTPUT_KEYS)}"
            )
        if not isinstance(value, bool):
            raise StudyError(f"{source}: output.{key} must be true or false")
        out[key] = value
    study = Study(
        name=st.get("name", default_name),
        base=base_path,
        set=list(fixed) + list(extra_set),
        vary=dict(vary),
        output=out,
        description=st.get("description", ""),
        source=source,
    )
    check_study(study)
    return study


def check_study(study: Study) -> None:
    """Validate the base case with every override of the first and the last case (so a wrong
    key fails at once, not in a worker), without meshing."""
    from .case import CaseError, load_case

    tasks = study.tasks()
    for task in {0: tasks[0], len(tasks) - 1: tasks[-1]}.values():
        try:
            load_case(task["base"], task["overrides"])
        except CaseError as exc:
            raise StudyError(f"{study.source}: case {task['case_id']}: {exc}") from None


# --------------------------------------------------------------------------- one case
def result_arrays(scene, result, fields: bool = False) -> dict[str, np.ndarray]:
    """The compact record of a run for result.npz (see the module docstring)."""
    from .measures.contact_edges import contact_growth, contact_profile
    from .output.fields import centroids
    from .output.history import ELEMENT_EVENTS

    ev = result["events"]
    kinds = np.asarray(list(ev["kind"]), dtype="U16")
    entity = np.asarray(ev["entity"], dtype=np.int64)
    centres = centroids(scene.nodes, scene.triangles)
    xy = np.zeros((len(entity), 2))
    for k, (kind, e) in enumerate(zip(kinds, entity)):
        xy[k] = centres[e] if kind in ELEMENT_EVENTS else scene.pair_xy[e]
    arrays = {
        "events_step": np.asarray(ev["step"], dtype=np.int64),
        "events_load_fraction": np.asarray(ev["load_fraction"], dtype=float),
        "events_kind": kinds,
        "events_entity": entity,
        "events_xy": xy,
    }
    for key, value in result["steps"].items():
        arrays[f"steps_{key}"] = np.asarray(value)
    snaps = result.get("snapshots", [])
    arrays["snap_load_fraction"] = np.asarray([s["load_fraction"] for s in snaps], dtype=float)
    if len(scene.pair_xy):
        profiles = [contact_profile(scene, s) for s in snaps]
        order = (
            contact_profile(scene, snaps[-1])["pair"] if snaps else np.argsort(scene.pair_xy[:, 0])
        )
        arrays["profile_pair"] = np.asarray(order)
        arrays["profile_x"] = scene.pair_xy[order, 0]
        arrays["profile_y"] = scene.pair_xy[order, 1]
        for key in ("pressure", "tangential_stress", "rtd", "status", "gap"):
            arrays[f"profile_{key}"] = (
                np.array([p[key] for p in profiles]) if profiles else np.zeros((0, len(order)))
            )
        arrays["closure_fraction"] = np.asarray(result["closure_fraction"], dtype=float)[order]
        arrays["predicted_closure"] = np.asarray(result["predicted_closure"], dtype=float)[order]
        gf, gx = contact_growth(scene, result)
        arrays["growth_load_fraction"], arrays["growth_x"] = gf, gx
    if fields and snaps:
        arrays["snap_u"] = np.array([np.asarray(sn["u"]).reshape(-1, 2) for sn in snaps])
        last = snaps[-1]
        arrays.update(
            {
                "nodes": scene.nodes,
                "triangles": scene.triangles,
                "element_body": scene.element_body,
                "u": np.asarray(last["u"]).reshape(-1, 2),
                "stress": np.asarray(last["stress"], dtype=float).reshape(-1, 4),
            }
        )
        for key in ("plastic_strain", "plastic"):
            if key in last:
                arrays[key] = np.asarray(last[key])
    return arrays


def run_task(task: dict) -> dict:
    """Worker: solve one case and return its summary and arrays (the parent writes them).
    Never raises for a bad case: the error comes back as ``{"error": message}``."""
    from .output.results import case_toml, write_results
    from .runner import prepare, solve
    from .output.summary import summarize

    start = time.perf_counter()
    out = {"case_id": task["case_id"], "host": os.uname().nodename, "pid": os.getpid()}
    try:
        first_yield = (
            ["solver.stop_at_first_yield=true"]
            if task["options"].get("stop_at_first_yield")
            else []
        )
        scene = prepare(task["base"], [*task["overrides"], *first_yield])
        result = solve(scene)
        summary = summarize(scene, result, wall_time_s=time.perf_counter() - start)
        arrays = result_arrays(scene, result, task["options"].get("fields", False))
        interrupted = result["stop"]["kind"] == "interrupted"
        if task["options"].get("results") and not interrupted:
            try:
                write_results(task["stage"], scene, result, summary)
            except Exception as exc:  # noqa: BLE001 - a broken plot must not lose the run
                summary["figures_error"] = f"{type(exc).__name__}: {exc}"
                write_results(task["stage"], scene, result, summary, figures=False)
    except KeyboardInterrupt:
        out["interrupted"] = True
        return out
    except Exception as exc:  # noqa: BLE001 - reported per case, the sweep goes on
        out["error"] = f"{type(exc).__name__}: {exc}"
        return out
    out.update(
        summary=summary, arrays=arrays, interrupted=interrupted, case_toml=case_toml(scene, summary)
    )
    return out


# --------------------------------------------------------------------------- files
def _identity(task: dict) -> dict:
    return {
        "base": task["base"],
        "overrides": list(task["overrides"]),
        "options": dict(task["options"]),
    }


def is_done(out: Path, task: dict) -> bool:
    """A finished case: its folder holds a summary written for the same overrides/options."""
    path = out / task["case_id"] / "summary.json"
    if not path.exists():
        return False
    try:
        with open(path) as fh:
            recorded = json.load(fh).get("sweep", {})
    except (OSError, json.JSONDecodeError):
        return False
    return {k: recorded.get(k) for k in ("base", "overrides", "options")} == _identity(task)


def write_case(out: Path, task: dict, payload: dict) -> Path:
    """Write one finished case atomically: stage, then rename the folder into place."""
    stage = out / f".partial-{task['case_id']}"
    stage.mkdir(parents=True, exist_ok=True)
    summary = dict(payload["summary"])
    summary["sweep"] = {
        "case_id": task["case_id"],
        "params": task["params"],
        "host": payload.get("host"),
        **_identity(task),
    }
    np.savez_compressed(stage / "result.npz", **payload["arrays"])
    write_summary_json(stage / "summary.json", summary)
    (stage / "case.toml").write_text(payload["case_toml"], encoding="utf-8")
    final = out / task["case_id"]
    if final.exists():
        shutil.rmtree(final)
    os.rename(stage, final)
    return final


def load_summary(out: str | Path, cid: str) -> dict:
    with open(Path(out) / cid / "summary.json") as fh:
        return json.load(fh)


def load_arrays(out: str | Path, cid: str) -> dict[str, np.ndarray]:
    with np.load(Path(out) / cid / "result.npz") as data:
        return {k: data[k] for k in data.files}


def _flatten(d: dict, prefix: str = "") -> dict:
    flat = {}
    for k, v in d.items():
        if k == "sweep":
            continue
        if isinstance(v, dict):
            flat.update(_flatten(v, f"{prefix}{k}."))
        elif isinstance(v, (int, float, str, bool)) or v is None:
            flat[f"{prefix}{k}"] = v
    return flat


FIRST_COLUMNS = (
    "case",
    "final_load_fraction",
    "first_yield_load_fraction",
    "first_yield_x",
    "first_yield_depth",
    "contact_half_width",
    "stick_half_width",
    "peak_pressure",
    "n_events",
    "n_plastic_elements",
    "wall_time_s",
)


def write_table(out: Path, tasks: list[dict]) -> Path:
    """``summaries.csv``: one row per finished case, parameters first."""
    rows = []
    for task in tasks:
        if (out / task["case_id"] / "summary.json").exists():
            s = load_summary(out, task["case_id"])
            rows.append((task, _flatten(s)))
    params = list(dict.fromkeys(k for t in tasks for k in t["params"]))
    keys = sorted({k for _, flat in rows for k in flat})
    cols = [k for k in FIRST_COLUMNS if k in keys] + [k for k in keys if k not in FIRST_COLUMNS]
    path = out / "summaries.csv"
    tmp = out / ".summaries.csv.partial"
    with open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case_id", *params, *cols])
        for task, flat in rows:
            w.writerow(
                [
                    task["case_id"],
                    *(task["params"].get(p, "") for p in params),
                    *("" if flat.get(c) is None else flat.get(c) for c in cols),
                ]
            )
    os.replace(tmp, path)
    return path


# --------------------------------------------------------------------------- the runner
def default_workers() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def _executor(workers: int | None, mpi: bool):
    if mpi:
        try:
            from mpi4py.futures import MPIPoolExecutor
        except ImportError as exc:
            raise StudyError(f"--mpi needs mpi4py ({exc}): install python3-mpi4py") from None
        # main=False: the workers must not re-run the parent's __main__ (`-m slipstep` is the
        # CLI itself); run_task is imported from slipstep.sweep.
        return MPIPoolExecutor(max_workers=workers, main=False)
    # "spawn", not fork: a forked child of a process whose engine (faer/rayon) already started
    # threads can inherit a held lock and hang (seen under pytest).
    import multiprocessing

    return cf.ProcessPoolExecutor(
        max_workers=workers or default_workers(),
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_ignore_sigint,
    )


def _ignore_sigint() -> None:
    """Local workers leave Ctrl-C to the parent, which cancels the pending cases and ends the
    workers (their unfinished case is simply not written)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _test_interrupt(finished: int) -> None:
    """``SLIPSTEP_TEST_INTERRUPT=case=N``: a real SIGINT in this process once N cases are
    written, so that tests interrupt a sweep at a known case instead of racing a clock (the
    engine reads ``event=N`` the same way)."""
    if os.environ.get("SLIPSTEP_TEST_INTERRUPT", "").strip() == f"case={finished}":
        import signal

        signal.raise_signal(signal.SIGINT)


def _stop(executor) -> None:
    """Cancel what has not started and end the local worker processes now."""
    procs = list((getattr(executor, "_processes", None) or {}).values())  # gone after shutdown
    executor.shutdown(wait=False, cancel_futures=True)
    for proc in procs:
        if proc.is_alive():
            proc.terminate()


@dataclass
class SweepReport:
    out: Path
    tasks: list[dict]
    done: list[str]  # case ids finished in this call
    skipped: list[str]  # already finished before (resumed)
    failed: dict  # case id -> error message
    interrupted: bool = False

    @property
    def complete(self) -> bool:
        return not self.failed and not self.interrupted


def run_sweep(
    study: Study, out: str | Path, workers: int | None = None, mpi: bool = False, log=print
) -> SweepReport:
    """Run every case of ``study`` not already finished in ``out``; see the module docstring."""
    return run_tasks(
        study.tasks(),
        out,
        workers=workers,
        mpi=mpi,
        log=log,
        name=study.name,
        about={"description": study.description, "source": study.source},
    )


def run_tasks(
    tasks: list[dict],
    out: str | Path,
    workers: int | None = None,
    mpi: bool = False,
    log=print,
    name: str = "sweep",
    about: dict | None = None,
) -> SweepReport:
    """Run the tasks (dicts as made by :meth:`Study.tasks`: case_id, params, base, overrides,
    options) not already finished in ``out``, in worker processes, writing each as it ends."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    tasks = [dict(t) for t in tasks]
    ids = [t["case_id"] for t in tasks]
    if len(set(ids)) != len(ids):
        raise StudyError(f"{name}: duplicate case ids")
    for stale in out.glob(".partial-*"):  # left by a sweep that was killed
        shutil.rmtree(stale, ignore_errors=True)
    with open(out / ".study.json.partial", "w") as fh:
        json.dump(json_safe({"name": name, **(about or {}), "tasks": tasks}), fh, indent=2)
    os.replace(out / ".study.json.partial", out / "study.json")

    todo = [t for t in tasks if not is_done(out, t)]
    skipped = [t["case_id"] for t in tasks if t not in todo]
    report = SweepReport(out=out, tasks=tasks, done=[], skipped=skipped, failed={})
    if log and skipped:
        log(f"{name}: {len(skipped)} of {len(tasks)} cases already done in {out}")
    if todo:
        for t in todo:
            t["stage"] = str(out / f".partial-{t['case_id']}")
        executor = _executor(workers, mpi)
        start = time.perf_counter()
        try:
            futures = {executor.submit(run_task, t): t for t in todo}
            for fut in cf.as_completed(futures):
                task = futures[fut]
                payload = fut.result()
                n = len(report.done) + len(report.failed) + len(skipped) + 1
                if payload.get("interrupted"):
                    report.interrupted = True
                    continue
                if "error" in payload:
                    report.failed[task["case_id"]] = payload["error"]
                    shutil.rmtree(task["stage"], ignore_errors=True)
                    if log:
                        log(f"[{n}/{len(tasks)}] {task['case_id']}: FAILED: {payload['error']}")
                    continue
                write_case(out, task, payload)
                report.done.append(task["case_id"])
                if log:
                    log(f"[{n}/{len(tasks)}] {task['case_id']}: {_brief(payload['summary'])}")
                _test_interrupt(len(report.done))
        except KeyboardInterrupt:
            report.interrupted = True
            _stop(executor)
        except BaseException:
            _stop(executor)
            raise
        else:
            executor.shutdown(wait=True)
        if log:
            log(
                f"{name}: {len(report.done)} cases run in "
                f"{time.perf_counter() - start:.1f} s ({'MPI' if mpi else 'local processes'})"
            )
    write_table(out, tasks)
    return report


def _brief(s: dict) -> str:
    parts = [f"f = {s['final_load_fraction']:.4g}"]
    if s.get("first_yield_load_fraction") is not None:
        parts.append(f"first yield at f = {s['first_yield_load_fraction']:.4g}")
    if contact_text(s):
        parts.append(contact_text(s))
    parts.append(f"{s['n_events']} events, {s['wall_time_s']:.2f} s")
    return ", ".join(parts)


def main(args) -> int:
    """``slipstep sweep`` (called by the CLI with parsed arguments)."""
    study = load_study(shipped.resolve(args.study, "studies"), getattr(args, "overrides", []) or [])
    out = args.out or f"results/{study.name}"
    log = None if getattr(args, "quiet", False) else (lambda m: print(m, flush=True))
    report = run_sweep(study, out, workers=args.workers, mpi=args.mpi, log=log)
    if report.interrupted:
        print(
            f"slipstep: sweep interrupted: {len(report.done) + len(report.skipped)} of "
            f"{len(report.tasks)} cases are done in {out}; run the same command again to "
            f"resume",
            file=sys.stderr,
        )
        return 130
    if report.failed:
        for cid, msg in report.failed.items():
            print(f"slipstep: error: case {cid}: {msg}", file=sys.stderr)
        return 1
    if log:
        log(f"{out}/summaries.csv")
    return 0
