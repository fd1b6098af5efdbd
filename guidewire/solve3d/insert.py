"""Quasi-static insertion and rotation in 3-D: pushed, pulled and turned step by step, each step warm-started.

Each step is one :func:`guidewire.solve3d.solve3d` of the scene at that step's inserted length and clamp rotation,
started from the previous step's answer by the *track* predictor: the wire slides along its previous shape (the
first ``L_prev`` of the new wire lies where the previous wire lay, a longer wire continues the previous tip's tangent),
and every bar keeps the roll of the material now there (the frame of the material at ``s − ΔL`` in the previous step,
turned onto the new tangent by the least rotation; the new material at the entrance takes the clamp's frame). A
rotation step changes the clamp's frame only: the first joints take the twist and the solve spreads it.

The bar density of the scene (``wire.bars / wire.length``) is kept: a step of length ``L`` has ``round(L · density)``
bars (at least one per piece); with refined sections (a J tip of finer bars, :attr:`guidewire.Section.refinement`)
the density is per refined mm (:attr:`guidewire.Wire.bar_density`), so the tip keeps its bars as the shaft grows.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..rod import kinematics
from ..rod import quaternion as quat
from ..status import Status, outcome
from .program import bar_layout
from .result import Solution3D
from .scene import Scene3D
from .solve import solve3d

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Insertion3D:
    """The steps of :func:`insert3d`: the asked lengths (mm) and rotations (rad), one :class:`Solution3D` per step
    solved, the wall time (s), and why it stopped early (None when complete)."""

    lengths: tuple[float, ...]
    rotations: tuple[float, ...]
    steps: list[Solution3D]
    seconds: float
    error: str | None = None

    @property
    def complete(self) -> bool:
        return self.error is None and len(self.steps) == len(self.lengths)

    @property
    def status(self) -> Status:
        """Why the insertion ended (:func:`guidewire.status.outcome`)."""
        return outcome(self.steps, self.error)

    def to_dict(self) -> dict[str, Any]:
        return {"complete": self.complete, "status": self.status.name, "error": self.error, "seconds": self.seconds,
                "steps": [dict(s.to_dict(), inserted_length=float(np.sum(s.lengths)), rotation=s.base_rotation)
                          for s in self.steps]}


def scene_at(scene: Scene3D, length: float, rotation: float, density: float) -> Scene3D:
    """``scene`` inserted to ``length`` (mm) with the clamp turned to ``rotation`` (rad), ``density`` bars per mm
    (per refined mm where sections are refined: :meth:`guidewire.Wire.bars_at`)."""
    wire = scene.wire.with_length(length)
    bars = scene.wire.bars_at(length, density)
    try:
        return replace(scene.with_rotation(rotation), wire=replace(wire, bars=bars, bar_lengths=None))
    except ValueError:  # fewer bars than pieces: one per piece
        return replace(scene.with_rotation(rotation), wire=replace(wire, bars=bars + len(wire.sections) + 2,
                                                                   bar_lengths=None))


def tracked_frames(previous: Solution3D, scene: Scene3D) -> FloatArray:
    """Start frames (n, 4) for ``scene`` from ``previous`` by the track predictor (see the module docstring)."""
    lengths, _ = bar_layout(scene)
    s_mid = np.cumsum(lengths) - 0.5 * lengths
    old_nodes_s = np.concatenate(([0.0], np.cumsum(previous.lengths)))
    shift = float(np.sum(lengths)) - float(old_nodes_s[-1])
    n_old = previous.n_bars
    where = np.clip(np.searchsorted(old_nodes_s, s_mid) - 1, 0, n_old - 1)
    tangents = previous.frames[where, 2].copy()
    base = quat.from_frames(scene.base.frame())[0]
    material = s_mid - shift
    m = np.clip(np.searchsorted(old_nodes_s, material) - 1, 0, n_old - 1)
    carried = np.where((material < 0.0)[:, None], base, previous.quaternions[m])
    carried = quat.continuous(carried, base)
    turn = quat.swing(kinematics.unit_tangents(carried), tangents)
    return quat.continuous(np.stack(quat.multiply(turn.T, carried.T), axis=1), base)


STEP_MAX_ITER = 40
"""Iterations a warm-started step may take before it is split in two (a converging step takes 3-8)."""

MAX_HALVINGS = 5
"""Splits of one step at most (down to 1/32 of it)."""

STEP_BUDGET = 300
"""Iterations of all the solves of one step together, unless ``max_iter`` says otherwise."""


def tracked_multipliers(previous: Solution3D, scene: Scene3D, n: int) -> list[FloatArray] | None:
    """The multipliers of ``previous`` carried to ``scene`` with ``n`` bars, row block by row block, as the track
    predictor carries the shape (bar ``k`` and node ``k`` keep their place: the first ``min(n_old, n)`` take the old
    values, new ones start at zero): closure (3 per bar), pinned contacts (as they were), walls (one per wall and node),
    lumen (one per node; a touching tip's going to the new tip) and creases (as they were). None when ``previous`` has
    none (a failed solve) or another layout."""
    old = previous.extras.get("multipliers")
    if old is None:
        return None
    n_old, keep = previous.n_bars, min(previous.n_bars, n)

    def carried(values: FloatArray, per: int, groups: int = 1) -> FloatArray:
        a = np.asarray(values, dtype=float).reshape(groups, n_old, per)
        out = np.zeros((groups, n, per))
        out[:, :keep] = a[:, :keep]
        return out.ravel()

    def node_rows(values: FloatArray, groups: int = 1) -> FloatArray:
        """One row per node (and group): carried, a touching tip's force going to the new tip node (a tip pressed
        on a wall stays on it while the wire is pushed or pulled; left at node ``n_old`` it guessed a contact inside
        the wire's run while the step's answer held the new tip's row, and the first QP of every such step went to
        a backend)."""
        a = np.asarray(values, dtype=float).reshape(groups, n_old)
        out = carried(values, 1, groups).reshape(groups, n)
        if n != n_old:
            touching = a[:, -1] != 0.0  # (a lumen force is positive, a wall's negative)
            if n_old <= n:
                out[touching, n_old - 1] = 0.0
            out[touching, n - 1] = a[touching, -1]
        return out.ravel()

    blocks = [carried(old[0], 3)]
    index = 1
    if any(c.point is not None for c in scene.contacts):
        blocks.append(np.asarray(old[index], dtype=float))
        index += 1
    if scene.walls:
        blocks.append(node_rows(old[index], len(scene.walls)))
        index += 1
    if scene.vessel is not None:
        blocks.append(node_rows(old[index]))
        index += 1
        if getattr(scene.vessel, "creases", ()):
            blocks.append(np.asarray(old[index], dtype=float))  # (its places keep their slots)
            index += 1
    return blocks if index == len(old) else None


def advance(scene: Scene3D, previous: Solution3D, length: float, turn: float, density: float,
            options: dict[str, Any]) -> Solution3D:
    """The step from ``previous`` to ``(length, turn)``, split in halves (recursively, :data:`MAX_HALVINGS` times)
    while a warm-started solve does not converge within :data:`STEP_MAX_ITER` iterations: a wire whose tip meets a
    wall, or a J-tip that snaps, moves far in one step, and shorter steps keep each start near its answer. All the
    solves of one step share ``options["max_iter"]`` (default :data:`STEP_BUDGET`) iterations. A step that cannot be
    followed so (a fold: a J wire turned in a curved tube snaps) is solved once more from the built-in start
    (:func:`solve3d` without a warm start, as many iterations again), whose answer, when it converges, is the step's
    (``extras["cold"]`` True); otherwise the step fails with the message of its last warm solve. The answer carries
    ``extras["substeps"]`` (solves made) and ``extras["step_iterations"]`` (their iterations)."""
    budget = [int(options.get("max_iter", STEP_BUDGET))]
    rest = {key: value for key, value in options.items() if key != "max_iter"}
    sol = _advance(scene, previous, length, turn, density, rest, 0, budget)
    spent = int(options.get("max_iter", STEP_BUDGET)) - budget[0]
    if not sol.success:
        # (a safety net: at a fold, where the branch followed ends and the wire snaps, the warm start leaves the
        # saddle along its negative curvature, the model's shift covering only the reduced Hessian's; while that
        # shift was the size of the curvature across the rows, 100-900, the warm starts crawled at |d| ~ 1e-5 and
        # this solve found the equilibrium the wire snaps to)
        cold = solve3d(scene_at(scene, length, turn, density), max_iter=int(options.get("max_iter", STEP_BUDGET)),
                       **rest)
        spent += cold.iterations
        if cold.success:
            cold.extras["substeps"] = sol.extras.get("substeps", 1) + 1
            cold.extras["cold"] = True
            sol = cold
    sol.extras["step_iterations"] = spent
    return sol


def _advance(scene: Scene3D, previous: Solution3D, length: float, turn: float, density: float,
             options: dict[str, Any], depth: int, budget: list[int]) -> Solution3D:
    target = scene_at(scene, length, turn, density)
    last = depth >= MAX_HALVINGS
    limit = budget[0] if last else min(budget[0], STEP_MAX_ITER)
    frames = tracked_frames(previous, target)
    sol = solve3d(target, initial_frames=frames, initial_multipliers=tracked_multipliers(previous, target, len(frames)),
                  max_iter=max(1, limit), **options)
    budget[0] -= sol.iterations
    sol.extras["substeps"] = 1
    if sol.success or last or budget[0] <= 0:
        return sol
    before = float(np.sum(previous.lengths))
    middle = _advance(scene, previous, 0.5 * (before + length), 0.5 * (previous.base_rotation + turn), density,
                      options, depth + 1, budget)
    if not middle.success:
        return middle
    sol = _advance(scene, middle, length, turn, density, options, depth + 1, budget)
    sol.extras["substeps"] += middle.extras["substeps"]
    return sol


def checked_steps(scene: Scene3D, lengths: Iterable[float],
                  rotations: Iterable[float] | float | None) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The lengths (mm) and clamp rotations (rad) of :func:`insert3d`, one each per step; a ValueError naming the
    field otherwise."""
    values = tuple(float(v) for v in lengths)
    if not values or any(not np.isfinite(v) or v <= 0.0 for v in values):
        raise ValueError("lengths must be positive finite inserted lengths (mm), e.g. numpy.arange(10, 101, 1.0).")
    if rotations is None:
        return values, (scene.base.rotation,) * len(values)
    if np.ndim(rotations) == 0:
        return values, (float(rotations),) * len(values)  # type: ignore[arg-type]
    turns = tuple(float(v) for v in rotations)  # type: ignore[union-attr]
    if len(turns) != len(values):
        raise ValueError(f"rotations has {len(turns)} values for {len(values)} lengths; give one rotation (rad) per "
                         "step, or one number for all.")
    if not all(np.isfinite(turns)):
        raise ValueError("rotations must be finite (rad).")
    return values, turns


def insert3d(scene: Scene3D, lengths: Iterable[float], rotations: Iterable[float] | float | None = None, *,
             progress: Callable[[Solution3D, int, int], None] | None = None, **options: Any) -> Insertion3D:
    """Push, pull and turn the wire of ``scene`` through ``lengths`` (mm) and clamp ``rotations`` (rad).

    Parameters
    ----------
    scene : Scene3D
        Its bar density (``wire.bars / wire.length``; per refined mm with refined sections,
        :attr:`guidewire.Wire.bar_density`) is kept at every length.
    lengths : iterable of float
        Inserted length of every step (mm, positive; any order: a shorter one pulls back).
    rotations : iterable of float, float or None
        The clamp's rotation at every step (rad, absolute, one per length); one number for all; None keeps
        ``scene.base.rotation``.
    progress : callable, optional
        ``progress(solution, index, total)`` after each step.
    **options
        Passed to :func:`solve3d` (``tol``, ``max_iter``, ``qp_solver``).

    Returns
    -------
    Insertion3D
        A failed step is kept (its status and message say why) and ends the insertion.
    """
    values, turns = checked_steps(scene, lengths, rotations)
    for key in ("initial_frames", "initial_nodes", "initial_multipliers"):
        if key in options:
            raise ValueError(f"{key} is set by the insertion (each step starts from the last); do not pass it.")
    density = scene.wire.bar_density
    start = time.perf_counter()
    steps: list[Solution3D] = []
    error = None
    previous: Solution3D | None = None
    for i, (length, turn) in enumerate(zip(values, turns, strict=True)):
        if previous is None:
            sol = solve3d(scene_at(scene, length, turn, density), **options)
        else:
            sol = advance(scene, previous, length, turn, density, options)
        steps.append(sol)
        if progress is not None:
            progress(sol, i, len(values))
        if not sol.success:
            error = f"step {i + 1} (L = {length:g} mm, rotation {turn:g} rad) failed: {sol.message}"
            break
        previous = sol
    return Insertion3D(values, turns, steps, time.perf_counter() - start, error)
