"""A large vessel solve starts from the answer of the same scene at a quarter of its bars (at least 100)
(:func:`guidewire.solve.pipeline.nested_start`): the same answer as from the default start, in fewer iterations, and
the default start again when the coarse solve fails."""

from __future__ import annotations

from dataclasses import replace
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

import guidewire
from guidewire.solve import pipeline
from guidewire.solve.options import SolveOptions

VESSELS = Path(str(resources.files("guidewire") / "scenes" / "vessels"))
CASES = [("tortuous", None), ("s_bend", None), ("aortic_arch", 250.0)]
BARS = 400


def _scene(name: str, length: float | None) -> guidewire.Scene:
    scene = guidewire.load_scene(VESSELS / f"{name}.toml")
    return scene if length is None else scene.with_wire(length=length)


def _plain(scene: guidewire.Scene, monkeypatch: pytest.MonkeyPatch, bars: int = BARS) -> guidewire.Solution:
    with monkeypatch.context() as patch:
        patch.setattr(pipeline, "NESTED_FROM", 10**9)  # (no scene is that large: the default start)
        return guidewire.solve(scene, bars=bars, branches="first")


def _coarse(bars: int) -> int:
    return max(pipeline.NESTED_MIN_BARS, bars // pipeline.NESTED_RATIO)


@pytest.mark.parametrize("bars", [250, BARS, 560])  # (the dense program of bar angles at 250, the full space above)
@pytest.mark.parametrize(("name", "length"), CASES)
def test_a_nested_start_reaches_the_default_starts_answer_in_fewer_iterations(name, length, bars, monkeypatch):
    scene = _scene(name, length)
    nested = guidewire.solve(scene, bars=bars, branches="first")
    plain = _plain(scene, monkeypatch, bars)
    assert nested.success and plain.success, (nested.message, plain.message)
    assert nested.coarse_bars == (_coarse(bars),) and plain.coarse_bars == ()
    assert nested.to_dict()["coarse_bars"] == [_coarse(bars)]
    # one branch: the energies within the multi-start's tie (a relative 1e-6), the nodes within 1 % of a bar
    assert abs(nested.energy - plain.energy) <= 1e-6 * plain.energy
    assert np.max(np.hypot(*(nested.nodes - plain.nodes).T)) <= 1e-2 * scene.wire.length / bars
    # the fine program starts where the lumen's rows already model the answer's walls: fewer rounds, fewer iterations
    assert nested.rounds < plain.rounds and nested.iterations < plain.iterations


@pytest.mark.parametrize(("name", "length"), CASES)
def test_the_nested_start_lies_inside_the_lumen_on_the_coarse_answers_chords(name, length):
    """Every node of the interpolated start clears the wall by the wire's radius (up to the chord rule's rounding):
    the coarse answer's rows keep its chords inside, and the start's nodes lie on them at the fine arc lengths."""
    scene = _scene(name, length)
    made = pipeline.nested_start(scene, SolveOptions(branches="first"), BARS, 0.0)
    assert made is not None
    nodes, coarse = made
    assert coarse.success and coarse.n_bars == _coarse(BARS) and coarse.coarse_bars == ()
    assert nodes.shape == (BARS + 1, 2)
    bars = np.hypot(*np.diff(nodes, axis=0).T)
    assert np.all(bars <= scene.wire.length / BARS * (1.0 + 1e-9))  # chords of a bent polyline: never longer
    clearance = scene.vessel.clearance(nodes[1:]).distance
    assert np.min(clearance - 0.5 * scene.wire.diameter) >= -1e-6


def test_a_failed_coarse_solve_leaves_the_default_start(monkeypatch):
    scene = _scene("tortuous", None)
    original = pipeline.solve_once

    def coarse_fails(scene, options, start):
        sol = original(scene, options, start)
        return replace(sol, success=False) if options.bars == _coarse(BARS) else sol

    monkeypatch.setattr(pipeline, "solve_once", coarse_fails)
    sol = guidewire.solve(scene, bars=BARS, branches="first")
    monkeypatch.undo()
    plain = _plain(scene, monkeypatch)
    assert sol.success and sol.coarse_bars == ()
    assert sol.energy == plain.energy and sol.iterations == plain.iterations


@pytest.mark.parametrize("given", ["initial_angles", "bars_below"])
def test_a_given_start_or_a_small_chain_is_not_nested(given):
    scene = _scene("bend", None)
    if given == "initial_angles":
        start = guidewire.formulate(scene.with_bars(BARS)).model.x0
        sol = guidewire.solve(scene, bars=BARS, initial_angles=start)
    else:
        sol = guidewire.solve(scene, bars=pipeline.NESTED_FROM * pipeline.NESTED_MIN_BARS - 1, branches="first")
    assert sol.success and sol.coarse_bars == ()


@pytest.mark.parametrize(("name", "length", "bars"), [("aortic_arch", 230.0, 240), ("s_bend_branch", 70.0, 240)])
def test_the_candidate_starts_are_nested_too_and_the_lowest_answer_is_no_higher(name, length, bars, monkeypatch):
    """``branches="lowest"`` in a branched vessel: each branch start is solved at the coarse bars first (from the
    start's own nodes there), then from that answer; the lowest answer is at least as low as from the starts as
    given (on these two: the arch's same minimum, the S-bend's branch a lower one)."""
    scene = _scene(name, length)
    nested = guidewire.solve(scene, bars=bars)
    with monkeypatch.context() as patch:
        patch.setattr(pipeline, "NESTED_FROM", 10**9)
        plain = guidewire.solve(scene, bars=bars)
    assert nested.success and plain.success and nested.starts == plain.starts > 1
    assert nested.coarse_bars == (_coarse(bars),)
    assert nested.energy <= plain.energy * (1.0 + 1e-6)


def test_a_coarse_solve_that_stalls_is_not_retried_with_damped_bfgs(monkeypatch):
    """The arch at 240 mm, 240 bars, ``branches="lowest"``: one candidate's coarse solve stalls (its iteration limit);
    a start is not worth the damped-BFGS retry (4 s there), so the candidate's fine solve starts as given, and the
    answer is the one the starts as given reach."""
    scene = _scene("aortic_arch", 240.0).with_bars(240)
    calls = []
    original = pipeline.solve_once

    def spied(scene, options, start):
        sol = original(scene, options, start)
        calls.append((options.bars, options.bfgs_retry, sol))
        return sol

    monkeypatch.setattr(pipeline, "solve_once", spied)
    nested = guidewire.solve(scene)
    coarse = [(retry, sol) for bars, retry, sol in calls if bars == _coarse(240)]
    # (every coarse solve: no retry, so no answer from one; on this machine one of the four stalls at its limit)
    assert coarse and all(not retry and sol.fallback is None for retry, sol in coarse)
    monkeypatch.undo()
    with monkeypatch.context() as patch:
        patch.setattr(pipeline, "NESTED_FROM", 10**9)
        plain = guidewire.solve(scene)
    assert nested.success and abs(nested.energy - plain.energy) <= 1e-6 * plain.energy


def test_the_cli_summary_says_where_the_start_came_from():
    from guidewire.app.cli import _summary

    scene = _scene("s_bend", None)
    nested = guidewire.solve(scene, bars=250, branches="first")
    small = guidewire.solve(scene, bars=150, branches="first")
    assert f"(from the answer at {_coarse(250)} bars)" in _summary(nested)
    assert "from the answer at" not in _summary(small)


def test_a_candidate_whose_coarse_solve_fails_is_dropped(monkeypatch):
    """A candidate start of ``branches="lowest"`` whose coarse solve fails is not solved at the fine bars from its
    start as given (where such starts crept to their iteration limits too); the first start's answer is kept."""
    scene = _scene("s_bend_branch", 70.0)
    original, solve_in = pipeline.solve_once, pipeline._solve_in
    programs = []

    def coarse_candidates_fail(scene, options, start):
        sol = original(scene, options, start)
        return replace(sol, success=False) if options.nest_start and options.bars == _coarse(240) else sol

    def spied_in(scene, options, layout, *args, **kwargs):
        programs.append((options.bars, options.nest_start))
        return solve_in(scene, options, layout, *args, **kwargs)

    monkeypatch.setattr(pipeline, "solve_once", coarse_candidates_fail)
    monkeypatch.setattr(pipeline, "_solve_in", spied_in)
    sol = guidewire.solve(scene, bars=240)
    monkeypatch.undo()
    first = guidewire.solve(scene, bars=240, branches="first")
    # the candidates' coarse programs were solved, their fine ones never
    assert (_coarse(240), True) in programs and (240, True) not in programs
    assert sol.success and sol.starts > 1 and sol.energy == first.energy
