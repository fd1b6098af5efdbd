"""Code written for ``scipy.optimize.minimize(method="SLSQP")`` runs unchanged on ``sqp.minimize``.

Each *script* below is user code as one would write it for SLSQP, parametrised only by the ``minimize`` it calls. It
runs on both, and the answers are compared: same ``x`` and ``fun``, same ``success`` and ``status`` (our codes agree
with SLSQP's table), same ``multipliers`` array (type, order, sign). The problems are our own.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from scipy.optimize import Bounds, LinearConstraint, NonlinearConstraint, OptimizeWarning
from scipy.optimize import minimize as scipy_minimize

import sqp

Minimize = Callable[..., Any]


def slsqp(*args: Any, **kwargs: Any) -> Any:
    return scipy_minimize(*args, **kwargs)


def ours(*args: Any, **kwargs: Any) -> Any:
    return sqp.minimize(*args, **kwargs)


# --- the scripts ------------------------------------------------------------------------------------------------------

def weighted_distance(x, w):
    return float(w[0] * (x[0] - 2.0) ** 2 + w[1] * (x[1] - 1.0) ** 2)


def script_positional_args(minimize: Minimize) -> Any:
    """``args`` third and positional, as in scipy's signature; ``method`` by name."""
    cons = {"type": "ineq", "fun": lambda x, w: 1.0 - x[0] - x[1], "args": ((3.0, 1.0),)}
    return minimize(weighted_distance, [0.0, 0.0], ((3.0, 1.0),), "SLSQP", constraints=cons)


def script_options_dict(minimize: Minimize) -> Any:
    """SLSQP's options: ``maxiter``, ``ftol``, ``eps``, ``disp=False``."""
    return minimize(lambda x: (x[0] - 1) ** 2 + (x[1] - 2.5) ** 2, [2.0, 0.0], method="slsqp",
                    constraints=({"type": "ineq", "fun": lambda x: x[0] - 2 * x[1] + 2},
                                 {"type": "ineq", "fun": lambda x: -x[0] - 2 * x[1] + 6},
                                 {"type": "ineq", "fun": lambda x: -x[0] + 2 * x[1] + 2}),
                    bounds=((0, None), (0, None)),
                    options={"maxiter": 200, "ftol": 1e-10, "eps": 1e-9, "disp": False})


def script_fun_returns_gradient(minimize: Minimize) -> Any:
    """``jac=True``: the objective returns ``(f, g)``."""
    def fg(x):
        return float(x @ x), 2 * x

    return minimize(fg, [1.0, 2.0, 3.0], jac=True, method="SLSQP",
                    constraints=[{"type": "eq", "fun": lambda x: x.sum() - 1.0, "jac": lambda x: np.ones(3)}])


@pytest.fixture(params=["2-point", "3-point", "cs"])
def scheme(request):
    return request.param


def script_difference_scheme(minimize: Minimize, scheme: str) -> Any:
    """A named finite-difference scheme (complex-safe functions for ``'cs'``), with a relative step option."""
    return minimize(lambda x: (x[0] - 1.0) ** 2 + np.exp(x[1]) - 2 * x[1], np.array([3.0, 1.0]), jac=scheme,
                    method="SLSQP", constraints=[NonlinearConstraint(lambda x: x[0] ** 2 + x[1] ** 2, -np.inf, 2.0)],
                    options={"finite_diff_rel_step": 1e-7 if scheme != "cs" else None})


def script_scalar_bounds_and_scalar_x0(minimize: Minimize) -> Any:
    """``Bounds(lo, hi)`` with scalars (stored with shape (1,), broadcast) and a scalar ``x0``."""
    return minimize(lambda x: (x[0] + 1.0) ** 2, 3.0, method="SLSQP", bounds=Bounds(0.0, np.inf))


def script_broadcast_bounds(minimize: Minimize) -> Any:
    """``Bounds(0, np.inf)`` on three variables, with a start outside them (clipped, no warning)."""
    return minimize(lambda x: float(np.sum((x - np.array([-1.0, 2.0, 3.0])) ** 2)), [-5.0, 1.0, 1.0],
                    method="SLSQP", bounds=Bounds(0, np.inf),
                    constraints=[LinearConstraint(np.ones((1, 3)), -np.inf, 4.0)], tol=1e-10)


def script_mixed_constraints(minimize: Minimize) -> Any:
    """A two-sided NonlinearConstraint mixing an equality and inequalities, a LinearConstraint and a dict: the
    multiplier array's order and signs are SLSQP's."""
    nl = NonlinearConstraint(lambda x: np.array([x[0] + x[1] + x[2], x[0] * x[1], x[2]]),
                             [1.0, -np.inf, 0.5], [1.0, 0.05, 2.0])
    lin = LinearConstraint([[1.0, -1.0, 0.0]], -0.5, 0.5)
    dct = {"type": "ineq", "fun": lambda x: x[1] + 1.0}
    return minimize(lambda x: (x[0] - 2) ** 2 + (x[1] - 1) ** 2 + x[2] ** 2, [0.3, 0.3, 0.4], method="SLSQP",
                    constraints=[nl, lin, dct], options={"ftol": 1e-10})


SCRIPTS = [script_positional_args, script_options_dict, script_fun_returns_gradient,
           script_scalar_bounds_and_scalar_x0, script_broadcast_bounds, script_mixed_constraints]


def _run_both(script: Callable[..., Any], *extra: Any) -> tuple[Any, Any]:
    with warnings.catch_warnings():
        # scipy itself warns about a NonlinearConstraint mixing equalities and inequalities: not ours to test
        warnings.filterwarnings("ignore", message="Equality and inequality constraints", category=OptimizeWarning)
        warnings.filterwarnings("ignore", category=np.exceptions.ComplexWarning)  # scipy's own cast under 'cs'
        ref = script(slsqp, *extra)
    return ref, script(ours, *extra)


def _same_answer(ref: Any, res: Any, atol: float = 1e-5) -> None:
    assert ref.success and res.success, (ref.message, res.message)
    assert res.status == ref.status == 0
    np.testing.assert_allclose(res.x, ref.x, atol=atol)
    assert res.fun == pytest.approx(ref.fun, abs=atol)
    assert isinstance(res.multipliers, np.ndarray) and res.multipliers.shape == ref.multipliers.shape
    np.testing.assert_allclose(res.multipliers, ref.multipliers, atol=1e-4)


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda s: s.__name__)
def test_user_code_runs_unchanged_and_agrees(script):
    ref, res = _run_both(script)
    _same_answer(ref, res)


def test_difference_schemes_agree(scheme):
    ref, res = _run_both(script_difference_scheme, scheme)
    _same_answer(ref, res, atol=1e-4)


def test_three_point_is_central_not_forward():
    """'3-point' evaluates on both sides of x (a forward scheme would only step one way)."""
    seen: list[np.ndarray] = []

    def f(x):
        seen.append(np.array(x))
        return float((x[0] - 1.0) ** 2)

    sqp.minimize(f, [3.0], jac="3-point", options={"maxiter": 1})
    steps = np.array([s[0] for s in seen]) - 3.0
    assert np.any(steps > 0) and np.any(steps < 0)


def test_multipliers_of_a_mixed_constraint_have_slsqp_order_and_sign():
    ref, res = _run_both(script_mixed_constraints)
    # one equality row first, then: the NonlinearConstraint's own inequality rows appended after the others
    assert res.multipliers.size == 1 + 2 + 1 + 3
    flat = np.concatenate(res.constraint_multipliers)
    assert res.multipliers[0] == pytest.approx(flat[0])
    assert np.all(res.multipliers[1:] >= -1e-8)  # SLSQP's inequality multipliers are nonnegative


# --- callbacks --------------------------------------------------------------------------------------------------------

def script_callback_xk(minimize: Minimize) -> tuple[Any, list[np.ndarray]]:
    xs: list[np.ndarray] = []
    res = minimize(lambda x: (x[0] - 1) ** 2 + (x[1] + 1) ** 2 + x[0] * x[1], [3.0, 3.0], method="SLSQP",
                   callback=lambda xk: xs.append(xk))
    return res, xs


def script_callback_stop(minimize: Minimize) -> tuple[Any, list[float]]:
    seen: list[float] = []

    def stop_after_two(intermediate_result):
        seen.append(intermediate_result.fun)
        if len(seen) == 2:
            raise StopIteration

    res = minimize(lambda x: (x[0] - 1) ** 4 + (x[1] + 1) ** 2, [3.0, 3.0], method="SLSQP", callback=stop_after_two)
    return res, seen


def test_callback_with_xk_gets_arrays():
    (ref, ref_xs), (res, xs) = _run_both(script_callback_xk)
    for seen in (ref_xs, xs):
        assert seen and all(isinstance(x, np.ndarray) and x.shape == (2,) for x in seen)
    np.testing.assert_allclose(xs[-1], ref_xs[-1], atol=1e-5)


def test_callback_named_intermediate_result_gets_a_result_and_stop_iteration_stops():
    (ref, ref_seen), (res, seen) = _run_both(script_callback_stop)
    assert len(ref_seen) == len(seen) == 2
    assert ref.success is res.success is False
    assert res.status == ref.status == 99 == sqp.Status.CALLBACK


# --- statuses, options and refusals -----------------------------------------------------------------------------------

def script_iteration_limit(minimize: Minimize) -> Any:
    rosen = lambda x: 100 * (x[1] - x[0] ** 2) ** 2 + (1 - x[0]) ** 2  # noqa: E731
    return minimize(rosen, [-1.2, 1.0], method="SLSQP", options={"maxiter": 3},
                    constraints=[{"type": "ineq", "fun": lambda x: 4 - x @ x}])


def test_iteration_limit_has_slsqps_code():
    ref, res = _run_both(script_iteration_limit)
    assert not ref.success and not res.success
    assert res.status == ref.status == 9 == sqp.Status.MAX_ITER
    assert res.nit == ref.nit == 3


def test_unknown_option_warns_as_scipy_does():
    for minimize in (slsqp, ours):
        with pytest.warns(OptimizeWarning, match="Unknown solver options: maxfev"):
            res = minimize(lambda x: float(x @ x), [1.0, 1.0], method="SLSQP", options={"maxfev": 10})
        assert res.success


def test_other_methods_are_refused_clearly():
    with pytest.raises(ValueError, match="method='trust-constr'.*scipy.optimize.minimize"):
        sqp.minimize(lambda x: float(x @ x), [1.0], method="trust-constr")


def test_tol_and_ftol_set_the_kkt_tolerance():
    problem = {"fun": lambda x: float(np.sum(np.exp(x) - x)), "x0": [1.0, -2.0]}
    loose = sqp.minimize(**problem, tol=1e-3)
    tight = sqp.minimize(**problem, options={"ftol": 1e-12})
    assert loose.success and tight.success
    assert tight.kkt["stationarity"] <= 1e-12 < loose.kkt["stationarity"] <= 1e-3


def test_max_iter_and_maxiter_together_are_refused():
    with pytest.raises(ValueError, match="max_iter and options\\['maxiter'\\]"):
        sqp.minimize(lambda x: float(x @ x), [1.0], max_iter=5, options={"maxiter": 5})


def test_disp_with_iprint_2_prints_the_iteration_table(capsys):
    sqp.minimize(lambda x: float(x @ x), [1.0, 2.0], options={"disp": True, "iprint": 2})
    out = capsys.readouterr().out
    assert "Exit mode 0" in out and out.count("\n") > 6
    sqp.minimize(lambda x: float(x @ x), [1.0, 2.0], options={"disp": False, "iprint": 2})
    assert capsys.readouterr().out == ""


def test_fun_returning_a_pair_is_called_once_per_point():
    calls = []

    def fg(x):
        calls.append(np.array(x))
        return float(x @ x), 2 * x

    res = sqp.minimize(fg, [1.0, 2.0], jac=True)
    assert res.success
    # the gradient came with the value: no call beyond the counted ones (the check of the input at x0 is the start's)
    assert len(calls) == res.nfev
