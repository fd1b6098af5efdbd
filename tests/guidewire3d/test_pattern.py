"""The program's fixed sparsity patterns: the matrix a pattern fills is scipy's COO construction, entry for entry."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from guidewire.solve3d.pattern import Pattern


@pytest.mark.parametrize("compressed", ["csc", "csr"])
def test_pattern_matrix_is_scipys_coo_construction(compressed):
    rng = np.random.default_rng(7)
    flat = rng.choice(40 * 30, size=300, replace=False)
    rows, cols = flat // 30, flat % 30
    data = rng.normal(size=300)
    data[::17] = 0.0  # (explicit zeros stay stored, as in scipy's conversion)
    built = Pattern.of(rows, cols, (40, 30), compressed).matrix(data)
    kind = sp.csc_matrix if compressed == "csc" else sp.csr_matrix
    expected = kind((data, (rows, cols)), shape=(40, 30))
    assert built.format == compressed and built.has_sorted_indices
    assert np.array_equal(built.indptr, expected.indptr) and np.array_equal(built.indices, expected.indices)
    assert np.array_equal(built.data, expected.data)


def test_pattern_refuses_a_repeated_entry():
    with pytest.raises(ValueError, match="repeats an entry"):
        Pattern.of(np.array([0, 1, 0]), np.array([2, 2, 2]), (3, 3))
