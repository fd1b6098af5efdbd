"""``solve(scene)``: formulate, call :func:`sqp.minimize`, assemble the :class:`~guidewire.result.Solution`."""

from __future__ import annotations

import time
from typing import Any

import sqp

from .formulation import formulate
from .result import Solution, build_solution
from .scene import Scene


def solve(
    scene: Scene,
    *,
    scheme: str | None = None,
    bars: int | None = None,
    initial_angles: Any = None,
    initial_nodes: Any = None,
    qp_solver: str = "osqp",
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
    qp_solver, qp_options, tol, max_iter, verbose
        Passed to :func:`sqp.minimize`. The exact (constant) energy Hessian is passed as ``hess0``.

    Returns
    -------
    Solution
        Also when the solver fails: then ``success`` is False and ``status``/``message`` say why.

    Raises
    ------
    ValueError
        Before any solving, for bad options or an infeasible scene (e.g. the printed Table 5: two contacts farther
        apart than the wire between them).
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene is {type(scene).__name__}; expected guidewire.Scene (see guidewire.load_scene).")
    form = formulate(scene, scheme=scheme, bars=bars, initial_angles=initial_angles, initial_nodes=initial_nodes)
    start = time.perf_counter()
    res = sqp.minimize(
        **form.arguments(), qp_solver=qp_solver, qp_options=qp_options, tol=tol, max_iter=max_iter, verbose=verbose
    )
    return build_solution(form, res, time.perf_counter() - start)
