"""Mesh files: ``.msh`` (gmsh) and ``.xdmf`` (meshio) read into a :class:`slipstep.mesh.Mesh`,
a ``meshio.Mesh`` converted, and a mesh written as gmsh MSH 2.2 for other codes."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .gmsh_api import gmsh_session, triangles_and_edges
from .base import Mesh, MeshError
from .triangles import checked_mesh, from_arrays, planar_coordinates


def mesh_file(path) -> tuple[Path, str, str]:
    """(path, its name for messages, its lower-case suffix) of a mesh file that exists, else a
    one-line MeshError."""
    path = Path(path)
    if not path.exists():
        raise MeshError(f"{path}: no such mesh file")
    return path, str(path), path.suffix.lower()


def read_mesh(path: str | Path, edge_file: str | Path | None = None, scale: float = 1.0) -> Mesh:
    """Read a triangle mesh: ``.msh`` (through gmsh; physical line names are the edge tags,
    physical points the node sets) or ``.xdmf`` (through meshio; line cells, from the same file
    or from ``edge_file``, tagged by the first integer cell-data array; a tag is named by its
    meshio field_data name if present, else by its number).

    A mesh whose triangles are ALL clockwise is flipped; a mix is an error naming the first
    inverted element.
    """
    path, where, suffix = mesh_file(path)
    if suffix == ".msh":
        xyz, triangles, edges, node_sets = read_msh_isolated(path, where, triangles_and_edges)
    elif suffix == ".xdmf":
        xyz, triangles, edges = _read_xdmf(path)
        node_sets = {}
        if edge_file:
            _, extra_tris, extra = _read_xdmf(Path(edge_file), need_triangles=False)
            if len(extra_tris) and not np.array_equal(extra_tris, triangles):
                raise MeshError(f"{edge_file}: holds triangles too: keep only the line cells")
            edges.update(extra)
    else:
        raise MeshError(f"{where}: unknown mesh format '{suffix}': use .msh or .xdmf")
    xy = planar_coordinates(xyz, where)
    if not np.isfinite(xy).all():
        k = int(np.nonzero(~np.isfinite(xy).all(axis=1))[0][0])
        raise MeshError(
            f"{where}: node {k} has a non-finite coordinate "
            f"({', '.join(str(c) for c in xy[k])}): fix the mesh file"
        )
    return checked_mesh(xy * scale, triangles, edges, node_sets, where=where, flip_clockwise=True)


def _read_msh(path: str, where: str, extract):
    """``extract(gmsh)`` of a .msh file (nodes, elements, tags and node sets), through gmsh."""
    with gmsh_session() as gmsh:
        try:
            gmsh.open(path)
        except Exception as exc:  # gmsh raises bare Exception
            raise MeshError(f"{where}: gmsh cannot read it: {' '.join(str(exc).split())}") from None
        try:
            return extract(gmsh)
        except MeshError as exc:
            raise MeshError(f"{where}: {exc}") from None


def _msh_child(path: str, where: str, extract, conn) -> None:
    import faulthandler

    faulthandler.disable()  # a crashing gmsh must not print a Python stack (pytest enables it)
    devnull = os.open(os.devnull, os.O_WRONLY)  # nor libc/C++ noise
    os.dup2(devnull, 1)
    os.dup2(devnull, 2)
    try:
        conn.send(("ok", _read_msh(path, where, extract)))
    except MeshError as exc:
        conn.send(("error", str(exc)))
    except BaseException as exc:  # noqa: BLE001 - anything else gmsh raises
        conn.send(("error", f"{where}: gmsh cannot read it: {' '.join(str(exc).split())}"))
    finally:
        conn.close()


def read_msh_isolated(path: Path, where: str, extract):
    """``extract(gmsh)`` of a .msh file (:func:`slipstep.mesh.gmsh_api.triangles_and_edges`, or
    ``tetrahedra_and_faces`` in 3D) read in a forked child process: gmsh corrupts its memory on
    some damaged .msh files and crashes the whole process (segmentation fault, abort; found by
    tests/case/test_fuzz.py), so a crash there becomes a MeshError here."""
    import multiprocessing

    try:
        ctx = multiprocessing.get_context("fork")
    except ValueError:  # no fork on this platform: read in-process
        return _read_msh(str(path), where, extract)
    receive, send = ctx.Pipe(duplex=False)
    child = ctx.Process(target=_msh_child, args=(str(path), where, extract, send), daemon=True)
    child.start()
    send.close()
    try:
        kind, payload = receive.recv()
    except EOFError:  # the child died without an answer
        kind, payload = None, None
    finally:
        receive.close()
        child.join()
    if kind == "ok":
        return payload
    if kind == "error":
        raise MeshError(payload)
    raise MeshError(
        f"{where}: gmsh crashed while reading it (exit code {child.exitcode}): the "
        f"file is damaged or truncated; export the mesh again"
    )


def _read_xdmf(path: Path, need_triangles: bool = True):
    return _meshio_cells(xdmf_mesh(path), str(path), need_triangles)


def xdmf_mesh(path: Path):
    """The ``meshio.Mesh`` of an .xdmf file; MeshError (one line) for anything meshio cannot
    read (a missing file, broken XML or HDF5, several grids)."""
    try:
        import meshio
    except ImportError:
        raise MeshError("meshio is needed to read .xdmf meshes: pip install meshio") from None
    if not path.exists():
        raise MeshError(f"{path}: no such mesh file")
    try:
        # the XDMF reader itself: meshio.read prints the reader's error and calls sys.exit
        m = meshio.xdmf.read(str(path))
    except SystemExit:
        raise MeshError(f"{path}: meshio cannot read it") from None
    except Exception as exc:  # noqa: BLE001 - XML, HDF5, numpy and meshio errors alike
        why = " ".join(str(exc).split()) or f"{type(exc).__name__} (not a valid XDMF mesh)"
        if "one grid" in why:  # meshio reads a single grid
            raise MeshError(
                f"{path}: meshio cannot read this XDMF (several grids, e.g. a time "
                f"series?): write the mesh on its own"
            ) from None
        raise MeshError(f"{path}: meshio cannot read it: {why}") from None
    return m


def _meshio_cells(m, where: str, need_triangles: bool = True):
    """(points, triangles, edges) of a meshio.Mesh: triangle cells, and line cells tagged by
    the first integer cell-data array (a tag named by its field_data name if any)."""
    triangles = [b.data for b in m.cells if b.type == "triangle"]
    for b in m.cells:
        if b.type not in ("triangle", "line", "vertex"):
            hint = " (a volume mesh: set analysis.dimension = 3)" if b.type == "tetra" else ""
            raise MeshError(
                f"{where}: cells of type '{b.type}': only triangles and lines "
                f"are supported{hint}"
            )
    if need_triangles and not triangles:
        raise MeshError(f"{where}: no triangle cells")
    tri = np.concatenate(triangles) if triangles else np.zeros((0, 3), np.int64)
    return m.points, tri, tagged_cells(m, "line", where)


def tagged_cells(m, kind: str, where: str) -> dict[str, np.ndarray]:
    """The cells of type ``kind`` ("line" in 2D, "triangle" for the faces of a 3D mesh) of a
    meshio.Mesh grouped by the first integer cell-data array of their block: tag name (its
    field_data name if any, else its number) -> cells."""
    dim = {"line": 1, "triangle": 2}[kind]
    names = {
        int(v[0]): k
        for k, v in getattr(m, "field_data", {}).items()
        if len(v) >= 2 and int(v[1]) == dim
    }
    out: dict[str, np.ndarray] = {}
    for i, block_ in enumerate(m.cells):
        if block_.type != kind:
            continue
        tags = None
        for arrays in m.cell_data.values():
            a = np.asarray(arrays[i])
            if a.ndim >= 1 and a.shape[1:] in ((), (1,)):  # one value per cell
                if np.issubdtype(a.dtype, np.integer) or np.all(a == np.round(a)):
                    tags = a.reshape(-1).astype(np.int64)
                    break
        if tags is None:
            raise MeshError(f"{where}: {kind} cells without an integer tag array: tag them")
        for t in np.unique(tags):
            name = names.get(int(t), str(int(t)))
            cells = block_.data[tags == t]
            out[name] = np.concatenate([out[name], cells]) if name in out else cells
    return out


def from_meshio(mesh, where: str = "meshio mesh") -> Mesh:
    """A body's mesh from a ``meshio.Mesh`` (e.g. ``meshio.read("body.msh")``): its triangle
    cells, and its line cells as edges tagged by the first integer cell-data array (gmsh's
    physical groups), each tag named by its ``field_data`` name when there is one."""
    points, triangles, edges = _meshio_cells(mesh, where)
    return from_arrays(points, triangles, edges, where=where)


def write_msh(mesh: Mesh, path: str | Path) -> dict[str, int]:
    """Write ``mesh`` as a gmsh MSH 2.2 ASCII file that :func:`read_mesh` (and other codes, e.g.
    GetFEM's gmsh import) read back: nodes with z = 0, triangles in physical surface ``body``,
    every edge tag a named physical line group, every node set a named physical point group.
    Returns the physical tag of each group (edges first, sorted by name; then node sets; the
    surface last): readers that number regions by tag need it."""
    edges, sets = sorted(mesh.edges), sorted(set(mesh.node_sets) - set(mesh.edges))
    tags = {name: i + 1 for i, name in enumerate(edges + sets)}
    tags["body"] = len(tags) + 1
    rows = [f'1 {tags[n]} "{n}"' for n in edges] + [f'0 {tags[n]} "{n}"' for n in sets]
    rows.append(f'2 {tags["body"]} "body"')
    # elements: id type(15 point, 1 line, 2 triangle) 2 physical elementary node ids (1-based)
    elements = [(15, tags[n], [[int(k)] for k in mesh.node_sets[n]]) for n in sets]
    elements += [(1, tags[n], mesh.edges[n].tolist()) for n in edges]
    elements.append((2, tags["body"], mesh.triangles.tolist()))
    lines = [
        "$MeshFormat",
        "2.2 0 8",
        "$EndMeshFormat",
        "$PhysicalNames",
        str(len(rows)),
        *rows,
        "$EndPhysicalNames",
        "$Nodes",
        str(mesh.n_nodes),
    ]
    lines += [f"{i + 1} {x!r} {y!r} 0" for i, (x, y) in enumerate(mesh.nodes.tolist())]
    lines += ["$EndNodes", "$Elements", str(sum(len(e[2]) for e in elements))]
    k = 0
    for kind, tag, conn in elements:
        for nodes in conn:
            k += 1
            lines.append(f"{k} {kind} 2 {tag} {tag} " + " ".join(str(n + 1) for n in nodes))
    lines.append("$EndElements")
    Path(path).write_text("\n".join(lines) + "\n")
    return tags
