"""A 3-D vessel: a main centreline with a radius and branches, each a :class:`~guidewire.vessel3d.tube.Tube`.

Units mm. Built from data (``centreline = [[x, y, z], ...]``, ``radius`` one number or one per point, branches each
with their own centreline starting inside the lumen), checked when built: a centreline with fewer than two points,
repeated consecutive points, non-finite values, a radius that is not positive, a bend tighter than the radius or a
tube that comes back within its radius of itself is refused with a ``ValueError`` naming the field and the points.

The lumen of a tree is the union of its tubes: a point's row is the best tube's (the largest ``g``,
:mod:`guidewire.vessel3d.tube`), or, beside the crease around a branch's opening where the wire's ball stands over the
opening in neither tube alone, its distance from the crease (:mod:`guidewire.vessel3d.crease`).
:meth:`Vessel3D.clearance` reports the distance to the wall in mm (> 0 inside).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from ..vessel.curves import outlets
from .crease import Crease, CreaseMinima, find_creases
from .tube import Tube

FloatArray = NDArray[np.float64]
Polyline = tuple[tuple[float, float, float], ...]

CREASE_SLOTS = 2
"""Places per crease where it may hold a wire (:meth:`Vessel3D.crease_contacts`): a wire across a branch's opening
rests on its rim at two."""

CREASE_HELD = 1.0
"""A node row's value (mm) where a crease's rows hold the node instead (:meth:`Vessel3D.lumen_rows` with
``creases="held"``): any positive number, the row is inactive."""

ROUTE_SPACING = 0.1
"""Spacing (mm) of the centreline samples along which :meth:`Vessel3D.route` measures arc length."""

BEND_LIMIT = 1.0
"""A tube whose centreline curvature times radius reaches this anywhere overlaps itself there (refused)."""


def _polyline(value: Any, name: str) -> Polyline:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} is {value!r}; expected a list of points [[x, y, z], ...] in mm.") from None
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"{name} has shape {arr.shape}; expected (m, 3) points [[x, y, z], ...] in mm (a 2-column "
                         "centreline is a planar guidewire.Vessel).")
    if len(arr) < 2:
        raise ValueError(f"{name} has {len(arr)} point(s); give at least two.")
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"{name}[{i}] is {arr[i].tolist()}; every coordinate must be finite (mm).")
    same = np.linalg.norm(np.diff(arr, axis=0), axis=1) == 0.0
    if same.any():
        i = int(np.argmax(same))
        raise ValueError(f"{name}[{i}] and [{i + 1}] are the same point {arr[i].tolist()}; remove the repeat.")
    return tuple(tuple(float(x) for x in row) for row in arr)  # type: ignore[misc]


def _radius(value: Any, count: int, name: str) -> float | tuple[float, ...]:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        out: float | tuple[float, ...] = float(arr)
    elif arr.shape == (count,):
        out = tuple(float(v) for v in arr)
    else:
        raise ValueError(f"{name} has shape {arr.shape}; give one radius (mm) or one per centreline point ({count}).")
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise ValueError(f"{name} must be finite and positive (mm); got {arr.ravel()[:4].tolist()}.")
    return out


def _fmt(p: Sequence[float]) -> str:
    return "(" + ", ".join(f"{v:.4g}" for v in p) + ")"


@dataclass(frozen=True)
class Branch3D:
    """A side branch: its centreline (first point inside the parent's lumen) and radius."""

    centreline: Polyline
    radius: float | tuple[float, ...]
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "centreline", _polyline(self.centreline, "vessel.branch.centreline"))
        object.__setattr__(self, "radius", _radius(self.radius, len(self.centreline), "vessel.branch.radius"))


@dataclass(frozen=True)
class Vessel3D:
    """A tree of tubes in 3-D (see the module docstring); build with :meth:`from_centreline`."""

    centreline: Polyline
    radius: float | tuple[float, ...]
    branches: tuple[Branch3D, ...] = ()
    name: str = ""
    _tubes: Any = field(default=None, init=False, repr=False, compare=False)
    _memo: Any = field(default=None, init=False, repr=False, compare=False)
    _creases: Any = field(default=None, init=False, repr=False, compare=False)

    @classmethod
    def from_centreline(cls, centreline: Any, radius: Any, branches: Sequence[Any] = (), name: str = "") -> Vessel3D:
        """A tube around ``centreline`` (m, 3) with ``radius`` (one or one per point) and ``branches`` (each a
        :class:`Branch3D` or a pair ``(centreline, radius)``)."""
        items = []
        for i, b in enumerate(branches):
            if isinstance(b, Branch3D):
                items.append(b)
            elif isinstance(b, Sequence) and len(b) in (2, 3):
                try:
                    items.append(Branch3D(*b))
                except (TypeError, ValueError) as error:
                    raise type(error)(str(error).replace("vessel.branch", f"vessel.branch[{i}]")) from None
            else:
                raise TypeError(f"vessel.branch[{i}] is {b!r}; expected a Branch3D or (centreline, radius).")
        return cls(centreline, radius, tuple(items), name)

    def __post_init__(self) -> None:
        line = _polyline(self.centreline, "vessel.centreline")
        object.__setattr__(self, "centreline", line)
        object.__setattr__(self, "radius", _radius(self.radius, len(line), "vessel.radius"))
        for i, b in enumerate(self.branches):
            if not isinstance(b, Branch3D):
                raise TypeError(f"vessel.branch[{i}] is {type(b).__name__}; expected Branch3D.")
        lines = [(line, self.radius)] + [(b.centreline, b.radius) for b in self.branches]
        tails = outlets([c[-1] for c, _ in lines], [r[-1] if isinstance(r, tuple) else r for _, r in lines],
                        [b.centreline[0] for b in self.branches])
        main = Tube(np.array(line), np.asarray(self.radius, dtype=float), tail=tails[0])
        _check_tube(main, "vessel.centreline")
        tubes = [main]
        for i, b in enumerate(self.branches):
            tube = Tube(np.array(b.centreline), np.asarray(b.radius, dtype=float), tail=tails[i + 1])
            _check_tube(tube, f"vessel.branch[{i}].centreline")
            start = np.array(b.centreline[:1])
            inside = max(float(t.rows(start, np.zeros(1))[0][0]) for t in tubes)
            if inside < 0.0:
                raise ValueError(f"vessel.branch[{i}] starts at {_fmt(b.centreline[0])}, outside the lumen it "
                                 "branches from; start each branch inside its parent's lumen.")
            tubes.append(tube)
        object.__setattr__(self, "_tubes", tuple(tubes))
        object.__setattr__(self, "_memo", {})
        object.__setattr__(self, "_creases", None)

    def __getstate__(self) -> dict[str, Any]:
        return {"centreline": self.centreline, "radius": self.radius, "branches": self.branches, "name": self.name}

    def __setstate__(self, state: dict[str, Any]) -> None:
        for key, value in state.items():
            object.__setattr__(self, key, value)
        self.__post_init__()

    # -- geometry ------------------------------------------------------------------------------------------------
    @property
    def tubes(self) -> tuple[Tube, ...]:
        return self._tubes

    @property
    def creases(self) -> tuple[Crease, ...]:
        """The creases around the branches' openings (:func:`guidewire.vessel3d.crease.find_creases`), found on first
        use (~0.1 s a branch)."""
        if self._creases is None:
            object.__setattr__(self, "_creases", find_creases(self._tubes))
        return self._creases

    @property
    def entrance(self) -> tuple[FloatArray, FloatArray]:
        """The entrance point and the unit tangent pointing in."""
        p, t = self._tubes[0].path(np.zeros(1))
        return p[0], t[0]

    @property
    def entrance_normal(self) -> None:
        """No preferred material ``d1`` at the entrance (the clamp picks the world axis least aligned with the
        tangent)."""
        return None

    @property
    def length(self) -> float:
        """Chord length of the main centreline (mm)."""
        return self._tubes[0].end

    def path(self, s: Any) -> tuple[FloatArray, FloatArray]:
        """Points (m, 3) and unit tangents along the main centreline at ``s`` (mm from the entrance)."""
        return self._tubes[0].path(np.atleast_1d(np.asarray(s, dtype=float)))

    def route(self, s: Any, tube: str | int) -> FloatArray:
        """Points (m, 3) at arc lengths ``s`` (mm from the entrance) along the centrelines from the entrance into
        ``tube`` (a name of :attr:`tube_names` or an index): the main centreline up to where the first tube on the
        way leaves it (its first point's nearest centreline point), that tube's up to where the next leaves, and so
        on, the last one to its end and straight on. A start for a wire that is to lie in that branch (the
        ``initial_nodes`` of :func:`guidewire.solve3d.solve3d`)."""
        names = self.tube_names
        if isinstance(tube, str):
            if tube not in names:
                raise ValueError(f"tube is {tube!r}; this vessel's tubes are {', '.join(names)}.")
            tube = names.index(tube)
        if not 0 <= int(tube) < len(self._tubes):
            raise ValueError(f"tube is {tube!r}; this vessel has tubes 0 to {len(self._tubes) - 1}.")
        chain = [int(tube)]
        while chain[-1] != 0:
            chain.append(self._parent(chain[-1]))
        chain.reverse()
        lines = self.centrelines(ROUTE_SPACING)
        pieces = []
        for here, ahead in zip(chain[:-1], chain[1:], strict=True):
            k = int(np.argmin(np.linalg.norm(lines[here] - self._tubes[ahead].points[0], axis=1)))
            pieces.append(lines[here][:k])
        last = self._tubes[chain[-1]]
        line = np.vstack((*pieces, lines[chain[-1]]))
        arc = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(line, axis=0), axis=1))))
        s = np.atleast_1d(np.asarray(s, dtype=float))
        inside = np.column_stack([np.interp(np.minimum(s, arc[-1]), arc, line[:, i]) for i in range(3)])
        return inside + np.maximum(s - arc[-1], 0.0)[:, None] * last.tail_tangent

    def _parent(self, j: int) -> int:
        """The tube that branch ``j`` leaves: of the tubes before it, the one whose lumen holds its first point
        deepest."""
        start = self._tubes[j].points[:1]
        depth = [float(self._tubes[i].rows(start, np.zeros(1))[0][0]) for i in range(j)]
        return int(np.argmax(depth))

    # -- the lumen -----------------------------------------------------------------------------------------------
    def lumen_rows(self, points: FloatArray, radii: FloatArray,
                   creases: str = "rows") -> tuple[FloatArray, FloatArray, FloatArray]:
        """Rows ``g ≥ 0`` for points (m, 3) of wire radii (m,): values, gradients (m, 3), Hessians (m, 3, 3) — the
        largest of the tubes' rows and, with ``creases="rows"``, the creases' (see the module docstring). With
        ``creases="held"`` a point in a crease's cone gets :data:`CREASE_HELD` (no derivatives): the rows of a wire
        whose contacts with the creases are rows of their own (:meth:`crease_contacts`), which bound every node's
        distance from them."""
        if creases not in ("rows", "held"):
            raise ValueError(f"creases is {creases!r}; expected 'rows' or 'held'.")
        p = np.ascontiguousarray(points, dtype=float)
        r = np.broadcast_to(np.asarray(radii, dtype=float), (len(p),))
        key = (p.tobytes(), r.tobytes(), creases)
        memo = self._memo
        if memo.get("key") != key:
            g, grad, hess, _ = self._tubes[0].rows(p, r)
            best = [g.copy(), grad.copy(), hess.copy()]
            for tube in self._tubes[1:]:
                # (a branch is evaluated only at the points it might hold better than the tubes before it: its
                # row is at most the bound of Tube.row_bound, and every row is a function of its own point alone)
                near = np.flatnonzero(tube.row_bound(p, r, best[0]) >= best[0])
                if not near.size:
                    continue
                g, grad, hess, _ = tube.rows(p[near], r[near])
                better = g > best[0][near]
                take = near[better]
                best[0][take], best[1][take], best[2][take] = g[better], grad[better], hess[better]
            for crease in self.creases:
                rows = crease.rows(p, r)
                better = rows.value > best[0][rows.index]
                take = rows.index[better]
                if creases == "held":
                    best[0][take], best[1][take], best[2][take] = CREASE_HELD, 0.0, 0.0
                else:
                    best[0][take], best[1][take], best[2][take] = (rows.value[better], rows.gradient[better],
                                                                    rows.hessian[better])
            memo.update(key=key, value=tuple(best))
        return memo["value"]

    def crease_contacts(self, nodes: FloatArray, bar_radius: FloatArray,
                        node_radius: FloatArray) -> tuple[CreaseMinima, ...]:
        """Per crease, where it comes nearest the wire ``nodes`` (n + 1, 3; the clamp first) of bar and node radii
        (n,), in its cone and reach (:meth:`guidewire.vessel3d.crease.Crease.minima`): the :data:`CREASE_SLOTS`
        nearest, in their order along the wire."""
        nodes = np.ascontiguousarray(nodes, dtype=float)
        key = (nodes.tobytes(), np.asarray(bar_radius, dtype=float).tobytes(),
               np.asarray(node_radius, dtype=float).tobytes())
        memo = self._memo
        if memo.get("crease_key") != key:
            out = []
            for crease in self.creases:
                found = crease.minima(nodes, np.asarray(bar_radius, dtype=float),
                                      np.asarray(node_radius, dtype=float))
                if found.bar.size > CREASE_SLOTS:
                    found = found.take(np.sort(np.argsort(found.value, kind="stable")[:CREASE_SLOTS]))
                out.append(found)
            memo["crease_key"], memo["crease_value"] = key, tuple(out)
        return memo["crease_value"]

    @property
    def tube_names(self) -> tuple[str, ...]:
        """Names of the tubes, main first (``"main"``, then each branch's name or ``"branch <i>"``)."""
        return ("main",) + tuple(b.name or f"branch {i}" for i, b in enumerate(self.branches))

    def tube_of(self, points: FloatArray) -> NDArray[np.int_]:
        """Index (into :attr:`tube_names`) of the tube each point (m, 3) lies deepest in: the largest clearance
        ``R(u) − |p − c(u)|`` over the tubes (where a branch leaves its parent, the one whose axis is nearer)."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        depth = np.stack([t.rows(p, np.zeros(len(p)))[0] for t in self._tubes])
        return np.argmax(depth, axis=0)

    def clearance(self, points: FloatArray, radii: FloatArray | float = 0.0) -> tuple[FloatArray, FloatArray]:
        """``(D, n)``: the largest ``R(u) − r − |p − c(u)|`` over the tubes, or beside a crease the distance from it
        less ``r`` (mm, > 0 inside by that margin), and the inward unit normal at each point (m, 3)."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        r = np.broadcast_to(np.asarray(radii, dtype=float), (len(p),))
        best_d = np.full(len(p), -np.inf)
        best_n = np.zeros((len(p), 3))
        for tube in self._tubes:
            e = tube.closest(p, r)
            v = e.centre - p
            dist = np.linalg.norm(v, axis=1)
            d = e.radius - r - dist
            n = v / np.where(dist > 0.0, dist, 1.0)[:, None]
            better = d > best_d
            best_d = np.where(better, d, best_d)
            best_n = np.where(better[:, None], n, best_n)
        for crease in self.creases:
            rows = crease.rows(p, np.asarray(r, dtype=float))
            better = rows.value > best_d[rows.index]
            best_d[rows.index[better]] = rows.value[better]
            best_n[rows.index[better]] = rows.gradient[better]
        return best_d, best_n

    def centrelines(self, spacing: float = 1.0) -> list[FloatArray]:
        """Sampled centrelines (main first) for drawing."""
        out = []
        for tube in self._tubes:
            u = np.linspace(0.0, tube.end, max(2, int(math.ceil(tube.end / spacing)) + 1))
            out.append(tube.evaluate(u).centre)
        return out


def _check_tube(tube: Tube, name: str) -> None:
    """Refuse a bend tighter than the radius and a tube that comes back within its radius of itself."""
    u = tube.u[tube.u <= tube.end]
    e = tube.evaluate(u)
    speed = np.linalg.norm(e.d1, axis=1)
    kappa = np.linalg.norm(np.cross(e.d1, e.d2), axis=1) / speed**3
    bend = kappa * e.radius
    points = tube.points
    worst = int(np.argmax(bend))
    if bend[worst] >= BEND_LIMIT:
        i = int(np.argmin(np.linalg.norm(points - e.centre[worst], axis=1)))
        raise ValueError(f"{name} bends tighter than the lumen radius near point {i} {_fmt(points[i])}: bend radius "
                         f"{1.0 / kappa[worst]:.3g} mm < radius {e.radius[worst]:.3g} mm, so the tube overlaps itself; "
                         "smooth the bend (more, farther-spread points) or reduce the radius there.")
    tree = cKDTree(e.centre)
    pairs = tree.query_pairs(2.0 * float(e.radius.max()), output_type="ndarray")
    if len(pairs):
        i, j = pairs[:, 0], pairs[:, 1]
        far = np.abs(u[i] - u[j]) > math.pi * np.maximum(e.radius[i], e.radius[j])
        close = np.linalg.norm(e.centre[i] - e.centre[j], axis=1) < e.radius[i] + e.radius[j]
        bad = np.flatnonzero(far & close)
        if bad.size:
            a, b = sorted((int(i[bad[0]]), int(j[bad[0]])))
            pa = int(np.argmin(np.linalg.norm(points - e.centre[a], axis=1)))
            pb = int(np.argmin(np.linalg.norm(points - e.centre[b], axis=1)))
            raise ValueError(f"{name} comes back within the lumen radius of itself: near point {pa} "
                             f"{_fmt(points[pa])} and point {pb} {_fmt(points[pb])} the tube overlaps itself; move "
                             "those stretches apart or reduce the radius.")
