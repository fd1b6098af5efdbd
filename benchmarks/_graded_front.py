"""The graded-density part of ``discrete_density.py --graded``: uniform against curvature-graded bars on every paper
scene with a continuum reference — mean node error against run time (the Pareto front), and the bars and time each
layout needs for a given mean node error (the measured gain of the paper's "discrete density by curvature").

Per scene and bar count ``n``: ``solve(scene, bars=n)`` (uniform) and ``solve(scene, bars=n, density="curvature")``
(a uniform coarse solve of ``max(10, 2·pieces, n // 2)`` bars, then ``n`` bars graded by its curvature; its time is
both solves), alternated in the same process, time the median of ``repeats``; error the mean distance of the nodes
from the exact continuum elastica at the same arc length. "At equal error": the bars and time to reach ``target``
mm, interpolated log-log between the two bar counts that bracket it.
"""

from __future__ import annotations

import math
import statistics
from pathlib import Path
from typing import Any

import _tables as T
import numpy as np

import guidewire
from guidewire.reference import continuum_reference
from guidewire.reference.scene_reference import node_errors

BARS = (10, 14, 20, 28, 40, 56, 80, 113, 160)
QUICK_BARS = (20, 40, 80)
DENSITIES = ("uniform", "curvature")


def run(repeats: int, quick: bool) -> list[dict[str, Any]]:
    """One row per scene × bar count × density."""
    scenes = guidewire.paper_scenes()
    if quick:
        scenes = {k: scenes[k] for k in ("table1_pi_4", "table4")}
    rows = []
    for name, scene in scenes.items():
        reference, _ = continuum_reference(scene)
        if reference is None:
            continue
        for n in QUICK_BARS if quick else BARS:
            times: dict[str, list[float]] = {d: [] for d in DENSITIES}
            sols: dict[str, Any] = {}
            for _ in range(repeats):
                for density in DENSITIES:  # alternated: the machine's load hits both alike
                    sols[density] = guidewire.solve(scene, bars=n, density=density)
                    times[density].append(sols[density].solve_time_s)
            for density in DENSITIES:
                sol = sols[density]
                lengths = np.diff(sol.s)
                rows.append({"scene": name, "density": density, "bars": n, "success": sol.success,
                             "time_s": statistics.median(times[density]), "repeats": repeats,
                             "mean_error_mm": float(np.mean(node_errors(sol, reference))) if sol.success else math.nan,
                             "longest_over_shortest": float(lengths.max() / lengths.min())})
    return rows


def at_error(rows: list[dict[str, Any]], target: float) -> tuple[float, float]:
    """``(bars, time_s)`` reaching mean error ``target``, log-log interpolated over ``rows`` (one scene, one
    density); nan when the bar counts do not bracket it."""
    pts = sorted((r["bars"], r["mean_error_mm"], r["time_s"]) for r in rows if r["success"])
    for (n0, e0, t0), (n1, e1, t1) in zip(pts, pts[1:], strict=False):
        if e0 >= target >= e1 and e0 > e1:
            w = math.log(e0 / target) / math.log(e0 / e1)
            return math.exp((1 - w) * math.log(n0) + w * math.log(n1)), math.exp((1 - w) * math.log(t0)
                                                                                 + w * math.log(t1))
    return math.nan, math.nan


def gain_table(rows: list[dict[str, Any]], target: float) -> tuple[list[str], list[list[Any]]]:
    """Per scene: bars and time at ``target`` for both densities, and their ratios."""
    body = []
    for name in dict.fromkeys(r["scene"] for r in rows):
        u = at_error([r for r in rows if r["scene"] == name and r["density"] == "uniform"], target)
        g = at_error([r for r in rows if r["scene"] == name and r["density"] == "curvature"], target)
        body.append([name, u[0], g[0], g[0] / u[0], 1e3 * u[1], 1e3 * g[1], g[1] / u[1]])
    header = ["scene", "uniform: bars", "graded: bars", "bars graded/uniform", "uniform: time (ms)",
              "graded: time (ms)", "time graded/uniform"]
    return header, body


def write(rows: list[dict[str, Any]], stem: Path, env: list[str], repeats: int, targets: tuple[float, ...]) -> None:
    T.write_csv(rows, stem.with_suffix(".csv"))
    lines = ["# Discrete density by curvature: uniform against curvature-graded bars (ours, paper scenes)", "",
             *[f"- {e}" for e in env], "- " + (__doc__ or "").split("\n\n")[1].replace("\n", " "),
             f"- time: median of {repeats} alternated runs, BLAS one thread", ""]
    for target in targets:
        header, body = gain_table(rows, target)
        ratios = [r[3] for r in body if np.isfinite(r[3])]
        tratios = [r[6] for r in body if np.isfinite(r[6])]
        lines += [f"## At a mean node error of {target:g} mm", ""] + T.markdown_table(header, body)
        if ratios:
            lines += ["", f"Bars graded/uniform: median {statistics.median(ratios):.3g}, range {min(ratios):.3g}–"
                      f"{max(ratios):.3g}; time graded/uniform: median {statistics.median(tratios):.3g}, range "
                      f"{min(tratios):.3g}–{max(tratios):.3g} ({len(ratios)} scenes).", ""]
    lines += ["## Every solve", ""] + T.markdown_table(
        ["scene", "density", "bars", "time (ms)", "mean error (mm)", "longest/shortest bar", "success"],
        [[r["scene"], r["density"], r["bars"], 1e3 * r["time_s"], r["mean_error_mm"], r["longest_over_shortest"],
          r["success"]] for r in rows])
    T.write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines[: lines.index("## Every solve")]))
    plot(rows, stem.with_suffix(".png"), targets)


def plot(rows: list[dict[str, Any]], path: Path, targets: tuple[float, ...]) -> None:
    plt = T.pyplot()
    if plt is None:
        return
    names = list(dict.fromkeys(r["scene"] for r in rows))
    fig, (ax_n, ax_t) = plt.subplots(1, 2, figsize=(14, 6))
    for i, name in enumerate(names):
        for density, style in (("uniform", "--"), ("curvature", "-")):
            rs = sorted((r for r in rows if r["scene"] == name and r["density"] == density and r["success"]),
                        key=lambda r: r["bars"])
            kw = {"color": f"C{i % 10}", "ls": style, "marker": "o" if density == "curvature" else "s", "ms": 3,
                  "label": name if density == "curvature" else None}
            ax_n.loglog([r["bars"] for r in rs], [r["mean_error_mm"] for r in rs], **kw)
            ax_t.loglog([1e3 * r["time_s"] for r in rs], [r["mean_error_mm"] for r in rs], **kw)
    for ax in (ax_n, ax_t):
        for target in targets:
            ax.axhline(target, color="grey", lw=0.8, ls=":")
        ax.grid(True, which="both", alpha=0.3)
        ax.set_ylabel("mean node error against the continuum (mm)")
    ax_n.set_xlabel("bars n")
    ax_t.set_xlabel("run time (ms, median; graded includes its coarse solve)")
    ax_n.set_title("error vs bars: solid = curvature-graded, dashed = uniform")
    ax_t.set_title("error vs run time (Pareto front)")
    ax_n.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
