"""Many insertions on an executor: :func:`insert_many`, the :func:`guidewire.insert` counterpart of
:func:`guidewire.batch.solve_many` (same executors, same failure-as-data rule, slim solutions)."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from concurrent.futures import Executor
from dataclasses import replace
from typing import Any

from ..march.insertion import Insertion, insert
from ..scene.scene import Scene
from .scenes import SceneError, check_workers, run_tasks, slim

InsertResult = Insertion | SceneError


def insert_one(scene: Scene, lengths: Sequence[float], options: dict[str, Any]) -> InsertResult:
    """One insertion as a batch runs it (in the worker): an :class:`~guidewire.Insertion` with slim steps, or a
    :class:`~guidewire.batch.SceneError` when :func:`guidewire.insert` raises."""
    try:
        out = insert(scene, lengths, **options)
    except Exception as exc:  # one insertion's exception is its result, never the batch's
        return SceneError.from_exception(scene, exc, "solve")
    return replace(out, steps=[slim(step) for step in out.steps])


def insert_many(
    jobs: Iterable[tuple[Scene, Sequence[float]]],
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    progress: bool = True,
    **options: Any,
) -> list[InsertResult]:
    """Run :func:`guidewire.insert` for every ``(scene, lengths)`` job on an executor, results in input order.

    Parameters
    ----------
    jobs : iterable of (Scene, sequence of float)
        The scene (its bar density is kept) and the inserted lengths (mm) of each insertion.
    executor, workers, progress
        As :func:`guidewire.batch.solve_many` (default: a process pool with one BLAS thread per worker).
    **options
        Passed to :func:`guidewire.insert` (``predictor``, ``qp_solver``, ``tol``, ...).

    Returns
    -------
    list of Insertion or SceneError
        An insertion that raised (bad lengths, an infeasible first step…) is a ``SceneError`` naming why; a step that
        failed to converge is a step of its insertion, as with :func:`guidewire.insert`.
    """
    jobs = [(scene, [float(v) for v in lengths]) for scene, lengths in jobs]
    for i, (scene, _) in enumerate(jobs):
        if not isinstance(scene, Scene):
            raise TypeError(f"jobs[{i}][0] is {type(scene).__name__}; expected guidewire.Scene.")
    check_workers(workers)
    if executor is not None and workers is not None:
        raise ValueError("give workers (the size of the default process pool) or executor, not both.")
    scenes = [scene for scene, _ in jobs]
    tasks = [(insert_one, (scene, lengths, options), range(i, i + 1)) for i, (scene, lengths) in enumerate(jobs)]
    return [result for _, result in sorted(run_tasks(tasks, scenes, executor, workers, progress),
                                           key=lambda pair: pair[0])]
