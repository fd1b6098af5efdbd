"""``solve(scene)``, the front door: check the arguments, then hand the scene and one
:class:`~guidewire.solve.options.SolveOptions` to the pipeline (:func:`guidewire.solve.pipeline.run`) or, for
``tol_mm`` and curvature-graded bars, to the refinement (:mod:`guidewire.solve.refine`), which calls the pipeline."""

from __future__ import annotations

from typing import Any

from ..scene.scene import Scene
from . import refine
from .branches import check_branches
from .options import MAX_ITER, TOL, SolveOptions
from .pipeline import run
from .result import Solution

#: Values of ``solve(density=...)`` (None: the wire's).
DENSITIES = (None, "uniform", "curvature")


def solve(
    scene: Scene,
    *,
    scheme: str | None = None,
    bars: int | None = None,
    initial_angles: Any = None,
    initial_nodes: Any = None,
    hessian: str = "exact",
    layout: str = "auto",
    multipliers0: Any = None,
    qp_solver: str | None = None,
    qp_options: dict[str, Any] | None = None,
    tol: float = TOL,
    max_iter: int = MAX_ITER,
    verbose: bool = False,
    tol_mm: float | None = None,
    density: str | None = None,
    reuse: Any = None,
    branches: str = "lowest",
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
    layout : {"auto", "reduced", "full"}
        ``"reduced"``: the paper's program, bar angles only. ``"full"``: bar angles and node positions, closed by
        sparse equalities (:mod:`guidewire.program.full_space`; exact Hessian only), O(n) per iteration. ``"auto"``
        (default): :func:`~guidewire.solve.options.choose_layout`. Both give the same shape and the same multipliers.
    multipliers0 : Solution, BlockMultipliers or sequence of arrays, optional
        Starting multipliers: a neighbouring :class:`Solution` or a
        :class:`~guidewire.program.formulation.BlockMultipliers` (their blocks matched by kind, members and row, see
        :meth:`Formulation.multipliers0`), or one array per constraint block of this scene's formulation.
    qp_solver : str, optional
        qpsolvers backend, or None/"auto" (default) for :func:`sqp.minimize`'s choice by the program's structure.
    qp_options, tol, max_iter, verbose
        Passed to :func:`sqp.minimize`.
    tol_mm : float, optional
        Solve to this estimated mean node error (mm) instead of with ``bars``: doubled layouts and a Richardson
        estimate (:func:`guidewire.solve.refine.solve_to_tolerance`); the answer carries ``error_estimate_mm``.
    density : {"uniform", "curvature"}, optional
        Bar layout; default ``scene.wire.density``. ``"curvature"``: the bars graded by the curvature of a coarse
        solve (:mod:`~guidewire.chain.density`, :func:`.refine.solve_graded`); with ``tol_mm`` (where None means
        ``"curvature"``) graded pairs, ``"uniform"`` doubled uniform bars. Ignored when the wire has explicit
        ``bar_lengths``.
    reuse : guidewire.program.model.ModelReuse, optional
        Keep what the last scene formulated through it shares with ``scene`` (:func:`guidewire.solve_sequence`).
    branches : {"lowest", "first"}
        ``"lowest"`` (default): when the answer from the default start has a pose (the base or a contact with a
        point) whose tangent is free, also solve from the mirror starts of :mod:`guidewire.solve.branches` (that bow
        reflected about the chord between poses) and keep the lowest energy; in a vessel with branches, also from a
        start along the way through each branch the wire reaches. ``Solution.starts`` counts the starts. Not with
        ``initial_angles``/``initial_nodes`` (a given start chooses its branch). ``"first"``: the default start's
        answer only.

    Returns
    -------
    Solution
        Also when the solver fails: then ``success`` is False, ``status``/``message`` say why, and no forces are
        reported. Walls are constrained through a working set of nodes in the reduced layout (those near the wall at
        the start, plus any found violating it), and the returned shape is checked against every wall at every
        node. When an exact-Hessian solve stalls (:data:`~guidewire.solve.pipeline.FALLBACK_STATUSES`), the reduced
        program is solved again
        from the same start with damped BFGS (at most ``min(max_iter, max(50, max_iter // 5))`` iterations); an
        answer found that way has ``fallback = "damped BFGS"`` and says so in ``message``.

    Raises
    ------
    ValueError
        Before any solving, for bad options or an infeasible scene (e.g. the printed Table 5: two contacts farther
        apart than the wire between them).
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene is {type(scene).__name__}; expected guidewire.Scene (see guidewire.load_scene).")
    check_branches(branches)
    density = scene.wire.density if density is None else density
    if density not in DENSITIES:
        raise ValueError(f"density is {density!r}; expected 'uniform' or 'curvature' (or None: the wire's).")
    common = {"scheme": scheme, "hessian": hessian, "layout": layout, "qp_solver": qp_solver,
              "qp_options": qp_options, "tol": tol, "max_iter": max_iter, "verbose": verbose, "branches": branches}
    if tol_mm is not None or (density == "curvature" and scene.wire.bar_lengths is None):
        if any(v is not None for v in (initial_angles, initial_nodes, multipliers0)) or (tol_mm and bars):
            raise ValueError("tol_mm and density='curvature' choose the bars and the starts; do not pass "
                             "initial_angles, initial_nodes or multipliers0 (nor bars with tol_mm).")
        options = SolveOptions(**common)
        if tol_mm is not None:
            return refine.solve_to_tolerance(scene, tol_mm, options, density=density or "curvature")
        return refine.solve_graded(scene, scene.wire.bars if bars is None else bars, options)
    options = SolveOptions(bars=bars, initial_angles=initial_angles, initial_nodes=initial_nodes,
                           multipliers0=multipliers0, reuse=reuse, **common)
    options.check()
    return run(scene, options)
