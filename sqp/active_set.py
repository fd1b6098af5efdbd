"""A sparse QP solved on a guessed active set: the warm start of an SQP whose active set changes little between
iterations.

For ``min 1/2 d^T B d + g^T d  s.t.  E d = e,  G d <= h`` with ``B`` positive definite, the step of the rows ``A``
guessed active is the KKT point of the equality QP on ``E`` and ``G_A`` (one sparse solve). When its multipliers
``z_A`` are nonnegative and it meets the other rows, it satisfies the QP's KKT conditions, which for a convex QP are
sufficient: it is *the* solution (unique in ``d``), the one an interior-point backend approaches to its tolerance.
Otherwise the guess is corrected as the primal-dual active-set method does (Hintermüller, Ito & Kunisch, 2002: rows
with a negative multiplier leave, violated rows join) for at most :data:`MAX_GUESSES` solves, and then the caller
asks its backends. The guess comes from the last QP's multipliers (or the caller's starting ones), so an SQP near a
solution, or warm-started from a neighbouring problem's answer, usually needs one solve.

The KKT matrix ``[[B, C^T], [C, 0]]`` (``C = [E; G_A]``) is ordered with every row right after the last variable it
involves (:func:`interleaved_order`): for a banded ``B`` and rows local in the variables (a discretised rod: each row
touches one element's variables) the matrix is then banded, and LAPACK's banded LU with partial pivoting
(``dgbtrf``) factorises it in O(N b²). A wider band than :data:`MAX_KKT_BANDWIDTH` is left to the backends.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.linalg import lapack

from sqp.kkt import inf_norm
from sqp.qp_call import QP_RESIDUAL_TOL

Array = NDArray[np.float64]

#: Solves of one QP on corrected guesses before the backends are asked.
MAX_GUESSES = 3

#: Solves of the first QP of a solve, whose guess is the caller's starting multipliers: the first step of a
#: warm-started solve moves the most (on the guidewire's 3-D insertion steps the corrections of that guess wandered
#: over dozens of rows and never settled), so one solve is tried before the backends.
FIRST_GUESSES = 1

#: Widest band (``max |i - j|`` over the KKT matrix's entries in :func:`interleaved_order`) solved here.
MAX_KKT_BANDWIDTH = 48

#: A row is met when ``G_i d - h_i`` is at most this times the QP's scale; a multiplier is nonnegative above minus it.
ACTIVE_SET_TOL = 1e-10


def interleaved_order(C: Any, n: int) -> NDArray[np.intp]:
    """A permutation of the ``n + m`` KKT unknowns (variables, then the ``m`` rows of ``C``) putting every row
    right after the last variable it involves (an empty row after the first variable), variables in their order."""
    Cr = sp.csr_matrix(C)
    counts = np.diff(Cr.indptr)
    last = np.zeros(Cr.shape[0], dtype=np.int64)
    full = counts > 0
    if np.any(full):
        last[full] = np.maximum.reduceat(Cr.indices, Cr.indptr[:-1][full])
    key = np.concatenate((2 * np.arange(n, dtype=np.int64), 2 * last + 1))
    return np.argsort(key, kind="stable")


def banded_kkt(B: Any, g: Array, C: Any, c: Array) -> tuple[Array, Array] | None:
    """The KKT point ``(d, y)`` of ``min 1/2 d^T B d + g^T d  s.t.  C d = c`` (``B d + g + C^T y = 0``, qpsolvers'
    sign), by LAPACK's banded LU of the KKT matrix in :func:`interleaved_order`; None when the band is wider than
    :data:`MAX_KKT_BANDWIDTH`, the matrix is exactly singular or the answer is not finite."""
    n, m = g.size, c.size
    size = n + m
    perm = interleaved_order(C, n)
    where = np.empty(size, dtype=np.intp)
    where[perm] = np.arange(size)
    B, C = sp.csc_matrix(B), sp.csr_matrix(C)
    B.sum_duplicates()  # (no-ops on canonical matrices: every entry below is then placed once)
    C.sum_duplicates()
    # (coordinates straight from the compressed arrays: B's column and C's row of an entry is its pointer segment)
    b_col = np.repeat(np.arange(n), np.diff(B.indptr))
    c_row = np.repeat(np.arange(m), np.diff(C.indptr)) + n
    r = where[np.concatenate((B.indices, c_row, C.indices))]
    k = where[np.concatenate((b_col, C.indices, c_row))]
    if not r.size:
        return None
    kl, ku = int(np.max(r - k)), int(np.max(k - r))
    if max(kl, ku) > MAX_KKT_BANDWIDTH:
        return None
    ab = np.zeros((2 * kl + ku + 1, size))
    ab.reshape(-1)[(kl + ku + r - k) * size + k] = np.concatenate((B.data, C.data, C.data))
    lu, piv, info = lapack.dgbtrf(ab, kl, ku, overwrite_ab=True)
    if info != 0:
        return None
    x, info = lapack.dgbtrs(lu, kl, ku, np.concatenate((-g, c))[perm], piv)
    if info != 0 or not np.isfinite(x).all():
        return None
    out = np.empty(size)
    out[perm] = x
    return out[:n], out[n:]


def guessed_qp(B: Any, g: Array, E: Any, e: Array, G: Any, h: Array, active: NDArray[np.bool_],
               scale: float, solves: int = MAX_GUESSES) -> tuple[Array, Array, Array] | None:
    """The solution ``(d, y, z)`` of ``min 1/2 d^T B d + g^T d  s.t.  E d = e,  G d <= h`` (``B`` sparse positive
    definite; qpsolvers' signs: ``B d + g + E^T y + G^T z = 0``, ``z >= 0``) from the rows ``active`` (bool (m_G,))
    guessed active, or None when ``solves`` solves (default :data:`MAX_GUESSES`) do not find it (see the module
    docstring)."""
    G = sp.csr_matrix(G)
    E = sp.csr_matrix(E)
    m_eq = e.size
    tol = ACTIVE_SET_TOL * scale
    active = np.asarray(active, dtype=bool).copy()
    for _ in range(solves):
        rows = np.flatnonzero(active)
        C = sp.vstack((E, G[rows]), format="csr") if rows.size else E
        step = banded_kkt(B, g, C, np.concatenate((e, h[rows])))
        if step is None:
            return None
        d, w = step
        z_active = w[m_eq:]
        slack = G @ d - h
        leave = rows[z_active < -tol]
        join = np.flatnonzero(~active & (slack > tol))
        if not leave.size and not join.size:
            z = np.zeros(h.size)
            z[rows] = np.maximum(z_active, 0.0)
            y = w[:m_eq]
            dual = inf_norm(B @ d + g + E.T @ y + G.T @ z)
            prim = max(inf_norm(E @ d - e) if m_eq else 0.0, float(np.max(slack, initial=0.0)))
            return (d, y, z) if max(dual, prim) <= QP_RESIDUAL_TOL * scale else None
        active[leave] = False
        active[join] = True
    return None
