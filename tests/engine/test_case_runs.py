"""End-to-end runs of the shipped cases through the compiled engine."""

from __future__ import annotations

import json

import pytest

from slipstep import cli, run_case

# Physics of these runs is asserted in test_hertz.py, test_two_blocks.py, test_plasticity_hertz.py;
# here: the files a run writes and the command line.


@pytest.fixture(scope="module")
def hertz_frictionless(tmp_path_factory):
    out = tmp_path_factory.mktemp("hertz")
    result, summary = run_case(None, out=out)
    return out, result, summary


def test_hertz_output_files(hertz_frictionless):
    out, _, s = hertz_frictionless
    for name in (
        "summary.json",
        "events.csv",
        "contact_profile.csv",
        "results.xdmf",
        "results.h5",
        "contact_interface.png",
        "contact_growth.png",
    ):
        assert (out / name).stat().st_size > 0, name
    assert json.loads((out / "summary.json").read_text())["n_events"] == s["n_events"]


def test_cli_run_default_case(tmp_path, capsys):
    assert cli.main(["run", "--out", str(tmp_path), "--quiet", "--set", "output.xdmf=false"]) == 0
    assert (tmp_path / "summary.json").exists()
