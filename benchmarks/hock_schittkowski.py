"""Hock–Schittkowski benchmark: this engine (each installed QP backend) against scipy SLSQP, trust-constr and IPOPT.

Every solver gets the same start and the same analytic derivatives, in one process, with BLAS pinned to one thread.
A problem is *solved* when max violation <= 1e-6 and f - f* <= 1e-6 max(1, |f*|). A *false success* is a claimed
success at a point that is infeasible or not a KKT point, judged independently (:mod:`sqp.problems.judge`).

Usage: ``python benchmarks/hock_schittkowski.py [--quick] [--repeats K] [--solvers a,b,...]``
Writes ``benchmarks/results/hock_schittkowski.{md,csv}``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import argparse  # noqa: E402
import csv  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import scipy  # noqa: E402
from scipy.optimize import LinearConstraint, minimize  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

import sqp  # noqa: E402
from sqp.problems.hock_schittkowski import all_problems  # noqa: E402
from sqp.problems.judge import judge  # noqa: E402
from sqp.problems.problem import TestProblem  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
QUICK = ["HS1", "HS6", "HS7", "HS14", "HS21", "HS35", "HS43", "HS71", "HS76", "HS100"]
#: Shift (seconds) of the shifted geometric mean of run times, as qpbenchmark uses.
TIME_SHIFT = 1e-3


def _dict_constraints(prob: TestProblem) -> list[dict[str, Any]]:
    """All constraints as SLSQP dicts (for peers that take only dicts)."""
    out: list[dict[str, Any]] = []
    for con in prob.constraints:
        if not isinstance(con, LinearConstraint):
            out.append(con)
            continue
        A = np.atleast_2d(np.asarray(con.A, dtype=float))
        lb = np.broadcast_to(np.asarray(con.lb, float), (A.shape[0],))
        ub = np.broadcast_to(np.asarray(con.ub, float), (A.shape[0],))
        eq = lb == ub
        if eq.any():
            out.append({"type": "eq", "fun": lambda x, A=A[eq], b=lb[eq]: A @ x - b, "jac": lambda x, A=A[eq]: A})
        lo = ~eq & np.isfinite(lb)
        if lo.any():
            out.append({"type": "ineq", "fun": lambda x, A=A[lo], b=lb[lo]: A @ x - b, "jac": lambda x, A=A[lo]: A})
        up = ~eq & np.isfinite(ub)
        if up.any():
            out.append({"type": "ineq", "fun": lambda x, A=A[up], b=ub[up]: b - A @ x, "jac": lambda x, A=A[up]: -A})
    return out


def _counted(prob: TestProblem) -> tuple[Callable[[Any], float], list[int]]:
    count = [0]

    def fun(x: Any) -> float:
        count[0] += 1
        return prob.fun(x)

    return fun, count


def run_ours(prob: TestProblem, backend: str) -> dict[str, Any]:
    res = sqp.minimize(prob.fun, prob.x0, prob.jac, prob.bounds, prob.constraints, qp_solver=backend)
    return {"x": res.x, "f": res.fun, "success": res.success, "nfev": res.nfev, "nit": res.nit,
            "message": res.message}


def run_scipy(prob: TestProblem, method: str, options: dict[str, Any]) -> dict[str, Any]:
    fun, count = _counted(prob)
    res = minimize(fun, prob.x0, jac=prob.jac, bounds=prob.bounds, constraints=_dict_constraints(prob),
                   method=method, options=options)
    return {"x": res.x, "f": res.fun, "success": bool(res.success), "nfev": count[0], "nit": res.nit,
            "message": str(res.message)}


def run_ipopt(prob: TestProblem) -> dict[str, Any]:
    from cyipopt import minimize_ipopt

    fun, count = _counted(prob)
    res = minimize_ipopt(fun, prob.x0, jac=prob.jac, bounds=prob.bounds, constraints=_dict_constraints(prob),
                         options={"hessian_approximation": "limited-memory", "print_level": 0, "max_iter": 3000,
                                  "tol": 1e-8, "sb": "yes"})
    return {"x": res.x, "f": res.fun, "success": bool(res.success), "nfev": count[0], "nit": res.nit,
            "message": str(res.message)}


def solvers(names: list[str] | None) -> dict[str, Callable[[TestProblem], dict[str, Any]]]:
    table: dict[str, Callable[[TestProblem], dict[str, Any]]] = {}
    for backend in sqp.installed_solvers():
        table[f"sqp[{backend}]"] = lambda p, b=backend: run_ours(p, b)
    table["scipy SLSQP"] = lambda p: run_scipy(p, "SLSQP", {"maxiter": 500})
    table["scipy trust-constr"] = lambda p: run_scipy(p, "trust-constr", {"maxiter": 3000})
    try:
        import cyipopt  # noqa: F401

        table["IPOPT (L-BFGS)"] = run_ipopt
    except ImportError:
        pass
    if names:
        table = {k: v for k, v in table.items() if any(n in k for n in names)}
    return table


def measure(prob: TestProblem, run: Callable[[TestProblem], dict[str, Any]], repeats: int) -> dict[str, Any]:
    times = []
    out: dict[str, Any] = {}
    for _ in range(repeats):
        t = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                out = run(prob)
        except Exception as exc:  # a peer crashing is a result, not the end of the benchmark
            out = {"x": np.full(prob.n, np.nan), "f": np.nan, "success": False, "nfev": 0, "nit": 0,
                   "message": f"raised {type(exc).__name__}: {exc}"}
        times.append(time.perf_counter() - t)
    v = judge(prob, out["x"])
    return {**out, "time": float(np.median(times)), "solved": v.solved, "maxcv": v.maxcv,
            "stationarity": v.stationarity, "false_success": v.false_success(out["success"]),
            "unsolved_success": bool(out["success"] and not v.solved)}


def sgm(values: list[float], shift: float = TIME_SHIFT) -> float:
    """Shifted geometric mean."""
    return float(np.exp(np.mean(np.log(np.asarray(values) + shift))) - shift)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="ten problems, one repeat (under a minute)")
    ap.add_argument("--repeats", type=int, default=3, help="timing repeats per solve (median reported)")
    ap.add_argument("--solvers", type=str, default="", help="comma-separated substrings of solver names")
    ap.add_argument("--out", type=Path, default=RESULTS)
    a = ap.parse_args()
    probs = all_problems()
    if a.quick:
        probs = [p for p in probs if p.name in QUICK]
    repeats = 1 if a.quick else a.repeats
    table = solvers([s for s in a.solvers.split(",") if s] or None)
    print(f"machine: {platform.machine()} {platform.processor()} {os.cpu_count()} cores; python "
          f"{platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}; BLAS pinned to 1 thread")
    print(f"{len(probs)} problems, {len(table)} solvers, median of {repeats} repeats")
    try:
        from tqdm import tqdm
    except ImportError:  # progress bar is optional
        def tqdm(x: Any, **_: Any) -> Any:
            return x
    rows: list[dict[str, Any]] = []
    with threadpool_limits(limits=1):
        for prob in tqdm(probs, desc="problems"):
            for name, run in table.items():
                r = measure(prob, run, repeats)
                rows.append({"problem": prob.name, "solver": name, **{k: r[k] for k in (
                    "solved", "success", "false_success", "unsolved_success", "f", "maxcv", "stationarity",
                    "nfev", "nit", "time", "message")}})
    write(rows, probs, table, a.out, repeats, quick=a.quick)


def write(rows: list[dict[str, Any]], probs: list[TestProblem], table: dict[str, Any], out: Path, repeats: int,
          *, quick: bool) -> None:
    out.mkdir(parents=True, exist_ok=True)
    stem = "hock_schittkowski_quick" if quick else "hock_schittkowski"
    with open(out / f"{stem}.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    ref = "scipy SLSQP"
    ref_times = {r["problem"]: r["time"] for r in rows if r["solver"] == ref}
    summary = []
    for name in table:
        rs = [r for r in rows if r["solver"] == name]
        ratio = sgm([r["time"] for r in rs]) / sgm([ref_times[r["problem"]] for r in rs]) if ref_times else np.nan
        summary.append({
            "solver": name, "solved": sum(r["solved"] for r in rs), "false": sum(r["false_success"] for r in rs),
            "false_names": ", ".join(r["problem"] for r in rs if r["false_success"]),
            "unsolved_success": sum(r["unsolved_success"] for r in rs),
            "nfev": float(np.mean([r["nfev"] for r in rs])), "sgm": sgm([r["time"] for r in rs]), "ratio": ratio,
            "unsolved": ", ".join(r["problem"] for r in rs if not r["solved"]),
        })
    summary.sort(key=lambda s: (-s["solved"], s["false"], s["sgm"]))
    lines = [
        f"# Hock–Schittkowski: {len(probs)} problems",
        "",
        f"Same start and analytic derivatives for every solver, one process, BLAS pinned to one thread; time = median "
        f"of {repeats} repeat(s); *solved*: max violation ≤ 1e-6 and f − f* ≤ 1e-6·max(1, |f*|). *False success*: "
        "success claimed at a point that is infeasible or not a KKT point (independent check: bounded least-squares "
        "multipliers on the active set, scaled stationarity ≤ 1e-4). Time ratio: shifted geometric mean (shift 1 ms) "
        "relative to scipy SLSQP on the same problems in the same run.",
        "",
        f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
        f"{platform.machine()}, {os.cpu_count()} cores",
        "",
        "| solver | solved | false successes | successes not solved | mean f-evals | time sgm (ms) | × SLSQP |",
        "|---|---|---|---|---|---|---|",
    ]
    for s in summary:
        false = f"{s['false']} ({s['false_names']})" if s["false"] else "0"
        lines.append(f"| {s['solver']} | {s['solved']} | {false} | {s['unsolved_success']} | {s['nfev']:.1f} | "
                     f"{1e3 * s['sgm']:.2f} | {s['ratio']:.2f} |")
    lines += ["", "## Not solved", ""]
    for s in summary:
        lines.append(f"- **{s['solver']}**: {s['unsolved'] or '—'}")
    (out / f"{stem}.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
