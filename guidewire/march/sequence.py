"""Quasi-static advancement (paper §2.1): a sequence of scenes, each solved from the previous answer, with a
polynomial predictor (secant, then quadratic) along a steady change."""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..program.formulation import BlockMultipliers
from ..program.model import ModelReuse
from ..scene.scene import Scene
from ..solve.front import solve
from ..solve.result import Solution
from ..status import Status, outcome

#: The predictor of :func:`solve_sequence` extrapolates along scene changes at least this parallel (cosine).
SECANT_COSINE = 0.999

#: Most previous answers the predictor extrapolates through: 3, a quadratic (2 is the secant). Measured on Table 1
#: (θ_B = π/4, n = 100, 0.5 mm steps): start error 1.3e-4 rad (secant) -> 1.3e-6 (quadratic), 2 -> 1 SQP iterations.
PREDICTOR_POINTS = 3


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

    @property
    def status(self) -> Status:
        """Why the sequence ended (:func:`guidewire.status.outcome`): SUCCESS, the first failed step's status, or
        SCENE_REFUSED."""
        return outcome(self.solutions, self.error)

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
    Along a steady change both are extrapolated through the last answers (the predictor of a continuation method):
    a quadratic through three when the last three changes are parallel, else the secant through two when the last
    two are, so the Newton corrector starts O(h³) (O(h²)) rather than O(h) from the answer: one SQP iteration per
    step on Table 1's sliding contact. Only successful answers of the same bar layout are extrapolated through.
    What consecutive scenes share of their programs is built once (:class:`guidewire.program.model.ModelReuse`: the bar
    layout and the energy with its Hessian when only targets move), giving the same answers as building each step
    anew.

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
    parameters: list[tuple[tuple[Any, ...], Any]] = []  # of the last scenes solved, then of this one
    options.setdefault("reuse", ModelReuse())
    for step, scene in enumerate(scenes):
        parameters = [*parameters[-PREDICTOR_POINTS:], _scene_parameters(scene)]
        if out:
            prev = out[-1]
            options["initial_angles"] = _resampled_angles(prev, scene, options.get("bars"))
            options["multipliers0"] = prev
            points = _steady_points(out, parameters, options["initial_angles"].size)
            if points:
                weights = _lagrange_weights(_positions(parameters[-points - 1:]))
                options["initial_angles"], options["multipliers0"] = _prediction(out[-points:], weights)
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


def _steady_points(out: list[Solution], parameters: list[tuple[tuple[Any, ...], Any]], size: int) -> int:
    """How many of the last answers the predictor extrapolates through (0, 2 or up to :data:`PREDICTOR_POINTS`):
    each a success with ``size`` bar angles, the scene changes between them and to the new scene parallel."""
    usable = 0
    for k in range(1, min(len(out), PREDICTOR_POINTS) + 1):
        sol = out[-k]
        if not sol.success or sol.bar_angles.size != size:
            break
        if k >= 2 and not _secant(*parameters[-k - 1:][:3]):
            break
        usable = k
    return usable if usable >= 2 else 0


def _positions(parameters: list[tuple[tuple[Any, ...], Any]]) -> list[float]:
    """Arc positions of the scene parameters along their (parallel) changes, the first at 0."""
    out = [0.0]
    for (_, a), (_, b) in zip(parameters[:-1], parameters[1:], strict=True):
        d = b - a
        out.append(out[-1] + math.sqrt(float(d @ d)))
    return out


def _lagrange_weights(tau: list[float]) -> list[float]:
    """Weights ``w_j`` of the polynomial through the values at ``tau[:-1]`` evaluated at ``tau[-1]``:
    ``p(tau[-1]) = Σ_j w_j y_j`` (a secant for two points, a quadratic for three)."""
    nodes, t = tau[:-1], tau[-1]
    weights = []
    for j, tj in enumerate(nodes):
        w = 1.0
        for i, ti in enumerate(nodes):
            if i != j:
                w *= (t - ti) / (tj - ti)
        weights.append(w)
    return weights


def _prediction(sols: list[Solution], weights: list[float]) -> tuple[Any, BlockMultipliers]:
    """Start angles and multipliers extrapolated through ``sols`` (oldest first) with ``weights``.

    A multiplier is extrapolated only where its block has the same rows in every solution and it kept its sign
    through them and keeps it (a wall or b₂ row that is leaving or entering contact keeps its last value)."""
    prev = sols[-1]
    angles = sum(w * s.bar_angles for w, s in zip(weights, sols, strict=True))
    lam = []
    for i, (block, a) in enumerate(zip(prev.blocks, prev.multipliers, strict=True)):
        values = [_same_rows(s, i, block) for s in sols[:-1]]
        if any(v is None for v in values):
            lam.append(a)
            continue
        values.append(a)
        guess = sum(w * v for w, v in zip(weights, values, strict=True))
        sign = np.sign(a)
        same = np.sign(guess) == sign
        for v in values[:-1]:
            same &= np.sign(v) == sign
        lam.append(np.where(same, guess, a))
    return angles, BlockMultipliers(prev.blocks, tuple(lam))


def _same_rows(sol: Solution, i: int, block: Any) -> Any:
    """The multipliers of ``sol``'s block with ``block``'s key when it has the same rows (looked for at position
    ``i`` first, where a sequence keeps it), else None."""
    blocks = sol.blocks
    if i < len(blocks) and blocks[i].key == block.key:
        found = i
    else:
        found = next((j for j, b in enumerate(blocks) if b.key == block.key), -1)
        if found < 0:
            return None
    return sol.multipliers[found] if np.array_equal(blocks[found].row_keys, block.row_keys) else None


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
