"""The engine on the Hock–Schittkowski collection: every problem solved to the collection's strict criterion.

A problem the engine does not solve is an explicit expected failure with its reason (``EXPECTED_FAILURES``), never
deleted. Success must never be claimed at a point that is infeasible or not a KKT point (checked independently).
"""

from __future__ import annotations

import numpy as np
import pytest

import sqp
from sqp.problems.hock_schittkowski import BUILDERS
from sqp.problems.judge import judge

#: name -> why the engine does not solve it (kept visible as xfail, strict: an unexpected pass is reported).
EXPECTED_FAILURES: dict[str, str] = {
    "HS13": "no constraint qualification holds at the minimiser (1, 0) (a cusp); the line search stalls just short of "
            "it (feasible, f within 4e-5 of f*) without a KKT certificate, so the status is LINE_SEARCH, not success",
    "HS16": "from x0 (clipped to (-0.5, 1)) the iterates reach the local minimum (-0.5, 1/sqrt 2), f = 23.14; "
            "SLSQP and trust-constr stop there too",
    "HS54": "badly scaled (variables from 1e-3 to 1e8): BFGS stalls at f = -0.8674 with scaled stationarity 0.14 and "
            "stops with SMALL_STEP (SLSQP and trust-constr claim success at f = 0)",
    "HS59": "converges to the local minimum f = -6.7495, as SLSQP and trust-constr do",
    "HS97": "converges to the local minimum f = 4.0712 (SLSQP reaches 3.1358 but claims no success)",
    "HS98": "converges to the local minimum f = 4.0712 (SLSQP reaches f* = 3.1358)",
    "HS116": "converges to the local minimum f = 97.591 (f* = 97.588), a KKT point, since DAQP meets the rows of the "
             "linearisation to 1e-9 instead of its default 1e-6 (which reached f* on this path and, on others, left "
             "steps that are no descent direction of the merit function)",
}


def _params():
    for name in BUILDERS:
        marks = [pytest.mark.xfail(reason=EXPECTED_FAILURES[name], strict=True)] if name in EXPECTED_FAILURES else []
        yield pytest.param(name, marks=marks, id=name)


def _starts_outside_bounds(prob) -> bool:
    if prob.bounds is None:
        return False
    lo = np.array([-np.inf if b[0] is None else b[0] for b in prob.bounds], dtype=float)
    hi = np.array([np.inf if b[1] is None else b[1] for b in prob.bounds], dtype=float)
    x0 = np.asarray(prob.x0, dtype=float)
    return bool(np.any(x0 < lo) or np.any(x0 > hi))


def _minimize(prob):
    """Solve from the collection's x0; several HS problems start outside their bounds: the result records it."""
    res = sqp.minimize(prob.fun, prob.x0, jac=prob.jac, bounds=prob.bounds, constraints=prob.constraints)
    assert (res.x0_clipped.size > 0) == _starts_outside_bounds(prob)
    return res


@pytest.mark.parametrize("name", list(_params()))
def test_solved(name):
    prob = BUILDERS[name]()
    res = _minimize(prob)
    verdict = judge(prob, res.x)
    assert not verdict.false_success(res.success), f"false success: {res.message} {verdict}"
    assert res.maxcv == pytest.approx(prob.max_violation(res.x), abs=1e-12)
    assert verdict.solved, f"{res.message} f={res.fun} f*={prob.fstar} maxcv={res.maxcv}"
    assert res.success, res.message
    level = 1e-8 if res.status == sqp.Status.SUCCESS.code else 1e-6  # ACCEPTABLE: rounding stopped progress
    assert res.kkt["stationarity"] <= level and res.kkt["complementarity"] <= level
    assert res.kkt["feasibility"] <= 1e-8 * max(1.0, float(np.max(np.abs(res.x))))
    assert verdict.kkt_point
    assert res.x.shape == (prob.n,)
    assert res.fun == pytest.approx(prob.fun(res.x), rel=1e-12, abs=1e-14)


def test_expected_failures_are_honest():
    """The problems not solved still never claim success at an infeasible or non-stationary point."""
    false = []
    for name in EXPECTED_FAILURES:
        prob = BUILDERS[name]()
        res = _minimize(prob)
        if judge(prob, res.x).false_success(res.success):
            false.append(name)
    assert false == []
