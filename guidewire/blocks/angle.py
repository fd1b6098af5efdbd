"""Contacts with a prescribed tangent in the paper's scheme: ``φ_k = θ*`` on the bar ending at the contact node
(paper Eqs. 16–18). In the second-order scheme a prescribed tangent is an energy term and this block is absent."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np
import scipy.sparse as sp

from .base import AngleRows, Block, FloatArray, Loads, WorkingSet

if TYPE_CHECKING:
    from ..program.model import Model


@dataclass(frozen=True)
class Angle(Block):
    """One row ``φ_k = θ*`` per contact with an angle (scheme ``"paper"`` only), in contact order.

    Multipliers: the moment (N·mm, counter-clockwise) each contact exerts on the wire.
    """

    kind: ClassVar[str] = "angle"
    unit: ClassVar[str] = "rad"

    @classmethod
    def build(cls, model: Model, working_set: WorkingSet = None) -> list[Block]:
        ids = [i for i, c in enumerate(model.scene.contacts) if c.angle is not None]
        if model.scene.wire.scheme != "paper" or not ids:
            return []
        return [cls(tuple(ids), model.contact_nodes[ids])]

    def rows(self, model: Model) -> AngleRows:
        m, n = self.size, model.n
        A = sp.csr_matrix((np.ones(m), (np.arange(m), self.nodes - 1)), shape=(m, n))
        theta = np.array([model.scene.contacts[i].angle for i in self.members], dtype=float)
        return AngleRows(A, theta, theta)

    def add_loads(self, model: Model, lam: FloatArray, loads: Loads, points: FloatArray) -> None:
        loads.moments.update(zip(self.members, np.asarray(lam, dtype=float).tolist(), strict=True))
