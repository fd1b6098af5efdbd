"""Which nearest walls lie in another tube's opening (:meth:`guidewire.vessel.Vessel.opening`): the depth bounds that
spare the search far from every junction change no answer."""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

import guidewire
from guidewire.vessel.geometry import FAR_WALL_TOLERANCE

VESSELS = resources.files("guidewire") / "scenes" / "vessels"


@pytest.mark.parametrize("name", ["aortic_arch", "s_bend_branch"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_bounded_opening_test_equals_the_search_everywhere(name, seed):
    """Points along every tube (centreline ± up to the radius, so most wall points are far from a junction and a few
    sit in an opening): ``opening`` equals the plain test, the clearance of the wall point against the tolerance."""
    vessel = guidewire.load_scene(str(VESSELS / f"{name}.toml")).vessel
    rng = np.random.default_rng(seed)
    ways = [vessel.path(rng.uniform(0.0, vessel.length, 400))[0]]
    for k in range(len(vessel.branches)):  # (the way through each branch, a little past its junction on)
        ways.append(vessel.route(vessel.junction(k) + rng.uniform(-10.0, 40.0, 200), k)[0])
    centre = np.vstack(ways)
    points = centre + rng.uniform(-2.0, 2.0, centre.shape)
    near = vessel.clearance(points)
    inside = near.distance > 0.0
    b, d = near.boundary[inside], near.distance[inside]
    plain = vessel.clearance(b).distance > FAR_WALL_TOLERANCE * d
    np.testing.assert_array_equal(vessel.opening(b, d), plain)
    assert plain.any() and not plain.all()  # (the family reaches openings and plain walls alike)

