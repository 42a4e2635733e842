"""The 3D series of `make bench` (bench/run.py runs it as its series ``3d``): the targets of the
3D engine, each run its own process (bench/processes.py's ``run_child``: the whole process timed,
spawn to exit), one at a time.

  hertz     cases/hertz_sphere_3d.toml (the eighth sphere, elastic, frictionless) on the meshes
            GetFEM solves in bench/getfem_hertz_3d.py (the same h_contact, the same mesh): a and
            p0 against Hertz, the whole process against GetFEM's on the same mesh
  mindlin   cases/mindlin_sphere_3d.toml (the half sphere on a block, pressed then sheared to
            Q = 0.5 mu P): the stick radius against Mindlin's c = a (1 - Q/(mu P))^(1/3) for the
            measured P and Q, in contact-node spacings of the sphere's mesh (the case's mesh
            and the next finer, the block's spacing 0.75 of the sphere's as in the case;
            bench/mindlin_convergence_3d.py runs the mesh series and the unloading)
  plastic   cases/sphere_on_flat_plastic_3d.toml (the eighth, elastic-perfectly plastic, to
            10 omega_c) and slipstep's axisymmetric run of the same scene
            (cases/sphere_on_flat_plastic.toml with the same mesh sizes near the contact, the
            same motion): the force-approach curves

Targets: Hertz at ~100k DOFs a within 2 %, p0 within 3 %, the whole process at least 10x
faster than GetFEM's on the same mesh; Mindlin's stick radius within one contact-node spacing
of Mindlin's c (a spacing resolves the stick edge); the elastoplastic force-approach within
2 % of the axisymmetric run.

The speed target is taken from bench/paired_3d.py's run when it exists (the two codes
alternated pair by pair, so both meet the same load), else from the two separate series.

Writes results_3d.json (the runs), results_3d.md, hertz_3d.png and error_vs_time_3d.png (the
errors against the references over the whole-process time: the Hertz sphere beside GetFEM, and
the thick sphere beside dolfinx from bench/dolfinx_side_by_side_3d.json, written by
bench/dolfinx_side_by_side.py --scene sphere); bench/run.py's report gets `section` and both
charts too.

    python bench/series_3d.py [--quick] [--out DIR]     # the series alone
    python bench/series_3d.py --rerun hertz        # those again, the other saved runs kept
    python bench/series_3d.py --report bench/results_3d.json
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

from processes import fmt, machine, pct, run_child

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CASES = ROOT / "cases"
GETFEM_3D_JSON = HERE / "getfem_results_3d.json"
SPHERE_JSON = HERE / "dolfinx_side_by_side_3d.json"  # the thick sphere beside dolfinx
TIMEOUT_S = 900.0
R_PLASTIC, OMEGA = 10.0, 0.00213  # the plastic sphere's R and final interference
PLASTIC_MESH = ["mesh.contact_zone=0.2", "mesh.growth=0.3", "mesh.h_max=2.0"]
PLASTIC_TIMES = [0.1, 0.25, 0.5, 0.75, 1.0]
PLASTIC_FROM = 0.25  # the curves are compared from this load fraction
MINDLIN_R, MINDLIN_E, MINDLIN_NU, MINDLIN_MU = 50.0, 70000.0, 0.3, 0.3
A_TOL, P0_TOL, SPEED_UP, SPACINGS, PLASTIC_TOL = 0.02, 0.03, 10.0, 1.0, 0.02
TARGET_DOFS = 90_000  # "~100k DOFs": the Hertz target's run has at least
FULL = {
    "hertz": [0.05, 0.03, 0.02, 0.0125, 0.0105],
    "mindlin": [(0.04, 0.03), (0.03, 0.0225)],
    "plastic": [0.015, 0.01],
}
QUICK = {"hertz": [0.05, 0.03], "mindlin": [(0.04, 0.03)], "plastic": [0.025]}


# --------------------------------------------------------------------------- specs
def specs(sizes: dict) -> list[dict]:
    """The runs of the series: name, case, overrides, the mesh size h (the sphere's)."""
    out = [
        {
            "name": "hertz",
            "case": "hertz_sphere_3d",
            "h": h,
            "overrides": [f"mesh.h_contact={h}", "output.snapshots=[1.0]"],
        }
        for h in sizes["hertz"]
    ]
    out += [
        {
            "name": "mindlin",
            "case": "mindlin_sphere_3d",
            "h": hs,
            "overrides": [
                f"body.sphere.mesh.h_contact={hs}",
                f"body.block.mesh.h_contact={hb}",
                "output.snapshots=[1.0, 2.0]",
            ],
        }
        for hs, hb in sizes["mindlin"]
    ]
    for h in sizes["plastic"]:
        mesh = [f"mesh.h_contact={h}", *PLASTIC_MESH, f"output.snapshots={PLASTIC_TIMES}"]
        out.append(
            {"name": "plastic", "case": "sphere_on_flat_plastic_3d", "h": h, "overrides": mesh}
        )
        out.append(
            {
                "name": "plastic_axi",
                "case": "sphere_on_flat_plastic",
                "h": h,
                "overrides": [*mesh, f"contact.motion=[0.0, {OMEGA}]", "contact.x_max=0.3"],
            }
        )
    return [{**s, "series": "3d", "plastic": False, "delta": None} for s in out]


# --------------------------------------------------------------------------- one run (child)
def one(spec: dict) -> dict:
    """One run in this process (bench/run.py --one): the scene, the engine, the summary."""
    import resource

    import numpy as np

    from slipstep import prepare, solve
    from slipstep.output.summary import summarize

    t0 = time.perf_counter()
    scene = prepare(CASES / f"{spec['case']}.toml", overrides=spec["overrides"])
    t1 = time.perf_counter()
    result = solve(scene)
    t2 = time.perf_counter()
    s = summarize(scene, result, wall_time_s=t2 - t1)
    t3 = time.perf_counter()
    snaps = result["snapshots"]
    last = float(np.sum(snaps[-1]["lambda_n"]))
    mirror = s["total_normal_force"] / last if last else 1.0  # the full contact's factor
    fit = hertz_fit(scene, snaps[-1], s.get("contact_radius")) if scene.dimension == 3 else None
    keys = (
        "contact_radius",
        "contact_half_width",
        "peak_pressure",
        "max_nodal_pressure",
        "stick_radius",
        "total_normal_force",
        "total_tangential_force",
        "n_yielded_elements",
    )
    return {
        "status": "ok" if result["stop"]["kind"] == "completed" else result["stop"]["kind"],
        "dofs": scene.n_dofs,
        "events": s["n_events"],
        "steps": s["n_steps"],
        "factorizations": s["n_factorizations"],
        "solves": s["n_solves"],
        "mesh_s": t1 - t0,
        "engine_s": t2 - t1,
        "summary_s": t3 - t2,
        "total_s": t3 - t0,
        "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "max_equilibrium_residual": s["max_equilibrium_residual"],
        **{k: s.get(k) for k in keys},
        "p0_fit": fit,
        "reference": dict(scene.reference or {}),
        "curve": [[float(x["t"]), mirror * float(np.sum(x["lambda_n"]))] for x in snaps],
    }


def hertz_fit(scene, snapshot: dict, a) -> float | None:
    """p0 of Hertz's profile p0 sqrt(1 - r^2/a^2) fitted to the nodal pressures inside 0.9 a
    (a the run's contact radius), least squares weighted by the nodes' areas: the peak of the
    pressure the nodes carry together, where the largest nodal pressure is one node's."""
    import numpy as np

    from slipstep.measures.contact_faces import contact_profile_3d

    if not a:
        return None
    prof = contact_profile_3d(scene, snapshot)
    r = np.hypot(prof["x"][:, 0], prof["x"][:, 1])
    inside = r < 0.9 * a
    shape = np.sqrt(1 - (r[inside] / a) ** 2)
    w = np.asarray(scene.pair_area)[prof["pair"]][inside]
    return float(np.sum(w * prof["pressure"][inside] * shape) / np.sum(w * shape**2))


# --------------------------------------------------------------------------- the series (parent)
def series(
    sizes: dict, out: Path, timeout: float = TIMEOUT_S, keep=(), kept_on: str | None = None
) -> list[dict]:
    """Every run of ``specs(sizes)`` in its own process; results_3d.json rewritten after each,
    with the machine and code they ran on.  ``keep``: saved runs kept instead of run again
    (those of the same name and h), measured as ``kept_on`` says."""
    runs = list(keep)
    measured = measured_on() + (
        f"; the runs kept from before: {kept_on}" if keep and kept_on else ""
    )
    done = {(r["name"], r["h"]) for r in runs}
    for spec in specs(sizes):
        if (spec["name"], spec["h"]) in done:
            continue
        r = run_child(spec, timeout)
        runs.append(r)
        print(line_of(r), flush=True)
        (out / "results_3d.json").write_text(
            json.dumps({"measured": measured, "runs": runs}, indent=1)
        )
    return runs


def line_of(r: dict) -> str:
    head = f"3d {r['name']:11s} h={r['h']:<7g}"
    if r["status"] != "ok":
        return f"{head} {r['status']}: {r.get('error', '')}"
    return (
        f"{head} {r['dofs']:8d} DOFs {r['events']:6d} events  engine {r['engine_s']:8.2f} s  "
        f"process {r['wall_s']:8.2f} s  F={r['total_normal_force']:.4g}"
    )


# --------------------------------------------------------------------------- derived numbers
def hertz_errors(r: dict) -> tuple[float, float]:
    """Errors of a and of the summary's p0 (in 3D the peak recovered from the nodal pressures)."""
    ref = r["reference"]
    return r["contact_radius"] / ref["a_hertz"] - 1, r["peak_pressure"] / ref["p0_hertz"] - 1


def nodal_error(r: dict) -> float:
    """Error of the largest nodal pressure (GetFEM's p0 is the same measure)."""
    return (r.get("max_nodal_pressure") or r["peak_pressure"]) / r["reference"]["p0_hertz"] - 1


def fit_error(r: dict):
    return None if r.get("p0_fit") is None else r["p0_fit"] / r["reference"]["p0_hertz"] - 1


def mindlin_numbers(r: dict) -> dict:
    """Mindlin's a and c for the run's measured P and Q (two bodies of the same material:
    E* = E / (2 (1 - nu^2))), and the stick radius's distance to c in node spacings."""
    P, Q = r["total_normal_force"], r["total_tangential_force"]
    e_star = MINDLIN_E / (2 * (1 - MINDLIN_NU**2))
    a = (3 * P * MINDLIN_R / (4 * e_star)) ** (1 / 3)
    c = a * (1 - Q / (MINDLIN_MU * P)) ** (1 / 3)
    return {
        "a": a,
        "c": c,
        "ratio": Q / (MINDLIN_MU * P),
        "c_over_a": r["stick_radius"] / a,
        "spacings": (r["stick_radius"] - c) / r["h"],
    }


def plastic_pairs(runs: list[dict]) -> list[tuple[dict, dict, float]]:
    """(3D run, axisymmetric run, largest |F_3D / F_axi - 1| from PLASTIC_FROM) per mesh."""
    out = []
    for r in ok(runs, "plastic"):
        axi = next((x for x in ok(runs, "plastic_axi") if x["h"] == r["h"]), None)
        if axi:
            f_axi = dict((round(t, 9), f) for t, f in axi["curve"])
            diffs = [
                abs(f / f_axi[round(t, 9)] - 1)
                for t, f in r["curve"]
                if t >= PLASTIC_FROM and round(t, 9) in f_axi
            ]
            out.append((r, axi, max(diffs) if diffs else math.nan))
    return out


def ok(runs: list[dict], name: str) -> list[dict]:
    return [r for r in runs if r.get("name") == name and r["status"] == "ok"]


def getfem_runs(doc: dict | None) -> list[dict]:
    return [g for g in (doc or {}).get("runs", []) if g.get("status") in ("ok", "not_converged")]


# --------------------------------------------------------------------------- report
def section(runs: list[dict], gf_doc: dict | None) -> list[str]:
    """The 3D section of results.md: targets, then the tables."""

    gf = getfem_runs(gf_doc)
    L = ["## 3D targets (bench/series_3d.py)", "", "| target | measured | met |", "|---|---|---|"]
    L += target_rows(runs, gf) + [""]
    L += [
        "### Hertz sphere in 3D, side by side with GetFEM 5.4 on the same mesh",
        "",
        "slipstep: cases/hertz_sphere_3d.toml at h_contact = h, one process per run. GetFEM: "
        "bench/getfem_hertz_3d.py on the same mesh (written from slipstep's scene as .msh), its "
        "nodal contact with the rigid obstacle z, one load step, Newton from u = 0 (MUMPS); "
        "`nodal` = version 1, `tuned` = version 2 (its best setting here). a = the equivalent "
        "radius of the closed nodes' tributary areas, p0 node = the largest nodal pressure, "
        "both codes alike; errors against Hertz (a = 0.24455 mm, p0 = 239.51 MPa).",
        "",
        "p0 recovered: slipstep's summary peak_pressure, the maximum of a quadratic fit to the "
        "nodal pressures within 4 spacings of the largest (cases/README.md). p0 fit: Hertz's "
        "profile fitted to the nodal pressures inside 0.9 a (least squares, weighted by the "
        "nodes' areas, a = the run's contact radius).",
        "",
        "| h | code | DOFs | events / Newton its | engine / solve [s] | process [s] | a [mm] | "
        "err a | p0 node [MPa] | err p0 node | err p0 recovered | err p0 fit | "
        "GetFEM / slipstep |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in sorted(ok(runs, "hertz"), key=lambda r: -r["h"]):
        ea, ep = hertz_errors(r)
        L.append(
            f"| {r['h']:g} | slipstep | {r['dofs']} | {r['events']} events | "
            f"{fmt(r['engine_s'], '.2f')} | {fmt(r['wall_s'], '.2f')} | "
            f"{fmt(r['contact_radius'], '.5f')} | {pct(ea, '+.2f')} | "
            f"{fmt(r.get('max_nodal_pressure') or r['peak_pressure'], '.2f')} | "
            f"{pct(nodal_error(r), '+.2f')} | {pct(ep, '+.2f')} | "
            f"{pct(fit_error(r), '+.2f')} | |"
        )
        for g in sorted((g for g in gf if g["h"] == r["h"]), key=lambda g: g["setting"]):
            L.append(
                f"| {g['h']:g} | GetFEM {g['setting']} | {g['dofs']} | "
                f"{g['newton_iterations']} Newton | {fmt(g['solve_s'], '.2f')} | "
                f"{fmt(g['wall_s'], '.2f')} | {fmt(g['a'], '.5f')} | "
                f"{pct(g['a_error'], '+.2f')} | {fmt(g['p0'], '.2f')} | "
                f"{pct(g['p0_error'], '+.2f')} | | | {fmt(g['wall_s'] / r['wall_s'], '.1f')} |"
            )
    L += [
        "",
        "### Mindlin's sphere (cases/mindlin_sphere_3d.toml)",
        "",
        "| h sphere | DOFs | events | process [s] | P [N] | Q/(mu P) | contact radius | a (Hertz, "
        "P) | stick radius | c (Mindlin) | stick / a | (stick - c) / h |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in ok(runs, "mindlin"):
        m = mindlin_numbers(r)
        L.append(
            f"| {r['h']:g} | {r['dofs']} | {r['events']} | {fmt(r['wall_s'], '.1f')} | "
            f"{fmt(r['total_normal_force'], '.3f')} | {fmt(m['ratio'], '.4f')} | "
            f"{fmt(r['contact_radius'], '.4f')} | {fmt(m['a'], '.4f')} | "
            f"{fmt(r['stick_radius'], '.4f')} | {fmt(m['c'], '.4f')} | "
            f"{fmt(m['c_over_a'], '.3f')} | {fmt(m['spacings'], '+.2f')} |"
        )
    L += [
        "",
        "### Elastoplastic sphere on a flat: 3D against the axisymmetric run",
        "",
        f"Force at the snapshots t = omega / ({OMEGA} mm); the largest difference from t = "
        f"{PLASTIC_FROM:g}.",
        "",
        "| h | 3D DOFs | 3D events | 3D process [s] | axi DOFs | axi process [s] | F 3D / F axi "
        "at t | largest diff |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r, axi, d in plastic_pairs(runs):
        ratios = ", ".join(
            f"{t:g}: {f / fa:.4f}" for (t, f), (_, fa) in zip(r["curve"], axi["curve"])
        )
        L.append(
            f"| {r['h']:g} | {r['dofs']} | {r['events']} | {fmt(r['wall_s'], '.1f')} | "
            f"{axi['dofs']} | {fmt(axi['wall_s'], '.1f')} | {ratios} | {pct(d, '.2f')} |"
        )
    failed = [r for r in runs if r["status"] != "ok"]
    if failed:
        L += [
            "",
            "Runs that did not finish: "
            + "; ".join(
                f"{r['name']} h = {r['h']:g}: {r['status']} ({r.get('error', '')})" for r in failed
            ),
        ]
    return (
        L
        + [""]
        + sphere_section(load_sphere())
        + [
            "`hertz_3d.png`: the whole process against DOFs (slipstep, GetFEM), the errors of a and "
            "p0 against DOFs, the plastic force-approach curves. `error_vs_time_3d.png`: the error "
            "against the reference over the time, log–log: (1) |a − a_Hertz| / a_Hertz and (2) "
            "|p0 − p0_Hertz| / p0_Hertz of the Hertz sphere against the whole process, slipstep and "
            "GetFEM (nodal, tuned) a line each over the meshes (labelled in DOFs; grey: the same mesh, "
            "hence the same error, with GetFEM's time over slipstep's), p0 as the largest nodal "
            "pressure for both and slipstep's recovered and fitted peaks beside; hollow: the paired "
            "run; (3) the thick sphere's e_σ against Hill and (4) its path difference d_max to "
            "slipstep's exact run, against the solve time, slipstep (exact, δ) and dolfinx (N load "
            "steps), colour = mesh.",
            "",
        ]
    )


def sphere_section(doc: dict | None) -> list[str]:
    """The thick sphere beside dolfinx in short (bench/dolfinx_side_by_side_3d.md in full)."""
    if not doc:
        return [
            "No thick-sphere comparison with dolfinx (`bench/dolfinx_side_by_side.py --scene "
            "sphere` writes it).",
            "",
        ]
    from dolfinx_side_by_side import beyond

    def reached(hit: dict) -> str:
        return f"{beyond(hit)}{hit['N_interp']:.0f}, {beyond(hit)}{fmt(hit['t_interp'], '.3g')}"

    L = [
        "### Thick sphere in 3D, side by side with dolfinx on the same mesh",
        "",
        "cases/thick_sphere_3d.toml (elastic-perfectly plastic, p = 280 MPa), slipstep's exact "
        "mode (δ = 0) and default (δ = 0.03) against dolfinx 0.5 (Newton, N load steps) on the "
        "identical tetrahedra (`dolfinx_side_by_side_3d.md`: every run, the measures). Solve "
        "wall times in process (meshing common, dolfinx's set-up apart). Against Hill at the "
        "final pressure: e_σ (L2 over σ_R and σ_t), e_u (u at the outer radius), the plastic "
        "front c_fe; path: d_max to slipstep's exact run (every stress component and ε_p, "
        "largest element difference over the largest value) and its stress part d_σ max; "
        "dolfinx as close to the exact run as slipstep's default: N interpolated log–log "
        "between the N tried, or extrapolated with d ~ C/N (≈), a lower bound where d fell "
        "more slowly than 1/N (≥).",
        "",
        "| h bore | DOFs | exact s (events) | default s | e_σ | e_u | c_fe vs Hill's c | "
        "dolfinx N = 1: s, e_σ | default's d_max (d_σ max) | dolfinx at that d_max: N, s | "
        "at that d_σ max: N, s | dolfinx / default (d_max; d_σ max) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for m in doc["meshes"]:
        g = next(g for g in m["grouped"] if g["default"])
        one, hit, st = m["runs"][0], g["dolfinx"], g["dolfinx_stress"]
        L.append(
            f"| {m['h']:g} | {m['dofs']} | {fmt(m['t_s'], '.3g')} ({m['events']}) | "
            f"{fmt(g['t'], '.3g')} | {pct(m['e_sig_s'], '.2f')} | {pct(m['e_u_s'], '+.2f')} | "
            f"{m['c_fe']:.3f} vs {m['c_hill']:.3f} mm | N = {one['N']}: "
            f"{fmt(one['t_d'], '.3g')}, {pct(one['e_sig'], '.2f')} | {pct(g['d_max'], '.2f')} "
            f"({pct(g['d_stress'], '.3f')}) | {reached(hit)} | {reached(st)} | "
            f"{beyond(hit)}{hit['t_interp'] / g['t']:.0f}; {beyond(st)}"
            f"{st['t_interp'] / g['t']:.0f} |"
        )
    return L + [""]


def target_rows(runs: list[dict], gf: list[dict]) -> list[str]:
    rows = []
    big = [r for r in ok(runs, "hertz") if r["dofs"] >= TARGET_DOFS]
    if big:
        r = min(big, key=lambda r: r["dofs"])
        ea, ep = hertz_errors(r)
        rows.append(
            f"| Hertz 3D at ~100k DOFs: a within {A_TOL:.0%}, p0 within {P0_TOL:.0%} | "
            f"{r['dofs']} DOFs: a {pct(ea, '+.2f')}, p0 {pct(ep, '+.2f')} (recovered "
            f"peak; the largest nodal pressure {pct(nodal_error(r), '+.2f')}, Hertz's "
            f"profile fitted to the nodes {pct(fit_error(r), '+.2f')}) | "
            f"{yes(abs(ea) <= A_TOL and abs(ep) <= P0_TOL)} |"
        )
        paired = paired_row(runs)
        if paired:
            rows.append(paired)
        for g in (g for g in gf if g["h"] == r["h"] and g["status"] == "ok" and not paired):
            speed = g["wall_s"] / r["wall_s"]
            rows.append(
                f"| whole process ≥ {SPEED_UP:g}x faster than GetFEM ({g['setting']}) on "
                f"the same mesh | {fmt(r['wall_s'], '.1f')} s vs {fmt(g['wall_s'], '.1f')} "
                f"s: {speed:.1f}x (separate series, not paired) | "
                f"{yes(speed >= SPEED_UP)} |"
            )
    else:
        rows.append(f"| Hertz 3D at ~100k DOFs | no run of at least {TARGET_DOFS} DOFs | no |")
    mindlin = max(ok(runs, "mindlin"), key=lambda r: r["dofs"], default=None)
    if mindlin:
        m = mindlin_numbers(mindlin)
        rows.append(
            f"| Mindlin: stick radius within {SPACINGS:g} node spacings of c = a (1 - "
            f"Q/(mu P))^(1/3) | h = {mindlin['h']:g}: stick/a = {m['c_over_a']:.3f} "
            f"(Mindlin {(1 - m['ratio']) ** (1 / 3):.3f}), {m['spacings']:+.2f} spacings | "
            f"{yes(abs(m['spacings']) <= SPACINGS)} |"
        )
    pairs = plastic_pairs(runs)
    if pairs:
        r, _, d = min(pairs, key=lambda p: p[0]["h"])
        rows.append(
            f"| elastoplastic sphere 3D: force-approach within {PLASTIC_TOL:.0%} of the "
            f"axisymmetric run | h = {r['h']:g}: largest difference {pct(d, '.2f')} | "
            f"{yes(d <= PLASTIC_TOL)} |"
        )
    return rows


def paired_row(runs: list[dict]) -> str | None:
    """The speed target from bench/paired_3d.py's runs (the two codes alternated, pair by
    pair), one clause per mesh size, with the BLAS both processes loaded."""
    from paired_3d import PAIRED_JSON, runs_of

    if not PAIRED_JSON.exists():
        return None
    doc = json.loads(PAIRED_JSON.read_text())
    sizes = [p for p in runs_of(doc) if p.get("median_ratio_wall") is not None]
    if not sizes:
        return None
    dofs = {r["h"]: r["dofs"] for r in ok(runs, "hertz")}
    clauses = "; ".join(
        (f"{dofs[p['h']]} DOFs: " if p["h"] in dofs else f"h = {p['h']:g}: ")
        + ", ".join(
            f"{q['slipstep']['wall_s']:.1f} s vs {q['getfem']['wall_s']:.1f} s" for q in p["pairs"]
        )
        + f" ({p['median_ratio_wall']:.1f}x)"
        for p in sizes
    )
    met = all(p["median_ratio_wall"] >= SPEED_UP for p in sizes)
    return (
        f"| whole process ≥ {SPEED_UP:g}x faster than GetFEM (tuned) on the same mesh, "
        f"paired | slipstep's command line vs GetFEM, BLAS {doc.get('blas', 'not recorded')}: "
        f"{clauses} | {yes(met)} |"
    )


def yes(flag: bool) -> str:
    return "yes" if flag else "**no**"


# --------------------------------------------------------------------------- chart
def chart(runs: list[dict], gf_doc: dict | None, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    gf = getfem_runs(gf_doc)
    fig, ax = plt.subplots(1, 3, figsize=(16, 5))
    hz = sorted(ok(runs, "hertz"), key=lambda r: r["dofs"])
    ax[0].loglog([r["dofs"] for r in hz], [r["wall_s"] for r in hz], "o-", label="slipstep")
    for setting, style in (("nodal", "s--"), ("tuned", "^--")):
        gs = sorted((g for g in gf if g["setting"] == setting), key=lambda g: g["dofs"])
        ax[0].loglog(
            [g["dofs"] for g in gs], [g["wall_s"] for g in gs], style, label=f"GetFEM {setting}"
        )
    ax[0].set(xlabel="DOFs", ylabel="whole process [s]", title="Hertz sphere 3D: run time")
    for i, what in enumerate(("a", "p0")):
        ax[1].loglog(
            [r["dofs"] for r in hz],
            [abs(hertz_errors(r)[i]) for r in hz],
            "o-" if i == 0 else "o:",
            ms=10,
            fillstyle="none",
            label=f"slipstep |err {what}| (the same discrete problem as GetFEM's)",
        )
        gs = sorted((g for g in gf if g["setting"] == "tuned"), key=lambda g: g["dofs"])
        ax[1].loglog(
            [g["dofs"] for g in gs],
            [abs(g[f"{what}_error"]) for g in gs],
            "s-" if i == 0 else "s:",
            label=f"GetFEM |err {what}|",
        )
    ax[1].axhline(A_TOL, color="grey", lw=0.7)
    ax[1].axhline(P0_TOL, color="grey", lw=0.7, ls=":")
    ax[1].set(xlabel="DOFs", ylabel="|error| against Hertz", title="Hertz sphere 3D: a and p0")
    for r, axi, _ in plastic_pairs(runs):
        for run_, style, what in ((r, "o-", "3D"), (axi, "s--", "axisymmetric")):
            t, f = zip(*run_["curve"])
            ax[2].plot([OMEGA * x * 1e3 for x in t], f, style, label=f"{what}, h = {r['h']:g}")
    ax[2].set(
        xlabel="interference omega [um]", ylabel="force [N]", title="elastoplastic sphere on a flat"
    )
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
        if a.get_legend_handles_labels()[0]:
            a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def charts(runs: list[dict], gf_doc: dict | None, out: Path) -> None:
    """hertz_3d.png and error_vs_time_3d.png into ``out``."""
    chart(runs, gf_doc, out / "hertz_3d.png")
    error_chart(runs, gf_doc, load_sphere(), out / "error_vs_time_3d.png")


def error_chart(runs: list[dict], gf_doc: dict | None, sphere: dict | None, path: Path) -> None:
    """error_vs_time_3d.png: the errors against the references over the time (section's
    closing paragraph says what is drawn)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(14, 10.5))
    hz = sorted(ok(runs, "hertz"), key=lambda r: r["dofs"])
    gf = getfem_runs(gf_doc)
    slipstep_errors = {
        "a": [("slipstep", lambda r: hertz_errors(r)[0], "o-C0")],
        "p0": [
            ("slipstep, largest nodal pressure (GetFEM's measure)", nodal_error, "o-C0"),
            ("slipstep, recovered peak", lambda r: hertz_errors(r)[1], "v:C4"),
            ("slipstep, Hertz's profile fitted", fit_error, "D:C5"),
        ],
    }
    for axis, what in zip(ax[0], ("a", "p0")):
        for label, err, style in slipstep_errors[what]:
            rs = [r for r in hz if err(r) is not None]
            axis.loglog(
                [r["wall_s"] for r in rs], [abs(err(r)) for r in rs], style, ms=6, label=label
            )
        for setting, style in (("nodal", "s--C1"), ("tuned", "^--C2")):
            gs = sorted((g for g in gf if g["setting"] == setting), key=lambda g: g["dofs"])
            axis.loglog(
                [g["wall_s"] for g in gs],
                [abs(g[f"{what}_error"]) for g in gs],
                style,
                ms=6,
                label=f"GetFEM {setting}",
            )
        same_mesh_ratios(axis, hz, gf, what)
        paired_points(axis, hz, what)
        axis.set(
            xlabel="whole process [s]",
            ylabel=f"|{what} − {what}_Hertz| / {what}_Hertz",
            title=f"Hertz sphere 3D: {what} against Hertz vs time",
        )
        axis.legend(fontsize=7)
    sphere_panels(ax[1], sphere)
    for a in ax.ravel():
        a.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def same_mesh_ratios(axis, hz: list[dict], gf: list[dict], what: str) -> None:
    """Each slipstep run labelled with its DOFs and joined (grey) to GetFEM's fastest run on the
    same mesh, the same discrete problem hence the same error, labelled with the time ratio."""
    for r in hz:
        e = abs(hertz_errors(r)[0] if what == "a" else nodal_error(r))
        axis.annotate(
            f"{r['dofs'] / 1000:.1f}k",
            (r["wall_s"], e),
            textcoords="offset points",
            xytext=(-4, 5),
            ha="right",
            fontsize=6,
        )
        g = min(
            (g for g in gf if g["h"] == r["h"] and g["status"] == "ok"),
            key=lambda g: g["wall_s"],
            default=None,
        )
        if g:
            axis.plot([r["wall_s"], g["wall_s"]], [e, e], color="0.6", lw=0.6, zorder=0)
            axis.annotate(
                f"×{g['wall_s'] / r['wall_s']:.0f}",
                (g["wall_s"], e),
                textcoords="offset points",
                xytext=(5, -3),
                fontsize=6,
                color="0.3",
            )


def paired_points(axis, hz: list[dict], what: str) -> None:
    """bench/paired_3d.py's pairs (the two codes alternated): hollow markers at each mesh's error."""
    from paired_3d import PAIRED_JSON, runs_of

    if not PAIRED_JSON.exists():
        return
    for size in runs_of(json.loads(PAIRED_JSON.read_text())):
        r = next((r for r in hz if r["h"] == size["h"]), None)
        if r is None:
            continue
        e = abs(hertz_errors(r)[0] if what == "a" else nodal_error(r))
        for p in size["pairs"]:
            axis.loglog(p["slipstep"]["wall_s"], e, "o", mfc="none", mec="C0", ms=10)
            axis.loglog(p["getfem"]["wall_s"], e, "^", mfc="none", mec="C2", ms=10)
    axis.plot([], [], "o", mfc="none", mec="0.3", label="paired run (slipstep ○, GetFEM △)")


def sphere_panels(ax, sphere: dict | None) -> None:
    """The thick sphere beside dolfinx: e_σ against Hill, the path difference to the exact run."""
    if not sphere:
        for a in ax:
            a.text(0.5, 0.5, "no dolfinx_side_by_side_3d.json", transform=a.transAxes, ha="center")
        return
    from dolfinx_side_by_side import hill_panel, path_panel

    hill_panel(ax[0], sphere["meshes"])
    path_panel(ax[1], sphere["meshes"])
    ax[0].set_title(
        "thick sphere 3D: e_σ against Hill vs solve time (labels: dolfinx N)", fontsize=10
    )
    ax[1].set_title(
        "thick sphere 3D: difference to slipstep's exact path vs solve time\n"
        "dolfinx over N (lines), slipstep δ (● default, ▲ others); dotted: the exact "
        "run's time",
        fontsize=9,
    )


def load_sphere() -> dict | None:
    return json.loads(SPHERE_JSON.read_text()) if SPHERE_JSON.exists() else None


def load(out: Path) -> tuple[list[dict], dict | None]:
    """The saved 3D runs (empty without results_3d.json) and GetFEM's 3D runs."""
    path = out / "results_3d.json"
    runs = json.loads(path.read_text())["runs"] if path.exists() else []
    gf = json.loads(GETFEM_3D_JSON.read_text()) if GETFEM_3D_JSON.exists() else None
    return runs, gf


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a few small runs")
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--report", type=Path, metavar="JSON", help="only the report from saved runs")
    ap.add_argument(
        "--rerun",
        default="",
        help="comma list of series (hertz, mindlin, plastic): "
        "run these again, keep the other saved runs",
    )
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    saved = args.report or args.out / "results_3d.json"
    if not args.report:
        again = set(args.rerun.split(",")) if args.rerun else None
        before = json.loads(saved.read_text()) if again and saved.exists() else {"runs": []}
        keep = (
            [
                r
                for r in before["runs"]
                if r["status"] == "ok" and r["name"].removesuffix("_axi") not in again
            ]
            if again
            else []
        )
        series(QUICK if args.quick else FULL, args.out, keep=keep, kept_on=before.get("measured"))
    doc = json.loads(saved.read_text())
    runs, gf = doc["runs"], load(args.out)[1]
    charts(runs, gf, args.out)
    text = "\n".join(header(doc.get("measured")) + section(runs, gf))
    (args.out / "results_3d.md").write_text(text)
    print(text)
    return 0


def measured_on() -> str:
    """The machine and the code now: saved with the runs as they are measured."""

    m = machine()
    return (
        f"{m['cpu']}, {m['cores']} cores, {m['ram_gib']} GiB RAM, shared with other jobs "
        f"(load average {m['load_start']:.1f} at the start). slipstep git {m['git']}, engine "
        f"built {m['engine_mtime']}"
    )


def header(measured: str | None) -> list[str]:
    """The machine and the code a standalone 3D report was measured on, as saved with the runs
    (bench/run.py's full report has its own)."""
    measured = measured or (
        measured_on() + " (when this report was written: the runs do not " "say where they ran)"
    )
    return [
        "# Benchmark: the 3D series (bench/series_3d.py)",
        "",
        f"Machine: {measured}. Each run its own process, one at a time; process = spawn to "
        f"exit. GetFEM's runs: `getfem_results_3d.json` (bench/getfem_hertz_3d.py). This "
        f"section also joins `results.md` when `make bench` runs bench/run.py. The paired "
        f"speed row: bench/paired_3d.json (its own note). The thick sphere beside dolfinx: "
        f"`dolfinx_side_by_side_3d.md` (its own machine line).",
        "",
    ]


if __name__ == "__main__":
    raise SystemExit(main())
