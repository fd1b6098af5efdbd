"""The structured KKT path takes a few dense rows stored sparse (whose Gram matrix is dense), which the
augmented-Lagrangian path could only convexify by an identity shift that spoils Newton's convergence."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import guidewire
from sqp.structured import candidate


def _banded(n: int) -> sp.csc_matrix:
    return sp.diags([-np.ones(n - 1), 2.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csc")


def test_dense_rows_stored_sparse_take_the_structured_path():
    n = 400
    rng = np.random.default_rng(1)
    dense_rows = rng.standard_normal((3, n))
    assert candidate(_banded(n), dense_rows)
    assert candidate(_banded(n), sp.csr_matrix(dense_rows))


def test_sparse_rows_with_a_sparse_gram_keep_the_augmented_lagrangian_path():
    n = 400
    rows = sp.csr_matrix(([1.0, -1.0, 1.0, -1.0, 1.0, -1.0], [0, 1, 10, 11, 20, 21], [0, 2, 4, 6]), shape=(3, n))
    assert not candidate(_banded(n), rows)


@pytest.mark.parametrize("bars", [301, 500])
def test_paper_scheme_above_the_dense_limit_converges_like_newton(bars):
    # the paper scheme's contact rows arrive as sparse rows with every entry filled; they took 21-23 iterations
    # (an identity shift in place of the exact Hessian) where the dense path below 300 bars takes 4
    scene = guidewire.paper_scenes()["table1_pi_4"].with_scheme("paper").with_bars(bars)
    sol = guidewire.solve(scene)
    assert sol.success, sol.message
    assert sol.iterations <= 6
    full = guidewire.solve(scene, layout="full")
    assert full.success
    assert sol.energy == pytest.approx(full.energy, rel=1e-7)
