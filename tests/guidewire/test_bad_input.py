"""Every bad scene file the reliability issue lists: a clear error naming the field and the fix, before any solve.

Each case is a scene file (the valid Table 1 scene below with one edit) and words its message must contain. The same
cases run through the Python API (``load_scene`` then ``solve``: ValueError/TypeError, and ``sqp.minimize`` is never
called) and through the command line (exit status 2, one line on stderr, no traceback).
"""

from __future__ import annotations

import re
import warnings

import pytest

import sqp
from guidewire import Section, Vessel, Wire, load_scene, solve
from guidewire.app import cli
from guidewire.fields import SuspiciousValueWarning
from guidewire.program.feasibility import infeasibility

VALID = """\
[wire]
length = 100.0
bars = 50

[base]
point = [0.0, 0.0]
angle = 0.0

[[contact]]
s = 100.0
point = [60.0, 40.0]
angle = 0.785398
"""

CONTACT_50 = "\n[[contact]]\ns = 50.0\npoint = [40.0, 20.0]\n"


def edit(old: str, new: str) -> str:
    assert old in VALID
    return VALID.replace(old, new)


CASES = {
    "not TOML": ("[wire\nlength = 100", "is not valid TOML"),
    "not UTF-8": (b"\xff\xfe[wire]", "not UTF-8"),
    "unknown key": (edit("length = 100.0", "lenght = 100.0"), "unknown key 'lenght'; did you mean 'length'?"),
    "unknown top-level key": ("colour = 'red'\n" + VALID, "unknown key 'colour'"),
    "unknown table": (VALID + "\n[[contcat]]\ns = 1.0\nangle = 0.0\n", "did you mean 'contact'?"),
    "wrong type (string)": (edit("length = 100.0", 'length = "100"'), "wire.length is '100' of type str"),
    "wrong type (point)": (edit("point = [0.0, 0.0]", "point = 0.0"), "base.point is 0.0"),
    "wrong type (table)": ("wire = 3\n" + VALID.split("\n", 3)[3], "[wire] is int; expected a table"),
    "wrong type (name)": ("name = 5\n" + VALID, "name is 5; expected a string"),
    "missing bars": (edit("bars = 50\n", ""), "missing the required key 'bars'; add it, e.g. bars = 100"),
    "missing base": (VALID.split("[base]")[0], "missing the required key 'base'"),
    "missing contact s": (edit("s = 100.0\n", ""), "[contact 1] is missing the required key 's'"),
    "length zero": (edit("length = 100.0", "length = 0.0"), "wire.length is 0.0; the inserted length must be positive"),
    "length negative": (edit("length = 100.0", "length = -5.0"), "wire.length is -5.0"),
    "bars zero": (edit("bars = 50", "bars = 0"), "wire.bars is 0; use at least 1 bar"),
    "bars fractional": (edit("bars = 50", "bars = 50.5"), "wire.bars is 50.5; expected a whole number"),
    "bars string": (edit("bars = 50", 'bars = "50"'), "wire.bars is '50'; expected a whole number"),
    "contact beyond the wire": (edit("s = 100.0", "s = 120.0"), "has s = 120; contacts need 0 < s ≤ wire.length"),
    "contact at the base": (edit("s = 100.0", "s = 0.0"), "has s = 0; contacts need 0 < s ≤ wire.length"),
    "contact at negative s": (edit("s = 100.0", "s = -1.0"), "has s = -1; contacts need 0 < s"),
    "two contacts at one s": (VALID + CONTACT_50.replace("50.0", "100.0"), "both at s = 100; give each arc length"),
    "contacts out of order": (VALID + CONTACT_50, "list contacts by strictly increasing s"),
    "NaN length": (edit("length = 100.0", "length = nan"), "wire.length is nan; expected a finite number"),
    "inf point": (edit("point = [60.0, 40.0]", "point = [inf, 40.0]"), "contact.point[0] is inf"),
    "NaN angle": (edit("angle = 0.785398", "angle = nan"), "contact.angle is nan"),
    "NaN base angle": (edit("angle = 0.0", "angle = nan"), "base.angle is nan"),
    "inf modulus": (edit("bars = 50", "bars = 50\nyoungs_modulus = inf"), "wire.youngs_modulus is inf"),
    "NaN b2": (edit("bars = 50", "bars = 50\nmax_relative_angle = nan"), "wire.max_relative_angle is nan"),
    "inf wall offset": (VALID + "\n[[wall]]\nnormal = [1.0, 0.0]\noffset = -inf\n", "wall.offset is -inf"),
    "contact with neither": (edit("point = [60.0, 40.0]\nangle = 0.785398\n", ""), "neither point nor angle"),
    "zero wall normal": (VALID + "\n[[wall]]\nnormal = [0.0, 0.0]\noffset = 5.0\n", "wall.normal is [0, 0]"),
    "contact outside a wall": (VALID + "\n[[wall]]\nnormal = [1.0, 0.0]\noffset = 45.0\n",
                               "(60, 40) lies outside wall 1 (1·x + 0·y ≤ 45); move the point inside"),
    "base outside a wall": (VALID + "\n[[wall]]\nnormal = [-1.0, 0.0]\noffset = -1.0\n",
                            "base (0, 0) lies outside wall 1"),
    "b2 too small for the turning": (edit("bars = 50", "bars = 50\nmax_relative_angle = 0.005"),
                                     "raise b₂ to at least 0.0154"),
    "b2 too small, paper scheme": (edit("bars = 50", "bars = 50\nmax_relative_angle = 0.005\nscheme = 'paper'"),
                                   "are 50 joints apart"),
    "b2 too small to reach a point": (
        edit("point = [60.0, 40.0]\nangle = 0.785398", "point = [0.0, 50.0]")
        .replace("bars = 50", "bars = 50\nmax_relative_angle = 0.01"),
        "reach at most 24.96"),
    "contacts too far apart": (edit("point = [60.0, 40.0]", "point = [90.0, 50.0]"),
                               "102.96 mm apart with only 100.0 mm of wire"),
    "taut with an angle a straight wire cannot meet": (
        edit("point = [60.0, 40.0]\nangle = 0.785398", "point = [100.0, 0.0]\nangle = 0.3"),
        "must be straight along 0 rad, but contact 1's prescribed angle is 0.3 rad"),
    "taut, base angle off the chord": (
        edit("point = [60.0, 40.0]\nangle = 0.785398", "point = [0.0, 100.0]"),
        "must be straight along 1.5708 rad, but base's prescribed angle is 0 rad"),
    "one bar between two points of another distance": (
        edit("bars = 50", "bars = 2").replace("point = [60.0, 40.0]\nangle = 0.785398", "point = [99.9, 0.0]")
        .replace("[[contact]]", "[[contact]]\ns = 50.0\npoint = [50.0, 0.0]\n\n[[contact]]", 1),
        "there is one bar of 50 mm, which must span 49.9 mm: rigid bars cannot"),
    "paper scheme, two bars, one fixed by the contact angle": (
        edit("bars = 50", "bars = 2\nscheme = 'paper'"),
        "besides the 1 bar(s) a prescribed angle fixes there is one bar of 50 mm, which must span 25.07"),
}


def _write(tmp_path, text):
    path = tmp_path / "scene.toml"
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    return path


def test_the_valid_scene_is_valid(tmp_path):
    scene = load_scene(_write(tmp_path, VALID))
    assert infeasibility(scene) is None
    assert solve(scene).success


@pytest.mark.parametrize("case", list(CASES))
def test_bad_scene_raises_before_any_solve_with_its_message(case, tmp_path, monkeypatch):
    text, words = CASES[case]
    called = []
    monkeypatch.setattr(sqp, "minimize", lambda *a, **k: called.append(1))
    with pytest.raises((ValueError, TypeError)) as info:
        solve(load_scene(_write(tmp_path, text)))
    assert words in str(info.value), str(info.value)
    assert not called


@pytest.mark.parametrize("case", list(CASES))
def test_bad_scene_exits_2_with_one_line(case, tmp_path, capsys, monkeypatch):
    text, words = CASES[case]
    monkeypatch.setattr(sqp, "minimize", lambda *a, **k: pytest.fail("solved a bad scene"))
    assert cli.main(["solve", str(_write(tmp_path, text))]) == cli.EXIT_BAD_INPUT
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.count("\n") == 1 and captured.err.startswith("error: ")
    assert re.sub(r"\s+", " ", words) in captured.err and "Traceback" not in captured.err


@pytest.mark.parametrize("diameter, unit", [(0.00036, "metres"), (0.0009, "metres"), (0.014, "inches"),
                                            (360.0, "µm"), (890.0, "µm")])
def test_a_wire_diameter_in_the_wrong_unit_warns_naming_the_field_and_the_unit(diameter, unit):
    with pytest.warns(SuspiciousValueWarning, match=rf"wire\.diameter is .* mm.*{unit}"):
        Wire(length=100.0, bars=10, diameter=diameter)
    with pytest.warns(SuspiciousValueWarning, match=r"section\.diameter"):
        Section(length=10.0, diameter=diameter)


@pytest.mark.parametrize("diameter", [0.05, 0.2, 0.36, 0.89, 2.0, 5.0])
def test_guidewire_and_catheter_diameters_pass_silently(diameter):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Wire(length=100.0, bars=10, diameter=diameter)


def test_a_lumen_radius_in_micrometres_warns_naming_the_field():
    with pytest.warns(SuspiciousValueWarning, match=r"vessel\.radius is 1500 mm.*µm give 1\.5 mm"):
        Vessel(centreline=[[0.0, 0.0], [10.0, 0.0]], radius=1500.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Vessel(centreline=[[0.0, 0.0], [300.0, 0.0]], radius=15.0)  # the aorta
