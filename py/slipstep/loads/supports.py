"""Supports and prescribed displacements: the engine's ``fixed_dofs`` from ``[[bc]]`` fix and
symmetry (and the axis in axisymmetry), each displacement load's DOFs and values, and which
DOFs each [[bc]] holds.  The same in 3D, with three components per node (dof = 3 node + c)
and symmetry on plane faces."""

from __future__ import annotations

import numpy as np

from ..case_record import Bc
from .path import Load, case_loads
from ..overrides import element_key
from ..scene import Scene
from ..section import AXIS_TOLERANCE, is_axisymmetric
from ..toml_writing import point_text


def supports(scene: Scene) -> np.ndarray:
    """The engine's ``fixed_dofs``: ``fix`` components, and ``symmetry`` = the normal component
    of an edge parallel to an axis (dof = 2*node + component; in 3D of a plane face parallel to
    a coordinate plane, dof = 3*node + component).  Fills ``scene.support_dofs``
    (per bc name: its fix, symmetry and displacement DOFs) and ``scene.prescribed`` (per load
    name: the displacement DOFs and their values at factor 1, never among the fixed ones)."""
    bcs, dim = scene.case.record.bc, scene.dimension
    holder = np.full(dim * len(scene.nodes), -1, dtype=np.int64)  # the bc fixing each DOF
    fixed, scene.support_dofs, scene.prescribed = [], {}, {}
    for i, bc in enumerate(bcs):
        nodes = _bc_nodes(scene, bc)
        components = {"xyz".index(c) for c in bc.fix}
        if bc.symmetry:
            components.add(_symmetry_component(scene, bc, element_key("bc", bcs, i)))
        dofs = [dim * nodes + c for c in sorted(components)]
        fixed.extend(dofs)
        for d in dofs:
            holder[d[holder[d] < 0]] = i
        _add_support(scene, bc.name or f"bc {i}", dofs)
    owner = holder.copy()  # the bc fixing or prescribing each DOF
    for load in case_loads(scene.case.record):
        if load.array == "bc" and load.kinematic:
            dofs, values = _prescribed(scene, load, owner, holder)
            scene.prescribed[load.label] = {"dofs": dofs, "values": values}
            _add_support(scene, bcs[load.index].name or f"bc {load.index}", [dofs])
    if is_axisymmetric(scene.case):
        fixed.append(_axis_supports(scene))
    if not fixed:
        return np.zeros(0, dtype=np.int64)
    return np.unique(np.concatenate(fixed)).astype(np.int64)


def support_groups(scene) -> dict[str, np.ndarray]:
    """Per [[bc]] name (``scene.support_dofs``, in its order) the DOFs whose reaction it
    reports: each DOF in one group only, the first that holds it (a node on the edge of a fixed
    base and a symmetry plane counts in the base), so that the groups' reactions add up to the
    supports' total.  The engine records each group's reaction at every increment (its
    ``support_names`` / ``support_dofs``); :func:`slipstep.output.history.reactions` sums the same
    DOFs of a snapshot."""
    taken: set[int] = set()
    out = {}
    for name, dofs in getattr(scene, "support_dofs", {}).items():
        dofs = np.asarray(dofs, dtype=np.int64)
        mine = dofs[~np.isin(dofs, np.fromiter(taken, dtype=np.int64, count=len(taken)))]
        taken.update(mine.tolist())
        out[name] = mine
    return out


def engine_support_groups(scene) -> dict:
    """The model keys of :func:`support_groups` (docs/engine_api.md)."""
    groups = support_groups(scene)
    return {"support_names": list(groups), "support_dofs": list(groups.values())}


def _axis_supports(scene: Scene) -> np.ndarray:
    """Axisymmetry: u_r = 0 at every node on the axis x = 0 (within 1e-9 of the scene's size,
    the engine's AXIS_TOLERANCE; the engine adds them too); a prescribed radial displacement
    there is an error naming the [[bc]]."""
    size = float(np.linalg.norm(np.ptp(scene.nodes, axis=0))) or 1.0
    dofs = 2 * np.flatnonzero(np.abs(scene.nodes[:, 0]) <= AXIS_TOLERANCE * size)
    for name, p in scene.prescribed.items():
        clash = np.isin(p["dofs"], dofs)
        if clash.any():
            node = int(p["dofs"][np.argmax(clash)]) // 2
            load = next(x for x in case_loads(scene.case.record) if x.label == name)
            raise scene.case.error(
                f"{load.key}.displacement.x",
                f"node {node} (0, "
                f"{scene.nodes[node, 1]:.6g}) lies on the axis x = 0, where "
                f'plane = "axisymmetric" holds u_r = 0 already: drop x '
                f"from displacement, or use a node set off the axis",
            )
    return dofs.astype(np.int64)


def _add_support(scene: Scene, name: str, dofs: list) -> None:
    """Add DOFs to a bc's entry of ``scene.support_dofs`` (bcs sharing a name share it; a bc
    that holds nothing, a pure force load, has none)."""
    if name not in scene.support_dofs and not any(len(d) for d in dofs):
        return
    old = scene.support_dofs.get(name, np.zeros(0, dtype=np.int64))
    scene.support_dofs[name] = np.unique(np.concatenate([old, *dofs])).astype(np.int64)


def _bc_nodes(scene: Scene, bc: Bc) -> np.ndarray:
    """Global ids (sorted, unique) of the nodes of a [[bc]]'s edge (face) or node set."""
    mesh = scene.meshes[bc.body]
    tag = bc.boundary_tag
    nodes = np.unique(mesh.tags[tag]) if tag else mesh.node_sets[bc.nodes]
    return np.unique(np.asarray(nodes, dtype=np.int64)) + scene.offsets[bc.body]


def _symmetry_component(scene: Scene, bc: Bc, key: str) -> int:
    """The component a ``symmetry`` edge holds: x for a vertical edge, y for a horizontal one
    (each segment normal within 1e-9 of the axis: straight up to round-off); in 3D the
    component normal to a plane face parallel to a coordinate plane."""
    tag = bc.boundary_tag
    n = scene.idealisation.facet_normals(scene.nodes, scene.global_boundary(bc.body, tag))
    for c in range(scene.dimension):
        if np.all(np.abs(n[:, c]) > 1 - 1e-9):
            if "xyz"[c] in bc.displacement:
                raise scene.case.error(
                    f"{key}.displacement.{'xyz'[c]}",
                    f"symmetry = true "
                    f"holds {'xyz'[c]} on {scene.idealisation.boundary} '{tag}' (its normal "
                    f"component): a component is held or prescribed, not "
                    f"both; remove symmetry or {'xyz'[c]} from displacement",
                )
            return c
    raise scene.case.error(
        f"{key}.symmetry",
        f"{scene.idealisation.boundary} '{tag}' is not {scene.idealisation.axis_aligned}: use "
        f"fix = [...] instead",
    )


def _prescribed(scene: Scene, load: Load, owner: np.ndarray, holder: np.ndarray):
    """(dofs, values) of a displacement [[bc]], sorted by DOF; a DOF already fixed or
    prescribed by another [[bc]] is an error (the engine eliminates each DOF once)."""
    bcs, d = scene.case.record.bc, scene.dimension
    bc = bcs[load.index]
    nodes = _bc_nodes(scene, bc)
    comps = sorted("xyz".index(c) for c in bc.displacement)
    dofs = np.concatenate([d * nodes + c for c in comps])
    values = np.concatenate([np.full(len(nodes), bc.displacement["xyz"[c]]) for c in comps])
    order = np.argsort(dofs, kind="stable")
    dofs, values = dofs[order], values[order]
    clash = owner[dofs] >= 0
    if clash.any():
        k = int(dofs[np.argmax(clash)])
        c, node = "xyz"[k % d], k // d
        how = "fix/symmetry" if holder[k] >= 0 else "displacement"
        raise scene.case.error(
            f"{load.key}.displacement.{c}",
            f"node {node} "
            f"{point_text(scene.nodes[node])} is also held in {c} by "
            f"{element_key('bc', bcs, int(owner[k]))} ({how}): each "
            f"component is fixed or prescribed once; drop {c} from one of "
            f'them (a zero component is a support: fix = ["{c}"] may '
            f"overlap others), or use a node set without that node",
        )
    owner[dofs] = load.index
    return dofs.astype(np.int64), values.astype(np.float64)
