"""A vessel lumen as a smooth 2-D region: a centreline with a radius (and branches), or the space between two walls.

Units mm and rad throughout. Two ways to give a lumen:

- :meth:`Vessel.from_centreline`: a centreline polyline (entrance first) with a radius (one number, or one per
  point), and optionally branches, each its own centreline and radius starting inside the parent's lumen. The
  centreline is interpolated by a C² cubic spline in chord length (~ arc length) and the radius by a monotone cubic
  (PCHIP, no overshoot) in the same parameter ``u``. A tube is the union of the disks of radius ``R(u)`` centred on
  ``c(u)``; its signed distance is ``max_u R(u) − |p − c(u)|`` (exact for a constant radius), whose gradient is
  exactly ``−(p − c(u*))/|p − c(u*)|``, so the distance is C¹ in the point away from the medial axis. The entrance is
  closed by the first disk (a rounded cap); the far end is open: the tube continues straight along its last tangent
  with its last radius for :data:`TAIL_REACH` (50 mm, or 4 end radii if longer) before a rounded cap, so a tip pushed
  past the end is not blocked. The lumen of a tree is the union of its tubes
  (the largest signed distance).
- :meth:`Vessel.from_walls`: the lumen between two wall polylines, each interpolated the same way and continued
  straight beyond both of its ends; the signed distance is the distance to the nearer wall, positive on the lumen
  side. The entrance is the midpoint of the walls' first points.

:meth:`Vessel.clearance` answers, for many points at once, the signed distance, the outward normal, the nearest
boundary point and the boundary's curvature there (see :class:`Clearance`). The closest centreline parameter is found
by a k-d tree on a fine sampling cached at construction and polished by Newton steps on the spline, all vectorised.
A branch is searched only for the points a cheap bound says it could be nearer than the main tube for
(:meth:`_TubeGeometry.best`: the same answer as searching every tube), and a vessel keeps its last few answers
(:class:`_Memo`, exact: keyed by the points' coordinates; a vessel never changes).

Only 2-D is built; the data model (tuples of coordinates) admits any dimension so that 3-D can follow.
"""

from __future__ import annotations

import math
import numbers
import threading
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline, PchipInterpolator
from scipy.spatial import cKDTree

from .fields import fmt as _fmt
from .fields import fmt_point as _fmt_point

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


# ----------------------------------------------------------------------------------------------------------------
# validation of the data
def _polyline(value: Any, name: str, *, min_points: int = 2) -> Polyline:
    """``value`` as a tuple of points (tuples of finite floats, all of one dimension); 2-D only is built."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence | np.ndarray):
        raise TypeError(f"{name} is {value!r}; expected a list of points [[x, y], ...] in mm.")
    points = []
    for i, item in enumerate(value):
        if isinstance(item, str | bytes) or not isinstance(item, Sequence | np.ndarray):
            raise TypeError(f"{name}[{i}] is {item!r}; expected a point [x, y] in mm.")
        coords = []
        for j, x in enumerate(item):
            if isinstance(x, bool | np.bool_) or not isinstance(x, numbers.Real):
                raise TypeError(f"{name}[{i}][{j}] is {x!r}; expected a real number (mm).")
            if not math.isfinite(float(x)):
                raise ValueError(f"{name}[{i}][{j}] is {float(x)}; expected a finite number (mm).")
            coords.append(float(x))
        points.append(tuple(coords))
    if len(points) < min_points:
        raise ValueError(f"{name} has {len(points)} point(s); give at least {min_points} points [[x, y], ...] (mm), "
                         "entrance first.")
    dims = {len(p) for p in points}
    if len(dims) > 1:
        raise ValueError(f"{name} mixes points of {sorted(dims)} coordinates; give every point as [x, y] (mm).")
    dim = dims.pop()
    if dim != 2:
        raise ValueError(f"{name} has points of {dim} coordinate(s); only 2-D vessels are built so far: give [x, y] "
                         "(mm), e.g. project a 3-D centreline onto its plane.")
    for i in range(1, len(points)):
        if points[i] == points[i - 1]:
            raise ValueError(f"{name}[{i}] repeats {name}[{i - 1}] {_fmt_point(points[i])}; remove the duplicate "
                             "point (the centreline needs distinct consecutive points).")
    return tuple(points)


def _radius(value: Any, count: int, name: str) -> float | tuple[float, ...]:
    """One positive radius (mm) or one per point."""
    if isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_):
        values: list[Any] = [value]
    elif isinstance(value, Sequence | np.ndarray) and not isinstance(value, str | bytes):
        values = list(value)
        if len(values) != count:
            raise ValueError(f"{name} has {len(values)} values for {count} centreline points; give one radius (mm) "
                             "or one per centreline point.")
    else:
        raise TypeError(f"{name} is {value!r}; expected a radius in mm or a list of one per centreline point.")
    out = []
    for i, r in enumerate(values):
        label = name if len(values) == 1 and not isinstance(value, Sequence | np.ndarray) else f"{name}[{i}]"
        if isinstance(r, bool | np.bool_) or not isinstance(r, numbers.Real):
            raise TypeError(f"{label} is {r!r}; expected a real number (mm).")
        r = float(r)
        if not math.isfinite(r) or r <= 0.0:
            raise ValueError(f"{label} is {_fmt(r)}; the lumen radius must be a positive number of mm (a radius, "
                             "not a diameter).")
        out.append(r)
    return out[0] if not isinstance(value, Sequence | np.ndarray) else tuple(out)


def _segments_cross(a0: FloatArray, a1: FloatArray, b0: FloatArray, b1: FloatArray) -> NDArray[np.bool_]:
    """Whether segments ``a0a1`` and ``b0b1`` (broadcast) properly intersect or touch."""

    def orient(p: FloatArray, q: FloatArray, r: FloatArray) -> FloatArray:
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])

    d1, d2 = orient(b0, b1, a0), orient(b0, b1, a1)
    d3, d4 = orient(a0, a1, b0), orient(a0, a1, b1)
    return (d1 * d2 <= 0.0) & (d3 * d4 <= 0.0) & ~((d1 == 0) & (d2 == 0) & (d3 == 0) & (d4 == 0))


def _self_crossing(points: FloatArray) -> tuple[int, int] | None:
    """The first pair of non-adjacent segments of a polyline that cross, or None."""
    a0, a1 = points[:-1, None, :], points[1:, None, :]
    b0, b1 = points[None, :-1, :], points[None, 1:, :]
    cross = _segments_cross(a0, a1, b0, b1)
    n = len(points) - 1
    i, j = np.triu_indices(n, k=2)
    hits = np.flatnonzero(cross[i, j])
    return None if hits.size == 0 else (int(i[hits[0]]), int(j[hits[0]]))


@dataclass(frozen=True)
class Branch:
    """A side branch: its own centreline (starting inside the parent's lumen, leading away) and radius.

    Parameters
    ----------
    centreline : sequence of [x, y]
        Points in mm, the junction first.
    radius : float or sequence of float
        Lumen radius in mm, one number or one per centreline point.
    """

    centreline: Polyline
    radius: float | tuple[float, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "centreline", _polyline(self.centreline, "vessel.branch.centreline"))
        object.__setattr__(self, "radius", _radius(self.radius, len(self.centreline), "vessel.branch.radius"))


# ----------------------------------------------------------------------------------------------------------------
# smooth curves
class _Curve:
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
        self._s_of_u = CubicSpline(self.u, self.s)

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

    def s_of_u(self, u: FloatArray) -> FloatArray:
        return np.asarray(self._s_of_u(np.clip(u, self.lo, self.hi)), dtype=float)


class _Tubes:
    """The closest-point machinery shared by tubes (``R > 0``, union of disks) and walls (``R ≡ 0``), vectorised over
    points and curves.

    For every curve it finds ``u* = argmax_u R(u) − |p − c(u)|`` (the nearest sample of a k-d tree, then Newton
    steps) and compares it with the straight continuations of the curve past its open ends.
    """

    def __init__(self, curves: Sequence[_Curve], *, head_open: Sequence[bool], tail_open: Sequence[bool],
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
        u = np.empty(len(q))
        for i, tree in enumerate(self.trees):
            mine = k == i
            if mine.all():
                u = self.curves[i].u[tree.query(q)[1]] + self.offsets[i]
            elif mine.any():
                u[mine] = self.curves[i].u[tree.query(q[mine])[1]] + self.offsets[i]
        pairs = k
        if len(k) and np.all(k == k[0]):
            k = int(k[0])  # one curve: its data as scalars, broadcast (the same arithmetic, fewer gathers)
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


def _menger(a: FloatArray, b: FloatArray, c: FloatArray) -> FloatArray:
    """Signed curvature of the circle through ``a, b, c`` (> 0 turning left), elementwise."""
    ab, bc, ac = b - a, c - b, c - a
    cross = ab[:, 0] * bc[:, 1] - ab[:, 1] * bc[:, 0]
    return 2.0 * cross / (np.hypot(*ab.T) * np.hypot(*bc.T) * np.hypot(*ac.T))


def _spacing(points: FloatArray, radius: FloatArray) -> float:
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


# ----------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Vessel:
    """A vessel lumen (mm): a centreline with a radius and branches, or the space between two walls.

    Build it with :meth:`from_centreline` or :meth:`from_walls`; the fields are the data as given (tuples, so a
    vessel is a hashable, comparable, picklable value). Exactly one of ``centreline`` and ``walls`` is set.

    Parameters
    ----------
    centreline : tuple of points
        Main centreline points (mm), entrance first; empty for a two-wall vessel.
    radius : float or tuple of float
        Main lumen radius (mm): one number, or one per centreline point; ignored (0) for a two-wall vessel.
    branches : tuple of Branch
        Side branches of the main tube, each starting inside its lumen.
    walls : tuple of two polylines
        The two wall polylines (mm) of a two-wall vessel, both listed from the entrance; empty otherwise.
    """

    centreline: Polyline = ()
    radius: float | tuple[float, ...] = 0.0
    branches: tuple[Branch, ...] = ()
    walls: tuple[Polyline, ...] = ()
    _geometry: Any = field(default=None, init=False, repr=False, compare=False)

    # ------------------------------------------------------------------------------------------------------------
    @classmethod
    def from_centreline(cls, centreline: ArrayLike, radius: float | ArrayLike,
                        branches: Sequence[Branch | tuple[ArrayLike, float | ArrayLike]] = ()) -> Vessel:
        """A tube (and branches) around a centreline.

        Parameters
        ----------
        centreline : array_like, shape (n, 2)
            Points in mm, entrance first, n ≥ 2, no repeated consecutive points.
        radius : float or array_like, shape (n,)
            Lumen radius in mm (> 0): one number, or one per centreline point (interpolated monotonically).
        branches : sequence of Branch or (centreline, radius)
            Side branches, each with its first point inside the main lumen.

        Raises
        ------
        TypeError, ValueError
            A bad field, named (``vessel.centreline``, ``vessel.radius``, ``vessel.branch[1].radius`` ...).
        """
        items = []
        for i, b in enumerate(branches):
            if isinstance(b, Branch):
                items.append(b)
                continue
            if isinstance(b, str | bytes) or not isinstance(b, Sequence) or len(b) != 2:
                raise TypeError(f"vessel.branch[{i}] is {b!r}; expected a Branch or a pair (centreline, radius).")
            items.append(_named(lambda b=b: Branch(_as_tuple(b[0]), _as_tuple(b[1])), "vessel.branch",
                                f"vessel.branch[{i}]"))
        return cls(centreline=_as_tuple(centreline), radius=_as_tuple(radius), branches=tuple(items))

    @classmethod
    def from_walls(cls, wall_a: ArrayLike, wall_b: ArrayLike) -> Vessel:
        """The lumen between two wall polylines (mm), both listed from the entrance; the entrance is the midpoint of
        their first points.

        Raises
        ------
        TypeError, ValueError
            Fewer than two points, repeated points, a self-intersecting wall, or walls that cross each other (the
            message names ``vessel.walls[0]`` or ``vessel.walls[1]``).
        """
        return cls(walls=(_as_tuple(wall_a), _as_tuple(wall_b)))

    # ------------------------------------------------------------------------------------------------------------
    def __post_init__(self) -> None:
        if self.walls:
            if self.centreline or self.branches:
                raise ValueError("vessel has both walls and a centreline; give either `walls` (two polylines) or "
                                 "`centreline` with `radius` (and branches), not both.")
            if isinstance(self.walls, str | bytes) or not isinstance(self.walls, Sequence) or len(self.walls) != 2:
                raise ValueError("vessel.walls must be exactly two polylines [[[x, y], ...], [[x, y], ...]] (mm).")
            walls = tuple(_polyline(w, f"vessel.walls[{i}]") for i, w in enumerate(self.walls))
            object.__setattr__(self, "walls", walls)
            object.__setattr__(self, "radius", 0.0)
            object.__setattr__(self, "_geometry", _WallGeometry(walls))
            return
        if isinstance(self.centreline, Sequence) and len(self.centreline) == 0:
            raise ValueError("vessel has no centreline and no walls; give `centreline = [[x, y], ...]` with `radius`, "
                             "or `walls` (two polylines).")
        centreline = _polyline(self.centreline, "vessel.centreline")
        radius = _radius(self.radius, len(centreline), "vessel.radius")
        branches = []
        for i, b in enumerate(self.branches):
            if not isinstance(b, Branch):
                raise TypeError(f"vessel.branch[{i}] is {type(b).__name__}; expected guidewire.vessel.Branch.")
            branches.append(b)
        object.__setattr__(self, "centreline", centreline)
        object.__setattr__(self, "radius", radius)
        object.__setattr__(self, "branches", tuple(branches))
        object.__setattr__(self, "_geometry", _TubeGeometry(centreline, radius, tuple(branches)))

    def __getstate__(self) -> dict[str, Any]:
        return {"centreline": self.centreline, "radius": self.radius, "branches": self.branches, "walls": self.walls}

    def __setstate__(self, state: dict[str, Any]) -> None:
        for key, value in state.items():
            object.__setattr__(self, key, value)
        object.__setattr__(self, "_geometry", None)
        self.__post_init__()

    # ------------------------------------------------------------------------------------------------------------
    @property
    def kind(self) -> str:
        """``"centreline"`` or ``"walls"``."""
        return "walls" if self.walls else "centreline"

    @property
    def entrance_point(self) -> tuple[float, float]:
        """The entrance (mm): the centreline's first point, or the midpoint of the walls' first points."""
        return self._geometry.entrance[0]

    @property
    def entrance_angle(self) -> float:
        """Tangent angle (rad) of the centreline at the entrance, pointing into the vessel."""
        return self._geometry.entrance[1]

    @property
    def length(self) -> float:
        """Arc length (mm) of the main centreline (of the walls' midline for a two-wall vessel)."""
        return self._geometry.main.length

    def clearance(self, points: ArrayLike) -> Clearance:
        """Signed distance (mm), outward normal, nearest boundary point and boundary curvature (1/mm) for points.

        Parameters
        ----------
        points : array_like, shape (m, 2) or (2,)
            Query points in mm.

        Returns
        -------
        Clearance
            Arrays of length m (see :class:`Clearance`); ``distance > 0`` inside the lumen. Read-only: the last
            :data:`MEMO_SIZE` answers are kept (keyed by the exact coordinates; the vessel never changes), so the same
            points asked again — a solve asks at its start, at its answer and when checking that answer, an insertion
            step at the same base every step — are answered without work.
        """
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        return self._geometry.answers.get(p, self._geometry.clearance)

    def past_end(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether each point lies beyond a tube's far end (in the straight continuation that lets a tip leave the
        vessel), shape (m,). Always False for the lumen between two walls (open at both ends)."""
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        return self._geometry.past_end(p)

    def path(self, s: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Points (m, 2) in mm and tangent angles (m,) in rad of the main centreline at arc lengths ``s`` (mm) from
        the entrance; beyond either end the centreline continues straight along its end tangent."""
        return self._geometry.path(np.atleast_1d(np.asarray(s, dtype=float)))

    def radius_at(self, s: ArrayLike) -> FloatArray:
        """Lumen radius (mm) of the main tube at arc lengths ``s`` (mm); the end values beyond the ends. For a
        two-wall vessel, half the distance between the walls along the midline."""
        main = self._geometry.main
        u = main.u_of_s(np.atleast_1d(np.asarray(s, dtype=float)))
        return main.evaluate(u)[0][:, 2]

    def centrelines(self) -> list[FloatArray]:
        """Fine samplings (k, 2) in mm of the main centreline (the walls' midline) and of every branch."""
        return [c.samples.copy() for c in self._geometry.centre_curves]

    def wall_lines(self) -> list[FloatArray]:
        """Fine samplings (k, 2) in mm of every wall line: both sides of each tube, or the two walls."""
        return self._geometry.wall_lines()

    # ------------------------------------------------------------------------------------------------------------
    def mapped(self, transform: Any) -> Vessel:
        """The vessel with every point mapped by ``transform`` ((k, 2) array → (k, 2) array, mm)."""

        def move(line: Polyline) -> Polyline:
            return tuple(tuple(float(x) for x in p) for p in transform(np.asarray(line, dtype=float)))

        if self.walls:
            return Vessel(walls=tuple(move(w) for w in self.walls))
        return Vessel(centreline=move(self.centreline), radius=self.radius,
                      branches=tuple(Branch(move(b.centreline), b.radius) for b in self.branches))

    def mirrored(self) -> Vessel:
        """The vessel reflected in the x-axis (``y → −y``)."""
        return self.mapped(lambda p: p * np.array([1.0, -1.0]))

    def rotated(self, angle: float, center: tuple[float, float] = (0.0, 0.0)) -> Vessel:
        """The vessel turned counter-clockwise by ``angle`` (rad) about ``center`` (mm)."""
        c, s = math.cos(angle), math.sin(angle)
        rot = np.array([[c, -s], [s, c]])
        centre = np.asarray(center, dtype=float)
        return self.mapped(lambda p: (p - centre) @ rot.T + centre)


def _as_tuple(value: Any) -> Any:
    """Arrays and nested lists as nested tuples (so a vessel is hashable); scalars unchanged."""
    if isinstance(value, np.ndarray):
        return _as_tuple(value.tolist())
    if isinstance(value, list | tuple):
        return tuple(_as_tuple(v) for v in value)
    return value


def _named(build: Any, old: str, new: str) -> Any:
    """Call ``build``; rename ``old`` to ``new`` in the message of a TypeError/ValueError it raises."""
    try:
        return build()
    except (TypeError, ValueError) as exc:
        raise type(exc)(str(exc).replace(old, new)) from None


# ----------------------------------------------------------------------------------------------------------------
MEMO_SIZE = 4
"""Answers of :meth:`Vessel.clearance` a vessel keeps (see :class:`_Memo`)."""


class _Memo:
    """The last :data:`MEMO_SIZE` answers (least recently used dropped first) of :meth:`Vessel.clearance`, keyed by
    the points' exact bytes (and shape). It belongs to one vessel's geometry, which never changes, so an answer can
    never be stale; the answer's arrays are made read-only, since every caller shares them. Thread-safe.

    Every point's answer depends on that point alone (the closest-point search is elementwise), so points that begin
    with a kept query's points — an insertion step starts from the previous answer with bars added at the tip — reuse
    its answer for those rows and compute only the rest."""

    def __init__(self) -> None:
        self._answers: dict[tuple[tuple[int, ...], bytes], tuple[FloatArray, Clearance]] = {}
        self._lock = threading.Lock()

    def get(self, points: FloatArray, compute: Any) -> Clearance:
        key = (points.shape, points.tobytes())
        with self._lock:
            hit = self._answers.pop(key, None)
            if hit is not None:
                self._answers[key] = hit  # now the most recently used
                return hit[1]
            prefix = max(((p, c) for p, c in self._answers.values()
                          if 0 < len(p) < len(points) and np.array_equal(p, points[:len(p)])),
                         key=lambda pc: len(pc[0]), default=None)
        if prefix is None:
            out = compute(points)
        else:
            known, rest = prefix[1], compute(points[len(prefix[0]):])
            out = Clearance(**{name: np.concatenate((getattr(known, name), getattr(rest, name)))
                               for name in ("distance", "normal", "boundary", "curvature")})
        for value in (out.distance, out.normal, out.boundary, out.curvature):
            value.flags.writeable = False
        kept = points.copy()
        kept.flags.writeable = False
        with self._lock:
            while len(self._answers) >= MEMO_SIZE:
                del self._answers[next(iter(self._answers))]
            self._answers[key] = (kept, out)
        return out


class _TubeGeometry:
    """The built geometry of a centreline vessel: the main tube and branches as one :class:`_Tubes`."""

    def __init__(self, centreline: Polyline, radius: float | tuple[float, ...], branches: tuple[Branch, ...]):
        lines = [(np.asarray(centreline, dtype=float), np.broadcast_to(radius, (len(centreline),)).astype(float),
                  "vessel")]
        lines += [(np.asarray(b.centreline, dtype=float), np.broadcast_to(b.radius, (len(b.centreline),)).astype(float),
                   f"vessel.branch[{i}]") for i, b in enumerate(branches)]
        curves = []
        for points, rad, name in lines:
            curve = _Curve(points, rad, spacing=_spacing(points, rad))
            _check_bend(curve, points, name)
            curves.append(curve)
        self.main = curves[0]
        self.centre_curves = curves
        self.answers = _Memo()
        self.entrance = _entrance(self.main)
        # the entrance is capped (the first disk); branch junctions too (they lie inside the parent); far ends open
        reach = [max(TAIL_REACH, TAIL_REACH_RADII * float(c.radius[-1])) for c in curves]
        self.tubes = _Tubes(curves, head_open=[False] * len(curves), tail_open=[True] * len(curves), reach=reach)
        self.varying = np.array([np.ptp(rad) > 0.0 for _, rad, _ in lines])
        if len(curves) > 1:
            main_only = _Tubes(curves[:1], head_open=[False], tail_open=[True])
            start = np.array([c.samples[0] for c in curves[1:]])
            best = main_only.closest(start)
            inside = best["radius"] - best["r"]
            for i, d in enumerate(inside):
                if d <= 0.0:
                    raise ValueError(
                        f"vessel.branch[{i}].centreline starts at {_fmt_point(start[i])}, {-d:.3g} mm outside the "
                        "main lumen; start each branch inside its parent (e.g. on the parent's centreline)."
                    )

    def best(self, p: FloatArray) -> tuple[dict[str, FloatArray], NDArray[np.intp]]:
        """The closest-point answers of :meth:`_Tubes.closest_pairs` and, per point, the index into them of the tube
        with the largest signed distance (the first such tube on a tie, as ``argmax`` over all tubes).

        The main tube is searched for every point; another tube only where :meth:`_Tubes.upper_bound` says it could
        beat the main one (a point in the aorta far from a branch never searches the branch): the same answer as
        searching every tube, at a fraction of the cost."""
        tubes = self.tubes
        m, t = len(p), len(tubes.curves)
        main = tubes.closest_pairs(p, np.zeros(m, dtype=np.intp))
        if t == 1:
            return main, np.arange(m)
        depth = main["radius"] - main["r"]
        bound = tubes.upper_bound(p)[:, 1:]
        ii, kk = np.nonzero(bound.T >= depth[None, :] - 1e-9 * np.maximum(1.0, tubes.rmax[1:, None]))
        if ii.size == 0:
            return main, np.arange(m)
        # ii: tube − 1 (k-major, as closest()); kk: point
        other = tubes.closest_pairs(p[kk], ii + 1)
        both = {name: np.concatenate((main[name], other[name])) for name in main}
        value = np.full((t, m), -np.inf)
        value[0] = depth
        value[ii + 1, kk] = other["radius"] - other["r"]
        where = np.zeros((t, m), dtype=np.intp)
        where[0] = np.arange(m)
        where[ii + 1, kk] = m + np.arange(ii.size)
        return both, where[np.argmax(value, axis=0), np.arange(m)]

    def past_end(self, p: FloatArray) -> NDArray[np.bool_]:
        tubes = self.tubes
        # only a point beyond some tube's far end plane can be in its straight continuation, and a point inside the
        # lumen (lower_bound ≥ 0, where the closest-point search is exact) only where that continuation's signed
        # distance can reach the largest one; a point outside is searched whenever it is beyond a plane
        out = np.zeros(len(p), dtype=bool)
        lam = np.einsum("mkj,kj->mk", p[:, None, :] - tubes.tail_point[None], tubes.tail_tangent)
        beyond = lam > 0.0
        if not beyond.any():
            return out
        foot = tubes.tail_point + np.minimum(lam, tubes.reach)[:, :, None] * tubes.tail_tangent
        reach = tubes.tail_radius - np.hypot(*(p[:, None, :] - foot).transpose(2, 0, 1))
        lower = tubes.lower_bound(p)
        floor = np.where(lower >= 0.0, lower - 1e-9 * max(1.0, float(tubes.rmax.max())), -np.inf)
        candidates = np.flatnonzero((beyond & (reach >= floor[:, None])).any(axis=1))
        if candidates.size:
            best, flat = self.best(p[candidates])
            out[candidates] = np.isin(best["source"][flat], (2, 3))
        return out

    def clearance(self, p: FloatArray) -> Clearance:
        tubes = self.tubes
        best, flat = self.best(p)
        u, k, source = best["u"][flat], best["k"][flat], best["source"][flat]
        v, r, radius, centre = best["v"][flat], best["r"][flat], best["radius"][flat], best["centre"][flat]
        tangent, kappa = best["t"][flat], best["kappa"][flat]
        left = np.column_stack((-tangent[:, 1], tangent[:, 0]))
        on_axis = r <= 1e-12 * np.maximum(radius, 1.0)
        e = np.where(on_axis[:, None], left, v / np.where(on_axis, 1.0, r)[:, None])
        boundary = centre + radius[:, None] * e
        side = np.where(e[:, 0] * left[:, 0] + e[:, 1] * left[:, 1] >= 0.0, 1.0, -1.0)
        # boundary curvature: the offset curve's κ/(1 − side·R·κ) where the radius is constant (exact); where it
        # varies, the circle through three points of the disks' envelope around u*
        curvature = side * kappa / (1.0 - side * radius * kappa)
        varying = self.varying[k] & (source == 0)
        if varying.any():
            i = np.flatnonzero(varying)
            kv, h = k[i], tubes.h[k[i]]
            mid = np.clip(u[i], tubes.lo[kv] + h, tubes.hi[kv] - h)
            n = len(i)
            b = tubes.envelope(np.concatenate((mid - h, mid, mid + h)), np.tile(kv, 3), np.tile(side[i], 3))
            curvature[i] = side[i] * _menger(b[:n], b[n:2 * n], b[2 * n:])
        cap = (source == 0) & (u <= tubes.lo[k]) & (e[:, 0] * tangent[:, 0] + e[:, 1] * tangent[:, 1] < 0.0)
        cap |= source == 3
        curvature = np.where(cap, -1.0 / radius, curvature)
        return Clearance(distance=radius - r, normal=e, boundary=boundary, curvature=curvature)

    def path(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        return _path(self.main, s)

    def wall_lines(self) -> list[FloatArray]:
        out = []
        for k, c in enumerate(self.tubes.curves):
            kk = np.full(len(c.u), k)
            u = c.u + self.tubes.offsets[k]
            out += [self.tubes.envelope(u, kk, np.full(len(u), side)) for side in (1.0, -1.0)]
        return out


def _path(curve: _Curve, s: FloatArray) -> tuple[FloatArray, FloatArray]:
    value, d1, _ = curve.evaluate(curve.u_of_s(s))
    points, angle = value[:, :2].copy(), np.arctan2(d1[:, 1], d1[:, 0])
    before, after = s < 0.0, s > curve.length
    for mask, extra in ((before, s), (after, s - curve.length)):
        if mask.any():
            points[mask] += extra[mask, None] * np.column_stack((np.cos(angle[mask]), np.sin(angle[mask])))
    return points, angle


def _entrance(curve: _Curve) -> tuple[tuple[float, float], float]:
    """The entrance point (mm) and tangent angle (rad) of a main centreline (built once: a vessel never changes)."""
    p, a = _path(curve, np.zeros(1))
    return (float(p[0, 0]), float(p[0, 1])), float(a[0])


def _check_bend(curve: _Curve, points: FloatArray, name: str) -> None:
    """Refuse a tube that overlaps itself: a bend tighter than the radius, or two stretches closer than their radii."""
    bend = np.abs(curve.kappa) * curve.radius
    worst = int(np.argmax(bend))
    if bend[worst] >= BEND_LIMIT:
        i = int(np.argmin(np.hypot(*(points - curve.samples[worst]).T)))
        raise ValueError(
            f"{name}.centreline bends tighter than the lumen radius near point {i} {_fmt_point(points[i])}: bend "
            f"radius {1.0 / abs(curve.kappa[worst]):.3g} mm < radius {curve.radius[worst]:.3g} mm, so the tube "
            "overlaps itself; smooth the bend (more, farther-spread points) or reduce the radius there."
        )
    tree = cKDTree(curve.samples)
    pairs = tree.query_pairs(2.0 * float(curve.radius.max()), output_type="ndarray")
    if len(pairs):
        i, j = pairs[:, 0], pairs[:, 1]
        far = np.abs(curve.s[i] - curve.s[j]) > math.pi * np.maximum(curve.radius[i], curve.radius[j])
        close = np.hypot(*(curve.samples[i] - curve.samples[j]).T) < curve.radius[i] + curve.radius[j]
        bad = np.flatnonzero(far & close)
        if bad.size:
            a, b = sorted((int(i[bad[0]]), int(j[bad[0]])))
            pa = int(np.argmin(np.hypot(*(points - curve.samples[a]).T)))
            pb = int(np.argmin(np.hypot(*(points - curve.samples[b]).T)))
            raise ValueError(
                f"{name}.centreline comes back within the lumen radius of itself: near point {pa} "
                f"{_fmt_point(points[pa])} and point {pb} {_fmt_point(points[pb])} the tube overlaps itself; move "
                "those stretches apart or reduce the radius."
            )


class _WallGeometry:
    """The built geometry of a two-wall vessel: each wall a spline continued straight past both ends."""

    def __init__(self, walls: tuple[Polyline, Polyline]):
        arrays = [np.asarray(w, dtype=float) for w in walls]
        for i, a in enumerate(arrays):
            hit = _self_crossing(a)
            if hit is not None:
                raise ValueError(
                    f"vessel.walls[{i}] crosses itself: its segments {hit[0]} and {hit[1]} (points "
                    f"{hit[0]}–{hit[0] + 1} and {hit[1]}–{hit[1] + 1}) intersect; give a simple polyline."
                )
        a, b = arrays
        cross = _segments_cross(a[:-1, None], a[1:, None], b[None, :-1], b[None, 1:])
        if cross.any():
            i, j = np.argwhere(cross)[0]
            raise ValueError(f"vessel.walls[0] segment {i} crosses vessel.walls[1] segment {j}; the two walls must not "
                             "meet (the lumen lies between them).")
        width = float(np.hypot(*(a[0] - b[0])))
        curves = [_Curve(w, np.zeros(len(w)), spacing=min(_spacing(w, np.zeros(0)), 0.25 * width)) for w in arrays]
        self.tubes = _Tubes(curves, head_open=[True, True], tail_open=[True, True])
        # which side of each wall the lumen is on (+1 left): the side of the other wall's first point
        self.side = np.empty(2)
        for i, (own, other) in enumerate(((a, b), (b, a))):
            t = self.tubes.head_tangent[i]
            d = other[0] - own[0]
            self.side[i] = 1.0 if t[0] * d[1] - t[1] * d[0] > 0.0 else -1.0
        if not np.all(np.isfinite(self.side)):  # pragma: no cover - the first points differ (walls do not meet)
            raise ValueError("vessel.walls start at the same point; the entrance needs two distinct wall points.")
        # the midline: points at equal fractions of both walls' arc lengths, averaged; radius half their distance
        frac = np.linspace(0.0, 1.0, 201)
        pa, _ = _path(curves[0], frac * curves[0].length)
        pb, _ = _path(curves[1], frac * curves[1].length)
        mid = 0.5 * (pa + pb)
        keep = np.concatenate(([True], np.hypot(*np.diff(mid, axis=0).T) > 1e-9))
        half = 0.5 * np.hypot(*(pa - pb).T)
        self.main = _Curve(mid[keep], half[keep], spacing=SAMPLE_SPACING)
        self.centre_curves = [self.main]
        self.answers = _Memo()
        self.entrance = _entrance(self.main)

    def clearance(self, p: FloatArray) -> Clearance:
        tubes = self.tubes
        m = len(p)
        best = tubes.closest(p)
        k, v, r, kappa = best["k"], best["v"], best["r"], best["kappa"]
        left = np.column_stack((-best["t"][:, 1], best["t"][:, 0]))
        side = self.side[k]
        inward = side[:, None] * left  # unit normal pointing into the lumen
        sign = np.where(np.einsum("ij,ij->i", v, inward) >= 0.0, 1.0, -1.0)
        distance = (sign * r).reshape(2, m)
        pick = np.argmin(distance, axis=0)
        flat = pick * m + np.arange(m)
        return Clearance(distance=distance[pick, np.arange(m)], normal=-inward[flat], boundary=best["centre"][flat],
                         curvature=-side[flat] * kappa[flat])

    def past_end(self, p: FloatArray) -> NDArray[np.bool_]:
        return np.zeros(len(p), dtype=bool)

    def path(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        return _path(self.main, s)

    def wall_lines(self) -> list[FloatArray]:
        return [c.samples.copy() for c in self.tubes.curves]
