"""Mindlin's stick radius in 3D against the mesh, and the Mindlin-Deresiewicz unloading (issue
37, point 6): cases/mindlin_sphere_3d.toml (the half sphere pressed onto a block of the same
material, then sheared along x) driven through a load path with one more stage, the shear
reversed from Q* to -Q*, on a series of meshes.  Writes mindlin_convergence_3d.json (the runs)
and mindlin_convergence_3d.md (the tables).

For each run, with P the contact's measured normal force and Q* the applied shear (the cut's
traction times its meshed area, both halves):

    a = (3 P R / (4 E*))^(1/3),  E* = E / (2 (1 - nu^2))                  (Hertz)
    loading to Q:           c  = a (1 - Q / (mu P))^(1/3)                 (Mindlin)
    unloading Q* -> Q:      c' = a (1 - (Q* - Q) / (2 mu P))^(1/3)        (Mindlin-Deresiewicz)
    energy per cycle +-Q*:  W = (9 mu^2 P^2 K / (10 a)) [1 - (1 - s)^(5/3) - (5 s / 6)(1 + (1 - s)^(2/3))],
                            s = Q*/(mu P), K = 2 (2 - nu)/G             (the loop of Johnson 7.58-7.59)

measured: the summary's contact_radius and stick_radius (cases/README.md: for node_to_surface
the area of the contactor triangles with a closed, resp. stuck, row at a corner), beside the
former measure (the rows' tributary areas); the half loop, twice the shear's work over the
reversal (the states at +-Q* mirror each other, so the elastic energy returns and the linear
compliance of the bodies does no net work), from the cut's traction-weighted x displacement at
the snapshots (trapezoidal).

Series:
  measure   the contact radius alone: the two bodies pressed without friction (equal spacings),
            and the sphere of cases/hertz_sphere_3d.toml on its rigid plane, each measured both
            ways; shows which measure fits which kind of contact row
  case      the case's own mesh family (growth 0.2, the block's spacing 0.75 of the sphere's)
            at its loads (Q* = 0.5 mu P), h = 0.06, 0.04, 0.03
  ci        the tests' family (growth 0.5, the same ratio, Q* = 0.6 mu P: the shear raised as in
            tests/physics3d/test_mindlin_deresiewicz_3d.py, whose meshes are the first two),
            h = 0.06, 0.04, 0.035, 0.03
  ci_mu     the tests' two meshes run at mu = 0.2 against the references at 0.3: the mutation
  equal     as ci with equal spacings on both bodies, h = 0.06, 0.04, 0.035, 0.03
  coarse_target  the case's family with the block's spacing 1.5 times the sphere's (the
            case's mesh before this study: sphere 0.04, block 0.06)
  target    the sphere's spacing 0.04 with the block's 0.06, 0.04, 0.03, 0.02 (growth 0.5, Q* =
            0.6 mu P): the press's locked-in tangential forces against the target's spacing

    python bench/mindlin_convergence_3d.py [--quick]      # runs, then writes the .json and .md
    python bench/mindlin_convergence_3d.py --only target  # that series again, the others kept
    python bench/mindlin_convergence_3d.py --report       # the .md again from the .json
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
CASE = HERE.parent / "cases" / "mindlin_sphere_3d.toml"
R, E, NU, MU = 50.0, 70000.0, 0.3, 0.3
E_STAR, G = E / (2 * (1 - NU**2)), E / (2 * (1 + NU))
PER_STAGE = 12  # snapshots per stage of the shear and of its reversal
REVERSE = """
[[stage]]
name = "reverse"
factors = { shear = -1.0 }
"""
SERIES = {
    "case": {
        "sizes": [(0.06, 0.045), (0.04, 0.03), (0.03, 0.0225)],
        "growth": 0.2,
        "traction": None,
    },
    "ci": {
        "sizes": [(0.06, 0.045), (0.04, 0.03), (0.035, 0.02625), (0.03, 0.0225)],
        "growth": 0.5,
        "traction": 7.153e-4,
    },
    # mu off by a third (the run's mu = 0.2, the references at the case's 0.3): what the tests'
    # mutation runs see
    "ci_mu": {
        "sizes": [(0.06, 0.045), (0.04, 0.03)],
        "growth": 0.5,
        "traction": 7.153e-4,
        "mu": 0.2,
    },
    # the target's spacing against the contactor's: equal, and 1.5 times it (the case's mesh
    # before this study)
    "equal": {
        "sizes": [(0.06, 0.06), (0.04, 0.04), (0.035, 0.035), (0.03, 0.03)],
        "growth": 0.5,
        "traction": 7.153e-4,
    },
    "coarse_target": {
        "sizes": [(0.06, 0.09), (0.04, 0.06), (0.03, 0.045)],
        "growth": 0.2,
        "traction": None,
    },
    # the sphere's mesh kept, the block's contact spacing varied: the press's locked-in
    # tangential forces and the stick radius against the target's spacing
    "target": {
        "sizes": [(0.04, 0.06), (0.04, 0.04), (0.04, 0.03), (0.04, 0.02)],
        "growth": 0.5,
        "traction": 7.153e-4,
    },
}
QUICK = {
    "case": [(0.06, 0.045)],
    "ci": [(0.06, 0.045), (0.04, 0.03)],
    "ci_mu": [(0.06, 0.045)],
    "equal": [],
    "coarse_target": [],
    "target": [],
}
MEASURE_TWO_BODIES, MEASURE_RIGID = [0.06, 0.04, 0.03], [0.05, 0.04, 0.03, 0.02]


# --------------------------------------------------------------------------- closed forms
def hertz_a(P: float) -> float:
    return (3 * P * R / (4 * E_STAR)) ** (1 / 3)


def loop_energy(P: float, Q_star: float, mu: float = MU) -> float:
    """Mindlin-Deresiewicz's energy per cycle +-Q* of two spheres' worth of compliance (the
    loop of Johnson's 7.58-7.59 with K = 2 (2 - nu)/G: both bodies of this material)."""
    s, a = Q_star / (mu * P), hertz_a(P)
    K = 2 * (2 - NU) / G
    return (
        9
        * mu**2
        * P**2
        * K
        / (10 * a)
        * (1 - (1 - s) ** (5 / 3) - 5 * s / 6 * (1 + (1 - s) ** (2 / 3)))
    )


# --------------------------------------------------------------------------- measures
def tributary_radius(scene, snap, chosen) -> float:
    """The former measure: sqrt(area / pi) of the chosen rows' tributary areas (full contact)."""
    from slipstep.measures.contact_faces import mirror_planes

    factor = 2.0 ** len(mirror_planes(scene, 0))
    return math.sqrt(factor * float(scene.pair_area[chosen].sum()) / math.pi)


def cut_weights(scene) -> np.ndarray:
    """Each node's share of a uniform traction on the sphere's cut: its tributary area there."""
    from slipstep.contact.faces import tributary_areas

    return tributary_areas(
        scene.nodes, scene.global_boundary("sphere", "top"), np.arange(len(scene.nodes))
    )


# --------------------------------------------------------------------------- runs
def run_path(
    hs: float, hb: float, growth: float, traction: float | None, mu: float | None = None
) -> dict:
    """The case with the reversal stage on one mesh: its numbers along the path (``mu``: the
    run's friction instead of the case's; the references stay at the case's MU)."""
    from slipstep import build_scene, parse_case, solve
    from slipstep.measures.contact_faces import contact_numbers_3d

    times = sorted(
        {
            1.0,
            *(1 + k / PER_STAGE for k in range(1, PER_STAGE + 1)),
            *(2 + k / PER_STAGE for k in range(1, PER_STAGE + 1)),
        }
    )
    sets = [
        f"body.sphere.mesh.h_contact={hs}",
        f"body.block.mesh.h_contact={hb}",
        f"body.sphere.mesh.growth={growth}",
        f"body.block.mesh.growth={growth}",
        f"output.snapshots={times}",
    ]
    if traction is not None:
        sets.append(f"bc.shear.traction=[{traction}, 0.0, 0.0]")
    if mu is not None:
        sets.append(f"contact.mu={mu}")
    t0 = time.perf_counter()
    scene = build_scene(
        parse_case(CASE.read_text() + REVERSE, "mindlin_reversed", CASE.parent, sets)
    )
    t1 = time.perf_counter()
    result = solve(scene)
    t2 = time.perf_counter()
    snaps = {s["t"]: s for s in result["snapshots"]}  # the last at each time
    tx = next(b for b in scene.case.data["bc"] if b["name"] == "shear")["traction"][0]
    w = cut_weights(scene)
    Q_star = 2 * tx * w.sum()
    press = snaps[1.0]
    P = contact_numbers_3d(scene, press, 0)["total_normal_force"]
    a = hertz_a(P)
    lt = np.linalg.norm(np.asarray(press["lambda_t"]), axis=1)
    ln = np.asarray(press["lambda_n"])
    closed = np.asarray(press["status"]) > 0
    ratio = lt[closed] / (MU * ln[closed])
    path = []
    for t in sorted(snaps):
        if t < 1.0:
            continue
        s = snaps[t]
        m = contact_numbers_3d(scene, s, 0)
        status = np.asarray(s["status"])
        Q = Q_star * (t - 1 if t <= 2 else 1 - 2 * (t - 2))
        reference = (
            a * (1 - Q / (MU * P)) ** (1 / 3)
            if t <= 2
            else a * (1 - (Q_star - Q) / (2 * MU * P)) ** (1 / 3)
        )
        u = np.asarray(s["u"]).reshape(-1, 3)
        path.append(
            {
                "t": t,
                "Q": Q,
                "c_ref": reference,
                "stick": m["stick_radius"],
                "stick_tributary": tributary_radius(scene, s, status == 1),
                "contact": m["contact_radius"],
                "contact_tributary": tributary_radius(scene, s, status > 0),
                "n_slip": m["n_slip"],
                "delta": float(w @ u[:, 0] / w.sum()),
            }
        )
    half = [p for p in path if p["t"] >= 2.0]
    work = sum(
        0.5 * (p0["Q"] + p1["Q"]) * (p1["delta"] - p0["delta"])
        for p0, p1 in zip(half[:-1], half[1:])
    )
    return {
        "hs": hs,
        "hb": hb,
        "growth": growth,
        "dofs": scene.n_dofs,
        "events": len(set(np.asarray(result["events"]["step"]).tolist())),
        "mesh_s": t1 - t0,
        "engine_s": t2 - t1,
        "status": result["stop"]["kind"],
        "P": P,
        "a": a,
        "Q_star": Q_star,
        "s": Q_star / (MU * P),
        "press_ratio_mean": float(ratio.mean()),
        "press_ratio_max": float(ratio.max()),
        "loop": 2 * work,
        "loop_md": loop_energy(P, Q_star),
        "path": path,
    }


def run_pressed(hs: float) -> dict:
    """The two bodies pressed without friction (the cut held in x): the contact radius both ways."""
    import tomllib

    from slipstep import run

    d = tomllib.loads(CASE.read_text())
    d["stage"] = [d["stage"][0]]
    d["bc"] = [b for b in d["bc"] if b["name"] != "shear"]
    d["bc"].append({"name": "hold_x", "body": "sphere", "face": "top", "displacement": {"x": 0.0}})
    d["stage"][0]["factors"]["hold_x"] = 1.0
    d["contact"][0]["mu"] = 0.0
    for body in d["body"]:
        body["mesh"].update(h_contact=hs, growth=0.5)
    d["output"] = {"snapshots": [1.0]}
    r = run(d, progress=False)
    snap = r.raw["snapshots"][-1]
    P = r.summary["total_normal_force"]
    status = np.asarray(snap["status"])
    return {
        "kind": "node_to_surface, frictionless",
        "h": hs,
        "a": hertz_a(P),
        "contact": r.summary["contact_radius"],
        "contact_tributary": tributary_radius(r.scene, snap, status > 0),
    }


def run_rigid(h: float) -> dict:
    """The sphere of hertz_sphere_3d.toml on its rigid plane (rows at the nodes)."""
    from slipstep import run
    from slipstep.measures.contact_faces import zone_area

    r = run(
        HERE.parent / "cases" / "hertz_sphere_3d.toml",
        progress=False,
        overrides=[f"mesh.h_contact={h}", "mesh.growth=0.5", "output.snapshots=[1.0]"],
    )
    P = r.summary["total_normal_force"]
    a = (3 * P * R * (1 - NU**2) / (4 * E)) ** (1 / 3)
    status = np.asarray(r.raw["snapshots"][-1]["status"])
    # the supports' measure for comparison, as zone_area would take it for mortar rows
    from slipstep.contact.faces import contactor_face
    from slipstep.mesh.tetrahedra import triangle_normals

    face = r.scene.global_boundary(*contactor_face(r.scene.case.data["contact"][0]))
    on = np.zeros(len(r.scene.nodes), dtype=bool)
    on[r.scene.model["pairs"]["node_a"][status > 0]] = True
    _, area = triangle_normals(r.scene.nodes, face)
    supports = math.sqrt(4 * float(area[on[face].any(axis=1)].sum()) / math.pi)
    assert math.isclose(
        4 * zone_area(r.scene, 0, status > 0),
        math.pi * r.summary["contact_radius"] ** 2,
        rel_tol=1e-12,
    )
    return {
        "kind": "rigid_plane",
        "h": h,
        "a": a,
        "contact": supports,
        "contact_tributary": r.summary["contact_radius"],
    }


# --------------------------------------------------------------------------- report
def at(run: dict, t: float) -> dict:
    return min(run["path"], key=lambda p: abs(p["t"] - t))


def report(doc: dict) -> str:
    L = [
        "# Mindlin's stick radius in 3D against the mesh (bench/mindlin_convergence_3d.py)",
        "",
        f"Measured: {doc['measured']}.",
        "",
        "cases/mindlin_sphere_3d.toml with one more stage, the shear reversed from Q* to -Q* "
        "(Q linear in the path time t: Q* at t = 2, 0 at 2.5, -Q* at 3). a = Hertz's radius for "
        "the measured P, c Mindlin's at Q*, c' Mindlin-Deresiewicz's on the reversal. "
        "Errors in spacings of the sphere's contact mesh (h).  *supports*: the summary's measure "
        "(node_to_surface: the contactor triangles with a closed, resp. stuck, row at a corner); "
        "*tributary*: the former one (the rows' tributary areas).",
        "",
    ]
    L += [
        "## Which measure: the contact radius alone",
        "",
        "The two bodies pressed without friction, and the sphere on a rigid plane, each measured "
        "both ways (a: Hertz for the measured P). A node_to_surface row's gap is a mean over "
        "its node's support, weighted by N_j; a rigid plane's row is its node's own gap.",
        "",
        "| contact rows | h | a [mm] | a/h | tributary - a [h] | supports - a [h] |",
        "|---|---|---|---|---|---|",
    ]
    for m in doc["measure"]:
        L.append(
            f"| {m['kind']} | {m['h']:g} | {m['a']:.4f} | {m['a'] / m['h']:.1f} | "
            f"{(m['contact_tributary'] - m['a']) / m['h']:+.2f} | "
            f"{(m['contact'] - m['a']) / m['h']:+.2f} |"
        )
    for name, title in (
        ("case", "The case's mesh family (growth 0.2, block spacing 0.75 h), Q* = " "0.5 mu P"),
        ("ci", "The tests' family (growth 0.5, block spacing 0.75 h), Q* = 0.6 mu " "P"),
        (
            "ci_mu",
            "The tests' family with mu off by a third (the run at mu = 0.2, "
            "the references at the case's 0.3)",
        ),
        ("equal", "Equal spacings on both bodies (growth 0.5), Q* = 0.6 mu P"),
        (
            "coarse_target",
            "The block's spacing 1.5 h (growth 0.2: the case's mesh " "before), Q* = 0.5 mu P",
        ),
        (
            "target",
            "The sphere's spacing kept at 0.04, the block's varied (growth " "0.5), Q* = 0.6 mu P",
        ),
    ):
        runs = [r for r in doc["runs"] if r["series"] == name and r["status"] == "completed"]
        failed = [r for r in doc["runs"] if r["series"] == name and r["status"] != "completed"]
        if not runs:
            continue
        L += [
            "",
            f"## {title}",
            "",
            "Loading to Q*: the stick radius c against Mindlin's.",
            "",
            "| h | h block | DOFs | events | engine [s] | P [N] | Q*/(mu P) | a/h | contact - a "
            "[h] | c (Mindlin) [mm] | stick radius [mm] | stick - c [h] | stick - c [mm] | "
            "tributary - c [h] | press: mean, max of abs(lambda_t)/(mu lambda_n) |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        for r in runs:
            p = at(r, 2.0)
            L.append(
                f"| {r['hs']:g} | {r['hb']:g} | {r['dofs']} | {r['events']} | "
                f"{r['engine_s']:.0f} | "
                f"{r['P']:.2f} | {r['s']:.3f} | {r['a'] / r['hs']:.1f} | "
                f"{(p['contact'] - r['a']) / r['hs']:+.2f} | {p['c_ref']:.4f} | "
                f"{p['stick']:.4f} | {(p['stick'] - p['c_ref']) / r['hs']:+.2f} | "
                f"{p['stick'] - p['c_ref']:+.4f} | "
                f"{(p['stick_tributary'] - p['c_ref']) / r['hs']:+.2f} | "
                f"{r['press_ratio_mean']:.2f}, {r['press_ratio_max']:.2f} |"
            )
        L += [
            "",
            "Along the path: the largest |stick - reference| in spacings over the snapshots "
            "of the loading (c) and of the reversal (c'); c' at Q = 0 and at -Q*; the loop.",
            "",
            "| h | h block | loading: max err [h] | reversal: max err [h] | c' at Q = 0 [mm] | "
            "measured [mm] | err [h] | c' at -Q* [mm] | measured [mm] | err [h] | loop W / W_MD |",
            "|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        for r in runs:
            load = [p for p in r["path"] if 1.0 < p["t"] <= 2.0]
            back = [p for p in r["path"] if p["t"] > 2.0]
            worst = [max(abs(p["stick"] - p["c_ref"]) for p in x) / r["hs"] for x in (load, back)]
            z, e = at(r, 2.5), at(r, 3.0)
            L.append(
                f"| {r['hs']:g} | {r['hb']:g} | {worst[0]:.2f} | {worst[1]:.2f} | "
                f"{z['c_ref']:.4f} | "
                f"{z['stick']:.4f} | {(z['stick'] - z['c_ref']) / r['hs']:+.2f} | "
                f"{e['c_ref']:.4f} | {e['stick']:.4f} | "
                f"{(e['stick'] - e['c_ref']) / r['hs']:+.2f} | "
                f"{r['loop'] / r['loop_md']:.3f} |"
            )
        for r in failed:
            L += [
                "",
                f"h = {r['hs']:g} / {r['hb']:g}: the run stopped ({r['status']}): "
                f"{r.get('error', '')}",
            ]
    L += [
        "",
        "Notes",
        "",
        "- The press of two bodies of the same material (Dundurs' beta = 0) leaves no tangential "
        "traction in the continuum; meshed independently, the two faces' radial displacements "
        "differ by their discretisation errors and the stuck rows carry them: the last column of "
        "the loading tables (before any shear). Those rows start the shear part of the way to "
        "the cone.",
        "- P is not Hertz's for the case's approach: the tetrahedra, graded away from the "
        "contact, are stiffer than the continuum (see cases/mindlin_sphere_3d.toml); every "
        "reference here is taken at the measured P.",
        "",
    ]
    return "\n".join(L)


def measured_on() -> str:
    import os
    import subprocess

    git = subprocess.run(
        ["git", "-C", str(HERE), "describe", "--always", "--dirty"], capture_output=True, text=True
    ).stdout.strip()
    return (
        f"slipstep git {git}, {os.cpu_count()} cores shared with other jobs, load average "
        f"{os.getloadavg()[0]:.1f} at the start"
    )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--report", action="store_true")
    ap.add_argument("--only", nargs="+", choices=list(SERIES), default=None)
    ap.add_argument("--out", type=Path, default=HERE)
    args = ap.parse_args(argv)
    json_path, md_path = (
        args.out / "mindlin_convergence_3d.json",
        args.out / "mindlin_convergence_3d.md",
    )
    if args.report:
        md_path.write_text(report(json.loads(json_path.read_text())))
        return 0
    doc = {"measured": measured_on(), "measure": [], "runs": []}
    if args.only:  # the other series kept as they were measured
        doc = json.loads(json_path.read_text())
        doc["runs"] = [r for r in doc["runs"] if r["series"] not in args.only]
        doc["measured"] += f"; the series {', '.join(args.only)} again: {measured_on()}"
    else:
        for h in MEASURE_TWO_BODIES[:1] if args.quick else MEASURE_TWO_BODIES:
            doc["measure"].append(run_pressed(h))
        for h in MEASURE_RIGID[:1] if args.quick else MEASURE_RIGID:
            doc["measure"].append(run_rigid(h))
    for name, spec in SERIES.items():
        if args.only and name not in args.only:
            continue
        for hs, hb in QUICK[name] if args.quick else spec["sizes"]:
            try:
                r = run_path(hs, hb, spec["growth"], spec["traction"], spec.get("mu"))
            except Exception as error:  # an engine's refusal is a result too: kept, named
                stop = getattr(getattr(error, "result", None), "stop", None) or {}
                r = {
                    "hs": hs,
                    "hb": hb,
                    "growth": spec["growth"],
                    "status": "error",
                    "error": f"{type(error).__name__}: {error}",
                    "t": stop.get("t"),
                }
                print(f"{name} h={hs:g}: {r['error']}", flush=True)
            r["series"] = name
            doc["runs"].append(r)
            if r["status"] == "completed":
                p = at(r, 2.0)
                print(
                    f"{name} h={hs:g}: {r['dofs']} DOFs, {r['events']} events, "
                    f"{r['engine_s']:.0f} s; stick - c = {(p['stick'] - p['c_ref']) / hs:+.2f} h",
                    flush=True,
                )
            json_path.write_text(json.dumps(doc, indent=1))
    md_path.write_text(report(doc))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
