"""A clamped wire with a free end pushed against one straight frictionless wall: :func:`clamp_wall_free_end`.

Closed form in incomplete elliptic integrals (pendulum substitution): tangential contact with a straight tail
along the wall or, for a shallow wall, the free end resting on it; verified by integrating the elastica.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import brentq
from scipy.special import ellipeinc, ellipkinc

from .. import fields
from .ode import integrate
from .pieces import assemble, curved_piece, lowest_first, straight_piece, straight_shape
from .shapes import Array, ContinuumShape

__all__ = ["clamp_wall_free_end", "max_wall_violation", "unit_wall", "wall_shapes"]


def _pendulum_integrals(phi0: float, sigma: float, amplitude: Array) -> tuple[Array, Array, Array, Array]:
    """Oriented elliptic integrals of the path ``φ0 → σA`` of ``φ'' = -(f/EI) sin φ`` ending at rest.

    With ``sin(φ/2) = k sin ψ``, ``k = sin(A/2)``, ``m = k²`` the path runs over ``ψ ∈ [ψ0, σπ/2]`` and
    ``ds = λ dψ / sqrt(1 - m sin²ψ)`` with ``λ = sqrt(EI/f)``.  Returns ``(ψ0, m, I_F, I_E)`` where
    ``I_F = σ (F(σπ/2|m) - F(ψ0|m))`` and ``I_E`` likewise with ``E``; then the length is ``λ I_F``, the
    displacement along the wall normal ``λ (2 I_E - I_F)``, and the energy ``2 EI/λ (I_E - (1 - m) I_F)``.
    """
    k = np.sin(0.5 * amplitude)
    m = k * k
    psi0 = np.arcsin(np.clip(math.sin(0.5 * phi0) / k, -1.0, 1.0))
    end = sigma * 0.5 * np.pi
    i_f = sigma * (ellipkinc(end, m) - ellipkinc(psi0, m))
    i_e = sigma * (ellipeinc(end, m) - ellipeinc(psi0, m))
    return psi0, m, i_f, i_e


def _wall_parameters(
    phi0: float, sigma: float, depth: float, length: float
) -> list[tuple[float, float, float]]:
    """Candidate contact solutions ``(A, λ, ℓ)`` for one turning sense (``A = π/2``: tangential contact)."""
    out = []
    _, _, i_f, i_e = _pendulum_integrals(phi0, sigma, np.array([0.5 * np.pi]))
    reach = float(2.0 * i_e[0] - i_f[0])
    if reach > 0.0:
        lam = depth / reach
        if lam * float(i_f[0]) <= length * (1.0 + 1e-12):
            out.append((0.5 * np.pi, lam, lam * float(i_f[0])))
            return out
    # tip contact: the whole wire is bent, its free end rests on the wall at an angle
    lo = abs(phi0)
    amps = lo + (0.5 * np.pi - lo) * np.concatenate([[1e-7], np.linspace(0.0, 1.0, 65)[1:]])

    def ratio(a: Array) -> Array:
        _, _, f_, e_ = _pendulum_integrals(phi0, sigma, a)
        with np.errstate(divide="ignore", invalid="ignore"):
            return (2.0 * e_ - f_) / f_ - depth / length

    h = ratio(amps)
    for j in np.nonzero(np.isfinite(h[:-1]) & np.isfinite(h[1:]) & (np.sign(h[:-1]) != np.sign(h[1:])))[0]:
        a = brentq(lambda x: float(ratio(np.array([x]))[0]), amps[j], amps[j + 1], xtol=1e-15, rtol=1e-15)
        if a >= 0.5 * np.pi * (1.0 - 1e-12):
            continue
        _, _, i_f, _ = _pendulum_integrals(phi0, sigma, np.array([a]))
        out.append((a, length / float(i_f[0]), length))
    return out


def unit_wall(normal: ArrayLike, offset: Any, name: str = "wall") -> tuple[Array, float]:
    """The wall ``normal · p ≤ offset`` as ``(unit normal, offset / |normal|)``; ``name`` labels messages."""
    n = np.asarray(fields.point(normal, f"{name} normal"))
    norm = float(np.linalg.norm(n))
    if norm == 0.0:
        raise ValueError(f"{name} normal must be non-zero")
    return n / norm, fields.real(offset, f"{name} offset") / norm


def max_wall_violation(shape: ContinuumShape, n: Array, c: float, samples: int = 4001) -> float:
    """Largest ``n · p - c`` (mm) over ``samples`` evenly spaced points and the piece boundaries."""
    s = np.unique(np.concatenate([np.linspace(0.0, shape.length, samples), shape.breakpoints]))
    return float(np.max(shape.position(s) @ n - c))


def clamp_wall_free_end(
    p0: ArrayLike, theta0: float, length: float, wall_normal: ArrayLike, wall_offset: float, EI: float
) -> ContinuumShape:
    """Clamped wire with a free end, bent by one straight frictionless wall ``{p : normal·p ≤ offset}``.

    Parameters
    ----------
    p0 : array_like, shape (2,)
        Clamp point (mm); must lie strictly inside the allowed half-plane.
    theta0 : float
        Clamp angle (rad).
    length : float
        Wire length (mm).
    wall_normal : array_like, shape (2,)
        Outward normal of the wall (any non-zero length; normalised internally).
    wall_offset : float
        Offset in the units of ``wall_normal``: the allowed side is ``wall_normal · p ≤ wall_offset``.
    EI : float
        Bending stiffness (N·mm²).

    Returns
    -------
    ContinuumShape
        The straight wire when it does not cross the wall.  Otherwise an elastica with constant internal
        force ``F = -f n`` (the wall reaction, ``f > 0``) from the clamp to the contact point ``s_c``, where
        the moment vanishes; for ``s_c < length`` the contact is tangential and a straight tail lies on the
        wall, otherwise (small penetration) the free end rests on the wall at an angle.  Reactions: base
        clamp and wall (kind ``"wall"``, at ``s_c``).

    Raises
    ------
    TypeError
        A value of the wrong type (a string or a bool for a number, a non-sequence for a point), as
        :mod:`guidewire.fields` reports it.
    ValueError
        For malformed input, or when ``p0`` is not strictly inside the allowed half-plane while the wire is
        pushed against the wall.
    RuntimeError
        When no candidate passes the verification (should not happen).

    Notes
    -----
    With ``φ = θ - α`` (``α`` the direction of the normal) the elastica is a pendulum,
    ``EI φ'' = -f sin φ``, with first integral ``EI κ²/2 - f cos φ = const``.  The clamp-to-contact stretch
    is a monotone swing of amplitude ``A`` ending at rest (``κ = 0``) on the wall; the substitution
    ``sin(φ/2) = sin(A/2) sin ψ`` turns length, penetration depth and energy into incomplete elliptic
    integrals (see :func:`_pendulum_integrals`).  Tangential contact is ``A = π/2``, which fixes the force
    from the clamp-to-wall distance ``d``; for ``φ0 = 0`` the energy is ``EI J² / (2 d)`` with
    ``J = ∫_0^{π/2} sqrt(cos φ) dφ = sqrt(2) (2 E(1/2) - K(1/2))``, i.e. 1.0312 N·mm for Fig. 6b
    (``d = 45``, ``EI = 64.65``), and the contact is at ``s_c = d K(1/2) / (2 E(1/2) - K(1/2)) = 98.48``
    mm.  Both turning senses are solved; the lower-energy one is kept (the counter-clockwise one on a
    tie).  The result is re-integrated as an initial-value problem and verified: it ends on the wall with
    zero curvature and never crosses it.
    """
    p0 = np.asarray(fields.point(p0, "p0"))
    theta0 = fields.real(theta0, "theta0")
    length = fields.real(length, "length", positive=True)
    EI = fields.real(EI, "EI", positive=True)
    n, c = unit_wall(wall_normal, wall_offset)
    return wall_shapes(p0, theta0, length, n, c, EI)[0]


def wall_shapes(
    p0: Array, theta0: float, length: float, n: Array, c: float, EI: float
) -> list[ContinuumShape]:
    """Every verified clamp-wall shape (validated input, unit normal), lowest energy first."""
    depth = c - float(n @ p0)
    alpha = math.atan2(n[1], n[0])
    phi0 = math.remainder(theta0 - alpha, 2.0 * math.pi)
    if depth < 0.0:
        raise ValueError(f"p0 = {fields.fmt_point(p0)} lies {-depth:.6g} mm beyond the wall")
    if length * math.cos(phi0) <= depth:
        return [straight_shape(p0, theta0, length, EI)]
    if depth == 0.0:
        raise ValueError(f"p0 = {fields.fmt_point(p0)} lies on the wall and the wire points into it")
    shapes: list[ContinuumShape] = []
    for sigma in (1.0, -1.0):
        for amp, lam, ell in _wall_parameters(phi0, sigma, depth, length):
            psi0, m, i_f, i_e = _pendulum_integrals(phi0, sigma, np.array([amp]))
            kappa0 = sigma * 2.0 * math.sin(0.5 * amp) * math.cos(float(psi0[0])) / lam
            g = -((ell / lam) ** 2) * n
            sol = integrate(theta0, kappa0 * ell, g)
            if sol.status != 0:
                continue
            piece = curved_piece(0.0, ell, p0, theta0, kappa0 * ell, g, EI, sol.sol, sol.y[4, -1])
            pieces = [piece]
            end, theta_end, kappa_end = piece.end_state()
            theta_exact = theta0 + sigma * amp - phi0
            scale = max(1.0, length)
            if (
                abs(theta_end - theta_exact) > 1e-8
                or abs(kappa_end) * scale > 1e-8
                or abs(float(n @ end) - c) > 1e-8 * scale
            ):
                continue
            if length - ell > 1e-12 * length:
                pieces.append(straight_piece(ell, length - ell, end, theta_exact))
            shape = assemble(pieces, length, EI, p0, [(ell, "wall")])
            expected = 2.0 * EI / lam * float(i_e[0] - (1.0 - m[0]) * i_f[0])
            if abs(shape.energy - expected) > 1e-8 * max(expected, 1e-12):
                continue
            if max_wall_violation(shape, n, c) > 1e-9 * scale:
                continue
            shapes.append(shape)
    if not shapes:
        raise RuntimeError("no verified wall-contact shape found")
    return lowest_first(shapes)
