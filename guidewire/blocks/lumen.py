"""A vessel lumen: every node stays inside the vessel by the wire's radius (the contacts are found, not given).

The lumen's wall is curved, so its exact row ``clearance(p_k) ≥ d/2`` is nonlinear in the node position. This block
writes it, node by node, as the wall's tangent line at the nearest wall point ``b_k`` (outward unit normal ``n_k``):
``n_k · p_k ≤ n_k · b_k − d/2 − sag_k`` — a :class:`~guidewire.blocks.base.NodeRows` row, linear in the node like a
wall's (paper Eqs. 23–24, one half-plane per node instead of one per wall). :meth:`Lumen.refine` then moves each
tangent line to the wall point nearest the answer and solves again: at a fixed point every line touches the wall at
its node's nearest point, so the first-order optimality conditions are those of the curved lumen; the error of a line
moved by ``δ`` along a wall of curvature ``κ`` is ``κ δ²/2``, so the rounds converge quadratically.

``sag_k = l² κ⁺ / 8`` keeps the chord of a bar of length ``l`` from cutting through a wall that bulges into the lumen
(curvature ``κ⁺ > 0``: the inner wall of a bend; 43 µm for ``l = 1`` mm, ``ρ = 2.9`` mm).

Rows exist only for the nodes near the wall (a working set: within :data:`NEAR_BARS` bar lengths, or
:data:`NEAR_FRACTION` of their own distance to the wall, of touching it), and every node is checked against the
true lumen before a shape is returned (:meth:`Lumen.violation`). Multiplier ``λ_k ≥ 0``: the wall's normal force on
node ``k`` in N, along ``−n_k``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from .base import Block, FloatArray, IntArray, Loads, NodeRows

if TYPE_CHECKING:
    from ..model import Model

NEAR_BARS = 3.0
"""Nodes closer to touching the wall than this many bar lengths get a row."""

NEAR_FRACTION = 0.25
"""… or closer than this fraction of the lumen radius there (the distance from the wall of the lumen's centre)."""

PLANE_TOLERANCE = 10.0
"""A tangent line its node touches is moved when the true clearance of the node differs from the line's by more than
this times the solve tolerance ``tol · max(1, L)`` (mm)."""

TOUCHING_BARS = 0.1
"""A node within this many bar lengths of its line touches it (only those lines need to be exact)."""


def _needed(model: Model, curvature: FloatArray, nodes: IntArray) -> FloatArray:
    """Clearance each node needs (mm): the wire's radius plus the sag of its longer bar's chord on a bulging wall."""
    lengths = model.chain.lengths
    bar = np.maximum(lengths[np.minimum(nodes, lengths.size) - 1], lengths[np.minimum(nodes, lengths.size - 1)])
    return 0.5 * model.scene.wire.diameter + bar**2 * np.maximum(curvature, 0.0) / 8.0


@dataclass(frozen=True)
class Lumen(Block):
    """Tangent-line rows ``n_k · p_k ≤ offset_k`` keeping the nodes of the working set inside ``scene.vessel``.

    Attributes
    ----------
    normals : ndarray, shape (rows, 2)
        Outward unit normal of the wall at each row's linearisation point.
    offsets : ndarray, shape (rows,)
        ``n_k · b_k − needed clearance`` (mm).
    """

    kind: ClassVar[str] = "lumen"
    normals: FloatArray = field(default_factory=lambda: np.zeros((0, 2)), compare=False)
    offsets: FloatArray = field(default_factory=lambda: np.zeros(0), compare=False)

    @classmethod
    def build(cls, model: Model, working_set: Any = None) -> list[Block]:
        vessel = getattr(model.scene, "vessel", None)
        if vessel is None:
            return []
        points = model.chain.nodes(model.x0)
        if working_set is None:
            nodes = np.arange(1, model.n + 1)
        elif isinstance(working_set, str):
            nodes = cls._near(model, points)
        else:
            nodes = np.unique(np.asarray(working_set.get(("lumen", (0,)), np.arange(1, model.n + 1)), dtype=int))
        return [cls._linearised(model, nodes, points)]

    @staticmethod
    def _near(model: Model, points: FloatArray) -> IntArray:
        """Nodes 1..n near touching the wall (at least the closest one)."""
        c = model.scene.vessel.clearance(points[1:])
        slack = c.distance - _needed(model, c.curvature, np.arange(1, model.n + 1))
        band = np.maximum(NEAR_BARS * float(np.max(model.chain.lengths)), NEAR_FRACTION * np.maximum(c.distance, 0.0))
        near = np.flatnonzero(slack <= band) + 1
        return near if near.size else np.array([int(np.argmin(slack)) + 1])

    @classmethod
    def _linearised(cls, model: Model, nodes: IntArray, points: FloatArray) -> Lumen:
        c = model.scene.vessel.clearance(points[nodes])
        offsets = np.einsum("ij,ij->i", c.normal, c.boundary) - _needed(model, c.curvature, nodes)
        return cls((0,), np.asarray(nodes, dtype=int), normals=c.normal, offsets=offsets)

    def rows(self, model: Model) -> NodeRows:
        return NodeRows(self.nodes, -self.normals, -self.offsets, np.full(self.size, np.inf))

    def add_loads(self, model: Model, lam: FloatArray, loads: Loads) -> None:
        np.add.at(loads.node_forces, self.nodes, -np.asarray(lam, dtype=float)[:, None] * self.normals)

    def slack(self, model: Model, points: FloatArray) -> FloatArray:
        """True clearance minus the clearance needed, at every node 1..n (mm; negative: outside the lumen)."""
        c = model.scene.vessel.clearance(points[1:])
        return c.distance - _needed(model, c.curvature, np.arange(1, model.n + 1))

    def violation(self, model: Model, phi: FloatArray, points: FloatArray | None = None) -> FloatArray:
        """Violation at *every* node 1..n against the true (curved) lumen, not only the working set's lines."""
        points = model.chain.nodes(phi) if points is None else points
        return np.maximum(-self.slack(model, points), 0.0)

    def refine(self, model: Model, phi: FloatArray, tolerance: float) -> Block | None:
        """Add the nodes that leave the lumen (and their neighbours) and move every line touched by its node whose
        true clearance differs from the line's by more than :data:`PLANE_TOLERANCE` ``× tolerance`` to the wall
        point nearest the node; None when neither is needed."""
        points = model.chain.nodes(phi)
        slack = self.slack(model, points)
        violated = np.flatnonzero(slack < -tolerance) + 1
        line_slack = self.offsets - np.einsum("ij,ij->i", self.normals, points[self.nodes])
        touching = line_slack <= TOUCHING_BARS * float(np.max(model.chain.lengths))
        stale = touching & (np.abs(slack[self.nodes - 1] - line_slack) > PLANE_TOLERANCE * tolerance)
        if not violated.size and not np.any(stale):
            return None
        extra = np.clip(np.concatenate([violated - 1, violated, violated + 1]), 1, model.n)
        nodes = np.union1d(self.nodes, extra)
        return replace(self._linearised(model, nodes, points), index=self.index)
