"""Every file of a run in one folder, all or nothing: the writers of :mod:`slipstep.output`,
the figures of :mod:`slipstep.figures` and the resolved case (``case.toml``) write into a
staging folder inside the output folder, which is then renamed into place, so a run that
fails half-way leaves the previous results intact."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from . import writers as output
from ..errors import InputError
from .resolved_case import resolved_case_text
from ..measures.resultants import write_history_csv


def write_results(
    out: str | Path,
    scene,
    result,
    summary: dict,
    figures: bool | None = None,
    xdmf: bool | None = None,
) -> list[Path]:
    """Write every output file of a run into ``out`` (created if needed); returns the paths.
    ``figures`` and ``xdmf`` default to the case's ``[output]`` choices.

    Staged in ``out/.partial-<pid>`` and renamed into place at the end.
    """
    out = Path(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        why = "it is a regular file" if out.is_file() else exc.strerror
        raise InputError(
            f"{out}: cannot write the results there ({why}): choose another " f"--out folder"
        ) from None
    options = scene.case.record.output
    figures = options.figures if figures is None else figures
    xdmf = options.xdmf if xdmf is None else xdmf
    stage = out / f".partial-{os.getpid()}"
    if stage.exists():
        shutil.rmtree(stage)
    stage.mkdir()
    try:
        snaps = result.get("snapshots", [])
        output.write_events_csv(stage / "events.csv", scene, result)
        write_history_csv(stage / "history.csv", scene, result)
        if snaps and len(scene.pair_xy):
            output.write_profile_csv(stage / "contact_profile.csv", scene, snaps[-1])
        if xdmf and snaps:
            output.write_xdmf(stage, scene, result)
        if figures:
            scene.idealisation.write_figures(stage, scene, result, summary)
        output.write_summary_json(stage / "summary.json", summary)
        (stage / "case.toml").write_text(case_toml(scene, summary), encoding="utf-8")
        written = []
        for item in sorted(stage.iterdir()):
            os.replace(item, out / item.name)
            written.append(out / item.name)
        return written
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def case_toml(scene, summary: dict) -> str:
    """The run's ``case.toml``: its resolved case (:mod:`slipstep.output.resolved_case`), headed by
    where it came from and the versions it ran with (``summary["versions"]``)."""
    case = scene.case
    sets = "".join(f" --set {item}" for item in case.overrides)
    made = ", ".join(f"{k} {v}" for k, v in summary.get("versions", {}).items())
    header = [
        "The case of this run, resolved (every default filled in, the overrides applied):",
        f"  {case.source}{sets}",
        "Rerun it: slipstep run case.toml",
        *([f"Made with {made}."] if made else []),
    ]
    return resolved_case_text(case, scene.given_meshes, header)
