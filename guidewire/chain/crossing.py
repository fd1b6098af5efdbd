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
    ii, jj = _candidate_pairs(a, b, 2.0 * scale)
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


CHUNK_BARS = 8
"""Bars per chunk of :func:`_candidate_pairs` (whose boxes are compared before the bars')."""


def _candidate_pairs(a: FloatArray, b: FloatArray, margin: float) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Pairs ``i < j − 1`` of bars that may cross or touch: those whose bounding boxes, grown by ``margin`` (≥ the
    touching distance), overlap, except within a run of bars that advances along one direction (:func:`_monotone`).

    The bars are taken in chunks of :data:`CHUNK_BARS` consecutive ones, whose boxes are compared first; a chunk and
    its successor, when the 2 chunks' bars pass the monotone test, need no pair between or within them; the bars of
    the other overlapping chunks are compared pairwise. So a wire that only comes back near itself in a few places
    costs O(n), and a pair is never missed (the boxes contain every point within ``margin`` of a bar)."""
    n = a.shape[0]
    lo, hi = np.minimum(a, b) - margin, np.maximum(a, b) + margin
    first = np.arange(0, n, CHUNK_BARS)
    chunk_lo, chunk_hi = np.minimum.reduceat(lo, first, axis=0), np.maximum.reduceat(hi, first, axis=0)
    overlap = ((chunk_lo[:, None, :] <= chunk_hi[None, :, :]) & (chunk_lo[None, :, :] <= chunk_hi[:, None, :])).all(2)
    overlap = np.triu(overlap)  # chunk pairs p ≤ q (a chunk with itself included)
    advancing = _monotone_windows(b - a, first, margin)
    index = np.arange(first.size)
    overlap[index[advancing], index[advancing]] = False
    pair = advancing[:-1]
    overlap[index[:-1][pair], index[1:][pair]] = False
    p, q = np.nonzero(overlap)
    if not p.size:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    offset = np.arange(CHUNK_BARS)
    i = np.broadcast_to(first[p][:, None, None] + offset[None, :, None], (p.size, CHUNK_BARS, CHUNK_BARS)).ravel()
    j = np.broadcast_to(first[q][:, None, None] + offset[None, None, :], (p.size, CHUNK_BARS, CHUNK_BARS)).ravel()
    keep = (j >= i + 2) & (j < n)
    i, j = i[keep], j[keep]
    keep = (lo[i, 0] <= hi[j, 0]) & (lo[j, 0] <= hi[i, 0]) & (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1])
    return i[keep], j[keep]


def _monotone_windows(d: FloatArray, first: NDArray[np.intp], margin: float) -> NDArray[np.bool_]:
    """Per chunk starting at ``first``: whether the bars of it and the next chunk (or of it alone, the last) pass
    :func:`_monotone`'s test (every bar advances by more than ``margin`` along the bisector of the window's first and
    last bars), so that no two of them can cross or touch."""
    n = d.shape[0]
    bars = np.minimum(first[:, None] + np.arange(2 * CHUNK_BARS)[None, :], n - 1)  # (W, 2K), the tail repeated
    lengths = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-300)
    unit = d / lengths[:, None]
    u = unit[bars[:, 0]] + unit[bars[:, -1]]
    norm = np.hypot(u[:, 0], u[:, 1])
    u = u / np.maximum(norm, 1e-300)[:, None]
    advance = d[bars, 0] * u[:, :1] + d[bars, 1] * u[:, 1:]
    return (norm >= 1e-12) & (advance.min(axis=1) > margin)


def _cross(u: FloatArray, v: FloatArray) -> FloatArray:
    return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]


def _point_segment_distance(p: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    r = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, r) / np.einsum("ij,ij->i", r, r), 0.0, 1.0)
    return np.hypot(*(a + t[:, None] * r - p).T)


def _segments_cross(a: FloatArray, b: FloatArray, c: FloatArray, d: FloatArray, eps: float) -> NDArray[np.bool_]:
    """Whether segment ``ab`` meets segment ``cd`` (row-wise): a proper crossing (each segment's ends strictly on
    both sides of the other's line, by more than ``eps`` mm), or an end point within ``eps`` of the other segment.

    The four end points' tests (``c``, ``d`` against ``ab``; ``a``, ``b`` against ``cd``) run stacked, as one array
    of 4m rows."""
    m = a.shape[0]
    point = np.concatenate((c, d, a, b))
    start, end = np.concatenate((a, a, c, c)), np.concatenate((b, b, d, d))
    r = end - start
    side = (_cross(r, point - start) / np.hypot(r[:, 0], r[:, 1])).reshape(4, m)  # signed distances from the lines
    clear = np.abs(side).min(axis=0) > eps
    sign = np.sign(side)
    proper = clear & (sign[0] != sign[1]) & (sign[2] != sign[3])
    touching = _point_segment_distance(point, start, end).reshape(4, m).min(axis=0) <= eps
    return proper | touching
