"""Bar tangents from the material frames, with their derivatives in the chart, and node positions.

Bar ``k`` runs from node ``k − 1`` to node ``k`` (node 0 the clamp) along its frame's third axis::

    t(q) = R(q) e3 = N(q) / |q|²,   N(q) = (2(xz + wy), 2(yz − wx), w² − x² − y² + z²)

(homogeneous of degree 0: the chart's unnormalised ``q = q⁰ + E ω`` needs no unit-norm row), and
``p_k = p_0 + Σ_{j ≤ k} l_j t_j``. The derivatives ``∂t/∂ω`` (3 × 3 per bar) and ``∂²t/∂ω²`` (3 × 3 × 3 per bar) are
exact (the quotient rule on the quadratic forms ``N_i = qᵀ A_i q`` and ``|q|²``, carried through the affine chart),
O(n) for the whole chain.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import quaternion as quat

FloatArray = NDArray[np.float64]


TANGENT_FORMS = np.array([[[0, 0, 1, 0], [0, 0, 0, 1], [1, 0, 0, 0], [0, 1, 0, 0]],
                          [[0, -1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1], [0, 0, 1, 0]],
                          [[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1]]], dtype=float)
"""Symmetric ``A_i`` (3, 4, 4) with ``N_i(q) = qᵀ A_i q`` (:func:`guidewire.rod.quaternion.tangent_components`)."""


def chart_forms(basis: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``(EᵀE (n, 3, 3), Eᵀ A_i E (n, 3, 3, 3))`` of the charts ``basis`` (n, 4, 3): the parts of :func:`tangents`'
    second derivatives that do not depend on ``ω`` (a program keeps its charts through a solve: computed once)."""
    return basis.transpose(0, 2, 1) @ basis, basis.transpose(0, 2, 1)[:, None] @ (TANGENT_FORMS @ basis[:, None])


def tangents(q0: FloatArray, basis: FloatArray, omega: FloatArray, derivatives: bool = True,
             forms: tuple[FloatArray, FloatArray] | None = None) -> tuple[Any, Any, Any]:
    """Unit tangents (n, 3), ``∂t/∂ω`` (n, 3, 3) and ``∂²t/∂ω²`` (n, 3, 3, 3) at ``q = q0 + basis ω``; with
    ``derivatives`` False the tangents alone (the same numbers) and two None. ``forms``: :func:`chart_forms` of
    ``basis`` when the caller keeps them (else computed here; the same numbers)."""
    q = q0 + np.einsum("kij,kj->ki", basis, omega)
    # N_i = qᵀ A_i q and s = |q|²; t_i = N_i / s by the quotient rule in q, then through the chart (q affine in ω:
    # ∂t/∂ω = ∂t/∂q E, ∂²t/∂ω² = Eᵀ ∂²t/∂q² E)
    s = np.einsum("ki,ki->k", q, q)
    grad_n = 2.0 * np.einsum("iab,kb->kia", TANGENT_FORMS, q)  # ∂N_i/∂q (n, 3, 4)
    n_value = 0.5 * np.einsum("kia,ka->ki", grad_n, q)
    t = n_value / s[:, None]
    if not derivatives:
        return t, None, None
    e_grad_n = grad_n @ basis  # Eᵀ ∂N_i/∂q (n, 3, 3)
    e_q = np.einsum("kab,ka->kb", basis, q)  # Eᵀ q (n, 3)
    dt = (e_grad_n - 2.0 * t[:, :, None] * e_q[:, None, :]) / s[:, None, None]
    ete, eae = chart_forms(basis) if forms is None else forms  # EᵀE, Eᵀ A_i E (n, 3, 3, 3)
    mixed = e_grad_n[:, :, :, None] * e_q[:, None, None, :]
    ddt = (2.0 * eae - 2.0 * (mixed + mixed.transpose(0, 1, 3, 2)) / s[:, None, None, None]
           - 2.0 * t[:, :, None, None] * ete[:, None] + 8.0 * t[:, :, None, None] * (e_q[:, None, :, None]
                                                                                     * e_q[:, None, None, :])
           / s[:, None, None, None]) / s[:, None, None, None]
    return t, dt, ddt


def unit_tangents(q: FloatArray) -> FloatArray:
    """Unit tangents (n, 3) of frames ``q`` (n, 4), normalised or not."""
    q = quat.as_array(q)
    return np.stack(quat.tangent_components(q.T), axis=1) / quat.norm2(q.T)[:, None]


def nodes(base_point: FloatArray, lengths: FloatArray, q: FloatArray) -> FloatArray:
    """Node positions (n + 1, 3), the clamp first: the running sum of ``l_k t_k``."""
    steps = np.asarray(lengths, dtype=float)[:, None] * unit_tangents(q)
    return np.vstack((np.asarray(base_point, dtype=float), np.asarray(base_point, dtype=float)
                      + np.cumsum(steps, axis=0)))
