"""The two kinds of lumen geometry behind :class:`guidewire.vessel.Vessel` — a tree of tubes, or the space between
two walls — and the answers a vessel keeps (:class:`Memo`). Built on :mod:`guidewire.vessel.curves`.

Units mm and rad; private to :mod:`guidewire.vessel`.
"""

from __future__ import annotations

import math
import threading
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from ..fields import fmt_point as _fmt_point
from .curves import (
    BEND_LIMIT,
    CLEARANCE_FIELDS,
    SAMPLE_SPACING,
    TAIL_REACH,
    TAIL_REACH_RADII,
    Clearance,
    Curve,
    Tubes,
    menger,
    outlets,
    sample_spacing,
    segments_cross,
    self_crossing,
)

FloatArray = NDArray[np.float64]
Polyline = tuple[tuple[float, ...], ...]


# ----------------------------------------------------------------------------------------------------------------
FAR_WALL_TOLERANCE = 0.02
"""The point across the nearest disk is on the lumen's wall unless it lies deeper inside the lumen than this fraction
of its distance from the query point (then it is in another tube's opening or behind the entrance cap; a tapering
tube's disks put it at most ``R R'²/2`` inside, 1e-4 mm for ``R' = 0.01``)."""

CORNER_TOLERANCE = 1e-3
"""Two tubes' walls cross on the lumen's boundary (:func:`wall_corners`) where the crossing's clearance is within this
fraction of the largest radius of 0 (the sampled walls are chords of the true ones)."""

MEMO_SIZE = 4
"""Queries of :meth:`Vessel.clearance` and :meth:`Vessel.far_side` a vessel keeps (see :class:`Memo`)."""

Record = dict[str, NDArray[Any]]

RECORD_KEYS = ("u", "k", "source", "v", "r", "radius", "centre", "t", "kappa")
"""What a :class:`TubeGeometry` record keeps of the search, per point."""
"""The closest-point search's answer for ``m`` points, every array's first axis the point (see :meth:`Memo.get`)."""


class Memo:
    """The last :data:`MEMO_SIZE` queries (least recently used dropped first) of :meth:`Vessel.clearance` and
    :meth:`Vessel.far_side`, keyed by the points' exact bytes (and shape): for each, the closest-point search's
    :data:`Record` and the answers derived from it (the nearest wall, the far one). It belongs to one vessel's
    geometry, which never changes, so an answer can never be stale; the answers' arrays are made read-only, since
    every caller shares them. Thread-safe.

    The near and the far wall of a point come from one search, made once for both: a lumen block asks for both at
    the start nodes, then the checks ask for the near one at the answer.

    Every point's answer depends on that point alone (the closest-point search and what is derived from it are
    elementwise), so points that begin with a kept query's points — an insertion step starts from the previous answer
    with bars added at the tip, the lumen's rows from the predictor's nodes with only the new tip turned — reuse its
    record and answers for the leading rows the two share and compute only the rest."""

    def __init__(self) -> None:
        self._answers: dict[tuple[tuple[int, ...], bytes], _Entry] = {}
        self._lock = threading.Lock()

    def get(self, points: FloatArray, kind: str, search: Any, derive: Any) -> Clearance:
        """The answer of ``kind`` (``"near"`` or ``"far"``) for ``points``: ``derive(record, kind)`` of the
        ``search(points)`` record, each made only for the points no kept query gives."""
        key = (points.shape, points.tobytes())
        with self._lock:
            entry = self._answers.pop(key, None)
            if entry is not None:
                self._answers[key] = entry  # now the most recently used
                if kind in entry.answers:
                    return entry.answers[kind]
            else:
                shared, prefix = max(((_leading(e.points, points), e) for e in self._answers.values()),
                                     key=lambda pair: pair[0], default=(0, None))
        if entry is None:
            if prefix is None or shared == 0:
                entry = _Entry(points, search(points), None)
            else:
                record = {name: value[:shared] for name, value in prefix.record.items()}
                if shared < len(points):
                    rest = search(points[shared:])
                    record = {name: np.concatenate((record[name], rest[name])) for name in rest}
                entry = _Entry(points, record, (shared, prefix.answers))
        known = entry.source[1].get(kind) if entry.source is not None else None
        if known is None:
            out = derive(entry.record, kind)
        else:
            start = entry.source[0]
            parts = [{name: getattr(known, name)[:start] for name in CLEARANCE_FIELDS}]
            if start < len(points):
                new = derive({name: value[start:] for name, value in entry.record.items()}, kind)
                parts.append({name: getattr(new, name) for name in CLEARANCE_FIELDS})
            out = Clearance(**{name: np.concatenate([part[name] for part in parts]) for name in CLEARANCE_FIELDS})
        for value in (out.distance, out.normal, out.boundary, out.curvature):
            value.flags.writeable = False
        with self._lock:
            entry.answers[kind] = out
            if key not in self._answers:
                while len(self._answers) >= MEMO_SIZE:
                    del self._answers[next(iter(self._answers))]
                self._answers[key] = entry
        return out


def _leading(kept: FloatArray, points: FloatArray) -> int:
    """How many leading rows of ``points`` equal those of ``kept`` (0 for another dimension)."""
    n = min(len(kept), len(points))
    if n == 0 or kept.shape[1:] != points.shape[1:]:
        return 0
    same = np.all(kept[:n] == points[:n], axis=1)
    return n if same.all() else int(np.argmin(same))


class _Entry:
    """One query a :class:`Memo` keeps: its points, the search's record, the answers derived so far (by kind), and
    where its first rows came from (the length of the kept query it extends and that query's answers) or None."""

    def __init__(self, points: FloatArray, record: Record, source: tuple[int, dict[str, Clearance]] | None) -> None:
        self.points = points.copy()
        self.record = record
        self.answers: dict[str, Clearance] = {}
        self.source = source
        for value in (self.points, *record.values()):
            value.flags.writeable = False


class TubeGeometry:
    """The built geometry of a centreline vessel: the main tube and branches as one :class:`Tubes`."""

    def __init__(self, centreline: Polyline, radius: float | tuple[float, ...], branches: tuple[Any, ...]):
        # (branches: guidewire.vessel.Branch values)
        lines = [(np.asarray(centreline, dtype=float), np.broadcast_to(radius, (len(centreline),)).astype(float),
                  "vessel")]
        lines += [(np.asarray(b.centreline, dtype=float), np.broadcast_to(b.radius, (len(b.centreline),)).astype(float),
                   f"vessel.branch[{i}]") for i, b in enumerate(branches)]
        curves = []
        for points, rad, name in lines:
            curve = Curve(points, rad, spacing=sample_spacing(points, rad))
            check_bend(curve, points, name)
            curves.append(curve)
        self.main = curves[0]
        self.centre_curves = curves
        self.answers = Memo()
        self.entrance = curve_entrance(self.main)
        # the entrance is capped (the first disk); branch junctions too (they lie inside the parent); far ends open,
        # but a trunk's end where branches start (a bifurcation: the lumen goes on in them) is capped too
        tails = outlets([p[-1] for p, _, _ in lines], [float(r[-1]) for _, r, _ in lines],
                        [p[0] for p, _, _ in lines[1:]])
        reach = [max(TAIL_REACH, TAIL_REACH_RADII * float(c.radius[-1])) if open_ else 0.0
                 for c, open_ in zip(curves, tails, strict=True)]
        self.tubes = Tubes(curves, head_open=[False] * len(curves), tail_open=tails, reach=reach)
        self.varying = np.array([np.ptp(rad) > 0.0 for _, rad, _ in lines])
        self._corners: tuple[FloatArray, FloatArray, FloatArray] | None = None if len(curves) > 1 else (
            np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2, 2)))
        self._boundary: tuple[Any, FloatArray, FloatArray] | None = None
        if len(curves) > 1:
            main_only = Tubes(curves[:1], head_open=[False], tail_open=[True])
            start = np.array([c.samples[0] for c in curves[1:]])
            best = main_only.closest(start)
            inside = best["radius"] - best["r"]
            for i, d in enumerate(inside):
                if d <= 0.0:
                    raise ValueError(
                        f"vessel.branch[{i}].centreline starts at {_fmt_point(start[i])}, {-d:.3g} mm outside the "
                        "main lumen; start each branch inside its parent (e.g. on the parent's centreline)."
                    )

    @property
    def corners(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Where two tubes' walls meet on the lumen's boundary (the wall's corners at a branch's opening), shape
        (c, 2) in mm, and the wall's angle at each (rad, < π: the wedge of wall between the lumen's two sides);
        computed once."""
        if self._corners is None:
            points = wall_corners(self.wall_lines(), self.clearance, float(self.tubes.rmax.max()))
            angles, faces = wedge(points, self.clearance, float(self.tubes.rmax.min()))
            self._corners = (points, angles, faces)
        return self._corners

    @property
    def boundary_samples(self) -> tuple[Any, FloatArray, FloatArray]:
        """Samples of every tube's wall — its sides (:meth:`wall_lines`), its entrance cap, the straight tail past its
        far end and the cap that closes it, about every :data:`SAMPLE_SPACING` mm — that lie on the lumen's
        boundary (in no other tube's lumen: clearance within :data:`CORNER_TOLERANCE` ``×`` the largest radius of 0),
        as a k-d tree, the points (s, 2) in mm and the boundary's curvature at each (1/mm); computed once."""
        if self._boundary is None:
            tubes = self.tubes
            parts = self.wall_lines()
            for k in range(len(tubes.curves)):
                t, r = tubes.tail_tangent[k], float(tubes.tail_radius[k])
                normal = np.array([-t[1], t[0]])
                along = np.linspace(0.0, float(tubes.reach[k]), int(np.ceil(tubes.reach[k] / SAMPLE_SPACING)) + 1)
                line = tubes.tail_point[k] + along[:, None] * t
                parts += [line + r * normal, line - r * normal]
                for centre, radius, axis in ((tubes.head_point[k], float(tubes.head_radius[k]), -tubes.head_tangent[k]),
                                             (line[-1], r, t)):
                    turn = np.linspace(-0.5 * np.pi, 0.5 * np.pi, int(np.ceil(np.pi * radius / SAMPLE_SPACING)) + 1)
                    c, s_ = np.cos(turn)[:, None], np.sin(turn)[:, None]
                    parts.append(centre + radius * (c * axis + s_ * np.array([-axis[1], axis[0]])))
            points = np.concatenate(parts)
            near = self.clearance(points)
            on = near.distance <= CORNER_TOLERANCE * float(self.tubes.rmax.max())
            self._boundary = (cKDTree(points[on]), points[on], np.asarray(near.curvature[on], dtype=float))
        return self._boundary

    def boundary_nearest(self, p: FloatArray) -> Clearance:
        """The nearest sampled point of the lumen's boundary (:attr:`boundary_samples`) to each point inside: its
        distance (mm), the unit vector to it (the outward normal there, up to the sampling), the point and the
        boundary's curvature there."""
        tree, points, curvature = self.boundary_samples
        gap, i = tree.query(p)
        gap = np.asarray(gap, dtype=float)
        normal = (points[i] - p) / np.maximum(gap, np.finfo(float).tiny)[:, None]
        return Clearance(distance=gap, normal=normal, boundary=points[i].copy(), curvature=curvature[i].copy())

    def best(self, p: FloatArray) -> tuple[dict[str, FloatArray], NDArray[np.intp]]:
        """The closest-point answers of :meth:`Tubes.closest_pairs` and, per point, the index into them of the tube
        with the largest signed distance (the first such tube on a tie, as ``argmax`` over all tubes).

        The main tube is searched for every point, another tube only where :meth:`Tubes.upper_bound` says it could
        reach the largest answer (a point in the aorta far from a branch never searches the branch): the same answer
        as searching every tube, at a fraction of the cost. The main tube and the others that could reach
        :meth:`Tubes.lower_bound` of the largest distance are searched in one call; where no answer reaches that
        bound (a point far outside, where a local search can stop short of the nearest point), the other tubes that
        could reach the largest answer found are searched too."""
        tubes = self.tubes
        m, t = len(p), len(tubes.curves)
        if t == 1:
            return tubes.closest_pairs(p, np.zeros(m, dtype=np.intp)), np.arange(m)
        slack = 1e-9 * np.maximum(1.0, tubes.rmax[1:, None])
        bound = tubes.upper_bound(p)[:, 1:].T  # (tube − 1, point)
        searched = bound >= tubes.lower_bound(p) - slack
        ii, kk = np.nonzero(searched)  # ii: tube − 1 (k-major, as closest()); kk: point
        found = tubes.closest_pairs(np.concatenate((p, p[kk])), np.concatenate((np.zeros(m, dtype=np.intp), ii + 1)))
        value = np.full((t, m), -np.inf)
        value[0] = found["radius"][:m] - found["r"][:m]
        value[ii + 1, kk] = found["radius"][m:] - found["r"][m:]
        more = ~searched & (bound >= value.max(axis=0) - slack)  # (only where every answer fell short of the bound)
        if more.any():
            ie, ke = np.nonzero(more)
            extra = tubes.closest_pairs(p[ke], ie + 1)
            found = {name: np.concatenate((found[name], extra[name])) for name in found}
            value[ie + 1, ke] = extra["radius"] - extra["r"]
            ii, kk = np.concatenate((ii, ie)), np.concatenate((kk, ke))
        if ii.size == 0:
            return found, np.arange(m)
        where = np.zeros((t, m), dtype=np.intp)
        where[0] = np.arange(m)
        where[ii + 1, kk] = m + np.arange(ii.size)
        return found, where[np.argmax(value, axis=0), np.arange(m)]

    def tube_depths(self, p: FloatArray) -> FloatArray:
        """Signed distance (mm, > 0 inside) of every point to every tube's wall, shape (m, tubes): the values whose
        largest :meth:`clearance` gives."""
        tubes = self.tubes
        m, t = len(p), len(tubes.curves)
        found = tubes.closest_pairs(np.repeat(p, t, axis=0), np.tile(np.arange(t, dtype=np.intp), m))
        return (found["radius"] - found["r"]).reshape(m, t)

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

    def search(self, p: FloatArray) -> Record:
        """The closest-point search's answer for every point (:data:`Record`): :meth:`best`'s, of the tube it
        picks."""
        best, flat = self.best(p)
        return {name: best[name][flat] for name in RECORD_KEYS}

    def derive(self, record: Record, kind: str) -> Clearance:
        """The nearest wall (``kind = "near"``) or the far one (``"far"``, :meth:`far_side`) of a :meth:`search`
        record."""
        if kind == "near":
            return self._wall(record, 1.0)
        far = self._wall(record, -1.0)
        check = self.search(far.boundary)  # (only its signed distance is needed: :meth:`_wall`'s ``radius − r``)
        gone = check["radius"] - check["r"] > FAR_WALL_TOLERANCE * far.distance
        return Clearance(distance=np.where(gone, np.inf, far.distance), normal=far.normal, boundary=far.boundary,
                         curvature=far.curvature)

    def clearance(self, p: FloatArray) -> Clearance:
        return self._wall(self.search(p), 1.0)

    def far_side(self, p: FloatArray) -> Clearance:
        """The wall across the lumen from the nearest one (:meth:`Vessel.far_side`): through the centre of the
        nearest disk, on its other side; ``distance`` inf where that point is not on the lumen's boundary (an
        entrance cap, a branch's opening)."""
        return self.derive(self.search(p), "far")

    def _wall(self, record: Record, across: float) -> Clearance:
        """The nearest wall (``across = 1``) or the one across the nearest disk (``across = −1``) of the points of a
        :meth:`search` record: signed distance along the disk's radius, outward normal, wall point and its
        curvature."""
        tubes = self.tubes
        u, k, source = record["u"], record["k"], record["source"]
        v, r, radius, centre = record["v"], record["r"], record["radius"], record["centre"]
        tangent, kappa = record["t"], record["kappa"]
        left = np.column_stack((-tangent[:, 1], tangent[:, 0]))
        on_axis = r <= 1e-12 * np.maximum(radius, 1.0)
        e = across * np.where(on_axis[:, None], left, v / np.where(on_axis, 1.0, r)[:, None])
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
            curvature[i] = side[i] * menger(b[:n], b[n:2 * n], b[2 * n:])
        cap = (source == 0) & (u <= tubes.lo[k]) & (e[:, 0] * tangent[:, 0] + e[:, 1] * tangent[:, 1] < 0.0)
        cap |= source == 3
        curvature = np.where(cap, -1.0 / radius, curvature)
        return Clearance(distance=radius - across * r, normal=e, boundary=boundary, curvature=curvature)

    def path(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        return curve_path(self.main, s)

    def junction(self, branch: int) -> float:
        """Arc length (mm) along the main centreline of the point nearest to branch ``branch``'s first point."""
        curve = self.centre_curves[branch + 1]
        gap = np.hypot(*(self.main.samples - curve.samples[0]).T)
        return float(self.main.s[int(np.argmin(gap))])

    def route(self, s: FloatArray, branch: int) -> tuple[FloatArray, FloatArray]:
        """Points and tangent angles at arc lengths ``s`` along the main centreline up to branch ``branch``'s
        :meth:`junction`, and along the branch's centreline after it."""
        s_j = self.junction(branch)
        points, angles = curve_path(self.main, s)
        after = s > s_j
        if after.any():
            points[after], angles[after] = curve_path(self.centre_curves[branch + 1], s[after] - s_j)
        return points, angles

    def wall_lines(self) -> list[FloatArray]:
        out = []
        for k, c in enumerate(self.tubes.curves):
            kk = np.full(len(c.u), k)
            u = c.u + self.tubes.offsets[k]
            out += [self.tubes.envelope(u, kk, np.full(len(u), side)) for side in (1.0, -1.0)]
        return out


def wall_corners(lines: list[FloatArray], clearance: Any, scale: float) -> FloatArray:
    """Points where wall polylines of different tubes (two per tube, in order) cross on the lumen's boundary (the
    crossing point's clearance within :data:`CORNER_TOLERANCE` ``× scale`` of 0, not inside a third tube), (c, 2)."""
    found = []
    for i, a in enumerate(lines):
        for b in lines[2 * (i // 2 + 1):]:
            a0, a1, b0, b1 = a[:-1, None], a[1:, None], b[None, :-1], b[None, 1:]
            ii, jj = np.nonzero(segments_cross(a0, a1, b0, b1))
            if ii.size:
                da, db, w = a[ii + 1] - a[ii], b[jj + 1] - b[jj], b[jj] - a[ii]
                det = da[:, 0] * db[:, 1] - da[:, 1] * db[:, 0]
                t = (w[:, 0] * db[:, 1] - w[:, 1] * db[:, 0]) / np.where(det == 0.0, 1.0, det)
                found.append(a[ii] + t[:, None] * da)
    if not found:
        return np.zeros((0, 2))
    points = np.concatenate(found)
    on_wall = np.abs(clearance(points).distance) <= CORNER_TOLERANCE * scale
    return points[on_wall]


WEDGE_RAYS = 720
"""Directions sampled around a corner to measure its wedge of wall (:func:`wedge`), 0.5° apart."""

WEDGE_REACH = 1e-3
"""... at this fraction of the least tube radius from the corner."""


def wedge(points: FloatArray, clearance: Any, radius: float) -> tuple[FloatArray, FloatArray]:
    """The angle (rad) of the wedge of wall at each corner — the share of :data:`WEDGE_RAYS` directions around it
    whose point at :data:`WEDGE_REACH` ``× radius`` lies outside the lumen, times 2π — and the directions (unit
    vectors, shape (corners, 2, 2)) of its two walls from the corner: the middles between the last ray inside and the
    first outside at either edge of the wedge (to half a ray's angle)."""
    if not len(points):
        return np.zeros(0), np.zeros((0, 2, 2))
    a = 2.0 * math.pi * (np.arange(WEDGE_RAYS) + 0.5) / WEDGE_RAYS
    probe = points[:, None, :] + WEDGE_REACH * radius * np.stack((np.cos(a), np.sin(a)), axis=1)[None]
    outside = clearance(probe.reshape(-1, 2)).distance.reshape(len(points), WEDGE_RAYS) < 0.0
    step = 2.0 * math.pi / WEDGE_RAYS
    enter = np.argmax(outside & ~np.roll(outside, 1, axis=1), axis=1)  # first ray outside after one inside
    leave = np.argmax(~outside & np.roll(outside, 1, axis=1), axis=1)  # first ray inside after one outside
    faces = np.stack([np.stack((np.cos(t), np.sin(t)), axis=-1)
                      for t in (a[enter] - 0.5 * step, a[leave] - 0.5 * step)], axis=1)
    return 2.0 * math.pi * outside.mean(axis=1), faces


def curve_path(curve: Curve, s: FloatArray) -> tuple[FloatArray, FloatArray]:
    value, d1, _ = curve.evaluate(curve.u_of_s(s))
    points, angle = value[:, :2].copy(), np.arctan2(d1[:, 1], d1[:, 0])
    before, after = s < 0.0, s > curve.length
    for mask, extra in ((before, s), (after, s - curve.length)):
        if mask.any():
            points[mask] += extra[mask, None] * np.column_stack((np.cos(angle[mask]), np.sin(angle[mask])))
    return points, angle


def curve_entrance(curve: Curve) -> tuple[tuple[float, float], float]:
    """The entrance point (mm) and tangent angle (rad) of a main centreline (built once: a vessel never changes)."""
    p, a = curve_path(curve, np.zeros(1))
    return (float(p[0, 0]), float(p[0, 1])), float(a[0])


def check_bend(curve: Curve, points: FloatArray, name: str) -> None:
    """Refuse a tube that overlaps itself: a bend tighter than the radius, or two stretches closer than their radii."""
    bend = np.abs(curve.kappa) * curve.radius
    worst = int(np.argmax(bend))
    if bend[worst] >= BEND_LIMIT:
        i = _nearest_point(curve, worst)
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
            pa, pb = _nearest_point(curve, a), _nearest_point(curve, b)
            raise ValueError(
                f"{name}.centreline comes back within the lumen radius of itself: near point {pa} "
                f"{_fmt_point(points[pa])} and point {pb} {_fmt_point(points[pb])} the tube overlaps itself; move "
                "those stretches apart or reduce the radius."
            )


def _nearest_point(curve: Curve, sample: int) -> int:
    """The centreline point nearest to a curve sample *along the curve* (by the spline's parameter): where the tube
    comes back onto itself the two samples lie at one place, and the nearest point in space would name one point
    twice."""
    return int(np.argmin(np.abs(curve.breaks - curve.u[sample])))


class WallGeometry:
    """The built geometry of a two-wall vessel: each wall a spline continued straight past both ends."""

    def __init__(self, walls: tuple[Polyline, Polyline]):
        arrays = [np.asarray(w, dtype=float) for w in walls]
        for i, a in enumerate(arrays):
            hit = self_crossing(a)
            if hit is not None:
                raise ValueError(
                    f"vessel.walls[{i}] crosses itself: its segments {hit[0]} and {hit[1]} (points "
                    f"{hit[0]}–{hit[0] + 1} and {hit[1]}–{hit[1] + 1}) intersect; give a simple polyline."
                )
        a, b = arrays
        cross = segments_cross(a[:-1, None], a[1:, None], b[None, :-1], b[None, 1:])
        if cross.any():
            i, j = np.argwhere(cross)[0]
            raise ValueError(f"vessel.walls[0] segment {i} crosses vessel.walls[1] segment {j}; the two walls must not "
                             "meet (the lumen lies between them).")
        width = float(np.hypot(*(a[0] - b[0])))
        curves = [Curve(w, np.zeros(len(w)), spacing=min(sample_spacing(w, np.zeros(0)), 0.25 * width)) for w in arrays]
        self.tubes = Tubes(curves, head_open=[True, True], tail_open=[True, True])
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
        pa, _ = curve_path(curves[0], frac * curves[0].length)
        pb, _ = curve_path(curves[1], frac * curves[1].length)
        mid = 0.5 * (pa + pb)
        keep = np.concatenate(([True], np.hypot(*np.diff(mid, axis=0).T) > 1e-9))
        half = 0.5 * np.hypot(*(pa - pb).T)
        self.main = Curve(mid[keep], half[keep], spacing=SAMPLE_SPACING)
        self.centre_curves = [self.main]
        self.answers = Memo()
        self.entrance = curve_entrance(self.main)

    def search(self, p: FloatArray) -> Record:
        """The closest-point search on both walls (:meth:`Tubes.closest`) as a :data:`Record`: arrays of shape
        (m, 2, ...), the point first, then the wall."""
        best, m = self.tubes.closest(p), len(p)
        return {name: np.swapaxes(best[name].reshape((2, m) + best[name].shape[1:]), 0, 1)
                for name in ("k", "v", "r", "t", "kappa", "centre")}

    def derive(self, record: Record, kind: str) -> Clearance:
        """The nearer wall (``kind = "near"``) or the other one (``"far"``) of a :meth:`search` record."""
        return self._wall(record, 1.0 if kind == "near" else -1.0)

    def clearance(self, p: FloatArray) -> Clearance:
        return self._wall(self.search(p), 1.0)

    def _wall(self, record: Record, across: float) -> Clearance:
        """The nearer wall (``across = 1``) or the other one (``across = −1``) of the points of a :meth:`search`
        record."""
        m = len(record["k"])
        best = {name: np.swapaxes(value, 0, 1).reshape((2 * m,) + value.shape[2:]) for name, value in record.items()}
        k, v, r, kappa = best["k"], best["v"], best["r"], best["kappa"]
        left = np.column_stack((-best["t"][:, 1], best["t"][:, 0]))
        side = self.side[k]
        inward = side[:, None] * left  # unit normal pointing into the lumen
        sign = np.where(np.einsum("ij,ij->i", v, inward) >= 0.0, 1.0, -1.0)
        distance = (sign * r).reshape(2, m)
        pick = np.argmin(distance, axis=0)
        flat = pick * m + np.arange(m)
        if across < 0.0:
            pick = 1 - pick
            flat = pick * m + np.arange(m)
        return Clearance(distance=distance[pick, np.arange(m)], normal=-inward[flat], boundary=best["centre"][flat],
                         curvature=-side[flat] * kappa[flat])

    corners = (np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2, 2)))
    """A two-wall lumen has no corners."""

    def far_side(self, p: FloatArray) -> Clearance:
        """The other wall (:meth:`Vessel.far_side`)."""
        return self._wall(self.search(p), -1.0)

    def past_end(self, p: FloatArray) -> NDArray[np.bool_]:
        return np.zeros(len(p), dtype=bool)

    def path(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        return curve_path(self.main, s)

    def wall_lines(self) -> list[FloatArray]:
        return [c.samples.copy() for c in self.tubes.curves]


