"""The start curve's Newton grid (coarse rule, then polish) picks the curve the full 12-step grid on the 64-point
rule picked, on every paper scene (issue 16): the chosen curve closes on the next pose to its tolerance, and its
coefficients and energy are the frozen grid's (the winner, up to rounding)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import guidewire
from guidewire import initial_shape as shape
from guidewire.chain.kinematics import BarChain, scene_bars

SCENES = sorted(p for p in (Path(guidewire.__file__).parent / "scenes").glob("*.toml") if p.stem != "table5")


def _frozen_segment_curves(p0, p1, a0, a1, length):
    """The grid as it was before issue 16: 25 starts × 12 damped Newton steps on the 64-point rule, frozen here."""
    u = (np.arange(64) + 0.5) / 64
    basis = np.stack((np.sin(np.pi * u), np.sin(2.0 * np.pi * u)))
    weights = np.column_stack((np.ones(64), basis.T)) / 64
    grid = np.linspace(-2.0 * math.pi, 2.0 * math.pi, 5)
    c = np.stack(np.meshgrid(grid, grid, indexing="ij"), axis=-1).reshape(-1, 2)
    phase = (a0 + (a1 - a0) * u) - np.array([0.0, 0.5 * np.pi])[:, None, None]
    target = ((p1 - p0) / length)[:, None]
    step = np.empty_like(c)
    for _ in range(12):
        m = np.cos(phase + c @ basis) @ weights
        r = m[:, :, 0] - target
        (cos1, cos2), (sin1, sin2) = m[0, :, 1:].T, m[1, :, 1:].T
        det = sin2 * cos1 - sin1 * cos2
        inv = np.divide(1.0, det, out=np.zeros_like(det), where=np.abs(det) > 1e-12)
        step[:, 0] = -(sin2 * r[1] + cos2 * r[0]) * inv
        step[:, 1] = (cos1 * r[0] + sin1 * r[1]) * inv
        size = np.abs(step).max(axis=1)
        c += step * np.minimum(1.0, 1.0 / np.maximum(size, 1e-300))[:, None]
        if size.max() <= 1e-13:
            break
    m = np.cos(phase + c @ basis) @ weights
    miss = np.hypot(m[0, :, 0] - target[0, 0], m[1, :, 0] - target[1, 0]) * length
    slope = (a1 - a0) + np.pi * c[:, :1] * np.cos(np.pi * u) + 2.0 * np.pi * c[:, 1:] * np.cos(2.0 * np.pi * u)
    return c, miss, np.mean(slope**2, axis=1) / length


def _calls(path, bars, monkeypatch):
    """The arguments of every grid the default start of ``path`` at ``bars`` runs."""
    calls = []
    real, real_many = shape._segment_curves, shape._many_segment_curves

    def record(*args):
        calls.append(args)
        return real(*args)

    def record_many(segments):
        calls.extend(segments)
        return real_many(segments)

    scene = guidewire.load_scene(path).with_bars(bars)
    lengths, nodes = scene_bars(scene)
    with monkeypatch.context() as m:
        m.setattr(shape, "_segment_curves", record)
        m.setattr(shape, "_many_segment_curves", record_many)
        shape.initial_angles(scene, BarChain(np.asarray(scene.base.point, dtype=float), lengths), nodes)
    return calls


def _closure(c, a0, a1, length):
    """End point minus start point of the curve with coefficients ``c`` (mm), by a fine midpoint rule."""
    u = (np.arange(4096) + 0.5) / 4096
    theta = a0 + (a1 - a0) * u + c[0] * np.sin(np.pi * u) + c[1] * np.sin(2.0 * np.pi * u)
    return length * np.array([np.cos(theta).mean(), np.sin(theta).mean()])


@pytest.mark.parametrize("path", SCENES, ids=lambda p: p.stem)
@pytest.mark.parametrize("bars", [25, 100, 1000])
def test_the_winner_is_the_frozen_grids_and_closes(path, bars, monkeypatch):
    for p0, p1, a0, a1, length in _calls(path, bars, monkeypatch):
        c, miss, energy = shape._segment_curves(p0, p1, a0, a1, length)
        closing = miss <= shape.CLOSURE_TOLERANCE * length
        c_old, miss_old, energy_old = _frozen_segment_curves(p0, p1, a0, a1, length)
        closing_old = miss_old <= shape.CLOSURE_TOLERANCE * length
        assert closing.any() == closing_old.any()
        if not closing.any():
            continue
        k = shape._least(c, np.where(closing, energy, np.inf))
        k_old = int(np.argmin(np.where(closing_old, energy_old, np.inf)))
        # same energy; same curve, or its mirror twin of the same energy (a tie the frozen grid broke by rounding)
        assert energy[k] == pytest.approx(energy_old[k_old], rel=1e-12)
        twins = closing_old & np.isclose(energy_old, energy_old[k_old], rtol=1e-12, atol=0.0)
        assert np.min(np.abs(c_old[twins] - c[k]).max(axis=1)) < 1e-10
        # the chosen curve meets the next pose (checked independently on a 64x finer rule, up to the 64-point
        # rule's own error, ~1e-4 of ℓ for the most bent curves)
        assert np.allclose(_closure(c[k], a0, a1, length), p1 - p0, rtol=0.0, atol=5e-4 * length)
        assert miss[k] <= shape.CLOSURE_TOLERANCE * length


def test_near_tie_goes_to_the_least_c2_not_to_rounding():
    c = np.array([[0.9, 1.0], [0.9, -1.0], [3.0, 0.0]])
    energy = np.array([1.0, 1.0 + 1e-14, 0.5 + 1.0])
    assert shape._least(c, energy) == 1
    assert shape._least(c, np.array([1.0, 1.0 + 1e-9, 2.0])) == 0  # a real difference is not a tie
    assert shape._least(c, np.full(3, np.inf)) == 0


def test_symmetric_segment_has_mirror_twins_and_the_choice_is_stable():
    """θ₀ = θ₁ = 0 on a chord shorter than the wire: the grid finds both mirror-image curves (c₁, ±c₂) of equal
    energy, and the start takes c₂ < 0 whatever the rounding."""
    p0, p1 = np.zeros(2), np.array([80.0, 0.0])
    c, miss, energy = shape._segment_curves(p0, p1, 0.0, 0.0, 100.0)
    closing = miss <= shape.CLOSURE_TOLERANCE * 100.0
    k = shape._least(c, np.where(closing, energy, np.inf))
    assert c[k, 1] < 0.0
    mirror = np.flatnonzero(closing & np.isclose(c[:, 1], -c[k, 1], rtol=1e-9) & np.isclose(c[:, 0], c[k, 0]))
    assert mirror.size and energy[mirror[0]] == pytest.approx(energy[k], rel=1e-12)


def test_grids_of_several_segments_at_once_are_each_segments_own():
    """:func:`_many_segment_curves` (the segments of a scene as one Newton iteration) finds each segment's curves:
    the same winner and energy as the segment alone, up to rounding."""
    rng = np.random.default_rng(3)
    for _ in range(40):
        segments = []
        for _ in range(int(rng.integers(2, 5))):
            p0 = 10.0 * rng.normal(size=2)
            p1 = p0 + 10.0 * rng.normal(size=2)
            a0, a1 = 2.0 * rng.normal(size=2)
            segments.append((p0, p1, float(a0), float(a1), float(np.hypot(*(p1 - p0)) * (1.0 + 2.0 * rng.random()))))
        for segment, (c, miss, energy) in zip(segments, shape._many_segment_curves(segments), strict=True):
            c_one, miss_one, energy_one = shape._segment_curves(*segment)
            tolerance = shape.CLOSURE_TOLERANCE * segment[4]
            assert np.array_equal(np.isfinite(miss), np.isfinite(miss_one))
            closing, closing_one = np.where(miss <= tolerance, energy, np.inf), np.where(miss_one <= tolerance,
                                                                                        energy_one, np.inf)
            k, k_one = shape._least(c, closing), shape._least(c_one, closing_one)
            assert np.isfinite(closing[k]) == np.isfinite(closing_one[k_one])
            if np.isfinite(closing[k]):
                assert closing[k] == pytest.approx(closing_one[k_one], rel=1e-13)
                assert np.abs(c[k] - c_one[k_one]).max() < 1e-10

