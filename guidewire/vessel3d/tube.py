"""One 3-D tube: a C² centreline spline with a radius, the closest-ball search, and the lumen row's derivatives.

The centreline ``c(u)`` is the cubic spline (not-a-knot, as the planar :mod:`guidewire.vessel_curves`) through the
points in chord length ``u`` (≈ arc length); the radius ``R(u)`` is monotone cubic (PCHIP, no overshoot) in the same
``u``. Past the last point an outlet continues straight along its last tangent with its last radius for
:data:`TAIL_REACH` mm (or :data:`TAIL_REACH_RADII` radii), so a tip pushed past the end is not stopped; a tube built
with ``tail=False`` (a trunk whose end is a bifurcation: the lumen goes on in its branches, not straight on) ends in
its last ball, as it begins in its first.

The lumen is the union of the balls ``|p − c(u)| ≤ R(u)``; a wire node of radius ``r`` must lie in the union of the
shrunk balls, ``g(p) = max_u h(p, u) ≥ 0`` with (mm)::

    h(p, u) = (a² − |v|²) / (2a),     a = R(u) − r,   v = p − c(u)

Its zero set is the shrunk ball's surface, where ``|∇_p h| = |v| / a = 1``: at the wall ``h`` is the clearance to first
order and its multiplier is the wall's force in N. Unlike the clearance ``a − |v|`` it is smooth on the centreline and
its curvature is bounded by ``1/a`` everywhere (the clearance's is ``1/|v|``, which made a node near the axis with a
small multiplier estimate dominate the Lagrangian Hessian). Across the wall's tangent plane — the directions a
touching node may still move in — it curves like the true distance. At the maximiser ``u*`` (``h_u = 0``, Newton's
method from the nearest sample of a k-d tree, vectorised over points) the envelope theorem gives the exact
derivatives::

    ∇g = −v / a,        ∇²g = h_pp − h_pu h_puᵀ / h_uu,        h_pp = −I / a,      h_pu = c' / a + v a' / a²,
    h_u  = a'/2 + v·c' / a + |v|² a' / (2a²),
    h_uu = a''/2 + (v·c'' − |c'|²) / a − 2 (v·c') a' / a² + |v|² a'' / (2a²) − |v|² a'² / a³     (< 0 at a maximum)

(a ball's ``h_pp`` where ``u*`` sits at either cap: the entrance ``u = 0`` or the end of the search range).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline, PchipInterpolator
from scipy.spatial import cKDTree

FloatArray = NDArray[np.float64]

TAIL_REACH = 50.0
"""Straight continuation past the far end (mm), or :data:`TAIL_REACH_RADII` end radii if longer."""

TAIL_REACH_RADII = 4.0

SAMPLE_SPACING = 0.5
"""Largest spacing (mm) of the samples that start the closest-ball search (smaller in narrow or tight tubes)."""

NEWTON_STEPS = 5
"""Newton steps on ``u`` from the nearest sample (quadratic convergence from within a spacing)."""

NEWTON_TOL = 1e-7
"""A point's search stops after a Newton step no larger than this many sample spacings: the error it leaves is of
the order of its square over the curve's scale (~1e-15 mm), where further steps only move ``u`` by rounding (on the
arch at 356 nodes the largest steps were 0.46, 8e-4, 7e-9, then 5e-14 mm)."""

MIN_GAP = 1e-3
"""Floor of ``a = R − r`` (mm): a lumen narrower than the wire has no room, and its row stays finite."""


@dataclass(frozen=True)
class Closest:
    """Per point: ``u*``, the centre ``c``, ``c'``, ``c''`` (3 each), ``R, R', R''`` and whether ``u*`` is at a
    cap, the entrance or the end of the search range (a ball there, not the tube's side)."""

    u: FloatArray
    centre: FloatArray
    d1: FloatArray
    d2: FloatArray
    radius: FloatArray
    radius_d1: FloatArray
    radius_d2: FloatArray
    at_cap: NDArray[np.bool_]


class Tube:
    """A tube around ``points`` (m, 3) with ``radius`` (one value or one per point), continued straight past its
    end if ``tail`` (an outlet) or closed by its last ball (a bifurcation); see the module docstring."""

    def __init__(self, points: FloatArray, radius: FloatArray, tail: bool = True) -> None:
        points = np.asarray(points, dtype=float)
        radius = np.broadcast_to(np.asarray(radius, dtype=float), (len(points),)).copy()
        chord = np.linalg.norm(np.diff(points, axis=0), axis=1)
        self.points = points
        self.breaks = np.concatenate(([0.0], np.cumsum(chord)))
        self.end = float(self.breaks[-1])
        if len(points) == 2:
            self.spline = CubicSpline(self.breaks, points, bc_type="natural")
        else:
            self.spline = CubicSpline(self.breaks, points, bc_type="not-a-knot")
        self.constant_radius = bool(np.all(radius == radius[0]))
        self.radius_curve = None if self.constant_radius else PchipInterpolator(self.breaks, radius)
        self.radius0 = float(radius[0])
        self.max_radius = float(radius.max())  # (PCHIP does not overshoot: the largest radius anywhere)
        # the pieces' coefficients side by side, (pieces, 4, 3 + 1): the centre's and the radius's (zero when
        # constant), highest power first, as scipy's PPoly stores them
        coef = np.zeros((len(points) - 1, 4, 4))
        coef[:, :, :3] = np.moveaxis(self.spline.c, 0, 1)
        if self.radius_curve is not None:
            coef[:, :, 3] = self.radius_curve.c.T
        self._coef = coef
        tail_point, tail_d1, _ = self._spline(np.array([self.end]))
        self.tail_point = tail_point[0]
        self.tail_tangent = tail_d1[0] / np.linalg.norm(tail_d1[0])
        self.tail_radius = float(radius[-1])
        self.reach = max(TAIL_REACH, TAIL_REACH_RADII * self.tail_radius) if tail else 0.0
        self.top = self.end + self.reach
        spacing = min(SAMPLE_SPACING, 0.25 * float(radius.min()))
        self.u = np.linspace(0.0, self.top, max(2, int(np.ceil(self.top / spacing)) + 1))
        self.spacing = float(self.u[1] - self.u[0])
        value = self.evaluate(self.u)
        self.samples = value.centre
        self.sample_radius = value.radius
        self.tree = cKDTree(self.samples)
        # no point of the centreline is farther than this from its nearest sample (half a spacing at the largest
        # speed |c'| seen at the samples, doubled for the speed between them)
        self.sample_reach = self.spacing * float(np.max(np.linalg.norm(value.d1, axis=1)))
        self.box = np.stack((self.samples.min(axis=0), self.samples.max(axis=0)))

    # -- evaluation ----------------------------------------------------------------------------------------------
    def _spline(self, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        return self.spline(u), self.spline(u, 1), self.spline(u, 2)

    def _pieces(self, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Centre and radius (m, 4) with their first and second derivatives at ``u`` in ``[0, end]``: scipy's
        ``PPoly`` evaluation (the piece ``breaks[i] <= u < breaks[i + 1]``, the last one closed; the terms summed
        in its order, ``c_j s^p`` times the derivative's factor) for all four curves at once, the same numbers as
        calling the spline and the PCHIP curve three times each."""
        i = np.clip(np.searchsorted(self.breaks, u, side="right") - 1, 0, self.breaks.size - 2)
        s = (u - self.breaks[i])[:, None]
        c = self._coef[i]
        c0, c1, c2, c3 = c[:, 0], c[:, 1], c[:, 2], c[:, 3]
        s2 = s * s
        value = c3 + c2 * s + c1 * s2 + c0 * (s2 * s)
        d1 = c2 + (c1 * s) * 2.0 + (c0 * s2) * 3.0
        d2 = c1 * 2.0 + (c0 * s) * 6.0
        return value, d1, d2

    def evaluate(self, u: FloatArray) -> Closest:
        """Centre, derivatives and radius at ``u`` (clipped to ``[0, end + reach]``; straight past ``end``)."""
        u = np.clip(np.asarray(u, dtype=float), 0.0, self.top)
        inside = u <= self.end
        if inside.all():  # (the usual case, a wire in the tube: no tail to splice in)
            value, first, second = self._pieces(u)
            if self.constant_radius:
                r, r1, r2 = np.full(u.size, self.radius0), np.zeros(u.size), np.zeros(u.size)
            else:
                r, r1, r2 = value[:, 3], first[:, 3], second[:, 3]
            return Closest(u, value[:, :3], first[:, :3], second[:, :3], r, r1, r2, (u <= 0.0) | (u >= self.top))
        ui = np.where(inside, u, self.end)
        value, first, second = self._pieces(ui)
        past = (u - self.end)[:, None]
        c = np.where(inside[:, None], value[:, :3], self.tail_point + past * self.tail_tangent)
        d1 = np.where(inside[:, None], first[:, :3], self.tail_tangent)
        d2 = np.where(inside[:, None], second[:, :3], 0.0)
        if self.constant_radius:
            r, r1, r2 = np.full(u.size, self.radius0), np.zeros(u.size), np.zeros(u.size)
        else:
            r = np.where(inside, value[:, 3], self.tail_radius)
            r1 = np.where(inside, first[:, 3], 0.0)
            r2 = np.where(inside, second[:, 3], 0.0)
        return Closest(u, c, d1, d2, r, r1, r2, (u <= 0.0) | (u >= self.top))

    # -- the lumen row -------------------------------------------------------------------------------------------
    def closest(self, p: FloatArray, r: FloatArray) -> Closest:
        """``u* = argmax_u h(p, u)`` for points ``p`` (m, 3) of wire radii ``r`` (m,)."""
        _, index = self.tree.query(p)
        u = self.u[index]
        h = self.spacing
        live = np.arange(len(p))  # (points still searching: each point's steps depend on its own point alone)
        for _ in range(NEWTON_STEPS):
            if not live.size:
                break
            # Newton on G = a h_u (nearly linear in u), whose slope at the root is a h_uu < 0
            parts = _Parts(self.evaluate(u[live]), p[live], r[live])
            G = parts.a * parts.hu
            slope = parts.a1 * parts.hu + parts.a * parts.huu
            step = np.where(slope < 0.0, -G / np.where(slope < 0.0, slope, -1.0), np.sign(G) * h)
            u[live] = np.clip(u[live] + np.clip(step, -h, h), 0.0, self.top)
            # (a step this small leaves an error of the order of its square: rounding)
            live = live[np.abs(step) > NEWTON_TOL * h]
        return self.evaluate(u)

    def rows(self, p: FloatArray, r: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, Closest]:
        """``g`` (m,), ``∇g`` (m, 3), ``∇²g`` (m, 3, 3) and the closest-ball data (see the module docstring)."""
        e = self.closest(p, r)
        parts = _Parts(e, p, r)
        a, v = parts.a, parts.v
        g = 0.5 * (a - parts.vv / a)
        grad = -v / a[:, None]
        hpp = -np.broadcast_to(np.eye(3), (len(a), 3, 3)) / a[:, None, None]
        hpu = e.d1 / a[:, None] + v * (parts.a1 / a**2)[:, None]
        huu = np.minimum(parts.huu, -1e-12)
        hess = hpp - hpu[:, :, None] * hpu[:, None, :] / huu[:, None, None]
        hess = np.where(e.at_cap[:, None, None], hpp, hess)
        return g, grad, hess, e

    def row_bound(self, p: FloatArray, r: FloatArray, floor: FloatArray | None = None) -> FloatArray:
        """An upper bound (m,) of the lumen row ``g(p) = max_u h(p, u)`` of points ``p`` (m, 3), wire radii ``r``
        (m,), from the nearest sample alone: ``h = a/2 − |v|²/(2a)`` grows with ``a``, so ``h ≤ (A² − D²)/(2A)``
        with ``A`` the largest ``a`` anywhere and ``D ≤ |v|`` the sample's distance less :attr:`sample_reach`.
        The samples' bounding box gives a first, weaker ``D`` at no search: points whose bound from it is already
        below ``floor`` (m,) keep that bound, and the nearest sample is searched for the others only."""
        big_a = np.maximum(self.max_radius - r, MIN_GAP)
        outside = np.maximum(np.maximum(self.box[0] - p, p - self.box[1]), 0.0)
        bound = _ball_bound(np.sqrt(np.einsum("ij,ij->i", outside, outside)) - self.sample_reach, big_a)
        near = np.arange(len(p)) if floor is None else np.flatnonzero(bound >= floor)
        if near.size:
            distance, _ = self.tree.query(p[near])
            bound[near] = _ball_bound(distance - self.sample_reach, big_a[near])
        return bound

    def path(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Points and unit tangents at chord parameters ``s`` (≈ arc length from the entrance; straight past the
        end without limit, whether the lumen goes on there or not, and before the entrance along the first tangent):
        a guide for a wire's start, not the lumen."""
        s = np.asarray(s, dtype=float)
        e = self.evaluate(np.clip(s, 0.0, self.end))
        t = e.d1 / np.linalg.norm(e.d1, axis=1, keepdims=True)
        offset = np.where(s < 0.0, s, np.maximum(s - self.end, 0.0))
        return e.centre + offset[:, None] * t, t


def _ball_bound(low: FloatArray, big_a: FloatArray) -> FloatArray:
    """``(A² − D²)/(2A)`` with ``D = max(low, 0)``: the largest ``h`` at a distance of at least ``low``."""
    low = np.maximum(low, 0.0)
    return 0.5 * (big_a - low * low / big_a)


class _Parts:
    """``a = R − r`` (floored at :data:`MIN_GAP`), its ``u``-derivatives, ``v = p − c`` and ``h_u``, ``h_uu`` of
    ``h = (a² − |v|²) / (2a)`` at a :class:`Closest` (see the module docstring)."""

    def __init__(self, e: Closest, p: FloatArray, r: FloatArray) -> None:
        self.a = np.maximum(e.radius - r, MIN_GAP)
        self.a1, a2 = e.radius_d1, e.radius_d2
        self.v = v = p - e.centre
        self.vv = np.einsum("ij,ij->i", v, v)
        a, a1, vv = self.a, self.a1, self.vv
        vc = np.einsum("ij,ij->i", v, e.d1)
        cc = np.einsum("ij,ij->i", e.d1, e.d1)
        vc2 = np.einsum("ij,ij->i", v, e.d2)
        self.hu = 0.5 * a1 + vc / a + vv * a1 / (2.0 * a**2)
        self.huu = (0.5 * a2 + (vc2 - cc) / a - 2.0 * vc * a1 / a**2 + vv * a2 / (2.0 * a**2)
                    - vv * a1**2 / a**3)
