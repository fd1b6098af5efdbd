"""The elastic QP above ``DENSE_LIMIT`` variables: DAQP's proximal iteration (:data:`sqp.backends.ELASTIC_QP_OPTIONS`)
answers it as quadprog does.

The elastic QP's slack variables carry no curvature but a regularisation ``1e-10 max|B_ii|``; a family of such QPs
(random positive definite ``B``, pairs of contradictory rows, so that many slacks are positive) of more than
``DENSE_LIMIT`` variables in all (on which DAQP's default regularisation takes ~7 times as long: 3.5 s, 0.47 s with the
proximal iteration; quadprog 1.5 s)."""

from __future__ import annotations

import numpy as np
import pytest

from sqp.backends import DEFAULT_QP_OPTIONS, DENSE_LIMIT, ELASTIC_QP_OPTIONS, elastic_backends
from sqp.qp_call import solve_qp
from sqp.subproblem import _elastic_matrices_dense


@pytest.mark.parametrize("seed", range(2))
def test_daqps_proximal_answer_to_a_large_elastic_qp_is_quadprogs(seed):
    rng = np.random.default_rng(seed)
    n, m = 120, 200 + 10 * seed
    A = rng.standard_normal((n, n))
    B = A @ A.T / n + 0.1 * np.eye(n)
    g = rng.standard_normal(n)
    half = rng.standard_normal((m // 2, n))
    b = half @ rng.standard_normal(n)
    M = np.vstack((half, -half))  # (pairs of contradictory rows a·d ≥ b, a·d ≤ b − gap: each pair needs slack)
    lo = np.concatenate((b, -b + rng.uniform(0.1, 1.0, m // 2)))
    low = np.arange(m)
    G, E, P = _elastic_matrices_dense(B, M, low, np.zeros(0, dtype=int), np.zeros((0, n)), np.zeros((0, n)))
    rho = 10.0
    q = np.concatenate((g, np.full(m, rho)))
    lb = np.concatenate((np.full(n, -np.inf), np.zeros(m)))
    ub = np.full(n + m, np.inf)
    assert n + m > DENSE_LIMIT
    backends = elastic_backends([("daqp", DEFAULT_QP_OPTIONS["daqp"])], n + m)
    assert backends[0][1] == {**DEFAULT_QP_OPTIONS["daqp"], **ELASTIC_QP_OPTIONS["daqp"]}
    args = (P, q, G, -lo, E, np.zeros(0), lb, ub, None, rho)
    ours, used = solve_qp(backends, *args)
    reference, _ = solve_qp([("quadprog", {})], *args)
    assert ours is not None and used == "daqp" and reference is not None
    slack = ours.x[n:]
    assert np.count_nonzero(slack > 1e-6) >= m // 2  # (the family's QPs are elastic: a slack in every pair)
    np.testing.assert_allclose(ours.x, reference.x, atol=1e-6 * max(1.0, float(np.max(np.abs(reference.x)))))
    objective = [0.5 * x @ P @ x + q @ x for x in (ours.x, reference.x)]
    assert objective[0] == pytest.approx(objective[1], rel=1e-9)


def test_small_elastic_qps_keep_daqps_default():
    """Up to ``DENSE_LIMIT`` variables the backends are asked with their own settings."""
    backends = [("daqp", DEFAULT_QP_OPTIONS["daqp"]), ("clarabel", DEFAULT_QP_OPTIONS["clarabel"])]
    assert elastic_backends(backends, DENSE_LIMIT) is backends
    assert [s for _, s in elastic_backends(backends, DENSE_LIMIT + 1)][1] == DEFAULT_QP_OPTIONS["clarabel"]
