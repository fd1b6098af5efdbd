"""``Section.refinement``: a section's bars per mm relative to the wire's own stretch (a J tip of finer bars, as SOFA
BeamAdapter's beam density per section and stEVE's J wire). The uniform layout shares the bars in proportion to length
times refinement, in 2-D and 3-D alike; an insertion keeps the bars per refined mm, so the tip keeps its bars."""

from __future__ import annotations

import math
import tomllib
from dataclasses import replace

import numpy as np
import pytest

import guidewire
from guidewire import Base, Scene, Section, Wire
from guidewire.chain import place_bars
from guidewire.chain.kinematics import scene_bars
from guidewire.scene.file import scene_from_dict
from guidewire.solve3d import Scene3D
from guidewire.solve3d.program import bar_layout

TIP = 15.0


def _wire(length: float, bars: int, refinement: float) -> Wire:
    return Wire(length=length, bars=bars, sections=(Section.arc(TIP / 0.4 / math.pi, 0.4 * math.pi,
                                                                refinement=refinement),))


@pytest.mark.parametrize("refinement", [0.5, 2.0, 2.886, 5.0])
@pytest.mark.parametrize("bars", [20, 57, 200])
def test_bars_are_shared_by_length_times_refinement_in_2d_and_3d(refinement, bars):
    """The tip section's and the shaft's bar counts are the largest-remainder shares of length × refinement (each
    within one of its ideal share), the bars sum to the wire, a node sits on the section boundary, and the planar and
    3-D layouts are the same bars."""
    wire = _wire(100.0, bars, refinement)
    planar, _ = scene_bars(Scene(wire=wire, base=Base(point=(0.0, 0.0), angle=0.0)))
    spatial, _ = bar_layout(Scene3D(wire=wire))
    np.testing.assert_array_equal(planar, spatial)
    assert planar.size == bars and np.sum(planar) == pytest.approx(100.0, rel=1e-12)
    s = np.concatenate(([0.0], np.cumsum(planar)))
    tip = int(np.sum(s > 100.0 - TIP + 1e-9))  # bars wholly inside the tip section
    assert np.min(np.abs(s - (100.0 - TIP))) < 1e-9  # (a node on the boundary)
    ideal = bars * TIP * refinement / (100.0 - TIP + TIP * refinement)
    assert abs(tip - ideal) < 1.0
    assert abs((bars - tip) - (bars - ideal)) < 1.0
    shaft_bar, tip_bar = planar[0], planar[-1]
    np.testing.assert_allclose(planar[:bars - tip], shaft_bar, rtol=1e-12)  # equal within each piece
    np.testing.assert_allclose(planar[bars - tip:], tip_bar, rtol=1e-12)
    # the ratio of bar lengths is the refinement, to the rounding of the two counts
    ratio = shaft_bar / tip_bar
    low = (100.0 - TIP) / (bars - ideal + 1.0) / (TIP / max(ideal - 1.0, 1.0))
    high = (100.0 - TIP) / max(bars - ideal - 1.0, 1.0) / (TIP / (ideal + 1.0))
    assert low <= ratio <= high


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_refinement_of_one_is_the_plain_layout(seed):
    """``refinement = 1`` everywhere is the layout without refinement, bar for bar, whatever the contacts."""
    rng = np.random.default_rng(seed)
    contacts = np.sort(rng.uniform(5.0, 95.0, 3))
    plain = place_bars(100.0, 80, contacts, (85.0,))
    ones = place_bars(100.0, 80, contacts, (85.0,), refinement=lambda s: np.ones_like(s))
    np.testing.assert_array_equal(plain[0], ones[0])
    np.testing.assert_array_equal(plain[1], ones[1])
    assert not _wire(100.0, 80, 1.0).refined and _wire(100.0, 80, 2.0).refined


@pytest.mark.parametrize("refinement", [2.0, 3.0])
def test_a_planar_insertion_keeps_the_tips_bars_and_the_shafts_bar_length(refinement):
    """Pushed from 20 to 60 mm in 5 mm steps at 0.5 bar per refined mm: every step has the tip's share of bars
    within 1.5 of ``0.5 · 15 · refinement`` and shaft bars within rounding of 2 mm, and the bars per refined mm of
    the scene at every length."""
    wire = _wire(20.0, 10, refinement)
    assert wire.bar_density == pytest.approx(10 / (5.0 + TIP * refinement))
    scene = Scene(wire=replace(wire, bars=wire.bars_at(20.0, 0.5)), base=Base(point=(0.0, 0.0), angle=0.0))
    lengths = np.arange(25.0, 61.0, 5.0)
    out = guidewire.insert(scene, lengths)
    assert out.complete, out.error
    for length, sol in zip(lengths, out.steps, strict=True):
        s = np.asarray(sol.s)
        tip = int(np.sum(s > length - TIP + 1e-9))
        # (the step's bars are its refined length times the density rounded, ±1/2, shared by largest remainder, ±1)
        assert abs(tip - 0.5 * TIP * refinement) < 1.5
        shaft = np.diff(s)[: s.size - 1 - tip]
        assert np.all(np.abs(shaft - 2.0) <= 3.0 / shaft.size)  # (2 mm · |c − c_ideal| / c, |c − c_ideal| < 1.5)
        assert s.size - 1 == scene.wire.bars_at(length)


def test_refinement_in_a_scene_file_and_back():
    text = """
[base]
point = [0.0, 0.0]
angle = 0.0
[wire]
length = 50.0
bars = 40
[[wire.section]]
length = 15.0
rest_curvature = 0.08
refinement = 2.5
"""
    scene = scene_from_dict(tomllib.loads(text))
    assert scene.wire.sections[0].refinement == 2.5
    again = scene_from_dict(tomllib.loads(guidewire.scene_to_toml(scene)))
    assert again.wire == scene.wire
    plain = scene_from_dict(tomllib.loads(text.replace("refinement = 2.5\n", "")))
    assert plain.wire.sections[0].refinement == 1.0
    assert "refinement" not in guidewire.scene_to_toml(plain)


@pytest.mark.parametrize(("value", "error"), [(0.0, ValueError), (-2.0, ValueError), (math.inf, ValueError),
                                              ("2", TypeError), (True, TypeError)])
def test_a_bad_refinement_names_the_field(value, error):
    with pytest.raises(error, match="section.refinement"):
        Section(length=10.0, refinement=value)
