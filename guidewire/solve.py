"""``solve(scene)``: formulate, call :func:`sqp.minimize`, assemble the :class:`~guidewire.result.Solution`."""

from __future__ import annotations

import time
from collections.abc import Iterable
from typing import Any

import numpy as np

import sqp

from .formulation import DENSE_BARS, formulate, wall_gaps
from .full_space import DENSE_BARS as FULL_DENSE_BARS
from .full_space import solve_full
from .result import Solution, build_solution
from .scene import Scene

#: Rounds of the wall working set: solve, add every node that violates a wall, solve again from the answer.
MAX_WALL_ROUNDS = 8


FORMULATIONS = ("auto", "reduced", "full")

#: ``formulation="auto"`` uses the full-space program above this many bars (see :func:`choose_formulation`).
FULL_SPACE_BARS = 200


def default_qp_solver(bars: int, formulation: str = "reduced") -> str:
    """The QP backend :func:`solve` uses for ``bars`` bars when none is given: DAQP while the engine works densely;
    above that PIQP's sparse backend for the full-space program (10-20 ms per subproblem at 1600 bars, Clarabel
    50 ms, OSQP not converging) and Clarabel for the reduced one (dense wall rows stored sparse)."""
    if formulation == "full":
        return "daqp" if bars <= FULL_DENSE_BARS else "piqp"
    return "daqp" if bars <= DENSE_BARS else "clarabel"


def choose_formulation(bars: int, hessian: str = "exact") -> str:
    """What ``formulation="auto"`` means: the reduced program (angles only) up to :data:`FULL_SPACE_BARS` bars,
    where its dense QPs are fastest, and the full-space one (:mod:`guidewire.full_space`: angles and nodes, every
    row sparse) above, with the exact Hessian. Measured on Fig. 6a at 400 / 1600 bars: reduced 2.1 s / 76 s, full
    28 ms / 0.10 s; Table 1 (π/4) at 1600 bars: reduced 68 ms, full 51 ms; the paper scenes at 150 bars: reduced
    1.6-2x faster, at 200 a tie (reduced 0.7-1x the time), at 300 full 1.3-1.7x faster. The BFGS path stays
    reduced (the paper's algorithm)."""
    return "full" if hessian == "exact" and bars > FULL_SPACE_BARS else "reduced"


def solve(
    scene: Scene,
    *,
    scheme: str | None = None,
    bars: int | None = None,
    initial_angles: Any = None,
    initial_nodes: Any = None,
    hessian: str = "exact",
    formulation: str = "auto",
    multipliers0: Any = None,
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
    formulation : {"auto", "reduced", "full"}
        ``"reduced"``: the paper's program, bar angles only (dense rows: a node depends on every earlier angle).
        ``"full"``: bar angles and node positions as variables, closed by sparse equalities
        (:mod:`guidewire.full_space`; exact Hessian only), O(n) per iteration. ``"auto"`` (default):
        :func:`choose_formulation` (full space above :data:`FULL_SPACE_BARS` bars). Both give the same shape.
    multipliers0 : sequence of arrays, optional
        Starting multipliers (``solution.result.constraint_multipliers`` of a neighbouring solve with the same
        constraint blocks), used when the blocks match; see :func:`solve_sequence`.
    qp_solver : str, optional
        qpsolvers backend; default :func:`default_qp_solver` (DAQP for small problems, else PIQP (full space) or
        Clarabel (reduced)).
    qp_options, tol, max_iter, verbose
        Passed to :func:`sqp.minimize`.

    Returns
    -------
    Solution
        Also when the solver fails: then ``success`` is False and ``status``/``message`` say why. Walls are
        constrained through a working set of nodes (those near the wall at the start, plus any found violating it),
        and the returned shape is checked against every wall at every node. When the exact-Hessian solve of the
        reduced program stalls (:data:`FALLBACK_STATUSES`), it is solved again from the same start with damped BFGS
        (at most ``min(max_iter, max(50, max_iter // 5))`` iterations); a success that way says so in ``message``.

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
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation is {formulation!r}; expected one of {FORMULATIONS}.")
    if formulation == "full" and hessian != "exact":
        raise ValueError("formulation='full' needs hessian='exact' (the BFGS path is the paper's reduced program).")
    n_bars = scene.wire.bars if bars is None else bars
    if formulation == "full" or (formulation == "auto" and isinstance(n_bars, int)
                                 and choose_formulation(n_bars, hessian) == "full"):
        return solve_full(scene, scheme=scheme, bars=bars, initial_angles=initial_angles, initial_nodes=initial_nodes,
                          multipliers0=multipliers0, qp_solver=qp_solver, qp_options=qp_options, tol=tol,
                          max_iter=max_iter, verbose=verbose)
    start = time.perf_counter()
    form = formulate(scene, scheme=scheme, bars=bars, initial_angles=initial_angles, initial_nodes=initial_nodes,
                     wall_nodes="near")
    backend = qp_solver if qp_solver is not None else default_qp_solver(form.n)
    options = {"qp_solver": backend, "qp_options": qp_options, "tol": tol, "max_iter": max_iter, "verbose": verbose}
    start_angles = form.x0
    form, res = _solve_reduced(form, hessian, multipliers0, options)
    if hessian == "exact" and res.status in FALLBACK_STATUSES:
        # Newton–SQP can stall where the exact Lagrangian Hessian is indefinite on the constraints' null space at
        # poor multiplier estimates (a nearly taut stretch between two points); the paper's damped BFGS, started
        # from the exact energy Hessian, does not depend on them: solve again from the same start
        first = f"{sqp.Status.from_code(res.status).name} after {res.nit} exact-Hessian iterations"
        budget = {**options, "max_iter": min(max_iter, max(FALLBACK_MIN_ITER, max_iter // 5))}  # (a failure: quick)
        form_q, res_q = _solve_reduced(formulate(form.scene, initial_angles=start_angles, wall_nodes="near"), "bfgs",
                                       None, budget)
        if res_q.success:
            res_q.message = f"{res_q.message} (damped BFGS; the exact-Hessian run ended {first})"
            form, res = form_q, res_q
    return build_solution(form, res, time.perf_counter() - start)


#: The damped-BFGS retry of :func:`solve` may take ``min(max_iter, max(FALLBACK_MIN_ITER, max_iter // 5))``
#: iterations (it needed 12 where the exact-Hessian run stalled; an infeasible scene fails twice, the second time
#: quickly; the user's ``max_iter`` is never exceeded).
FALLBACK_MIN_ITER = 50

#: Outcomes of an exact-Hessian solve after which :func:`solve` tries the damped-BFGS algorithm from the same start.
FALLBACK_STATUSES = tuple(status.code for status in (
    sqp.Status.MAX_ITER, sqp.Status.LINE_SEARCH, sqp.Status.SMALL_STEP, sqp.Status.INFEASIBLE, sqp.Status.QP_FAILED))


def _solve_reduced(form: Any, hessian: str, multipliers0: Any, options: dict[str, Any]) -> tuple[Any, Any]:
    """Solve the reduced program of ``form`` with the wall working set: solve, add every node that violates a wall
    (and its neighbours), solve again from the answer, up to :data:`MAX_WALL_ROUNDS` times."""
    for _ in range(MAX_WALL_ROUNDS):
        args = form.arguments()
        if hessian == "exact":
            args["hess"] = form.hess
        if multipliers0 is not None and [np.size(m) for m in multipliers0] == [b.rows for b in form.blocks]:
            args["multipliers0"] = multipliers0
        res = sqp.minimize(**args, **options)
        if not form.scene.walls:
            break
        gaps = wall_gaps(form.chain, res.x, form.scene.walls)
        tolerance = options["tol"] * max(1.0, form.scene.wire.length)
        violated = [np.flatnonzero(g < -tolerance) + 1 for g in gaps]
        if not any(v.size for v in violated):
            break
        # add the violators and their neighbours, then solve again from the answer
        wall_nodes = [np.union1d(b.nodes, np.clip(np.concatenate([v - 1, v, v + 1]), 1, form.n))
                      for b, v in zip(form.block("wall"), violated, strict=True)]
        form = formulate(form.scene, initial_angles=res.x, wall_nodes=wall_nodes)
    return form, res


def solve_sequence(scenes: Iterable[Scene], **options: Any) -> list[Solution]:
    """Quasi-static advancement (paper §2.1): solve each scene starting from the previous answer.

    Each solve after the first starts from the previous shape (bar angles re-sampled by relative arc length when
    the bar layout changes) and, when the constraint blocks are the same, from the previous multipliers, so a small
    change of the scene (a contact moving along a wall, the inserted length growing) costs one or two Newton steps.

    Parameters
    ----------
    scenes : iterable of Scene
        The steps, in order.
    **options
        Passed to :func:`solve` (``scheme``, ``bars``, ``hessian``, ``qp_solver``, ``tol``, ...); ``initial_angles``
        and ``multipliers0`` of the first step only.

    Returns
    -------
    list of Solution
        One per scene; a failed step is returned as data and the next step starts from its shape anyway.
    """
    out: list[Solution] = []
    for scene in scenes:
        if out:
            prev = out[-1]
            options["initial_angles"] = _resampled_angles(prev, scene, options.get("bars"))
            options["multipliers0"] = prev.result.constraint_multipliers
            t = _secant_factor(out[-2].scene, prev.scene, scene) if len(out) >= 2 else 0.0
            if t and out[-2].bar_angles.size == prev.bar_angles.size == options["initial_angles"].size:
                options["initial_angles"], options["multipliers0"] = _secant_prediction(out[-2], prev, t)
        out.append(solve(scene, **options))
    return out


#: The secant predictor of :func:`solve_sequence` is used when the last two scene changes are this parallel (cosine).
SECANT_COSINE = 0.999


def _scene_parameters(scene: Scene) -> tuple[tuple[Any, ...], Any]:
    """(layout, values): which geometric fields of ``scene`` are set, and their values (mm, rad) as one vector."""
    key: list[Any] = [scene.wire.bars, scene.base.angle is None, len(scene.contacts), len(scene.walls),
                      scene.wire.max_relative_angle is None]
    values = [scene.wire.length, *scene.base.point]
    values += [] if scene.base.angle is None else [scene.base.angle]
    values += [] if scene.wire.max_relative_angle is None else [scene.wire.max_relative_angle]
    for c in scene.contacts:
        key += [c.point is None, c.angle is None]
        values += [c.s, *(c.point or ())] + ([] if c.angle is None else [c.angle])
    for w in scene.walls:
        values += [*w.normal, w.offset]
    return tuple(key), np.asarray(values, dtype=float)


def _secant_factor(a: Scene, b: Scene, c: Scene) -> float:
    """``t`` with ``p(c) − p(b) = t (p(b) − p(a))`` for the scene parameters ``p`` when the two changes are parallel
    (a steady advance: a contact moving along a line, the inserted length growing), else 0."""
    (ka, pa), (kb, pb), (kc, pc) = _scene_parameters(a), _scene_parameters(b), _scene_parameters(c)
    if not (ka == kb == kc) or pa.size != pc.size:
        return 0.0
    old, new = pb - pa, pc - pb
    norm_old, norm_new = float(np.linalg.norm(old)), float(np.linalg.norm(new))
    if norm_old == 0.0 or norm_new == 0.0 or float(old @ new) < SECANT_COSINE * norm_old * norm_new:
        return 0.0
    return norm_new / norm_old


def _secant_prediction(older: Solution, prev: Solution, t: float) -> tuple[Any, Any]:
    """Start angles and multipliers extrapolated along the last change: ``x + t (x − x_older)`` (the first-order
    predictor of a continuation method, so the Newton corrector starts O(h²) rather than O(h) from the answer).
    A multiplier is extrapolated only where it kept its sign over both steps and keeps it (a wall or b₂ row that
    is leaving or entering contact keeps its last value)."""
    angles = prev.bar_angles + t * (prev.bar_angles - older.bar_angles)
    lam_prev, lam_older = prev.result.constraint_multipliers, older.result.constraint_multipliers
    if [np.size(v) for v in lam_prev] != [np.size(v) for v in lam_older]:
        return angles, lam_prev
    lam = []
    for a, b in zip(lam_prev, lam_older, strict=True):
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        guess = a + t * (a - b)
        lam.append(np.where((np.sign(guess) == np.sign(a)) & (np.sign(a) == np.sign(b)), guess, a))
    return angles, lam


def _resampled_angles(prev: Solution, scene: Scene, bars: int | None) -> Any:
    """The previous bar angles at the new bars' midpoints, by relative arc length."""
    n_new = bars if bars is not None else scene.wire.bars
    old = prev.bar_angles
    if old.size == n_new and np.isclose(prev.s[-1], scene.wire.length):
        return old
    s_old = 0.5 * (prev.s[1:] + prev.s[:-1]) / prev.s[-1]
    s_new = (np.arange(n_new) + 0.5) / n_new
    return np.interp(s_new, s_old, old)
