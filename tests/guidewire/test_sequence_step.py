"""The sequence step's shortcuts give the same numbers as the general paths they skip."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import guidewire.march.sequence as sequence
from guidewire import formulate, paper_scenes, solve, solve_sequence
from guidewire.program.formulation import BlockMultipliers


def _sliding(steps: int) -> list:
    scene = paper_scenes()["table1_pi_4"]
    (b,) = scene.contacts
    return [replace(scene, contacts=(replace(b, point=(b.point[0] - 0.5 * k, b.point[1])),)) for k in range(steps)]


def test_block_multipliers_start_like_the_solution() -> None:
    """``multipliers0`` as BlockMultipliers is matched exactly as the Solution it comes from."""
    scenes = _sliding(2)
    first = solve(scenes[0], bars=40)
    a = solve(scenes[1], bars=40, initial_angles=first.bar_angles, multipliers0=first)
    b = solve(scenes[1], bars=40, initial_angles=first.bar_angles,
              multipliers0=BlockMultipliers(first.blocks, first.multipliers))
    assert a.energy == b.energy and a.iterations == b.iterations
    np.testing.assert_array_equal(a.bar_angles, b.bar_angles)


def test_prediction_matches_blocks_by_key() -> None:
    """Blocks found by position or by key give the same extrapolation; a block missing in an earlier answer keeps
    its last multipliers."""
    sols = list(solve_sequence(_sliding(4), bars=40))[1:]
    weights = sequence._lagrange_weights([0.0, 1.0, 2.0, 3.0])
    angles, lam = sequence._prediction(sols, weights)
    np.testing.assert_array_equal(angles, sum(w * s.bar_angles for w, s in zip(weights, sols, strict=True)))
    guess = sum(w * s.multipliers[0] for w, s in zip(weights, sols, strict=True))
    np.testing.assert_array_equal(lam.multipliers[0], guess)  # (no sign change along this slide)
    assert lam.blocks == sols[-1].blocks
    lonely = replace(sols[0], blocks=(), multipliers=())
    _, kept = sequence._prediction([lonely, *sols[1:]], weights)
    np.testing.assert_array_equal(kept.multipliers[0], sols[-1].multipliers[0])


def test_max_violation_reads_the_rows_it_was_built_with() -> None:
    """The rows a formulation keeps are those its blocks build: the same largest violation either way."""
    form = formulate(paper_scenes()["table1_pi_4"], bars=30)
    phi = form.x0 + 0.01
    rebuilt = replace(form, rows=())
    assert form.rows and form.max_violation(phi) == rebuilt.max_violation(phi) > 0.0
