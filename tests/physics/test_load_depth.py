"""Load-depth curves from the history of increments (issue 38) against closed forms.

An elastic sphere (R = 50 mm, E = 70 GPa, ν = 0.3; the hemisphere of hertz_sphere.toml,
axisymmetric, its mesh) pressed onto a rigid frictionless flat by a prescribed displacement δ
of its cut, 1.2 µm (Hertz's approach at P ≈ 30 N), then drawn back to 0.  The force P is the
cut's reaction along δ at every increment (no snapshot needed), the flat's force on the sphere
its opposite.

- Hertz (Johnson §4.2): P = (4/3) E* √R δ^(3/2), E* = E/(1 − ν²), the flat rigid.  The cut's
  displacement is Hertz's approach plus the hemisphere's own compression, O(a/R) = 0.5 % of it
  (a = 0.245 mm); the mesh (a/h = 20) measures a within 0.8 %.  Measured: P within +0.02 %
  (δ = 0.2 δ_max) to +0.37 % (δ_max) of Hertz's; tolerance 1 %.
- Oliver–Pharr on the unloading (:mod:`slipstep.measures.indentation`, the paraboloid's ε = 0.75, β = 1,
  A = π (2R h_c − h_c²)): elastic unloading retraces Hertz's curve, so the power law fits
  m = 3/2 with h_f = 0, S = 2 E* a, h_c = δ_max/2 and E_r = E*.  Measured: E_r +0.58 %,
  m = 1.521, h_f = −0.009 δ_max, h_c = 0.502 δ_max; tolerances 2 % on E_r, 0.05 on m, 2 % of
  δ_max on h_f and h_c.  E off by 5 % fails them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import needs_gmsh, write_case
from physics import EQUILIBRIUM_TOL

from slipstep import prepare, solve
from slipstep.measures.indentation import oliver_pharr
from slipstep.measures.resultants import drivers, step_history

E, NU, R, DELTA = 70000.0, 0.3, 50.0, 1.2e-3
E_STAR = E / (1.0 - NU**2)

SPHERE = f"""
[case]
name = "sphere_by_displacement"
units = "mm, N, MPa"
[analysis]
plane = "axisymmetric"
[output]
snapshots = [1.0, 2.0]
figures = false
xdmf = false
[[stage]]
name = "press"
factors = {{ approach = 1.0 }}
[[stage]]
name = "release"
factors = {{ approach = 0.0 }}
[[body]]
name = "sphere"
[body.mesh]
generator = "quarter_cylinder"
R = {R}
h_contact = 0.012
contact_zone = 0.5
h_max = 3.0
growth = 0.1
[body.material]
E = {E}
nu = {NU}
[[bc]]
name = "approach"
body = "sphere"
edge = "top"
displacement = {{ y = {-DELTA} }}
[[contact]]
name = "flat"
kind = "rigid_line"
body = "sphere"
edge = "arc"
point = [0.0, 0.0]
normal = [0.0, 1.0]
x_max = 0.5
mu = 0.0
"""


@pytest.fixture(scope="module")
def pressed(tmp_path_factory):
    """(scene, result, history, the approach's driver curve)."""
    pytest.importorskip("gmsh")
    scene = prepare(write_case(tmp_path_factory.mktemp("sphere"), SPHERE))
    result = solve(scene)
    assert result["stop"]["kind"] == "completed"
    h = step_history(scene, result)
    return scene, result, h, drivers(scene, h)["approach"]


def hertz_force(delta):
    return 4.0 / 3.0 * E_STAR * math.sqrt(R) * np.asarray(delta) ** 1.5


@needs_gmsh
def test_the_force_follows_hertz_at_every_increment(pressed):
    scene, result, h, d = pressed
    assert d["kind"] == "displacement" and d["direction"].tolist() == [0.0, -1.0, 0.0]
    loading = (h["stage"] == 0) & (d["displacement"] >= 0.2 * DELTA)
    assert loading.sum() >= 10  # an increment per closing ring: the curve, not two points
    error = d["force"][loading] / hertz_force(d["displacement"][loading]) - 1.0
    assert np.abs(error).max() <= 0.01, error
    # the flat pushes the sphere up by what the cut's reaction pushes it down
    flat = h["contact_force"][:, 0, 1]
    assert np.all(np.abs(flat - d["force"]) <= EQUILIBRIUM_TOL * d["force"].max())
    assert d["displacement"][-1] == 0.0 and abs(d["force"][-1]) <= 1e-9 * d["force"].max()


@needs_gmsh
def test_oliver_pharr_recovers_the_modulus_of_an_elastic_unloading(pressed):
    _, _, h, d = pressed
    op = oliver_pharr(d["displacement"], d["force"], "sphere", radius=R)
    assert op["h_max"] == pytest.approx(DELTA, rel=1e-12) and op["n_fit"] >= 4
    assert abs(op["m"] - 1.5) <= 0.05, op
    assert abs(op["h_f"]) <= 0.02 * DELTA, op
    assert abs(op["h_c"] - DELTA / 2) <= 0.02 * DELTA, op
    assert op["E_r"] == pytest.approx(E_STAR, rel=0.02), op
    assert abs(op["E_r"] / (1.05 * E_STAR) - 1) > 0.02  # 5 % off in E would fail


def test_oliver_pharr_of_the_closed_forms():
    """On exact curves: Hertz's paraboloid unloading gives E* (to the area's h_c² term,
    2.5e-4 here) and m = 3/2; a plastic-like unloading P = α (h − h_f)^m is fitted exactly."""
    h = np.concatenate([np.linspace(0.0, 0.01, 30), np.linspace(0.01, 0.0, 30)[1:]])
    op = oliver_pharr(h, hertz_force(h), "sphere", radius=R)
    assert op["E_r"] == pytest.approx(E_STAR, rel=1e-3) and op["m"] == pytest.approx(1.5, abs=1e-9)
    unload = np.linspace(0.03, 0.02, 40)
    curve = np.concatenate([np.linspace(0.0, 0.03, 20), unload[1:]])
    P = np.concatenate(
        [
            2e3 * np.linspace(0.0, 0.03, 20) ** 1.2,
            7e3 * (unload[1:] - 0.021).clip(0) ** 1.4 * (2e3 * 0.03**1.2) / (7e3 * 0.009**1.4),
        ]
    )
    op = oliver_pharr(curve, P, "vickers")
    assert op["h_f"] == pytest.approx(0.021, rel=1e-6) and op["m"] == pytest.approx(1.4, rel=1e-6)
    S = P[19] * 1.4 / (0.03 - 0.021)
    assert op["S"] == pytest.approx(S, rel=1e-6)
    h_c = 0.03 - 0.72 * P[19] / S
    assert op["A"] == pytest.approx(4 * math.tan(math.radians(68)) ** 2 * h_c**2, rel=1e-6)
    assert op["E_r"] == pytest.approx(
        math.sqrt(math.pi) * S / (2 * 1.012 * math.sqrt(op["A"])), rel=1e-12
    )
