"""Every shipped 3D case (conftest.shipped_cases(3)) is run by a closed-form test of this folder:
its file name appears in one of them (the 3D cases need meshes coarsened for CI, so there is no
one loop over them as tests/physics/test_balance.py has for the 2D ones; each test checks the
equilibrium of its run's snapshots from the stresses)."""

from __future__ import annotations

from pathlib import Path

from conftest import shipped_cases


def test_every_shipped_3d_case_has_its_closed_form_test():
    here = Path(__file__).parent
    text = "".join(p.read_text() for p in here.glob("test_*.py") if p.name != Path(__file__).name)
    untested = [p.name for p in shipped_cases(3) if p.name not in text]
    assert not untested, f"3D cases no test in {here} runs: {untested}"
