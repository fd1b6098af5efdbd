"""A sparse QP solved on a guessed active set: the warm start of an SQP whose active set changes little between
iterations.

For ``min 1/2 d^T B d + g^T d  s.t.  E d = e,  G d <= h`` with ``B`` positive definite, the step of the rows ``A``
guessed active is the KKT point of the equality QP on ``E`` and ``G_A`` (one sparse solve). When its multipliers
``z_A`` are nonnegative and it meets the other rows, it satisfies the QP's KKT conditions, which for a convex QP are
sufficient: it is *the* solution (unique in ``d``), the one an interior-point backend approaches to its tolerance.
Otherwise the guess is corrected as the primal-dual active-set method does (Hintermüller, Ito & Kunisch, 2002: rows
with a negative multiplier leave, violated rows join) for at most :data:`MAX_GUESSES` solves, and then the caller
asks its backends (when every backend fails, the caller corrects it for up to :data:`RESCUE_GUESSES` solves). The
guess comes from the last QP's multipliers (or the caller's starting ones), so an SQP near a solution, or
warm-started from a neighbouring problem's answer, usually needs one solve.

The KKT matrix ``[[B, C^T], [C, 0]]`` (``C = [E; G_A]``) is ordered with every row right after the last variable it
involves (:func:`interleaved_order`): for a banded ``B`` and rows local in the variables (a discretised rod: each row
touches one element's variables) the matrix is then banded, and LAPACK's banded LU with partial pivoting
(``dgbtrf``) factorises it in O(N b²). A wider band than :data:`MAX_KKT_BANDWIDTH` is left to the backends.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.linalg import lapack

from sqp.compressed import as_csc, as_csr
from sqp.kkt import inf_norm
from sqp.qp_call import QP_RESIDUAL_TOL

Array = NDArray[np.float64]

#: Solves of one QP on corrected guesses before the backends are asked.
MAX_GUESSES = 3

#: Solves of the first QP of a solve, whose guess is the caller's starting multipliers: the first step of a
#: warm-started solve moves the most (on the guidewire's 3-D insertion steps the corrections of that guess wandered
#: over dozens of rows and never settled), so one solve is tried before the backends.
FIRST_GUESSES = 1

#: Solves of corrected guesses made when every backend has failed the QP (before its elastic form is solved): the
#: backends' failures are numerical (an augmented-Lagrangian model Hessian with a condition number ~1e11 on the
#: guidewire's compressed vessel programs: PIQP and Clarabel stop short where DAQP and quadprog solve the same QP),
#: while the corrections solve the KKT system directly (4 solves there). An answer is checked like any other, so a
#: correction that wanders only costs these solves (each O(n) on a banded KKT matrix, O(n² k) by the range-space
#: method for a dense factored model with k rows guessed).
RESCUE_GUESSES = 25

#: Widest band (``max |i - j|`` over the KKT matrix's entries in :func:`interleaved_order`) solved here.
MAX_KKT_BANDWIDTH = 48

#: A row is met when ``G_i d - h_i`` is at most this times the QP's scale; a multiplier is nonnegative above minus it.
ACTIVE_SET_TOL = 1e-10


def interleaved_order(C: Any, n: int) -> NDArray[np.intp]:
    """A permutation of the ``n + m`` KKT unknowns (variables, then the ``m`` rows of ``C``) putting every row
    right after the last variable it involves (an empty row after the first variable), variables in their order."""
    Cr = as_csr(C)
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
    return _KKTParts(B, C).solve(np.ones(sp.csr_matrix(C).shape[0], dtype=bool), np.empty(0), g, c)


class _KKTParts:
    """The entries of ``B`` and of the rows ``[E; G]`` in coordinates, found once for the several guesses of one QP:
    the KKT matrix of ``E`` and any subset of ``G``'s rows is then placed in LAPACK's band storage without building
    sparse matrices (the same band matrix, entry for entry, as from ``vstack((E, G[rows]))``)."""

    def __init__(self, B: Any, E: Any, G: Any | None = None) -> None:
        B = _canonical(as_csc(B))  # (every entry below is then placed once)
        self.n = B.shape[0]
        self.b_row, self.b_col, self.b_data = B.indices, np.repeat(np.arange(self.n), np.diff(B.indptr)), B.data
        self.e_row, self.e_col, self.e_data, self.e_last = _row_entries(E)
        if G is not None:
            self.g_row, self.g_col, self.g_data, self.g_last = _row_entries(G)

    def solve(self, e_rows: NDArray[np.bool_], g_rows: NDArray[np.intp], g: Array,
              c: Array) -> tuple[Array, Array] | None:
        """:func:`banded_kkt` with ``C`` the rows ``e_rows`` (bool, of ``E``) then ``g_rows`` (indices into ``G``)."""
        n = self.n
        e_index = np.flatnonzero(e_rows)
        e_place = np.full(e_rows.size, -1)
        e_place[e_index] = np.arange(e_index.size)
        keep = e_place[self.e_row] >= 0
        rows, cols, data = [e_place[self.e_row[keep]]], [self.e_col[keep]], [self.e_data[keep]]
        last = [self.e_last[e_index]]
        if g_rows.size:
            g_place = np.full(self.g_last.size, -1)
            g_place[g_rows] = np.arange(g_rows.size) + e_index.size
            keep = g_place[self.g_row] >= 0
            rows.append(g_place[self.g_row[keep]])
            cols.append(self.g_col[keep])
            data.append(self.g_data[keep])
            last.append(self.g_last[g_rows])
        c_row, c_col, c_data = np.concatenate(rows), np.concatenate(cols), np.concatenate(data)
        size = n + c.size
        layout = _band_layout(size, self.b_row, self.b_col, c_row, c_col, np.concatenate(last))
        if layout is None:
            return None
        perm, kl, ku, place = layout
        ab = np.zeros((2 * kl + ku + 1, size))
        ab.reshape(-1)[place] = np.concatenate((self.b_data, c_data, c_data))
        lu, piv, info = lapack.dgbtrf(ab, kl, ku, overwrite_ab=True)
        if info != 0:
            return None
        x, info = lapack.dgbtrs(lu, kl, ku, np.concatenate((-g, c))[perm], piv)
        if info != 0 or not np.isfinite(x).all():
            return None
        out = np.empty(size)
        out[perm] = x
        return out[:n], out[n:]


@dataclass(frozen=True)
class _Layout:
    """Where the KKT matrix's entries go in band storage, for one pattern (see :func:`_band_layout`)."""

    size: int
    b_row: NDArray[np.intp]
    b_col: NDArray[np.intp]
    c_row: NDArray[np.intp]
    c_col: NDArray[np.intp]
    perm: NDArray[np.intp]
    kl: int
    ku: int
    place: NDArray[np.intp]


_LAST_LAYOUT: list[_Layout] = []
"""The last pattern's layout: an SQP's QPs keep the Hessian's and the rows' patterns, and mostly the active set, from
one iteration to the next, so the ordering and the band positions are found again only when the pattern changes."""


def _band_layout(size: int, b_row: NDArray[np.intp], b_col: NDArray[np.intp], c_row: NDArray[np.intp],
                 c_col: NDArray[np.intp], last: NDArray[np.int64]) -> tuple[NDArray[np.intp], int, int,
                                                                            NDArray[np.intp]] | None:
    """``(perm, kl, ku, place)`` of the KKT matrix of size ``size`` with ``B``'s entries at ``(b_row, b_col)`` and
    the rows' at ``(c_row, c_col)`` (row ``i`` of ``C`` ending at column ``last[i]``): the order of
    :func:`interleaved_order`, the band widths and each entry's flat position in LAPACK's band storage (``B``'s,
    then ``C``'s, then ``C^T``'s); None when empty or wider than :data:`MAX_KKT_BANDWIDTH`. The patterns are compared
    entry for entry with the last call's, whose layout is then reused."""
    if _LAST_LAYOUT:
        old = _LAST_LAYOUT[0]
        if old.size == size and all(np.array_equal(x, y) for x, y in ((old.b_row, b_row), (old.b_col, b_col),
                                                                      (old.c_row, c_row), (old.c_col, c_col))):
            return old.perm, old.kl, old.ku, old.place
    n = size - last.size
    key = np.concatenate((2 * np.arange(n, dtype=np.int64), 2 * last + 1))
    perm = np.argsort(key, kind="stable")
    where = np.empty(size, dtype=np.intp)
    where[perm] = np.arange(size)
    r = where[np.concatenate((b_row, c_row + n, c_col))]
    k = where[np.concatenate((b_col, c_col, c_row + n))]
    if not r.size:
        return None
    kl, ku = int(np.max(r - k)), int(np.max(k - r))
    if max(kl, ku) > MAX_KKT_BANDWIDTH:
        return None
    place = (kl + ku + r - k) * size + k
    _LAST_LAYOUT[:] = [_Layout(size, b_row.copy(), b_col.copy(), c_row.copy(), c_col.copy(), perm, kl, ku, place)]
    return perm, kl, ku, place


def _canonical(M: Any) -> Any:
    """The compressed ``M`` with every entry once, indices sorted: ``M`` itself when it is so already, else a copy
    with its duplicates summed (never ``M`` changed in place: it may be the caller's matrix)."""
    if M.has_canonical_format:
        return M
    M = M.copy()
    M.sum_duplicates()
    return M


def _row_entries(M: Any) -> tuple[NDArray[np.intp], NDArray[np.intp], Array, NDArray[np.int64]]:
    """Row, column and value of every entry of ``M`` (canonical CSR order), and each row's last column (0 for an
    empty row: :func:`interleaved_order` puts it after the first variable)."""
    M = _canonical(as_csr(M))
    counts = np.diff(M.indptr)
    last = np.zeros(M.shape[0], dtype=np.int64)
    full = counts > 0
    if np.any(full):
        last[full] = np.maximum.reduceat(M.indices, M.indptr[:-1][full])
    return np.repeat(np.arange(M.shape[0]), counts), M.indices, M.data, last


def guessed_qp(B: Any, g: Array, E: Any, e: Array, G: Any, h: Array, active: NDArray[np.bool_],
               scale: float, solves: int = MAX_GUESSES) -> tuple[Array, Array, Array] | None:
    """The solution ``(d, y, z)`` of ``min 1/2 d^T B d + g^T d  s.t.  E d = e,  G d <= h`` (``B`` sparse positive
    definite; qpsolvers' signs: ``B d + g + E^T y + G^T z = 0``, ``z >= 0``) from the rows ``active`` (bool (m_G,))
    guessed active, or None when ``solves`` solves (default :data:`MAX_GUESSES`) do not find it (see the module
    docstring)."""
    G = as_csr(G)
    E = as_csr(E)
    # (a row whose linearisation has no gradient cannot hold a step: held in a guess, it made the KKT matrix
    # singular and sent the QP to a backend — a node row that yields to the crease rows beside a branch's opening,
    # carried active from the step before)
    active = np.asarray(active, dtype=bool) & (np.asarray(abs(G).sum(axis=1)).ravel() > 0.0)
    parts = _KKTParts(B, E, G)
    every_equality = np.ones(e.size, dtype=bool)
    return corrected_guess(lambda rows, rhs: parts.solve(every_equality, rows, g, rhs),
                           B, g, E, e, G, h, active, scale, solves)


def corrected_guess(solve_kkt: Callable[[NDArray[np.intp], Array], tuple[Array, Array] | None], B: Any, g: Array,
                    E: Any, e: Array, G: Any, h: Array, active: NDArray[np.bool_], scale: float,
                    solves: int) -> tuple[Array, Array, Array] | None:
    """The primal-dual active-set correction of a guess (module docstring), whatever solves each guess:
    ``solve_kkt(rows, rhs)`` is the KKT point ``(d, w)`` of the equality QP on ``E`` and ``G[rows]`` with right-hand
    side ``rhs`` (None when it cannot be solved). ``(d, y, z)`` when a guess's step meets every row, its multipliers
    are nonnegative and it passes a backend's residual check, else None after ``solves`` solves."""
    m_eq = e.size
    tol = ACTIVE_SET_TOL * scale
    active = np.asarray(active, dtype=bool).copy()
    for _ in range(solves):
        rows = np.flatnonzero(active)
        step = solve_kkt(rows, np.concatenate((e, h[rows])))
        if step is None:
            return None
        d, w = step
        z_active = w[m_eq:]
        slack = G @ d - h
        leave = rows[z_active < -tol]
        join = np.flatnonzero(~active & (slack > tol))
        if not leave.size and not join.size:
            if not (np.isfinite(d).all() and np.isfinite(w).all()):
                return None
            z = np.zeros(h.size)
            z[rows] = np.maximum(z_active, 0.0)
            y = w[:m_eq]
            dual = inf_norm(B @ d + g + E.T @ y + G.T @ z)
            prim = max(inf_norm(E @ d - e) if m_eq else 0.0, float(np.max(slack, initial=0.0)))
            return (d, y, z) if max(dual, prim) <= QP_RESIDUAL_TOL * scale else None
        active[leave] = False
        active[join] = True
    return None
