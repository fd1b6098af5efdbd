"""Why a guidewire solve ended: :class:`Status`, an ``IntEnum`` whose members are :class:`sqp.Status`'s (same names,
codes and messages: a run of the engine ends the solve) and the outcomes guidewire adds on top of a run, numbered
from 20 on (sqp's own use 0-15 and 99)."""

from __future__ import annotations

from collections.abc import Sequence
from enum import IntEnum
from typing import Any

import sqp


class _Coded(IntEnum):
    """An ``IntEnum`` whose members carry a message (as :class:`sqp.Status`'s do)."""

    message: str

    def __new__(cls, code: int, message: str) -> _Coded:
        member = int.__new__(cls, code)
        member._value_ = code
        member.message = message
        return member

    @property
    def code(self) -> int:
        """The number (``Solution.status``)."""
        return int(self)

    @property
    def success(self) -> bool:
        """Whether the status counts as a success (SUCCESS and ACCEPTABLE)."""
        return self.name in ("SUCCESS", "ACCEPTABLE")


#: Outcomes guidewire adds to sqp's: the run converged but the shape fails a check a user would see
#: (:func:`guidewire.solve.result.shape_defect`: bars crossing each other or leaving the vessel).
GUIDEWIRE_STATUSES = {
    "SHAPE_REJECTED": (20, "The solver converged, but to a shape that fails a check a user would see (bars crossing "
                           "each other, or the wire leaving the vessel)."),
    "SCENE_REFUSED": (21, "The scene was refused before any solve (a value out of range, or a scene that cannot be "
                          "met, such as contacts farther apart than the wire is long); the message says which."),
}

Status = _Coded("Status", {**{s.name: (s.code, s.message) for s in sqp.Status}, **GUIDEWIRE_STATUSES},
                module=__name__)
Status.__doc__ = """Why a solve ended (``Solution.status``): every :class:`sqp.Status` (same name, code and message)
and :data:`GUIDEWIRE_STATUSES` (SHAPE_REJECTED = 20, SCENE_REFUSED = 21)."""

#: ``Solution.status`` of a run that converged to a shape failing :func:`guidewire.solve.result.shape_defect`.
SHAPE_REJECTED = Status.SHAPE_REJECTED


def outcome(steps: Sequence[Any], error: str | None) -> Any:
    """The :class:`Status` of a run of steps (an insertion, a sequence): the first failed step's, else SCENE_REFUSED
    when a step's scene was refused before solving (``error``), else SUCCESS."""
    for step in steps:
        if not step.success:
            return Status(step.status)
    return Status.SCENE_REFUSED if error is not None else Status.SUCCESS
