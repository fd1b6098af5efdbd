""":func:`sqp.hessian.convexify` with ``alone_first=False``: ``W + r0 C^T C`` tested before ``W`` alone (one
Cholesky factorisation less when ``W`` is indefinite), with the same answer bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import NonlinearConstraint

import sqp
from sqp import hessian, hessian_strategy
from sqp.problems.hock_schittkowski import all_problems


def matrices(n: int, m: int, seed: int, kind: str):
    """``W`` and rows ``C``: ``kind`` "definite" (W itself positive definite), "rows" (one negative eigenvalue along a
    row of ``C``: ``W + r C^T C`` is, from some ``r`` on), "steep" (as "rows", but only from a weight 100-10000 times
    ``r0``), "null" (negative on the null space of ``C``: no weight does, the identity shift), "barely" (positive
    definite with a smallest eigenvalue 1e-12 of its largest)."""
    rng = np.random.default_rng(seed)
    M = rng.standard_normal((n, n))
    W = M @ M.T / n + np.eye(n)
    C = rng.standard_normal((m, n))
    if kind in ("rows", "steep"):
        u = C[0] / np.linalg.norm(C[0])
        W = W - (50.0 if kind == "rows" else 1e4) * np.outer(u, u)
    elif kind == "null":
        u = np.linalg.svd(C)[2][m]
        W = W - 50.0 * np.outer(u, u)
    elif kind == "barely":
        lam, V = np.linalg.eigh(W)
        lam[0] = 1e-12 * lam[-1]
        W = (V * lam) @ V.T
        W = 0.5 * (W + W.T)
    return W, C


def same(a, b) -> None:
    """Two :func:`convexify` answers bit for bit: matrix, shift, weight and the Cholesky factor handed over."""
    assert type(a[0]) is type(b[0])
    assert np.array_equal(np.asarray(a[0]), np.asarray(b[0]))
    assert a[1:] == b[1:]
    La, Lb = getattr(a[0], "cholesky", None), getattr(b[0], "cholesky", None)
    assert (La is None) == (Lb is None) and (La is None or np.array_equal(La, Lb))


@pytest.mark.parametrize("kind", ["definite", "rows", "steep", "null", "barely"])
@pytest.mark.parametrize("m", [1, 2, 3, 6])
@pytest.mark.parametrize("seed", range(3))
def test_w_plus_r0_gram_first_gives_the_same_matrix_weight_and_factor(kind, m, seed):
    W, C = matrices(30, m, seed, kind)
    for shift in (0.0, 1e-3):
        same(hessian.convexify(W, shift, C, 0.0, alone_first=False), hessian.convexify(W, shift, C, 0.0))
    same(hessian.convexify(W, 0.0, C, 0.5, alone_first=False), hessian.convexify(W, 0.0, C, 0.5))  # a last weight


def test_the_shortcut_is_taken_for_an_indefinite_w_and_refused_for_a_definite_one(monkeypatch):
    """One Cholesky factorisation instead of two when W is indefinite; when W alone is positive definite, its own test
    decides (so the answer is W, weight 0, as before)."""
    calls = []
    real = hessian.lapack.dpotrf

    def counting(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(hessian.lapack, "dpotrf", counting)
    steep = matrices(30, 2, 0, "rows")
    slight = np.diag(np.r_[-0.005, np.full(29, 10.0)])  # r0 = 1e-3 * 10 / 1 = 0.01 > 0.005: accepted at once
    for W, C in (steep, (slight, np.eye(30)[:2])):  # (W + r0 C^T C accepted a few weights later, or at once)
        B, delta, rho = hessian.convexify(W, 0.0, C, 0.0, alone_first=False)
        assert rho > 0.0 and delta == 0.0
        new = len(calls)
        calls.clear()
        hessian.convexify(W, 0.0, C, 0.0)
        assert new == len(calls) - 1  # W alone (failing) not factorised
        calls.clear()
    assert new == 1
    W, C = matrices(30, 2, 0, "definite")
    B, delta, rho = hessian.convexify(W, 0.0, C, 0.0, alone_first=False)
    assert (delta, rho) == (0.0, 0.0) and np.array_equal(np.asarray(B), W)
    W, C = matrices(30, 2, 0, "null")
    first = hessian._indefinite_first(W, C, C.T @ C)
    assert first is not None and first[0] is None  # W + r0 C^T C is not positive definite either: on at 10 r0


def test_the_largest_eigenvalue_in_closed_form():
    rng = np.random.default_rng(4)
    for _ in range(50):
        M = rng.standard_normal((2, 2))
        M = M @ M.T
        assert hessian._largest_eigenvalue(M) == pytest.approx(np.linalg.eigvalsh(M)[-1], rel=1e-13, abs=1e-15)
    assert hessian._largest_eigenvalue(np.array([[3.0]])) == 3.0


def chain(n: int):
    """A compressed elastic chain pinned at its tip (the reduced program in miniature, as in
    tests/sqp/test_structured_kkt.py), with a dense Hessian: W indefinite near the answer."""
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


def _solve_both(monkeypatch, run):
    """``run()`` with the strategy's guess as it is, then with ``W`` always tested alone first (the old order)."""
    guessed = []
    real = hessian.convexify

    def spy(W, shift=0.0, C=None, rho=0.0, alone_first=True, equality_only=False, rungs=None, **limit):
        guessed.append(not alone_first and rho == 0.0)
        return real(W, shift, C, rho, alone_first, equality_only, rungs, **limit)

    monkeypatch.setattr(hessian_strategy, "convexify", spy)
    new = run()
    monkeypatch.setattr(hessian_strategy, "convexify",
                        lambda W, shift=0.0, C=None, rho=0.0, alone_first=True, equality_only=False, rungs=None,
                        **limit: real(W, shift, C, rho, True, equality_only, rungs, **limit))
    old = run()
    return new, old, guessed


@pytest.mark.parametrize("warm", [False, True])
def test_a_buckled_chain_is_solved_bit_for_bit_as_before(monkeypatch, warm):
    fun, jac, hess, con, x0 = chain(60)
    ref = sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[con], tol=1e-9)
    assert ref.success
    kw = {"multipliers0": ref.constraint_multipliers} if warm else {}
    start = ref.x + 1e-3 * np.sin(np.arange(60)) if warm else x0
    new, old, guessed = _solve_both(monkeypatch, lambda: sqp.minimize(fun, start, jac=jac, hess=hess,
                                                                      constraints=[con], tol=1e-9, **kw))
    assert any(guessed)  # the shortcut was offered (after an indefinite W, or at a start with multipliers)
    assert new.status == old.status and new.nit == old.nit and new.nfev == old.nfev
    assert np.array_equal(new.x, old.x) and new.fun == old.fun
    assert np.array_equal(np.asarray(new.hess), np.asarray(old.hess))


@pytest.mark.parametrize("name", ["HS39", "HS77", "HS78", "HS79"])
def test_hock_schittkowski_equality_problems_solved_bit_for_bit_as_before(monkeypatch, name):
    """Equality-constrained HS problems given exact-enough Hessians (central differences of the analytic gradients;
    the same matrices both times): the same status, iterations, evaluations and answer, bit for bit."""
    prob = next(p for p in all_problems() if p.name == name)
    (c,) = prob.constraints
    x0 = np.asarray(prob.x0, dtype=float)
    m = np.atleast_1d(c["fun"](x0)).size

    def fd(grad, x, h=1e-5):
        return np.stack([(np.asarray(grad(x + h * u)) - np.asarray(grad(x - h * u))) / (2 * h)
                         for u in np.eye(x.size)], axis=-1)

    def hess(x):
        H = fd(prob.jac, x)
        return 0.5 * (H + H.T)

    def chess(x, v):
        T = fd(lambda y: np.atleast_2d(c["jac"](y)), x).reshape(m, x.size, x.size)
        H = np.einsum("i,ijk->jk", v, T)
        return 0.5 * (H + H.T)

    con = NonlinearConstraint(c["fun"], 0.0, 0.0, jac=c["jac"], hess=chess)
    new, old, _ = _solve_both(monkeypatch, lambda: sqp.minimize(prob.fun, x0, jac=prob.jac, hess=hess,
                                                                constraints=[con], tol=1e-8))
    assert new.status == old.status and new.nit == old.nit and new.nfev == old.nfev
    assert np.array_equal(new.x, old.x)
