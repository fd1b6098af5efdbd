"""A sparse model's augmented-Lagrangian weight fades once it is no longer needed (:func:`sqp.hessian.convexify`).

The weight that made ``W + r C^T C`` positive definite is the next iteration's start, quartered. A sparse weight that
was kept instead ratcheted up: after one iteration that needed a large weight every later model carried it, and on
the guidewire's vessels at 1 600-3 200 bars those models were too ill-conditioned for the QP backends.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from sqp.hessian import DENSE_LIMIT, LADDER_GROWTH, WEIGHT_DECAY, convexify


def _blocks(across: float, seed: int, copies: int = 34) -> tuple[sp.csc_matrix, sp.csr_matrix]:
    """Block-diagonal ``(W, C)`` of ``copies`` 12-variable blocks, each positive definite on its 5 rows' null space
    (eigenvalues 1..7 there) and ``-across`` on their row space (rows with singular values 1 to 1e-2)."""
    rng = np.random.default_rng(seed)
    Ws, Cs = [], []
    for _ in range(copies):
        U, _ = np.linalg.qr(rng.standard_normal((5, 5)))
        V, _ = np.linalg.qr(rng.standard_normal((12, 12)))
        Y, Z = V[:, :5], V[:, 5:]
        Cs.append(U @ np.diag(np.logspace(0.0, -2.0, 5)) @ Y.T)
        W = Z @ np.diag(1.0 + np.arange(7.0)) @ Z.T - across * (Y @ Y.T)
        Ws.append(0.5 * (W + W.T))
    return sp.block_diag(Ws, format="csc"), sp.block_diag(Cs, format="csr")


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("before", [1e2, 1e4])
def test_a_sparse_weight_falls_back_to_what_the_model_needs(seed, before):
    """After a model that needed a large weight (curvature ``-before`` across the rows), models needing a small one
    (``-1`` across) are given, after a few more than ``log_4`` of the ratio iterations, weights below ten times the
    one a fresh ladder finds (the quartered weight fails below the least weight that passes, ``w*``, and the ladder
    then takes ten times it: once below ``4 w*`` the weights stay below ``10 w*``, and a fresh ladder's is at least
    ``w*``); every model positive definite without a shift."""
    W_big, C = _blocks(before, seed)
    W_small, _ = _blocks(1.0, seed)
    assert W_big.shape[0] > DENSE_LIMIT  # (the sparse path)
    _, _, heavy = convexify(W_big, 0.0, C, 0.0)
    _, _, fresh = convexify(W_small, 0.0, C, 0.0)
    assert heavy > 10.0 * fresh > 0.0
    weight, weights = heavy, []
    for _ in range(int(np.ceil(np.log(heavy / fresh) / np.log(WEIGHT_DECAY))) + 8):
        B, delta, weight = convexify(W_small, 0.0, C, weight, alone_first=False)
        assert delta == 0.0
        np.testing.assert_allclose((B - W_small - weight * (C.T @ C)).toarray(), 0.0, atol=1e-9 * weight)
        weights.append(weight)
    assert max(weights[-4:]) < LADDER_GROWTH * fresh
