"""One engine snapshot read in the scene's shapes (slipstep.output.snapshot.Snapshot): its
arrays are the snapshot's, reshaped by the scene's dimension and stress width, and a key the
snapshot lacks is None."""

from __future__ import annotations

import numpy as np
from conftest import needs_gmsh

from slipstep.build import build_scene
from slipstep.case import load_case, parse_case
from slipstep.output.snapshot import Snapshot
from space3d import SPHERE


def engine_like_snapshot(n: int, m: int, p: int, d: int, stress_width: int) -> dict:
    """A snapshot in the engine's layout whose entries count 0, 1, 2, ... (so a reshape that
    reorders or mixes them shows)."""

    def count(*shape):
        return np.arange(np.prod(shape), dtype=float).reshape(shape)

    tangential = (p,) if d == 2 else (p, 2)
    return {
        "t": 1.5,
        "stage": 1,
        "load_fraction": 0.5,
        "u": count(n, d),
        "reaction": count(n, d),
        "stress": count(m, stress_width),
        "plastic_strain": count(m),
        "plastic": np.zeros(m, np.int8),
        "lambda_n": count(p),
        "lambda_t": count(*tangential),
        "status": np.ones(p, np.int8),
        "gap": count(p),
        "rtd": count(*tangential),
    }


@needs_gmsh
def test_a_2d_snapshot_is_read_in_the_section_shapes():
    scene = build_scene(load_case(None))
    n, m, p = len(scene.nodes), len(scene.elements), len(scene.pair_xy)
    snap = engine_like_snapshot(n, m, p, 2, 4)
    del snap["reaction"], snap["plastic_strain"]
    s = Snapshot.of(scene, snap)
    assert (s.t, s.stage, s.load_fraction) == (1.5, 1, 0.5)
    assert s.u.shape == (n, 2) and np.array_equal(s.u, snap["u"])
    assert s.stress.shape == (m, 4) and s.lambda_t.shape == (p,)
    assert s.reaction is None and s.plastic_strain is None
    assert s.plastic.dtype == np.int8 and s.status.dtype == np.int8  # as the engine gave them


@needs_gmsh
def test_a_3d_snapshot_is_read_in_the_solid_shapes_from_flat_arrays():
    scene = build_scene(parse_case(SPHERE.replace("h_contact = 0.3", "h_contact = 0.8"), "s.toml"))
    n, m, p = len(scene.nodes), len(scene.elements), len(scene.pair_xy)
    assert p > 0
    snap = {
        k: np.ravel(v) if np.ndim(v) else v for k, v in engine_like_snapshot(n, m, p, 3, 6).items()
    }
    s = Snapshot.of(scene, snap)
    assert s.u.shape == s.reaction.shape == (n, 3) and s.u[1, 0] == 3.0
    assert s.stress.shape == (m, 6) and s.stress[1, 0] == 6.0
    assert s.lambda_t.shape == (p, 2) and s.lambda_t[1, 0] == 2.0
    assert s.plastic_strain.shape == (m,)
