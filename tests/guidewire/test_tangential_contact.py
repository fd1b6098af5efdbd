"""Contacts along the wire that hold it lengthwise, and what they do to the push reading.

A frictionless wire on smooth walls is touched along its normal, so pushing it ΔL further costs ΔE: the entrance push
is dE/dL (``test_vessel_solve.test_entrance_push_is_the_energy_rate``). The node rows of a vessel's corner (a branch's
opening) meet the wire at an angle and hold it lengthwise; along an insertion, the energy's rate is then the push
less that force (:meth:`Solution.tangential_contact_force`), and the step is flagged.
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


@pytest.fixture(scope="module")
def corner():
    """``s_bend_branch`` at 4 bars/mm, its wire pushed past the branch's corner (38-46 mm)."""
    return _insertion("s_bend_branch", 34.0, 46.0, 4.0)


def test_smooth_walls_hold_the_wire_along_its_normal_only():
    lengths, steps = _insertion("s_bend", 30.0, 42.0, 4.0)
    along = np.array([s.tangential_contact_force() for s in steps])
    push = np.array([s.entrance_force() for s in steps])
    assert np.max(np.abs(along)) <= 0.2 * TANGENTIAL_LIMIT_N
    assert not any("lengthwise" in f or "along its length" in f for s in steps for f in step_flags(s, "warm"))
    rates, where = _smooth_rates(lengths, steps)
    assert where.size >= 5
    np.testing.assert_allclose(push[where], rates, atol=0.01)


def test_a_corner_holds_the_wire_and_the_push_carries_that_force(corner):
    lengths, steps = corner
    along = np.array([s.tangential_contact_force() for s in steps])
    push = np.array([s.entrance_force() for s in steps])
    rates, where = _smooth_rates(lengths, steps, tol=0.05)  # (the energy curves more here: 0.1-0.2 N per mm)
    held = where[np.abs(along[where]) > TANGENTIAL_LIMIT_N]
    assert held.size >= 6  # past the corner, between the steps where a contact is made or lost
    rate_at = dict(zip(where.tolist(), rates.tolist(), strict=True))
    expected = np.array([rate_at[i] for i in held])
    # the energy's rate along the insertion is the push less the lengthwise force, not the push
    np.testing.assert_allclose(push[held] - along[held], expected, atol=0.03)
    assert np.max(np.abs(push[held] - expected)) > 5 * 0.03
    for i in held:
        assert any("along its length" in f for f in step_flags(steps[i], "warm"))
    before = [i for i, length in enumerate(lengths) if length <= 36.0]
    assert np.max(np.abs(along[before])) <= 0.2 * TANGENTIAL_LIMIT_N  # on the S-bend's smooth wall, before it


@pytest.mark.xfail(strict=True, reason="a vessel's corner is modelled by node rows, which hold the wire lengthwise; "
                                       "a bar-to-corner row (force normal to the bar) would let it slide")
def test_a_corner_lets_the_wire_slide(corner):
    lengths, steps = corner
    along = np.array([s.tangential_contact_force() for s in steps])
    assert np.max(np.abs(along)) <= TANGENTIAL_LIMIT_N
