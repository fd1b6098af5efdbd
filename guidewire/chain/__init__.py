"""The bar chain: bar layouts and kinematics (:mod:`.kinematics`), bars graded by curvature (:mod:`.density`) and
self-crossing of a chain of segments (:mod:`.crossing`)."""

from .kinematics import BarChain, explicit_bars, place_bars, scene_bars

__all__ = ["BarChain", "explicit_bars", "place_bars", "scene_bars"]
