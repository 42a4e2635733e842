"""The stability study's report: its CSV, its markdown table and its figure (``stability``
runs the scenarios; this writes what they found)."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

#: The CSV's columns, in order.
COLUMNS = [
    "scenario",
    "group",
    "status",
    "error",
    "n_events",
    "n_steps",
    "final_load_fraction",
    "max_residual",
    "max_drift",
    "reference",
    "rel_error",
    "note",
    "wall_s",
    "p_full",
]


def _fmt(v):
    if isinstance(v, float):
        if math.isnan(v):
            return ""
        return f"{v:.3g}" if abs(v) >= 1e-3 or v == 0 else f"{v:.1e}"
    return str(v)


def write_csv(path: Path, rows: list[dict]) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in COLUMNS})


def markdown_table(rows: list[dict]) -> str:
    cols = [
        "scenario",
        "status",
        "n_events",
        "final_load_fraction",
        "max_residual",
        "max_drift",
        "rel_error",
        "wall_s",
        "note",
        "error",
    ]
    head = [
        "scenario",
        "status",
        "events",
        "f_end",
        "max residual",
        "max drift",
        "error vs ref",
        "wall s",
        "what it shows",
        "error line",
    ]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        lines.append("| " + " | ".join(_fmt(r.get(c, "")).replace("|", "/") for c in cols) + " |")
    return "\n".join(lines)


def figure(path: Path, rows: list[dict], inc: dict) -> None:
    from .figures.frame import Plots  # pyplot's calls on the object API: notebook-safe

    plt = Plots()

    fig, (ax0, ax1, ax2) = plt.subplots(1, 3, figsize=(18, 5.5))
    p_lim = inc.get("p_lim", float("nan"))
    styles = {"gmsh CST": "-", "structured 2-tri": "--", "union jack": ":"}
    u_lim = None
    for (mname, nu), val in inc.get("curves", {}).items():
        pp, ur = val[0], val[1]
        u_lim = u_lim or (1 + 0.3) * 250 / math.sqrt(3) * (2 - 0.6) * 20.0 / 200000.0
        ax1.plot(ur * 1e3, pp, styles.get(mname, "-"), label=f"{mname}, nu = {nu}")
    ax1.axhline(p_lim, color="k", lw=0.8)
    ax1.text(0.0, p_lim, " Hill limit 2k ln(b/a)", va="bottom")
    if u_lim:
        ax1.set_xlim(0, 30 * u_lim * 1e3)
    ax1.set_xlabel("outer radial displacement u(b) [µm] (clipped)")
    ax1.set_ylabel("bore pressure p [MPa]")
    ax1.set_title("thick cylinder loaded to 1.1 p_lim")
    ax1.legend(fontsize=7)
    markers = {"gmsh CST": "o", "structured 2-tri": "s", "union jack": "^"}
    for mname in markers:
        sel = [r for r in rows if r.get("mesh") == mname]
        if not sel:
            continue
        x = [r["nu"] for r in sel]
        y = [(r["p_full"] / p_lim) if not math.isnan(r["p_full"]) else float("nan") for r in sel]
        ax0.plot(range(len(x)), y, marker=markers[mname], label=mname)
        for i, r in enumerate(sel):
            if r["status"] not in ("completed", "limit load") or math.isnan(r["p_full"]):
                ax0.plot(i, 1.1, "x", color="tab:red", ms=10)
        ax0.set_xticks(range(len(x)), [str(v) for v in x])
    ax0.axhline(1.0, color="k", lw=0.8)
    ax0.set_xlabel("Poisson's ratio nu")
    ax0.set_ylabel("p (all elements plastic) / Hill limit")
    ax0.set_title("volumetric locking of CST (x: never fully plastic / stopped)")
    ax0.legend(fontsize=8)
    names = [r["scenario"] for r in rows if r["group"] != "newton"]
    res = [
        r["max_residual"] if isinstance(r["max_residual"], float) else float("nan")
        for r in rows
        if r["group"] != "newton"
    ]
    res = [max(x, 1e-17) if not math.isnan(x) else float("nan") for x in res]
    colors = [
        "tab:green" if r["status"] == "completed" else "tab:red"
        for r in rows
        if r["group"] != "newton"
    ]
    y = np.arange(len(names))
    ax2.barh(y, res, color=colors)
    failed = [i for i, x in enumerate(res) if math.isnan(x)]
    if failed:  # no residual: the run failed, mark it at the tolerance
        ax2.plot([1e-9] * len(failed), failed, "x", color="tab:red", ms=9)
    ax2.set_xscale("log")
    ax2.axvline(1e-9, color="k", lw=0.8, ls="--")
    ax2.set_yticks(y, names, fontsize=6)
    ax2.invert_yaxis()
    ax2.set_xlabel("max equilibrium residual (green: completed, red: stopped/failed)")
    ax2.set_title("every scenario")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
