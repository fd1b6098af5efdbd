"""Equality-only QP subproblems with a small dense exact Hessian: the dense analogue of :mod:`sqp.structured`.

The KKT matrix of ``min 1/2 d^T W d + g^T d  s.t.  E d = e`` (``n`` variables, ``m`` rows),

    K = [[W, E^T], [E, 0]],

is factorised once as ``P K P^T = L D L^T`` (LAPACK's Bunch–Kaufman ``dsytrf``; ``D`` has 1x1 and 2x2 blocks). By
Sylvester's law of inertia ``D`` has ``K``'s inertia, and ``K`` has the inertia ``(n, m, 0)`` exactly when ``E`` has
full rank and ``W`` is positive definite on its null space (Nocedal & Wright, Thm. 16.3; Gould's inertia test). Then
the KKT point is the unique minimiser of the QP with any Hessian ``W + rho E^T E`` that is positive definite (the
augmented-Lagrangian term is constant on ``E d = e``): the exact Newton–SQP step and its multipliers, without the
failing Cholesky test of ``W``, the Gram product, the trial Cholesky factorisations of ``W + rho E^T E`` and the
multiplier correction of :func:`sqp.hessian.convexify`'s general path.

:class:`ConvexifiedExact <sqp.hessian_strategy.ConvexifiedExact>` hands such a ``W`` (a few dense rows, at most
:data:`sqp.hessian.DENSE_LIMIT` variables) to the QP as a :class:`DeferredHessian`; any other subproblem, or a ``K``
with the wrong inertia, asks for the general convexification first (:meth:`DeferredHessian.convexified`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.linalg import lapack

from sqp.structured import range_space_kkt

Array = NDArray[np.float64]

#: Largest number of rows ``C`` for which :func:`candidate` holds (and at most a quarter of the variables), as
#: :data:`sqp.structured.MAX_SCHUR_ROWS`; the guidewire's reduced program has 2-6 contact rows.
MAX_ROWS = 64


def candidate(W: Any, C: Any) -> bool:
    """Whether the dense KKT path applies to the Hessian ``W`` and the rows ``C`` the QP keeps as equalities: ``W`` a
    dense array, ``C`` present with ``1 <= m <= min(MAX_ROWS, n // 4)`` rows."""
    if sp.issparse(W) or C is None:
        return False
    m = C.shape[0]
    return 1 <= m <= min(MAX_ROWS, W.shape[0] // 4)


def inertia(ldu: Array, ipiv: NDArray[np.int32]) -> tuple[int, int, int]:
    """The inertia ``(positive, negative, zero)`` of the block-diagonal ``D`` of a lower ``dsytrf`` factorisation.

    ``ipiv[k] > 0`` marks a 1x1 block ``D[k, k]``; two equal negative entries ``ipiv[k] = ipiv[k + 1] < 0`` a 2x2
    block ``[[D[k, k], D[k + 1, k]], [D[k + 1, k], D[k + 1, k + 1]]]``, which has one eigenvalue of each sign when its
    determinant is negative, else two of its trace's sign.
    """
    diag = ldu.diagonal()
    two = ipiv < 0
    if not two.any():
        pos = int(np.count_nonzero(diag > 0.0))
        neg = int(np.count_nonzero(diag < 0.0))
        return pos, neg, diag.size - pos - neg
    one = diag[~two]
    first = np.flatnonzero(two)[::2]  # (2x2 blocks do not overlap: a run of negative entries pairs up in order)
    a, c, b = diag[first], diag[first + 1], ldu[first + 1, first]
    det = a * c - b * b
    tr = a + c
    mixed = int(np.count_nonzero(det < 0.0))
    pos = int(np.count_nonzero(one > 0.0)) + mixed + 2 * int(np.count_nonzero((det > 0.0) & (tr > 0.0)))
    neg = int(np.count_nonzero(one < 0.0)) + mixed + 2 * int(np.count_nonzero((det > 0.0) & (tr < 0.0)))
    return pos, neg, diag.size - pos - neg


def factor_kkt(W: Array, E: Array) -> tuple[Array, NDArray[np.int32]] | None:
    """The Bunch–Kaufman factorisation of ``K = [[W, E^T], [E, 0]]`` when ``K`` has the inertia ``(n, m, 0)``, else
    None (``W`` not positive definite on the null space of ``E``, ``E`` rank-deficient, or an exactly zero pivot).

    Returns
    -------
    (ldu, ipiv)
        ``dsytrf``'s lower factor and pivots, for :func:`solve_kkt`.
    """
    n, m = W.shape[0], E.shape[0]
    K = np.empty((n + m, n + m), order="F")
    K[:n, :n] = W
    K[n:, :n] = E
    K[n:, n:] = 0.0  # (the upper triangle is never read: lower=1)
    # (the unblocked factorisation, dsytrf's default workspace: at n = 100 it took 15 us, the blocked one 32 us)
    ldu, ipiv, info = lapack.dsytrf(K, lower=1, overwrite_a=1)
    if info != 0:
        return None
    if inertia(ldu, ipiv) != (n, m, 0):
        return None
    return ldu, ipiv


def solve_kkt(factor: tuple[Array, NDArray[np.int32]], g: Array, e: Array,
              inverse_block: bool = False) -> tuple[Array, Array, Array | None] | None:
    """``(d, y, Y)`` solving ``[[W, E^T], [E, 0]] [d; y] = [-g; e]`` with the factor of :func:`factor_kkt` (qpsolvers'
    sign for the multipliers ``y``: ``W d + g + E^T y = 0``); None if LAPACK reports an error.

    With ``inverse_block`` also ``Y``, the ``m x m`` trailing block of ``K^{-1}`` (``-S^{-1}`` for the Schur
    complement ``S = E W^{-1} E^T`` when ``W`` is nonsingular; see :func:`augmented_weight`), from ``m`` more
    right-hand sides ``[0; I]`` in the same solve; else ``Y`` is None.
    """
    n, m = g.size, e.size
    rhs = np.zeros((n + m, 1 + m if inverse_block else 1), order="F")
    rhs[:n, 0] = -g
    rhs[n:, 0] = e
    if inverse_block:
        rhs[n:, 1:] = np.eye(m)
    x, info = lapack.dsytrs(factor[0], factor[1], rhs, lower=1, overwrite_b=1)
    if info != 0:
        return None
    return x[:n, 0], x[n:, 0], (x[n:, 1:] if inverse_block else None)


#: Relative distance from a threshold within which :func:`augmented_weight` does not decide a test that today's
#: Cholesky factorisation would decide in floating point (it then leaves the choice to that factorisation).
DECISION_RTOL = 1e-8


def augmented_weight(Y: Array, scale: float, base: float, weight: float, tries: int = 12) -> float | None:
    """The augmented-Lagrangian weight :func:`sqp.hessian.convexify`'s general path would accept for ``W`` and rows
    ``E`` whose KKT matrix ``K`` has the inertia ``(n, m, 0)``, decided without factorising ``W + rho E^T E``.

    ``W + rho E^T E`` is positive definite exactly when ``rho > rho* = max(0, lambda_max(Y))`` for ``Y`` the
    trailing ``m x m`` block of ``K^{-1}``: with ``S = E W^{-1} E^T`` (``Y = -S^{-1}``), Haynsworth's inertia formula
    on ``[[W, E^T], [E, -I / rho]]`` both ways gives ``In(W + rho E^T E) = In(W) + In(-(S + I / rho)) - (0, m, 0)``
    and ``In(K) = In(W) + In(-S)``; so ``W`` alone is positive definite when ``lambda_max(Y) < 0``. The tests of
    ``convexify`` are replayed on that: ``W`` alone when ``weight`` is 0, then ``r0 = 1e-3 scale / base`` (or
    ``weight / 4``) growing tenfold over ``tries`` weights.

    Parameters
    ----------
    Y : ndarray, shape (m, m)
        The trailing block of ``K^{-1}`` (:func:`solve_kkt`).
    scale, base : float
        ``max(1, max|W_ii|)`` and ``max (E^T E)_ii``, as ``convexify`` computes them.
    weight : float
        The weight that worked last iteration (0 when none did).

    Returns
    -------
    float or None
        The weight (0 for ``W`` itself), or None when no weight of the ladder would do (``convexify`` goes on to the
        identity shift) or one of the tests lies within :data:`DECISION_RTOL` of its threshold.
    """
    top = _largest_eigenvalue(Y)
    if not np.isfinite(top) or base <= 0.0:
        return None
    r0 = 1e-3 * scale / base
    if weight <= 0.0:
        if top < -DECISION_RTOL * r0:
            return 0.0
        if top <= DECISION_RTOL * r0:
            return None
    r = r0 if weight <= 0.0 else weight / 4.0
    for _ in range(tries):
        if r > top * (1.0 + DECISION_RTOL):
            return r
        if r >= top * (1.0 - DECISION_RTOL):
            return None
        r *= 10.0
    return None


def _largest_eigenvalue(Y: Array) -> float:
    """The largest eigenvalue of the symmetric part of the small ``Y`` (closed form up to 2 x 2: numpy's ``eigvalsh``
    costs 5-25 us there)."""
    m = Y.shape[0]
    if m == 1:
        return float(Y[0, 0])
    if m == 2:
        a, c, b = float(Y[0, 0]), float(Y[1, 1]), 0.5 * (float(Y[0, 1]) + float(Y[1, 0]))
        return 0.5 * (a + c) + math.hypot(0.5 * (a - c), b)
    return float(np.linalg.eigvalsh(0.5 * (Y + Y.T))[-1])


class DeferredHessian(np.ndarray):
    """A dense exact Hessian ``W`` handed to the QP unconvexified, with its convexification deferred.

    As an array it is ``W`` itself. Only an equality-only subproblem whose KKT matrix has the inertia ``(n, m, 0)``
    may use it as it is (:meth:`kkt`); any other first replaces it by :meth:`convexified`, the positive-definite
    matrix of :func:`sqp.hessian.convexify`'s general path (computed on demand). After a KKT step, :meth:`settled`
    gives the matrix that path would have handed to the QP (``W + rho E^T E`` with the weight it would accept,
    :func:`augmented_weight`), for the merit function and the result, still carrying ``K``'s factorisation. ``K``'s
    factorisation is kept for the rows it was made for (a second-order correction solves the same ``K`` with other
    right-hand sides). Like :class:`sqp.hessian.CholeskyHessian`, nothing derived from it keeps these caches.
    """

    positive_definite = False
    _convexify: Callable[[], Any] | None = None
    _settle: Callable[[Array, Array], Any] | None = None
    _rows: Array | None = None
    _factor: tuple[Array, NDArray[np.int32]] | None = None
    _inverse_block: Array | None = None

    @classmethod
    def wrap(cls, W: Array, convexify: Callable[[], Any] | None,
             settle: Callable[[Array, Array], Any] | None = None) -> DeferredHessian:
        """``W`` (a view, no copy) carrying ``convexify() -> B``, its positive-definite replacement, and
        ``settle(E, Y) -> B or None``, the matrix of that replacement's augmented-Lagrangian path (see
        :meth:`settled`)."""
        out = np.asarray(W).view(cls)
        out._convexify = convexify
        out._settle = settle
        return out

    def convexified(self) -> Any:
        """The general convexification of ``W`` (computed now; a plain copy of ``W`` if none was given)."""
        if self._convexify is None:
            return np.asarray(self).view(np.ndarray)
        return self._convexify()

    def settled(self) -> Any:
        """After :meth:`kkt` found a step: the matrix ``B`` the general convexification gives when it is
        ``W + rho E^T E`` (or ``W``), as a positive-definite :class:`DeferredHessian` carrying this ``K``'s
        factorisation; None when that cannot be decided here (then convexify and solve again); itself when already
        positive definite."""
        if self.positive_definite:
            return self
        if self._settle is None or self._rows is None or self._inverse_block is None:
            return None
        B = self._settle(self._rows, self._inverse_block)
        if B is None:
            return None
        out = DeferredHessian.wrap(np.asarray(B), None)
        out.positive_definite = True
        out._rows, out._factor = self._rows, self._factor
        return out

    def kkt(self, g: Array, E: Any, e: Array) -> tuple[Array, Array] | None:
        """The KKT point ``(d, y)`` of ``min 1/2 d^T W d + g^T d  s.t.  E d = e`` (``W d + g + E^T y = 0``), or None
        when ``K``'s inertia is wrong (see :func:`factor_kkt`)."""
        E = E.toarray() if sp.issparse(E) else np.asarray(E, dtype=float)
        fresh = self._rows is None or self._rows.shape != E.shape or not np.array_equal(self._rows, E)
        if fresh:
            self._rows, self._factor = E, factor_kkt(np.asarray(self).view(np.ndarray), E)
        if self._factor is None:
            return None
        out = solve_kkt(self._factor, g, e, inverse_block=fresh and self._settle is not None)
        if out is None:
            return None
        if fresh:
            self._inverse_block = out[2]
        return out[0], out[1]

    def __array_finalize__(self, obj: Any) -> None:
        self._convexify = None
        self._settle = None
        self._rows = None
        self._factor = None
        self._inverse_block = None

    def __array_wrap__(self, array: Any, context: Any = None, return_scalar: bool = False) -> Any:
        out = np.asarray(array).view(np.ndarray)
        return out[()] if return_scalar else out

    def __reduce__(self) -> tuple[Any, ...]:
        return (np.array, (np.asarray(self).view(np.ndarray),))


def factored_kkt(B: Any, g: Array, E: Any, e: Array) -> tuple[Array, Array] | None:
    """The KKT point of an equality-only QP with a dense ``B`` that carries a factorisation: by
    :meth:`DeferredHessian.kkt`, or for a :class:`sqp.hessian.CholeskyHessian` by the range-space method
    (:func:`sqp.structured.range_space_kkt`); None when ``B`` carries none or the solve refuses."""
    if isinstance(B, DeferredHessian):
        return B.kkt(g, E, e)
    L = getattr(B, "cholesky", None)
    return None if L is None else range_space_kkt(L, g, E, e)
