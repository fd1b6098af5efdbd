"""Self-crossing shapes are found (against a brute-force test of every pair) and never reported as a success."""

from __future__ import annotations

import numpy as np
import pytest

from guidewire import Base, Scene, Wall, Wire, solve
from guidewire.chain.crossing import crossing_bars


def _brute(p):
    """Every non-adjacent pair by exact orientation tests (generic positions: no touching)."""
    def orient(a, b, c):
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    for i in range(len(p) - 1):
        for j in range(i + 2, len(p) - 1):
            a, b, c, d = p[i], p[i + 1], p[j], p[j + 1]
            if orient(a, b, c) != orient(a, b, d) and orient(c, d, a) != orient(c, d, b):
                return (i, j)
    return None


@pytest.mark.parametrize("seed", range(5))
def test_first_crossing_matches_brute_force_on_random_walks(seed):
    rng = np.random.default_rng(seed)
    for _ in range(40):
        angles = np.cumsum(rng.normal(0.0, 0.8, 30))
        p = np.vstack([[0.0, 0.0], np.cumsum(np.c_[np.cos(angles), np.sin(angles)], axis=0)])
        assert crossing_bars(p) == _brute(p)


@pytest.mark.parametrize("seed", range(3))
def test_the_monotone_shortcut_agrees_with_brute_force_near_a_half_turn(seed):
    """Chains turning by 0.8π–2.2π in all (bends, hooks, loops; first and last bars sometimes parallel): the O(n)
    answer for chains that advance along one direction agrees with the pairwise test."""
    rng = np.random.default_rng(100 + seed)
    for total in np.linspace(0.8 * np.pi, 2.2 * np.pi, 30):
        turns = rng.uniform(0.0, 2.0, 40)
        angles = np.cumsum(turns * total / turns.sum()) + rng.normal(0.0, 0.05, 40)
        p = np.vstack([[0.0, 0.0], np.cumsum(np.c_[np.cos(angles), np.sin(angles)], axis=0)])
        assert crossing_bars(p) == _brute(p)


def test_shapes_that_do_and_do_not_cross():
    t = np.linspace(0.0, 4.0 * np.pi, 200)
    assert crossing_bars(np.c_[np.cos(t), np.sin(t)]) is not None  # two turns of one circle: a coil
    t = np.linspace(0.0, 1.9 * np.pi, 200)
    assert crossing_bars(np.c_[np.cos(t), np.sin(t)]) is None  # most of a circle, open
    flat = np.c_[np.linspace(0.0, 10.0, 1001), 1e-12 * np.random.default_rng(1).standard_normal(1001)]
    assert crossing_bars(flat) is None  # a wire lying flat along a wall: collinear bars apart are not a crossing
    assert crossing_bars(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, -1.0]])) == (0, 2)


def test_two_wall_channel_gives_the_straight_wire_not_a_coil():
    """The issue's channel (|y| ≤ 2, clamp angle 0.6, L = 80, free end) once returned a self-crossing coil as a
    success (E = 475.5 N·mm). The continuum reference's energy is 1.5128 N·mm."""
    scene = Scene(Wire(80.0, 80), Base((0.0, 0.0), 0.6), walls=(Wall((0.0, 1.0), 2.0), Wall((0.0, -1.0), 2.0)))
    sol = solve(scene)
    assert sol.success, sol.message
    assert sol.energy == pytest.approx(1.5128, rel=0.01) and sol.iterations <= 10
    assert crossing_bars(sol.nodes) is None and np.max(np.abs(sol.nodes[:, 1])) <= 2.0 + 1e-9


def _brute_touching(p, tolerance=1e-9):
    """The first pair by :func:`guidewire.crossing._segments_cross` over every non-adjacent pair (touching included)."""
    from guidewire.chain.crossing import _segments_cross

    a, b = p[:-1], p[1:]
    scale = tolerance * np.hypot(*(b - a).T).max()
    i, j = np.triu_indices(a.shape[0], 2)
    hit = _segments_cross(a[i], b[i], a[j], b[j], scale)
    if not hit.any():
        return None
    k = np.lexsort((j[hit], i[hit]))[0]
    return int(i[hit][k]), int(j[hit][k])


@pytest.mark.parametrize("gap", [-1e-10, 1e-10, 5e-10, -2e-9, 2e-9])
@pytest.mark.parametrize("bars", [5, 30, 101])
def test_a_wire_folded_back_onto_itself_touches_whatever_its_position(gap, bars):
    """Folded back at a distance ``gap`` (mm, bars of 1 mm): within the touching distance (1e-9 of the longest bar)
    it touches, beyond it not — also when the two strands lie on either side of a coordinate line (the boxes of the
    candidate search are grown by the touching distance)."""
    angles = np.concatenate((np.zeros(bars // 2), np.full(bars - bars // 2, np.pi)))
    steps = np.c_[np.cos(angles), np.sin(angles)]
    steps[bars // 2] = [0.0, gap]
    for shift in (0.0, 0.37, -5.0):
        p = np.vstack([[0.0, 0.0], np.cumsum(steps, axis=0)]) + [0.0, shift]
        assert crossing_bars(p) == _brute_touching(p)
        assert (crossing_bars(p) is not None) == (abs(gap) <= 1e-9)


@pytest.mark.parametrize("seed", range(3))
def test_first_touching_or_crossing_pair_matches_brute_force_on_lattice_walks(seed):
    """Walks on a lattice (collinear and touching bars everywhere) and coils: the pair found is the first one."""
    rng = np.random.default_rng(200 + seed)
    for _ in range(30):
        steps = rng.integers(-1, 2, (int(rng.integers(5, 80)), 2)).astype(float)
        steps[np.all(steps == 0.0, axis=1)] = [1.0, 0.0]
        p = np.vstack([[0.0, 0.0], np.cumsum(steps, axis=0)]) * rng.uniform(0.1, 10.0)
        assert crossing_bars(p) == _brute_touching(p)
    t = np.linspace(0.0, rng.uniform(1.0, 5.0) * np.pi, 151)
    coil = np.c_[(1.0 + 0.2 * t / t[-1]) * np.cos(t), (1.0 + 0.2 * t / t[-1]) * np.sin(t)]
    assert crossing_bars(coil) == _brute_touching(coil)
