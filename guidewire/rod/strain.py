"""The strains of a joint between two material frames: bending (turning angle, in material axes) and twist.

Given the frames of two bars as quaternions ``q_a`` (nearer the base) and ``q_b``, their relative rotation in the
body axes of ``a`` is ``r = q̄_a ⊗ q_b = (r0, rx, ry, rz)``. It splits uniquely into a *swing* (the least rotation
taking ``t_a`` onto ``t_b``: the parallel transport of discrete elastic rods, Bergou et al. 2008) and a *twist* about
the tangent (the angle between the transported ``d1_a`` and ``d1_b``). With ``a = rx² + ry²`` and ``b = r0² + rz²``::

    turning angle     ψ = 2 atan2(√a, √b)                  (= acos(t_a · t_b) exactly)
    twist             τ = 2 atan2(rz, r0)                  (DER's twist: transported d1_a to d1_b about t_b)
    bending vector    κ = ψ (rx, ry) / √a = 2 G(a/b) (rx, ry) / √b,    G(y) = atan(√y) / √y

``κ`` holds the components of the swing's rotation vector ``ψ b̂`` (``b̂`` the unit binormal ``t_a × t_b / |…|``)
in the frame halfway between ``a`` and ``b`` (``a``'s frame turned about its tangent by ``τ/2``); in ``a``'s own axes
they are ``2 G (r0 + i rz)(rx + i ry) / b`` and in ``b``'s ``2 G (r0 − i rz)(rx + i ry) / b`` (as complex numbers
``κ1 + i κ2``). ``G`` is smooth at 0 (``1 − y/3 + y²/5 − …``), so every strain is a smooth function of ``r`` while the
joint turns by less than a half-turn; each is homogeneous of degree 0 in ``r`` (unnormalised quaternions are fine).

A planar chain with ``d2`` normal to its plane and no twist has ``κ = (0, Δφ)`` and ``τ = 0``, with ``Δφ`` the signed
turning angle of the planar model (:mod:`guidewire.energy`): the 3-D energy is the 2-D one there.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .jet import Jet, atan2

FloatArray = NDArray[np.float64]

SERIES_LIMIT = 0.05
"""Below this ``y`` the function ``G(y) = atan(√y)/√y`` and its derivatives are summed as power series (the closed
forms lose digits to cancellation as ``y → 0``); 24 terms leave an error below 1e-30 there."""

_TERMS = 24
_K = np.arange(_TERMS)
_COEF = (-1.0) ** _K / (2 * _K + 1)


def atan_ratio(y: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``G(y) = atan(√y)/√y`` with ``G'`` and ``G''`` for ``y ≥ 0`` (vectorised)."""
    y = np.asarray(y, dtype=float)
    small = y < SERIES_LIMIT
    ys = np.where(small, y, 0.0)
    powers = ys[..., None] ** _K  # y^k
    g_s = powers @ _COEF
    g1_s = powers[..., :-1] @ (_COEF[1:] * _K[1:])
    g2_s = powers[..., :-2] @ (_COEF[2:] * _K[2:] * _K[1:-1])
    yl = np.where(small, 1.0, y)
    root = np.sqrt(yl)
    g = np.arctan(root) / root
    h = 1.0 / (1.0 + yl) - g
    g1 = h / (2.0 * yl)
    h1 = -1.0 / (1.0 + yl) ** 2 - g1
    g2 = (h1 * yl - h) / (2.0 * yl**2)
    return np.where(small, g_s, g), np.where(small, g1_s, g1), np.where(small, g2_s, g2)


def joint_strain(r: list[Jet], axes: str = "mid") -> tuple[Jet, Jet, Jet]:
    """``(κ1, κ2, τ)`` of the relative rotation ``r`` (four jets), the bending in ``axes`` ``"mid"``, ``"a"`` or
    ``"b"`` (see the module docstring)."""
    r0, rx, ry, rz = r
    a = rx.square() + ry.square()
    b = r0.square() + rz.square()
    g = (a / b).map(atan_ratio)
    tau = 2.0 * atan2(rz, r0)
    if axes == "mid":
        scale = 2.0 * g / b.sqrt()
        return scale * rx, scale * ry, tau
    sign = 1.0 if axes == "a" else -1.0
    scale = 2.0 * g / b
    c1 = r0 * rx - sign * (rz * ry)
    c2 = r0 * ry + sign * (rz * rx)
    return scale * c1, scale * c2, tau


def turning_angle(r: list[Jet]) -> Jet:
    """``ψ = 2 atan2(√a, √b)``, the angle between the two tangents (rad)."""
    r0, rx, ry, rz = r
    return 2.0 * atan2((rx.square() + ry.square()).sqrt(), (r0.square() + rz.square()).sqrt())
