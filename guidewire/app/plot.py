"""Figures in the style of the paper's Figs. 4, 5, 6 and 13: equal aspect, the wire coloured by bending stress with a
colour bar, contacts with their tangent arrows, walls, the vessel (walls and dashed centrelines) when the scene has
one, and the continuum reference when given.

Needs matplotlib (the ``[plot]`` extra); it is imported only when a function here is called. The functions build
``matplotlib.figure.Figure`` objects directly (no pyplot), so they change no global state and need no display.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..scene.scene import Scene
from ..solve.result import Solution
from ..status import Status

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

STRESS_CMAP = "viridis"  # (perceptually uniform, readable in grey and by colour-blind readers)

#: The colour of a wire whose solve failed: drawn, so the user sees what was rejected, but never in stress colours.
FAILURE_COLOR = "crimson"
"""Colour map of the bending stress (the paper's figures use a rainbow map)."""


def load_matplotlib() -> Any:
    try:
        import matplotlib
    except ImportError as exc:  # pragma: no cover - exercised only without the extra
        raise ImportError(
            "guidewire.app.plot needs matplotlib: pip install 'guidewire-sqp[plot]'"
        ) from exc
    return matplotlib


def _wall_segment(normal: tuple[float, float], offset: float, box: np.ndarray) -> np.ndarray:
    """A stretch of the line ``n̂·p = offset`` covering ``box = [[xmin, ymin], [xmax, ymax]]``, shape (2, 2); the
    axis limits clip it."""
    nx, ny = normal
    direction = np.array([-ny, nx])
    foot = offset * np.array([nx, ny])
    radius = float(np.hypot(*(box[1] - box[0])))
    t0 = float(direction @ (box.mean(axis=0) - foot))
    return foot + np.outer([t0 - radius, t0 + radius], direction)


def draw_scene(ax: Axes, scene: Scene, *, arrow_length: float | None = None, color: str = "k",
               labels: bool = True) -> None:
    """Draw the base and the contacts of ``scene`` on ``ax``, with tangent arrows and (``labels``) their names."""
    length = arrow_length if arrow_length is not None else 0.08 * scene.wire.length
    poses = [(scene.base.name, scene.base.point, scene.base.angle)]
    poses += [(c.label(i), c.point, c.angle) for i, c in enumerate(scene.contacts) if c.point is not None]
    for name, point, angle in poses:
        ax.plot(*point, "o", color=color, markersize=4, zorder=4)
        if labels:  # (on the far side from the tangent arrow, so the arrow never hides the name)
            away = (4.0, -10.0) if angle is None else (-11.0 * math.cos(angle), -11.0 * math.sin(angle))
            ax.annotate(name, point, textcoords="offset points", xytext=away, fontsize=8, color=color,
                        ha="center" if angle is not None else "left", va="center", zorder=5,
                        bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.7, "pad": 0.5})
        if angle is not None:
            ax.annotate(
                "", xy=(point[0] + length * math.cos(angle), point[1] + length * math.sin(angle)), xytext=point,
                arrowprops={"arrowstyle": "->", "color": color, "lw": 1.0}, zorder=4,
            )


def draw_walls(ax: Axes, scene: Scene, box: np.ndarray) -> None:
    """Draw every wall of ``scene`` across ``box`` (hatched on the forbidden side)."""
    for wall in scene.walls:
        normal, offset = wall.unit()
        seg = _wall_segment(normal, offset, box)
        ax.plot(seg[:, 0], seg[:, 1], color="0.3", lw=2.0, zorder=1)
        shift = 0.02 * float(np.hypot(*(box[1] - box[0]))) * np.asarray(normal)
        band = np.vstack((seg, seg[::-1] + shift))
        ax.fill(band[:, 0], band[:, 1], facecolor="none", edgecolor="0.5", hatch="///", lw=0.0, zorder=1)


def draw_vessel(ax: Axes, vessel: Any, *, color: str = "0.35") -> None:
    """Draw a :class:`~guidewire.vessel.Vessel`: both walls of each tube (or the two walls) as lines, the parts of a
    wall inside another tube of the tree left out, and the centrelines dashed (mm)."""
    lines = vessel.wall_lines()
    scale = max(1.0, float(np.ptp(np.vstack(lines), axis=0).max()))
    for line in lines:
        inside = vessel.clearance(line).distance > 1e-6 * scale  # a branch's wall across its parent's lumen
        shown = np.where(inside[:, None], np.nan, line)
        ax.plot(shown[:, 0], shown[:, 1], color=color, lw=1.5, zorder=1)
    for centre in vessel.centrelines():
        ax.plot(centre[:, 0], centre[:, 1], ls="--", color=color, lw=0.7, zorder=1)


def draw_solution(
    ax: Axes, solution: Solution, *, norm: Any = None, reference: Any = None, linewidth: float = 3.0
) -> Any:
    """Draw one solved wire on ``ax``, coloured by bending stress (MPa); returns the ``LineCollection`` (None for a
    failed solve, drawn dashed in :data:`FAILURE_COLOR` without stresses).

    Each bar takes the larger stress of its two end nodes. ``reference`` (a continuum shape with ``.position(s)``)
    is drawn as a thin dashed black line on top.
    """
    mpl = load_matplotlib()
    from matplotlib.collections import LineCollection

    segments = np.stack((solution.nodes[:-1], solution.nodes[1:]), axis=1)
    if not solution.success:  # (no stresses of a failed solve: the shape in the failure colour, dashed)
        failed = LineCollection(segments, colors=FAILURE_COLOR, linewidths=0.6 * linewidth, linestyles="--",
                                zorder=2, label="failed solve")
        ax.add_collection(failed)
        return None
    stress = np.maximum(solution.bending_stress_mpa[:-1], solution.bending_stress_mpa[1:])
    if norm is None:
        norm = mpl.colors.Normalize(0.0, max(float(stress.max()), 1e-12))
    lines = LineCollection(segments, cmap=STRESS_CMAP, norm=norm, linewidths=linewidth, zorder=2)
    lines.set_array(stress)
    ax.add_collection(lines)
    if reference is not None:
        s = np.linspace(0.0, solution.scene.wire.length, 400)
        ref = reference.position(s)
        ax.plot(ref[:, 0], ref[:, 1], "k--", lw=0.8, zorder=3, label="continuum reference")
    return lines


def _box(points: np.ndarray) -> np.ndarray:
    lo, hi = points.min(axis=0), points.max(axis=0)
    pad = 0.08 * max(float(np.max(hi - lo)), 1.0)
    return np.array([lo - pad, hi + pad])


def _short_name(scene: Scene) -> str:
    """What tells overlaid scenes of one figure apart: the last prescribed tangent angle (``θ_B = −π/4``, in
    quarters of π where it is one), else the scene's name."""
    posed = [(c.label(i), c.angle) for i, c in enumerate(scene.contacts) if c.angle is not None]
    if not posed:
        return scene.name or ""
    name, angle = posed[-1]
    quarters = angle / (math.pi / 4)
    symbol = rf"$\theta_{{{name}}}$"
    if abs(quarters - round(quarters)) > 1e-9:
        return f"{symbol} = {angle:.4g}"
    k = int(round(quarters))
    text = {0: "0", 1: "π/4", 2: "π/2", 3: "3π/4", 4: "π"}.get(abs(k), f"{abs(k)}π/4")
    return f"{symbol} = {'−' if k < 0 else ''}{text}"


def plot_panel(
    ax: Axes,
    scene: Scene,
    solutions: Sequence[Solution],
    *,
    references: Sequence[Any] | None = None,
    norm: Any = None,
    title: str = "",
    message: str = "",
) -> Any:
    """One panel: the scenes' walls and vessel, every solution coloured by stress, their contacts; returns the last
    ``LineCollection`` (for a colour bar) or None. ``message`` is written in the panel (e.g. an infeasibility)."""
    points = [np.asarray([scene.base.point])]
    points += [np.asarray([c.point]) for c in scene.contacts if c.point is not None]
    points += [sol.nodes for sol in solutions]
    if scene.vessel is not None:
        points += scene.vessel.wall_lines()
    box = _box(np.vstack(points))
    draw_walls(ax, scene, box)
    if scene.vessel is not None:
        draw_vessel(ax, scene.vessel)
    last = None
    for i, sol in enumerate(solutions):
        ref = references[i] if references is not None else None
        last = draw_solution(ax, sol, norm=norm, reference=ref)
        draw_scene(ax, sol.scene, labels=i == 0)
        if len(solutions) > 1:  # overlaid shapes (Figs. 4 and 5): each named along itself, in place of a legend
            where = int((len(sol.nodes) - 1) * (0.2 + 0.6 * i / (len(solutions) - 1)))
            ax.annotate(_short_name(sol.scene), sol.nodes[where], textcoords="offset points",
                        xytext=(5, 5), fontsize=7, color="0.15", zorder=5,
                        bbox={"facecolor": "white", "edgecolor": "0.8", "alpha": 0.8, "pad": 0.8})
    if not solutions:
        draw_scene(ax, scene)
    if message:
        ax.text(0.03, 0.97, message, transform=ax.transAxes, fontsize=8, color="firebrick", va="top",
                bbox={"facecolor": "white", "edgecolor": "firebrick", "alpha": 0.9})
    ax.set_xlim(box[0, 0], box[1, 0])
    ax.set_ylim(box[0, 1], box[1, 1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.grid(True, lw=0.3, alpha=0.5)
    if title:
        ax.set_title(title, fontsize=9)
    return last


def plot_solution(solution: Solution, *, reference: Any = None, title: str | None = None) -> Figure:
    """A figure of one solved scene with a stress colour bar (MPa); a failed solve's title starts ``FAILED
    (STATUS):`` (before ``title`` when one is given) in the failure colour, with the message on the figure."""
    load_matplotlib()
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.0, 5.0), layout="constrained")
    ax = fig.add_subplot()
    refs = None if reference is None else [reference]
    heading = f"{solution.scene.name} ({solution.scheme}), E = {solution.energy:.4g} N·mm" if title is None else title
    if not solution.success:
        heading = f"FAILED ({status_name(solution.status)}): {solution.scene.name if title is None else title}"
        plot_panel(ax, solution.scene, [solution], references=refs, title=heading,
                   message=textwrap.fill(solution.message, 70))
        ax.title.set_color(FAILURE_COLOR)
        _fit_height(fig, ax)
        return fig
    lines = plot_panel(ax, solution.scene, [solution], references=refs, title=heading)
    draw_contact_forces(ax, solution)
    fig.colorbar(lines, ax=ax, label="bending stress σ (MPa)", shrink=0.8)
    _fit_height(fig, ax)
    return fig


def _fit_height(fig: Figure, ax: Axes) -> None:
    """Size the figure's height to the panel's aspect (equal axes), so that a wide vessel leaves no blank band."""
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    width = fig.get_figwidth()
    fig.set_figheight(float(np.clip(0.8 * width * (y1 - y0) / max(x1 - x0, 1e-9) + 1.0, 2.8, 8.0)))


def status_name(status: int) -> str:
    """The name of a :attr:`Solution.status` code (a :class:`guidewire.Status`)."""
    try:
        return Status(status).name
    except ValueError:
        return str(status)


def draw_contact_forces(ax: Axes, sol: Solution, *, scale: float | None = None) -> None:
    """Arrows of the wall/lumen contact forces on the wire (length ∝ force; ``scale`` mm per N)."""
    contacts = sol.contacts()
    if not contacts:
        return
    forces = np.array([c["force_n"] for c in contacts])
    if scale is None:
        scale = 0.1 * float(np.ptp(sol.nodes, axis=0).max() or 1.0) / float(forces.max())
    for c, f in zip(contacts, forces, strict=True):
        tip = np.asarray(c["point"])
        tail = tip + scale * f * np.asarray(c["normal"])  # the push points inwards, along −normal, onto the wire
        ax.annotate("", xy=tip, xytext=tail, arrowprops={"arrowstyle": "->", "color": "tab:red", "lw": 1.2},
                    zorder=4)


def plot_group(
    panels: Sequence[tuple[Scene, Sequence[Solution], Sequence[Any] | None, str, str]],
    *,
    suptitle: str = "",
) -> Figure:
    """Several panels side by side with one shared stress colour bar, as the paper's Figs. 4–6 and 13.

    Parameters
    ----------
    panels : sequence of (scene, solutions, references or None, title, message)
        One panel per entry; several solutions in one panel are overlaid (Fig. 4 draws the five θ_B together).
    suptitle : str
    """
    mpl = load_matplotlib()
    from matplotlib.figure import Figure

    stresses = [float(sol.bending_stress_mpa.max()) for _, sols, *_ in panels for sol in sols]
    norm = mpl.colors.Normalize(0.0, max(stresses + [1e-12]))
    fig = Figure(figsize=(5.0 * len(panels) + 1.0, 5.0), layout="constrained")
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    for ax, (scene, sols, refs, title, message) in zip(axes, panels, strict=True):
        plot_panel(ax, scene, sols, references=refs, norm=norm, title=title, message=message)
    mappable = mpl.cm.ScalarMappable(norm=norm, cmap=STRESS_CMAP)
    fig.colorbar(mappable, ax=list(axes), label="bending stress σ (MPa)", shrink=0.8)
    if suptitle:
        fig.suptitle(suptitle, fontsize=10)
    return fig
