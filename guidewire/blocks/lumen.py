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
that wall is its deepest tube's and the row is exact again.

Where a branch leaves, its walls meet the parent's at a corner (:attr:`guidewire.vessel.Vessel.corners`) that no
curvature describes: a bar between a node in the parent and one in the branch cuts through it while both nodes keep
their clearance (measured on ``scenes/vessels/s_bend_branch.toml``: insertion steps from 40 mm on with a bar's
midpoint 0.32 mm closer to the corner than the wire's radius). The corner is kept at the wire's radius from the *bars*
that pass it: a bar within :data:`BAR_ROW_REACH` bar lengths of touching corner ``C``, whose foot from ``C`` lies on
it, gets a row on the distance of ``C`` from its line, ``(p_{k+1} − p_k) × (C − p_k) / l ≥ r`` (signed: positive on
the lumen's side) — exact while the foot stays on the bar, quadratic in the bar's two nodes
(:class:`~guidewire.blocks.base.NodeRows`), its force normal to the bar at the foot. A row on a node's distance
from the corner instead (``|p − C| ≥ ρ``, with ``ρ`` large enough that no chord cuts the wedge) meets the wire at an
angle and held it lengthwise, as friction would: past ``s_bend_branch``'s corner at 4 bars/mm the contacts held the
wire with 0.1-0.6 N along its length, the entrance push read up to 0.6 N off ``dE/dL`` (negative while the energy
rose), and the wire hooked on the corner (3.97 against 3.72 N·mm at 46 mm); with the bar rows the lengthwise force is
below 2 mN at 2, 4 and 8 bars/mm and the push is ``dE/dL``. A node still gets a row on its distance from the corner
(``≥ r``, Hessian ``t tᵀ/D``) where the bars' rows leave it exposed: the end of a close bar whose foot lies beyond it
(the wire's kink rests on the corner), and every node within the lumen's width (plus :data:`CORNER_BARS` bar lengths)
of the corner that is no end of a bar with a row (a node moves across the lumen in one round; a row there beside a
bar's, nearly parallel to it as the foot nears the node, left the multipliers ill-defined). A node whose nearest
boundary point is the corner (:meth:`Vessel.nearest_corner`: in the corner's cone) has no wall row, whose wall would
run on through the opening.

A bar's row holds while the foot stays on its bar, so a contact sliding over a corner moves from bar to bar one round
at a time (a round ends when a foot has left its bar, :meth:`Lumen.refine`): pushing ``s_bend_branch``'s wire 0.5 mm
past the corner at 4 bars/mm takes 3-8 rounds and 11-61 iterations a step, where the node rows took 1-2 and 3-10
(34-46 mm: 1.6 s against 0.45 s); at 1 bar/mm along the aortic arch (20-250 mm), 212 iterations in 246 rounds
against 215 in 248.

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
"""A node gets a row on its distance from a corner when it is within the lumen's width there plus this many bar
lengths of needing it (a node moves across the lumen, no farther, in one round) and no bar's row on that corner
covers it (module docstring)."""

BAR_ROW_REACH = 1.0
"""A bar gets a row on its distance from a corner when it is within this many bar lengths of touching it (farther,
the rows on its nodes' distance from the corner keep it away; a bar's row is a line through the corner, which a node
far along the wire would meet where the wire bends: the arch's cold solve at 211 mm, 2 bars/mm, ran 24 rounds to
INFEASIBLE with rows on every bar whose foot lay on it)."""

KEY_STRIDE = 1 << 24
"""Row keys: ``node + side × KEY_STRIDE`` (:attr:`Lumen.sides`)."""

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


def _bar_radii(model: Model) -> FloatArray:
    """The wire's radius (mm) on every bar 0..n−1 (bar ``j`` joins nodes ``j`` and ``j + 1``), at its midpoint."""
    lengths = model.chain.lengths
    return 0.5 * model.scene.wire.properties_at(model.chain.arc_lengths[:-1] + 0.5 * lengths).diameter


def _corner_feet(points: FloatArray, corners: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """For every bar ``j`` (nodes ``j``, ``j + 1`` of ``points``) and corner: the foot parameter ``τ`` of the corner
    on the bar's line (0 at node ``j``, 1 at node ``j + 1``), the bar's unit normal towards the corner (shape (bars,
    corners, 2)) and the corner's distance from the bar as a segment (mm)."""
    start, step = points[:-1, None, :], (points[1:] - points[:-1])[:, None, :]
    length2 = np.maximum(np.einsum("bcj,bcj->bc", step, step), np.finfo(float).tiny)
    rel = corners[None, :, :] - start
    tau = np.einsum("bcj,bcj->bc", rel, step) / length2
    gap = rel - np.clip(tau, 0.0, 1.0)[:, :, None] * step
    left = np.stack((-step[..., 1], step[..., 0]), axis=-1) / np.sqrt(length2)[:, :, None]
    side = np.where(np.einsum("bcj,bcj->bc", rel, left) >= 0.0, 1.0, -1.0)
    return tau, side[:, :, None] * left, np.hypot(gap[..., 0], gap[..., 1])


def _corner_slack(reach: tuple[IntArray, IntArray, FloatArray, FloatArray, FloatArray],
                  inside: FloatArray) -> FloatArray:
    """The least clearance from the vessel's corners of each node's two bars, less the wire's radius there (mm, every
    node 1..n): what the bar rows of the corners keep ≥ 0. ``reach`` is :func:`_corner_reach` at the nodes, ``inside``
    the lumen's clearance (:meth:`Vessel.lumen_clearance`) of its points nearest the corners. A bar within its length
    of a corner whose nearest point to it lies outside the lumen has passed behind the corner, through its wedge of
    wall, its two nodes in the lumen on either side: its clearance is that point's (negative)."""
    j, c, _, distance, radius = reach
    clearance = distance.copy()
    if j.size:
        clearance[j, c] = np.where(inside < 0.0, inside, distance[j, c])
    bars = np.min(clearance, axis=1) - radius
    return np.minimum(bars, np.append(bars[1:], np.inf))


def _corner_reach(model: Model, points: FloatArray) -> tuple[IntArray, IntArray, FloatArray, FloatArray, FloatArray]:
    """The bars within their length (plus the wire's radius) of a corner, as (bar, corner) pairs ``j, c``, the point
    of each such bar nearest its corner (mm), every bar's distance from every corner and the wire's radius on every
    bar (:func:`_corner_slack`'s parts)."""
    tau, _, distance = _corner_feet(points, model.scene.vessel.corners)
    radius = _bar_radii(model)
    j, c = np.nonzero(distance < (model.chain.lengths + radius)[:, None])
    foot = points[j] + np.clip(tau[j, c], 0.0, 1.0)[:, None] * (points[j + 1] - points[j])
    return j, c, foot, distance, radius


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
        the lumen's boundary: module docstring), 1 the wall across the lumen (:meth:`Vessel.far_side`), ``2 + 2c``
        the vessel's corner ``c``, from the bar between the row's node and the next, ``3 + 2c`` that corner from the
        node. ``nodes`` holds a node once for each (in that order).
    fractions : ndarray, shape (rows,)
        Where on its bar a bar's row holds it (``τ`` of the corner's foot at the model, > 0); 0 for a node's row.
    turns : ndarray, shape (rows,)
        ``±1/l`` of a bar's row (the sign that makes its value the corner's distance on the side of ``−normal``), 0
        for a node's row (:class:`~guidewire.blocks.base.NodeRows`).
    """

    kind: ClassVar[str] = "lumen"
    centres: FloatArray = field(default_factory=lambda: np.zeros((0, 2)), compare=False)
    normals: FloatArray = field(default_factory=lambda: np.zeros((0, 2)), compare=False)
    depths: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    curvatures: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    needed: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    sides: IntArray = field(default_factory=lambda: np.zeros(0, dtype=int), compare=False)
    fractions: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    turns: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)

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
        opening = None
        if vessel.corners.size:
            # the nearest wall of the tube a node lies deepest in, where it runs through another tube's lumen and the
            # node clears that tube's wall too, is no wall: a row on it holds the node from moving into that tube;
            # the row is on the nearest point of the lumen's boundary instead (the module docstring)
            opening = vessel.opening(near.boundary[nodes - 1], depth)
            gone = np.flatnonzero(opening)
            if gone.size:
                second = np.sort(vessel.tube_depths(points[nodes[gone]]), axis=1)[:, -2]  # (a corner: ≥ 2 tubes)
                gone = gone[second >= _needed(model, near.curvature[nodes[gone] - 1], nodes[gone])]
            if gone.size:
                wall = vessel.nearest_boundary(points[nodes[gone]])
                wall_depth = depth.copy()  # (normal and curvature are copies already: fancy indexing)
                normal[gone], wall_depth[gone], curvature[gone] = wall.normal, wall.distance, 0.0
        # a node in a corner's cone (the corner its nearest wall point) has a row on its distance from the corner
        # instead of a wall row, whose point (the nearest wall or boundary sample) lies off the corner in an opening
        cone, _ = vessel.nearest_corner(points[nodes], near.take(nodes - 1), opening)
        wall_row = cone < 0
        zero = np.zeros(nodes.size)
        parts = [(nodes[wall_row], normal[wall_row], wall_depth[wall_row], curvature[wall_row],
                  np.zeros(int(wall_row.sum()), dtype=int), zero[wall_row], zero[wall_row]),
                 (nodes[keep], far.normal[keep], far.distance[keep], far.curvature[keep],
                  np.ones(int(keep.sum()), dtype=int), zero[keep], zero[keep])]
        corner_needed: list[FloatArray] = []
        if vessel.corners.size:
            parts += cls._corner_parts(model, nodes, points, depth + np.where(keep, far.distance, depth),
                                       corner_needed)
        rows, normals, depths, curvatures, sides, tau, turns = (np.concatenate(column)
                                                                for column in zip(*parts, strict=True))
        wall = sides < 2
        needed = _needed(model, np.where(wall, curvatures, 0.0), rows)
        if not wall.all():
            needed[~wall] = np.concatenate(corner_needed)
        centres = points[rows].copy()
        bar = np.flatnonzero(tau)
        centres[bar] += tau[bar, None] * (points[rows[bar] + 1] - centres[bar])
        return cls((0,), rows, centres=centres, normals=normals, depths=depths, curvatures=curvatures,
                   needed=needed, sides=sides, fractions=tau, turns=turns)

    @staticmethod
    def _corner_parts(model: Model, nodes: IntArray, points: FloatArray, width: FloatArray,
                      needed: list[FloatArray]) -> list[tuple[Any, ...]]:
        """The corners' rows (module docstring), as ``_modelled``'s parts, for the bars and nodes of ``nodes``; what
        each row needs is appended to ``needed``. A bar within :data:`BAR_ROW_REACH` bar lengths of touching a corner,
        whose foot ``q`` from it lies on the bar, gets a linear row at ``q`` along its normal towards the corner (the
        bar ``r`` clear of it, its force normal to the bar and shared by its two nodes); every node within the lumen's
        ``width`` (plus :data:`CORNER_BARS` bar lengths) of a corner a row on its distance from it (≥ the wire's
        radius)."""
        vessel = model.scene.vessel
        corners = vessel.corners
        tau, normal, distance = _corner_feet(points, corners)
        # the bar belongs on the lumen's side of the corner: its row's normal points from the bar to the corner,
        # unless the bar's foot lies inside the wedge of wall (the bar has crossed it): then away, to push it back
        faces = vessel.corner_faces
        into_wall = faces[:, 0] + faces[:, 1]
        into_wall /= np.linalg.norm(into_wall, axis=1, keepdims=True)
        foot = -(distance[:, :, None] * normal)
        crossed = np.einsum("bcj,cj->bc", foot, into_wall) > distance * np.cos(0.5 * vessel.corner_angles)[None, :]
        normal = np.where(crossed[:, :, None], -normal, normal)
        radius = _bar_radii(model)
        member = np.zeros(model.n + 2, dtype=bool)
        member[nodes] = True
        close = (distance - radius[:, None] <= BAR_ROW_REACH * model.chain.lengths[:, None]) & (
            member[:-2] | member[1:-1])[:, None]  # bar j: nodes j and j + 1
        close[0] = False  # (the first bar leaves the fixed base node: the entrance lies far from any corner)
        on_bar = close & (tau >= 0.0) & (tau <= 1.0)
        j, c = np.nonzero(on_bar)
        n_jc = normal[j, c]
        q = points[j] + tau[j, c, None] * (points[j + 1] - points[j])
        step = points[j + 1] - points[j]
        sign = np.sign(np.einsum("ij,ij->i", n_jc, np.column_stack((-step[:, 1], step[:, 0]))))
        parts = [(j, n_jc, np.einsum("ij,ij->i", n_jc, corners[c] - q), np.zeros(j.size), 2 + 2 * c,
                  np.clip(tau[j, c], 0.0, 1.0), sign / model.chain.lengths[j])]
        needed.append(radius[j])
        toward = corners[None, :, :] - points[nodes][:, None, :]
        gap = np.hypot(toward[..., 0], toward[..., 1])
        r = 0.5 * node_diameters(model, nodes)
        near = gap - r[:, None] <= (width + CORNER_BARS * _bars(model, nodes))[:, None]
        # a node of a bar with a row on the same corner needs none: the bar's row keeps it farther, and a second row
        # there, nearly parallel to the bar's when the foot nears the node, left the multipliers ill-defined (28 to
        # 61 iterations a step past s_bend_branch's corner at 4 bars/mm, with as many rounds); but the end of a close
        # bar whose foot lies beyond it is that bar's nearest point: its row there is the node's
        held = np.zeros((model.n + 2, corners.shape[0]), dtype=bool)
        held[j, c], held[j + 1, c] = True, True
        jo, co = np.nonzero(close & ~on_bar)
        held[np.where(tau[jo, co] < 0.0, jo, jo + 1), co] = False
        i, c = np.nonzero(near & ~held[nodes])
        parts.append((nodes[i], toward[i, c] / np.maximum(gap[i, c], np.finfo(float).tiny)[:, None], gap[i, c],
                      np.zeros(i.size), 2 + 2 * c + 1, np.zeros(i.size), np.zeros(i.size)))
        needed.append(r[i])
        return parts

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
            built = self._build_rows(model.scene.vessel.corners)
            for array in (built.directions, built.lb, built.ub, built.hessians):
                array.flags.writeable = False
            object.__setattr__(self, "_kept_rows", built)  # (a cache, not a field: not compared, copied or pickled)
        return built

    def _build_rows(self, corners: FloatArray) -> NodeRows:
        tangent = np.column_stack((-self.normals[:, 1], self.normals[:, 0]))
        wall = self.sides < 2
        kappa = np.where(wall, self.curvatures, 0.0)
        radial = (self.sides >= 2) & (self.sides % 2 == 1)  # a node's distance from a corner
        weight = np.where(wall, kappa / np.maximum(1.0 + kappa * self.depths, MIN_DENOMINATOR),
                          np.where(radial, 1.0 / np.maximum(self.depths, self.needed), 0.0))  # |p − C|: t tᵀ / D
        hessians = weight[:, None, None] * tangent[:, :, None] * tangent[:, None, :]
        d = -self.normals
        lb = self.needed - self.depths + np.einsum("ij,ij->i", d, self.centres)
        if not np.any(self.turns):
            return NodeRows(self.nodes, d, lb, np.full(self.size, np.inf), hessians=hessians, centres=self.centres)
        bar = self.turns != 0.0
        lb[bar] = self.needed[bar]  # (a bar's row is the corner's distance from the bar's line itself)
        pivots = np.zeros((self.size, 2))
        pivots[bar] = corners[self.sides[bar] // 2 - 1]
        return NodeRows(self.nodes, d, lb, np.full(self.size, np.inf), hessians=hessians, centres=self.centres,
                        fractions=self.fractions, pivots=pivots, turns=self.turns)

    def add_loads(self, model: Model, lam: FloatArray, loads: Loads, points: FloatArray) -> None:
        """The wall pushes node ``k`` with ``λ_k`` along the row's gradient at the model's centre, ``d = −n``; a
        corner pushes a bar with ``λ`` normal to it at ``points``, shared by its two nodes as ``1 − τ`` and ``τ``
        (the foot there: :meth:`contact_frames`)."""
        rows = self.rows(model)
        normals, fractions = self.contact_frames(model.scene, points)
        bars = np.flatnonzero(self.turns)
        if bars.size:
            rows = replace(rows, directions=-normals, fractions=fractions)
        rows.add_to_nodes(np.asarray(lam, dtype=float)[:, None] * rows.directions, loads.node_forces)

    def slack(self, model: Model, points: FloatArray) -> FloatArray:
        """True clearance minus the clearance needed, at every node 1..n (mm; negative: outside the lumen or too
        near one of its corners). The last answer is kept (read-only): a solve asks for it at its answer twice, to
        refine the rows (:meth:`refine`) and to check the shape (:meth:`violation`)."""
        return self._slacks(model, points)[0]

    def wall_slack(self, model: Model, points: FloatArray) -> FloatArray:
        """:meth:`slack` against the lumen's boundary alone, the bars' clearance from its corners left out (mm, every
        node 1..n): what a node's wall row (side 0 or 1) models, so what :meth:`_touching_gap` compares it with.
        Kept with :meth:`slack`."""
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
        """The slack at every node against the lumen's boundary and the bars' clearance from its corners together,
        and against the boundary alone."""
        nodes = np.arange(1, model.n + 1)
        vessel = model.scene.vessel
        if not vessel.corners.size:
            c = vessel.clearance(points[1:])
            wall = c.distance - _needed(model, c.curvature, nodes)
            return wall, wall
        # the nearest corner of the nodes and of the bars' points nearest the corners in one call, so the openings
        # it asks for are one search (every point's answer is its own; the two clearances asked apart, as the rows
        # and the last step asked them: a step that ends where it started finds them kept)
        reach = _corner_reach(model, points)
        both = vessel.clearance(points[1:])
        if reach[2].size:
            both = both.joined(vessel.clearance(reach[2]))
        corner, gap = vessel.nearest_corner(np.concatenate((points[1:], reach[2])), both)
        n = model.n
        wall = both.distance[:n] - _needed(model, both.curvature[:n], nodes)
        # (in a corner's cone the boundary is the corner: the node's distance from it, not its tube's clearance; a
        # wall row there models a wall that is not there, whose gap to this sends the rounds on to re-model it)
        wall = np.where(corner[:n] >= 0, gap[:n] - 0.5 * node_diameters(model, nodes), wall)
        feet = np.where(corner[n:] >= 0, gap[n:], both.distance[n:])  # (their lumen_clearance)
        return np.minimum(wall, _corner_slack(reach, feet)), wall

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
        corner = np.flatnonzero(self.sides >= 2)
        if corner.size:
            c, radial = np.divmod(self.sides[corner] - 2, 2)
            radial = radial.astype(bool)
            k = self.nodes[corner]
            corners = model.scene.vessel.corners
            true_slack[corner[radial]] = (np.hypot(*(points[k[radial]] - corners[c[radial]]).T)
                                          - self.needed[corner[radial]])
            on_bar = corner[~radial]
            if on_bar.size:  # a bar's row: its bar's clearance from the corner (its line's while the foot is on it)
                _, _, distance = _corner_feet(points, corners)
                true_slack[on_bar] = distance[self.nodes[on_bar], c[~radial]] - self.needed[on_bar]
        touching = model_slack <= TOUCHING_BARS * float(np.max(model.chain.lengths))
        return np.where(touching, np.abs(true_slack - model_slack), 0.0)

    def contact_frames(self, scene: Any, points: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The rows' outward normals and where on its bar each touches the wire, at node positions ``points``: a
        node's row its model's (exact at a converged answer, :meth:`refine`); a bar's row its bar's normal there
        (on the model's side) and the corner's foot on it, clipped to the bar — the row is exact wherever the
        foot lies on the bar, so the bar may have turned and slid under it since the row was made."""
        bars = np.flatnonzero(self.turns)
        if not bars.size:
            return self.normals, self.fractions
        tau, normal, _ = _corner_feet(points, scene.vessel.corners)
        k, c = self.nodes[bars], self.sides[bars] // 2 - 1
        normals, fractions = self.normals.copy(), self.fractions.copy()
        turned = normal[k, c]
        normals[bars] = np.where((np.einsum("ij,ij->i", turned, self.normals[bars]) >= 0.0)[:, None], turned, -turned)
        fractions[bars] = np.clip(tau[k, c], 0.0, 1.0)
        return normals, fractions

    def advanced(self, bars: int) -> Block:
        return replace(self, nodes=self.nodes + bars)

    def with_tip(self, old: int, new: int) -> Block:
        return replace(self, nodes=np.where(self.nodes == old, new, self.nodes))
