"""Warm insertion steps in vessels: a step warm-started from the last converges like Newton's method (its stale
multipliers released at once), and the tracked start's new length is steered inside the lumen where the tip meets
a wall head on."""

from __future__ import annotations

import numpy as np
import pytest

from guidewire import insert, load_scene, solve
from guidewire.march.insertion import EXTENSION_TURNS, _bar_lengths, _tracked_angles

VESSELS = "guidewire/scenes/vessels"


def _scene(name: str, length: float):
    scene = load_scene(f"{VESSELS}/{name}.toml")
    density = scene.wire.bars / scene.wire.length
    return scene.with_wire(length=length, bars=round(length * density))


@pytest.mark.parametrize(("name", "first", "last"), [("tortuous", 40.0, 50.0), ("s_bend", 60.0, 70.0)])
def test_warm_steps_in_compressed_vessels_take_few_iterations(name, first, last):
    """1 mm steps of a wire pressed against both walls: each starts a millimetre from its answer, with the last
    step's multipliers on the rows it touched, so Newton–SQP needs a few iterations a round. (When a row the QP
    released kept a multiplier, the augmented-Lagrangian term stayed on it and held the iterates at a wall they were
    leaving: 27-74 iterations a step on the tortuous vessel, 58-151 on the S-bend, converging linearly.)"""
    out = insert(_scene(name, first), np.arange(first, last + 0.5, 1.0))
    assert out.complete and all(s.success for s in out.steps)
    warm = [s.iterations for s, how in zip(out.steps, out.started, strict=True) if how == "warm"]
    assert len(warm) == len(out.steps) - 1
    assert np.median(warm) <= 8 and max(warm) <= 20, warm


def _start_parts(prev, scene):
    """The tracked start's pieces: bar lengths, which bars lie past the previous tip (midpoint beyond its last
    midpoint), and the unsteered angles (the previous shape, its tip's tangent continued)."""
    lengths = _bar_lengths(scene, scene.wire.bars)
    mid = np.cumsum(lengths) - 0.5 * lengths
    s_old = 0.5 * (prev.s[1:] + prev.s[:-1])
    return lengths, mid > s_old[-1], np.interp(mid, s_old, prev.bar_angles)


def _nodes(prev, lengths, angles):
    """Nodes 1..n of bar ``angles`` from the previous step's base (mm)."""
    return prev.nodes[0] + np.cumsum(lengths[:, None] * np.column_stack((np.cos(angles), np.sin(angles))), axis=0)


def test_a_tracked_start_keeps_its_new_length_inside_the_lumen():
    """Pushing 3 or 6 mm past converged shapes in three vessels: where the tip's tangent continued leaves the lumen,
    the start turns the new length by the smallest listed turn that keeps its nodes inside by the wire's radius (no
    smaller one does); elsewhere it is the tangent continued."""
    steered = 0
    for name, length in (("bend", 40.0), ("bend", 55.0), ("s_bend", 45.0), ("s_bend", 62.0), ("tortuous", 30.0),
                         ("tortuous", 44.0), ("aortic_arch", 120.0), ("aortic_arch", 170.0)):
        prev = solve(_scene(name, length))
        assert prev.success
        for push in (3.0, 6.0):
            scene = _scene(name, length + push)
            lengths, new, straight = _start_parts(prev, scene)
            start = _tracked_angles(prev, scene, scene.wire.bars)
            need = 0.5 * scene.wire.diameter

            def clearance(angles, new=new, lengths=lengths, prev=prev, scene=scene):
                return scene.vessel.clearance(_nodes(prev, lengths, angles)[new]).distance.min()

            np.testing.assert_array_equal(start[~new], straight[~new])  # the old length keeps its track
            turn = start[new] - straight[new]
            assert np.ptp(turn) == 0.0  # the new length turns as a whole
            if clearance(straight) >= need:
                assert turn[0] == 0.0
                continue
            steered += 1
            assert clearance(start) >= need
            for other in EXTENSION_TURNS[np.abs(EXTENSION_TURNS) < abs(turn[0]) - 1e-12]:
                assert clearance(np.where(new, straight + other, straight)) < need
    assert steered >= 2  # the family does exercise the steering


@pytest.mark.parametrize(("name", "first", "last"), [("aortic_arch", 232.0, 240.0), ("bend", 40.0, 48.0),
                                                     ("s_bend", 64.0, 72.0), ("tortuous", 25.0, 31.0)])
def test_a_touching_tip_carries_its_force_to_the_new_tip(name, first, last):
    """The track predictor's multipliers: where the tip presses on the wall, its rows' forces go to the new tip node
    and every other row keeps its node (a contact stays where it is on the wall while the wire slides past it); the
    next step's answer holds the new tip's row in most steps, as the warm start guesses (a tip passing the end of a
    bend lifts off)."""
    from guidewire.march.insertion import _tracked_multipliers

    out = insert(_scene(name, first), np.arange(first, last + 0.5, 1.0))
    assert out.complete and all(s.success for s in out.steps)
    checked, held_tip = 0, 0
    for prev, nxt in zip(out.steps, out.steps[1:], strict=False):
        lumen = [k for k, b in enumerate(prev.blocks) if b.kind == "lumen"][0]
        block, lam = prev.blocks[lumen], np.asarray(prev.multipliers[lumen])
        tip = block.nodes == prev.n_bars
        if not np.any(lam[tip] > 0.0):
            continue
        carried = _tracked_multipliers(prev, nxt.n_bars)
        moved = carried.blocks[lumen]
        assert np.array_equal(moved.nodes[tip], np.full(tip.sum(), nxt.n_bars))
        assert np.array_equal(moved.nodes[~tip], block.nodes[~tip]) and np.array_equal(moved.sides, block.sides)
        after = [k for k, b in enumerate(nxt.blocks) if b.kind == "lumen"][0]
        held = nxt.blocks[after].nodes[np.asarray(nxt.multipliers[after]) > 0.0]
        held_tip += int(nxt.n_bars in held)
        checked += 1
    assert checked >= 4 and held_tip >= 0.75 * checked, (held_tip, checked)
