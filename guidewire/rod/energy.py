"""Bending and twist energy of a clamped 3D bar chain, with its analytic gradient.

Variables: node positions ``x`` (shape ``(n + 1, 3)``, node 0 at the clamp) and one material angle ``θ_j`` per bar.

Bending uses the weights of the planar second-order scheme (:mod:`guidewire.energy`): the turning angle ``α`` between
consecutive bars ``k, k+1`` carries ``c = EI / (l_k + l_{k+1})`` (uniform ``EI``), the clamp is a half joint between
the base tangent and bar 1 with ``c = EI / l_1``; ``E_b = Σ c α²``. For a planar chain ``α = |φ_{k+1} − φ_k|``, so the
energy is the 2D one exactly. ``α = atan2(|a × b|, a · b)`` for the unit tangents ``a, b``; ``α²`` is smooth at
``α = 0`` (its gradient carries ``α / sin α → 1``).

Twist between consecutive material frames: ``E_t = Σ GJ / (l_k + l_{k+1}) (θ_{k+1} − θ_k)²`` plus the base half joint
``GJ / l_1 (θ_1 − ψ₀)²`` with the imposed base rotation ``ψ₀``. The reference twist of the parallel-transported frame
is not included yet, so twist is exact for straight or planar chains only (no rest curvature either).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

POISSON_STEEL_NITINOL = 0.3  # G = E / (2 (1 + ν)); ν ≈ 0.3 for steel and nitinol


@dataclass(frozen=True)
class RodEnergy:
    """Energy of a clamped rod with bar lengths ``lengths`` (``(n,)``), stiffnesses ``EI`` and ``GJ`` (scalars)."""

    lengths: FloatArray
    EI: float
    GJ: float
    base_tangent: FloatArray
    base_angle: float = 0.0

    def __post_init__(self) -> None:
        lengths = np.asarray(self.lengths, dtype=float)
        if lengths.ndim != 1 or lengths.size < 1 or not np.all(lengths > 0):
            raise ValueError(f"lengths has shape {lengths.shape}; expected (n,) positive bar lengths.")
        if not (self.EI > 0 and self.GJ >= 0):
            raise ValueError("EI must be positive and GJ non-negative.")
        t0 = np.asarray(self.base_tangent, dtype=float)
        if t0.shape != (3,) or not np.isclose(np.linalg.norm(t0), 1.0):
            raise ValueError(f"base_tangent has shape {t0.shape}; expected a unit 3-vector.")
        object.__setattr__(self, "lengths", lengths)
        object.__setattr__(self, "base_tangent", t0)

    @property
    def weights(self) -> FloatArray:
        """Bending weights per joint, ``(n,)``: the clamp half joint first, then the interior joints."""
        l = self.lengths
        return np.concatenate([[1.0 / l[0]], 1.0 / (l[:-1] + l[1:])])

    def _tangents(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        e = np.diff(x, axis=0)
        norm = np.linalg.norm(e, axis=1)
        return np.vstack([self.base_tangent, e / norm[:, None]]), norm

    def bending(self, x: FloatArray) -> float:
        """Bending energy ``Σ c α²`` of node positions ``x`` (``(n + 1, 3)``)."""
        t, _ = self._tangents(x)
        alpha = _turning(t[:-1], t[1:])
        return float(self.EI * np.sum(self.weights * alpha**2))

    def bending_gradient(self, x: FloatArray) -> FloatArray:
        """Gradient of :meth:`bending` with respect to ``x``, ``(n + 1, 3)`` (node 0 included, as a free node)."""
        t, norm = self._tangents(x)
        a, b = t[:-1], t[1:]
        cos = np.einsum("ij,ij->i", a, b)
        alpha = _turning(a, b)
        ratio = np.where(alpha > 1e-8, alpha / np.maximum(np.sin(alpha), 1e-300), 1.0)
        coef = -2.0 * self.EI * self.weights * ratio
        d_b = coef[:, None] * (a - cos[:, None] * b)  # d(c α²)/d b̂ projected; divide by |e| below
        d_a = coef[:, None] * (b - cos[:, None] * a)
        g_edge = d_b / norm[:, None]
        g_edge[:-1] += d_a[1:] / norm[:-1, None]
        g = np.zeros_like(x, dtype=float)
        g[1:] += g_edge
        g[:-1] -= g_edge
        return g

    def twist(self, theta: FloatArray) -> float:
        """Twist energy of the material angles ``theta`` (``(n,)``)."""
        d = np.diff(np.concatenate([[self.base_angle], theta]))
        return float(self.GJ * np.sum(self.weights * d**2))

    def twist_gradient(self, theta: FloatArray) -> FloatArray:
        """Gradient of :meth:`twist`, ``(n,)``."""
        d = np.diff(np.concatenate([[self.base_angle], theta]))
        w = 2.0 * self.GJ * self.weights * d
        g = w.copy()
        g[:-1] -= w[1:]
        return g


def _turning(a: FloatArray, b: FloatArray) -> FloatArray:
    """Angle between unit vectors row by row, ``atan2(|a × b|, a · b)``."""
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))
