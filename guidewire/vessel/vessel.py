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
  past the end is not blocked — unless a branch starts at that end (within half its end radius: a bifurcation, the
  lumen goes on in the branches), where the last disk closes it. The lumen of a tree is the union of its tubes
  (the largest signed distance).
- :meth:`Vessel.from_walls`: the lumen between two wall polylines, each interpolated the same way and continued
  straight beyond both of its ends; the signed distance is the distance to the nearer wall, positive on the lumen
  side. The entrance is the midpoint of the walls' first points.

:meth:`Vessel.clearance` answers, for many points at once, the signed distance, the outward normal, the nearest
boundary point and the boundary's curvature there (see :class:`Clearance`). The closest centreline parameter is found
by a k-d tree on a fine sampling cached at construction and polished by Newton steps on the spline, all vectorised.
A branch is searched only for the points a cheap bound says it could be nearer than the main tube for
(:meth:`TubeGeometry.best`: the same answer as searching every tube), and a vessel keeps its last few answers
(:class:`Memo`, exact: keyed by the points' coordinates; a vessel never changes).

Only 2-D is built; the data model (tuples of coordinates) admits any dimension so that 3-D can follow.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..fields import fmt as _fmt
from ..fields import fmt_point as _fmt_point
from ..fields import warn_radius
from .curves import Clearance
from .geometry import FAR_WALL_TOLERANCE, Memo, TubeGeometry, WallGeometry

FloatArray = NDArray[np.float64]
Polyline = tuple[tuple[float, ...], ...]


def _polyline(value: Any, name: str, *, min_points: int = 2) -> Polyline:
    """``value`` as a tuple of points (tuples of finite floats, all of one dimension); 2-D only is built."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence | np.ndarray):
        raise TypeError(f"{name} is {value!r}; expected a list of points [[x, y], ...] in mm.")
    points = [_point(item, f"{name}[{i}]") for i, item in enumerate(value)]
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


def _point(item: Any, label: str) -> tuple[float, ...]:
    """One point of a polyline as a tuple of finite floats."""
    if isinstance(item, str | bytes) or not isinstance(item, Sequence | np.ndarray):
        raise TypeError(f"{label} is {item!r}; expected a point [x, y] in mm.")
    coords = []
    for j, x in enumerate(item):
        if isinstance(x, bool | np.bool_) or not isinstance(x, numbers.Real):
            raise TypeError(f"{label}[{j}] is {x!r}; expected a real number (mm).")
        if not math.isfinite(float(x)):
            raise ValueError(f"{label}[{j}] is {float(x)}; expected a finite number (mm).")
        coords.append(float(x))
    return tuple(coords)


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
        warn_radius(r, label)
        out.append(r)
    return out[0] if not isinstance(value, Sequence | np.ndarray) else tuple(out)


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
            object.__setattr__(self, "_geometry", WallGeometry(walls))
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
        object.__setattr__(self, "_geometry", TubeGeometry(centreline, radius, tuple(branches)))

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
        geometry = self._geometry
        return geometry.answers.get(p, "near", geometry.search, geometry.derive)

    @property
    def corners(self) -> FloatArray:
        """The lumen wall's corners (mm), shape (c, 2): where a branch's walls meet its parent's at the opening, the
        wall turning sharply into the lumen (a chord between two inside points can cut through it,
        :mod:`guidewire.blocks.lumen`); none for a vessel without branches."""
        return self._geometry.corners[0]

    @property
    def corner_angles(self) -> FloatArray:
        """The angle (rad, 0 to π) of the wedge of wall at each of :attr:`corners`, shape (c,)."""
        return self._geometry.corners[1]

    @property
    def corner_faces(self) -> FloatArray:
        """The directions (unit vectors) of the two walls that meet at each of :attr:`corners`, from the corner along
        each wall, shape (c, 2, 2): a point inside the lumen whose offset from the corner has no positive component
        along either has the corner as its nearest wall point."""
        return self._geometry.corners[2]

    def nearest_corner(self, points: ArrayLike, near: Clearance | None = None,
                       opening: NDArray[np.bool_] | None = None) -> tuple[NDArray[np.int_], FloatArray]:
        """For each point inside: the corner (index into :attr:`corners`) that is its nearest point of the lumen's
        boundary, or −1, and its distance from that corner (mm; inf for −1).

        A point whose offset from a corner has no positive component along either wall that meets there
        (:attr:`corner_faces`) lies in the corner's cone: the nearest point of both walls, as far as they are the
        lumen's boundary, is the corner. It is the nearest boundary point unless :meth:`clearance`'s wall is nearer
        and not in an opening (:meth:`opening`) — or the point lies farther from the corner than the widest tube's
        diameter (its own tube has a nearer wall). ``near`` is :meth:`clearance` at ``points`` when the caller has it,
        ``opening`` :meth:`opening` of its wall points (``near.boundary``, ``near.distance``) when the caller has that
        too (every point's answer is its own: the caller's flags for all of them serve the few asked here).
        """
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        corners = self.corners
        index, found = np.full(p.shape[0], -1), np.full(p.shape[0], np.inf)
        if not corners.size or not p.size:
            return index, found
        near = self.clearance(p) if near is None else near
        offset = p[:, None, :] - corners[None]
        gap = np.hypot(offset[..., 0], offset[..., 1])
        # (the cone is unbounded; beyond the widest tube's diameter a point's own tube has a nearer wall)
        cone = (gap <= 2.0 * float(self._geometry.tubes.rmax.max())) & (near.distance > 0.0)[:, None]
        cone[cone] = np.all(np.einsum("mj,mfj->mf", offset[cone], self.corner_faces[np.nonzero(cone)[1]]) <= 0.0,
                            axis=1)
        distance = np.where(cone, gap, np.inf)
        best = np.argmin(distance, axis=1)
        nearest = distance[np.arange(p.shape[0]), best]
        ask = np.flatnonzero(np.isfinite(nearest) & (near.distance < nearest))  # a wall nearer, if it is there
        real = np.ones(p.shape[0], dtype=bool)
        if ask.size:
            real[ask] = ~(self.opening(near.boundary[ask], near.distance[ask]) if opening is None else opening[ask])
        held = np.isfinite(nearest) & ~((near.distance < nearest) & real)
        index[held], found[held] = best[held], nearest[held]
        return index, found

    def lumen_clearance(self, points: ArrayLike) -> FloatArray:
        """Distance (mm, > 0 inside) of each point from the lumen's boundary, its corners included: :meth:`clearance`'s,
        or the distance from the corner that is the nearest boundary point (:meth:`nearest_corner`) — where tubes
        meet, the wall of the tube a point lies deepest in runs on through the opening, and a point beside the
        opening's corner can be nearer that wall than the lumen's boundary is to it."""
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        near = self.clearance(p)
        index, gap = self.nearest_corner(p, near)
        return np.where(index >= 0, gap, near.distance)

    def far_side(self, points: ArrayLike) -> Clearance:
        """The wall across the lumen from the nearest one, for points inside (mm, unit normals, 1/mm).

        For a tube, the wall point across the disk that gives :meth:`clearance` (through its centre, on its other
        side); for a two-wall vessel, the farther wall. A node's row on its nearest wall alone lets it cross the
        lumen and pass through this one unseen (:mod:`guidewire.blocks.lumen`).

        Returns
        -------
        Clearance
            As :meth:`clearance` for that wall: ``distance`` (≥ the nearest wall's), outward ``normal``,
            ``boundary`` point and ``curvature``; ``distance`` is inf where the point across is no wall (behind the
            entrance cap, in a branch's opening).
        """
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        geometry = self._geometry
        return geometry.answers.get(p, "far", geometry.search, geometry.derive)

    def opening(self, boundary: ArrayLike, distance: ArrayLike) -> NDArray[np.bool_]:
        """Whether each wall point ``boundary`` that :meth:`clearance` gave a point inside at ``distance`` (mm) lies in
        an opening instead, shape (m,): deeper inside the lumen than
        :data:`~guidewire.vessel.geometry.FAR_WALL_TOLERANCE` ``× distance``.

        :meth:`clearance` measures a point against the tube it lies deepest in; where tubes overlap (a branch's
        opening, two branches whose openings meet), that tube's wall can run through another tube's lumen (the
        parent's wall across the opening), a wall that is not there. False where ``distance ≤ 0`` (a point outside:
        its nearest wall is the one it crossed)."""
        b = np.asarray(boundary, dtype=float).reshape(-1, 2)
        d = np.asarray(distance, dtype=float).reshape(-1)
        ask = d > 0.0
        tubes = getattr(self._geometry, "tubes", None)
        if ask.any() and tubes is not None and len(tubes.curves) > 1:
            # (a wall point lies in another tube's lumen only where two tubes' depth bounds reach it, its own —
            # depth ~0 on its wall — and that one's: elsewhere, far from every junction, nothing to search)
            slack = 1e-9 * max(1.0, float(tubes.rmax.max()))
            ask[ask] = np.count_nonzero(tubes.upper_bound(b[ask]) >= -slack, axis=1) >= 2
        out = np.zeros(d.size, dtype=bool)
        if ask.any():
            out[ask] = self.clearance(b[ask]).distance > FAR_WALL_TOLERANCE * d[ask]
        return out

    def nearest_boundary(self, points: ArrayLike) -> Clearance:
        """The nearest point of the lumen's boundary to each point inside (mm, unit normals, 1/mm): a wall point in
        no other tube's lumen, where :meth:`clearance`'s nearest wall (of the tube the point lies deepest in) may lie
        in an opening (:meth:`opening`).

        For a tree of tubes the boundary is sampled (every tube's sides at its centreline's fine sampling, entrance
        cap, straight tail and the cap that closes it, less the samples inside another tube): the point, its
        distance and the unit vector to it are the nearest sample's (the distance at most half the gap between
        neighbouring samples more than the exact one: ~:data:`~guidewire.vessel.curves.SAMPLE_SPACING` mm, more on
        the outer side of a bend), the curvature the wall's there. A two-wall vessel has no openings: its
        :meth:`clearance`.

        Returns
        -------
        Clearance
            ``distance`` (≥ 0), ``normal`` (from the point towards the boundary point), ``boundary`` and
            ``curvature``, each of length m.
        """
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        geometry = self._geometry
        if isinstance(geometry, TubeGeometry):
            return geometry.boundary_nearest(p)
        return self.clearance(p)

    def tube_depths(self, points: ArrayLike) -> FloatArray:
        """Signed distance (mm, > 0 inside) of each point to the wall of each tube (main first, then the branches),
        shape (m, 1 + branches): :meth:`clearance` is the largest of them. A two-wall vessel has one lumen: its
        :meth:`clearance`, shape (m, 1)."""
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        geometry = self._geometry
        if isinstance(geometry, TubeGeometry):
            return geometry.tube_depths(p)
        return np.asarray(self.clearance(p).distance, dtype=float)[:, None]

    def forget_queries(self) -> None:
        """Drop the kept answers of :meth:`clearance` and :meth:`far_side` (the built geometry — corners, boundary
        samples — stays): the same solve repeated then searches as its first run did, which is what a benchmark
        that repeats a cold solve should time."""
        self._geometry.answers = Memo()

    def past_end(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether each point lies beyond a tube's far end (in the straight continuation that lets a tip leave the
        vessel), shape (m,). Always False for the lumen between two walls (open at both ends)."""
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        return self._geometry.past_end(p)

    def path(self, s: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Points (m, 2) in mm and tangent angles (m,) in rad of the main centreline at arc lengths ``s`` (mm) from
        the entrance; beyond either end the centreline continues straight along its end tangent."""
        return self._geometry.path(np.atleast_1d(np.asarray(s, dtype=float)))

    def route(self, s: ArrayLike, branch: int) -> tuple[FloatArray, FloatArray]:
        """Points (m, 2) in mm and tangent angles (m,) in rad at arc lengths ``s`` (mm) along the way through branch
        ``branch`` (0-based, as in ``branches``): the main centreline up to the junction (the main centreline's point
        nearest the branch's first point), the branch's centreline after it (straight on past its end)."""
        if not 0 <= int(branch) < len(self.branches):
            raise ValueError(f"branch is {branch!r}; this vessel has {len(self.branches)} branch(es), numbered from 0.")
        return self._geometry.route(np.atleast_1d(np.asarray(s, dtype=float)), int(branch))

    def junction(self, branch: int) -> float:
        """Arc length (mm) along the main centreline where branch ``branch`` leaves it (see :meth:`route`)."""
        if not 0 <= int(branch) < len(self.branches):
            raise ValueError(f"branch is {branch!r}; this vessel has {len(self.branches)} branch(es), numbered from 0.")
        return self._geometry.junction(int(branch))

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
