"""Benchmark: Hertz cylinder refinement series (elastic, mu = 0 and 0.3), timed per phase.

Writes bench/results.md (table, machine, versions) and two charts: run time vs DOFs (log-log,
fitted slope) and error vs run time (the speed-accuracy chart). Run with `make bench`.
"""

from __future__ import annotations

import math
import platform
import sys
import time
from pathlib import Path

import numpy as np

import slipstep
from slipstep import prepare, solve

HERE = Path(__file__).resolve().parent
SIZES = [0.12, 0.06, 0.03, 0.015, 0.0075]
MUS = [0.0, 0.3]
P, R, E, NU = 1000.0, 125.0, 70000.0, 0.3
A_H = math.sqrt(4 * P * R / (math.pi * E / (1 - NU**2)))
P0_H = 2 * P / (math.pi * A_H)


def one(h: float, mu: float) -> dict:
    t0 = time.perf_counter()
    scene = prepare(None, overrides=[f"mesh.h_contact={h}", f"contact.mu={mu}", "output.snapshots=[1.0]"])
    t_mesh = time.perf_counter() - t0
    t1 = time.perf_counter()
    result = solve(scene)
    t_solve = time.perf_counter() - t1
    s = slipstep.output.summarize(scene, result, wall_time_s=t_solve)
    return {"h": h, "mu": mu, "dofs": scene.n_dofs, "events": s["n_events"], "steps": s["n_steps"],
            "factorizations": result["n_factorizations"], "solves": result["n_solves"],
            "mesh_s": t_mesh, "solve_s": t_solve, **{f"t_{k}": v for k, v in result["timings"].items()},
            "a": s["contact_half_width"], "p0": s["peak_pressure"]}


def main() -> int:
    rows = [one(h, mu) for mu in MUS for h in SIZES]
    for mu in MUS:  # error vs Hertz (mu = 0) or vs the finest run of the same mu
        ref = [r for r in rows if r["mu"] == mu][-1]
        a_ref, p_ref = (A_H, P0_H) if mu == 0 else (ref["a"], ref["p0"])
        for r in rows:
            if r["mu"] == mu:
                r["err_a"] = abs(r["a"] / a_ref - 1)
                r["err_p0"] = abs(r["p0"] / p_ref - 1)
    lines = ["# Benchmark: Hertz cylinder, elastic (bench/run.py)", "",
             f"Machine: {platform.machine()}, {platform.processor() or ''} Python {sys.version.split()[0]}, "
             f"numpy {np.__version__}; times in seconds; errors vs Hertz (mu = 0) or the finest mesh (mu > 0).", "",
             "| mu | h_contact | DOFs | events | steps | factorizations | solves | assembly | factor | solves s | events s | solve total | mesh | err a | err p0 |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['mu']} | {r['h']} | {r['dofs']} | {r['events']} | {r['steps']} | {r['factorizations']} | "
                     f"{r['solves']} | {r['t_assembly']:.3f} | {r['t_factorization']:.3f} | {r['t_solves']:.3f} | "
                     f"{r['t_events']:.3f} | {r['solve_s']:.3f} | {r['mesh_s']:.2f} | {r['err_a']:.2e} | {r['err_p0']:.2e} |")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 4))
    for mu in MUS:
        d = np.array([[r["dofs"], r["solve_s"]] for r in rows if r["mu"] == mu])
        slope = np.polyfit(np.log(d[:, 0]), np.log(d[:, 1]), 1)[0]
        ax.loglog(d[:, 0], d[:, 1], "o-", label=f"mu = {mu} (slope {slope:.2f})")
        lines.append(f"\nFitted slope of solve time vs DOFs, mu = {mu}: {slope:.2f}")
    ax.set_xlabel("DOFs"); ax.set_ylabel("solve time [s]"); ax.legend(); ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout(); fig.savefig(HERE / "time_vs_dofs.png", dpi=120); plt.close(fig)
    fig, ax = plt.subplots(figsize=(5, 4))
    for mu in MUS:
        d = [(r["solve_s"], r["err_a"], r["err_p0"]) for r in rows if r["mu"] == mu and r["err_a"] > 0]
        if d:
            d = np.array(d)
            ax.loglog(d[:, 0], d[:, 1], "o-", label=f"a, mu = {mu}")
            ax.loglog(d[:, 0], d[:, 2], "s--", label=f"p0, mu = {mu}")
    ax.set_xlabel("solve time [s]"); ax.set_ylabel("relative error"); ax.legend(); ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout(); fig.savefig(HERE / "error_vs_time.png", dpi=120); plt.close(fig)
    (HERE / "results.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
