"""The cache of generated meshes (slipstep.mesh.cache): what meshes again and what does not.

Every test counts gmsh's sessions (calls of ``gmsh.initialize``), not time: a cache hit opens
none, a miss one per generated body.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import needs_gmsh

from slipstep.mesh import triangle_generators as generators, cache as mesh_cache
from slipstep import prepare
from slipstep.mesh import tetrahedron_generators as generators_3d

#: A coarse quarter cylinder (R, h_contact, contact_zone, h_max, growth): ~100 elements.
CYLINDER = (10.0, 0.5, 1.0, 3.0, 0.3)


@pytest.fixture
def gmsh_sessions(monkeypatch, tmp_path):
    """A fresh cache folder for the test, and a list that grows by one per gmsh session."""
    import gmsh

    monkeypatch.setenv("SLIPSTEP_CACHE", str(tmp_path / "cache"))
    sessions = []
    initialize = gmsh.initialize

    def counted(*args, **kwargs):
        sessions.append(1)
        return initialize(*args, **kwargs)

    monkeypatch.setattr(gmsh, "initialize", counted)
    return sessions


def entries(tmp_path):
    return sorted((tmp_path / "cache" / "meshes").glob("*.npz"))


def same_mesh(a, b) -> bool:
    """Equal arrays, tags and node sets (exactly: the cache stores the arrays bit for bit)."""

    def equal(x: dict, y: dict) -> bool:
        return x.keys() == y.keys() and all(np.array_equal(x[k], y[k]) for k in x)

    return (
        type(a) is type(b)
        and np.array_equal(a.nodes, b.nodes)
        and np.array_equal(a.elements, b.elements)
        and equal(a.tags, b.tags)
        and equal(a.node_sets, b.node_sets)
    )


@needs_gmsh
def test_an_unchanged_mesh_is_read_back_not_meshed_again(gmsh_sessions, tmp_path):
    first = generators.quarter_cylinder(*CYLINDER)
    again = generators.quarter_cylinder(*CYLINDER)
    assert len(gmsh_sessions) == 1 and len(entries(tmp_path)) == 1
    assert same_mesh(first, again)
    # the defaults are part of the key: the growth given by keyword or by default is one entry
    generators.quarter_cylinder(10.0, 0.5, 1.0, 3.0)
    generators.quarter_cylinder(10.0, 0.5, 1.0, 3.0, growth=0.1)
    assert len(gmsh_sessions) == 2 and len(entries(tmp_path)) == 2


@needs_gmsh
def test_a_changed_parameter_meshes_again(gmsh_sessions, tmp_path):
    base = generators.quarter_cylinder(*CYLINDER)
    finer = generators.quarter_cylinder(10.0, 0.4, 1.0, 3.0, 0.3)
    assert len(gmsh_sessions) == 2 and len(entries(tmp_path)) == 2
    assert finer.n_elements > base.n_elements
    # another generator with the same numbers is another mesh
    generators.disc(*CYLINDER)
    assert len(gmsh_sessions) == 3


@needs_gmsh
def test_another_gmsh_or_meshing_code_meshes_again(gmsh_sessions, monkeypatch):
    generators.quarter_cylinder(*CYLINDER)
    monkeypatch.setattr(mesh_cache, "gmsh_version", lambda: "0.0.0-other")
    generators.quarter_cylinder(*CYLINDER)
    assert len(gmsh_sessions) == 2
    monkeypatch.setattr(mesh_cache, "code_version", lambda: "edited")
    generators.quarter_cylinder(*CYLINDER)
    generators.quarter_cylinder(*CYLINDER)
    assert len(gmsh_sessions) == 3


@needs_gmsh
def test_a_damaged_or_altered_entry_is_meshed_again(gmsh_sessions, tmp_path):
    fresh = generators.quarter_cylinder(*CYLINDER)
    (path,) = entries(tmp_path)
    path.write_bytes(path.read_bytes()[:200])  # cut short: not a readable archive
    assert same_mesh(generators.quarter_cylinder(*CYLINDER), fresh)
    assert len(gmsh_sessions) == 2
    # a readable entry whose nodes were moved (its digest no longer matches them)
    with np.load(path) as f:
        arrays = {k: f[k] for k in f.files}
    arrays["nodes"] = arrays["nodes"] * 1.5
    with open(path, "wb") as f:
        np.savez(f, **arrays)
    assert same_mesh(generators.quarter_cylinder(*CYLINDER), fresh)
    assert len(gmsh_sessions) == 3
    # it was rewritten whole: read back from here on
    assert same_mesh(generators.quarter_cylinder(*CYLINDER), fresh)
    assert len(gmsh_sessions) == 3


@needs_gmsh
def test_off_meshes_every_time_and_writes_nothing(gmsh_sessions, tmp_path, monkeypatch):
    monkeypatch.setenv("SLIPSTEP_CACHE", "off")
    generators.quarter_cylinder(*CYLINDER)
    generators.quarter_cylinder(*CYLINDER)
    assert len(gmsh_sessions) == 2
    assert not (tmp_path / "cache").exists()


@needs_gmsh
def test_a_cache_that_cannot_be_written_is_skipped(gmsh_sessions, tmp_path, monkeypatch):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("SLIPSTEP_CACHE", str(blocker))
    first = generators.quarter_cylinder(*CYLINDER)
    assert same_mesh(generators.quarter_cylinder(*CYLINDER), first)
    assert len(gmsh_sessions) == 2


@needs_gmsh
def test_a_case_rerun_builds_its_scene_without_gmsh(gmsh_sessions):
    """The path of `slipstep run`: the second scene of a case is built from the cache, and a
    changed mesh key (--set mesh.h_contact) meshes again."""
    first = prepare(None, overrides=["mesh.h_contact=0.2"])
    again = prepare(None, overrides=["mesh.h_contact=0.2"])
    assert len(gmsh_sessions) == 1
    assert np.array_equal(first.nodes, again.nodes) and np.array_equal(
        first.triangles, again.triangles
    )
    prepare(None, overrides=["mesh.h_contact=0.25"])
    assert len(gmsh_sessions) == 2
    # a key that is not the mesh's reuses the mesh
    prepare(None, overrides=["mesh.h_contact=0.2", "contact.mu=0.1"])
    assert len(gmsh_sessions) == 2


@needs_gmsh
def test_tetrahedra_are_cached_too(gmsh_sessions, tmp_path):
    first = generators_3d.shell(1.0, 2.0, 0.5)
    again = generators_3d.shell(1.0, 2.0, 0.5)
    assert len(gmsh_sessions) == 1 and same_mesh(first, again)
    generators_3d.shell(1.0, 2.0, 0.5, h_outer=0.8)
    assert len(gmsh_sessions) == 2
