"""Bar tangents from the material frames, with their derivatives in the chart, and node positions.

Bar ``k`` runs from node ``k − 1`` to node ``k`` (node 0 the clamp) along its frame's third axis::

    t(q) = R(q) e3 = N(q) / |q|²,   N(q) = (2(xz + wy), 2(yz − wx), w² − x² − y² + z²)

(homogeneous of degree 0: the chart's unnormalised ``q = q⁰ + E ω`` needs no unit-norm row), and
``p_k = p_0 + Σ_{j ≤ k} l_j t_j``. The derivatives ``∂t/∂ω`` (3 × 3 per bar) and ``∂²t/∂ω²`` (3 × 3 × 3 per bar) are
exact (:mod:`guidewire.rod.jet`), O(n) for the whole chain.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from . import quaternion as quat
from .jet import Jet

FloatArray = NDArray[np.float64]


def tangents(q0: FloatArray, basis: FloatArray, omega: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Unit tangents (n, 3), ``∂t/∂ω`` (n, 3, 3) and ``∂²t/∂ω²`` (n, 3, 3, 3) at ``q = q0 + basis ω``."""
    q = q0 + np.einsum("kij,kj->ki", basis, omega)
    jets = [Jet.affine(q[:, c], basis[:, c]) for c in range(4)]
    inverse = quat.norm2(jets).reciprocal()
    t = [component * inverse for component in quat.tangent_components(jets)]
    return (np.stack([c.value for c in t], axis=1), np.stack([c.grad for c in t], axis=1),
            np.stack([c.hess for c in t], axis=1))


def unit_tangents(q: FloatArray) -> FloatArray:
    """Unit tangents (n, 3) of frames ``q`` (n, 4), normalised or not."""
    q = quat.as_array(q)
    return np.stack(quat.tangent_components(q.T), axis=1) / quat.norm2(q.T)[:, None]


def nodes(base_point: FloatArray, lengths: FloatArray, q: FloatArray) -> FloatArray:
    """Node positions (n + 1, 3), the clamp first: the running sum of ``l_k t_k``."""
    steps = np.asarray(lengths, dtype=float)[:, None] * unit_tangents(q)
    return np.vstack((np.asarray(base_point, dtype=float), np.asarray(base_point, dtype=float)
                      + np.cumsum(steps, axis=0)))
