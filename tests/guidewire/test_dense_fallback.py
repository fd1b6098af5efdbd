"""The dense program that stands in for a failed full-space vessel solve has a bounded number of iterations.

Above ``FULL_SPACE_BARS`` a vessel scene is solved in the full space; when that fails, the dense program of bar
angles (O(n³) an iteration) is the last resort. It converges in the iterations a vessel step needs, but unbounded it
would spend the engine's 500 a round on a step that does not, minutes at ~1 000 bars: it gets
``DENSE_FALLBACK_ITER`` over its rounds, and so does its damped-BFGS retry.
"""

from __future__ import annotations

import sys
from importlib import resources

import pytest

import guidewire

VESSELS = resources.files("guidewire") / "scenes" / "vessels"
PIPELINE = sys.modules["guidewire.solve.pipeline"]


def _scene(name: str, length: float, bars: int) -> guidewire.Scene:
    return guidewire.load_scene(str(VESSELS / f"{name}.toml")).with_wire(length=length, bars=bars)


@pytest.mark.parametrize(("name", "length", "bars"), [("bend", 40.0, 320), ("s_bend", 45.0, 330),
                                                      ("tortuous", 40.0, 340)])
def test_the_dense_fallback_stops_within_its_budget_and_reaches_the_full_space_answer(monkeypatch, name, length,
                                                                                       bars):
    """With the full space cut to one iteration a round (so it fails), the dense program answers: with its default
    budget at the full-space solve's energy (to the solver's tolerance); with a budget of 2 iterations it stops
    there (with its BFGS retry, at most 2 + 2 iterations beyond the full space's 8 rounds of one)."""
    scene = _scene(name, length, bars)
    full = guidewire.solve(scene, branches="first")
    assert full.success and full.layout == "full"
    monkeypatch.setattr(PIPELINE, "FULL_VESSEL_ITER", 1)
    dense = guidewire.solve(scene, branches="first")
    assert dense.success and dense.layout == "reduced"
    assert abs(dense.energy - full.energy) <= 1e-6 * max(1.0, abs(full.energy))
    monkeypatch.setattr(PIPELINE, "DENSE_FALLBACK_ITER", 2)
    cut = guidewire.solve(scene, branches="first")
    assert cut.iterations <= PIPELINE.MAX_ROUNDS * 1 + 2 + 2
