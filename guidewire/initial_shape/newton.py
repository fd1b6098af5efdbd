"""The batched Newton iteration that closes the default start's two-mode curves (:mod:`guidewire.initial_shape`,
step 2): the shared quadrature tables of a midpoint rule and damped Newton steps on every row of a grid at once."""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@functools.cache
def curve_tables(samples: int) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """What every closure solve of the start curves shares (read-only) for a midpoint rule of ``samples`` points: the
    points ``u`` (M,), the basis ``sin(πu), sin(2πu)`` repeated (2, 2M) — the arguments of cos θ and of
    ``sin θ = cos(θ − π/2)`` side by side —, the block weights (2M, 6) whose one matrix product gives the means of
    (cos θ, sin θ) and their derivatives in c (columns: cos × [mean, d/dc₁, d/dc₂], then sin × the same), and
    ``cos(πu), cos(2πu)`` (2, M) for the slopes of the basis."""
    u = (np.arange(samples) + 0.5) / samples  # midpoints, s = u ℓ
    basis = np.stack((np.sin(np.pi * u), np.sin(2.0 * np.pi * u)))
    weights = np.column_stack((np.ones(samples), basis.T)) / samples
    blocks = np.zeros((2 * samples, 6))
    blocks[:samples, :3], blocks[samples:, 3:] = weights, weights
    tables = (u, np.hstack((basis, basis)), blocks, np.stack((np.cos(np.pi * u), np.cos(2.0 * np.pi * u))))
    for table in tables:
        table.flags.writeable = False
    return tables


def curve_lines(samples: int, a0: FloatArray, a1: FloatArray) -> FloatArray:
    """The part of the arguments ``[θ | θ − π/2]`` at the sample points that does not depend on ``c``, one row
    (2M,) per segment (``a0``, ``a1``: shape (S,))."""
    u = curve_tables(samples)[0]
    line = a0[:, None] + (a1 - a0)[:, None] * u
    return np.hstack((line, line - 0.5 * np.pi))


#: Columns of the means ``[cm0 − tx, cm1, cm2, sm0 − ty, sm1, sm2]`` (``cm``: cos θ, ``sm``: sin θ; 0 the mean, 1 and
#: 2 its derivatives in c₁, c₂) whose products :func:`newton` needs — ``sm2·cm1, sm1·cm2, sm2·ry, cm2·rx, cm1·rx,
#: sm1·ry``: the six left factors, then the six right ones, one ``take`` — and the matrix summing them into the
#: Jacobian's determinant and the two numerators of Cramer's rule. (Every sum it forms has two non-zero terms of
#: weight ±1: exactly the subtraction or addition it replaces.)
PAIRS = np.array([5, 4, 5, 2, 1, 4, 1, 2, 3, 0, 0, 3])
CRAMER = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0],
                    [0.0, 0.0, 1.0]])


def newton(c: FloatArray, lines: FloatArray, offset: FloatArray, samples: int, steps: int
            ) -> tuple[FloatArray, bool]:
    """``steps`` damped Newton steps (``|Δc|∞ ≤ 1``) on the closure ``mean(cos θ, sin θ) = target`` for every row of
    ``c`` (R, 2) at once, in place, on the ``samples``-point rule; ``lines`` (R or 1, 2M) is each row's part of the
    arguments without ``c`` (:func:`curve_lines`), ``offset`` (R or 1, 6) its target in columns 0 and 3 (the rows may
    belong to different segments). Stops early once every step is below 1e-13. Returns the end-point miss / ℓ (R,)
    before the last step, and whether it stopped so (then every miss is the end point's up to that last step:
    below 1e-12, or exactly the end point's where the Jacobian is singular and no step is made).

    Each step is a handful of whole-array operations (the 2 × 2 solves of all rows by Cramer's rule as one product
    and one matrix product, :data:`CRAMER`): per row the same arithmetic as writing the rule out term by term."""
    _, basis, blocks, _ = curve_tables(samples)
    means, settled = None, False
    for _ in range(steps):
        args = c @ basis
        args += lines
        means = np.cos(args, out=args) @ blocks
        means -= offset  # the residual in columns 0 and 3
        pairs = means.take(PAIRS, axis=1)
        cramer = (pairs[:, :6] * pairs[:, 6:]) @ CRAMER  # det, −(sm2 ry + cm2 rx), cm1 rx + sm1 ry
        det = cramer[:, 0]
        step = cramer[:, 1:] * (1.0 / np.where(np.abs(det) > 1e-12, det, np.inf))[:, None]  # singular: no step
        size = np.maximum.reduce(np.abs(step), axis=1)
        largest = np.maximum.reduce(size, initial=0.0)
        if largest > 1.0:  # damped rows (|Δc|∞ ≤ 1); otherwise every factor would be exactly 1
            step *= (1.0 / np.maximum(size, 1.0))[:, None]
        c += step
        if largest <= 1e-13:
            settled = True
            break
    return (np.full(c.shape[0], np.inf) if means is None else np.hypot(means[:, 0], means[:, 3])), settled
