"""Hock–Schittkowski benchmark: this engine (each installed QP backend) against scipy SLSQP, trust-constr and IPOPT.

Every solver gets the same start and the same analytic derivatives, in one process, with BLAS pinned to one thread.
A problem is *solved* when max violation <= 1e-6 and f - f* <= 1e-6 max(1, |f*|). A *false success* is a claimed
success at a point that is infeasible or not a KKT point, judged independently (:mod:`sqp.problems.judge`).

Time: the median over repeats of the ``minimize`` call alone (ours: :func:`sqp.minimize`; the peers of :mod:`_peers`
with their constraint conversions prepared before it).

Usage: ``python benchmarks/hock_schittkowski.py [--quick] [--repeats K] [--out DIR] [--solvers a,b,...]``
Writes ``hock_schittkowski.{md,csv}`` (``hock_schittkowski_quick.*`` with ``--quick``) in ``--out`` (default
``benchmarks/results``).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import _arguments as A
import _environment as E  # first: pins BLAS to one thread before numpy loads
import _peers
import _tables as T
import _timing
import numpy as np
from _problems import Problem
from _timing import sgm

import sqp
from sqp.problems.hock_schittkowski import all_problems
from sqp.problems.judge import judge
from sqp.problems.problem import TestProblem

QUICK = ["HS1", "HS6", "HS7", "HS14", "HS21", "HS35", "HS43", "HS71", "HS76", "HS100"]


def problem(prob: TestProblem) -> Problem:
    """The test problem as the peers of :mod:`_peers` take it (no Hessians: they use quasi-Newton ones)."""
    return Problem(prob.fun, prob.jac, prob.x0, prob.constraints, prob.bounds)


def run_ours(prob: TestProblem, backend: str) -> dict[str, Any]:
    start = time.perf_counter()
    res = sqp.minimize(prob.fun, prob.x0, jac=prob.jac, bounds=prob.bounds, constraints=prob.constraints,
                       qp_solver=backend)
    return {"x": res.x, "f": res.fun, "success": res.success, "nfev": res.nfev, "nit": res.nit,
            "message": res.message, "time": time.perf_counter() - start}


def solvers(names: list[str] | None) -> dict[str, Callable[[TestProblem], dict[str, Any]]]:
    """Ours with every installed QP backend and the peers: SLSQP and trust-constr with every constraint as a dict
    (``maxiter`` 500 and 3000), IPOPT with dense dicts and its limited-memory quasi-Newton."""
    table: dict[str, Callable[[TestProblem], dict[str, Any]]] = {}
    for backend in sqp.installed_solvers():
        table[f"sqp[{backend}]"] = lambda p, b=backend: run_ours(p, b)
    table["scipy SLSQP"] = lambda p: _peers.run_slsqp(problem(p), maxiter=500)
    table["scipy trust-constr"] = lambda p: _peers.run_trust_constr(problem(p), maxiter=3000, linear_as_dicts=True)
    if E.ipopt_available():
        table["IPOPT (L-BFGS)"] = lambda p: _peers.run_ipopt(problem(p), sparse=False)
    if names:
        table = {k: v for k, v in table.items() if any(n in k for n in names)}
    return table


def measure(prob: TestProblem, run: Callable[[TestProblem], dict[str, Any]], repeats: int) -> dict[str, Any]:
    """Median time of ``repeats`` runs (no limit) and the last answer, judged independently."""
    out = _timing.measure(run, prob, repeats, adaptive=False)
    if out["outcome"] != "ran":  # a peer crashing is a result, not the end of the benchmark
        out.update(x=np.full(prob.n, np.nan), f=np.nan)
    v = judge(prob, out["x"])
    return {**out, "solved": v.solved, "maxcv": v.maxcv,
            "stationarity": v.stationarity, "false_success": v.false_success(out["success"]),
            "unsolved_success": bool(out["success"] and not v.solved)}


def main() -> None:
    ap = A.parser(__doc__, quick_help="ten problems, one repeat (under a minute)", repeats=3, solvers=True)
    a = A.parse(ap)
    probs = all_problems()
    if a.quick:
        probs = [p for p in probs if p.name in QUICK]
    repeats = a.repeats
    table = solvers(A.names(a.solvers) or None)
    env = E.environment(guidewire=False)
    print("\n".join(env))
    print(f"{len(probs)} problems, {len(table)} solvers, median of {repeats} repeats")
    rows: list[dict[str, Any]] = []
    with E.one_thread():
        for prob in E.progress(probs, desc="problems"):
            for name, run in table.items():
                r = measure(prob, run, repeats)
                rows.append({"problem": prob.name, "solver": name, **{k: r[k] for k in (
                    "solved", "success", "false_success", "unsolved_success", "f", "maxcv", "stationarity",
                    "nfev", "nit", "time", "message")}})
    write(rows, probs, table, a.out, repeats, env, quick=a.quick)


def write(rows: list[dict[str, Any]], probs: list[TestProblem], table: dict[str, Any], out: Path, repeats: int,
          env: list[str], *, quick: bool) -> None:
    stem = T.output_stem(out, "hock_schittkowski", quick)
    T.write_csv(rows, stem.with_suffix(".csv"))
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
        *[f"- {e}" for e in env],
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
    T.write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
