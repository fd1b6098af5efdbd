"""A generic nonlinear program (:class:`Problem`) and the conversions between scipy's constraint kinds.

A :class:`Problem` is ``fun``/``jac``/``x0`` with optional objective Hessian ``hess``, ``bounds`` and scipy-style
``constraints``: ``LinearConstraint`` objects, ``NonlinearConstraint`` objects and dicts ``{"type": "eq"|"ineq",
"fun", "jac"}`` (``ineq``: ``fun(x) ≥ 0``) with an optional ``"hess"``, scipy's convention ``hess(x, v) = Σ v_i ∇²c_i``.
The conversions between these kinds are written once here (:func:`as_dicts` for SLSQP and cyipopt,
:func:`trust_constr_constraints`), with the violation of any answer (:func:`violations`). *Exact Hessians*
(:func:`has_exact_hessians`): the objective's and every nonlinear constraint's.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.optimize import BFGS, LinearConstraint, NonlinearConstraint


@dataclass(frozen=True)
class Problem:
    """One nonlinear program as the peers take it."""

    fun: Callable[[Any], float]
    jac: Callable[[Any], Any]
    x0: np.ndarray
    constraints: Sequence[Any] = ()
    bounds: Any = None
    hess: Callable[[Any], Any] | None = None

    @property
    def n(self) -> int:
        return int(np.size(self.x0))


def dense(matrix: Any) -> np.ndarray:
    """A dense float array from an array or a scipy sparse matrix."""
    return matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix, dtype=float)


def has_exact_hessians(problem: Problem) -> bool:
    """Whether the objective and every nonlinear constraint offer their exact Hessian."""
    def exact(con: Any) -> bool:
        if isinstance(con, LinearConstraint):
            return True
        if isinstance(con, NonlinearConstraint):
            return callable(con.hess)
        return "hess" in con
    return callable(problem.hess) and all(exact(c) for c in problem.constraints)


def _rows_as_dicts(fun: Callable[[Any], Any], jac: Callable[[Any], Any], hess: Callable[[Any, Any], Any] | None,
                   lb: np.ndarray, ub: np.ndarray, n: int) -> list[dict[str, Any]]:
    """``lb ≤ fun(x) ≤ ub`` as dicts: equalities, then finite lower sides, then finite upper sides (sign −1)."""
    eq = lb == ub
    lo = ~eq & np.isfinite(lb)
    up = ~eq & np.isfinite(ub)
    out: list[dict[str, Any]] = []
    for kind, rows, sign, rhs in (("eq", eq, 1.0, lb), ("ineq", lo, 1.0, lb), ("ineq", up, -1.0, ub)):
        if not rows.any():
            continue
        d = {"type": kind, "fun": lambda x, r=rows, s=sign, b=sign * rhs[rows]: s * np.atleast_1d(fun(x))[r] - b,
             "jac": lambda x, r=rows, s=sign: s * dense(jac(x)).reshape(-1, n)[r]}
        if hess is not None:
            def rows_hess(x: Any, v: Any, r: np.ndarray = rows, s: float = sign) -> Any:
                full = np.zeros(r.size)
                full[r] = s * np.asarray(v, dtype=float)
                return hess(x, full)
            d["hess"] = rows_hess
        out.append(d)
    return out


def _linear_as_dicts(con: LinearConstraint, n: int, with_hess: bool) -> list[dict[str, Any]]:
    A = dense(con.A).reshape(-1, n)
    lb = np.broadcast_to(np.asarray(con.lb, dtype=float), (A.shape[0],))
    ub = np.broadcast_to(np.asarray(con.ub, dtype=float), (A.shape[0],))
    zero = sp.coo_array((n, n))
    out: list[dict[str, Any]] = []
    eq = lb == ub
    lo = ~eq & np.isfinite(lb)
    up = ~eq & np.isfinite(ub)
    for kind, rows, sign, rhs in (("eq", eq, 1.0, lb), ("ineq", lo, 1.0, lb), ("ineq", up, -1.0, ub)):
        if rows.any():
            Ar, br = sign * A[rows], sign * rhs[rows]
            d = {"type": kind, "fun": lambda x, Ar=Ar, br=br: Ar @ x - br, "jac": lambda x, Ar=Ar: Ar}
            if with_hess:
                d["hess"] = lambda x, v, z=zero: z
            out.append(d)
    return out


def as_dicts(problem: Problem, *, with_hess: bool = False, dense_jac: bool = True) -> list[dict[str, Any]]:
    """Every constraint as a dict (SLSQP's and cyipopt's form): linear rows and ``NonlinearConstraint`` sides split
    into equalities and ``≥ 0`` inequalities; dicts as they are (Jacobians made dense with ``dense_jac``).
    ``with_hess``: every dict has a ``"hess"`` (zero for linear rows; needs :func:`has_exact_hessians`)."""
    n = problem.n
    out: list[dict[str, Any]] = []
    for con in problem.constraints:
        if isinstance(con, LinearConstraint):
            out += _linear_as_dicts(con, n, with_hess)
        elif isinstance(con, NonlinearConstraint):
            m = np.atleast_1d(con.fun(problem.x0)).size
            lb = np.broadcast_to(np.asarray(con.lb, dtype=float), (m,))
            ub = np.broadcast_to(np.asarray(con.ub, dtype=float), (m,))
            out += _rows_as_dicts(con.fun, con.jac, con.hess if with_hess else None, lb, ub, n)
        elif dense_jac:
            d = {"type": con["type"], "fun": con["fun"], "jac": lambda x, j=con["jac"]: dense(j(x))}
            out.append({**d, "hess": con["hess"]} if with_hess else d)
        else:
            out.append(dict(con) if with_hess else {k: v for k, v in con.items() if k != "hess"})
    return out


def violations(problem: Problem, x: Any) -> np.ndarray:
    """Violation (≥ 0) of every bound and constraint row at ``x``, concatenated."""
    x = np.asarray(x, dtype=float)
    parts = [np.zeros(0)]
    if problem.bounds is not None:
        lo = np.array([-np.inf if b[0] is None else b[0] for b in problem.bounds], dtype=float)
        hi = np.array([np.inf if b[1] is None else b[1] for b in problem.bounds], dtype=float)
        parts.append(np.maximum(np.maximum(lo - x, x - hi), 0.0))
    for con in problem.constraints:
        if isinstance(con, LinearConstraint | NonlinearConstraint):
            ax = con.A @ x if isinstance(con, LinearConstraint) else np.asarray(con.fun(x), dtype=float)
            parts.append(np.maximum(np.maximum(con.lb - ax, ax - con.ub), 0.0).ravel())
        else:
            c = np.asarray(con["fun"](x), dtype=float)
            parts.append(np.abs(c) if con["type"] == "eq" else np.maximum(-c, 0.0))
    return np.concatenate(parts)


def max_violation(problem: Problem, x: Any) -> float:
    """The largest violation of any bound or constraint row at ``x`` (0 without constraints)."""
    return float(np.max(violations(problem, x), initial=0.0))


def trust_constr_constraints(problem: Problem, exact: bool, *, linear_as_dicts: bool = False) -> list[Any]:
    """Dicts as ``NonlinearConstraint`` (exact ``hess`` or scipy's BFGS), the other objects as they are;
    ``linear_as_dicts``: linear constraints too become ``NonlinearConstraint`` s (through :func:`as_dicts`)."""
    out: list[Any] = []
    for con in problem.constraints:
        if isinstance(con, LinearConstraint) and not linear_as_dicts or isinstance(con, NonlinearConstraint):
            out.append(con)
            continue
        for d in as_dicts(Problem(problem.fun, problem.jac, problem.x0, (con,)), with_hess=exact, dense_jac=False):
            ub = 0.0 if d["type"] == "eq" else np.inf
            out.append(NonlinearConstraint(d["fun"], 0.0, ub, jac=d["jac"], hess=d["hess"] if exact else BFGS()))
    return out
