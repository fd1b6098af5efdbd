"""The working-set rounds of a vessel solve and the branch starts of ``branches="lowest"`` (issue 27).

A vessel's lumen rows are tangent planes of the wall at the nodes near it; :func:`guidewire.solve` solves, moves the
planes to the answer and solves again until they fit. An answer whose rounds ran out is feasible but may be held by
a plane where the wall is not: it is no success, its message names the row, and it carries no forces.
"""

from __future__ import annotations

import sys
from importlib import resources

import numpy as np
import pytest

import guidewire
from guidewire.solve.branches import route_starts

VESSELS = resources.files("guidewire") / "scenes" / "vessels"
PIPELINE = sys.modules["guidewire.solve.pipeline"]


def _scene(name: str, length: float | None = None) -> guidewire.Scene:
    scene = guidewire.load_scene(str(VESSELS / f"{name}.toml"))
    return scene if length is None else scene.with_wire(length=length, bars=round(length))


@pytest.mark.parametrize(("name", "length"), [("bend", None), ("tortuous", None)])
def test_an_answer_whose_rounds_ran_out_is_rejected_with_the_row_that_did_not_fit(monkeypatch, name, length):
    """With one round allowed, scenes that need more (measured: bend 2, tortuous 7) converge on planes that do not
    fit the answer: the solve fails with SHAPE_REJECTED, names the lumen row's node, its arc length and the distance,
    and reports no force; with the rounds it needs, the same scene succeeds."""
    scene = _scene(name, length)
    full = guidewire.solve(scene, branches="first")
    assert full.success and full.rounds >= 2
    monkeypatch.setattr(PIPELINE, "MAX_ROUNDS", 1)
    cut = guidewire.solve(scene, branches="first")
    assert cut.rounds == 1
    assert not cut.success and cut.status == guidewire.Status.SHAPE_REJECTED
    assert "rounds ran out" in cut.message and "lumen" in cut.message and " mm from the constraint" in cut.message
    node = int(cut.message.split("row at node ")[1].split()[0])
    assert 0 < node <= cut.n_bars and f"(s = {cut.s[node]:.4g} mm)" in cut.message
    assert all(r.force is None for r in cut.reactions) and cut.wall_forces is None


def test_a_start_given_through_a_branch_returns_a_result_not_a_traceback():
    """The aortic arch's wire of 200 mm started along the way into its third branch (junction at 176.5 mm): the
    rounds run out (the planes at the branch's opening keep moving), and the solve returns a result whose rows
    belong to the program it solved (it raised a broadcasting ValueError when the last refinement's rows were paired
    with the previous program's multipliers)."""
    scene = _scene("aortic_arch", 200.0)
    labels = [label for label, _ in route_starts(scene)]
    assert labels == ["branch start 3"]  # (branches 1 and 2 leave at 220.5 and 204.5 mm: beyond the wire)
    sol = guidewire.solve(scene, initial_angles=route_starts(scene)[0][1], branches="first")
    assert sol.success or sol.status == guidewire.Status.SHAPE_REJECTED
    assert np.isfinite(sol.energy) and sol.nodes.shape == (201, 2)


@pytest.mark.parametrize("length", [66.0, 70.0, 80.0])
def test_lowest_tries_the_way_through_a_branch(length):
    """``s_bend_branch`` beyond the branch: the start along the main centreline ends in the S (5.39-5.88 N·mm), the
    start through the branch lower, inside the branch's lumen; ``branches="first"`` keeps the first, ``"lowest"``
    the branch's, and says which start gave it."""
    scene = _scene("s_bend_branch", length)
    first = guidewire.solve(scene, branches="first")
    lowest = guidewire.solve(scene)
    assert first.success and lowest.success and lowest.starts == 2
    assert lowest.energy < first.energy * (1.0 - 1e-3)
    assert "branch start 1" in lowest.message
    radius = 0.5 * scene.wire.diameter
    assert scene.vessel.lumen_clearance(lowest.nodes).min() >= radius - 1e-6 * length
    depths = scene.vessel.tube_depths(lowest.nodes[50:51])[0]  # the wire's point at s = 50 mm: in the branch
    assert depths[1] > depths[0]


def test_route_starts_follow_each_reachable_branch():
    """One start per branch leaving before the last bar's midpoint, each bar along the route's tangent there."""
    arch = _scene("aortic_arch")
    junctions = [arch.vessel.junction(b) for b in range(len(arch.vessel.branches))]
    for length in (150.0, 180.0, 210.0, 250.0):
        scene = arch.with_wire(length=length, bars=round(length))
        starts = route_starts(scene)
        reach = [b for b, s in enumerate(junctions) if s < length - 0.5]
        assert [label for label, _ in starts] == [f"branch start {b + 1}" for b in reach]
        s_mid = np.arange(round(length)) + 0.5
        for (_, angles), b in zip(starts, reach, strict=True):
            _, tangent = arch.vessel.route(s_mid, b)
            assert np.allclose(np.cos(angles), np.cos(tangent)) and np.allclose(np.sin(angles), np.sin(tangent))
    assert route_starts(_scene("bend")) == []


@pytest.mark.parametrize("length", [22.5, 27.0])
def test_coarse_bars_in_the_tortuous_vessel_settle_within_the_rounds(length):
    """2 mm bars in the tortuous coronary vessel: the lumen rows move towards the answer's wall points by a ratio of
    ~0.18 a round, so the rows need 9-10 rounds to fit the answer to the solve's tolerance (8 rejected both lengths);
    the answer is accepted, every node inside the lumen."""
    scene = guidewire.load_scene(str(VESSELS / "tortuous.toml"))
    sol = guidewire.solve(scene.with_wire(length=length, bars=round(0.5 * length)), branches="first")
    assert sol.success and 8 < sol.rounds <= PIPELINE.MAX_ROUNDS
