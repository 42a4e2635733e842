"""The frame every figure of a run is drawn in: a matplotlib Figure outside pyplot with fixed
margins, the caller's axes, titles, unit labels, the status colours, writing a PNG.  Shared by
:mod:`slipstep.figures` (the plane's and the load path's figures), :mod:`slipstep.figures.solid`
and :mod:`slipstep.figures.loads`, which import it and not each other.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

STATUS_COLOURS = {0: "0.6", 1: "tab:blue", 2: "tab:red"}
STATUS_LABELS = {0: "open", 1: "stick", 2: "slip"}
DPI = 110  # 7 x 6 in -> 770 x 660 px


def new_figure(width: float, height: float, layout: str | None = None, **margins):
    """A matplotlib Figure outside pyplot (no backend switch, no global figure list) with fixed
    margins (fractions of the figure, ``subplots_adjust`` keywords), or with ``layout``
    ("constrained": matplotlib's layout engine, slower)."""
    import warnings

    with warnings.catch_warnings():
        # Debian's mpl_toolkits (3D axes) sits beside the venv's matplotlib; only 2D plots here
        warnings.filterwarnings("ignore", message="Unable to import Axes3D")
        from matplotlib.figure import Figure
    if layout is not None:
        return Figure(figsize=(width, height), dpi=DPI, constrained_layout=layout == "constrained")
    fig = Figure(figsize=(width, height), dpi=DPI)
    fig.subplots_adjust(**{"left": 0.13, "right": 0.96, "bottom": 0.1, "top": 0.9, **margins})
    return fig


class Plots:
    """pyplot's figure-making calls that the studies' figures use (``figure``, ``subplots``,
    ``close``, ``get_cmap``) on the object API: same calls, no pyplot state, no backend."""

    @staticmethod
    def figure(figsize=(6.4, 4.8), constrained_layout: bool = False):
        return new_figure(*figsize, layout="constrained" if constrained_layout else "none")

    @staticmethod
    def subplots(
        nrows: int = 1,
        ncols: int = 1,
        figsize=(6.4, 4.8),
        constrained_layout: bool = False,
        **kwargs,
    ):
        fig = Plots.figure(figsize, constrained_layout)
        return fig, fig.subplots(nrows, ncols, **kwargs)

    @staticmethod
    def close(fig) -> None:
        """Nothing to release: no pyplot registry holds the figure."""

    @staticmethod
    def get_cmap(name: str):
        import matplotlib

        return matplotlib.colormaps[name]


def preload() -> None:
    """Pay the first figure's fixed cost (importing matplotlib's figure and Agg modules, PIL,
    loading the font: ~0.2-0.3 s) without drawing anything that is kept; slipstep.runner calls
    it in a thread while the engine runs with the GIL released."""
    import io

    fig = new_figure(1, 1)
    fig.text(0.5, 0.5, "0")
    fig.savefig(io.BytesIO(), format="png")


def finish(fig, path: Path | None):
    """Write ``fig`` to ``path`` (PNG, Agg) and return the path; None: return the Figure.

    Every title is pinned at the top of its axes (y = 1): matplotlib otherwise measures the
    tick labels of every axes at each draw to place them (~1/5 of the drawing time here),
    and no axes here has tick labels on top."""
    for ax in fig.axes:
        ax.set_title(ax.get_title(), y=1.0, fontsize=ax.title.get_fontsize())
    if path is None:
        return fig
    fig.savefig(path, dpi=DPI)
    return Path(path)


def given_axes(ax, n: int, what: str) -> list:
    """The caller's axes for a figure of ``n`` panels: one Axes, or a sequence of ``n`` (from
    their own figure: ``fig.subplots(n)``), as a list."""
    axes = list(ax) if isinstance(ax, (list, tuple, np.ndarray)) else [ax]
    axes = list(np.ravel(np.asarray(axes, dtype=object)))
    if len(axes) != n or not all(hasattr(a, "figure") for a in axes):
        raise ValueError(
            f"ax = {ax!r}: the {what} figure draws {n} panel(s): give "
            f"{'an Axes' if n == 1 else f'{n} Axes, e.g. fig.subplots({n})'}"
        )
    return axes


def title(fig, axes: list, text: str, own: bool, **kwargs) -> None:
    """The figure's title: over its own figure, over the first of the caller's axes."""
    if own:
        fig.suptitle(text, fontsize=10, **kwargs)
    else:
        axes[0].set_title(text, fontsize=10)


def label(text: str, scene, kind: str) -> str:
    """``text [unit]`` with the case's unit of ``kind`` (length, force, stress), if known."""
    unit = scene.case.units.get(kind)
    return f"{text} [{unit}]" if unit else text
