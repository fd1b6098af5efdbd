"""Scenes that once broke the solver (found by the property tests): each must now be solved, and solved right."""

from __future__ import annotations

import math

import numpy as np
import pytest

from guidewire import Base, Contact, Scene, Wall, Wire, paper_scenes, solve
from guidewire.fields import SuspiciousValueWarning
from guidewire.program.feasibility import infeasibility
from guidewire.status import SHAPE_REJECTED


def test_nearly_taut_stretch_between_two_points_is_solved_by_the_bfgs_fallback():
    # three bars span a chord 0.04 % shorter than themselves: the exact-Hessian Newton-SQP stalls there (the
    # Lagrangian Hessian is indefinite on the constraints' null space at its early multiplier estimates)
    scene = Scene(Wire(40.0, 20), Base((0.0, 0.0), 0.0),
                  (Contact(26.0, (23.73222646196566, 6.140930078963846)),
                   Contact(32.0, (28.65398708387217, 2.7136899116487796))))
    sol = solve(scene)
    assert sol.success, sol.message
    assert "damped BFGS" in sol.message and "exact-Hessian run ended" in sol.message
    assert sol.max_violation <= 1e-9 and sol.result.kkt["stationarity"] <= 1e-8
    bfgs = solve(scene, hessian="bfgs")
    assert sol.energy == pytest.approx(bfgs.energy, rel=1e-8)


@pytest.mark.parametrize("angle", [0.0, 0.5, 1.0, -1.0, 2.5])
def test_a_straight_taut_wire_is_solved_in_any_orientation(angle):
    # the start's chord direction is taken in the base angle's winding (atan2 wraps at ±π)
    scene = Scene(Wire(40.0, 20), Base((0.0, 0.0), 3.0),
                  (Contact(6.0, (6.0 * math.cos(3.0), 6.0 * math.sin(3.0))),)).rotated(angle)
    sol = solve(scene)
    assert sol.success, sol.message
    assert sol.energy == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(sol.bar_angles, 3.0 + angle, atol=1e-9)


def test_prescribed_angles_are_literal_a_full_turn_more_is_a_loop():
    """θ + 2π is taken literally: the wire turns a full loop more to meet it. In the plane a loop crosses itself,
    which no wire can do, so the converged shape is reported as rejected (not as a success), and says why."""
    base = paper_scenes()["table1_pi_4"].with_scheme("paper")
    contact = base.contacts[0]
    with pytest.warns(SuspiciousValueWarning, match="contact.angle is 7.06858 rad, more than a full turn"):
        looped = Scene(base.wire, base.base, (Contact(contact.s, contact.point, contact.angle + 2.0 * math.pi),))
    plain, loop = solve(base), solve(looped)
    assert plain.success, plain.message
    assert not loop.success and loop.status == SHAPE_REJECTED and "cross each other" in loop.message
    assert loop.result.success  # the program itself converged: only the shape check rejects it
    assert loop.bar_angles[-1] == pytest.approx(contact.angle + 2.0 * math.pi, abs=1e-9)
    assert loop.bar_angles[-1] - loop.bar_angles[0] > 2.0 * math.pi - 1.0  # the wire turns a full loop more
    assert loop.energy > 5.0 * plain.energy
    assert loop.wall_forces is None and all(r.force is None for r in loop.reactions)


def _arc_point(s: float, curvature: float, angle: float) -> tuple[float, float]:
    """The point at arc length ``s`` of a circular arc from the origin with tangent ``angle`` there."""
    x, y = math.sin(curvature * s) / curvature, (1.0 - math.cos(curvature * s)) / curvature
    return (x * math.cos(angle) - y * math.sin(angle), x * math.sin(angle) + y * math.cos(angle))


@pytest.mark.parametrize("slack", [1e-4, 1e-7, 1e-9, 1e-11, 1e-12])
@pytest.mark.parametrize("base_angle", [2.0, None])
def test_nearly_taut_wire_between_two_points_is_solved_in_a_few_iterations(slack, base_angle):
    # points on a very shallow circular arc: the chord of the whole arc is (1 - slack) times its length. A straight
    # start (the old one) made the position rows' Jacobian lose rank and ended LINE_SEARCH at iteration 0; the
    # taut-angle check rejected slack 1e-8 with the base angle, which the slack does allow
    s1, s2 = 11.79, 50.11
    curvature = math.sqrt(24.0 * slack) / s2
    scene = Scene(Wire(70.75, 48), Base((0.0, 0.0), base_angle),
                  (Contact(s1, _arc_point(s1, curvature, 2.0)), Contact(s2, _arc_point(s2, curvature, 2.0))))
    assert infeasibility(scene) is None
    sol = solve(scene)
    assert sol.success, sol.message
    assert sol.iterations <= 8 and "BFGS" not in sol.message
    assert sol.max_violation <= 1e-10
    # the energy of the discrete arc the points lie on bounds the minimum (EI κ² / 2 over the clamped part)
    assert sol.energy <= 0.5 * scene.wire.bending_stiffness * curvature**2 * s2 * (1.0 + 1e-3)


def test_mirrored_wall_scene_gives_the_mirrored_shape():
    # found by hypothesis (nightly): the free part's start curved towards +κ whenever both signs cleared the wall, so
    # the mirrored scene started (and ended) on another branch, 42 mm away
    scene = Scene(Wire(40.0, 20), Base((0.0, 0.0), 2.1875), (Contact(6.0, (-4.345432334959481, 4.097300514564373)),),
                  (Wall((-0.8369595530782943, 0.5472647499254653), 24.226805831418574),))
    sol, mirrored = solve(scene), solve(scene.mirrored())
    assert sol.success and mirrored.success
    np.testing.assert_allclose(mirrored.nodes, sol.nodes * [1.0, -1.0], atol=1e-9)
    assert mirrored.energy == pytest.approx(sol.energy, rel=1e-12)
