"""Cold solves of the aortic arch whose nodes lie in the openings of its first two branches (issue 27).

A node whose nearest wall (of the tube it lies deepest in) runs through another tube's lumen gets its row on the
nearest point of the lumen's boundary (:meth:`guidewire.vessel.Vessel.nearest_boundary`). Left without a row on that
side (nodes 199-208 of the cold solve at 211 mm, 1 bar per mm), nothing held them there: the next round swung the
wire's distal part back along the arch and out through its outer wall, up to 18 mm outside the lumen, and the solve
failed after ~20 s.
"""

from __future__ import annotations

import numpy as np
import pytest
from arch_checks import VESSELS, arch, inside, tube

import guidewire
from guidewire.vessel.curves import SAMPLE_SPACING
from guidewire.vessel.geometry import CORNER_TOLERANCE

LENGTHS_1 = (205.0, 207.0, 209.0, 211.0, 213.0, 216.0, 218.0)
LENGTHS_2 = (206.0, 211.0, 216.0)


def _insertion(bars_per_mm: int) -> dict[float, guidewire.Solution]:
    """The warm insertion at ``bars_per_mm``, 1 mm steps, by inserted length."""
    start = arch().with_wire(length=200.0, bars=200 * bars_per_mm)
    steps = guidewire.insert(start, np.arange(1.0, max(LENGTHS_1 + LENGTHS_2) + 0.5, 1.0)).steps
    return {float(round(s.scene.wire.length)): s for s in steps}


@pytest.fixture(scope="module")
def insertions() -> dict[int, dict[float, guidewire.Solution]]:
    return {1: _insertion(1), 2: _insertion(2)}


@pytest.mark.parametrize("name", ["aortic_arch", "s_bend_branch"])
def test_the_nearest_boundary_point_lies_on_the_boundary_no_nearer_than_the_deepest_tubes_wall(name):
    """Points across every tube: the nearest boundary point is on the lumen's boundary, so no nearer than the wall of
    the tube the point lies deepest in (the signed distance of a union is at least its largest member's), and within
    half a sample spacing of that wall where that wall is the boundary (not in an opening)."""
    vessel = guidewire.load_scene(str(VESSELS / f"{name}.toml")).vessel
    rng = np.random.default_rng(7)
    ways = [vessel.path(rng.uniform(0.0, vessel.length, 300))[0]]
    for k in range(len(vessel.branches)):
        ways.append(vessel.route(vessel.junction(k) + rng.uniform(-10.0, 40.0, 150), k)[0])
    points = np.vstack(ways) + rng.uniform(-3.0, 3.0, (sum(len(w) for w in ways), 2))
    near = vessel.clearance(points)
    inside = near.distance > 0.0
    points, depth, wall = points[inside], near.distance[inside], near.boundary[inside]
    found = vessel.nearest_boundary(points)
    scale = CORNER_TOLERANCE * max(np.max(vessel.radius), *(np.max(b.radius) for b in vessel.branches))
    assert np.all(np.abs(vessel.clearance(found.boundary).distance) <= scale)
    np.testing.assert_allclose(np.hypot(*(found.boundary - points).T), found.distance, rtol=1e-12)
    np.testing.assert_allclose(np.hypot(*found.normal.T), 1.0, rtol=1e-12)
    assert np.all(found.distance >= depth - scale)
    plain = ~vessel.opening(wall, depth)
    assert np.all(found.distance[plain] <= depth[plain] + 0.5 * SAMPLE_SPACING)
    assert (~plain).any() and plain.any()  # (the family reaches openings and plain walls alike)


@pytest.mark.parametrize("length", LENGTHS_1)
def test_cold_solves_at_1_bar_per_mm_succeed_and_reach_the_insertions_energy(insertions, length):
    """The cold solve (the main centreline's start alone) succeeds inside the lumen; where its tip is in the branch
    the warm insertion's is in, at the insertion's energy (relative 1e-6), and where not, the solve with the
    branch starts (``branches="lowest"``) is, below the first answer."""
    scene = arch().with_wire(length=length, bars=round(length))
    warm = insertions[1][length]
    first = guidewire.solve(scene, branches="first")
    assert warm.success and first.success, first.message
    inside(scene, first)
    if tube(scene, first.nodes[-1]) != tube(scene, warm.nodes[-1]):
        lowest = guidewire.solve(scene)
        assert lowest.success, lowest.message
        inside(scene, lowest)
        assert lowest.energy <= first.energy
        first = lowest
    assert tube(scene, first.nodes[-1]) == tube(scene, warm.nodes[-1])
    assert first.energy == pytest.approx(warm.energy, rel=1e-6)


@pytest.mark.parametrize("length", LENGTHS_2)
def test_cold_solves_at_2_bars_per_mm_reach_the_insertions_branch_and_energy(insertions, length):
    """At 2 bars per mm (the full-space program), the cold solve with the branch starts succeeds inside the lumen,
    in the branch the warm insertion at the same density reaches, at its energy (relative 1e-6)."""
    scene = arch().with_wire(length=length, bars=round(2 * length))
    warm = insertions[2][length]
    cold = guidewire.solve(scene)
    assert warm.success and cold.success, cold.message
    inside(scene, cold)
    assert tube(scene, cold.nodes[-1]) == tube(scene, warm.nodes[-1])
    assert cold.energy == pytest.approx(warm.energy, rel=1e-6)
