"""Finite-difference derivatives as scipy's SLSQP takes them, with evaluation points inside the variable bounds.

The differences are scipy's own (``scipy.optimize._numdiff.approx_derivative``, the routine SLSQP calls), with
SLSQP's choice of step: ``jac=None`` is a forward difference with the absolute step ``eps`` (option ``eps``, default
``sqrt(machine epsilon)``); ``jac='2-point'``, ``'3-point'`` or ``'cs'`` is that scheme with the relative step
``finite_diff_rel_step`` (None: scipy's automatic choice). A constraint without a ``jac`` is differenced the same way.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize._numdiff import approx_derivative

Array = NDArray[np.float64]

#: SLSQP's default absolute finite-difference step (its option ``eps``): the square root of machine epsilon.
SLSQP_EPS = float(np.sqrt(np.finfo(float).eps))

#: The finite-difference schemes a string ``jac`` may name (scipy's ``FD_METHODS``).
FD_METHODS = ("2-point", "3-point", "cs")


@dataclass(frozen=True)
class FiniteDifferences:
    """How missing derivatives are approximated.

    Attributes
    ----------
    method : {"2-point", "3-point", "cs"}
        The scheme (``"2-point"`` for ``jac=None``).
    rel_step : float, array_like or None
        Relative step (``finite_diff_rel_step``); used when ``abs_step`` is None.
    abs_step : float or None
        Absolute step (SLSQP's ``eps`` when ``jac=None``).
    workers : int, map-like callable or None
        Passed to ``approx_derivative`` (evaluations in parallel), as SLSQP's ``workers`` option.
    """

    method: str = "2-point"
    rel_step: Any = None
    abs_step: float | None = SLSQP_EPS
    workers: Any = None

    @classmethod
    def for_jac(cls, jac: Any, eps: float = SLSQP_EPS, rel_step: Any = None, workers: Any = None) -> FiniteDifferences:
        """SLSQP's rule: a named scheme uses the relative step, anything else forward differences with ``eps``."""
        if isinstance(jac, str) and jac in FD_METHODS:
            return cls(method=jac, rel_step=rel_step, abs_step=None, workers=workers)
        return cls(method="2-point", rel_step=None, abs_step=eps, workers=workers)

    def jacobian(self, fun: Callable[[Array], Any], x: Array, lower: Array, upper: Array, f0: Any = None) -> Array:
        """Jacobian ``(m, n)`` of ``fun`` at ``x`` (``m = 1`` for a scalar function); no evaluation point leaves
        ``[lower, upper]``."""
        x = np.clip(np.asarray(x, dtype=float), lower, upper)
        J = approx_derivative(fun, x, method=self.method, rel_step=self.rel_step, abs_step=self.abs_step,
                              f0=f0, bounds=(lower, upper), workers=self.workers)
        return np.atleast_2d(np.asarray(J, dtype=float)).reshape(-1, x.size)
