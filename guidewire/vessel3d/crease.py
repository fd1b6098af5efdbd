"""The creases of a 3-D lumen: the curves where a branch's wall meets the wall of the lumen it leaves.

A tree's lumen is the union of its tubes, so its boundary is not smooth where two walls meet: around every branch's
opening runs a crease, an edge of the boundary that points into the lumen (as a 2-D corner does). A wire node of
radius ``r`` fits where its ball lies in the union — which is more than lying in one tube's shrunk lumen: beside a
crease the ball may stand over the opening, in neither tube alone. Per tube the row ``max_i g_i`` (the best tube's,
:mod:`guidewire.vessel3d.tube`) keeps such a node at the wall of one tube, whose part there lies inside the other
tube, and that wall's force meets the wire at an angle: it holds the wire lengthwise where a frictionless wire would
slide over the crease (stEVE's J wire steered into the type I arch's left subclavian artery: 0.79 N of 1.19 N).

Geometry. Seen from a point ``p`` whose nearest point on a crease is ``X``, with ``w = p − X``, the two walls leave
``X`` in the plane normal to the crease along ``e_j`` (tube ``j``'s wall, away from tube ``o``: ``e_j · n_o < 0``
with ``n_o`` tube ``o``'s inward normal at ``X``) and ``e_o``. Where ``w · e_j ≤ 0`` and ``w · e_o ≤ 0`` — the
*cone* of the crease, inside the lumen — the nearest point of the lumen's boundary is ``X`` itself, so the clearance
is ``|w|`` and the node's row is::

    g_K(p) = |p − X(p)| − r,     ∇g_K = ŵ,     ∇²g_K = (I − ŵŵᵀ)/|w| − K' K'ᵀ / (|w| (|K'|² − w·K''))

(the distance to a curve ``K(σ)`` at its closest point, the envelope theorem over ``σ``). On the cone's sides it
meets the tubes' rows with the same value and gradient to first order in the clearance (the tube row ``d − d²/(2a)``
against ``d``; at a touching node, ``d = 0``, the same), so the row of a node is the largest of the tubes' rows and
the creases': exact at contact, and a node touching a crease is pushed straight away from it.

Construction. Around each branch ``j`` (its wall at angle ``φ`` about its axis, the envelope of its balls), the first
``u`` at which the wall leaves the other tubes (``max_{i≠j} g_i = 0`` with ``r = 0``) is bracketed on a grid and
found by a bracketed root search, for :data:`ANGLES` angles; the crease is the periodic cubic spline through these
points in ``φ`` (on both walls to ≤ 6e-7 mm on the shipped arches). A branch that leaves the side wall of one tube
has one such closed curve. At a bifurcation where a trunk ends in two branches (stEVE's brachiocephalic trunk in the
right subclavian and common carotid arteries; the trunk ends in its last ball, :mod:`guidewire.vessel3d.tube`) each
branch's crease meets two walls, the trunk's and its sibling's, in two arcs that meet at corners where the three
walls meet: each corner is found by Newton's method on the branch wall's ``(u, φ)`` (on all three walls to 1e-14
mm), each arc is a not-a-knot cubic spline through its knots and its two corners, the crease their piecewise cubic.
A crease whose spline strays more than :data:`WALL_TOL` from its walls between the knots is found again with twice
the angles (type I: the right common carotid's, 512 angles, 1e-5 mm). The tube's own closest-ball search can stop at
a local maximum where a tube bends almost as tightly as its radius (stEVE's common-origin trunk, arch types IV and
VI, bent to 0.95 of its radius: up to 6e-3 mm short of the global one, a conservative row): the creases of those
trunks are as far from their walls. The carina — the arc along both siblings' walls — appears in both
siblings' creases; the later sibling's holds it, the other's arc has no rows. A point whose nearest crease point
is a corner (three walls near) keeps the tubes' rows.

A wire's rows (:meth:`Crease.minima`). A crease holds a wire where it comes nearest it: inside a bar — the nearest
pair of the segment ``P(τ) = (1 − τ) a + τ b`` and the crease, ``g = |P − X| − r`` with gradient ``(1 − τ) ŵ``,
``τ ŵ`` over the bar's two nodes and the Hessian of the envelope theorem over ``(τ, φ)``::

    ∇²g = B (I − ŵŵᵀ) Bᵀ / |w| − F (F_yy)⁻¹ Fᵀ,   B = [(1 − τ) I; τ I],   F = [∂∇g/∂τ, ∂∇g/∂φ] (6 × 2)

— or at a node, nearer than both its bars' inner points (the node's distance above). The 3-D program gives these
places rows that follow them along the wire (:mod:`guidewire.solve3d.program`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline, PPoly
from scipy.spatial import cKDTree

from .tube import Tube

FloatArray = NDArray[np.float64]

ANGLES = 256
"""Angles about a branch's axis at which its crease is found (the spline's knots around a closed crease)."""

MAX_ANGLES = 1024
WALL_TOL = 1e-5
"""A crease whose spline strays more than ``WALL_TOL`` (mm) from its walls between its knots is found again at
twice the angles, up to ``MAX_ANGLES``."""

SCAN_STEP = 0.1
"""Grid step along a branch (in its start radius) on which the crease is bracketed before the root search."""

ROOT_STEPS = 40
"""Most steps of the bracketed root search (Illinois) of each crease point along the branch; it stops once every
point's row is within 1e-14 of the largest radius of zero, or its bracket within 1e-13 of the grid step."""

CORNER_STEPS = 30
"""Most Newton steps of a corner's search (where three walls meet; quadratic from the middle of two knots)."""

NEWTON_STEPS = 8
"""Newton steps on a crease's parameter from the nearest sample (quadratic from within a sample spacing)."""

SAMPLES_PER_KNOT = 8
"""Samples per knot interval in the k-d tree that starts the closest-point search."""

REACH = 0.5
"""A node is held by a crease's row only within this fraction of the smaller tube radius at the crease point: the
cone argument is local (the walls curve away over a radius)."""


@dataclass(frozen=True)
class CreaseMinima:
    """Where a crease comes nearest a wire (:meth:`Crease.minima`): for each, the bar ``k`` (from node ``k`` to
    node ``k + 1``, the clamp node 0) and the place ``τ`` on it (1 at a node: node ``k + 1`` itself), the row
    ``g = |P − X| − r`` and its gradient (6,) over the bar's two nodes and Hessian (6, 6)."""

    bar: NDArray[np.intp]
    fraction: FloatArray
    value: FloatArray
    gradient: FloatArray
    hessian: FloatArray

    @classmethod
    def empty(cls) -> CreaseMinima:
        return cls(np.zeros(0, dtype=np.intp), np.zeros(0), np.zeros(0), np.zeros((0, 6)), np.zeros((0, 6, 6)))

    @classmethod
    def join(cls, parts: Sequence[CreaseMinima]) -> CreaseMinima:
        if not parts:
            return cls.empty()
        return cls(*(np.concatenate([getattr(p, f) for p in parts]) for f in _FIELDS))

    def take(self, index: NDArray[np.intp]) -> CreaseMinima:
        return CreaseMinima(*(getattr(self, f)[index] for f in _FIELDS))


_FIELDS = ("bar", "fraction", "value", "gradient", "hessian")


@dataclass(frozen=True)
class CreaseRows:
    """The rows of the points a crease holds: their indices into the asked points, ``g`` (m,), ``∇g`` (m, 3) and
    ``∇²g`` (m, 3, 3)."""

    index: NDArray[np.intp]
    value: FloatArray
    gradient: FloatArray
    hessian: FloatArray


class Crease:
    """The crease where the wall of tube ``branch`` leaves the other tubes: a closed curve ``K(φ)`` over
    ``[lo, hi]`` (one period of the angle about the branch's axis), one smooth arc per tube it meets (``others``),
    the arcs meeting at :attr:`corners` (see the module docstring). ``spline`` is a periodic cubic spline (one
    arc) or a piecewise cubic whose breaks include the corners; an arc not ``owned`` (another branch's crease holds
    the same curve) has no rows."""

    def __init__(self, branch: int, spline: PPoly, others: Sequence[int], owned: Sequence[bool],
                 tubes: Sequence[Tube], corners: FloatArray | None = None) -> None:
        self.branch, self.others, self.owned = branch, tuple(others), tuple(owned)
        self.other = self.others[0]
        self.spline = spline
        self.lo, self.hi = float(spline.x[0]), float(spline.x[-1])
        self.corners = np.zeros(0) if corners is None else np.asarray(corners, dtype=float)
        count = SAMPLES_PER_KNOT * (len(spline.x) - 1) + 1
        if self.corners.size:  # (knots no longer evenly spaced: the samples evenly within each interval)
            step = np.diff(spline.x)[:, None] * (np.arange(SAMPLES_PER_KNOT) / SAMPLES_PER_KNOT)[None, :]
            self.sigma = np.append((spline.x[:-1, None] + step).ravel(), spline.x[-1])
        else:
            self.sigma = np.linspace(self.lo, self.hi, count)
        self.samples = self.spline(self.sigma)
        self.tree = cKDTree(self.samples)
        self.spacing = float(np.max(np.diff(self.sigma)) if self.corners.size else self.sigma[1] - self.sigma[0])
        self._tubes = tuple(tubes)
        self._arc = self.arc_at(self.sigma)
        # (the walls' directions away from the crease and the rows' reach at the samples, interpolated between)
        self._e_j, self._e_o, self.sample_reach = self._cone_sides(self.samples, self.spline(self.sigma, 1))
        owned_samples = np.asarray(self.owned)[self._arc] & ~self.at_corner(self.sigma)
        self.sample_reach = np.where(owned_samples, self.sample_reach, 0.0)
        self.reach = float(self.sample_reach.max())
        self.box = np.stack((self.samples.min(axis=0), self.samples.max(axis=0)))
        self.chord = float(np.max(np.linalg.norm(np.diff(self.samples, axis=0), axis=1)))  # (samples' spacing)

    @classmethod
    def periodic(cls, branch: int, other: int, phi: FloatArray, points: FloatArray, tubes: Sequence[Tube]) -> Crease:
        """The crease through ``points`` at angles ``phi`` (evenly spaced, one period) on one other tube's wall."""
        knots = np.append(phi, phi[0] + 2.0 * np.pi)
        return cls(branch, CubicSpline(knots, np.vstack((points, points[:1])), bc_type="periodic"), (other,), (True,),
                   tubes)

    @property
    def points(self) -> FloatArray:
        """The crease's sampled points (for drawing and checks)."""
        return self.samples

    def closest(self, p: FloatArray) -> FloatArray:
        """The parameter of the nearest crease point to each of ``p`` (m, 3): Newton's method on
        ``|p − K(φ)|²/2`` from the nearest sample."""
        _, index = self.tree.query(p)
        sigma = self.sigma[index]
        h = self.spacing
        for _ in range(NEWTON_STEPS):
            x, d1, d2 = self.spline(sigma), self.spline(sigma, 1), self.spline(sigma, 2)
            w = p - x
            slope = np.einsum("ij,ij->i", d1, d1) - np.einsum("ij,ij->i", w, d2)  # f'' of f = |p − K|²/2
            grad = -np.einsum("ij,ij->i", w, d1)
            step = np.where(slope > 0.0, -grad / np.where(slope > 0.0, slope, 1.0), -np.sign(grad) * h)
            step = self._within_arc(sigma, np.clip(step, -h, h))
            sigma = self.lo + np.mod(sigma + step - self.lo, self.hi - self.lo)
            if np.all(np.abs(step) <= 1e-13 * max(1.0, abs(self.hi))):
                break
        return sigma

    def _within_arc(self, sigma: FloatArray, step: FloatArray) -> FloatArray:
        """``step`` cut so that ``sigma + step`` does not pass a corner (a search that reaches one stops there:
        the nearest point is on the arc it started on, or the corner itself)."""
        if not self.corners.size:
            return step
        bounds = np.concatenate((self.corners, [self.hi]))
        i = np.clip(np.searchsorted(bounds, sigma, side="right") - 1, 0, len(bounds) - 2)
        return np.clip(step, bounds[i] - sigma, bounds[i + 1] - sigma)

    def wall_error(self) -> float:
        """The largest distance (mm, to first order: the tubes' rows) from either wall of the crease's points
        halfway between its knots, where a spline through points on both walls strays most."""
        x = self.spline.x
        mid = 0.5 * (x[1:] + x[:-1])
        points, arc = self.spline(mid), self.arc_at(mid)
        zero = np.zeros(len(mid))
        error = np.abs(self._tubes[self.branch].rows(points, zero)[0])
        for k, other in enumerate(self.others):
            on = arc == k
            error[on] = np.maximum(error[on], np.abs(self._tubes[other].rows(points[on], zero[on])[0]))
        return float(error.max())

    def arc_at(self, sigma: FloatArray) -> NDArray[np.intp]:
        """The arc (index into :attr:`others`) of the crease points at ``sigma`` in ``[lo, hi]`` (a corner: the arc
        it starts)."""
        if not self.corners.size:
            return np.zeros(np.shape(sigma), dtype=np.intp)
        bounds = np.append(self.corners, self.hi)
        return np.clip(np.searchsorted(bounds, sigma, side="right") - 1, 0, len(self.others) - 1)

    def at_corner(self, sigma: FloatArray) -> NDArray[np.bool_]:
        """Whether the crease points at ``sigma`` are corners (where three walls meet: no row of this crease)."""
        if not self.corners.size:
            return np.zeros(np.shape(sigma), dtype=bool)
        gap = np.abs(np.asarray(sigma)[..., None] - np.concatenate((self.corners, [self.hi])))
        return np.any(gap <= 1e-12 * (self.hi - self.lo), axis=-1)

    def rows(self, p: FloatArray, r: FloatArray) -> CreaseRows:
        """The rows ``g_K = |p − X| − r`` of the points ``p`` (m, 3) of wire radii ``r`` (m,) that lie in this
        crease's cone within its reach (see the module docstring); the others are left out."""
        empty = CreaseRows(np.zeros(0, dtype=np.intp), np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3, 3)))
        outside = np.maximum(np.maximum(self.box[0] - p, p - self.box[1]), 0.0)
        near = np.flatnonzero(np.einsum("ij,ij->i", outside, outside) <= self.reach**2)
        if not near.size:
            return empty
        q = p[near]
        distance, index = self.tree.query(q)
        keep = distance <= self.sample_reach[index] + self.spacing * float(np.max(np.abs(self.spline(self.sigma[
            index], 1))))
        near, q = near[keep], q[keep]
        if not near.size:
            return empty
        sigma = self.closest(q)
        x, d1, d2 = self.spline(sigma), self.spline(sigma, 1), self.spline(sigma, 2)
        w = q - x
        d = np.sqrt(np.einsum("ij,ij->i", w, w))
        cone = self._in_cone(sigma, w, d) & (d > 0.0) & ~self.at_corner(sigma)
        if not cone.any():
            return empty
        i = np.flatnonzero(cone)
        w, d, d1, d2 = w[i], d[i], d1[i], d2[i]
        unit = w / d[:, None]
        hess = _point_hessian(unit, d, d1, d2)
        return CreaseRows(near[i], d - r[near[i]], unit, hess)

    def _segments(self, a: FloatArray, b: FloatArray) -> tuple[FloatArray, ...]:
        """The nearest pair of each segment from ``a`` to ``b`` (m, 3 each) and the crease: ``τ`` in ``[0, 1]`` and
        ``φ`` by Newton's method on ``|a + τ (b − a) − K(φ)|²/2`` (with ``τ`` at a bound, on ``φ`` alone), from the
        best of the segment's ends and middle each from its nearest sample. Returns ``τ, φ``."""
        d = b - a
        dd = np.einsum("ij,ij->i", d, d)
        starts = np.stack((a, 0.5 * (a + b), b))
        gap, index = self.tree.query(starts.reshape(-1, 3))
        pick = np.argmin(gap.reshape(3, -1), axis=0)
        tau = 0.5 * pick
        sigma = self.sigma[index.reshape(3, -1)[pick, np.arange(len(a))]]
        h = self.spacing
        for _ in range(NEWTON_STEPS + 4):
            x, k1, k2 = self.spline(sigma), self.spline(sigma, 1), self.spline(sigma, 2)
            w = a + tau[:, None] * d - x
            g_tau = np.einsum("ij,ij->i", w, d)
            g_sig = -np.einsum("ij,ij->i", w, k1)
            h_ts = -np.einsum("ij,ij->i", d, k1)
            h_ss = np.einsum("ij,ij->i", k1, k1) - np.einsum("ij,ij->i", w, k2)
            det = dd * h_ss - h_ts**2
            good = (det > 1e-12 * dd * np.abs(h_ss)) & (h_ss > 0.0)
            safe = np.where(good, det, 1.0)
            step_t = np.where(good, -(h_ss * g_tau - h_ts * g_sig) / safe, -g_tau / np.maximum(dd, 1e-300))
            step_s = np.where(good, -(dd * g_sig - h_ts * g_tau) / safe, -np.sign(g_sig) * h)
            pinned = (tau + step_t < 0.0) | (tau + step_t > 1.0)  # (τ at a bound: φ's own Newton step)
            step_s = np.where(pinned, np.where(h_ss > 0.0, -g_sig / np.where(h_ss > 0.0, h_ss, 1.0),
                                               -np.sign(g_sig) * h), step_s)
            step_s = self._within_arc(sigma, np.clip(step_s, -h, h))
            new_tau = np.clip(tau + step_t, 0.0, 1.0)
            moved = np.abs(new_tau - tau)
            tau = new_tau
            sigma = self.lo + np.mod(sigma + step_s - self.lo, self.hi - self.lo)
            if np.all(np.abs(step_s) <= 1e-13 * max(1.0, self.hi)) and np.all(moved <= 1e-13):
                break
        return tau, sigma

    def minima(self, nodes: FloatArray, bar_radius: FloatArray, node_radius: FloatArray) -> CreaseMinima:
        """The local minima, along the wire, of the distance between the crease and the polyline ``nodes``
        (n + 1, 3; the clamp first) that lie in the crease's cone within its reach: a bar's inner point where the
        segment's nearest point lies inside it (row ``|P − X| − r`` over its two nodes, the envelope theorem over
        ``(τ, φ)``), or a node nearer than both its bars' inner points (the node's own distance). Sorted by their
        place along the wire."""
        a, b = nodes[:-1], nodes[1:]
        lo_box, hi_box = np.minimum(a, b), np.maximum(a, b)
        outside = np.maximum(np.maximum(self.box[0] - hi_box, lo_box - self.box[1]), 0.0)
        near = np.flatnonzero(np.einsum("ij,ij->i", outside, outside) <= self.reach**2)
        if near.size:
            # (and whose middle's nearest sample, less half the bar and a sample chord, is within the reach)
            half = 0.5 * np.linalg.norm(b[near] - a[near], axis=1)
            gap, _ = self.tree.query(0.5 * (a[near] + b[near]))
            near = near[gap - half - self.chord <= self.reach]
        if not near.size:
            return CreaseMinima.empty()
        tau, sigma = self._segments(a[near], b[near])
        n = len(a)
        at_end = np.zeros(n + 1, dtype=bool)  # (node j + 1 is bar j's nearest point)
        at_start = np.ones(n + 1, dtype=bool)  # (node j is bar j's nearest point; bars far away count as such)
        at_end[near + 1] = tau >= 1.0
        at_start[near] = tau <= 0.0
        inner = (tau > 0.0) & (tau < 1.0)
        # a node is a minimum where its bar before ends there and the bar after starts there (the tip: the last bar
        # ends there); the clamp never (it does not move)
        node_min = np.flatnonzero(at_end[1:] & np.append(at_start[1:n], True)) + 1
        parts = []
        if inner.any():
            parts.append(self._bar_minima(near[inner], a[near[inner]], b[near[inner]], tau[inner], sigma[inner],
                                          bar_radius[near[inner]]))
        if node_min.size:
            where = np.searchsorted(near, node_min - 1)
            parts.append(self._node_minima(node_min, nodes[node_min], sigma[where], node_radius[node_min - 1]))
        found = CreaseMinima.join(parts)
        order = np.argsort(found.bar + found.fraction, kind="stable")
        return found.take(order)

    def _bar_minima(self, bar: NDArray[np.intp], a: FloatArray, b: FloatArray, tau: FloatArray, sigma: FloatArray,
                    r: FloatArray) -> CreaseMinima:
        x, k1, k2 = self.spline(sigma), self.spline(sigma, 1), self.spline(sigma, 2)
        d = b - a
        dd = np.einsum("ij,ij->i", d, d)
        w = a + tau[:, None] * d - x
        dist = np.sqrt(np.einsum("ij,ij->i", w, w))
        keep = (dist > 0.0) & self._in_cone(sigma, w, dist) & ~self.at_corner(sigma)
        if not keep.any():
            return CreaseMinima.empty()
        i = np.flatnonzero(keep)
        tau, w, dist, d, dd, k1, k2 = tau[i], w[i], dist[i], d[i], dd[i], k1[i], k2[i]
        unit = w / dist[:, None]
        m = len(i)
        # ∇ over (a, b): B ŵ with B = [(1 − τ) I; τ I]
        weights = np.stack((1.0 - tau, tau), axis=1)
        grad = (weights[:, :, None] * unit[:, None, :]).reshape(m, 6)
        proj = np.eye(3)[None] - unit[:, :, None] * unit[:, None, :]
        f_xx = (weights[:, :, None, None, None] * weights[:, None, :, None, None]
                * proj[:, None, None, :, :] / dist[:, None, None, None, None])  # (m, 2, 2, 3, 3)
        f_xx = f_xx.transpose(0, 1, 3, 2, 4).reshape(m, 6, 6)
        # mixed terms (ŵ · d = ŵ · K' = 0 at the nearest pair)
        f_xt = np.concatenate((-unit + (1.0 - tau)[:, None] * d / dist[:, None],
                               unit + tau[:, None] * d / dist[:, None]), axis=1)
        f_xs = -np.concatenate(((1.0 - tau)[:, None] * k1, tau[:, None] * k1), axis=1) / dist[:, None]
        f_tt = dd / dist
        f_ts = -np.einsum("ij,ij->i", d, k1) / dist
        f_ss = np.einsum("ij,ij->i", k1, k1) / dist - np.einsum("ij,ij->i", unit, k2)
        det = f_tt * f_ss - f_ts**2
        inv = np.stack((np.stack((f_ss, -f_ts), axis=1), np.stack((-f_ts, f_tt), axis=1)), axis=1)
        inv /= det[:, None, None]
        mixed = np.stack((f_xt, f_xs), axis=2)  # (m, 6, 2)
        hess = f_xx - np.einsum("mia,mab,mjb->mij", mixed, inv, mixed)
        return CreaseMinima(bar[i], tau, dist - r[i], grad, hess)

    def _node_minima(self, node: NDArray[np.intp], p: FloatArray, sigma: FloatArray, r: FloatArray) -> CreaseMinima:
        x, k1, k2 = self.spline(sigma), self.spline(sigma, 1), self.spline(sigma, 2)
        w = p - x
        dist = np.sqrt(np.einsum("ij,ij->i", w, w))
        keep = (dist > 0.0) & self._in_cone(sigma, w, dist) & ~self.at_corner(sigma)
        if not keep.any():
            return CreaseMinima.empty()
        i = np.flatnonzero(keep)
        w, dist, k1, k2 = w[i], dist[i], k1[i], k2[i]
        unit, m = w / dist[:, None], len(i)
        grad = np.zeros((m, 6))
        grad[:, 3:] = unit
        hess = np.zeros((m, 6, 6))
        hess[:, 3:, 3:] = _point_hessian(unit, dist, k1, k2)
        return CreaseMinima(node[i] - 1, np.ones(m), dist - r[i], grad, hess)

    def _cone_sides(self, x: FloatArray, k1: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """At crease points ``x`` with tangents ``k1``: the directions ``e_j``, ``e_o`` in which the two walls leave
        the crease (normal to it, each away from the other tube) and the rows' reach."""
        tangent = k1 / np.linalg.norm(k1, axis=1)[:, None]
        n_j, radius_j = _inward(self._tubes[self.branch], x)
        n_o, radius_o = np.zeros_like(x), np.zeros(len(x))
        for arc, other in enumerate(self.others):
            on = self._arc == arc
            n_o[on], radius_o[on] = _inward(self._tubes[other], x[on])
        radius = (radius_j, radius_o)
        e_j = np.cross(n_j, tangent)
        e_j *= np.where(np.einsum("ij,ij->i", e_j, n_o) < 0.0, 1.0, -1.0)[:, None]
        e_o = np.cross(n_o, tangent)
        e_o *= np.where(np.einsum("ij,ij->i", e_o, n_j) < 0.0, 1.0, -1.0)[:, None]
        return e_j, e_o, REACH * np.minimum(*radius)

    def _in_cone(self, sigma: FloatArray, w: FloatArray, dist: FloatArray) -> NDArray[np.bool_]:
        """Whether ``w`` (from the crease points at ``sigma``) lies in the crease's cone within its reach: the
        walls' directions and the reach interpolated linearly between the samples (a cone's side is placed to
        ~1e-5 rad; on it the crease's row and the wall's agree to first order, so the switch is smooth there)."""
        if self.corners.size:
            i = np.clip(np.searchsorted(self.sigma, sigma, side="right") - 1, 0, len(self.sigma) - 2)
            t = ((sigma - self.sigma[i]) / (self.sigma[i + 1] - self.sigma[i]))[:, None]
        else:
            at = (sigma - self.lo) / self.spacing
            i = np.clip(np.floor(at).astype(np.intp), 0, len(self.sigma) - 2)
            t = (at - i)[:, None]
        e_j = (1.0 - t) * self._e_j[i] + t * self._e_j[i + 1]
        e_o = (1.0 - t) * self._e_o[i] + t * self._e_o[i + 1]
        reach = (1.0 - t[:, 0]) * self.sample_reach[i] + t[:, 0] * self.sample_reach[i + 1]
        return (np.einsum("ij,ij->i", w, e_j) <= 0.0) & (np.einsum("ij,ij->i", w, e_o) <= 0.0) & (dist <= reach)


def _inward(tube: Tube, x: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Unit normals into ``tube`` at its wall points ``x`` (m, 3) and its radius there."""
    e = tube.closest(x, np.zeros(len(x)))
    v = e.centre - x
    return v / np.linalg.norm(v, axis=1)[:, None], e.radius


def _point_hessian(unit: FloatArray, dist: FloatArray, k1: FloatArray, k2: FloatArray) -> FloatArray:
    """``∇²|p − K(φ*)|`` (m, 3, 3) at nearest points: ``(I − ŵŵᵀ)/|w| − K'K'ᵀ / (|w| (|K'|² − w·K''))``."""
    curvature = np.einsum("ij,ij->i", k1, k1) - dist * np.einsum("ij,ij->i", unit, k2)  # (> 0 at a nearest point)
    return ((np.eye(3)[None] - unit[:, :, None] * unit[:, None, :]) / dist[:, None, None]
            - k1[:, :, None] * k1[:, None, :] / (dist * np.maximum(curvature, 1e-300))[:, None, None])


def find_creases(tubes: Sequence[Tube]) -> tuple[Crease, ...]:
    """The creases of the lumen of ``tubes`` (main first): around each branch whose wall starts inside the other
    tubes, where its wall leaves them (see the module docstring). Where the crease meets two tubes (a bifurcation
    at a trunk's end: the branch leaves the trunk's end and its sibling), it has corners where three walls meet
    (Newton's method on the branch wall's ``(u, φ)``) and one arc per tube; the arc along a later sibling's wall is
    that sibling's (its crease runs along the same curve) and has no rows here. A crease that strays more than
    :data:`WALL_TOL` from its walls between its knots is found again with twice the angles, up to
    :data:`MAX_ANGLES`."""
    found = [None] + [_branch_crease(tubes, j) for j in range(1, len(tubes))]
    out: list[Crease] = []
    for j in range(1, len(tubes)):
        item, angles, kept = found[j], ANGLES, None
        while item is not None:
            phi, x, other, along = item
            if np.all(other == other[0]):
                crease = Crease.periodic(j, int(other[0]), phi, x, tubes)
            else:
                spline, others, corners = _arcs(tubes, j, phi, x, other, along)
                owned = [o < j or found[o] is None for o in others]
                crease = Crease(j, spline, others, owned, tubes, corners) if any(owned) else None
            if crease is None:
                break
            kept = crease
            if angles >= MAX_ANGLES or crease.wall_error() <= WALL_TOL:
                break
            angles *= 2  # (a crease that turns fast in its angle: knots twice as dense)
            item = _branch_crease(tubes, j, angles)
        if kept is not None:
            out.append(kept)
    return tuple(out)


def _arcs(tubes: Sequence[Tube], j: int, phi: FloatArray, x: FloatArray, other: NDArray[np.intp],
          along: FloatArray) -> tuple[PPoly, list[int], FloatArray]:
    """The piecewise spline of a crease that meets more than one tube (knots at angles ``phi``, points ``x``, the
    tube each leaves last ``other``, at ``along`` on the branch): its corners — between two knots whose tubes
    differ, the point of the branch's wall on both tubes' walls, by Newton's method on its ``(u, φ)`` (central
    differences for the Jacobian) — and a not-a-knot cubic spline per arc between corners, through the arc's knots
    and its two corners, as one periodic piecewise cubic starting at the first corner. Returns the spline, each
    arc's tube and the corners' angles (increasing, the first at the spline's start)."""
    switch = np.flatnonzero(other != np.roll(other, 1))  # (knot k differs from knot k − 1)
    period = 2.0 * np.pi
    o1, o2 = other[switch - 1], other[switch]
    # Newton on (u, φ): branch j's wall point on both tubes' walls, from the middle of the two knots
    corner = 0.5 * (phi[switch - 1] - np.where(switch == 0, period, 0.0) + phi[switch])
    u = 0.5 * (along[switch - 1] + along[switch])
    hu, hp = 1e-6 * tubes[j].radius0, 1e-6

    def rows(uu: FloatArray, pp: FloatArray) -> FloatArray:
        w = _wall_at(tubes[j], uu, np.mod(pp, period))
        zero = np.zeros(1)
        return np.array([[tubes[t].rows(w[k:k + 1], zero)[0][0] for t in (o1[k], o2[k])] for k in range(len(w))])

    for _ in range(CORNER_STEPS):
        f = rows(u, corner)
        if np.max(np.abs(f)) <= 1e-14 * tubes[j].max_radius:
            break
        ju = (rows(u + hu, corner) - rows(u - hu, corner)) / (2.0 * hu)
        jp = (rows(u, corner + hp) - rows(u, corner - hp)) / (2.0 * hp)
        step = np.linalg.solve(np.stack((ju, jp), axis=2), -f[:, :, None])[:, :, 0]
        u, corner = u + step[:, 0], corner + step[:, 1]
    corner_point = _wall_at(tubes[j], u, np.mod(corner, period))
    # one period from the first corner: knots and corners in increasing angle
    start = corner[0]
    knot_phi = start + np.mod(phi - start, period)
    corner_phi = start + np.mod(corner - start, period)
    corner_phi[0] = start
    order = np.argsort(corner_phi)
    corner_phi, corner_point, arc_other = corner_phi[order], corner_point[order], o2[order]
    bounds = np.append(corner_phi, start + period)
    gap = 1e-3 * (phi[1] - phi[0])  # (a knot this close to a corner would only bend the spline)
    breaks, coefficients = [], []
    for k in range(len(corner_phi)):
        inside = (knot_phi > bounds[k] + gap) & (knot_phi < bounds[k + 1] - gap)
        idx = np.flatnonzero(inside)
        idx = idx[np.argsort(knot_phi[idx])]
        t = np.concatenate(([bounds[k]], knot_phi[idx], [bounds[k + 1]]))
        pts = np.vstack((corner_point[k], x[idx], corner_point[(k + 1) % len(corner_phi)]))
        piece = CubicSpline(t, pts, bc_type="not-a-knot" if len(t) >= 4 else "natural")
        breaks.append(piece.x[:-1] if k < len(corner_phi) - 1 else piece.x)
        coefficients.append(piece.c)
    spline = PPoly(np.concatenate(coefficients, axis=1), np.concatenate(breaks), extrapolate="periodic")
    return spline, [int(o) for o in arc_other], corner_phi


def _others_row(tubes: Sequence[Tube], j: int, x: FloatArray,
                among: Sequence[int] | None = None) -> tuple[FloatArray, NDArray[np.intp]]:
    """``max_{i ≠ j} g_i(x)`` with ``r = 0`` (over the tubes ``among`` if given) and the tube that gives it, for
    points ``x`` (m, 3)."""
    best = np.full(len(x), -np.inf)
    which = np.full(len(x), -1, dtype=np.intp)
    zero = np.zeros(len(x))
    for i, tube in enumerate(tubes):
        if i == j or (among is not None and i not in among):
            continue
        near = np.flatnonzero(tube.row_bound(x, zero, best) >= best)
        if not near.size:
            continue
        g = tube.rows(x[near], zero[near])[0]
        better = g > best[near]
        best[near[better]] = g[better]
        which[near[better]] = i
    return best, which


def _at(tube: Tube, u: float, phi: FloatArray) -> FloatArray:
    """:func:`_wall` at one ``u`` for every angle ``phi``."""
    return _wall_at(tube, np.full(len(phi), u), phi)


def _wall_at(tube: Tube, u: FloatArray, phi: FloatArray) -> FloatArray:
    """:func:`_wall` at ``u`` and ``phi`` (one each per point) in :func:`_frame`."""
    return _wall(tube, u, phi, _frame(tube, u))


def _wall(tube: Tube, u: FloatArray, phi: FloatArray, frame: tuple[FloatArray, FloatArray]) -> FloatArray:
    """Points of ``tube``'s wall (the envelope of its balls) at ``u`` and angle ``phi`` about its axis, in the normal
    frame ``frame`` (two unit vectors per ``u``, normal to the axis)."""
    e = tube.evaluate(u)
    speed = np.linalg.norm(e.d1, axis=1)
    t = e.d1 / speed[:, None]
    slope = np.clip(e.radius_d1 / speed, -0.99, 0.99)  # (the envelope's tilt: e · t = −R'/|c'|)
    a, b = frame
    around = np.cos(phi)[:, None] * a + np.sin(phi)[:, None] * b
    direction = -slope[:, None] * t + np.sqrt(1.0 - slope**2)[:, None] * around
    return e.centre + e.radius[:, None] * direction


def _frame(tube: Tube, u: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Unit normals ``a, b`` to the axis at ``u``: a fixed world axis (the one least along the axis at the start)
    projected onto the normal plane, and ``t × a``."""
    e = tube.evaluate(u)
    t = e.d1 / np.linalg.norm(e.d1, axis=1)[:, None]
    ref = np.eye(3)[int(np.argmin(np.abs(tube.evaluate(np.zeros(1)).d1[0])))]
    a = ref - np.einsum("ij,j->i", t, ref)[:, None] * t
    a /= np.linalg.norm(a, axis=1)[:, None]
    return a, np.cross(t, a)


def _branch_crease(tubes: Sequence[Tube], j: int, angles: int = ANGLES) -> tuple[FloatArray, FloatArray,
                                                                                 NDArray[np.intp], FloatArray] | None:
    """Angles, crease points, the tube met and the ``u`` there, around branch ``j``: for each angle the first ``u``
    where its wall leaves the other tubes; None when its wall starts outside them (no opening to crease)."""
    phi = np.linspace(0.0, 2.0 * np.pi, angles, endpoint=False)
    ring = _at(tubes[j], 0.0, phi)
    if not np.all(_others_row(tubes, j, ring)[0] > 0.0):
        return None  # (its wall starts outside the others at some angle: no crease around its start)
    zero = np.zeros(len(ring))
    start = [i for i, t in enumerate(tubes) if i != j and np.max(t.rows(ring, zero)[0]) > 0.0]
    return _exits(tubes, j, phi, start)


def _exits(tubes: Sequence[Tube], j: int, phi: FloatArray,
           start: Sequence[int]) -> tuple[FloatArray, FloatArray, NDArray[np.intp], FloatArray] | None:
    """At angles ``phi`` about branch ``j``'s axis, the first ``u`` where its wall leaves the other tubes (bracketed
    on a grid, then Illinois): the angles, the points, the tube each leaves last and the ``u``; None if it never
    leaves. ``start``: the tubes its start lies in."""
    tube = tubes[j]
    step = SCAN_STEP * tube.radius0
    # (the wall has left the tubes it starts in wherever the axis lies a radius outside them: the scan ends there;
    # a tube that leaves the branch's own side further on, as the bovine arch's left common carotid leaves the
    # brachiocephalic trunk, is not one of them)
    axis_u = np.arange(0.0, tube.end + step, step)
    axis = tube.evaluate(axis_u)
    out = np.flatnonzero(_others_row(tubes, j, axis.centre, start)[0] < -axis.radius)
    if not out.size:
        return None  # (a branch that never leaves the others)
    grid = axis_u[: out[0] + 1]
    uu, pp = np.repeat(grid, len(phi)), np.tile(phi, grid.size)
    outside = (_others_row(tubes, j, _wall_at(tube, uu, pp))[0] <= 0.0).reshape(grid.size, len(phi))
    if not outside[-1].all():
        return None
    first = np.maximum(np.argmax(outside, axis=0), 1)  # (the first grid value outside: every angle starts inside)
    lo = grid[first - 1]
    a, b = lo.copy(), lo + step
    fa, fb = _others_row(tubes, j, _wall_at(tube, a, phi))[0], _others_row(tubes, j, _wall_at(tube, b, phi))[0]
    last = np.zeros(len(phi))  # (the end replaced last: −1 the inner, +1 the outer)
    for _ in range(ROOT_STEPS):  # (Illinois: regula falsi that halves the value of an end kept twice)
        u = (a * fb - b * fa) / (fb - fa)
        f = _others_row(tubes, j, _wall_at(tube, u, phi))[0]
        inner = f > 0.0
        fb = np.where(inner & (last < 0.0), 0.5 * fb, fb)
        fa = np.where(~inner & (last > 0.0), 0.5 * fa, fa)
        a, fa = np.where(inner, u, a), np.where(inner, f, fa)
        b, fb = np.where(inner, b, u), np.where(inner, fb, f)
        last = np.where(inner, -1.0, 1.0)
        if np.max(np.minimum(np.abs(fa), np.abs(fb))) <= 1e-14 * tube.max_radius or np.max(b - a) <= 1e-13 * step:
            break
    u = np.where(np.abs(fa) < np.abs(fb), a, b)
    x = _wall_at(tube, u, phi)
    _, other = _others_row(tubes, j, x)
    return phi, x, other, u
