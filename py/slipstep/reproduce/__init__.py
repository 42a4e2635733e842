"""``slipstep reproduce --out DIR [--quick]``: the paper's Table 1 and Figs. 5-16, regenerated.

Abdalla, Ali-Eldin & Ghazy, §5: every scene is run through the sweep runner
(:mod:`slipstep.sweep`, local processes), each writing its full results (XDMF series, CSV,
per-run PNGs) under ``DIR/runs/<scene>``; Fig. 10 is the study ``studies/fig10_onset_of_yield.toml``
run by the same runner under ``DIR/fig10``.  Then the paper's figures are drawn with the
closed-form curves overlaid wherever one exists, and ``DIR/report.md`` gathers them with what
agrees, what does not, and why; ``DIR/reproduce.json`` holds every number and check.

Scenes
  * Hertz cylinder (§5.1): the built-in case (R = 125 mm, E = 70 GPa, nu = 0.3, P = 1000 N/mm,
    plane strain, quarter model); elastoplastic with Al-5%Mg Sy = 200 MPa and linear hardening
    H' = 700 MPa (the paper gives no hardening value: ours); mu = 0, 0.1, 0.35.
  * Block on a half-space (§5.2): ``cases/paper_block_elastic.toml`` (q = 1.2 MPa, mu = 0.2, plane
    strain) and ``cases/paper_block_plastic.toml`` (q = 36 MPa, plane stress, mu = 0 and 0.2).

Axisymmetric page (:mod:`slipstep.reproduce.axisymmetric`): ``DIR/axisymmetric.md``,
the Hertz sphere, first yield against Huber, the thick sphere against Lame and Hill, and the
elastic-plastic sphere on a rigid flat against Kogut & Etsion and Jackson & Green; linked
from report.md.

A rerun into the same DIR reuses the finished runs (the sweep runner resumes); delete DIR to
start afresh.  ``--quick`` uses coarse meshes (for the tests).

Modules: ``scenes`` (the runs and the paper's and closed-form values), ``numbers`` (what is
measured, reproduce.json), ``figures``, ``report`` (report.md: the template ``report.md``
filled with the numbers), ``axisymmetric`` (its page).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from .. import sweep
from ..output.writers import json_safe
from . import axisymmetric
from .figures import draw
from .numbers import collect, onset_rows
from .report import write_report
from .scenes import FULL, QUICK, Run, fig10_study, scene_tasks


def reproduce(out: str | Path, quick: bool = False, workers: int | None = None, log=print) -> dict:
    """Run every scene, draw every figure, write report.md and reproduce.json; returns the
    numbers (also in reproduce.json)."""
    start = time.perf_counter()
    settings = QUICK if quick else FULL
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    runs, probe_failed, study = run_scenes(settings, out, workers, log)
    t_runs = time.perf_counter() - start
    fig10_rows = onset_rows(study, out / "fig10")
    numbers = collect(settings, runs, probe_failed, fig10_rows, out / "runs")
    figures, timeline = draw(out, runs, numbers)
    numbers["events"] = {
        label: {k: int(v) for k, v in zip(*np.unique(r.data["events_kind"], return_counts=True))}
        for label, r in timeline
    }
    numbers["wall_time_s"] = {
        "runs": t_runs,
        "total": time.perf_counter() - start,
        "solver_sum": float(
            sum(r["wall_time_s"] for r in numbers["runs"].values())
            + sum(
                sweep.load_summary(out / "fig10", t["case_id"])["wall_time_s"]
                for t in study.tasks()
            )
        ),
    }
    numbers["figures"] = {k: p.name for k, p in figures.items()}
    numbers["axisymmetric"] = axisymmetric.page(out, quick, workers, log)
    write_report(out / "report.md", numbers)
    numbers["wall_time_s"]["total"] = time.perf_counter() - start
    with open(out / ".reproduce.json.partial", "w") as fh:
        json.dump(json_safe(numbers), fh, indent=2)
        fh.write("\n")
    (out / ".reproduce.json.partial").replace(out / "reproduce.json")
    if log:
        log(
            f"reproduce: {len(figures)} figures, report.md in {out} "
            f"({numbers['wall_time_s']['total']:.1f} s)"
        )
    return numbers


def run_scenes(settings, out: Path, workers, log) -> tuple[dict, dict, sweep.Study]:
    """Run every scene into ``out/runs`` and the Fig. 10 study into ``out/fig10`` (finished
    runs are reused): the finished runs by id, the probes that failed (id -> message), and
    the study."""
    tasks = scene_tasks(settings)
    rep = sweep.run_tasks(tasks, out / "runs", workers=workers, log=log, name="reproduce")
    _raise_failures(rep)
    probe_failed = {cid: msg for cid, msg in rep.failed.items() if cid.startswith("probe_")}
    study = fig10_study(settings)
    _raise_failures(sweep.run_sweep(study, out / "fig10", workers=workers, log=log))
    runs = {
        t["case_id"]: Run(out / "runs", t["case_id"])
        for t in tasks
        if t["case_id"] not in probe_failed
    }
    return runs, probe_failed, study


def _raise_failures(rep) -> None:
    if rep.interrupted:
        raise KeyboardInterrupt
    failed = {cid: msg for cid, msg in rep.failed.items() if not cid.startswith("probe_")}
    if failed:
        cid, msg = next(iter(failed.items()))
        raise RuntimeError(f"run {cid} failed: {msg}")


def main(args) -> int:
    try:
        reproduce(
            args.out, quick=args.quick, workers=args.workers, log=lambda m: print(m, flush=True)
        )
    except FileNotFoundError as exc:
        print(f"slipstep: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:
        print(f"slipstep: error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(
            f"slipstep: reproduce interrupted; rerun the same command to resume "
            f"(finished runs in {args.out} are kept)",
            file=sys.stderr,
        )
        return 130
    return 0
