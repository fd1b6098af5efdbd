"""Figures of 3-D solutions: the vessel as a tube surface with the wire coloured by bending stress, and the two
projections a C-arm shows (AP: viewed along ``y``, the frontal plane ``x–z``; lateral: viewed along ``x``, the plane
``y–z``); an animation of an insertion; an interactive HTML view (plotly, the ``[html]`` extra).

Needs matplotlib (the ``[plot]`` extra), imported when a function is called.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .plot import FAILURE_COLOR, STRESS_CMAP, load_matplotlib, status_name

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..solve3d.insert import Insertion3D
    from ..solve3d.result import Solution3D
    from ..solve3d.scene import Scene3D

FloatArray = NDArray[np.float64]

TUBE_SPACING = 1.0
"""Spacing (mm) of the tube surface's rings."""

TUBE_SIDES = 24
"""Points per ring of the tube surface."""

PROJECTIONS = (("AP", (0, 2), "x (mm)", "z (mm)"), ("lateral", (1, 2), "y (mm)", "z (mm)"))
"""The two C-arm views: name, the two world axes drawn, their labels."""


def bending_stress(sol: Solution3D, scene: Scene3D) -> FloatArray:
    """Bending stress (MPa) at the nodes ``0..n``: ``E (d/2) |κ − κ⁰|`` at each inner joint from the discrete
    curvature binormal ``2 t_a × t_b / ((1 + t_a · t_b) l̄)`` less the rest curvature ``κ⁰ d₂`` (a J-tip bends toward
    its ``d₁``), with the joint's larger ``E d``; zero at the clamp and the tip."""
    t = sol.frames[:, 2]
    out = np.zeros(sol.n_bars + 1)
    if sol.n_bars < 2:
        return out
    a, b = t[:-1], t[1:]
    mean = 0.5 * (sol.lengths[:-1] + sol.lengths[1:])
    kappa = 2.0 * np.cross(a, b) / ((1.0 + np.einsum("ij,ij->i", a, b)) * mean)[:, None]
    s_mid = np.cumsum(sol.lengths) - 0.5 * sol.lengths
    props = scene.wire.properties_at(s_mid)
    d2 = 0.5 * (sol.frames[:-1, 1] + sol.frames[1:, 1])
    rest = 0.5 * (props.rest_curvature[:-1] + props.rest_curvature[1:])
    excess = np.linalg.norm(kappa - rest[:, None] * d2, axis=1)
    ed = np.maximum(props.youngs_modulus[:-1] * props.diameter[:-1], props.youngs_modulus[1:] * props.diameter[1:])
    out[1:-1] = 0.5 * ed * excess
    return out


def tube_rings(vessel: Any, spacing: float = TUBE_SPACING, sides: int = TUBE_SIDES) -> list[FloatArray]:
    """Per tube of ``vessel`` (main first) its surface points, shape (rings, sides, 3): circles of the lumen radius
    about the centreline in planes across it (frames carried along by projection, so they do not spin)."""
    out = []
    angle = np.linspace(0.0, 2.0 * np.pi, sides)
    for tube in vessel.tubes:
        u = np.linspace(0.0, tube.end, max(2, int(np.ceil(tube.end / spacing)) + 1))
        e = tube.evaluate(u)
        t = e.d1 / np.linalg.norm(e.d1, axis=1, keepdims=True)
        normals = np.empty_like(t)
        seed = np.eye(3)[int(np.argmin(np.abs(t[0])))]
        n = seed - (seed @ t[0]) * t[0]
        for i in range(len(t)):  # (a drawing helper over rings, not a solver path)
            n = n - (n @ t[i]) * t[i]
            n /= np.linalg.norm(n)
            normals[i] = n
        binormals = np.cross(t, normals)
        ring = (np.cos(angle)[None, :, None] * normals[:, None, :]
                + np.sin(angle)[None, :, None] * binormals[:, None, :])
        out.append(e.centre[:, None, :] + e.radius[:, None, None] * ring)
    return out


def _title(sol: Solution3D, name: str) -> tuple[str, str]:
    if sol.success:
        return (f"{name}: E = {sol.energy:.4g} N·mm (bending {sol.bending_energy:.4g}, twist {sol.twist_energy:.3g}), "
                f"{sol.n_bars} bars", "k")
    return f"{name}: FAILED ({status_name(sol.status)}) — {sol.message[:90]}", FAILURE_COLOR


def _draw_projection(ax: Axes, rings: list[FloatArray], axes: tuple[int, int]) -> None:
    for ring in rings:
        pts = ring.reshape(-1, 3)
        ax.plot(pts[:, axes[0]], pts[:, axes[1]], ",", color="0.6", alpha=0.25)


def plot_solution3d(sol: Solution3D, scene: Scene3D, *, title: str | None = None) -> Figure:
    """The wire of ``sol`` in ``scene``'s vessel: a 3-D view (tube surface, wire coloured by bending stress, contact
    forces as arrows) and the AP and lateral projections. A failed solve is drawn in crimson with its status in the
    title, never coloured as a shape."""
    mpl = load_matplotlib()
    from matplotlib import colors
    from matplotlib.cm import ScalarMappable
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the 3-D projection)

    fig = Figure(figsize=(15, 5.2))
    ax3 = fig.add_subplot(1, 3, 1, projection="3d")
    rings = tube_rings(scene.vessel) if scene.vessel is not None else []
    for ring in rings:
        ax3.plot_surface(ring[..., 0], ring[..., 1], ring[..., 2], color="0.7", alpha=0.12, linewidth=0)
    stress = bending_stress(sol, scene)
    norm = colors.Normalize(0.0, max(1.0, float(stress.max())))
    cmap = mpl.colormaps[STRESS_CMAP]
    p = sol.nodes
    if sol.success:
        for k in range(sol.n_bars):  # (one segment per bar so that each has its stress colour)
            ax3.plot(p[k:k + 2, 0], p[k:k + 2, 1], p[k:k + 2, 2], color=cmap(norm(0.5 * (stress[k] + stress[k + 1]))),
                     linewidth=2.5)
        for f in sol.forces:
            ax3.quiver(*f.point, *(f.normal * 3.0), color="tab:red", linewidth=1)
        sm = ScalarMappable(norm=norm, cmap=cmap)
        fig.colorbar(sm, ax=ax3, shrink=0.6, pad=0.12, label="bending stress (MPa)")
    else:
        ax3.plot(p[:, 0], p[:, 1], p[:, 2], color=FAILURE_COLOR, linewidth=2.0)
    ax3.set_xlabel("x (mm)")
    ax3.set_ylabel("y (mm)")
    ax3.set_zlabel("z (mm)")
    box = np.vstack([p] + [r.reshape(-1, 3) for r in rings])
    centre, half = 0.5 * (box.max(0) + box.min(0)), 0.5 * float(np.ptp(box, axis=0).max())
    ax3.set_xlim(centre[0] - half, centre[0] + half)
    ax3.set_ylim(centre[1] - half, centre[1] + half)
    ax3.set_zlim(centre[2] - half, centre[2] + half)
    for i, (name, axes, xl, yl) in enumerate(PROJECTIONS):
        ax = fig.add_subplot(1, 3, i + 2)
        _draw_projection(ax, rings, axes)
        ax.plot(p[:, axes[0]], p[:, axes[1]], color="k" if sol.success else FAILURE_COLOR, linewidth=1.8)
        ax.plot(*p[-1, list(axes)], "o", color="k" if sol.success else FAILURE_COLOR, markersize=3)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(name)
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
    text, colour = _title(sol, title or scene.name or "scene")
    fig.suptitle(text, color=colour)
    fig.tight_layout()
    return fig


def save_animation3d(out: Insertion3D, scene: Scene3D, path: str | Path, *, fps: int = 10) -> None:
    """A GIF of the insertion's steps in the AP and lateral projections (the tube drawn once, the wire per frame;
    a failed step in crimson)."""
    load_matplotlib()
    from matplotlib.animation import FuncAnimation, PillowWriter
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 5))
    axs = fig.subplots(1, 2)
    rings = tube_rings(scene.vessel) if scene.vessel is not None else []
    lines = []
    everything = np.vstack([s.nodes for s in out.steps] + [r.reshape(-1, 3) for r in rings])
    for ax, (name, axes, xl, yl) in zip(axs, PROJECTIONS, strict=True):
        _draw_projection(ax, rings, axes)
        (line,) = ax.plot([], [], color="k", linewidth=1.8)
        lines.append((line, axes))
        ax.set_xlim(everything[:, axes[0]].min() - 2, everything[:, axes[0]].max() + 2)
        ax.set_ylim(everything[:, axes[1]].min() - 2, everything[:, axes[1]].max() + 2)
        ax.set_aspect("equal", adjustable="box")
        ax.set_title(name)
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
    label = fig.suptitle("")

    def frame(i: int) -> list[Any]:
        sol = out.steps[i]
        for line, axes in lines:
            line.set_data(sol.nodes[:, axes[0]], sol.nodes[:, axes[1]])
            line.set_color("k" if sol.success else FAILURE_COLOR)
        rotation = np.degrees(out.rotations[i])
        state = "" if sol.success else f" FAILED ({status_name(sol.status)})"
        label.set_text(f"L = {out.lengths[i]:.1f} mm, rotation {rotation:.0f}°, E = {sol.energy:.3g} N·mm{state}")
        label.set_color("k" if sol.success else FAILURE_COLOR)
        return [line for line, _ in lines] + [label]

    animation = FuncAnimation(fig, frame, frames=len(out.steps), blit=False)
    animation.save(str(path), writer=PillowWriter(fps=fps))


def write_html(sol: Solution3D, scene: Scene3D, path: str | Path) -> None:
    """An interactive view (rotate, zoom) of the tube and the wire coloured by bending stress, as one HTML file.

    Raises
    ------
    ImportError
        When plotly is not installed: ``pip install "guidewire[html]"``.
    """
    try:
        import plotly.graph_objects as go
    except ImportError:
        raise ImportError('the interactive HTML view needs plotly: pip install "guidewire[html]"') from None
    data = []
    if scene.vessel is not None:
        for ring in tube_rings(scene.vessel):
            data.append(go.Surface(x=ring[..., 0], y=ring[..., 1], z=ring[..., 2], opacity=0.2, showscale=False,
                                   colorscale=[[0, "lightgrey"], [1, "lightgrey"]], hoverinfo="skip"))
    stress = bending_stress(sol, scene)
    p = sol.nodes
    data.append(go.Scatter3d(x=p[:, 0], y=p[:, 1], z=p[:, 2], mode="lines",
                             line={"width": 6, "color": stress if sol.success else FAILURE_COLOR,
                                   "colorscale": "Viridis", "showscale": sol.success,
                                   "colorbar": {"title": "stress (MPa)"}},
                             name="wire"))
    text, _ = _title(sol, scene.name or "scene")
    fig = go.Figure(data=data, layout={"title": text, "scene": {"aspectmode": "data", "xaxis_title": "x (mm)",
                                                                 "yaxis_title": "y (mm)", "zaxis_title": "z (mm)"}})
    fig.write_html(str(path), include_plotlyjs=True)
