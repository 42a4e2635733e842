"""A rigid plane that moves along a tangent the pairs' frames do not line up with: every stuck
pair's node follows the plane's whole motion (its gap and both tangential slips stay zero), so
the motion's components along t1 and t2 both reach the pairs (eqs. 21, 25 with the target
translated). Until 2026-12 the path dropped the t2 component (rust/src/driver/path.rs,
`LoadPath::stage`): the nodes moved along t1 only.

The same scene turned as a whole by a rotation no frame axis lines up with (no symmetry plane,
every pair's frame oblique to the mesh's axes, the motion with a share along n, t1 and t2
alike): the stuck nodes follow the turned motion in every component, and the whole field is the
turned field of the scene as built (an isotropic body, its clamp holding all components)."""

import numpy as np
from conftest import needs_gmsh

import slipstep
from slipstep import _engine
from slipstep.build import build_scene

#: The plane's motion at factor 1: into the block by D and along 30 degrees in its plane by S.
D, S, ANGLE = 2e-3, 6e-4, np.radians(30.0)
MOTION = np.array([S * np.cos(ANGLE), S * np.sin(ANGLE), D])

CASE = f"""
[case]
name = "dragged_block_3d"
[analysis]
dimension = 3
[[body]]
name = "block"
[body.mesh]
generator = "box"
x0 = -0.5
y0 = -0.5
z0 = 0.0
width = 1.0
depth = 1.0
height = 0.5
h = 0.25
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
name = "clamp"
body = "block"
face = "top"
fix = ["x", "y", "z"]
[[contact]]
name = "plane"
kind = "rigid_plane"
body = "block"
face = "bottom"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
mu = 2.0
motion = [{MOTION[0]}, {MOTION[1]}, {MOTION[2]}]
"""


def rotation(axis, angle: float) -> np.ndarray:
    """Rodrigues: the rotation by `angle` about `axis`."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * cross + (1.0 - np.cos(angle)) * cross @ cross


#: A turn no frame axis lines up with.
TURN = rotation([1.0, -2.0, 3.0], 0.7)


def stuck_displacements(model: dict, snap: dict) -> np.ndarray:
    """The displacements of the nodes of the stuck pairs (at least the face's 9 inner ones)."""
    stuck = np.asarray(snap["status"]) == 1
    assert stuck.sum() >= 9, snap["status"]
    nodes = np.asarray(model["pairs"]["node_a"])[stuck]
    return np.asarray(snap["u"]).reshape(-1, 3)[nodes]


@needs_gmsh
def test_stuck_nodes_follow_the_whole_tangential_motion_of_the_plane():
    result = slipstep.run(slipstep.parse_case(CASE), progress=False)
    assert result.completed, result.stop
    u = stuck_displacements(result.scene.model, result.snapshot())
    # stuck at zero gap from the start: the node moves with the plane, to round-off of D
    assert np.abs(u - MOTION).max() <= 1e-9 * D, np.abs(u - MOTION).max(axis=0)


@needs_gmsh
def test_a_turned_scene_follows_the_turned_motion_in_every_component():
    model = build_scene(slipstep.parse_case(CASE)).model
    turned = {**model, "nodes": np.asarray(model["nodes"]) @ TURN.T}
    pairs = model["pairs"]
    turned["pairs"] = {
        **pairs,
        "normal": np.asarray(pairs["normal"]) @ TURN.T,
        "tangent": np.asarray(pairs["tangent"]) @ TURN.T,
    }
    turned["patterns"] = [
        {**p, "motion": np.asarray(p["motion"]) @ TURN.T} for p in model["patterns"]
    ]
    frames = np.concatenate([turned["pairs"]["normal"], turned["pairs"]["tangent"][:, 0]])
    assert np.abs(frames).min() > 0.05  # no frame direction along a mesh axis
    motion = TURN @ MOTION
    shares = [turned["pairs"]["normal"][0] @ motion] + list(turned["pairs"]["tangent"][0] @ motion)
    assert np.abs(shares).min() > 0.1 * S, shares  # the motion along n, t1 and t2 alike

    built, result = _engine.solve(model, False), _engine.solve(turned, False)
    assert result["stop"]["kind"] == "completed", result["stop"]
    snap = result["snapshots"][-1]
    u = stuck_displacements(turned, snap)
    assert np.abs(u - motion).max() <= 1e-9 * D, np.abs(u - motion).max(axis=0)
    # invariance: the turned scene's field is the built scene's, turned
    expected = np.asarray(built["snapshots"][-1]["u"]).reshape(-1, 3) @ TURN.T
    assert np.abs(np.asarray(snap["u"]).reshape(-1, 3) - expected).max() <= 1e-9 * D
