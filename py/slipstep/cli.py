"""The ``slipstep`` command.

    slipstep run [CASE] [--out DIR] [--set KEY=VALUE ...] [--quiet]
    slipstep check [CASE] [--set KEY=VALUE ...]
    slipstep list
    slipstep keys [SECTION]
    slipstep new NAME [--from CASE]
    slipstep crosscheck [CASE.toml] [--out DIR] [--set KEY=VALUE ...] [--steps 5,10,20,50]
    slipstep sweep STUDY.toml [--out DIR] [--workers N] [--mpi]
    slipstep reproduce [--out DIR] [--quick]
    slipstep study stability [--out DIR] [--quick]

CASE is a case file or the name of a shipped case (``slipstep list``; STUDY likewise), so an
installed wheel runs from any folder; without CASE the built-in Hertz cylinder (paper §5.1)
runs.  ``keys`` prints the case keys (from the schema the validator checks), ``new`` copies a
shipped case to edit.  A :class:`~slipstep.errors.SlipstepError` prints one line
``slipstep: error: ...`` on stderr and exits 2 (set SLIPSTEP_TRACEBACK=1 for its traceback); any
other exception is a bug and shows its traceback.  A run that stops early writes what it
computed: Ctrl-C exits 130, any other early stop (its ``stop["message"]`` says why) exits 2.
``run`` shows a progress bar on stderr when it is a terminal (tqdm), else a start and an end
line.
"""

from __future__ import annotations

import argparse
import os
import sys

from . import ranks, shipped
from .case import load_case
from .errors import InputError, InternalError, SlipstepError
from .build import build_scene
from .runner import run_case
from .output.snapshots import predicted_text
from .output.summary import one_line
from .version import __version__

EXIT_ERROR = 2
EXIT_INTERRUPTED = 130


KEYS_HELP = "repeatable; the keys: `slipstep keys`"


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="slipstep",
        description="Event-driven frictional contact (adaptive incremental, "
        "no load steps, no penalties).",
        epilog="A case is a TOML file or the name of a shipped "
        "case (`slipstep list`). Every key of a case, its default and meaning: `slipstep keys "
        "[SECTION]`. A shipped case copied to edit: `slipstep new NAME --from hertz_sphere`.",
    )
    p.add_argument("--version", action="version", version=f"slipstep {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    for name, text in (
        ("run", "solve a case and write its results"),
        ("check", "validate and mesh a case, print its size, do not solve"),
    ):
        s = sub.add_parser(name, help=text, description=text)
        s.add_argument(
            "case",
            nargs="?",
            default=None,
            help="case file or shipped case name (`slipstep list`; default: the "
            "built-in Hertz cylinder)",
        )
        s.add_argument(
            "--set",
            dest="overrides",
            action="append",
            default=[],
            metavar="KEY=VALUE",
            help=f"override a key, e.g. --set contact.mu=0.35 " f"({KEYS_HELP})",
        )
        if name == "run":
            s.add_argument("--out", default=None, help="output folder (default: results/<case>)")
            s.add_argument("--quiet", action="store_true", help="no progress, no summary line")
    s = sub.add_parser(
        "sweep",
        help="run a parameter study (local processes or MPI)",
        description="run every case of a study TOML (see slipstep.sweep); "
        "finished cases are kept, so a rerun resumes",
    )
    s.add_argument("study", help="study file (studies/*.toml) or shipped study name")
    s.add_argument("--out", default=None, help="output folder (default: results/<study>)")
    s.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    s.add_argument(
        "--mpi",
        action="store_true",
        help="use mpi4py.futures.MPIPoolExecutor: "
        "mpirun -n N python -m mpi4py.futures -m slipstep sweep STUDY --mpi (as root: mpirun "
        "--allow-run-as-root ...)",
    )
    s.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help=f"override a key in every case ({KEYS_HELP})",
    )
    s.add_argument("--quiet", action="store_true", help="no progress lines")
    s = sub.add_parser(
        "reproduce",
        help="regenerate the paper's table and figures + report.md",
        description="regenerate Table 1 and Figs. 5-16 of the paper with "
        "closed-form overlays, and report.md",
    )
    s.add_argument("--out", default="results/reproduce", help="output folder")
    s.add_argument("--quick", action="store_true", help="coarse meshes (for tests)")
    s.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    s = sub.add_parser(
        "study",
        help="built-in studies: `study stability`",
        description="run a built-in study and write report.md, a chart and a " "CSV table",
    )
    s.add_argument("name", choices=["stability"], help="which study")
    s.add_argument("--out", default="results/stability", help="output folder")
    s.add_argument("--quick", action="store_true", help="coarse meshes, fewer runs (for tests)")
    sub.add_parser(
        "list",
        help="list the shipped cases and studies",
        description="the cases and studies shipped with slipstep: give their names "
        "to run, check, crosscheck, sweep and new",
    )
    s = sub.add_parser(
        "keys",
        help="the keys of a case file: type, default, meaning",
        description="every key a case file may hold, table by table, with its "
        "type, unit, default and meaning",
    )
    s.add_argument(
        "section",
        nargs="?",
        default=None,
        help="one section (solver, contact, mesh, ...) or key (contact.mu)",
    )
    s.add_argument(
        "--json-schema",
        action="store_true",
        help="print the case schema as a JSON Schema, for editors",
    )
    s = sub.add_parser(
        "new",
        help="copy a shipped case to NAME.toml, to edit",
        description="write NAME.toml, a copy of a shipped case named NAME, to "
        "edit; then `slipstep check NAME.toml` and `slipstep run NAME.toml`",
    )
    s.add_argument("name", help="the new case's name (and file NAME.toml)")
    s.add_argument(
        "--from",
        dest="source",
        default="hertz_cylinder",
        help="the shipped case to copy (`slipstep list`; default hertz_cylinder)",
    )
    # cross-check against dolfinx (optional; slipstep.fenicsx imports dolfinx lazily)
    text = "solve a case with slipstep and with dolfinx (FEniCSx) and write a comparison report"
    s = sub.add_parser("crosscheck", help=text, description=text)
    s.add_argument(
        "case",
        nargs="?",
        default=None,
        help="case file or shipped case name (default: the built-in Hertz cylinder)",
    )
    s.add_argument("--out", default=None, help="report folder (default: results/<case>_crosscheck)")
    s.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help=f"override a key ({KEYS_HELP})",
    )
    s.add_argument(
        "--steps",
        default="5,10,20,50",
        help="dolfinx load steps to compare, elastoplastic bulk scenes (default 5,10,20,50)",
    )
    s.add_argument(
        "--substeps",
        type=int,
        default=1,
        help="dolfinx steps per slipstep event, elastoplastic contact replay (default 1)",
    )
    return p


def _error(message: str) -> int:
    print(f"slipstep: error: {message}", file=sys.stderr)
    return EXIT_ERROR


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    spaced = _spaced_set(argv)
    if spaced:
        return _error(spaced)
    args = _parser().parse_args(argv)
    try:
        return _command(args)
    except (SlipstepError, InternalError) as exc:
        if os.environ.get("SLIPSTEP_TRACEBACK"):
            raise
        return _error(str(exc))
    except KeyboardInterrupt as exc:
        print(f"slipstep: {str(exc) or 'interrupted'}", file=sys.stderr)
        return EXIT_INTERRUPTED


def _spaced_set(argv: list[str]) -> str | None:
    """``--set contact.mu 0.2`` (a space for the =): the message that says how to write it."""
    words = [
        w
        for item in argv
        for w in (["--set", item[len("--set=") :]] if item.startswith("--set=") else [item])
    ]
    for i, item in enumerate(words[:-1]):
        if item == "--set" and "=" not in words[i + 1]:
            key, after = words[i + 1], (words[i + 2 :] or ["-"])[0]
            value = None if after.startswith("-") else after
            written = f"--set {key} {value}" if value else f"--set {key}"
            return (
                f"{written}: write KEY=VALUE as one word, --set {key}={value or 'VALUE'} "
                f"(the keys: `slipstep keys`)"
            )
    return None


def _command(args) -> int:
    if args.command == "check":
        return _check(args)
    if args.command == "list":
        return _list()
    if args.command == "keys" and args.json_schema:
        from .json_schema import text

        sys.stdout.write(text())
        return 0
    if args.command == "keys":
        from .keys import reference

        print(reference(args.section))
        return 0
    if args.command == "new":
        return _new(args)
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


def _case(args):
    """The case the command line names (a file, a shipped name, or None: the built-in one)."""
    return load_case(shipped.resolve(args.case), args.overrides)


def _list() -> int:
    for name in shipped.names("cases"):
        print(f"{name:28s} {load_case(shipped.path(name)).record.case.description}")
    for name in shipped.names("studies"):
        print(f"{name:28s} (study: slipstep sweep {name})")
    return 0


def _new(args) -> int:
    """NAME.toml: a copy of the shipped case ``--from`` named NAME."""
    target = shipped.copy(args.source, args.name)
    files = shipped.referenced_files(load_case(target).data)  # the copy is a valid case
    beside = f" (with {', '.join(files)} beside it)" if files else ""
    print(
        f"{target}: a copy of the shipped case {args.source}, named {target.stem}{beside}; "
        f"edit it, then `slipstep check {target}` and `slipstep run {target}` (keys: "
        f"`slipstep keys`)"
    )
    return 0


def _check(args) -> int:
    scene = build_scene(_case(args))
    m = scene.engine_model
    print(
        f"{scene.case.name}: {len(m.nodes)} nodes, {len(scene.elements)} elements, "
        f"{scene.n_dofs} dofs, {len(m.pairs)} contact pairs, "
        f"{len(m.fixed_dofs)} fixed dofs"
    )
    print(predicted_text(scene))
    return 0


def _crosscheck(args) -> int:
    try:
        steps = tuple(int(n) for n in args.steps.split(",") if n.strip())
    except ValueError:
        raise InputError(f"--steps {args.steps}: give load step counts like 5,10,20,50") from None
    from .fenicsx import require_dolfinx

    out = args.out or f"results/{_case(args).name}_crosscheck"
    try:
        require_dolfinx()
        from .fenicsx.crosscheck import run as crosscheck

        report = crosscheck(
            shipped.resolve(args.case), out, args.overrides, steps=steps, substeps=args.substeps
        )
    except NotImplementedError as exc:  # a scene the cross-check does not cover
        return _error(str(exc))
    print(f"{report['case']}: {report['mode']} -> {out}/crosscheck.md")
    return 0


def _run(args) -> int:
    case = _case(args)
    out = args.out or f"results/{case.name}"
    result, summary = run_case(case, out, progress=not args.quiet)
    if ranks.rank() != 0:  # a MUMPS run's other ranks: rank 0 reports
        return 0
    if not args.quiet:
        print(f"{one_line(summary)} -> {out}")
    if summary.get("contact_reached_last_candidate"):
        print(
            "slipstep: warning: the last candidate pair of a contact is closed, so the "
            "contact may extend beyond the candidates: widen the candidate window "
            "(contact.x_min/x_max/y_min/y_max)",
            file=sys.stderr,
        )
    stop = result["stop"]
    if stop["kind"] == "interrupted":
        where = (
            f"t = {summary['final_t']:.4g} of {summary['n_stages']} stages"
            if summary.get("n_stages", 1) > 1
            else f"load fraction {summary['final_load_fraction']:.4g}"
        )
        print(f"slipstep: interrupted at {where}; partial results in {out}", file=sys.stderr)
        return EXIT_INTERRUPTED
    if stop.get("message"):  # any early stop but one the case asked for (first_yield)
        return _error(f"{stop['message']} (partial results in {out})")
    if stop.get("late_interrupt"):
        print(
            f"slipstep: interrupted as the run completed; complete results in {out}",
            file=sys.stderr,
        )
        return EXIT_INTERRUPTED
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
