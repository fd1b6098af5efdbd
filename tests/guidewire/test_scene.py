"""Scene values, scene files and the feasibility check: bad input is refused with a message naming the field."""

from __future__ import annotations

import math

import pytest

from guidewire import Base, Contact, Scene, Wall, Wire, load_scene, paper_scenes, scene_to_toml
from guidewire.program.feasibility import check_feasible, infeasibility
from guidewire.scene.paper import paper_wire, scene_path


def _scene(**changes):
    fields = {"wire": Wire(100.0, 100), "base": Base((0.0, 0.0), 0.0), "contacts": (Contact(100.0, (60.0, 40.0), 0.0),)}
    fields.update(changes)
    return Scene(**fields)


@pytest.mark.parametrize(
    ("build", "error", "words"),
    [
        (lambda: Wire(-1.0, 10), ValueError, "wire.length"),
        (lambda: Wire(100.0, 0), ValueError, "wire.bars"),
        (lambda: Wire(100.0, 2.5), TypeError, "wire.bars"),
        (lambda: Wire(100.0, 10, youngs_modulus=0.0), ValueError, "wire.youngs_modulus"),
        (lambda: Wire(100.0, 10, scheme="third"), ValueError, "wire.scheme"),
        (lambda: Wire(100.0, 10, max_relative_angle=-0.1), ValueError, "max_relative_angle"),
        (lambda: Wire(float("nan"), 10), ValueError, "wire.length"),
        (lambda: Base((0.0,), 0.0), ValueError, "base.point"),
        (lambda: Base("origin"), TypeError, "base.point"),
        (lambda: Contact(10.0), ValueError, "neither point nor angle"),
        (lambda: Wall((0.0, 0.0), 1.0), ValueError, "wall.normal"),
        (lambda: _scene(contacts=(Contact(120.0, (60.0, 40.0)),)), ValueError, "0 < s ≤ wire.length"),
        (lambda: _scene(contacts=(Contact(0.0, (0.0, 0.0)),)), ValueError, "0 < s ≤ wire.length"),
        (lambda: _scene(contacts=(Contact(60.0, (1.0, 1.0)), Contact(50.0, (2.0, 2.0)))), ValueError, "increasing"),
        (lambda: _scene(wire=Wire(100.0, 1), contacts=(Contact(50.0, (40.0, 0.0)),)), ValueError, "one bar per"),
        (lambda: _scene(wire="wire"), TypeError, "scene.wire"),
    ],
)
def test_bad_values_are_refused_naming_the_field(build, error, words):
    with pytest.raises(error, match=words):
        build()


def test_wire_stiffness_defaults_and_paper_value():
    assert Wire(1.0, 1).second_moment == pytest.approx(math.pi * 0.78**4 / 64)
    assert paper_wire().bending_stiffness == pytest.approx(64.6496, abs=1e-4)  # 3560 MPa × 0.01816 mm⁴


def test_table5_is_reported_infeasible_with_the_distances():
    scene = paper_scenes()["table5"]
    expected = (
        "P3 (80, 28.5) at s = 91.5 and P4 (98, 42.5) at s = 112.5 are 22.80 mm apart with only 21.0 mm of wire"
    )
    assert expected in infeasibility(scene)
    with pytest.raises(ValueError, match=r"22\.80 mm apart with only 21\.0 mm of wire"):
        check_feasible(scene)


def test_other_paper_scenes_are_feasible():
    assert [name for name, s in paper_scenes().items() if infeasibility(s)] == ["table5"]


def test_contact_outside_a_wall_is_infeasible():
    scene = _scene(walls=(Wall((1.0, 0.0), 45.0),))
    assert "outside wall 1" in infeasibility(scene)


def test_toml_round_trip_and_shipped_files_match_the_values(tmp_path):
    for name, scene in paper_scenes().items():
        assert load_scene(scene_path(name)) == scene, name
        path = tmp_path / f"{name}.toml"
        path.write_text(scene_to_toml(scene.with_wire(max_relative_angle=0.2)))
        assert load_scene(path) == scene.with_wire(max_relative_angle=0.2)


def test_issue_example_file_reads(tmp_path):
    path = tmp_path / "example.toml"
    path.write_text(
        """
[wire]
length = 100.0
bars = 100
youngs_modulus = 3560.0
diameter = 0.78
max_relative_angle = 0.2
scheme = "paper"

[base]
point = [0.0, 0.0]
angle = 0.0

[[contact]]
s = 100.0
point = [60.0, 40.0]
angle = 0.7853981634

[[wall]]
normal = [1.0, 0.0]
offset = 65.0
"""
    )
    scene = load_scene(path)
    assert scene.name == "example"
    assert scene.wire.scheme == "paper" and scene.wire.max_relative_angle == 0.2
    assert scene.contacts[0].point == (60.0, 40.0) and scene.walls[0].offset == 65.0


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("[wire]\nlength = 1\n", "missing"),
        ("[wire]\nlength = 10\nbars = 5\ncolour = 1\n[base]\npoint = [0, 0]\n", "unknown key"),
        ("[wire]\nlength = 10\nbars = 5\n[base]\npoint = [0, 0]\n[contact]\ns = 5\nangle = 0\n", r"\[\[contact\]\]"),
        ("[wire\n", "not valid TOML"),
        ("[wire]\nlength = -10\nbars = 5\n[base]\npoint = [0, 0]\n", "wire.length"),
        ("[wire]\nlength = 10\nbars = 5\n[base]\npoint = 'x'\n", "base.point"),
    ],
)
def test_bad_files_raise_value_error_with_the_path(tmp_path, text, words):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError, match=words):
        load_scene(path)


def test_helpers():
    scene = paper_scenes()["table4"]
    assert scene.with_bars(40).wire.bars == 40
    assert scene.with_scheme("paper").wire.scheme == "paper"
    mirrored = scene.mirrored()
    assert mirrored.base.angle == -scene.base.angle
    assert [c.point for c in mirrored.contacts] == [(c.point[0], -c.point[1]) for c in scene.contacts]
    assert mirrored.mirrored().contacts == scene.contacts
    assert paper_scenes()["fig6a"].mirrored().walls[0].normal == (1.5, 1.0)


def test_a_contact_at_the_end_up_to_rounding_is_at_the_end():
    length, n = 125.85925307380032, 24
    for s in (n * (length / n), length * (1 - 1e-15), length * (1 + 1e-15)):
        scene = _scene(wire=Wire(length, n), contacts=(Contact(s, (60.0, 40.0)),))
        assert scene.contacts[0].s == length
    assert _scene(contacts=(Contact(100.0 - 1e-6, (60.0, 40.0)),)).contacts[0].s == 100.0 - 1e-6
