"""No contact holds a frictionless wire lengthwise, not even a vessel's corner, so the entrance push is dE/dL.

A frictionless wire on smooth walls is touched along its normal, so pushing it ΔL further costs ΔE: the entrance push
is dE/dL (``test_vessel_solve.test_entrance_push_is_the_energy_rate``). At a branch's opening the wall turns sharply
into the lumen at a corner: a row on a node's distance from the corner meets the wire at an angle and held it
lengthwise, as friction would (0.1-0.6 N past ``s_bend_branch``'s corner, the push off by as much, even negative while
the energy rose). The corner's row is on the distance of the bar that passes it (:mod:`guidewire.blocks.lumen`),
whose force is normal to the bar.
"""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

import guidewire
from guidewire.march.insertion import TANGENTIAL_LIMIT_N, step_flags

VESSELS = resources.files("guidewire") / "scenes" / "vessels"
STEP = 0.5


def _insertion(name: str, first: float, last: float, density: float) -> tuple[np.ndarray, list]:
    scene = guidewire.load_scene(f"{VESSELS}/{name}.toml")
    lengths = np.arange(first, last + 1e-9, STEP)
    out = guidewire.insert(scene.with_wire(length=first, bars=round(first * density)), lengths)
    assert out.complete and all(s.success for s in out.steps)
    return lengths, out.steps


def _smooth_rates(lengths: np.ndarray, steps: list, tol: float = 0.01) -> tuple[np.ndarray, np.ndarray]:
    """The energy's rate along the insertion (central differences) at the steps where it has one: the forward and
    backward differences agree to ``tol`` (N) — no contact made, lost or moved to another node across the step —
    and those steps' indices."""
    energy = np.array([s.energy for s in steps])
    slopes = np.diff(energy) / np.diff(lengths)
    inner = np.flatnonzero(np.abs(slopes[1:] - slopes[:-1]) <= tol) + 1
    return 0.5 * (slopes[inner - 1] + slopes[inner]), inner


@pytest.fixture(scope="module", params=[2.0, 4.0])
def corner(request):
    """``s_bend_branch`` at 2 and 4 bars/mm, its wire pushed past the branch's corner (38-46 mm)."""
    return _insertion("s_bend_branch", 34.0, 46.0, request.param)


def test_smooth_walls_hold_the_wire_along_its_normal_only():
    lengths, steps = _insertion("s_bend", 30.0, 42.0, 4.0)
    along = np.array([s.tangential_contact_force() for s in steps])
    push = np.array([s.entrance_force() for s in steps])
    assert np.max(np.abs(along)) <= 0.2 * TANGENTIAL_LIMIT_N
    assert not any("lengthwise" in f or "along its length" in f for s in steps for f in step_flags(s, "warm"))
    rates, where = _smooth_rates(lengths, steps)
    assert where.size >= 5
    np.testing.assert_allclose(push[where], rates, atol=0.01)


def test_a_corner_lets_the_wire_slide(corner):
    lengths, steps = corner
    along = np.array([s.tangential_contact_force() for s in steps])
    assert np.max(np.abs(along)) <= 0.1 * TANGENTIAL_LIMIT_N
    assert not any("along its length" in f for s in steps for f in step_flags(s, "warm"))
    past = [(s, c) for s in steps if s.s[-1] >= 42.0 for c in s.contacts() if "fraction" in c]
    assert past  # (the wire passes the corner on a bar's row, not on a node's)
    corners = steps[0].scene.vessel.corners
    for s, c in past:  # touching at the wire's radius from the corner, pressed straight away from it
        point, normal = np.asarray(c["point"]), np.asarray(c["normal"])
        k, tau = c["node"], c["fraction"]
        np.testing.assert_allclose(point, (1.0 - tau) * s.nodes[k] + tau * s.nodes[k + 1], atol=1e-12)
        offset = corners - point
        gap = np.hypot(offset[:, 0], offset[:, 1])
        nearest = int(np.argmin(gap))
        assert abs(gap[nearest] - 0.5 * s.scene.wire.diameter) <= 1e-6 * s.scene.wire.length
        np.testing.assert_allclose(normal, offset[nearest] / gap[nearest], atol=1e-5)


def test_the_push_does_the_energys_work_past_a_corner(corner):
    """Over each step from 42 to 45 mm — the wire sliding over the corner, no contact made or lost — the energy rises
    by the push's work: ``ΔE = ΔL (p_i + p_{i+1})/2`` to the trapezoid rule's error ``ΔL³ |p''|/12``, with ``p''``
    bounded by the push's second differences at both ends of the step (doubled, plus 1e-4 N·mm for the rest of the
    expansion). The corner's node rows held the wire there with 0.3-0.6 N, and the push read −0.06-0.05 N while the
    energy rose by 0.15-0.2 N·mm a step."""
    lengths, steps = corner
    energy = np.array([s.energy for s in steps])
    push = np.array([s.entrance_force() for s in steps])
    h = STEP
    span = np.flatnonzero((lengths[:-1] >= 42.0 - 1e-9) & (lengths[1:] <= 45.0 + 1e-9))
    assert span.size == 6
    work = 0.5 * h * (push[span] + push[span + 1])
    second = np.abs(push[2:] - 2.0 * push[1:-1] + push[:-2]) / h**2  # at lengths[1:-1]
    curvature = np.maximum(second[span - 1], second[span])
    bound = 2.0 * h**3 * curvature / 12.0 + 1e-4
    assert np.all(np.abs(np.diff(energy)[span] - work) <= bound)
