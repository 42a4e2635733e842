"""Mesh exchange: slipstep scene <-> XDMF/HDF5 <-> dolfinx, with explicit maps.

Files written by :func:`write_scene_xdmf` (layout measured to load in dolfinx 0.5.2 and in
meshio and ParaView; see examples/README.md)::

    NAME.xdmf        Grid "mesh":  2D points (XY), triangles, cell attribute "body"
                     (= body index + 1 = the engine's element_material + 1)
    NAME.h5          its arrays, plus /slipstep/node_sets/<name> and the attribute
                     ``slipstep`` = JSON {"cell_tags": {...}, "edge_tags": {...}}
    NAME_edges.xdmf  Grid "edges": the same points, the tagged boundary segments (Polyline, 2
                     nodes), cell attribute "edge" (1..K, one per (body, edge tag))
    NAME_edges.h5    its arrays (dolfinx 0.5.2 opens the .h5 named after the .xdmf, whatever
                     the DataItem says, so the two files cannot share one .h5)

Tag names also go into an ``Information`` element in meshio's field_data layout, so
``slipstep.mesh.triangle_files.read_mesh(NAME.xdmf, NAME_edges.xdmf)`` (and thus a case with ``file =`` /
``edge_file =``) gets the edge tags back by name.  With one body the edge names are the
body's own tags (``arc``); with several they are ``<body>.<tag>``.

dolfinx reorders nodes and cells when it builds its mesh.  :class:`DolfinxMesh` keeps the
maps, built from ``mesh.geometry.input_global_indices`` and
``mesh.topology.original_cell_index`` (serial):

    node_of_geom[g]  slipstep node of dolfinx geometry node g;  geom_of_node = inverse
    element_of_cell[c] slipstep element of dolfinx cell c;      cell_of_element = inverse
    block_of_node(V)[i]  dof block (unrolled dofs 2*block + component) of slipstep node i in a
                         P1 (vector) space V;  dg0_dof_of_element(W) likewise for DG0.

Only :func:`read_dolfinx` and :func:`write_dolfinx_xdmf` need dolfinx; writing and
:func:`read_xdmf_h5` need h5py only.

A 3D scene is exchanged alike: XYZ points, "Tetrahedron" cells and, in NAME_edges.xdmf, its
face tags as "Triangle" facets (the file keeps its name: it holds the facets).
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import dolfinx_api as api

MESH_GRID = "mesh"
EDGE_GRID = "edges"


# --------------------------------------------------------------------------- scene -> arrays
def edge_id(edge_names: dict, name: str) -> int:
    """The tag value of the edge called ``name`` in ``edge_names`` (value -> name)."""
    for k, v in edge_names.items():
        if v == name:
            return int(k)
    raise KeyError(f"no edge tag named {name!r} (known: {', '.join(edge_names.values())})")


@dataclass
class MeshData:
    """A tagged 2D triangle mesh as plain arrays (any numbering); in 3D ``triangles`` holds the
    tetrahedra and ``segments`` the tagged face triangles (the facets of either dimension).

    cell_tags (M,) int, segments (K, 2) node pairs, edge_tags (K,) int; ``cell_names`` and
    ``edge_names`` map tag value -> name; node_sets name -> node ids; ``topology`` the XDMF
    names of the cells and facets (a scene's: its idealisation's ``xdmf_topology``).
    """

    nodes: np.ndarray
    triangles: np.ndarray
    cell_tags: np.ndarray
    segments: np.ndarray
    edge_tags: np.ndarray
    cell_names: dict = field(default_factory=dict)
    edge_names: dict = field(default_factory=dict)
    node_sets: dict = field(default_factory=dict)
    topology: tuple[str, str] = ("Triangle", "Polyline")

    def edge_id(self, name: str) -> int:
        return edge_id(self.edge_names, name)


def scene_mesh_data(scene) -> MeshData:
    """The global mesh of a :class:`slipstep.scene.Scene` with body cell tags and edge tags."""
    several = len(scene.bodies) > 1
    segs, tags, edge_names, node_sets = [], [], {}, {}
    per = scene.nodes.shape[1]  # nodes of a facet: 2 (segments), 3 (triangles)
    for name in scene.bodies:
        mesh, off = scene.meshes[name], scene.offsets[name]
        for tag, s in mesh.tags.items():
            value = len(edge_names) + 1
            edge_names[value] = f"{name}.{tag}" if several else tag
            segs.append(np.asarray(s, dtype=np.int64).reshape(-1, per) + off)
            tags.append(np.full(len(s), value, dtype=np.int32))
        for tag, ids in mesh.node_sets.items():
            if tag not in mesh.tags:  # every edge (face) tag is also a node set: not repeated
                node_sets[f"{name}.{tag}" if several else tag] = np.asarray(ids) + off
    return MeshData(
        nodes=np.asarray(scene.nodes, dtype=np.float64),
        triangles=np.asarray(scene.elements, dtype=np.int64),
        cell_tags=(np.asarray(scene.element_body) + 1).astype(np.int32),
        segments=np.concatenate(segs) if segs else np.zeros((0, per), np.int64),
        edge_tags=np.concatenate(tags) if tags else np.zeros(0, np.int32),
        cell_names={i + 1: b for i, b in enumerate(scene.bodies)},
        edge_names=edge_names,
        node_sets=node_sets,
        topology=scene.idealisation.xdmf_topology,
    )


# --------------------------------------------------------------------------- writing
def exchange_paths(path: str | Path) -> tuple[Path, Path, Path]:
    """(NAME.xdmf, NAME_edges.xdmf, NAME.h5) for a path NAME.xdmf (or NAME); the edge file's
    arrays are in NAME_edges.h5."""
    path = Path(path)
    if path.suffix.lower() != ".xdmf":
        path = path.with_name(path.name + ".xdmf")
    return path, path.with_name(path.stem + "_edges.xdmf"), path.with_suffix(".h5")


def _check_unique_edges(data: MeshData) -> None:
    key = np.sort(data.segments, axis=1)
    _, index, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    if (counts > 1).any():
        i = index[np.argmax(counts > 1)]
        dup = np.flatnonzero((key == key[i]).all(1))
        names = sorted(
            {data.edge_names.get(int(data.edge_tags[j]), str(data.edge_tags[j])) for j in dup}
        )
        raise ValueError(
            f"segment {key[i].tolist()} carries several edge tags ({', '.join(names)}):"
            f" dolfinx facet tags hold one value per facet; tag it once"
        )


def _data_item(parent, h5name: str, dataset: str, array: np.ndarray):
    kind = "Float" if np.issubdtype(array.dtype, np.floating) else "Int"
    shape = " ".join(str(s) for s in array.shape)
    item = ET.SubElement(
        parent,
        "DataItem",
        DataType=kind,
        Dimensions=shape,
        Format="HDF",
        Precision=str(array.dtype.itemsize),
    )
    item.text = f"{h5name}:/{dataset}"


def _information(grid, names: dict, dim: int):
    """meshio's field_data layout: <main><map key="name" dim="d">value</map>...</main>."""
    if not names:
        return
    main = ET.Element("main")
    for value, name in names.items():
        m = ET.SubElement(main, "map", key=str(name), dim=str(dim))
        m.text = str(int(value))
    info = ET.SubElement(grid, "Information", Name="Information", Value=str(len(names)))
    info.text = ET.tostring(main, encoding="unicode")


def _grid_xml(
    h5name: str,
    name: str,
    topology: str,
    n_per: int,
    cells_ds: str,
    cells,
    attr_name: str,
    attr_ds: str,
    attr,
    names: dict,
    dim: int,
    points,
) -> ET.Element:
    root = ET.Element("Xdmf", Version="3.0")
    domain = ET.SubElement(root, "Domain")
    grid = ET.SubElement(domain, "Grid", Name=name, GridType="Uniform")
    _information(grid, names, dim)
    geo = ET.SubElement(grid, "Geometry", GeometryType="XYZ" if points.shape[1] == 3 else "XY")
    _data_item(geo, h5name, "mesh/geometry", points)
    topo = ET.SubElement(
        grid,
        "Topology",
        TopologyType=topology,
        NumberOfElements=str(len(cells)),
        NodesPerElement=str(n_per),
    )
    _data_item(topo, h5name, cells_ds, cells)
    att = ET.SubElement(grid, "Attribute", Name=attr_name, AttributeType="Scalar", Center="Cell")
    _data_item(att, h5name, attr_ds, attr)
    return root


def write_mesh_xdmf(path: str | Path, data: MeshData) -> tuple[Path, Path, Path]:
    """Write ``data`` as NAME.xdmf + NAME.h5 (triangles + cell tags) and NAME_edges.xdmf +
    NAME_edges.h5 (segments + edge tags); in 3D tetrahedra and face triangles.  Returns
    (NAME.xdmf, NAME_edges.xdmf, NAME.h5)."""
    import h5py

    xdmf, edges_xdmf, h5 = exchange_paths(path)
    xdmf.parent.mkdir(parents=True, exist_ok=True)
    _check_unique_edges(data)
    nodes = np.ascontiguousarray(data.nodes, dtype=np.float64)
    if nodes.ndim != 2 or nodes.shape[1] not in (2, 3):
        raise ValueError(f"nodes must be (N, 2) or, in 3D, (N, 3), not {nodes.shape}")
    gdim = nodes.shape[1]
    tris = np.ascontiguousarray(data.triangles, dtype=np.int64)
    segs = np.ascontiguousarray(data.segments, dtype=np.int64).reshape(-1, gdim)
    ctags = np.ascontiguousarray(data.cell_tags, dtype=np.int32)
    etags = np.ascontiguousarray(data.edge_tags, dtype=np.int32)
    meta = {
        "cell_tags": {str(k): v for k, v in data.cell_names.items()},
        "edge_tags": {str(k): v for k, v in data.edge_names.items()},
    }
    edges_h5 = edges_xdmf.with_suffix(".h5")
    with h5py.File(h5, "w") as f:
        f["mesh/geometry"] = nodes
        f["mesh/topology"] = tris
        f["mesh/body"] = ctags
        for name, ids in data.node_sets.items():
            f[f"slipstep/node_sets/{name}"] = np.asarray(ids, dtype=np.int64)
        f.attrs["slipstep"] = json.dumps(meta)
    with h5py.File(edges_h5, "w") as f:
        f["mesh/geometry"] = nodes
        f["edges/topology"] = segs
        f["edges/edge"] = etags
    cell, facet = data.topology
    mesh_xml = _grid_xml(
        h5.name,
        MESH_GRID,
        cell,
        gdim + 1,
        "mesh/topology",
        tris,
        "body",
        "mesh/body",
        ctags,
        data.cell_names,
        gdim,
        nodes,
    )
    edge_xml = _grid_xml(
        edges_h5.name,
        EDGE_GRID,
        facet,
        gdim,
        "edges/topology",
        segs,
        "edge",
        "edges/edge",
        etags,
        data.edge_names,
        gdim - 1,
        nodes,
    )
    for root, p in ((mesh_xml, xdmf), (edge_xml, edges_xdmf)):
        ET.indent(root)
        p.write_text('<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n")
    return xdmf, edges_xdmf, h5


def write_scene_xdmf(scene, path: str | Path) -> tuple[Path, Path, Path]:
    """Write a scene's global mesh (body cell tags, edge tags, node sets).  See the module doc."""
    return write_mesh_xdmf(path, scene_mesh_data(scene))


# --------------------------------------------------------------------------- reading (h5py)
def _h5_array(xdmf: Path, item: ET.Element) -> np.ndarray:
    import h5py

    text = item.text.strip()
    fmt = item.get("Format", "XML")
    if fmt == "XML":
        shape = [int(s) for s in item.get("Dimensions").split()]
        dtype = (
            np.float64
            if item.get("DataType", item.get("NumberType", "Float")) == "Float"
            else np.int64
        )
        return np.array(text.split(), dtype=dtype).reshape(shape)
    fname, _, dataset = text.partition(":")
    with h5py.File(xdmf.parent / fname, "r") as f:
        return f[dataset][()]


def _grids(xdmf: Path) -> dict:
    root = ET.parse(xdmf).getroot()
    out = {}
    for grid in root.iter("Grid"):
        if grid.get("GridType", "Uniform") == "Uniform":
            out[grid.get("Name")] = grid
    return out


def _read_grid(xdmf: Path, grid: ET.Element, geometry=None):
    geo = grid.find("Geometry")
    points = _h5_array(xdmf, geo.find("DataItem")) if geo is not None else geometry
    topo = grid.find("Topology")
    cells = _h5_array(xdmf, topo.find("DataItem")).astype(np.int64)
    cells = cells.reshape(int(topo.get("NumberOfElements")), -1)
    values, names = None, {}
    att = grid.find("Attribute")
    if att is not None:
        values = _h5_array(xdmf, att.find("DataItem")).reshape(-1).astype(np.int32)
    info = grid.find("Information")
    if info is not None and info.text:
        for m in ET.fromstring(info.text):
            names[int(m.text)] = m.get("key")
    return points, topo.get("TopologyType"), cells, values, names


def read_xdmf_h5(path: str | Path, edges_path: str | Path | None = None) -> MeshData:
    """Read a tagged triangle mesh with h5py, without dolfinx or meshio.

    Reads both layouts: slipstep's pair of files (``NAME.xdmf`` + ``NAME_edges.xdmf``, found
    automatically), and dolfinx's single file (``XDMFFile.write_mesh`` then
    ``write_meshtags`` for the cell and the facet tags: grids "mesh", then one grid per
    meshtags whose topology is triangles (cell tags) or lines (facet tags)).  Meshtags given
    as node tuples are matched to the triangles; untagged cells get tag 0.
    """
    xdmf = Path(path)
    grids = _grids(xdmf)
    tri_grid = grids[MESH_GRID] if MESH_GRID in grids else next(iter(grids.values()))
    nodes, kind, tris, ctags, cnames = _read_grid(xdmf, tri_grid)
    if kind.lower() != "triangle":
        raise ValueError(f"{xdmf}: the first grid holds {kind} cells, not triangles")
    nodes = np.asarray(nodes, dtype=np.float64)[:, :2]
    segs, etags, enames = np.zeros((0, 2), np.int64), np.zeros(0, np.int32), {}
    if ctags is None:
        ctags = np.zeros(len(tris), np.int32)
    for name, grid in grids.items():  # dolfinx layout: meshtags grids in the same file
        if grid is tri_grid:
            continue
        _, k, cells, vals, _ = _read_grid(xdmf, grid, nodes)
        if k.lower() == "triangle":
            ctags = _match_tags(tris, cells, vals, len(tris))
        elif k.lower() == "polyline":
            segs, etags = cells, vals
    default_edges = xdmf.with_name(xdmf.stem + "_edges.xdmf")
    edges_path = (
        Path(edges_path) if edges_path else (default_edges if default_edges.exists() else None)
    )
    if edges_path is not None:
        eg = _grids(edges_path)
        _, _, segs, etags, enames = _read_grid(edges_path, next(iter(eg.values())), nodes)
    node_sets, meta = {}, {}
    h5 = xdmf.with_suffix(".h5")
    if h5.exists():
        import h5py

        with h5py.File(h5, "r") as f:
            if "slipstep" in f.attrs:
                meta = json.loads(f.attrs["slipstep"])
            if "slipstep/node_sets" in f:
                node_sets = {k: v[()] for k, v in f["slipstep/node_sets"].items()}
    cnames = cnames or {int(k): v for k, v in meta.get("cell_tags", {}).items()}
    enames = enames or {int(k): v for k, v in meta.get("edge_tags", {}).items()}
    return MeshData(nodes, tris, ctags, segs.reshape(-1, 2), etags, cnames, enames, node_sets)


def _match_tags(cells: np.ndarray, tagged: np.ndarray, values: np.ndarray, n: int) -> np.ndarray:
    """Tag of each row of ``cells`` given tagged node tuples (any vertex order)."""
    index = {tuple(sorted(c)): i for i, c in enumerate(cells.tolist())}
    out = np.zeros(n, np.int32)
    for c, v in zip(tagged.tolist(), values.tolist()):
        out[index[tuple(sorted(c))]] = v
    return out


# --------------------------------------------------------------------------- dolfinx side
@dataclass
class DolfinxMesh:
    """A dolfinx mesh read from the exchange files, its tags, and the maps to slipstep."""

    mesh: object  # dolfinx.mesh.Mesh
    cell_tags: object  # dolfinx MeshTags, dim 2 (body index + 1)
    facet_tags: object  # dolfinx MeshTags, dim 1 (edge tag values)
    cell_names: dict
    edge_names: dict
    node_of_geom: np.ndarray  # (N,) slipstep node of each dolfinx geometry node
    geom_of_node: np.ndarray  # (N,) inverse
    element_of_cell: np.ndarray  # (M,) slipstep element of each dolfinx cell
    cell_of_element: np.ndarray  # (M,) inverse

    @property
    def n_nodes(self) -> int:
        return len(self.node_of_geom)

    @property
    def n_cells(self) -> int:
        return len(self.element_of_cell)

    def edge_id(self, name: str) -> int:
        return edge_id(self.edge_names, name)

    def facets(self, name: str) -> np.ndarray:
        """dolfinx facet indices of an edge tag."""
        return api.tagged(self.facet_tags, self.edge_id(name))

    @property
    def gdim(self) -> int:
        """2 for triangles, 3 for tetrahedra."""
        return api.mesh_kind(self.mesh)[2]

    def block_of_node(self, V) -> np.ndarray:
        """Dof block of each slipstep node in a P1 (scalar or vector) space V on this mesh.

        Built cell by cell: local vertex j of cell c has geometry node geometry.dofmap[c][j]
        and dof block V.dofmap[c][j] (P1 on an affine P1 mesh: same local layout)."""
        if api.dofs_per_cell(V) != self.gdim + 1:
            raise ValueError(
                "block_of_node needs a P1 space (a dof per vertex of a triangle " "or tetrahedron)"
            )
        block_of_geom = np.full(self.n_nodes, -1, dtype=np.int64)
        block_of_geom[api.cell_nodes(self.mesh).ravel()] = api.cell_dofs(V).ravel()
        return block_of_geom[self.geom_of_node]

    def dg0_dof_of_element(self, W) -> np.ndarray:
        """Dof (block) of each slipstep element in a DG0 space W on this mesh."""
        return api.cell_dofs(W)[self.cell_of_element, 0].astype(np.int64)

    # conversions between slipstep-ordered arrays and dolfinx Functions --------------------
    def set_vector_function(self, func, values: np.ndarray) -> None:
        """Set a P1 vector Function from a slipstep (N, 2) nodal array (3D: (N, 3))."""
        block, d = self.block_of_node(api.space_of(func)), self.gdim
        api.dof_values(func).reshape(-1, d)[block] = np.asarray(values).reshape(-1, d)
        api.scatter(func)

    def vector_function_values(self, func) -> np.ndarray:
        """A P1 vector Function as a slipstep (N, 2) nodal array (3D: (N, 3))."""
        block = self.block_of_node(api.space_of(func))
        return api.dof_values(func).reshape(-1, self.gdim)[block].copy()

    def cell_function_values(self, func) -> np.ndarray:
        """A DG0 Function (any value size) as a slipstep (M, k) per-element array."""
        W = api.space_of(func)
        values = api.dof_values(func).reshape(-1, api.block_size(W))
        return values[self.dg0_dof_of_element(W)].copy()

    def set_cell_function(self, func, values: np.ndarray) -> None:
        """Set a DG0 Function (any value size) from a slipstep (M, k) per-element array."""
        W = api.space_of(func)
        bs = api.block_size(W)
        api.dof_values(func).reshape(-1, bs)[self.dg0_dof_of_element(W)] = np.asarray(
            values
        ).reshape(self.n_cells, bs)
        api.scatter(func)

    def slipstep_triangles(self) -> np.ndarray:
        """dolfinx cells (in dolfinx cell order) as slipstep node triples."""
        return self.node_of_geom[api.cell_nodes(self.mesh)]


def read_dolfinx(path: str | Path, edges_path: str | Path | None = None) -> DolfinxMesh:
    """Read the exchange files (``write_scene_xdmf``) into dolfinx and build the maps."""
    xdmf, default_edges, h5 = exchange_paths(path)
    edges_xdmf = Path(edges_path) if edges_path else default_edges
    msh, ct, ft = api.read_tagged_mesh(xdmf, MESH_GRID, edges_xdmf, EDGE_GRID)
    meta = {}
    import h5py

    with h5py.File(h5, "r") as f:
        if "slipstep" in f.attrs:
            meta = json.loads(f.attrs["slipstep"])
    node_of_geom = api.input_node_index(msh)
    element_of_cell = api.input_cell_index(msh)
    return DolfinxMesh(
        mesh=msh,
        cell_tags=ct,
        facet_tags=ft,
        cell_names={int(k): v for k, v in meta.get("cell_tags", {}).items()},
        edge_names={int(k): v for k, v in meta.get("edge_tags", {}).items()},
        node_of_geom=node_of_geom,
        geom_of_node=_inverse(node_of_geom),
        element_of_cell=element_of_cell,
        cell_of_element=_inverse(element_of_cell),
    )


def _inverse(perm: np.ndarray) -> np.ndarray:
    inv = np.full(len(perm), -1, dtype=np.int64)
    inv[perm] = np.arange(len(perm))
    if (inv < 0).any():
        raise ValueError(
            "the dolfinx numbering is not a permutation of the input "
            "(ghosts or several processes?): slipstep.fenicsx runs in serial"
        )
    return inv


def scene_to_dolfinx(scene, folder: str | Path, name: str = "mesh") -> DolfinxMesh:
    """Write the scene's mesh to ``folder/name.xdmf`` (+ edges, h5) and read it into dolfinx."""
    path = Path(folder) / f"{name}.xdmf"
    write_scene_xdmf(scene, path)
    return read_dolfinx(path)


def write_dolfinx_xdmf(dm: DolfinxMesh, path: str | Path) -> Path:
    """Write the dolfinx mesh with its cell and facet tags the dolfinx way: one file, grids
    "mesh", "cell_tags", "facet_tags" (read back with :func:`read_xdmf_h5`)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    api.write_tagged_mesh(path, dm.mesh, {"cell_tags": dm.cell_tags, "facet_tags": dm.facet_tags})
    return path


def map_by_coordinates(reference: np.ndarray, other: np.ndarray) -> np.ndarray:
    """Index into ``reference`` of each row of ``other`` with identical coordinates (exact:
    the exchange is float64 both ways).  Raises if a point has no exact twin."""
    ref = {tuple(p): i for i, p in enumerate(np.asarray(reference, dtype=np.float64).tolist())}
    if len(ref) != len(reference):
        raise ValueError("the reference mesh has coincident nodes: map them by index instead")
    try:
        return np.array(
            [ref[tuple(p)] for p in np.asarray(other, np.float64).tolist()], dtype=np.int64
        )
    except KeyError as exc:
        raise ValueError(f"node {exc.args[0]} has no exact twin in the reference mesh") from None
