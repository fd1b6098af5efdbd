"""The rounding noise of a function along a line, estimated from its values on a small equally spaced stencil.

A value that sums large terms which cancel (HS268's constant 14463 with ``f* = 0``; a user's energy written as a
difference of large numbers) is known only to a noise level ``eps_f`` far above the rounding unit times ``|f|``.
Near a solution the decrease a step can make falls below ``eps_f``, and an Armijo test on such values accepts or
rejects steps by luck. The line search (:mod:`sqp.linesearch`) asks this module for ``eps_f`` once plain
backtracking has failed, and then relaxes its test by ``2 eps_f`` (Berahas, Byrd & Nocedal, SIAM J. Optim. 29, 2019).

The estimate is Moré & Wild's ECnoise (SIAM J. Sci. Comput. 33, 2011): the ``k``-th differences of values on an
equally spaced stencil cancel the smooth part of the function to order ``h^k`` while the noise survives in them with
variance ``(2k)!/(k!)^2 sigma^2``, so ``sigma_k = sqrt(gamma_k mean(Delta^k f)^2)`` with ``gamma_k = (k!)^2/(2k)!``
estimates ``sigma`` for every ``k``; an order is trusted when its differences change sign (noise, not the smooth
part, dominates them) and three consecutive orders agree within a factor :data:`AGREEMENT`.
"""

from __future__ import annotations

from collections.abc import Callable
from math import factorial

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

#: Stencil intervals (``m + 1`` values; Moré & Wild's ECnoise: 6 to 8): each estimate costs that many evaluations.
STENCIL_INTERVALS = 6

#: Highest difference order used; three consecutive orders from 1 up to this are compared.
MAX_ORDER = 6

#: Consecutive orders ``k, k+1, k+2`` whose estimates agree within this factor are trusted (Moré & Wild: 4).
AGREEMENT = 4.0

#: A bound on the noise of one value, in standard deviations: ``eps_f = NOISE_BOUND * sigma`` (three deviations
#: cover 99.7 % of Gaussian noise and all of the uniform noise of rounding, whose bound is ``sqrt(3) sigma``).
NOISE_BOUND = 3.0

#: Stencil spans tried, as fractions of the step: when the smooth part still dominates the differences over the
#: whole step, the stencil shrinks by a factor 100 (Moré & Wild's "h too large" remedy), twice at most.
SPANS = (1.0, 1e-2, 1e-4)


def stencil_noise(values: Array, change: Array | float = 0.0) -> Array:
    """The noise's standard deviation of each column of ``values`` (rows: an equally spaced stencil), NaN where the
    smooth part dominates every difference order (the stencil is too wide for that column).

    Where fewer than half a column's values are distinct, the function changes by less than its resolution across
    the stencil: its noise is then at least the largest difference seen (a rounding step) and at least ``change``
    (per column), the change across the stencil that its linear model predicts and the values did not show; the
    larger is returned divided by :data:`NOISE_BOUND`, so that the bound (:func:`noise_along`) is that value.
    """
    f = np.asarray(values, dtype=float)
    if f.ndim == 1:
        f = f[:, None]
    m = f.shape[0] - 1
    orders = min(MAX_ORDER, m)
    sigma = np.empty((orders, f.shape[1]))
    signs = np.empty((orders, f.shape[1]), dtype=bool)
    diff = f
    for k in range(1, orders + 1):
        diff = np.diff(diff, axis=0)
        gamma = factorial(k) ** 2 / factorial(2 * k)
        sigma[k - 1] = np.sqrt(gamma * np.mean(diff * diff, axis=0))
        signs[k - 1] = (diff.max(axis=0) > 0.0) & (diff.min(axis=0) < 0.0)
    out = np.full(f.shape[1], np.nan)
    for k in range(orders - 3, -1, -1):  # (downwards: the lowest qualifying order is written last)
        group = sigma[k:k + 3]
        ok = signs[k] & (group.max(axis=0) <= AGREEMENT * group.min(axis=0))
        out[ok] = sigma[k, ok]
    ordered = np.sort(f, axis=0)
    distinct = 1 + np.count_nonzero(np.diff(ordered, axis=0), axis=0)
    flat = distinct < (m + 2) // 2
    out[flat] = np.maximum(np.ptp(f[:, flat], axis=0), np.abs(np.broadcast_to(change, out.shape)[flat])) / NOISE_BOUND
    return out


def noise_along(values_at: Callable[[float], Array | None], at0: Array, slopes: Array,
                at1: Array | None = None) -> tuple[Array, int]:
    """Bounds on the noise of the components of ``values_at`` (a vector function of the step length) near ``0``,
    from stencils on ``[0, span]`` for the spans :data:`SPANS` in turn: a component is settled by the first span
    over which its differences are noise-dominated, and bounded by 0 when none is (it is smooth down to the
    smallest span: no noise is seen at the scale of the step).

    ``at0`` is ``values_at(0)`` and ``slopes`` its derivative there (the linear model's prediction for a stencil
    whose values are all equal: :func:`stencil_noise`); ``at1``, when given, is ``values_at(1)`` (an evaluation
    saved). ``values_at`` returns None where a value is not finite, which ends the search with what is settled.
    Returns the bounds ``NOISE_BOUND * sigma`` and the number of evaluations made.
    """
    at0 = np.asarray(at0, dtype=float)
    bound = np.full(at0.size, np.nan)
    evaluations = 0
    for span in SPANS:
        rows = [at0]
        for a in span * np.arange(1, STENCIL_INTERVALS + 1) / STENCIL_INTERVALS:
            if a == 1.0 and at1 is not None:
                rows.append(np.asarray(at1, dtype=float))
                continue
            value = values_at(float(a))
            evaluations += 1
            if value is None:
                return np.nan_to_num(bound, nan=0.0), evaluations
            rows.append(np.asarray(value, dtype=float))
        sigma = stencil_noise(np.vstack(rows), slopes * span)
        todo = np.isnan(bound)
        bound[todo] = NOISE_BOUND * sigma[todo]
        if not np.isnan(bound).any():
            break
    return np.nan_to_num(bound, nan=0.0), evaluations
