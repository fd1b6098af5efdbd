"""The "structure limit" row of the peers benchmark (``benchmarks/_structure_limit.py``): plain Newton-KKT steps
reach the same answer as ours from the same start, and refuse programs with inequality rows."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import _guidewire as G  # noqa: E402
import _structure_limit as L  # noqa: E402

import guidewire  # noqa: E402

SCENES = guidewire.paper_scenes()


@pytest.mark.parametrize(("name", "bars"), [("table2_pi_4", 60), ("table1_pi_4", 400)])
def test_the_structure_limit_reaches_our_answer_in_newton_steps(name, bars):
    case = G.make_case(SCENES[name], bars=bars)
    assert L.applicable(case.problem)
    limit = L.run_structure_limit(case.problem)
    ours = G.run_ours(case)
    assert limit["success"] and ours["success"], (limit["message"], ours["message"])
    assert limit["nit"] <= 5  # quadratic convergence from the elastica-like start
    energy = case.problem.fun(limit["x"])
    assert energy == pytest.approx(case.problem.fun(ours["x"]), rel=1e-9)
    assert np.max(np.abs(limit["x"] - ours["x"])) < 1e-6  # the same shape, not only the same energy


def test_the_structure_limit_refuses_wall_scenes():
    case = G.make_case(SCENES["fig6a"], bars=30)
    assert not L.applicable(case.problem)
    with pytest.raises(ValueError, match="equality-only"):
        L.run_structure_limit(case.problem)
