"""Self-intersection of a bar chain: a shape whose bars cross each other is not a wire's shape, whatever the KKT
residuals of the program say (the bending energy and the contact rows do not see it)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

def crossing_bars(nodes: FloatArray, tolerance: float = 1e-9) -> tuple[int, int] | None:
    """The first pair of non-adjacent bars ``(i, j)``, ``i < j`` (0-based), that cross or touch, or None.

    Parameters
    ----------
    nodes : ndarray, shape (n + 1, 2)
        The chain's node positions (mm); bar ``i`` joins nodes ``i`` and ``i + 1``.
    tolerance : float
        Relative margin (of the bar lengths) by which two bars must clear each other's lines to count as apart, so a
        crossing at a shared end point is not missed by rounding. Adjacent bars (which share a node) are not tested.

    Returns
    -------
    tuple of int or None
    """
    p = np.asarray(nodes, dtype=float)
    a, b = p[:-1], p[1:]
    n = a.shape[0]
    if n < 3:
        return None
    d = b - a
    lengths = np.hypot(*d.T)
    scale = tolerance * max(float(lengths.max()), 1e-300)
    if _monotone(d, 2.0 * scale):
        return None
    ii, jj = _candidate_pairs(a, b, max(float(lengths.max()), 1e-12) + 2.0 * scale)
    if ii.size == 0:
        return None
    hit = _segments_cross(a[ii], b[ii], a[jj], b[jj], scale)
    if not np.any(hit):
        return None
    first = np.lexsort((jj[hit], ii[hit]))[0]
    return int(ii[hit][first]), int(jj[hit][first])


def _monotone(d: FloatArray, margin: float) -> bool:
    """Whether every bar advances by more than ``margin`` along one direction ``u`` (the bisector of the first and
    last bars' directions): then the nodes' projections on ``u`` increase strictly, two non-adjacent bars ``i`` and
    ``j ≥ i + 2`` are separated along ``u`` by at least bar ``i + 1``'s advance, and no pair can cross or touch — the
    answer, in O(n), for every chain whose tangent turns by less than π in all (most wires in a vessel)."""
    u = d[0] / max(float(np.hypot(*d[0])), 1e-300) + d[-1] / max(float(np.hypot(*d[-1])), 1e-300)
    norm = float(np.hypot(*u))
    if norm < 1e-12:
        return False
    return bool(np.min(d @ (u / norm)) > margin)


def _candidate_pairs(a: FloatArray, b: FloatArray, cell: float) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Pairs ``i < j − 1`` of bars that share a cell of a uniform grid of spacing ``cell`` (≥ every bar length, so a
    bar's bounding box spans at most 2 × 2 cells): O(n) expected instead of all n² pairs."""
    n = a.shape[0]
    lo = np.floor(np.minimum(a, b) / cell).astype(np.int64)
    hi = np.floor(np.maximum(a, b) / cell).astype(np.int64)
    cx = np.stack((lo[:, 0], hi[:, 0], lo[:, 0], hi[:, 0]), axis=1)
    cy = np.stack((lo[:, 1], lo[:, 1], hi[:, 1], hi[:, 1]), axis=1)
    bars = np.repeat(np.arange(n), 4)
    # one integer key per (cell, bar), sorted: equal cells are runs, and within a run the bars increase
    x, y = cx.ravel(), cy.ravel()
    x, y = x - x.min(), y - y.min()
    key = (x * (int(y.max()) + 1) + y) * n + bars
    key = np.unique(key)  # sorted, a bar once per cell
    cell_of, bar = key // n, key % n
    same_cell_run = np.r_[True, cell_of[1:] != cell_of[:-1]]
    group = np.cumsum(same_cell_run) - 1
    first, out_i, out_j = np.flatnonzero(same_cell_run), [], []
    size = np.diff(np.r_[first, bar.size])
    for offset in range(1, int(size.max())):
        k = np.flatnonzero(group[offset:] == group[:-offset])
        out_i.append(bar[k])
        out_j.append(bar[k + offset])
    if not out_i:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    i, j = np.concatenate(out_i), np.concatenate(out_j)
    keep = j >= i + 2
    pairs = np.unique(i[keep].astype(np.int64) * n + j[keep])
    return pairs // n, pairs % n


def _cross(u: FloatArray, v: FloatArray) -> FloatArray:
    return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]


def _point_segment_distance(p: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    r = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, r) / np.einsum("ij,ij->i", r, r), 0.0, 1.0)
    return np.hypot(*(a + t[:, None] * r - p).T)


def _segments_cross(a: FloatArray, b: FloatArray, c: FloatArray, d: FloatArray, eps: float) -> NDArray[np.bool_]:
    """Whether segment ``ab`` meets segment ``cd`` (row-wise): a proper crossing (each segment's ends strictly on
    both sides of the other's line, by more than ``eps`` mm), or an end point within ``eps`` of the other segment."""
    r, s = b - a, d - c
    la, lc = np.hypot(*r.T), np.hypot(*s.T)
    d1, d2 = _cross(r, c - a) / la, _cross(r, d - a) / la  # signed distances of c, d from line ab
    d3, d4 = _cross(s, a - c) / lc, _cross(s, b - c) / lc  # and of a, b from line cd
    clear = (np.minimum(np.minimum(np.abs(d1), np.abs(d2)), np.minimum(np.abs(d3), np.abs(d4))) > eps)
    proper = clear & (np.sign(d1) != np.sign(d2)) & (np.sign(d3) != np.sign(d4))
    touching = np.minimum(np.minimum(_point_segment_distance(c, a, b), _point_segment_distance(d, a, b)),
                          np.minimum(_point_segment_distance(a, c, d), _point_segment_distance(b, c, d))) <= eps
    return proper | touching
