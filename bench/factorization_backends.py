"""Factorization backends on the 3D elastic Hertz sphere (cases/hertz_sphere_3d.toml): faer
in-process against PETSc's MUMPS on 1 and 2 MPI ranks, at several mesh sizes.

    .venv/bin/python bench/factorization_backends.py [--h 0.02 0.0125 0.0105] [--only mumps2]

writes its table to bench/factorization_backends_table.md (bench/factorization_backends.md
quotes it with the conclusions).

Each run is a whole ``slipstep`` run without output files, one process per rank (``mpirun -n 2``
for two ranks); every rank reports its peak resident memory (getrusage) and the engine's timers:
factorization (the numeric factorizations, the first one's analysis included), flexibility (G,
the contact DOFs' block of K^-1), solves, and the run's wall time. As root OpenMPI needs
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 (set here).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "cases" / "hertz_sphere_3d.toml"
BACKENDS = (("faer", None), ("mumps", 1), ("mumps", 2))


def worker(h: float, factorization: str, folder: Path) -> None:
    """One rank's run: its report as ``folder/rank<r>.json`` (the ranks' stdout interleave)."""
    from slipstep import ranks
    from slipstep.runner import run

    start = time.perf_counter()
    result = run(
        CASE,
        overrides=[f"mesh.h_contact={h}", f"solver.factorization={factorization}"],
        progress=False,
    )
    s = result.summary
    report = {
        "rank": ranks.rank(),
        "n_dofs": s["n_dofs"],
        "n_pairs": s["n_pairs"],
        "n_events": s["n_events"],
        "timings": s["engine_timings_s"],
        "wall_s": time.perf_counter() - start,
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    }
    (folder / f"rank{report['rank']}.json").write_text(json.dumps(report))


def measure(h: float, factorization: str, ranks: int | None) -> list[dict]:
    folder = Path(tempfile.mkdtemp(prefix="factorization_backends_"))
    command = [sys.executable, __file__, "--worker", str(h), factorization, str(folder)]
    if ranks is not None:
        command = ["mpirun", "-n", str(ranks), *command]
    env = dict(
        os.environ,
        OMPI_ALLOW_RUN_AS_ROOT="1",
        OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
        OMPI_MCA_rmaps_base_oversubscribe="1",
        MPLBACKEND="Agg",
    )
    subprocess.run(command, capture_output=True, text=True, env=env, check=True)
    return [json.loads(p.read_text()) for p in sorted(folder.glob("rank*.json"))]


def row(h: float, name: str, ranks: int | None, reports: list[dict]) -> str:
    r0 = reports[0]
    t = r0["timings"]
    memory = " / ".join(f"{r['peak_rss_mb']:.0f}" for r in reports)
    label = name if ranks is None else f"{name}, {ranks} rank{'s' * (ranks > 1)}"
    return (
        f"| {h} | {r0['n_dofs']} | {r0['n_pairs']} | {r0['n_events']} | {label} | "
        f"{t['factorization']:.2f} | {t['flexibility']:.2f} | {t['solves']:.2f} | "
        f"{t['events']:.2f} | {max(r['wall_s'] for r in reports):.1f} | {memory} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--h", type=float, nargs="+", default=[0.02, 0.0125, 0.0105])
    parser.add_argument(
        "--out", type=Path, default=ROOT / "bench" / "factorization_backends_table.md"
    )
    parser.add_argument("--worker", nargs=3, metavar=("H", "FACTORIZATION", "FOLDER"))
    parser.add_argument("--only", choices=["faer", "mumps1", "mumps2"], help="one backend")
    args = parser.parse_args()
    if args.worker:
        return worker(float(args.worker[0]), args.worker[1], Path(args.worker[2]))
    lines = [
        "| h | DOFs | pairs | events | factorization | factorize [s] | G [s] | solves [s] | "
        "events [s] | run [s] | peak RSS per rank [MB] |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for h in args.h:
        for name, ranks in BACKENDS:
            if args.only and args.only != name + (str(ranks) if ranks else ""):
                continue
            lines.append(row(h, name, ranks, measure(h, name, ranks)))
            print(lines[-1], flush=True)
    args.out.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
