"""Positive-definiteness tests of ``W + r C^T C + delta I`` for the convexification ladders of :mod:`sqp.hessian`,
in LAPACK's band storage.

A ladder tests the same pencil at several weights ``r`` and shifts ``delta`` (up to ~20 tests in one iteration on
the guidewire's vessel programs). Forming each candidate as a scipy.sparse sum, sorting it and placing it in band
storage cost more than its banded Cholesky factorisation (``dpbtrf``, O(n b²)); here ``W``'s and ``C^T C``'s lower
bands are placed once, every test combines them elementwise, and the caller forms the sparse matrix only for the
candidate that passes. The entries are the same numbers as the sparse sums' (``W_ij + r (C^T C)_ij``, then
``+ delta`` on the diagonal, in that order), so each test decides as the factorisation of the formed matrix does.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import lapack

from sqp.compressed import as_csc

Array = NDArray[np.float64]

#: Widest band (``max |i - j|`` over the stored entries) for which a sparse matrix is tested by LAPACK's banded
#: Cholesky (``dpbtrf``, O(n b²)) instead of SuperLU's unpivoted LU: on the guidewire's 3-D program (1200-1500
#: variables, band 8-11) 0.05 ms against 0.6 ms. Both test the signs of the same pivots (Sylvester's law).
BANDED_CHOLESKY_MAX = 32


def _lower_entries(M: Any) -> tuple[NDArray[np.intp], NDArray[np.intp], Array, int]:
    """Offset below the diagonal, column and value of every stored entry on or below the diagonal of the square
    sparse ``M`` (duplicates summed), and ``max |i - j|`` over all its stored entries."""
    M = as_csc(M)
    if not M.has_canonical_format:  # (every entry once: the band is filled by assignment)
        M = M.copy()
        M.sum_duplicates()
    col = np.repeat(np.arange(M.shape[0]), np.diff(M.indptr))
    offset = M.indices - col
    lower = offset >= 0
    return offset[lower], col[lower], M.data[lower], int(np.max(np.abs(offset), initial=0))


def band_positive_definite(ab: Array, floor: float = 0.0) -> bool:
    """Whether the symmetric matrix in lower band storage ``ab`` (overwritten) has a Cholesky factorisation with
    every pivot ``L_ii^2`` positive, finite and above ``floor``."""
    factor, info = lapack.dpbtrf(ab, lower=1, overwrite_ab=1)
    pivots = factor[0]
    return bool(info == 0 and np.all(np.isfinite(pivots)) and np.all(pivots > 0.0)
                and np.all(pivots * pivots > floor))


def lower_band(M: Any) -> Array | None:
    """The square sparse ``M``'s lower band in LAPACK storage (``ab[i - j, j] = M_ij``), or None when its band is
    wider than :data:`BANDED_CHOLESKY_MAX` (or it is empty)."""
    offset, col, data, width = _lower_entries(M)
    n = M.shape[0]
    if not n or width > BANDED_CHOLESKY_MAX:
        return None
    return _placed(offset, col, data, int(np.max(offset, initial=0)) + 1, n)


def _placed(offset: NDArray[np.intp], col: NDArray[np.intp], data: Array, rows: int, n: int) -> Array:
    """A ``rows x n`` lower band array holding ``data`` at ``ab[offset, col]``, zeros elsewhere."""
    ab = np.zeros((rows, n))
    ab.reshape(-1)[offset * n + col] = data
    return ab


class BandPencil:
    """``W`` and (optionally) ``C^T C``, both sparse symmetric, placed in one lower band: :meth:`positive_definite`
    tests ``W + r C^T C + delta I`` for any ``r`` and ``delta`` without forming it."""

    def __init__(self, W: Array, CtC: Array | None) -> None:
        self.W = W
        self.CtC = CtC

    @classmethod
    def of(cls, W: Any, CtC: Any = None) -> BandPencil | None:
        """The pencil of the sparse ``W`` and ``CtC`` (None: ``W`` alone), or None when their common band is wider
        than :data:`BANDED_CHOLESKY_MAX` (the caller then forms and tests each matrix as before)."""
        n = W.shape[0]
        parts = [_lower_entries(W)] + ([_lower_entries(CtC)] if CtC is not None else [])
        width = max(part[3] for part in parts)
        if not n or width > BANDED_CHOLESKY_MAX:
            return None
        rows = 1 + max(int(np.max(part[0], initial=0)) for part in parts)
        bands = [_placed(offset, col, data, rows, n) for offset, col, data, _ in parts]
        return cls(bands[0], bands[1] if CtC is not None else None)

    def positive_definite(self, r: float = 0.0, delta: float = 0.0, floor: float = 0.0) -> bool:
        """Whether ``W + r C^T C + delta I`` is positive definite with every Cholesky pivot ``L_ii^2`` above
        ``floor``."""
        ab = self.W + r * self.CtC if (r != 0.0 and self.CtC is not None) else self.W.copy()
        if delta != 0.0:
            ab[0] += delta
        return band_positive_definite(ab, floor)
