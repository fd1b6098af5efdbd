"""scipy's functional SLSQP interface, :func:`fmin_slsqp`, on this engine: the same arguments and returns, so that code
written against ``scipy.optimize.fmin_slsqp`` runs unchanged."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from sqp.derivatives import SLSQP_EPS
from sqp.solver import minimize


def fmin_slsqp(
    func: Callable[..., Any],
    x0: Any,
    eqcons: Sequence[Callable[..., Any]] = (),
    f_eqcons: Callable[..., Any] | None = None,
    ieqcons: Sequence[Callable[..., Any]] = (),
    f_ieqcons: Callable[..., Any] | None = None,
    bounds: Any = (),
    fprime: Callable[..., Any] | None = None,
    fprime_eqcons: Callable[..., Any] | None = None,
    fprime_ieqcons: Callable[..., Any] | None = None,
    args: tuple[Any, ...] = (),
    iter: int = 100,  # noqa: A002 (scipy's name)
    acc: float = 1.0e-6,
    iprint: int = 1,
    disp: int | None = None,
    full_output: int = 0,
    epsilon: float = SLSQP_EPS,
    callback: Callable[..., Any] | None = None,
) -> Any:
    """Minimise ``func(x, *args)`` under equality and inequality constraints and bounds: scipy's
    ``fmin_slsqp`` call, solved by :func:`sqp.minimize`.

    Parameters
    ----------
    func, x0, args
        The objective and the start, as in scipy.
    eqcons, ieqcons : sequence of callables
        Scalar constraints ``c(x, *args) == 0`` and ``c(x, *args) >= 0``, differenced.
    f_eqcons, f_ieqcons : callable, optional
        Vector constraints (``== 0``, ``>= 0``) with their Jacobians ``fprime_eqcons``/``fprime_ieqcons`` (None:
        differenced).
    bounds : sequence of (lo, hi)
        Variable bounds (``()``: none).
    fprime : callable, optional
        The gradient (None: forward differences with step ``epsilon``).
    iter, acc : int, float
        The iteration limit and the KKT tolerance (SLSQP's ``acc``).
    iprint, disp : int
        0: quiet; 1: the summary; 2: also the iteration table (``disp`` overrides ``iprint``, as in scipy).
    full_output : bool
        Return ``(x, fx, its, imode, smode)`` instead of ``x``.
    epsilon : float
        Finite-difference step.
    callback : callable, optional
        ``callback(xk)`` after each iteration.

    Returns
    -------
    x : ndarray
        The solution; with ``full_output``: ``x``, ``f(x)``, the iteration count, the status code (SLSQP's table
        where the two agree: :class:`sqp.Status`) and its message.
    """
    if disp is not None:
        iprint = disp
    cons: list[dict[str, Any]] = [{"type": "eq", "fun": c, "args": args} for c in eqcons]
    cons += [{"type": "ineq", "fun": c, "args": args} for c in ieqcons]
    if f_eqcons:
        cons.append({"type": "eq", "fun": f_eqcons, "jac": fprime_eqcons, "args": args})
    if f_ieqcons:
        cons.append({"type": "ineq", "fun": f_ieqcons, "jac": fprime_ieqcons, "args": args})
    options = {"maxiter": iter, "ftol": acc, "iprint": iprint, "disp": iprint != 0, "eps": epsilon}
    res = minimize(func, x0, args, jac=fprime, bounds=bounds if bounds is not None and len(bounds) else None,
                   constraints=cons, callback=callback, options=options)
    x = np.asarray(res.x)
    if full_output:
        return x, res.fun, res.nit, int(res.status), res.message
    return x
