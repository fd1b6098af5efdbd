"""One evaluation of the problem at one point, and the counters of how many were made."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from sqp.derivatives import forward_difference
from sqp.hessian import DENSE_LIMIT
from sqp.problem import Problem, block_jacobian

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Point:
    """Values at ``x``: objective ``f``, nonlinear rows ``c`` (stacked) and linear rows ``r = A x``."""

    x: Array
    f: float
    c: Array
    r: Array

    @property
    def finite(self) -> bool:
        return bool(np.isfinite(self.f) and np.all(np.isfinite(self.c)))


@dataclass(frozen=True)
class Derivatives:
    """Objective gradient ``g`` (n,) and nonlinear-row Jacobian ``J`` (m, n; dense or CSR) at a point."""

    g: Array
    J: Any

    @property
    def finite(self) -> bool:
        data = self.J.data if sp.issparse(self.J) else self.J
        return bool(np.all(np.isfinite(self.g)) and np.all(np.isfinite(data)))


class Evaluator:
    """Evaluates a :class:`Problem`, counting objective (``nfev``) and derivative (``njev``) evaluations.

    Finite-difference gradients count their objective evaluations in ``nfev`` (as scipy does).
    """

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        self.nfev = 0
        self.njev = 0
        self.nhev = 0

    def _f(self, x: Array) -> float:
        self.nfev += 1
        val = np.asarray(self.problem.fun(x.copy()), dtype=float)
        return float(val.reshape(-1)[0]) if val.size == 1 else float("nan")

    def point(self, x: Array) -> Point:
        """Evaluate ``f``, the nonlinear rows and the linear rows at ``x``."""
        p = self.problem
        f = self._f(x)
        if p.blocks:
            c = np.concatenate([np.atleast_1d(np.asarray(b.fun(x.copy()), dtype=float)).ravel() for b in p.blocks])
        else:
            c = np.zeros(0)
        r = p.A @ x if p.A.shape[0] else np.zeros(0)
        return Point(x=x, f=f, c=c, r=np.asarray(r, dtype=float).ravel())

    def derivatives(self, pt: Point) -> Derivatives:
        """Gradient and nonlinear Jacobian at an evaluated point."""
        p = self.problem
        x = pt.x
        self.njev += 1
        if p.grad is None:
            g = forward_difference(lambda z: np.array([self._f(z)]), x, p.lower, p.upper, f0=np.array([pt.f]))[0]
        else:
            g = np.asarray(p.grad(x.copy()), dtype=float).reshape(-1)
        if p.blocks:
            parts = [block_jacobian(b, x.copy(), p.lower, p.upper) for b in p.blocks]
            J = sp.vstack(parts, format="csr") if any(sp.issparse(m) for m in parts) else np.vstack(parts)
        else:
            J = np.zeros((0, x.size))
        return Derivatives(g=g, J=J)

    def lagrangian_hessian(self, x: Array, lam_nl: Array) -> Any:
        """``grad^2 f(x) - sum_i lam_i grad^2 c_i(x)`` from the user's Hessians (dense or sparse)."""
        p = self.problem
        assert p.hess is not None
        self.nhev += 1
        H = p.hess(x.copy())
        if sp.issparse(H) and H.shape[0] <= DENSE_LIMIT:
            H = H.toarray()  # small: dense arithmetic is cheaper than scipy.sparse's per-call overhead
        W = H.tocsc() if sp.issparse(H) else np.array(H, dtype=float)
        start = 0
        for block in p.blocks:
            v = lam_nl[start : start + block.size]
            start += block.size
            if not np.any(v):
                continue
            assert block.hess is not None
            Hc = block.hess(x.copy(), v)
            if sp.issparse(Hc) and not sp.issparse(W):
                Hc = Hc.toarray()
            W = W - (Hc if sp.issparse(Hc) else np.asarray(Hc, dtype=float))
        if sp.issparse(W):
            return sp.csc_matrix(W)
        return np.asarray(W)
