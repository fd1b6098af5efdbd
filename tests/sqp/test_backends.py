"""``qp_solver="auto"``: the backend chosen from the model's structure, recorded, and the same solve as naming it."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import LinearConstraint

import sqp
from sqp.backends import PREFERENCE, choose_qp_solver

ALL = ["daqp", "piqp", "clarabel", "osqp", "quadprog", "proxqp"]


@pytest.mark.parametrize(
    ("n", "sparse", "expected"),
    [(1, False, "daqp"), (sqp.DENSE_LIMIT, True, "daqp"), (sqp.DENSE_LIMIT + 1, True, "piqp"),
     (sqp.DENSE_LIMIT + 1, False, "daqp")],
)
def test_the_rule(n, sparse, expected):
    assert choose_qp_solver(n, sparse, ALL) == expected


def test_a_missing_pick_falls_back_along_the_preference_list():
    assert PREFERENCE == ("daqp", "piqp", "clarabel", "osqp", "quadprog", "proxqp")
    assert choose_qp_solver(10, False, ["osqp", "quadprog"]) == "osqp"
    assert choose_qp_solver(400, True, ["daqp", "clarabel"]) == "daqp"
    assert choose_qp_solver(400, False, ["proxqp"]) == "proxqp"
    with pytest.raises(ValueError, match="none of daqp"):
        choose_qp_solver(10, False, [])


def test_unknown_name_lists_auto_and_the_installed_backends():
    with pytest.raises(ValueError, match="'auto'") as info:
        sqp.Options(qp_solver="nosuch")
    assert all(name in str(info.value) for name in sqp.installed_solvers())
    with pytest.raises(TypeError, match="qp_solver"):
        sqp.Options(qp_solver=3)  # type: ignore[arg-type]


def _quadratic(n: int, sparse: bool) -> dict:
    """min |x - t|^2 s.t. two-sided difference rows (sparse or dense A)."""
    t = np.linspace(-1.0, 1.0, n)
    A = sp.diags([np.ones(n - 1), -np.ones(n - 1)], [0, 1], shape=(n - 1, n), format="csr")
    return {"fun": lambda x: float((x - t) @ (x - t)), "x0": np.zeros(n), "jac": lambda x: 2 * (x - t),
            "constraints": [LinearConstraint(A if sparse else A.toarray(), -1e-3, 1e-3)]}


@pytest.mark.parametrize(("n", "sparse", "expected"), [(20, True, "daqp"), (sqp.DENSE_LIMIT + 10, True, "piqp"),
                                                       (sqp.DENSE_LIMIT + 10, False, "daqp")])
def test_auto_is_the_named_backend_and_says_which(n, sparse, expected, capsys):
    if expected not in sqp.installed_solvers():
        pytest.skip(f"{expected} not installed")
    auto = sqp.minimize(**_quadratic(n, sparse), verbose=True)
    assert auto.success and auto.qp_solver == expected
    assert f"qp_solver = {expected} (auto: " in capsys.readouterr().out
    named = sqp.minimize(**_quadratic(n, sparse), qp_solver=expected)
    assert named.qp_solver == expected
    assert (auto.nit, auto.nfev) == (named.nit, named.nfev)
    np.testing.assert_array_equal(auto.x, named.x)


def test_a_named_backend_is_kept():
    res = sqp.minimize(**_quadratic(20, True), qp_solver="quadprog")
    assert res.success and res.qp_solver == "quadprog"


def test_options_resolve_per_problem():
    from sqp.build import build_problem

    problem = build_problem(**{k: v for k, v in _quadratic(sqp.DENSE_LIMIT + 10, True).items()}, bounds=None)
    assert sqp.Options().for_problem(problem).qp_solver == "piqp"
    assert sqp.Options(qp_solver="osqp").for_problem(problem).qp_solver == "osqp"
    with pytest.raises(ValueError, match="for_problem"):
        _ = sqp.Options().backends


@pytest.mark.parametrize(("n", "sparse"), [(sqp.DENSE_LIMIT - 10, True), (sqp.DENSE_LIMIT + 10, True),
                                           (sqp.DENSE_LIMIT + 10, False), (4 * sqp.DENSE_LIMIT, True)])
def test_a_large_program_falls_back_to_sparse_backends_only(n, sparse):
    """``qp_solver="auto"`` above DENSE_LIMIT with every Jacobian sparse picks a sparse backend, and its default
    fallbacks leave out the dense ones (an O(n^3) rescue of a large sparse program took 55-111 s a subproblem where
    Clarabel took ~1 s); a program with dense rows is dense anyway and keeps them, as do programs at or below the
    limit, and whenever the caller names the fallbacks or the backend they stay as given."""
    from sqp.build import build_problem
    from sqp.options import DEFAULT_QP_FALLBACKS, DENSE_BACKENDS

    problem = build_problem(**_quadratic(n, sparse), bounds=None)
    auto = sqp.Options().for_problem(problem)
    large = n > sqp.DENSE_LIMIT and sparse
    expected = tuple(b for b in DEFAULT_QP_FALLBACKS if not (large and b in DENSE_BACKENDS))
    assert auto.qp_fallbacks == expected
    assert not large or all(name not in DENSE_BACKENDS for name, _ in auto.backends)
    assert sqp.Options(qp_fallbacks=("quadprog",)).for_problem(problem).qp_fallbacks == ("quadprog",)
    assert sqp.Options(qp_solver="piqp").for_problem(problem).qp_fallbacks == DEFAULT_QP_FALLBACKS


@pytest.mark.parametrize("n", [40, 120])
@pytest.mark.parametrize("seed", [0, 1])
def test_an_interior_point_run_out_of_iterations_is_not_retried_looser(monkeypatch, n, seed):
    """PIQP stopped at its iteration limit: the next backend is asked at once (no retry: see
    ``sqp.qp_call._ran_out``), and that backend's answer is the QP's; a PIQP failure of another kind keeps its retry."""
    from sqp import qp_call

    rng = np.random.default_rng(seed)
    M = rng.standard_normal((n, n))
    P = sp.csc_matrix(M @ M.T + n * np.eye(n))
    q = rng.standard_normal(n)
    G = sp.csc_matrix(rng.standard_normal((n // 2, n)))
    h = np.abs(rng.standard_normal(n // 2))
    calls = []
    solve = qp_call._backends.solve_problem

    def counted(problem, solver, initvals=None, **options):
        calls.append(solver)
        return solve(problem, solver=solver, initvals=initvals, **options)

    monkeypatch.setattr(qp_call._backends, "solve_problem", counted)
    E, e = sp.csc_matrix((0, n)), np.zeros(0)
    sol, used = qp_call.solve_qp([("piqp", {"max_iter": 1}), ("clarabel", {})], P, q, G, h, E, e, None, None,
                                 None, 1.0)
    assert calls == ["piqp", "clarabel"] and used == "clarabel"
    reference = qp_call.solve_qp([("clarabel", {})], P, q, G, h, E, e, None, None, None, 1.0)[0]
    np.testing.assert_allclose(sol.x, reference.x, rtol=0, atol=1e-9 * max(1.0, float(np.abs(reference.x).max())))
    calls.clear()
    monkeypatch.setattr(qp_call, "_ran_out", lambda solver, sol: False)
    qp_call.solve_qp([("piqp", {"max_iter": 1}), ("clarabel", {})], P, q, G, h, E, e, None, None, None, 1.0)
    assert calls == ["piqp", "piqp", "clarabel"]


def test_daqp_runs_with_an_iteration_limit_far_above_what_its_answers_need(monkeypatch):
    """DAQP is asked with ``iter_limit`` (2 000: its answers took at most 236 iterations on the guidewire's programs;
    a failing elastic QP at its default 10 000 cost 10 s); a small QP's answer is unchanged."""
    from sqp import backends

    seen = []
    solve = backends._daqp_module.solve

    def recorded(*args, **kwargs):
        seen.append(kwargs.get("iter_limit"))
        return solve(*args, **kwargs)

    monkeypatch.setattr(backends._daqp_module, "solve", recorded)
    res = sqp.minimize(lambda x: float((x - 2.0) @ (x - 2.0)), np.zeros(3), jac=lambda x: 2.0 * (x - 2.0),
                       constraints=[LinearConstraint(np.ones((1, 3)), -np.inf, 3.0)], qp_solver="daqp")
    assert res.success and seen and set(seen) == {backends.DEFAULT_QP_OPTIONS["daqp"]["iter_limit"]}
    np.testing.assert_allclose(res.x, np.ones(3), atol=1e-8)
