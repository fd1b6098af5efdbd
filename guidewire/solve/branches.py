"""The lowest-energy branch: after the first solve, more starts where a free tangent left the branch in doubt.

A contact with a position and no tangent is a pin: the wire may pass it bowing either way, and the default start
(:mod:`guidewire.initial_shape`) estimates the tangent there. Between two consecutive *poses* (the base and the
contacts with a point) the wire bows to one side or the other, or makes an S; a local method (ours, like SLSQP or
IPOPT) keeps the bow it starts with. Measured on 800 random generating-chain scenes (:mod:`guidewire.scene.generated`,
``benchmarks/branches.py``): the default start alone ends above the generating chain in 8 (1 %, up to 18 % more
energy), every one of them next to a pin.

With ``branches="lowest"`` (the default of :func:`guidewire.solve`), when the first answer succeeded and has a pose
with a free tangent, each segment between poses gets a mirror start per free-tangent end: that end's tangent reflected
about the segment's chord (which turns the segment's C into an S or back), every other pose keeping the first
answer's tangent, re-sampled onto the chain by :func:`guidewire.initial_shape.initial_angles` (the scene with those
tangents prescribed). A reflection that moves no tangent by more than :data:`SAME_BOW` is the first start again and
is skipped. Each candidate is solved (at most :func:`candidate_iterations` iterations: a lower branch converges
about as fast as the first, a failing one is cut short) and the lowest energy kept, lower by more than
:data:`ENERGY_TIE` (relative) to replace an earlier answer; a failed or shape-rejected candidate never replaces a
success. Scenes whose tangents are all prescribed (every paper scene) or vessels without branches solve once,
and so do contact and wall scenes answered in the full-space layout (above 300 bars): there a candidate solved from a
given start can take far longer than the first solve (9 s against 0.17 s measured on two contacts 0.5 mm apart at 400
bars), so the multi-start is limited to the reduced program.

A mirror start changes a tangent's side of the chord; a branch can also differ in *how far* a free tangent turns. On
a hand-written scene (a 70 mm wire pinned at s = 40 mm and clamped at its tip 15.7 mm from the pin) the default start
and both mirror starts ended at 37.09 N·mm with the pin's tangent at 0.80 rad, while continuation from a nearby
scene reached a valid 23.58 N·mm with it at 1.41 rad. So each free pose also gets a *tangent-scan start*: of
:data:`SCAN_POINTS` trial tangents around the circle (every other pose keeping the first answer's tangent), the one
whose start curves bend least over the segments next to it (:func:`guidewire.initial_shape.least_bending`; on that
scene the scan's least bending sits at 1.5 rad, where the energy with the tangent held is least too), when those
curves bend less than the first answer over the same segments by more than :data:`SCAN_MARGIN` (then the first
answer is on a higher branch than a curve of the family shows possible) and the trial is not within the scan's
spacing of a mirror start. Measured on the 800 random
scenes: the scan added a start on 1.4 % of them, changed no energy there, and costs about 2–3 ms per scene with a
free tangent (a batched Newton grid over 12 × 2 segments).

In a vessel the wire's ends are the entrance and a free tip, and the branch in doubt is the way it takes: the
default start follows the main centreline, and each branch that leaves it before the wire's last bar gets a *branch
start* along the way through that branch (:func:`route_starts`). Measured on the shipped vessels: in the aortic arch
at 230 and 250 mm the way into the third branch ends at 0.078 and 0.088 N·mm against the main centreline's 1.30 and
1.76; in ``s_bend_branch`` from 64 mm the branch's answer (5.03 N·mm) is below the S's (5.39-5.88). A candidate's
iteration limit counts over all its working-set rounds (a start whose lumen planes never settle is cut short). Branch
starts are bar angles, which the full-space program starts from as well, so a vessel gets them in either layout (the
arch at 2 bars per mm, 205 / 210 mm, 410-420 bars in the full space: 0.036 / 0.045 N·mm through the third branch
against the main centreline's 0.315, 0.7 s against 0.25 s).

A wire pushed over an opening can enter it with its tip before the branch's centreline has left the main one
under the tip, where there is no route start yet, and a route start made a little further on slides back into the
main route. So while the tip is within a main-lumen radius ``R`` of a branch's junction ``J``, the branch also gets
a *push start* (:func:`push_starts`): the wire inserted from ``J − R`` in steps of ``R/2`` (each step from the one
before, as :func:`guidewire.insert` does), its last shape. Measured on ``s_bend_branch`` (1 bar/mm): at 41-42.5 mm the
push start ends at 1.98-2.51 N·mm, the insertion's answer, where the default and route starts end at 2.66-2.79 on the
main route; a solve in that window costs 140-300 ms against 50-90 ms outside it.

From 200 bars in a vessel, each candidate is solved at a quarter of its bars first and its fine solve starts from
that answer, as the first start is (:func:`guidewire.solve.pipeline.nested_start`).

The candidates are built from the scene's geometry and the first answer only, so the mirrored or rotated scene gets
the mirrored or rotated candidates, in the same order, and keeps the mirrored or rotated answer.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from ..chain.kinematics import BarChain, scene_bars
from ..initial_shape import initial_angles, least_bending, route_angles
from ..scene.scene import Scene
from .result import Solution

FloatArray = NDArray[np.float64]

BRANCHES = ("lowest", "first")
"""Values of ``solve(branches=...)``: the lowest energy of the candidate starts, or the default start's answer only."""

SAME_BOW = 1e-3
"""A reflection moving every reflected tangent by less than this (rad) starts where the first answer did: skipped."""

ENERGY_TIE = 1e-6
"""A candidate replaces the answer so far only when its energy is lower by more than this fraction (so rounding
never swaps two answers of one minimum, and a mirrored scene keeps the mirrored answer)."""

CANDIDATE_MIN_ITER, CANDIDATE_ITER_FACTOR = 80, 4
"""A candidate may take ``max(CANDIDATE_MIN_ITER, CANDIDATE_ITER_FACTOR × the first answer's iterations)``
iterations (never more than the caller's ``max_iter``); measured: candidates that converge take a median of 11,
the failing ones (2 %) ran to the 500 limit. A branch start whose wire slides over the branch's corner takes more,
a few iterations a round for each bar the contact passes (``s_bend_branch`` from 60 mm at 1 bar/mm: 51-53
iterations in 9 rounds, where the first answer took 9-13)."""


def check_branches(branches: object) -> str:
    """``branches`` if valid, else a ValueError naming the choices."""
    if not isinstance(branches, str) or branches not in BRANCHES:
        raise ValueError(f"branches is {branches!r}; expected 'lowest' (try the candidate starts where a free tangent "
                         "leaves the branch in doubt, keep the lowest energy) or 'first' (the default start only).")
    return branches


def candidate_iterations(first: Solution, max_iter: int) -> int:
    """Iteration limit of a candidate start's solve."""
    return min(max_iter, max(CANDIDATE_MIN_ITER, CANDIDATE_ITER_FACTOR * first.iterations))


def _reflect(angle: float, chord: float) -> float:
    """``angle`` reflected about the direction ``chord`` (``2·chord − angle``), in ``angle``'s winding."""
    return angle + math.remainder(2.0 * math.remainder(chord - angle, 2.0 * math.pi), 2.0 * math.pi)


def candidate_starts(first: Solution) -> list[tuple[str, FloatArray]]:
    """The candidate starts of the module docstring for the scene ``first`` solved (empty when no pose has a free
    tangent, or ``first`` failed).

    Parameters
    ----------
    first : Solution
        The answer from the default start (``first.scene`` with the bars and scheme used).

    Returns
    -------
    list of (str, ndarray of shape (n,))
        A label (``"mirror start k"``, ``"tangent-scan start k"``) and the bar angles (rad) of each candidate, in a
        fixed order: the mirror starts segment by segment from the base, its first end reflected, then its second
        (reflecting both ends of a segment at once, a mirror C, found no lower branch that these missed on the 800
        benchmark scenes and cost a quarter more solves: not tried); then the tangent-scan start of each free pose
        from the base on.
    """
    scene = first.scene
    if not first.success:
        return []
    if getattr(scene, "vessel", None) is not None:  # (bar angles, which either layout starts from)
        return [] if scene.contacts else route_starts(scene) + push_starts(scene)
    if first.layout != "reduced":
        return []
    contacts = scene.contacts
    posed = [i for i, c in enumerate(contacts) if c.point is not None]
    free = [scene.base.angle is None] + [contacts[i].angle is None for i in posed]
    if len(posed) == 0 or not any(free):
        return []
    lengths, contact_nodes = scene_bars(scene)
    chain = BarChain(np.asarray(scene.base.point, dtype=float), lengths)
    pose_nodes = [0] + [int(contact_nodes[i]) for i in posed]
    points = np.array([scene.base.point] + [contacts[i].point for i in posed], dtype=float)
    tangents = first.tangent_angles[pose_nodes].astype(float)
    trials = _mirror_trials(tangents, np.arctan2(*(points[1:] - points[:-1])[:, ::-1].T), free)
    spans = np.diff(np.concatenate(([0.0], np.cumsum(lengths)))[pose_nodes])
    trials += _scan_trials(first, points, tangents, spans, pose_nodes, free, trials)
    counts = {"mirror": 0, "tangent-scan": 0}
    starts = []
    for kind, trial in trials:
        counts[kind] += 1
        starts.append((f"{kind} start {counts[kind]}",
                       initial_angles(_with_pose_tangents(scene, posed, trial), chain, contact_nodes)))
    return starts


def route_starts(scene: Scene) -> list[tuple[str, FloatArray]]:
    """A start through each branch of ``scene``'s vessel that leaves the main centreline before the wire's last
    bar's midpoint (:func:`guidewire.initial_shape.route_angles`), labelled ``"branch start k"`` (k from 1 in the
    vessel's branch order); empty for a vessel without branches."""
    vessel = scene.vessel
    if not getattr(vessel, "branches", ()):
        return []
    lengths, _ = scene_bars(scene)
    chain = BarChain(np.asarray(scene.base.point, dtype=float), lengths)
    last_mid = float(chain.arc_lengths[-2] + 0.5 * lengths[-1])
    return [(f"branch start {b + 1}", route_angles(vessel, chain, scene.base.angle, b))
            for b in range(len(vessel.branches)) if vessel.junction(b) < last_mid]


PUSH_REACH = 1.0
"""A push start is made while the tip is within this many main-lumen radii of a branch's junction (either side)."""

PUSH_STEP = 0.5
"""Its insertion steps, in main-lumen radii at the junction."""


def push_starts(scene: Scene) -> list[tuple[str, FloatArray]]:
    """A start for each branch whose opening the tip is passing (its junction within :data:`PUSH_REACH` main-lumen
    radii ``R`` of the wire's length ``L``): the wire inserted from ``J − R`` to ``L`` in steps of at most
    :data:`PUSH_STEP` ``R`` (:func:`guidewire.insert`, each step from the one before, the first from the default
    start), the last step's bar angles, labelled ``"push start k"``. A wire pushed over an opening may enter it with
    its tip before the branch's centreline leaves the main one under the tip, where no route start is made and the
    route start a little further on slides back into the main route. Empty when the insertion does not reach ``L``
    on the scene's own bars."""
    from ..march.insertion import insert  # (insert solves each step with guidewire.solve)

    vessel = scene.vessel
    if not getattr(vessel, "branches", ()):
        return []
    lengths, _ = scene_bars(scene)
    total = float(scene.wire.length)
    starts = []
    for b in range(len(vessel.branches)):
        junction = vessel.junction(b)
        radius = float(vessel.radius_at(np.array([junction]))[0])
        begin = junction - PUSH_REACH * radius
        if not begin < total <= junction + PUSH_REACH * radius or begin <= 0.0:
            continue
        count = max(1, math.ceil((total - begin) / (PUSH_STEP * radius) - 1e-9))
        pushed = insert(scene, np.linspace(begin, total, count + 1), branches="first")
        last = pushed.steps[-1] if pushed.steps else None
        if pushed.complete and last is not None and last.success and last.n_bars == lengths.size:
            starts.append((f"push start {b + 1}", last.bar_angles.copy()))
    return starts


def _mirror_trials(tangents: FloatArray, chords: FloatArray, free: list[bool]) -> list[tuple[str, FloatArray]]:
    """The poses' tangents with one free end of a segment reflected about its chord, segment by segment from the
    base (its first end, then its second), skipping reflections that move no tangent by :data:`SAME_BOW`."""
    trials = []
    for j, chord in enumerate(chords):  # segment j: from pose j to pose j + 1
        for e in (j, j + 1):
            if free[e]:
                trial = tangents.copy()
                trial[e] = _reflect(float(tangents[e]), float(chord))
                if np.abs(trial - tangents).max() >= SAME_BOW:
                    trials.append(("mirror", trial))
    return trials


def _scan_trials(first: Solution, points: FloatArray, tangents: FloatArray, spans: FloatArray, pose_nodes: list[int],
                 free: list[bool], mirrors: list[tuple[str, FloatArray]]) -> list[tuple[str, FloatArray]]:
    """The tangent-scan trial of every free pose from the base on, where the scan's curves bend clearly less than
    the first answer next to the pose (the first answer then sits on a higher branch) and no earlier trial starts
    within the scan's spacing."""
    trials = list(mirrors)
    bending = first.relative_angles * first.curvature  # ∫ θ'² ds per node (Δθ · κ = κ² w)
    for e in np.flatnonzero(free):
        scan, least = _scan_tangent(points, tangents, spans, int(e))
        lo, hi = pose_nodes[max(e - 1, 0)], pose_nodes[min(e + 1, len(pose_nodes) - 1)]
        own = float(bending[lo : hi + 1].sum() - 0.5 * (bending[lo] + bending[hi]))
        trial = tangents.copy()
        trial[e] = scan
        spacing = 2.0 * math.pi / SCAN_POINTS
        if least < (1.0 - SCAN_MARGIN) * own and all(np.abs(trial - other).max() > spacing for _, other in trials):
            trials.append(("tangent-scan", trial))
    return trials[len(mirrors):]


SCAN_POINTS, SCAN_MARGIN = 12, 0.05
"""Trial tangents of a free pose in the tangent scan (:func:`_scan_tangent`), evenly around the circle; the scan's
start is tried when its curves bend less than the first answer by more than this fraction (next to the pose)."""


def _scan_tangent(points: FloatArray, tangents: FloatArray, spans: FloatArray, e: int) -> tuple[float, float]:
    """Of :data:`SCAN_POINTS` trial tangents of pose ``e`` (the first answer's, ``tangents[e]``, turned by odd
    multiples of ``π / SCAN_POINTS``), the one whose start curves bend least over the segments next to it
    (:func:`guidewire.initial_shape.least_bending`, every other pose keeping its tangent), and that bending
    ``∫ θ'² ds`` (1/mm; ``inf`` when no trial closes). (Not weighted by the wire's stiffness: a start, not an
    energy.)"""
    sides = [j for j in (e - 1, e) if 0 <= j < points.shape[0] - 1]
    # (offsets symmetric about 0, so a mirrored scene scans the mirrored trials; a tie goes to the smaller turn)
    offsets = 2.0 * math.pi * (np.arange(SCAN_POINTS) - 0.5 * (SCAN_POINTS - 1)) / SCAN_POINTS
    trials = tangents[e] + offsets[np.argsort(np.abs(offsets), kind="stable")]
    segments = []
    for phi in trials:
        for j in sides:
            ends = [phi if k == e else tangents[k] for k in (j, j + 1)]
            segments.append((points[j], points[j + 1], float(ends[0]), float(ends[1]), float(spans[j])))
    total = least_bending(segments).reshape(SCAN_POINTS, len(sides)).sum(axis=1)
    k = int(np.argmin(total))
    return float(trials[k]), float(total[k])


def _with_pose_tangents(scene: Scene, posed: list[int], tangents: FloatArray) -> Scene:
    """``scene`` with every pose's tangent prescribed: ``tangents[0]`` at the base, ``tangents[1 + k]`` at contact
    ``posed[k]``."""
    contacts = list(scene.contacts)
    for k, i in enumerate(posed):
        contacts[i] = replace(contacts[i], angle=float(tangents[1 + k]))
    return replace(scene, base=replace(scene.base, angle=float(tangents[0])), contacts=tuple(contacts))


def lowest_branch(first: Solution, solve_from: Callable[[FloatArray], Solution], started: float) -> Solution:
    """The lowest-energy successful answer of ``first`` and of :func:`solve_from` on each :func:`candidate_starts`.

    Parameters
    ----------
    first : Solution
        The answer from the default start.
    solve_from : callable
        Solves the same scene (bars, scheme, options) from the given bar angles.
    started : float
        ``time.perf_counter()`` at the start of the whole solve: the answer's ``solve_time_s`` covers every start.

    Returns
    -------
    Solution
        The kept answer, with ``starts`` the number of starts solved (1 + candidates) and ``message`` saying which
        start gave it when it was not the first.
    """
    candidates = candidate_starts(first)
    if not candidates:
        return first
    best, best_label = first, ""
    for label, x0 in candidates:
        sol = solve_from(x0)
        if sol.success and sol.energy < best.energy - ENERGY_TIE * abs(best.energy):
            best, best_label = sol, label
    starts = 1 + len(candidates)
    message = best.message
    if best_label:
        message = (f"{message} (the lowest energy of {starts} starts: {best_label}; the default start "
                   f"ended at {first.energy:.6g} N·mm)")
    return replace(best, starts=starts, message=message, solve_time_s=time.perf_counter() - started)
