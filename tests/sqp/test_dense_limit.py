"""``sqp.minimize(dense_limit=...)``: the most variables the engine works densely at. Below it a sparse problem is made
dense (model Hessian, linear rows, DAQP); with a lower limit it stays sparse — its QPs solved on guessed active sets
by banded KKT solves, or by a sparse backend — and reaches the same point."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from quartic_chain import chain_in_a_box
from scipy.optimize import LinearConstraint

import sqp
from sqp.backends import auto_choice

ALL = ["daqp", "piqp", "clarabel"]


def _chain_in_a_box(target: np.ndarray) -> tuple:
    """:func:`quartic_chain.chain_in_a_box` with ``x_0 − x_1 = 0.1`` too (a sparse linear equality): exact sparse
    Hessians and rows local in the variables, as a discretised rod's."""
    fun, jac, hess, rows = chain_in_a_box(target)
    step = LinearConstraint(sp.csr_matrix(([1.0, -1.0], ([0, 0], [0, 1])), shape=(1, target.size)), 0.1, 0.1)
    return fun, jac, hess, [rows, step]


@pytest.mark.parametrize("n", [8, 40, 150, sqp.DENSE_LIMIT])
@pytest.mark.parametrize("seed", [0, 1])
def test_a_sparse_problem_kept_sparse_below_the_default_limit_reaches_the_same_point(n, seed):
    """At sizes the engine would make dense, ``dense_limit=0`` keeps the problem sparse: the backend "auto" picks is
    the sparse one, QPs are solved on their guessed active sets (a path only a sparse model Hessian takes), and the
    answer is the dense path's (both converge to a KKT residual of 1e-10 on a strictly convex problem, whose
    minimiser is unique)."""
    target = 2.0 * np.random.default_rng(seed).normal(size=n)
    fun, jac, hess, constraints = _chain_in_a_box(target)
    dense = sqp.minimize(fun, np.zeros(n), jac=jac, hess=hess, constraints=constraints, tol=1e-10,
                         active_set_guess=True)
    kept = sqp.minimize(fun, np.zeros(n), jac=jac, hess=hess, constraints=constraints, tol=1e-10,
                        active_set_guess=True, dense_limit=0)
    assert dense.success and kept.success, (dense.message, kept.message)
    assert dense.qp_solver == "daqp" and kept.qp_solver == "piqp"
    assert all(rec.qp_status != "active set" for rec in dense.history)
    assert any(rec.qp_status == "active set" for rec in kept.history)
    held = np.abs(kept.x) > np.sqrt(0.5) - 1e-9
    assert 0 < held.sum() < n  # (rows both held and free: the QPs had an active set to find)
    np.testing.assert_allclose(kept.x, dense.x, atol=1e-8)
    assert kept.fun == pytest.approx(dense.fun, rel=1e-12)


def test_the_auto_choice_follows_the_limit():
    assert auto_choice(50, True, ALL)[0] == "daqp"
    assert auto_choice(50, True, ALL, dense_limit=0)[0] == "piqp"
    assert auto_choice(50, False, ALL, dense_limit=0)[0] == "daqp"  # (dense rows: a dense backend whatever the limit)
    assert auto_choice(400, True, ALL, dense_limit=500)[0] == "daqp"
    assert "dense_limit = 0" in auto_choice(50, True, ALL, dense_limit=0)[1]


@pytest.mark.parametrize("bad", [-1, 2.5, True, "300", None])
def test_a_bad_limit_is_refused_before_the_solve(bad):
    calls = []

    def fun(x):
        calls.append(1)
        return float(x @ x)

    with pytest.raises(ValueError, match="dense_limit"):
        sqp.minimize(fun, np.ones(3), dense_limit=bad)
    assert not calls
