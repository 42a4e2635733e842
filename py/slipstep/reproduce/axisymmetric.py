"""The axisymmetric page of ``slipstep reproduce``: ``DIR/axisymmetric.md`` with its
figures, every number also under ``axisymmetric`` in ``reproduce.json``.

Scenes (run by the sweep runner into ``DIR/axisymmetric/axi_*``, resumed like the others):

* the Hertz sphere, ``cases/hertz_sphere.toml``: contact radius a, peak pressure p0 and the
  pressure profile against Hertz; with Sy = 130 MPa, stopped at its first yield event, the load
  and depth of first yield against Huber's axis field (von Mises, nu = 0.3: 0.620 p0 at 0.481a);
* the thick sphere, ``cases/thick_sphere.toml`` (Hill, ch. V): elastic at p = 140 MPa against
  Lame's field; the case (p = 280 MPa) for first yield p_e = (2Y/3)(1 - a^3/b^3) and the
  elastic-plastic radius c(p) from p = 2Y ln(c/a) + (2Y/3)(1 - c^3/b^3), read from the yield
  events (the zone only grows: every event is a yield); asked for 1.1 x the limit, the limit
  load stop against 2Y ln(b/a);
* the elastic-perfectly plastic sphere on a rigid flat, ``cases/sphere_on_flat_plastic.toml``,
  to 50 omega_c on two or three meshes: force and contact area against interference with the
  fits of Kogut & Etsion (2002) and Jackson & Green (2005) (:mod:`slipstep.measures.references`).

Figures are drawn on :class:`matplotlib.figure.Figure` objects (no pyplot).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import shipped, sweep
from ..output.fields import centroids
from ..measures.references import (
    jackson_green,
    jackson_green_critical,
    kogut_etsion,
    kogut_etsion_critical,
    thick_sphere_lame,
    thick_sphere_pressure,
    thick_sphere_radius,
)
from .scenes import task

HERTZ, THICK, SPHERE_FLAT = "hertz_sphere.toml", "thick_sphere.toml", "sphere_on_flat_plastic.toml"
SY_FIRST_YIELD = 130.0  # MPa: the Hertz sphere yields at f = 0.67 of P = 30 N
P_LAME = 140.0  # MPa: below p_e = 145.8 for the elastic thick sphere
LIMIT_FACTOR = 1.1  # the thick sphere asked for 1.1 x its limit pressure
W_MARKS = (1.5, 3.0, 6.0, 12.0, 24.0, 48.0)  # omega/omega_c of the KE/JG table


@dataclass(frozen=True)
class Meshes:
    """Overrides per scene: the Hertz sphere's contact size, the thick sphere's, and the
    sphere on a flat's meshes (label, scale of h_contact and growth) coarsest first."""

    hertz: list
    thick: list
    sphere_flat: tuple


FULL = Meshes([], [], (("2h", 2.0), ("h (the case)", 1.0), ("h/2", 0.5)))
QUICK = Meshes(
    ["mesh.h_contact=0.03"], ["mesh.h=0.5", "mesh.h_outer=1.6"], (("4h", 4.0), ("2h", 2.0))
)


def _case(name: str) -> Path:
    return shipped.path(name)


def _task(cid: str, case: str, overrides, **options) -> dict:
    return task(cid, _case(case), overrides, **options)


def _flat_mesh(scale: float) -> list[str]:
    from ..case import load_case

    mesh = load_case(_case(SPHERE_FLAT)).record.body[0].mesh
    return [
        f"mesh.h_contact={mesh['h_contact'] * scale:g}",
        f"mesh.growth={mesh['growth'] * scale:g}",
    ]


@dataclass(frozen=True)
class ThickSphere:
    """cases/thick_sphere.toml: bore a, outer radius b, yield stress Y, pressure p."""

    a: float
    b: float
    Y: float
    p: float

    @property
    def p_e(self) -> float:
        return 2.0 * self.Y / 3.0 * (1.0 - self.a**3 / self.b**3)

    @property
    def p_limit(self) -> float:
        return 2.0 * self.Y * math.log(self.b / self.a)


def thick_sphere() -> ThickSphere:
    from ..case import load_case

    case = load_case(_case(THICK)).record
    mesh, mat = case.body[0].mesh, case.body[0].material
    p = next(bc.pressure for bc in case.bc if bc.edge == "inner")
    return ThickSphere(mesh["a"], mesh["b"], mat.Sy, p)


def tasks(m: Meshes) -> list[dict]:
    """The page's runs, longest first."""
    out = [
        _task(f"axi_sphere_flat_{i}", SPHERE_FLAT, _flat_mesh(scale), fields=True)
        for i, (_, scale) in reversed(list(enumerate(m.sphere_flat)))
    ]
    limit = LIMIT_FACTOR * thick_sphere().p_limit
    # The limit on the case's mesh, quick or not: the CST's overshoot of the limit pressure in
    # isochoric flow is 0.19 % there and 2.1 % at twice its h (event by event, measured).
    out += [
        _task("axi_thick_plastic", THICK, m.thick, fields=True),
        _task("axi_thick_limit", THICK, ["output.snapshots=[1.0]", f"bc.bore.pressure={limit!r}"]),
        _task(
            "axi_thick_elastic",
            THICK,
            [*m.thick, "material.Sy=1e9", f"bc.bore.pressure={P_LAME:g}", "output.snapshots=[1.0]"],
            fields=True,
        ),
        _task("axi_hertz_elastic", HERTZ, m.hertz),
        _task(
            "axi_hertz_first_yield",
            HERTZ,
            [*m.hertz, f"material.Sy={SY_FIRST_YIELD:g}", "output.snapshots=[1.0]"],
            stop_at_first_yield=True,
        ),
    ]
    return out


# --------------------------------------------------------------------------- the numbers
def _run(folder: Path, cid: str) -> tuple[dict, dict]:
    return sweep.load_summary(folder, cid), sweep.load_arrays(folder, cid)


def hertz_numbers(folder: Path) -> dict:
    """a, p0 and the profile against Hertz; first yield against Huber."""
    s, d = _run(folder, "axi_hertz_elastic")
    ref = s["hertz"]
    a, p0 = ref["a_hertz"], ref["p0_hertz"]
    x, p = d["profile_x"], d["profile_pressure"][-1]
    inside = x < 0.9 * a
    dev = (p[inside] - p0 * np.sqrt(1.0 - (x[inside] / a) ** 2)) / p0
    y, _ = _run(folder, "axi_hertz_first_yield")
    f = y["first_yield_load_fraction"]
    a_f = a * f ** (1.0 / 3.0)
    return {
        "n_nodes": s["n_nodes"],
        "a": s["contact_half_width"],
        "a_hertz": a,
        "a_err": s["contact_half_width"] / a - 1.0,
        "p0": s["peak_pressure"],
        "p0_hertz": p0,
        "p0_err": s["peak_pressure"] / p0 - 1.0,
        "profile_rms": float(np.sqrt(np.mean(dev**2))),
        "profile_max": float(np.abs(dev).max()),
        "yield_f": f,
        "yield_f_huber": y["hertz"]["f_yield_johnson"],
        "yield_f_err": y["hertz"]["first_yield_rel_error"],
        "yield_depth_over_a": y["first_yield_depth"] / a_f,
        "yield_depth_huber_over_a": y["hertz"]["first_yield_depth_huber"] / a_f,
        "profile_x": x,
        "profile_p": p,
    }


def ring_volumes(nodes: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """2 pi r_bar A of every element (Pappus)."""
    p = nodes[triangles]
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    return math.pi * p[:, :, 0].mean(axis=1) * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def thick_numbers(folder: Path) -> dict:
    """Lame (elastic), first yield, c(p) and the limit against Hill."""
    ts = thick_sphere()
    a, b = ts.a, ts.b
    s, d = _run(folder, "axi_thick_elastic")
    centre = centroids(d["nodes"], d["triangles"])
    rho = np.linalg.norm(centre, axis=1)
    c, sn = (centre / rho[:, None]).T
    sr, sz, st, trz = d["stress"].T
    radial = sr * c**2 + sz * sn**2 + 2 * trz * c * sn
    lame_r, lame_t = thick_sphere_lame(rho, P_LAME, a, b)
    out = {
        "a": a,
        "b": b,
        "Y": ts.Y,
        "n_nodes": s["n_nodes"],
        "lame_rho": rho,
        "lame_radial": radial,
        "lame_hoop": st,
        "lame_radial_rms": float(np.sqrt(np.mean(((radial - lame_r) / P_LAME) ** 2))),
        "lame_hoop_rms": float(np.sqrt(np.mean(((st - lame_t) / P_LAME) ** 2))),
    }
    out.update(_plastic_front(folder, ts))
    lim, _ = _run(folder, "axi_thick_limit")
    p_stop = lim["final_load_fraction"] * LIMIT_FACTOR * ts.p_limit
    out.update(
        limit_stop=lim["stop"]["kind"],
        p_stop=p_stop,
        p_limit=ts.p_limit,
        limit_err=p_stop / ts.p_limit - 1.0,
    )
    return out


def _plastic_front(folder: Path, ts: ThickSphere) -> dict:
    """First yield and c(p) from the yield events: the plastic shell's ring volume after each
    element's first yield gives c = (a^3 + 3V/(2 pi))^(1/3) (the quarter section is the upper
    hemisphere); compared with Hill's from 1.05 p_e on."""
    s, d = _run(folder, "axi_thick_plastic")
    volume = ring_volumes(d["nodes"], d["triangles"])
    yields = d["events_kind"] == "yield"
    f, element = d["events_load_fraction"][yields], d["events_entity"][yields]
    order = np.sort(np.unique(element, return_index=True)[1])  # each element's first yield
    p = f[order] * ts.p
    c = (ts.a**3 + 1.5 * np.cumsum(volume[element[order]]) / math.pi) ** (1.0 / 3.0)
    beyond = p >= 1.05 * ts.p_e
    c_hill = thick_sphere_radius(p, ts.a, ts.b, ts.Y)
    return {
        "p_first_yield": float(p[0]),
        "p_e": ts.p_e,
        "p_first_yield_err": p[0] / ts.p_e - 1,
        "front_p": p,
        "front_c": c,
        "c_max_err": float(np.abs(c - c_hill)[beyond].max()),
        "c_final": float(c[-1]),
        "c_hill_final": float(thick_sphere_radius(ts.p, ts.a, ts.b, ts.Y)),
        "only_yield_events": bool(set(np.unique(d["events_kind"])) <= {"yield"}),
        "n_events": s["n_events"],
    }


def sphere_flat_numbers(folder: Path, m: Meshes) -> dict:
    """Per mesh: (w, P/P_c, A/A_c) at every closure for both normalisations, and the
    deviations from the fits over 1 <= w <= 50."""
    from ..case import load_case

    case = load_case(_case(SPHERE_FLAT)).record
    mat, R = case.body[0].material, case.body[0].mesh["R"]
    omega_max = case.contact[0].motion[1]
    E_star = mat.E / (1.0 - mat.nu**2)
    fits = {
        "KE": (kogut_etsion_critical(R, E_star, mat.Sy, mat.nu), kogut_etsion),
        "JG": (
            jackson_green_critical(R, E_star, mat.Sy, mat.nu),
            lambda w: jackson_green(w, R, E_star, mat.Sy, mat.nu),
        ),
    }
    out = {"E": mat.E, "nu": mat.nu, "Y": mat.Sy, "R": R, "meshes": []}
    for i, (label, _) in enumerate(m.sphere_flat):
        s, d = _run(folder, f"axi_sphere_flat_{i}")
        omega, a, P = closure_curve(d, omega_max)
        row = {
            "label": label,
            "n_nodes": s["n_nodes"],
            "n_events": s["n_events"],
            "wall_time_s": s["wall_time_s"],
            "omega": omega,
            "a": a,
            "P": P,
        }
        for name, (crit, formula) in fits.items():
            w = omega / crit.interference
            keep = (w >= 1.0) & (w <= 50.5)
            P_fit, A_fit = formula(w[keep])
            dP = P[keep] / crit.force / P_fit - 1.0
            dA = math.pi * a[keep] ** 2 / crit.area / A_fit - 1.0
            row[name] = {
                "P_range": [float(dP.min()), float(dP.max())],
                "A_range": [float(dA.min()), float(dA.max())],
                "at": _marks(w[keep], dP, dA),
            }
        out["meshes"].append(row)
    out["critical"] = {k: vars(c) for k, (c, _) in fits.items()}
    return out


def closure_curve(d: dict, omega_max: float):
    """(omega, a, P) at every closure of a sweep record: the closure fractions x the motion,
    the closing node's radius, the total contact force at the end of that increment."""
    f, r = d["closure_fraction"], d["profile_x"]
    keep = np.isfinite(f) & (f > 0)
    order = np.argsort(f[keep])
    fc = f[keep][order]
    P = np.interp(fc, d["steps_load_fraction"], d["steps_normal_force"])
    return fc * omega_max, r[keep][order], P


def _marks(w, dP, dA) -> dict:
    """The deviations at the closure nearest each of W_MARKS."""
    out = {}
    for mark in W_MARKS:
        if len(w) and w.min() <= mark <= w.max() * 1.05:
            k = int(np.argmin(np.abs(np.log(w / mark))))
            out[f"{mark:g}"] = {"w": float(w[k]), "dP": float(dP[k]), "dA": float(dA[k])}
    return out


# --------------------------------------------------------------------------- figures
def fig_hertz(path: Path, h: dict) -> Path:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 4.8), layout="constrained")
    ax = fig.add_subplot()
    x, p = h["profile_x"], h["profile_p"]
    m = x <= 1.6 * h["a_hertz"]
    ax.plot(x[m], p[m], "o-", ms=3, lw=1, label="slipstep (nodal λn / ring area)")
    xs = np.linspace(0, h["a_hertz"], 300)
    ax.plot(
        xs,
        h["p0_hertz"] * np.sqrt(1 - (xs / h["a_hertz"]) ** 2),
        "k--",
        lw=1,
        label=f"Hertz: a = {h['a_hertz']:.4g} mm, p0 = {h['p0_hertz']:.4g} MPa",
    )
    ax.axvline(h["a"], color="tab:blue", ls=":", lw=1, label=f"slipstep a = {h['a']:.4g} mm")
    ax.set_xlabel("r (mm)")
    ax.set_ylabel("contact pressure (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Hertz sphere (R = 50 mm, P = 30 N, axisymmetric)", fontsize=10)
    fig.savefig(path, dpi=120)
    return path


def fig_thick(path: Path, t: dict) -> Path:
    from matplotlib.figure import Figure

    a, b, Y = t["a"], t["b"], t["Y"]
    fig = Figure(figsize=(12, 4.6), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    rho = np.linspace(a, b, 200)
    sr, st = thick_sphere_lame(rho, P_LAME, a, b)
    ax1.plot(t["lame_rho"], t["lame_radial"], ".", ms=2, color="tab:blue", label="σ_R, elements")
    ax1.plot(
        t["lame_rho"], t["lame_hoop"], ".", ms=2, color="tab:orange", label="σ_θ (hoop), elements"
    )
    ax1.plot(rho, sr, "k-", lw=1, label="Lamé")
    ax1.plot(rho, st, "k--", lw=1)
    ax1.set_xlabel("spherical radius ρ (mm)")
    ax1.set_ylabel("stress (MPa)")
    ax1.set_title(f"elastic, p = {P_LAME:g} MPa", fontsize=10)
    ax1.legend(fontsize=8)
    ax1.grid(alpha=0.3)
    cs = np.linspace(a, b, 400)
    ax2.plot(
        thick_sphere_pressure(cs, a, b, Y),
        cs,
        "k-",
        lw=1,
        label="Hill: p = 2Y ln(c/a) + (2Y/3)(1 − c³/b³)",
    )
    ax2.step(
        t["front_p"],
        t["front_c"],
        where="post",
        color="tab:red",
        label="slipstep: plastic shell's ring volume, per yield event",
    )
    ax2.axvline(t["p_e"], color="0.5", ls=":", lw=1, label=f"p_e = {t['p_e']:.1f} MPa")
    ax2.axvline(
        t["p_limit"],
        color="0.3",
        ls="--",
        lw=1,
        label=f"limit 2Y ln(b/a) = {t['p_limit']:.1f}; stop at {t['p_stop']:.1f}",
    )
    ax2.set_xlabel("internal pressure p (MPa)")
    ax2.set_ylabel("elastic-plastic radius c (mm)")
    ax2.set_title(f"elastic-perfectly plastic (Y = {Y:g} MPa)", fontsize=10)
    ax2.legend(fontsize=8)
    ax2.grid(alpha=0.3)
    fig.suptitle(
        f"Thick-walled sphere a = {a:g}, b = {b:g} mm under internal pressure", fontsize=11
    )
    fig.savefig(path, dpi=120)
    return path


def fig_sphere_flat(path: Path, sf: dict) -> Path:
    """Top: P/P_c and A/A_c against omega/omega_c (KE's critical values), every mesh, both
    fits. Bottom: the runs' deviations from each fit, and the fits' from each other."""
    from matplotlib.figure import Figure

    ke, jg = (sf["critical"][k] for k in ("KE", "JG"))
    w = np.geomspace(0.1, 55, 400)
    fits = _fits_in_ke_units(sf, w)
    fig = Figure(figsize=(12, 8.5), layout="constrained")
    axes = fig.subplots(2, 2, sharex=True)
    for col, key, label in ((0, "P", "P / P_c"), (1, "A", "A / A_c")):
        top, bottom = axes[0, col], axes[1, col]
        top.loglog(w, fits["KE"][key], "k-", lw=1.2, label="Kogut & Etsion (2002)")
        top.loglog(w, fits["JG"][key], "k--", lw=1.2, label="Jackson & Green (2005)")
        bottom.semilogx(
            w,
            100 * (fits["JG"][key] / fits["KE"][key] - 1),
            "k:",
            lw=1,
            label="Jackson & Green − Kogut & Etsion",
        )
        for row, marker in zip(sf["meshes"], "sov^"):
            x = row["omega"] / ke["interference"]
            y = row["P"] / ke["force"] if key == "P" else math.pi * row["a"] ** 2 / ke["area"]
            keep = x >= w[0]
            top.loglog(
                x[keep],
                y[keep],
                marker,
                ms=3.5,
                mfc="none",
                label=f"slipstep, {row['label']} ({row['n_nodes']} nodes)",
            )
            ref = _fits_in_ke_units(sf, x[keep])
            for fit, colour in (("KE", "tab:blue"), ("JG", "tab:red")):
                bottom.semilogx(
                    x[keep],
                    100 * (y[keep] / ref[fit][key] - 1),
                    marker,
                    ms=3.5,
                    color=colour,
                    mfc="none",
                    alpha=0.45 + 0.55 * (row is sf["meshes"][-1]),
                    label=f"{row['label']} − {fit}",
                )
        top.set_ylabel(f"{label} (Kogut & Etsion's critical values)")
        bottom.set_ylabel(f"{key}: slipstep / fit − 1 (%)")
        bottom.set_xlabel("ω / ω_c")
        for ax in (top, bottom):
            ax.axvline(1.0, color="0.6", ls=":", lw=1)
            ax.axvline(6.0, color="0.6", ls=":", lw=1)
            ax.grid(alpha=0.3, which="both")
        top.legend(fontsize=8)
        bottom.axhline(0.0, color="0.3", lw=0.8)
        bottom.set_ylim(-12, 15)
        bottom.legend(fontsize=7, ncol=2)
    fig.suptitle(
        f"Elastic-perfectly plastic sphere on a rigid flat (E/Y = {sf['E'] / sf['Y']:g}, "
        f"ν = {sf['nu']:g}): force and contact area against interference",
        fontsize=11,
    )
    fig.savefig(path, dpi=120)
    return path


def _fits_in_ke_units(sf: dict, w) -> dict:
    """Both fits at w = omega/omega_c(KE), as P/P_c and A/A_c with KE's critical values."""
    R, Y, nu = sf["R"], sf["Y"], sf["nu"]
    E_star = sf["E"] / (1 - nu**2)
    ke, jg = (sf["critical"][k] for k in ("KE", "JG"))
    Pk, Ak = kogut_etsion(w)
    Pj, Aj = jackson_green(
        np.asarray(w) * ke["interference"] / jg["interference"], R, E_star, Y, nu
    )
    return {
        "KE": {"P": Pk, "A": Ak},
        "JG": {"P": Pj * jg["force"] / ke["force"], "A": Aj * jg["area"] / ke["area"]},
    }


# --------------------------------------------------------------------------- the page
def _pc(x: float) -> str:
    return f"{100 * x:+.2f} %"


def _hertz_lines(h: dict) -> list[str]:
    return [
        "## Hertz sphere on a rigid flat",
        "",
        "![Hertz sphere](axi_hertz_sphere.png)",
        "",
        f"`cases/hertz_sphere.toml` ({h['n_nodes']} nodes): R = 50 mm, E = 70 GPa, ν = 0.3, "
        "P = 30 N (a ring total), the hemisphere's section r ≥ 0. Pressures are the nodal "
        "contact forces over their consistent ring areas.",
        "",
        "| quantity | closed form | slipstep | error |",
        "|---|---|---|---|",
        f"| contact radius a (mm) | {h['a_hertz']:.4f} (Hertz) | {h['a']:.4f} | "
        f"{_pc(h['a_err'])} |",
        f"| peak pressure p0 (MPa) | {h['p0_hertz']:.1f} (Hertz) | {h['p0']:.1f} | "
        f"{_pc(h['p0_err'])} |",
        f"| pressure profile, r < 0.9 a | p0 √(1 − r²/a²) | rms {100 * h['profile_rms']:.2f} %, "
        f"largest {100 * h['profile_max']:.2f} % of p0 | |",
        f"| first yield, Sy = {SY_FIRST_YIELD:g} MPa: load fraction | {h['yield_f_huber']:.4f} "
        f"(Huber's axis field: 0.620 p0 = Sy) | {h['yield_f']:.4f} | {_pc(h['yield_f_err'])} |",
        f"| its depth / a | {h['yield_depth_huber_over_a']:.3f} | "
        f"{h['yield_depth_over_a']:.3f} (the element's centroid) | |",
        "",
    ]


def _thick_lines(t: dict) -> list[str]:
    return [
        "## Thick-walled sphere under internal pressure (Hill, ch. V)",
        "",
        "![Thick sphere](axi_thick_sphere.png)",
        "",
        f"`cases/thick_sphere.toml` ({t['n_nodes']} nodes): a = {t['a']:g}, b = {t['b']:g} mm, "
        f"Y = {t['Y']:g} MPa, H′ = 0. With σθ = σφ von Mises and Tresca are one condition, so "
        "Hill's solution is exact for von Mises. The hoop stress σθ comes from the ring's hoop "
        "strain u_r/r, the meridional σφ from the section's stresses.",
        "",
        "| quantity | closed form | slipstep | error |",
        "|---|---|---|---|",
        f"| elastic σ_R at p = {P_LAME:g} MPa (element centroids) | Lamé | rms "
        f"{100 * t['lame_radial_rms']:.2f} % of p | |",
        f"| elastic σθ (hoop) | Lamé | rms {100 * t['lame_hoop_rms']:.2f} % of p | |",
        f"| first yield pressure (MPa) | p_e = (2Y/3)(1 − a³/b³) = {t['p_e']:.2f} | "
        f"{t['p_first_yield']:.2f} | {_pc(t['p_first_yield_err'])} |",
        f"| elastic-plastic radius c (mm), from 1.05 p_e to p = {t['front_p'][-1]:.0f} MPa | "
        f"Hill | largest difference {t['c_max_err']:.3f} mm | |",
        f"| c at the case's pressure (mm) | {t['c_hill_final']:.3f} | {t['c_final']:.3f} | "
        f"{_pc(t['c_final'] / t['c_hill_final'] - 1)} |",
        f"| limit pressure (MPa), asked for {LIMIT_FACTOR:g}× (the case's mesh) | 2Y ln(b/a) = {t['p_limit']:.2f} | "
        f"{t['p_stop']:.2f} (stop: {t['limit_stop']}) | {_pc(t['limit_err'])} |",
        "",
        f"The case's {t['n_events']} events are all yield events "
        f"({'yes' if t['only_yield_events'] else '**no**'}): the plastic shell only grows, so "
        "the radius c is read after every one of them from the shell's ring volume "
        "2π/3 (c³ − a³).",
        "",
    ]


def _sphere_flat_lines(sf: dict) -> list[str]:
    ke, jg = sf["critical"]["KE"], sf["critical"]["JG"]
    lines = [
        "## Elastic-perfectly plastic sphere on a rigid flat: Kogut & Etsion, Jackson & Green",
        "",
        "![sphere on flat](axi_sphere_on_flat.png)",
        "",
        f"`cases/sphere_on_flat_plastic.toml`: R = {sf['R']:g} mm, E = {sf['E'] / 1000:g} GPa, "
        f"ν = {sf['nu']:g}, Y = {sf['Y']:g} MPa (E/Y = {sf['E'] / sf['Y']:g}), H′ = 0, "
        "frictionless, the flat moved up to 50 ω_c against the hemisphere's held base "
        "(ω = the interference, as both papers define it); `solver.group_tol = 0.01`. First "
        f"yield: ω_c = {1000 * ke['interference']:.4f} µm (KE: K H = 2.8 (0.454 + 0.41ν) Y), "
        f"{1000 * jg['interference']:.4f} µm (JG: C = 1.295 e^0.736ν). Measures at every node "
        "closure: ω, the node's radius a (A = πa²) and the flat's total force P.",
        "",
        "Kogut, Etsion, J. Appl. Mech. 69 (2002) 657–662; Jackson, Green, J. Tribol. 127 "
        "(2005) 343–354. The accuracy each paper states for its fits is not reproduced here "
        "(only the papers' openings were at hand); the two fits, made from two independent "
        "finite-element studies, differ from each other by up to 4.6 % in P and 7.0 % in A "
        "over 1 ≤ ω/ω_c ≤ 50.",
        "",
        "| mesh | nodes | events | s | P − KE | A − KE | P − JG | A − JG |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for row in sf["meshes"]:
        rng = [
            f"{100 * row[fit][k][0]:+.1f} … {100 * row[fit][k][1]:+.1f} %"
            for fit in ("KE", "JG")
            for k in ("P_range", "A_range")
        ]
        lines.append(
            f"| {row['label']} | {row['n_nodes']} | {row['n_events']} | "
            f"{row['wall_time_s']:.1f} | " + " | ".join(rng) + " |"
        )
    finest = sf["meshes"][-1]
    lines += [
        "",
        f"On the finest mesh ({finest['label']}), at the closures nearest:",
        "",
        "| ω/ω_c (KE) | P − KE | A − KE | P − JG | A − JG |",
        "|---|---|---|---|---|",
    ]
    for mark, v in finest["KE"]["at"].items():
        j = finest["JG"]["at"].get(mark, {"dP": float("nan"), "dA": float("nan")})
        lines.append(
            f"| {v['w']:.2f} | {_pc(v['dP'])} | {_pc(v['dA'])} | {_pc(j['dP'])} | "
            f"{_pc(j['dA'])} |"
        )
    lines += [
        "",
        "The force converges fast with the mesh; the contact radius, read at the "
        "closing node, converges at first order in h/a (h ≈ a/15 on the case mesh at every "
        "ω), from above: the area's excess over the fits shrinks as the mesh is refined "
        "(the test `tests/physics/test_sphere_on_flat_plastic.py` asserts it).",
        "",
    ]
    return lines


def write_page(path: Path, n: dict) -> Path:
    lines = [
        "# slipstep: axisymmetric analysis",
        "",
        "Generated by `slipstep reproduce" + (" --quick" if n["quick"] else "") + "`; "
        "the runs are in `axisymmetric/axi_*/`, every number in `reproduce.json` under "
        "`axisymmetric`."
        + (" **Quick mode: coarse meshes, for the tests.**" if n["quick"] else ""),
        "",
    ]
    lines += _hertz_lines(n["hertz"]) + _thick_lines(n["thick"])
    lines += _sphere_flat_lines(n["sphere_flat"])
    path.write_text("\n".join(lines))
    return path


def page(out: str | Path, quick: bool = False, workers: int | None = None, log=print) -> dict:
    """Run the page's scenes into ``out/axisymmetric``, draw its figures and write
    ``out/axisymmetric.md``; returns its numbers (arrays left out)."""
    out = Path(out)
    m = QUICK if quick else FULL
    folder = out / "axisymmetric"
    rep = sweep.run_tasks(
        tasks(m), folder, workers=workers, log=log, name="reproduce (axisymmetric)"
    )
    if rep.interrupted:
        raise KeyboardInterrupt
    if rep.failed:
        cid, msg = next(iter(rep.failed.items()))
        raise RuntimeError(f"run {cid} failed: {msg}")
    n = {
        "quick": quick,
        "hertz": hertz_numbers(folder),
        "thick": thick_numbers(folder),
        "sphere_flat": sphere_flat_numbers(folder, m),
    }
    n["figures"] = [
        fig_hertz(out / "axi_hertz_sphere.png", n["hertz"]).name,
        fig_thick(out / "axi_thick_sphere.png", n["thick"]).name,
        fig_sphere_flat(out / "axi_sphere_on_flat.png", n["sphere_flat"]).name,
    ]
    write_page(out / "axisymmetric.md", n)
    return _scalars(n)


def _scalars(n):
    """The numbers without their arrays (for reproduce.json)."""
    if isinstance(n, dict):
        return {k: _scalars(v) for k, v in n.items() if not isinstance(v, np.ndarray)}
    if isinstance(n, list):
        return [_scalars(v) for v in n]
    return n
