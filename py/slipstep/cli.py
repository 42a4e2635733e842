"""The ``slipstep`` command.

    slipstep run [CASE.toml] [--out DIR] [--set KEY=VALUE ...] [--quiet]
    slipstep check [CASE.toml] [--set KEY=VALUE ...]
    slipstep crosscheck [CASE.toml] [--out DIR] [--set KEY=VALUE ...] [--steps 5,10,20,50]
    slipstep sweep STUDY.toml [--out DIR] [--workers N] [--mpi]
    slipstep reproduce [--out DIR] [--quick]
    slipstep study stability [--out DIR] [--quick]

Without CASE the built-in Hertz cylinder (paper §5.1) runs.  Errors print one line
``slipstep: error: ...`` on stderr and exit 2; Ctrl-C writes what was computed and exits 130.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

from .case import CaseError, load_case
from .mesh import MeshError
from .model import build_scene
from .output import one_line, summarize, write_results
from .runner import EngineMissing, solve

EXIT_ERROR = 2
EXIT_INTERRUPTED = 130


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="slipstep", description="Event-driven frictional contact "
                                "(adaptive incremental, no load steps, no penalties).")
    sub = p.add_subparsers(dest="command", required=True)
    for name, text in (("run", "solve a case and write its results"),
                       ("check", "validate and mesh a case, print its size, do not solve")):
        s = sub.add_parser(name, help=text, description=text)
        s.add_argument("case", nargs="?", default=None,
                       help="case file (default: the built-in Hertz cylinder)")
        s.add_argument("--set", dest="overrides", action="append", default=[],
                       metavar="KEY=VALUE", help="override a key, e.g. --set contact.mu=0.35 "
                       "(repeatable; see cases/README.md)")
        if name == "run":
            s.add_argument("--out", default=None, help="output folder (default: results/<case>)")
            s.add_argument("--quiet", action="store_true", help="no progress, no summary line")
    s = sub.add_parser("sweep", help="run a parameter study (local processes or MPI)",
                       description="run every case of a study TOML (see slipstep.sweep); "
                       "finished cases are kept, so a rerun resumes")
    s.add_argument("study", help="study file (studies/*.toml)")
    s.add_argument("--out", default=None, help="output folder (default: results/<study>)")
    s.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    s.add_argument("--mpi", action="store_true", help="use mpi4py.futures.MPIPoolExecutor: "
                   "mpirun -n N python -m mpi4py.futures -m slipstep sweep STUDY --mpi")
    s.add_argument("--set", dest="overrides", action="append", default=[],
                   metavar="KEY=VALUE", help="override a key in every case (repeatable)")
    s.add_argument("--quiet", action="store_true", help="no progress lines")
    s = sub.add_parser("reproduce", help="regenerate the paper's table and figures + report.md",
                       description="regenerate Table 1 and Figs. 5-16 of the paper with "
                       "closed-form overlays, and report.md")
    s.add_argument("--out", default="results/reproduce", help="output folder")
    s.add_argument("--quick", action="store_true", help="coarse meshes (for tests)")
    s.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    s = sub.add_parser("study", help="built-in studies: `study stability` (issue 7)",
                       description="run a built-in study and write report.md, a chart and a "
                       "CSV table")
    s.add_argument("name", choices=["stability"], help="which study")
    s.add_argument("--out", default="results/stability", help="output folder")
    s.add_argument("--quick", action="store_true", help="coarse meshes, fewer runs (for tests)")
    # cross-check against dolfinx (optional; slipstep.fenicsx imports dolfinx lazily)
    text = "solve a case with slipstep and with dolfinx (FEniCSx) and write a comparison report"
    s = sub.add_parser("crosscheck", help=text, description=text)
    s.add_argument("case", nargs="?", default=None,
                   help="case file (default: the built-in Hertz cylinder)")
    s.add_argument("--out", default=None, help="report folder (default: results/<case>_crosscheck)")
    s.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="override a key (repeatable; see cases/README.md)")
    s.add_argument("--steps", default="5,10,20,50",
                   help="dolfinx load steps to compare, elastoplastic bulk scenes (default 5,10,20,50)")
    s.add_argument("--substeps", type=int, default=1,
                   help="dolfinx steps per slipstep event, elastoplastic contact replay (default 1)")
    return p


def _error(message: str) -> int:
    print(f"slipstep: error: {message}", file=sys.stderr)
    return EXIT_ERROR


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.command == "check":
            return _check(args)
        if args.command == "crosscheck":
            return _crosscheck(args)
        if args.command == "sweep":
            from .sweep import main as sweep_main
            return sweep_main(args)
        if args.command == "study":
            from .stability import main as stability_main
            return stability_main(args)
        if args.command == "reproduce":
            from .reproduce import main as reproduce_main
            return reproduce_main(args)
        return _run(args)
    except (CaseError, MeshError, EngineMissing, ValueError) as exc:
        # ValueError: the engine reports model errors that way (docs/engine_api.md)
        if os.environ.get("SLIPSTEP_TRACEBACK"):
            raise
        return _error(str(exc))
    except KeyboardInterrupt:
        print("slipstep: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


def _check(args) -> int:
    scene = build_scene(load_case(args.case, args.overrides))
    m = scene.model
    print(f"{scene.case.name}: {len(m['nodes'])} nodes, {len(m['triangles'])} elements, "
          f"{2 * len(m['nodes'])} dofs, {len(m['pairs']['node_a'])} contact pairs, "
          f"{len(m['fixed_dofs'])} fixed dofs")
    return 0


def _crosscheck(args) -> int:
    try:
        steps = tuple(int(n) for n in args.steps.split(",") if n.strip())
    except ValueError:
        return _error(f"--steps {args.steps}: give load step counts like 5,10,20,50")
    from .fenicsx import DolfinxMissing, require_dolfinx
    out = args.out or f"results/{load_case(args.case, args.overrides).name}_crosscheck"
    try:
        require_dolfinx()
        from .fenicsx.crosscheck import run
        report = run(args.case, out, args.overrides, steps=steps, substeps=args.substeps)
    except (DolfinxMissing, NotImplementedError) as exc:
        return _error(str(exc))
    print(f"{report['case']}: {report['mode']} -> {out}/crosscheck.md")
    return 0


def _run(args) -> int:
    start = time.perf_counter()
    case = load_case(args.case, args.overrides)
    out = args.out or f"results/{case.name}"
    scene = build_scene(case)
    result = solve(scene, progress=not args.quiet)
    summary = summarize(scene, result, wall_time_s=time.perf_counter() - start)
    try:
        write_results(out, scene, result, summary)
    except KeyboardInterrupt:
        print("slipstep: interrupted while writing results; nothing was replaced in "
              f"{out}", file=sys.stderr)
        return EXIT_INTERRUPTED
    if not args.quiet:
        print(f"{one_line(summary)} -> {out}")
    if summary.get("contact_reached_last_candidate"):
        print("slipstep: warning: the outermost candidate pair is closed, so the contact may "
              "extend beyond the candidates: widen the candidate window (contact.x_max)",
              file=sys.stderr)
    if result.get("stop_reason"):
        return _error(f"{result['stop_reason']} (partial results in {out})")
    if summary["interrupted"]:
        print(f"slipstep: interrupted at load fraction {summary['final_load_fraction']:.4g}; "
              f"partial results in {out}", file=sys.stderr)
        return EXIT_INTERRUPTED
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
