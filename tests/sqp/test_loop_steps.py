"""Each step of the SQP loop (paper §2.2) on its own: the Hessian strategies (Eq. 6, exact made convex), the penalty
update (Eq. 13), the merit line search (Eq. 12) as a function of its inputs, and the termination monitor."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import BFGS

from sqp.build import build_problem
from sqp.hessian_strategy import ConvexifiedExact, DampedBFGS, hessian_strategy
from sqp.iterate import Evaluator, State
from sqp.linesearch import line_search, merit_search
from sqp.merit import ARMIJO, directional_derivative, merit, penalties
from sqp.monitor import SETTLED_STEPS, STALL_ITERATIONS, Monitor
from sqp.options import Options
from sqp.result import Status
from sqp.solver import bounded_steps, subproblem
from sqp.subproblem import QPStep
from sqp.termination import INFEASIBLE_STALL, RESTART_BOUNDED_ITERATIONS, SETTLED_STEP


def _circle(x0=(1.2, -0.7), hess=True):
    """min x0 x1 on the circle x.x = 2 (an indefinite Lagrangian Hessian at lam = 0.3): x* = (1, -1), lam* = -1/2."""
    con = {"type": "eq", "fun": lambda x: np.array([x @ x - 2]), "jac": lambda x: 2 * x[None, :],
           "hess": lambda x, v: 2 * v[0] * np.eye(2)}
    H = (lambda x: np.array([[0.0, 1.0], [1.0, 0.0]])) if hess else None
    return build_problem(lambda x: x[0] * x[1], list(x0), lambda x: np.array([x[1], x[0]]), None, [con], (), H)


def _state(problem, x, B=None, mu=None, qp=None):
    ev = Evaluator(problem)
    pt = ev.point(np.asarray(x, dtype=float))
    der = ev.derivatives(pt)
    m = problem.nonlinear.lb.size
    return ev, State(pt=pt, der=der, B=np.eye(problem.n) if B is None else B,
                     mu=np.zeros(m) if mu is None else np.asarray(mu, dtype=float), qp=qp)


def _qp(problem, d, lam, *, elastic=False, found=True):
    return QPStep(d=np.asarray(d, dtype=float), lam_nl=np.asarray(lam, dtype=float),
                  lam_lin=np.zeros(problem.linear.lb.size), z=np.zeros(problem.n), found=found, elastic=elastic,
                  slack=0.0, status="optimal" if found else "failed")


# --- the Hessian (Eq. 6, or the exact Hessian made positive definite) ---------------------------------------------

def test_strategy_is_chosen_by_the_problem():
    assert isinstance(hessian_strategy(_circle(), None, None), ConvexifiedExact)
    assert isinstance(hessian_strategy(_circle(hess=False), None, None), DampedBFGS)


@pytest.mark.parametrize("curvature", [1.0, -0.5])  # plain BFGS, and a step of negative curvature (Powell damping)
def test_damped_bfgs_strategy_matches_scipys_damped_update(curvature):
    """scipy's BFGS(exception_strategy='damp_update', min_curvature=0.2) is Powell's damped update (Powell 1978):
    the strategy's update from the same B, s, y must agree to rounding."""
    rng = np.random.default_rng(3)
    n = 4
    Q = rng.standard_normal((n, n))
    H = Q @ Q.T + n * np.eye(n)
    problem = build_problem(lambda x: 0.5 * curvature * x @ H @ x, np.ones(n), lambda x: curvature * H @ x, None, [],
                            (), None)
    B0 = np.diag([1.0, 2.0, 3.0, 4.0])
    strategy = DampedBFGS(problem, B0)
    ev, st = _state(problem, np.ones(n))
    st = State(st.pt, st.der, strategy.initial(st), st.mu)
    new = Evaluator(problem).derivatives(ev.point(np.ones(n) - 0.3 * np.arange(n)))
    s = -0.3 * np.arange(n)
    qp = _qp(problem, s, [])
    B, damped = strategy.update(st, new, qp, s, first=True)  # hess0 given: no Shanno-Phua scaling
    oracle = BFGS(exception_strategy="damp_update", min_curvature=0.2, init_scale=1.0)
    oracle.initialize(n, "hess")
    oracle.B = B0.copy()
    oracle.update(s, new.g - st.der.g)
    np.testing.assert_allclose(B, oracle.get_matrix(), rtol=1e-10, atol=1e-12)
    assert damped == (curvature < 0)
    assert np.all(np.linalg.eigvalsh(B) > 0)
    np.testing.assert_array_equal(st.B, B0)  # the state's matrix is not changed in place


def test_identity_start_is_rescaled_once_by_shanno_phua():
    problem = build_problem(lambda x: 2.0 * x @ x, [1.0, 1.0], lambda x: 4.0 * x, None, [], (), None)
    strategy = DampedBFGS(problem, None)
    ev, st = _state(problem, [1.0, 1.0])
    st = State(st.pt, st.der, strategy.initial(st), st.mu)
    np.testing.assert_array_equal(st.B, np.eye(2))  # |g| = 4 <= 5 max(1, |x|): the bare identity
    s = np.array([-0.5, -0.25])
    new = ev.derivatives(ev.point(st.pt.x + s))
    B, _ = strategy.update(st, new, _qp(problem, s, []), s, first=True)
    np.testing.assert_allclose(B, 4.0 * np.eye(2), rtol=1e-12)  # y = 4 s: the scaled identity is already exact
    B_later, _ = strategy.update(st, new, _qp(problem, s, []), s, first=False)
    assert not np.allclose(B_later, 4.0 * np.eye(2))  # later iterations: no rescaling


def test_a_steep_start_scales_the_identity_to_bound_the_first_step():
    """HS64-like: |g0| = 1e5 at x0 = (1, 2); the first steepest-descent step is kept to FIRST_STEP_LENGTH * 2."""
    from sqp.hessian_strategy import FIRST_STEP_LENGTH

    problem = build_problem(lambda x: 1e5 * x[0], [1.0, 2.0], lambda x: np.array([1e5, 0.0]), None, [], (), None)
    strategy = DampedBFGS(problem, None)
    _, st = _state(problem, [1.0, 2.0])
    B = strategy.initial(st)
    np.testing.assert_allclose(np.max(np.abs(np.linalg.solve(B, st.der.g))), FIRST_STEP_LENGTH * 2.0, rtol=1e-12)
    hess0 = np.diag([3.0, 4.0])
    np.testing.assert_array_equal(DampedBFGS(problem, hess0).initial(st), hess0)  # hess0 is used as given


def test_convexified_exact_gives_a_positive_definite_model_and_newton_multipliers():
    problem = _circle()
    strategy = ConvexifiedExact(problem, np.array([0.3]))
    ev, st = _state(problem, problem.x0)
    B = strategy.model(ev, st)
    W = ev.lagrangian_hessian(st.pt.x, np.array([0.3]))
    assert np.linalg.eigvalsh(W)[0] < 0 < np.linalg.eigvalsh(B)[0]  # indefinite W, positive-definite model
    st = State(pt=st.pt, der=st.der, B=B, mu=st.mu)
    qp, _, B_used = subproblem(problem, Options().for_problem(problem), st, 0.0, strategy)
    assert qp.found and B_used is B
    # the corrected multipliers are the Newton step's: W d + g - J^T lam = 0
    np.testing.assert_allclose(W @ qp.d + st.der.g - st.der.J.T @ qp.lam_nl, 0.0, atol=1e-10)
    assert strategy.update(st, st.der, qp, qp.d, first=True) == (B, False)


def test_a_nonfinite_user_hessian_gives_no_model():
    con = {"type": "eq", "fun": lambda x: np.array([x @ x - 2]), "jac": lambda x: 2 * x[None, :],
           "hess": lambda x, v: np.full((2, 2), np.nan)}
    problem = build_problem(lambda x: x[0] * x[1], [1.2, -0.7], lambda x: np.array([x[1], x[0]]), None, [con], (),
                            lambda x: np.eye(2))
    ev, st = _state(problem, problem.x0)
    assert ConvexifiedExact(problem, np.array([1.0])).model(ev, st) is None
    assert ev.hessian_nonfinite == "constraints[0]['hess']"


# --- the penalty update (Eq. 13) and the merit line search (Eq. 12) ------------------------------------------------

def test_penalties_follow_powells_update_and_make_the_step_a_descent_direction():
    problem = _circle(hess=False)
    _, st = _state(problem, [1.2, -0.7], mu=[4.0])
    qp = _qp(problem, [-0.05, -0.05], [1.0])
    mu = penalties(problem, st, qp)
    assert mu[0] >= 2.5  # max(|lam|, (mu + |lam|) / 2), Eq. 13
    np.testing.assert_array_equal(st.mu, [4.0])
    # a step that reduces the violation but raises f: the penalty grows until it is a descent direction
    _, st0 = _state(problem, [1.3, 0.5], mu=[0.0])
    d = np.array([0.02, 0.0])
    up = penalties(problem, st0, _qp(problem, d, [0.0]))
    D = directional_derivative(st0.der.g, d, st0.pt.c, st0.der.J @ d, problem.nonlinear, up)
    # N&W Eq. 18.36: mu >= (g.d + d.Bd / 2) / ((1 - rho) dv), dv = 0.06 - 0.008
    np.testing.assert_allclose(up, [(0.01 + 0.5 * 0.0004) / (0.5 * 0.052)], rtol=1e-9)
    assert D < 0.0


def test_line_search_is_a_function_of_its_inputs_and_meets_armijo():
    problem = _circle(hess=False)
    ev, st = _state(problem, [1.2, -0.7], mu=[1.0])
    d = np.array([-0.2, -0.3]) * 0.5
    mu = np.array([1.0])
    before = ev.nfev
    search = line_search(problem, Options().for_problem(problem), ev, st, d, mu)
    assert search.pt is not None and 0 < search.alpha <= 1
    phi0 = merit(st.pt.f, st.pt.c, problem.nonlinear, mu)
    D = directional_derivative(st.der.g, d, st.pt.c, st.der.J @ d, problem.nonlinear, mu)
    assert merit(search.pt.f, search.pt.c, problem.nonlinear, mu) <= phi0 + ARMIJO * search.alpha * D
    np.testing.assert_array_equal(mu, [1.0])
    np.testing.assert_array_equal(st.mu, [1.0])
    assert ev.nfev > before  # only the evaluator's counters move
    again = line_search(problem, Options().for_problem(problem), ev, st, d, mu)
    assert again.alpha == search.alpha and np.array_equal(again.pt.x, search.pt.x)


def test_an_ascent_direction_raises_the_penalties_it_returns_not_the_callers():
    """At x = (1.3, 0.5) (violation 0.06) the step (0.02, 0) reduces the violation but raises f: with mu = 0 it is an
    ascent direction of the merit function; the search raises the penalty to (D + 1) / violation and goes on."""
    problem = _circle(hess=False)
    ev, st = _state(problem, [1.3, 0.5])
    mu = np.zeros(1)
    search = line_search(problem, Options().for_problem(problem), ev, st, np.array([0.02, 0.0]), mu)
    np.testing.assert_allclose(search.mu, [(0.5 * 0.02 + 1.0) / 0.06], rtol=1e-12)
    assert search.pt is not None
    np.testing.assert_array_equal(mu, [0.0])
    np.testing.assert_array_equal(st.mu, [0.0])
    # an ascent direction that also raises the violation: no penalty helps, no point, nothing evaluated
    before = ev.nfev
    up = line_search(problem, Options().for_problem(problem), ev, st, np.array([-0.05, 0.05]), mu)
    assert up.pt is None and ev.nfev == before


def test_merit_search_with_sane_penalties_is_the_line_search():
    problem = _circle(hess=False)
    ev, st = _state(problem, [1.2, -0.7], mu=[1.0])
    qp = _qp(problem, [-0.1, -0.15], [0.5])
    a = merit_search(problem, Options().for_problem(problem), ev, st, qp, np.array([1.0]))
    b = line_search(problem, Options().for_problem(problem), ev, st, qp.d, np.array([1.0]))
    assert a.alpha == b.alpha and np.array_equal(a.pt.x, b.pt.x) and np.array_equal(a.mu, b.mu)


def test_step_bound_lasts_the_first_iterations_only():
    bounded = Options(step_bound=0.5)
    assert bounded_steps(bounded, RESTART_BOUNDED_ITERATIONS - 1).step_bound == 0.5
    assert bounded_steps(bounded, RESTART_BOUNDED_ITERATIONS).step_bound == np.inf
    free = Options()
    assert bounded_steps(free, RESTART_BOUNDED_ITERATIONS) is free


# --- termination: one monitor --------------------------------------------------------------------------------------

def _monitor(problem, st, tol=1e-8, max_iter=50):
    from sqp.kkt import max_violation

    return Monitor(problem, tol, max_iter, st.pt, max_violation(problem, st.pt.x, st.pt.c, st.pt.r))


def test_monitor_stops_at_a_kkt_point_at_the_limit_and_on_a_failed_qp():
    problem = _circle(hess=False)
    options = Options().for_problem(problem)
    _, st = _state(problem, [1.0, -1.0])
    exact = _qp(problem, [0.0, 0.0], [-0.5])  # grad f = (-1, 1) = lam grad c = -0.5 (2, -2)
    mon = _monitor(problem, st)
    assert mon.after_qp(options, State(st.pt, st.der, st.B, st.mu, exact), exact, 0).status is Status.SUCCESS
    assert mon.kkt.stationarity <= 1e-15
    wrong = _qp(problem, [0.0, 0.0], [0.2])
    st_wrong = State(st.pt, st.der, st.B, st.mu, wrong)
    assert mon.after_qp(options, st_wrong, wrong, 3) is None
    assert mon.after_qp(options, st_wrong, wrong, 50).status is Status.MAX_ITER
    failed = mon.after_qp(options, st, _qp(problem, [0.0, 0.0], [0.0], found=False), 7)
    assert failed.status is Status.QP_FAILED and "daqp" in failed.detail and "iteration 7" in failed.detail


def test_monitor_counts_negligible_steps_and_judges_the_stalled_point():
    problem = _circle(hess=False)
    options = Options().for_problem(problem)
    _, st = _state(problem, [1.0, -1.0])
    # multipliers a little off: not SUCCESS at tol 1e-8, but within the ACCEPTABLE level
    close = _qp(problem, [1e-16, 0.0], [-0.5 - 2e-7])
    st = State(st.pt, st.der, st.B, st.mu, close)
    mon = _monitor(problem, st)
    for k in range(STALL_ITERATIONS):
        assert mon.after_qp(options, st, close, k) is None
        stop = mon.after_search(st, st.pt, None, 1.0, k)
        assert (stop is None) == (k < STALL_ITERATIONS - 1)
    assert stop.status is Status.ACCEPTABLE and stop.qp is close
    # far from stationary: the same stall is SMALL_STEP, not a success
    far = _qp(problem, [1e-16, 0.0], [0.3])
    st_far = State(st.pt, st.der, st.B, st.mu, far)
    mon = _monitor(problem, st_far)
    for k in range(STALL_ITERATIONS):
        mon.after_qp(options, st_far, far, k)
        stop = mon.after_search(st_far, st_far.pt, None, 1.0, k)
    assert stop.status is Status.SMALL_STEP
    # no point accepted because every trial was NaN: NONFINITE naming the function
    mon = _monitor(problem, st_far)
    mon.after_qp(options, st_far, far, 0)
    stop = mon.after_search(st_far, None, "fun", 1e-10, 0)
    assert stop.status is Status.NONFINITE and "fun returned NaN" in stop.detail


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_monitor_ends_on_settled_newton_steps_only_at_an_acceptable_point(scale):
    """With exact Hessians, :data:`SETTLED_STEPS` QP steps in a row below :data:`SETTLED_STEP` relative to the point
    end the solve ACCEPTABLE when the point passes the ACCEPTABLE test (its residual is rounding's), and nothing
    less does: one such step, a step just above the level, multipliers outside the ACCEPTABLE level, a damped-BFGS
    model (whose small step says nothing about the distance to a solution)."""
    x = scale * np.array([1.0, -1.0])
    level = SETTLED_STEP * (1.0 + scale)
    off = 2e-7 / min(scale, 1.0)  # multipliers off by a scaled stationarity residual 4e-7 (lam* = -1/2)
    con = {"type": "eq", "fun": lambda z: np.array([z @ z - 2 * scale**2]), "jac": lambda z: 2 * z[None, :],
           "hess": lambda z, v: 2 * v[0] * np.eye(2)}
    for hess in (True, False):
        H = (lambda z: np.array([[0.0, 1.0], [1.0, 0.0]])) if hess else None
        problem = build_problem(lambda z: z[0] * z[1], list(x), lambda z: np.array([z[1], z[0]]), None, [con], (), H)
        options = Options().for_problem(problem)
        _, st = _state(problem, x)
        for d_size, lam, settles in ((0.5 * level, -0.5 - off, True), (2.0 * level, -0.5 - off, False),
                                     (0.5 * level, -0.3, False)):
            qp = _qp(problem, [d_size, 0.0], [lam])
            st = State(st.pt, st.der, st.B, st.mu, qp)
            mon = _monitor(problem, st)
            stops = [mon.after_qp(options, st, qp, k) for k in range(SETTLED_STEPS + 1)]
            assert mon.kkt.stationarity > 1e-8  # (not SUCCESS at tol)
            assert all(stop is None for stop in stops[:SETTLED_STEPS - 1])
            if settles and hess:
                assert stops[SETTLED_STEPS - 1].status is Status.ACCEPTABLE
            else:
                assert all(stop is None for stop in stops), (hess, d_size, lam)
            # a step that is not settled breaks the run
            mon = _monitor(problem, st)
            big = _qp(problem, [2.0 * level, 0.0], [lam])
            for k in range(2 * SETTLED_STEPS):
                step = qp if k % 2 == 0 else big
                assert mon.after_qp(options, State(st.pt, st.der, st.B, st.mu, step), step, k) is None


def test_monitor_detects_divergence_and_stalled_infeasibility():
    problem = build_problem(lambda x: -x[0], [0.0], lambda x: np.array([-1.0]), [(0, None)], [], (), None)
    _, st = _state(problem, [0.0])
    mon = _monitor(problem, st)
    _, far = _state(problem, [1e11])
    step = _qp(problem, [1e11], [])
    assert mon.after_step(State(far.pt, far.der, far.B, far.mu, step), 0.0, 12).status is Status.UNBOUNDED
    _, near = _state(problem, [1e3])
    assert _monitor(problem, st).after_step(State(near.pt, near.der, near.B, near.mu, step), 0.0, 12) is None

    circle = _circle(hess=False)
    _, st = _state(circle, [3.0, 3.0])
    mon = _monitor(circle, st)
    elastic = _qp(circle, [1e-3, 0.0], [1.0], elastic=True)
    stops = [mon.after_step(State(st.pt, st.der, st.B, st.mu, elastic), 16.0, k) for k in range(INFEASIBLE_STALL)]
    assert all(s is None for s in stops[:-1]) and stops[-1].status is Status.INFEASIBLE
    assert "Least violation reached: 1.60e+01" in mon.detail(stops[-1]).detail


def test_monitor_confirms_a_converged_newton_step_without_another_qp():
    problem = _circle(hess=False)
    options = Options().for_problem(problem)
    _, st = _state(problem, [1.0, -1.0])
    mon = _monitor(problem, st)
    good = State(st.pt, st.der, st.B, st.mu, _qp(problem, [1e-9, 0.0], [-0.5]))
    assert mon.confirmed(options, good, 0.0).status is Status.SUCCESS
    off = State(st.pt, st.der, st.B, st.mu, _qp(problem, [1e-9, 0.0], [-0.5 - 1e-8]))
    assert mon.confirmed(options, off, 0.0) is None  # passes tol, not the 1e-2 tol margin

