"""A test problem with its known answer, in the form `sqp.minimize` and `scipy.optimize.minimize` accept."""

from __future__ import annotations

import csv
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cache
from importlib import resources
from typing import Any

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class TestProblem:
    """One nonlinear program with a starting point and its best-known optimal value.

    Attributes
    ----------
    name : str
        Collection name, e.g. ``"HS71"``.
    fun, jac : callable
        Objective ``f(x) -> float`` and its analytic gradient ``g(x) -> (n,)``.
    x0 : ndarray, shape (n,)
        The collection's starting point.
    bounds : sequence of (lo, hi) or None
        Variable bounds, ``None`` for an unbounded side; ``None`` when there are no bounds.
    constraints : tuple
        SLSQP-style dicts ``{"type": "eq"|"ineq", "fun", "jac"}`` (``ineq`` means ``fun(x) >= 0``) for nonlinear
        constraints and ``scipy.optimize.LinearConstraint`` objects for linear ones.
    fstar : float
        Best-known optimal objective value.
    xstar : ndarray or None
        A known minimiser, when published.
    """

    __test__ = False  # not a pytest class

    name: str
    fun: Callable[[NDArray[np.float64]], float]
    jac: Callable[[NDArray[np.float64]], NDArray[np.float64]]
    x0: NDArray[np.float64]
    bounds: Sequence[tuple[float | None, float | None]] | None
    constraints: tuple[Any, ...]
    fstar: float
    xstar: NDArray[np.float64] | None = None
    notes: str = field(default="")

    @property
    def n(self) -> int:
        """Number of variables."""
        return int(np.size(self.x0))

    def max_violation(self, x: NDArray[np.float64]) -> float:
        """Largest violation of any bound or constraint at ``x``, judged independently of any solver."""
        from scipy.optimize import LinearConstraint

        x = np.asarray(x, dtype=float)
        worst = 0.0
        if self.bounds is not None:
            lo = np.array([-np.inf if b[0] is None else b[0] for b in self.bounds], dtype=float)
            hi = np.array([np.inf if b[1] is None else b[1] for b in self.bounds], dtype=float)
            worst = max(worst, float(np.max(np.maximum(lo - x, 0.0), initial=0.0)))
            worst = max(worst, float(np.max(np.maximum(x - hi, 0.0), initial=0.0)))
        for con in self.constraints:
            if isinstance(con, LinearConstraint):
                ax = np.atleast_2d(con.A) @ x
                lb = np.broadcast_to(con.lb, ax.shape)
                ub = np.broadcast_to(con.ub, ax.shape)
                viol = np.maximum(np.maximum(lb - ax, ax - ub), 0.0)
            else:
                c = np.atleast_1d(np.asarray(con["fun"](x), dtype=float))
                viol = np.abs(c) if con["type"] == "eq" else np.maximum(-c, 0.0)
            worst = max(worst, float(np.max(viol, initial=0.0)))
        return worst

    def is_solved(self, x: NDArray[np.float64], f: float, maxcv: float, *, tol: float = 1e-6) -> bool:
        """The collection's strict test: ``maxcv <= tol`` and ``f - fstar <= tol * max(1, |fstar|)``."""
        return bool(maxcv <= tol and f - self.fstar <= tol * max(1.0, abs(self.fstar)))


@cache
def hs_optima() -> dict[str, float]:
    """Best-known optimal values of the Hock–Schittkowski problems, keyed by name (``"HS71"``)."""
    text = resources.files("sqp.problems").joinpath("data/hs_optima.csv").read_text()
    rows = csv.DictReader(line for line in text.splitlines() if not line.startswith("#"))
    return {row["name"]: float(row["fstar"]) for row in rows}


def hs_problem(
    name: str,
    fun: Callable[[NDArray[np.float64]], float],
    jac: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    x0: Any,
    bounds: Sequence[tuple[float | None, float | None]] | None = None,
    constraints: Sequence[Any] = (),
    xstar: Any = None,
    notes: str = "",
) -> TestProblem:
    """A Hock–Schittkowski :class:`TestProblem`, its f* looked up in the optima table."""
    return TestProblem(
        name=name, fun=fun, jac=jac, x0=np.asarray(x0, dtype=float),
        bounds=None if bounds is None else list(bounds), constraints=tuple(constraints), fstar=hs_optima()[name],
        xstar=None if xstar is None else np.asarray(xstar, dtype=float), notes=notes,
    )


def eq(fun: Callable[[NDArray[np.float64]], Any], jac: Callable[[NDArray[np.float64]], Any]) -> dict[str, Any]:
    """Nonlinear equality constraints ``fun(x) = 0`` as an SLSQP dict."""
    return {"type": "eq", "fun": fun, "jac": jac}


def ineq(fun: Callable[[NDArray[np.float64]], Any], jac: Callable[[NDArray[np.float64]], Any]) -> dict[str, Any]:
    """Nonlinear inequality constraints ``fun(x) >= 0`` as an SLSQP dict."""
    return {"type": "ineq", "fun": fun, "jac": jac}
