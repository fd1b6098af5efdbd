"""Curves and tubes behind :class:`guidewire.vessel.Vessel`: the C² centreline splines with their radius, the
closest-point search over a union of tubes, the wall-crossing tests, and the :class:`Clearance` answer.

Units mm and rad; private to :mod:`guidewire.vessel` (which re-exports :class:`Clearance` and the constants).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline, PchipInterpolator
from scipy.spatial import cKDTree

FloatArray = NDArray[np.float64]
Polyline = tuple[tuple[float, ...], ...]

SAMPLE_SPACING = 0.5
"""Largest spacing (mm) of the fine sampling used to start the closest-point search; smaller for narrow or tightly
bent tubes (a quarter of the least radius, a quarter of the least bend radius)."""

NEWTON_STEPS = 3
"""Newton steps on the spline parameter after the nearest sample (quadratic convergence from within one spacing:
~1e-3, 1e-6, 1e-12 of a spacing)."""

TAIL_REACH = 50.0
"""A tube continues straight past its far end for this many mm (or :data:`TAIL_REACH_RADII` end radii if longer),
then closes with a rounded cap: far enough for a tip to leave the vessel unhindered, short enough not to reach back
into another part of the tree."""

TAIL_REACH_RADII = 4.0
"""The tube's straight continuation reaches at least this many end radii (see :data:`TAIL_REACH`)."""

BIFURCATION_REACH = 0.5
"""A branch that starts within this fraction of a tube's end radius from its last point makes that end a
bifurcation (:func:`outlets`)."""

HULL_SAMPLES = 16
"""Samples per covering disk of the bound that lets :meth:`Vessel.clearance` skip the tubes a point is far from."""

BEND_LIMIT = 1.0
"""A tube whose centreline curvature times radius reaches this anywhere overlaps itself there (refused)."""


@dataclass(frozen=True, eq=False)
class Clearance:
    """The lumen's answer for ``m`` query points (:meth:`Vessel.clearance`).

    Attributes
    ----------
    distance : ndarray, shape (m,)
        Signed distance (mm) from the point to the lumen boundary: > 0 inside the lumen, < 0 outside.
    normal : ndarray, shape (m, 2)
        Unit outward normal of the boundary at the nearest boundary point (pointing out of the lumen); it is the
        gradient of ``−distance`` with respect to the point.
    boundary : ndarray, shape (m, 2)
        That nearest boundary point (mm): ``point + distance · normal``.
    curvature : ndarray, shape (m,)
        Curvature (1/mm) of the boundary there: > 0 where the wall bulges into the lumen (the inner wall of a bend,
        where a chord between two inside points can cut through the wall), < 0 where it curves away (the outer wall
        of a bend, the entrance cap), 0 on a straight wall.
    """

    distance: FloatArray
    normal: FloatArray
    boundary: FloatArray
    curvature: FloatArray

    def take(self, index: ArrayLike) -> Clearance:
        """The answers for the points ``index`` selects."""
        return Clearance(self.distance[index], self.normal[index], self.boundary[index], self.curvature[index])

    def joined(self, other: Clearance) -> Clearance:
        """These answers, then ``other``'s (for the points of both, in that order)."""
        return Clearance(*(np.concatenate((getattr(self, name), getattr(other, name))) for name in CLEARANCE_FIELDS))


CLEARANCE_FIELDS = ("distance", "normal", "boundary", "curvature")
"""The fields of a :class:`Clearance`, in order."""


# ----------------------------------------------------------------------------------------------------------------
# validation of the data
def segments_cross(a0: FloatArray, a1: FloatArray, b0: FloatArray, b1: FloatArray) -> NDArray[np.bool_]:
    """Whether segments ``a0a1`` and ``b0b1`` (broadcast) properly intersect or touch."""

    def orient(p: FloatArray, q: FloatArray, r: FloatArray) -> FloatArray:
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])

    d1, d2 = orient(b0, b1, a0), orient(b0, b1, a1)
    d3, d4 = orient(a0, a1, b0), orient(a0, a1, b1)
    return (d1 * d2 <= 0.0) & (d3 * d4 <= 0.0) & ~((d1 == 0) & (d2 == 0) & (d3 == 0) & (d4 == 0))


def self_crossing(points: FloatArray) -> tuple[int, int] | None:
    """The first pair of non-adjacent segments of a polyline that cross, or None."""
    a0, a1 = points[:-1, None, :], points[1:, None, :]
    b0, b1 = points[None, :-1, :], points[None, 1:, :]
    cross = segments_cross(a0, a1, b0, b1)
    n = len(points) - 1
    i, j = np.triu_indices(n, k=2)
    hits = np.flatnonzero(cross[i, j])
    return None if hits.size == 0 else (int(i[hits[0]]), int(j[hits[0]]))


# ----------------------------------------------------------------------------------------------------------------
# smooth curves
class Curve:
    """A C² cubic spline ``c(u)`` through a polyline (chord-length parameter ``u``) with a PCHIP radius ``R(u)``.

    ``coef`` has shape (4, n − 1, 3): the cubic coefficients (highest degree first, as ``scipy.interpolate.PPoly``)
    of x, y and R on each interval of ``breaks``.
    """

    def __init__(self, points: FloatArray, radius: FloatArray, *, spacing: float = SAMPLE_SPACING) -> None:
        chord = np.hypot(*np.diff(points, axis=0).T)
        self.breaks = np.concatenate(([0.0], np.cumsum(chord)))
        if len(points) == 2:  # a straight segment
            c = np.zeros((4, 1, 3))
            c[2, 0, :2] = (points[1] - points[0]) / chord[0]
            c[3, 0, :2] = points[0]
        else:
            c = np.zeros((4, len(points) - 1, 3))
            c[:, :, :2] = CubicSpline(self.breaks, points, bc_type="not-a-knot").c
        if np.all(radius == radius[0]):
            c[3, :, 2] = radius[0]
        else:
            c[:, :, 2] = PchipInterpolator(self.breaks, radius).c
        self.coef = c
        self.points = points
        self.lo, self.hi = 0.0, float(self.breaks[-1])
        # a fine sampling: each interval cut into pieces of at most `spacing`
        pieces = np.maximum(1, np.ceil(chord / spacing).astype(int))
        self.u = np.concatenate([np.linspace(a, b, k, endpoint=False) for a, b, k in
                                 zip(self.breaks[:-1], self.breaks[1:], pieces, strict=True)] + [self.breaks[-1:]])
        value, d1, d2 = self.evaluate(self.u)
        self.samples, self.radius = value[:, :2], value[:, 2]
        self.speed = np.hypot(d1[:, 0], d1[:, 1])
        self.kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / self.speed**3
        # arc length by 3-point Gauss–Legendre on every sample interval (the speed is smooth within one)
        nodes, weights = np.polynomial.legendre.leggauss(3)
        mid, half = 0.5 * (self.u[1:] + self.u[:-1]), 0.5 * np.diff(self.u)
        gauss = mid[:, None] + half[:, None] * nodes[None, :]
        _, gd1, _ = self.evaluate(gauss.ravel())
        speed = np.hypot(gd1[:, 0], gd1[:, 1]).reshape(gauss.shape)
        self.s = np.concatenate(([0.0], np.cumsum(half * (speed @ weights))))
        self.length = float(self.s[-1])
        self._u_of_s = CubicSpline(self.s, self.u)

    def segment(self, u: FloatArray) -> NDArray[np.intp]:
        return np.clip(np.searchsorted(self.breaks, u, side="right") - 1, 0, len(self.breaks) - 2)

    def evaluate(self, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Value, first and second derivatives in ``u`` of (x, y, R), each shape (m, 3); ``u`` clipped to the curve."""
        u = np.clip(u, self.lo, self.hi)
        j = self.segment(u)
        x = (u - self.breaks[j])[:, None]
        c0, c1, c2, c3 = self.coef[:, j, :]
        value = ((c0 * x + c1) * x + c2) * x + c3
        d1 = (3.0 * c0 * x + 2.0 * c1) * x + c2
        d2 = 6.0 * c0 * x + 2.0 * c1
        return value, d1, d2

    def u_of_s(self, s: FloatArray) -> FloatArray:
        return np.asarray(self._u_of_s(np.clip(s, 0.0, self.length)), dtype=float)


class Tubes:
    """The closest-point machinery shared by tubes (``R > 0``, union of disks) and walls (``R ≡ 0``), vectorised over
    points and curves.

    For every curve it finds ``u* = argmax_u R(u) − |p − c(u)|`` (the nearest sample of a k-d tree, then Newton
    steps) and compares it with the straight continuations of the curve past its open ends.
    """

    def __init__(self, curves: Sequence[Curve], *, head_open: Sequence[bool], tail_open: Sequence[bool],
                 reach: float | Sequence[float] = math.inf) -> None:
        self.curves = tuple(curves)
        self.reach = np.broadcast_to(np.asarray(reach, dtype=float), (len(curves),)).copy()
        self.trees = tuple(cKDTree(c.samples) for c in curves)
        self.head_open = np.asarray(head_open, dtype=bool)
        self.tail_open = np.asarray(tail_open, dtype=bool)
        # all curves in one parameter line: curve k lives on [offset_k, offset_k + hi_k]
        offsets, breaks, coefs, start = [], [], [], 0.0
        for c in curves:
            offsets.append(start)
            breaks.append(c.breaks + start)
            coefs.append(c.coef)
            coefs.append(np.zeros((4, 1, 3)))  # the gap interval between two curves (never evaluated)
            start += c.hi + 1.0
        self.offsets = np.asarray(offsets)
        self.breaks = np.concatenate(breaks)
        coef = np.concatenate(coefs[:-1], axis=1)
        self.flat = np.ascontiguousarray(coef.transpose(1, 0, 2).reshape(-1, 12))  # (segment, 4 × (x, y, R))
        self.lo = self.offsets.copy()
        self.hi = self.offsets + np.array([c.hi for c in curves])
        self.first_seg = np.searchsorted(self.breaks, self.lo, side="right") - 1
        self.last_seg = np.searchsorted(self.breaks, self.hi, side="left") - 1
        self.h = np.array([float(np.max(np.diff(c.u))) if len(c.u) > 1 else 1.0 for c in curves])
        # the straight continuations: end points, unit tangents and radii
        heads = [c.evaluate(np.array([c.lo])) for c in curves]
        tails = [c.evaluate(np.array([c.hi])) for c in curves]
        self.head_point = np.array([v[0, :2] for v, _, _ in heads])
        self.head_tangent = np.array([d[0, :2] / np.hypot(*d[0, :2]) for _, d, _ in heads])
        self.head_radius = np.array([v[0, 2] for v, _, _ in heads])
        self.tail_point = np.array([v[0, :2] for v, _, _ in tails])
        self.tail_tangent = np.array([d[0, :2] / np.hypot(*d[0, :2]) for _, d, _ in tails])
        self.tail_radius = np.array([v[0, 2] for v, _, _ in tails])
        self._build_hulls()

    def _build_hulls(self) -> None:
        """Disks that together cover each curve and its finite straight continuations (``hull_centre``,
        ``hull_radius``, ``hull_curve``; grouped by curve, from ``hull_start[k]``) and each curve's largest radius
        ``rmax``: a lower bound of the distance to curve ``k`` for :meth:`upper_bound`.

        A run of :data:`HULL_SAMPLES` samples is covered by the disk about its middle sample reaching its farthest
        sample plus half its longest sample interval (a point of the curve between two samples lies within half that
        interval's arc length of one of them); a continuation of finite reach by disks about pieces of
        :data:`HULL_SAMPLES` spacings. An infinite continuation (a wall's) gets none: :meth:`upper_bound` is then
        not a bound, and only tubes use it."""
        centres, radii, owner, depth = [], [], [], []
        for k, c in enumerate(self.curves):
            ds = np.diff(c.s)
            for a in range(0, max(len(c.u) - 1, 1), HULL_SAMPLES):
                b = min(a + HULL_SAMPLES, len(c.u) - 1)
                mid = c.samples[(a + b) // 2]
                reach = float(np.max(np.hypot(*(c.samples[a:b + 1] - mid).T)))
                centres.append(mid)
                radii.append(reach + 0.5 * float(np.max(ds[a:b], initial=0.0)))
                owner.append(k)
                depth.append(float(c.radius[(a + b) // 2]))
            for is_open, point, direction, sign in ((self.head_open[k], self.head_point[k], self.head_tangent[k], -1.0),
                                                    (self.tail_open[k], self.tail_point[k], self.tail_tangent[k], 1.0)):
                if not is_open or not math.isfinite(self.reach[k]):
                    continue
                pieces = max(1, math.ceil(self.reach[k] / (HULL_SAMPLES * self.h[k])))
                piece = self.reach[k] / pieces
                for j in range(pieces):
                    centres.append(point + sign * (j + 0.5) * piece * direction)
                    radii.append(0.5 * piece)
                    owner.append(k)
                    depth.append(float(self.tail_radius[k] if sign > 0 else self.head_radius[k]))
        self.hull_centre = np.array(centres)
        self.hull_radius = np.array(radii)
        self.hull_curve = np.array(owner, dtype=np.intp)
        self.hull_depth = np.array(depth)  # the tube's radius at each disk's centre (a point of the tube's axis)
        self.hull_start = np.searchsorted(self.hull_curve, np.arange(len(self.curves)))
        self.rmax = np.array([max(float(np.max(c.radius)), float(self.head_radius[k]), float(self.tail_radius[k]))
                              for k, c in enumerate(self.curves)])

    def lower_bound(self, p: FloatArray) -> FloatArray:
        """A lower bound, shape (m,), of the largest signed distance ``R − |p − c|`` of every point to any tube: its
        value at the best of the hull disks' centres (each a point of a tube's axis)."""
        dx = p[:, None, 0] - self.hull_centre[None, :, 0]
        dy = p[:, None, 1] - self.hull_centre[None, :, 1]
        return np.max(self.hull_depth - np.sqrt(dx * dx + dy * dy), axis=1)

    def upper_bound(self, p: FloatArray) -> FloatArray:
        """An upper bound, shape (m, T), of the signed distance ``max R − |p − c|`` of every point to every tube
        (its largest radius minus a lower bound of the distance to its centreline and finite continuations)."""
        dx = p[:, None, 0] - self.hull_centre[None, :, 0]
        dy = p[:, None, 1] - self.hull_centre[None, :, 1]
        gap = np.sqrt(dx * dx + dy * dy) - self.hull_radius
        return self.rmax - np.minimum.reduceat(gap, self.hull_start, axis=1)

    def evaluate(self, u: FloatArray, k: NDArray[np.intp] | int) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Value, first and second ``u``-derivatives of (x, y, R) of curve ``k`` (one per value, or one for all) at
        ``u``, each shape (m, 3)."""
        j = np.minimum(np.maximum(np.searchsorted(self.breaks, u, side="right") - 1, self.first_seg[k]),
                       self.last_seg[k])
        x = (u - self.breaks[j])[:, None]
        c = self.flat[j]
        c0, c1, c2, c3 = c[:, 0:3], c[:, 3:6], c[:, 6:9], c[:, 9:12]
        a = c0 * x
        return ((a + c1) * x + c2) * x + c3, (3.0 * a + 2.0 * c1) * x + c2, 6.0 * a + 2.0 * c1

    def closest(self, p: FloatArray) -> dict[str, FloatArray]:
        """For every curve k and point i (flattened k-major, length T·m): the best parameter ``u``, the centre ``c``,
        the radius ``R``, the offset ``v = p − c`` and its length ``r``, where it came from (``source``: 0 the
        spline, 1 past the head, 2 past the tail, 3 on the cap closing a continuation), and the curve's unit tangent
        ``t`` and signed curvature ``kappa`` there (0 on the straight continuations)."""
        m, t = len(p), len(self.curves)
        if t == 1:
            return self.closest_pairs(p, np.zeros(m, dtype=np.intp))
        return self.closest_pairs(np.tile(p, (t, 1)), np.repeat(np.arange(t), m))

    def closest_pairs(self, q: FloatArray, k: NDArray[np.intp]) -> dict[str, FloatArray]:
        """:meth:`closest` for the pairs (point ``q[i]``, curve ``k[i]``) only (elementwise: the same answer for a
        pair whichever others are asked with it)."""
        pairs = k
        if len(k) and np.all(k == k[0]):
            k = int(k[0])  # one curve: its data as scalars, broadcast (the same arithmetic, fewer gathers)
            u = self.curves[k].u[self.trees[k].query(q)[1]] + self.offsets[k]  # (its tree only)
        else:
            u = np.empty(len(q))
            for i, tree in enumerate(self.trees):
                mine = k == i
                if mine.all():
                    u = self.curves[i].u[tree.query(q)[1]] + self.offsets[i]
                elif mine.any():
                    u[mine] = self.curves[i].u[tree.query(q[mine])[1]] + self.offsets[i]
        lo, hi, h = self.lo[k], self.hi[k], self.h[k]
        for step_number in range(NEWTON_STEPS + 1):
            value, d1, d2 = self.evaluate(u, k)
            if step_number == NEWTON_STEPS:
                break
            # stationarity of |p − c| − R, times r so that it is smooth on the axis and quadratic for R' = 0:
            # G = v·c' + r R' = 0, G' = v·c'' − |c'|² − (e·c') R' + r R''  (v = p − c, e = v / r)
            v = q - value[:, :2]
            r = np.hypot(v[:, 0], v[:, 1])
            vc1 = v[:, 0] * d1[:, 0] + v[:, 1] * d1[:, 1]
            g = vc1 + r * d1[:, 2]
            slope = (v[:, 0] * d2[:, 0] + v[:, 1] * d2[:, 1] - d1[:, 0] ** 2 - d1[:, 1] ** 2
                     - vc1 / np.maximum(r, 1e-300) * d1[:, 2] + r * d2[:, 2])
            step = np.where(slope < 0.0, -g / np.where(slope < 0.0, slope, -1.0), np.sign(g) * h)
            u = np.minimum(np.maximum(u + np.minimum(np.maximum(step, -h), h), lo), hi)
        centre, radius = value[:, :2], value[:, 2]
        speed = np.hypot(d1[:, 0], d1[:, 1])
        tangent = d1[:, :2] / speed[:, None]
        kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed**3
        source = np.zeros(len(u), dtype=np.intp)
        # the straight continuations past open ends: project on the end's tangent line
        for end, is_open, point, direction, rad, sign in (
            (1, self.head_open, self.head_point, self.head_tangent, self.head_radius, -1.0),
            (2, self.tail_open, self.tail_point, self.tail_tangent, self.tail_radius, 1.0),
        ):
            if not is_open.any():
                continue
            lam = np.einsum("ij,ij->i", q - point[k], np.broadcast_to(direction[k], q.shape))
            past = is_open[k] & (sign * lam > 0.0)
            if not past.any():
                continue
            capped = np.abs(lam) > self.reach[k]  # a continuation of finite reach ends in a rounded cap
            lam = np.clip(lam, -self.reach[k], self.reach[k])
            foot = point[k] + lam[:, None] * direction[k]
            gain = (rad[k] - np.hypot(*(q - foot).T)) - (radius - np.hypot(*(q - centre).T))
            better = past & (gain > 0.0)
            centre = np.where(better[:, None], foot, centre)
            radius = np.where(better, rad[k], radius)
            tangent = np.where(better[:, None], direction[k], tangent)
            kappa = np.where(better, 0.0, kappa)
            source = np.where(better, np.where(capped, 3, end), source)
        v = q - centre
        return {"u": u, "k": pairs, "centre": centre, "radius": radius, "v": v,
                "r": np.hypot(v[:, 0], v[:, 1]), "source": source, "t": tangent, "kappa": kappa}

    def envelope(self, u: FloatArray, k: NDArray[np.intp], side: FloatArray) -> FloatArray:
        """Boundary points ``c + R e`` of tube ``k`` at ``u`` on ``side`` (+1 left, −1 right), where ``e`` makes the
        disk family stationary: ``e · t = −R'/|c'|``."""
        value, d1, _ = self.evaluate(u, k)
        speed = np.hypot(d1[:, 0], d1[:, 1])
        t = d1[:, :2] / speed[:, None]
        n = np.column_stack((-t[:, 1], t[:, 0]))
        q = np.clip(d1[:, 2] / speed, -0.99, 0.99)
        e = -q[:, None] * t + (side * np.sqrt(1.0 - q**2))[:, None] * n
        return value[:, :2] + value[:, 2:3] * e


def outlets(ends: Sequence[ArrayLike], end_radii: Sequence[float], starts: Sequence[ArrayLike]) -> list[bool]:
    """Per centreline (its last point ``ends[k]`` and end radius), whether its end is an outlet — its tube goes on
    straight past it — rather than a bifurcation: a trunk ends in a bifurcation when a branch (first points
    ``starts``, one per centreline but the first, the main one) starts within :data:`BIFURCATION_REACH` end radii
    of its last point. The lumen then goes on in the branches, not straight on: the tube ends in its last disk or
    ball. Any dimension."""
    first = [np.asarray(p, dtype=float) for p in starts]
    out = []
    for k, (end, radius) in enumerate(zip(ends, end_radii, strict=True)):
        gap = np.array([np.linalg.norm(p - np.asarray(end, dtype=float)) for p in first])
        gap[k - 1:k] = np.inf  # (a branch's own start is not a branch of its end)
        out.append(not bool(np.any(gap <= BIFURCATION_REACH * float(radius))))
    return out


def menger(a: FloatArray, b: FloatArray, c: FloatArray) -> FloatArray:
    """Signed curvature of the circle through ``a, b, c`` (> 0 turning left), elementwise."""
    ab, bc, ac = b - a, c - b, c - a
    cross = ab[:, 0] * bc[:, 1] - ab[:, 1] * bc[:, 0]
    return 2.0 * cross / (np.hypot(*ab.T) * np.hypot(*bc.T) * np.hypot(*ac.T))


def sample_spacing(points: FloatArray, radius: FloatArray) -> float:
    """Sampling spacing (mm) for a curve: ≤ SAMPLE_SPACING, a quarter of the least radius and of the least turn
    radius of the polyline (estimated from its turning angles)."""
    seg = np.diff(points, axis=0)
    length = np.hypot(*seg.T)
    spacing = SAMPLE_SPACING
    if radius.size and radius.max() > 0.0:
        spacing = min(spacing, 0.25 * float(radius[radius > 0].min()))
    if len(points) > 2:
        turn = np.abs(np.angle(np.exp(1j * np.diff(np.arctan2(seg[:, 1], seg[:, 0])))))
        bend = np.minimum(length[:-1], length[1:]) / np.maximum(turn, 1e-12)
        spacing = min(spacing, 0.25 * float(bend.min()))
    return max(spacing, 1e-3)


