"""Figures of an insertion (:func:`guidewire.insert`): the last shape with the contact forces, entrance force and
energy against the inserted length, and an animation of every step (needs matplotlib; GIFs through Pillow, which
matplotlib installs)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .insertion import Insertion
from .plot import _matplotlib, draw_contact_forces, plot_panel


def plot_insertion(insertion: Insertion) -> Any:
    """Two panels: the last step's shape (stress colours, contact forces) and entrance force and energy against the
    inserted length (failed steps marked)."""
    _matplotlib()
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
    ax_force.grid(True, lw=0.3, alpha=0.5)
    ax_force.set_title("push and energy along the insertion", fontsize=9)
    return fig


def save_animation(insertion: Insertion, path: str | Path, *, fps: int = 10) -> None:
    """Write every step as one frame of an animation (a ``.gif`` through Pillow), on the axes of the last step."""
    _matplotlib()
    from matplotlib.animation import FuncAnimation, PillowWriter
    from matplotlib.figure import Figure

    steps = insertion.steps
    fig = Figure(figsize=(6.0, 5.0), layout="constrained")
    ax = fig.add_subplot()
    everything = np.vstack([s.nodes for s in steps])
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    pad = 0.08 * max(float(np.max(hi - lo)), 1.0)

    def frame(i: int) -> list[Any]:
        ax.clear()
        sol = steps[i]
        plot_panel(ax, sol.scene, [sol], title=f"inserted {sol.scene.wire.length:g} mm"
                   + ("" if sol.success else " (failed)"))
        draw_contact_forces(ax, sol)
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
        return []

    FuncAnimation(fig, frame, frames=len(steps), blit=False).save(str(path), writer=PillowWriter(fps=fps))
