"""Many scenes or insertions at once on any executor (:mod:`.scenes`, :mod:`.insertions`), and the resumable
JSON-lines run of ``python -m guidewire batch`` (:mod:`.files`)."""

from .insertions import insert_many
from .scenes import SceneError, solve_many

__all__ = ["SceneError", "insert_many", "solve_many"]
