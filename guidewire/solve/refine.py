"""Error-controlled refinement: solve to a mean node error ``tol_mm``.

The second-order scheme's node error falls as ``h²`` (tested on graded layouts too), so two solves with ``n`` and
``2n`` bars give a Richardson estimate of the finer one's error: with ``p_n(s)`` the coarse nodes and ``P_2n`` the
fine wire (its interpolating cubic B-spline, :func:`guidewire.chain.spline.wire_spline`, whose own error is ``O(h⁴)``),

    e_2n ≈ mean_k |P_2n(s_k) − p_n(s_k)| / (2² − 1)

over the coarse nodes ``s_k``. The pair need not be uniform: any layout and the same layout with every bar halved
(the same density, hence the same error constant over ``h²``) give it.

:func:`solve_to_tolerance` has two ways to a mean node error ``tol_mm``:

- ``density="uniform"``: double uniform bars from ``start_bars`` until the estimate is at most ``tol_mm`` (each pair
  is the previous fine solve and a new one with twice the bars);
- ``density="curvature"`` (the default of ``solve(tol_mm=…)``): one uniform pair (``n₀``, ``2n₀``) gives a first
  estimate ``e``; as ``e ∝ n⁻²``, a pair of ``n = n₀·sqrt(e/tol_mm)·``:data:`SAFETY` and ``2n`` bars should meet
  ``tol_mm``; that pair is laid out by the curvature of the last fine solve (:mod:`guidewire.chain.density`: the graded
  ``n``-bar layout and the same with every bar halved), solved, and estimated again, until the estimate is at most
  ``tol_mm``. The answer is the fine member of the last pair.

:func:`solve_graded` is ``solve(scene, bars=n, density="curvature")``: a uniform coarse solve, then ``n`` bars graded
by its curvature.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np

from ..chain.density import curvature_density, graded_bars
from ..chain.spline import wire_spline
from ..fields import real
from ..scene.scene import Scene
from ..wire import piece_count
from .options import SolveOptions
from .pipeline import run
from .result import Solution

START_BARS = 10
"""Bars of the first, coarsest solve (raised to two per piece the contacts and sections cut)."""

MAX_BARS = 2560
"""The finest layout tried; if the estimate is still above ``tol_mm`` there, the answer says so."""

SAFETY = 1.1
"""The predicted bar count of the next pair is raised by this factor (the estimate is itself an estimate)."""

def estimate_error(coarse: Solution, fine: Solution) -> float:
    """Richardson estimate (mm) of the mean node error of ``fine`` (twice the bars of ``coarse``), see the module
    docstring."""
    spline = wire_spline(fine.nodes, fine.s)
    s = np.clip(coarse.s, fine.s[0], fine.s[-1])  # graded layouts' running sums may differ in the last bit
    gap = np.hypot(*(spline(s) - coarse.nodes).T)
    return float(np.mean(gap)) / 3.0


def graded_scene(scene: Scene, solution: Solution, bars: int, halve: bool = False) -> Scene:
    """``scene`` with ``bars`` bars graded by the curvature of ``solution`` (twice as many, every bar halved, with
    ``halve``)."""
    wire = scene.wire
    grid, rho = curvature_density(solution.s, solution.curvature)
    lengths = graded_bars(wire.length, bars, [c.s for c in scene.contacts], wire.section_boundaries(), grid, rho)
    if halve:
        lengths = np.repeat(0.5 * lengths, 2)
    return scene.with_wire(bars=int(lengths.size), bar_lengths=tuple(lengths.tolist()), density="uniform")


def _first_bars(scene: Scene, start_bars: int) -> int:
    pieces = piece_count(scene.wire.length, [c.s for c in scene.contacts], scene.wire.section_boundaries())
    return max(int(start_bars), 2 * pieces)


def solve_graded(scene: Scene, bars: int, options: SolveOptions, *, start_bars: int = START_BARS) -> Solution:
    """Solve ``scene`` with ``bars`` bars graded by curvature: a uniform coarse solve of
    ``max(start_bars, 2·pieces, bars // 2)`` bars (at most ``bars``), then :func:`graded_scene`.

    Returns
    -------
    Solution
        The graded solve, ``solve_time_s`` both solves together; a failed coarse solve is returned as it is.
    """
    options.check()
    start = time.perf_counter()
    coarse = run(scene.with_wire(density="uniform", bar_lengths=None),
                 replace(options, bars=min(int(bars), max(_first_bars(scene, start_bars), int(bars) // 2))))
    if not coarse.success:
        return replace(coarse, solve_time_s=time.perf_counter() - start)
    sol = run(graded_scene(scene, coarse, int(bars)), options)
    return replace(sol, solve_time_s=time.perf_counter() - start)


def solve_to_tolerance(scene: Scene, tol_mm: float, options: SolveOptions, *, density: str = "curvature",
                       start_bars: int = START_BARS, max_bars: int = MAX_BARS) -> Solution:
    """Solve ``scene`` with the fewest bars whose estimated mean node error is ≤ ``tol_mm`` (module docstring).

    Parameters
    ----------
    scene : Scene
    tol_mm : float
        Target mean node error (mm), positive.
    density : {"curvature", "uniform"}
        Graded pairs sized by the estimate's ``n⁻²`` (default), or doubled uniform bars.
    start_bars, max_bars : int
        First and largest bar counts.
    options : SolveOptions
        Of every solve (their ``bars`` and starts are chosen here).

    Returns
    -------
    Solution
        The finest solve, with ``error_estimate_mm`` set and ``solve_time_s`` the time of every solve together. A
        failed solve is returned as it is (its estimate nan); at ``max_bars`` the estimate may exceed ``tol_mm``,
        and ``message`` says so.
    """
    tol_mm = real(tol_mm, "tol_mm", positive=True)
    if density not in ("curvature", "uniform"):
        raise ValueError(f"density is {density!r}; expected 'curvature' or 'uniform'.")
    options.check()
    start = time.perf_counter()
    base = scene.with_wire(density="uniform", bar_lengths=None)
    n = _first_bars(scene, start_bars)
    coarse = run(base, replace(options, bars=n))
    fine = run(base, replace(options, bars=2 * n)) if coarse.success else coarse
    while True:
        if not (coarse.success and fine.success):
            failed = fine if coarse.success else coarse
            return replace(failed, solve_time_s=time.perf_counter() - start, error_estimate_mm=float("nan"))
        estimate = estimate_error(coarse, fine)
        if estimate <= tol_mm or 2 * fine.n_bars > max_bars:
            message = fine.message
            if estimate > tol_mm:
                message = (f"{message} The estimated mean node error {estimate:.3g} mm is above tol_mm = {tol_mm:g} "
                           f"at max_bars = {max_bars}.")
            return replace(fine, solve_time_s=time.perf_counter() - start, error_estimate_mm=estimate,
                           message=message)
        if density == "uniform":
            coarse, fine = fine, run(base, replace(options, bars=2 * fine.n_bars))
            continue
        n = max(coarse.n_bars + 1, math.ceil(coarse.n_bars * math.sqrt(estimate / tol_mm) * SAFETY))
        n = min(n, max_bars // 2)
        coarse = run(graded_scene(scene, fine, n), options)
        fine = run(graded_scene(scene, fine, n, halve=True), options) if coarse.success else coarse
