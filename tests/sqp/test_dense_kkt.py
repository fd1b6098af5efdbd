"""The dense KKT path of :mod:`sqp.dense_kkt`: an unconvexified dense exact Hessian, one Bunch–Kaufman factorisation
of the KKT matrix, the inertia test, and the fallback to the general convexification."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.linalg import lapack
from scipy.optimize import NonlinearConstraint

import sqp
from sqp import dense_kkt, hessian
from sqp.problem import Rows
from sqp.problems.hock_schittkowski import all_problems
from sqp.structured import needs_convexification, range_space_kkt
from sqp.subproblem import linearise, solve_subproblem


def indefinite_on_rows(n: int, m: int, seed: int = 0, convex_on_null_space: bool = True):
    """``W`` with one negative eigenvalue, along a direction in the row space of ``E`` (then ``W`` is positive
    definite on ``E``'s null space) or in that null space."""
    rng = np.random.default_rng(seed)
    M = rng.standard_normal((n, n))
    W = M @ M.T / n + np.eye(n)
    E = rng.standard_normal((m, n))
    if convex_on_null_space:
        u = E[0] / np.linalg.norm(E[0])
    else:
        Z = np.linalg.svd(E)[2][m:]
        u = Z[0]
    W = W - 50.0 * np.outer(u, u)
    return W, E, rng.standard_normal(n), rng.standard_normal(m)


@pytest.mark.parametrize("seed", range(5))
def test_the_dense_kkt_step_is_the_convexified_paths_step_and_newton_multipliers(seed):
    n, m = 24, 3
    W, E, g, e = indefinite_on_rows(n, m, seed)
    assert np.min(np.linalg.eigvalsh(W)) < 0.0
    B, delta, rho = hessian.convexify(W, 0.0, E, 0.0)  # today's path: W + rho E^T E, Cholesky, range space
    assert rho > 0.0 and delta == 0.0
    d_ref, y_qp = range_space_kkt(B.cholesky, g, E, e)
    y_ref = y_qp + rho * (E @ d_ref)  # the multipliers moved back (sqp.multipliers.newton_multipliers)
    D = dense_kkt.DeferredHessian.wrap(W, lambda: pytest.fail("convexified although K's inertia is right"))
    d, y = D.kkt(g, E, e)
    scale = max(np.abs(d_ref).max(), 1.0)
    np.testing.assert_allclose(d, d_ref, rtol=1e-12, atol=1e-12 * scale)
    np.testing.assert_allclose(y, y_ref, rtol=1e-12, atol=1e-12 * np.abs(y_ref).max())
    # and through the QP: an equality-only subproblem takes the step from the factorisation of K
    rows = Rows.from_bounds(np.zeros(m), np.zeros(m))
    none = Rows.from_bounds(np.zeros(0), np.zeros(0))
    qp = solve_subproblem(D, g, linearise(E, -e, rows), linearise(np.zeros((0, n)), np.zeros(0), none),
                          np.full(n, -np.inf), np.full(n, np.inf), backends=[("daqp", {})])
    assert qp.found and qp.status == "kkt"
    np.testing.assert_allclose(qp.d, d_ref, rtol=1e-12, atol=1e-12 * scale)


def test_the_inertia_test_rejects_a_hessian_indefinite_on_the_null_space():
    n, m = 24, 3
    W, E, g, e = indefinite_on_rows(n, m, 1, convex_on_null_space=False)
    D = dense_kkt.DeferredHessian.wrap(W, lambda: hessian.convexify(W, 0.0, E, 0.0)[0])
    assert needs_convexification(D)
    assert D.kkt(g, E, e) is None  # K has n - 1 positive eigenvalues: no QP minimiser on E d = e
    rows = Rows.from_bounds(np.zeros(m), np.zeros(m))
    none = Rows.from_bounds(np.zeros(0), np.zeros(0))
    lin = linearise(np.zeros((0, n)), np.zeros(0), none)
    box = (np.full(n, -np.inf), np.full(n, np.inf))
    qp = solve_subproblem(D, g, linearise(E, -e, rows), lin, *box, backends=[("daqp", {})])
    assert not qp.found and qp.status == "indefinite"  # not the saddle point an LU solve of K would give
    B = D.convexified()  # the fallback: the general path (here the identity shift; no weight convexifies it)
    assert not needs_convexification(B) and np.min(np.linalg.eigvalsh(np.asarray(B))) > 0.0


@pytest.mark.parametrize("seed", range(20))
def test_inertia_from_bunch_kaufman_blocks_matches_the_eigenvalues(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 40))
    A = rng.standard_normal((n, n))
    A = A + A.T
    if seed % 3 == 0:
        A[np.diag_indices(n)] = 0.0  # zero diagonal: Bunch–Kaufman must take 2x2 pivots
    ldu, ipiv, info = lapack.dsytrf(np.asfortranarray(A), lower=1)
    assert info == 0
    ev = np.linalg.eigvalsh(A)
    assert dense_kkt.inertia(ldu, ipiv) == (int(np.sum(ev > 0)), int(np.sum(ev < 0)), 0)
    if seed % 3 == 0:
        assert (ipiv < 0).any()


def test_candidate_and_caches():
    W = np.eye(12)
    assert dense_kkt.candidate(W, np.ones((3, 12)))
    assert not dense_kkt.candidate(W, None)
    assert not dense_kkt.candidate(W, np.ones((4, 12)))  # more than a quarter of the variables
    assert not dense_kkt.candidate(sp.identity(12, format="csc"), np.ones((2, 12)))
    D = dense_kkt.DeferredHessian.wrap(W, lambda: None)
    assert type(pickle.loads(pickle.dumps(D))) is np.ndarray
    for derived in (D + 1.0, D @ np.ones(12), D.T, D.copy()):
        assert not isinstance(derived, dense_kkt.DeferredHessian) or derived._convexify is None


def chain(n: int):
    """A compressed elastic chain pinned at its tip (tests/sqp/test_structured_kkt.py), dense: W indefinite."""
    D = np.diff(np.eye(n), axis=0)
    H = D.T @ D
    H[0, 0] += 1.0
    target = np.array([0.9, 0.2])

    def cfun(t):
        return np.array([np.mean(np.cos(t)), np.mean(np.sin(t))]) - target

    def cjac(t):
        return np.vstack((-np.sin(t), np.cos(t))) / n

    def chess(t, v):
        return np.diag((-v[0] * np.cos(t) - v[1] * np.sin(t)) / n)

    con = NonlinearConstraint(cfun, 0.0, 0.0, jac=cjac, hess=chess)
    return (lambda t: 0.5 * float(t @ H @ t)), (lambda t: H @ t), (lambda t: H), con, np.linspace(0.0, 0.3, n)


def test_a_buckled_dense_chain_is_solved_as_by_the_convexified_path(monkeypatch):
    fun, jac, hess, con, x0 = chain(60)
    new = sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[con], tol=1e-9)
    assert new.success and all(rec.qp_status == "kkt" for rec in new.history)
    monkeypatch.setattr(dense_kkt, "candidate", lambda W, C: False)
    old = sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[con], tol=1e-9)
    assert old.success and new.nit <= old.nit
    assert abs(new.fun - old.fun) <= 1e-12 * abs(old.fun)
    assert np.max(np.abs(new.x - old.x)) < 1e-8


@pytest.mark.parametrize("name", ["HS77", "HS78", "HS79", "HS39"])
def test_hock_schittkowski_equality_problems_solved_the_same(monkeypatch, name):
    """Equality-only HS problems with exact Hessians (central differences of the analytic gradients; the same
    matrices on both paths), the dense KKT path forced on (their few variables keep it off by default): the same
    status, iterations no more, the same answer."""
    prob = next(p for p in all_problems() if p.name == name)
    (c,) = prob.constraints
    m = np.atleast_1d(c["fun"](np.asarray(prob.x0, dtype=float))).size

    def fd(grad, x, h=1e-5):
        cols = [(np.asarray(grad(x + h * u)) - np.asarray(grad(x - h * u))) / (2 * h) for u in np.eye(x.size)]
        return np.stack(cols, axis=-1)

    def hess(x):
        H = fd(prob.jac, x)
        return 0.5 * (H + H.T)

    def chess(x, v):
        T = fd(lambda y: np.atleast_2d(c["jac"](y)), x).reshape(m, x.size, x.size)
        H = np.einsum("i,ijk->jk", v, T)
        return 0.5 * (H + H.T)

    con = NonlinearConstraint(c["fun"], 0.0, 0.0, jac=c["jac"], hess=chess)
    run = lambda: sqp.minimize(prob.fun, np.asarray(prob.x0, dtype=float), jac=prob.jac, hess=hess,  # noqa: E731
                               constraints=[con], tol=1e-8)
    monkeypatch.setattr(dense_kkt, "candidate", lambda W, C: C is not None and not sp.issparse(W))
    new = run()
    monkeypatch.setattr(dense_kkt, "candidate", lambda W, C: False)
    old = run()
    assert new.status == old.status or (new.success and old.success and new.status.name == "SUCCESS")  # or better
    assert new.nit <= old.nit
    np.testing.assert_allclose(new.x, old.x, rtol=1e-7, atol=1e-7)
