"""Cattaneo–Mindlin partial slip and Mindlin–Deresiewicz hysteresis of a line contact
(cases/cattaneo_mindlin.toml: a half cylinder R = 125 mm on a block of the same material,
Dundurs β = 0, node-to-segment contact, μ = 0.3; pressed by a prescribed approach, then sheared
by a tangential traction on its cut up to Q* = 0.755 μP), here with the load path cycled by
two more [[stage]]s: the shear reversed to −Q*, then back to +Q*.

* The stick zone: centred, c = a √(1 − Q/μP) (Johnson §7.1).
* The shear tractions themselves (tests/physics.py ``cattaneo_traction``): they see the
  contact's size and pressure, which c/a does not.
* Energy: over the cycle the work of the load on the cut equals the frictional dissipation
  −Σ λ_t Δrtd (over every increment, trapezoidal: exact on the piecewise-linear path) plus the
  change of the elastic energy (recomputed from the stresses): the loop's area is what friction
  dissipates, recomputed pair by pair.
* That area against the planar analogue of Mindlin–Deresiewicz's energy per cycle
  (``line_contact_dissipation``, derived in tests/physics.py): W ∝ (1 − ν²)/E, so it sees a
  compliance error (E off by 20 %: W off by 17 %) that c/a cannot.

Two meshes, h = 0.1 and 0.05 mm at the contact (a = 1.84 mm); the reasons of each tolerance
are with each test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, applied_load, strain_energy, worst_equilibrium
from slipstep.measures.references import cattaneo_traction, line_contact_dissipation

from slipstep import build_scene, parse_case, solve

pytestmark = needs_gmsh

R, E, NU = 125.0, 70000.0, 0.3
E_STAR = E / (2.0 * (1.0 - NU**2))  # two equal bodies: 1/E* = 2 (1 - nu^2)/E
CYCLE = """
[[stage]]
name = "reverse"
factors = { shear = -1.0 }

[[stage]]
name = "return"
factors = { shear = 1.0 }
"""
MESHES = (0.1, 0.05)


@pytest.fixture(scope="module")
def runs():
    text = (CASES / "cattaneo_mindlin.toml").read_text() + CYCLE
    out = {}
    for h in MESHES:
        sets = [
            f"body.roller.mesh.h_contact={h}",
            f"body.block.mesh.h_contact={h}",
            "output.figures=false",
        ]
        scene = build_scene(parse_case(text, "cattaneo_mindlin", CASES, sets))
        result = solve(scene)
        assert result["stop"]["kind"] == "completed", result["stop"]
        out[h] = (scene, result)
    return out


def settled(snaps):
    """The last snapshot at each path time (after every event there)."""
    return [s for s, nxt in zip(snaps, snaps[1:] + [None]) if nxt is None or nxt["t"] != s["t"]]


def normal_load(result) -> float:
    """P per unit thickness at the end of the approach (the rows' λ_n; the cut's reaction)."""
    return float([s for s in result["snapshots"] if s["stage"] == 0][-1]["lambda_n"].sum())


def shear_peak(scene) -> float:
    """Q* = 2R t_x: the cut's traction at factor 1 over its width 2R."""
    bc = next(b for b in scene.case.data["bc"] if b["name"] == "shear")
    return bc["traction"][0] * 2.0 * R


def tributary(scene) -> np.ndarray:
    """Each contactor row's length on the roller's arc (half its two segments)."""
    arc = scene.global_edge("roller", "arc")
    length = np.linalg.norm(scene.nodes[arc[:, 1]] - scene.nodes[arc[:, 0]], axis=1)
    per_node = np.zeros(len(scene.nodes))
    np.add.at(per_node, arc[:, 0], 0.5 * length)
    np.add.at(per_node, arc[:, 1], 0.5 * length)
    return per_node[scene.model["pairs"]["node_a"]]


def test_runs_are_in_equilibrium(runs):
    for scene, result in runs.values():
        worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
        assert worst <= EQUILIBRIUM_TOL, (k, f, worst)


def test_stick_zone(runs):
    """Q/μP = 0.25, 0.5, 0.75 (the tangential stage is linear in t; statuses only change at
    events, so the state at a given Q is the last settled snapshot before it), on the fine
    mesh: the stick zone is centred within one node spacing h = 0.05 mm, and its half-width
    c = a √(1 − Q/μP) within h (a from the closed pairs; c, a measured on nodes h apart). The
    normal load P is the approach's and does not change while Q grows (β = 0): the two
    independently meshed surfaces couple a little discretely, which must stay far below what
    the c check allows (h/a = 2.5 %): 1e-3."""
    scene, result = runs[0.05]
    mu = scene.case.data["contact"][0]["mu"]
    x = scene.pair_xy[:, 0]
    snaps = settled(result["snapshots"])
    P = normal_load(result)
    shear = [s for s in snaps if s["stage"] == 1]
    assert max(abs(s["lambda_n"].sum() / P - 1) for s in shear) < 1e-3
    h = 0.05
    for ratio in (0.25, 0.5, 0.75):
        t = 1.0 + ratio * mu * P / shear_peak(scene)
        s = [s for s in shear if s["t"] <= t + 1e-12][-1]
        status = np.asarray(s["status"])
        closed, stick = x[status > 0], x[status == 1]
        a = 0.5 * (closed.max() - closed.min())
        c = 0.5 * (stick.max() - stick.min())
        centre = 0.5 * (stick.max() + stick.min())
        assert abs(centre) <= h, f"Q/μP = {ratio}: stick zone centred at {centre}"
        assert abs(c - a * math.sqrt(1 - ratio)) <= h, f"Q/μP = {ratio}: c/a = {c / a:.4f}"
        assert (status[(x > stick.max()) & (status > 0)] == 2).all()


def traction_errors(scene, result) -> list[float]:
    """∫ |q − q_Cattaneo| dx / (μP) at Q/μP ~ 0.25, 0.5, 0.75 of the first shear stage: q the
    nodal shear λ_t/(L t) (L each row's tributary length on the arc), the reference at the
    snapshot's own Q = Σ λ_t, with Hertz's a = √(4PR/(πE*)), p0 = 2P/(πa) for its P."""
    mu = scene.case.data["contact"][0]["mu"]
    x, length = scene.pair_xy[:, 0], tributary(scene) * scene.model["thickness"]
    P = normal_load(result)
    a = math.sqrt(4.0 * P * R / (math.pi * E_STAR))
    p0 = 2.0 * P / (math.pi * a)
    shear = [s for s in settled(result["snapshots"]) if s["stage"] == 1]
    errors = []
    for ratio in (0.25, 0.5, 0.75):
        t = 1.0 + ratio * mu * P / shear_peak(scene)
        snap = [s for s in shear if s["t"] <= t + 1e-12][-1]
        Q = float(snap["lambda_t"].sum())
        reference = cattaneo_traction(x, a, a * math.sqrt(1.0 - Q / (mu * P)), p0, mu)
        q = np.asarray(snap["lambda_t"]) / length
        errors.append(float(np.sum(np.abs(q - reference) * length) / (mu * P)))
    return errors


def test_shear_tractions_follow_cattaneo(runs):
    """The nodal shear against Cattaneo's q(x) in the L1 norm relative to μP: it falls from
    h = 0.1 to 0.05 at each Q and is within 5 % on the fine mesh (measured 4.6, 4.3, 3.7 % and
    2.9, 2.4, 1.8 %: nodal tractions of linear elements, whose error is spread over the
    contact, with the derivative of q singular at the contact and stick edges).  E off by
    20 % (5 %) moves Hertz's a and p0 and Cattaneo's q by 9-12 % (2.6-3.1 %) in this norm."""
    coarse, fine = (traction_errors(*runs[h]) for h in MESHES)
    assert all(f < c for c, f in zip(coarse, fine)), (coarse, fine)
    assert max(fine) <= 0.05, fine


def cycle_energies(scene, result) -> dict:
    """Over the cycle t = 2 (Q*) -> 3 (-Q*) -> 4 (Q*), increment by increment (every event a
    snapshot; trapezoidal, exact on the piecewise-linear path): ``work`` of the applied loads
    (the supports' reactions do none: their DOFs do not move after the approach),
    ``dissipated`` = −Σ λ_t Δrtd − Σ λ_n Δgap, and ``elastic`` = the strain energy's change."""
    snaps = [s for s in result["snapshots"] if s["t"] >= 2.0 - 1e-12]
    model, body = scene.model, scene.case.data["body"][0]["material"]
    work = dissipated = 0.0
    for s0, s1 in zip(snaps[:-1], snaps[1:]):
        force = 0.5 * (applied_load(model, s0["t"]) + applied_load(model, s1["t"]))
        work += float(force @ (np.asarray(s1["u"]) - np.asarray(s0["u"])).reshape(-1))
        for lam, rel in (("lambda_t", "rtd"), ("lambda_n", "gap")):
            dissipated -= float(0.5 * (s0[lam] + s1[lam]) @ (np.asarray(s1[rel]) - s0[rel]))
    energy = [
        strain_energy(
            scene.nodes, scene.triangles, s["stress"], body["E"], body["nu"], model["thickness"]
        )
        for s in (snaps[0], snaps[-1])
    ]
    return {"work": work, "dissipated": dissipated, "elastic": energy[1] - energy[0]}


def test_loop_area_is_the_frictional_dissipation(runs):
    """The work of the shear over the cycle (the hysteresis loop's area) = the energy friction
    dissipates, recomputed pair by pair from the slip increments and the tangential forces,
    + the change of the elastic energy, to 1e-9 of the work: an identity of any equilibrium
    path that is linear between events (both sides summed over the same increments), so only
    round-off separates them (measured 4e-14).  The cycle closes: the elastic energy returns to
    within 1e-3 of the work (Masing: the state at +Q* is the same before and after the cycle;
    measured 1e-6, 7e-6: the two meshes' stick and slip patterns repeat to an event).  E off
    by 20 % leaves this identity whole (it holds for any stiffness): the next test sees it."""
    for h, (scene, result) in runs.items():
        e = cycle_energies(scene, result)
        assert e["work"] > 0 and e["dissipated"] > 0
        assert abs(e["work"] - e["dissipated"] - e["elastic"]) <= 1e-9 * e["work"], (h, e)
        assert abs(e["elastic"]) <= 1e-3 * e["work"], (h, e)


def test_dissipation_per_cycle_is_mindlin_deresiewicz(runs):
    """The loop's area against the planar Mindlin–Deresiewicz energy for the measured P and
    the applied Q*: within 1 % on both meshes, closer on the finer (measured +0.61 %,
    +0.03 %).  The closed form is for half-planes: the cylinder's curvature (a/R = 0.015) and
    the block's depth (a/H = 0.046) enter as their squares, below 0.3 %; the rest is the
    discretization of the slip zones (first order in h/a = 0.054, 0.027).  W ∝ (1 − ν²)/E at
    a given P: E off by 2 % already moves it by 2 %; the case with E x 1.2 (its approach then
    presses harder) gives -15.5 %, -16.5 %."""
    errors = []
    for h in MESHES:
        scene, result = runs[h]
        mu = scene.case.data["contact"][0]["mu"]
        W = line_contact_dissipation(normal_load(result), shear_peak(scene), mu, E, NU)
        errors.append(cycle_energies(scene, result)["work"] / W - 1.0)
    assert abs(errors[1]) < abs(errors[0]) <= 0.01, errors
