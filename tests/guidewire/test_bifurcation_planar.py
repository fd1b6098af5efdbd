"""A planar trunk that ends in a bifurcation (a Y): the lumen goes on in its two arms, not straight on past the
trunk's end (the 3-D counterpart: ``tests/guidewire3d/test_bifurcation.py``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import guidewire
from guidewire import Scene, Vessel, Wire


def _y(angle_deg: float, bend: float = 0.0, mirror: float = 1.0) -> Vessel:
    """A trunk ``y = bend x²`` (radius 2.5 mm) over 0-40 mm ending in two straight 2 mm arms at ±``angle`` from its
    end tangent; ``mirror`` −1 reflects it in the x-axis."""
    x = np.linspace(0.0, 40.0, 21)
    main = np.column_stack((x, bend * x**2))
    end = main[-1]
    t = np.array([1.0, 2.0 * bend * 40.0])
    t /= np.linalg.norm(t)
    n = np.array([-t[1], t[0]])
    s = np.linspace(0.0, 40.0, 21)
    arms = [(end + s[:, None] * (math.cos(side * math.radians(angle_deg)) * t
                                 + math.sin(side * math.radians(angle_deg)) * n), 2.0) for side in (1.0, -1.0)]
    flip = np.array([1.0, mirror])
    return Vessel.from_centreline(main * flip, 2.5, [(a * flip, r) for a, r in arms])


@pytest.mark.parametrize("angle", [25.0, 40.0, 60.0])
def test_no_lumen_straight_past_a_trunks_bifurcating_end(angle):
    """On the trunk's axis past its end: inside while in its last disk (2.5 mm) or an arm (until the arms' axes
    part by their radius, ``2 / sin(angle)`` mm), outside beyond — the carina is wall. Before, the trunk went on
    straight for 50 mm through it. An outlet and a branch leaving the side keep the straight continuation."""
    vessel = _y(angle)
    past = np.linspace(0.5, 30.0, 60)
    clearance = vessel.clearance(np.column_stack((40.0 + past, np.zeros_like(past)))).distance
    edge = max(2.5, 2.0 / math.sin(math.radians(angle)))
    assert np.all(clearance[past < edge - 1e-6] > 0.0)
    assert np.all(clearance[past > edge + 1e-6] < 0.0)
    x = np.linspace(0.0, 60.0, 31)
    side = np.array([30.0, 0.0]) + np.linspace(0.0, 30.0, 16)[:, None] * np.array([math.cos(1.0), math.sin(1.0)])
    outlet = Vessel.from_centreline(np.column_stack((x, np.zeros_like(x))), 2.5, [(side, 2.0)])
    assert np.all(outlet.clearance(np.array([[60.0 + d, 0.0] for d in (5.0, 20.0, 45.0)])).distance > 2.4)


@pytest.mark.parametrize("length", [50.0, 60.0, 75.0])
def test_a_wire_past_the_bifurcation_lies_in_an_arm(length):
    """Solved cold (``branches="lowest"``: the default start and one through each arm) the wire lies in an arm,
    every node in the lumen, at or below the energy an insertion reaches; the mirrored Y gives the mirrored wire."""
    wire = Wire(length=length, bars=int(length), youngs_modulus=60000.0, diameter=0.36)
    vessel = _y(35.0, bend=0.002)
    sol = guidewire.solve(Scene.in_vessel(wire, vessel))
    assert sol.success, sol.message
    assert vessel.clearance(sol.nodes).distance.min() >= 0.18 - 1e-6
    tip = sol.nodes[-1]
    assert np.hypot(*(tip - [40.0, 3.2])) > 5.0 and abs(tip[1] - 3.2) > 2.0  # (off the trunk's axis: in an arm)
    pushed = guidewire.insert(Scene.in_vessel(Wire(length=30.0, bars=30, youngs_modulus=60000.0, diameter=0.36),
                                              vessel), np.arange(30.0, length + 0.5, 1.0))
    assert pushed.complete
    assert sol.energy <= pushed.steps[-1].energy * (1.0 + 1e-6)
    mirrored = guidewire.solve(Scene.in_vessel(wire, _y(35.0, bend=0.002, mirror=-1.0)))
    assert mirrored.energy == pytest.approx(sol.energy, rel=1e-9)
    np.testing.assert_allclose(mirrored.nodes * [1.0, -1.0], sol.nodes, atol=1e-7)
