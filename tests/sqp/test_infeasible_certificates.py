"""A backend's certificate of primal infeasibility ends the search for a QP answer (the elastic QP is the remedy)."""

from __future__ import annotations

import numpy as np
import pytest
import qpsolvers

import sqp.qp_call as qp_call

pytest.importorskip("clarabel")


def _infeasible_qp():
    # x1 + x2 <= -1 and x1 + x2 >= 1
    P, q = np.eye(2), np.ones(2)
    G, h = np.array([[1.0, 1.0], [-1.0, -1.0]]), np.array([-1.0, -1.0])
    return P, q, G, h, np.zeros((0, 2)), np.zeros(0)


def test_clarabel_primal_infeasible_stops_the_fallbacks(monkeypatch):
    calls = []
    solve = qp_call._backends.solve_problem

    def recorded(problem, solver, **kw):
        calls.append(solver)
        return solve(problem, solver=solver, **kw)

    monkeypatch.setattr(qp_call._backends, "solve_problem", recorded)
    P, q, G, h, E, e = _infeasible_qp()
    sol, reason = qp_call.solve_qp((("clarabel", {}), ("quadprog", {})), P, q, G, h, E, e, None, None, None, 1.0)
    assert sol is None and reason == "QP infeasible"
    assert calls == ["clarabel"]  # no retry with looser tolerances, no next backend


@pytest.mark.parametrize("status, certified", [
    ("PrimalInfeasible", True), ("AlmostPrimalInfeasible", False), ("DualInfeasible", False),
    ("MaxIterations", False)])
def test_only_a_primal_infeasibility_certificate_counts(status, certified):
    import clarabel

    P, q, G, h, E, e = _infeasible_qp()
    sol = qpsolvers.Solution(qpsolvers.Problem(P, q, G, h))
    sol.extras = {"status": getattr(clarabel.SolverStatus, status)}
    assert qp_call._declared_infeasible(sol) is certified


@pytest.mark.parametrize("status, certified", [("primal infeasible", True), ("dual infeasible", False),
                                               ("primal infeasible inaccurate", False)])
def test_osqp_style_info_status(status, certified):
    class Info:
        pass

    info = Info()
    info.status = status
    P, q, G, h, E, e = _infeasible_qp()
    sol = qpsolvers.Solution(qpsolvers.Problem(P, q, G, h))
    sol.extras = {"info": info}
    assert qp_call._declared_infeasible(sol) is certified
