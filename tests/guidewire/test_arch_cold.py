"""Cold solves of the aortic arch past its branch openings (issue 27).

Where two tubes overlap (the arch's brachiocephalic trunk and left common carotid open side by side, their tubes
overlapping each other and the arch), :meth:`Vessel.clearance` measures a point against the tube it lies deepest in,
whose wall there can run through another tube's lumen. A lumen row on that wall held every node of a cold start in
the arch as it slid into the openings, one node a round, until the working-set rounds ran out (SHAPE_REJECTED at
203-215 mm, 1 and 2 bars per mm). Such a row is left out where the node clears the other tube's wall too.
"""

from __future__ import annotations

import numpy as np
import pytest
from arch_checks import arch, inside, tube

import guidewire

LENGTHS = (200.0, 203.0, 205.0, 208.0, 210.0, 214.0)


@pytest.fixture(scope="module")
def insertion() -> dict[float, guidewire.Solution]:
    """The warm insertion at 1 bar per mm, 1 mm steps, by inserted length."""
    start = arch().with_wire(length=200.0, bars=200)
    steps = guidewire.insert(start, np.arange(1.0, max(LENGTHS) + 0.5, 1.0)).steps
    return {float(round(s.scene.wire.length)): s for s in steps}


@pytest.mark.parametrize("length", LENGTHS)
def test_cold_solves_at_1_bar_per_mm_reach_the_insertions_answer(insertion, length):
    """At 1 bar per mm the cold solve succeeds with every node inside the lumen, its tip in the branch the warm
    insertion's is in, at the insertion's energy (relative 1e-6)."""
    scene = arch().with_wire(length=length, bars=round(length))
    cold = guidewire.solve(scene)
    warm = insertion[length]
    assert warm.success and cold.success, cold.message
    inside(scene, cold)
    assert tube(scene, cold.nodes[-1]) == tube(scene, warm.nodes[-1])
    assert cold.energy == pytest.approx(warm.energy, rel=1e-6)


@pytest.mark.parametrize("length", LENGTHS)
def test_cold_solves_at_2_bars_per_mm_converge_inside_the_lumen(insertion, length):
    """At 2 bars per mm (the full-space program) the cold solve succeeds with every node inside the lumen, within
    the working-set rounds; with ``branches="lowest"`` (the default) its tip is in the branch the warm insertion
    reaches (its branch starts are tried in the full space too), below the main centreline's answer."""
    scene = arch().with_wire(length=length, bars=round(2 * length))
    cold = guidewire.solve(scene)
    assert cold.success, cold.message
    inside(scene, cold)
    assert tube(scene, cold.nodes[-1]) == tube(scene, insertion[length].nodes[-1])
    first = guidewire.solve(scene, branches="first")
    assert cold.energy <= first.energy
