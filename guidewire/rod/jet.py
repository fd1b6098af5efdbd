"""Second-order jets: a value with its exact gradient and Hessian, carried through arithmetic by the chain rule.

The rod's strains are short formulas in the entries of a few quaternions (:mod:`guidewire.rod.strain`). Writing
their second derivatives out by hand is long and easy to get wrong; a :class:`Jet` carries, for ``m`` independent
instances at once (one per joint, vectorised), the value ``f`` (shape ``(m,)``), the gradient ``∂f/∂z`` (shape
``(m, k)``) and the Hessian ``∂²f/∂z²`` (shape ``(m, k, k)``) with respect to the ``k`` local variables of that instance
(the two bars' rotation parameters of a joint, ``k = 6``). Every operation applies the exact product, quotient or
chain rule, so the derivatives are the analytic ones (checked against finite differences in the tests); the cost is
O(m k²) per operation, O(n) per evaluation of the whole rod.

Rules (``'`` gradient, ``''`` Hessian):

- ``(f g)' = f' g + f g'``, ``(f g)'' = f'' g + f' g'ᵀ + g' f'ᵀ + f g''``;
- ``h(f)' = h'(f) f'``, ``h(f)'' = h''(f) f' f'ᵀ + h'(f) f''``;
- ``atan2(y, x)`` with ``∂/∂y = x/ρ²``, ``∂/∂x = −y/ρ²``, ``ρ² = x² + y²`` and their derivatives.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Jet:
    """``m`` scalar functions of ``k`` local variables each, with their gradients and Hessians.

    Attributes
    ----------
    value : ndarray, shape (m,)
    grad : ndarray, shape (m, k)
    hess : ndarray, shape (m, k, k), symmetric
    """

    value: FloatArray
    grad: FloatArray
    hess: FloatArray

    @classmethod
    def variables(cls, values: FloatArray) -> list[Jet]:
        """The ``k`` independent variables themselves, from ``values`` of shape (m, k)."""
        values = np.asarray(values, dtype=float)
        m, k = values.shape
        eye = np.eye(k)
        zero = np.zeros((m, k, k))
        return [cls(values[:, i].copy(), np.broadcast_to(eye[i], (m, k)).copy(), zero) for i in range(k)]

    @classmethod
    def affine(cls, offset: FloatArray, slope: FloatArray) -> Jet:
        """``offset + slope · z``: value ``offset`` (m,), gradient ``slope`` (m, k), Hessian zero."""
        slope = np.asarray(slope, dtype=float)
        m, k = slope.shape
        return cls(np.asarray(offset, dtype=float), slope, np.zeros((m, k, k)))

    @classmethod
    def constant(cls, value: FloatArray, k: int) -> Jet:
        value = np.asarray(value, dtype=float)
        m = value.size
        return cls(value, np.zeros((m, k)), np.zeros((m, k, k)))

    @property
    def k(self) -> int:
        return int(self.grad.shape[1])

    # -- arithmetic ------------------------------------------------------------------------------------------------
    def __add__(self, other: Jet | float | FloatArray) -> Jet:
        if isinstance(other, Jet):
            return Jet(self.value + other.value, self.grad + other.grad, self.hess + other.hess)
        return Jet(self.value + other, self.grad, self.hess)

    __radd__ = __add__

    def __neg__(self) -> Jet:
        return Jet(-self.value, -self.grad, -self.hess)

    def __sub__(self, other: Jet | float | FloatArray) -> Jet:
        return self + (-other)

    def __rsub__(self, other: float | FloatArray) -> Jet:
        return (-self) + other

    def __mul__(self, other: Jet | float | FloatArray) -> Jet:
        if isinstance(other, Jet):
            outer = self.grad[:, :, None] * other.grad[:, None, :]
            return Jet(self.value * other.value,
                       self.grad * other.value[:, None] + other.grad * self.value[:, None],
                       self.hess * other.value[:, None, None] + other.hess * self.value[:, None, None]
                       + outer + outer.transpose(0, 2, 1))
        c = np.asarray(other, dtype=float)
        if c.ndim == 0:
            return Jet(self.value * c, self.grad * c, self.hess * c)
        return Jet(self.value * c, self.grad * c[:, None], self.hess * c[:, None, None])

    __rmul__ = __mul__

    def square(self) -> Jet:
        """``f²`` (one outer product instead of two)."""
        outer = self.grad[:, :, None] * self.grad[:, None, :]
        return Jet(self.value**2, 2.0 * self.value[:, None] * self.grad,
                   2.0 * (outer + self.value[:, None, None] * self.hess))

    def apply(self, h: FloatArray, h1: FloatArray, h2: FloatArray) -> Jet:
        """``h(f)`` given ``h``, ``h'`` and ``h''`` evaluated at ``f`` (each shape (m,))."""
        outer = self.grad[:, :, None] * self.grad[:, None, :]
        return Jet(np.asarray(h, dtype=float), h1[:, None] * self.grad,
                   h2[:, None, None] * outer + h1[:, None, None] * self.hess)

    def map(self, function: Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray]]) -> Jet:
        """``h(f)`` for ``function(f) -> (h, h', h'')``."""
        return self.apply(*function(self.value))

    def reciprocal(self) -> Jet:
        v = self.value
        return self.apply(1.0 / v, -1.0 / v**2, 2.0 / v**3)

    def __truediv__(self, other: Jet | float | FloatArray) -> Jet:
        if isinstance(other, Jet):
            return self * other.reciprocal()
        return self * (1.0 / np.asarray(other, dtype=float))

    def sqrt(self) -> Jet:
        r = np.sqrt(self.value)
        return self.apply(r, 0.5 / r, -0.25 / (r * self.value))


def atan2(y: Jet, x: Jet) -> Jet:
    """``atan2(y, x)`` with its exact gradient and Hessian (``(x, y) ≠ 0``)."""
    rho2 = x.value**2 + y.value**2
    hy, hx = x.value / rho2, -y.value / rho2
    hyy = -2.0 * x.value * y.value / rho2**2
    hxy = (y.value**2 - x.value**2) / rho2**2
    gy, gx = y.grad, x.grad
    cross = gy[:, :, None] * gx[:, None, :]
    hess = (hyy[:, None, None] * (gy[:, :, None] * gy[:, None, :] - gx[:, :, None] * gx[:, None, :])
            + hxy[:, None, None] * (cross + cross.transpose(0, 2, 1))
            + hy[:, None, None] * y.hess + hx[:, None, None] * x.hess)
    return Jet(np.arctan2(y.value, x.value), hy[:, None] * gy + hx[:, None] * gx, hess)


def stack_values(jets: list[Jet]) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Values (m, c), gradients (m, c, k) and Hessians (m, c, k, k) of ``c`` jets side by side."""
    return (np.stack([j.value for j in jets], axis=1), np.stack([j.grad for j in jets], axis=1),
            np.stack([j.hess for j in jets], axis=1))
