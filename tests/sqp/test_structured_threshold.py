"""The structured KKT path between ``STRUCTURED_MIN`` and ``DENSE_LIMIT`` variables (equality-only problems): the
same answers as the dense path it replaces there, and a fallback convexification whose shift and weight the Hessian
strategy keeps, as when ``convexify`` made them itself."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import guidewire
import guidewire.program.reduced
import sqp
from sqp import hessian, hessian_strategy, iterate, structured

N = 200


def _force_dense(monkeypatch):
    """The old rule: every Hessian dense up to DENSE_LIMIT (no structured path below it)."""
    monkeypatch.setattr(hessian, "STRUCTURED_MIN", hessian.DENSE_LIMIT)
    monkeypatch.setattr(iterate, "STRUCTURED_MIN", hessian.DENSE_LIMIT)


def _count_factorisations(monkeypatch):
    calls = []
    real = structured.factor_symmetric

    def spy(W):
        calls.append(W.shape[0])
        return real(W)

    monkeypatch.setattr(structured, "factor_symmetric", spy)
    return calls


def _sphere_projection():
    """min |x − a|² s.t. |x|² = 1 (answer a/|a|), sparse Hessians: W = 2(1 − λ) I, indefinite for λ > 1."""
    a = np.linspace(1.0, 2.0, N)
    eye = sp.identity(N, format="csc")
    con = {"type": "eq", "fun": lambda x: np.array([x @ x - 1.0]), "jac": lambda x: 2.0 * x[None, :],
           "hess": lambda x, v: 2.0 * v[0] * eye}
    return a, dict(fun=lambda x: float((x - a) @ (x - a)), jac=lambda x: 2.0 * (x - a), hess=lambda x: 2.0 * eye,
                   constraints=[con])


def test_sphere_projection_same_answer_through_the_structured_fallback(monkeypatch):
    """Warm-started with λ = 5 the first W = −8 I is not convex on the row's null space: the structured path's
    inertia test sends the QP to the general convexification (an identity shift), whose shift the strategy keeps."""
    a, kw = _sphere_projection()
    x0 = np.full(N, 1.0 / np.sqrt(N))
    kept = []
    real_multipliers = hessian_strategy.ConvexifiedExact.multipliers

    def spy(self, st, qp):
        factored = self.factored
        out = real_multipliers(self, st, qp)
        if factored is not None and factored.convexification is not None:
            kept.append((factored.convexification, self.shift, self.weight))
        return out

    monkeypatch.setattr(hessian_strategy.ConvexifiedExact, "multipliers", spy)
    calls = _count_factorisations(monkeypatch)
    res = sqp.minimize(x0=x0, multipliers0=[np.array([5.0])], **kw)
    assert res.success, res.message
    np.testing.assert_allclose(res.x, a / np.linalg.norm(a), atol=1e-9)
    assert calls and all(n == N for n in calls)  # the structured path served it
    assert kept and kept[0][0][0] > 0.0 and kept[0][1:] == kept[0][0]  # the fallback's shift, kept
    monkeypatch.undo()
    _force_dense(monkeypatch)
    dense = sqp.minimize(x0=x0, multipliers0=[np.array([5.0])], **kw)
    assert dense.success and dense.nit == res.nit
    np.testing.assert_allclose(res.x, dense.x, atol=1e-12)


@pytest.mark.parametrize("name", ["table1_pi_4", "table2_minus_pi_4", "table4"])
def test_contact_scene_at_200_bars_same_answer_as_the_dense_path(monkeypatch, name):
    scene = guidewire.paper_scenes()[name]
    calls = _count_factorisations(monkeypatch)
    sol = guidewire.solve(scene, bars=N)
    assert sol.success, sol.message
    assert calls  # structured: W factorised as a sparse banded matrix
    monkeypatch.undo()
    _force_dense(monkeypatch)
    monkeypatch.setattr(guidewire.program.reduced, "STRUCTURED_MIN", hessian.DENSE_LIMIT)
    calls = _count_factorisations(monkeypatch)
    dense = guidewire.solve(scene, bars=N)
    assert not calls and dense.success
    assert sol.iterations == dense.iterations
    assert sol.energy == pytest.approx(dense.energy, rel=1e-10)
    np.testing.assert_allclose(sol.nodes, dense.nodes, atol=1e-9)


def test_wall_scene_below_dense_limit_keeps_the_dense_path(monkeypatch):
    """Inequality rows (walls) keep the dense convexification below DENSE_LIMIT: no structured factorisation."""
    calls = _count_factorisations(monkeypatch)
    sol = guidewire.solve(guidewire.paper_scenes()["fig6a"], bars=N)
    assert sol.success and sol.layout == "reduced" and not calls
