"""``solve(scene)``: formulate, call :func:`sqp.minimize`, assemble the :class:`~guidewire.result.Solution`."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

import sqp

from .formulation import DENSE_BARS, formulate, wall_gaps
from .result import Solution, build_solution
from .scene import Scene

#: Rounds of the wall working set: solve, add every node that violates a wall, solve again from the answer.
MAX_WALL_ROUNDS = 8


def default_qp_solver(bars: int) -> str:
    """The QP backend :func:`solve` uses for ``bars`` bars when none is given."""
    return "daqp" if bars <= DENSE_BARS else "clarabel"


def solve(
    scene: Scene,
    *,
    scheme: str | None = None,
    bars: int | None = None,
    initial_angles: Any = None,
    initial_nodes: Any = None,
    hessian: str = "exact",
    qp_solver: str | None = None,
    qp_options: dict[str, Any] | None = None,
    tol: float = 1e-8,
    max_iter: int = 500,
    verbose: bool = False,
) -> Solution:
    """Find the minimum-bending-energy shape of the wire in ``scene`` (paper §2.3) with :func:`sqp.minimize`.

    Parameters
    ----------
    scene : Scene
    scheme : {"second_order", "paper"}, optional
        Energy discretisation; default ``scene.wire.scheme`` (see :mod:`guidewire.energy`).
    bars : int, optional
        Number of bars; default ``scene.wire.bars``.
    initial_angles : array_like, shape (n,), optional
        Starting bar angles (rad). Default: the elastica-like start of :mod:`guidewire.initial_shape`.
    initial_nodes : array_like, shape (n + 1, 2), optional
        Starting node positions instead (base first; only bar directions are used).
    hessian : {"exact", "bfgs"}
        ``"exact"`` (default): the exact Lagrangian Hessian of the bar chain (constant tridiagonal energy Hessian
        plus diagonal constraint terms), a Newton–SQP method converging in 3–6 iterations on the paper scenes.
        ``"bfgs"``: the paper's damped BFGS (Eq. 6), started from the exact energy Hessian (``hess0``).
    qp_solver : str, optional
        qpsolvers backend; default :func:`default_qp_solver` (DAQP up to :data:`DENSE_BARS` bars, else Clarabel).
    qp_options, tol, max_iter, verbose
        Passed to :func:`sqp.minimize`.

    Returns
    -------
    Solution
        Also when the solver fails: then ``success`` is False and ``status``/``message`` say why. Walls are
        constrained through a working set of nodes (those near the wall at the start, plus any found violating it),
        and the returned shape is checked against every wall at every node.

    Raises
    ------
    ValueError
        Before any solving, for bad options or an infeasible scene (e.g. the printed Table 5: two contacts farther
        apart than the wire between them).
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene is {type(scene).__name__}; expected guidewire.Scene (see guidewire.load_scene).")
    if hessian not in ("exact", "bfgs"):
        raise ValueError(f"hessian is {hessian!r}; expected 'exact' or 'bfgs'.")
    wall_nodes: Any = "near"
    start = time.perf_counter()
    form = formulate(scene, scheme=scheme, bars=bars, initial_angles=initial_angles, initial_nodes=initial_nodes,
                     wall_nodes=wall_nodes)
    backend = qp_solver if qp_solver is not None else default_qp_solver(form.n)
    for _ in range(MAX_WALL_ROUNDS):
        args = form.arguments()
        if hessian == "exact":
            args["hess"] = form.hess
        res = sqp.minimize(**args, qp_solver=backend, qp_options=qp_options, tol=tol, max_iter=max_iter,
                           verbose=verbose)
        if not form.scene.walls:
            break
        gaps = wall_gaps(form.chain, res.x, form.scene.walls)
        tolerance = tol * max(1.0, form.scene.wire.length)
        violated = [np.flatnonzero(g < -tolerance) + 1 for g in gaps]
        if not any(v.size for v in violated):
            break
        # add the violators and their neighbours, then solve again from the answer
        wall_nodes = [np.union1d(b.nodes, np.clip(np.concatenate([v - 1, v, v + 1]), 1, form.n))
                      for b, v in zip(form.block("wall"), violated, strict=True)]
        form = formulate(form.scene, initial_angles=res.x, wall_nodes=wall_nodes)
    return build_solution(form, res, time.perf_counter() - start)
