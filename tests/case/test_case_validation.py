"""Case files: parsing, --set overrides, and one-line validation errors that name the key."""

from __future__ import annotations

import math
import re

import pytest
from conftest import CASES, MINIMAL, ROOT, write_case

from slipstep import schema
from slipstep.case import CaseError, load_case, parse_case


def error_of(text: str, overrides=(), source="cases/x.toml") -> str:
    with pytest.raises(CaseError) as info:
        parse_case(text, source=source, overrides=overrides)
    message = str(info.value)
    assert "\n" not in message, "errors must be one line"
    assert message.startswith(source) or message.startswith("--set"), message
    return message


def test_minimal_case_fills_defaults():
    c = parse_case(MINIMAL)
    assert c.name == "mini"
    assert c.data["analysis"] == {"dimension": 2, "plane": "strain", "thickness": 1.0}
    assert c.data["output"]["snapshots"] == "auto"  # "events" in 2D (slipstep.output.snapshots)
    assert c.data["solver"]["tie_tol"] == 1e-9
    material = c.data["body"][0]["material"]
    assert material == {"E": 1000.0, "nu": 0.25, "Sy": None, "H": None}
    contact = c.data["contact"][0]
    assert contact["x_max"] == math.inf and contact["mu"] == 0.3


def test_the_shipped_cases_validate():
    for path in sorted(CASES.glob("*.toml")):
        c = load_case(path)
        assert c.data["body"], path


def test_embedded_default_is_the_hertz_case_and_cases_link_to_it():
    default = load_case(None)
    assert default.name == "hertz_cylinder"
    assert default.data["load"]["P"] == 1000.0
    body = default.data["body"][0]
    assert body["mesh"]["R"] == 125.0 and body["material"] == {
        "E": 70000.0,
        "nu": 0.3,
        "Sy": None,
        "H": None,
    }
    link = CASES / "hertz_cylinder.toml"
    assert link.is_symlink()
    assert link.resolve() == (ROOT / "py/slipstep/data/hertz_cylinder.toml").resolve()


# --------------------------------------------------------------------------- errors
def test_missing_material_key_names_it():
    text = MINIMAL.replace("nu = 0.25\n", "")
    msg = error_of(text)
    assert "material.nu is missing" in msg and "add `nu = ...`" in msg


def test_missing_material_table():
    text = MINIMAL.replace("[body.material]\nE = 1000.0\nnu = 0.25\n", "")
    assert "material is missing" in error_of(text)


def test_nu_at_one_half_is_rejected_with_the_fix():
    msg = error_of(MINIMAL.replace("nu = 0.25", "nu = 0.5"))
    assert msg == (
        "cases/x.toml: material.nu = 0.5 is not allowed: Poisson's ratio must "
        "satisfy -1 < nu < 0.5 (use 0.499 for near-incompressible)"
    )


@pytest.mark.parametrize(
    "bad, key",
    [
        ("E = 1000.0", "material.E"),
    ],
)
def test_non_positive_modulus(bad, key):
    msg = error_of(MINIMAL.replace(bad, "E = -5.0"))
    assert f"{key} = -5.0 is not allowed" in msg


def test_negative_mu_names_the_key():
    msg = error_of(MINIMAL.replace("mu = 0.3", "mu = -0.1"))
    assert "contact.mu = -0.1 is not allowed: mu must be >= 0" in msg


def test_unknown_bc_edge_tag_lists_the_tags():
    msg = error_of(MINIMAL.replace('edge = "bottom"', 'edge = "botom"'))
    assert 'bc.edge = "botom" is not allowed' in msg
    assert "bottom, right, top, left" in msg


def test_unknown_body_in_bc():
    msg = error_of(MINIMAL.replace('body = "b"\nedge = "bottom"', 'body = "c"\nedge = "bottom"'))
    assert 'bc.body = "c" is not allowed: no body has that name (bodies: b)' in msg


def test_malformed_toml_is_one_line_with_position():
    msg = error_of(MINIMAL.replace("nx = 4", "nx = = 4"))
    assert msg.startswith("cases/x.toml: invalid TOML:")
    assert re.search(r"line \d+", msg)


def test_unknown_key_in_file_lists_valid_keys():
    msg = error_of(MINIMAL.replace("nu = 0.25", "nu = 0.25\nnuu = 1"))
    assert "unknown key material.nuu" in msg and "valid keys: E, nu, Sy, H" in msg


def test_wrong_type():
    msg = error_of(MINIMAL.replace("nx = 4", 'nx = "four"'))
    assert 'mesh.nx = "four" is not allowed: expected an integer' in msg


def test_plasticity_parameters_are_checked():
    msg = error_of(MINIMAL.replace("nu = 0.25", "nu = 0.25\nSy = 0.0"))
    assert "material.Sy = 0.0 is not allowed" in msg
    msg = error_of(MINIMAL.replace("nu = 0.25", "nu = 0.25\nSy = 100.0\nH = -1.0"))
    assert "material.H = -1.0 is not allowed" in msg


def test_bad_snapshot_fractions():
    msg = error_of(MINIMAL + "\n[output]\nsnapshots = [0.5, 0.2]\n")
    assert (
        "output.snapshots = [0.5, 0.2] is not allowed: the load fractions must be strictly "
        "increasing" in msg
    )
    msg = error_of(MINIMAL + "\n[output]\nsnapshots = [0.0, 1.0]\n")
    assert "(0, 1]" in msg


def test_bad_plane():
    msg = error_of(MINIMAL + '\n[analysis]\nplane = "spherical"\n')
    assert (
        'analysis.plane = "spherical" is not allowed: use "strain" or "stress" or ' '"axisymmetric"'
    ) in msg


def test_bc_that_does_nothing():
    msg = error_of(MINIMAL.replace('fix = ["x", "y"]', ""))
    assert "bc does nothing" in msg


def test_two_bodies_use_names_in_keys():
    second = (
        MINIMAL.split("[[bc]]")[0]
        .replace('name = "b"', 'name = "c"')
        .replace('[case]\nname = "mini"\n', "")
    )
    text = MINIMAL + second.replace("nu = 0.25", "nu = 0.7")
    msg = error_of(text)
    assert "body.c.material.nu = 0.7 is not allowed" in msg


def test_load_needs_a_quarter_cylinder():
    msg = error_of(MINIMAL + "\n[load]\nP = 10.0\n")
    assert "load.P is not allowed here" in msg


# --------------------------------------------------------------------------- overrides
def test_overrides_are_single_keys():
    c = load_case(None, ["contact.mu=0.35", "mesh.h_contact=0.02", "load.P=500"])
    assert c.data["contact"][0]["mu"] == 0.35
    assert c.data["body"][0]["mesh"]["h_contact"] == 0.02
    assert c.data["load"]["P"] == 500.0


def test_override_by_name_index_and_bare_word():
    c = load_case(
        CASES / "two_blocks.toml",
        [
            "body.punch.material.E=210000",
            "bc.load.pressure=20",
            "bc.1.symmetry=false",
            "bc.1.fix=['x']",
            "analysis.plane=stress",
            "solver.max_events=50",
        ],
    )
    assert c.body("punch")["material"]["E"] == 210000.0
    assert c.data["bc"][0]["pressure"] == 20.0
    assert c.data["bc"][1]["fix"] == ["x"] and c.data["bc"][1]["symmetry"] is False
    assert c.data["analysis"]["plane"] == "stress"
    assert c.data["solver"]["max_events"] == 50


def test_unknown_override_key_lists_valid_keys():
    with pytest.raises(CaseError) as info:
        load_case(None, ["contact.muu=0.3"])
    msg = str(info.value)
    assert msg.startswith("--set contact.muu=0.3: unknown key 'muu' in [[contact]]; valid keys:")
    assert "mu" in msg.split("valid keys:")[1] and "\n" not in msg


def test_unknown_override_section():
    with pytest.raises(CaseError, match=r"unknown key 'material_E'; valid first parts are"):
        load_case(None, ["material_E=3"])


def test_ambiguous_override_asks_for_an_index():
    with pytest.raises(
        CaseError, match=r"has 2 \[\[body\]\] entries: say which, e.g. " r"body.0.material.E"
    ):
        load_case(CASES / "two_blocks.toml", ["body.material.E=3"])
    with pytest.raises(CaseError, match=r"short for body.<name>.material"):
        load_case(CASES / "two_blocks.toml", ["material.E=3"])


def test_override_values_are_validated_like_the_file():
    with pytest.raises(CaseError) as info:
        load_case(None, ["material.nu=0.5"])
    assert "material.nu = 0.5 is not allowed" in str(info.value)
    with pytest.raises(CaseError, match=r"--set contact.mu: expected KEY=VALUE|expected KEY=VALUE"):
        load_case(None, ["contact.mu"])


def test_missing_case_file():
    with pytest.raises(CaseError, match=r"nope.toml: no such case file"):
        load_case("nope.toml")


def test_file_source_is_the_given_path(tmp_path):
    path = write_case(tmp_path, MINIMAL.replace("nu = 0.25", "nu = 0.5"))
    with pytest.raises(CaseError) as info:
        load_case(path)
    assert str(info.value).startswith(f"{path}: material.nu = 0.5")


def test_readme_documents_every_key():
    readme = (CASES / "README.md").read_text()
    tables = [
        schema.CASE_KEYS,
        schema.ANALYSIS_KEYS,
        schema.LOAD_KEYS,
        schema.OUTPUT_KEYS,
        schema.SOLVER_KEYS,
        schema.BODY_KEYS,
        schema.MATERIAL_KEYS,
        schema.QUARTER_CYLINDER_KEYS,
        schema.BLOCK_KEYS,
        schema.QUARTER_ANNULUS_KEYS,
        schema.FILE_MESH_KEYS,
        schema.BC_KEYS,
        schema.POINT_LOAD_KEYS,
        schema.RIGID_LINE_KEYS,
        schema.NODE_TO_NODE_KEYS,
    ]
    missing = sorted({k for t in tables for k in t if f"`{k}`" not in readme})
    assert not missing, f"cases/README.md does not document {missing}"
