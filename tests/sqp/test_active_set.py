"""The QP on a guessed active set (sqp.active_set): the same solution as a backend's on banded QPs whose guess is
right or one row off, None when the guess cannot be corrected in time, and the interleaved ordering's band."""

from __future__ import annotations

import numpy as np
import pytest
import qpsolvers
import scipy.sparse as sp
from quartic_chain import chain_in_a_box

import sqp
from sqp.active_set import banded_kkt, guessed_qp, interleaved_order


def _chain_qp(n: int, seed: int) -> tuple[sp.csc_matrix, np.ndarray, sp.csr_matrix, np.ndarray, sp.csr_matrix,
                                           np.ndarray]:
    """A banded QP like a discretised rod's: a positive-definite pentadiagonal ``P``, equality rows coupling
    neighbours, one inequality row per variable, about a third of them binding."""
    rng = np.random.default_rng(seed)
    main = 4.0 + rng.uniform(0.0, 1.0, n)
    P = sp.diags([main, -np.ones(n - 1), 0.3 * np.ones(n - 2), -np.ones(n - 1), 0.3 * np.ones(n - 2)],
                 [0, 1, 2, -1, -2], format="csc")
    q = rng.normal(size=n)
    k = np.arange(0, n - 2, 3)
    E = sp.csr_matrix((np.tile([1.0, -2.0, 1.0], k.size), (np.repeat(np.arange(k.size), 3),
                       (k[:, None] + np.arange(3)).ravel())), shape=(k.size, n))
    e = 0.1 * rng.normal(size=k.size)
    G = sp.identity(n, format="csr")
    h = 0.2 * rng.normal(size=n) + 0.1
    return P, q, E, e, G, h


def _reference(P, q, E, e, G, h):
    sol = qpsolvers.solve_problem(qpsolvers.Problem(P, q, G, h, E, e), solver="piqp", eps_abs=1e-11, eps_rel=0.0)
    assert sol.found
    return sol


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("off", [0, 1])
def test_guessed_qp_is_the_backends_solution(seed, off):
    """Guessed right (``off = 0``) or with one binding row missing and one slack row added (``off = 1``, corrected
    in the second solve), the step and multipliers are the backend's to its accuracy."""
    P, q, E, e, G, h = _chain_qp(60, seed)
    ref = _reference(P, q, E, e, G, h)
    active = ref.z > 1e-6  # (PIQP leaves tiny positive multipliers on slack rows)
    assert 3 <= active.sum() <= 57
    if off:
        active[np.flatnonzero(active)[0]] = False
        active[np.flatnonzero(~active)[-1]] = True
    found = guessed_qp(P, q, E, e, G, h, active, 1.0)
    assert found is not None
    d, y, z = found
    np.testing.assert_allclose(d, ref.x, atol=1e-8)
    np.testing.assert_allclose(y, ref.y, atol=1e-7)
    np.testing.assert_allclose(z, ref.z, atol=1e-7)
    assert np.all(z >= 0.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_guessed_row_without_a_gradient_is_left_out(seed):
    """Rows with a zero gradient and a positive bound (a row that cannot hold: a node row yielding to another
    block's) guessed active with the right ones: the backend's solution, in one solve, as without them."""
    P, q, E, e, G, h = _chain_qp(60, seed)
    zero = sp.csr_matrix((5, 60))
    G2 = sp.vstack((G, zero), format="csr")  # (stored as empty rows; explicit zeros below)
    G3 = sp.csr_matrix((np.zeros(5), (np.arange(60, 65), np.arange(5))), shape=(65, 60)) + G2
    h2 = np.concatenate((h, np.full(5, 1.0)))
    ref = _reference(P, q, E, e, G, h)
    active = np.concatenate((ref.z > 1e-6, np.ones(5, dtype=bool)))
    for rows in (G2, G3):
        found = guessed_qp(P, q, E, e, rows, h2, active, 1.0, solves=1)
        assert found is not None
        d, _, z = found
        np.testing.assert_allclose(d, ref.x, atol=1e-8)
        assert np.all(z[60:] == 0.0)


def test_a_guess_that_needs_more_corrections_is_refused():
    """From no row guessed active, two solves do not reach a solution with many binding rows: None (the caller
    asks its backends)."""
    P, q, E, e, G, h = _chain_qp(60, 0)
    assert guessed_qp(P, q, E, e, G, h, np.zeros(60, dtype=bool), 1.0) is None


def test_interleaved_order_keeps_a_local_kkt_matrix_banded():
    """Rows after their last variable: the KKT matrix of the chain QP has a band of a few entries, where the
    natural order (rows last) has the full width."""
    P, q, E, e, G, h = _chain_qp(300, 1)
    C = sp.vstack((E, G[:40:7]), format="csr")
    K = sp.bmat([[P, C.T], [C, None]], format="coo")
    perm = interleaved_order(C, 300)
    where = np.empty(perm.size, dtype=int)
    where[perm] = np.arange(perm.size)
    assert np.max(np.abs(where[K.row] - where[K.col])) <= 6 < np.max(np.abs(K.row - K.col))
    d, y = banded_kkt(P, q, C, np.concatenate((e, h[:40:7])))
    np.testing.assert_allclose(P @ d + q + C.T @ y, 0.0, atol=1e-12)
    np.testing.assert_allclose(C @ d, np.concatenate((e, h[:40:7])), atol=1e-12)


def test_minimize_with_the_guess_matches_without_on_a_sparse_problem():
    """A sparse nonlinear program above the dense limit solved with ``active_set_guess`` reaches the same point as
    the backends alone, with some subproblem solved on the guess."""
    n = 400
    fun, jac, hess, lumen = chain_in_a_box(np.random.default_rng(4).normal(size=n))
    plain = sqp.minimize(fun, np.zeros(n), jac=jac, hess=hess, constraints=[lumen])
    guessed = sqp.minimize(fun, np.zeros(n), jac=jac, hess=hess, constraints=[lumen], active_set_guess=True)
    assert plain.success and guessed.success
    assert any(rec.qp_status == "active set" for rec in guessed.history)
    np.testing.assert_allclose(guessed.x, plain.x, atol=1e-7)
    assert guessed.fun == pytest.approx(plain.fun, rel=1e-10)



@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("shift", [1e-4, 1e-2])
def test_a_start_without_multipliers_guesses_its_own_working_set(seed, shift):
    """With no starting multipliers the first QP is guessed on the rows the start meets with no slack (or violates):
    a start on the solution's active rows, its other components moved by ``shift``, has its first QP solved by one
    banded KKT solve instead of a backend, and reaches the same point; the same start without the guess goes to the
    backend."""
    n = 400
    rng = np.random.default_rng(seed)
    # runs of 20 components pulled well outside the rows (|target| 2) or kept well inside (0.2): every row strictly
    # active or strictly slack at the solution, so the QP's active set is the solution's at any nearby start
    outside = np.repeat(rng.uniform(size=n // 20) < 0.5, 20)
    target = np.where(outside, 2.0, 0.2) * rng.choice([-1.0, 1.0])  # (one side: no run pulled across the middle)
    fun, jac, hess, lumen = chain_in_a_box(target)
    plain = sqp.minimize(fun, np.zeros(n), jac=jac, hess=hess, constraints=[lumen])
    assert plain.success
    held = np.abs(plain.constraint_multipliers[0]) > 1e-8
    np.testing.assert_array_equal(held, outside)
    # (the free components moved towards the middle, so that no row the solution releases starts without slack)
    x0 = np.where(held, np.sign(plain.x) * np.sqrt(0.5), plain.x * (1.0 - shift * rng.uniform(size=n)))
    guessed = sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[lumen], active_set_guess=True)
    assert guessed.success, guessed.message
    assert guessed.history[0].qp_status == "active set"
    np.testing.assert_allclose(guessed.x, plain.x, atol=1e-7)
    unguessed = sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[lumen])
    assert unguessed.history[0].qp_status != "active set"
    assert guessed.fun == pytest.approx(plain.fun, rel=1e-10)

def test_a_qp_every_backend_fails_is_solved_by_further_corrections_of_its_guess():
    """When every backend fails a QP that has a guess (simulated by a backend stopped after one iteration, as PIQP and
    Clarabel stop short on an ill-conditioned augmented-Lagrangian model), the guess is corrected further
    (:data:`sqp.active_set.RESCUE_GUESSES` solves) and its checked answer is the QP's solution, not a failure that
    sends the iteration to the elastic QP. Over bound-constrained chain QPs guessed with every row's state flipped
    (some need more corrections than :data:`~sqp.active_set.MAX_GUESSES`); with nothing guessed the QP still fails."""
    from sqp.active_set import MAX_GUESSES
    from sqp.problem import Rows
    from sqp.subproblem import LinearisedRows, solve_subproblem

    stopped = [("piqp", {"max_iter": 1})]
    beyond = 0
    for n, seed in [(80, 0), (200, 0), (200, 1), (200, 4), (200, 5)]:
        P, q, _, _, G, h = _chain_qp(n, seed)
        ref = qpsolvers.solve_problem(qpsolvers.Problem(P.toarray(), q, G.toarray(), h), solver="quadprog")
        guess = ~(ref.z > 1e-9)
        no_rows = sp.csr_matrix((0, n))
        beyond += guessed_qp(P, q, no_rows, np.zeros(0), G, h, guess, 1.0, MAX_GUESSES) is None
        lb = np.full(n, -np.inf)
        linear = LinearisedRows(M=sp.csr_matrix(G), lo=lb, hi=h, rows=Rows.from_bounds(lb, h))
        none = np.zeros(0)
        nonlinear = LinearisedRows(M=no_rows, lo=none, hi=none, rows=Rows.from_bounds(none, none))
        box = (np.full(n, -np.inf), np.full(n, np.inf))
        qp = solve_subproblem(P, q, nonlinear, linear, *box, backends=stopped, active=guess)
        assert qp.found and qp.status == "active set" and not qp.elastic
        np.testing.assert_allclose(qp.d, ref.x, atol=1e-8)
        assert not solve_subproblem(P, q, nonlinear, linear, *box, backends=stopped).found
    assert beyond >= 2


def test_a_backends_answer_to_a_guessed_qp_is_polished_to_the_kkt_point_of_the_rows_it_holds():
    """A QP with a guess that the guess does not solve goes to the backend; its answer is then solved again exactly
    on the rows its multipliers hold (one banded KKT solve): stationarity and complementarity to rounding (an interior
    point leaves its own tolerance in them, which an SQP's KKT test near a solution cannot get below), the same
    step as a dense active-set backend's, over bound-constrained chain QPs of several sizes."""
    from sqp.problem import Rows
    from sqp.subproblem import LinearisedRows, solve_subproblem

    for n, seed in [(60, 0), (80, 1), (200, 2), (200, 3)]:
        P, q, _, _, G, h = _chain_qp(n, seed)
        ref = qpsolvers.solve_problem(qpsolvers.Problem(P.toarray(), q, G.toarray(), h), solver="quadprog")
        guess = np.zeros(n, dtype=bool)
        no_rows = sp.csr_matrix((0, n))
        assert guessed_qp(P, q, no_rows, np.zeros(0), G, h, guess, 1.0, 1) is None  # the guess alone fails
        lb = np.full(n, -np.inf)
        linear = LinearisedRows(M=sp.csr_matrix(G), lo=lb, hi=h, rows=Rows.from_bounds(lb, h))
        none = np.zeros(0)
        nonlinear = LinearisedRows(M=no_rows, lo=none, hi=none, rows=Rows.from_bounds(none, none))
        box = (np.full(n, -np.inf), np.full(n, np.inf))
        qp = solve_subproblem(P, q, nonlinear, linear, *box, backends=[("piqp", {})], active=guess, first=True)
        assert qp.found and qp.status == "polished"
        z = -qp.lam_lin  # (the engine's sign: a held upper side has a negative multiplier)
        assert np.all(z >= 0.0)
        assert np.max(np.abs(P @ qp.d + q + G.T @ z)) <= 1e-12
        assert np.max(np.abs(z * (G @ qp.d - h))) <= 1e-12 and np.max(G @ qp.d - h) <= 1e-12
        np.testing.assert_allclose(qp.d, ref.x, atol=1e-10)
