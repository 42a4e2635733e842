"""Large 3D scenes, whole process: the Hertz sphere of cases/hertz_sphere_3d.toml (the eighth,
elastic, on a rigid flat) on graded meshes of ~100k, ~300k, ~600k and ~1M DOFs, each run one
`slipstep run` process at default settings, one at a time.

A size is a mesh: h_contact (a/h with Hertz's a = 0.24455 mm), the radius of the uniformly
fine zone, the size growth outside it, and z_max, the candidates' depth below the flat (the
candidates reach r = sqrt(2 R z_max), 1.25 a for 0.0009 mm). The fine zone covers the contact
and its near field (1.2 a); outside it the size grows slowly (0.05, 0.03 per mm) so the DOFs
resolve the subsurface field instead of only the contact.

Per run: DOFs, pairs, events, the engine's phases (its own timers: assembly, factorization, G
= flexibility, solves, events), the process's wall time (spawn to exit: Python start, mesh
from the cache or gmsh, problem build, engine, output) and its peak resident memory (wait4),
and the contact radius and peak pressure against Hertz. --mu runs it with Coulomb friction
(the flat's mu): the normal answer is then Spence's, not Hertz's (a rigid flat's friction
couples the tangential tractions to the normal ones through (1 - 2 nu) / (2 (1 - nu)) = 0.29
for nu = 0.3); the errors are still given against Hertz.

    python bench/large_3d.py --size 100k 300k [--mu 0.3] [--cold]
    python bench/large_3d.py --report           # bench/large_3d.md from bench/large_3d.json
    python bench/large_3d.py --dump-mesh PREFIX --size 300k [--mu 0.3]
        # the mesh as raw files for rust/examples/ordering_work.rs (the orderings' symbolic work)

--cold meshes into a fresh cache folder (the first run of a scene: gmsh included).
Writes bench/large_3d.json (runs kept by size and mu) and bench/large_3d.md.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
RESULTS = HERE / "large_3d.json"
REPORT = HERE / "large_3d.md"
HERTZ_A, HERTZ_P0 = 0.24455, 239.51  # mm, MPa (the case file's reference)

#: name -> (h_contact, contact_zone, growth, z_max)
SIZES = {
    "100k": (0.0105, 0.4, 0.2, 0.0016),
    "300k": (0.008, 0.3, 0.05, 0.0009),
    "600k": (0.0061, 0.3, 0.04, 0.0009),
    "1M": (0.0061, 0.3, 0.03, 0.0009),
}
PHASES = ("assembly", "factorization", "flexibility", "solves", "events")


def overrides(size: str, mu: float) -> list[str]:
    h, zone, growth, z_max = SIZES[size]
    keys = {
        "mesh.h_contact": h,
        "mesh.contact_zone": zone,
        "mesh.growth": growth,
        "contact.flat.z_max": z_max,
        "contact.flat.mu": mu,
    }
    return [a for k, v in keys.items() for a in ("--set", f"{k}={v!r}")]


def run(size: str, mu: float, cold: bool, out: Path) -> dict:
    """One whole `slipstep run` process: its wall time, peak RSS and summary."""
    env = dict(os.environ, MPLBACKEND="Agg")
    cache = tempfile.TemporaryDirectory() if cold else None
    if cache:
        env["SLIPSTEP_CACHE"] = cache.name
    cmd = [
        sys.executable,
        "-m",
        "slipstep",
        "run",
        "cases/hertz_sphere_3d.toml",
        "--quiet",
        "--out",
        str(out),
        *overrides(size, mu),
    ]
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, cwd=ROOT, env=env, stderr=subprocess.PIPE, text=True)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    err = p.stderr.read().strip()
    if cache:
        cache.cleanup()
    record = {
        "size": size,
        "mu": mu,
        "cold": cold,
        "mesh": dict(zip(("h_contact", "contact_zone", "growth", "z_max"), SIZES[size])),
        "wall_s": wall,
        "peak_rss_mb": usage.ru_maxrss / 1024.0,
        "exit": os.waitstatus_to_exitcode(status),
    }
    summary_path = out / "summary.json"
    if record["exit"] != 0 or not summary_path.exists():
        return {**record, "error": err.splitlines()[-1] if err else "no summary"}
    s = json.loads(summary_path.read_text())
    return {
        **record,
        **{
            k: s[k]
            for k in (
                "n_dofs",
                "n_pairs",
                "n_events",
                "contact_radius",
                "peak_pressure",
                "total_normal_force",
            )
        },
        "engine_s": s["wall_time_s"],
        "phases_s": {k: s["engine_timings_s"].get(k, 0.0) for k in PHASES},
        "a_over_h": HERTZ_A / SIZES[size][0],
        "a_error": s["contact_radius"] / HERTZ_A - 1.0,
        "p0_error": s["peak_pressure"] / HERTZ_P0 - 1.0,
    }


def dump_mesh(size: str, prefix: str) -> None:
    """The size's mesh (through the mesh cache) as PREFIX.points (f64 x 3), PREFIX.tets (u64
    x 4) and PREFIX.contact (u64: the surface nodes within z_max of the flat, the candidates)."""
    import numpy as np
    from slipstep.mesh.tetrahedron_generators import sphere

    h, zone, growth, z_max = SIZES[size]
    mesh = sphere(
        R=50.0, h_contact=h, contact_zone=zone, h_max=5.0, growth=growth, portion="eighth"
    )
    surface = mesh.node_sets["surface"]
    np.asarray(mesh.nodes, dtype="<f8").tofile(prefix + ".points")
    np.asarray(mesh.tetrahedra, dtype="<u8").tofile(prefix + ".tets")
    np.asarray(surface[mesh.nodes[surface, 2] <= z_max], dtype="<u8").tofile(prefix + ".contact")


def report(runs: list[dict]) -> str:
    head = (
        "| size | mu | a/h | DOFs | pairs | events | assembly | factorization | G | solves | events [s] "
        "| engine [s] | whole process [s] | peak RSS [MB] | a vs Hertz | p0 vs Hertz |"
    )
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in runs:
        if "error" in r:
            lines.append(
                f"| {r['size']} | {r['mu']} | | | | | | | | | | | {r['wall_s']:.0f} | {r['peak_rss_mb']:.0f} | {r['error']} | |"
            )
            continue
        ph = r["phases_s"]
        lines.append(
            f"| {r['size']}{' (cold cache)' if r['cold'] else ''} | {r['mu']} | {r['a_over_h']:.0f} | {r['n_dofs']} | {r['n_pairs']} | {r['n_events']} "
            f"| {ph['assembly']:.1f} | {ph['factorization']:.1f} | {ph['flexibility']:.1f} | {ph['solves']:.1f} | {ph['events']:.1f} "
            f"| {r['engine_s']:.1f} | {r['wall_s']:.1f} | {r['peak_rss_mb']:.0f} | {100 * r['a_error']:+.2f} % | {100 * r['p0_error']:+.2f} % |"
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", nargs="+", choices=list(SIZES), default=["100k", "300k"])
    ap.add_argument("--mu", type=float, default=0.0)
    ap.add_argument("--cold", action="store_true", help="mesh into a fresh cache (gmsh included)")
    ap.add_argument(
        "--report", action="store_true", help="only write the table from the saved runs"
    )
    ap.add_argument(
        "--dump-mesh", metavar="PREFIX", help="write the first size's mesh as raw files and stop"
    )
    args = ap.parse_args()
    if args.dump_mesh:
        dump_mesh(args.size[0], args.dump_mesh)
        return
    runs = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    if not args.report:
        for size in args.size:
            with tempfile.TemporaryDirectory() as out:
                r = run(size, args.mu, args.cold, Path(out))
            print(json.dumps(r), flush=True)
            runs = [
                x for x in runs if (x["size"], x["mu"], x["cold"]) != (size, args.mu, args.cold)
            ] + [r]
            RESULTS.write_text(json.dumps(runs, indent=1) + "\n")
    order = list(SIZES)
    runs.sort(key=lambda r: (r["mu"], r["cold"], order.index(r["size"])))
    text = REPORT.read_text() if REPORT.exists() else ""
    marker = "<!-- table -->"
    table = f"{marker}\n{report(runs)}{marker}"
    if text.count(marker) == 2:
        start, end = text.index(marker), text.rindex(marker) + len(marker)
        text = text[:start] + table + text[end:]
    else:
        text = "# Large 3D scenes\n\n" + table + "\n"
    REPORT.write_text(text)


if __name__ == "__main__":
    main()
