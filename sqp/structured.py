"""Structured solves of equality-only QP subproblems: a sparse (banded) model Hessian and a few constraint rows.

The KKT system of ``min 1/2 d^T W d + g^T d  s.t.  E d = e``,

    [[W, E^T], [E, 0]] [d; y] = [-g; e],

is solved by one unpivoted sparse factorisation ``W = L D L^T`` (O(n b^2) for bandwidth ``b``; O(n) for the
tridiagonal Hessian of a bar chain's bending energy) and the small dense Schur complement ``S = E W^{-1} E^T``
(``m x m`` for ``m`` rows). Its inertia decides whether convexification is needed at all (Nocedal & Wright,
Thm. 16.3 and §16.2; Gould's inertia test): ``In(K) = In(W) + In(-S)`` (Haynsworth), so ``K`` has the inertia
``(n, m, 0)`` of a QP whose Hessian is positive definite on the null space of ``E`` exactly when ``S`` has as many
negative eigenvalues as ``D`` has negative pivots and none zero. Then the KKT point is the unique minimiser of the QP
with any Hessian ``W + rho E^T E`` that is positive definite (the augmented-Lagrangian term is constant on
``E d = e``): the exact Newton–SQP step, found without a single trial factorisation of a shifted matrix.

:func:`sqp.hessian.convexify` wraps a Hessian that qualifies (:func:`candidate`) in a :class:`FactoredHessian` that
carries the factorisation and, for an indefinite ``W``, the deferred convexification used when the subproblem turns
out not to be equality-only or ``K``'s inertia is wrong.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray
from scipy.linalg import lapack

Array = NDArray[np.float64]

#: Largest number of constraint rows the dense Schur complement is used for (its cost: ``m`` sparse triangular
#: solves and an ``m x m`` eigen-decomposition; the guidewire's reduced program has 2-6 contact rows).
MAX_SCHUR_ROWS = 64

#: A sparse ``C^T C`` is used only while it has at most this many nonzeros per variable (a banded one, e.g. the
#: guidewire's full-space closure rows, has about 5); a denser one (dense rows stored sparse) would make the sparse
#: factorisation as costly as a dense one.
SPARSE_GRAM_DENSITY = 20

#: Largest bandwidth ``max |i - j|`` over the nonzeros of ``W`` for which the unpivoted factorisation in the natural
#: order is used (its fill stays inside the band; the reduced program's energy Hessian has bandwidth 1 or 2).
MAX_BANDWIDTH = 32

#: An eigenvalue of the Schur complement below this times its largest magnitude counts as zero (``K`` singular).
SINGULAR_RTOL = 1e-13

#: :func:`range_space_kkt` refines its answer once when ``||E d - e||_inf`` exceeds this times
#: ``||e||_inf + || |E| |d| ||_inf`` (a backward-stable solve leaves a few machine epsilons there).
REFINE_RTOL = 1e-10


@dataclass(frozen=True)
class SymmetricFactor:
    """An unpivoted ``L D U`` factorisation of a symmetric sparse matrix (``U = D L^T`` in exact arithmetic).

    Attributes
    ----------
    lu : scipy.sparse.linalg.SuperLU
        The factorisation (natural column order, no row pivoting).
    negatives : int
        Number of negative pivots: by Sylvester's law of inertia, the number of negative eigenvalues.
    """

    lu: Any
    negatives: int

    @property
    def positive_definite(self) -> bool:
        return self.negatives == 0

    def solve(self, rhs: Array) -> Array:
        """``W^{-1} rhs`` for a vector or an ``(n, k)`` block."""
        return self.lu.solve(np.ascontiguousarray(rhs, dtype=float))


def bandwidth(W: Any) -> int:
    """``max |i - j|`` over the stored entries of the sparse matrix ``W`` (0 for a diagonal or empty one)."""
    if W.format not in ("csc", "csr"):
        W = sp.csc_matrix(W)
    if W.indices.size == 0:
        return 0
    # (from the compressed arrays directly: a COO copy costs more than the rest of the test; the row of a CSC entry is
    # its index and its column the pointer segment it lies in, and the other way round for CSR)
    n_major = W.shape[0] if W.format == "csr" else W.shape[1]
    major = np.repeat(np.arange(n_major, dtype=np.int64), np.diff(W.indptr))
    return int(np.abs(W.indices.astype(np.int64) - major).max())


def factor_symmetric(W: Any) -> SymmetricFactor | None:
    """The unpivoted factorisation of the sparse symmetric ``W``, or None when it needs pivoting or breaks down
    (a zero pivot: ``W`` or one of its leading blocks is singular)."""
    A = sp.csc_matrix(W)
    A.sort_indices()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            lu = spla.splu(A, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError:  # exactly singular
        return None
    pivots = lu.U.diagonal()
    if not np.all(lu.perm_r == np.arange(A.shape[0])) or not np.all(np.isfinite(pivots)) or np.any(pivots == 0.0):
        return None
    return SymmetricFactor(lu=lu, negatives=int(np.count_nonzero(pivots < 0.0)))


def candidate(W: Any, C: Any) -> bool:
    """Whether the structured path applies to the sparse Hessian ``W`` and the rows ``C`` the QP keeps as
    equalities: ``W`` banded (:data:`MAX_BANDWIDTH`), ``C`` absent or a few (:data:`MAX_SCHUR_ROWS`) dense rows.

    (Sparse rows whose Gram matrix stays sparse keep :func:`sqp.hessian.convexify`'s augmented-Lagrangian path,
    whose multipliers the loop corrects; dense rows, however stored, would get only its identity shift, which
    changes the step.)"""
    if not sp.issparse(W) or W.shape[0] < 2:
        return False
    if C is not None and C.shape[0] > min(MAX_SCHUR_ROWS, W.shape[0] // 4):
        return False
    if C is not None and sp.issparse(C) and not _dense_gram(C):
        return False  # (sparse rows with a sparse Gram matrix: the augmented-Lagrangian path serves them)
    return bandwidth(W) <= MAX_BANDWIDTH


def _dense_gram(C: Any) -> bool:
    """Whether the sparse rows ``C`` may make ``C^T C`` too dense for the augmented-Lagrangian path of
    :func:`sqp.hessian.convexify` (more than :data:`SPARSE_GRAM_DENSITY` nonzeros per variable, bounded by the sum of
    the squared row counts): a few rows with many nonzeros each (the paper scheme's contact rows, stored sparse)
    fill the Gram matrix, and that path would fall back to an identity shift, which changes the Newton step
    (measured: Table 1 in the paper scheme took 21-23 iterations instead of 4 above 300 bars)."""
    counts = np.diff(sp.csr_matrix(C).indptr).astype(float)
    return float(counts @ counts) > SPARSE_GRAM_DENSITY * C.shape[1]


class FactoredHessian(sp.csc_matrix):
    """A sparse model Hessian ``W`` with its factorisation, as :func:`sqp.hessian.convexify` hands it to the QP.

    As a matrix it is ``W`` itself. When ``W`` is indefinite it is usable only by :func:`equality_kkt` (an
    equality-only subproblem whose KKT matrix has the right inertia); any other subproblem first replaces it by
    :meth:`convexified`, the positive-definite matrix the general path of ``convexify`` gives. Pickles (and copies
    made by scipy) are plain CSC matrices: the factorisation is a cache, not state.
    """

    factor: SymmetricFactor | None = None
    _convexify: Callable[[], tuple[Any, float, float]] | None = None
    #: ``(delta, rho)`` of :meth:`convexified` once it ran (the shift and augmented-Lagrangian weight it used).
    convexification: tuple[float, float] | None = None

    @classmethod
    def wrap(cls, W: Any, factor: SymmetricFactor, convexify: Callable[[], tuple[Any, float, float]]
             ) -> FactoredHessian:
        """``W`` (sparse) carrying ``factor`` and ``convexify() -> (B, delta, rho)`` (a positive-definite
        replacement, as :func:`sqp.hessian.convexify` returns it)."""
        out = cls(sp.csc_matrix(W))
        out.sort_indices()
        out.factor = factor
        out._convexify = convexify
        return out

    @property
    def positive_definite(self) -> bool:
        return self.factor is not None and self.factor.positive_definite

    def convexified(self) -> Any:
        """``W`` when positive definite, else the general convexification of ``W`` (computed now)."""
        if self.positive_definite or self._convexify is None:
            return self
        B, delta, rho = self._convexify()
        self.convexification = (delta, rho)
        return B

    def __reduce__(self) -> tuple[Any, ...]:
        return (sp.csc_matrix, ((self.data, self.indices, self.indptr), self.shape))


def needs_convexification(B: Any) -> bool:
    """Whether ``B`` is an indefinite :class:`FactoredHessian` (only :func:`equality_kkt` may use it as it is)."""
    return isinstance(B, FactoredHessian) and not B.positive_definite


def equality_kkt(B: Any, g: Array, E: Any, e: Array) -> tuple[Array, Array] | None:
    """The KKT point of ``min 1/2 d^T B d + g^T d  s.t.  E d = e`` by the factorisation of the sparse ``B`` and the
    Schur complement of its few rows, when the KKT matrix has the inertia of a convex QP (see the module text).

    Returns
    -------
    (d, y) or None
        The step and the equality multipliers in qpsolvers' sign (``B d + g + E^T y = 0``); None when the
        structure does not fit (``B`` dense or too wide a band, too many rows), the factorisation breaks down, or
        ``K``'s inertia is wrong or it is singular (then no QP with this data has a unique minimiser on ``E``).
    """
    if not sp.issparse(B):
        return None
    n, m = g.size, e.size
    factor = B.factor if isinstance(B, FactoredHessian) else None
    if factor is None:
        if m > min(MAX_SCHUR_ROWS, n // 4) or bandwidth(B) > MAX_BANDWIDTH:
            return None
        factor = factor_symmetric(B)
        if factor is None:
            return None
    if m > MAX_SCHUR_ROWS:
        return None
    Ed = E.toarray() if sp.issparse(E) else np.asarray(E, dtype=float).reshape(m, n)
    w = factor.solve(g)
    if m == 0:
        return (-w, np.zeros(0)) if factor.positive_definite else None
    X = factor.solve(Ed.T)
    S = Ed @ X
    S = 0.5 * (S + S.T)
    sigma, V = np.linalg.eigh(S)
    size = float(np.max(np.abs(sigma)))
    if not np.isfinite(size) or size == 0.0 or float(np.min(np.abs(sigma))) <= SINGULAR_RTOL * size:
        return None
    if int(np.count_nonzero(sigma < 0.0)) != factor.negatives:
        return None  # W is not positive definite on the null space of E
    y = -(V @ ((V.T @ (e + Ed @ w)) / sigma))
    d = -(w + X @ y)
    return d, y


def range_space_kkt(L: Array, g: Array, E: Array, e: Array) -> tuple[Array, Array] | None:
    """The KKT point of ``min 1/2 d^T B d + g^T d  s.t.  E d = e`` from ``B = L L^T`` (Nocedal & Wright §16.2, the
    Schur-complement method): ``[w, X] = B^{-1} [g, E^T]``, ``(E X) y = -(e + E w)``, ``d = -(w + X y)``; None when
    the ``m x m`` Schur complement ``E X`` is exactly singular (dependent rows). The dense counterpart of
    :func:`equality_kkt` for a positive-definite ``B`` (:class:`sqp.hessian.CholeskyHessian` carries ``L``).

    Returns
    -------
    (d, y) or None
        The step and the equality multipliers in qpsolvers' sign (``B d + g + E^T y = 0``).
    """
    n, m = g.size, e.size
    rhs = np.empty((n, m + 1), order="F")
    rhs[:, 0] = g
    rhs[:, 1:] = E.T
    # (scipy's cho_solve without its checks and copies: a C-ordered L is passed as the upper triangle L^T, its
    # Fortran-ordered view, so that LAPACK reads it in place; the same solves, the same numbers)
    WX, info = (lapack.dpotrs(L, rhs, lower=1, overwrite_b=True) if L.flags.f_contiguous
                else lapack.dpotrs(L.T, rhs, lower=0, overwrite_b=True))
    if info != 0:
        return None
    w, X = WX[:, 0], WX[:, 1:]
    if e.size == 0:
        return -w, np.zeros(0)
    # (LAPACK's dgesv through scipy, as the factorisation: np.linalg.solve costs 20-27 us here against 9 us, most of
    # it in reaching numpy's own LAPACK between scipy's calls)
    S = E @ X
    lu, piv, y, info = lapack.dgesv(S, e + E @ w)
    if info != 0:  # exactly singular
        return None
    y = -y
    d = -(w + X @ y)
    # one step of iterative refinement on the rows when they are met visibly worse than rounding allows: an
    # ill-conditioned B with nearly dependent rows (a nearly taut wire between two points) loses digits in E X and
    # leaves E d - e at 1e-6 of E d's size, enough for the merit function to call the step an ascent one. The
    # correction of the rows' residual r solves the KKT system with right-hand side (0, r): the same factors
    r = e - E @ d
    if np.max(np.abs(r)) > REFINE_RTOL * (np.max(np.abs(e)) + np.max(np.abs(E) @ np.abs(d))):
        dy, info = lapack.dgetrs(lu, piv, r)
        if info == 0:
            y = y - dy
            d = d + X @ dy
    return d, y
