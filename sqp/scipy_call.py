"""scipy's calling convention for SLSQP, read into the engine's settings.

``scipy.optimize.minimize(fun, x0, args, method="SLSQP", jac, hess, hessp, bounds, constraints, tol, callback,
options)`` is accepted unchanged by :func:`sqp.minimize`; this module maps what scipy's SLSQP reads from it: the
``options`` dict (``maxiter``, ``ftol``, ``disp``, ``iprint``, ``eps``, ``finite_diff_rel_step``, ``workers``; any
other key warns with ``OptimizeWarning`` as scipy does), ``tol``, the callback's two signatures and the summary
``disp`` prints.
"""

from __future__ import annotations

import inspect
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import OptimizeResult, OptimizeWarning

from sqp.derivatives import SLSQP_EPS, FiniteDifferences

#: The ``options`` keys scipy's SLSQP reads (``scipy.optimize._slsqp_py._minimize_slsqp``).
SLSQP_OPTIONS = ("maxiter", "ftol", "iprint", "disp", "eps", "finite_diff_rel_step", "workers")

#: The KKT tolerance when neither ``tol`` nor ``options["ftol"]`` is given and the gradient is the user's. Stricter
#: than SLSQP's ``ftol = 1e-6``, which bounds the change of ``f`` and the sum of the violations rather than scaled
#: KKT residuals.
DEFAULT_TOL = 1e-8

#: The same with a finite-difference gradient: SLSQP's own default ``ftol``. A forward difference with SLSQP's step
#: ``sqrt(machine epsilon) = 1.5e-8`` has an error of that order, so 1e-8 would be out of its reach.
DEFAULT_TOL_DIFFERENCES = 1e-6

#: The iteration limit when neither ``max_iter`` nor ``options["maxiter"]`` is given (SLSQP's default is 100).
DEFAULT_MAX_ITER = 500

#: ``method`` values that mean this solver (compared case-insensitively; None as in scipy's automatic choice).
METHODS = ("slsqp",)


@dataclass(frozen=True)
class CallSettings:
    """What the scipy-style arguments ask of the engine.

    Attributes
    ----------
    tol : float
        KKT tolerance (``options["ftol"]``, else ``tol``, else :data:`DEFAULT_TOL` with a gradient given and
        :data:`DEFAULT_TOL_DIFFERENCES` with a finite-difference one).
    max_iter : int
        Iteration limit (``max_iter``, else ``options["maxiter"]``, else :data:`DEFAULT_MAX_ITER`).
    disp : bool
        Print SLSQP's final summary (``options["disp"]``, with ``iprint >= 1``).
    table : bool
        Print the iteration table (``verbose``, or ``disp`` with ``iprint >= 2``).
    differences : FiniteDifferences
        Finite-difference settings (``eps``, ``finite_diff_rel_step``, ``workers``).
    """

    tol: float
    max_iter: int
    disp: bool
    table: bool
    differences: FiniteDifferences


def check_method(method: Any) -> None:
    """``method`` must be None or ``"SLSQP"`` (any case); ValueError otherwise, naming scipy for the others."""
    if method is None:
        return
    if not isinstance(method, str) or method.lower() not in METHODS:
        raise ValueError(f"method={method!r}: sqp.minimize is an SLSQP replacement and takes method=None or 'SLSQP'; "
                         "for other methods call scipy.optimize.minimize.")


def read_settings(jac: Any, tol: float | None, options: dict[str, Any] | None, max_iter: int | None,
                  verbose: bool) -> CallSettings:
    """The engine's settings from scipy's ``tol`` and ``options`` and our ``max_iter``/``verbose``.

    An unknown option warns with ``OptimizeWarning`` (``"Unknown solver options: ..."``) and is ignored, as in scipy.
    ``tol`` is ``options.setdefault("ftol", tol)``, as in scipy's ``minimize``; the result is the tolerance on the
    scaled KKT residuals and on the violation. ``max_iter`` and ``options["maxiter"]`` may not both be given.
    """
    if not isinstance(options, dict | None):
        raise TypeError(f"options must be a dict such as {{'maxiter': 100, 'ftol': 1e-6}}; got "
                        f"{type(options).__name__}.")
    opts = dict(options or {})
    unknown = [k for k in opts if k not in SLSQP_OPTIONS]
    if unknown:
        warnings.warn(f"Unknown solver options: {', '.join(map(str, unknown))}", OptimizeWarning, stacklevel=3)
    if tol is not None:
        opts.setdefault("ftol", tol)
    if max_iter is not None and "maxiter" in opts:
        raise ValueError("max_iter and options['maxiter'] are the same setting; give one of them.")
    iprint = int(opts.get("iprint", 1))
    disp = bool(opts.get("disp", False)) and iprint >= 1
    eps = float(opts.get("eps", SLSQP_EPS))
    return CallSettings(
        tol=float(opts.get("ftol", DEFAULT_TOL if callable(jac) or jac is True else DEFAULT_TOL_DIFFERENCES)),
        max_iter=_as_int(max_iter if max_iter is not None else opts.get("maxiter", DEFAULT_MAX_ITER)),
        disp=disp,
        table=bool(verbose) or (disp and iprint >= 2),
        differences=FiniteDifferences.for_jac(jac, eps=eps, rel_step=opts.get("finite_diff_rel_step"),
                                              workers=opts.get("workers")),
    )


def _as_int(value: Any) -> Any:
    """An integral float (``maxiter=1e3``) as an int; anything else unchanged, for :class:`sqp.Options` to check."""
    if isinstance(value, float) and value.is_integer():
        return int(value)
    return value


def adapt_callback(callback: Callable[..., Any] | None) -> Callable[[OptimizeResult], Any] | None:
    """The user's callback as the loop calls it, ``cb(intermediate_result)``, following scipy's rule: a callback
    whose only parameter is named ``intermediate_result`` gets the ``OptimizeResult`` (by keyword), any other gets
    a copy of ``xk``."""
    if callback is None:
        return None
    if not callable(callback):
        raise TypeError("callback must be callable: callback(xk) or callback(intermediate_result).")
    try:
        params = set(inspect.signature(callback).parameters)
    except (TypeError, ValueError):  # builtins without a signature get xk
        params = set()
    if params == {"intermediate_result"}:
        return lambda res: callback(intermediate_result=res)
    return lambda res: callback(np.copy(res.x))


def print_summary(res: OptimizeResult) -> None:
    """SLSQP's final summary (``disp=True``), with our status name and where ``x0`` was clipped."""
    print(f"{res.message}    (Exit mode {int(res.status)}: {res.status_name})")
    print("            Current function value:", res.fun)
    print("            Iterations:", res.nit)
    print("            Function evaluations:", res.nfev)
    print("            Gradient evaluations:", res.njev)
    if res.x0_clipped.size:
        print(f"            x0 clipped into the bounds at indices {res.x0_clipped.tolist()}")
