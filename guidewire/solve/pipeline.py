"""The solve pipeline, one scene and one :class:`~guidewire.solve.options.SolveOptions` through it: formulate →
:func:`sqp.minimize` → working-set rounds → damped-BFGS fallback → :class:`~guidewire.solve.result.Solution`, then the
mirror starts of :mod:`guidewire.solve.branches`. :func:`guidewire.solve` checks the options and calls :func:`run`;
so do the refinement (:mod:`guidewire.solve.refine`) and the continuation drivers."""

from __future__ import annotations

import contextlib
import functools
import time
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from threadpoolctl import ThreadpoolController

import sqp

from ..chain.kinematics import BarChain, scene_bars
from ..program.formulation import BlockMultipliers, Formulation, assemble, formulate
from ..scene.scene import Scene
from .branches import candidate_iterations, lowest_branch
from .options import SolveOptions, check_memory, choose_layout, fits_memory, program_bytes
from .result import Solution, build_solution

#: Rounds of the working set: solve, refine every block whose rows do not fit the answer (a wall: add the violating
#: nodes and their neighbours; a lumen: move its tangent planes), solve again from the answer. A lumen's rows move
#: towards the wall points of the answer by a fixed ratio a round (0.1-0.2 for coarse bars in the tortuous vessel:
#: from 0.19 mm to the 2e-7 mm the answer is checked to takes 9-10 rounds, where 8 rejected 2 of 15 lengths at
#: 0.5 bars/mm and 9 of 15 at 0.25; 16 rounds reject 0 and 2); the rounds that settle sooner are not affected.
MAX_ROUNDS = 16

#: The damped-BFGS retry of :func:`solve_once` may take ``min(max_iter, max(FALLBACK_MIN_ITER, max_iter // 5))``
#: iterations (it needed 12 where the exact-Hessian run stalled; an infeasible scene fails twice, the second time
#: quickly; the user's ``max_iter`` is never exceeded).
FALLBACK_MIN_ITER = 50

#: Outcomes of an exact-Hessian solve after which :func:`solve_once` tries the damped-BFGS algorithm from the same
#: start.
FALLBACK_STATUSES = tuple(status.code for status in (
    sqp.Status.MAX_ITER, sqp.Status.LINE_SEARCH, sqp.Status.SMALL_STEP, sqp.Status.INFEASIBLE, sqp.Status.QP_FAILED))

#: The name :attr:`Solution.fallback` gives the retry.
FALLBACK = "damped BFGS"

#: A vessel scene the automatic layout puts in the full space (:func:`choose_layout`) gets this many iterations a
#: round there before :func:`solve_once` solves the reduced program instead (when it fits in memory). Measured: the
#: bend converges in 4 at 100-80 000 bars; the S-bend and the 250 mm arch at 400 bars did not within 500 (the
#: identity shift that a compressed wire's Lagrangian Hessian needs on the closure rows' null space turns the
#: iteration linear), where the reduced program takes 14-20.
FULL_VESSEL_ITER = 30

#: Iterations the dense program of bar angles may take over all its rounds when it stands in for a failed full-space
#: solve of a vessel scene (and again for the damped-BFGS retry after it): above :data:`FULL_VESSEL_ITER`'s scenes'
#: sizes an iteration there costs O(n³) (0.2 s at 700 bars, the S-bend's insertion at 12 bars/mm, which converges
#: there in 10-24), so the engine's 500 a round would make a failing step last many minutes instead of failing.
DENSE_FALLBACK_ITER = 100

#: A vessel scene of ``n ≥ NESTED_FROM × NESTED_MIN_BARS`` bars, from the default start, starts from the answer of the
#: same scene at ``max(NESTED_MIN_BARS, n // NESTED_RATIO)`` bars instead (itself so started while it has that many;
#: the coarse answer's nodes interpolated along the wire, :func:`nested_start`). The default start follows the
#: centreline, so the first working-set round modelled the lumen where the wire is not (its rows 1.2 mm off the
#: answer's wall points on the tortuous vessel) and the program spent 11-34 iterations in 3-5 rounds getting there;
#: from the coarse answer it takes 2-6 in 1-3. Measured on the compressed vessels (``branches="first"``, medians of 3,
#: one BLAS thread, the coarse solves included), plain → nested: tortuous 200 / 400 / 1 600 / 3 200 bars 84 → 52,
#: 194 → 69, 556 → 122, 1 537 → 213 ms; S-bend 250 / 400 / 1 600 / 3 200: 97 → 47, 101 → 51, 331 → 100, 716 → 195 ms;
#: arch (250 mm) 250 / 400 / 1 600 / 3 200: 98 → 60, 144 → 63, 349 → 139, 1 382 → 478 ms; the bend (4 iterations
#: either way) within 10 %; the energies the same to 3e-8 (relative). Below 100 bars a coarse chain's bars are
#: long enough (2-4 mm) for the chord rule to need many more rounds. The candidate starts of ``branches="lowest"``
#: are nested too, each from its own start's nodes at the coarse bars (``SolveOptions.nest_start``), and one whose
#: coarse solve fails is dropped: the arch (default ``branches``) at 250 mm and 300 bars 45 s → 1.1 s (a branch start
#: that crept through its rounds), at 240 mm and 240 bars 1.6 → 0.4 s, at 250 mm and 500 / 1 000 bars 1.5 → 0.5 s and
#: 2.2 → 0.8 s, the same answers (1-2 bars/mm, 150-250 mm: the same energy at every length tried); ``s_bend_branch``
#: at 200-320 bars the same or a lower minimum (68-80 mm: 4.59-4.70 against 4.82 N·mm).
NESTED_RATIO = 4
NESTED_MIN_BARS = 100
NESTED_FROM = 2

#: BLAS threads while solving: the matrices are small (≤ 300 variables dense; the full space is sparse), where a
#: second BLAS thread only adds synchronisation (on Table 1, θ_B = π/4, 100 bars, on a 2-core machine under load:
#: 47.7 ms with OpenBLAS's default 2 threads, 7.2 ms with 1). The caller's setting is restored after.
BLAS_THREADS = 1


def run(scene: Scene, options: SolveOptions) -> Solution:
    """Solve ``scene`` with checked ``options``: from the default start (or the given one), then, with
    ``branches="lowest"`` and no given start, from the mirror starts of :mod:`guidewire.solve.branches`, keeping the
    lowest energy. Raises ValueError before any work for a vessel scene too large for memory."""
    check_memory(scene, scene.wire.bars if options.bars is None else int(options.bars), options.layout,
                 options.hessian)
    start = time.perf_counter()
    with _blas_limit():
        first = solve_once(scene, options, start)
        if options.branches == "first" or options.given_start:
            return first
        limit = candidate_iterations(first, options.max_iter)
        candidate = replace(options, initial_nodes=None, multipliers0=None, reuse=None, max_iter=limit,
                            round_iterations=limit, dense_retry=False, nest_start=True)

        def solve_from(x0: Any) -> Solution:
            return solve_once(scene, replace(candidate, initial_angles=x0), time.perf_counter())

        return lowest_branch(first, solve_from, start)


def _solve_in(scene: Scene, options: SolveOptions, layout: str, minimize_options: dict[str, Any],
              runs: list[Any], budget: int | None = None) -> tuple[Formulation, Any, bool]:
    """Formulate ``scene`` in ``layout`` and solve it through the working-set rounds (:func:`rounds`)."""
    form = formulate(scene, layout=layout, scheme=options.scheme, bars=options.bars,
                     initial_angles=options.initial_angles, initial_nodes=options.initial_nodes,
                     wall_nodes="near" if layout == "reduced" else None, reuse=options.reuse)
    limits = [b for b in (budget, options.round_iterations) if b is not None]
    return rounds(form, options.hessian, start_multipliers(form, options.multipliers0), minimize_options, runs,
                  min(limits) if limits else None)


def solve_once(scene: Scene, options: SolveOptions, start: float) -> Solution:
    """One start: formulate, minimize through the working-set rounds, and when the exact Hessian stalls
    (:data:`FALLBACK_STATUSES`) solve the reduced program again from the same start with damped BFGS (at most
    ``min(max_iter, max(FALLBACK_MIN_ITER, max_iter // 5))`` iterations). A vessel scene in the full space by the
    automatic choice gets :data:`FULL_VESSEL_ITER` iterations a round there, then the reduced program, with
    :data:`DENSE_FALLBACK_ITER` iterations over its rounds (its damped-BFGS retry too); neither reduced retry is made
    when the dense program does not fit in memory, nor for a candidate or coarse start (``options.dense_retry``; the
    message says which); a coarse start gets no damped-BFGS retry either (``options.bfgs_retry``). From the default
    start (or a candidate's), a large vessel scene first makes its start by a coarser solve (:func:`nested_start`);
    a candidate whose coarse solve fails is dropped.
    ``start`` is when the clock started."""
    n_bars = scene.wire.bars if options.bars is None else options.bars
    coarse: tuple[int, ...] = ()
    made = nested_start(scene, options, n_bars, start)
    if made is not None and made[0] is not None:
        options = replace(options, initial_angles=None, initial_nodes=made[0])
        coarse = (*made[1].coarse_bars, made[1].n_bars)
    elif made is not None and options.given_start:
        # a candidate whose coarse solve failed is dropped: from its start as given the finer solves crept to their
        # limits too (the arch at 250 mm, 1 000 bars: 50 iterations at 250 bars and at 1 000, 4.7 s, for nothing)
        return replace(made[1], message=f"{made[1].message} (a candidate start: its solve at {made[1].n_bars} bars "
                                        "failed, so it is dropped)")
    layout = options.layout
    if layout == "auto":
        layout = choose_layout(n_bars, options.hessian, scene) if isinstance(n_bars, int) else "reduced"
    minimize_options = options.minimize_options()
    runs: list[Any] = []
    tried = options.layout == "auto" and layout == "full" and scene.vessel is not None
    form, res, settled = _solve_in(scene, options, layout, {**minimize_options, "max_iter": min(
        options.max_iter, FULL_VESSEL_ITER)} if tried else minimize_options, runs)
    failed = not res.success
    dense = not failed or scene.vessel is None or fits_memory(form.model.n, "reduced")
    fallback_budget = DENSE_FALLBACK_ITER if tried and failed else None
    if tried and failed and dense and options.dense_retry:
        form, res, settled = _solve_in(scene, options, "reduced", minimize_options, runs, fallback_budget)
    answer, fallback, message = form, None, None
    if tried and failed and not options.dense_retry:
        message = f"{res.message} (a candidate or coarse start: no retry in the dense program)"
    elif options.hessian == "exact" and res.status in FALLBACK_STATUSES and not dense:
        message = (f"{res.message} (no {FALLBACK} retry: the dense program of bar angles needs about "
                   f"{program_bytes(form.model.n, 'reduced') / 2**30:.1f} GiB, more than the memory available)")
    elif options.hessian == "exact" and res.status in FALLBACK_STATUSES and options.bfgs_retry:
        # Newton–SQP can stall where the exact Lagrangian Hessian is indefinite on the constraints' null space at
        # poor multiplier estimates (a nearly taut stretch between two points); the paper's damped BFGS, started
        # from the exact energy Hessian, does not depend on them: solve again from the same start
        stalled = f"{sqp.Status.from_code(res.status).name} after {res.nit} exact-Hessian iterations"
        max_iter = options.max_iter
        budget = {**minimize_options, "max_iter": min(max_iter, max(FALLBACK_MIN_ITER, max_iter // 5))}
        retry = formulate(form.scene, layout="reduced", initial_angles=form.model.x0, wall_nodes="near", check=False)
        form_q, res_q, settled_q = rounds(retry, "bfgs", None, budget, runs, fallback_budget)
        if res_q.success:
            answer, res, fallback, settled = form_q, res_q, FALLBACK, settled_q
            message = f"{res_q.message} ({FALLBACK}; the exact-Hessian run ended {stalled})"
        else:
            message = (f"{res.message} (a {FALLBACK} retry failed too: "
                       f"{sqp.Status.from_code(res_q.status).name} after {res_q.nit} iterations)")
    return replace(build_solution(answer, res, time.perf_counter() - start, iterations=sum(int(r.nit) for r in runs),
                                  rounds=len(runs), fallback=fallback, message=message, tol=options.tol,
                                  settled=settled), coarse_bars=coarse)


def nested_start(scene: Scene, options: SolveOptions, n_bars: Any, start: float) -> tuple[Any, Solution] | None:
    """The start :data:`NESTED_RATIO` makes for a vessel scene of ``n_bars`` bars from the default start (exact
    Hessian, bars placed by count), or from a given one with ``options.nest_start`` (a candidate start of
    ``branches="lowest"``): the nodes of the scene's answer at ``m = max(NESTED_MIN_BARS, n_bars // NESTED_RATIO)``
    bars (solved by :func:`solve_once`, so itself nested while large enough; from the given start's nodes at the
    coarse chain's arc lengths when there is one) interpolated linearly along the wire at this chain's node arc
    lengths — on the coarse answer's chords, which its rows keep inside the lumen — with the coarse solution (the
    nodes None when it failed: then the default start is used, and a candidate is dropped); None when the scene does
    not qualify."""
    if (scene.vessel is None or (options.given_start and not options.nest_start) or options.hessian != "exact"
            or options.multipliers0 is not None or not isinstance(n_bars, int) or scene.wire.bar_lengths is not None
            or n_bars < NESTED_FROM * NESTED_MIN_BARS):
        return None
    m = max(NESTED_MIN_BARS, n_bars // NESTED_RATIO)
    s = _node_arc_lengths(scene, n_bars)
    # (a start only: one that fails is not worth a retry, densely or with damped BFGS)
    coarse_options = replace(options, bars=m, dense_retry=False, bfgs_retry=False)
    if options.given_start:
        given = options.initial_nodes
        if given is None:
            given = BarChain(np.asarray(scene.base.point, dtype=float), np.diff(s)).nodes(
                np.asarray(options.initial_angles, dtype=float))
        coarse_options = replace(coarse_options, initial_angles=None,
                                 initial_nodes=_along(np.asarray(given, dtype=float), s, _node_arc_lengths(scene, m)))
    coarse = solve_once(scene, coarse_options, start)
    return (_along(coarse.nodes, coarse.s, s) if coarse.success else None), coarse


def _node_arc_lengths(scene: Scene, bars: int) -> Any:
    """Arc length (mm) of every node of the scene's chain of ``bars`` bars (:func:`scene_bars`), base first."""
    lengths, _ = scene_bars(scene.with_bars(bars))
    return np.concatenate(([0.0], np.cumsum(lengths)))


def _along(nodes: Any, s: Any, at: Any) -> Any:
    """The polyline ``nodes`` (at arc lengths ``s``) interpolated linearly at the arc lengths ``at`` (of the same
    wire: the two running sums' last bits aside)."""
    at = np.clip(at * (s[-1] / at[-1]), s[0], s[-1])
    return np.column_stack([np.interp(at, s, nodes[:, i]) for i in range(nodes.shape[1])])


def start_multipliers(form: Formulation, multipliers0: Any) -> list[Any] | None:
    """``multipliers0`` of :func:`guidewire.solve` as ``sqp.minimize`` takes them for ``form``, or None."""
    if multipliers0 is None:
        return None
    if isinstance(multipliers0, Solution | BlockMultipliers):
        return form.multipliers0(multipliers0.blocks, multipliers0.multipliers)
    if isinstance(multipliers0, Sequence) and len(multipliers0) == len(form.blocks):
        return form.multipliers0(form.blocks, multipliers0)
    raise ValueError(f"multipliers0 must be a Solution or {len(form.blocks)} arrays, one per constraint block "
                     f"({', '.join(b.kind for b in form.blocks) or 'none'}).")


def rounds(form: Formulation, hessian: str, multipliers0: Any, options: dict[str, Any],
           runs: list[Any], budget: int | None = None) -> tuple[Formulation, Any, bool]:
    """Solve ``form``; while a block's rows do not fit the answer (:meth:`Block.refine`: a wall's working set misses a
    violated node, a lumen's tangent planes moved), refine them and solve again from the answer and its multipliers
    (matched by row), up to :data:`MAX_ROUNDS` solves. ``options`` are :func:`sqp.minimize`'s; every ``sqp`` result
    is appended to ``runs``; with ``budget`` the rounds stop once their iterations reach it together. Returns the
    formulation solved last, its result, and whether its rows fit that result (False when the rounds ran out
    first: :func:`~guidewire.solve.result.build_solution` then rejects a converged answer, naming the row that
    stands farthest from the constraint it models)."""
    settled = False
    for round_ in range(MAX_ROUNDS):
        args = form.arguments()
        if hessian == "exact":
            args["hess"] = form.hess
            args.update(form.layout.newton_options(form.blocks))
        if multipliers0 is not None:
            args["multipliers0"] = multipliers0
        if budget is not None:
            options = {**options, "max_iter": max(1, min(int(options["max_iter"]), budget))}
        res = sqp.minimize(**args, **options)
        runs.append(res)
        phi = form.angles(res.x)
        tolerance = options["tol"] * max(1.0, form.scene.wire.length)
        refined = [block.refine(form.model, phi, tolerance) for block in form.blocks]
        settled = all(r is None for r in refined)
        if budget is not None:
            budget -= int(res.nit)
        if settled or round_ == MAX_ROUNDS - 1 or (budget is not None and budget <= 0):
            break
        blocks = [b if r is None else r for b, r in zip(form.blocks, refined, strict=True)]
        previous = form
        form = assemble(replace(form.model, x0=phi), form.layout.name, blocks)
        multipliers0 = form.multipliers0(previous.blocks, previous.multipliers(res))
    return form, res, settled


@functools.cache
def _blas() -> Any:
    """One ``threadpoolctl`` controller of the BLAS libraries (inspecting the loaded libraries costs ~1 ms)."""
    return ThreadpoolController().select(user_api="blas")


def _blas_limit() -> Any:
    """A context that runs BLAS on :data:`BLAS_THREADS` threads and restores the caller's setting after; a no-op
    when every BLAS library runs that few already (asking costs ~1 µs a library, where limiting and restoring cost
    ~40 µs a solve)."""
    blas = _blas()
    if all(lib.num_threads <= BLAS_THREADS for lib in blas.lib_controllers):
        return contextlib.nullcontext()
    return blas.limit(limits=BLAS_THREADS, user_api="blas")
