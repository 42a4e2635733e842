"""A block pressed onto a frictional flat whose contact pairs all slip.

A 10 x 5 block (nu = 0.3, plane strain) under a uniform pressure q on its top rests on a rigid
flat with mu <= 0.1, held by nothing else.  Its base expands both ways and slips outwards; where
the slip changes sense one pair sticks, and which one depends on the block's translation along
the flat, which the small contact system does not determine while every pair slips.  With 20
elements across a node lies on the axis and sticks; with 19 or 39 none does, and such runs were
refused as a free body (translation in x).  They must complete, on every mesh parity, with a
solution checked from the arrays alone:

* equilibrium: the contact forces carry q w, with no net friction and the pressure's moment;
  and by virtual work with the linear fields v = (0, y), (y, 0), (x, 0) (in the element space,
  and no support constrains them) the stresses integrate to -q w h, 0 and sum_i f_x,i x_i;
* Coulomb's law at every pair from lambda and u: inside the cone the pair has not moved
  (it sticks from the start of the proportional path), on the cone friction opposes its slip;
* mirror invariance: the mirror image of the 19-element mesh gives the mirror image of the
  forces and stresses, though its arbitrary choices (pinned DOF, event order) differ;
* mesh convergence: the top's settlement of the 39-element mesh is closer to the 79-element
  one than either coarse parity's, and the two parities at one h differ by less than halving h.

A body that nothing holds in x (frictionless) is still refused as a free body.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import write_case

import slipstep
from slipstep.errors import FreeBodyError

W, H, Q, E, NU = 10.0, 5.0, 1.0, 1000.0, 0.3

BLOCK = f"""
[case]
name = "block_on_flat"

[output]
figures = false
xdmf = false

[[body]]
name = "block"
[body.mesh]
generator = "block"
width = {W}
height = {H}
nx = 19
ny = 5
[body.material]
E = {E}
nu = {NU}

[[bc]]
name = "load"
body = "block"
edge = "top"
pressure = {Q}

[[contact]]
name = "flat"
kind = "rigid_line"
body = "block"
edge = "bottom"
mu = 0.1
"""

#: Forces and their moments are balanced to the engine's equilibrium_tol, 1e-9 of the load.
FORCE_TOL = 1e-9 * Q * W
#: A pair inside the cone by more than this (relative) sticks; its tangential displacement is
#: then the round-off of the solves, 1e-9 of the largest displacement (as the engine's checks).
CONE_TIE, ROUND_OFF = 1e-6, 1e-9


def run(tmp_path, *overrides, meshes=None, text=BLOCK):
    return slipstep.run(
        write_case(tmp_path, text), None, list(overrides), progress=False, meshes=meshes
    )


def contact_arrays(result):
    """x of node a, the normal force, the friction force along x (t = (-1, 0) on the flat),
    and u_x of node a, at the last snapshot."""
    snap = result.raw["snapshots"][-1]
    node_a = np.asarray(result.scene.model["pairs"]["node_a"])
    u = np.asarray(snap["u"]).reshape(-1, 2)
    return (
        result.nodes[node_a, 0],
        np.asarray(snap["lambda_n"]),
        -np.asarray(snap["lambda_t"]),
        u[node_a, 0],
        u,
    )


def element_areas(result) -> np.ndarray:
    p = result.nodes[result.triangles]
    return 0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))


@pytest.mark.parametrize("nx", [19, 20, 39])
@pytest.mark.parametrize("mu", [0.05, 0.1])
def test_every_mesh_parity_completes_with_a_valid_solution(tmp_path, nx, mu):
    result = run(tmp_path, f"mesh.nx={nx}", f"contact.mu={mu}")
    assert result.stop["kind"] == "completed", result.stop
    x, ln, fx, ux, u = contact_arrays(result)
    assert abs(ln.sum() - Q * W) < FORCE_TOL and abs(fx.sum()) < FORCE_TOL
    assert abs((x * ln).sum() - Q * W * W / 2) < FORCE_TOL * W
    # Virtual work with linear fields: the stresses carry what the contact forces say.
    stress, area = np.asarray(result.raw["snapshots"][-1]["stress"]), element_areas(result)
    assert abs(area @ stress[:, 1] + Q * W * H) < FORCE_TOL * H
    assert abs(area @ stress[:, 3]) < FORCE_TOL * H
    assert abs(area @ stress[:, 0] - (fx * x).sum()) < FORCE_TOL * W
    # Coulomb's law, pair by pair, from the forces and the displacements.
    assert np.all(ln > 0) and np.all(np.abs(fx) <= mu * ln * (1 + ROUND_OFF))
    inside = np.abs(fx) < mu * ln * (1 - CONE_TIE)
    assert np.all(np.abs(ux[inside]) <= ROUND_OFF * np.abs(u).max())
    assert np.all(fx[~inside] * ux[~inside] <= ROUND_OFF * Q * np.abs(u).max())


def test_the_mirror_image_gives_the_mirror_image(tmp_path):
    result = run(tmp_path)
    mesh = result.scene.meshes["block"]
    nodes = mesh.nodes * [-1.0, 1.0] + [W, 0.0]
    mirror = slipstep.from_arrays(nodes, mesh.triangles, mesh.edges)  # flipped counter-clockwise
    given = BLOCK.replace('generator = "block"', 'generator = "given"')
    given = "\n".join(
        line for line in given.splitlines() if not line.startswith(("width", "height", "nx", "ny"))
    )
    mirrored = run(tmp_path, meshes={"block": mirror}, text=given)
    assert mirrored.stop["kind"] == "completed"
    x, ln, fx, _, _ = contact_arrays(result)
    xm, lnm, fxm, _, _ = contact_arrays(mirrored)
    order, order_m = np.argsort(x), np.argsort(-xm)
    assert np.allclose(xm[order_m], W - x[order], rtol=0, atol=1e-12 * W)
    # Two solves of mirror-image systems: round-off, 1e-9 of the load.
    assert np.allclose(lnm[order_m], ln[order], rtol=0, atol=FORCE_TOL)
    assert np.allclose(fxm[order_m], -fx[order], rtol=0, atol=FORCE_TOL)
    centroid = lambda r: r.nodes[r.triangles].mean(axis=1)  # noqa: E731
    c, cm = centroid(result), centroid(mirrored)
    match = [int(np.argmin(np.hypot(cm[:, 0] - (W - a), cm[:, 1] - b))) for a, b in c]
    s, sm = (np.asarray(r.raw["snapshots"][-1]["stress"]) for r in (result, mirrored))
    assert np.allclose(sm[match] * [1, 1, 1, -1], s, rtol=0, atol=1e-9 * Q)


def test_the_settlement_converges_whatever_the_parity(tmp_path):
    def settlement(nx, ny):
        result = run(tmp_path, f"mesh.nx={nx}", f"mesh.ny={ny}")
        u = np.asarray(result.raw["snapshots"][-1]["u"]).reshape(-1, 2)
        return u[np.isclose(result.nodes[:, 1], H), 1].mean()

    odd, even, finer, finest = (
        settlement(19, 5),
        settlement(20, 5),
        settlement(39, 10),
        settlement(79, 20),
    )
    # Frictionless, the stress is uniform and CST exact: -q h (1 - nu^2)/E; friction restrains
    # the base's expansion and stiffens the block, by a few per cent at mu = 0.1.
    frictionless = -Q * H * (1 - NU**2) / E
    assert 0.95 < odd / frictionless < 1 and 0.95 < even / frictionless < 1
    assert abs(finer - finest) < min(abs(odd - finest), abs(even - finest))
    assert abs(odd - even) < abs(even - finer)


def test_a_block_nothing_holds_in_x_is_still_a_free_body(tmp_path):
    with pytest.raises(FreeBodyError, match=r"body 'block' is free to move \(translation in x\)"):
        run(tmp_path, "contact.mu=0")
