"""The lumen keeps each node its own section's radius from the wall (issue 14): a thin tip may come closer."""

from __future__ import annotations

import math

import numpy as np
import pytest

import guidewire
from guidewire import Base, Scene, Section, Vessel, Wall, Wire, solve
from guidewire.blocks.lumen import node_diameters
from guidewire.program.model import build_model

J_TIP = Section.arc(12.1, 0.4 * math.pi, youngs_modulus=17_000.0, diameter=0.7)
SHAFT = {"youngs_modulus": 80_000.0, "diameter": 0.89}
H = 3.0  # half-width of the straight channel (mm)
CHANNEL = Vessel.from_walls([[-10.0, H], [100.0, H]], [[-10.0, -H], [100.0, -H]])


def test_node_diameters_take_the_section_and_the_larger_at_a_boundary():
    wire = Wire(10.0, 10, diameter=0.8, sections=(Section(2.0, diameter=0.5), Section(3.0, diameter=0.9)))
    model = build_model(Scene(wire, Base((0.0, 0.0), 0.0)))
    nodes = np.arange(1, 11)  # boundaries at s = 5 (0.8 | 0.9) and s = 8 (0.9 | 0.5)
    np.testing.assert_array_equal(node_diameters(model, nodes), [0.8] * 4 + [0.9] * 4 + [0.5] * 2)
    uniform = build_model(Scene(Wire(10.0, 10, diameter=0.8), Base((0.0, 0.0), 0.0)))
    np.testing.assert_array_equal(node_diameters(uniform, nodes), np.full(10, 0.8))


def test_a_thin_j_tip_touches_the_channel_wall_at_its_own_radius():
    """The J (tip OD 0.7 mm) curls up to the channel's wall y = 3: its tip node's centre stops at 3 − 0.35 mm, not at
    3 − 0.445 (the shaft's radius), and the answer is that of a straight wall at y = 2.65."""
    wire = Wire(40.0, 40, **SHAFT, sections=(J_TIP,))
    sol = solve(Scene(wire, Base((0.0, 0.0), 0.0), vessel=CHANNEL))
    assert sol.success
    contacts = sol.contacts()
    assert [c["node"] for c in contacts] == [40]  # the tip node only
    assert sol.nodes[-1, 1] == pytest.approx(H - 0.35, abs=1e-8)
    assert contacts[0]["force_n"] > 0.0
    walled = solve(Scene(wire, Base((0.0, 0.0), 0.0), walls=(Wall((0.0, 1.0), H - 0.35),)))
    assert walled.success and sol.energy == pytest.approx(walled.energy, rel=1e-9)
    np.testing.assert_allclose(sol.nodes, walled.nodes, atol=1e-8)


def test_a_single_section_wire_keeps_its_lumen():
    """A section with the wire's own diameter and stiffness changes nothing in a curved vessel (same layout: its
    boundary at s = 27 mm is a node of the 40-bar chain)."""
    bend = guidewire.load_scene("guidewire/scenes/vessels/bend.toml")
    plain = solve(bend)
    same = solve(bend.with_wire(sections=(Section(13.0, diameter=bend.wire.diameter,  # boundary on a node
                                                  moment_of_inertia=bend.wire.second_moment),)))
    assert plain.success and same.success
    assert same.energy == pytest.approx(plain.energy, rel=1e-10)
    np.testing.assert_allclose(same.nodes, plain.nodes, atol=1e-8)


def test_a_contact_point_is_checked_against_its_own_sections_radius():
    """A tip contact 0.3 mm from the channel's wall: room for the 0.5 mm tip (radius 0.25), not for the 0.9 mm shaft;
    the feasibility check takes the radius where the point lies on the wire."""
    wire = Wire(40.0, 40, youngs_modulus=80_000.0, diameter=0.9,
                sections=(Section(10.0, diameter=0.5, youngs_modulus=17_000.0),))
    contact = guidewire.Contact(40.0, point=(39.0, H - 0.3))
    scene = Scene(wire, Base((0.0, 0.0), 0.0), contacts=(contact,), vessel=CHANNEL)
    sol = solve(scene)
    assert sol.success
    assert sol.nodes[-1] == pytest.approx([39.0, H - 0.3], abs=1e-8)
    assert np.all(np.abs(sol.nodes[:, 1]) <= H - 0.5 * node_diameters(build_model(scene), np.arange(0, 41)) + 1e-8)
    thick = scene.with_wire(sections=())  # the whole wire 0.9 mm: the point is too close to the wall
    with pytest.raises(ValueError, match="too close to the lumen's wall"):
        solve(thick)
