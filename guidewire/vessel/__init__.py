"""Vessel lumens: centreline curves (:mod:`.curves`), their tube geometry (:mod:`.geometry`) and the
:class:`Vessel` a scene carries (:mod:`.vessel`)."""

from .vessel import Branch, Clearance, Vessel

__all__ = ["Branch", "Clearance", "Vessel"]
