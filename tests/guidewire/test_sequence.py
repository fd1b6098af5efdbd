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


def test_steady_advance_uses_the_polynomial_predictor():
    """Along a steady advance (equal, parallel scene changes) the third step starts from the secant through the last
    two answers (one Newton step and the converged check: 2 iterations) and every later one from the quadratic
    through the last three, close enough (O(h³)) that one SQP iteration meets the tolerance; the answers are the
    cold solves' to 1e-9."""
    scenes = _sliding(8)
    sols = guidewire.solve_sequence(scenes)
    assert all(s.success for s in sols)
    assert [s.iterations for s in sols[2:]] == [2] + [1] * 5
    for s, scene in zip(sols[3:], scenes[3:], strict=True):
        cold = guidewire.solve(scene)
        assert s.energy == pytest.approx(cold.energy, rel=1e-9)
        np.testing.assert_allclose(s.nodes, cold.nodes, atol=1e-7)
        assert s.result.status == 0 and s.result.kkt["stationarity"] <= 1e-8  # SUCCESS: the strict test


def test_the_predictor_extrapolates_through_successful_answers_of_one_layout_only():
    """The predictor's points: the last answers that succeeded with the new step's bar count, joined by parallel
    scene changes; a quadratic's weights reproduce a quadratic exactly."""
    from guidewire.march.sequence import _lagrange_weights, _positions, _scene_parameters, _steady_points

    scenes = _sliding(5)
    sols = list(guidewire.solve_sequence(scenes[:4]))
    params = [_scene_parameters(s) for s in scenes[:5]]
    n = sols[-1].bar_angles.size
    assert _steady_points(sols, params[-4:], n) == 3
    assert _steady_points(sols, params[-4:], n + 1) == 0  # another bar count: no extrapolation
    assert _steady_points(sols[:1], params[-2:], n) == 0  # one answer: nothing to extrapolate
    failed = [*sols[:-2], replace(sols[-2], success=False), sols[-1]]
    assert _steady_points(failed, params[-4:], n) == 0  # the failed answer ends the run at one point
    bent = [*params[-4:-1], _scene_parameters(replace(scenes[4], contacts=(replace(scenes[4].contacts[0],
                                                                                   point=(60.0, 45.0)),)))]
    assert _steady_points(sols, bent, n) == 0  # the new change is not along the last ones
    tau = _positions(params[-4:])
    np.testing.assert_allclose(np.diff(tau), 0.5)  # 0.5 mm per step
    w = _lagrange_weights([0.0, 1.0, 3.0, 4.5])
    assert sum(wj * t**2 for wj, t in zip(w, [0.0, 1.0, 3.0], strict=True)) == pytest.approx(4.5**2)
    assert _lagrange_weights([0.0, 1.0, 2.0, 3.0]) == pytest.approx([1.0, -3.0, 3.0])


def test_secant_factor_only_for_parallel_changes():
    from guidewire.march.sequence import secant_factor as _secant_factor

    a, b, c, _ = _sliding(4)
    assert _secant_factor(a, b, c) == pytest.approx(1.0)
    assert _secant_factor(a, c, c) == 0.0  # no change
    assert _secant_factor(a, b, replace(c, contacts=(replace(c.contacts[0], point=(60.0, 45.0)),))) == 0.0
    assert _secant_factor(a, b, b.with_bars(50)) == 0.0  # another layout


def test_reused_models_give_the_answers_of_models_built_anew():
    """``solve_sequence`` keeps the bar layout and the energy between steps when only targets move: the same shapes
    (to 1e-9 mm), energies and iteration counts as building every step's program anew (``reuse=None``)."""
    from guidewire.program.model import ModelReuse

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
