"""The resumable JSON-lines run of ``python -m guidewire batch`` (:func:`solve_files`): every scene file solved by
:func:`~guidewire.batch.scenes.solve_iter`, one JSON line per scene as it finishes, the files already in the output
skipped on a rerun."""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable, Iterable
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..scene.file import load_scene
from ..scene.scene import Scene
from .scenes import BatchResult, SceneError, check_solve_options, solve_iter


def record(result: BatchResult, *, name: str, file: str | None) -> dict[str, Any]:
    """One JSON line of a batch: ``name`` and ``file`` (absolute path, or None for a scene given as a value), then
    :meth:`Solution.to_dict` or :meth:`SceneError.to_dict`."""
    return {"name": name, "file": file, **result.to_dict()}


def scene_files(paths: Iterable[str | Path]) -> list[Path]:
    """The scene files named by ``paths``: a file as given, a directory's ``*.toml`` files (not its subdirectories),
    each once (absolute), in the order given and by name within a directory.

    Raises
    ------
    ValueError
        A path that does not exist, or a directory without ``*.toml`` files.
    """
    files: dict[Path, None] = {}
    for path in map(Path, paths):
        if path.is_dir():
            found = sorted(p for p in path.glob("*.toml") if p.is_file())
            if not found:
                raise ValueError(f"{path}: a directory without scene files (*.toml)")
            files.update(dict.fromkeys(p.resolve() for p in found))
        elif path.is_file():
            files[path.resolve()] = None
        else:
            raise ValueError(f"{path}: no such scene file or directory")
    return list(files)


def done_files(out: str | Path) -> set[str]:
    """The ``file`` of every record in the JSON-lines file ``out`` that a resumed run skips: solved scenes and
    scenes whose solve raised (a scene that could not be read, or that the executor could not run, is retried).
    An unfinished last line (a run killed while writing) is cut off. Nothing when ``out`` does not exist."""
    path = Path(out)
    if not path.exists():
        return set()
    data = path.read_bytes()
    if data and not data.endswith(b"\n"):
        with path.open("r+b") as handle:
            handle.truncate(data.rfind(b"\n") + 1)
        data = data[: data.rfind(b"\n") + 1]
    done = set()
    for number, line in enumerate(data.decode("utf-8").splitlines(), 1):
        if not line.strip():
            continue
        try:
            item = json.loads(line)
        except json.JSONDecodeError as exc:
            raise ValueError(f"{path}: line {number} is not JSON ({exc.msg}); is it a batch's output?") from None
        if not isinstance(item, dict) or not isinstance(item.get("file"), str):
            raise ValueError(f"{path}: line {number} has no 'file'; is it a batch's output?")
        if item.get("success") is not False or item.get("stage", "solve") == "solve":
            done.add(item["file"])
    return done


@dataclass(frozen=True)
class BatchSummary:
    """What :func:`solve_files` did.

    Attributes
    ----------
    converged, not_converged, errors : int
        Scenes of this run solved successfully, solved without convergence, and without a solution
        (:class:`SceneError`: unreadable, raised, or not run).
    skipped : int
        Scenes already in the output (resumed).
    seconds : float
        Wall-clock time of this run's solving.
    """

    converged: int
    not_converged: int
    errors: int
    skipped: int
    seconds: float

    @property
    def ran(self) -> int:
        """Scenes of this run."""
        return self.converged + self.not_converged + self.errors

    @property
    def throughput(self) -> float:
        """Scenes per second in this run (nan when none ran)."""
        return self.ran / self.seconds if self.ran and self.seconds > 0 else float("nan")

    def __str__(self) -> str:
        rate = f", {self.throughput:.3g} scenes/s" if self.ran else ""
        return (f"{self.ran} scenes in {self.seconds:.3g} s{rate}: {self.converged} converged, {self.not_converged} "
                f"not converged, {self.errors} without a solution; {self.skipped} already in the output")


def solve_files(
    paths: Iterable[str | Path],
    out: str | Path,
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    progress: bool = True,
    chunksize: int = 1,
    on_result: Callable[[dict[str, Any]], None] | None = None,
    **solve_options: Any,
) -> BatchSummary:
    """Solve scene files into the JSON-lines file ``out``, one :func:`record` per scene, appended as each completes
    (so a killed run keeps what it finished) and skipping the files already there (:func:`done_files`).

    ``paths`` are files or directories (:func:`scene_files`); a file that does not read as a scene is recorded
    (``stage="load"``) like a scene whose solve raised. ``on_result`` is called with each record written. The other
    parameters are :func:`solve_many`'s.

    Raises
    ------
    ValueError, TypeError
        Bad ``paths``, an ``out`` that is not a batch's output, bad options: before any solve.
    """
    check_solve_options(solve_options)
    files = scene_files(paths)
    done = done_files(out)
    todo = [f for f in files if str(f) not in done]
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    counts = {"converged": 0, "not_converged": 0, "errors": 0}
    start = time.perf_counter()
    with out.open("a", encoding="utf-8") as handle:

        def write(item: dict[str, Any]) -> None:
            handle.write(json.dumps(item) + "\n")
            handle.flush()
            os.fsync(handle.fileno())
            key = "errors" if "error" in item else "converged" if item["success"] else "not_converged"
            counts[key] += 1
            if on_result is not None:
                on_result(item)

        loaded: list[tuple[Path, Scene]] = []
        for file in todo:
            try:
                loaded.append((file, load_scene(file)))
            except (OSError, ValueError) as exc:
                write(record(SceneError.from_exception(None, exc, "load"), name=file.stem, file=str(file)))
        if loaded:
            results = solve_iter([scene for _, scene in loaded], executor=executor, workers=workers,
                                 progress=progress, chunksize=chunksize, **solve_options)
            for index, result in results:
                file, scene = loaded[index]
                write(record(result, name=scene.name or file.stem, file=str(file)))
    return BatchSummary(**counts, skipped=len(files) - len(todo), seconds=time.perf_counter() - start)
