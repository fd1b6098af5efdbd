"""Solving one scene: the front door :func:`solve` (:mod:`.front`), the mirror starts of :mod:`.branches`, the
error-controlled refinement of :mod:`.refine`, and the :class:`Solution` (:mod:`.result`)."""

from .front import solve
from .result import Reaction, Solution

__all__ = ["Reaction", "Solution", "solve"]
