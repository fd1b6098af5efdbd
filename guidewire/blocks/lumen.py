"""A vessel lumen: every node stays inside the vessel by the wire's radius (the contacts are found, not given).

The lumen's wall is curved, so its exact row ``D(p_k) ≥ d_k/2`` (``D`` the signed distance to the wall, > 0 inside;
``d_k`` the diameter of the section node ``k`` lies in, the larger one at a section boundary) is nonlinear in the node
position. This block writes it, node by node, as the second-order model of ``D`` around the
node's position ``p⁰_k`` when the row was made — ``D⁰ − n · (p − p⁰) + ½ (p − p⁰)ᵀ κ/(1 + κ D⁰) t tᵀ (p − p⁰)``
with ``n`` the outward normal and ``t`` the tangent at the nearest wall point and ``κ`` the wall's curvature there
(the exact Hessian of the distance to a curve of curvature ``κ``) — a quadratic
:class:`~guidewire.blocks.base.NodeRows` row (paper Eqs. 23–24 with the wall's curvature). SQP with this row converges
like Newton's method within a round (a tangent line alone leaves out ``λ ∇²D`` from the Lagrangian Hessian and
converged linearly, over many rounds, on a tortuous vessel); :meth:`Lumen.refine` then re-centres the model on the
answer and solves again only when the model and the true distance disagree.

``sag_k = l² κ⁺ / 8`` keeps the chord of a bar of length ``l`` from cutting through a wall that bulges into the lumen
(curvature ``κ⁺ > 0``: the inner wall of a bend; 43 µm for ``l = 1`` mm, ``ρ = 2.9`` mm).

Every node gets a row on each side: a node in a tube lies between two walls, and a row on the nearer one alone does
not see the other, so it gets a second row on the wall across the lumen (:meth:`guidewire.vessel.Vessel.far_side`;
none where that side is open: a branch's opening, the entrance cap). And every node gets its rows, not only those
near a wall at the start: a node without a row, or with one on one side only, moves across the lumen and out in a
single round wherever the wire leaves the centreline start, and the rounds that follow re-model it from far outside.
Measured on ``scenes/vessels/s_bend.toml`` (lumen radius 2.5 → 1.5 mm): with rows on the nearest wall for the nodes
within 3 bar lengths or a quarter of their distance of touching it, the cold solve at 69 mm ended SHAPE_REJECTED (26
nodes up to 9 mm outside after the first round, 1596 iterations), and 45 mm in 180 bars took 107 iterations (12 s);
with both rows at every node, 10 iterations, and 9 (0.04 s).

Where tubes overlap (a branch's opening; two branches whose openings meet, as the aortic arch's first two), the
nearest wall (:meth:`Vessel.clearance`: of the tube the node lies deepest in) can run through another tube's lumen
(:meth:`Vessel.opening`); where the node also clears that other tube's wall (:meth:`Vessel.tube_depths`) its row is
not on that wall: such a row, a wall that is not there, held the nodes sliding into the opening, one node a round (the
arch's cold solves at 203-215 mm ran out of rounds). Nor is the node left without a row on that side: left so (the
arch's cold solve at 211 mm, 1 bar/mm: nodes 199-208, in the openings of the first two branches, after the first
round), nothing held those nodes on that side, the next round's SQP swung the wire's distal part back along the arch
and out through its outer wall (its answer had nodes up to 18 mm outside the lumen, where the rows made at the
round's start model nothing), and the rounds ran out after 20 s. Its row is on the nearest point of the lumen's boundary
(:meth:`Vessel.nearest_boundary`: a wall point in no other tube's lumen), as a tangent line (curvature 0: that wall can
belong to a tube the node is not in, whose curvature about the node means nothing); once the node comes near a wall,
that wall is its deepest tube's and the row is exact again. A node beside a corner, inside neither tube by its
clearance, keeps its nearest wall's row (what it is checked against is the deepest tube's clearance).

Where a branch leaves, its walls meet the parent's at a corner (:attr:`guidewire.vessel.Vessel.corners`) that no
curvature describes: a bar between a node in the parent and one in the branch cuts through it while both nodes keep
their clearance (measured on ``scenes/vessels/s_bend_branch.toml``: insertion steps from 40 mm on with a bar's
midpoint 0.32 mm closer to the corner than the wire's radius, its energy swinging by 10 % as the nodes slid past the
corner). A node near a corner ``C`` whose wedge of wall has the angle ``2φ`` (:attr:`Vessel.corner_angles`) needs
``|p − C| ≥ √(r² + w²)``, ``w = max(l/2, (l − 2r cos φ)/(2 sin φ))``: with both nodes of a bar of length ``l`` that far
from ``C`` and ``r`` from the walls, its chord passes ``C`` at ``r`` or more on the lumen's side (``l/2``, the sag
rule's limit ``κ → ∞``) and is too short to span the wedge's two walls from one side to the other (the shortest such
chord, symmetric about the wedge's bisector, has length ``2 sin φ √(R² − r²) + 2r cos φ``). Its row is the same
quadratic model with ``D = |p − C|`` (Hessian ``t tᵀ/D``), for the nodes within the lumen's width (plus
:data:`CORNER_BARS` bar lengths) of needing it.

Every node is checked against the true lumen before a shape is returned (:meth:`Lumen.violation`). Multiplier
``λ_r ≥ 0``: the wall's normal force on the row's node in N, along ``−n_r``.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from .base import Block, FloatArray, IntArray, Loads, NodeRows, WorkingSet, grown_by_neighbours

if TYPE_CHECKING:
    from ..program.model import Model

PLANE_TOLERANCE = 1.0
"""A row its node touches is re-centred when the true clearance of the node differs from the row's model by more than
this times the solve tolerance ``tol · max(1, L)`` (mm)."""

MIN_DENOMINATOR = 0.1
"""Floor of ``1 + κ D⁰`` in the distance's curvature ``κ/(1 + κ D⁰)`` (a node far outside a bulging wall)."""

CORNER_BARS = 3.0
"""A node gets a row on a wall corner when it is within the lumen's width there plus this many bar lengths of needing
it (a node moves across the lumen, no farther, in one round)."""

MIN_WEDGE = 0.1
"""Least wedge angle (rad) a corner's rows assume (a thinner wedge of wall would need nodes ever farther away)."""

KEY_STRIDE = 1 << 24
"""Row keys: ``node + side × KEY_STRIDE`` (side 0 the nearest wall, 1 across, ``2 + c`` corner ``c``)."""

CACHES = ("_kept_rows", "_kept_slack")
"""What a :class:`Lumen` keeps besides its fields: its rows (:meth:`Lumen.rows`) and its last slack
(:meth:`Lumen.slack`)."""

TOUCHING_BARS = 0.1
"""A node within this many bar lengths of its row's bound touches it (only those rows need to be exact)."""


def node_diameters(model: Model, nodes: IntArray) -> FloatArray:
    """Wire diameter (mm) at each node ``1..n`` of ``nodes``: that of the section the node lies in, the larger of the
    two at a section boundary (the node joins a bar of each)."""
    wire, lengths = model.scene.wire, model.chain.lengths
    if not wire.sections:
        return np.full(np.shape(nodes), wire.diameter)
    bars = wire.properties_at(model.chain.arc_lengths[:-1] + 0.5 * lengths).diameter  # per bar, at its midpoint
    return np.maximum(bars[np.minimum(nodes, lengths.size) - 1], bars[np.minimum(nodes, lengths.size - 1)])


def _needed(model: Model, curvature: FloatArray, nodes: IntArray) -> FloatArray:
    """Clearance each node needs (mm): its radius (:func:`node_diameters`) plus the sag of its longer bar's chord on a
    bulging wall."""
    return 0.5 * node_diameters(model, nodes) + _bars(model, nodes) ** 2 * np.maximum(curvature, 0.0) / 8.0


def _bars(model: Model, nodes: IntArray) -> FloatArray:
    """The longer of the two bars at each node (the only one at the tip), mm."""
    lengths = model.chain.lengths
    return np.maximum(lengths[np.minimum(nodes, lengths.size) - 1], lengths[np.minimum(nodes, lengths.size - 1)])


def _corner_needed(model: Model, nodes: IntArray) -> FloatArray:
    """Distance (mm) each node of ``nodes`` needs from each corner of the vessel, shape (nodes, corners):
    ``√(r² + w²)``, ``w = max(l/2, (l − 2r cos φ)/(2 sin φ))`` with ``φ`` half the corner's wedge angle (module
    docstring)."""
    r, l = 0.5 * node_diameters(model, nodes)[:, None], _bars(model, nodes)[:, None]
    half = 0.5 * np.clip(model.scene.vessel.corner_angles, MIN_WEDGE, np.pi)[None, :]
    return np.hypot(r, np.maximum(0.5 * l, (l - 2.0 * r * np.cos(half)) / (2.0 * np.sin(half))))


def _corner_gaps(model: Model, points: FloatArray, nodes: IntArray) -> FloatArray:
    """Distance (mm) of every node of ``nodes`` from every corner of the vessel, shape (nodes, corners)."""
    corners = model.scene.vessel.corners
    return np.hypot(points[nodes, None, 0] - corners[None, :, 0], points[nodes, None, 1] - corners[None, :, 1])


@dataclass(frozen=True)
class Lumen(Block):
    """Rows keeping the nodes inside ``scene.vessel`` (see the module docstring).

    Attributes
    ----------
    centres : ndarray, shape (rows, 2)
        Node positions ``p⁰`` where each row's model is taken (mm).
    normals : ndarray, shape (rows, 2)
        Outward unit normal of the wall at the nearest wall point.
    depths : ndarray, shape (rows,)
        ``D⁰``: signed distance of ``p⁰`` to the wall (mm, > 0 inside).
    curvatures : ndarray, shape (rows,)
        Wall curvature there (1/mm, > 0 where it bulges into the lumen).
    needed : ndarray, shape (rows,)
        Clearance each node needs (mm): ``d_k/2`` (its section's diameter) plus the chord sag.
    sides : ndarray of int, shape (rows,)
        What each row keeps the node from: 0 its nearest wall (where that lies in an opening, the nearest point of
        the lumen's boundary: module docstring), 1 the wall across the lumen (:meth:`Vessel.far_side`),
        ``2 + c`` the vessel's corner ``c`` (curvature inf). ``nodes`` holds a node once for each (in that order).
    """

    kind: ClassVar[str] = "lumen"
    centres: FloatArray = field(default_factory=lambda: np.zeros((0, 2)), compare=False)
    normals: FloatArray = field(default_factory=lambda: np.zeros((0, 2)), compare=False)
    depths: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    curvatures: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    needed: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    sides: IntArray = field(default_factory=lambda: np.zeros(0, dtype=int), compare=False)

    @classmethod
    def build(cls, model: Model, working_set: WorkingSet = None) -> list[Block]:
        """The lumen's rows at the start ``model.x0``: for every node (``working_set`` None or ``"near"``; see the
        module docstring), or the nodes a mapping gives under ``("lumen", (0,))``."""
        vessel = getattr(model.scene, "vessel", None)
        if vessel is None:
            return []
        points = model.chain.nodes(model.x0)
        nodes = np.arange(1, model.n + 1)
        if working_set is not None and not isinstance(working_set, str):
            nodes = np.unique(np.asarray(working_set.get(("lumen", (0,)), nodes), dtype=int))
        return [cls._modelled(model, nodes, points)]

    @classmethod
    def _modelled(cls, model: Model, nodes: IntArray, points: FloatArray) -> Lumen:
        """Rows for ``nodes`` (sorted, unique) modelled at ``points``: each on its nearest wall, then each whose lumen
        has a wall across on that one, then on the corners within reach (module docstring)."""
        vessel = model.scene.vessel
        nodes = np.asarray(nodes, dtype=int)
        near = vessel.clearance(points[1:])  # every node (the answer is kept for the checks that follow)
        far = vessel.far_side(points[nodes])
        keep = np.isfinite(far.distance)
        depth = near.distance[nodes - 1]
        normal, wall_depth, curvature = near.normal[nodes - 1], depth, near.curvature[nodes - 1]
        if vessel.corners.size:
            # the nearest wall of the tube a node lies deepest in, where it runs through another tube's lumen and the
            # node clears that tube's wall too, is no wall: a row on it holds the node from moving into that tube;
            # the row is on the nearest point of the lumen's boundary instead (the module docstring)
            gone = np.flatnonzero(vessel.opening(near.boundary[nodes - 1], depth))
            if gone.size:
                second = np.sort(vessel.tube_depths(points[nodes[gone]]), axis=1)[:, -2]  # (a corner: ≥ 2 tubes)
                gone = gone[second >= _needed(model, near.curvature[nodes[gone] - 1], nodes[gone])]
            if gone.size:
                wall = vessel.nearest_boundary(points[nodes[gone]])
                wall_depth = depth.copy()  # (normal and curvature are copies already: fancy indexing)
                normal[gone], wall_depth[gone], curvature[gone] = wall.normal, wall.distance, 0.0
        parts = [(nodes, normal, wall_depth, curvature, np.zeros(nodes.size, dtype=int)),
                 (nodes[keep], far.normal[keep], far.distance[keep], far.curvature[keep],
                  np.ones(int(keep.sum()), dtype=int))]
        if vessel.corners.size:
            gaps = _corner_gaps(model, points, nodes)
            width = depth + np.where(keep, far.distance, depth)
            reach = width + CORNER_BARS * _bars(model, nodes)
            corner_needed = _corner_needed(model, nodes)
            k, c = np.nonzero(gaps - corner_needed <= reach[:, None])
            toward = vessel.corners[c] - points[nodes[k]]
            parts.append((nodes[k], toward / gaps[k, c, None], gaps[k, c], np.full(k.size, np.inf), 2 + c))
        rows, normals, depths, curvatures, sides = (np.concatenate(column) for column in zip(*parts, strict=True))
        wall = sides < 2
        needed = _needed(model, np.where(wall, curvatures, 0.0), rows)
        if not wall.all():
            needed[~wall] = corner_needed[k, c]
        return cls((0,), rows, centres=points[rows].copy(), normals=normals, depths=depths, curvatures=curvatures,
                   needed=needed, sides=sides)

    def __getstate__(self) -> dict[str, Any]:
        """The fields only (what pickling and copying keep): the cached rows and slack are rebuilt on demand."""
        return {name: value for name, value in self.__dict__.items() if name not in CACHES}

    @property
    def row_keys(self) -> IntArray:
        """``k + side × KEY_STRIDE`` for node ``k``'s row on ``side`` (see :attr:`sides`)."""
        return self.nodes + self.sides * KEY_STRIDE

    def rows(self, model: Model) -> NodeRows:
        """The rows' quadratic models (module docstring), built once per block (they depend on the block's fields
        alone; the program, the refinement and the loads all read them): read-only arrays."""
        built = self.__dict__.get("_kept_rows")
        if built is None:
            built = self._build_rows()
            for array in (built.directions, built.lb, built.ub, built.hessians):
                array.flags.writeable = False
            object.__setattr__(self, "_kept_rows", built)  # (a cache, not a field: not compared, copied or pickled)
        return built

    def _build_rows(self) -> NodeRows:
        tangent = np.column_stack((-self.normals[:, 1], self.normals[:, 0]))
        wall = np.isfinite(self.curvatures)
        kappa = np.where(wall, self.curvatures, 0.0)
        weight = np.where(wall, kappa / np.maximum(1.0 + kappa * self.depths, MIN_DENOMINATOR),
                          1.0 / np.maximum(self.depths, self.needed))  # a corner: |p − C|'s Hessian t tᵀ / D
        hessians = weight[:, None, None] * tangent[:, :, None] * tangent[:, None, :]
        d = -self.normals
        lb = self.needed - self.depths + np.einsum("ij,ij->i", d, self.centres)
        return NodeRows(self.nodes, d, lb, np.full(self.size, np.inf), hessians=hessians, centres=self.centres)

    def add_loads(self, model: Model, lam: FloatArray, loads: Loads) -> None:
        """The wall pushes node ``k`` with ``λ_k`` along the row's gradient (``−n`` at the model's centre)."""
        rows = self.rows(model)
        np.add.at(loads.node_forces, self.nodes, np.asarray(lam, dtype=float)[:, None] * rows.gradients(
            self._points(model)))

    def _points(self, model: Model) -> FloatArray:
        """Node positions (n + 1, 2) with the rows' nodes at their model centres (where the loads are evaluated)."""
        out = np.zeros((model.n + 1, 2))
        out[self.nodes] = self.centres
        return out

    def slack(self, model: Model, points: FloatArray) -> FloatArray:
        """True clearance minus the clearance needed, at every node 1..n (mm; negative: outside the lumen or too
        near one of its corners). The last answer is kept (read-only): a solve asks for it at its answer twice, to
        refine the rows (:meth:`refine`) and to check the shape (:meth:`violation`)."""
        return self._slacks(model, points)[0]

    def wall_slack(self, model: Model, points: FloatArray) -> FloatArray:
        """:meth:`slack` against the nearest wall alone, the vessel's corners left out (mm, every node 1..n): what a
        wall row (side 0 or 1) models, so what :meth:`_touching_gap` compares it with. Kept with :meth:`slack`."""
        return self._slacks(model, points)[1]

    def _slacks(self, model: Model, points: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(:meth:`slack`, :meth:`wall_slack`) at ``points``, from the kept pair when ``points`` are the last ones."""
        kept = self.__dict__.get("_kept_slack")
        if kept is not None and kept[0]() is model and np.array_equal(kept[1], points):
            return kept[2], kept[3]
        slack, wall = self._slack(model, points)
        slack.flags.writeable = False
        wall.flags.writeable = False
        object.__setattr__(self, "_kept_slack", (weakref.ref(model), np.array(points, dtype=float), slack, wall))
        return slack, wall

    def _slack(self, model: Model, points: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The slack at every node against the walls and corners together, and against the nearest wall alone."""
        nodes = np.arange(1, model.n + 1)
        c = model.scene.vessel.clearance(points[1:])
        wall = c.distance - _needed(model, c.curvature, nodes)
        slack = wall
        if model.scene.vessel.corners.size:
            gaps = _corner_gaps(model, points, nodes)
            slack = np.minimum(wall, np.min(gaps - _corner_needed(model, nodes), axis=1))
        return slack, wall

    def violation(self, model: Model, phi: FloatArray, points: FloatArray | None = None,
                  rows: Any = None) -> FloatArray:
        """Violation at *every* node 1..n against the true (curved) lumen, not only the working set's rows (``rows`` is
        not read)."""
        points = model.chain.nodes(phi) if points is None else points
        return np.maximum(-self.slack(model, points), 0.0)

    def violation_nodes(self, model: Model) -> IntArray:
        """Every node 1..n (:meth:`violation` checks them all)."""
        return np.arange(1, model.n + 1)

    def describe(self, model: Model) -> str:
        return "lumen (the wire outside the vessel)"

    def refine(self, model: Model, phi: FloatArray, tolerance: float) -> Block | None:
        """Add the nodes that leave the lumen (and their neighbours) and re-centre every row whose node nearly
        touches it while the model and the true distance there differ by more than :data:`PLANE_TOLERANCE`
        ``× tolerance``; None when neither is needed."""
        points = model.chain.nodes(phi)
        violated = np.flatnonzero(self.slack(model, points) < -tolerance) + 1
        gap = self._touching_gap(model, points, self.wall_slack(model, points))
        if not violated.size and not np.any(gap > PLANE_TOLERANCE * tolerance):
            return None
        nodes = grown_by_neighbours(np.unique(self.nodes), violated, model.n)
        return replace(self._modelled(model, nodes, points), index=self.index)

    def mismatch(self, model: Model, phi: FloatArray) -> tuple[float, int] | None:
        """The largest ``|model slack − true slack|`` (mm) over the rows whose node touches, and its node."""
        points = model.chain.nodes(phi)
        gap = self._touching_gap(model, points, self.wall_slack(model, points))
        if not gap.size or not np.any(gap > 0.0):
            return None
        k = int(np.argmax(gap))
        return float(gap[k]), int(self.nodes[k])

    def _touching_gap(self, model: Model, points: FloatArray, slack: FloatArray) -> FloatArray:
        """Per row, ``|model slack − true slack|`` (mm) where the row's node touches (model slack within
        :data:`TOUCHING_BARS` bar lengths), 0 elsewhere; ``slack`` is :meth:`wall_slack` at ``points``.

        A wall row is compared with the wall's slack alone and a corner row with its corner's: a node held by a
        corner (its :meth:`slack` that corner's) while its wall row also touches would otherwise show the wall row a
        gap of the wall's own slack, which re-centring the row at the same point cannot close (the rounds then ran
        out: the aortic arch inserted at 4 bars/mm, 205-210 mm, a wall row 5 µm from a node a corner held)."""
        rows = self.rows(model)
        model_slack = rows.values(points) - rows.lb
        true_slack = slack[self.nodes - 1]
        corner = self.sides >= 2
        if corner.any():
            c = model.scene.vessel.corners[self.sides[corner] - 2]
            true_slack[corner] = np.hypot(*(points[self.nodes[corner]] - c).T) - self.needed[corner]
        touching = model_slack <= TOUCHING_BARS * float(np.max(model.chain.lengths))
        return np.where(touching, np.abs(true_slack - model_slack), 0.0)

    def contact_normals(self, scene: Any) -> FloatArray:
        return self.normals

    def advanced(self, bars: int) -> Block:
        return replace(self, nodes=self.nodes + bars)

    def with_tip(self, old: int, new: int) -> Block:
        return replace(self, nodes=np.where(self.nodes == old, new, self.nodes))
