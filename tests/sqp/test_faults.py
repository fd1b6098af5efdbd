"""Deliberately broken problems: each ends with a clear error or an honest status, never a false success.

Bad input is refused before any solve (also ``test_components.py::test_bad_input_is_refused_before_any_work``);
faults met during a solve (NaN/inf, an infeasible problem, an iteration limit, a failing QP backend, a user function
that raises or changes its output size) end with an exception naming the function and the iteration, or with a
non-success status whose message says what happened.
"""

from __future__ import annotations

import functools
import re

import numpy as np
import pytest
from scipy.optimize import LinearConstraint, NonlinearConstraint

import sqp
import sqp.backends
import sqp.subproblem

# min (x0 - 1)^2 + (x1 + 2)^2 s.t. x0^2 + x1^2 <= 1: the answer is (1, -2) / sqrt(5), reached from x0 = (0, 0)
# in a few iterations; the unconstrained minimiser (1, -2) is outside the disc.
X_STAR = np.array([1.0, -2.0]) / np.sqrt(5.0)


def f(x):
    return (x[0] - 1.0) ** 2 + (x[1] + 2.0) ** 2


def g(x):
    return np.array([2.0 * (x[0] - 1.0), 2.0 * (x[1] + 2.0)])


def disc(x):
    return np.array([1.0 - x @ x])


def disc_jac(x):
    return -2.0 * x[None, :]


DISC = {"type": "ineq", "fun": disc, "jac": disc_jac}


def assert_failed_honestly(res, status):
    assert not res.success, res.message
    assert res.status == status.code, f"{res.status_name}: {res.message}"
    assert res.status_name == status.name


# --- x0 outside the bounds ------------------------------------------------------------------------------------------


def test_x0_outside_the_bounds_is_clipped_silently_and_recorded():
    # (filterwarnings = error: any warning here fails the test; SLSQP clips without one)
    seen = []

    def fun(x):
        seen.append(x.copy())
        return f(x) + x[2] ** 2

    res = sqp.minimize(fun, [5.0, -7.0, 0.1], jac=lambda x: np.append(g(x), 2 * x[2]),
                       bounds=[(0.0, 0.2), (-1.0, 1.0), (-1.0, 1.0)])
    np.testing.assert_array_equal(seen[0], [0.2, -1.0, 0.1])  # the first evaluation is at the clipped start
    assert res.success and np.allclose(res.x, [0.2, -1.0, 0.0])
    assert res.x0_clipped.tolist() == [0, 1]


def test_disp_reports_the_clipped_start(capsys):
    sqp.minimize(lambda x: float(x @ x), np.full(4, 2.0), jac=lambda x: 2 * x, bounds=[(-1.0, 1.0)] * 4,
                 options={"disp": True})
    out = capsys.readouterr().out
    assert "x0 clipped into the bounds at indices [0, 1, 2, 3]" in out and "(Exit mode 0: SUCCESS)" in out


def test_start_inside_the_bounds_records_no_clipping():
    res = sqp.minimize(f, [0.1, 0.2], jac=g, bounds=[(0.0, 1.0), (-1.0, 1.0)])
    assert res.x0_clipped.size == 0


def test_x0_within_rounding_of_a_bound_is_clipped_silently():
    # (filterwarnings = error: any warning here fails the test)
    res = sqp.minimize(f, [1.0 + 1e-15, -1e6 * (1 + 1e-13)], jac=g, bounds=[(0.0, 1.0), (-1e6, 0.0)])
    assert res.success


# --- a constraint function of the wrong length -----------------------------------------------------------------------


def test_nonlinear_constraint_length_differs_from_its_lb_ub():
    con = NonlinearConstraint(lambda x: np.array([x[0], x[1], x[0] + x[1]]), [0.0, 0.0], [1.0, 1.0])
    with pytest.raises(ValueError, match=re.escape("constraints[0].fun returned 3 value(s) at x0 but "
                                                   "constraints[0].lb has 2")):
        sqp.minimize(f, [0.0, 0.0], jac=g, constraints=[con])


@pytest.mark.parametrize("con", [
    {"type": "ineq", "fun": lambda x: np.array([[x[0]], [x[1]]])},
    NonlinearConstraint(lambda x: np.array([[x[0], x[1]]]), 0.0, 1.0),
], ids=["dict", "NonlinearConstraint"])
def test_a_two_dimensional_constraint_value_is_refused(con):
    with pytest.raises(ValueError, match=r"constraints\[1\].*returned an array of shape \((2, 1|1, 2)\) at x0"):
        sqp.minimize(f, [0.0, 0.0], jac=g, constraints=[DISC, con])


def _far(x):
    """Points reached by the first step of the disc problem (not the start)."""
    return x[0] > 0.2


@pytest.mark.parametrize(("kwargs", "text"), [
    ({"constraints": [DISC, {"type": "ineq", "fun": lambda x: np.array([5.0, 5.0][: 2 if _far(x) else 1]),
                             "jac": lambda x: np.zeros((2 if _far(x) else 1, 2))}]},
     "constraints[1]['fun'] returned 2 value(s) (shape (2,)) at iteration 1; it returned 1 at x0"),
    ({"constraints": [DISC, NonlinearConstraint(lambda x: x[0] + 5.0 if not _far(x) else np.ones((1, 1)), 0.0,
                                                np.inf)]},
     "constraints[1].fun returned 1 value(s) (shape (1, 1)) at iteration 1"),
    ({"fun": lambda x: f(x) if not _far(x) else np.array([f(x), 0.0]), "constraints": [DISC]},
     "fun returned an array of shape (2,) at iteration 1; it must return a scalar"),
    ({"jac": lambda x: g(x) if not _far(x) else np.ones(3), "constraints": [DISC]},
     "jac returned shape (3,) at iteration 1; expected (2,)"),
    ({"constraints": [{"type": "ineq", "fun": disc, "jac": lambda x: disc_jac(x) if not _far(x) else np.ones((2, 2))}]},
     "constraints[0]['jac'] returned shape (2, 2) at iteration 1; expected (1, 2)"),
    ({"constraints": [{**DISC, "hess": lambda x, v: -2 * v[0] * np.eye(2)}],
      "hess": lambda x: 2 * np.eye(2) if not _far(x) else np.eye(3)},
     "hess returned shape (3, 3) at iteration 2; expected (2, 2)"),
], ids=["dict-fun-grows", "object-fun-2d", "objective-array", "gradient", "jacobian", "hessian"])
def test_an_output_that_changes_size_during_the_solve_is_an_error(kwargs, text):
    args = {"fun": f, "x0": [0.0, 0.0], "jac": g} | kwargs
    with pytest.raises(ValueError, match=re.escape(text)):
        sqp.minimize(**args)


# --- a user function that raises --------------------------------------------------------------------------------------


class Boom(Exception):
    """Raised by the deliberately broken user functions."""


def _raising(fn, raised, armed):
    """``fn``, but raising a fresh :class:`Boom` (kept in ``raised``) once ``armed()`` is True."""

    @functools.wraps(fn)  # (keeps the callback's signature, which decides what it is passed)
    def wrapper(*a, **k):
        if armed():
            raised.append(Boom("user code failed"))
            raise raised[-1]
        return fn(*a, **k)

    return wrapper


@pytest.mark.parametrize("culprit", ["fun", "jac", "hess", "constraints[1]['fun']", "constraints[1]['jac']",
                                     "constraints[1]['hess']", "constraints[0].fun", "constraints[0].jac",
                                     "constraints[0].hess", "callback"])
def test_an_exception_from_user_code_propagates_with_the_iteration(culprit):
    """Armed once the callback has seen iteration 2: the culprit raises at iteration 3 (the callback at 2 itself)."""
    done = [0]
    raised: list[Boom] = []
    armed = (lambda: done[0] >= 2) if culprit != "callback" else (lambda: done[0] >= 1)
    wrap = (lambda name, fn: _raising(fn, raised, armed) if name == culprit else fn)  # noqa: E731
    # min |x - t|^2 on a ring 1 <= |x|^2 <= 2 and above a parabola (both active): several iterations with exact
    # Hessians
    t = np.array([3.0, 1.0, 0.5])
    ring = NonlinearConstraint(wrap("constraints[0].fun", lambda x: np.array([x @ x])), 1.0, 2.0,
                               jac=wrap("constraints[0].jac", lambda x: 2 * x[None, :]),
                               hess=wrap("constraints[0].hess", lambda x, v: 2 * v[0] * np.eye(3)))
    bowl = {"type": "ineq", "fun": wrap("constraints[1]['fun']", lambda x: np.array([x[1] - x[0] ** 2])),
            "jac": wrap("constraints[1]['jac']", lambda x: np.array([[-2 * x[0], 1.0, 0.0]])),
            "hess": wrap("constraints[1]['hess']", lambda x, v: np.diag([-2 * v[0], 0.0, 0.0]))}

    def callback(intermediate_result):
        done[0] = intermediate_result.nit

    with pytest.raises(Boom) as info:
        sqp.minimize(wrap("fun", lambda x: float((x - t) @ (x - t))), [1.0, 0.2, 0.1],
                     jac=wrap("jac", lambda x: 2 * (x - t)), constraints=[ring, bowl],
                     hess=wrap("hess", lambda x: 2 * np.eye(3)), callback=wrap("callback", callback))
    assert type(info.value) is Boom and info.value is raised[-1]  # the same exception, not wrapped
    assert str(info.value) == "user code failed"
    expected = 2 if culprit == "callback" else 3
    notes = getattr(info.value, "__notes__", [])
    assert len(notes) == 1, notes
    assert notes[0].startswith(f"sqp.minimize: raised by {culprit} at iteration {expected} (x = ["), notes


def test_an_exception_at_x0_is_reported_at_the_start():
    def fun(x):
        raise KeyError("no such thing")

    with pytest.raises(KeyError) as info:
        sqp.minimize(fun, [1.0, 2.0])
    assert info.value.__notes__ == ["sqp.minimize: raised by fun at iteration 0 (the start point) (x = [1., 2.])."]


def test_stop_iteration_from_the_callback_is_still_a_clean_stop():
    def cb(intermediate_result):
        raise StopIteration

    res = sqp.minimize(f, [0.0, 0.0], jac=g, constraints=[DISC], callback=cb)
    assert_failed_honestly(res, sqp.Status.CALLBACK)


# --- NaN and inf ------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("where", ["constraint", "gradient", "jacobian"])
def test_nan_at_a_trial_point_shortens_the_step(where):
    """Non-finite values beyond x0 = 0.6 (the minimiser is at 0.447): the full first step lands there; shorter steps
    reach the answer."""
    bad = lambda x: x[0] > 0.6  # noqa: E731
    con = {"type": "ineq", "fun": lambda x: np.array([np.nan]) if where == "constraint" and bad(x) else disc(x),
           "jac": lambda x: np.full((1, 2), np.inf) if where == "jacobian" and bad(x) else disc_jac(x)}
    jac = lambda x: np.full(2, np.nan) if where == "gradient" and bad(x) else g(x)  # noqa: E731
    res = sqp.minimize(f, [0.0, 0.0], jac=jac, constraints=[con])
    assert res.success, res.message
    np.testing.assert_allclose(res.x, X_STAR, atol=1e-7)
    assert all(np.isfinite(r.f) and np.isfinite(r.maxcv) for r in res.history)
    assert any(r.alpha < 1.0 for r in res.history)


@pytest.mark.parametrize(("where", "name"), [
    ("fun", "fun"), ("jac", "jac"), ("cfun", "constraints[0]['fun']"), ("cjac", "constraints[0]['jac']"),
    ("fd", "fun (in its finite-difference gradient)"),
])
def test_nan_at_x0_is_nonfinite_naming_the_function(where, name):
    nan = lambda shape: np.full(shape, np.nan)  # noqa: E731
    con = {"type": "ineq", "fun": (lambda x: nan(1)) if where == "cfun" else disc,
           "jac": (lambda x: nan((1, 2))) if where == "cjac" else disc_jac}
    fun = {"fun": lambda x: np.inf, "fd": lambda x: f(x) if np.all(x == 0.0) else np.nan}.get(where, f)
    res = sqp.minimize(fun, [0.0, 0.0], jac=None if where == "fd" else (lambda x: nan(2)) if where == "jac" else g,
                       constraints=[con])
    assert_failed_honestly(res, sqp.Status.NONFINITE)
    assert f"{name} returned NaN or inf at the start point (iteration 0" in res.message, res.message


@pytest.mark.parametrize(("where", "name"), [
    ("fun", "fun"), ("jac", "jac"), ("cfun", "constraints[0]['fun']"), ("cjac", "constraints[0]['jac']"),
])
def test_nan_everywhere_but_at_x0_is_nonfinite_naming_the_function(where, name):
    at_start = lambda x: bool(np.all(x == 0.0))  # noqa: E731
    bad = lambda w, value: (lambda x: value(x) if at_start(x) or where != w else np.nan * value(x))  # noqa: E731
    con = {"type": "ineq", "fun": bad("cfun", disc), "jac": bad("cjac", disc_jac)}
    res = sqp.minimize(bad("fun", f), [0.0, 0.0], jac=bad("jac", g), constraints=[con])
    assert_failed_honestly(res, sqp.Status.NONFINITE)
    assert f"{name} returned NaN or inf at every trial point of iteration 1 down to step length" in res.message, \
        res.message
    assert res.nit == 0 and np.all(res.x == 0.0) and np.isfinite(res.fun)


def test_nan_from_an_exact_hessian_is_nonfinite():
    res = sqp.minimize(f, [0.0, 0.0], jac=g, constraints=[{**DISC, "hess": lambda x, v: -2 * v[0] * np.eye(2)}],
                       hess=lambda x: np.full((2, 2), np.nan))
    assert_failed_honestly(res, sqp.Status.NONFINITE)
    assert "hess returned NaN or inf at iteration 1" in res.message


# --- infeasible problems ---------------------------------------------------------------------------------------------


def _least_violation(message):
    """The violation (sum over the rows) and the largest row's, as the INFEASIBLE message states them."""
    found = re.search(r"Least violation reached: ([0-9.e+-]+) \(sum over the rows; largest ([0-9.e+-]+)\) at x = \[",
                      message)
    assert found, message
    return float(found.group(1)), float(found.group(2))


def test_an_impossible_inequality_is_infeasible_with_the_least_violation():
    con = {"type": "ineq", "fun": lambda x: np.array([-(x @ x) - 1.0]), "jac": lambda x: -2 * x[None, :]}
    res = sqp.minimize(lambda x: x @ x, [1.0, 1.0], jac=lambda x: 2 * x, constraints=[con])
    assert_failed_honestly(res, sqp.Status.INFEASIBLE)
    assert "could not be satisfied" in res.message
    total, largest = _least_violation(res.message)
    # -(|x|^2) - 1 >= 0 is violated by 1 + |x|^2, least (1) at x = 0: the message, x and maxcv say so
    assert total == largest == pytest.approx(1.0, abs=1e-9) and res.maxcv == pytest.approx(1.0, abs=1e-9)
    np.testing.assert_allclose(res.x, 0.0, atol=1e-5)


def test_contradictory_equalities_are_infeasible_with_the_least_violation():
    # |x|^2 = 1 and |x|^2 = 4: the violation |r - 1| + |r - 4| (r = |x|^2) is least, 3, for every r in [1, 4]
    cons = [{"type": "eq", "fun": lambda x: np.array([x @ x - 1.0]), "jac": lambda x: 2 * x[None, :]},
            {"type": "eq", "fun": lambda x: np.array([x @ x - 4.0]), "jac": lambda x: 2 * x[None, :]}]
    res = sqp.minimize(lambda x: x[0] + x[1], [0.5, 0.3], jac=lambda x: np.ones(2), constraints=cons)
    assert_failed_honestly(res, sqp.Status.INFEASIBLE)
    total, largest = _least_violation(res.message)
    r = float(res.x @ res.x)
    assert total == pytest.approx(3.0, abs=1e-8) and 1.0 - 1e-8 <= r <= 4.0 + 1e-8
    assert largest == pytest.approx(res.maxcv, rel=1e-3) == pytest.approx(max(abs(r - 1.0), abs(r - 4.0)), rel=1e-3)


@pytest.mark.parametrize("bounds", [None, [(0.0, 1.0), (0.0, 1.0)]])
def test_contradictory_linear_constraints_are_linear_infeasible(bounds):
    lin = LinearConstraint([[1.0, 1.0], [1.0, 1.0]], [1.0, 3.0], [1.0, 3.0]) if bounds is None else \
        LinearConstraint([[1.0, 1.0]], 3.0, 4.0)
    res = sqp.minimize(f, [0.0, 0.0], jac=g, bounds=bounds, constraints=[lin, DISC])
    assert_failed_honestly(res, sqp.Status.LINEAR_INFEASIBLE)


# --- limits, wrong derivatives, unbounded problems --------------------------------------------------------------------


def test_max_iter_zero():
    res = sqp.minimize(f, [0.0, 0.0], jac=g, constraints=[DISC], max_iter=0)
    assert_failed_honestly(res, sqp.Status.MAX_ITER)
    assert res.nit == 0 and "max_iter (now 0)" in res.message
    np.testing.assert_array_equal(res.x, [0.0, 0.0])


@pytest.mark.parametrize("constraints", [(), [DISC]], ids=["unconstrained", "disc"])
def test_a_wrong_gradient_is_no_success(constraints):
    res = sqp.minimize(f, [0.0, 0.0], jac=lambda x: -g(x), constraints=constraints)  # sign flipped
    assert not res.success, res.message
    assert res.status_name in ("LINE_SEARCH", "SMALL_STEP", "MAX_ITER"), res.message


UNBOUNDED_CASES = {
    "linear objective on a box corner": ({"fun": lambda x: -x[0], "x0": [1.0, 1.0], "bounds": [(0, None)] * 2},
                                         lambda x: np.array([-1.0, 0.0])),
    "along a parabola": ({"fun": lambda x: -x[0] - x[1], "x0": [1.0, 1.0],
                          "constraints": [{"type": "ineq", "fun": lambda x: x[0] - x[1] ** 2}]},
                         lambda x: np.array([-1.0, -1.0])),
    "free linear objective": ({"fun": lambda x: -x[0], "x0": [0.0, 0.0]}, lambda x: np.array([-1.0, 0.0])),
}


@pytest.mark.parametrize("differences", [False, True], ids=["analytic", "finite-differences"])
@pytest.mark.parametrize("case", list(UNBOUNDED_CASES))
def test_an_unbounded_problem_ends_unbounded_quickly_and_quietly(case, differences):
    # (filterwarnings = error: an overflow RuntimeWarning on the way fails the test)
    problem, jac = UNBOUNDED_CASES[case]
    res = sqp.minimize(**problem, jac=None if differences else jac)
    assert res.status == sqp.Status.UNBOUNDED and not res.success, res.message
    assert res.nit <= 30 and res.fun < -1e9 and res.maxcv <= 1e-8 * max(1.0, np.max(np.abs(res.x)))


INFEASIBLE_CASES = {
    # an equality x0 + x1 = 1 that the bounds and x0 >= 2 make impossible (the shape of scipy's gh-5743)
    "equality against an inequality": {
        "fun": lambda x: x @ x, "x0": [1.0, 2.0], "bounds": [(0, None)] * 2,
        "constraints": [{"type": "eq", "fun": lambda x: x[0] + x[1] - 1}, {"type": "ineq", "fun": lambda x: x[0] - 2}]},
    "disc and a far half-plane": {
        "fun": lambda x: x @ x, "x0": [0.0, 0.0],
        "constraints": [{"type": "ineq", "fun": lambda x: 1 - x @ x},
                        {"type": "ineq", "fun": lambda x: x[0] + x[1] - 3}]},
    "two disjoint discs": {
        "fun": lambda x: x[0] + x[1], "x0": [0.0, 0.0],
        "constraints": [{"type": "ineq", "fun": lambda x: 1 - x @ x},
                        {"type": "ineq", "fun": lambda x: 1 - (x[0] - 3) ** 2 - x[1] ** 2}]},
}


@pytest.mark.parametrize("case", list(INFEASIBLE_CASES))
def test_an_infeasible_problem_ends_infeasible_quickly(case):
    res = sqp.minimize(**INFEASIBLE_CASES[case])
    assert res.status == sqp.Status.INFEASIBLE and not res.success, res.message
    assert res.nit <= 25 and "Least violation reached" in res.message


# --- QP backend failures ----------------------------------------------------------------------------------------------


def _broken(monkeypatch, names, mode):
    """Make the engine's one call to a backend (:func:`sqp.backends.solve_problem`: DAQP directly, the others through
    qpsolvers) fail for the backends ``names`` in a given way."""
    real = sqp.backends.solve_problem

    def fake(problem, solver, **kwargs):
        if solver in names:
            if mode == "raise":
                raise RuntimeError(f"{solver} is down")
            if mode == "our-bug":
                raise TypeError("a bug on our side")
            if mode == "none":
                return None
            if mode == "not-a-solution":
                return "garbage"
            sol = real(problem, solver=solver, **kwargs)
            if sol.x is None:  # the backend found nothing itself: nothing to corrupt
                return sol
            sol.x = np.full(sol.x.size + 1, 7.0) if mode == "wrong-size" else sol.x * np.nan
            return sol
        return real(problem, solver=solver, **kwargs)

    monkeypatch.setattr(sqp.backends, "solve_problem", fake)


def test_a_bug_of_ours_around_a_backend_is_not_reported_as_a_failed_qp(monkeypatch):
    _broken(monkeypatch, ["daqp"], "our-bug")
    with pytest.raises(TypeError, match="a bug on our side"):
        sqp.minimize(f, [0.0, 0.0], jac=g, constraints=[DISC], qp_solver="daqp")


@pytest.mark.parametrize("mode", ["raise", "none", "not-a-solution", "wrong-size", "nan"])
def test_a_failing_backend_falls_back_and_the_table_says_which_answered(monkeypatch, capsys, mode):
    _broken(monkeypatch, {"daqp"}, mode)
    res = sqp.minimize(f, [0.0, 0.0], jac=g, constraints=[DISC], verbose=True)
    assert res.success, res.message
    np.testing.assert_allclose(res.x, X_STAR, atol=1e-7)
    assert res.history and all(r.qp_status == "opt[quadprog]" for r in res.history)
    assert "opt[quadprog]" in capsys.readouterr().out


def test_every_backend_failing_is_qp_failed_naming_them(monkeypatch):
    _broken(monkeypatch, {"daqp", "quadprog", "clarabel", "osqp"}, "raise")
    res = sqp.minimize(f, [0.0, 0.0], jac=g, constraints=[DISC])
    assert_failed_honestly(res, sqp.Status.QP_FAILED)
    assert "Backends tried: daqp, quadprog, clarabel" in res.message


def test_every_backend_failing_on_the_start_projection_is_not_called_infeasible(monkeypatch):
    _broken(monkeypatch, {"daqp", "quadprog", "clarabel", "osqp"}, "none")
    res = sqp.minimize(f, [0.0, 0.0], jac=g, constraints=[LinearConstraint([[1.0, 1.0]], 0.5, 1.0)])
    assert_failed_honestly(res, sqp.Status.QP_FAILED)
    assert "Backends tried: daqp, quadprog, clarabel" in res.message
