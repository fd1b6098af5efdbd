"""Result types of the continuum reference: support reactions, elastica pieces and whole-wire shapes.

Units: mm, rad, N, N·mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]

__all__ = ["Array", "ContinuumReaction", "ContinuumShape", "ElasticaPiece"]


@dataclass(frozen=True, eq=False)
class ContinuumReaction:
    """Force and moment that a support (clamp, contact or wall) exerts on the wire.

    Attributes
    ----------
    s : float
        Arc length of the support point (mm).
    point : ndarray, shape (2,)
        Position of the support point (mm).
    force : ndarray, shape (2,)
        Force exerted on the wire (N).
    moment : float
        Moment exerted on the wire (N·mm, counter-clockwise positive).
    kind : str
        ``"clamp"`` for the base and fully clamped contacts, ``"wall"`` for a wall contact.
    """

    s: float
    point: Array
    force: Array
    moment: float
    kind: str


@dataclass(frozen=True, eq=False)
class ElasticaPiece:
    """One unloaded stretch of the wire: an elastica with constant internal force.

    The piece starts at arc length ``s0`` at ``point`` with angle ``theta0`` and curvature ``kappa0`` and
    carries the internal force ``force``.  Its shape is stored as the dense output of an initial-value
    integration in the non-dimensional arc length ``u = (s - s0) / length`` (``None`` for a straight piece
    without force, which is evaluated in closed form).

    Attributes
    ----------
    s0, length : float
        Start arc length and length (mm).
    point : ndarray, shape (2,)
        Start position (mm).
    theta0 : float
        Start tangent angle (rad, not wrapped).
    kappa0 : float
        Start curvature (1/mm).
    force : ndarray, shape (2,)
        Internal force (N): the force the distal part exerts on the proximal part.
    energy : float
        Bending energy of the piece (N·mm).
    dense : object or None
        Callable ``u -> (5, k)`` array (a ``scipy`` ``OdeSolution``, or several stitched together by multiple
        shooting) of the non-dimensional state ``(X, Y, theta, kappa_hat, E)`` with ``X = (x - x0) / length``,
        ``kappa_hat = kappa * length`` and ``E = ∫ kappa_hat² du``.
    EI : float or None
        The piece's own bending stiffness (N·mm²) on a wire with sections; None takes the shape's ``EI``.
    rest_curvature : float
        The piece's rest curvature ``κ₀`` (1/mm); its bending moment is ``EI (κ - κ₀)``.
    """

    s0: float
    length: float
    point: Array
    theta0: float
    kappa0: float
    force: Array
    energy: float
    dense: Any
    EI: float | None = None
    rest_curvature: float = 0.0

    @property
    def s1(self) -> float:
        """End arc length (mm)."""
        return self.s0 + self.length

    def state(self, s: Array) -> tuple[Array, Array, Array, Array]:
        """Return ``(x, y, theta, kappa)`` at arc lengths ``s`` (which must lie in the piece)."""
        ds = np.asarray(s, dtype=float) - self.s0
        if self.dense is None:
            c, si = math.cos(self.theta0), math.sin(self.theta0)
            theta = np.full(ds.shape, self.theta0)
            return self.point[0] + c * ds, self.point[1] + si * ds, theta, np.zeros(ds.shape)
        z = self.dense(ds / self.length)
        return (
            self.point[0] + self.length * z[0],
            self.point[1] + self.length * z[1],
            z[2],
            z[3] / self.length,
        )

    def end_state(self) -> tuple[Array, float, float]:
        """Return ``(point, theta, kappa)`` at the end of the piece."""
        x, y, th, k = self.state(np.array([self.s1]))
        return np.array([x[0], y[0]]), float(th[0]), float(k[0])

    def moment(self, kappa: Any, EI: float) -> Any:
        """Bending moment ``EI (κ - κ₀)`` (N·mm) at curvature ``kappa``; ``EI`` is used when the piece has none."""
        return (EI if self.EI is None else self.EI) * (kappa - self.rest_curvature)


@dataclass(frozen=True, eq=False)
class ContinuumShape:
    """Equilibrium shape of the continuum wire: a chain of :class:`ElasticaPiece`.

    Attributes
    ----------
    length : float
        Total arc length (mm).
    energy : float
        Bending energy ``EI/2 ∫ (κ - κ₀)² ds`` (N·mm).
    EI : float
        Bending stiffness (N·mm²); on a wire with sections the base's (each piece carries its own).
    pieces : tuple of ElasticaPiece
        Consecutive pieces covering ``[0, length]``.
    reactions : tuple of ContinuumReaction
        Forces and moments of the supports on the wire (they balance: the wire carries no other load).

    Notes
    -----
    At a piece boundary ``s`` belongs to the following piece (the curvature may jump at an interior clamp or a section
    boundary; position and angle are continuous, and so is the moment at a section boundary).
    """

    length: float
    energy: float
    EI: float
    pieces: tuple[ElasticaPiece, ...]
    reactions: tuple[ContinuumReaction, ...] = ()

    @property
    def breakpoints(self) -> Array:
        """Arc lengths where the pieces start, and the total length, shape ``(len(pieces) + 1,)``."""
        return np.array([p.s0 for p in self.pieces] + [self.length])

    def _evaluate(self, s: ArrayLike) -> tuple[Array, Array, Array, Array, Array, Array]:
        s = np.atleast_1d(np.asarray(s, dtype=float))
        if s.ndim != 1:
            raise ValueError(f"s must be a scalar or a 1-D array, got shape {s.shape}")
        if not np.all(np.isfinite(s)):
            raise ValueError("s must be finite")
        slack = 1e-9 * max(self.length, 1.0)
        if s.size and (s.min() < -slack or s.max() > self.length + slack):
            raise ValueError(
                f"s must lie in [0, {self.length:g}] mm, got values in [{s.min():g}, {s.max():g}]"
            )
        s = np.clip(s, 0.0, self.length)
        starts = np.array([p.s0 for p in self.pieces])
        which = np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(self.pieces) - 1)
        x, y, th, k, moment = (np.empty(s.shape) for _ in range(5))
        force = np.empty((s.size, 2))
        for j, piece in enumerate(self.pieces):
            mask = which == j
            if np.any(mask):
                x[mask], y[mask], th[mask], k[mask] = piece.state(s[mask])
                force[mask] = piece.force
                moment[mask] = piece.moment(k[mask], self.EI)
        return x, y, th, k, force, moment

    def position(self, s: ArrayLike) -> Array:
        """Positions (mm) at arc lengths ``s``, shape ``(k, 2)``."""
        x, y, *_ = self._evaluate(s)
        return np.column_stack([x, y])

    def tangent_angle(self, s: ArrayLike) -> Array:
        """Tangent angles (rad, continuous, not wrapped) at arc lengths ``s``, shape ``(k,)``."""
        return self._evaluate(s)[2]

    def curvature(self, s: ArrayLike) -> Array:
        """Curvatures ``dθ/ds`` (1/mm) at arc lengths ``s``, shape ``(k,)``."""
        return self._evaluate(s)[3]

    def bending_moment(self, s: ArrayLike) -> Array:
        """Bending moments ``EI (κ - κ₀)`` (N·mm) at arc lengths ``s``, shape ``(k,)``."""
        return self._evaluate(s)[5]

    def internal_force(self, s: ArrayLike) -> Array:
        """Internal forces (N) at arc lengths ``s``, shape ``(k, 2)``: distal part on proximal part."""
        return self._evaluate(s)[4]
