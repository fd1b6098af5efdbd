"""The dense model Hessian's Cholesky factor, kept from convexification's test and reused by the equality-only QP."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from sqp import hessian
from sqp.hessian import CholeskyHessian, convexify
from sqp.structured import range_space_kkt
from sqp.subproblem import _equality_qp


def _spd(n, seed=0):
    M = np.random.default_rng(seed).standard_normal((n, n))
    return M @ M.T + np.eye(n)


def _kkt(B, g, E, e):
    n, m = g.size, e.size
    K = np.block([[B, E.T], [E, np.zeros((m, m))]])
    sol = np.linalg.solve(K, np.concatenate((-g, e)))
    return sol[:n], sol[n:]


@pytest.mark.parametrize("case", ["definite", "augmented", "shifted"])
def test_convexify_hands_over_the_factor_of_the_matrix_it_returns(case):
    n = 12
    rng = np.random.default_rng(1)
    W = _spd(n)
    C = None
    if case != "definite":
        C = rng.standard_normal((3, n))
        u = C[0] / np.linalg.norm(C[0])
        W = W - 100.0 * np.outer(u, u)  # indefinite along a row of C only: the augmented term fixes it
        C = C if case == "augmented" else None
    B, delta, rho = convexify(W, 0.0, C, 0.0)
    assert isinstance(B, CholeskyHessian)
    assert (rho > 0.0) == (case == "augmented") and (delta > 0.0) == (case == "shifted")
    L = B.cholesky
    np.testing.assert_allclose(L @ L.T, np.asarray(B), rtol=1e-12, atol=1e-12)
    assert np.array_equal(np.tril(L), L)
    expected = W + (rho * C.T @ C if C is not None else 0.0) + delta * np.eye(n)
    np.testing.assert_allclose(np.asarray(B), expected, rtol=1e-13, atol=1e-12)


def test_nothing_derived_from_the_matrix_keeps_its_factor():
    B = hessian._accepted(_spd(5), False)
    assert B.cholesky is not None
    for derived in (B + np.eye(5), 2.0 * B, B @ np.ones(5), np.sqrt(np.abs(B))):
        assert type(derived) is np.ndarray
    assert type(B @ np.ones(5) @ np.ones(5)) is not CholeskyHessian
    for view in (B.T, B[:3, :3], B.copy()):
        assert view.cholesky is None
    assert type(pickle.loads(pickle.dumps(B))) is np.ndarray
    assert hessian._accepted(-_spd(5), False) is None


@pytest.mark.parametrize("m", [0, 1, 4])
def test_the_range_space_step_is_the_kkt_point(m):
    n = 15
    rng = np.random.default_rng(m)
    B, g = _spd(n, m), rng.standard_normal(n)
    E, e = rng.standard_normal((m, n)), rng.standard_normal(m)
    d, y = range_space_kkt(np.linalg.cholesky(B), g, E, e)
    d_ref, y_ref = _kkt(B, g, E, e)
    np.testing.assert_allclose(d, d_ref, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(y, y_ref, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(B @ d + g + E.T @ y, 0.0, atol=1e-10)
    np.testing.assert_allclose(E @ d, e, atol=1e-12)


def test_dependent_rows_still_give_the_unique_step_and_a_singular_schur_complement_falls_back_to_lu():
    n = 6
    rng = np.random.default_rng(3)
    B, g = _spd(n), rng.standard_normal(n)
    row = np.zeros(n)
    row[0] = 1.0
    E, e = np.vstack([row, row]), np.array([0.5, 0.5])  # the same row twice: consistent, dependent
    d, y = _equality_qp(hessian._accepted(B, False), g, E, e, 1.0)
    d_ref = _kkt(B, g, E[:1], e[:1])[0]  # the step is unique; the multipliers are one valid split
    np.testing.assert_allclose(d, d_ref, atol=1e-12)
    np.testing.assert_allclose(B @ d + g + E.T @ y, 0.0, atol=1e-9)
    zero = np.vstack([row, np.zeros(n)])  # an exactly zero row: S exactly singular, and K too
    assert range_space_kkt(np.linalg.cholesky(B), g, zero, np.array([0.5, 0.0])) is None
    assert _equality_qp(hessian._accepted(B, False), g, zero, np.array([0.5, 0.0]), 1.0) is None


def test_the_factored_and_plain_equality_qp_agree_to_rounding():
    n, m = 40, 3
    rng = np.random.default_rng(7)
    B, g = _spd(n, 7), rng.standard_normal(n)
    E, e = rng.standard_normal((m, n)), rng.standard_normal(m)
    fast = _equality_qp(hessian._accepted(B, False), g, E, e, 1.0)
    slow = _equality_qp(B, g, E, e, 1.0)
    np.testing.assert_allclose(fast[0], slow[0], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(fast[1], slow[1], rtol=1e-10, atol=1e-12)
