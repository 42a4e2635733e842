"""How ``progress=True`` shows itself (slipstep.progress.display): a tqdm bar when stderr is a
terminal; in a log or a pipe one line at the first report and one at the end, with no bar
frames (a ``\\r`` in a log file).  The engine's reports are driven by hand, so nothing here
depends on how long a run takes.  In a Jupyter kernel: tests/package/test_examples.py."""

from __future__ import annotations

import io
import re

import pytest

from slipstep.progress import Bar, Notes, Reporter, display, in_kernel

RESULT = {
    "events": {"step": [0] * 548},
    "steps": {"load_fraction": [0.0] * 120},
    "stop": {"kind": "interrupted", "t": 0.2},
}


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _reported(monkeypatch, stderr) -> str:
    """Two engine reports and the end of the run, as slipstep.runner.solve drives them."""
    monkeypatch.setattr("sys.stderr", stderr)
    reporter = Reporter(True, "hertz", 1)
    assert reporter.report(100, 20, 0.1) is None and reporter.report(239, 50, 0.15) is None
    reporter.finish(RESULT)
    return stderr.getvalue()


def test_a_log_gets_a_start_and_an_end_line(monkeypatch):
    text = _reported(monkeypatch, io.StringIO())
    assert "\r" not in text
    start, end = text.splitlines()
    assert start == "hertz: running, t = 0.1 of 1 after 100 events"
    assert re.fullmatch(
        r"hertz: interrupted at t = 0.2 of 1: 548 events, 120 increments, " r"\d+\.\d s", end
    ), end


def test_a_terminal_gets_the_bar(monkeypatch):
    text = _reported(monkeypatch, Terminal())
    frames = text.split("\r")
    assert len(frames) > 2  # redrawn in place
    assert "hertz: interrupted" in frames[-1] and "548 events, 120 increments" in text


def test_the_display_follows_stderr(monkeypatch):
    assert not in_kernel()  # pytest is no Jupyter kernel
    monkeypatch.setattr("sys.stderr", io.StringIO())
    assert isinstance(display("x", 1), Notes)
    monkeypatch.setattr("sys.stderr", Terminal())
    bar = display("x", 1)
    assert isinstance(bar, Bar)
    bar.abandon()
    monkeypatch.setattr("sys.stderr", None)  # pythonw, a daemon: no stderr at all
    assert isinstance(display("x", 1), Notes)


@pytest.mark.parametrize("answer", [None, False, True])
def test_a_callable_gets_the_reports_and_its_answer_is_passed_back(monkeypatch, answer):
    """The engine's callback contract: (events, steps, t), the user's answer returned."""
    seen = []
    reporter = Reporter(lambda p: seen.append(p) or answer, "x", 2)
    assert reporter.report(3, 2, 1.5) is answer
    assert (seen[0].events, seen[0].steps, seen[0].t, seen[0].fraction) == (3, 2, 1.5, 0.75)
