"""Half-plane walls ``n̂ · p_k ≤ offset`` at the nodes (paper Eqs. 23–24), one block per wall.

Rows are written as ``−n̂ · p_k ≥ −offset`` (a lower bound), so the multiplier ``λ_k ≥ 0`` is the magnitude of the
wall's push on node ``k`` and ``λ_k d = −λ_k n̂`` its force. The base node is fixed and checked once, before solving.
A wall constrains a *working set* of nodes: those of the start within :data:`WORKING_DISTANCE` ``× L`` of it, grown
by :meth:`Wall.refine` with every node found violating it (and its neighbours) until none does."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from .base import Block, FloatArray, IntArray, Loads, NodeRows, WorkingSet, grown_by_neighbours

if TYPE_CHECKING:
    from ..program.model import Model

WORKING_DISTANCE = 0.25
"""Nodes of the start closer to a wall than this fraction of the wire length get a wall row in the working set."""


def near_nodes(points: FloatArray, normal: FloatArray, offset: float, length: float) -> IntArray:
    """Nodes 1..n within ``WORKING_DISTANCE · L`` of the wall ``n̂·p ≤ offset`` (at least the closest one)."""
    gap = offset - points[1:] @ np.asarray(normal)
    near = np.flatnonzero(gap <= WORKING_DISTANCE * length) + 1
    return near if near.size else np.array([int(np.argmin(gap)) + 1])


@dataclass(frozen=True)
class Wall(Block):
    """``offset − n̂ · p_k ≥ 0`` (mm) for the nodes of the working set of wall ``members[0]``."""

    kind: ClassVar[str] = "wall"

    @classmethod
    def build(cls, model: Model, working_set: WorkingSet = None) -> list[Block]:
        out: list[Block] = []
        n = model.n
        start = model.chain.nodes(model.x0) if model.scene.walls and isinstance(working_set, str) else None
        for j, wall in enumerate(model.scene.walls):
            normal, offset = wall.unit()
            if working_set is None:
                nodes = np.arange(1, n + 1)
            elif isinstance(working_set, str):
                if working_set != "near":
                    raise ValueError(f"working_set is {working_set!r}; expected None, 'near' or a mapping.")
                nodes = near_nodes(start, np.asarray(normal), offset, model.scene.wire.length)
            else:
                nodes = np.unique(np.asarray(working_set.get(("wall", (j,)), np.arange(1, n + 1)), dtype=int))
            out.append(cls((j,), nodes))
        return out

    def rows(self, model: Model) -> NodeRows:
        normal, offset = model.scene.walls[self.members[0]].unit()
        m = self.size
        return NodeRows(self.nodes, np.tile(-np.asarray(normal, dtype=float), (m, 1)), np.full(m, -offset),
                        np.full(m, np.inf))

    def add_loads(self, model: Model, lam: FloatArray, loads: Loads, points: FloatArray) -> None:
        normal, _ = model.scene.walls[self.members[0]].unit()
        np.add.at(loads.node_forces, self.nodes, -np.asarray(lam, dtype=float)[:, None] * np.asarray(normal))

    def gaps(self, model: Model, points: FloatArray) -> FloatArray:
        """``offset − n̂ · p_k`` at every node 1..n (negative: violated), mm."""
        normal, offset = model.scene.walls[self.members[0]].unit()
        return offset - points[1:] @ np.asarray(normal)

    def violation(self, model: Model, phi: FloatArray, points: FloatArray | None = None,
                  rows: Any = None) -> FloatArray:
        """Violation at *every* node 1..n, not only the working set (the answer must respect the whole wall; ``rows``
        is not read)."""
        points = model.chain.nodes(phi) if points is None else points
        return np.maximum(-self.gaps(model, points), 0.0)

    def violation_nodes(self, model: Model) -> IntArray:
        """Every node 1..n (:meth:`violation` checks them all)."""
        return np.arange(1, model.n + 1)

    def describe(self, model: Model) -> str:
        return f"wall {self.members[0]} (the wire beyond it)"

    def refine(self, model: Model, phi: FloatArray, tolerance: float) -> Block | None:
        violated = np.flatnonzero(self.gaps(model, model.chain.nodes(phi)) < -tolerance) + 1
        if not violated.size:
            return None
        nodes = grown_by_neighbours(self.nodes, violated, model.n)
        return None if nodes.size == self.nodes.size else replace(self, nodes=nodes)

    def contact_normals(self, scene: Any) -> FloatArray:
        normal, _ = scene.walls[self.members[0]].unit()
        return np.tile(np.asarray(normal, dtype=float), (self.size, 1))

    def advanced(self, bars: int) -> Block:
        return replace(self, nodes=self.nodes + bars)

    def with_tip(self, old: int, new: int) -> Block:
        return replace(self, nodes=np.where(self.nodes == old, new, self.nodes))
