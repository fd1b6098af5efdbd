"""Quasi-static advancement: warm-started steps reach the same shapes as cold solves, in fewer iterations."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import guidewire
from guidewire import Contact, Scene


def _sliding(steps=8):
    """Table 1 (θ_B = π/4) with B moving 0.5 mm per step along the direction (-0.6, 0.8)."""
    base = guidewire.paper_scenes()["table1_pi_4"]
    c = base.contacts[-1]
    return [Scene(base.wire, base.base, (Contact(c.s, (c.point[0] - 0.3 * k, c.point[1] + 0.4 * k), c.angle),),
                  base.walls) for k in range(steps)]


def test_warm_started_steps_match_cold_solves_with_fewer_iterations():
    scenes = _sliding()
    warm = guidewire.solve_sequence(scenes)
    cold = [guidewire.solve(s) for s in scenes]
    assert all(s.success for s in warm)
    for w, c in zip(warm, cold, strict=True):
        assert w.energy == pytest.approx(c.energy, rel=1e-9)
        np.testing.assert_allclose(w.nodes, c.nodes, atol=1e-7)
    assert sum(s.iterations for s in warm[1:]) < sum(s.iterations for s in cold[1:])
    assert max(s.iterations for s in warm[1:]) <= 3


def test_growing_inserted_length_resamples_the_previous_shape():
    base = guidewire.paper_scenes()["fig6b"]  # the wire pushed further in against the wall x <= 45
    scenes = [replace(base, wire=replace(base.wire, length=length, bars=int(length))) for length in (90.0, 95.0, 100.0)]
    sols = guidewire.solve_sequence(scenes)
    assert all(s.success for s in sols)
    assert [s.nodes.shape[0] for s in sols] == [91, 96, 101]
    assert all(s.max_violation <= 1e-8 for s in sols)


def test_steady_advance_uses_the_secant_predictor():
    """Along a steady advance (equal, parallel scene changes) each step after the second starts from the secant
    extrapolation of the last two answers: one Newton step and the converged check (2 iterations)."""
    sols = guidewire.solve_sequence(_sliding(8))
    assert all(s.success for s in sols)
    assert [s.iterations for s in sols[2:]] == [2] * 6


def test_secant_factor_only_for_parallel_changes():
    from guidewire.sequence import secant_factor as _secant_factor

    a, b, c, _ = _sliding(4)
    assert _secant_factor(a, b, c) == pytest.approx(1.0)
    assert _secant_factor(a, c, c) == 0.0  # no change
    assert _secant_factor(a, b, replace(c, contacts=(replace(c.contacts[0], point=(60.0, 45.0)),))) == 0.0
    assert _secant_factor(a, b, b.with_bars(50)) == 0.0  # another layout


def test_reused_models_give_the_answers_of_models_built_anew():
    """``solve_sequence`` keeps the bar layout and the energy between steps when only targets move: the same shapes
    (to 1e-9 mm), energies and iteration counts as building every step's program anew (``reuse=None``)."""
    from guidewire.model import ModelReuse

    scenes = _sliding(6)
    reuse = ModelReuse()
    kept = guidewire.solve_sequence(scenes, reuse=reuse)
    fresh = guidewire.solve_sequence(scenes, reuse=None)
    assert reuse.hits["layout"] == reuse.hits["energy"] == len(scenes) - 1  # every step after the first kept both
    for a, b in zip(kept, fresh, strict=True):
        assert a.success and b.success
        np.testing.assert_allclose(a.nodes, b.nodes, rtol=0.0, atol=1e-9)
        assert a.energy == pytest.approx(b.energy, rel=1e-12)
        assert a.iterations == b.iterations
