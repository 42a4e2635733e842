"""Patch tests of the axisymmetric ring element through the whole front (case -> engine).

A cylinder r_in <= r <= r_in + 1, 0 <= z <= 1 (structured block mesh, 4 x 4 cells) held axially
on z = 0 and loaded on its other edges by the tractions sigma . n of the uniform stress of the
strain state

    u_r = A r,  u_z = B z   =>   eps_r = eps_theta = A,  eps_z = B,  gamma_rz = 0,

sigma_r = sigma_theta = 2 (lambda + G) A + lambda B, sigma_z = 2 lambda A + (lambda + 2G) B.  With
sigma_r = sigma_theta the uniform stress satisfies the radial equilibrium
d sigma_r/dr + (sigma_r - sigma_theta)/r = 0 without body force, so this is the exact solution.
It lies in the finite element space (linear u), the centroid hoop strain (u_r1 + u_r2 + u_r3)/
(3 r_bar) is exact for u_r proportional to r, and the ring weight 2 pi r_bar A integrates the
virtual work of a uniform stress exactly; with consistent ring loads (2 pi int N_i r t ds, the
case's [[bc]] traction) the engine must reproduce the state to round-off, on a patch that
touches the axis (r_in = 0: its axis nodes held radially by the analysis) and on one away from
it (r_in = 0.5).  Round-off: displacements of order 1e-3 from a solve of ~50 DOFs (1e-14
absolute), stresses of order 1 (1e-11), equilibrium recomputed in tests/physics.py (1e-12
relative).

Also: a rigid translation along the axis (the only zero-energy mode of a ring) prescribed on the
bottom edge produces no strain, stress or force; and a uniform pressure on a block resting on a
rigid flat gives the same pressure at every contact node, the axis node included (the
consistent ring area of slipstep.contact.edges.contact_areas).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import write_case
import physics

from slipstep import Case, prepare, run, solve
from slipstep.measures.contact_edges import contact_profile

E, NU = 1000.0, 0.3
LAME, G = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
A, B = 2e-3, -1e-3
SIGMA_R = 2 * (LAME + G) * A + LAME * B
SIGMA_Z = 2 * LAME * A + (LAME + 2 * G) * B


def patch_case(r_in: float, extra: str = "") -> str:
    inner = (
        f'[[bc]]\nbody = "patch"\nedge = "left"\ntraction = [{-SIGMA_R!r}, 0.0]\n'
        if r_in > 0
        else ""
    )
    return f'''
[analysis]
plane = "axisymmetric"
[output]
figures = false
xdmf = false
[[body]]
name = "patch"
[body.mesh]
generator = "block"
x0 = {r_in}
width = 1.0
height = 1.0
nx = 4
ny = 4
[body.material]
E = {E}
nu = {NU}
[[bc]]
body = "patch"
edge = "bottom"
symmetry = true
[[bc]]
body = "patch"
edge = "right"
traction = [{SIGMA_R!r}, 0.0]
[[bc]]
body = "patch"
edge = "top"
traction = [0.0, {SIGMA_Z!r}]
{inner}{extra}'''


@pytest.mark.parametrize("r_in", [0.0, 0.5], ids=["touching_axis", "away_from_axis"])
def test_uniform_radial_and_axial_strain_is_reproduced(tmp_path, r_in):
    scene = prepare(write_case(tmp_path, patch_case(r_in)))
    result = solve(scene)
    snap = result["snapshots"][-1]
    u = np.asarray(snap["u"]).reshape(-1, 2)
    r, z = scene.nodes.T
    assert np.abs(u[:, 0] - A * r).max() < 1e-14
    assert np.abs(u[:, 1] - B * z).max() < 1e-14
    stress = np.asarray(snap["stress"])
    assert np.abs(stress - [SIGMA_R, SIGMA_Z, SIGMA_R, 0.0]).max() < 1e-11
    assert physics.equilibrium_residual(scene.model, snap) < 1e-12
    if r_in == 0.0:  # the axis nodes are held radially: their reaction is the only force there
        axis = np.flatnonzero(r == 0.0)
        assert len(axis) == 5 and np.all(u[axis, 0] == 0.0)


def test_equilibrium_check_sees_a_wrong_hoop_stress(tmp_path):
    """The recomputed ring equilibrium is not blind to the hoop stress: 10 % too much sigma_theta
    leaves an unbalanced radial force far above round-off."""
    scene = prepare(write_case(tmp_path, patch_case(0.5)))
    snap = dict(solve(scene)["snapshots"][-1])
    snap["stress"] = np.asarray(snap["stress"]) * [1.0, 1.0, 1.1, 1.0]
    assert physics.equilibrium_residual(scene.model, snap) > 1e-2


def test_axial_rigid_translation_is_free_of_strain_and_force(tmp_path):
    """u_z = 0.01 prescribed on the bottom edge, nothing else: the ring translates along the
    axis as a rigid body (a zero-energy mode: no radial support needed, u_r = 0), no stress,
    no reaction (round-off of a solve with displacements 0.01)."""
    text = (
        patch_case(0.5).split("[[bc]]")[0]
        + '''
[[bc]]
body = "patch"
edge = "bottom"
displacement = {y = 0.01}
'''
    )
    scene = prepare(write_case(tmp_path, text))
    snap = solve(scene)["snapshots"][-1]
    u = np.asarray(snap["u"]).reshape(-1, 2)
    assert np.abs(u[:, 1] - 0.01).max() < 1e-15 and np.abs(u[:, 0]).max() < 1e-15
    assert np.abs(np.asarray(snap["stress"])).max() < 1e-11
    assert np.abs(np.asarray(snap["reaction"])).max() < 1e-12


def test_uniform_pressure_on_a_flat_is_read_at_every_ring(tmp_path):
    """A cylinder resting frictionlessly on a rigid flat under a uniform pressure q on its
    top: the state is uniform (sigma_z = -q), the contact forces are the consistent ring loads
    of q, and the pressure profile (lambda_n over the consistent ring area) reads q at every
    node to round-off, the axis node too (a lumped disc pi (L/2)^2 there would read 4/3 q)."""
    q = 7.0
    text = (
        patch_case(0.0).split("[[bc]]")[0]
        + f'''
[[bc]]
body = "patch"
edge = "top"
pressure = {q}
[[contact]]
kind = "rigid_line"
body = "patch"
edge = "bottom"
'''
    )
    scene = prepare(write_case(tmp_path, text))
    snap = solve(scene)["snapshots"][-1]
    prof = contact_profile(scene, snap)
    assert len(prof["pressure"]) == 5 and prof["x"][0] == 0.0
    assert np.abs(prof["pressure"] / q - 1.0).max() < 1e-12
    assert np.sum(snap["lambda_n"]) == pytest.approx(q * np.pi, rel=1e-12)  # q times the disc
    assert np.abs(np.asarray(snap["stress"]) - [0.0, -q, 0.0, 0.0]).max() < 1e-12


def test_the_hoop_stress_is_the_out_of_plane_component_in_axisymmetry():
    """The ring patch u_r = A r, u_z = B z through slipstep.run: sigma_r =
    sigma_theta = 2 (lambda + G) A + lambda B, sigma_z = 2 lambda A + (lambda + 2 G) B, tau = 0;
    x = r, y = z and the out-of-plane zz is the hoop stress."""
    r = run(Case.from_toml(patch_case(0.5)), progress=False)
    exact = np.diag([SIGMA_R, SIGMA_Z, SIGMA_R])
    tensor = r.to_meshio().cell_data["stress"][0].reshape(-1, 3, 3)
    assert np.abs(tensor - exact).max() <= 1e-11
    assert np.abs(r.fields()["nodal_stress"] - [SIGMA_R, SIGMA_Z, SIGMA_R, 0.0]).max() <= 1e-11
