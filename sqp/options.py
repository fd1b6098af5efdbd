"""Solver options, validated once before any work."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from sqp.subproblem import DEFAULT_QP_OPTIONS, check_solver_name, installed_solvers


@dataclass(frozen=True)
class Options:
    """Settings of one solve.

    Attributes
    ----------
    tol : float
        Tolerance on the scaled KKT residuals (stationarity, complementarity) and on the absolute constraint
        violation.
    max_iter : int
        Maximum number of SQP iterations.
    qp_solver : str
        qpsolvers backend for the subproblems. Default "daqp" (dense active set): on the Hock–Schittkowski
        subproblems it was both the most accurate and the fastest installed backend (benchmarks/results).
    qp_options : dict
        Backend settings, merged over :data:`sqp.subproblem.DEFAULT_QP_OPTIONS`.
    callback : callable or None
        ``callback(intermediate_result)`` after every iteration; raising ``StopIteration`` ends the solve.
    verbose : bool
        Print the iteration table.
    second_order_correction : bool
        Try a second-order correction when the full step is rejected (the Maratos-effect remedy).
    qp_fallbacks : tuple of str
        Backends asked, in order, when ``qp_solver`` fails a subproblem even after its retries (skipped when not
        installed). The iteration table marks such a step ``opt[name]``. ``()`` disables the fallback.
    """

    tol: float = 1e-8
    max_iter: int = 500
    qp_solver: str = "daqp"
    qp_options: dict[str, Any] = field(default_factory=dict)
    callback: Callable[[Any], Any] | None = None
    verbose: bool = False
    second_order_correction: bool = True
    qp_fallbacks: tuple[str, ...] = ("quadprog", "osqp")

    def __post_init__(self) -> None:
        if not isinstance(self.tol, int | float) or not self.tol > 0:
            raise ValueError(f"tol = {self.tol!r}; expected a positive number such as 1e-8.")
        if isinstance(self.max_iter, bool) or not isinstance(self.max_iter, int) or self.max_iter < 0:
            raise ValueError(f"max_iter = {self.max_iter!r}; expected a nonnegative integer.")
        if not isinstance(self.qp_solver, str):
            raise TypeError(f"qp_solver must be a backend name (str); got {type(self.qp_solver).__name__}.")
        check_solver_name(self.qp_solver)
        if not isinstance(self.qp_options, dict):
            raise TypeError(f"qp_options must be a dict of backend settings; got {type(self.qp_options).__name__}.")
        if self.callback is not None and not callable(self.callback):
            raise TypeError("callback must be callable: callback(intermediate_result).")

    @property
    def backend_options(self) -> dict[str, Any]:
        """Backend settings actually passed to qpsolvers."""
        return {**DEFAULT_QP_OPTIONS.get(self.qp_solver, {}), **self.qp_options}

    @property
    def backends(self) -> list[tuple[str, dict[str, Any]]]:
        """The chosen backend with its settings, then the installed fallbacks with theirs."""
        out = [(self.qp_solver, self.backend_options)]
        for name in self.qp_fallbacks:
            if name != self.qp_solver and name in installed_solvers():
                out.append((name, dict(DEFAULT_QP_OPTIONS.get(name, {}))))
        return out
