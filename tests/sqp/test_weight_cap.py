"""The augmented-Lagrangian ladder stops at a weight a QP backend can still use (:data:`sqp.hessian.AL_WEIGHT_RUNGS`).

``W = [[-a, b], [b, eps]]`` with the row ``C = [1, 0]`` is convex on the row's null space (curvature ``eps``), and
``W + r C^T C`` is positive definite exactly when ``r > a + b^2 / eps``: the flatter the null space, the larger the
weight. Up to the ladder's last rung (``1e9`` times its first weight) the weight is the model; past it, the identity
shift is, whose model is well conditioned; the weight's would have a condition of ``r / eps`` (~1e15 for the
aortic arch's start that took 54.6 s: every QP on such a model failed in every backend).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from sqp.hessian import AL_WEIGHT_RUNGS, AL_WEIGHT_START, DENSE_LIMIT, LADDER_GROWTH, convexify


def _pair(needed: float) -> tuple[np.ndarray, np.ndarray]:
    """``(W, C)`` with ``a = b = 1``: ``W + r C^T C`` positive definite exactly for ``r > needed``."""
    eps = 1.0 / (needed - 1.0)
    return np.array([[-1.0, 1.0], [1.0, eps]]), np.array([[1.0, 0.0]])


def _problem(needed: float, sparse: bool) -> tuple[object, object]:
    W, C = _pair(needed)
    if not sparse:
        return W, C
    copies = DENSE_LIMIT // 2 + 1  # (block-diagonal copies: the sparse, banded path above DENSE_LIMIT)
    return sp.block_diag([W] * copies, format="csc"), sp.block_diag([C] * copies, format="csr")


LAST_RUNG = AL_WEIGHT_START * LADDER_GROWTH ** (AL_WEIGHT_RUNGS - 1)  # (scale and max C^T C_ii are 1 here)


@pytest.mark.parametrize("sparse", [False, True])
@pytest.mark.parametrize("needed", [3e1, 3e3, 3e5, 3e6, 3e8, 3e10])
def test_the_weight_stops_at_the_last_rung_and_the_shift_takes_over(needed, sparse):
    W, C = _problem(needed, sparse)
    B, delta, weight = convexify(W, 0.0, C, 0.0)
    dense = B.toarray() if sp.issparse(B) else np.asarray(B)
    lowest = float(np.linalg.eigvalsh(dense)[0])
    assert lowest > 0.0
    # (the cap measured on the arch: weights past 1e9 times the first left QPs no backend could solve)
    assert weight <= 1e9 * AL_WEIGHT_START and np.linalg.cond(dense) < 1e13
    if needed < LAST_RUNG:
        # the first rung past the weight needed, and no shift
        assert delta == 0.0 and needed < weight <= LADDER_GROWTH * needed
    else:
        # the shift: W + delta I, conditioned by W's own spectrum (|eigenvalues| about 1.6), not by r / eps
        assert weight == 0.0 and delta > 0.0
        np.testing.assert_allclose(dense, (W.toarray() if sp.issparse(W) else W) + delta * np.eye(dense.shape[0]),
                                   rtol=0, atol=1e-12)
        assert np.linalg.cond(dense) < 1e10
