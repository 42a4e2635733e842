"""Progress of a run as the engine reports it, and the ways to show it.

The event loop runs in Rust with the GIL released.  Every ``REPORT_INTERVAL_S`` (0.1 s)
between two increments it attaches to the interpreter and calls the progress callback with
``(events, steps, t)``; after a Ctrl-C it attaches at the next increment and stops.  :class:`Reporter`
turns what :func:`slipstep.run` is given as ``progress`` into that callback:

- ``False`` / ``None``: no reports (Ctrl-C still stops the run);
- ``True``: progress over the path time t, shown where the run's output goes
  (:func:`display`): a tqdm widget in a Jupyter kernel with ipywidgets (the ``notebook``
  extra), a tqdm bar when stderr is a terminal, and otherwise (a log, a pipe, a kernel without
  ipywidgets) one line when the first report comes and one at the end, no bar frames;
- a callable ``f(progress: Progress)``: called with a :class:`Progress`; returning ``False``
  stops the run like Ctrl-C (the partial result is returned, ``stop.kind == "interrupted"``).
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass

from .output.history import final_time

# Seconds between two reports of a running engine (0: after every increment).
REPORT_INTERVAL_S = 0.1


@dataclass(frozen=True)
class Progress:
    """One report of a running engine."""

    events: int  # events so far (rows of result["events"])
    steps: int  # increments so far
    t: float  # path time reached (the load fraction for one stage)
    n_stages: int  # the path ends at t = n_stages
    elapsed: float  # seconds since the engine started

    @property
    def fraction(self) -> float:
        """How far along the load path, 0..1."""
        return self.t / self.n_stages if self.n_stages else 0.0


class Bar:
    """A tqdm bar over the path time t, with the event and increment counts beside it: a
    widget in a notebook, else text on stderr."""

    def __init__(self, name: str, n_stages: int, notebook: bool = False):
        if notebook:
            from tqdm.notebook import tqdm
        else:
            from tqdm.std import tqdm

        self.bar = tqdm(
            total=float(n_stages),
            desc=name,
            unit="t",
            leave=True,
            file=sys.stderr,
            bar_format="{desc}: {percentage:3.0f}%|{bar}| t = {n:.3g}/{total:g} "
            "[{elapsed}{postfix}]",
        )

    def __call__(self, p: Progress) -> None:
        self.bar.n = p.t
        self.bar.set_postfix_str(f"{p.events} events, {p.steps} increments", refresh=False)
        self.bar.refresh()

    def close(self, p: Progress, stop: str) -> None:
        """The final state; the description says how the run stopped unless it completed."""
        if stop != "completed":
            self.bar.set_description_str(f"{self.bar.desc}: {stop}", refresh=False)
        self(p)
        self.bar.close()

    def abandon(self) -> None:
        """Close after a failure (the error is reported by the caller)."""
        self.bar.close()


class Notes:
    """Progress for a log: one line on stderr at the first report, one at the end; no bar
    frames (``\\r``) in a file or a pipe.  ``hint`` ends the first line."""

    def __init__(self, name: str, hint: str = ""):
        self.name, self.hint, self.started = name, hint, False

    def __call__(self, p: Progress) -> None:
        if not self.started:
            self.note(
                f"running, t = {p.t:.3g} of {p.n_stages} after {p.events} events" f"{self.hint}"
            )
            self.started = True

    def close(self, p: Progress, stop: str) -> None:
        self.note(
            f"{stop} at t = {p.t:.4g} of {p.n_stages}: {p.events} events, {p.steps} "
            f"increments, {p.elapsed:.1f} s"
        )

    def note(self, text: str) -> None:
        if sys.stderr is not None:  # None: pythonw, a daemon
            print(f"{self.name}: {text}", file=sys.stderr, flush=True)

    def abandon(self) -> None:
        """After a failure: the caller's error line is the end note."""


def in_kernel() -> bool:
    """Whether this is a Jupyter kernel (IPython's kernel app), where stderr is no terminal
    but a notebook can show a widget."""
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython else None
    return shell is not None and "IPKernelApp" in shell.config


def display(name: str, n_stages: int):
    """How ``progress=True`` shows itself here (see the module's documentation)."""
    if in_kernel():
        from tqdm.notebook import IProgress  # None without ipywidgets

        if IProgress is not None:
            return Bar(name, n_stages, notebook=True)
        return Notes(name, " (a progress bar needs ipywidgets: pip install ipywidgets)")
    if getattr(sys.stderr, "isatty", lambda: False)():
        return Bar(name, n_stages)
    return Notes(name)


class Reporter:
    """What one run reports to: ``callback`` is the engine's (False for none), ``finish``
    closes the display with the run's final state (with None, after a failure, it only
    closes).

    The display appears with the first report, so a run shorter than one report interval (and
    an input error found before the first increment) prints nothing."""

    def __init__(self, progress, name: str, n_stages: int):
        self.start, self.name, self.n_stages = time.perf_counter(), name, n_stages
        self.bar, self.user = None, None
        if progress not in (None, False, True) and not callable(progress):
            raise TypeError(
                f"progress = {progress!r}: give True (a bar), False, or a callable "
                f"f(progress: slipstep.progress.Progress)"
            )
        self.wants_bar = progress is True
        self.user = progress if callable(progress) and progress is not True else None
        self.callback = self.report if (self.wants_bar or self.user) else False

    def progress(self, events: int, steps: int, t: float) -> Progress:
        return Progress(events, steps, t, self.n_stages, time.perf_counter() - self.start)

    def report(self, events: int, steps: int, t: float):
        """The engine's callback; the user's answer (False = stop) is passed back."""
        p = self.progress(events, steps, t)
        if self.user:
            return self.user(p)
        if self.bar is None:
            self.bar = display(self.name, self.n_stages)
        return self.bar(p)

    def finish(self, result: dict | None) -> None:
        """Close the display, showing the run's final state (a callable gets no final report:
        the result is in the caller's hands)."""
        if self.bar and result is not None:
            p = self.progress(
                len(result["events"]["step"]),
                len(result["steps"]["load_fraction"]),
                final_time(result),
            )
            self.bar.close(p, result["stop"]["kind"])
        elif self.bar:
            self.bar.abandon()
