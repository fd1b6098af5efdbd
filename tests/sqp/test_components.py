"""Each piece of the engine alone: damped BFGS, merit derivative, elastic QP, statuses, input checks."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import BFGS, Bounds, LinearConstraint, NonlinearConstraint

import sqp
from sqp.backends import DEFAULT_QP_OPTIONS
from sqp.hessian import damped_bfgs_update
from sqp.merit import directional_derivative, merit
from sqp.problem import Rows
from sqp.subproblem import linearise, solve_subproblem


def test_damped_bfgs_matches_scipy_damp_update():
    rng = np.random.default_rng(1)
    n = 6
    oracle = BFGS(exception_strategy="damp_update", min_curvature=0.2, init_scale=1.0)
    oracle.initialize(n, "hess")
    B = np.eye(n)
    damped_seen = 0
    for k in range(12):
        s = rng.standard_normal(n)
        y = rng.standard_normal(n) if k % 2 else s * 2.0 + 0.1 * rng.standard_normal(n)  # both regimes
        B, damped = damped_bfgs_update(B, s, y)
        damped_seen += damped
        oracle.update(s, y)
        np.testing.assert_allclose(B, oracle.get_matrix(), rtol=1e-9, atol=1e-10)
        assert np.all(np.linalg.eigvalsh(B) > 0)
    assert 0 < damped_seen < 12


def test_merit_directional_derivative_matches_finite_difference():
    rng = np.random.default_rng(2)
    n, m = 4, 3
    Q = rng.standard_normal((n, n))
    f = lambda x: 0.5 * x @ Q @ Q.T @ x + x.sum()  # noqa: E731
    g = lambda x: Q @ Q.T @ x + 1.0  # noqa: E731
    W = rng.standard_normal((m, n))
    c = lambda x: np.array([np.sin(W[0] @ x) + 2.0, W[1] @ x - 3.0, (W[2] @ x) ** 2 + 1.0])  # noqa: E731
    J = lambda x: np.vstack([np.cos(W[0] @ x) * W[0], W[1], 2 * (W[2] @ x) * W[2]])  # noqa: E731
    rows = Rows.from_bounds(np.array([0.0, 0.0, -np.inf]), np.array([0.0, np.inf, 0.5]))  # eq, lower, upper
    mu = np.array([2.0, 3.0, 0.7])
    x = rng.standard_normal(n) * 0.3
    d = rng.standard_normal(n)
    t = 1e-7
    D = directional_derivative(g(x), t * d, c(x), J(x) @ (t * d), rows, mu) / t
    fd = (merit(f(x + t * d), c(x + t * d), rows, mu) - merit(f(x), c(x), rows, mu)) / t
    assert rows.violation(c(x)).min() > 1e-3  # away from the kinks
    assert D == pytest.approx(fd, rel=1e-5, abs=1e-6)


def test_elastic_qp_solves_an_inconsistent_linearisation():
    # c(x) = x0^2 + x1^2 - 1 = 0 linearised at the origin: 0 d - 1 = 0 has no solution
    rows = Rows.from_bounds(np.zeros(1), np.zeros(1))
    nl = linearise(np.zeros((1, 2)), np.array([-1.0]), rows)
    lin = linearise(np.zeros((0, 2)), np.zeros(0), Rows.from_bounds(np.zeros(0), np.zeros(0)))
    box = np.full(2, np.inf)
    backends = [("osqp", DEFAULT_QP_OPTIONS["osqp"])]
    plain = solve_subproblem(np.eye(2), np.array([1.0, 1.0]), nl, lin, -box, box, backends=backends)
    assert not plain.found
    el = solve_subproblem(np.eye(2), np.array([1.0, 1.0]), nl, lin, -box, box, backends=backends,
                          elastic_penalty=100.0)
    assert el.found and el.elastic
    np.testing.assert_allclose(el.d, [-1.0, -1.0], atol=1e-6)  # the slack absorbs the row; d = -B^-1 g
    assert el.slack == pytest.approx(1.0, abs=1e-6)
    # and the whole solve continues from there to the constrained minimum of x0 + x1 on the unit circle
    res = sqp.minimize(lambda x: x[0] + x[1], [0.0, 0.0], jac=lambda x: np.ones(2),
                       constraints={"type": "eq", "fun": lambda x: np.array([x @ x - 1]),
                                    "jac": lambda x: 2 * x[None, :]})
    assert res.success, res.message
    np.testing.assert_allclose(res.x, -np.sqrt(0.5) * np.ones(2), atol=1e-7)


def test_equality_only_qp_is_solved_directly_and_matches_the_backends():
    import qpsolvers

    rng = np.random.default_rng(3)
    n, m = 30, 4
    R = rng.standard_normal((n, n))
    B, g = R @ R.T + n * np.eye(n), rng.standard_normal(n)
    J, c = rng.standard_normal((m, n)), rng.standard_normal(m)
    rows = Rows.from_bounds(np.zeros(m), np.zeros(m))
    lin = linearise(np.zeros((0, n)), np.zeros(0), Rows.from_bounds(np.zeros(0), np.zeros(0)))
    box = np.full(n, np.inf)
    step = solve_subproblem(B, g, linearise(J, c, rows), lin, -box, box, backends=[("osqp", {})])
    assert step.found and step.status == "kkt"  # no backend asked (OSQP at its defaults would be far less exact)
    ref = qpsolvers.solve_problem(qpsolvers.Problem(B, g, A=J, b=-c), solver="daqp")
    np.testing.assert_allclose(step.d, ref.x, atol=1e-10)
    np.testing.assert_allclose(step.lam_nl, -ref.y, atol=1e-9)  # engine convention: grad f = J^T lam
    np.testing.assert_allclose(B @ step.d + g, J.T @ step.lam_nl, atol=1e-9)
    # a repeated row makes the KKT matrix singular: whichever path answers, the step is the same and the
    # multipliers (no longer unique) still satisfy stationarity
    J2, c2 = np.vstack([J, J[:1]]), np.concatenate([c, c[:1]])
    rows2 = Rows.from_bounds(np.zeros(m + 1), np.zeros(m + 1))
    step2 = solve_subproblem(B, g, linearise(J2, c2, rows2), lin, -box, box,
                             backends=[("daqp", DEFAULT_QP_OPTIONS["daqp"]), ("piqp", DEFAULT_QP_OPTIONS["piqp"])])
    assert step2.found
    np.testing.assert_allclose(step2.d, ref.x, atol=1e-6)
    np.testing.assert_allclose(B @ step2.d + g, J2.T @ step2.lam_nl, atol=1e-6)
    # inconsistent equalities (the same row asking for two values): no step, and no crash
    c3 = np.concatenate([c, c[:1] + 1.0])
    step3 = solve_subproblem(B, g, linearise(J2, c3, rows2), lin, -box, box,
                             backends=[("daqp", DEFAULT_QP_OPTIONS["daqp"])])
    assert not step3.found


def test_sparse_elastic_qp_matches_the_dense_one():
    """A sparse model Hessian keeps the elastic QP sparse (PIQP's sparse backend), with the dense QP's answer."""
    import scipy.sparse as sp

    rng = np.random.default_rng(3)
    n = 6
    A = rng.standard_normal((n, n))
    B = A @ A.T + n * np.eye(n)
    g = rng.standard_normal(n)
    M = rng.standard_normal((2, n))
    rows = Rows.from_bounds(np.array([0.0, 0.0]), np.array([0.0, np.inf]))  # an equality and a lower row
    nl = linearise(np.vstack([M[0], M[0]]), np.array([-1.0, -5.0]), rows)  # the same direction, inconsistent
    lin = linearise(np.zeros((0, n)), np.zeros(0), Rows.from_bounds(np.zeros(0), np.zeros(0)))
    box = np.full(n, np.inf)
    dense = solve_subproblem(B, g, nl, lin, -box, box, backends=[("piqp", {})], elastic_penalty=50.0)
    sparse = solve_subproblem(sp.csc_matrix(B), g, nl, lin, -box, box, backends=[("piqp", {})],
                              elastic_penalty=50.0)
    assert dense.found and sparse.found and dense.elastic and sparse.elastic
    np.testing.assert_allclose(sparse.d, dense.d, atol=1e-6)
    np.testing.assert_allclose(sparse.lam_nl, dense.lam_nl, atol=1e-5)
    assert sparse.slack == pytest.approx(dense.slack, abs=1e-6) and sparse.slack > 0.1


def test_max_iter_status():
    res = sqp.minimize(lambda x: (x[0] - 3) ** 4 + x[1] ** 2, [0.0, 1.0], max_iter=1)
    assert not res.success
    assert res.status == sqp.Status.MAX_ITER.code
    assert "max_iter" in res.message and res.nit == 1


def test_nan_objective_has_its_own_status():
    res = sqp.minimize(lambda x: np.nan, [1.0, 2.0])
    assert not res.success and res.status == sqp.Status.NONFINITE.code
    assert "NaN" in res.message


def test_nan_inside_the_line_search_is_rejected_not_accepted():
    # f is NaN for x0 > 1.5; the full first step lands there; the answer must still be the true minimiser
    f = lambda x: np.nan if x[0] > 1.5 else (x[0] - 1.0) ** 2 + x[1] ** 2  # noqa: E731
    g = lambda x: np.array([2 * (x[0] - 1.0), 2 * x[1]])  # noqa: E731
    res = sqp.minimize(f, [-3.0, 1.0], jac=g, hess0=0.05 * np.eye(2))
    assert res.success, res.message
    np.testing.assert_allclose(res.x, [1.0, 0.0], atol=1e-6)
    assert all(np.isfinite(r.f) for r in res.history)


def test_infeasible_problem_reports_why():
    res = sqp.minimize(lambda x: x @ x, [1.0, 1.0], jac=lambda x: 2 * x,
                       constraints={"type": "ineq", "fun": lambda x: np.array([-(x @ x) - 1.0]),
                                    "jac": lambda x: -2 * x[None, :]})
    assert not res.success
    assert res.status == sqp.Status.INFEASIBLE.code, res.message
    assert "infeasible" in res.message
    assert res.maxcv == pytest.approx(1.0, abs=1e-6)


def test_inconsistent_linear_constraints_and_bounds():
    res = sqp.minimize(lambda x: x @ x, [0.0, 0.0], bounds=[(0, 1), (0, 1)],
                       constraints=LinearConstraint([[1.0, 1.0]], 3.0, 4.0))
    assert not res.success and res.status == sqp.Status.LINEAR_INFEASIBLE.code


def test_callback_stop_iteration():
    seen = []

    def cb(intermediate_result):
        seen.append(intermediate_result.x.copy())
        if len(seen) == 2:
            raise StopIteration

    res = sqp.minimize(lambda x: (x[0] - 3) ** 4 + (x[1] + 1) ** 2, [0.0, 0.0], callback=cb)
    assert res.status == sqp.Status.CALLBACK.code and not res.success and len(seen) == 2


def test_finite_difference_points_stay_inside_bounds_and_linear_rows_stay_exact():
    lo, hi = np.array([1.0, -2.0, 0.0]), np.array([3.0, 2.0, 0.5])

    def f(x):
        if np.any(x < lo) or np.any(x > hi):
            raise AssertionError(f"evaluated outside the bounds at {x}")
        return (x[0] - 5) ** 2 + (x[1] - 1) ** 2 + x[2] ** 2 + x[0] * x[2]

    lin = LinearConstraint([[1.0, 1.0, 1.0]], -np.inf, 3.0)
    xs = []
    res = sqp.minimize(f, [2.0, 0.0, 0.25], bounds=Bounds(lo, hi), constraints=[lin],
                       callback=lambda xk: xs.append(xk))
    assert res.success, res.message
    assert all(x.sum() <= 3.0 + 1e-12 for x in xs)
    np.testing.assert_allclose(res.x, [3.0, 0.0, 0.0], atol=1e-7)  # x0 at its bound, sum row active
    assert res.bound_multipliers[2] > 0  # x2 at its lower bound


def test_multiplier_convention_and_blocks():
    # min -x0 - x1 s.t. x0^2 + x1^2 <= 2 (NonlinearConstraint upper side), x0 - x1 == 0 (dict eq)
    con1 = NonlinearConstraint(lambda x: x @ x, -np.inf, 2.0, jac=lambda x: 2 * x[None, :])
    con2 = {"type": "eq", "fun": lambda x: np.array([x[0] - x[1]]), "jac": lambda x: np.array([[1.0, -1.0]])}
    res = sqp.minimize(lambda x: -x.sum(), [0.5, 0.2], jac=lambda x: -np.ones(2), constraints=[con1, con2])
    assert res.success, res.message
    np.testing.assert_allclose(res.x, [1.0, 1.0], atol=1e-8)
    lam1, lam2 = res.constraint_multipliers
    assert lam1.shape == (1,) and lam2.shape == (1,)
    assert lam1[0] == pytest.approx(-0.5, abs=1e-7)  # upper side active -> negative
    grad = -np.ones(2)
    np.testing.assert_allclose(grad, lam1[0] * 2 * res.x + lam2[0] * np.array([1.0, -1.0]), atol=1e-7)
    # SLSQP's array: the equality row first, then the inequality as 2 - x @ x >= 0 with a nonnegative multiplier
    np.testing.assert_allclose(res.multipliers, [lam2[0], -lam1[0]])
    assert res.kkt["stationarity"] <= 1e-8 and res.kkt["feasibility"] <= 1e-8
    assert len(res.history) == res.nit


@pytest.mark.parametrize("backend", sqp.installed_solvers())
def test_every_installed_backend_solves_hs71(backend):
    f = lambda x: x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2]  # noqa: E731
    g = lambda x: np.array([x[3] * (2 * x[0] + x[1] + x[2]), x[0] * x[3], x[0] * x[3] + 1,  # noqa: E731
                            x[0] * (x[0] + x[1] + x[2])])
    cons = [{"type": "ineq", "fun": lambda x: np.array([x.prod() - 25]),
             "jac": lambda x: np.array([[x[1] * x[2] * x[3], x[0] * x[2] * x[3], x[0] * x[1] * x[3],
                                         x[0] * x[1] * x[2]]])},
            {"type": "eq", "fun": lambda x: np.array([x @ x - 40]), "jac": lambda x: 2 * x[None, :]}]
    res = sqp.minimize(f, [1, 5, 5, 1], jac=g, bounds=[(1, 5)] * 4, constraints=cons, qp_solver=backend)
    assert res.success, res.message
    assert res.fun == pytest.approx(17.0140172891563, rel=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "exc", "text"),
    [
        ({"x0": np.zeros((2, 2))}, ValueError, "x0 has shape"),
        ({"x0": [1.0, np.nan]}, ValueError, "non-finite"),
        ({"bounds": [(0, 1)] * 3}, ValueError, "bounds has 3 pairs; expected 2"),
        ({"bounds": [(0, 1), (2, 1)]}, ValueError, "bounds[1] has lo = 2.0 > hi = 1.0"),
        ({"constraints": {"type": "ineqq", "fun": lambda x: x[0]}}, ValueError, "'ineqq'"),
        ({"jac": lambda x: np.ones(3)}, ValueError, "jac returned shape (3,)"),
        ({"fun": lambda x: x}, ValueError, "must return a scalar"),
        ({"qp_solver": "nosuch"}, ValueError, "installed: "),
        ({"constraints": [{"type": "eq", "fun": lambda x: x[0], "jac": lambda x: np.ones((1, 3))}]}, ValueError,
         "expected (1, 2)"),
        ({"tol": -1.0}, ValueError, "tol"),
        ({"constraints": [42]}, TypeError, "constraints[0] is a int"),
    ],
)
def test_bad_input_is_refused_before_any_work(kwargs, exc, text):
    calls = []

    def fun(x):
        calls.append(1)
        return float(np.sum(x**2))

    args = {"fun": fun, "x0": [1.0, 2.0]} | kwargs
    with pytest.raises(exc) as info:
        sqp.minimize(**args)
    assert text in str(info.value)


@pytest.mark.parametrize("backend", ["daqp", "osqp"])
def test_exact_sparse_hessian_and_sparse_jacobian(backend):
    """min sum (x_i - t_i)^2 on the sphere |x|^2 = 1: exact answer t/|t|; Newton-fast with the exact Hessian."""
    import scipy.sparse as sps

    n = 40
    t = np.linspace(1.0, 2.0, n)
    con = NonlinearConstraint(lambda x: np.array([x @ x]), 1.0, 1.0, jac=lambda x: sps.csr_matrix(2 * x[None, :]),
                              hess=lambda x, v: sps.identity(n, format="csc") * (2 * v[0]))
    res = sqp.minimize(lambda x: np.sum((x - t) ** 2), np.ones(n) / np.sqrt(n), jac=lambda x: 2 * (x - t),
                       constraints=[con], hess=lambda x: sps.identity(n, format="csc") * 2.0, qp_solver=backend)
    assert res.success, res.message
    np.testing.assert_allclose(res.x, t / np.linalg.norm(t), atol=1e-8)
    assert res.nit <= 8  # Newton's method, not BFGS's hundreds of steps
    bfgs = sqp.minimize(lambda x: np.sum((x - t) ** 2), np.ones(n) / np.sqrt(n), jac=lambda x: 2 * (x - t),
                        constraints=[con], qp_solver=backend)
    assert bfgs.success and res.nit < bfgs.nit


def test_multipliers0_warm_start_and_its_shape_check():
    con = {"type": "eq", "fun": lambda x: np.array([x @ x - 1]), "jac": lambda x: 2 * x[None, :],
           "hess": lambda x, v: 2 * v[0] * np.eye(2)}
    f, g, H = (lambda x: x[0] + 2 * x[1]), (lambda x: np.array([1.0, 2.0])), (lambda x: np.zeros((2, 2)))
    cold = sqp.minimize(f, [0.0, -1.0], jac=g, constraints=[con], hess=H)
    warm = sqp.minimize(f, cold.x + 1e-3, jac=g, constraints=[con], hess=H, multipliers0=cold.constraint_multipliers)
    assert cold.success and warm.success
    np.testing.assert_allclose(warm.x, -np.array([1.0, 2.0]) / np.sqrt(5.0), atol=1e-9)
    assert warm.nit <= 3
    with pytest.raises(ValueError, match="multipliers0"):
        sqp.minimize(f, [0.0, -1.0], jac=g, constraints=[con], hess=H, multipliers0=[np.zeros(3)])


def test_newton_multipliers_undo_the_augmented_lagrangian_term():
    """With ``B = W + rho C^T C`` (``W`` indefinite) the QP solves ``B d + g - J^T lam = 0``; the corrected
    multipliers solve ``W d + g - J^T lam' = 0``: the step's own Newton multipliers, used by the KKT test."""
    from sqp.build import build_problem
    from sqp.hessian import convexify
    from sqp.iterate import Evaluator, State
    from sqp.multipliers import al_rows, equality_rows, held_rows, newton_multipliers
    from sqp.options import Options
    from sqp.step import qp_step

    con = {"type": "eq", "fun": lambda x: np.array([x @ x - 2]), "jac": lambda x: 2 * x[None, :],
           "hess": lambda x, v: 2 * v[0] * np.eye(2)}
    problem = build_problem(lambda x: x[0] * x[1], [1.2, -0.7], lambda x: np.array([x[1], x[0]]), None, [con], (),
                            lambda x: np.array([[0.0, 1.0], [1.0, 0.0]]))
    ev = Evaluator(problem)
    pt = ev.point(problem.x0)
    der = ev.derivatives(pt)
    lam = np.array([0.3])
    W = ev.lagrangian_hessian(pt.x, lam)
    assert np.linalg.eigvalsh(W)[0] < 0  # indefinite: the term is needed
    rows = al_rows(problem, lam)
    B, delta, rho = convexify(W, 0.0, equality_rows(problem, der.J, rows), 0.0)
    assert delta == 0.0 and rho > 0.0
    st = State(pt=pt, der=der, B=B, mu=np.zeros(1))
    qp, _, _ = qp_step(problem, Options().for_problem(problem), st, 0.0)
    assert qp.found and not qp.elastic
    np.testing.assert_allclose(B @ qp.d + der.g - der.J.T @ qp.lam_nl, 0.0, atol=1e-10)
    fixed = newton_multipliers(problem, st, qp, rows, rho, held_rows(problem, st, qp))
    np.testing.assert_allclose(W @ qp.d + der.g - der.J.T @ fixed.lam_nl, 0.0, atol=1e-10)
    assert abs(fixed.lam_nl[0] - qp.lam_nl[0]) > 1e-3  # a real correction, not a no-op


def test_newton_multipliers_leave_a_row_the_qp_released_at_zero():
    """An inequality in ``C`` (it carried a multiplier, e.g. a warm start's) that the QP leaves inactive gets no
    multiplier from the correction: ``-rho C_i d`` is no force, and carrying it would keep the row in the next ``C``
    (:func:`~sqp.multipliers.al_rows`) for ever. The rows the QP kept are corrected as before."""
    from sqp.build import build_problem
    from sqp.hessian import convexify
    from sqp.iterate import Evaluator, State
    from sqp.multipliers import al_rows, equality_rows, held_rows, newton_multipliers
    from sqp.options import Options
    from sqp.step import qp_step

    eq = {"type": "eq", "fun": lambda x: np.array([x @ x - 2]), "jac": lambda x: 2 * x[None, :],
          "hess": lambda x, v: 2 * v[0] * np.eye(2)}
    ineq = {"type": "ineq", "fun": lambda x: np.array([4 - x[0] ** 2]), "jac": lambda x: np.array([[-2 * x[0], 0]]),
            "hess": lambda x, v: -2 * v[0] * np.diag([1.0, 0.0])}
    for start, stale in (([1.2, -0.7], 0.3), ([0.8, -1.3], 1.0), ([1.5, -0.4], 0.05)):
        # (W = [[1 + 2 stale, 2], [2, 1]]: indefinite for stale < 1.5, so the term is needed)
        problem = build_problem(lambda x: 2 * x[0] * x[1], start, lambda x: 2 * np.array([x[1], x[0]]), None,
                                [eq, ineq], (), lambda x: np.array([[0.0, 2.0], [2.0, 0.0]]))
        ev = Evaluator(problem)
        pt = ev.point(problem.x0)
        der = ev.derivatives(pt)
        lam = np.array([-0.5, stale])  # (the inequality, 4 - x0^2 >= 0, is far from active)
        rows = al_rows(problem, lam)
        assert rows.tolist() == [0, 1]
        B, _, rho = convexify(ev.lagrangian_hessian(pt.x, lam), 0.0, equality_rows(problem, der.J, rows), 0.0)
        assert rho > 0.0
        st = State(pt=pt, der=der, B=B, mu=np.zeros(2))
        qp, _, _ = qp_step(problem, Options().for_problem(problem), st, 0.0)
        assert qp.found and qp.lam_nl[1] == 0.0 and abs(der.J[1] @ qp.d) > 1e-3  # released, and the row moved
        fixed = newton_multipliers(problem, st, qp, rows, rho, held_rows(problem, st, qp))
        assert fixed.lam_nl[1] == 0.0
        assert fixed.lam_nl[0] == pytest.approx(qp.lam_nl[0] - rho * float(der.J[0] @ qp.d), rel=1e-12)
        assert al_rows(problem, fixed.lam_nl).tolist() == [0]


def test_held_rows_are_the_rows_the_qp_step_keeps_at_a_bound():
    """An interior-point QP leaves tiny multipliers on inactive rows: a row is held only when its linearisation sits
    at the bound its multiplier loads; two-sided rows by the multiplier's sign; equalities always."""
    from sqp.build import build_problem
    from sqp.iterate import Evaluator, State
    from sqp.multipliers import held_rows
    from sqp.subproblem import QPStep

    rows = [{"type": "eq", "fun": lambda x: np.array([x[0] + x[1] - 1.0]), "jac": lambda x: np.array([[1.0, 1.0]])},
            {"type": "ineq", "fun": lambda x: np.array([x[0], x[1], 2.0 - x[0]]),
             "jac": lambda x: np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]])}]
    for x0, d in (([0.25, 0.75], [-0.25, 0.25]), ([1.5, -0.5], [0.5, -0.5]), ([0.4, 0.6], [0.1, -0.1])):
        problem = build_problem(lambda x: x @ x, x0, lambda x: 2 * x, None, rows, ())
        ev = Evaluator(problem)
        pt = ev.point(problem.x0)
        st = State(pt=pt, der=ev.derivatives(pt), B=np.eye(2), mu=np.zeros(4))
        lin = pt.c + st.der.J @ np.asarray(d)
        lam = np.where(np.abs(lin) < 1e-12, 0.7, 1e-11)  # loaded where at the bound, IPM noise elsewhere
        lam[0] = -0.3  # (the equality: held whatever its multiplier)
        qp = QPStep(d=np.asarray(d, float), lam_nl=lam, lam_lin=np.zeros(0), z=np.zeros(0), found=True,
                    elastic=False, slack=0.0, status="optimal")
        expected = [0] + [1 + i for i in range(3) if abs(lin[1 + i]) < 1e-12]
        assert held_rows(problem, st, qp).tolist() == expected


def test_newton_sqp_ends_without_a_confirming_qp_when_the_step_already_converged():
    """Near a solution the last QP's multipliers pass the KKT test at the new point with the wide margin: the
    solve stops there (one Hessian per iteration, not one more) with residuals far below tol."""
    con = {"type": "eq", "fun": lambda x: np.array([x @ x - 1]), "jac": lambda x: 2 * x[None, :],
           "hess": lambda x, v: 2 * v[0] * np.eye(2)}
    f, g, H = (lambda x: x[0] + 2 * x[1]), (lambda x: np.array([1.0, 2.0])), (lambda x: np.zeros((2, 2)))
    exact = -np.array([1.0, 2.0]) / np.sqrt(5.0)
    res = sqp.minimize(f, exact + 1e-4, jac=g, constraints=[con], hess=H, multipliers0=[np.array([-np.sqrt(5) / 2])])
    assert res.success and res.nit <= 3
    assert res.nhev == res.nit  # no confirming Hessian (and QP) after the last step
    assert max(res.kkt.values()) <= 1e-10
    np.testing.assert_allclose(res.x, exact, atol=1e-12)


def test_hess0_with_exact_hessians_is_shape_checked_only():
    """With ``hess`` given, ``hess0`` is not used (exact Hessians replace it): a wrong shape is still an error
    before any solve, an indefinite one is not."""
    f, g, H = (lambda x: float(x @ x)), (lambda x: 2 * x), (lambda x: 2 * np.eye(2))
    with pytest.raises(ValueError, match="hess0 has shape"):
        sqp.minimize(f, [1.0, 2.0], jac=g, hess=H, hess0=np.eye(3))
    res = sqp.minimize(f, [1.0, 2.0], jac=g, hess=H, hess0=-np.eye(2))
    assert res.success and np.allclose(res.x, 0.0, atol=1e-12)
    with pytest.raises(ValueError, match="negative eigenvalue"):  # without hess it is the BFGS start: checked
        sqp.minimize(f, [1.0, 2.0], jac=g, hess0=-np.eye(2))
