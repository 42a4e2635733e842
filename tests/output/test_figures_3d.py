"""The 3D figures and the Result's 3D views as a user meets them (issue 38, points 5 and 6), on the
Vickers block (cases/vickers_indentation_3d.toml: frictionless, elastoplastic, loaded and drawn
back) and on closed forms:

- circles of the equivalent radii only on a round zone (:func:`is_round`: a disc of nodes is,
  a square of the same area reaches 1.25 times its radius and is not, nor is a strip);
- axes named as the axis they are within 2 degrees of, and read in its positive direction
  (the pyramid's contact, whose normal points down, is seen with x to the right and y up);
- the view zoomed to the closed nodes, not the candidate window;
- every label inside its figure (a y label was clipped);
- a frictionless contact has no stick: its closed nodes are "closed", the summary line names
  no stick radius;
- the plastic zone on a section: a plane through a tetrahedron cuts it in a polygon of known
  area (closed form), and the figure's colours are the section's elements' values;
- the Result in 3D: events with z, profile columns x, y, z, elements and tetrahedra (triangles
  named as absent), figures drawn on the caller's axes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh

import slipstep
from slipstep.figures import solid as fig3d
from slipstep.output.summary import one_line


@pytest.fixture(scope="module")
def vickers():
    pytest.importorskip("gmsh")
    return slipstep.run(
        CASES / "vickers_indentation_3d.toml",
        progress=False,
        overrides=["output.snapshots=[0.5, 1.0, 2.0]"],
    )


def _grid(h: float, inside) -> np.ndarray:
    x, y = np.meshgrid(np.arange(-2, 2 + h / 2, h), np.arange(-2, 2 + h / 2, h))
    points = np.column_stack([x.ravel(), y.ravel()])
    return points[inside(points)]


def test_only_a_round_zone_is_round():
    h = 0.05
    disc = _grid(h, lambda p: np.hypot(*p.T) <= 1.0)
    square = _grid(h, lambda p: np.abs(p).max(axis=1) <= math.sqrt(math.pi) / 2)  # area pi
    strip = _grid(h, lambda p: (np.abs(p[:, 0]) <= 0.2) & (np.abs(p[:, 1]) <= 1.9))
    assert fig3d.is_round(disc, 1.0, h)
    assert not fig3d.is_round(square, 1.0, h)
    assert not fig3d.is_round(strip, math.sqrt(0.4 * 3.8 / math.pi), h)


def test_an_axis_is_named_within_two_degrees():
    lean = np.array([0.0, -1.0, 0.014]) / math.hypot(1.0, 0.014)  # 0.8 degrees
    assert fig3d._axis_text(lean) == "-y" and fig3d._axis_text(-lean) == "y"
    off = np.array([0.0, math.cos(0.05), math.sin(0.05)])  # 2.9 degrees
    assert fig3d._axis_text(off).startswith("(")


def test_a_plane_cuts_a_tetrahedron_in_its_closed_form_section():
    """The corner tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1) cut by z = 1/2: the triangle
    of legs 1/2, area 1/8; by x = 0, its face in the plane: area 1/2."""
    nodes = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    tets = np.array([[0, 1, 2, 3]])
    ex, ey, ez = np.eye(3)

    def area(p):
        x, y = p[:, 0], p[:, 1]
        return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))

    cells, polygons = fig3d.section(nodes, tets, [0, 0, 0.5], ex, ey)
    assert list(cells) == [0] and math.isclose(area(polygons[0]), 1 / 8, rel_tol=1e-12)
    cells, polygons = fig3d.section(nodes, tets, [0, 0, 0], ey, ez)
    assert list(cells) == [0] and math.isclose(area(polygons[0]), 1 / 2, rel_tol=1e-12)


@needs_gmsh
def test_the_contact_view_reads_like_the_axes_and_shows_the_contact(vickers):
    fig = vickers.figure("contact_area")
    (ax,) = fig.axes
    assert ax.get_xlabel().startswith("along x") and ax.get_ylabel().startswith("along y")
    closed = [line for line in ax.lines if line.get_label().startswith("closed")]
    x, y = closed[0].get_xdata(), closed[0].get_ydata()
    assert len(x) > 0 and (y >= -1e-12).all()  # the quarter y >= 0 is drawn above the x axis
    candidates = [line for line in ax.lines if line.get_label().startswith("open")][0]
    low, high = ax.get_xlim()
    assert low <= x.min() and x.max() <= high < candidates.get_xdata().max()
    labels = [line.get_label() for line in ax.lines]
    assert not any(text.startswith(("slip", "stick", "contact radius")) for text in labels)
    assert "t = 1" in ax.get_title()  # drawn back at the end: shown at the largest force


@needs_gmsh
def test_every_label_lies_inside_its_figure(vickers):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    for name, fig in vickers.figures().items():
        canvas = FigureCanvasAgg(fig)
        canvas.draw()  # the labels are placed when drawn
        renderer = canvas.get_renderer()
        for ax in fig.axes:
            for text in (ax.xaxis.label, ax.yaxis.label):
                box = text.get_window_extent(renderer)
                assert box.x0 >= 0 and box.y0 >= 0, (name, text.get_text())
                assert box.x1 <= fig.bbox.width and box.y1 <= fig.bbox.height, name


@needs_gmsh
def test_a_frictionless_run_names_no_stick(vickers):
    assert vickers.summary["frictionless"]
    assert "stick" not in one_line(vickers.summary)


@needs_gmsh
def test_the_plastic_zone_is_drawn_from_the_section_s_elements(vickers):
    from matplotlib.figure import Figure

    fig = Figure()
    panels = fig.subplots(1, 2)
    assert vickers.figure("plastic_zone", ax=panels) is fig
    end = vickers.fields()
    snap = vickers.snapshot()
    centre, e1, up = fig3d._section_plane(vickers.scene, snap)
    cells, _ = fig3d.section(vickers.nodes, vickers.tetrahedra, centre, e1, up)
    stress, strain = (panel.collections[0].get_array() for panel in panels)
    assert np.array_equal(stress, end["von_mises"][cells])
    assert np.array_equal(strain, end["plastic_strain"][cells]) and strain.max() > 0


@needs_gmsh
def test_the_result_s_views_in_3d(vickers):
    from matplotlib.figure import Figure

    ev = vickers.events
    assert ev.dtype.names[-3:] == ("x", "y", "z")
    pair = ev["entity_kind"] == "pair"
    assert np.array_equal(
        np.column_stack([ev["x"], ev["y"], ev["z"]])[pair],
        vickers.scene.pair_xy[ev["entity"][pair]],
    )
    prof = vickers.profile(1.0, stage=1)
    assert np.array_equal(np.column_stack([prof["x"], prof["y"], prof["z"]]), prof["position"])
    assert vickers.elements is vickers.tetrahedra and vickers.tetrahedra.shape[1] == 4
    with pytest.raises(AttributeError, match="r.tetrahedra"):
        vickers.triangles
    assert "DOFs" in vickers._repr_html_()
    fig = Figure()
    ax = fig.subplots()
    assert vickers.figure("contact_area", ax=ax) is fig and ax.lines
    with pytest.raises(ValueError, match="draws 2 panel"):
        vickers.figure("plastic_zone", ax=Figure().subplots())


@needs_gmsh
@pytest.mark.filterwarnings("error")
def test_a_contact_of_one_node_has_its_peak_without_a_warning(vickers):
    """A pyramid touching with its tip alone closes one node: the peak fit has no spacing to
    measure (numpy's 'Mean of empty slice' leaked here) and gives that node's pressure."""
    from slipstep.measures.contact_faces import recovered_peak

    prof = vickers.profile(1.0, stage=1)
    one = {
        **prof,
        "status": np.where(np.arange(len(prof["status"])) == 0, 2, 0),
        "x": prof["position"],
    }
    assert recovered_peak(vickers.scene, one, 0, 0.01) == prof["pressure"][0]
