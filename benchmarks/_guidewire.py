"""The one adapter through which the benchmarks touch guidewire beyond ``guidewire.solve`` and the scene classes.

The contract it relies on, all in this file:

- ``guidewire.formulate(scene, *, bars=None, scheme=None, initial_angles=None)`` returns ``form`` with
  ``form.fun``, ``form.jac``, ``form.hess`` (exact objective Hessian), ``form.constraints`` (scipy-style:
  ``LinearConstraint``, ``NonlinearConstraint`` and dicts, the latter with an optional ``"hess"``), ``form.x0``,
  ``form.n`` and ``form.arguments()`` (keys fun, x0, jac, bounds, constraints, hess0) — nothing else of it;
- ``guidewire.solve`` returns a Solution with ``.nodes``, ``.s``, ``.bar_angles``, ``.energy``, ``.success``,
  ``.message``, ``.iterations``, ``.solve_time_s`` and ``.result`` (the raw sqp result: ``.nfev``, ``.kkt``);
- the continuum reference, ``continuum_reference`` and ``node_errors`` (the paper's Eq. 25), and the scene's
  feasibility check, imported or called once each, below.

Every solver of a guidewire benchmark is called on one :class:`Case` (a scene formulated once, with its start): ours
through :func:`run_ours`, the peers of :mod:`_peers` on the case's generic :class:`_problems.Problem`
(:func:`peer_variants`). Any answer ``x`` is judged on the same scale by :func:`evaluate` and :func:`branch`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

import numpy as np
from _peers import hessian_note, peer_runners
from _problems import Problem, max_violation
from _timing import measure

import guidewire
import sqp
from guidewire import formulate
from guidewire.program.feasibility import infeasibility
from guidewire.reference import continuum_reference, node_errors

#: An answer counts as feasible when no constraint is violated by more than this (mm or rad).
FEASIBILITY_TOL = 1e-6
#: Relative energy gap to the best feasible energy of the same problem below which an answer is on the lowest branch.
SAME_ENERGY_RTOL = 1e-6
#: Relative gap above which it is on another branch (in between: the same branch, not fully converged).
OTHER_BRANCH_RTOL = 1e-3


def feasible(scene: guidewire.Scene) -> bool:
    """Whether nothing obvious forbids a shape (:func:`guidewire.program.feasibility.infeasibility`)."""
    return infeasibility(scene) is None


@dataclass(frozen=True)
class Case:
    """One problem as every solver sees it: the scene (bars and scheme applied), its program and start."""

    scene: guidewire.Scene
    problem: Problem
    start: str  # "default" (the formulation's elastica-like start), "straight" (all angles 0) or "previous"

    @property
    def n(self) -> int:
        return self.problem.n


def make_case(scene: guidewire.Scene, *, bars: int | None = None, scheme: str | None = None,
              start: str = "default", initial_angles: Any = None) -> Case:
    """Formulate ``scene`` once; ``start="straight"`` starts every solver from all bar angles 0, ``initial_angles``
    from those."""
    if scheme is not None:
        scene = scene.with_scheme(scheme)
    if bars is not None:
        scene = scene.with_bars(bars)
    if start == "straight":
        initial_angles = np.zeros(scene.wire.bars)
    form = formulate(scene, initial_angles=initial_angles)
    args = form.arguments()
    problem = Problem(fun=form.fun, jac=form.jac, x0=form.x0, constraints=tuple(form.constraints),
                      bounds=args["bounds"], hess=form.hess)
    assert problem.n == form.n
    return Case(scene, problem, start)


def step_problem(sol: Any, initial_angles: Any) -> Problem:
    """The program of a solved step as our last round stated it — its blocks (a lumen's rows modelled where that
    round left them, exact at the answer) — from ``initial_angles``: the same NLP and start for a peer."""
    from guidewire.program.formulation import assemble
    from guidewire.program.model import build_model

    form = assemble(build_model(sol.scene, initial_angles=initial_angles), sol.layout, sol.blocks)
    return Problem(fun=form.fun, jac=form.jac, x0=form.x0, constraints=tuple(form.constraints), bounds=None,
                   hess=form.hess)


# ----------------------------------------------------------------------------------------------------------------
# Ours
# ----------------------------------------------------------------------------------------------------------------
def run_ours(case: Case, *, qp_solver: str | None = None, hessian: str | None = None,
             max_iter: int = 500) -> dict[str, Any]:
    """:func:`guidewire.solve` from the case's start; time = ``Solution.solve_time_s``."""
    kwargs: dict[str, Any] = {"initial_angles": case.problem.x0, "max_iter": max_iter}
    if qp_solver is not None:
        kwargs["qp_solver"] = qp_solver
    if hessian is not None:
        kwargs["hessian"] = hessian
    sol = guidewire.solve(case.scene, **kwargs)
    _CHAINS.setdefault(case.scene, _chain_of(sol))
    kkt = getattr(sol.result, "kkt", None) or {}
    return {"x": sol.bar_angles, "success": sol.success, "message": sol.message, "nit": sol.iterations,
            "nfev": int(getattr(sol.result, "nfev", 0)), "time": sol.solve_time_s, "solution": sol,
            "kkt": max((float(v) for v in kkt.values()), default=math.nan)}


def ours_variants(backends: bool = True) -> dict[str, Callable[[Case], dict[str, Any]]]:
    """Our solver: ``ours`` (every default of :func:`guidewire.solve`: exact Hessian, automatic QP backend),
    ``ours[bfgs]`` (the paper's damped BFGS) and, with ``backends``, ``ours[<backend>]`` for every installed QP
    backend named explicitly."""
    out: dict[str, Callable[[Case], dict[str, Any]]] = {"ours": run_ours,
                                                        "ours[bfgs]": lambda c: run_ours(c, hessian="bfgs")}
    if backends:
        for name in sqp.installed_solvers():
            out[f"ours[{name}]"] = lambda c, b=name: run_ours(c, qp_solver=b)
    return out


def peer_variants(names: Sequence[str] = ("SLSQP", "trust-constr", "IPOPT")) -> dict[str, Callable[[Case], Any]]:
    """The installed peers of :mod:`_peers` among ``names``, called on a case's program."""
    return {name: (lambda c, r=run: r(c.problem)) for name, run in peer_runners(names).items()}


def warm_up(solvers: dict[str, Callable[[Case], Any]], limit: float | None) -> None:
    """Run every solver once on Table 1 (θ_B = π/4) at 10 bars, untimed: first calls load libraries."""
    warm = make_case(guidewire.paper_scenes()["table1_pi_4"], bars=10)
    for run in solvers.values():
        measure(run, warm, 1, limit)


def peer_hessian_note(case: Case) -> str:
    """How the peers get second derivatives for this case's formulation (for the Markdown notes)."""
    return hessian_note(case.problem)


# ----------------------------------------------------------------------------------------------------------------
# Judging any answer
# ----------------------------------------------------------------------------------------------------------------
_CHAINS: dict[guidewire.Scene, tuple[np.ndarray, np.ndarray]] = {}


def _chain_of(sol: Any) -> tuple[np.ndarray, np.ndarray]:
    """The bar chain of a Solution: base point and arc length of every node."""
    return np.asarray(sol.nodes[0], dtype=float), np.asarray(sol.s, dtype=float)


def nodes_at(case: Case, x: Any) -> tuple[np.ndarray, np.ndarray]:
    """Node positions (n + 1, 2) at bar angles ``x`` and their arc lengths.

    The chain (base point, bar lengths) is read off a Solution of the same scene: ours' when it ran on the case,
    else a one-iteration solve (the formulation's chain is not part of the contract)."""
    if case.scene not in _CHAINS:
        _CHAINS[case.scene] = _chain_of(guidewire.solve(case.scene, max_iter=1))
    base, s = _CHAINS[case.scene]
    steps = np.diff(s)[:, None] * np.column_stack((np.cos(x), np.sin(x)))
    return np.vstack((base, base + np.cumsum(steps, axis=0))), s


_REFERENCES: dict[Any, tuple[Any, str]] = {}


def reference(scene: guidewire.Scene) -> tuple[Any, str]:
    """The continuum reference of ``scene`` (the equal-lowest continuum shapes; errors are taken against the
    nearest, so mirror twins count), or ``(None, why not)``. Independent of bars and scheme; cached."""
    key = (scene.base, scene.contacts, scene.walls, scene.wire.length, scene.wire.bending_stiffness)
    if key not in _REFERENCES:
        try:
            _REFERENCES[key] = continuum_reference(scene)
        except Exception as exc:  # the reference failing is recorded, not fatal
            _REFERENCES[key] = (None, f"reference raised {type(exc).__name__}: {exc}")
    return _REFERENCES[key]


def reference_errors(nodes: np.ndarray, s: np.ndarray, ref: Any) -> tuple[float, float]:
    """Mean and max node error (mm; the paper's Eq. 25), nan without reference."""
    if ref is None:
        return math.nan, math.nan
    errors = node_errors(SimpleNamespace(nodes=nodes, s=s), ref)
    return float(errors.mean()), float(errors.max())


def evaluate(case: Case, x: Any, ref: Any) -> dict[str, float]:
    """Energy (N·mm), largest violation and node errors (mm) against the continuum reference at angles ``x``."""
    nan = {"energy": math.nan, "max_violation": math.nan, "mean_error_mm": math.nan, "max_error_mm": math.nan}
    if x is None:
        return nan
    x = np.asarray(x, dtype=float)
    if x.shape != (case.n,) or not np.all(np.isfinite(x)):
        return nan
    mean, worst = reference_errors(*nodes_at(case, x), ref) if ref is not None else (math.nan, math.nan)
    return {"energy": float(case.problem.fun(x)), "max_violation": max_violation(case.problem, x),
            "mean_error_mm": mean, "max_error_mm": worst}


def branch(energy: float, violation: float, best: float) -> str:
    """``lowest``, ``near (+δ)`` (same branch, not fully converged), ``other (+δ)``, ``infeasible`` or ``—``."""
    if not np.isfinite(energy) or not np.isfinite(violation):
        return "—"
    if violation > FEASIBILITY_TOL:
        return "infeasible"
    gap = (energy - best) / max(abs(best), 1e-300)
    if gap <= SAME_ENERGY_RTOL:
        return "lowest"
    return f"{'near' if gap <= OTHER_BRANCH_RTOL else 'other'} (+{gap:.1e})"
