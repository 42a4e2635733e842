"""Supports and prescribed displacements: the engine's ``fixed_dofs`` from ``[[bc]]`` fix and
symmetry (and the axis in axisymmetry), each displacement load's DOFs and values, and which
DOFs each [[bc]] holds."""

from __future__ import annotations

import numpy as np

from . import mesh as meshing
from .loadpath import Load, case_loads
from .overrides import element_key
from .scene import Scene
from .section import AXIS_TOLERANCE, is_axisymmetric


def supports(scene: Scene) -> np.ndarray:
    """The engine's ``fixed_dofs``: ``fix`` components, and ``symmetry`` = the normal component
    of an edge parallel to an axis (dof = 2*node + component).  Fills ``scene.support_dofs``
    (per bc name: its fix, symmetry and displacement DOFs) and ``scene.prescribed`` (per load
    name: the displacement DOFs and their values at factor 1, never among the fixed ones)."""
    bcs = scene.case.data["bc"]
    holder = np.full(2 * len(scene.nodes), -1, dtype=np.int64)  # the bc fixing each DOF
    fixed, scene.support_dofs, scene.prescribed = [], {}, {}
    for i, bc in enumerate(bcs):
        nodes = _bc_nodes(scene, bc)
        components = {"xy".index(c) for c in bc["fix"]}
        if bc["symmetry"]:
            components.add(_symmetry_component(scene, bc, element_key("bc", bcs, i)))
        dofs = [2 * nodes + c for c in sorted(components)]
        fixed.extend(dofs)
        for d in dofs:
            holder[d[holder[d] < 0]] = i
        _add_support(scene, bc["name"] or f"bc {i}", dofs)
    owner = holder.copy()  # the bc fixing or prescribing each DOF
    for load in case_loads(scene.case.data):
        if load.array == "bc" and load.kinematic:
            dofs, values = _prescribed(scene, load, owner, holder)
            scene.prescribed[load.label] = {"dofs": dofs, "values": values}
            _add_support(scene, bcs[load.index]["name"] or f"bc {load.index}", [dofs])
    if is_axisymmetric(scene.case):
        fixed.append(_axis_supports(scene))
    if not fixed:
        return np.zeros(0, dtype=np.int64)
    return np.unique(np.concatenate(fixed)).astype(np.int64)


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
            load = next(x for x in case_loads(scene.case.data) if x.label == name)
            raise scene.case.error(f"{load.key}.displacement.x", f"node {node} (0, "
                                   f"{scene.nodes[node, 1]:.6g}) lies on the axis x = 0, where "
                                   f'plane = "axisymmetric" holds u_r = 0 already: drop x '
                                   f"from displacement, or use a node set off the axis")
    return dofs.astype(np.int64)


def _add_support(scene: Scene, name: str, dofs: list) -> None:
    """Add DOFs to a bc's entry of ``scene.support_dofs`` (bcs sharing a name share it; a bc
    that holds nothing, a pure force load, has none)."""
    if name not in scene.support_dofs and not any(len(d) for d in dofs):
        return
    old = scene.support_dofs.get(name, np.zeros(0, dtype=np.int64))
    scene.support_dofs[name] = np.unique(np.concatenate([old, *dofs])).astype(np.int64)


def _bc_nodes(scene: Scene, bc: dict) -> np.ndarray:
    """Global ids (sorted, unique) of the nodes of a [[bc]]'s edge or node set."""
    mesh = scene.meshes[bc["body"]]
    nodes = mesh.edge_nodes(bc["edge"]) if bc["edge"] else mesh.node_sets[bc["nodes"]]
    return np.unique(np.asarray(nodes, dtype=np.int64)) + scene.offsets[bc["body"]]


def _symmetry_component(scene: Scene, bc: dict, key: str) -> int:
    """The component a ``symmetry`` edge holds: x for a vertical edge, y for a horizontal one
    (each segment normal within 1e-9 of the axis: straight up to round-off)."""
    n = meshing.outward_normals(scene.nodes, scene.global_edge(bc["body"], bc["edge"]))
    for c in (0, 1):
        if np.all(np.abs(n[:, c]) > 1 - 1e-9):
            if "xy"[c] in bc["displacement"]:
                raise scene.case.error(f"{key}.displacement.{'xy'[c]}", f"symmetry = true "
                                       f"holds {'xy'[c]} on edge '{bc['edge']}' (its normal "
                                       f"component): a component is held or prescribed, not "
                                       f"both; remove symmetry or {'xy'[c]} from displacement")
            return c
    raise scene.case.error(f"{key}.symmetry", f"edge '{bc['edge']}' is not a straight line "
                           f"parallel to the x or y axis: use fix = [...] instead")


def _prescribed(scene: Scene, load: Load, owner: np.ndarray, holder: np.ndarray):
    """(dofs, values) of a displacement [[bc]], sorted by DOF; a DOF already fixed or
    prescribed by another [[bc]] is an error (the engine eliminates each DOF once)."""
    bcs = scene.case.data["bc"]
    bc = bcs[load.index]
    nodes = _bc_nodes(scene, bc)
    comps = sorted("xy".index(c) for c in bc["displacement"])
    dofs = np.concatenate([2 * nodes + c for c in comps])
    values = np.concatenate([np.full(len(nodes), bc["displacement"]["xy"[c]]) for c in comps])
    order = np.argsort(dofs, kind="stable")
    dofs, values = dofs[order], values[order]
    clash = owner[dofs] >= 0
    if clash.any():
        d = int(dofs[np.argmax(clash)])
        c, (x, y) = "xy"[d % 2], scene.nodes[d // 2]
        how = "fix/symmetry" if holder[d] >= 0 else "displacement"
        raise scene.case.error(f"{load.key}.displacement.{c}", f"node {d // 2} ({x:.6g}, "
                               f"{y:.6g}) is also held in {c} by "
                               f"{element_key('bc', bcs, int(owner[d]))} ({how}): each "
                               f"component is fixed or prescribed once; drop {c} from one of "
                               f'them (a zero component is a support: fix = ["{c}"] may '
                               f"overlap others), or use a node set without that node")
    owner[dofs] = load.index
    return dofs.astype(np.int64), values.astype(np.float64)
