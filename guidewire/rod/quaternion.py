"""Unit quaternions for the bars' material frames, and the chart that makes them optimisation variables.

Convention: ``q = (w, x, y, z)`` (scalar first), Hamilton product, ``R(q) v = q ⊗ (0, v) ⊗ q̄``. Bar ``k``'s material
frame is ``(d1, d2, d3) = R(q_k) (e1, e2, e3)`` with ``d3 = t_k`` the bar's unit tangent. Frames given as the rows of
matrices ``F = [d1; d2; d3]`` (shape (..., 3, 3)) convert both ways.

The chart (Gibbs–Rodrigues parameters about a reference frame). Each bar carries a reference quaternion ``q⁰`` (the
frame at the start of a solve) and three variables ``ω``::

    q(ω) = q⁰ ⊗ (1, ω) = q⁰ + E ω,     E = [q⁰ ⊗ (0, e1), q⁰ ⊗ (0, e2), q⁰ ⊗ (0, e3)]     (4 × 3, orthonormal, ⊥ q⁰)

``(1, ω)`` is the rotation by ``2 atan|ω|`` about ``ω/|ω|`` in the bar's own (body) axes, so the chart covers every
frame except the half-turns from ``q⁰``, it is affine in ``ω`` (the strains' second derivatives come from the
formulas alone), and ``q(ω)`` is not normalised: every quantity built on it (:func:`tangent`,
:mod:`guidewire.rod.strain`) is homogeneous of degree 0 in each quaternion, so no unit-norm row is needed and no
gauge direction is left. A solve whose bars turn by more than a right angle is re-centred (``q⁰ ← q(ω)``) and
continued.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .jet import Jet

FloatArray = NDArray[np.float64]


def multiply(p: Any, q: Any) -> list[Any]:
    """Hamilton product ``p ⊗ q`` of quaternions given as four components each (arrays or jets)."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return [pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw]


def conjugate(q: Any) -> list[Any]:
    """``q̄ = (w, −x, −y, −z)`` of four components."""
    return [q[0], -q[1], -q[2], -q[3]]


def relative(qa: Any, qb: Any) -> list[Any]:
    """``r = q̄_a ⊗ q_b``: frame ``b`` seen from frame ``a`` (body axes of ``a``), four components."""
    return multiply(conjugate(qa), qb)


#: ``r = q̄_a ⊗ q_b`` as a bilinear form: ``r_i = Σ_jk RELATIVE[i, j, k] a_j b_k``.
RELATIVE = np.zeros((4, 4, 4))
for _i, _j, _k, _sign in ((0, 0, 0, 1), (0, 1, 1, 1), (0, 2, 2, 1), (0, 3, 3, 1),
                          (1, 0, 1, 1), (1, 1, 0, -1), (1, 2, 3, -1), (1, 3, 2, 1),
                          (2, 0, 2, 1), (2, 1, 3, 1), (2, 2, 0, -1), (2, 3, 1, -1),
                          (3, 0, 3, 1), (3, 1, 2, -1), (3, 2, 1, 1), (3, 3, 0, -1)):
    RELATIVE[_i, _j, _k] = _sign


def relative_affine(qa: list[Jet], qb: list[Jet]) -> list[Jet]:
    """:func:`relative` of jets that are affine in their variables (zero Hessians, as :meth:`Jet.affine` and
    :meth:`Jet.constant` make them; not checked), from the bilinear form :data:`RELATIVE` at once: the gradient
    ``Σ M (a' b + a b')`` and the Hessian ``Σ M (a' b'ᵀ + b' a'ᵀ)`` (the same numbers as :func:`relative` to
    rounding, without its 16 jet products)."""
    a = np.stack([j.value for j in qa], axis=1)
    b = np.stack([j.value for j in qb], axis=1)
    ga = np.stack([j.grad for j in qa], axis=1)
    gb = np.stack([j.grad for j in qb], axis=1)
    value = np.einsum("ijk,mj,mk->mi", RELATIVE, a, b)
    mb = np.einsum("ijk,mk->mij", RELATIVE, b)  # ∂r_i/∂a_j
    ma = np.einsum("ijk,mj->mik", RELATIVE, a)  # ∂r_i/∂b_k
    grad = np.einsum("mij,mja->mia", mb, ga) + np.einsum("mik,mka->mia", ma, gb)
    cross = np.einsum("ijk,mja,mkb->miab", RELATIVE, ga, gb, optimize=True)
    hess = cross + cross.transpose(0, 1, 3, 2)
    return [Jet(value[:, i], grad[:, i], hess[:, i]) for i in range(4)]


def relative_jacobians(a: FloatArray, slope_a: FloatArray, b: FloatArray,
                       slope_b: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``r = q̄_a ⊗ q_b`` (m, 4) of frames ``a``, ``b`` (m, 4) affine in their own variables with slopes ``slope_a``,
    ``slope_b`` (m, 4, k), and ``∂r/∂ω_a``, ``∂r/∂ω_b`` (m, 4, k each), from the bilinear form :data:`RELATIVE`;
    the mixed second derivative is ``Σ_jk RELATIVE_ijk slope_a,j ⊗ slope_b,k`` (the other two vanish)."""
    value = np.einsum("ijk,mj,mk->mi", RELATIVE, a, b)
    d_a = np.einsum("ijk,mk->mij", RELATIVE, b) @ slope_a  # ∂r_i/∂a_j · ∂a_j/∂ω_a
    d_b = np.einsum("ijk,mj->mik", RELATIVE, a) @ slope_b
    return value, d_a, d_b


def tangent_components(q: Any) -> tuple[Any, Any, Any]:
    """``R(q) e3 |q|²``: the third column of the rotation matrix times ``|q|²`` (quadratic in ``q``)."""
    w, x, y, z = q
    return 2.0 * (x * z + w * y), 2.0 * (y * z - w * x), w * w - x * x - y * y + z * z


def norm2(q: Any) -> Any:
    w, x, y, z = q
    return w * w + x * x + y * y + z * z


def as_array(q: FloatArray) -> FloatArray:
    """``q`` as an array of shape (m, 4)."""
    return np.atleast_2d(np.asarray(q, dtype=float))


def chart_basis(q0: FloatArray) -> FloatArray:
    """``E`` of the chart at each reference ``q0`` (shape (m, 4)): shape (m, 4, 3), ``q(ω) = q0 + E ω``."""
    q0 = as_array(q0)
    m = q0.shape[0]
    eye = np.zeros((3, m, 4))
    eye[0, :, 1] = eye[1, :, 2] = eye[2, :, 3] = 1.0
    cols = [np.stack(multiply(q0.T, e.T), axis=1) for e in eye]
    return np.stack(cols, axis=2)


def normalised(q: FloatArray) -> FloatArray:
    q = as_array(q)
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def to_frames(q: FloatArray) -> FloatArray:
    """Material frames ``[d1; d2; d3]`` as rows, shape (m, 3, 3), of quaternions (m, 4) (normalised first)."""
    w, x, y, z = normalised(q).T
    rot = np.empty((w.size, 3, 3))  # R(q) with columns d1, d2, d3
    rot[:, 0, 0] = 1 - 2 * (y * y + z * z)
    rot[:, 0, 1] = 2 * (x * y - w * z)
    rot[:, 0, 2] = 2 * (x * z + w * y)
    rot[:, 1, 0] = 2 * (x * y + w * z)
    rot[:, 1, 1] = 1 - 2 * (x * x + z * z)
    rot[:, 1, 2] = 2 * (y * z - w * x)
    rot[:, 2, 0] = 2 * (x * z - w * y)
    rot[:, 2, 1] = 2 * (y * z + w * x)
    rot[:, 2, 2] = 1 - 2 * (x * x + y * y)
    return rot.transpose(0, 2, 1)


def from_frames(frames: FloatArray) -> FloatArray:
    """Quaternions (m, 4) of frames given as rows ``[d1; d2; d3]`` (m, 3, 3), orthonormal and right-handed.

    Shepperd's method (the largest of the four squared components chosen per frame, so no division by a small
    number); each quaternion is returned with ``w ≥ 0``.
    """
    rot = np.asarray(frames, dtype=float).reshape(-1, 3, 3).transpose(0, 2, 1)  # columns d1, d2, d3
    m = rot.shape[0]
    tr = np.trace(rot, axis1=1, axis2=2)
    diag = np.stack((tr, rot[:, 0, 0], rot[:, 1, 1], rot[:, 2, 2]), axis=1)
    pick = np.argmax(diag, axis=1)
    q = np.empty((m, 4))
    r = rot
    for case in range(4):
        sel = pick == case
        if not np.any(sel):
            continue
        R = r[sel]
        if case == 0:
            s = 2.0 * np.sqrt(1.0 + tr[sel])
            q[sel] = np.column_stack((0.25 * s, (R[:, 2, 1] - R[:, 1, 2]) / s, (R[:, 0, 2] - R[:, 2, 0]) / s,
                                      (R[:, 1, 0] - R[:, 0, 1]) / s))
        elif case == 1:
            s = 2.0 * np.sqrt(1.0 + R[:, 0, 0] - R[:, 1, 1] - R[:, 2, 2])
            q[sel] = np.column_stack(((R[:, 2, 1] - R[:, 1, 2]) / s, 0.25 * s, (R[:, 0, 1] + R[:, 1, 0]) / s,
                                      (R[:, 0, 2] + R[:, 2, 0]) / s))
        elif case == 2:
            s = 2.0 * np.sqrt(1.0 - R[:, 0, 0] + R[:, 1, 1] - R[:, 2, 2])
            q[sel] = np.column_stack(((R[:, 0, 2] - R[:, 2, 0]) / s, (R[:, 0, 1] + R[:, 1, 0]) / s, 0.25 * s,
                                      (R[:, 1, 2] + R[:, 2, 1]) / s))
        else:
            s = 2.0 * np.sqrt(1.0 - R[:, 0, 0] - R[:, 1, 1] + R[:, 2, 2])
            q[sel] = np.column_stack(((R[:, 1, 0] - R[:, 0, 1]) / s, (R[:, 0, 2] + R[:, 2, 0]) / s,
                                      (R[:, 1, 2] + R[:, 2, 1]) / s, 0.25 * s))
    return q * np.where(q[:, :1] < 0.0, -1.0, 1.0)


def continuous(q: FloatArray, previous: FloatArray | None = None) -> FloatArray:
    """Signs flipped so that consecutive quaternions (and the first one with ``previous``) have a positive dot
    product: ``q`` and ``−q`` are one frame, and the strains need neighbours within a half-turn of each other."""
    q = as_array(q).copy()
    ref = np.vstack((as_array(previous) if previous is not None else q[:1], q[:-1]))
    # the sign chain: each flip relative to its predecessor, accumulated
    flip = np.einsum("ij,ij->i", q, ref) < 0.0
    if previous is None:
        flip[0] = False
    sign = np.where(np.cumsum(flip) % 2 == 1, -1.0, 1.0)
    return q * sign[:, None]


def rotation_about(axis: FloatArray, angle: FloatArray) -> FloatArray:
    """Quaternions (m, 4) of rotations by ``angle`` (m,) about unit ``axis`` (m, 3) (world axes)."""
    axis = np.atleast_2d(np.asarray(axis, dtype=float))
    half = 0.5 * np.asarray(angle, dtype=float)
    return np.column_stack((np.cos(half), np.sin(half)[..., None] * axis))


def frame_from_tangent(tangent: FloatArray, normal_hint: FloatArray | None = None) -> FloatArray:
    """A frame ``[d1; d2; d3]`` (3, 3) with ``d3`` along ``tangent``: ``d1`` the part of ``normal_hint`` across the
    tangent (default: the world axis least aligned with it), ``d2 = d3 × d1``."""
    t = np.asarray(tangent, dtype=float)
    t = t / np.linalg.norm(t)
    if normal_hint is None:
        normal_hint = np.eye(3)[int(np.argmin(np.abs(t)))]
    h = np.asarray(normal_hint, dtype=float)
    d1 = h - (h @ t) * t
    norm = np.linalg.norm(d1)
    if norm < 1e-9:
        raise ValueError(f"the normal hint {h.tolist()} is parallel to the tangent {t.tolist()}; give a direction "
                         "across it.")
    d1 /= norm
    return np.vstack((d1, np.cross(t, d1), t))


def swing(a: FloatArray, b: FloatArray) -> FloatArray:
    """Quaternions (m, 4) of the least rotations taking unit vectors ``a`` onto ``b`` (m, 3 each; not antiparallel):
    ``(1 + a·b, a × b)`` normalised."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    q = np.column_stack((1.0 + np.einsum("ij,ij->i", a, b), np.cross(a, b)))
    if np.any(q[:, 0] <= 1e-12):
        raise ValueError("two consecutive directions are antiparallel; a frame cannot be carried across a half-turn.")
    return normalised(q)


def cumulative_product(q: FloatArray) -> FloatArray:
    """``P_k = q_k ⊗ q_{k−1} ⊗ … ⊗ q_0`` for quaternions (m, 4), by prefix doubling: ⌈log₂ m⌉ vectorised rounds."""
    out = as_array(q).copy()
    step = 1
    while step < out.shape[0]:
        later = np.stack(multiply(out[step:].T, out[:-step].T), axis=1)
        out[step:] = later
        step *= 2
    return out


def transported_frames(base: FloatArray, tangents: FloatArray) -> FloatArray:
    """Quaternions (m, 4) of the frames parallel-transported from the clamp frame ``base`` (a quaternion) along unit
    ``tangents`` (m, 3): frame ``k`` is ``swing(t_{k−1} → t_k) ⊗ frame_{k−1}``, frame ``−1`` the clamp (no twist)."""
    t = np.asarray(tangents, dtype=float)
    t = t / np.linalg.norm(t, axis=1, keepdims=True)
    t_base = np.stack(tangent_components(normalised(base)[0]))
    previous = np.vstack((t_base, t[:-1]))
    total = cumulative_product(swing(previous, t))
    return continuous(np.stack(multiply(total.T, normalised(base)[0]), axis=1), normalised(base)[0])
