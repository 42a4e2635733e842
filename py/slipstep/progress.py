"""Progress of a run as the engine reports it, and the ways to show it.

The event loop runs in Rust with the GIL released.  Every ``REPORT_INTERVAL_S`` (0.1 s)
between two increments it attaches to the interpreter and calls the progress callback with
``(events, steps, t)``; after a Ctrl-C it attaches at the next increment and stops.  :class:`Reporter`
turns what :func:`slipstep.run` is given as ``progress`` into that callback:

- ``False`` / ``None``: no reports (Ctrl-C still stops the run);
- ``True``: a tqdm bar over the path time t (``tqdm.auto``: a widget in Jupyter, a text bar on
  stderr in a terminal);
- a callable ``f(progress: Progress)``: called with a :class:`Progress`; returning ``False``
  stops the run like Ctrl-C (the partial result is returned, ``stop.kind == "interrupted"``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from .derived import final_time

# Seconds between two reports of a running engine (0: after every increment).
REPORT_INTERVAL_S = 0.1


@dataclass(frozen=True)
class Progress:
    """One report of a running engine."""

    events: int          # events so far (rows of result["events"])
    steps: int           # increments so far
    t: float             # path time reached (the load fraction for one stage)
    n_stages: int        # the path ends at t = n_stages
    elapsed: float       # seconds since the engine started

    @property
    def fraction(self) -> float:
        """How far along the load path, 0..1."""
        return self.t / self.n_stages if self.n_stages else 0.0


class Bar:
    """A tqdm bar over the path time t, with the event and increment counts beside it."""

    def __init__(self, name: str, n_stages: int):
        from tqdm.auto import tqdm

        self.bar = tqdm(total=float(n_stages), desc=name, unit="t", leave=True,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| t = {n:.3g}/{total:g} "
                                   "[{elapsed}{postfix}]")

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


class Reporter:
    """What one run reports to: ``callback`` is the engine's (False for none), ``finish``
    closes a bar with the run's final state (with None, after a failure, it only closes).

    The bar appears with the first report, so a run shorter than one report interval (and an
    input error found before the first increment) prints nothing."""

    def __init__(self, progress, name: str, n_stages: int):
        self.start, self.name, self.n_stages = time.perf_counter(), name, n_stages
        self.bar, self.user = None, None
        if progress not in (None, False, True) and not callable(progress):
            raise TypeError(f"progress = {progress!r}: give True (a bar), False, or a callable "
                            f"f(progress: slipstep.progress.Progress)")
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
            self.bar = Bar(self.name, self.n_stages)
        return self.bar(p)

    def finish(self, result: dict | None) -> None:
        """Close the bar, showing the run's final state (a callable gets no final report: the
        result is in the caller's hands)."""
        if self.bar and result is not None:
            p = self.progress(len(result["events"]["step"]),
                              len(result["steps"]["load_fraction"]), final_time(result))
            self.bar.close(p, result["stop"]["kind"])
        elif self.bar:
            self.bar.bar.close()
