"""A trunk that ends in a bifurcation: the lumen goes on in its branches, not straight on past the trunk's end.

The trunk's tube ends in its last ball (as every tube begins in its first): a point straight past the end and
outside both branches is outside the lumen, the row there is that ball's (its derivatives checked against central
differences), an outlet keeps its straight continuation, and a wire pushed along the trunk turns into a branch."""

from __future__ import annotations

import math

import numpy as np
import pytest

from guidewire import Wire
from guidewire.solve3d import Scene3D, solve3d
from guidewire.vessel3d import Vessel3D
from guidewire.vessel3d.arch import ARCH_TYPES, aortic_arch


def _y(angle_deg: float, trunk: float = 40.0, arm: float = 40.0, radius: float = 3.0, tilt: float = 0.0) -> Vessel3D:
    """A straight trunk along ``+z`` (radius 3.2 mm) ending at ``(0, 0, trunk)`` where two straight arms of
    ``radius`` leave at ``±angle`` in a plane turned by ``tilt`` about the axis."""
    z = np.linspace(0.0, trunk, 21)
    main = np.column_stack((np.zeros_like(z), np.zeros_like(z), z))
    end = main[-1]
    s = np.linspace(0.0, arm, 21)
    arms = []
    for sign in (1.0, -1.0):
        a = math.radians(sign * angle_deg)
        d = np.array([math.sin(a) * math.cos(tilt), math.sin(a) * math.sin(tilt), math.cos(a)])
        arms.append((end + s[:, None] * d, radius))
    return Vessel3D.from_centreline(main, 3.2, arms)


@pytest.mark.parametrize("angle", [25.0, 40.0, 60.0])
@pytest.mark.parametrize("tilt", [0.0, 1.1])
def test_a_trunk_ending_in_a_bifurcation_has_no_lumen_straight_past_its_end(angle, tilt):
    """Points on the trunk's axis past its end: inside while in its last ball or in an arm, outside beyond — the
    carina (between the arms) is wall. Before, the trunk went on straight for 50 mm, through the carina."""
    vessel = _y(angle, tilt=tilt)
    trunk, left, right = vessel.tubes
    assert trunk.reach == 0.0 and left.reach > 0.0 and right.reach > 0.0
    past = np.linspace(0.5, 30.0, 60)
    points = np.column_stack((np.zeros_like(past), np.zeros_like(past), 40.0 + past))
    clearance, _ = vessel.clearance(points)
    # on the axis at height z above the end the arms' walls are at distance (z sin θ - 3 ...) : the point leaves
    # both arms where z sin(angle) exceeds the arm's radius (as the arms' axes part), and the trunk's last ball
    # at z = 3.2
    arm_leaves = 3.0 / math.sin(math.radians(angle))
    inside = past < max(3.2, arm_leaves) - 1e-6
    outside = past > max(3.2, arm_leaves) + 1e-6
    assert np.all(clearance[inside] > 0.0)
    assert np.all(clearance[outside] < 0.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_end_balls_row_matches_central_differences(seed):
    """Points just past the trunk's end, off the arms: the row is the end ball's (its closest ``u`` is the end), its
    gradient and Hessian (the ball's ``−I/a``) against central differences (step 1e-5 mm, errors ~1e-10)."""
    vessel = _y(70.0)
    trunk = vessel.tubes[0]
    rng = np.random.default_rng(seed)
    direction = rng.normal(size=(10, 3))
    direction[:, 2] = np.abs(direction[:, 2]) + 1.0  # (ahead of the end's plane)
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    p = np.array([0.0, 0.0, 40.0]) + rng.uniform(0.2, 2.5, 10)[:, None] * direction
    r = np.full(len(p), 0.2)
    g, grad, hess, e = trunk.rows(p, r)
    assert np.all(e.u == trunk.end) and np.all(e.at_cap)
    h = 1e-5
    for i in range(3):
        step = np.zeros(3)
        step[i] = h
        gp, dp, _, _ = trunk.rows(p + step, r)
        gm, dm, _, _ = trunk.rows(p - step, r)
        assert np.allclose((gp - gm) / (2 * h), grad[:, i], rtol=0, atol=1e-8)
        assert np.allclose((dp - dm) / (2 * h), hess[:, :, i], rtol=0, atol=1e-6)
    distance = np.linalg.norm(p - [0.0, 0.0, 40.0], axis=1)
    a = 3.2 - 0.2
    assert np.allclose(g, (a * a - distance**2) / (2 * a), rtol=0, atol=1e-12)


def test_an_outlet_and_a_side_branch_keep_the_straight_continuation():
    """A branch leaving the trunk's side (not at its end) leaves the trunk an outlet: it goes on past its end."""
    z = np.linspace(0.0, 60.0, 31)
    main = np.column_stack((np.zeros_like(z), np.zeros_like(z), z))
    s = np.linspace(0.0, 30.0, 16)
    side = np.array([0.0, 0.0, 30.0]) + s[:, None] * np.array([math.sin(0.6), 0.0, math.cos(0.6)])
    vessel = Vessel3D.from_centreline(main, 3.0, [(side, 2.0)])
    assert vessel.tubes[0].reach >= 50.0 and vessel.tubes[1].reach >= 50.0
    clearance, _ = vessel.clearance(np.array([[0.0, 0.0, 60.0 + d] for d in (5.0, 20.0, 45.0)]))
    assert np.all(clearance > 2.9)


@pytest.mark.parametrize("arch_type", ARCH_TYPES)
def test_the_arch_trunks_end_in_their_branches(arch_type):
    """In stEVE's arches exactly the trunks that branches leave from at their end are closed there."""
    from guidewire.vessel3d.arch import _LAYOUT

    vessel = aortic_arch(arch_type)
    names = vessel.tube_names
    parents = {row[2] for row in _LAYOUT["Va" if arch_type == "V" else arch_type] if row[3] == "end"}
    for name, tube in zip(names, vessel.tubes, strict=True):
        assert (tube.reach == 0.0) == (name in parents), name


@pytest.mark.parametrize("length", [60.0, 75.0])
def test_a_wire_pushed_along_the_trunk_turns_into_an_arm(length):
    """A wire longer than the trunk, solved cold, lies in one arm: every node in the lumen, the tip in an arm (not
    past the trunk's end on its axis, where the old continuation let it go straight)."""
    vessel = _y(35.0, tilt=0.3)
    wire = Wire(length=length, bars=int(length), youngs_modulus=60000.0, diameter=0.36)
    sol = solve3d(Scene3D.in_vessel(wire, vessel))
    assert sol.success, sol.message
    clearance, _ = vessel.clearance(sol.nodes, 0.18)
    assert clearance.min() > -1e-6
    tip = vessel.tube_of(sol.nodes[-1:])[0]
    assert tip in (1, 2)
    assert math.hypot(sol.nodes[-1, 0], sol.nodes[-1, 1]) > 3.0


@pytest.mark.parametrize(("child", "length", "on_fork"), [("right_common_carotid", 334.0, True),
                                                          ("right_subclavian", 344.0, False)])
def test_a_wire_through_the_trunks_bifurcation_slides_over_its_creases(child, length, on_fork):
    """stEVE's J wire in the type I arch, solved cold from a start along the centrelines through the
    brachiocephalic trunk into one of its two branches (tip 20-30 mm in): it converges with the tip in that branch,
    every bar keeps its radius from the creases it crosses (the trunk's opening and the bifurcation's, its true
    nearest pair), every node in the lumen, balance — and the contacts hold it along itself by less than 2 % of
    their force (measured 0.3 and 0.8 %; where the bifurcation had the tubes' rows and the trunk went on straight
    past its end, 9.5 % in the carotid, and the subclavian's start ended in the trunk's straight continuation). Into
    the carotid the wire rests on the bifurcation's crease (``on_fork``), into the subclavian on the trunk's opening
    only."""
    from pathlib import Path

    from guidewire.solve3d.file import load_scene
    from guidewire.solve3d.insert import scene_at
    from guidewire.solve3d.program import bar_layout

    root = Path(__file__).resolve().parents[2]
    scene = load_scene(root / "guidewire" / "scenes" / "vessels3d" / "aortic_arch_I.toml")
    vessel = scene.vessel
    target = scene_at(scene, length, 0.0, scene.wire.bars / scene.wire.length)
    lengths, _ = bar_layout(target)
    sol = solve3d(target, initial_nodes=vessel.route(np.concatenate(([0.0], np.cumsum(lengths))), child))
    assert sol.success, sol.message
    assert vessel.tube_names[vessel.tube_of(sol.nodes[-1:])[0]] == child
    middle = np.cumsum(sol.lengths) - 0.5 * sol.lengths
    radius = 0.5 * target.wire.properties_at(middle).diameter
    a, b = sol.nodes[:-1], sol.nodes[1:]
    held = False
    for crease in vessel.creases:
        tau, phi = crease._segments(a, b)
        gap = np.linalg.norm(a + tau[:, None] * (b - a) - crease.spline(phi), axis=1)
        mine = np.asarray(crease.owned)[crease.arc_at(phi)] & ~crease.at_corner(phi)
        assert np.min((gap - radius)[mine]) >= -1e-6
        held |= bool(crease.corners.size > 0 and np.min((gap - radius)[mine]) < 1e-6)
    assert held == on_fork
    node_radius = np.maximum(radius, np.append(radius[1:], radius[-1]))
    assert vessel.lumen_rows(sol.nodes[1:], node_radius)[0].min() >= -1e-6
    total = sum(f.magnitude for f in sol.forces)
    force, moment = sol.balance()
    assert force <= 1e-6 * max(total, 1.0) and moment <= 1e-6 * 400.0 * max(total, 1.0)
    assert abs(sol.tangential_contact_force()) <= 0.02 * total


@pytest.mark.parametrize("arch_type", ARCH_TYPES)
def test_every_arch_types_creases_lie_on_their_walls(arch_type):
    """Every type's creases: each on its walls between its knots to ``WALL_TOL`` (the common-origin trunks of types
    IV and VI, bent to 0.95 of their radius, to 1e-2 mm: their own closest-ball search, module docstring), and a
    crease around every branch that leaves a tube's side — the bovine arch's (II) brachiocephalic trunk too, from
    whose side its left common carotid leaves."""
    from guidewire.vessel3d.crease import WALL_TOL

    vessel = aortic_arch(arch_type)
    names = vessel.tube_names
    for crease in vessel.creases:
        tolerance = 1e-2 if "trunk" in names[crease.branch] else WALL_TOL
        assert crease.wall_error() <= tolerance, names[crease.branch]
    with_crease = {names[c.branch] for c in vessel.creases}
    if arch_type == "II":
        assert {"brachiocephalic", "left_common_carotid", "right_common_carotid", "right_subclavian"} <= with_crease


@pytest.mark.parametrize("arch_type", ["I", "II", "IV", "VI"])
def test_a_route_runs_along_the_centrelines_into_each_tube(arch_type):
    """``Vessel3D.route``: from the entrance, points 1 mm apart along the centrelines (chords of 1 mm to the
    centrelines' sampling), through every tube on the way to the asked tube's end (inside the lumen all the way, the
    middle of the last stretch in the asked tube); a bad name is refused naming the tubes."""
    vessel = aortic_arch(arch_type)
    s = np.arange(0.0, 400.0, 1.0)
    for name in vessel.tube_names[1:]:
        points = vessel.route(s, name)
        assert np.allclose(points[0], vessel.entrance[0], atol=1e-12)
        chords = np.linalg.norm(np.diff(points, axis=0), axis=1)
        assert np.all(chords <= 1.0 + 1e-9) and np.all(chords > 0.95)
        index = vessel.tube_names.index(name)
        tube = vessel.tubes[index]
        end = int(np.argmin(np.linalg.norm(points - tube.points[-1], axis=1)))  # (where the route ends the tube)
        assert np.linalg.norm(points[end] - tube.points[-1]) <= 0.5
        assert vessel.clearance(points[: end + 1])[0].min() > 0.0
        middle = end - int(0.5 * tube.end)
        assert vessel.tube_of(points[middle:middle + 1])[0] == index
    with pytest.raises(ValueError, match="tubes are main"):
        vessel.route(s, "aorta_root")


def _bent_y(sign: float, order: tuple[int, int] = (0, 1)) -> Vessel3D:
    """A trunk bending toward ``+x`` (``sign`` 1) or ``−x`` (−1) that ends in two arms at ±35° in the x-z plane
    (arm 0 on the bend's outer side), listed in ``order``: mirror images of one another in ``x → −x``."""
    z = np.linspace(0.0, 40.0, 21)
    main = np.column_stack((sign * 0.004 * z**2, np.zeros_like(z), z))
    end = main[-1]
    s = np.linspace(0.0, 40.0, 21)
    arms = [(end + s[:, None] * np.array([sign * side * math.sin(0.61), 0.0, math.cos(0.61)]), 2.5)
            for side in (1.0, -1.0)]
    return Vessel3D.from_centreline(main, 3.0, [arms[k] for k in order])


@pytest.mark.parametrize("length", [55.0, 70.0])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_the_carina_holds_a_wire_the_same_whichever_crease_holds_it(length, sign):
    """A wire started along the centrelines into the arm on the bend's inner side wraps the carina (a crease
    contact there, nothing along the wire). The same vessel with its arms listed the other way round — the carina
    then held by the other arm's crease — and its mirror image give the same answer: energy to 1e-7 (relative),
    nodes to 1e-4 mm."""
    from guidewire.solve3d.program import bar_layout

    wire = Wire(length=length, bars=int(length), youngs_modulus=60000.0, diameter=0.36)
    answers = []
    vessels = ((_bent_y(1.0), 2), (_bent_y(1.0, (1, 0)), 1), (_bent_y(-1.0), 2))
    holders = []
    for vessel, _ in vessels[:2]:  # (the arm whose crease holds the carina: the later-listed one)
        holder = [c.branch for c in vessel.creases for o, own in zip(c.others, c.owned, strict=True) if o and own]
        assert len(holder) == 1
        holders.append(vessel.tubes[holder[0]].points[-1])
    assert np.linalg.norm(holders[0] - holders[1]) > 10.0
    for vessel, arm in vessels:
        scene = Scene3D.in_vessel(wire, vessel)
        lengths, _ = bar_layout(scene)
        sol = solve3d(scene, initial_nodes=vessel.route(np.concatenate(([0.0], np.cumsum(lengths))), arm))
        assert sol.success, sol.message
        assert any(f.kind == "crease" and f.magnitude > 0.05 for f in sol.forces)
        assert abs(sol.tangential_contact_force()) < 1e-9
        answers.append(sol)
    first, swapped, mirrored = answers
    assert swapped.energy == pytest.approx(first.energy, rel=1e-7)
    assert mirrored.energy == pytest.approx(first.energy, rel=1e-7)
    np.testing.assert_allclose(swapped.nodes, first.nodes, atol=1e-4)
    np.testing.assert_allclose(mirrored.nodes * [-1.0, 1.0, 1.0], first.nodes, atol=1e-4)
