"""Contacts with a prescribed position: ``p_k = P`` (paper Eqs. 20–21), two rows (x, y) per contact."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from .base import Block, FloatArray, IntArray, Loads, NodeRows, WorkingSet

if TYPE_CHECKING:
    from ..program.model import Model


@dataclass(frozen=True)
class Position(Block):
    """``x_k = P_x``, ``y_k = P_y`` for every contact with a point, in contact order (rows x₁, y₁, x₂, y₂, …).

    Multipliers: the force (N) each contact exerts on the wire, ``(F_x, F_y)``.
    """

    kind: ClassVar[str] = "position"

    @classmethod
    def build(cls, model: Model, working_set: WorkingSet = None) -> list[Block]:
        ids = [i for i, c in enumerate(model.scene.contacts) if c.point is not None]
        if not ids:
            return []
        return [cls(tuple(ids), np.repeat(model.contact_nodes[ids], 2))]

    def rows(self, model: Model) -> NodeRows:
        targets = np.array([model.scene.contacts[i].point for i in self.members], dtype=float).ravel()
        axes = np.tile(np.eye(2), (len(self.members), 1))
        return NodeRows(self.nodes, axes, targets, targets)

    @property
    def row_keys(self) -> IntArray:
        return np.arange(self.size)

    def add_loads(self, model: Model, lam: FloatArray, loads: Loads, points: FloatArray) -> None:
        for i, force in zip(self.members, np.reshape(lam, (-1, 2)), strict=True):
            loads.forces[i] = force.copy()
