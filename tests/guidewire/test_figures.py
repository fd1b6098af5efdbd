"""Figures tell the truth: a failed solve is marked, a success shows its contact forces."""

from __future__ import annotations

from dataclasses import replace
from importlib import resources

import matplotlib.colors as mcolors
import pytest

import guidewire
from guidewire.plot import FAILURE_COLOR, plot_solution

VESSELS = resources.files("guidewire") / "scenes" / "vessels"


@pytest.fixture(scope="module")
def solved():
    return guidewire.solve(guidewire.load_scene(str(VESSELS / "tortuous.toml")))


def test_a_success_draws_one_arrow_per_contact_and_a_stress_colour_bar(solved):
    assert solved.success and solved.contacts()
    fig = plot_solution(solved)
    ax = fig.axes[0]
    arrows = [a for a in ax.texts if getattr(a, "arrow_patch", None) is not None
              and mcolors.same_color(a.arrow_patch.get_edgecolor(), "tab:red")]
    assert len(arrows) == len(solved.contacts())
    assert len(fig.axes) == 2  # the panel and its colour bar
    assert "FAILED" not in ax.get_title()


def test_a_failed_solve_is_marked_in_title_colour_and_message(solved):
    failed = replace(solved, success=False, status=20, message="The solver converged, but the shape is rejected: x.")
    fig = plot_solution(failed)
    ax = fig.axes[0]
    assert ax.get_title().startswith("FAILED (SHAPE_REJECTED)")
    assert mcolors.same_color(ax.title.get_color(), FAILURE_COLOR)
    assert len(fig.axes) == 1  # no stress colour bar for a shape without stresses
    assert any("rejected" in t.get_text() for t in ax.texts)
    assert any(mcolors.same_color(c.get_edgecolor()[0], FAILURE_COLOR) for c in ax.collections
               if len(c.get_edgecolor()))
