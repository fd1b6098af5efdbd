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


def test_a_candidate_start_that_fails_in_the_full_space_is_dropped_not_solved_densely(monkeypatch):
    """``branches="lowest"`` on the aortic arch at 240 mm and 480 bars: a candidate start whose full-space solve
    fails is dropped, not retried in the dense program (O(n³) an iteration: at 960 bars one such retry took 65 s and
    ended rejected); the answer is the lowest of the starts that succeeded."""
    scene = _scene("aortic_arch", 240.0, 480)
    calls, answers = [], []
    solve_in, solve_once = PIPELINE._solve_in, PIPELINE.solve_once

    def spied_in(scene, options, layout, *args, **kwargs):
        calls.append((layout, options.dense_retry))
        return solve_in(scene, options, layout, *args, **kwargs)

    def spied_once(*args, **kwargs):
        answers.append(solve_once(*args, **kwargs))
        return answers[-1]

    monkeypatch.setattr(PIPELINE, "_solve_in", spied_in)
    monkeypatch.setattr(PIPELINE, "solve_once", spied_once)
    # (from the nested starts every candidate succeeds there: the starts as given, one of which fails)
    monkeypatch.setattr(PIPELINE, "NESTED_FROM", 10**9)
    lowest = guidewire.solve(scene)
    candidates = answers[1:]
    dropped = [a for a in candidates if not a.success]
    assert dropped and all("no retry in the dense program" in a.message for a in dropped)
    assert {layout for layout, retry in calls if not retry} == {"full"}
    assert lowest.success and lowest.energy == min(a.energy for a in answers if a.success)
