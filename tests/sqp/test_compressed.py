"""sqp.compressed: a matrix already in the asked format is returned itself, anything else as the constructor gives it;
the single-block stacks of the subproblem and the augmented-Lagrangian rows never alias the caller's matrices."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from sqp.compressed import as_csc, as_csr
from sqp.problem import Rows
from sqp.subproblem import LinearisedRows, _stack_rows, _vstack


def _matrix() -> sp.csr_matrix:
    return sp.csr_matrix(np.array([[1.0, 0.0, 2.0], [0.0, 3.0, 0.0]]))


def test_settled_matrices_are_returned_themselves() -> None:
    M = _matrix()
    assert as_csr(M) is M
    C = M.tocsc()
    assert as_csc(C) is C
    assert as_csc(C, dtype=float) is C


def test_other_inputs_are_converted_like_the_constructor() -> None:
    M = _matrix()
    for got, want in ((as_csc(M), sp.csc_matrix(M)), (as_csr(M.tocsc()), sp.csr_matrix(M.tocsc())),
                      (as_csr(M.toarray()), sp.csr_matrix(M.toarray())), (as_csr(sp.csr_array(M)), sp.csr_matrix(M)),
                      (as_csc(M.tocsc().astype(np.float32), dtype=float), sp.csc_matrix(M.tocsc(), dtype=float))):
        assert type(got) is type(want) and got.dtype == want.dtype
        np.testing.assert_array_equal(got.toarray(), want.toarray())


def test_unpruned_matrix_is_rebuilt() -> None:
    M = _matrix()
    M.data = np.concatenate((M.data, [9.0]))
    M.indices = np.concatenate((M.indices, [0])).astype(M.indptr.dtype)
    out = as_csr(M)
    assert out is not M and out.data.size == out.nnz == 3


def test_single_block_stack_is_the_block_unless_shared() -> None:
    B = _matrix()
    assert _vstack([B], 3, "csr") is B
    assert _vstack([B], 3, "csr", {id(B)}) is not B
    assert _vstack([B], 3, "csc").format == "csc"
    J = _matrix()
    every_row = Rows.from_bounds(np.zeros(2), np.zeros(2))  # (all equalities: the block would be J itself)
    E, _, _, _, _ = _stack_rows([LinearisedRows(M=J, lo=every_row.lb, hi=every_row.ub, rows=every_row)], 3, "csr")
    assert E is not J
    np.testing.assert_array_equal(E.toarray(), J.toarray())


def test_rows_times_is_the_submatrix_product_bit_for_bit() -> None:
    from sqp.multipliers import _rows_times

    rng = np.random.default_rng(3)
    M = sp.random(40, 30, density=0.3, format="csr", random_state=rng)
    d = rng.standard_normal(30)
    rows = np.array([1, 4, 5, 17, 39])
    for kind in (sp.csr_matrix, sp.csc_matrix, lambda m: m.toarray()):
        got = _rows_times(kind(M), rows, d)
        want = np.asarray(kind(M)[rows] @ d).ravel()
        assert got.tobytes() == want.tobytes()


def test_sparse_copy_is_a_fresh_csr_copy() -> None:
    from sqp.iterate import _sparse_copy

    M = _matrix()
    out = _sparse_copy(M)
    assert type(out) is sp.csr_matrix and out is not M and not np.shares_memory(out.data, M.data)
    np.testing.assert_array_equal(out.toarray(), M.toarray())
    C = _sparse_copy(M.tocsc())
    assert type(C) is sp.csr_matrix
    np.testing.assert_array_equal(C.toarray(), M.toarray())


def test_rows_of_runs_are_the_slices_bit_for_bit() -> None:
    from sqp.subproblem import _rows_of

    rng = np.random.default_rng(5)
    M = sp.random(30, 12, density=0.3, format="csr", random_state=rng)
    for index in (np.arange(3, 11), np.arange(30), np.array([2, 5, 9]), np.arange(0)):
        for negate in (False, True):
            for kind in (sp.csr_matrix, sp.csc_matrix, lambda m: m.toarray()):
                A = kind(M)
                want = -A[index] if negate else A[index]
                got = _rows_of(A, index, negate)
                assert type(got) is type(want) and got.shape == want.shape
                if sp.issparse(want):
                    want, got = sp.csr_matrix(want), sp.csr_matrix(got)
                    for name in ("data", "indices", "indptr"):
                        assert getattr(got, name).tobytes() == getattr(want, name).tobytes()
                else:
                    assert got.tobytes() == want.tobytes()


def test_canonical_sums_duplicates_in_a_copy() -> None:
    from sqp.active_set import _canonical

    M = _matrix()
    assert _canonical(M) is M
    D = sp.csr_matrix((np.array([1.0, 2.0, 5.0]), np.array([2, 0, 2]), np.array([0, 3, 3])), shape=(2, 3))
    before = (D.data.copy(), D.indices.copy(), D.indptr.copy())
    out = _canonical(D)
    assert out is not D and out.has_canonical_format
    np.testing.assert_array_equal(out.toarray(), [[2.0, 0.0, 6.0], [0.0, 0.0, 0.0]])
    for got, want in zip((D.data, D.indices, D.indptr), before, strict=True):
        np.testing.assert_array_equal(got, want)
