"""A fixed sparsity pattern filled with new values: the program's Jacobians and Hessians keep their entries' places
from one evaluation to the next, so the COO → compressed conversion (a sort and a duplicate sum) is made once.

The matrix of :meth:`Pattern.matrix` is the one ``scipy.sparse.csc_matrix((data, (rows, cols)), shape)`` (or
``csr_matrix``) builds, canonical (sorted indices, no duplicates), entry for entry: the entries are permuted into the
compressed order found once, and duplicates (none in this program) are refused at construction.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]


@dataclass(frozen=True)
class Pattern:
    """The compressed layout of COO entries ``(rows, cols)`` of a ``shape`` matrix in ``"csc"`` or ``"csr"``.

    Attributes
    ----------
    order : ndarray of int (nnz,)
        Position in the COO data of each compressed entry.
    indices, indptr : ndarray of int32
        The compressed arrays (sorted indices).
    """

    shape: tuple[int, int]
    compressed: str
    order: IntArray
    indices: NDArray[np.int32]
    indptr: NDArray[np.int32]

    @classmethod
    def of(cls, rows: IntArray, cols: IntArray, shape: tuple[int, int], compressed: str = "csc") -> Pattern:
        """The layout of entries at ``rows``, ``cols`` (each (nnz,)); a ValueError when an entry repeats."""
        if compressed not in ("csc", "csr"):
            raise ValueError(f"compressed is {compressed!r}; expected 'csc' or 'csr'.")
        rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
        major, minor = (cols, rows) if compressed == "csc" else (rows, cols)
        order = np.lexsort((minor, major))
        key = major[order] * shape[0 if compressed == "csc" else 1] + minor[order]
        if key.size and np.any(np.diff(key) == 0):
            raise ValueError("the pattern repeats an entry; give each (row, column) once.")
        size = shape[1] if compressed == "csc" else shape[0]
        indptr = np.concatenate(([0], np.cumsum(np.bincount(major, minlength=size)))).astype(np.int32)
        return cls(shape, compressed, order, minor[order].astype(np.int32), indptr)

    def matrix(self, data: FloatArray) -> Any:
        """The matrix with COO values ``data`` (nnz,), in the pattern's order of ``(rows, cols)``."""
        kind = sp.csc_matrix if self.compressed == "csc" else sp.csr_matrix
        out = kind((np.asarray(data, dtype=float)[self.order], self.indices, self.indptr), shape=self.shape)
        out.has_canonical_format = True
        return out
