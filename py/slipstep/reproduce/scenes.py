"""The scenes of the reproduction: the paper's numbers and the closed-form values they are
compared with, the mesh settings (full and quick), every run as a sweep task, and one finished
run read back (:class:`Run`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import shipped, sweep
from ..measures.contact_edges import stick_half_width
from ..measures.references import (
    JOHNSON_LINE_YIELD,
    JOHNSON_LINE_YIELD_DEPTH,
    effective_modulus,
    hertz_line,
)


SY, H_PLASTIC = 200.0, 700.0  # Al-5%Mg yield stress (paper) and our hardening modulus
PLASTIC = [f"material.Sy={SY:g}", f"material.H={H_PLASTIC:g}"]
MUS = (0.0, 0.1, 0.35)
R, E, NU, P = 125.0, 70000.0, 0.3, 1000.0
E_STAR = effective_modulus(E, NU)
A_HERTZ, P0_HERTZ = hertz_line(P, R, E, NU)  # 1.4384 mm, 442.6 MPa
P0_JOHNSON = JOHNSON_LINE_YIELD * SY  # 358 MPa (von Mises, nu = 0.3)
A_JOHNSON = 2.0 * R * P0_JOHNSON / E_STAR  # Hertz a at p0 = 358: 1.164 mm
F_JOHNSON = (P0_JOHNSON / P0_HERTZ) ** 2  # 0.654
DEPTH_JOHNSON = JOHNSON_LINE_YIELD_DEPTH  # z / a of first yield
PAPER_TABLE1 = {  # analytical (paper), FEM (paper), error % (paper)
    "elastic_a": (1.438, 1.43, 0.58),
    "elastic_p0": (442.6, 451.0, 1.86),
    "yield_a": (1.036, 1.08, 4.04),
    "yield_p0": (358.0, 323.9, 9.5),
}
BLOCK_B = 10.0  # punch half-width in the block cases (mm)


@dataclass(frozen=True)
class Settings:
    """Mesh sizes (mm). Full: the shipped default mesh for Table 1 and Fig. 10 (h = 0.03 at the
    contact), h = 0.1 for the full elastoplastic cylinder runs (one refactorization per yield
    event: 500-650 events, 2-4 s each), the case files' meshes for the blocks (their half-space
    is the structured grid of spacing h inside refine_box under the punch, graded outside)."""

    quick: bool
    h_table: float
    h_cyl: float
    h_fig10: float | None  # None: the study's own (the default mesh)
    h_block_elastic: float
    h_block_plastic: float
    h_check_elastic: float  # half-space doubling check, elastic case
    h_check_plastic: float  # half-space doubling check, elastoplastic mu = 0.2


FULL = Settings(False, 0.03, 0.1, None, 0.5, 1.0, 0.5, 2.0)


QUICK = Settings(True, 0.1, 0.15, 0.1, 1.0, 2.0, 1.0, 2.0)


def shipped_path(kind: str, name: str) -> Path:
    """A shipped case or study (:mod:`slipstep.shipped`: works from an installed wheel)."""
    return shipped.path(name, kind)


def task(cid: str, base, overrides, **options) -> dict:
    opts = dict(sweep.OUTPUT_KEYS)
    opts.update(options)
    return {
        "case_id": cid,
        "params": {"scene": cid},
        "base": None if base is None else str(base),
        "overrides": list(overrides),
        "options": opts,
    }


def mu_id(mu: float) -> str:
    return f"{mu:g}"


def _block_mesh(h: float) -> list[str]:
    """The block cases at spacing h: the punch, and the half-space's structured grid inside its
    refine_box (the grading outside follows from h, h_max and growth)."""
    return [f"body.punch.mesh.h={h:g}", f"body.halfspace.mesh.h={h:g}"]


# the half-space's size doubled (10 b -> 20 b each way); its refine_box, spacing and grading law
# stay, so the mesh near the punch is the same and only the far field grows
DOUBLE = [
    "body.halfspace.mesh.width=200",
    "body.halfspace.mesh.height=200",
    "body.halfspace.mesh.y0=-200",
]


def scene_tasks(s: Settings) -> list[dict]:
    """Every run of the reproduction but Fig. 10 (longest first, for the process pool)."""
    block_el, block_pl = (
        shipped_path("cases", "paper_block_elastic.toml"),
        shipped_path("cases", "paper_block_plastic.toml"),
    )
    snaps = "output.snapshots=[0.25, 0.5, 0.75, 1.0]"
    tasks = []
    for mu in (0.2, 0.0):
        tasks.append(
            task(
                f"block_plastic_mu{mu_id(mu)}",
                block_pl,
                [*_block_mesh(s.h_block_plastic), f"contact.mu={mu}"],
                results=True,
                fields=True,
            )
        )
    tasks.append(task("block_elastic", block_el, _block_mesh(s.h_block_elastic), results=True))
    tasks.append(
        task("check_block_elastic_2x", block_el, [*_block_mesh(s.h_check_elastic), *DOUBLE, snaps])
    )
    if s.h_check_elastic != s.h_block_elastic:
        tasks.append(
            task("check_block_elastic_1x", block_el, [*_block_mesh(s.h_check_elastic), snaps])
        )
    for mu in MUS[::-1]:
        tasks.append(
            task(
                f"cyl_plastic_mu{mu_id(mu)}",
                None,
                [*PLASTIC, f"mesh.h_contact={s.h_cyl:g}", f"contact.mu={mu}", snaps],
                results=True,
                fields=True,
            )
        )
    tasks.append(
        task("table1_elastic", None, [f"mesh.h_contact={s.h_table:g}", snaps], results=True)
    )
    tasks.append(
        task(
            "table1_yield",
            None,
            [*PLASTIC, f"mesh.h_contact={s.h_table:g}", "output.snapshots=[1.0]"],
            results=True,
            fields=True,
            stop_at_first_yield=True,
        )
    )
    for mu in MUS:
        tasks.append(
            task(
                f"cyl_elastic_mu{mu_id(mu)}",
                None,
                [f"mesh.h_contact={s.h_cyl:g}", f"contact.mu={mu}", snaps],
                results=True,
            )
        )
    tasks.append(
        task(
            "check_block_plastic_2x",
            block_pl,
            [*_block_mesh(s.h_check_plastic), "contact.mu=0.2", *DOUBLE],
        )
    )
    if s.h_check_plastic != s.h_block_plastic:  # else block_plastic_mu0.2 is that run
        tasks.append(
            task(
                "check_block_plastic_1x",
                block_pl,
                [*_block_mesh(s.h_check_plastic), "contact.mu=0.2"],
            )
        )
    # the same half-space without hardening (H' = 0): where would it flow? (may fail to finish)
    tasks.append(
        task(
            "probe_block_perfectly_plastic",
            block_pl,
            [*_block_mesh(s.h_check_plastic), "body.halfspace.material.H=0"],
            fields=True,
        )
    )
    tasks.append(
        task(
            "block_plastic_elastic_reference",
            block_pl,
            [
                *_block_mesh(s.h_block_plastic),
                "contact.mu=0.2",
                "body.punch.material.Sy=1e12",
                "body.halfspace.material.Sy=1e12",
            ],
            results=False,
        )
    )
    return tasks


def fig10_study(s: Settings) -> sweep.Study:
    extra = [] if s.h_fig10 is None else [f"mesh.h_contact={s.h_fig10:g}"]
    return sweep.load_study(shipped_path("studies", "fig10_onset_of_yield.toml"), extra_set=extra)


class Run:
    """One finished run: its summary and arrays (result.npz)."""

    def __init__(self, folder: Path, cid: str):
        self.cid = cid
        self.folder = folder / cid
        self.summary = sweep.load_summary(folder, cid)
        self.data = sweep.load_arrays(folder, cid)

    @property
    def x(self):
        return self.data["profile_x"]

    def profile(self, key: str, k: int = -1) -> np.ndarray:
        """A contact quantity at snapshot k; tangential quantities turned to +x (the engine's
        tangent for a normal (0, 1) is -x)."""
        v = self.data[f"profile_{key}"][k]
        return -v if key in ("tangential_stress", "rtd") else v

    def snapshot_index(self, f: float) -> int:
        return int(np.argmin(np.abs(self.data["snap_load_fraction"] - f)))

    def status(self, k: int = -1) -> np.ndarray:
        return self.data["profile_status"][k].astype(int)

    @property
    def a(self) -> float:
        return float(self.summary["contact_half_width"])

    def pressure_ratio(self) -> float:
        """Peak over mean pressure, mean = (normal force of the modelled part) / a."""
        return float(self.summary["peak_pressure"] / (self.summary["total_normal_force"] / self.a))

    def slip_length(self, k: int = -1, a: float | None = None) -> float:
        a = self.a if a is None else a
        return a - stick_half_width(self.x, self.status(k), a)
