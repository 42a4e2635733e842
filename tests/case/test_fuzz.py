"""Fuzzing (issue 7, part 2): the case parser, the mesh readers and the engine.

The only acceptable outcomes are a result or the module's own error with a one-line message:

- ``slipstep.case.parse_case`` (random TOML documents, mutations of every shipped and
  catalogue case, random ``--set`` overrides): a Case or a ``CaseError``;
- ``slipstep.mesh.triangle_files.read_mesh`` (random, truncated and mutated ``.msh`` / ``.xdmf`` / ``.h5``
  bytes): a Mesh or a ``MeshError``;
- ``slipstep._engine.solve`` (random small meshes, supports, loads and contact pairs, many of
  them degenerate): a result with no NaN in it, or a ``SlipstepError`` (the contract's classes,
  slipstep.errors; not ``InternalError``, which is a bug).

Separately, scenes known to be solvable (supported, no initial penetration, finite values,
loads below collapse) must complete, in equilibrium recomputed from their arrays: there an
error is a failure.

Never another exception type, a Rust panic (pyo3 raises ``pyo3_runtime.PanicException``, a
``BaseException``), a crash of the process, or a hang (a time limit per example).

``make test`` runs a bounded, derandomized number of examples (a few seconds per target);
``make fuzz`` runs ``SLIPSTEP_FUZZ_EXAMPLES`` random examples per target (default 2000 there).
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest
from conftest import time_limit
from physics import EQUILIBRIUM_TOL, worst_equilibrium

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from slipstep.case import CaseError, parse_case  # noqa: E402
from slipstep.errors import SlipstepError  # noqa: E402
from slipstep.mesh import MeshError  # noqa: E402
from slipstep.mesh.triangle_files import read_mesh  # noqa: E402

# meshio parses damaged inline XML data with numpy.fromstring, which warns about it
pytestmark = pytest.mark.filterwarnings(
    "ignore:string or file could not be read:DeprecationWarning"
)

ROOT = Path(__file__).resolve().parents[2]
CATALOGUE = ROOT / "tests" / "case" / "bad_inputs"

#: examples per target: a fixed, derandomized budget in `make test`; SLIPSTEP_FUZZ_EXAMPLES
#: (make fuzz) switches to that many random examples.
LONG = int(os.environ.get("SLIPSTEP_FUZZ_EXAMPLES", "0") or 0)


def budget(n: int):
    """Hypothesis settings: ``n`` examples in `make test` (derandomized, so the run is the
    same every time), LONG random ones under `make fuzz`."""
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
            HealthCheck.function_scoped_fixture,
        ],
    )


def assert_one_line(exc: BaseException) -> None:
    msg = str(exc)
    assert msg.strip(), f"{type(exc).__name__} with an empty message"
    assert "\n" not in msg and "\r" not in msg, f"multi-line message: {msg!r}"


# =========================================================================== TOML documents
def toml_key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)


def toml_value(v) -> str:
    """A TOML literal (inline tables and arrays only, so any nesting is one line)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{toml_key(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    return v.isoformat()  # dates and times


def toml_document(doc: dict) -> str:
    return "".join(f"{toml_key(k)} = {toml_value(v)}\n" for k, v in doc.items())


#: names the schema uses, so that random documents get past the first unknown-key check
VOCABULARY = [
    "case",
    "analysis",
    "load",
    "output",
    "solver",
    "body",
    "bc",
    "point_load",
    "contact",
    "name",
    "mesh",
    "material",
    "generator",
    "block",
    "quarter_cylinder",
    "quarter_annulus",
    "file",
    "E",
    "nu",
    "Sy",
    "H",
    "width",
    "height",
    "nx",
    "ny",
    "h",
    "x0",
    "y0",
    "R",
    "h_contact",
    "contact_zone",
    "h_max",
    "growth",
    "edge",
    "nodes",
    "fix",
    "symmetry",
    "pressure",
    "traction",
    "kind",
    "rigid_line",
    "node_to_node",
    "body_a",
    "body_b",
    "edge_a",
    "edge_b",
    "mu",
    "normal",
    "point",
    "tolerance",
    "x_min",
    "x_max",
    "snapshots",
    "events",
    "figures",
    "xdmf",
    "tie_tol",
    "max_events",
    "plane",
    "thickness",
    "strain",
    "stress",
    "P",
    "at",
    "force",
    "top",
    "bottom",
    "left",
    "right",
    "arc",
    "x",
    "y",
    "scale",
    "edge_file",
    # load paths (issue 13) and contact geometry (issue 14)
    "stage",
    "factors",
    "displacement",
    "motion",
    "node_to_segment",
    "rigid_circle",
    "rigid_polyline",
    "centre",
    "radius",
    "side",
    "points",
    "focus",
    "half_cylinder",
]

names = st.sampled_from(VOCABULARY) | st.text(min_size=1, max_size=8)
scalars = (
    st.integers(min_value=-(10**20), max_value=10**20)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.sampled_from([0.0, -0.0, 0.5, 0.499, 1.0, 1e-300, 1e300, -1.0, 2, 0])
    | st.booleans()
    | st.sampled_from(VOCABULARY)
    | st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=12)
    | st.dates()
)
values = st.recursive(
    scalars,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(names, inner, max_size=5),
    max_leaves=12,
)


def shipped_texts() -> list[tuple[str, str]]:
    out = []
    for p in sorted([*(ROOT / "cases").glob("*.toml"), *CATALOGUE.glob("*.toml")]):
        try:
            out.append((p.name, p.read_text(encoding="utf-8")))
        except UnicodeDecodeError:
            pass
    return out


SHIPPED = shipped_texts()
PARSEABLE = []
for _name, _text in SHIPPED:
    with contextlib.suppress(tomllib.TOMLDecodeError):
        PARSEABLE.append((_name, tomllib.loads(_text)))


def check_parse(text: str, overrides=()) -> None:
    """parse_case: a Case, or a one-line CaseError naming the source."""
    try:
        with time_limit(10, "parse_case"):
            parse_case(text, source="fuzz.toml", base_dir=ROOT, overrides=overrides)
    except CaseError as exc:
        assert_one_line(exc)
        assert str(exc).startswith(("fuzz.toml", "--set")), str(exc)


@budget(300)
@given(
    doc=st.dictionaries(names, values, max_size=8),
    overrides=st.lists(st.text(max_size=30), max_size=2),
)
def test_fuzz_case_parser_random_documents(doc, overrides):
    check_parse(toml_document(doc), overrides)


@budget(300)
@given(data=st.data())
def test_fuzz_case_parser_mutated_shipped_cases(data):
    """Text mutations of every case in cases/ and tests/case/bad_inputs/: a line dropped, doubled,
    truncated, or a value replaced by a random TOML literal."""
    name, text = data.draw(st.sampled_from(SHIPPED), label="case")
    lines = text.splitlines()
    for _ in range(data.draw(st.integers(1, 3), label="n_mutations")):
        if not lines:
            break
        i = data.draw(st.integers(0, len(lines) - 1), label="line")
        op = data.draw(st.sampled_from(["drop", "double", "cut", "value", "insert"]))
        if op == "drop":
            del lines[i]
        elif op == "double":
            lines.insert(i, lines[i])
        elif op == "cut":
            lines[i] = lines[i][: data.draw(st.integers(0, max(len(lines[i]) - 1, 0)))]
        elif op == "value" and "=" in lines[i]:
            key = lines[i].split("=", 1)[0]
            lines[i] = f"{key}= {toml_value(data.draw(values, label='value'))}"
        else:
            key = data.draw(names, label="key")
            lines.insert(i, f"{toml_key(key)} = {toml_value(data.draw(values, label='value'))}")
    check_parse("\n".join(lines) + "\n")


def key_paths(doc, prefix=()):
    """Every (path, container) of a parsed document, for structured mutations."""
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield prefix + (k,)
            yield from key_paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield prefix + (i,)
            yield from key_paths(v, prefix + (i,))


@budget(300)
@given(data=st.data())
def test_fuzz_case_parser_structured_mutations(data):
    """A parsed shipped case with one value replaced, one key deleted or one key added, then
    serialized again; plus random well-formed --set overrides of real keys."""
    import copy

    name, doc = data.draw(st.sampled_from(PARSEABLE), label="case")
    doc = copy.deepcopy(doc)
    paths = list(key_paths(doc))
    for _ in range(data.draw(st.integers(1, 3), label="n_mutations")):
        if not paths:
            break
        path = data.draw(st.sampled_from(paths), label="path")
        parent = doc
        for p in path[:-1]:
            parent = parent[p]
        op = data.draw(st.sampled_from(["replace", "delete", "add"]), label="op")
        if op == "replace":
            parent[path[-1]] = data.draw(values, label="value")
        elif op == "delete":
            del parent[path[-1]]
        elif isinstance(parent, dict):
            parent[data.draw(names, label="new key")] = data.draw(values, label="value")
        paths = list(key_paths(doc))
    dotted = [".".join(str(p) for p in path) for path in paths]
    overrides = [
        f"{data.draw(st.sampled_from(dotted or ['x']))}={toml_value(data.draw(values))}"
        for _ in range(data.draw(st.integers(0, 2), label="n_overrides"))
    ]
    check_parse(toml_document(doc), overrides)


# =========================================================================== mesh files
def _good_mesh_files(folder: Path) -> dict[str, bytes]:
    """A small mesh in every format read_mesh takes: gmsh 2.2 ASCII, 4.1 ASCII and binary
    (written by gmsh itself), XDMF with inline XML data and XDMF + HDF5."""
    import meshio

    from slipstep.mesh.gmsh_api import gmsh_session

    files = {"v22.msh": (CATALOGUE / "mesh_unknown_node_set.msh").read_bytes()}
    (folder / "v22.msh").write_bytes(files["v22.msh"])
    with gmsh_session() as gmsh:
        gmsh.model.add("square")
        geo = gmsh.model.geo
        p = [geo.addPoint(x, y, 0.0) for x, y in [(0, 0), (1, 0), (1, 1), (0, 1)]]
        lines = [geo.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
        surface = geo.addPlaneSurface([geo.addCurveLoop(lines)])
        geo.synchronize()
        gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [lines[0]]), "bottom")
        gmsh.model.setPhysicalName(0, gmsh.model.addPhysicalGroup(0, [p[0]]), "corner")
        gmsh.model.addPhysicalGroup(2, [surface])
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
        gmsh.model.mesh.generate(2)
        gmsh.write(str(folder / "v41.msh"))
        gmsh.option.setNumber("Mesh.Binary", 1)
        gmsh.write(str(folder / "v41b.msh"))
    pts = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], float)
    mesh = meshio.Mesh(
        pts,
        [
            ("triangle", np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])),
            ("line", np.array([[0, 1], [1, 2], [5, 4], [4, 3]])),
        ],
        cell_data={"tags": [np.zeros(4, int), np.array([1, 1, 2, 2])]},
    )
    meshio.xdmf.write(folder / "xml.xdmf", mesh, data_format="XML")
    meshio.xdmf.write(folder / "hdf.xdmf", mesh)
    for name in ("v41.msh", "v41b.msh", "xml.xdmf", "hdf.xdmf", "hdf.h5"):
        files[name] = (folder / name).read_bytes()
    return files


@pytest.fixture(scope="module")
def good_meshes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("good_meshes")
    files = _good_mesh_files(folder)
    for name in files:  # they are read correctly before they are mutated
        if not name.endswith(".h5"):
            read_mesh(folder / name)
    return files


TOKENS = [
    b"nan",
    b"inf",
    b"-1",
    b"0",
    b"1e308",
    b"99999",
    b"-99999",
    b"3.5",
    b" ",
    b"\n",
    b"$EndNodes",
    b"$Elements",
    b"<",
    b">",
    b'"',
    b"/>",
    b"2",
    b"3",
    b"\x00",
    b"\xff",
]


@st.composite
def mutated(draw, data: bytes) -> bytes:
    """``data`` with 1..4 byte-level mutations: truncation, a byte changed, a token inserted,
    a span deleted, a number replaced."""
    b = bytearray(data)
    for _ in range(draw(st.integers(1, 4))):
        if not b:
            break
        i = draw(st.integers(0, len(b) - 1))
        op = draw(st.sampled_from(["truncate", "byte", "token", "delete", "number"]))
        if op == "truncate":
            del b[i:]
        elif op == "byte":
            b[i] = draw(st.integers(0, 255))
        elif op == "token":
            b[i:i] = draw(st.sampled_from(TOKENS))
        elif op == "delete":
            del b[i : i + draw(st.integers(1, 40))]
        else:
            m = re.compile(rb"-?\d+(\.\d+)?(e[-+]?\d+)?").search(bytes(b), i)
            if m:
                b[m.start() : m.end()] = draw(st.sampled_from(TOKENS[:8]))
    return bytes(b)


def check_read(path: Path, seconds: float = 60) -> None:
    """read_mesh: a Mesh (finite, counter-clockwise), or a one-line MeshError."""
    try:
        with time_limit(seconds, f"read_mesh({path.name})"):
            mesh = read_mesh(path)
    except MeshError as exc:
        assert_one_line(exc)
        return
    assert np.isfinite(mesh.nodes).all()
    assert len(mesh.triangles) and mesh.triangles.min() >= 0
    assert mesh.triangles.max() < len(mesh.nodes)


@budget(60)
@given(data=st.data())
def test_fuzz_msh_reader(data, good_meshes, tmp_path):
    """Damaged gmsh files (2.2 and 4.1 ASCII; binary too under make fuzz, where gmsh may take
    seconds on a corrupted count).  gmsh crashes on some of them: read_mesh reads .msh files
    in a child process, so that becomes a MeshError."""
    names = ["v22.msh", "v41.msh"] + (["v41b.msh"] if LONG else [])
    name = data.draw(st.sampled_from(names), label="file")
    path = tmp_path / "fuzz.msh"
    path.write_bytes(data.draw(mutated(good_meshes[name]), label="bytes"))
    check_read(path)


@budget(150)
@given(data=st.data())
def test_fuzz_xdmf_reader(data, good_meshes, tmp_path):
    """Damaged XDMF (inline XML data), and XDMF + HDF5 with either file damaged."""
    if data.draw(st.booleans(), label="hdf5"):
        xdmf, h5 = good_meshes["hdf.xdmf"], good_meshes["hdf.h5"]
        if data.draw(st.booleans(), label="damage the .h5"):
            h5 = data.draw(mutated(h5), label="h5 bytes")
        else:
            xdmf = data.draw(mutated(xdmf), label="xdmf bytes")
        (tmp_path / "hdf.h5").write_bytes(h5)
        path = tmp_path / "hdf.xdmf"
        path.write_bytes(xdmf)
    else:
        path = tmp_path / "xml.xdmf"
        path.write_bytes(data.draw(mutated(good_meshes["xml.xdmf"]), label="bytes"))
    check_read(path)


@budget(100)
@given(raw=st.binary(max_size=400), suffix=st.sampled_from([".msh", ".xdmf"]))
def test_fuzz_mesh_reader_random_bytes(raw, suffix, tmp_path):
    path = tmp_path / f"random{suffix}"
    path.write_bytes(raw)
    check_read(path)


# =========================================================================== the engine
def _grid(nx: int, ny: int, jitter: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    xs, ys = np.meshgrid(np.linspace(0.0, 1.0, nx + 1), np.linspace(0.0, 1.0, ny + 1))
    nodes = np.column_stack([xs.ravel(), ys.ravel()]) + jitter / max(nx, ny)
    tris = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            tris += [[a, a + 1, a + nx + 2], [a, a + nx + 2, a + nx + 1]]
    return nodes, np.asarray(tris, dtype=np.int64)


SPECIAL = [np.nan, np.inf, -np.inf, 0.0, -0.0, -1.0, 1e300, 1e-300, 5e-324, 1e15]


@st.composite
def engine_models(draw, solvable: bool = False) -> dict:
    """A block on a rigid flat or on a second block (node-to-node), with random size, mesh
    distortion, supports, loads, gaps (ties included), friction and plasticity; one in three
    gets one value corrupted (NaN, inf, 0, huge, tiny, an index out of range).

    ``solvable``: only scenes known to have a solution, which the engine must reach: elements
    kept positive (mild distortion), a pair that starts closed (the first gap 0: the contact
    supports the block from the start), the block's left side held in x (no rigid translation
    or rotation left), loads that press it on its support (shear and point loads included:
    the held side takes the tangential part), an elastic or hardening material (Sy >= 2: at
    most 5 x its first yield under the largest load; nu <= 0.45: at 0.49 plane strain the
    engine stops hardening scenes at a "limit load" of stiffness 0; H >= 10 % of E: no collapse, and the tangent stays far above the engine's limit-load stop at 1e-3 of
    the initial stiffness; in plane strain: see the plane-stress reproducer below), the
    default solver options (drift control on: see the reproducer without it), no bound on the
    number of increments, nothing corrupted."""
    choose = lambda every, solvable_ones, label: draw(
        st.sampled_from(solvable_ones if solvable else every), label=label
    )
    nx, ny = draw(st.integers(1, 5), label="nx"), draw(st.integers(1, 4), label="ny")
    jitter = choose([0.0, 0.0, 0.05, 0.3, 3.0], [0.0, 0.0, 0.05], "jitter")
    seed = draw(st.integers(0, 2**32 - 1), label="seed")
    rng = np.random.default_rng(seed)
    nodes, tris = _grid(nx, ny, jitter * rng.standard_normal(((nx + 1) * (ny + 1), 2)))
    bottom, top = np.arange(nx + 1), np.arange(ny * (nx + 1), (nx + 1) * (ny + 1))
    left = np.arange(ny + 1) * (nx + 1)
    gap = draw(st.sampled_from(["zero", "equal", "random", "mixed"]), label="gaps")
    g = {
        "zero": np.zeros(nx + 1),
        "equal": np.full(nx + 1, 0.01),
        "random": rng.uniform(0, 0.05, nx + 1),
        "mixed": np.where(rng.random(nx + 1) < 0.5, 0.0, rng.uniform(0, 0.05, nx + 1)),
    }[gap]
    if solvable:
        g[0] = 0.0
    fixed = []
    if draw(st.booleans(), label="on a second block"):
        lower, ltris = _grid(nx, 1, np.zeros(((nx + 1) * 2, 2)))
        lower[:, 1] -= 1.0
        off = len(lower)
        nodes, tris = np.vstack([lower, nodes]), np.vstack([ltris, tris + off])
        node_a, node_b = bottom + off, np.arange(nx + 1) + nx + 1
        top, left = top + off, left + off
        nodes[node_a] = nodes[node_b] + np.column_stack([np.zeros(nx + 1), g])
        fixed += [2 * k + c for k in range(nx + 1) for c in (0, 1)]
    else:
        node_a, node_b = bottom, np.full(nx + 1, -1)
        nodes[node_a, 1] = g
    n = len(nodes)
    if solvable:
        fixed += [2 * int(k) for k in left]
    elif draw(st.booleans(), label="symmetry at x = 0"):
        fixed += [2 * int(k) for k in np.flatnonzero(np.abs(nodes[:, 0]) < 1e-12)]
    load = np.zeros(2 * n)
    kind = choose(
        ["press", "press+shear", "point", "pull"], ["press", "press+shear", "point"], "load"
    )
    q = choose([1.0, 10.0, 1e3], [1.0, 10.0], "load size")
    if kind == "press":
        load[2 * top + 1] = -q
    elif kind == "press+shear":
        load[2 * top + 1] = -q
        load[2 * top] = q * draw(st.sampled_from([-2.0, -0.3, 0.1, 0.5, 2.0]))
    elif kind == "point" and solvable:  # downwards on a top node
        load[2 * int(draw(st.sampled_from(top))) + 1] = -q
    elif kind == "point":
        load[draw(st.integers(0, 2 * n - 1))] = q * draw(st.sampled_from([-1.0, 1.0]))
    else:
        load[2 * top + 1] = q
    material = {
        "E": 1000.0,
        "nu": choose([0.0, 0.3, 0.45, 0.49, 0.499, -0.5], [0.0, 0.3, 0.45, 0.49], "nu"),
    }
    if draw(st.booleans(), label="plastic") and not (solvable and material["nu"] > 0.45):
        material["Sy"] = choose([0.5, 2.0, 20.0], [2.0, 20.0], "Sy")
        material["H"] = choose([0.0, 10.0, 1000.0], [100.0, 1000.0], "H")
    mu = draw(st.sampled_from([0.0, 0.1, 0.35, 1.0, 2.0]), label="mu")
    output = draw(st.sampled_from(["events", "fractions"]))
    plane = draw(st.sampled_from(["strain", "stress"]), label="plane")
    model = {
        "nodes": nodes,
        "triangles": tris,
        "element_material": np.zeros(len(tris), dtype=np.int64),
        "materials": [material],
        "plane": plane,
        "thickness": 1.0,
        "fixed_dofs": np.unique(np.asarray(fixed, dtype=np.int64)),
        "load": load,
        "pairs": {
            "node_a": node_a.astype(np.int64),
            "node_b": node_b.astype(np.int64),
            "normal": np.tile([0.0, 1.0], (nx + 1, 1)),
            "gap": g.astype(np.float64),
            "mu": np.full(nx + 1, mu),
        },
        "options": {
            "output": output,
            "fractions": np.array([0.25, 0.5, 1.0]),
            "tie_tol": draw(st.sampled_from([1e-9, 0.0, 1e-3])),
            "drift_control": draw(st.booleans()),
        },
    }
    if solvable:  # the default solver; loaded up to 40 x first yield: increments may be many
        del model["options"]["drift_control"]
        model["options"].update(max_events=10**6, limit_stiffness=0.0)
    elif draw(st.integers(0, 2), label="corrupt?") == 0:
        corrupt(model, draw, rng)
    return model


def corrupt(model: dict, draw, rng) -> None:
    """One value of the model replaced by something degenerate."""
    v = draw(st.sampled_from(SPECIAL), label="special")
    bad_index = draw(st.sampled_from([-1, -7, 10**6, 2**62, len(model["nodes"])]))
    field = draw(
        st.sampled_from(
            [
                "node",
                "load",
                "normal",
                "gap",
                "mu",
                "E",
                "nu",
                "Sy",
                "H",
                "thickness",
                "triangle",
                "fixed",
                "node_a",
                "node_b",
                "element_material",
                "duplicate pair",
                "no triangles",
                "clockwise",
                "collapsed node",
                "fractions",
                "tie_tol",
            ]
        ),
        label="corrupt",
    )
    pairs = model["pairs"]
    pick = lambda a: int(rng.integers(len(a)))  # noqa: E731
    if field == "node":
        model["nodes"][pick(model["nodes"]), pick([0, 1])] = v
    elif field == "load":
        model["load"][pick(model["load"])] = v
    elif field == "normal":
        pairs["normal"][pick(pairs["normal"]), pick([0, 1])] = v
    elif field in ("gap", "mu"):
        pairs[field][pick(pairs[field])] = v
    elif field in ("E", "nu", "Sy", "H"):
        model["materials"][0][field] = float(v)
    elif field == "thickness":
        model["thickness"] = float(v)
    elif field == "triangle":
        model["triangles"][pick(model["triangles"]), pick([0, 1, 2])] = bad_index
    elif field == "fixed":
        model["fixed_dofs"] = np.append(model["fixed_dofs"], bad_index).astype(np.int64)
    elif field in ("node_a", "node_b"):
        pairs[field][pick(pairs[field])] = bad_index
    elif field == "element_material":
        model["element_material"][pick(model["element_material"])] = abs(bad_index)
    elif field == "duplicate pair":
        for k in pairs:
            pairs[k] = np.concatenate([pairs[k], pairs[k][:1]])
    elif field == "no triangles":
        model["triangles"] = model["triangles"][:0]
        model["element_material"] = model["element_material"][:0]
    elif field == "clockwise":
        model["triangles"] = model["triangles"][:, ::-1].copy()
    elif field == "collapsed node":  # two nodes of a triangle at one point
        t = model["triangles"][0]
        model["nodes"][t[1]] = model["nodes"][t[0]]
    elif field == "fractions":
        model["options"]["output"] = "fractions"
        model["options"]["fractions"] = np.array([v, 0.5])
    else:
        model["options"]["tie_tol"] = float(v)


def assert_finite_result(result: dict) -> None:
    """No NaN or inf where the engine promises numbers (closure_fraction is NaN for a pair that
    never closed and predicted_closure inf for one that would not: documented)."""
    for i, snap in enumerate(result["snapshots"]):
        for key in ("u", "stress", "plastic_strain", "lambda_n", "lambda_t", "gap", "rtd"):
            assert np.isfinite(snap[key]).all(), f"snapshot {i}: {key} is not finite"
        assert np.isfinite(snap["load_fraction"])
    for key in ("load_fraction", "scale", "residual", "normal_force", "drift"):
        assert np.isfinite(result["steps"][key]).all(), f"steps.{key} is not finite"
    assert np.isfinite(result["events"]["load_fraction"]).all()
    assert math.isfinite(result["max_equilibrium_residual"])
    assert math.isfinite(result["max_drift"])
    assert not np.isinf(result["closure_fraction"]).any()
    assert not np.isnan(result["predicted_closure"]).any()


def check_solve(model: dict) -> dict | None:
    from slipstep import _engine

    try:
        with time_limit(30, "the engine"):
            result = _engine.solve(model, False)
    except SlipstepError as exc:
        assert_one_line(exc)
        return None
    stop = result["stop"]["kind"]
    assert stop != "interrupted", "the engine was stopped by the time limit (a hang?)"
    assert_finite_result(result)
    steps = result["steps"]
    assert np.all(np.diff(steps["load_fraction"]) >= 0), "the load fraction went back"
    if stop == "completed":
        assert steps["load_fraction"][-1] == 1.0
    return result


@budget(1500)
@given(model=engine_models())
def test_fuzz_engine(model):
    check_solve(model)


@budget(200)
@given(model=engine_models(solvable=True))
def test_fuzz_engine_solvable_scenes_complete_in_equilibrium(model):
    """Scenes known to have a solution (engine_models(solvable=True)) must complete: no error
    is acceptable here, and every snapshot is in equilibrium recomputed from its arrays
    (tests/physics.py, EQUILIBRIUM_TOL: the engine's contract), with λ_n >= 0 and Coulomb's
    |λ_t| <= μ λ_n to 1e-9 of the snapshot's largest λ_n (round-off of the contact forces,
    measured up to 2e-11 of it), and no penetration (gap >= -1e-9 of the block's size, 1:
    round-off of u)."""
    from slipstep import _engine

    with time_limit(30, "the engine"):
        result = _engine.solve(model, False)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert_finite_result(result)
    worst, k, f = worst_equilibrium(model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
    mu = model["pairs"]["mu"]
    for snap in result["snapshots"]:
        ln, lt = np.asarray(snap["lambda_n"]), np.asarray(snap["lambda_t"])
        round_off = 1e-9 * max(float(ln.max()), 1e-300)
        assert (ln >= -round_off).all() and (np.abs(lt) <= mu * ln + round_off).all()
        assert (np.asarray(snap["gap"]) >= -1e-9).all()


def test_a_hardening_block_in_plane_stress_completes_within_the_automatic_bound():
    """Found by the solvable fuzz: one square cell (two triangles) of a hardening material
    (Sy = 0.5, H = E) pressed by 10 on a rigid flat, its left side held in x, one corner
    closed and the other 0.01 off.  As the open corner comes down, each equilibrium correction
    unloaded the plastic elements a little along D_ep and the next increment scaled their
    stresses back out onto the surface, an out-of-balance force the next correction undid: in
    plane stress (a radial scaling) that drift never decayed, the corner hovered 1e-6 off the
    flat and the run stopped at the automatic bound (1250 increments) at f = 0.17 (30 867
    increments to the end).  Now 144 in plane stress, 117 in plane strain.  Both must
    complete in equilibrium (recomputed from the arrays, the engine's contract) with the
    corner closed: elastically it closes at f = 0.25 (the gap 0.01 against a deformation of
    order load/E = 0.02), and plastic flow only softens the cell."""
    from slipstep import _engine

    model = {
        "nodes": np.array([[0.0, 0.0], [1.0, 0.01], [0.0, 1.0], [1.0, 1.0]]),
        "triangles": np.array([[0, 1, 3], [0, 3, 2]]),
        "element_material": np.zeros(2, int),
        "materials": [{"E": 1000.0, "nu": 0.0, "Sy": 0.5, "H": 1000.0}],
        "thickness": 1.0,
        "fixed_dofs": np.array([0, 4]),
        "load": np.array([0, 0, 0, 0, 0, -10.0, 0, -10.0]),
        "pairs": {
            "node_a": np.array([0, 1]),
            "node_b": np.array([-1, -1]),
            "normal": np.array([[0.0, 1.0], [0.0, 1.0]]),
            "gap": np.array([0.0, 0.01]),
            "mu": np.zeros(2),
        },
    }
    for plane in ("strain", "stress"):
        scene = {**model, "plane": plane}
        result = _engine.solve(scene, False)
        assert result["stop"]["kind"] == "completed", (plane, result["stop"]["message"])
        worst, k, f = worst_equilibrium(scene, result["snapshots"])
        assert worst <= EQUILIBRIUM_TOL, (plane, k, f, worst)
        assert (result["snapshots"][-1]["status"] > 0).all(), plane


def test_a_hardening_block_on_a_block_without_drift_control_completes():
    """Found by the solvable fuzz: a 3 x 1 hardening block (plane strain, nu = 0.49, Sy = 20,
    H = 100, mu = 1) on a fixed block, node to node, one pair closed and three 0.01 off,
    pressed by 10 and sheared by 20 per top node, its left side held in x, snapshots at
    0.25, 0.5, 1.  Pair 1 closes at f = 0.248 into stick, and then would both separate and
    slip: one switch at a time cycles closed/open, and the rate problem that settles such a
    cycle found no set, since it held pair 0 (slipping on one side of its cone) to the other
    side too over the whole remaining load; the last resort froze pair 1 closed and it ended
    the increment in tension (without drift control at the snapshot f = 0.25: an error; with
    it the run went on past two freezes).  At the increment's start only the side a pair is
    on constrains it: pair 1 slips, and both runs complete with no pair frozen, every
    snapshot in equilibrium (recomputed from the arrays) and within Coulomb's cone."""
    from slipstep import _engine

    x = np.tile(np.arange(4) / 3.0, 4)
    y = np.repeat([-1.0, 0.0, 0.0, 1.0], 4)
    y[9:12] = 0.01
    tris = [[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6]]
    load = np.zeros(32)
    load[24::2], load[25::2] = 20.0, -10.0
    model = {
        "nodes": np.column_stack([x, y]),
        "triangles": np.array(tris + [[a + 8, b + 8, c + 8] for a, b, c in tris]),
        "element_material": np.zeros(12, int),
        "plane": "strain",
        "thickness": 1.0,
        "materials": [{"E": 1000.0, "nu": 0.49, "Sy": 20.0, "H": 100.0}],
        "fixed_dofs": np.array([0, 1, 2, 3, 4, 5, 6, 7, 16, 24]),
        "load": load,
        "pairs": {
            "node_a": np.arange(8, 12),
            "node_b": np.arange(4, 8),
            "normal": np.tile([0.0, 1.0], (4, 1)),
            "gap": np.array([0.0, 0.01, 0.01, 0.01]),
            "mu": np.ones(4),
        },
        "options": {"output": "fractions", "fractions": np.array([0.25, 0.5, 1.0])},
    }
    for drift_control in (True, False):
        model["options"]["drift_control"] = drift_control
        result = _engine.solve(model, False)
        assert result["stop"]["kind"] == "completed", drift_control
        assert "frozen" not in list(result["events"]["kind"]), drift_control
        worst, k, f = worst_equilibrium(model, result["snapshots"])
        assert worst <= EQUILIBRIUM_TOL, (drift_control, k, f, worst)
        for snap in result["snapshots"]:  # round-off of the contact forces: as the fuzz above
            ln, lt = snap["lambda_n"], snap["lambda_t"]
            round_off = 1e-9 * ln.max()
            assert (ln >= -round_off).all() and (np.abs(lt) <= ln + round_off).all()


def test_a_hardening_block_held_in_x_by_friction_alone_completes_without_drift_control():
    """A 4 x 1 block with slightly distorted nodes (nu = 0.499 plane strain, Sy = 0.5,
    H = 10, mu = 1) resting on a rigid flat at gap 0, held by nothing else, pressed by 1 per top
    node, drift control off: every pair slips at t = 0, where the rate problem sets which
    sticks.  Its corner then closes and separates at zero length, a cycle the rate problem used
    to find no set for (it held the pairs slipping along one side of their cones to the other
    side over the whole remaining load), so the corner was frozen and penetrated
    (IllPosedError at t = 0.29; with snapshots at 0.25 at that fraction).  The scene is well
    posed (a hardening body on friction, a load friction holds); it must complete, nothing
    frozen, in equilibrium (recomputed from the arrays), within Coulomb's cone, no penetration
    (round-off as in the fuzz above)."""
    from slipstep import _engine

    nodes = np.array(
        [
            [0.014190750494522187, 0.0],
            [0.2585063312322589, 0.0],
            [0.506402736691352, 0.0],
            [0.7664579398207183, 0.0],
            [1.004041309993055, 0.0],
            [0.007219257651766952, 0.9937439460877943],
            [0.24395134957696288, 0.9987008063836676],
            [0.496070567142536, 0.9819696511888898],
            [0.7567461263360208, 0.990424623738192],
            [1.002678452093274, 1.00895647093158],
        ]
    )
    model = {
        "nodes": nodes,
        "triangles": _grid(4, 1, np.zeros((10, 2)))[1],
        "element_material": np.zeros(8, int),
        "plane": "strain",
        "thickness": 1.0,
        "materials": [{"E": 1000.0, "nu": 0.499, "Sy": 0.5, "H": 10.0}],
        "fixed_dofs": np.zeros(0, int),
        "load": np.r_[np.zeros(10), [0.0, -1.0] * 5],
        "pairs": {
            "node_a": np.arange(5),
            "node_b": np.full(5, -1),
            "normal": np.tile([0.0, 1.0], (5, 1)),
            "gap": np.zeros(5),
            "mu": np.ones(5),
        },
        "options": {"drift_control": False, "tie_tol": 1e-3},
    }
    for output in ("events", "fractions"):
        model["options"].update(output=output, fractions=np.array([0.25, 0.5, 1.0]))
        result = _engine.solve(model, False)
        assert result["stop"]["kind"] == "completed", (output, result["stop"]["message"])
        assert "frozen" not in list(result["events"]["kind"]), output
        worst, k, f = worst_equilibrium(model, result["snapshots"])
        assert worst <= EQUILIBRIUM_TOL, (output, k, f, worst)
        for snap in result["snapshots"]:
            ln, lt = snap["lambda_n"], snap["lambda_t"]
            round_off = 1e-9 * ln.max()
            assert (ln >= -round_off).all() and (np.abs(lt) <= ln + round_off).all()
            assert (snap["gap"] >= -1e-9).all()


def test_a_separation_taken_with_a_tie_is_rebalanced():
    """A 4 x 1 hardening block (plane stress, Sy = 2, H = 100, mu = 2) on a fixed block, node
    to node, one pair closed and four off, pressed by 10 per top node, drift control off, ties
    within 1e-3: at f = 0.8585 the corner pair's separation comes with its slips (scales 1e-3
    apart) and was applied while the pair still carried lambda_n > 0; that force vanished
    without a correction (an equilibrium residual of 1.6e-4: EquilibriumError).  The force a
    switch drops is rebalanced now: the run completes, every snapshot in equilibrium
    (recomputed from the arrays)."""
    from slipstep import _engine

    x, y = np.tile(np.arange(5) / 4.0, 4), np.repeat([-1.0, 0.0, 0.0, 1.0], 5)
    y[11:15] = [0.00307501, 0.02755342, 0.00562164, 0.03777938]
    tris = _grid(4, 1, np.zeros((10, 2)))[1]
    load = np.zeros(40)
    load[31::2] = -10.0
    model = {
        "nodes": np.column_stack([x, y]),
        "triangles": np.vstack([tris, tris + 10]),
        "element_material": np.zeros(16, int),
        "plane": "stress",
        "thickness": 1.0,
        "materials": [{"E": 1000.0, "nu": 0.3, "Sy": 2.0, "H": 100.0}],
        "fixed_dofs": np.array([0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 20, 30]),
        "load": load,
        "pairs": {
            "node_a": np.arange(10, 15),
            "node_b": np.arange(5, 10),
            "normal": np.tile([0.0, 1.0], (5, 1)),
            "gap": y[10:15] - y[5:10],
            "mu": np.full(5, 2.0),
        },
        "options": {
            "output": "fractions",
            "fractions": np.array([0.25, 0.5, 1.0]),
            "tie_tol": 1e-3,
            "drift_control": False,
        },
    }
    result = _engine.solve(model, False)
    assert result["stop"]["kind"] == "completed", result["stop"]["message"]
    worst, k, f = worst_equilibrium(model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)


def test_a_hardening_block_reaches_no_limit_load():
    """Found by the solvable fuzz: a 2 x 2 block with H = E (plane strain, nu = 0.45,
    Sy = 2, mu = 2) pressed by 10 per top node on a rigid flat, its left side held in x, the
    bottom corner (0, 0) closed, the others 0.021 and 0.023 off: when the right corner closes
    and slips at once (f = 0.1347) the engine stops with "limit load reached ... the current
    stiffness fell to 0.0e0 of the initial one (a plastic mechanism)"; a hardening material
    has no limit load, and with limit_stiffness = 0 the run completes (101 increments).  The
    stop measured the trial taken right after the close + slip, with every element on its
    plastic tangent and pair 2 slipping: inadmissible at once (pair 2 sticks at zero length),
    no response of the block, and its remaining load did no positive work.  Trials the load
    does not advance along are not measured now: the run completes, in equilibrium
    (recomputed from the arrays)."""
    from slipstep import _engine

    x, y = np.meshgrid([0.0, 0.5, 1.0], [0.0, 0.5, 1.0])
    nodes = np.column_stack([x.ravel(), y.ravel()])
    nodes[1:3, 1] = [0.02087828499121349, 0.02327785993001651]
    model = {
        "nodes": nodes,
        "triangles": _grid(2, 2, np.zeros((9, 2)))[1],
        "element_material": np.zeros(8, int),
        "plane": "strain",
        "thickness": 1.0,
        "materials": [{"E": 1000.0, "nu": 0.45, "Sy": 2.0, "H": 1000.0}],
        "fixed_dofs": np.array([0, 6, 12]),
        "load": np.r_[np.zeros(12), [0, -10.0] * 3],
        "pairs": {
            "node_a": np.arange(3),
            "node_b": np.full(3, -1),
            "normal": np.tile([0.0, 1.0], (3, 1)),
            "gap": nodes[:3, 1].copy(),
            "mu": np.full(3, 2.0),
        },
    }
    result = _engine.solve(model, False)
    assert result["stop"]["kind"] == "completed", result["stop"]["message"]
    worst, k, f = worst_equilibrium(model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)


@budget(1000)
@given(
    n=st.integers(3, 12),
    m=st.integers(1, 12),
    seed=st.integers(0, 2**32 - 1),
    n_pairs=st.integers(0, 6),
)
def test_fuzz_engine_random_triangle_soup(n, m, seed, n_pairs):
    """Nodes anywhere, triangles of random nodes (overlapping, inverted, degenerate, isolated),
    random supports, loads and pairs: nearly always an error, never a crash."""
    rng = np.random.default_rng(seed)
    nodes = rng.uniform(-1, 1, (n, 2))
    tris = rng.integers(0, n, (m, 3)).astype(np.int64)
    pairs = {
        "node_a": rng.integers(0, n, n_pairs).astype(np.int64),
        "node_b": np.where(rng.random(n_pairs) < 0.5, -1, rng.integers(0, n, n_pairs)).astype(
            np.int64
        ),
        "normal": np.tile([0.0, 1.0], (n_pairs, 1)),
        "gap": rng.uniform(0, 0.1, n_pairs),
        "mu": rng.choice([0.0, 0.5], n_pairs),
    }
    model = {
        "nodes": nodes,
        "triangles": tris,
        "element_material": np.zeros(m, np.int64),
        "materials": [{"E": 1.0, "nu": 0.25}],
        "plane": "strain",
        "thickness": 1.0,
        "fixed_dofs": np.unique(rng.integers(0, 2 * n, rng.integers(0, 2 * n))).astype(np.int64),
        "load": rng.standard_normal(2 * n),
        "pairs": pairs,
    }
    check_solve(model)
