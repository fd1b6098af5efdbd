"""The identity shift on top of the augmented-Lagrangian term (:func:`sqp.hessian.shifted_augmented`) covers only the
negative curvature of ``W`` on the null space of the held rows ``C``: the weight grows while that lowers the shift.

``W`` is built with a prescribed reduced Hessian (on ``null(C)``, lowest eigenvalue ``-lam``) and a strongly negative
block across the rows (``-across``), with rows of very different sizes (as the guidewire's closure rows are, node
and frame variables in different units): at the ladder's first weight the shift must cover nearly all of
``across``, and a step along the reduced Hessian's negative direction is then ``across / lam`` times too short.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from sqp.hessian import AL_WEIGHT_START, LADDER_GROWTH, SHIFT_CONDITION, SHIFT_START, SHIFTED_WEIGHT, shifted_augmented


def _saddle(n: int, m: int, lam: float, across: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """``(W, C)``: ``C`` (m, n) with singular values from 1 down to 1e-2; ``W`` equal to ``diag(-lam, 1, 2, ...)``
    on an orthonormal basis of ``null(C)`` and to ``-across I`` on ``C``'s row space."""
    rng = np.random.default_rng(seed)
    U, _ = np.linalg.qr(rng.standard_normal((m, m)))
    V, _ = np.linalg.qr(rng.standard_normal((n, n)))
    Y, Z = V[:, :m], V[:, m:]
    C = U @ np.diag(np.logspace(0.0, -2.0, m)) @ Y.T
    reduced = np.concatenate(([-lam], 1.0 + np.arange(n - m - 1)))
    W = Z @ np.diag(reduced) @ Z.T - across * (Y @ Y.T)
    return 0.5 * (W + W.T), C


@pytest.mark.parametrize("lam", [1e-3, 0.1, 1.0])
@pytest.mark.parametrize("across", [30.0, 1e3, 1e5])
@pytest.mark.parametrize("sparse", [False, True])
@pytest.mark.parametrize("seed", [0, 1])
def test_the_shift_covers_the_reduced_hessian_not_the_curvature_across_the_rows(lam, across, sparse, seed):
    """``B = W + r C^T C + delta I`` is positive definite and its shift is within one rung of the ladder
    (``LADDER_GROWTH``) of the reduced Hessian's ``lam``, whatever the curvature across the rows (the first weight
    alone needed a shift of the order of ``across``), unless a shift that small would leave ``B`` worse conditioned
    than ``1 / SHIFT_CONDITION``: it is then within one rung of ``SHIFT_CONDITION (max|W_ii| + r max|C^T C_ii|)``
    and not below it."""
    W, C = _saddle(12, 5, lam, across, seed)
    Wm, Cm = (sp.csc_matrix(W), sp.csr_matrix(C)) if sparse else (W, C)
    B, delta, r = shifted_augmented(Wm, Cm, 0.0)
    dense = B.toarray() if sp.issparse(B) else np.asarray(B)
    np.testing.assert_allclose(dense, W + r * C.T @ C + delta * np.eye(12), rtol=1e-12, atol=1e-9 * r)
    assert np.linalg.eigvalsh(dense)[0] > 0.0
    scale = max(1.0, float(np.abs(W.diagonal()).max()))
    floor = SHIFT_CONDITION * (scale + r * float(np.max(np.diag(C.T @ C))))
    assert lam < delta <= LADDER_GROWTH * max(lam, SHIFT_START * scale, floor) * (1.0 + 1e-12)
    assert delta >= floor * (1.0 - 1e-12) or r == pytest.approx(SHIFTED_WEIGHT * AL_WEIGHT_START * scale / float(
        np.max(np.diag(C.T @ C))), rel=1e-14)


def test_where_the_first_weight_needs_the_first_rung_no_larger_weight_is_taken():
    """A ``W`` nearly positive definite everywhere (the ladder's first shift covers it at the first weight): the
    weight stays the first one, and ``B`` is what the single ladder gave."""
    W, C = _saddle(12, 5, 1e-12, -1.0, 0)  # (positive across the rows; -1e-12 on the null space)
    B, delta, r = shifted_augmented(W, C, 0.0)
    scale = max(1.0, float(np.abs(W.diagonal()).max()))
    assert r == pytest.approx(SHIFTED_WEIGHT * AL_WEIGHT_START * scale / float(np.max(np.diag(C.T @ C))), rel=1e-14)
    assert delta == pytest.approx(SHIFT_START * scale, rel=1e-14)
    assert np.linalg.eigvalsh(np.asarray(B))[0] > 0.0
