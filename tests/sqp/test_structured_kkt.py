"""The structured KKT solve of equality-only subproblems (:mod:`sqp.structured`) and the sorted matrices
:func:`sqp.hessian.convexify` hands to the sparse backends."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
import qpsolvers
import scipy.sparse as sp
from scipy.optimize import NonlinearConstraint

import sqp
from sqp import hessian, structured
from sqp.problem import Rows
from sqp.subproblem import linearise, solve_subproblem


def tridiagonal(n: int, shift: float = 0.0) -> sp.csc_matrix:
    """The bending-energy Hessian of a bar chain (second differences), shifted by ``-shift`` (a wire under
    compression is indefinite)."""
    main = np.full(n, 2.0 - shift)
    off = np.full(n - 1, -1.0)
    return sp.diags([off, main, off], [-1, 0, 1], format="csc")


def kkt_dense(W, E, g, e):
    n, m = W.shape[0], E.shape[0]
    K = np.block([[W, E.T], [E, np.zeros((m, m))]])
    sol = np.linalg.solve(K, np.concatenate((-g, e)))
    return sol[:n], sol[n:], np.linalg.eigvalsh(K)


def test_the_qp_handed_to_piqp_has_sorted_indices_even_without_the_positive_definiteness_test(monkeypatch):
    """W + rho C^T C of two sparse matrices comes out with unsorted CSC indices; PIQP rejects those. The test's
    splu used to sort them in place as a side effect: with the test skipped, the QP must still be accepted."""
    if "piqp" not in qpsolvers.available_solvers:
        pytest.skip("piqp not installed")
    n = 400
    rng = np.random.default_rng(0)
    W = tridiagonal(n, shift=0.3)  # indefinite: needs the augmented-Lagrangian term
    C = sp.random(n // 2, n, density=3 / n, random_state=1, format="csr") + sp.eye(n // 2, n, format="csr")
    assert not (W + sp.csc_matrix(C.T @ C)).has_sorted_indices  # the hazard is real
    calls = []  # W alone "fails" the test, W + rho C^T C "passes" it without the factorisation that used to sort

    def skipped_test(B, floor=0.0):
        calls.append(B)
        return len(calls) > 1

    monkeypatch.setattr(hessian, "_positive_definite", skipped_test)
    B, delta, rho = hessian.convexify(W, 0.0, C, 0.0)
    assert rho > 0.0 and delta == 0.0 and B.has_sorted_indices
    g = rng.standard_normal(n)
    c = rng.standard_normal(n // 2)
    rows = Rows.from_bounds(np.zeros(n // 2), np.zeros(n // 2))
    nl = linearise(sp.csc_matrix(C), c, rows)
    lin = linearise(np.zeros((0, n)), np.zeros(0), Rows.from_bounds(np.zeros(0), np.zeros(0)))
    qp = solve_subproblem(B, g, nl, lin, np.full(n, -10.0), np.full(n, 10.0), backends=[("piqp", {})])
    assert qp.found and qp.status == "optimal"


@pytest.mark.parametrize("shift", [0.0, 0.3])
def test_structured_kkt_is_the_dense_kkt_solution_when_the_inertia_is_right(shift):
    n, m = 400, 3
    rng = np.random.default_rng(1)
    W = tridiagonal(n, shift) + sp.diags(rng.uniform(0.0, 0.1, n), format="csc")
    E = rng.standard_normal((m, n))
    g, e = rng.standard_normal(n), rng.standard_normal(m)
    factor = structured.factor_symmetric(W)
    assert factor is not None
    d_ref, y_ref, eig = kkt_dense(W.toarray(), E, g, e)
    negatives_W = int(np.sum(np.linalg.eigvalsh(W.toarray()) < 0))
    assert factor.negatives == negatives_W  # Sylvester: the pivots' signs are the eigenvalues'
    right = int(np.sum(eig < 0)) == m  # In(K) = (n, m, 0): W is positive definite on the null space of E
    step = structured.equality_kkt(W, g, E, e)
    if not right:
        assert step is None
        return
    d, y = step
    assert np.allclose(d, d_ref, rtol=1e-10, atol=1e-10 * np.max(np.abs(d_ref)))
    assert np.allclose(y, y_ref, rtol=1e-10, atol=1e-10 * np.max(np.abs(y_ref)))


def test_wrong_inertia_is_detected_and_the_step_refused():
    """W negative definite in a direction E does not constrain: K has a wrong inertia, no QP minimiser."""
    n = 200
    W = tridiagonal(n, shift=1.0)  # eigenvalues 2 - 1 - 2cos(k pi/(n+1)): many negative
    E = np.zeros((1, n))
    E[0, 0] = 1.0
    assert structured.equality_kkt(W, np.ones(n), E, np.zeros(1)) is None


def test_candidate_structure():
    W = tridiagonal(400)
    assert structured.candidate(W, np.ones((3, 400)))
    assert structured.candidate(W, None)
    # dense rows stored sparse: their Gram matrix is dense, the AL path could only shift W (structured path)
    assert structured.candidate(W, sp.csr_matrix(np.ones((3, 400))))
    assert not structured.candidate(W, sp.csr_matrix(sp.eye(3, 400)))  # sparse rows, sparse Gram: the AL path
    assert not structured.candidate(W, np.ones((structured.MAX_SCHUR_ROWS + 1, 400)))
    assert not structured.candidate(W.toarray(), np.ones((3, 400)))
    wide = sp.csc_matrix(np.ones((400, 400)))
    assert structured.bandwidth(wide) == 399 and not structured.candidate(wide, np.ones((3, 400)))


def test_convexify_leaves_an_indefinite_banded_hessian_factored_and_defers_the_shift():
    n = 400
    W = tridiagonal(n, shift=0.3)
    C = np.random.default_rng(2).standard_normal((2, n))
    B, delta, rho = hessian.convexify(W, 0.0, C, 0.0)
    assert isinstance(B, structured.FactoredHessian) and (delta, rho) == (0.0, 0.0)
    assert structured.needs_convexification(B)
    assert abs(B - W).max() == 0.0  # as a matrix, W itself
    P = B.convexified()  # the general path: a dense-row C gets the identity shift
    assert np.min(np.linalg.eigvalsh(P.toarray())) > 0.0
    plain = pickle.loads(pickle.dumps(B))  # a result holding it pickles as a plain CSC matrix
    assert type(plain) is sp.csc_matrix and abs(plain - W).max() == 0.0


def chain_problem(n: int):
    """A compressed elastic chain of ``n`` bar angles pinned at its tip (a discrete elastica): bending energy
    ``1/2 sum (theta_{i+1} - theta_i)^2 + 1/2 theta_0^2``, tip position ``sum (cos, sin)(theta_i) / n`` fixed short
    of the straight length — the guidewire's reduced program in miniature: a tridiagonal energy Hessian, two dense
    rows whose Hessians are diagonal, and W indefinite at the answer (the chain is buckled)."""
    D = sp.diags([np.ones(n - 1), -np.ones(n - 1)], [0, 1], shape=(n - 1, n), format="csc")
    H = (D.T @ D + sp.diags(np.r_[1.0, np.zeros(n - 1)])).tocsc()
    target = np.array([0.9, 0.2])

    def fun(t):
        return 0.5 * float(t @ (H @ t))

    def jac(t):
        return H @ t

    def hess(t):
        return H

    def cfun(t):
        return np.array([np.mean(np.cos(t)), np.mean(np.sin(t))]) - target

    def cjac(t):
        return np.vstack((-np.sin(t), np.cos(t))) / n

    def chess(t, v):
        return sp.diags((-v[0] * np.cos(t) - v[1] * np.sin(t)) / n, format="csc")

    con = NonlinearConstraint(cfun, 0.0, 0.0, jac=cjac, hess=chess)
    x0 = np.linspace(0.0, 0.3, n)
    return fun, jac, hess, con, x0


def test_the_structured_path_gives_a_checked_kkt_point_of_a_buckled_chain_in_fewer_iterations(monkeypatch):
    n = 400  # above DENSE_LIMIT: the sparse model Hessian
    assert n > sqp.DENSE_LIMIT
    fun, jac, hess, con, x0 = chain_problem(n)
    res = sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[con], tol=1e-9)
    assert res.success, res.message
    assert np.allclose(con.fun(res.x), 0.0, atol=1e-9)  # tol
    # stationarity of the Lagrangian, with our own multipliers: grad f = J^T lam
    lam = np.linalg.lstsq(con.jac(res.x).T, jac(res.x), rcond=None)[0]
    assert np.max(np.abs(jac(res.x) - con.jac(res.x).T @ lam)) < 1e-7 * max(1.0, np.max(np.abs(jac(res.x))))
    # second-order sufficiency at the answer: W positive definite on the null space of J (a minimum)
    W = (hess(res.x) - chess_at(con, res.x, lam)).toarray()
    Z = np.linalg.svd(con.jac(res.x))[2][2:].T
    assert np.min(np.linalg.eigvalsh(Z.T @ W @ Z)) > 0.0
    assert np.min(np.linalg.eigvalsh(W)) < 0.0  # and W itself indefinite: the case convexify used to shift
    assert any(rec.qp_status == "kkt" for rec in res.history)
    # the general path (dense rows: the identity shift) reaches the same minimum in more iterations
    monkeypatch.setattr(structured, "candidate", lambda W, C: False)
    old = sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[con], tol=1e-9)
    assert old.success
    # (both stop at tol = 1e-9 in violation and scaled stationarity; the energy, 3e-3 here, moves by lam * that)
    assert abs(res.fun - old.fun) <= 1e-7 * abs(old.fun)
    assert np.max(np.abs(res.x - old.x)) < 1e-5  # a soft chain: its angles are conditioned ~1e3 worse
    assert res.nit < old.nit


def chess_at(con, x, lam):
    return con.hess(x, lam)
