"""Figures of an insertion (:func:`guidewire.insert`): the last shape with the contact forces, entrance force and
energy against the inserted length, and an animation of every step (needs matplotlib; GIFs through Pillow, which
matplotlib installs)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..march.insertion import Insertion
from .plot import FAILURE_COLOR, STRESS_CMAP, draw_contact_forces, load_matplotlib, plot_panel


def plot_insertion(insertion: Insertion) -> Any:
    """Two panels: the last step's shape (stress colours, contact forces) and entrance force and energy against the
    inserted length (failed steps marked)."""
    load_matplotlib()
    from matplotlib.figure import Figure

    steps = insertion.steps
    fig = Figure(figsize=(11.0, 4.8), layout="constrained")
    ax_shape, ax_force = fig.subplots(1, 2, width_ratios=(1.2, 1.0))
    last = steps[-1]
    lines = plot_panel(ax_shape, last.scene, [last], title=f"{last.scene.name or 'scene'}: inserted "
                       f"{last.scene.wire.length:g} mm, E = {last.energy:.4g} N·mm")
    draw_contact_forces(ax_shape, last)
    if lines is not None:
        fig.colorbar(lines, ax=ax_shape, label="bending stress σ (MPa)", shrink=0.8)
    length = np.array([s.scene.wire.length for s in steps])
    force = np.array([np.nan if s.entrance_force() is None else s.entrance_force() for s in steps])
    energy = np.array([s.energy if s.success else np.nan for s in steps])
    ax_force.plot(length, force, "-", color="tab:blue", label="push (N)")
    ax_force.set_xlabel("inserted length (mm)")
    ax_force.set_ylabel("push at the entrance, dE/dL (N)", color="tab:blue")
    ax_energy = ax_force.twinx()
    ax_energy.plot(length, energy, "-", color="tab:orange", label="bending energy (N·mm)")
    ax_energy.set_ylabel("bending energy (N·mm)", color="tab:orange")
    failed = [s.scene.wire.length for s in steps if not s.success]
    if failed:
        ax_force.plot(failed, np.zeros(len(failed)), "x", color="firebrick", label="failed step")
    readable_axis(ax_force, force)
    readable_axis(ax_energy, energy)
    ax_force.grid(True, lw=0.3, alpha=0.5)
    ax_force.set_title("push and energy along the insertion", fontsize=9)
    return fig


#: A series whose spread is at most this fraction of its size is drawn flat (:func:`readable_axis`).
FLAT_SPREAD = 1e-6


def readable_axis(ax: Any, values: Any) -> None:
    """Plain tick labels on ``ax``'s y axis (no offset such as ``1e-7 - 1.179e-3``), and a series flat to
    :data:`FLAT_SPREAD` of its size shown flat, ±10 % around it: its changes are the solves' rounding (a free tip
    extended straight keeps the energy to ~1e-9), which autoscaling would blow up into a trend."""
    ax.ticklabel_format(axis="y", useOffset=False)
    finite = np.asarray(values, dtype=float)
    finite = finite[np.isfinite(finite)]
    if not finite.size:
        return
    lo, hi = float(finite.min()), float(finite.max())
    size = max(abs(lo), abs(hi))
    if hi - lo <= FLAT_SPREAD * size:
        pad = 0.1 * size if size > 0.0 else 1.0
        ax.set_ylim(lo - pad, hi + pad)


#: The stress colour scale of an animation spans at least this (MPa).
STRESS_FLOOR_MPA = 1.0


def save_animation(insertion: Insertion, path: str | Path, *, fps: int = 10, dpi: int = 80) -> None:
    """Write every step as one frame of an animated ``.gif`` (through Pillow, which matplotlib installs).

    The frame is the whole vessel (every branch) and every shape of the insertion, rendered once; each step only
    draws the wire over that background, its stress colours on one scale fixed for the whole insertion (the colour
    bar's), its contact-force arrows and its length. A failed step is drawn dashed in the failure colour, without
    stresses. All frames share the first one's palette.
    """
    mpl = load_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure
    from PIL import Image

    steps = insertion.steps
    last = steps[-1]
    fig = Figure(figsize=(6.0, 5.0), dpi=dpi, layout="constrained")
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    plot_panel(ax, last.scene, [])  # the vessel, walls and supports
    points = [s.nodes for s in steps]
    if last.scene.vessel is not None:
        points += last.scene.vessel.wall_lines()
    everything = np.vstack(points)
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    pad = 0.05 * max(float(np.max(hi - lo)), 1.0)
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    # (at least STRESS_FLOOR_MPA: a stress-free wire is one colour, not rounding noise stretched over the scale)
    top = max([float(s.bending_stress_mpa.max()) for s in steps if s.success] + [STRESS_FLOOR_MPA])
    width, height = hi - lo + 2 * pad
    fig.set_size_inches(6.0, float(np.clip(4.2 * height / max(width, 1e-9) + 1.0, 3.0, 9.0)))
    wire = LineCollection([], cmap=STRESS_CMAP, norm=mpl.colors.Normalize(0.0, top), linewidths=3.0, zorder=2,
                          animated=True)
    ax.add_collection(wire)
    fig.colorbar(wire, ax=ax, label="bending stress σ (MPa)", shrink=0.8)
    label = ax.text(0.03, 0.97, "", transform=ax.transAxes, ha="left", va="top", fontsize=9, animated=True,
                    bbox={"facecolor": "white", "edgecolor": "0.7", "alpha": 0.9})
    canvas.draw()  # (the layout and the background, once)
    fig.set_layout_engine("none")
    background = canvas.copy_from_bbox(fig.bbox)
    frames = []
    for sol in steps:
        canvas.restore_region(background)
        wire.set_segments(np.stack((sol.nodes[:-1], sol.nodes[1:]), axis=1))
        if sol.success:
            wire.set_array(np.maximum(sol.bending_stress_mpa[:-1], sol.bending_stress_mpa[1:]))
            wire.set_linestyle("-")
        else:
            wire.set_array(None)
            wire.set_color(FAILURE_COLOR)
            wire.set_linestyle("--")
        ax.draw_artist(wire)
        before = len(ax.texts)
        draw_contact_forces(ax, sol)
        for arrow in ax.texts[before:]:
            ax.draw_artist(arrow)
            arrow.remove()
        label.set_text(f"inserted {sol.scene.wire.length:g} mm" + ("" if sol.success else " (FAILED)"))
        label.set_color("k" if sol.success else FAILURE_COLOR)
        ax.draw_artist(label)
        frames.append(Image.fromarray(np.asarray(canvas.buffer_rgba())[..., :3].copy()))
    first = frames[0].quantize(colors=255)
    rest = [f.quantize(palette=first, dither=Image.Dither.NONE) for f in frames[1:]]
    first.save(str(path), save_all=True, append_images=rest, duration=round(1000 / fps), loop=0)
