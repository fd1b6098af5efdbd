"""A wire inside a vessel: contacts found by the solver, checked as a user would — consistency with the paper's
contact-pose model, the wall scenes, forces normal/non-negative/balanced, second-order convergence, insertions that
stay inside the lumen and never cross themselves."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import guidewire
from guidewire import Base, Contact, Scene, Vessel, Wall, Wire, insert, paper_scenes, solve
from guidewire.chain.crossing import crossing_bars
from guidewire.solve.result import VIOLATION_FACTOR

VESSELS = "guidewire/scenes/vessels"


@pytest.fixture(scope="module")
def bend():
    return guidewire.load_scene(f"{VESSELS}/bend.toml")


def test_straight_channel_leaves_the_wire_straight():
    scene = guidewire.load_scene(f"{VESSELS}/straight_channel.toml")
    sol = solve(scene)
    assert sol.success and sol.energy == pytest.approx(0.0, abs=1e-12)
    assert sol.contacts() == [] and sol.entrance_force() == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(sol.nodes[:, 1], sol.nodes[0, 1], atol=1e-9)


def test_fig6b_as_a_vessel_reproduces_the_wall_result():
    """Fig. 6b's wall x ≤ 45 as one side of a wide vessel: the lumen keeps the wire's axis d/2 from the wall, so
    the answer is Fig. 6b's with the wall moved in by d/2."""
    fig6b = paper_scenes()["fig6b"]
    vessel = Vessel.from_walls([[45.0, -150.0], [45.0, 150.0]], [[-60.0, -150.0], [-60.0, 150.0]])
    in_vessel = solve(replace(fig6b, vessel=vessel, walls=()))
    half = 0.5 * fig6b.wire.diameter
    walled = solve(replace(fig6b, walls=(Wall((1.0, 0.0), 45.0 - half),)))
    assert in_vessel.success and walled.success
    assert in_vessel.energy == pytest.approx(walled.energy, rel=1e-9)
    np.testing.assert_allclose(in_vessel.nodes, walled.nodes, atol=1e-8)


def test_contacts_found_fed_back_as_poses_give_the_same_shape(bend):
    """The paper's model takes contact poses from collision detection; the poses the solver finds, given back as
    position contacts without the vessel, must reproduce the shape and the energy."""
    sol = solve(bend)
    found = sol.contacts()
    assert sol.success and found
    poses = tuple(Contact(c["s"], tuple(c["point"])) for c in found)
    again = solve(Scene(sol.scene.wire, sol.scene.base, poses))
    assert again.success
    assert again.energy == pytest.approx(sol.energy, rel=1e-8)
    np.testing.assert_allclose(again.nodes, sol.nodes, atol=1e-8)


def test_contact_forces_are_normal_non_negative_and_balance(bend):
    sol = solve(bend.with_wire(length=90.0, bars=90))
    contacts = sol.contacts()
    assert sol.success and contacts
    for c in contacts:
        assert c["force_n"] > 0
        on_node = sol.wall_forces[c["node"]]
        np.testing.assert_allclose(on_node, -c["force_n"] * np.asarray(c["normal"]), atol=1e-9)  # along −normal
    total = sol.wall_forces.sum(axis=0) + sol.reactions[0].force
    np.testing.assert_allclose(total, 0.0, atol=1e-9)
    assert abs(sol.moment_balance()) < 1e-5 * max(abs(sol.reactions[0].moment), 1e-3)
    # a frictionless wire with a free tip touches at isolated points: no three neighbouring nodes all in contact
    nodes = np.array([c["node"] for c in contacts])
    assert not np.any((nodes[2:] - nodes[:-2]) == 2)


def test_second_order_convergence_in_a_bend(bend):
    """Node error against a twice-finer chain shrinks by 4 per halving (measured 3.99999 and 3.99998)."""
    sols = {n: solve(bend.with_bars(n)) for n in (20, 40, 80)}
    e1 = np.max(np.abs(sols[20].nodes - sols[40].nodes[::2]))
    e2 = np.max(np.abs(sols[40].nodes - sols[80].nodes[::2]))
    assert all(s.success for s in sols.values())
    assert e1 / e2 == pytest.approx(4.0, rel=0.02)


@pytest.mark.parametrize(("name", "to", "step"), [("bend", 70.0, 5.0), ("tortuous", 40.0, 5.0)])
def test_insertion_stays_inside_the_lumen_and_never_crosses(name, to, step):
    scene = guidewire.load_scene(f"{VESSELS}/{name}.toml")
    out = insert(scene.with_wire(length=step, bars=max(1, round(step * scene.wire.bars / scene.wire.length))),
                 np.arange(step, to + 0.5 * step, step))
    assert out.complete
    for sol in out.steps:
        assert sol.success, sol.message
        # every node inside the lumen by d/2 (+ chord sag), not only the rows' nodes: to the documented
        # VIOLATION_FACTOR · tol · L (3e-6 mm at 30 mm)
        assert sol.max_violation <= VIOLATION_FACTOR * 1e-8 * sol.scene.wire.length
        assert crossing_bars(sol.nodes) is None
        clearance = sol.scene.vessel.clearance(sol.nodes[1:]).distance
        assert np.min(clearance) >= 0.5 * sol.scene.wire.diameter - 1e-5


def test_a_vessel_scene_starts_at_the_entrance_and_along_the_centreline(bend):
    vessel = bend.vessel
    assert bend.base.point == pytest.approx(vessel.entrance_point) and bend.base.angle == pytest.approx(
        vessel.entrance_angle)
    form = guidewire.formulate(bend)
    _, angles = vessel.path(form.chain.arc_lengths[:-1] + 0.5 * form.chain.lengths)
    np.testing.assert_allclose(form.x0, angles, atol=1e-12)
    assert [b.kind for b in form.blocks] == ["lumen"]


def test_the_base_must_be_inside_the_vessel(bend):
    outside = replace(bend, base=Base((0.0, 50.0), 0.0))
    with pytest.raises(ValueError, match="infeasible"):
        solve(outside)
    with pytest.raises(ValueError):
        Scene(Wire(10.0, 10), Base((0.0, 0.0), 0.0), vessel=Vessel.from_centreline([[0.0, 0.0]], 2.0))


@pytest.mark.parametrize("name", ["bend", "straight_channel_angled", "fig6b"])
def test_entrance_push_is_the_energy_rate(name, bend):
    """Virtual work: pushing ΔL more through a frictionless entrance costs ΔE, so the push equals dE/dL — the axial
    force at the entrance less the configurational force M₀²/(2EI) of a bent wire leaving a sleeve (measured: 0.0067
    = 0.0571 − 0.0504 N in the bend)."""
    if name == "fig6b":
        scene = paper_scenes()["fig6b"].with_wire(length=60.0, bars=200)
    else:
        scene = guidewire.load_scene(f"{VESSELS}/{name}.toml")
        scene = scene.with_wire(length=scene.wire.length + (20.0 if name == "bend" else 0.0), bars=200)
    h = 1e-3
    a, b = solve(scene), solve(scene.with_wire(length=scene.wire.length + h))
    assert a.success and b.success
    rate = (b.energy - a.energy) / h
    moment = a.reactions[0].moment
    assert abs(moment**2 / (2 * scene.wire.bending_stiffness)) > 0.01  # the configurational term matters here
    assert a.entrance_force() == pytest.approx(rate, abs=2e-3 * abs(a.axial_force()))


def test_a_tip_past_the_far_end_is_a_result_that_says_so(bend):
    inside, outside = solve(bend), solve(bend.with_wire(length=60.0, bars=60))  # the bend's centreline is 47.1 mm
    assert inside.success and "left the vessel" not in inside.message
    assert outside.success and "The tip has left the vessel past its far end." in outside.message
    assert bend.vessel.past_end([[0.0, 0.0]]).tolist() == [False]
