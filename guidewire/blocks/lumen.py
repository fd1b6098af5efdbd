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

Every node is checked against the true lumen before a shape is returned (:meth:`Lumen.violation`). Multiplier
``λ_r ≥ 0``: the wall's normal force on the row's node in N, along ``−n_r``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from .base import Block, FloatArray, IntArray, Loads, NodeRows, WorkingSet, grown_by_neighbours

if TYPE_CHECKING:
    from ..program.model import Model

PLANE_TOLERANCE = 1.0
"""A row its node touches is re-centred when the true clearance of the node differs from the row's model by more than
this times the solve tolerance ``tol · max(1, L)`` (mm)."""

MIN_DENOMINATOR = 0.1
"""Floor of ``1 + κ D⁰`` in the distance's curvature ``κ/(1 + κ D⁰)`` (a node far outside a bulging wall)."""

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
    lengths = model.chain.lengths
    bar = np.maximum(lengths[np.minimum(nodes, lengths.size) - 1], lengths[np.minimum(nodes, lengths.size - 1)])
    return 0.5 * node_diameters(model, nodes) + bar**2 * np.maximum(curvature, 0.0) / 8.0


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
    across : ndarray of bool, shape (rows,)
        Rows on the wall across the lumen (:meth:`Vessel.far_side`); the others are on the nearest wall. ``nodes``
        holds a node once or twice (nearest-wall rows first).
    """

    kind: ClassVar[str] = "lumen"
    centres: FloatArray = field(default_factory=lambda: np.zeros((0, 2)), compare=False)
    normals: FloatArray = field(default_factory=lambda: np.zeros((0, 2)), compare=False)
    depths: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    curvatures: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    needed: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)
    across: NDArray[np.bool_] = field(default_factory=lambda: np.zeros(0, dtype=bool), compare=False)

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
        """Rows for ``nodes`` (sorted, unique) modelled at ``points``: each on its nearest wall, then each whose
        lumen has a wall across on that one (nearest-wall rows first)."""
        vessel = model.scene.vessel
        nodes = np.asarray(nodes, dtype=int)
        near = vessel.clearance(points[1:])  # every node (the answer is kept for the checks that follow)
        far = vessel.far_side(points[nodes])
        keep = np.isfinite(far.distance)
        rows = np.concatenate((nodes, nodes[keep]))
        curvature = np.concatenate((near.curvature[nodes - 1], far.curvature[keep]))
        return cls((0,), rows, centres=points[rows].copy(),
                   normals=np.concatenate((near.normal[nodes - 1], far.normal[keep])),
                   depths=np.concatenate((near.distance[nodes - 1], far.distance[keep])), curvatures=curvature,
                   needed=_needed(model, curvature, rows), across=np.repeat([False, True], [nodes.size, keep.sum()]))

    @property
    def row_keys(self) -> IntArray:
        """``2 k`` for node ``k``'s row on its nearest wall, ``2 k + 1`` for its row across the lumen."""
        return 2 * self.nodes + self.across.astype(int)

    def rows(self, model: Model) -> NodeRows:
        tangent = np.column_stack((-self.normals[:, 1], self.normals[:, 0]))
        weight = self.curvatures / np.maximum(1.0 + self.curvatures * self.depths, MIN_DENOMINATOR)
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
        """True clearance minus the clearance needed, at every node 1..n (mm; negative: outside the lumen)."""
        c = model.scene.vessel.clearance(points[1:])
        return c.distance - _needed(model, c.curvature, np.arange(1, model.n + 1))

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
        slack = self.slack(model, points)
        violated = np.flatnonzero(slack < -tolerance) + 1
        rows = self.rows(model)
        model_slack = rows.values(points) - rows.lb
        touching = model_slack <= TOUCHING_BARS * float(np.max(model.chain.lengths))
        stale = touching & (np.abs(slack[self.nodes - 1] - model_slack) > PLANE_TOLERANCE * tolerance)
        if not violated.size and not np.any(stale):
            return None
        nodes = grown_by_neighbours(np.unique(self.nodes), violated, model.n)
        return replace(self._modelled(model, nodes, points), index=self.index)

    def contact_normals(self, scene: Any) -> FloatArray:
        return self.normals

    def advanced(self, bars: int) -> Block:
        return replace(self, nodes=self.nodes + bars)
