"""A pytest plugin that runs scipy's own SLSQP tests on this engine: each test module's ``minimize`` sends
``method="SLSQP"`` to :func:`sqp.minimize` (other methods to scipy) and its ``fmin_slsqp`` is :func:`sqp.fmin_slsqp`.
Every call routed to the engine is counted in the file named by ``SQP_SUITE_CALLS`` (one line per call), so that the
test driving it can tell that the engine, not scipy's SLSQP, answered."""

from __future__ import annotations

import os
from typing import Any

import scipy.optimize

import sqp

_scipy_minimize = scipy.optimize.minimize


def _count() -> None:
    path = os.environ.get("SQP_SUITE_CALLS")
    if path:
        with open(path, "a") as out:
            out.write("call\n")


def minimize(fun: Any, x0: Any, args: Any = (), method: Any = None, jac: Any = None, hess: Any = None,
             hessp: Any = None, bounds: Any = None, constraints: Any = (), tol: Any = None, callback: Any = None,
             options: Any = None) -> Any:
    if isinstance(method, str) and method.lower() == "slsqp":
        _count()
        return sqp.minimize(fun, x0, args, method, jac, hess, hessp, bounds, constraints, tol, callback, options)
    return _scipy_minimize(fun, x0, args, method, jac, hess, hessp, bounds, constraints, tol, callback, options)


def fmin_slsqp(*args: Any, **kwargs: Any) -> Any:
    _count()
    return sqp.fmin_slsqp(*args, **kwargs)


def pytest_runtest_setup(item: Any) -> None:
    module = item.module
    if hasattr(module, "minimize"):
        module.minimize = minimize
    if hasattr(module, "fmin_slsqp"):
        module.fmin_slsqp = fmin_slsqp
