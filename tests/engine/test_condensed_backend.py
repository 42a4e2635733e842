"""The condensed factorization (``[solver] factorization = "condensed"``: the far field's factor
kept, only the region near the contact refactorized) gives the history of the plain in-process
Cholesky (faer) to round-off, also when the plastic zone outgrows its region and it grows.

Both factor the same SPD matrices exactly (the condensed one as a block Cholesky in another
elimination order), so their solutions differ by about kappa(K) * eps relative: for these
coarse meshes kappa(K) ~ (body size / smallest element)^2, (125 / 0.15)^2 ~ 7e5 for the
cylinder, (10 / 0.04)^2 ~ 6e4 for the sphere, times eps = 2.2e-16: < 2e-10. An event's load
fraction is a ratio of such solutions. So: the same events (kind and entity, in order), load
fractions within 1e-9 and every snapshot's displacements within 1e-9 of the largest, a factor
5 above that bound. A far factor left stale after a change outside the region, or a wrong
interface coupling, moves them by far more or changes the events.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CASES, needs_gmsh

import slipstep

#: See the module's docstring: kappa(K) eps < 2e-10 for both meshes.
ROUND_OFF = 1e-9

HERTZ = (
    CASES / "hertz_cylinder.toml",
    [
        "contact.mu=0.35",
        "material.Sy=200",
        "material.H=700",
        "mesh.h_contact=0.15",
        "output.snapshots=[0.25, 0.5, 0.75, 1.0]",
    ],
)
SPHERE = (
    CASES / "sphere_on_flat_plastic_3d.toml",
    ["mesh.h_contact=0.04", "contact.motion=[0.0, 0.0, 0.0008]", "output.snapshots=[0.5, 1.0]"],
)


def run(scene, *extra):
    case, overrides = scene
    result = slipstep.run(case, overrides=[*overrides, *extra], progress=False)
    assert result.completed
    return result


def assert_same_history(plain, condensed):
    ev_p, ev_c = plain.raw["events"], condensed.raw["events"]
    assert len(ev_p["kind"]) > 10
    assert list(zip(ev_c["kind"], ev_c["entity"])) == list(zip(ev_p["kind"], ev_p["entity"]))
    assert (
        np.abs(np.asarray(ev_c["load_fraction"]) - np.asarray(ev_p["load_fraction"])).max()
        <= ROUND_OFF
    )
    u_p = np.array([s["u"] for s in plain.raw["snapshots"]])
    u_c = np.array([s["u"] for s in condensed.raw["snapshots"]])
    assert u_c.shape == u_p.shape
    scale = np.abs(u_p).max()
    assert scale > 0
    assert np.abs(u_c - u_p).max() <= ROUND_OFF * scale


@needs_gmsh
@pytest.mark.parametrize("scene", [HERTZ, SPHERE], ids=["hertz_plastic_2d", "sphere_plastic_3d"])
def test_the_condensed_factor_gives_the_plain_history_as_its_region_grows(scene):
    # Two element layers around the contact DOFs: a far field exists, the yield zone leaves
    # the region, K changes outside it, and the region must grow (its far factor rebuilt) for
    # the refactorizations to stay exact.
    plain = run(scene)
    condensed = run(scene, "solver.factorization=condensed", "solver.near_hops=2")
    assert plain.summary["n_yielded_elements"] > 0  # plastic: tangents change, K is refactorized
    assert condensed.summary["n_factorizations"] > 1
    assert condensed.summary["n_factor_builds"] > 1
    assert plain.summary["n_factor_builds"] == 1
    assert_same_history(plain, condensed)
