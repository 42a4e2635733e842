"""The 2D speed target measured side by side: slipstep at default settings against GetFEM 5.4
with N Newton load steps (10) on the same elastoplastic Hertz mesh (h_contact = 0.025 mm,
24.5k DOFs), whole process to whole process.

The commands alternate, round after round, so that both codes meet the same load of the
shared machine: slipstep with its mesh cache (filled by a first, unrecorded run), slipstep
with the cache off (`SLIPSTEP_CACHE=off`: it meshes), then GetFEM (which reads slipstep's mesh
from a .msh file written before the rounds, as bench/getfem_hertz.py does). Each round gives
the two ratios GetFEM / slipstep; the report is their median, with the load average of each
round and slipstep's engine timers.

Writes bench/side_by_side_2d.json (`--out`), read by bench/run.py's report.

    .venv/bin/python bench/side_by_side_2d.py [--rounds 5] [--h 0.025] [--steps 10]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import tempfile
import time
from pathlib import Path

import getfem_hertz
import run

HERE = Path(__file__).resolve().parent
OUT = HERE / "side_by_side_2d.json"
ROUNDS, H, STEPS = 5, 0.025, 10


def slipstep_process(h: float, cache: str) -> dict:
    """One slipstep process of the bench's default series at h (bench/run.py), with the mesh
    cache ``cache`` (a folder, or "off")."""
    previous = os.environ.get("SLIPSTEP_CACHE")
    os.environ["SLIPSTEP_CACHE"] = cache
    try:
        return run.run_child(run.spec_of("default", h), run.TIMEOUT_S)
    finally:
        if previous is None:
            os.environ.pop("SLIPSTEP_CACHE")
        else:
            os.environ["SLIPSTEP_CACHE"] = previous


def rounds(n: int, h: float, steps: int) -> list[dict]:
    """``n`` rounds of slipstep (cached mesh), slipstep (meshing) and GetFEM."""
    out = []
    run.compile_package()
    with tempfile.TemporaryDirectory() as tmp:
        cache = str(Path(tmp) / "cache")
        spec = getfem_hertz.scene_spec(h, steps, msh=Path(tmp) / "hertz.msh")
        slipstep_process(h, cache)  # fills the cache
        for k in range(n):
            load = os.getloadavg()[0]
            warm, cold = slipstep_process(h, cache), slipstep_process(h, "off")
            getfem = getfem_hertz.run_child(spec)
            bad = [r for r in (warm, cold, getfem) if r.get("status") != "ok"]
            if bad:
                raise SystemExit(f"round {k}: a run failed: {bad[0].get('error')}")
            row = {
                "load": load,
                "slipstep_s": warm["wall_s"],
                "slipstep_meshing_s": cold["wall_s"],
                "getfem_s": getfem["wall_s"],
                "ratio": getfem["wall_s"] / warm["wall_s"],
                "ratio_meshing": getfem["wall_s"] / cold["wall_s"],
                "engine_s": warm["engine_s"],
                "mesh_s": warm["mesh_s"],
                "mesh_meshing_s": cold["mesh_s"],
                "import_s": warm["import_s"],
                "timings": warm["timings"],
                "p0": warm["p0"],
                "getfem_p0": getfem["p0"],
                "dofs": warm["dofs"],
                "newton_iterations": getfem["newton_iterations"],
            }
            out.append(row)
            print(
                f"round {k + 1}/{n}: load {load:.2f}  slipstep {row['slipstep_s']:.2f} s "
                f"(meshing {row['slipstep_meshing_s']:.2f} s)  GetFEM {row['getfem_s']:.2f} s  "
                f"ratio {row['ratio']:.2f} (meshing {row['ratio_meshing']:.2f})",
                flush=True,
            )
    return out


def summary(rows: list[dict], h: float, steps: int) -> dict:
    med = lambda key: statistics.median(r[key] for r in rows)  # noqa: E731
    phases = rows[0]["timings"].keys()
    return {
        "h": h,
        "steps": steps,
        "dofs": rows[0]["dofs"],
        "rounds": len(rows),
        "ratio_median": med("ratio"),
        "ratio_meshing_median": med("ratio_meshing"),
        "slipstep_s_median": med("slipstep_s"),
        "slipstep_meshing_s_median": med("slipstep_meshing_s"),
        "getfem_s_median": med("getfem_s"),
        "engine_s_median": med("engine_s"),
        "timings_median": {p: statistics.median(r["timings"][p] for r in rows) for p in phases},
        "p0": rows[0]["p0"],
        "load": [r["load"] for r in rows],
        "written": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
        "runs": rows,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=ROUNDS)
    ap.add_argument("--h", type=float, default=H)
    ap.add_argument("--steps", type=int, default=STEPS)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    result = summary(rounds(args.rounds, args.h, args.steps), args.h, args.steps)
    args.out.write_text(json.dumps(result, indent=1) + "\n")
    print(
        f"median GetFEM / slipstep: {result['ratio_median']:.2f} (cached mesh), "
        f"{result['ratio_meshing_median']:.2f} (meshing); wrote {args.out}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
