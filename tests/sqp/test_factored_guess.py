"""A dense QP whose model Hessian carries its Cholesky factor, solved on a guessed active set by the range-space
method (sqp.subproblem._factored_guess): DAQP's solution on random strictly convex QPs whose guess is right or a row
off, None when the guess cannot be corrected in the solves allowed, and a nonlinear program with dense rows
solved with the guess reaching the backends' answer, the same iterations."""

from __future__ import annotations

import numpy as np
import pytest
import qpsolvers
from quartic_chain import quartic_chain

import sqp
from sqp.hessian import CholeskyHessian
from sqp.subproblem import _factored_guess


def _dense_qp(n: int, m: int, seed: int) -> tuple[CholeskyHessian, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                                  np.ndarray]:
    """A random strictly convex QP: ``B`` (with its factor), two equality rows, ``m`` inequality rows of which some
    bind at the solution."""
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    B = A @ A.T + n * np.eye(n)
    q = rng.normal(size=n)
    E = rng.normal(size=(2, n))
    e = 0.1 * rng.normal(size=2)
    G = rng.normal(size=(m, n))
    h = 0.05 * rng.normal(size=m)
    return CholeskyHessian.wrap(B, np.linalg.cholesky(B)), q, E, e, G, h


def _reference(B, q, E, e, G, h):
    sol = qpsolvers.solve_problem(qpsolvers.Problem(np.asarray(B), q, G, h, E, e), solver="daqp")
    assert sol.found
    return sol


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("off", [0, 1])
def test_the_factored_guess_is_daqps_solution(seed, off):
    """Guessed right (``off = 0``) or with one binding row left out and one slack row put in (``off = 1``,
    corrected within the three solves), the step and multipliers are DAQP's to rounding, the multipliers
    nonnegative."""
    B, q, E, e, G, h = _dense_qp(30 + 5 * seed, 40, seed)
    ref = _reference(B, q, E, e, G, h)
    active = ref.z > 1e-12
    assert 1 <= active.sum() <= 39
    if off:
        active[np.flatnonzero(active)[0]] = False
        active[np.flatnonzero(~active)[-1]] = True
    found = _factored_guess(B, q, E, e, G, h, active, 1.0, 3)
    assert found is not None
    d, y, z = found
    np.testing.assert_allclose(d, ref.x, atol=1e-10)
    np.testing.assert_allclose(y, ref.y, atol=1e-9)
    np.testing.assert_allclose(z, ref.z, atol=1e-9)
    assert np.all(z >= 0.0)


@pytest.mark.parametrize("seed", range(4))
def test_a_factored_guess_that_needs_more_corrections_is_refused(seed):
    """From no row guessed active, one solve does not reach a solution with binding rows: None (the caller asks
    its backends)."""
    B, q, E, e, G, h = _dense_qp(40, 40, seed)
    assert (_reference(B, q, E, e, G, h).z > 1e-12).any()
    assert _factored_guess(B, q, E, e, G, h, np.zeros(40, dtype=bool), 1.0, 1) is None


@pytest.mark.parametrize("seed", range(3))
def test_minimize_with_the_dense_guess_matches_the_backends(seed):
    """A program with dense nonlinear rows (each row reads every variable) and an exact Hessian solved with
    ``active_set_guess`` reaches the backends' point in the same iterations, some subproblem solved on the guess."""
    n = 60
    rng = np.random.default_rng(seed)
    target = 2.0 * rng.normal(size=n)
    W = rng.normal(size=(8, n)) / np.sqrt(n)

    fun, jac, tridiagonal = quartic_chain(target)

    def hess(x):
        main, off = tridiagonal(x)
        return np.diag(main) + np.diag(off, 1) + np.diag(off, -1)

    rows = {"type": "ineq", "fun": lambda x: 1.0 - (W @ x) ** 2, "jac": lambda x: -2.0 * (W @ x)[:, None] * W,
            "hess": lambda x, v: -2.0 * (W.T * v) @ W}
    plain = sqp.minimize(fun, np.zeros(n), jac=jac, hess=hess, constraints=[rows])
    guessed = sqp.minimize(fun, np.zeros(n), jac=jac, hess=hess, constraints=[rows], active_set_guess=True)
    assert plain.success and guessed.success
    assert any(rec.qp_status == "active set" for rec in guessed.history)
    assert guessed.nit == plain.nit
    np.testing.assert_allclose(guessed.x, plain.x, atol=1e-9)
    assert guessed.fun == pytest.approx(plain.fun, rel=1e-12)
