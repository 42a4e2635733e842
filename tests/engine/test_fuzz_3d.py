"""Fuzzing the engine in space (issue 37): generated frictional 3D scenes known to be solvable
must complete admissibly.

Beside the 2D fuzzer (tests/case/test_fuzz.py, whose budget rules it shares: a bounded,
derandomized set in `make test`, ``SLIPSTEP_FUZZ_EXAMPLES`` random ones per family in
`make fuzz-3d`).  Every scene is built by the product's case machinery (``slipstep.prepare`` of a
case dict, its meshes from the 3D generators, given from Python so that they can be rotated
and distorted) and solved by ``_engine.solve`` with a snapshot at every event.

The scenes (``scene_specs``: plain dicts, printed by hypothesis on a failure and turned into a
case file by ``write_case``), each in two stages, normal then tangential:

``block_on_flat``
    A structured box (nx, ny, nz drawn independently: 2..5, 2..5, 1..2, so the mesh has no
    symmetry the load could rely on; its interior and face nodes moved within their faces by
    up to 15 % of the spacing) resting on a rigid frictional plane at zero gap, held by
    nothing else: a uniform pressure p on its top (stage ``normal``), then a uniform traction
    of size r μ p, r <= 0.5, along a random direction of the top (stage ``tangential``, the
    pressure kept).  Force control: the resultant tangential load is r μ times the normal one,
    so the bottom's pairs can carry it with every pair inside its cone by the margin 1 − r >=
    0.5 (the rigid-body statics of a block on a flat: the tangential resultant must not exceed
    μ times the normal one; a margin of half absorbs the uneven pressure under the block's
    tilting moment).  Height <= 0.4 × the smaller side, so that moment r μ p A h <= p A h
    keeps the normal resultant within the base (off-centre by at most h <= 0.4 × the side <
    half of it): the block cannot tip.
``block_on_block``
    The same block on a larger fixed block, meshed independently (another spacing), the
    bottom of the upper against the top of the lower through ``node_to_surface``, at zero
    gap; the materials differ (E ratio 0.5..2).  Force control with the same margin.
``sphere_on_flat``
    The whole lower hemisphere (``generator = "sphere"``, ``portion = "half"``: no symmetry
    plane), its cut held by a prescribed displacement (zero in stage ``normal``), a rigid
    flat touching its lowest node (zero gap) moved into it by δ (stage ``normal``), then the
    cut moved tangentially by s <= μ δ (stage ``tangential``; Mindlin's sliding displacement
    of a sphere is (2 − ν)/(2(1 − ν)) μ δ >= μ δ, and the cut's displacement also shears the
    sphere's bulk: partial slip at most, though gross sliding would be solvable too under
    displacement control).  Candidates: the sphere's surface triangles below 4 δ (a face tag
    made in Python, which rotates with the scene), whose gaps beyond that cannot close.
``ball_into_block``
    A rigid sphere (radius 0.5..2 × the block's height) touching a node of a distorted box's
    top face (zero gap, or a gap up to half its approach), pressed in by δ, then the box's
    bottom moved tangentially by s <= μ δ (its bottom held by that displacement, zero in the
    first stage).
``punch_on_flat``
    A deformable flat-ended punch (``generator = "punch"``, round or square, the whole of it),
    its flat end on a rigid flat at zero gap, its top held by a prescribed displacement: the
    flat moved into it by δ, then the top moved tangentially by s <= μ δ.
``pyramid_into_block``
    A rigid Vickers or Berkovich pyramid (``slipstep.contact.indenters.pyramid``, turned about
    its axis by a random angle and tilted by up to 10°, written as an STL:
    ``kind = "rigid_surface"``) with its tip on a node of a distorted box's top face (zero
    gap), pressed in by δ, then the box's bottom moved tangentially by s <= μ δ.

Every scene is elastic (nominal strains ~1e-3: no plasticity, the load is far from any
yield), μ is drawn from [0.05, 2], ν from [0, 0.45], ``slip_turn`` from {0.05, 0.1, 0.3}; and
every coordinate, normal, load, motion and obstacle of the scene is turned by a random
rotation (a unit quaternion), or by none, so that the mesh's axes are not the load's.
Supports are ``displacement`` [[bc]]s of all three components (a support that rotates with the
body) or none (the blocks held by friction only).  No scene starts penetrated: the case
machinery refuses that (its ``tolerance``, 1e-9, snaps round-off gaps of the rotation to zero).

What must hold (``assert_admissible``), from the result arrays at every snapshot:

- the run completes (``stop.kind == "completed"``) without the anti-cycling last resort
  (``frozen`` events);
- Signorini: no penetration (gap >= −LENGTH_TOL × the run's largest displacement, motion or
  prescribed displacement, L), closed pairs touch (|gap| <= LENGTH_TOL L), open pairs carry no
  force (exactly 0), closed pairs no tension (λ_n >= −FORCE_TOL F);
- Coulomb in space (tests/physics.py's ``friction_in_space``, rust/src/coulomb.rs): a stuck
  pair that has not slipped since it closed inside the round cone |λ_t| <= μ λ_n, one that has
  inside its polygon (<= μ λ_n / cos slip_turn), a slipping pair within μ λ_n <= |λ_t| <=
  μ λ_n / cos slip_turn, each to FORCE_TOL F; no slipping pair produces work over a step,
  λ_t · ΔRTD <= FORCE_TOL F L + F LENGTH_TOL L with either end's force;
- equilibrium recomputed from the stresses, the loads and the contact forces
  (``physics.worst_equilibrium`` <= EQUILIBRIUM_TOL, the engine's contract);
- ``n_events <= EVENTS_PER_PAIR_STAGE × n_pairs × n_stages`` (K = 40: its comment gives the
  measured distribution and why the bound).

F is the scene's force scale: the largest of Σ|applied load| over the stage ends and Σ λ_n
over the snapshots (the force the contact carries under displacement control).
"""

from __future__ import annotations

import math
import os
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from conftest import needs_gmsh, time_limit
from physics import EQUILIBRIUM_TOL, applied_load, friction_in_space, worst_equilibrium

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

#: examples per family: a fixed, derandomized budget in `make test`; SLIPSTEP_FUZZ_EXAMPLES
#: (make fuzz-3d) switches to that many random examples (as tests/case/test_fuzz.py).
LONG = int(os.environ.get("SLIPSTEP_FUZZ_EXAMPLES", "0") or 0)

# Round-off, relative to the scene's scales as tests/engine/test_friction_facets_3d.py's: forces
# to F (the engine's noise floor is 1e-12 of its force scale, its own contact checks 1e-9 of
# it), lengths to L (the solves' round-off on these meshes of a few thousand DOFs is ~1e-12 of
# the displacements; the rotation's rounding of the coordinates ~1e-16 of the scene's size).
# A violated condition (a force outside its cone, a pair pulling or penetrating, a slip along
# its force) is of the order of the forces and displacements themselves.
FORCE_TOL = 1e-9
LENGTH_TOL = 1e-9

#: The bound on the events per pair and stage: n_events <= K n_pairs n_stages.  What one pair
#: can need in one stage of these monotonic loads: close, stick -> slip, slip -> stick,
#: separate, a few of each, and the turns of its slip, one slip_turn event per side of its
#: polygon it passes: 2θ = 2π/N apart with θ <= slip_turn, so at the smallest slip_turn drawn
#: (0.05: N = 64) a slip turning through half a revolution (radially outwards under the press,
#: then along the shear) takes 32.  K = 40 covers that with the status changes; engine cycling
#: or chattering (a pair switched back and forth along the load) exceeds it.  Measured with
#: SLIPSTEP_FUZZ_EXAMPLES = 200 (1190 admissible scenes of the six families): events /
#: (pairs x stages) median 0.07, 99th percentile 2.3, largest 4.3 (a pyramid into a block, 972
#: DOFs); the largest run had 677 events.
EVENTS_PER_PAIR_STAGE = 40

#: Seconds one scene may take before it counts as a hang (the largest take ~1 s).
HANG = 60


def budget(n: int):
    """Hypothesis settings: ``n`` examples in `make test` (derandomized), LONG random ones
    under `make fuzz-3d`."""
    return settings(
        max_examples=LONG or n,
        derandomize=not LONG,
        deadline=None,
        database=None,
        print_blob=True,
        suppress_health_check=[
            HealthCheck.too_slow,
            HealthCheck.data_too_large,
            HealthCheck.filter_too_much,
        ],
    )


# =========================================================================== geometry helpers
def rotation_of(q) -> np.ndarray:
    """The rotation of the quaternion q (any non-zero 4-vector, normalised here)."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def distorted(mesh, amount: float, seed: int, keep_planes=True):
    """``mesh`` with every node moved by up to ``amount`` × its shortest edge, each box face's
    nodes within their plane (``keep_planes``: a flat face stays flat, so zero gaps stay zero),
    halved until every tetrahedron keeps at least 30 % of its volume."""
    from slipstep.mesh import TetMesh
    from slipstep.mesh.tetrahedra import signed_volumes

    nodes, tets = mesh.nodes, mesh.tetrahedra
    rng = np.random.default_rng(seed)
    edges = np.concatenate([tets[:, [i, j]] for i in range(4) for j in range(i + 1, 4)])
    length = np.linalg.norm(nodes[edges[:, 0]] - nodes[edges[:, 1]], axis=1)
    shortest = np.full(len(nodes), np.inf)
    np.minimum.at(shortest, edges[:, 0], length)
    np.minimum.at(shortest, edges[:, 1], length)
    move = rng.uniform(-1.0, 1.0, nodes.shape) * shortest[:, None]
    if keep_planes:
        low, high = nodes.min(axis=0), nodes.max(axis=0)
        scale = float(np.ptp(nodes, axis=0).max())
        for axis in range(3):
            on = (np.abs(nodes[:, axis] - low[axis]) <= 1e-12 * scale) | (
                np.abs(nodes[:, axis] - high[axis]) <= 1e-12 * scale
            )
            move[on, axis] = 0.0
    volume = signed_volumes(nodes, tets)
    while True:
        moved = nodes + amount * move
        if (signed_volumes(moved, tets) >= 0.3 * volume).all():
            break
        amount *= 0.5
    faces = {k: v.copy() for k, v in mesh.faces.items()}
    return TetMesh(moved, tets.copy(), faces)


def turned(mesh, Q: np.ndarray):
    """``mesh`` with every node turned by Q (a rotation: orientation and faces are kept)."""
    from slipstep.mesh import TetMesh

    return TetMesh(
        mesh.nodes @ Q.T, mesh.tetrahedra.copy(), {k: v.copy() for k, v in mesh.faces.items()}
    )


def in_plane(angle: float, size: float) -> list[float]:
    return [size * math.cos(angle), size * math.sin(angle), 0.0]


# =========================================================================== the scenes
FAMILIES = (
    "block_on_flat",
    "block_on_block",
    "sphere_on_flat",
    "ball_into_block",
    "punch_on_flat",
    "pyramid_into_block",
)
#: the families meshed by gmsh (cached per session: slipstep.mesh.cache)
GMSH = ("sphere_on_flat", "punch_on_flat")

unit = st.floats(0.0, 1.0)


@st.composite
def scene_specs(draw, family: str) -> dict:
    """A scene's parameters (plain values: hypothesis prints them, ``write_case`` replays
    them): the family's geometry and the common draws (μ, ν, slip_turn, rotation, seed)."""
    spec = {
        "family": family,
        "mu": draw(st.floats(0.05, 2.0), label="mu"),
        "nu": draw(st.floats(0.0, 0.45), label="nu"),
        "slip_turn": draw(st.sampled_from([0.1, 0.05, 0.3]), label="slip_turn"),
        "rotation": draw(
            st.none()
            | st.tuples(*[st.floats(-1.0, 1.0)] * 4).filter(lambda q: np.linalg.norm(q) > 0.1),
            label="rotation",
        ),
        "seed": draw(st.integers(0, 2**32 - 1), label="seed"),
        "tangential": draw(st.floats(0.05, 1.0), label="tangential"),  # of the allowed most
        "direction": draw(st.floats(0.0, 2 * math.pi), label="direction"),
    }
    if family in ("block_on_flat", "block_on_block", "ball_into_block", "pyramid_into_block"):
        # sizes on a grid of 1/64: generators.box tags a face by its triangles' centres equal
        # to the plane's coordinate, which (3 h)/3 misses for some h (see
        # test_a_box_of_any_height_has_its_top_face below); k/64 is exact
        spec.update(
            width=draw(st.integers(64, 192), label="width") / 64,
            depth=draw(st.integers(64, 192), label="depth") / 64,
            nx=draw(st.integers(2, 8), label="nx"),
            ny=draw(st.integers(2, 8), label="ny"),
            nz=draw(st.integers(1, 3), label="nz"),
            distortion=draw(st.sampled_from([0.15, 0.0]), label="distortion"),
        )
        most = int(0.4 * min(spec["width"], spec["depth"]) * 64)  # height <= 0.4 x the base
        spec["height"] = draw(st.integers(most // 3, most), label="height") / 64
    if family == "block_on_block":
        spec.update(
            lower_nx=draw(st.integers(2, 9), label="lower_nx"),
            lower_ny=draw(st.integers(2, 9), label="lower_ny"),
            stiffness_ratio=draw(st.floats(0.5, 2.0), label="stiffness_ratio"),
            overhang=draw(st.tuples(*[st.integers(2, 16)] * 2), label="overhang"),
        )
    if family == "sphere_on_flat":
        spec.update(
            h_contact=draw(st.sampled_from([0.2, 0.25, 0.3]), label="h_contact"),
            approach=draw(st.floats(0.01, 0.04), label="approach"),
        )
    if family in ("ball_into_block", "pyramid_into_block"):
        # the contact reaches about `reach` x the spacing from the node touched first
        spec.update(node=draw(unit, label="node"), reach=draw(st.floats(0.5, 1.2), label="reach"))
    if family == "ball_into_block":
        spec.update(
            radius=draw(st.floats(1.5, 4.0), label="radius"),  # x the spacing
            gap=draw(st.sampled_from([0.0, 0.0, 0.3]), label="gap"),
        )  # x the approach
    if family == "punch_on_flat":
        spec.update(
            shape=draw(st.sampled_from(["round", "square"]), label="shape"),
            height=draw(st.sampled_from([0.75, 1.0, 1.5]), label="height"),
            h_contact=draw(st.sampled_from([0.2, 0.25, 0.3]), label="h_contact"),
            approach=draw(st.floats(0.0005, 0.002), label="approach"),
        )
    if family == "pyramid_into_block":
        spec.update(
            pyramid=draw(st.sampled_from(["vickers", "berkovich"]), label="pyramid"),
            spin=draw(st.floats(0.0, 2 * math.pi), label="spin"),
            tilt=draw(st.floats(0.0, math.radians(10.0)), label="tilt"),
        )
    return spec


def build(spec: dict, folder: Path):
    """(case dict, meshes) of a spec; files it needs (an indenter's STL) go into ``folder``."""
    from slipstep.mesh import tetrahedron_generators as generators

    Q = np.eye(3) if spec["rotation"] is None else rotation_of(spec["rotation"])
    family, mu, seed = spec["family"], spec["mu"], spec["seed"]
    E, nu = 1000.0, spec["nu"]
    case = {
        "case": {"name": family},
        "analysis": {"dimension": 3},
        "output": {"snapshots": "events"},
        "solver": {"slip_turn": spec["slip_turn"]},
        "stage": [
            {"name": "normal", "factors": {"press": 1.0}},
            {"name": "tangential", "factors": {"shear": 1.0}},
        ],
    }
    vec = lambda v: (Q @ np.asarray(v, dtype=float)).tolist()  # noqa: E731
    up = vec([0.0, 0.0, 1.0])

    def block(nx, ny, nz, corner=(0.0, 0.0, 0.0), size=None, salt=0):
        w, d, h = size or (spec["width"], spec["depth"], spec["height"])
        mesh = generators.box(w, d, h, nx, ny, nz, corner=corner)
        return distorted(mesh, spec["distortion"], seed + salt) if spec["distortion"] else mesh

    if family in ("block_on_flat", "block_on_block"):
        p = 1.0  # strain p/E = 1e-3
        shear = in_plane(spec["direction"], 0.5 * spec["tangential"] * mu * p)
        upper = block(spec["nx"], spec["ny"], spec["nz"])
        case["body"] = [{"name": "upper", "material": {"E": E, "nu": nu}}]
        case["bc"] = [
            {"name": "press", "body": "upper", "face": "top", "pressure": p},
            {"name": "shear", "body": "upper", "face": "top", "traction": vec(shear)},
        ]
        meshes = {"upper": turned(upper, Q)}
        if family == "block_on_flat":
            case["contact"] = [
                {
                    "name": "flat",
                    "kind": "rigid_plane",
                    "body": "upper",
                    "face": "bottom",
                    "point": [0.0, 0.0, 0.0],
                    "normal": up,
                    "mu": mu,
                }
            ]
        else:
            # the lower block reaches beyond the upper by 2/64 .. 1/4 on every side
            ox, oy = (k / 64 for k in spec["overhang"])
            size = (spec["width"] + 2 * ox, spec["depth"] + 2 * oy, 0.5)
            lower = block(
                spec["lower_nx"], spec["lower_ny"], 1, corner=(-ox, -oy, -0.5), size=size, salt=1
            )
            case["body"].append(
                {"name": "lower", "material": {"E": E * spec["stiffness_ratio"], "nu": nu}}
            )
            case["bc"].append(
                {"name": "base", "body": "lower", "face": "bottom", "fix": ["x", "y", "z"]}
            )
            case["contact"] = [
                {
                    "name": "interface",
                    "kind": "node_to_surface",
                    "body_a": "upper",
                    "face_a": "bottom",
                    "body_b": "lower",
                    "face_b": "top",
                    "mu": mu,
                }
            ]
            meshes["lower"] = turned(lower, Q)
        return case, meshes

    if family in ("sphere_on_flat", "punch_on_flat"):
        delta = spec["approach"]
    else:  # an indenter: the contact reaches about `reach` x the spacing h
        h = max(spec["width"] / spec["nx"], spec["depth"] / spec["ny"])
        radius, reach = spec.get("radius", 0.0) * h, spec["reach"] * h
        # a sphere's cap of that radius; a pyramid's face rises by tan(22 deg) = 0.4 per reach
        delta = radius - math.sqrt(radius**2 - reach**2) if radius else 0.4 * reach
    slide = in_plane(spec["direction"], spec["tangential"] * mu * delta)
    if family == "sphere_on_flat":
        from slipstep.mesh import TetMesh

        R, h = 10.0, spec["h_contact"]
        mesh = generators.sphere(R, h, 1.0, 4.0, 0.5, portion="half")
        surface = mesh.faces["surface"]
        cap = surface[(mesh.nodes[surface, 2] <= 4 * delta).all(axis=1)]
        mesh = TetMesh(
            mesh.nodes @ Q.T, mesh.tetrahedra.copy(), {"top": mesh.faces["top"].copy(), "cap": cap}
        )
        case["body"] = [{"name": "sphere", "material": {"E": E, "nu": nu}}]
        case["bc"] = [
            {
                "name": "shear",
                "body": "sphere",
                "face": "top",
                "displacement": dict(zip("xyz", vec(slide))),
            }
        ]
        case["contact"] = [
            {
                "name": "press",
                "kind": "rigid_plane",
                "body": "sphere",
                "face": "cap",
                "point": [0.0, 0.0, 0.0],
                "normal": up,
                "motion": vec([0.0, 0.0, delta]),
                "mu": mu,
            }
        ]
        return case, {"sphere": mesh}

    if family == "punch_on_flat":
        mesh = generators.punch(
            1.0,
            spec["height"],
            spec["h_contact"],
            0.3,
            0.5,
            0.5,
            shape=spec["shape"],
            portion="whole",
        )
        case["body"] = [{"name": "punch", "material": {"E": E, "nu": nu}}]
        case["bc"] = [
            {
                "name": "shear",
                "body": "punch",
                "face": "top",
                "displacement": dict(zip("xyz", vec(slide))),
            }
        ]
        case["contact"] = [
            {
                "name": "press",
                "kind": "rigid_plane",
                "body": "punch",
                "face": "bottom",
                "point": [0.0, 0.0, 0.0],
                "normal": up,
                "motion": vec([0.0, 0.0, delta]),
                "mu": mu,
            }
        ]
        return case, {"punch": turned(mesh, Q)}

    # a rigid indenter on a node of a block's top face, the block's bottom held by `shear`
    mesh = block(spec["nx"], spec["ny"], spec["nz"])
    top = np.unique(mesh.faces["top"])
    inner = top[
        (mesh.nodes[top, :2] > 1e-9).all(axis=1)
        & (mesh.nodes[top, :2] < [spec["width"] - 1e-9, spec["depth"] - 1e-9]).all(axis=1)
    ]
    tip = mesh.nodes[inner[min(int(spec["node"] * len(inner)), len(inner) - 1)]]
    case["body"] = [{"name": "block", "material": {"E": E, "nu": nu}}]
    case["bc"] = [
        {
            "name": "shear",
            "body": "block",
            "face": "bottom",
            "displacement": dict(zip("xyz", vec(slide))),
        }
    ]
    press = {
        "name": "press",
        "body": "block",
        "face": "top",
        "mu": mu,
        "motion": vec([0.0, 0.0, -delta]),
    }
    if family == "ball_into_block":
        centre = tip + [0.0, 0.0, radius + spec["gap"] * delta]
        press.update(kind="rigid_sphere", centre=vec(centre), radius=radius)
    else:
        from slipstep.contact.indenters import pyramid, write_stl

        points, triangles = pyramid(spec["pyramid"], [0.0, 0.0, 0.0], 4 * delta)
        c, s = math.cos(spec["spin"]), math.sin(spec["spin"])
        spin = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        c, s = math.cos(spec["tilt"]), math.sin(spec["tilt"])
        tilt = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
        points = (points @ (tilt @ spin).T + tip) @ Q.T
        stl = write_stl(folder / "indenter.stl", points, triangles)
        press.update(kind="rigid_surface", file=str(stl), side="outside")
    case["contact"] = [press]
    return case, {"block": turned(mesh, Q)}


# =========================================================================== the checks
def scales(model: dict, result: dict) -> tuple[float, float]:
    """(F, L): the force scale (Σ|applied load| at the stage ends, Σ λ_n at the snapshots) and
    the length scale (the largest displacement, motion or prescribed displacement)."""
    snaps = result["snapshots"]
    n_stages = max(1, len(model.get("stages", [])))
    force = max(
        [np.abs(applied_load(model, k)).sum() for k in range(1, n_stages + 1)]
        + [float(np.sum(s["lambda_n"])) for s in snaps]
    )
    prescribed = [
        np.abs(p.get("displacement_values", np.zeros(0))).max(initial=0.0)
        for p in model.get("patterns", [])
    ]
    prescribed += [
        np.abs(p.get("motion", np.zeros(0))).max(initial=0.0) for p in model.get("patterns", [])
    ]
    length = max([np.abs(s["u"]).max() for s in snaps] + prescribed)
    return force, length


def assert_admissible(model: dict, result: dict) -> dict:
    """The checks of the module text on a solved scene; returns what was measured."""
    assert result["stop"]["kind"] == "completed", result["stop"]
    kinds = Counter(result["events"]["kind"])
    assert "frozen" not in kinds and "frozen_element" not in kinds, kinds
    snaps = result["snapshots"]
    F, L = scales(model, result)
    force, length = FORCE_TOL * F, LENGTH_TOL * L
    for k, s in enumerate(snaps):
        closed = s["status"] > 0
        assert (s["gap"] >= -length).all(), (k, "penetration", s["gap"].min(), length)
        assert (np.abs(s["gap"][closed]) <= length).all(), (k, "a closed pair does not touch")
        assert (s["lambda_n"][~closed] == 0).all() and (s["lambda_t"][~closed] == 0).all(), (
            k,
            "an open pair carries force",
        )
        assert (s["lambda_n"][closed] >= -force).all(), (k, "tension", s["lambda_n"].min())
    worst = friction_in_space(
        model, snaps, model["options"]["slip_turn"], (length, force), result["events"]
    )
    assert worst["outside_round"] <= force, ("outside the round cone", worst, force)
    assert worst["outside_polygon"] <= force, ("outside the polygon", worst, force)
    assert worst["inside_facet"] <= force, ("a slipping pair inside its cone", worst, force)
    assert worst["beyond_facet"] <= force, ("a slipping pair beyond its facet", worst, force)
    assert worst["work"] <= F * length + force * L, ("a slip produces work", worst)
    residual, k, t = worst_equilibrium(model, snaps)
    assert residual <= EQUILIBRIUM_TOL, ("equilibrium", k, t, residual)
    n_pairs = len(model["pairs"]["node_a"])
    n_stages = max(1, len(model.get("stages", [])))
    n_events = len(result["events"]["kind"])
    assert n_events <= EVENTS_PER_PAIR_STAGE * n_pairs * n_stages, (n_events, n_pairs, kinds)
    return {
        "events_per_pair_stage": n_events / (n_pairs * n_stages),
        "kinds": kinds,
        "friction": worst,
        "equilibrium": residual,
        "pairs": n_pairs,
        "dofs": 3 * len(model["nodes"]),
    }


def write_case(spec: dict, folder) -> Path:
    """A spec as a case file ``folder/case.toml`` with its meshes as gmsh files beside it
    (physical surfaces: the face tags) and its indenter's STL: ``slipstep run case.toml``
    replays the scene (the reproduction of a failure)."""
    import meshio

    from slipstep.toml_writing import toml_table

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    case, meshes = build(spec, folder)
    for body in case["body"]:
        mesh = meshes[body["name"]]
        tags = list(mesh.faces)
        triangles = np.concatenate([mesh.faces[t] for t in tags])
        physical = np.concatenate([np.full(len(mesh.faces[t]), i + 1) for i, t in enumerate(tags)])
        meshio.write(
            folder / f"{body['name']}.msh",
            meshio.Mesh(
                mesh.nodes,
                [("tetra", mesh.tetrahedra), ("triangle", triangles)],
                cell_data={
                    "gmsh:physical": [np.full(len(mesh.tetrahedra), len(tags) + 1), physical],
                    "gmsh:geometrical": [np.ones(len(mesh.tetrahedra), int), physical],
                },
                field_data={
                    **{t: np.array([i + 1, 2]) for i, t in enumerate(tags)},
                    "volume": np.array([len(tags) + 1, 3]),
                },
            ),
            file_format="gmsh22",
            binary=False,
        )
        body["mesh"] = {"file": f"{body['name']}.msh"}
    for contact in case["contact"]:
        if "file" in contact:
            contact["file"] = Path(contact["file"]).name
    lines = [f"# tests/engine/test_fuzz_3d.py, scene {spec}"]
    for key, value in case.items():
        if isinstance(value, list):
            for item in value:
                plain = {
                    k: v
                    for k, v in item.items()
                    if not isinstance(v, dict) or k != "mesh" and k != "material"
                }
                lines += ["", *toml_table(f"[[{key}]]", plain)]
                for sub in ("mesh", "material"):
                    if sub in item:
                        lines += toml_table(f"[{key}.{sub}]", item[sub])
        else:
            lines += ["", *toml_table(f"[{key}]", value)]
    path = folder / "case.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def solve_spec(spec: dict):
    """(model, result) of a spec, the engine under the hang guard."""
    import slipstep
    from slipstep import _engine

    with tempfile.TemporaryDirectory() as folder:
        case, meshes = build(spec, Path(folder))
        for item in case["bc"] + case["contact"]:  # no load or contact on an empty face tag
            for body, face in (
                (item.get("body"), item.get("face")),
                (item.get("body_a"), item.get("face_a")),
                (item.get("body_b"), item.get("face_b")),
            ):
                assert face is None or len(meshes[body].faces[face]), (body, face)
        model = slipstep.prepare(case, meshes=meshes).model
    with time_limit(HANG, f"the engine on {spec}"):
        result = _engine.solve(model, False)
    return model, result


def check_spec(spec: dict) -> dict:
    model, result = solve_spec(spec)
    return assert_admissible(model, result)


# =========================================================================== the tests
@budget(25)
@given(spec=scene_specs("block_on_flat"))
def test_fuzz_block_on_a_rigid_flat(spec):
    check_spec(spec)


@budget(15)
@given(spec=scene_specs("block_on_block"))
def test_fuzz_block_on_a_block(spec):
    check_spec(spec)


@needs_gmsh
@budget(10)
@given(spec=scene_specs("sphere_on_flat"))
def test_fuzz_hemisphere_on_a_rigid_flat(spec):
    check_spec(spec)


@budget(20)
@given(spec=scene_specs("ball_into_block"))
def test_fuzz_rigid_ball_into_a_block(spec):
    check_spec(spec)


@needs_gmsh
@budget(10)
@given(spec=scene_specs("punch_on_flat"))
def test_fuzz_punch_on_a_rigid_flat(spec):
    check_spec(spec)


@budget(20)
@given(spec=scene_specs("pyramid_into_block"))
def test_fuzz_rigid_pyramid_into_a_block(spec):
    check_spec(spec)


# =========================================================================== found by the fuzz
# Scenes this fuzzer found that should complete and did not: each is minimised (by hand, from the
# spec hypothesis printed), replayable as a case file (``write_case(spec, folder)`` then
# ``slipstep run folder/case.toml``), an expected failure (strict) until fixed, then a test.


def test_a_box_of_any_height_has_its_top_face():
    """``generator = "box"`` tagged a face by the centres of its boundary triangles equal to the
    plane's coordinate, and a centre is the mean of three equal coordinates: (h + h + h)/3 is
    not h for h = 0.4657782158854201 (nor for 89 of 200 random sizes), so the face ``top`` of
    that box had no triangle, and a pressure on it was no load at all: the run "completed"
    unloaded, no error.  Found by the first draft of this fuzzer; the box now tags a triangle
    by its three corners on the plane (py/slipstep/mesh/tetrahedron_generators.py, ``_box_faces``)."""
    import slipstep
    from slipstep.mesh import tetrahedron_generators as generators

    height = 0.4657782158854201
    mesh = generators.box(1.0, 1.0, height, 2, 2, 1)
    empty = sorted(tag for tag, tris in mesh.faces.items() if not len(tris))
    case = {
        "analysis": {"dimension": 3},
        "body": [
            {
                "name": "b",
                "material": {"E": 1000.0, "nu": 0.3},
                "mesh": {
                    "generator": "box",
                    "width": 1.0,
                    "depth": 1.0,
                    "height": height,
                    "nx": 2,
                    "ny": 2,
                    "nz": 1,
                },
            }
        ],
        "bc": [
            {"body": "b", "face": "bottom", "fix": ["x", "y", "z"]},
            {"body": "b", "face": "top", "pressure": 1.0},
        ],
    }
    load = np.abs(slipstep.prepare(case).model["load"]).sum()
    assert not empty and load > 0, (empty, load)


#: A single cell (2 x 1 x 0.3125, six tetrahedra) resting at zero gap on a rigid frictional
#: flat (mu = 0.1), held by nothing else, pressed by p = 1 on its top, the scene turned by the
#: rotation of the quaternion (0.5, 0.4, 0.8, 0.6): at t = 0 every pair slips outwards (Poisson's
#: expansion) at zero force.  It stopped with FreeBodyError ("body 'upper' is free to move
#: ...") where the same scene on the axes completed: the rate problem eliminated every pair's
#: tangential force with its equation, but K# pins a node of the floating body, whose two
#: tangents' flexibilities are then dependent (turned off the axes, to round-off: M_ff of rank
#: 7 of 8, its Schur complement 1e33), and Lemke's first pivot was a ray.  The rate problem now
#: eliminates an independent set (rust/src/driver/rate_problem.rs, ``independent_free``).
FREE_BODY_WHEN_TURNED = {
    "family": "block_on_flat",
    "mu": 0.1,
    "nu": 0.3,
    "slip_turn": 0.1,
    "rotation": (0.5, 0.4, 0.8, 0.6),
    "seed": 0,
    "tangential": 0.5,
    "direction": 0.0,
    "width": 2.0,
    "depth": 1.0,
    "height": 0.3125,
    "nx": 1,
    "ny": 1,
    "nz": 1,
    "distortion": 0.0,
}


def test_a_pressed_block_on_a_turned_flat_is_held_by_its_slipping_pairs():
    check_spec(FREE_BODY_WHEN_TURNED)


def test_the_same_block_on_the_axes_completes():
    """The control of the expected failure above: the scene unturned."""
    check_spec({**FREE_BODY_WHEN_TURNED, "rotation": None})


#: A block 2 x 1.5 x 0.25 (2 x 2 x 1 cells, nodes moved by up to 15 % of the spacing, seed
#: 14943993) on a rigid frictional flat at zero gap (mu = 0.3, nu = 0.4), held by nothing
#: else, pressed by p = 1, then sheared by 0.1 x 0.5 mu p (a twentieth of what friction holds)
#: along x, the scene turned by the quaternion (-0.84, 0.85, -0.84, -0.84): at t = 1, where the
#: shear begins, pair 0 cycled through slip_turn and stick_to_slip at zero load increment, the
#: rate problem found no admissible set and the last resort froze it outside its cone:
#: IllPosedError "contact 'flat' pair 0 ... violates Coulomb's law (|lambda_t| = 8.275e-2 beyond
#: its cone by 4.300e-3, mu lambda_n = 7.829e-2) at load fraction 1.000000: its statuses cycled
#: at zero load increment ...".  Unturned, or with the nodes undistorted, it completes.  (The
#: same failure, also at t = 1 on pair 0, came from a 6 x 3 x 1 block turned by pi about y up to
#: round-off: with the rotation's off-diagonal entries 1e-37 it fails, with them exactly 0 it
#: completes, 85 events.)  The cause was the turned block's above (the rate problem's
#: dependent tangents of the pinned node), fixed with it.
ILL_POSED_AT_THE_SHEAR = {
    "family": "block_on_flat",
    "mu": 0.3,
    "nu": 0.4,
    "slip_turn": 0.1,
    "rotation": (-0.84, 0.85, -0.84, -0.84),
    "seed": 14943993,
    "tangential": 0.1,
    "direction": 0.0,
    "width": 2.0,
    "depth": 1.5,
    "height": 0.25,
    "nx": 2,
    "ny": 2,
    "nz": 1,
    "distortion": 0.15,
}


def test_a_turned_block_sheared_far_below_its_friction_completes():
    check_spec(ILL_POSED_AT_THE_SHEAR)


#: A structured 3 x 1 x 1 block (2 x 1 x 0.3125), not turned, not distorted, on a rigid flat at
#: zero gap (mu = 0.3, nu = 0.3), pressed by p = 1: at t = 0 its pairs slip outwards at zero
#: force; the pair slips with no cross row (rust/src/contact.rs: "at zero force it has no cross
#: row") over the whole first stage, one increment, so its slip is not held to its facet: pair
#: 0's friction force ends on the round cone (|lambda_t| = mu lambda_n) 0.314 rad (18 deg) off
#: its slip over the step, pair 5's 0.254 rad; the design bounds the lag by slip_turn = 0.1
#: (rust/src/coulomb.rs, cases/README.md's `slip_turn`) and tests/physics.py's
#: friction_in_space by 2 slip_turn.  The run is otherwise admissible (no work produced: the
#: force still opposes the slip's larger part), which is why assert_admissible does not check
#: the lag (the issue's list does not ask it); it is not rare: lags beyond 2 slip_turn in 4 of
#: the 91 scenes with slip among 30 derandomized ones per family (0 of 4 blocks on a flat, 2 of
#: 8 on a block, 1 of 28 hemispheres, 0 of 18 balls, 0 of 15 punches, 1 of 18 pyramids, the
#: worst 31 slip_turn, a pyramid's pair).
#: What happens: each pair takes its direction against its trial's slip rate, turn after turn
#: (rust/src/driver/slip_turn.rs), and the directions swing (each pair's friction moves its
#: neighbours' slips: turns of up to pi) until the pairs' turns run out.  Two fixes were tried
#: and left out: a pair out of turns holding its facet's cross row from zero force on (the
#: lag then at most 0.098, and 40 random scenes per family admissible with the lag checked;
#: but tests/engine/test_gross_sliding_3d.py's twisted block lost its symmetry, 7e-5 of its
#: forces, and the receding plate at mu = 1 reached the last resort), and asking the rate
#: problem there (the lag at most 0.098; but a plastic Berkovich block at mu = 0.5,
#: tests/engine/test_friction_facets_3d.py, then cycled into the last resort at t = 0.875).
LAG_AT_ZERO_FORCE_ONSET = {
    "family": "block_on_flat",
    "mu": 0.3,
    "nu": 0.3,
    "slip_turn": 0.1,
    "rotation": None,
    "seed": 0,
    "tangential": 0.5,
    "direction": 0.0,
    "width": 2.0,
    "depth": 1.0,
    "height": 0.3125,
    "nx": 3,
    "ny": 1,
    "nz": 1,
    "distortion": 0.0,
}


@pytest.mark.xfail(
    strict=True,
    reason="engine: pairs slipping from zero force take their "
    "directions from their trials turn after turn, which swing until the turns "
    "run out: a force lags its slip by 0.31 rad > 2 slip_turn; found by the 3D fuzz",
)
def test_a_pair_slipping_from_zero_force_keeps_its_force_against_its_slip():
    model, result = solve_spec(LAG_AT_ZERO_FORCE_ONSET)
    measured = assert_admissible(model, result)  # admissible otherwise
    assert measured["friction"]["lag"] <= 2 * model["options"]["slip_turn"] + 1e-6, measured
