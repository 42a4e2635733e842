"""The key reference (`slipstep keys`) and cases/README.md's key tables describe one schema.

`slipstep keys` prints slipstep.case's declarations (what the validator checks); the README's
tables are written by hand.  The README is read here independently, as markdown: its tables
must list exactly the schema's keys, section by section and variant by variant, and state the
schema's default wherever they state one as a literal.  A key added to the schema without its
README row, a row for a removed key, or a default changed on one side only fails here.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
import tomllib

import pytest

from conftest import CASES, ROOT

from slipstep import schema
from slipstep import keys

HEADING = re.compile(r"^#{2,4} .*?`\[\[?([a-z_.]+)\]\]?`")
VARIANT = re.compile(r'^\*\*`(generator|kind|file) = "([^"]+)"`\*\*')
TABLE_HEAD = "| key | type | default | meaning |"


def readme_tables() -> dict[tuple[str, str], dict[str, str]]:
    """{(section, variant): {key: default cell}} of cases/README.md's key tables; a variant is
    the paragraph heading before a table (``kind = "rigid_line"``), "file" for the file mesh."""
    tables: dict[tuple[str, str], dict[str, str]] = {}
    section, variant, rows = None, "", None
    for line in (CASES / "README.md").read_text().splitlines():
        if line.startswith("#"):
            found = HEADING.match(line)
            section, variant = (found.group(1) if found else None), ""
        elif found_variant := VARIANT.match(line):
            kind, value = found_variant.groups()
            variant = "file" if kind == "file" else f'{kind} = "{value}"'
        if line.strip() == TABLE_HEAD and section:
            rows = tables.setdefault((section, variant), {})
        elif rows is not None and line.startswith("| `"):
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
            for key in re.findall(r"`([^`]+)`", cells[0]):
                rows[key] = cells[2]
        elif not line.startswith("|"):
            rows = None
    return tables


def schema_tables() -> dict[tuple[str, str], dict]:
    """{(section, variant): keys} from `slipstep keys`' sections, one per generator or kind
    (quarter and half cylinder share one table: both are listed), "file" for the file mesh."""
    out = {}
    for s in keys.sections():
        selector, values = s.variants
        labels = [f'{selector} = "{v}"' for v in values] if values else [selector]
        for label in labels:
            out[(s.name, label)] = s.keys
    return out


#: Keys the README states outside the tables: the selecting key is in the variant's heading;
#: the keys every contact kind shares (one declaration) are in the paragraph "Common keys".
_KINDS = list(schema.CONTACT_VARIANTS.values())
CONTACT_COMMON = {k for k in _KINDS[0] if all(k in t and t[k] is _KINDS[0][k] for t in _KINDS)}


def documented_elsewhere(section: str) -> set[str]:
    if section == "body.mesh":
        return {"generator"}
    if section == "contact":
        return {"kind"} | CONTACT_COMMON
    return set()


def test_the_readme_is_read():
    # the reader finds tables known to be there (guards against a vacuous pass)
    tables = readme_tables()
    assert tables[("solver", "")]["group_tol"] == "`0.03`"
    assert "refine_box" in tables[("body.mesh", 'generator = "block"')]
    assert {"centre", "radius"} <= set(tables[("contact", 'kind = "rigid_circle"')])
    assert set(tables[("stage", "")]) == {"name", "factors"}


def test_every_schema_table_has_its_readme_table_with_the_same_keys():
    readme, declared = readme_tables(), schema_tables()
    for (section, variant), keys_ in declared.items():
        want = set(keys_) - documented_elsewhere(section)
        if section == "body":
            want |= set(schema.BODY_SUBTABLES)
        shared = [v for (s, v), k in declared.items() if s == section and k is keys_]
        got = next((readme[(section, v)] for v in shared if (section, v) in readme), None)
        if not want:
            continue  # generator = "given": no key but the generator
        assert got is not None, f"cases/README.md has no key table for [{section}] {variant}"
        assert set(got) == want, (
            f"[{section}] {variant}: README only {sorted(set(got) - want)}, "
            f"schema only {sorted(want - set(got))}"
        )
    stray = set(readme) - set(declared)
    assert not stray, f"README tables for sections the schema does not have: {sorted(stray)}"


def test_the_keys_shared_by_every_contact_kind_are_in_the_common_paragraph():
    text = (CASES / "README.md").read_text()
    common = next(line for line in text.split("\n\n") if line.startswith("Common keys:"))
    assert all(f"`{k}`" in common for k in CONTACT_COMMON | {"kind"}), common


ABSENT = object()  # "absent": the schema's None, or an empty inline table (no component)


def _readme_default(cell: str):
    """The default a README cell states, or ... when it states none as a literal."""
    if cell == "required":
        return schema.REQUIRED
    if cell.startswith("absent"):
        return ABSENT
    if cell == "±∞":
        return math.inf
    literal = re.fullmatch(r"`([^`]*)`", cell)
    if not literal:
        return ...  # words around it: "`\"stage <k>\"` (1-based)" is a description
    return tomllib.loads(f"v = {literal.group(1)}")["v"]


def test_the_readme_states_the_schema_defaults():
    declared = schema_tables()
    checked = 0
    for (section, variant), rows in readme_tables().items():
        for key, cell in rows.items():
            spec = declared[(section, variant)].get(key)
            got = _readme_default(cell)
            if spec is None or got is ...:
                continue  # body's sub-tables; a description ("the only quarter_cylinder body")
            checked += 1
            where = f"[{section}] {variant} {key}: README {cell}, schema {keys.default_text(spec)}"
            if got is math.inf:
                assert math.isinf(spec.default), where
            elif got is ABSENT:
                assert spec.default is None or spec.default == {}, where
            else:
                assert got == spec.default or got is spec.default, where
    assert checked > 60  # most rows state a literal default (guards against a vacuous pass)


# --------------------------------------------------------------------------- slipstep keys
def slipstep(*args):
    return subprocess.run(
        [sys.executable, "-m", "slipstep", *args],
        capture_output=True,
        text=True,
        timeout=120,
        env={"PYTHONPATH": str(ROOT / "py"), "PATH": "/usr/bin:/bin"},
    )


def test_keys_prints_every_section_and_key():
    out = slipstep("keys")
    assert out.returncode == 0, out.stderr
    for s in keys.sections():
        assert s.title in out.stdout, s.title
        for key in s.keys:
            assert re.search(rf"^  {re.escape(key)} ", out.stdout, re.M), (s.title, key)


@pytest.mark.parametrize(
    "which, title, absent",
    [
        ("solver", "[solver]", "[output]"),
        ("material", "[body.material]", "[body.mesh]"),
        ("contact.mu", '[contact] kind = "rigid_line" | "rigid_circle"', "radius"),
    ],
)
def test_keys_of_one_section_or_key(which, title, absent):
    out = slipstep("keys", which)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith(title) and absent not in out.stdout, out.stdout


def test_keys_of_an_unknown_section_suggests_one():
    out = slipstep("keys", "solvr")
    assert out.returncode == 2
    assert out.stderr.strip().splitlines() == [
        "slipstep: error: keys solvr: no such section or key (did you mean solver?); sections: "
        "analysis, bc, body, body.material, body.mesh, case, contact, load, material, mesh, "
        "output, point_load, solver, stage"
    ]
