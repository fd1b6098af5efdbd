"""The lazy wall search of the default start gives the eager search's start bit for bit (issue 16, lever 2)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import guidewire
from guidewire import Scene, Wall, Wire
from guidewire import initial_shape as shape
from guidewire.chain.kinematics import BarChain, scene_bars

SCENES = sorted(p for p in (Path(guidewire.__file__).parent / "scenes").rglob("*.toml")
                if "vessels3d" not in p.parts)  # (the planar scenes: 3-D ones are tests/guidewire3d's)


def _eager_free_part_angles(scene, start, angle, lengths):
    """The free part's search as it was before it was made lazy (every trial arc over every node), frozen here."""
    if lengths.size == 0:
        return np.zeros(0)
    s_mid = np.cumsum(lengths) - 0.5 * lengths
    if not scene.walls:
        return np.full(lengths.size, angle)
    total = float(lengths.sum())
    magnitudes = np.concatenate(([0.0], np.geomspace(1e-4, 10.0, 125))) * 4.0 * math.pi / total
    kappa = np.concatenate((magnitudes, -magnitudes[1:]))
    kappa = kappa[np.argsort(np.abs(kappa), kind="stable")]
    phi = angle + kappa[:, None] * s_mid[None, :]
    nodes = start + np.cumsum(lengths[None, :, None] * np.stack((np.cos(phi), np.sin(phi)), axis=-1), axis=1)
    gap = np.full(kappa.size, np.inf)
    for wall in scene.walls:
        (nx, ny), offset = wall.unit()
        gap = np.minimum(gap, np.min(offset - (nodes[..., 0] * nx + nodes[..., 1] * ny), axis=1))
    no_loop = np.abs(kappa) * total <= 2.0 * math.pi
    feasible = (gap >= 0.0) & no_loop
    if not feasible.any():
        return phi[int(np.argmax(np.where(no_loop, gap, -np.inf)))]
    least = np.flatnonzero(feasible & (np.abs(kappa) == np.abs(kappa[int(np.argmax(feasible))])))
    pick = int(least[np.argmax(gap[least])])
    return angle + min(1.05 * abs(kappa[pick]), 2.0 * math.pi / total) * np.sign(kappa[pick]) * s_mid


def _start(scene: Scene) -> np.ndarray:
    lengths, nodes = scene_bars(scene)
    return shape.initial_angles(scene, BarChain(np.asarray(scene.base.point, dtype=float), lengths), nodes)


def _both_starts(scene: Scene, monkeypatch: pytest.MonkeyPatch) -> tuple[np.ndarray, np.ndarray]:
    lazy = _start(scene)
    with monkeypatch.context() as m:
        m.setattr(shape, "_free_part_angles", _eager_free_part_angles)
        eager = _start(scene)
    return lazy, eager


@pytest.mark.parametrize("path", SCENES, ids=lambda p: p.stem)
@pytest.mark.parametrize("bars", [10, 25, 100, 1000])
def test_start_of_every_scene_file_is_bit_identical_to_the_eager_search(path, bars, monkeypatch):
    scene = guidewire.load_scene(path)
    scene = scene.with_bars(bars)
    lazy, eager = _both_starts(scene, monkeypatch)
    assert lazy.dtype == eager.dtype and np.array_equal(lazy, eager)


@pytest.mark.parametrize("seed", range(40))
def test_random_walls_including_the_infeasible_fallback_give_the_same_start(seed, monkeypatch):
    """A clamped wire in front of one to three random walls: some starts curve away, some clear nothing (the least
    violating arc): the lazy search picks the same arc every time, bit for bit."""
    rng = np.random.default_rng(seed)
    walls = []
    for _ in range(int(rng.integers(1, 4))):
        theta = rng.uniform(-math.pi, math.pi)
        walls.append(Wall((math.cos(theta), math.sin(theta)), float(rng.uniform(0.5, 60.0))))
    scene = Scene(Wire(length=float(rng.uniform(20.0, 150.0)), bars=int(rng.integers(5, 400))),
                  guidewire.Base((0.0, 0.0), float(rng.uniform(-1.0, 1.0))), (), tuple(walls))
    lazy, eager = _both_starts(scene, monkeypatch)
    assert np.array_equal(lazy, eager)


def test_lazy_search_visits_fewer_nodes_on_fig6a():
    """The point of the lazy search: on Fig. 6a at 1000 bars most trial arcs leave at their first pass."""
    scene = guidewire.paper_scenes()["fig6a"].with_bars(1000)
    lengths, _ = scene_bars(scene)
    s_mid = np.cumsum(lengths) - 0.5 * lengths
    total = float(lengths.sum())
    kappa = shape._trial_curvatures(total)
    kappa = kappa[np.abs(kappa) * total <= shape.MAX_FREE_TURNING]
    start = np.asarray(scene.base.point, dtype=float)
    angle = float(scene.base.angle)
    lazy = shape._wall_gaps(scene, start, angle, kappa, s_mid, lengths)
    eager = shape._wall_gaps(scene, start, angle, kappa, s_mid, lengths, lazy=False)
    clear = eager >= 0.0
    assert np.array_equal(lazy[clear], eager[clear])  # the arcs that clear the walls: exact gaps
    assert np.all(lazy[~clear] < 0.0)  # the others: found outside a wall
