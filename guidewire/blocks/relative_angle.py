"""The paper's bound on the joint angles, ``−b₂ ≤ Δθ ≤ b₂`` (Eq. 19), with ``wire.max_relative_angle = b₂``.

In absolute bar angles a joint angle is a difference of neighbours (or of a bar and a prescribed tangent), so the
rows stay exact and linear; one row per node with a joint, the node's total angle jump."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from .base import AngleRows, Block, WorkingSet

if TYPE_CHECKING:
    from ..program.model import Model


@dataclass(frozen=True)
class RelativeAngle(Block):
    """``−b₂ ≤ D_node φ − r_node ≤ b₂`` for every node with a joint. Multipliers: internal moments (N·mm); the
    bound is internal to the wire, so it exerts no load on it."""

    kind: ClassVar[str] = "relative_angle"
    unit: ClassVar[str] = "rad"

    @classmethod
    def build(cls, model: Model, working_set: WorkingSet = None) -> list[Block]:
        if model.scene.wire.max_relative_angle is None:
            return []
        joint_nodes = np.unique(model.energy.node)
        return [cls(tuple(int(k) for k in joint_nodes), joint_nodes)]

    def rows(self, model: Model) -> AngleRows:
        node_rows, node_offsets = model.energy.node_rows(model.n + 1)
        b2 = model.scene.wire.max_relative_angle
        offsets = node_offsets[self.nodes]
        return AngleRows(node_rows[self.nodes], offsets - b2, offsets + b2)
