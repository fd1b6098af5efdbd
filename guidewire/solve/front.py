"""``solve(scene)``: one pipeline whatever the layout — formulate → minimize → working-set rounds → fallback →
solution."""

from __future__ import annotations

import contextlib
import functools
import time
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import sqp

from ..program.formulation import LAYOUTS, BlockMultipliers, Formulation, assemble, formulate
from ..scene.scene import Scene
from .branches import candidate_iterations, check_branches, lowest_branch
from .result import Solution, build_solution

#: Rounds of the working set: solve, refine every block whose rows do not fit the answer (a wall: add the violating
#: nodes and their neighbours; a lumen: move its tangent planes), solve again from the answer.
MAX_ROUNDS = 8

#: ``layout="auto"`` uses the full-space program above this many bars for scenes with walls (see
#: :func:`choose_layout`): :data:`sqp.DENSE_LIMIT`, the most the reduced program's dense wall rows stay with DAQP
#: (measured with DAQP in the Hessian factor's coordinates, :data:`sqp.backends.LDP_MIN_VARIABLES`: Fig. 6a / 6b
#: reduced 6.9 / 6.7 ms against full 13.7 / 16.3 ms at 200 bars, 14.1 / 13.7 against 20.8 / 20.5 ms at 300).
FULL_SPACE_BARS = 300

#: The damped-BFGS retry of :func:`solve` may take ``min(max_iter, max(FALLBACK_MIN_ITER, max_iter // 5))``
#: iterations (it needed 12 where the exact-Hessian run stalled; an infeasible scene fails twice, the second time
#: quickly; the user's ``max_iter`` is never exceeded).
FALLBACK_MIN_ITER = 50

#: Outcomes of an exact-Hessian solve after which :func:`solve` tries the damped-BFGS algorithm from the same start.
FALLBACK_STATUSES = tuple(status.code for status in (
    sqp.Status.MAX_ITER, sqp.Status.LINE_SEARCH, sqp.Status.SMALL_STEP, sqp.Status.INFEASIBLE, sqp.Status.QP_FAILED))

#: The name :attr:`Solution.fallback` gives the retry.
FALLBACK = "damped BFGS"


def choose_layout(bars: int, hessian: str = "exact", scene: Scene | None = None) -> str:
    """What ``layout="auto"`` means: the reduced program (angles only) for contact scenes at every ``n`` and for
    wall scenes up to :data:`FULL_SPACE_BARS` bars; the full-space one (:mod:`guidewire.program.full_space`: angles and
    nodes, every row sparse) for wall scenes above, with the exact Hessian.

    Contact scenes (no walls, no vessel) have equality-only subproblems with a few dense rows and a banded energy
    Hessian: above :data:`sqp.hessian.STRUCTURED_MIN` the engine solves them by a structured KKT solve
    (:mod:`sqp.structured`), Newton's step in 3-4 iterations at every n. Measured, reduced against full in one
    process (medians of 5, BLAS one thread): Table 1 (π/4) 0.50x / 0.29x / 0.17x the time at 200 / 400 / 1600
    bars, Table 2 (π/4) 0.47x / 0.37x / 0.20x, Table 1 (-π/2) and Table 2 (π/2) alike. Wall rows are
    inequalities, dense in the reduced program: measured on Fig. 6a at 400 / 1600 bars reduced 2.1 s / 76 s, full
    28 ms / 0.10 s. The BFGS path stays reduced (the paper's algorithm), and so do vessel scenes: with the lumen's
    curved (quadratic) rows the full-space program is not yet reliable (the aortic arch at 245 bars ended MAX_ITER
    three rounds running, where the reduced one converges)."""
    if scene is not None and (scene.vessel is not None or not scene.walls):
        return "reduced"
    return "full" if hessian == "exact" and bars > FULL_SPACE_BARS else "reduced"


#: Peak memory of a vessel scene's dense program of bar angles, in units of ``n^2`` float64 values (``n`` bars):
#: measured 24-26 from the peak resident size at 200, 400 and 800 bars (the dense Hessian, its factor, the lumen
#: rows' Jacobian and the QP's copies).
DENSE_COPIES = 26


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation (``MemAvailable`` of ``/proc/meminfo``), or None where unknown."""
    try:
        with open("/proc/meminfo") as info:
            for line in info:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def check_memory(scene: Scene, bars: int, layout: str = "auto") -> None:
    """Refuse, before any work, a vessel scene whose dense program of bar angles would not fit in memory: a
    ValueError that gives the memory needed, the memory available and the largest bar count that fits."""
    if scene.vessel is None or layout == "full":
        return
    need = DENSE_COPIES * 8.0 * float(bars) ** 2
    have = available_memory()
    if have is None or need <= have:
        return
    fits = int((have / (DENSE_COPIES * 8.0)) ** 0.5)
    raise ValueError(
        f"a vessel scene with {bars} bars needs about {need / 2**30:.1f} GiB for its dense program of bar angles "
        f"({DENSE_COPIES} n² double values), more than the {have / 2**30:.1f} GiB available; use at most {fits} "
        "bars (bars = ..., or fewer bars per mm in the scene file).")


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
    tol: float = 1e-8,
    max_iter: int = 500,
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
        (default): :func:`choose_layout`. Both give the same shape and the same multipliers.
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
        reflected about the chord between poses) and keep the lowest energy; ``Solution.starts`` counts the starts.
        Not with ``initial_angles``/``initial_nodes`` (a given start chooses its branch). ``"first"``: the default
        start's answer only.

    Returns
    -------
    Solution
        Also when the solver fails: then ``success`` is False, ``status``/``message`` say why, and no forces are
        reported. Walls are constrained through a working set of nodes in the reduced layout (those near the wall at
        the start, plus any found violating it), and the returned shape is checked against every wall at every
        node. When an exact-Hessian solve stalls (:data:`FALLBACK_STATUSES`), the reduced program is solved again
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
    if density not in (None, "uniform", "curvature"):
        raise ValueError(f"density is {density!r}; expected 'uniform' or 'curvature' (or None: the wire's).")
    if tol_mm is not None or (density == "curvature" and scene.wire.bar_lengths is None):
        if any(v is not None for v in (initial_angles, initial_nodes, multipliers0)) or (tol_mm and bars):
            raise ValueError("tol_mm and density='curvature' choose the bars and the starts; do not pass "
                             "initial_angles, initial_nodes or multipliers0 (nor bars with tol_mm).")
        from . import refine

        kw = {"scheme": scheme, "hessian": hessian, "layout": layout, "qp_solver": qp_solver,
              "qp_options": qp_options, "tol": tol, "max_iter": max_iter, "verbose": verbose,
              "branches": branches}
        if tol_mm is not None:
            return refine.solve_to_tolerance(scene, tol_mm, density=density or "curvature", **kw)
        return refine.solve_graded(scene, scene.wire.bars if bars is None else bars, **kw)
    if hessian not in ("exact", "bfgs"):
        raise ValueError(f"hessian is {hessian!r}; expected 'exact' or 'bfgs'.")
    if layout not in ("auto", *LAYOUTS):
        raise ValueError(f"layout is {layout!r}; expected 'auto', 'reduced' or 'full'.")
    if layout == "full" and hessian != "exact":
        raise ValueError("layout='full' needs hessian='exact' (the BFGS path is the paper's reduced program).")
    check_memory(scene, scene.wire.bars if bars is None else int(bars), layout)
    start = time.perf_counter()
    with _blas_limit():
        first = _solve(scene, start, scheme, bars, initial_angles, initial_nodes, hessian, layout, multipliers0,
                       qp_solver, qp_options, tol, max_iter, verbose, reuse)
        if branches == "first" or initial_angles is not None or initial_nodes is not None:
            return first
        limit = candidate_iterations(first, max_iter)
        return lowest_branch(first, lambda x0: _solve(scene, time.perf_counter(), scheme, bars, x0, None, hessian,
                                                      layout, None, qp_solver, qp_options, tol, limit, verbose),
                             start)


#: BLAS threads while solving: the matrices are small (≤ 300 variables dense; the full space is sparse), where a
#: second BLAS thread only adds synchronisation — measured on Table 1 (θ_B = π/4, 100 bars) on the 2-core machine
#: under load: 47.7 ms with OpenBLAS's default 2 threads, 7.2 ms with 1. The caller's setting is restored after.
BLAS_THREADS = 1


@functools.cache
def _blas() -> Any:
    """One ``threadpoolctl`` controller of the BLAS libraries (inspecting the loaded libraries costs ~1 ms)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController().select(user_api="blas")


def _blas_limit() -> Any:
    """A context that runs BLAS on :data:`BLAS_THREADS` threads and restores the caller's setting after; a no-op
    when every BLAS library runs that few already (asking costs ~1 µs a library, where limiting and restoring cost
    ~40 µs a solve)."""
    blas = _blas()
    if all(lib.num_threads <= BLAS_THREADS for lib in blas.lib_controllers):
        return contextlib.nullcontext()
    return blas.limit(limits=BLAS_THREADS, user_api="blas")


def _solve(scene: Scene, start: float, scheme: str | None, bars: int | None, initial_angles: Any,
           initial_nodes: Any, hessian: str, layout: str, multipliers0: Any, qp_solver: str | None,
           qp_options: dict[str, Any] | None, tol: float, max_iter: int, verbose: bool, reuse: Any = None) -> Solution:
    n_bars = scene.wire.bars if bars is None else bars
    if layout == "auto":
        layout = choose_layout(n_bars, hessian, scene) if isinstance(n_bars, int) else "reduced"
    form = formulate(scene, layout=layout, scheme=scheme, bars=bars, initial_angles=initial_angles,
                     initial_nodes=initial_nodes, wall_nodes="near" if layout == "reduced" else None, reuse=reuse)
    options = {"qp_solver": None if qp_solver == "auto" else qp_solver, "qp_options": qp_options, "tol": tol,
               "max_iter": max_iter, "verbose": verbose}
    if options["qp_solver"] is None:
        del options["qp_solver"]
    runs: list[Any] = []
    first, res = _rounds(form, hessian, _start_multipliers(form, multipliers0), options, runs)
    answer, fallback, message = first, None, None
    if hessian == "exact" and res.status in FALLBACK_STATUSES:
        # Newton–SQP can stall where the exact Lagrangian Hessian is indefinite on the constraints' null space at
        # poor multiplier estimates (a nearly taut stretch between two points); the paper's damped BFGS, started
        # from the exact energy Hessian, does not depend on them: solve again from the same start
        stalled = f"{sqp.Status.from_code(res.status).name} after {res.nit} exact-Hessian iterations"
        budget = {**options, "max_iter": min(max_iter, max(FALLBACK_MIN_ITER, max_iter // 5))}  # (a failure: quick)
        retry = formulate(form.scene, layout="reduced", initial_angles=form.model.x0, wall_nodes="near", check=False)
        form_q, res_q = _rounds(retry, "bfgs", None, budget, runs)
        if res_q.success:
            answer, res, fallback = form_q, res_q, FALLBACK
            message = f"{res_q.message} ({FALLBACK}; the exact-Hessian run ended {stalled})"
        else:
            message = (f"{res.message} (a {FALLBACK} retry failed too: "
                       f"{sqp.Status.from_code(res_q.status).name} after {res_q.nit} iterations)")
    return build_solution(answer, res, time.perf_counter() - start, iterations=sum(int(r.nit) for r in runs),
                          rounds=len(runs), fallback=fallback, message=message, tol=tol)


def _start_multipliers(form: Formulation, multipliers0: Any) -> list[Any] | None:
    """``multipliers0`` of :func:`solve` as ``sqp.minimize`` takes them for ``form``, or None."""
    if multipliers0 is None:
        return None
    if isinstance(multipliers0, Solution | BlockMultipliers):
        return form.multipliers0(multipliers0.blocks, multipliers0.multipliers)
    if isinstance(multipliers0, Sequence) and len(multipliers0) == len(form.blocks):
        return form.multipliers0(form.blocks, multipliers0)
    raise ValueError(f"multipliers0 must be a Solution or {len(form.blocks)} arrays, one per constraint block "
                     f"({', '.join(b.kind for b in form.blocks) or 'none'}).")


def _rounds(form: Formulation, hessian: str, multipliers0: Any, options: dict[str, Any],
            runs: list[Any]) -> tuple[Formulation, Any]:
    """Solve ``form``; while a block's rows do not fit the answer (:meth:`Block.refine`: a wall's working set misses a
    violated node, a lumen's tangent planes moved), refine them and solve again from the answer and its multipliers
    (matched by row), up to :data:`MAX_ROUNDS` times. Every ``sqp`` result is appended to ``runs``."""
    for _ in range(MAX_ROUNDS):
        args = form.arguments()
        if hessian == "exact":
            args["hess"] = form.hess
        if multipliers0 is not None:
            args["multipliers0"] = multipliers0
        res = sqp.minimize(**args, **options)
        runs.append(res)
        phi = form.angles(res.x)
        tolerance = options["tol"] * max(1.0, form.scene.wire.length)
        refined = [block.refine(form.model, phi, tolerance) for block in form.blocks]
        if all(r is None for r in refined):
            break
        blocks = [b if r is None else r for b, r in zip(form.blocks, refined, strict=True)]
        previous = form
        form = assemble(replace(form.model, x0=phi), form.layout.name, blocks)
        multipliers0 = form.multipliers0(previous.blocks, previous.multipliers(res))
    return form, res
