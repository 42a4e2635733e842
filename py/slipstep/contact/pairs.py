"""The candidate pairs of a scene, in any dimension: every ``[[contact]]``'s rows, gathered into
the engine's ``pairs`` (docs/engine_api.md: node_a, node_b or -1 for a rigid obstacle, the
normal from the target towards node a, the initial gap, mu, the contact index, the mortar
weights compressed, and in 3D the tangent basis), and the scene's per-pair bookkeeping filled.
The rows of one contact are its dimension's (:func:`slipstep.contact.edges.pair_rows`,
:func:`slipstep.contact.faces.pair_rows`); node-to-node pairs, the same on edges and on faces,
are here."""

from __future__ import annotations

import numpy as np

from ..engine_model import ContactPairs
from ..case_record import NodeToNode
from ..validation.pairs import check_facing, check_gaps, check_matching

#: The columns every contact's rows give (``weights``: per row a list of (node, weight)).
COLUMNS = ("node_a", "node_b", "normal", "gap", "weights", "foot", "point_gap")


def contact_pairs(scene, rows_of, extent: str, foot_width: int, tangents=None) -> ContactPairs:
    """The engine's ``pairs`` of every ``[[contact]]`` of the scene.

    ``rows_of(scene, contact, key)`` gives one contact's rows (:data:`COLUMNS` and ``extent``,
    the size its force acts on: "length" in 2D, "area" in 3D), ``foot_width`` the columns of a row's foot, and
    ``tangents(normals)``, when given, each pair's tangent basis.  Fills the scene's pair
    positions, feet, own gaps, contact indices, ``pair_<extent>``, tangents and which contacts
    may be cut short (``contact_truncated``)."""
    contacts = scene.case.record.contact
    cols = {k: [] for k in (*COLUMNS, extent, "mu", "contact")}
    for i, c in enumerate(contacts):
        key = "contact" if len(contacts) == 1 else f"contact.{i}"
        rows = rows_of(scene, c, key)
        n = len(rows["node_a"])
        tag = scene.global_boundary(*c.contactor)
        scene.contact_truncated.append(bool(len(np.unique(rows["node_a"])) < len(np.unique(tag))))
        rows["contact"] = np.full(n, i, dtype=np.int64)
        rows["mu"] = np.full(n, float(c.mu))
        for k in cols:
            if k == "weights":
                cols[k].extend(rows.get("weights", [[]] * n))
            else:
                cols[k].append(rows[k])
    width = scene.nodes.shape[1]
    pairs = _pair_arrays(cols, width, tangents)
    scene.pair_xy = scene.nodes[pairs.node_a]
    scene.pair_foot = (
        np.concatenate(cols["foot"]).reshape(-1, foot_width)
        if cols["foot"]
        else np.zeros((0, foot_width))
    )
    scene.pair_point_gap = np.concatenate(cols["point_gap"]) if cols["point_gap"] else np.zeros(0)
    scene.pair_contact = pairs.contact
    setattr(scene, f"pair_{extent}", np.concatenate(cols[extent]) if cols[extent] else np.zeros(0))
    if tangents is not None:
        scene.pair_tangent = pairs.tangent
    return pairs


def _pair_arrays(cols: dict, width: int, tangents) -> ContactPairs:
    """The engine's ``pairs`` of the gathered columns (mortar rows compressed)."""
    if not cols["node_a"]:
        return ContactPairs(
            node_a=np.zeros(0, np.int64),
            node_b=np.zeros(0, np.int64),
            normal=np.zeros((0, width)),
            tangent=None if tangents is None else np.zeros((0, 2, width)),
            gap=np.zeros(0),
            mu=np.zeros(0),
            contact=np.zeros(0, np.int64),
        )
    normal = np.concatenate(cols["normal"]).reshape(-1, width)
    weights = {}
    if any(cols["weights"]):  # node-to-segment / node-to-surface rows (docs/engine_api.md)
        ptr, node, value = compressed_weights(cols["weights"])
        weights = {"weight_ptr": ptr, "weight_node": node, "weight_value": value}
    return ContactPairs(
        node_a=np.concatenate(cols["node_a"]).astype(np.int64),
        node_b=np.concatenate(cols["node_b"]).astype(np.int64),
        normal=normal,
        tangent=None if tangents is None else tangents(normal),
        gap=np.concatenate(cols["gap"]).astype(float),
        mu=np.concatenate(cols["mu"]).astype(np.float64),
        contact=np.concatenate(cols["contact"]).astype(np.int64),
        **weights,
    )


def compressed_weights(weights):
    """Per-pair weight lists [(node, c)] as the engine's compressed rows (weight_ptr,
    weight_node, weight_value); an empty list keeps the engine's default column."""
    ptr, node, value = [0], [], []
    for w in weights:
        node.extend(int(i) for i, _ in w)
        value.extend(float(c) for _, c in w)
        ptr.append(len(node))
    return (
        np.asarray(ptr, dtype=np.int64),
        np.asarray(node, dtype=np.int64),
        np.asarray(value, dtype=np.float64),
    )


def nearest_nodes(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each point of x: the index of the nearest point of y (the first of a tie) and the
    distance to it, computed in blocks (the full distance matrix of two large faces would not
    fit)."""
    index, distance = np.zeros(len(x), dtype=np.int64), np.zeros(len(x))
    for start in range(0, len(x), 256):
        d = np.linalg.norm(x[start : start + 256, None, :] - y[None, :, :], axis=2)
        index[start : start + 256] = np.argmin(d, axis=1)
        distance[start : start + 256] = d[np.arange(len(d)), index[start : start + 256]]
    return index, distance


def node_to_node_pairs(scene, c: NodeToNode, key: str):
    """Each node of edge_a (3D: face_a) with the nearest node of edge_b (face_b) within
    ``tolerance``; the normal is body b's outward normal at node b, the mean of its edge_b
    segments' (face_b triangles', by area) there, or the given one."""
    (_, body_a, tag_a), (_, body_b, tag_b) = c.surfaces
    seg_a = scene.global_boundary(body_a, tag_a)
    seg_b = scene.global_boundary(body_b, tag_b)
    nodes_a, nodes_b = np.unique(seg_a), np.unique(seg_b)
    nearest, distance = nearest_nodes(scene.nodes[nodes_a], scene.nodes[nodes_b])
    ok = distance <= c.tolerance
    label_a, label_b = f"{body_a}:{tag_a}", f"{body_b}:{tag_b}"
    if not ok.any():
        raise scene.case.error(
            f"{key}.tolerance",
            f"no node of {label_a} is within "
            f"{c.tolerance:g} of a node of {label_b}: the meshes must "
            f"match on the interface, or increase tolerance",
        )
    a, b = nodes_a[ok], nodes_b[nearest[ok]]
    check_matching(scene, nodes_a[~ok], seg_b, c.tolerance, label_a, label_b, key)
    check_matching(scene, np.setdiff1d(nodes_b, b), seg_a, c.tolerance, label_b, label_a, key)
    if len(np.unique(b)) != len(b):
        raise scene.case.error(
            f"{key}.tolerance",
            f"= {c.tolerance:g} pairs one target node "
            f"with several contactor nodes: decrease it",
        )
    if c.normal is not None:
        n = np.tile(np.asarray(c.normal) / np.linalg.norm(c.normal), (len(a), 1))
    else:
        n = scene.idealisation.surface_normals(scene.nodes, seg_b, b)
        n = n / np.linalg.norm(n, axis=1, keepdims=True)
    gap = np.einsum("ij,ij->i", scene.nodes[a] - scene.nodes[b], n)
    check_facing(scene, a, n, gap, c.tolerance, seg_a, b, seg_b, key)
    check_gaps(scene, a, gap, c.tolerance, key, f"move body '{body_a}' away from body '{body_b}'")
    gap = np.where(np.abs(gap) <= c.tolerance, 0.0, gap)
    return a, b, n, gap
