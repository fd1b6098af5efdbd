"""Quasi-static advancement (paper §2.1): a sequence of scenes, each solved from the previous answer, with a secant
predictor along a steady change."""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .model import ModelReuse
from .result import Solution
from .scene import Scene
from .solve import solve

#: The secant predictor of :func:`solve_sequence` is used when the last two scene changes are this parallel (cosine).
SECANT_COSINE = 0.999


@dataclass(frozen=True)
class SequenceResult:
    """What :func:`solve_sequence` did.

    Attributes
    ----------
    solutions : list of Solution
        One per step that was solved, in order (failed solves included: a failure is data).
    error : str or None
        Why the sequence stopped early (a step's scene refused before solving, e.g. infeasible), else None.
    failed_step : int or None
        Index of that step.
    """

    solutions: list[Solution]
    error: str | None = None
    failed_step: int | None = None

    @property
    def complete(self) -> bool:
        """Every step was solved (each may still have failed: see its ``success``)."""
        return self.error is None

    def __len__(self) -> int:
        return len(self.solutions)

    def __getitem__(self, i: Any) -> Any:
        return self.solutions[i]

    def __iter__(self) -> Any:
        return iter(self.solutions)


def solve_sequence(scenes: Iterable[Scene], **options: Any) -> SequenceResult:
    """Solve each scene starting from the previous answer.

    Each solve after the first starts from the previous shape (bar angles re-sampled by relative arc length when
    the bar layout changes) and from the previous multipliers (matched by constraint block and row), so a small
    change of the scene (a contact moving along a wall, the inserted length growing) costs one or two Newton steps.
    Along a steady change (the last two changes parallel) both are extrapolated (a secant predictor). What
    consecutive scenes share of their programs is built once (:class:`guidewire.model.ModelReuse`: the bar layout
    and the energy with its Hessian when only targets move), giving the same answers as building each step anew.

    Parameters
    ----------
    scenes : iterable of Scene
        The steps, in order.
    **options
        Passed to :func:`guidewire.solve` (``scheme``, ``bars``, ``hessian``, ``qp_solver``, ``tol``, ...);
        ``initial_angles`` and ``multipliers0`` of the first step only; ``reuse=None`` builds every step anew.

    Returns
    -------
    SequenceResult
        Behaves as the list of solutions. A failed solve is returned as data and the next step starts from its
        shape anyway; a step refused before solving (``ValueError``/``TypeError``, e.g. an infeasible scene) ends
        the sequence with the steps solved so far and the reason in ``error``.
    """
    out: list[Solution] = []
    parameters: list[tuple[tuple[Any, ...], Any]] = []  # of the scenes solved, then of this one
    options.setdefault("reuse", ModelReuse())
    for step, scene in enumerate(scenes):
        parameters = [*parameters[-2:], _scene_parameters(scene)]
        if out:
            prev = out[-1]
            options["initial_angles"] = _resampled_angles(prev, scene, options.get("bars"))
            options["multipliers0"] = prev
            t = _secant(*parameters[-3:]) if len(out) >= 2 else 0.0
            if t and out[-2].bar_angles.size == prev.bar_angles.size == options["initial_angles"].size:
                options["initial_angles"], options["multipliers0"] = _secant_prediction(out[-2], prev, t)
        try:
            out.append(solve(scene, **options))
        except (ValueError, TypeError) as exc:
            return SequenceResult(out, f"step {step}: {exc}", step)
    return SequenceResult(out)


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
    key += [(sec.youngs_modulus, sec.diameter, sec.moment_of_inertia) for sec in scene.wire.sections]
    values += [v for sec in scene.wire.sections for v in (sec.length, sec.rest_curvature)]
    return tuple(key), np.asarray(values, dtype=float)


def secant_factor(a: Scene, b: Scene, c: Scene) -> float:
    """``t`` with ``p(c) − p(b) = t (p(b) − p(a))`` for the scene parameters ``p`` when the two changes are parallel
    (a steady advance: a contact moving along a line, the inserted length growing), else 0."""
    return _secant(_scene_parameters(a), _scene_parameters(b), _scene_parameters(c))


def _secant(a: tuple[tuple[Any, ...], Any], b: tuple[tuple[Any, ...], Any], c: tuple[tuple[Any, ...], Any]) -> float:
    """:func:`secant_factor` from the three scenes' :func:`_scene_parameters`."""
    (ka, pa), (kb, pb), (kc, pc) = a, b, c
    if not (ka == kb == kc) or pa.size != pc.size:
        return 0.0
    old, new = pb - pa, pc - pb
    norm_old, norm_new = math.sqrt(float(old @ old)), math.sqrt(float(new @ new))  # (np.linalg.norm's arithmetic)
    if norm_old == 0.0 or norm_new == 0.0 or float(old @ new) < SECANT_COSINE * norm_old * norm_new:
        return 0.0
    return norm_new / norm_old


def _secant_prediction(older: Solution, prev: Solution, t: float) -> tuple[Any, Any]:
    """Start angles and multipliers extrapolated along the last change: ``x + t (x − x_older)`` (the first-order
    predictor of a continuation method, so the Newton corrector starts O(h²) rather than O(h) from the answer).
    A multiplier is extrapolated only where its block has the same rows in both solutions and it kept its sign over
    both steps and keeps it (a wall or b₂ row that is leaving or entering contact keeps its last value)."""
    angles = prev.bar_angles + t * (prev.bar_angles - older.bar_angles)
    before = {b.key: (b, v) for b, v in zip(older.blocks, older.multipliers, strict=True)}
    lam = []
    for block, a in zip(prev.blocks, prev.multipliers, strict=True):
        other = before.get(block.key)
        if other is None or not np.array_equal(other[0].row_keys, block.row_keys):
            lam.append(a)
            continue
        b = other[1]
        guess = a + t * (a - b)
        lam.append(np.where((np.sign(guess) == np.sign(a)) & (np.sign(a) == np.sign(b)), guess, a))
    return angles, replace(prev, multipliers=tuple(lam))


def _resampled_angles(prev: Solution, scene: Scene, bars: int | None) -> Any:
    """The previous bar angles at the new bars' midpoints, by relative arc length."""
    n_new = bars if bars is not None else scene.wire.bars
    old = prev.bar_angles
    length = float(scene.wire.length)
    if old.size == n_new and abs(float(prev.s[-1]) - length) <= 1e-8 + 1e-5 * abs(length):  # (np.isclose)
        return old
    s_old = 0.5 * (prev.s[1:] + prev.s[:-1]) / prev.s[-1]
    s_new = (np.arange(n_new) + 0.5) / n_new
    return np.interp(s_new, s_old, old)
