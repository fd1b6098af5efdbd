"""Figures tell the truth: a failed solve is marked, a success shows its contact forces."""

from __future__ import annotations

from dataclasses import replace
from importlib import resources

import matplotlib.colors as mcolors
import numpy as np
import pytest

import guidewire
from guidewire.app.plot import FAILURE_COLOR, plot_solution

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


def test_an_insertion_gif_renders_its_background_once(tmp_path):
    """100 steps through the aortic arch: one frame per step, all frames the same size, the wire moving; the whole
    animation costs less than a third of re-rendering the full figure for every frame (the old way, 10 s here;
    measured in the same run, so the bound holds on any machine), and under 10 s outright."""
    import io
    import time

    import numpy as np
    from PIL import Image

    from guidewire.app.plot_insertion import save_animation

    scene = guidewire.load_scene(str(VESSELS / "aortic_arch.toml"))
    ins = guidewire.insert(scene.with_wire(length=20.0, bars=20), np.linspace(20.0, 120.0, 100))
    path = tmp_path / "a.gif"
    started = time.perf_counter()
    save_animation(ins, path)
    elapsed = time.perf_counter() - started
    full = plot_solution(ins.steps[-1])
    started = time.perf_counter()
    for _ in range(3):
        full.savefig(io.BytesIO(), format="png", dpi=80)
    per_full_frame = (time.perf_counter() - started) / 3
    assert elapsed < min(100 * per_full_frame / 3, 10.0), (elapsed, per_full_frame)
    with Image.open(path) as gif:
        assert gif.n_frames == 100
        gif.seek(10)
        early = np.asarray(gif.convert("RGB"))
        gif.seek(90)
        late = np.asarray(gif.convert("RGB"))
    assert early.shape == late.shape and np.any(early != late)


def test_overlaid_shapes_are_named_and_the_pose_labels_drawn_once():
    """Fig. 4 draws five shapes in one panel: each carries its θ_B, and A and B are labelled once each."""
    from guidewire.app.plot import plot_group

    group = guidewire.paper_groups()["fig4"]
    sols = [guidewire.solve(scene, bars=30) for scene in group]
    ax = plot_group([(group[0], sols, None, "Fig. 4", "")]).axes[0]
    texts = [t.get_text() for t in ax.texts]
    names = sorted(t for t in texts if t.startswith(r"$\theta_{B}$"))
    assert names == sorted([r"$\theta_{B}$ = −π/2", r"$\theta_{B}$ = −π/4", r"$\theta_{B}$ = 0",
                            r"$\theta_{B}$ = π/4", r"$\theta_{B}$ = π/2"])
    assert texts.count("A") == 1 and texts.count("B") == 1


@pytest.mark.parametrize("value", [-1.179e-3, 6.48, 250.0])
def test_a_series_flat_to_rounding_is_drawn_flat_and_a_trend_is_not(value):
    """The insertion figure's push and energy axes: changes at the solves' rounding (1e-9 of the value, a free tip
    extended straight) are shown flat, ±10 % around the value, not autoscaled into a trend; a 1 % trend keeps
    matplotlib's own limits; no offset notation either way."""
    from matplotlib.figure import Figure

    from guidewire.app.plot_insertion import readable_axis

    flat = value * (1.0 + 1e-9 * np.array([0.0, 3.0, -2.0, 1.0]))
    trend = value * (1.0 + 1e-2 * np.arange(4.0))
    for series, drawn_flat in ((flat, True), (trend, False)):
        ax = Figure().subplots()
        ax.plot(np.arange(4.0), series)
        readable_axis(ax, series)
        lo, hi = ax.get_ylim()
        assert (hi - lo >= 0.19 * abs(value)) == drawn_flat
        assert lo <= series.min() and series.max() <= hi
        assert not ax.yaxis.get_major_formatter().get_useOffset()
