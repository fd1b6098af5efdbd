"""DAQP in the coordinates of the Hessian's Cholesky factor (:data:`sqp.backends.LDP_MIN_VARIABLES`): the same
step and multipliers as DAQP on the QP as it is, and the cases left as they are."""

from __future__ import annotations

import numpy as np
import pytest
import qpsolvers

import guidewire
from sqp import backends
from sqp.hessian import CholeskyHessian

pytest.importorskip("daqp")


def _qp(n=100, m_ineq=60, m_eq=3, seed=0, bounds=False):
    rng = np.random.default_rng(seed)
    M = rng.standard_normal((n, n))
    P = M @ M.T / n + np.eye(n)
    G = rng.standard_normal((m_ineq, n))
    h = np.abs(rng.standard_normal(m_ineq)) * 0.1  # the unconstrained minimiser violates many of these
    A = rng.standard_normal((m_eq, n)) if m_eq else None
    b = rng.standard_normal(m_eq) if m_eq else None
    q = 3.0 * rng.standard_normal(n)
    lb, ub = (-np.ones(n), np.ones(n)) if bounds else (None, None)
    return P, q, G, h, A, b, lb, ub


def _both(monkeypatch, P, q, G, h, A, b, lb, ub, initvals=None):
    new = backends._daqp(qpsolvers.Problem(P, q, G, h, A, b, lb, ub), initvals)
    monkeypatch.setattr(backends, "LDP_MIN_VARIABLES", 10**9)
    old = backends._daqp(qpsolvers.Problem(P, q, G, h, A, b, lb, ub), initvals)
    monkeypatch.undo()
    return new, old


@pytest.mark.parametrize("factored", [False, True])
def test_same_step_and_multipliers(monkeypatch, factored):
    P, q, G, h, A, b, lb, ub = _qp()
    if factored:
        P = CholeskyHessian.wrap(P, np.linalg.cholesky(P))
    assert backends._ldp_factor(P, 100, 0, 3) is not None
    new, old = _both(monkeypatch, P, q, G, h, A, b, lb, ub)
    assert new.found and old.found
    assert np.sum(old.z > 1e-9) >= 5  # several rows active: a real active-set solve
    np.testing.assert_allclose(new.x, old.x, atol=1e-10)
    np.testing.assert_allclose(new.z, old.z, atol=1e-9)
    np.testing.assert_allclose(new.y, old.y, atol=1e-9)
    assert new.obj == pytest.approx(old.obj, rel=1e-10)
    # warm start from the answer: the same again
    warm, _ = _both(monkeypatch, P, q, G, h, A, b, lb, ub, initvals=old.x)
    np.testing.assert_allclose(warm.x, old.x, atol=1e-10)


def test_left_as_it_is():
    P, q, G, h, A, b, lb, ub = _qp(n=60, m_eq=0)
    assert backends._ldp_factor(P, 60, 0, 0) is not None
    assert backends._ldp_factor(P, 60, 60, 0) is None  # bounds on the variables would become dense rows
    assert backends._ldp_factor(P, 60, 0, 8) is None  # many equality rows: DAQP's own reduction is faster
    small = P[:10, :10]
    assert backends._ldp_factor(small, 10, 0, 0) is None  # small QPs (Hock-Schittkowski) as they were
    assert backends._ldp_factor(-P, 60, 0, 0) is None  # not positive definite: DAQP's own handling


def test_bounded_qp_is_solved_as_before(monkeypatch):
    new, old = _both(monkeypatch, *_qp(n=60, m_eq=0, bounds=True))
    assert new.found and old.found
    np.testing.assert_array_equal(new.x, old.x)


def test_wall_scene_same_answer(monkeypatch):
    """Fig. 6a at 120 bars (reduced program, dense wall rows): the same shape, energy and iterations."""
    scene = guidewire.paper_scenes()["fig6a"]
    sol = guidewire.solve(scene, bars=120)
    monkeypatch.setattr(backends, "LDP_MIN_VARIABLES", 10**9)
    ref = guidewire.solve(scene, bars=120)
    assert sol.success and ref.success and sol.layout == "reduced"
    assert sol.iterations == ref.iterations
    assert sol.energy == pytest.approx(ref.energy, rel=1e-11)
    np.testing.assert_allclose(sol.nodes, ref.nodes, atol=1e-10)
