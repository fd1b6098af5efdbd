"""Exact-Hessian SQP started next to a saddle: the identity shift that makes the model positive definite, and the
extension of a shifted step (:func:`sqp.linesearch.expanded`).

The double well ``f = a ((x_0 / s)^2 - 1)^2 + |x_rest|^2 / 2`` has a saddle at ``x_0 = 0`` (curvature
``-4 a / s^2``, the most negative diagonal entry of the Hessian) and minima at ``x_0 = ±s``. From ``x_0 = t s`` the
descent goes to the minimum on the start's side.
"""

from __future__ import annotations

import numpy as np
import pytest

import sqp


def _double_well(s: float, a: float):
    def f(x):
        return a * ((x[0] / s) ** 2 - 1.0) ** 2 + 0.5 * float(np.sum(x[1:] ** 2))

    def g(x):
        out = x.copy()
        out[0] = 4.0 * a * x[0] / s**2 * ((x[0] / s) ** 2 - 1.0)
        return out

    def h(x):
        H = np.eye(x.size)
        H[0, 0] = a * (12.0 * x[0] ** 2 / s**4 - 4.0 / s**2)
        return H

    return f, g, h


@pytest.mark.parametrize("s", [0.1, 1.0, 10.0])
@pytest.mark.parametrize("a", [1e-2, 1.0, 1e2])
@pytest.mark.parametrize("t", [1e-2, -1e-4, 1e-6])
def test_a_start_next_to_a_saddle_reaches_the_minimum_on_its_side(s, a, t):
    """Every scale ``s``, depth ``a`` and distance ``t`` from the saddle: success at ``x_0 = sign(t) s`` with the
    gradient at tolerance, in at most 15 iterations. Measured 5-13; without the extension of shifted steps 23-35
    (the shifted step creeps away from the saddle by a factor ``1 + |lambda| / (delta - |lambda|)`` an iteration),
    and where ``-4 a / s^2`` is the Hessian's largest diagonal entry in size the shift ladder's power of ten met it
    exactly and the singular model ended the run in the first line search (7 of these 27 cases)."""
    f, g, h = _double_well(s, a)
    x0 = np.full(3, 0.3)
    x0[0] = t * s
    res = sqp.minimize(f, x0, jac=g, hess=h, tol=1e-10)
    assert res.success, res.message
    assert res.x[0] / s == pytest.approx(np.sign(t), abs=1e-6)
    assert np.abs(res.x[1:]).max() <= 1e-8
    assert res.nit <= 15


@pytest.mark.parametrize("t", [-1e-4, 1e-6])
def test_without_the_extension_the_same_minimum_takes_more_iterations(t):
    """``extend_shifted_steps=False`` (the 3-D guidewire's choice) reaches the same minimum, in more iterations: the
    extension is what removes the creep (measured 23-35 against 5-13)."""
    f, g, h = _double_well(1.0, 1.0)
    x0 = np.full(3, 0.3)
    x0[0] = t
    on = sqp.minimize(f, x0, jac=g, hess=h, tol=1e-10)
    off = sqp.minimize(f, x0, jac=g, hess=h, tol=1e-10, extend_shifted_steps=False)
    assert on.success and off.success
    assert off.x[0] == pytest.approx(np.sign(t), abs=1e-6)
    assert off.nit >= on.nit + 5
