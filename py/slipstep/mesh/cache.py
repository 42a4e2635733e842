"""A cache of the built-in gmsh meshes, so that a rerun or a sweep does not mesh again.

A generator's mesh is a function of its arguments, of the gmsh version and of the meshing code:
those three are an entry's key (:func:`key`).  An entry is one ``.npz`` file in
``<cache>/meshes``, named by the key's digest; it holds the key itself and a digest of its
arrays, and one that does not read, holds another key or whose arrays do not match their
digest is meshed again and rewritten, never trusted.  An entry is written to a temporary file
and renamed, so that processes meshing the same scene at once (a sweep's workers) never read
half of one.

Where: ``$SLIPSTEP_CACHE`` (a folder), else ``$XDG_CACHE_HOME/slipstep``, else
``~/.cache/slipstep``.  ``SLIPSTEP_CACHE=off`` meshes every time and writes nothing.  Entries
are never removed by slipstep: delete the folder to reclaim its space.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import inspect
import io
import json
import os
import re
import tempfile
from pathlib import Path

import numpy as np

#: The layout of an entry; a change makes every older entry stale.
FORMAT = 1
#: The modules whose source decides a generated mesh (the package's own files).
MESHING_CODE = (
    "base.py",
    "cache.py",
    "gmsh_api.py",
    "tetrahedra.py",
    "tetrahedron_generators.py",
    "triangle_generators.py",
    "triangles.py",
)
PACKAGE = Path(__file__).resolve().parent
OFF = "off"
#: gmsh's module states its version within this many bytes of its start.
GMSH_HEAD = 8192


def folder() -> Path | None:
    """The cache's folder, or None when it is off (``SLIPSTEP_CACHE=off``)."""
    chosen = os.environ.get("SLIPSTEP_CACHE", "").strip()
    if chosen.lower() == OFF:
        return None
    if chosen:
        return Path(chosen).expanduser()
    base = os.environ.get("XDG_CACHE_HOME", "").strip() or Path.home() / ".cache"
    return Path(base) / "slipstep"


@functools.lru_cache(maxsize=1)
def gmsh_version() -> str:
    """The installed gmsh's version, read from the head of its Python module (gmsh itself is
    not loaded: that takes longer than reading a cached mesh); "none" without gmsh."""
    import importlib.util

    spec = importlib.util.find_spec("gmsh")
    if spec is None or not spec.origin:
        return "none"
    try:
        with open(spec.origin, "rb") as f:
            head = f.read(GMSH_HEAD).decode("utf-8", "replace")
    except OSError:
        head = ""
    found = re.search(r'^GMSH_API_VERSION\s*=\s*"([^"]+)"', head, re.MULTILINE)
    return found.group(1) if found else f"unknown ({spec.origin})"


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """A digest of the meshing code's source (`MESHING_CODE`)."""
    h = hashlib.sha256()
    for name in MESHING_CODE:
        path = PACKAGE / name
        h.update(name.encode())
        h.update(path.read_bytes() if path.is_file() else b"missing")
    return h.hexdigest()


def key(generator: str, arguments: dict) -> str | None:
    """The entry's key: the generator, its arguments, the gmsh version, the code's digest and
    `FORMAT`, as canonical JSON; None when an argument has no exact text (not cached)."""
    try:
        args = json.dumps(_plain(arguments), sort_keys=True, allow_nan=True)
    except TypeError:
        return None
    return json.dumps(
        {
            "format": FORMAT,
            "generator": generator,
            "arguments": json.loads(args),
            "gmsh": gmsh_version(),
            "code": code_version(),
        },
        sort_keys=True,
    )


def _plain(value):
    """Arguments as JSON values (floats written exactly by their repr); TypeError for others."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    raise TypeError(f"no exact text for {type(value).__name__}")


def cached(generate):
    """``generate`` (a built-in generator) through the cache: its mesh read from the entry of
    its arguments when one is there and sound, else generated and stored."""
    signature = inspect.signature(generate)
    name = f"{generate.__module__}.{generate.__qualname__}"

    @functools.wraps(generate)
    def through_cache(*args, **kwargs):
        where = folder()
        bound = signature.bind(*args, **kwargs)
        bound.apply_defaults()
        entry_key = key(name, bound.arguments) if where is not None else None
        if entry_key is None:
            return generate(*args, **kwargs)
        path = where / "meshes" / f"{hashlib.sha256(entry_key.encode()).hexdigest()}.npz"
        mesh = load(path, entry_key)
        if mesh is None:
            mesh = generate(*args, **kwargs)
            store(path, entry_key, mesh)
        return mesh

    return through_cache


def _arrays(mesh) -> dict[str, np.ndarray]:
    """An entry's arrays: nodes, elements, every tag's cells and every node set."""
    out = {"nodes": mesh.nodes, "elements": mesh.elements}
    out.update({f"tag:{k}": v for k, v in mesh.tags.items()})
    out.update({f"set:{k}": v for k, v in mesh.node_sets.items()})
    return out


def _digest(entry_key: str, arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256(entry_key.encode())
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype.str}|{a.shape}".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def store(path: Path, entry_key: str, mesh) -> None:
    """Write the entry (a temporary file renamed into place); a cache that cannot be written
    is skipped: the run goes on with the mesh it made."""
    arrays = _arrays(mesh)
    buffer = io.BytesIO()
    np.savez(
        buffer,
        __key__=np.array(entry_key),
        __digest__=np.array(_digest(entry_key, arrays)),
        **arrays,
    )
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    except OSError:
        return
    try:
        with os.fdopen(handle, "wb") as f:
            f.write(buffer.getvalue())
        os.replace(temporary, path)
    except OSError:
        with contextlib.suppress(OSError):
            os.unlink(temporary)


def load(path: Path, entry_key: str):
    """The entry's mesh, or None when there is none or it is not sound (unreadable, another
    key, arrays that do not match their digest)."""
    from .tetrahedra import TetMesh
    from .triangles import TriangleMesh

    try:
        with np.load(path, allow_pickle=False) as f:
            arrays = {name: f[name] for name in f.files}
    except Exception:  # noqa: BLE001 - any damage means: mesh again
        return None
    stored_key, digest = arrays.pop("__key__", None), arrays.pop("__digest__", None)
    if stored_key is None or digest is None or str(stored_key) != entry_key:
        return None
    if (
        "nodes" not in arrays
        or "elements" not in arrays
        or _digest(entry_key, arrays) != str(digest)
    ):
        return None
    tags = {k[4:]: v for k, v in arrays.items() if k.startswith("tag:")}
    sets = {k[4:]: v for k, v in arrays.items() if k.startswith("set:")}
    nodes, elements = arrays["nodes"], arrays["elements"]
    if nodes.ndim != 2 or elements.ndim != 2 or elements.shape[1] not in (3, 4):
        return None
    make = TriangleMesh if elements.shape[1] == 3 else TetMesh
    return make(nodes, elements, tags, sets)
