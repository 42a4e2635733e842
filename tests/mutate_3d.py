"""Mutation runs of the 3D tests (issue 38.8), opt-in:

    SLIPSTEP_MUTATE_E=1.05 PYTHONPATH=tests python -m pytest -p mutate_3d tests/physics3d
    SLIPSTEP_MUTATE_MU=0.6667 PYTHONPATH=tests python -m pytest -p mutate_3d tests/physics3d

Every scene in space the tests build (``analysis.dimension = 3``) gets every body's E times
SLIPSTEP_MUTATE_E and every contact's mu times SLIPSTEP_MUTATE_MU, as if the engine or the front
had them wrong; planar and axisymmetric scenes (the references some 3D tests compare with) are
left as they are.  A test that still passes does not see that error.  (The tests that run a
mutant of their own on purpose then run a doubly mutated one: ignore them here.)
"""

from __future__ import annotations

import copy
import os

E_FACTOR = float(os.environ.get("SLIPSTEP_MUTATE_E", "1"))
MU_FACTOR = float(os.environ.get("SLIPSTEP_MUTATE_MU", "1"))


def mutated(case):
    if case.dimension != 3:
        return case
    case = copy.deepcopy(case)
    for body in case.data["body"]:
        body["material"]["E"] *= E_FACTOR
    for contact in case.data.get("contact", []):
        contact["mu"] *= MU_FACTOR
    return case


def pytest_configure(config):
    from slipstep.build import section as build
    from slipstep import runner

    original = build.build_scene

    def build_scene(case, *args, **kwargs):
        return original(mutated(case), *args, **kwargs)

    build.build_scene = runner.build_scene = build_scene


def pytest_report_header(config):
    return f"mutate_3d: scenes in space with E x {E_FACTOR}, mu x {MU_FACTOR}"
