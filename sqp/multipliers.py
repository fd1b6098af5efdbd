"""Multiplier estimates around the QP: the rows an exact Hessian is convexified on, the Newton multipliers recovered
from an augmented-Lagrangian QP, the Lagrangian gradient of the BFGS update and the test that the multipliers load
only active rows.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from sqp.compressed import as_csr
from sqp.iterate import Derivatives, State
from sqp.kkt import inf_norm
from sqp.problem import Problem
from sqp.subproblem import QPStep

Array = NDArray[np.float64]


def al_rows(problem: Problem, lam: Array) -> Array:
    """Nonlinear rows the QP keeps as equalities: the equalities and the inequalities with a nonzero multiplier."""
    rows = problem.nonlinear
    if rows.eq.size == rows.lb.size:  # (every row an equality: all of them, in order)
        return rows.eq
    # (np.union1d(eq, np.flatnonzero(lam)) without its sort: the same sorted indices from one mask)
    return np.flatnonzero(rows.is_eq | (lam != 0))


#: A row counts as held by the QP's step (:func:`held_rows`) when its linearisation ``c + J d`` is at its bound to
#: this relative tolerance: an active-set QP solver meets its active rows to rounding, an interior-point one to its
#: own tolerance (PIQP: ~1e-10 on the guidewire), while its inactive rows keep gaps of the problem's scale (there
#: 1e-2 mm and more).
HELD_TOL = 1e-6


def held_rows(problem: Problem, st: State, qp: QPStep) -> Array:
    """Nonlinear rows the QP's step holds as equalities: the equalities, and the inequalities with a nonzero
    multiplier whose linearisation ``c + J d`` sits at the bound that multiplier loads (to :data:`HELD_TOL`).

    An interior-point QP solver (PIQP, Clarabel) leaves tiny nonzero multipliers (~1e-11) on every inactive row:
    ``lam != 0`` alone would put all of them in the next augmented-Lagrangian term, which then biases every step
    (the guidewire's vessel at 800 bars in the full space: 1 600 rows instead of the one in contact, 1 000
    iterations instead of 4). For an active-set solver the two tests agree."""
    rows = problem.nonlinear
    if rows.eq.size == rows.lb.size:
        return rows.eq
    lam = qp.lam_nl
    lin = st.pt.c + np.asarray(st.der.J @ qp.d).ravel()
    with np.errstate(invalid="ignore"):
        at_lb = np.abs(lin - rows.lb) <= HELD_TOL * np.maximum(1.0, np.abs(rows.lb))
        at_ub = np.abs(rows.ub - lin) <= HELD_TOL * np.maximum(1.0, np.abs(rows.ub))
    return np.flatnonzero(rows.is_eq | ((lam > 0) & at_lb) | ((lam < 0) & at_ub))


def equality_rows(problem: Problem, J: Any, rows: Array) -> Any:
    """The rows ``C`` of the augmented-Lagrangian convexification of an exact Hessian: the nonlinear ``rows``
    (:func:`al_rows`) and the linear equalities."""
    parts = [J[rows]] if rows.size else []
    if problem.linear.eq.size:
        parts.append(problem.A[problem.linear.eq])
    if not parts:
        return None
    if len(parts) == 1 and (not sp.issparse(parts[0]) or type(parts[0]) is sp.csr_matrix):
        return as_csr(parts[0]) if sp.issparse(parts[0]) else parts[0]  # (J[rows] and A[eq] are copies already)
    if any(sp.issparse(p) for p in parts):
        return sp.vstack(parts, format="csr")
    return np.vstack(parts)


def _rows_times(M: Any, rows: NDArray[np.intp], d: Array) -> Array:
    """``M[rows] @ d`` (1-D). Of a CSR matrix, the rows of ``M @ d``: each row's sum runs over its stored entries in
    the same order either way (the same numbers), without building the submatrix."""
    if type(M) is sp.csr_matrix:
        return np.asarray(M @ d).ravel()[rows]
    return np.asarray(M[rows] @ d).ravel()


def newton_multipliers(problem: Problem, st: State, qp: QPStep, rows: Array, weight: float,
                       held: Array) -> QPStep:
    """The QP's multipliers with the augmented-Lagrangian term of :func:`~sqp.hessian.convexify` moved back into them.

    With ``B = W + weight C^T C`` the QP's stationarity ``B d + g - J^T lam - A^T lam_lin - z = 0`` is
    ``W d + g - J^T lam' - A^T lam_lin' - z = 0`` for ``lam' = lam - weight (C d)`` on the rows of ``C``: the step is
    Newton's and so are these multipliers, whereas ``lam`` itself is off by ``weight`` times the residual of those
    rows. (Near a solution the corrected ones are exact to second order, so the KKT test can use them at the new
    point.)

    Only the rows of ``C`` the QP held (``held``, :func:`held_rows`) are corrected. An inequality of ``C`` that the
    QP released keeps its own (zero) multiplier: its ``-weight (C d)`` is no contact force, and carrying it would keep
    the row in the next ``C`` for ever, its term then holding the iterates near a wall they are leaving (an
    insertion step warm-started with the last step's multipliers crawled over ~100 iterations at a linear rate so)."""
    lam_nl = qp.lam_nl.copy()
    if rows.size:
        kept = np.intersect1d(rows, held, assume_unique=True)
        lam_nl[kept] -= weight * _rows_times(st.der.J, kept, qp.d)
    lam_lin = qp.lam_lin.copy()
    eq = problem.linear.eq
    if eq.size:
        lam_lin[eq] -= weight * _rows_times(problem.A, eq, qp.d)
    # (the constructor, not dataclasses.replace: a third of its cost)
    return QPStep(d=qp.d, lam_nl=lam_nl, lam_lin=lam_lin, z=qp.z, found=qp.found, elastic=qp.elastic, slack=qp.slack,
                  status=qp.status, v_lin=qp.v_lin)


def nonlinear_lagrangian_gradient(problem: Problem, der: Derivatives, qp: QPStep) -> Array:
    """Only the nonlinear rows matter for ``y``: linear rows and bounds have constant gradients."""
    lam = qp.lam_nl
    # (lagrangian_gradient without the linear rows and bounds: g - J^T lam)
    return np.asarray(der.g - der.J.T @ lam).ravel() if lam.size else der.g.copy()


def loaded_rows_active(problem: Problem, st: State, tol: float) -> bool:
    """Whether every inequality row and bound with a nonzero multiplier in ``st.qp`` is active at ``st.pt`` to within
    the feasibility tolerance (so a solution reported with the last QP's multipliers has a contact force only where
    there is contact, as the next QP's would)."""
    qp = st.qp
    assert qp is not None
    x = st.pt.x
    limit = tol * max(1.0, inf_norm(x))
    with np.errstate(invalid="ignore"):
        for rows, values, lam in ((problem.nonlinear, st.pt.c, qp.lam_nl), (problem.linear, st.pt.r, qp.lam_lin),
                                  (problem.bound_rows if problem.has_bounds else None, x, qp.z)):
            if rows is None or lam.size == 0:
                continue
            gap = np.where(lam > 0, values - rows.lb, np.where(lam < 0, rows.ub - values, 0.0))
            if not (np.abs(gap) <= limit).all():  # (NaN fails too)
                return False
    return True
