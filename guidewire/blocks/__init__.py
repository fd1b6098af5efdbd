"""Constraint blocks: one small type per kind of constraint (see :mod:`guidewire.blocks.base`).

:data:`BLOCK_TYPES` is the registry: a formulation asks each type, in this order, for the blocks its scene needs.
A new kind (say, lumen rows keeping every node inside a vessel) is one new module defining a :class:`Block` subclass
and one more entry here."""

from .angle import Angle
from .base import AngleRows, Block, Loads, NodeRows, Rows, WorkingSet
from .lumen import Lumen
from .position import Position
from .relative_angle import RelativeAngle
from .wall import Wall

BLOCK_TYPES: tuple[type[Block], ...] = (Position, Angle, Wall, Lumen, RelativeAngle)

__all__ = ["BLOCK_TYPES", "Angle", "AngleRows", "Block", "Loads", "Lumen", "NodeRows", "Position", "RelativeAngle",
           "Rows", "Wall", "WorkingSet"]
