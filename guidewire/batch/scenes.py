"""Many scenes at once: :func:`solve_many` on any :class:`concurrent.futures.Executor`, and the resumable JSON-lines
run of ``python -m guidewire batch`` (:func:`~guidewire.batch.files.solve_files`).

>>> from concurrent.futures import ProcessPoolExecutor
>>> import guidewire
>>> scenes = [s.with_bars(30) for s in guidewire.paper_scenes().values()]
>>> with ProcessPoolExecutor(2) as pool:                                        # doctest: +SKIP
...     results = guidewire.solve_many(scenes, executor=pool, progress=False)
>>> [r.success for r in results]                                                # doctest: +SKIP
[True, True, ..., True, False]

The last scene, the printed Table 5, is infeasible: :func:`guidewire.solve` raises ``ValueError`` on it, and the batch
records that as a :class:`SceneError` (``success`` False, ``error`` the message) and goes on.

What travels between processes (or machines, with Dask's ``distributed.Client(...).get_executor()``) are plain
picklable values: the :class:`~guidewire.Scene` out, a :class:`~guidewire.Solution` (or :class:`SceneError`) back,
never a callable or a formulation. A :class:`~guidewire.Solution` from a batch is *slim*: its raw ``sqp`` ``result``
lacks ``hess``, the final Hessian approximation (a dense ``n × n`` matrix in the reduced layout: 80 kB of the 95 kB
of a pickled 100-bar solution, 8 MB at 1000 bars), which nothing downstream uses (warm starts take ``blocks`` and
``multipliers``, which are kept). Everything else is the solution :func:`guidewire.solve` returns, bit for bit.
"""

from __future__ import annotations

import contextlib
import inspect
import multiprocessing
import signal
import sys
import threading
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import Executor, Future, InvalidStateError, ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field, replace
from typing import Any

from ..scene.scene import Scene
from ..solve.front import solve
from ..solve.result import Solution
from ..status import Status

#: Fields of the raw ``sqp`` result that a batch does not ship back (see the module docstring).
SLIM_DROPPED = ("hess",)

#: :attr:`SceneError.stage` values: the scene file could not be read, :func:`guidewire.solve` raised on the scene,
#: or the executor failed to run it (a worker died, a value did not pickle, the task was cancelled).
STAGES = ("load", "solve", "executor")


@dataclass(frozen=True)
class SceneError:
    """A scene of a batch that produced no solution: its result in place of a :class:`~guidewire.Solution`.

    Attributes
    ----------
    scene : Scene or None
        The scene (None when its file could not be read).
    error : str
        The exception's message (e.g. why the scene is infeasible).
    error_type : str
        The exception's class name (``"ValueError"``).
    stage : {"load", "solve", "executor"}
        Where it was raised (:data:`STAGES`). ``"solve"`` is the scene's own verdict and is the same on every run;
        ``"load"`` and ``"executor"`` are retried by a resumed :func:`solve_files`.
    success : bool
        Always False, so that ``result.success`` reads the same for every result of a batch.
    status : Status
        SCENE_REFUSED, so that ``result.status`` reads the same for every result of a batch.
    """

    scene: Scene | None
    error: str
    error_type: str
    stage: str = "solve"
    success: bool = field(default=False, init=False)
    status: Status = field(default=Status.SCENE_REFUSED, init=False)

    def __post_init__(self) -> None:
        if self.stage not in STAGES:
            raise ValueError(f"stage is {self.stage!r}; expected one of {', '.join(map(repr, STAGES))}.")

    @classmethod
    def from_exception(cls, scene: Scene | None, exc: BaseException, stage: str = "solve") -> SceneError:
        """The error for ``exc`` raised on ``scene``."""
        return cls(scene, str(exc) or type(exc).__name__, type(exc).__name__, stage)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready values: ``success`` (False), ``error`` (the message), ``error_type`` and ``stage``."""
        return {"success": False, "error": self.error, "error_type": self.error_type, "stage": self.stage}


BatchResult = Solution | SceneError
"""What a batch gives for one scene."""


def slim(solution: Solution) -> Solution:
    """``solution`` with a raw ``sqp`` result lacking the fields of :data:`SLIM_DROPPED` (a copy; the rest shared)."""
    res = solution.result
    if isinstance(res, dict) and any(key in res for key in SLIM_DROPPED):
        kept = type(res)({key: value for key, value in res.items() if key not in SLIM_DROPPED})
        return replace(solution, result=kept)
    return solution


def solve_one(scene: Scene, options: dict[str, Any]) -> BatchResult:
    """Solve one scene as a batch does: a slim :class:`~guidewire.Solution`, or a :class:`SceneError` when
    :func:`guidewire.solve` raises (any ``Exception``). Runs in the worker."""
    try:
        return slim(solve(scene, **options))
    except Exception as exc:  # one scene's exception is that scene's result, never the batch's
        return SceneError.from_exception(scene, exc, "solve")


def solve_chunk(scenes: Sequence[Scene], options: dict[str, Any]) -> list[BatchResult]:
    """:func:`solve_one` on each of ``scenes``: one task of a batch with ``chunksize > 1``."""
    return [solve_one(scene, options) for scene in scenes]


def check_solve_options(options: dict[str, Any]) -> None:
    """TypeError naming an option :func:`guidewire.solve` does not take, before anything is submitted (a typo would
    otherwise be every scene's error)."""
    parameters = inspect.signature(solve).parameters
    unknown = sorted(set(options) - {name for name, p in parameters.items() if p.kind is p.KEYWORD_ONLY})
    if unknown:
        known = ", ".join(name for name, p in parameters.items() if p.kind is p.KEYWORD_ONLY)
        raise TypeError(f"solve option {unknown[0]!r} is not an option of guidewire.solve; its options are {known}.")


def default_executor(workers: int | None = None) -> ProcessPoolExecutor:
    """A :class:`~concurrent.futures.ProcessPoolExecutor` of ``workers`` processes (default: one per CPU).

    Its workers start from a fork server (spawned on platforms without one) rather than by forking this process,
    which may hold threads (BLAS, a Dask client, a progress bar) that a fork would copy mid-flight. Each worker
    limits its BLAS to one thread (:func:`single_thread_blas`), as Dask's workers do: with a process per core,
    BLAS threads only compete (measured on 2 cores, 100 bars: 2 workers with 2 BLAS threads each ran at 0.54× the
    serial throughput, with one thread each at about 2×), and ignores Ctrl-C (:func:`_worker_setup`).
    """
    check_workers(workers)
    method = "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"
    return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context(method),
                               initializer=_worker_setup)


def _worker_setup() -> None:
    """A default pool's worker: one BLAS thread (:func:`single_thread_blas`), and Ctrl-C left to the parent, which
    stops the workers itself (a worker interrupted too would print its own traceback)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    single_thread_blas()


@contextlib.contextmanager
def _main_unseen() -> Iterator[None]:
    """Start processes that do not import the caller's script.

    A spawned or fork-server worker imports the parent's ``__main__`` from its file before it runs anything, so a
    script without an ``if __name__ == "__main__":`` guard runs again in every worker, where its call of
    :func:`solve_many` may not start processes: the pool breaks and every scene came back an executor error. The
    default pool's tasks are this module's functions on guidewire's values, which never need the script, so while
    its workers start, ``__main__`` shows no file or module name (what :mod:`multiprocessing` reads to import it
    there) and the workers import only what the tasks name.
    """
    main = sys.modules.get("__main__")
    if main is None:
        yield
        return
    saved = {name: main.__dict__[name] for name in ("__file__", "__spec__") if name in main.__dict__}
    try:
        main.__dict__.pop("__file__", None)
        main.__dict__["__spec__"] = None
        yield
    finally:
        main.__dict__.pop("__spec__", None)
        main.__dict__.update(saved)


def single_thread_blas() -> bool:
    """Limit this process's BLAS/OpenMP pools to one thread, with threadpoolctl when it is installed (it is
    optional; it comes with the ``cluster`` extra). Returns whether it could."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        return False
    threadpool_limits(limits=1)  # kept: the limits are restored only on leaving it as a context manager
    return True


def check_workers(workers: Any) -> None:
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers is {workers!r}; expected a whole number of processes, at least 1.")


def _progress_bar(total: int, enabled: bool) -> Any:
    """A tqdm bar counting scenes (its rate is the throughput), or None without tqdm or when not enabled."""
    if not enabled:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:  # tqdm is optional: no bar
        return None
    return tqdm(total=total, unit="scene", desc="solve", smoothing=0.1)


def solve_iter(
    scenes: Iterable[Scene],
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    progress: bool = True,
    chunksize: int = 1,
    **solve_options: Any,
) -> Iterator[tuple[int, BatchResult]]:
    """Solve every scene on ``executor`` and yield ``(index, result)`` as each completes (see :func:`solve_many`).

    The arguments are checked at the call (TypeError/ValueError as :func:`solve_many`); the solving happens while
    the iterator is consumed. Stopping early (``break``, an exception, Ctrl-C) cancels the scenes not yet started
    and, when the executor is this function's own, shuts it down.
    """
    scenes = list(scenes)
    for i, scene in enumerate(scenes):
        if not isinstance(scene, Scene):
            raise TypeError(f"scenes[{i}] is {type(scene).__name__}; expected guidewire.Scene.")
    if isinstance(chunksize, bool) or not isinstance(chunksize, int) or chunksize < 1:
        raise ValueError(f"chunksize is {chunksize!r}; expected a whole number of scenes per task, at least 1.")
    check_workers(workers)
    if executor is not None and workers is not None:
        raise ValueError("give workers (the size of the default process pool) or executor, not both.")
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise TypeError(f"executor is {type(executor).__name__}; expected a concurrent.futures.Executor "
                        "(anything with submit(fn, *args) returning a Future).")
    check_solve_options(solve_options)
    return _run(scenes, executor, workers, progress, chunksize, solve_options)


def _run(scenes: list[Scene], executor: Executor | None, workers: int | None, progress: bool, chunksize: int,
         solve_options: dict[str, Any]) -> Iterator[tuple[int, BatchResult]]:
    """The generator of :func:`solve_iter` (arguments checked): one task per ``chunksize`` scenes."""
    tasks = []
    for start in range(0, len(scenes), chunksize):
        indices = range(start, min(start + chunksize, len(scenes)))
        if chunksize == 1:
            tasks.append((solve_one, (scenes[start], solve_options), indices))
        else:
            tasks.append((solve_chunk, (scenes[indices.start:indices.stop], solve_options), indices))
    return run_tasks(tasks, scenes, executor, workers, progress)


def run_tasks(tasks: Sequence[tuple[Callable[..., Any], tuple[Any, ...], range]], scenes: Sequence[Scene],
              executor: Executor | None, workers: int | None, progress: bool) -> Iterator[tuple[int, Any]]:
    """Submit every ``(fn, args, indices)`` task and yield ``(index, result)`` for the items ``indices`` of each as it
    completes (a task that the executor could not run: a :class:`SceneError` for each of its ``scenes``). Stopping
    early cancels the tasks not yet started and, when the executor is the default one made here, shuts it down."""
    own = executor is None
    pool = default_executor(workers) if own else executor
    bar = _progress_bar(len(scenes), progress)
    futures: dict[Future[Any], range] = {}
    stopped = False
    try:
        with _main_unseen() if own else contextlib.nullcontext():  # (the workers start during the submits)
            for fn, args, indices in tasks:
                futures[pool.submit(fn, *args)] = indices
        for future in as_completed(futures):
            indices = futures.pop(future)
            outcome = _outcome(future, [scenes[i] for i in indices])
            if bar is not None:
                bar.update(len(indices))
            yield from zip(indices, outcome, strict=True)
    except BaseException:  # (KeyboardInterrupt, SIGTERM made one by the CLI, an error of the caller's)
        if own:
            _terminate(pool)
            stopped = True
        raise
    finally:
        for future in futures:
            future.cancel()
        if bar is not None:
            bar.close()
        if own and not stopped:  # (a stopped pool's workers are reaped already: waiting on its manager could hang)
            pool.shutdown(wait=True, cancel_futures=True)


def _terminate(pool: Executor) -> None:
    """Stop a default pool's workers now, mid-scene, and reap them: an interrupted batch leaves no process behind
    (its fork server and resource tracker end with this process, when their pipes close)."""
    workers = list((getattr(pool, "_processes", None) or {}).values())  # (shutdown forgets them: read first)
    _quiet_manager(pool)
    pool.shutdown(wait=False, cancel_futures=True)
    for worker in workers:
        if worker.is_alive():
            worker.terminate()
    for worker in workers:
        worker.join(timeout=5.0)


def _quiet_manager(pool: Executor) -> None:
    """Keep the pool's manager thread from printing a traceback as it notices its workers gone: it then sets an
    exception on every task still pending, and CPython's executor (3.11) raises ``InvalidStateError`` on a task
    cancelled meanwhile (a race with the cancels above: one SIGTERM in a few hundred). That one error of that thread
    is dropped; any other still reaches the previous hook."""
    manager = getattr(pool, "_executor_manager_thread", None)
    if manager is None:
        return
    previous = threading.excepthook

    def hook(args: Any) -> None:
        if args.thread is manager and issubclass(args.exc_type, InvalidStateError):
            return
        previous(args)

    threading.excepthook = hook


def _outcome(future: Future[Any], scenes: list[Scene]) -> list[BatchResult]:
    """The results of a finished task: its value, or an executor-stage :class:`SceneError` for each of its scenes."""
    try:
        value = future.result()
    except BaseException as exc:  # the executor could not run it (a dead worker, a cancelled task, no pickling)
        if isinstance(exc, KeyboardInterrupt | SystemExit):
            raise
        return [SceneError.from_exception(scene, exc, "executor") for scene in scenes]
    return list(value) if isinstance(value, list) else [value]


def solve_many(
    scenes: Iterable[Scene],
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    progress: bool = True,
    ordered: bool = True,
    chunksize: int = 1,
    **solve_options: Any,
) -> list[BatchResult]:
    """Solve each scene with :func:`guidewire.solve` on an executor; one scene's failure never stops the batch.

    Parameters
    ----------
    scenes : iterable of Scene
    executor : concurrent.futures.Executor, optional
        Where to solve: anything with ``submit(fn, *args)`` returning a :class:`~concurrent.futures.Future` — a
        :class:`~concurrent.futures.ProcessPoolExecutor`, Dask's ``distributed.Client(...).get_executor()``, a
        :class:`~concurrent.futures.ThreadPoolExecutor` (no speed-up: the solver holds the GIL). Left open. Default:
        :func:`default_executor` of ``workers`` processes, shut down at the end.
    workers : int, optional
        Processes of the default executor (default: one per CPU); not with ``executor``.
    progress : bool
        Show a progress bar with the throughput (scenes/s) on stderr, when tqdm is installed (it is optional).
    ordered : bool
        True (default): the results in the order of ``scenes``. False: in the order they completed (each
        result's ``scene`` says which it is).
    chunksize : int
        Scenes per task (default 1). More amortises an executor's per-task cost (a Dask task costs milliseconds)
        over scenes that solve in milliseconds.
    **solve_options
        Passed to :func:`guidewire.solve` for every scene (``bars``, ``scheme``, ``qp_solver``, ``tol``, ...);
        an option it does not take is a TypeError before anything runs.

    Returns
    -------
    list of Solution or SceneError
        A slim :class:`~guidewire.Solution` per solved scene (see the module docstring; an unconverged solve is a
        Solution with ``success`` False), a :class:`SceneError` per scene on which :func:`guidewire.solve` raised
        (``stage="solve"``, e.g. an infeasible scene) or which the executor could not run (``stage="executor"``).

    Raises
    ------
    TypeError, ValueError
        For a scene that is not a :class:`~guidewire.Scene`, an unknown solve option, or bad ``workers``/
        ``chunksize``/``executor``, before any solve.
    """
    results = solve_iter(scenes, executor=executor, workers=workers, progress=progress, chunksize=chunksize,
                         **solve_options)
    if not ordered:
        return [result for _, result in results]
    pairs = sorted(results, key=lambda pair: pair[0])
    return [result for _, result in pairs]
