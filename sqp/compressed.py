"""Compressed sparse matrices without needless reconstruction.

``sp.csr_matrix(M)`` of a matrix that is already a CSR matrix builds a new object over the same arrays, and its
constructor's checks (index dtypes, format check, pruning) cost tens of microseconds each time; an SQP iteration asks
for the format of its Jacobians and Hessians many times. :func:`as_csr` and :func:`as_csc` return such a matrix
itself: the same arrays, hence the same numbers, as the constructor would give.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp


def _settled(M: Any, kind: type, dtype: Any) -> bool:
    """Whether ``M`` is exactly of class ``kind``, of ``dtype`` (any when None) and pruned (its arrays hold exactly
    its ``nnz`` entries, as the constructor would leave them)."""
    return (type(M) is kind and (dtype is None or M.dtype == np.dtype(dtype))
            and int(M.indptr[-1]) == M.indices.size == M.data.size)


def as_csr(M: Any, dtype: Any = None) -> Any:
    """``M`` as a CSR matrix (``sp.csr_matrix(M, dtype=dtype)``): ``M`` itself when it is one of that dtype already.

    Parameters
    ----------
    M : sparse matrix or array_like
        The matrix.
    dtype : dtype, optional
        The entries' type (default: ``M``'s).

    Returns
    -------
    scipy.sparse.csr_matrix
        ``M`` itself or a new matrix; a caller that changes the result's arrays in place changes ``M``'s (as with the
        constructor, which shares them).
    """
    return M if _settled(M, sp.csr_matrix, dtype) else sp.csr_matrix(M, dtype=dtype)


def as_csc(M: Any, dtype: Any = None) -> Any:
    """``M`` as a CSC matrix (``sp.csc_matrix(M, dtype=dtype)``): ``M`` itself when it is one of that dtype already
    (parameters and result as :func:`as_csr`'s)."""
    return M if _settled(M, sp.csc_matrix, dtype) else sp.csc_matrix(M, dtype=dtype)
