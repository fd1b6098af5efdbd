"""The peers every benchmark compares with, on a :class:`_problems.Problem`: scipy SLSQP, trust-constr, IPOPT.

With exact Hessians (:func:`_problems.has_exact_hessians`) trust-constr and IPOPT get them; otherwise trust-constr
gets the objective's (scipy's BFGS without one) and BFGS for the constraints, IPOPT its limited-memory quasi-Newton.
Every runner returns ``x``, ``f``, ``success``, ``message``, ``nit``, ``nfev`` (objective evaluations, counted) and
``time``: the wall time of the ``minimize`` call alone (conversions and sparsity patterns are prepared before it).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp
from _environment import ipopt_available
from _problems import Problem, as_dicts, dense, has_exact_hessians, trust_constr_constraints
from _structure_limit import run_structure_limit
from scipy.optimize import LinearConstraint, minimize

#: Default iteration caps of the peers (generous: SLSQP needs about n iterations on the guidewire problems).
PEER_MAX_ITER = {"SLSQP": 5000, "trust-constr": 1000, "IPOPT": 3000}
#: IPOPT's options besides the iteration cap (``tol`` as scipy-free peers use it).
IPOPT_OPTIONS = {"print_level": 0, "sb": "yes", "tol": 1e-8}
#: The display name of :func:`_structure_limit.run_structure_limit`.
STRUCTURE_LIMIT = "structure limit"


class FixedPattern:
    """Matrices on one fixed sparsity pattern, as ``coo_array`` (cyipopt needs the same coordinates every call).

    The pattern is the union of the nonzeros of ``samples`` (plus the diagonal when ``diagonal``); a later matrix
    with a nonzero outside it raises ``ValueError`` rather than silently dropping it.
    """

    def __init__(self, samples: Sequence[Any], shape: tuple[int, int], *, diagonal: bool = False) -> None:
        mask = np.zeros(shape, dtype=bool)
        for sample in samples:
            mask |= dense(sample).reshape(shape) != 0.0
        if diagonal:
            mask[np.diag_indices(min(shape))] = True
        self.shape = shape
        self.rows, self.cols = np.nonzero(mask)
        self.linear = self.rows * shape[1] + self.cols  # increasing (row-major)

    def __call__(self, matrix: Any) -> sp.coo_array:
        if sp.issparse(matrix):
            coo = sp.coo_array(matrix)
            linear = coo.row.astype(np.int64) * self.shape[1] + coo.col
            pos = np.minimum(np.searchsorted(self.linear, linear), max(self.linear.size - 1, 0))
            inside = self.linear[pos] == linear if self.linear.size else np.zeros(linear.size, bool)
            if not np.all(inside | (coo.data == 0.0)):
                raise ValueError("a matrix has a nonzero outside the sampled sparsity pattern")
            data = np.bincount(pos[inside], weights=coo.data[inside], minlength=self.linear.size)
        else:
            data = np.asarray(matrix, dtype=float).reshape(self.shape)[self.rows, self.cols]
        return sp.coo_array((data, (self.rows, self.cols)), shape=self.shape)


def ipopt_constraints(problem: Problem, exact: bool, *, sparse: bool = True) -> tuple[list[dict[str, Any]], Any]:
    """IPOPT's constraint dicts and objective Hessian (None unless ``exact``).

    ``sparse``: Jacobians (and, if ``exact``, Hessians) as ``coo_array`` on fixed patterns sampled at two random
    perturbations of ``x0`` (so no entry is zero by accident there); otherwise the dicts of :func:`as_dicts`.
    """
    n = problem.n
    dicts = as_dicts(problem, with_hess=exact, dense_jac=False)
    hess = problem.hess if exact else None
    if not sparse:
        return dicts, hess
    rng = np.random.default_rng(0)
    points = [problem.x0 + 0.1 * rng.standard_normal(n) for _ in range(2)]
    out: list[dict[str, Any]] = []
    for con in dicts:
        m = int(np.atleast_1d(con["fun"](problem.x0)).size)
        jp = FixedPattern([con["jac"](p) for p in points], (m, n))
        d = {"type": con["type"], "fun": con["fun"], "jac": lambda x, j=con["jac"], jp=jp: jp(j(x))}
        if exact:
            hp = FixedPattern([con["hess"](p, rng.standard_normal(m)) for p in points], (n, n))
            d["hess"] = lambda x, v, h=con["hess"], hp=hp: hp(h(x, v))
        out.append(d)
    if hess is None:
        return out, None
    op = FixedPattern([hess(p) for p in points], (n, n), diagonal=True)
    return out, lambda x: op(hess(x))


def counted(fun: Callable[[Any], float]) -> tuple[Callable[[Any], float], list[int]]:
    """``fun`` counting its calls in the returned one-element list."""
    count = [0]

    def wrapped(x: Any) -> float:
        count[0] += 1
        return fun(x)

    return wrapped, count


def _result(res: Any, count: list[int], elapsed: float) -> dict[str, Any]:
    message = res.message.decode() if isinstance(res.message, bytes) else str(res.message)
    return {"x": np.asarray(res.x), "f": float(res.fun), "success": bool(res.success), "message": message,
            "nit": int(res.nit), "nfev": count[0], "time": elapsed}


def run_slsqp(problem: Problem, *, maxiter: int = PEER_MAX_ITER["SLSQP"]) -> dict[str, Any]:
    """scipy SLSQP (scipy's default tolerances, ``maxiter`` raised), every constraint as a dict."""
    cons = as_dicts(problem)
    fun, count = counted(problem.fun)
    start = time.perf_counter()
    res = minimize(fun, problem.x0, jac=problem.jac, bounds=problem.bounds, constraints=cons, method="SLSQP",
                   options={"maxiter": maxiter})
    return _result(res, count, time.perf_counter() - start)


def run_trust_constr(problem: Problem, *, maxiter: int = PEER_MAX_ITER["trust-constr"],
                     linear_as_dicts: bool = False) -> dict[str, Any]:
    """scipy trust-constr: exact Hessians when offered, else the objective's (scipy's BFGS without) and BFGS for the
    constraints; ``linear_as_dicts``: see :func:`trust_constr_constraints`."""
    cons = trust_constr_constraints(problem, has_exact_hessians(problem), linear_as_dicts=linear_as_dicts)
    options: dict[str, Any] = {"maxiter": maxiter}
    if len(set(_sparse_jacobians(cons, problem.x0))) > 1:
        options["sparse_jacobian"] = True  # (trust-constr refuses a mixture: sparse for all, as it recommends)
    fun, count = counted(problem.fun)
    start = time.perf_counter()
    res = minimize(fun, problem.x0, jac=problem.jac, hess=problem.hess, bounds=problem.bounds, constraints=cons,
                   method="trust-constr", options=options)
    return _result(res, count, time.perf_counter() - start)


def _sparse_jacobians(cons: Sequence[Any], x0: Any) -> list[bool]:
    """Per constraint object, whether its Jacobian is a scipy sparse matrix (a ``LinearConstraint``'s ``A``, a
    ``NonlinearConstraint``'s ``jac`` at ``x0``)."""
    out = []
    for con in cons:
        if isinstance(con, LinearConstraint):
            out.append(sp.issparse(con.A))
        elif callable(getattr(con, "jac", None)):
            out.append(sp.issparse(con.jac(np.asarray(x0, dtype=float))))
    return out


def run_ipopt(problem: Problem, *, max_iter: int = PEER_MAX_ITER["IPOPT"], sparse: bool = True) -> dict[str, Any]:
    """IPOPT through cyipopt: exact Hessians when offered, else ``hessian_approximation = limited-memory``."""
    from cyipopt import minimize_ipopt

    exact = has_exact_hessians(problem)
    cons, hess = ipopt_constraints(problem, exact, sparse=sparse)
    options: dict[str, Any] = {**IPOPT_OPTIONS, "max_iter": max_iter}
    if not exact:
        options["hessian_approximation"] = "limited-memory"
    fun, count = counted(problem.fun)
    start = time.perf_counter()
    res = minimize_ipopt(fun, problem.x0, jac=problem.jac, hess=hess, bounds=problem.bounds, constraints=cons,
                         options=options)
    return _result(res, count, time.perf_counter() - start)


def peer_runners(names: Sequence[str] = ("SLSQP", "trust-constr", "IPOPT")) -> dict[str, Callable[[Problem], Any]]:
    """The installed peers among ``names`` (IPOPT only when cyipopt imports), keyed by display name; with
    ``"structure limit"`` also the minimal Newton-KKT solve of :mod:`_structure_limit` (equality-only programs)."""
    table: dict[str, Callable[[Problem], Any]] = {}
    if "SLSQP" in names:
        table["scipy SLSQP"] = run_slsqp
    if "trust-constr" in names:
        table["scipy trust-constr"] = run_trust_constr
    if "IPOPT" in names and ipopt_available():
        table["IPOPT"] = run_ipopt
    if STRUCTURE_LIMIT in names:
        table[STRUCTURE_LIMIT] = run_structure_limit
    return table


def hessian_note(problem: Problem) -> str:
    """How the peers get second derivatives for ``problem`` (for the Markdown notes)."""
    if has_exact_hessians(problem):
        return ("trust-constr and IPOPT get the exact Hessians of the formulation (energy and every constraint, "
                "IPOPT on fixed sparse patterns)")
    return ("the formulation offers no constraint Hessians: trust-constr gets the exact energy Hessian and scipy's "
            "BFGS for the constraints, IPOPT its limited-memory quasi-Newton")
