"""Is bench/getfem_hertz.py the same physics as slipstep, and what is the converged answer?

    .venv/bin/python bench/getfem_checks.py physics   [--h 0.05]
    .venv/bin/python bench/getfem_checks.py reference [--quick]

physics (a few minutes): on slipstep's mesh at h_contact = h,
  - elastic, μ = 0: GetFEM (one load step) against Hertz (a = 1.4384 mm, p0 = 442.6 MPa at
    P = 1000 N/mm) and against slipstep, node by node (the same discrete problem);
  - elastic, μ = 0.3: GetFEM with N = 10, 40 against slipstep (the friction law; the
    difference is load stepping);
  - elastoplastic Hertz (μ = 0.3, Sy = 200, H' = 700): GetFEM with N = 5, 10, 20, 40 load steps
    against slipstep's exact (event-by-event, solver.group_tol = 0) run: p0, a, the largest
    nodal pressure difference, and the contact force balance (P/2 = 500 N/mm).
reference (about an hour on a quiet 2-core machine): the elastoplastic scene on a ladder of
  meshes, slipstep exact (and grouped, δ = 1e-3, where exact takes too long) and GetFEM with
  N = 40 and 80; p0 and a extrapolated to h -> 0 (Richardson, observed order, per code).

Every run is a record in bench/getfem_checks.json (kept: a rerun skips what is there); the
tables go to bench/getfem_physics.md and bench/getfem_reference.md.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import getfem_hertz as peer  # noqa: E402

ELASTIC = ["contact.mu=0"]
FRICTION = ["contact.mu=0.3"]
HERTZ = {"a": 1.4384, "p0": 442.6}  # Johnson §4.3 at P = 1000 N/mm (the case file)
LADDER = {
    "exact": (0.2, 0.1, 0.07, 0.05, 0.035, 0.025),
    "grouped": (0.05, 0.035, 0.025, 0.0175, 0.0125, 0.009),
    "getfem": (0.1, 0.05, 0.025, 0.0125),
    "path": {0.1: (5, 10, 20, 40, 80, 160, 320), 0.05: (5, 10, 20, 40, 80, 160)},
}
QUICK = {
    "exact": (0.2, 0.1, 0.05),
    "grouped": (0.1, 0.05),
    "getfem": (0.2, 0.1),
    "path": {0.2: (10, 20, 40)},
}
GETFEM_STEPS = (40, 80)
FINE_H = 0.1  # Richardson triples for the reference a start at h <= FINE_H
GROUPED = "solver.group_tol=1e-3"
EXACT = "solver.group_tol=0"
STORE = HERE / "getfem_checks.json"


# --------------------------------------------------------------------------- runs (cached)
def slipstep_run(h: float, overrides: list[str]) -> dict:
    """slipstep on the scene at h_contact = h: p0, a, forces, the contact profile, times."""
    from slipstep import prepare, solve
    from slipstep.measures.contact_edges import contact_profile
    from slipstep.output.summary import summarize

    t0 = time.perf_counter()
    scene = prepare(
        peer.CASE, overrides=[*overrides, f"mesh.h_contact={h}", "output.snapshots=[1.0]"]
    )
    t1 = time.perf_counter()
    result = solve(scene)
    engine_s = time.perf_counter() - t1
    s = summarize(scene, result, wall_time_s=engine_s)
    prof = contact_profile(scene, result["snapshots"][-1])
    return {
        "code": "slipstep",
        "h": h,
        "dofs": scene.n_dofs,
        "events": s["n_events"],
        "p0": s["peak_pressure"],
        "a": s["contact_half_width"],
        "stick_half_width": s["stick_half_width"],
        "total_normal_force": s["total_normal_force"],
        "engine_s": engine_s,
        "mesh_s": t1 - t0,
        "x": prof["x"].tolist(),
        "pressure": prof["pressure"].tolist(),
    }


def getfem_run(h: float, overrides: list[str], steps: int) -> dict:
    """GetFEM (bench/getfem_hertz.py, its own process) on the same mesh as slipstep_run."""
    return {"code": "getfem", **peer.run_child(peer.scene_spec(h, steps, overrides))}


def cached(store: dict, key: str, make) -> dict:
    """store[key], made (and saved) if missing."""
    if key not in store:
        store[key] = make()
        STORE.write_text(json.dumps(store, indent=1) + "\n")
        print(
            f"{key}: p0 = {store[key].get('p0', float('nan')):.3f}, a = "
            f"{store[key].get('a', float('nan')):.5f}",
            flush=True,
        )
    return store[key]


def load_store() -> dict:
    return json.loads(STORE.read_text()) if STORE.exists() else {}


# --------------------------------------------------------------------------- physics checks
def node_difference(run: dict, ref: dict) -> float:
    """max |p - p_ref| over the candidates / p0_ref (the same candidates in both runs)."""
    assert np.array_equal(run["x"], ref["x"]), "the candidates differ"
    return float(np.abs(np.subtract(run["pressure"], ref["pressure"])).max() / ref["p0"])


def physics(store: dict, h: float) -> list[str]:
    """The two comparisons of the module docstring, as markdown lines."""
    el_ss = cached(store, f"slipstep elastic mu=0 h={h}", lambda: slipstep_run(h, ELASTIC))
    el_gf = cached(store, f"getfem elastic mu=0 h={h} N=1", lambda: getfem_run(h, ELASTIC, 1))
    lines = [
        f"## Same physics, h_contact = {h} mm ({el_ss['dofs']} DOFs)",
        "",
        "| run | p0 (MPa) | a (mm) | p0 vs Hertz | a vs Hertz | max Δp / p0 vs slipstep |"
        " force balance Σλn − P/2 (N/mm) |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, r in (
        ("slipstep, elastic μ = 0", el_ss),
        (
            "GetFEM N = 1, elastic μ = 0 (a: one step has no history to interpolate "
            "in, so the outermost closed node)",
            el_gf,
        ),
    ):
        lines.append(
            f"| {name} | {r['p0']:.3f} | {r['a']:.5f} | {r['p0'] / HERTZ['p0'] - 1:+.2%} "
            f"| {r['a'] / HERTZ['a'] - 1:+.2%} | {node_difference(r, el_ss):.1e} | "
            f"{r['total_normal_force'] - 500:+.1e} |"
        )
    fr_ss = cached(store, f"slipstep elastic mu=0.3 h={h}", lambda: slipstep_run(h, FRICTION))
    lines.append(
        f"| slipstep, elastic μ = 0.3 ({fr_ss['events']} events) | {fr_ss['p0']:.3f} | "
        f"{fr_ss['a']:.5f} | | | 0 | {fr_ss['total_normal_force'] - 500:+.1e} |"
    )
    for n in (10, 40):
        r = cached(store, f"getfem elastic mu=0.3 h={h} N={n}", lambda: getfem_run(h, FRICTION, n))
        lines.append(
            f"| GetFEM N = {n}, elastic μ = 0.3 | {r['p0']:.3f} | {r['a']:.5f} | | | "
            f"{node_difference(r, fr_ss):.1e} | {r['total_normal_force'] - 500:+.1e} |"
        )
    ep_ss = cached(store, f"slipstep exact h={h}", lambda: slipstep_run(h, [*peer.SCENE, EXACT]))
    lines.append(
        f"| slipstep exact, elastoplastic μ = 0.3 ({ep_ss['events']} events) | "
        f"{ep_ss['p0']:.3f} | {ep_ss['a']:.5f} | | | 0 | "
        f"{ep_ss['total_normal_force'] - 500:+.1e} |"
    )
    for n in peer.STEPS:
        r = cached(store, f"getfem h={h} N={n}", lambda: getfem_run(h, peer.SCENE, n))
        lines.append(
            f"| GetFEM N = {n}, elastoplastic ({r['newton_iterations']} Newton; p0 "
            f"{r['p0'] / ep_ss['p0'] - 1:+.2%}, a {r['a'] / ep_ss['a'] - 1:+.2%} vs "
            f"exact) | {r['p0']:.3f} | {r['a']:.5f} | | | {node_difference(r, ep_ss):.1e}"
            f" | {r['total_normal_force'] - 500:+.1e} |"
        )
    return lines + [""]


# --------------------------------------------------------------------------- reference
def richardson(h: list[float], v: list[float]) -> dict | None:
    """The limit of v(h) = v* + C h^q through three (h, v), h decreasing: the observed order q
    (bisection on the ratio of the two differences) and v*; None if the differences do not
    shrink with one sign (no asymptotic range) or q falls outside (0.2, 6)."""
    d1, d2 = v[1] - v[0], v[2] - v[1]
    if d1 == 0 or d2 / d1 <= 0 or abs(d2) >= abs(d1):
        return None

    def excess(q):  # the model's ratio of differences minus the observed one
        return (h[0] ** q - h[1] ** q) / (h[1] ** q - h[2] ** q) - d1 / d2

    lo, hi = 0.2, 6.0
    if excess(lo) * excess(hi) > 0:
        return None
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if excess(lo) * excess(mid) > 0 else (lo, mid)
    q = 0.5 * (lo + hi)
    c = d2 / (h[2] ** q - h[1] ** q)
    return {"h": h, "q": q, "limit": v[2] - c * h[2] ** q}


def halving_triples(runs: list[dict]) -> list[list[dict]]:
    """Runs (h1, h2, h3) of one series with h1/h2 and h2/h3 both 2 within 5 %."""
    by_h = sorted(runs, key=lambda r: -r["h"])
    near = [
        (i, j)
        for i, ri in enumerate(by_h)
        for j, rj in enumerate(by_h)
        if abs(ri["h"] / rj["h"] - 2.0) <= 0.1
    ]
    return [[by_h[i], by_h[j], by_h[k]] for i, j in near for j2, k in near if j2 == j]


def reference_runs(store: dict, ladder: dict) -> dict[str, list[dict]]:
    """The refinement series of each code (module docstring), cached."""
    series = {
        "slipstep exact": [
            cached(
                store, f"slipstep exact h={h}", lambda h=h: slipstep_run(h, [*peer.SCENE, EXACT])
            )
            for h in ladder["exact"]
        ],
        "slipstep δ = 1e-3": [
            cached(
                store,
                f"slipstep grouped h={h}",
                lambda h=h: slipstep_run(h, [*peer.SCENE, GROUPED]),
            )
            for h in ladder["grouped"]
        ],
    }
    for n in GETFEM_STEPS:
        series[f"GetFEM N = {n}"] = [
            cached(store, f"getfem h={h} N={n}", lambda h=h, n=n: getfem_run(h, peer.SCENE, n))
            for h in ladder["getfem"]
        ]
    return series


def path_convergence(store: dict, ladder: dict) -> list[str]:
    """GetFEM's load-stepping error on a fixed mesh: p0 and a with N steps against slipstep's
    exact run there (N -> infinity should close the gap if both solve the same rate problem)."""
    lines = [
        "## GetFEM N -> ∞ on a fixed mesh, against slipstep exact",
        "",
        "| h (mm) | N | Newton | p0 (MPa) | p0 − exact | a (mm) | a − exact |",
        "|---|---|---|---|---|---|---|",
    ]
    for h, steps in ladder["path"].items():
        exact = cached(
            store, f"slipstep exact h={h}", lambda h=h: slipstep_run(h, [*peer.SCENE, EXACT])
        )
        lines.append(
            f"| {h:g} | exact | {exact['events']} events | {exact['p0']:.3f} | 0 | "
            f"{exact['a']:.5f} | 0 |"
        )
        for n in steps:
            r = cached(store, f"getfem h={h} N={n}", lambda h=h, n=n: getfem_run(h, peer.SCENE, n))
            if "p0" in r:
                lines.append(
                    f"| {h:g} | {n} | {r['newton_iterations']} | {r['p0']:.3f} | "
                    f"{r['p0'] - exact['p0']:+.3f} | {r['a']:.5f} | "
                    f"{r['a'] - exact['a']:+.5f} |"
                )
    return lines + [""]


def series_table(series: dict[str, list[dict]]) -> list[str]:
    lines = [
        "## Refinement series, elastoplastic Hertz (μ = 0.3, Sy = 200, H' = 700)",
        "",
        "| series | h (mm) | DOFs | p0 (MPa) | a (mm) | events / Newton |",
        "|---|---|---|---|---|---|",
    ]
    for name, runs in series.items():
        for r in runs:
            work = r.get("events", r.get("newton_iterations"))
            lines.append(
                f"| {name} | {r['h']:g} | {r['dofs']} | {r['p0']:.3f} | {r['a']:.5f} " f"| {work} |"
            )
    return lines + [""]


def richardson_table(series: dict[str, list[dict]]) -> tuple[list[str], list[dict]]:
    """Every halving triple's Richardson limit: markdown, and the fits (series, key, h, limit)."""
    lines = [
        "| series | quantity | h triple (mm) | values | observed order | limit |",
        "|---|---|---|---|---|---|",
    ]
    fits = []
    for name, runs in series.items():
        for rows in halving_triples(runs):
            hs = [r["h"] for r in rows]
            for key in ("p0", "a"):
                fit = richardson(hs, [r[key] for r in rows])
                values = ", ".join(f"{r[key]:.4f}" for r in rows)
                got = "not monotone | –" if fit is None else f"{fit['q']:.2f} | {fit['limit']:.4f}"
                lines.append(
                    f"| {name} | {key} | {', '.join(f'{h:g}' for h in hs)} | {values} " f"| {got} |"
                )
                if fit is not None:
                    fits.append({"series": name, "key": key, **fit})
    return lines + [""], fits


def band(values: list[float]) -> tuple[float, float]:
    """(middle, half-width) of the values (nan without values)."""
    if not values:
        return math.nan, math.nan
    return 0.5 * (max(values) + min(values)), 0.5 * (max(values) - min(values))


def conclusion(series: dict[str, list[dict]], fits: list[dict]) -> list[str]:
    """The reference values.  p0: the finest path-exact runs (exact at its finest h, and the
    finer δ = 1e-3 runs corrected by their mean offset to exact where both ran): their scatter
    has no trend left, and Richardson finds no asymptotic range in it.  a: the Richardson
    limits of slipstep's series from triples within h <= FINE_H (δ = 1e-3 corrected alike).
    Each the middle of its values, ± half their spread."""
    exact = {r["h"]: r for r in series["slipstep exact"]}
    grouped = {r["h"]: r for r in series["slipstep δ = 1e-3"]}
    both = sorted(set(exact) & set(grouped))
    offset = {k: float(np.mean([exact[h][k] - grouped[h][k] for h in both])) for k in ("p0", "a")}
    h_min = min(exact)
    p0 = [exact[h_min]["p0"]] + [r["p0"] + offset["p0"] for h, r in grouped.items() if h < h_min]
    a = [
        f["limit"] + (offset["a"] if "δ" in f["series"] else 0.0)
        for f in fits
        if f["key"] == "a" and f["series"].startswith("slipstep") and f["h"][0] <= FINE_H
    ]
    (p_mid, p_half), (a_mid, a_half) = band(p0), band(a)
    return [
        "## Reference",
        "",
        f"δ = 1e-3 against exact on h = {', '.join(f'{h:g}' for h in both)} mm: p0 "
        f"{offset['p0']:+.3f} MPa, a {offset['a']:+.5f} mm (exact − grouped, mean).",
        "",
        f"- p0 = {p_mid:.2f} ± {p_half:.2f} MPa: slipstep exact at h = {h_min:g} and δ = 1e-3 "
        f"(corrected) below it: {', '.join(f'{v:.3f}' for v in p0)}",
        f"- a = {a_mid:.4f} ± {a_half:.4f} mm: Richardson limits of slipstep's series, triples "
        f"within h <= {FINE_H:g} mm: {', '.join(f'{v:.4f}' for v in a)}",
        "",
    ]


def reference(store: dict, ladder: dict) -> list[str]:
    """The series, every halving triple's Richardson limit and the reference, as markdown."""
    series = {
        name: [r for r in runs if "p0" in r] for name, runs in reference_runs(store, ladder).items()
    }
    rich, fits = richardson_table(series)
    return series_table(series) + rich + conclusion(series, fits)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("physics", help="GetFEM against Hertz and slipstep on one mesh")
    s.add_argument("--h", type=float, default=0.05)
    s = sub.add_parser("reference", help="refinement series and extrapolation")
    s.add_argument("--quick", action="store_true", help="coarse meshes only")
    args = p.parse_args(argv)
    store = load_store()
    ladder = QUICK if getattr(args, "quick", False) else LADDER
    lines = (
        physics(store, args.h)
        if args.command == "physics"
        else path_convergence(store, ladder) + reference(store, ladder)
    )
    text = "\n".join(lines)
    print(text)
    quick = "_quick" if getattr(args, "quick", False) else ""
    (HERE / f"getfem_{args.command}{quick}.md").write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
