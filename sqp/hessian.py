"""The model Hessian: damped BFGS of the Lagrangian Hessian (paper Eq. 6 with Powell's damping), or an exact
Lagrangian Hessian made positive definite by a diagonal shift.

Symbols (Nocedal & Wright, Procedure 18.2): ``B`` the current approximation, ``s = x+ - x``,
``y = grad L(x+, lam+) - grad L(x, lam+)``.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray
from scipy.linalg import lapack

from sqp import structured
from sqp.compressed import as_csc
from sqp.pencil import BandPencil, band_positive_definite, lower_band
from sqp.structured import SPARSE_GRAM_DENSITY

Array = NDArray[np.float64]

#: Powell's damping threshold: the update keeps ``s^T r >= 0.2 s^T B s`` (Nocedal & Wright, Eq. 18.15).
MIN_CURVATURE = 0.2


def damped_bfgs_update(B: Array, s: Array, y: Array) -> tuple[Array, bool]:
    """One damped BFGS update.

    Parameters
    ----------
    B : ndarray, shape (n, n)
        Symmetric positive-definite approximation of the Lagrangian Hessian.
    s, y : ndarray, shape (n,)
        Step and change of the Lagrangian gradient.

    Returns
    -------
    B_new : ndarray, shape (n, n)
        ``B - B s s^T B / (s^T B s) + r r^T / (s^T r)`` with ``r = theta y + (1 - theta) B s``, where
        ``theta = 1`` if ``s^T y >= 0.2 s^T B s`` and ``theta = 0.8 s^T B s / (s^T B s - s^T y)`` otherwise.
        Positive definite whenever ``B`` is. Returned unchanged when ``s^T B s`` is not positive.
    damped : bool
        Whether ``theta < 1`` was used.
    """
    Bs = B @ s
    sBs = float(s @ Bs)
    if not np.isfinite(sBs) or sBs <= 0.0 or not np.all(np.isfinite(y)):
        return B, False
    sy = float(s @ y)
    damped = sy < MIN_CURVATURE * sBs
    theta = (1.0 - MIN_CURVATURE) * sBs / (sBs - sy) if damped else 1.0
    r = theta * y + (1.0 - theta) * Bs
    sr = float(s @ r)
    B_new = B - np.outer(Bs, Bs) / sBs + np.outer(r, r) / sr
    return 0.5 * (B_new + B_new.T), damped


def initial_scaling(s: Array, y: Array) -> float:
    """Shanno–Phua scale ``y^T y / s^T y`` of an identity start (Nocedal & Wright, Eq. 6.20), or 1 if undefined."""
    sy = float(s @ y)
    yy = float(y @ y)
    if sy <= 0.0 or not np.isfinite(sy) or yy <= 0.0:
        return 1.0
    return yy / sy


#: Largest number of variables for which a sparse exact Hessian is made dense (Cholesky test, augmented-Lagrangian
#: term); above it the matrix stays sparse and only the identity shift is available.
DENSE_LIMIT = 300

#: Above this many variables an equality-only problem's sparse banded exact Hessian with a few dense constraint rows
#: takes the structured KKT path (:mod:`sqp.structured`) instead of being made dense, up to :data:`DENSE_LIMIT` too
#: (above it every problem's does). Measured on the guidewire's contact scenes (5 scenes, core-pinned, medians of
#: 9): the same time at 150 bars, 11 % less at 200 and 44 % less at 300, 28 % more at 100.
STRUCTURED_MIN = 150


def convexify(W: Any, shift: float = 0.0, C: Any = None, rho: float = 0.0,
              alone_first: bool = True, equality_only: bool = False,
              rungs: int | None = None, dense_limit: int = DENSE_LIMIT) -> tuple[Any, float, float]:
    """A positive-definite model Hessian from the exact Lagrangian Hessian ``W``, changing the QP step least.

    1. ``W`` itself when it is positive definite.
    2. ``W + rho C^T C`` (an augmented-Lagrangian term) where ``C`` holds the rows the QP keeps as equalities (the
       equality constraints and the inequalities active at the last step). On ``C d = const`` the added term is
       constant, so the QP step is the exact Newton–SQP step whenever ``W`` is positive definite on the null space
       of ``C`` (second-order sufficiency), while ``W`` alone may be indefinite — a wire under compression is.
       At most ``rungs`` weights are tried (default :data:`AL_WEIGHT_RUNGS`).
       ``rho`` starts at a quarter of the last value that worked (when sparse, not below the first weight
       ``1e-3 max|W_ii| / max|C^T C_ii|``), or at that first weight, and grows tenfold; ``W`` is not tested alone
       again once it needed the term. (A sparse weight kept rather than quartered ratcheted up to a million times
       the first on the guidewire's vessels at 1 600-3 200 bars, where the QP backends then failed on the
       ill-conditioned model: two 100-iteration PIQP runs and Clarabel's before the elastic QP, 2-10 s a solve.)
       Used when
       ``W`` is dense or small (up to ``dense_limit``, default :data:`DENSE_LIMIT`, variables a sparse ``W`` is
       made dense for it), and for a large sparse ``W`` when ``C`` is sparse and ``C^T C`` stays sparse (at most
       :data:`SPARSE_GRAM_DENSITY` nonzeros per variable; tested by the sparse LU below, O(n) when banded).
    3. ``W + delta I`` (an inertia correction as in IPOPT), ``delta`` from ``max(shift / 4, 1e-8 s)`` growing
       tenfold, ``s = max(1, max|W_ii|)``. (A shift along ``hess0`` instead of ``I`` was tried on the guidewire and
       needed 5-20x more iterations.)

    Dense matrices are tested by Cholesky; sparse ones by an LU factorisation without pivoting, whose pivots have the
    signs of the eigenvalues (Sylvester's law of inertia). With ``alone_first`` False (the caller expects ``W`` to be
    indefinite) a dense ``W`` without a last weight is not tested alone: ``W + r0 C^T C`` is tested first, and decides
    whether ``W`` itself is positive definite (:func:`_indefinite_first`); the answer is the same.

    A large sparse banded ``W`` with a few dense rows ``C`` (:func:`sqp.structured.candidate`: the guidewire's
    reduced program above ``dense_limit`` variables, which 2. cannot serve, or above :data:`STRUCTURED_MIN` when
    the problem has ``equality_only`` rows) is factorised once and returned as a
    :class:`sqp.structured.FactoredHessian`, even when indefinite: an equality-only subproblem is then solved as
    its KKT system with an inertia test (:func:`sqp.structured.equality_kkt`), the exact Newton step whenever ``W``
    is positive definite on the null space of its rows, and any other subproblem asks for 1.-3. first
    (:meth:`~sqp.structured.FactoredHessian.convexified`, on the dense ``W`` up to ``dense_limit``).

    Returns
    -------
    B : ndarray or sparse matrix
        The positive-definite matrix.
    delta, rho : float
        The identity shift and the augmented-Lagrangian weight used (0 when not needed).
    """
    n = W.shape[0]
    if (sp.issparse(W) and (n > dense_limit or (equality_only and n > STRUCTURED_MIN))
            and structured.candidate(W, C)):
        factor = structured.factor_symmetric(W)
        if factor is not None:
            def general() -> tuple[Any, float, float]:
                return _convexify(W.toarray() if n <= dense_limit else W, shift, C, rho, alone_first, rungs)
            return structured.FactoredHessian.wrap(W, factor, general), 0.0, 0.0
    if sp.issparse(W) and n <= dense_limit:
        W = W.toarray()
    return _convexify(W, shift, C, rho, alone_first, rungs)


def _convexify(W: Any, shift: float, C: Any, rho: float, alone_first: bool = True,
               max_rungs: int | None = None) -> tuple[Any, float, float]:
    """:func:`convexify`'s general path, 1.-3."""
    is_sparse = sp.issparse(W)
    # (a W that needed the augmented-Lagrangian term last time goes straight to it: the term leaves the step
    # unchanged, and testing W alone again costs a factorisation per iteration)
    guess = not (alone_first or is_sparse or rho > 0.0)  # (W expected indefinite: its own test skipped if it can be)
    CtC = _gram(C, is_sparse) if rho > 0.0 or guess else None  # (no product on iterations where W alone will do)
    rungs = 0  # (weights of the ladder below already known to fail)
    if guess and CtC is not None:
        first = _indefinite_first(W, C, CtC)
        if first is not None and first[0] is not None:
            return first
        if first is not None:
            rungs = 1
        else:
            CtC = None  # W alone may be positive definite: tested first, as without the guess
    if CtC is None:
        B = _accepted(_sorted(W, is_sparse), is_sparse)
        if B is not None:
            return B, 0.0, 0.0
        if rho <= 0.0:
            CtC = _gram(C, is_sparse)
    # (method calls on the diagonal views: W is n x n, n >= 1)
    scale = max(1.0, float(np.abs(W.diagonal()).max()))
    if CtC is not None:
        found = _augmented_ladder(W, CtC, rho, rungs, scale, is_sparse,
                                  AL_WEIGHT_RUNGS if max_rungs is None else max_rungs)
        if found is not None:
            return found
    return _shift_ladder(W, shift, scale, is_sparse, BandPencil.of(W) if is_sparse else None)


def augmented(W: Any, C: Any, rho: float, max_rungs: int,
              dense_limit: int = DENSE_LIMIT) -> tuple[Any, float, float] | None:
    """Path 2 of :func:`convexify` alone: ``W + r C^T C`` for the first weight of at most ``max_rungs`` (from
    ``rho / WEIGHT_DECAY`` or the first weight) that is positive definite, as ``(B, 0, r)``; None when none is (no
    identity shift is tried; a sparse ``W`` of at most ``dense_limit`` variables is made dense)."""
    if sp.issparse(W) and W.shape[0] <= dense_limit:
        W = W.toarray()
    is_sparse = sp.issparse(W)
    scale = max(1.0, float(np.abs(W.diagonal()).max()))
    return _augmented_ladder(W, _gram(C, is_sparse), rho, 0, scale, is_sparse, max_rungs)


#: The augmented-Lagrangian weight ``r`` of path 2 starts where ``r C^T C``'s diagonal is this fraction of ``W``'s
#: largest (at least 1): small enough to leave a convex ``W`` nearly unchanged on the rows' null space.
AL_WEIGHT_START = 1e-3

#: The weight and the identity shift of path 3 grow by this factor per failed Cholesky test (the ladder of Nocedal &
#: Wright, Algorithm 3.3, with their factor 10).
LADDER_GROWTH = 10.0

#: Rungs of the weight's ladder (weights up to 1e9 times the first, ``r max|C^T C_ii|`` up to 1e6 ``max|W_ii|``) before
#: the identity shift takes over. A ``W`` barely convex on the rows' null space can need a weight past that, whose
#: model then has a condition of ~1e15 on which every QP backend fails: with 12 rungs (weights to 1e11 times the
#: first) one start of the aortic arch's multi-start cold solve at 240 bars reached 1.1e12 every other iteration,
#: each such QP failed in all backends and in its elastic form (5-8 s), and the solve took 54.6 s instead of 1.9 s.
AL_WEIGHT_RUNGS = 10

#: A solve that needed a weight ``rho`` last time starts from ``rho / WEIGHT_DECAY`` on a dense ``W``, and one that
#: needed a shift from ``shift / WEIGHT_DECAY``: the Hessian drifts slowly between iterations, so a quarter of the
#: last value often passes at once, and a value no longer needed fades by that factor per iteration.
WEIGHT_DECAY = 4.0

#: The identity shift starts at this fraction of ``W``'s largest diagonal entry (at least 1) when none is carried.
SHIFT_START = 1e-8

#: Rungs of the shift's ladder (shifts up to 1e32 times the first): far past any finite Hessian's spectrum.
SHIFT_RUNGS = 40


def _augmented_ladder(W: Any, CtC: Any, rho: float, rungs: int, scale: float,
                      is_sparse: bool, max_rungs: int = AL_WEIGHT_RUNGS) -> tuple[Any, float, float] | None:
    """Path 2 of :func:`convexify`: the first weight ``r`` (from the last one, ``rho``, or :data:`AL_WEIGHT_START`)
    for which ``W + r C^T C`` passes the Cholesky test, ``rungs`` of the ``max_rungs`` of the ladder being known to
    fail; None when none does or ``C^T C`` is zero."""
    base = float(CtC.diagonal().max())  # (>= 0: a Gram matrix's diagonal)
    if base <= 0.0:
        return None
    r0 = AL_WEIGHT_START * scale / base
    r = r0 if rho <= 0.0 else max(rho / WEIGHT_DECAY, r0) if is_sparse else rho / WEIGHT_DECAY
    r *= LADDER_GROWTH**rungs  # (the same numbers as growing it tenfold: rungs is 0 or 1)
    pencil = BandPencil.of(W, CtC) if is_sparse else None
    for _ in range(max_rungs - rungs):
        # (a pivot within roundings of the weighted entries is no evidence of definiteness: with W indefinite on the
        # rows' null space no weight makes W + r C^T C positive definite, but a weight large enough passes a bare
        # Cholesky test on rounding-sized pivots, and the QP backends then fail on a model of condition ~1e17)
        floor = _pivot_floor(scale, r * base)
        if pencil is not None:  # (tested in band storage; the sparse sum formed for the weight that passes)
            if pencil.positive_definite(r, 0.0, floor):
                return _sorted(_plus_scaled(W, r, CtC, True), True), 0.0, r
        else:
            B = _accepted(_sorted(_plus_scaled(W, r, CtC, is_sparse), is_sparse), is_sparse, floor)
            if B is not None:
                return B, 0.0, r
        r *= LADDER_GROWTH
    return None


#: A shifted ``W + delta I`` is accepted only with every Cholesky pivot ``L_ii^2`` above this many roundings of its
#: entries, ``eps (max|W_ii| + delta)`` (a singular ``B`` would pass the bare test on a rounding-sized pivot and give
#: a step of 1e12 along its null vector).
SHIFT_PIVOT_ROUNDINGS = 100.0


def _shift_ladder(W: Any, shift: float, scale: float, is_sparse: bool, pencil: BandPencil | None = None,
                  r: float = 0.0, CtC: Any = None) -> tuple[Any, float, float]:
    """Path 3 of :func:`convexify`: ``W + delta I`` for the first ``delta`` (from the last one, ``shift``, or
    :data:`SHIFT_START`) that passes the Cholesky test (the last one tried when none does). With a ``pencil``
    (:class:`sqp.pencil.BandPencil` of ``W`` and ``CtC``) the matrix shifted is ``W + r CtC``, tested in band
    storage and formed once."""
    delta = max(shift / WEIGHT_DECAY, SHIFT_START * scale)
    for _ in range(SHIFT_RUNGS):
        if pencil is not None:
            if pencil.positive_definite(r, delta, _pivot_floor(scale, delta)):
                return _formed(W, r, CtC, delta, True), delta, 0.0
        else:
            accepted = _accepted(_formed(W, r, CtC, delta, is_sparse), is_sparse, _pivot_floor(scale, delta))
            if accepted is not None:
                return accepted, delta, 0.0
        delta *= LADDER_GROWTH
    delta /= LADDER_GROWTH
    return _formed(W, r, CtC, delta, is_sparse), delta, 0.0


def _pivot_floor(scale: float, delta: float) -> float:
    """The smallest Cholesky pivot ``L_ii^2`` the ladders accept in ``W`` plus a term whose largest diagonal entry is
    ``delta`` (a shift, or ``r max|C^T C_ii|``): :data:`SHIFT_PIVOT_ROUNDINGS` roundings of the entries."""
    # (W_ii + delta is exact to eps (|W_ii| + delta): a smaller pivot may be a zero eigenvalue, which a delta
    # of a power of ten times max|W_ii| meets exactly where W's most negative eigenvalue is -max|W_ii|)
    return SHIFT_PIVOT_ROUNDINGS * np.finfo(float).eps * (scale + delta)


def _formed(W: Any, r: float, CtC: Any, delta: float, is_sparse: bool) -> Any:
    """``W + r CtC + delta I`` (``r CtC`` left out when ``r`` is 0 or there is no ``CtC``), sorted CSC when
    sparse."""
    base = _plus_scaled(W, r, CtC, is_sparse) if (r != 0.0 and CtC is not None) else W
    eye = sp.identity(W.shape[0], format="csc") if is_sparse else np.eye(W.shape[0])
    return _sorted(base + delta * eye, is_sparse)


#: The augmented-Lagrangian weight under an identity shift (:func:`shifted_augmented`) starts at this many times the
#: augmented ladder's first weight: large enough that the shift need only cover the rows' null space, small enough
#: to leave the matrix's conditioning to the shift (on the guidewire's 3-D program 1e3 took an arch step from 32
#: iterations to 7).
SHIFTED_WEIGHT = 1e3

#: Weights past :data:`SHIFTED_WEIGHT` (each :data:`LADDER_GROWTH` times the last) that :func:`shifted_augmented`
#: tries for a smaller shift.
SHIFTED_WEIGHT_RUNGS = 6

#: Under a larger weight :func:`shifted_augmented` lowers the shift no further than this fraction of the matrix's
#: largest diagonal entry, ``max|W_ii| + r max|C^T C_ii|``: a smaller one passes the Cholesky test but leaves a model
#: whose condition exceeds ~1e9, on which the QP backends ran out of iterations (the guidewire's S-bend at 1 600
#: bars: weight 3.7e5, shift 2.5e-7 of ``max|W_ii|``, PIQP and Clarabel failing on most QPs that followed).
SHIFT_CONDITION = 1e-9


def shifted_augmented(W: Any, C: Any, shift: float) -> tuple[Any, float, float]:
    """``W + r C^T C + delta I`` for a ``W`` that is not positive definite on the null space of ``C`` (where
    :func:`convexify` would shift ``W`` alone, by as much as ``W``'s most negative curvature across the rows).
    Returns ``(B, delta, r)``.

    ``r`` starts at :data:`SHIFTED_WEIGHT` times the augmented ladder's first weight, with the first ``delta`` of
    the shift ladder (from the last one, ``shift``) that passes the Cholesky test; then it grows tenfold,
    :data:`SHIFTED_WEIGHT_RUNGS` times, and at each weight the shift falls tenfold while the test still passes
    (down to the ladder's first rung, and to :data:`SHIFT_CONDITION` of the matrix's diagonal): ``W + r C^T C``'s
    lowest eigenvalue rises with ``r`` towards that of ``W``
    on the null space of ``C``, the reduced Hessian, which is all the shift must cover. A shift kept larger than
    that is what makes a saddle slow to leave: the step along a direction of negative curvature ``-lambda`` is
    ``|g| / (delta - lambda)``, so with ``delta`` the size of ``W``'s curvature across the rows (a J-tip about to
    roll over in a curved tube, pressed against the wall: ``lambda`` of 0.1 on the rows' null space, 30 across them
    at the first weight) the iterates crept 1e-5 a step for hundreds of iterations, where a shift near ``lambda``
    leaves the saddle in tens."""
    is_sparse = sp.issparse(W)
    CtC = _gram(C, is_sparse)
    scale = max(1.0, float(np.abs(W.diagonal()).max()))
    base = float(CtC.diagonal().max()) if CtC is not None else 0.0
    if base <= 0.0:  # (or C^T C would not stay sparse: W alone is shifted)
        return _shift_ladder(W, shift, scale, is_sparse, BandPencil.of(W) if is_sparse else None)
    r = SHIFTED_WEIGHT * AL_WEIGHT_START * scale / base
    pencil = BandPencil.of(W, CtC) if is_sparse else None
    B, delta, _ = _shift_ladder(W, shift, scale, is_sparse, pencil, r, CtC)
    weight, formed = r, True
    for _ in range(SHIFTED_WEIGHT_RUNGS):
        r *= LADDER_GROWTH
        # (one test a weight while a tenth of the shift still fails; where it passes, tenfold smaller shifts while
        # they pass too: the lowest eigenvalue rises with the weight; with a pencil the matrix is formed at the end)
        while delta / LADDER_GROWTH >= max(SHIFT_START * scale, SHIFT_CONDITION * (scale + r * base)):
            smaller = delta / LADDER_GROWTH
            if pencil is not None:
                if not pencil.positive_definite(r, smaller, _pivot_floor(scale, smaller)):
                    break
                formed = False
            else:
                accepted = _accepted(_formed(W, r, CtC, smaller, is_sparse), is_sparse, _pivot_floor(scale, smaller))
                if accepted is None:
                    break
                B = accepted
            delta, weight = smaller, r
    return (B if formed else _formed(W, weight, CtC, delta, True)), delta, weight


#: A test of :func:`_indefinite_first` within this relative distance of its threshold is left to the Cholesky test
#: of ``W`` alone, which decides it in floating point.
DECISION_RTOL = 1e-8


def _indefinite_first(W: Array, C: Any, CtC: Array) -> tuple[Any, float, float] | tuple[None, float, float] | None:
    """The first two tests of :func:`convexify`'s path 2 for a dense ``W`` without a last weight, ``W`` alone and then
    ``W + r0 C^T C``, made in the other order: one factorisation instead of two when ``W`` is indefinite.

    ``B = W + r0 C^T C = L L^T`` decides ``W`` too: by Haynsworth's inertia formula on
    ``[[B, C^T], [C, I / r0]]``, ``In(W) = In(B) + In(I / r0 - C B^{-1} C^T) - In(I / r0)``, so ``W = B - r0 C^T C``
    is positive definite exactly when ``lambda_max(C B^{-1} C^T) < 1 / r0`` (an ``m x m`` matrix). And when ``B`` is
    not positive definite neither is ``W`` (``C^T C`` is positive semidefinite).

    Returns
    -------
    (B, 0, r0)
        ``W`` is indefinite and ``B`` (a :class:`CholeskyHessian`) is accepted: the answer of path 2.
    (None, 0, r0)
        ``B`` is not positive definite (nor ``W``): path 2 goes on at ``10 r0``.
    None
        ``W`` alone is, or is within :data:`DECISION_RTOL` of being, positive definite, or ``C^T C`` is zero: its
        own test decides, as without this shortcut.
    """
    base = float(CtC.diagonal().max())
    if base <= 0.0:
        return None
    r = AL_WEIGHT_START * max(1.0, float(np.abs(W.diagonal()).max())) / base
    B = _accepted(_plus_scaled(W, r, CtC, False), False)
    if B is None:
        return None, 0.0, r
    C = C.toarray() if sp.issparse(C) else np.asarray(C)
    L = B.cholesky
    X, info = (lapack.dpotrs(L, C.T, lower=1) if L.flags.f_contiguous  # (read in place, as range_space_kkt does)
               else lapack.dpotrs(L.T, C.T, lower=0))
    if info != 0:
        return None
    M = C @ X
    top = float(np.linalg.eigvalsh(0.5 * (M + M.T))[-1]) if M.shape[0] > 2 else _largest_eigenvalue(M)
    if not top * r > 1.0 + DECISION_RTOL:
        return None
    return B, 0.0, r


def _largest_eigenvalue(M: Array) -> float:
    """The largest eigenvalue of the symmetric part of a 1 x 1 or 2 x 2 ``M``, in closed form (numpy's ``eigvalsh``
    costs 5-25 us on one this small)."""
    if M.shape[0] == 1:
        return float(M[0, 0])
    a, c, b = float(M[0, 0]), float(M[1, 1]), 0.5 * (float(M[0, 1]) + float(M[1, 0]))
    return 0.5 * (a + c) + math.hypot(0.5 * (a - c), b)


def _gram(C: Any, is_sparse: bool) -> Any:
    """``C^T C`` for the augmented-Lagrangian term: dense for a dense ``W``; sparse CSC for a sparse ``W`` and a
    sparse ``C`` whose product stays sparse; otherwise None (no term)."""
    if C is None or not C.shape[0]:
        return None
    if not is_sparse:
        C = C.toarray() if sp.issparse(C) else np.asarray(C)
        return C.T @ C
    if not sp.issparse(C):
        return None
    CtC = as_csc(C.T @ C)
    if CtC.nnz > SPARSE_GRAM_DENSITY * CtC.shape[0]:
        return None
    # (the product's row indices come unsorted: sorted once here, the band placement of sqp.pencil and every
    # W + r C^T C of the ladders take the canonical paths instead of sorting a copy each; the same entries)
    if not CtC.has_sorted_indices:
        CtC.sort_indices()
    return CtC


def _plus_scaled(W: Any, r: float, CtC: Any, is_sparse: bool) -> Any:
    """``W + r * CtC``, dense in one new array (the sum taken in place of the product, the same numbers)."""
    if is_sparse:
        return W + r * CtC
    out = r * CtC
    out += W
    return out


def _sorted(B: Any, is_sparse: bool) -> Any:
    """``B`` as CSC with sorted row indices when sparse (a sum of sparse matrices need not have them, and PIQP
    rejects unsorted ones; the factorisation of :func:`_positive_definite` must not be relied on to sort them)."""
    if not is_sparse:
        return B
    B = as_csc(B)
    if not B.has_sorted_indices:
        B.sort_indices()
    return B


def _accepted(B: Any, is_sparse: bool, floor: float = 0.0) -> Any | None:
    """``B`` when it is positive definite with every pivot of its factorisation above ``floor`` (``L_ii^2``, or
    ``U_ii``), else None: a dense ``B`` as a :class:`CholeskyHessian` carrying the factor its Cholesky test computed
    (the equality-only QP reuses it), a sparse one as it is (tested by :func:`_positive_definite`)."""
    if is_sparse:
        return B if _positive_definite(B, floor) else None
    # (LAPACK's dpotrf through scipy: 1.4-2.6x faster than np.linalg.cholesky at n = 25-300, the same factor to
    # rounding; OpenBLAS's potrf lets a NaN pivot through, and any non-finite entry of L reaches its diagonal)
    L, info = lapack.dpotrf(B, lower=1, clean=1)
    pivots = L.diagonal()
    if info != 0 or not np.isfinite(pivots).all() or not np.all(pivots * pivots > floor):
        return None
    return CholeskyHessian.wrap(B, L)


def _positive_definite(B: Any, floor: float = 0.0) -> bool:
    """Whether the sparse symmetric ``B`` is positive definite: its banded Cholesky factorisation succeeds (a band
    up to :data:`sqp.pencil.BANDED_CHOLESKY_MAX`), else the pivots of its LU factorisation without pivoting are all
    positive (Sylvester's law of inertia); every pivot (``L_ii^2`` or ``U_ii``) above ``floor`` too."""
    ab = lower_band(B)
    if ab is not None:
        return band_positive_definite(ab, floor)
    B = as_csc(B)
    if not B.has_canonical_format:  # (every entry once)
        B = B.copy()
        B.sum_duplicates()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            lu = spla.splu(B, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError:  # exactly singular
        return False
    return bool(np.all(lu.perm_r == np.arange(B.shape[0])) and np.all(lu.U.diagonal() > max(floor, 0.0)))


class CholeskyHessian(np.ndarray):
    """A dense positive-definite model Hessian ``B`` carrying its Cholesky factor ``L`` (``B = L L^T``, lower), as
    :func:`convexify` computed it to test ``B``: the dense analogue of :class:`sqp.structured.FactoredHessian`.

    As an array it is ``B`` itself. The factor is a cache of this exact matrix, so nothing derived from it keeps it:
    arithmetic gives plain arrays, and views and copies carry ``cholesky = None``.
    """

    cholesky: Array | None = None

    @classmethod
    def wrap(cls, B: Array, L: Array) -> CholeskyHessian:
        """``B`` (a view, no copy) carrying its lower Cholesky factor ``L``."""
        out = np.asarray(B).view(cls)
        out.cholesky = L
        return out

    def __array_finalize__(self, obj: Any) -> None:
        self.cholesky = None

    def __array_wrap__(self, array: Any, context: Any = None, return_scalar: bool = False) -> Any:
        out = np.asarray(array).view(np.ndarray)
        return out[()] if return_scalar else out

    def __reduce__(self) -> tuple[Any, ...]:
        return (np.array, (np.asarray(self).view(np.ndarray),))
