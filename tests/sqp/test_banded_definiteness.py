"""The positive-definiteness test of a sparse model Hessian: LAPACK's banded Cholesky for a narrow band decides as
the unpivoted LU (Sylvester's law) does, on banded matrices on both sides of definiteness, with repeated entries."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from sqp.hessian import _positive_definite
from sqp.pencil import BANDED_CHOLESKY_MAX


def _lu_decides(B: sp.csc_matrix) -> bool:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lu = spla.splu(sp.csc_matrix(B), permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    return bool(np.all(lu.perm_r == np.arange(B.shape[0])) and np.all(lu.U.diagonal() > 0))


@pytest.mark.parametrize("band", [1, 8, BANDED_CHOLESKY_MAX])
def test_banded_test_agrees_with_the_lu_test_across_the_smallest_eigenvalue(band):
    rng = np.random.default_rng(band)
    n = 200
    diagonals = [rng.normal(size=n - k) for k in range(band + 1)]
    A = sp.diags(diagonals + diagonals[1:], list(range(band + 1)) + [-k for k in range(1, band + 1)], format="csc")
    low = float(np.linalg.eigvalsh(A.toarray())[0])
    for shift in (-low - 1e-3, -low + 1e-3, -low + 1.0):
        B = sp.csc_matrix(A + shift * sp.identity(n))
        assert _positive_definite(B) == _lu_decides(B) == (shift > -low)


def test_repeated_entries_are_summed():
    """A non-canonical CSC matrix (an entry stored twice) means the sum: ``[[1, 0], [0, -1 + 2]]`` is definite."""
    B = sp.csc_matrix((np.array([1.0, -1.0, 2.0]), np.array([0, 1, 1]), np.array([0, 1, 3])), shape=(2, 2))
    assert not B.has_canonical_format
    assert _positive_definite(B)
