"""Bar layouts graded by a density: the paper's "discrete density by curvature" (its closing paragraph).

Layout. Given a positive density ``ρ(s)`` (bars per mm, up to a factor) and ``n`` bars, :func:`graded_bars` shares
the bars out over the pieces that the contacts and section boundaries cut (in proportion to ``∫ρ`` over each piece,
largest-remainder rounding, at least one bar each) and, within a piece, puts the nodes at equal steps of the
cumulative ``∫ρ ds``: every bar carries the same share of ``∫ρ``. A constant density gives
:func:`guidewire.chain.place_bars`' uniform layout.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..wire import piece_ends

FloatArray = NDArray[np.float64]


def share_bars(weights: FloatArray, bars: int, minimum: int = 1) -> NDArray[np.int_]:
    """``bars`` shared out in proportion to ``weights`` (largest remainder), at least ``minimum`` each."""
    weights = np.asarray(weights, dtype=float)
    if bars < minimum * weights.size:
        raise ValueError(f"bars is {bars} but there are {weights.size} pieces; use at least {minimum} per piece.")
    ideal = bars * weights / weights.sum()
    count = np.maximum(np.floor(ideal).astype(int), minimum)
    while count.sum() > bars:
        count[np.argmax(np.where(count > minimum, count - ideal, -np.inf))] -= 1
    order = np.argsort(-(ideal - count), kind="stable")
    count[order[: bars - count.sum()]] += 1
    return count


def graded_bars(length: float, bars: int, contact_s: Sequence[float], breakpoints: Sequence[float],
                s_grid: FloatArray, density: FloatArray) -> FloatArray:
    """Bar lengths that equidistribute ``∫ρ ds`` with a node at every contact and breakpoint.

    Parameters
    ----------
    length : float
        Wire length ``L`` (mm).
    bars : int
        Number of bars, at least the number of pieces.
    contact_s, breakpoints : sequence of float
        Arc lengths that must be nodes (contacts, section boundaries), as for
        :func:`guidewire.chain.place_bars`.
    s_grid : ndarray, shape (m,)
        Increasing arc lengths from 0 to ``L`` where the density is given (the piece ends among them).
    density : ndarray, shape (m,)
        Positive density at ``s_grid``, linear in between.

    Returns
    -------
    ndarray, shape (bars,)
        Bar lengths (mm), base first, summing to ``L``.
    """
    ends = piece_ends(length, np.asarray(contact_s, dtype=float), breakpoints)
    starts = np.concatenate(([0.0], ends[:-1]))
    s_grid = np.asarray(s_grid, dtype=float)
    density = np.asarray(density, dtype=float)
    if s_grid.ndim != 1 or density.shape != s_grid.shape or s_grid.size < 2:
        raise ValueError("s_grid and density must be 1-D arrays of the same length (at least 2).")
    if not np.all(np.isfinite(density)) or np.any(density <= 0.0):
        raise ValueError("density must be finite and positive.")
    grid = np.unique(np.concatenate((s_grid, starts, ends)))
    rho = np.interp(grid, s_grid, density)
    cumulative = np.concatenate(([0.0], np.cumsum(0.5 * (rho[1:] + rho[:-1]) * np.diff(grid))))
    at = np.interp(np.concatenate((starts, ends)), grid, cumulative)
    weight = at[ends.size:] - at[: ends.size]
    count = share_bars(weight, bars)
    nodes = [np.zeros(1)]
    for a, b, lo, hi, k in zip(starts, ends, at[: ends.size], at[ends.size:], count, strict=True):
        targets = lo + (hi - lo) * np.arange(1, k + 1) / k
        inner = np.interp(targets[:-1], cumulative, grid)
        nodes.append(np.concatenate((np.clip(inner, a, b), [b])))
    return np.diff(np.concatenate(nodes))


INDICATOR_POWER = 1.0 / 3.0
"""``ρ ∝ τ^(1/3)``: bar ``j`` adds ``l_j³·τ_j`` to the node error, and ``Σ l_j³ τ_j`` at a fixed ``Σ 1 = n`` (with
``Σ l_j = L``) is least when ``l_j ∝ τ_j^(−1/3)``."""

DENSITY_FLOOR = 0.2
"""The density is at least this fraction of its mean: a stretch the coarse solve sees straight still gets bars."""

SPIKE_CAP = 10.0
"""The indicator is capped at this multiple of its median (a point force makes ``κ'`` jump)."""


def curvature_indicator(s: FloatArray, curvature: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``τ = |t''| = sqrt(κ⁴ + κ'²)`` at the bar midpoints of a solved chain, and the midpoints.

    ``t'' = −κ² t + κ' n`` is the integrand's second derivative in the midpoint rule ``p_k = Σ l_j t(φ_j)``, whose
    error over bar ``j`` is ``l_j³ t''/24``.

    Parameters
    ----------
    s : ndarray, shape (n + 1,)
        Node arc lengths (mm).
    curvature : ndarray, shape (n + 1,)
        Curvature at the nodes (1/mm).
    """
    s = np.asarray(s, dtype=float)
    kappa = np.asarray(curvature, dtype=float)
    lengths = np.diff(s)
    slope = np.diff(kappa) / lengths
    mean = 0.5 * (kappa[1:] + kappa[:-1])
    tau = np.sqrt(mean**4 + slope**2)
    cap = SPIKE_CAP * max(float(np.median(tau)), 1e-300)
    return 0.5 * (s[1:] + s[:-1]), np.minimum(tau, cap)


def curvature_density(s: FloatArray, curvature: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The bar density ``ρ ∝ τ^(1/3)`` (:data:`INDICATOR_POWER`, floored at :data:`DENSITY_FLOOR` of its mean) of a
    solved chain, on a grid from 0 to ``L``: ``(s_grid, ρ)`` for :func:`graded_bars`."""
    mid, tau = curvature_indicator(s, curvature)
    rho = tau**INDICATOR_POWER
    mean = float(np.sum(rho * np.diff(s)) / (s[-1] - s[0]))
    if not mean > 0.0:  # a straight wire: uniform
        rho = np.ones_like(rho)
    else:
        rho = np.maximum(rho, DENSITY_FLOOR * mean)
    grid = np.concatenate(([s[0]], mid, [s[-1]]))
    return grid, np.concatenate(([rho[0]], rho, [rho[-1]]))
