"""The ``slipstep`` command.

    slipstep run [CASE.toml] [--out DIR] [--set KEY=VALUE ...] [--quiet]
    slipstep check [CASE.toml] [--set KEY=VALUE ...]

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
    return p


def _error(message: str) -> int:
    print(f"slipstep: error: {message}", file=sys.stderr)
    return EXIT_ERROR


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.command == "check":
            return _check(args)
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
