"""The resolved case of a run: the validated document (every default filled in, the ``--set``
overrides applied) written back as a case file, ``case.toml`` beside the results, so that
``slipstep run <folder>/case.toml`` reruns it.

Written as it validates: mesh and surface files by their absolute paths, the keys that other keys make
inert and the validator refuses left out (:func:`slipstep.validation.document.inert_keys`),
and a body whose mesh came from Python as ``generator = "given"`` (its mesh is not in the
file: pass it again)."""

from __future__ import annotations

from pathlib import Path

from ..case import Case
from ..schema import ARRAY_KEYS, BODY_SUBTABLES, TABLES
from ..toml_writing import toml_table
from ..validation.document import inert_keys


def resolved_case_text(case: Case, given_meshes=(), header=()) -> str:
    """``case`` as case-file text; ``given_meshes`` names the bodies whose mesh came from
    Python, ``header`` lines open it as comments."""
    data = case.data
    inert = inert_keys(data)
    lines = [f"# {h}" for h in header]
    for name, keys in TABLES.items():
        if data.get(name) is not None:
            lines += ["", *toml_table(f"[{name}]", _known(data[name], keys, inert.get(name)))]
    for array, keys in ARRAY_KEYS.items():
        for i, element in enumerate(data[array]):
            table = _known(element, keys, inert.get(f"{array}.{i}"))
            if array == "contact" and table.get("file"):  # a rigid surface's file
                table["file"] = _absolute(case, table["file"])
            lines += ["", *toml_table(f"[[{array}]]", table)]
            if array == "body":
                lines += _body_tables(case, i, element, element["name"] in given_meshes, inert)
    return "\n".join(lines).lstrip("\n") + "\n"


def _body_tables(case: Case, i: int, body: dict, given: bool, inert: dict) -> list[str]:
    """[body.material] and [body.mesh] of body i (its mesh ``given`` from Python, or with its
    file paths made absolute)."""
    lines = [
        "",
        *toml_table("[body.material]", _known(body["material"], BODY_SUBTABLES["material"])),
    ]
    mesh = _known(body["mesh"], BODY_SUBTABLES["mesh"], inert.get(f"body.{i}.mesh"))
    if given:
        lines += [
            "",
            f"# body {body['name']!r}: its mesh came from Python "
            f"(slipstep.run(case, meshes={{...}})): pass it again to rerun",
        ]
        mesh = {"generator": "given"}
    elif "file" in mesh:
        for key in ("file", "edge_file", "face_file"):
            if mesh.get(key):
                mesh[key] = _absolute(case, mesh[key])
    return lines + ["", *toml_table("[body.mesh]", mesh)]


def _absolute(case: Case, name: str) -> str:
    """A file the case names, by its absolute path (a results folder is elsewhere)."""
    return str((Path(case.base_dir) / name).resolve())


def _known(table: dict, keys: dict, inert=()) -> dict:
    """The entries of a validated table that a case file may hold: schema keys with a value
    (None is an absent optional key), inert ones left out."""
    return {
        k: v for k, v in table.items() if k in keys and v is not None and k not in (inert or ())
    }
