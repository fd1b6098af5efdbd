"""``convexify_inequalities`` given row indices: the augmented-Lagrangian term covers those inequalities where they
hold, and where that leaves ``W`` indefinite every held row joins it before an identity shift is tried.

The family: ``f = −a x₁²/2 + |x₂..x₄|²/2 + g·x`` under ``1 − x₁ − ε x₂² ≥ 0`` and ``x₁ ≥ 0`` (and, with ``extra``, a
second row that never holds). ``W`` is indefinite along ``x₁`` by ``−a``; the row holds at the answer and its
gradient covers that direction, so ``W`` is positive definite on its null space: Newton's method with the term on
the row converges quadratically, while an identity shift (the term on no row) as large as ``a`` slows every other
direction by ``1/(1 + a)``.
"""

from __future__ import annotations

import numpy as np
import pytest

import sqp


def _problem(a: float, eps: float, g: np.ndarray, extra: bool) -> tuple:
    def fun(x):
        return -0.5 * a * x[0] ** 2 + 0.5 * float(x[1:] @ x[1:]) + float(g @ x)

    def jac(x):
        return np.concatenate(([-a * x[0]], x[1:])) + g

    def hess(x):
        return np.diag([-a, 1.0, 1.0, 1.0])

    rows = [{"type": "ineq", "fun": lambda x: np.array([1.0 - x[0] - eps * x[1] ** 2]),
             "jac": lambda x: np.array([[-1.0, -2.0 * eps * x[1], 0.0, 0.0]]),
             "hess": lambda x, v: -2.0 * eps * v[0] * np.diag([0.0, 1.0, 0.0, 0.0])}]
    if extra:  # (never holds: 10 + x₃ ≥ 0)
        rows.append({"type": "ineq", "fun": lambda x: np.array([10.0 + x[2]]),
                     "jac": lambda x: np.array([[0.0, 0.0, 1.0, 0.0]]),
                     "hess": lambda x, v: np.zeros((4, 4))})
    return fun, jac, hess, rows


@pytest.mark.parametrize("a", [3.0, 30.0, 300.0])
@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("extra", [False, True])
def test_held_rows_replace_the_shift_where_the_given_rows_leave_w_indefinite(a, seed, extra):
    """Given no rows (``()``) the held row joins the term wherever ``W`` needs it (after a try that did not help,
    not at the next iteration): the solve reaches the point of every held row's term (``True``) in at most twice its
    iterations (measured: the same in 14 of 18 cases, 14 against 8 at most) and of the shift (``False``) in fewer
    (the shift takes 3-10 times as many as ``True`` here)."""
    rng = np.random.default_rng(seed)
    g = np.concatenate(([-rng.uniform(0.5, 2.0)], rng.normal(0.0, 1.0, 3)))
    eps = rng.uniform(0.05, 0.2)
    fun, jac, hess, rows = _problem(a, eps, g, extra)
    x0 = np.concatenate(([0.2], rng.normal(0.0, 1.0, 3)))
    bounds = [(0.0, None)] + [(None, None)] * 3
    runs = {mode: sqp.minimize(fun, x0, jac=jac, hess=hess, bounds=bounds, constraints=rows,
                               convexify_inequalities=mode, tol=1e-10)
            for mode in (True, False, ())}
    for res in runs.values():
        assert res.success
    reference = runs[True].x
    np.testing.assert_allclose(runs[()].x, reference, rtol=0, atol=1e-9)
    # (the shifted steps stop, the KKT residual below tol, while still creeping along x₂..x₄ at the rate
    # 1/(1 + shift): up to 5e-6 away at a = 300, the energy the same to second order in that)
    np.testing.assert_allclose(runs[False].x, reference, rtol=0, atol=1e-4)
    assert runs[False].fun == pytest.approx(runs[True].fun, rel=1e-9)
    assert abs(1.0 - reference[0] - eps * reference[1] ** 2) < 1e-10  # (the row holds)
    assert runs[()].nit <= 2 * runs[True].nit
    assert runs[()].nit < runs[False].nit


@pytest.mark.parametrize("bad", ["rows", 1.5, object()])
def test_a_row_selection_that_is_not_indices_is_refused(bad):
    fun, jac, hess, rows = _problem(3.0, 0.1, np.array([-1.0, 0.0, 0.0, 0.0]), False)
    with pytest.raises(TypeError, match="convexify_inequalities"):
        sqp.minimize(fun, np.zeros(4), jac=jac, hess=hess, constraints=rows, convexify_inequalities=bad)


def test_negative_row_indices_are_refused():
    fun, jac, hess, rows = _problem(3.0, 0.1, np.array([-1.0, 0.0, 0.0, 0.0]), False)
    with pytest.raises(ValueError, match="non-negative"):
        sqp.minimize(fun, np.zeros(4), jac=jac, hess=hess, constraints=rows, convexify_inequalities=(-1,))
