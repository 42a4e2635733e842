"""summary.json for any scene (slipstep.output.summary): per-contact extents along the contact's
coordinate s, and the half-widths a, c only for a symmetric half model.

Extents are checked against values worked out by hand (synthetic profiles) and against the
run's own contact_profile.csv, recomputed here; half models are recognised from the case's
[[bc]] symmetry entries and the geometry alone (no engine needed for that part).
"""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest
from conftest import needs_gmsh

from slipstep import run_case
from slipstep.case import load_case, parse_case
from slipstep.measures.contact_edges import closed_extent, stick_extent
from slipstep.build import build_scene
from slipstep.output.summary import half_model_side, one_line

# A block x0 <= x <= x0 + width, 0 <= y <= 4, pressed and pushed sideways by a traction on its
# top, on the rigid flat y = 0 (all bottom nodes start closed, in stick).  {bcs}: more [[bc]].
BLOCK = """
[case]
name = "block_on_flat"
[output]
snapshots = [1.0]
figures = false
xdmf = false
[[body]]
name = "block"
[body.mesh]
generator = "block"
x0 = {x0}
width = {width}
height = 4.0
nx = 20
ny = 8
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
body = "block"
edge = "top"
traction = [{shear}, -1.0]
{bcs}
[[contact]]
name = "flat"
kind = "rigid_line"
body = "block"
edge = "bottom"
point = [{point}, 0.0]
normal = [0.0, 1.0]
mu = 0.5
"""


def symmetry(edge: str) -> str:
    return f'[[bc]]\nbody = "block"\nedge = "{edge}"\nsymmetry = true\n'


def block_case(x0=2.0, width=10.0, shear=0.2, bcs="", point=0.0) -> str:
    return BLOCK.format(x0=x0, width=width, shear=shear, bcs=bcs, point=point)


def read_profile(path) -> list[dict]:
    with open(path) as fh:
        return [
            {k: (v if k in ("status", "contact") else float(v)) for k, v in row.items()}
            for row in csv.DictReader(fh)
        ]


# --------------------------------------------------------------------------- extents by hand
def test_closed_extent_interpolates_both_ends_in_load_fraction():
    # pairs at s = -2 .. 2; the three middle ones closed (at f = 0.5, 0, 0.2: their last
    # crossings), the outer two open, to close at f = 2.5 (left) and 1.2 (right)
    s = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
    status = np.array([0, 2, 1, 2, 0])
    closure = np.array([np.nan, 0.5, 0.0, 0.2, np.nan])
    predicted = np.array([2.5, np.nan, np.nan, np.nan, 1.2])
    lo, hi = closed_extent(s, status, closure, predicted, 1.0)
    # left: -1 - 1 (1 - 0.5)/(2.5 - 0.5) = -1.25; right: 1 + 1 (1 - 0.2)/(1.2 - 0.2) = 1.8
    assert lo == pytest.approx(-1.25, abs=1e-15)
    assert hi == pytest.approx(1.8, abs=1e-15)
    # stick only at s = 0: each end midway to the slipping neighbour
    assert stick_extent(s, status, [lo, hi]) == [-0.5, 0.5]
    assert closed_extent(s, np.zeros(5, int), closure, predicted, 1.0) is None
    assert stick_extent(s, np.array([0, 2, 2, 2, 0]), [lo, hi]) is None


def test_a_receding_edge_interpolates_between_two_separations():
    # unloading: s = 2 separated at t = 1.2, s = 1 (still closed) separates at t = 2; the edge
    # left s = 2 at 1.2 and reaches s = 1 at 2: at t = 1.5, 2 - (1.5 - 1.2)/(2 - 1.2) = 1.625
    s = np.array([0.0, 1.0, 2.0])
    status = np.array([1, 1, 0])
    last = np.array([0.0, 0.0, 1.2])
    upcoming = np.array([np.inf, 2.0, np.inf])
    assert closed_extent(s, status, last, upcoming, 1.5)[1] == pytest.approx(1.625, abs=1e-15)
    # no crossing in the snapshot's stage (-inf / inf): the outermost closed pair
    assert closed_extent(s, status, np.full(3, -np.inf), upcoming, 1.5)[1] == 1.0


def test_stick_reaching_the_closed_edge_ends_there():
    s = np.array([0.0, 1.0, 2.0, 3.0])
    status = np.array([2, 1, 1, 0])
    closed = [0.0, 2.4]  # as interpolated between s = 2 (closed) and s = 3 (open)
    assert stick_extent(s, status, closed) == [0.5, 2.4]


# --------------------------------------------------------------------------- half models
@needs_gmsh
def test_the_hertz_quarter_cylinder_is_a_half_model():
    assert half_model_side(build_scene(load_case(None)), 0) == 1


@pytest.mark.parametrize(
    "x0, edge, point, side",
    [
        (2.0, None, 0.0, 0),  # no symmetry bc: a full model
        (2.0, "left", 0.0, 0),  # the mirror x = 2 is not through s = 0 (x = 0)
        (2.0, "left", 2.0, 1),  # the line's point on the mirror: s = x - 2 >= 0
        (-10.0, "right", 0.0, -1),  # the body on the negative side of its mirror x = 0
        (-5.0, "right", 5.0, -1),  # mirror x = 5 through s = 0 (point (5, 0)): s = x - 5 <= 0
        (-5.0, "right", 0.0, 0),  # mirror x = 5, but s = 0 at x = 0, inside the block
    ],
)
def test_half_model_from_the_symmetry_bc_and_the_geometry(x0, edge, point, side):
    text = block_case(x0, 10.0, bcs=symmetry(edge) if edge else "", point=point)
    assert half_model_side(build_scene(parse_case(text)), 0) == side


def test_a_mirror_parallel_to_the_contact_does_not_make_a_half_model():
    # the top edge y = 4 as a symmetry line: parallel to the flat, not across it
    scene = build_scene(parse_case(block_case(0.0, bcs=symmetry("top"))))
    assert half_model_side(scene, 0) == 0


# --------------------------------------------------------------------------- runs
@pytest.fixture(scope="module")
def hertz(tmp_path_factory):
    """The Hertz quarter cylinder with friction (mu = 0.2) on a coarse mesh (h_contact = 0.1)."""
    out = tmp_path_factory.mktemp("hertz")
    result, summary = run_case(
        None,
        out=out,
        overrides=[
            "mesh.h_contact=0.1",
            "contact.mu=0.2",
            "output.snapshots=[1.0]",
            "output.xdmf=false",
            "output.figures=false",
        ],
    )
    return out, result, summary


@needs_gmsh
def test_hertz_half_model_has_a_and_c_at_the_far_ends_of_the_extents(hertz):
    out, _, s = hertz
    contact = s["contacts"]["contact 0"]
    assert contact["half_model"] is True
    closed, stick = contact["closed_extent"], contact["stick_extent"]
    assert s["contact_half_width"] == closed[1] and s["stick_half_width"] == stick[1]
    # both zones start on the symmetry line: the node at (0, 0) is closed and sticks
    assert closed[0] == 0.0 and stick[0] == 0.0
    assert 0.0 < s["stick_half_width"] < s["contact_half_width"]

    # recomputed from contact_profile.csv: s = x here (flat y = 0 through (0, 0)); a lies
    # between the outermost closed node and the next open one, c between the outermost stick
    # node and the first slipping one beyond it
    prof = read_profile(out / "contact_profile.csv")
    assert all(r["s"] == r["x"] for r in prof)
    closed_x = [r["x"] for r in prof if r["status"] != "open"]
    open_beyond = [r["x"] for r in prof if r["status"] == "open" and r["x"] > max(closed_x)]
    assert max(closed_x) <= s["contact_half_width"] <= min(open_beyond)
    stick_x = [r["x"] for r in prof if r["status"] == "stick"]
    slip_beyond = [r["x"] for r in prof if r["status"] == "slip" and r["x"] > max(stick_x)]
    assert s["stick_half_width"] == pytest.approx(
        0.5 * (max(stick_x) + min(slip_beyond)), abs=1e-15
    )
    assert contact["n_closed"] == len(closed_x) and contact["n_stick"] == len(stick_x)
    # Hertz: a = sqrt(4 P R / (pi E*)), E* = E / (1 - nu^2); friction (mu = 0.2) moves it by
    # far less than the node spacing h_contact = 0.1, the resolution of the contact edge
    E_star = 70000.0 / (1 - 0.3**2)
    assert abs(s["contact_half_width"] - math.sqrt(4 * 1000.0 * 125.0 / (math.pi * E_star))) < 0.1
    # the quarter model carries P/2 = 500 N/mm; equilibrium to the engine's 1e-9
    assert contact["total_normal_force"] == pytest.approx(500.0, rel=1e-9)
    assert s["hertz"]["a_rel_error"] == pytest.approx(
        s["contact_half_width"] / s["hertz"]["a_hertz_at_final"] - 1, rel=1e-12
    )


@needs_gmsh
def test_summary_json_holds_the_contacts_by_name(hertz):
    out, _, s = hertz
    data = json.loads((out / "summary.json").read_text())
    assert (
        data["contacts"]["contact 0"]["closed_extent"]
        == s["contacts"]["contact 0"]["closed_extent"]
    )
    assert data["stop"]["kind"] == "completed"
    assert data["contact_half_width"] == s["contact_half_width"]


@pytest.fixture(scope="module")
def sheared(tmp_path_factory):
    """A full block (no symmetry), 2 <= x <= 12, pressed by q = 1 and pushed sideways by
    0.2 q on its top, on a rigid flat with mu = 0.5 (below gross sliding)."""
    path = tmp_path_factory.mktemp("sheared") / "block.toml"
    path.write_text(block_case(x0=2.0, width=10.0, shear=0.2))
    out = path.parent / "out"
    result, summary = run_case(path, out=out)
    return out, result, summary


def test_a_sheared_full_block_has_no_half_widths(sheared):
    out, result, s = sheared
    assert "contact_half_width" not in s and "stick_half_width" not in s
    assert "a =" not in one_line(s) and "flat: closed s in [2, 12]" in one_line(s)
    contact = s["contacts"]["flat"]
    assert contact["half_model"] is False
    # the whole bottom stays closed: its extent is the bottom edge exactly, x0 .. x0 + width
    assert contact["n_closed"] == contact["n_pairs"] == 21
    assert contact["closed_extent"] == [2.0, 12.0]
    lo, hi = contact["stick_extent"]
    assert 2.0 <= lo < hi <= 12.0
    # recomputed from contact_profile.csv: each end of the stick zone midway between the last
    # stick node and the first closed non-stick node beyond it, or at the closed edge
    prof = sorted(read_profile(out / "contact_profile.csv"), key=lambda r: r["s"])
    stick = [i for i, r in enumerate(prof) if r["status"] == "stick"]
    first, last = stick[0], stick[-1]
    expect_lo = 0.5 * (prof[first]["s"] + prof[first - 1]["s"]) if first > 0 else 2.0
    expect_hi = 0.5 * (prof[last]["s"] + prof[last + 1]["s"]) if last + 1 < len(prof) else 12.0
    assert (lo, hi) == (pytest.approx(expect_lo, abs=1e-15), pytest.approx(expect_hi, abs=1e-15))
    # the block is really sheared: friction carries the whole tangential load 0.2 q w t = 2
    # (lambda_t along t = (-n_y, n_x) = -x), the flat the whole normal load q w t = 10;
    # equilibrium to the engine's tolerance 1e-9
    assert contact["total_normal_force"] == pytest.approx(10.0, rel=1e-9)
    assert float(np.sum(result["snapshots"][-1]["lambda_t"])) == pytest.approx(2.0, rel=1e-9)
    assert contact["n_slip"] > 0, "the shear makes some of the bottom slip"


def test_a_mirrored_half_block_measures_a_and_c_towards_negative_s(tmp_path):
    """The block on the negative side of its mirror x = 0 (side -1): a = -s_min of the closed
    extent = the block's width, c = -s_min of the stick extent."""
    path = tmp_path / "mirrored.toml"
    path.write_text(block_case(x0=-10.0, width=10.0, shear=0.0, bcs=symmetry("right")))
    _, s = run_case(path)
    contact = s["contacts"]["flat"]
    assert contact["half_model"] is True
    assert contact["closed_extent"] == [-10.0, 0.0]
    assert s["contact_half_width"] == 10.0
    assert s["stick_half_width"] == -contact["stick_extent"][0] >= 0.0


# --------------------------------------------------------------------------- same way everywhere
def test_the_extent_midway_equals_the_final_extent_of_a_run_to_there():
    """Between events an event-driven run is linear, so in a frictionless elastic Hertz run
    (closures only) the engine's predicted closure of the next pair, used at the run's end, is
    the time it then closes: the extent at t = 0.5 of a run to P (interpolated between the
    closures of the run's events) equals the final extent of the same scene loaded to P/2 (its
    closure times twice as late), to round-off (1e-12).  At a snapshot other than the last the
    extent used to stop at the outermost closed node."""
    from slipstep.measures import contact_edges as contact_measures
    from slipstep import run

    common = ["mesh.h_contact=0.2", "contact.mu=0.0", "output.figures=false"]
    full = run(None, overrides=common + ["output.snapshots=[0.5, 1.0]"], progress=False)
    half = run(None, overrides=common + ["load.P=500.0", "output.snapshots=[1.0]"], progress=False)
    history = contact_measures.path_history(full.scene, full.raw)
    assert list(history["t"]) == [0.5, 1.0]
    assert history["extent"][0, 0, 1] == pytest.approx(
        half.summary["contact_half_width"], rel=1e-12
    )
    assert history["extent"][1, 0, 1] == full.summary["contact_half_width"]
    # the edge lies between nodes here, not on the outermost closed one
    closed = full.profile(0.5)["status"] > 0
    assert history["extent"][0, 0, 1] > full.profile(0.5)["s"][closed].max()


def test_one_contact_state_has_one_extent_at_a_stage_end_and_the_run_end():
    """Cattaneo-Mindlin with the same material on both sides (Dundurs beta = 0): the shear
    stage leaves the normal contact as the approach left it, so the closed zone at the
    approach's end and at the run's end is the same, and centred (the roller's contactor nodes
    are mirrored across x = 0, so to round-off).  The run's end used to be interpolated
    towards the engine's prediction for the next shear increment: [-1.982, 1.786] against
    [-1.784, 1.784] at the stage end on this mesh."""
    from slipstep import run

    coarse = [
        "body.roller.mesh.h_contact=0.2",
        "body.block.mesh.h_contact=0.2",
        "output.figures=false",
    ]
    r = run("cattaneo_mindlin", overrides=coarse, progress=False)
    approach, shear = (st["contacts"]["interface"] for st in r.summary["stages"])
    final = r.summary["contacts"]["interface"]
    assert approach["n_closed"] == shear["n_closed"] == final["n_closed"] > 0
    assert approach["closed_extent"] == shear["closed_extent"] == final["closed_extent"]
    lo, hi = final["closed_extent"]
    assert lo == pytest.approx(-hi, rel=1e-12)
