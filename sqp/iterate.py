"""One evaluation of the problem at one point, and the counters of how many were made."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from sqp.compressed import as_csc
from sqp.hessian import STRUCTURED_MIN
from sqp.kkt import max_violation
from sqp.problem import NonlinearBlock, Problem, StartValues, call_user, check_jacobian_shape
from sqp.subproblem import QPStep

Array = NDArray[np.float64]

#: The values of no rows (shared: never written to).
_EMPTY = np.zeros(0)
_EMPTY.flags.writeable = False


@dataclass(frozen=True)
class Point:
    """Values at ``x``: objective ``f``, nonlinear rows ``c`` (stacked) and linear rows ``r = A x``, with what every
    step of the iteration reads from them, computed once (:meth:`Evaluator.point`): the nonlinear rows' violations
    ``v`` (:meth:`~sqp.problem.Rows.violation`), the largest violation of any row or bound ``maxcv``
    (:func:`~sqp.kkt.max_violation`) and whether ``f`` and ``c`` are ``finite``."""

    x: Array
    f: float
    c: Array
    r: Array
    v: Array
    maxcv: float
    finite: bool


@dataclass(frozen=True)
class Derivatives:
    """Objective gradient ``g`` (n,) and nonlinear-row Jacobian ``J`` (m, n; dense or CSR) at a point."""

    g: Array
    J: Any

    @property
    def finite(self) -> bool:
        data = self.J.data if sp.issparse(self.J) else self.J
        return bool(np.isfinite(self.g).all() and np.isfinite(data).all())


class Evaluator:
    """Evaluates a :class:`Problem`, counting objective (``nfev``) and derivative (``njev``) evaluations.

    Finite-difference gradients count their objective evaluations in ``nfev`` (as scipy does). Every user function
    is called through :func:`~sqp.problem.call_user`: an exception it raises propagates with a note naming the
    function and the iteration ``nit`` (set by the solver: iteration ``k`` is the work that produces the ``k``-th
    iterate, from the Hessian and QP at ``x_{k-1}`` to the derivatives at the accepted point; 0 is the start). A
    function whose output changes size or shape during the solve is a ValueError naming it.

    The first evaluation of the start (:meth:`point` and :meth:`derivatives` at ``problem.start.x``) takes the values
    the input checks computed there (:class:`~sqp.problem.StartValues`) instead of calling the user's functions
    again, and counts them as if it had called them.
    """

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        self._start = problem.start  # (dropped once the start's derivatives are taken)
        self.nfev = 0
        self.njev = 0
        self.nhev = 0
        self.nit = 0
        #: Which Hessian returned NaN or inf in the last :meth:`lagrangian_hessian` (None when all were finite).
        self.hessian_nonfinite: str | None = None

    @property
    def where(self) -> str:
        return f"iteration {self.nit}"

    def _at_start(self, x: Array) -> StartValues | None:
        """The values computed at the start when ``x`` is that point and they have not been used up, else None."""
        start = self._start
        return start if start is not None and np.array_equal(x, start.x) else None

    def _f(self, x: Array, start: StartValues | None = None) -> float:
        self.nfev += 1
        out = start.f if start is not None else call_user("fun", self.problem.fun, x, self.where)
        val = np.asarray(out, dtype=float)
        if val.size != 1:
            raise ValueError(f"fun returned an array of shape {val.shape} at {self.where}; it must return a scalar "
                             "(the objective value).")
        return float(val.reshape(-1)[0])

    def _c(self, block: NonlinearBlock, x: Array, value: Array | None = None) -> Array:
        name = block.part("fun")
        val = np.asarray(call_user(name, block.fun, x, self.where) if value is None else value, dtype=float)
        if val.ndim > 1 or val.size != block.size:
            raise ValueError(f"{name} returned {val.size} value(s) (shape {val.shape}) at {self.where}; it returned "
                             f"{block.size} at x0. A constraint function must return the same number of values at "
                             "every point (a scalar or a 1-D array).")
        return np.atleast_1d(val)

    def _f_raw(self, x: Array) -> Any:
        """The objective as a finite-difference scheme sees it (complex for ``'cs'``), counted in ``nfev``."""
        self.nfev += 1
        return np.asarray(call_user("fun", self.problem.fun, x, self.where)).reshape(-1)[0]

    def _c_raw(self, block: NonlinearBlock, x: Array) -> Any:
        """A constraint's values as a finite-difference scheme sees them (complex for ``'cs'``)."""
        return np.atleast_1d(np.asarray(call_user(block.part("fun"), block.fun, x, self.where))).ravel()

    def _jac(self, block: NonlinearBlock, x: Array, value: Any = None) -> Any:
        p = self.problem
        if value is not None:  # (the start's, checked already)
            return value
        if block.jac is None:
            J = p.differences.jacobian(lambda z: self._c_raw(block, z), x, p.lower, p.upper)
            if J.shape != (block.size, x.size):
                raise ValueError(f"{block.part('fun')} returned {J.shape[0]} value(s) at {self.where}; it returned "
                                 f"{block.size} at x0.")
            return J
        return check_jacobian_shape(block, call_user(block.part("jac"), block.jac, x, self.where), x.size,
                                    self.where)

    def point(self, x: Array) -> Point:
        """Evaluate ``f``, the nonlinear rows and the linear rows at ``x``."""
        p = self.problem
        start = self._at_start(x)
        f = self._f(x, start)
        # (the stacking copies the user's arrays: a function that reuses its output buffer cannot change a Point)
        c = np.concatenate([self._c(b, x, None if start is None else start.c[i])
                            for i, b in enumerate(p.blocks)]) if p.blocks else _EMPTY
        r = np.asarray(p.A @ x, dtype=float).ravel() if p.A.shape[0] else _EMPTY
        finite = math.isfinite(f) and bool(np.isfinite(c).all())
        v = p.nonlinear.violation(c)
        return Point(x=x, f=f, c=c, r=r, v=v, maxcv=max_violation(p, x, c, r, v), finite=finite)

    def derivatives(self, pt: Point) -> Derivatives:
        """Gradient and nonlinear Jacobian at an evaluated point."""
        p = self.problem
        x = pt.x
        self.njev += 1
        start = self._at_start(x)
        self._start = None
        if p.grad is None:
            g = p.differences.jacobian(self._f_raw, x, p.lower, p.upper, f0=pt.f)[0]
        else:
            # (the start's gradient copied: it serves a restart's evaluator too)
            g = (np.array(start.g, dtype=float) if start is not None
                 else np.asarray(call_user("jac", p.grad, x, self.where), dtype=float))
            if g.shape != (x.size,):
                raise ValueError(f"jac returned shape {g.shape} at {self.where}; expected ({x.size},): the gradient "
                                 "of fun.")
        if p.blocks:
            parts = [self._jac(b, x, None if start is None else start.J[i]) for i, b in enumerate(p.blocks)]
            if len(parts) == 1:  # (a copy, as the stacking of several: the user may reuse the array)
                J = _sparse_copy(parts[0]) if sp.issparse(parts[0]) else parts[0].copy()
            else:
                J = sp.vstack(parts, format="csr") if any(sp.issparse(m) for m in parts) else np.vstack(parts)
        else:
            J = np.zeros((0, x.size))
        return Derivatives(g=g, J=J)

    def nonfinite_source(self, pt: Point, der: Derivatives | None = None) -> str | None:
        """The first user function whose value at ``pt`` (or derivative in ``der``) is NaN or inf, as the user names
        it (``"fun"``, ``"constraints[1]['jac']"``, ...); None when every value is finite."""
        p = self.problem
        if not np.isfinite(pt.f):
            return "fun"
        start = 0
        for block in p.blocks:
            if not np.all(np.isfinite(pt.c[start : start + block.size])):
                return block.part("fun")
            start += block.size
        if der is None:
            return None
        if not np.all(np.isfinite(der.g)):
            return "jac" if p.grad is not None else "fun (in its finite-difference gradient)"
        start = 0
        for block in p.blocks:
            rows = der.J[start : start + block.size]
            if not np.all(np.isfinite(rows.data if sp.issparse(rows) else rows)):
                fd = f"{block.part('fun')} (in its finite differences)"
                return block.part("jac") if block.jac is not None else fd
            start += block.size
        return None

    def lagrangian_hessian(self, x: Array, lam_nl: Array) -> Any:
        """``grad^2 f(x) - sum_i lam_i grad^2 c_i(x)`` from the user's Hessians (dense or sparse).

        Sets :attr:`hessian_nonfinite` to the first Hessian that returned NaN or inf."""
        p = self.problem
        assert p.hess is not None
        self.nhev += 1
        n = x.size
        self.hessian_nonfinite = None
        # where the engine works densely (Problem.dense): dense up to STRUCTURED_MIN variables (cheaper than
        # scipy.sparse's per-call overhead), then dense too unless the problem is equality-only and its objective
        # Hessian sparse (the structured path); sparse CSC otherwise, whatever format each Hessian comes in
        H = self._hessian("hess", call_user("hess", p.hess, x, self.where), n)
        dense = p.dense and (n <= STRUCTURED_MIN or not (p.equality_only and sp.issparse(H)))
        W = _as_format(H, dense)
        start = 0
        for block in p.blocks:
            v = lam_nl[start : start + block.size]
            start += block.size
            if not v.any():
                continue
            assert block.hess is not None
            name = block.part("hess")
            Hc = self._hessian(name, call_user(name, block.hess, x, self.where, v), n)
            if dense:  # (in place: W is this function's own copy)
                W -= Hc.toarray() if sp.issparse(Hc) else Hc
            else:
                W = W - _as_format(Hc, dense)
        if sp.issparse(W):
            return as_csc(W)
        return np.asarray(W)

    def _hessian(self, name: str, H: Any, n: int) -> Any:
        """``H`` checked: shape ``(n, n)`` (ValueError otherwise); a non-finite entry is recorded, not raised."""
        if not sp.issparse(H):
            H = np.asarray(H, dtype=float)
        if H.shape != (n, n):
            raise ValueError(f"{name} returned shape {H.shape} at {self.where}; expected ({n}, {n}).")
        data = H.data if sp.issparse(H) else H
        if self.hessian_nonfinite is None and not np.isfinite(data).all():
            self.hessian_nonfinite = name
        return H


def _sparse_copy(M: Any) -> Any:
    """A CSR copy of the sparse ``M`` (``sp.vstack([M], format="csr")``): a CSR matrix's own ``copy`` (the same
    arrays, copied) without the stacking's work."""
    return M.copy() if type(M) is sp.csr_matrix else sp.vstack([M], format="csr")


def _as_format(H: Any, dense: bool) -> Any:
    """``H`` as a float ndarray (``dense``) or a CSC matrix."""
    if dense:
        return H.toarray() if sp.issparse(H) else np.array(H, dtype=float)
    return as_csc(H, dtype=float)


@dataclass(frozen=True)
class State:
    """The handful of values carried from one iteration to the next (``B`` is None before an exact-Hessian solve's
    first model): replaced, never changed in place."""

    pt: Point
    der: Derivatives
    B: Any
    mu: Array
    qp: QPStep | None = None
