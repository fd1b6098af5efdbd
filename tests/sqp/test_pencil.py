"""The ladders' band-storage tests of ``W + r C^T C + delta I`` (:class:`sqp.pencil.BandPencil`) decide as the
factorisation of the formed sparse matrix does, on both sides of definiteness, and the ladders built on them return
the matrices they returned when every candidate was formed."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from sqp import hessian
from sqp.pencil import BandPencil


def _pencil_parts(seed: int, n: int = 120, band: int = 3) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    """An indefinite banded ``W`` and ``C^T C`` of local rows (each touching ``band`` consecutive variables), as
    a discretised rod's Lagrangian Hessian and closure rows are."""
    rng = np.random.default_rng(seed)
    diagonals = [rng.normal(size=n - k) for k in range(band + 1)]
    W = sp.diags(diagonals + diagonals[1:], list(range(band + 1)) + [-k for k in range(1, band + 1)], format="csc")
    m = n // 2
    rows = np.repeat(np.arange(m), band)
    starts = rng.integers(0, n - band, size=m)
    cols = (starts[:, None] + np.arange(band)).ravel()
    C = sp.csr_matrix((rng.normal(size=rows.size), (rows, cols)), shape=(m, n))
    return W, sp.csc_matrix(C.T @ C)


def _lowest(M: sp.spmatrix) -> float:
    return float(np.linalg.eigvalsh(M.toarray())[0])


@pytest.mark.parametrize("seed", range(6))
def test_a_pencil_test_decides_as_the_formed_matrix_and_its_spectrum_do(seed):
    W, CtC = _pencil_parts(seed)
    pencil = BandPencil.of(W, CtC)
    assert pencil is not None
    eye = sp.identity(W.shape[0], format="csc")
    for r in (0.0, 0.1, 10.0, 1e3):
        low = _lowest(W + r * CtC)
        for delta in (-low - 1e-3, -low + 1e-3, -low + 1.0):
            delta = max(delta, 0.0)
            formed = sp.csc_matrix(W + r * CtC + delta * eye)
            expected = low + delta > 0.0
            assert pencil.positive_definite(r, delta) == hessian._positive_definite(formed) == expected
    # (a floor on the pivots refuses what the bare test accepts)
    definite = -_lowest(W) + 1.0
    assert pencil.positive_definite(0.0, definite)
    assert not pencil.positive_definite(0.0, definite, floor=1e6)


def test_a_band_wider_than_the_banded_test_is_left_to_the_formed_matrices():
    n = 80
    W = sp.csc_matrix(sp.identity(n) + sp.diags([np.ones(n - 40)], [40]) + sp.diags([np.ones(n - 40)], [-40]))
    assert BandPencil.of(W) is None


@pytest.mark.parametrize("seed", range(4))
def test_the_ladders_return_the_matrices_formed_for_every_candidate(seed, monkeypatch):
    """:func:`sqp.hessian.shifted_augmented` and the augmented ladder with the pencil give the same ``B``, shift and
    weight, entry for entry, as with the pencil refused (every candidate formed and factorised)."""
    W, CtC = _pencil_parts(seed)
    rng = np.random.default_rng(100 + seed)
    C = sp.csr_matrix(sp.random(W.shape[0] // 3, W.shape[0], density=0.02, random_state=rng))
    with_pencil = [hessian.shifted_augmented(W, C, 0.0), hessian._convexify(W, 0.0, C, 0.0, True, 3)]
    monkeypatch.setattr(hessian.BandPencil, "of", classmethod(lambda cls, *a: None))
    formed = [hessian.shifted_augmented(W, C, 0.0), hessian._convexify(W, 0.0, C, 0.0, True, 3)]
    for (B1, d1, r1), (B2, d2, r2) in zip(with_pencil, formed, strict=True):
        assert (d1, r1) == (d2, r2)
        assert (B1 != B2).nnz == 0
    assert with_pencil[0][1] > 0.0  # (W is indefinite: the shift was needed)


@pytest.mark.parametrize("seed", range(4))
def test_the_gram_matrix_comes_sorted_and_the_ladder_returns_what_it_did_on_an_unsorted_one(seed):
    """:func:`sqp.hessian._gram` sorts the product's indices (scipy's sparse product leaves them unsorted), and the
    augmented ladder on it returns the matrix, entry for entry, and the weight it returns on the unsorted product."""
    W, _ = _pencil_parts(seed)
    W = sp.csc_matrix(W + (1.0 - _lowest(W)) * sp.identity(W.shape[0]))  # (positive definite: a rung passes)
    rng = np.random.default_rng(100 + seed)
    n, m = W.shape[0], W.shape[0] // 2
    rows = np.repeat(np.arange(m), 3)
    cols = (rng.integers(0, n - 3, size=m)[:, None] + np.arange(3)).ravel()
    C = sp.csr_matrix((rng.normal(size=rows.size), (rows, cols)), shape=(m, n))
    unsorted = sp.csc_matrix(C.T @ C)
    assert not unsorted.has_sorted_indices  # (else this test would not test the sorting)
    CtC = hessian._gram(C, True)
    assert CtC.has_sorted_indices and CtC.has_canonical_format
    assert abs(CtC - unsorted).max() == 0.0
    scale = max(1.0, float(np.abs(W.diagonal()).max()))
    found = hessian._augmented_ladder(W, CtC, 0.0, 0, scale, True)
    expected = hessian._augmented_ladder(W, unsorted, 0.0, 0, scale, True)
    assert found is not None and expected is not None
    assert found[1:] == expected[1:]
    for a, b in ((found[0].indptr, expected[0].indptr), (found[0].indices, expected[0].indices),
                 (found[0].data, expected[0].data)):
        assert np.array_equal(a, b)
