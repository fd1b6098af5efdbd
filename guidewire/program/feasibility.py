"""Why a scene cannot be met, found before any solve: :func:`infeasibility` and :func:`check_feasible` (which
:func:`guidewire.program.formulation.formulate` calls).

Each check is a *necessary* condition for a wire shape to exist, so a scene it rejects has no solution; a scene it
passes may still be infeasible in a way only the solver can tell (then the solve ends with a non-success status).

Continuum checks (any discretisation):

- **reach**: consecutive prescribed positions (the base and every contact with a point) no farther apart than the
  wire between them;
- **walls**: the base and every contact point inside every wall;
- **taut**: where two positions are as far apart as the wire between them (to a relative 1e-9), that wire must be
  the straight chord, so every prescribed angle at its ends or between them must be the chord's direction, up to the
  turn ``acos(1 − slack/l)`` the remaining slack allows one bar of length ``l``.

Vessel checks (when ``scene.vessel`` is set; :mod:`guidewire.vessel`):

- **vessel fit**: every lumen radius (each centreline point's, each branch's; half the walls' distance along their
  midline) larger than the wire's radius ``d/2``;
- **vessel positions**: the base and every contact point inside the lumen by at least ``d/2``;
- **vessel direction**: a clamped base at the entrance pointing into the vessel (within 90° of the centreline's
  tangent there).

Discrete checks (the scene's own ``bars`` and ``scheme``; :func:`guidewire.chain.place_bars` puts a node at every
contact). A prescribed tangent is an *anchor* at a position along the chain counted in joints: the base angle at 0
(the joint ``φ₁ − θ_A`` is bounded by b₂ in both schemes), a contact angle at node ``k`` at ``k`` in the paper scheme
(the row ``φ_k = θ*``), and in the second-order scheme at ``k + ½`` (the tangent at node ``k`` is the mean of its two
bars) or ``n + 1`` at the tip (the half joint ``θ* − φ_n`` is bounded by b₂). Then:

- **turning**: with ``|Δθ| ≤ b₂`` per joint, two anchors ``d`` joints apart can differ by at most ``d·b₂``;
- **discrete reach**: every bar angle lies in an interval (each anchor allows ``|φ_j − θ| ≤ |j − pos|·b₂``), so
  the bars between two prescribed positions reach at most ``Σ l_j max_{φ ∈ I_j} cos(φ − ψ)`` along their chord
  direction ``ψ``; and where every bar between two positions is either fixed by a prescribed angle or free, the free
  ones (rigid) must span what the fixed ones leave: between the longest minus the rest and their sum (a single bar:
  exactly its length).
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..chain.kinematics import scene_bars
from ..fields import fmt as _fmt
from ..fields import fmt_point as _fmt_point

if TYPE_CHECKING:
    from ..scene.scene import Scene

FloatArray = NDArray[np.float64]

FEASIBILITY_SLACK = 1e-9
"""Relative slack (of the wire length involved) allowed before a distance or a turn counts as out of reach."""

TAUT_ANGLE_TOLERANCE = 1e-6
"""A prescribed angle at a taut stretch of wire may differ from the chord direction by this much (rad), or by the turn
the remaining slack allows one bar, whichever is larger."""


def _point_label(name: str, p: tuple[float, float], s: float) -> str:
    return f"{name} ({_fmt(p[0])}, {_fmt(p[1])}) at s = {_fmt(s)}"


def _positions(scene: Scene) -> list[tuple[str, float, tuple[float, float], int]]:
    """(label, s, point, contact index or −1 for the base) of every prescribed position, by increasing s."""
    out = [(scene.base.name or "base", 0.0, scene.base.point, -1)]
    out += [(c.label(i), c.s, c.point, i) for i, c in enumerate(scene.contacts) if c.point is not None]
    return out


@lru_cache(maxsize=8)
def _bars(scene: Scene) -> tuple[FloatArray, NDArray[np.int_]]:
    """:func:`~guidewire.chain.place_bars` of the scene (bar lengths, contact nodes), shared by the checks."""
    return scene_bars(scene)


def _angle_gap(a: float, b: float) -> float:
    """``|a − b|`` modulo 2π, in [0, π]."""
    return abs(math.remainder(a - b, 2.0 * math.pi))


def continuum_reach(scene: Scene) -> str | None:
    """Two consecutive prescribed positions farther apart than the wire between them."""
    points = _positions(scene)
    for (name_a, s_a, p_a, _), (name_b, s_b, p_b, _) in zip(points, points[1:], strict=False):
        distance = math.dist(p_a, p_b)
        available = s_b - s_a
        if distance > available * (1.0 + FEASIBILITY_SLACK):
            return (
                f"{_point_label(name_a, p_a, s_a)} and {_point_label(name_b, p_b, s_b)} are {distance:.2f} mm "
                f"apart with only {available:.1f} mm of wire between them; move a contact or lengthen the wire "
                "between them"
            )
    return None


def walls(scene: Scene) -> str | None:
    """The base or a contact point outside a wall."""
    for j, wall in enumerate(scene.walls):
        for name, _, p, _ in _positions(scene):
            if wall.signed_distance(p) > 1e-9 * max(1.0, abs(wall.offset)):
                return (
                    f"{name} ({_fmt(p[0])}, {_fmt(p[1])}) lies outside wall {j + 1} "
                    f"({_fmt(wall.normal[0])}·x + {_fmt(wall.normal[1])}·y ≤ {_fmt(wall.offset)}); move the point "
                    "inside or the wall out"
                )
    return None


def vessel_fit(scene: Scene) -> str | None:
    """A lumen radius not larger than the wire's radius ``d/2``: the wire does not fit."""
    vessel = scene.vessel
    if vessel is None:
        return None
    half = 0.5 * scene.wire.diameter
    fix = f"widen the lumen or use a thinner wire (wire.diameter = {_fmt(scene.wire.diameter)} mm)"
    if vessel.walls:
        width, s = _narrowest_walls(vessel)
        if width <= half:
            p, _ = vessel.path(np.array([s]))
            return (f"the vessel's walls are {2.0 * width:.4g} mm apart near {_fmt_point(p[0])}, not wider than the "
                    f"wire (d = {_fmt(scene.wire.diameter)} mm); {fix}")
        return None
    for name, where, radius in _narrowest_tubes(vessel):
        if radius <= half:
            return (f"{name}{where} is {_fmt(radius)} mm, not larger than the wire's radius d/2 = "
                    f"{_fmt(half)} mm: the wire does not fit; {fix}")
    return None


@lru_cache(maxsize=8)
def _narrowest_walls(vessel: Any) -> tuple[float, float]:
    """Half the least distance (mm) of a two-wall vessel's walls along its midline, of 401 arc lengths, and that arc
    length (computed once per vessel: an insertion checks every step's scene)."""
    s = np.linspace(0.0, vessel.length, 401)
    width = vessel.radius_at(s)
    i = int(np.argmin(width))
    return float(width[i]), float(s[i])


@lru_cache(maxsize=8)
def _narrowest_tubes(vessel: Any) -> tuple[tuple[str, str, float], ...]:
    """(name, where, least radius in mm) of the main tube and every branch, in that order (computed once per
    vessel)."""
    tubes = [("vessel.radius", vessel.centreline, vessel.radius)]
    tubes += [(f"vessel.branch[{i}].radius", b.centreline, b.radius) for i, b in enumerate(vessel.branches)]
    out = []
    for name, line, radius in tubes:
        radii = np.broadcast_to(np.asarray(radius, dtype=float), (len(line),))
        i = int(np.argmin(radii))
        out.append((name, f"[{i}] at {_fmt_point(line[i])}" if isinstance(radius, tuple) else "", float(radii[i])))
    return tuple(out)


@lru_cache(maxsize=8)
def _entrance_radius(vessel: Any) -> float:
    """The main tube's radius (mm) at the entrance (computed once per vessel)."""
    return float(vessel.radius_at(0.0)[0])


def vessel_positions(scene: Scene) -> str | None:
    """The base or a contact point outside the lumen (closer than ``d/2`` to its wall, or beyond it)."""
    vessel = scene.vessel
    if vessel is None:
        return None
    positions = _positions(scene)
    distances = _clearances(vessel, tuple(p for _, _, p, _ in positions))
    for (name, s, p, _), d, half in zip(positions, distances, _half_diameters(scene, positions), strict=True):
        if d < half - 1e-9 * max(1.0, abs(half)):
            where = "outside the lumen" if d < 0.0 else "too close to the lumen's wall"
            return (f"{_point_label(name, p, s)} is {where}: its clearance is {d:.4g} mm but the wire needs d/2 = "
                    f"{_fmt(half)} mm; move it into the vessel (omit [base] to start at the entrance "
                    f"{_fmt_point(vessel.entrance_point)})")
    return None


@lru_cache(maxsize=8)
def _clearances(vessel: Any, points: tuple[tuple[float, float], ...]) -> tuple[float, ...]:
    """The vessel's signed clearance (mm) at each of ``points`` (kept per vessel and points: an insertion checks the
    same base at every step, and a closest-point search costs far more than the check around it)."""
    return tuple(float(d) for d in vessel.clearance(np.array(points, dtype=float)).distance)


def _half_diameters(scene: Scene, positions: list[tuple[str, float, tuple[float, float], int]]) -> FloatArray:
    """The wire's radius (mm) at each position's arc length: its section's, the larger of the two on a section
    boundary (as the lumen rows take it, :func:`guidewire.blocks.lumen.node_diameters`)."""
    wire = scene.wire
    s = np.array([p[1] for p in positions])
    below = np.maximum(s - 1e-9 * wire.length, 0.0)
    return 0.5 * np.maximum(wire.properties_at(s).diameter, wire.properties_at(below).diameter)


ENTRANCE_TOLERANCE = 1e-6
"""A base within this many mm (× max(1, lumen radius)) of the vessel's entrance is at the entrance."""


def vessel_direction(scene: Scene) -> str | None:
    """A clamped base at the vessel's entrance whose angle points out of the vessel (90° or more from the
    centreline's tangent there)."""
    vessel, angle = scene.vessel, scene.base.angle
    if vessel is None or angle is None:
        return None
    scale = max(1.0, _entrance_radius(vessel))
    if math.dist(scene.base.point, vessel.entrance_point) > ENTRANCE_TOLERANCE * scale:
        return None
    into = vessel.entrance_angle
    if math.cos(angle - into) <= 0.0:
        return (f"base.angle {_fmt(angle)} rad points out of the vessel at its entrance "
                f"{_fmt_point(vessel.entrance_point)}, where the vessel goes in along {into:.6g} rad; give an angle "
                "within 90° of that, or omit [base] to start along the centreline")
    return None


def taut_angles(scene: Scene) -> str | None:
    """A stretch of wire pulled straight between two positions, with a prescribed angle off its chord."""
    points = _positions(scene)
    if len(points) < 2:  # no stretch between two positions (the bars are not needed)
        return None
    lengths, nodes = _bars(scene)
    node_of = {-1: 0, **{i: int(k) for i, k in enumerate(nodes)}}
    for (name_a, s_a, p_a, i_a), (name_b, s_b, p_b, i_b) in zip(points, points[1:], strict=False):
        distance = math.dist(p_a, p_b)
        available = s_b - s_a
        if distance < available * (1.0 - FEASIBILITY_SLACK):
            continue
        # what slack there is lets one bar turn by up to acos(1 − slack / l): a kink the scene's bars can make
        bar = float(lengths[node_of[i_a]])
        tolerance = max(TAUT_ANGLE_TOLERANCE, math.acos(max(-1.0, 1.0 - max(available - distance, 0.0) / bar)))
        chord = math.atan2(p_b[1] - p_a[1], p_b[0] - p_a[0])
        angled = [(name_a, scene.base.angle if i_a < 0 else scene.contacts[i_a].angle)]
        angled += [(c.label(i), c.angle) for i, c in enumerate(scene.contacts) if s_a < c.s < s_b and c.point is None]
        angled.append((name_b, scene.contacts[i_b].angle))
        for name, angle in angled:
            if angle is not None and _angle_gap(angle, chord) > tolerance:
                return (
                    f"{_point_label(name_a, p_a, s_a)} and {_point_label(name_b, p_b, s_b)} are {distance:.6g} mm "
                    f"apart with {available:.6g} mm of wire between them, so that wire must be straight along "
                    f"{chord:.6g} rad, but {name}'s prescribed angle is {_fmt(angle)} rad; prescribe the chord's "
                    "direction or give the wire some slack"
                )
    return None


def _anchors(scene: Scene, contact_nodes: NDArray[np.int_]) -> list[tuple[float, float, str]]:
    """(position in joints, angle, label) of every prescribed tangent, by position (see the module docstring)."""
    n = scene.wire.bars
    out: list[tuple[float, float, str]] = []
    if scene.base.angle is not None:
        out.append((0.0, scene.base.angle, f"{scene.base.name or 'base'} (angle {_fmt(scene.base.angle)} rad)"))
    for i, (c, k) in enumerate(zip(scene.contacts, contact_nodes, strict=True)):
        if c.angle is None:
            continue
        if scene.wire.scheme == "paper":
            pos = float(k)
        else:
            pos = float(n + 1) if k == n else k + 0.5
        out.append((pos, c.angle, f"{c.label(i)} (angle {_fmt(c.angle)} rad at s = {_fmt(c.s)})"))
    return out


def _rest_curved(scene: Scene) -> bool:
    """Whether a section of the wire has a rest curvature: then b₂ bounds the bend away from the rest shape, which
    the b₂ checks here do not model, so they are skipped (no false refusals; the solver still enforces b₂)."""
    return any(sec.rest_curvature != 0.0 for sec in scene.wire.sections)


def turning(scene: Scene) -> str | None:
    """Two prescribed tangents further apart in angle than b₂ per joint allows."""
    b2 = scene.wire.max_relative_angle
    if b2 is None or _rest_curved(scene):
        return None
    _, nodes = _bars(scene)
    anchors = _anchors(scene, nodes)
    for (pos_a, th_a, name_a), (pos_b, th_b, name_b) in zip(anchors, anchors[1:], strict=False):
        joints = pos_b - pos_a
        turn = abs(th_b - th_a)
        if turn > joints * b2 * (1.0 + FEASIBILITY_SLACK) + 1e-12:
            return (
                f"{name_a} and {name_b} are {_fmt(joints)} joints apart in the {scene.wire.bars}-bar chain: turning "
                f"{turn:.6g} rad needs |Δθ| ≥ {turn / joints:.6g} rad per joint, but wire.max_relative_angle (b₂) is "
                f"{_fmt(b2)}; raise b₂ to at least {turn / joints:.6g} or use more bars"
            )
    return None


def _best_cosine(lo: FloatArray, hi: FloatArray, psi: float) -> FloatArray:
    """``max cos(φ − ψ)`` over ``φ ∈ [lo, hi]``, elementwise (1 where the interval contains ``ψ`` mod 2π)."""
    with np.errstate(invalid="ignore"):
        k = np.ceil((lo - psi) / (2.0 * np.pi))  # first ψ + 2πk ≥ lo
        contains = ~np.isfinite(lo) | ~np.isfinite(hi) | (psi + 2.0 * np.pi * k <= hi)
        ends = np.maximum(np.cos(lo - psi), np.cos(hi - psi))
    return np.where(contains, 1.0, ends)


def _rigid(pair: str, distance: float, n: int, fixed: str, what: str, need: float) -> str:
    """The message of rigid bars that cannot span what two positions need."""
    return (f"{pair} are {distance:.6g} mm apart; between them in the {n}-bar chain{fixed} there is {what}, which must "
            f"span {need:.6g} mm: rigid bars cannot; use more bars or move a contact")


def discrete_reach(scene: Scene) -> str | None:
    """Two prescribed positions the bars between them cannot join, given the anchors and b₂."""
    n = scene.wire.bars
    if len(_positions(scene)) < 2:  # no two positions to join (every reason below is about a pair)
        return None
    lengths, nodes = _bars(scene)
    anchors = _anchors(scene, nodes)
    b2 = math.inf if scene.wire.max_relative_angle is None or _rest_curved(scene) else scene.wire.max_relative_angle
    total = float(scene.wire.length)
    node_of = {-1: 0, **{i: int(k) for i, k in enumerate(nodes)}}
    spans = []  # (label of the pair, first bar, end bar, the two points)
    points = _positions(scene)
    for (name_a, s_a, p_a, i_a), (name_b, s_b, p_b, i_b) in zip(points, points[1:], strict=False):
        pair = f"{_point_label(name_a, p_a, s_a)} and {_point_label(name_b, p_b, s_b)}"
        spans.append((pair, node_of[i_a], node_of[i_b], p_a, p_b))
    if b2 == math.inf and (scene.wire.scheme != "paper" or not anchors):
        return _single_bar_reach(spans, lengths, total, n)
    j = np.arange(1, n + 1, dtype=float)
    lo, hi = np.full(n, -np.inf), np.full(n, np.inf)
    for pos, theta, _ in anchors:
        dist = np.abs(j - pos)
        reach = dist * b2 if math.isfinite(b2) else np.where(dist == 0.0, 0.0, np.inf)
        lo, hi = np.maximum(lo, theta - reach), np.minimum(hi, theta + reach)
    for pair, a, b, p_a, p_b in spans:
        delta = np.subtract(p_b, p_a)
        distance = float(np.hypot(*delta))
        reason = _rigid_reach(pair, delta, distance, lengths[a:b], lo[a:b], hi[a:b], total, n)
        if reason is not None:
            return reason
        psi = math.atan2(delta[1], delta[0])
        reach = float(lengths[a:b] @ _best_cosine(lo[a:b], hi[a:b], psi))
        if distance > reach + FEASIBILITY_SLACK * total:
            limit = "" if scene.wire.max_relative_angle is None else f" and b₂ = {_fmt(b2)}"
            return (
                f"{pair} are {distance:.6g} mm apart, but with the prescribed angles{limit} the {b - a} bars between "
                f"them (of the {n}-bar chain) reach at most {reach:.6g} mm in that direction; use more bars"
                + ("" if scene.wire.max_relative_angle is None else ", raise b₂")
                + " or move a contact"
            )
    return None


def _single_bar_reach(spans: list[Any], lengths: FloatArray, total: float, n: int) -> str | None:
    """No angle bounds a bar: every bar is free, and with equal bars between two positions (one segment) only a
    single bar has a least reach (its length; the most is the continuum check's)."""
    for pair, a, b, p_a, p_b in spans:
        distance = math.dist(p_a, p_b)
        if b - a == 1 and abs(distance - lengths[a]) > FEASIBILITY_SLACK * total:
            return _rigid(pair, distance, n, "", f"one bar of {lengths[a]:.6g} mm", distance)
    return None


def _rigid_reach(pair: str, delta: FloatArray, distance: float, seg: FloatArray, lo: FloatArray, hi: FloatArray,
                 total: float, n: int) -> str | None:
    """When every bar between two positions is pinned by a prescribed angle or free to turn all the way round
    (rigid bars): the free ones must span what the pinned ones leave, a distance between the longest free bar minus
    the others and their sum (a single bar: exactly its length)."""
    pinned = hi - lo <= 0.0  # bars whose angle a prescribed angle fixes (paper scheme)
    free = ~np.isfinite(hi - lo)  # bars free to turn all the way round
    if not np.all(pinned | free):
        return None
    rest = delta - seg[pinned] @ np.column_stack((np.cos(lo[pinned]), np.sin(lo[pinned])))
    need = float(np.hypot(*rest))
    longest, reach_free = float(seg[free].max(initial=0.0)), float(seg[free].sum())
    shortest = max(0.0, 2.0 * longest - reach_free)
    if shortest - FEASIBILITY_SLACK * total <= need <= reach_free + FEASIBILITY_SLACK * total:
        return None
    what = (f"one bar of {longest:.6g} mm" if free.sum() == 1 else
            f"{int(free.sum())} bars that span {shortest:.6g} to {reach_free:.6g} mm")
    fixed = f" besides the {int(pinned.sum())} bar(s) a prescribed angle fixes" if pinned.any() else ""
    return _rigid(pair, distance, n, fixed, what, need)


CHECKS = (
    continuum_reach, walls, vessel_fit, vessel_positions, vessel_direction, taut_angles, turning, discrete_reach,
)
"""The checks :func:`infeasibility` runs, in this order (the first reason found is reported)."""


def infeasibility(scene: Scene) -> str | None:
    """Why no wire shape can meet ``scene``: the first reason from :data:`CHECKS`, or None when nothing obvious
    forbids it.

    Necessary conditions only (see the module docstring): prescribed positions within reach of the wire between
    them, the base and contact points inside every wall, a vessel wide enough for the wire with the base and contact
    points inside its lumen and a clamp at its entrance pointing in, a taut stretch of wire straight along its chord,
    prescribed angles within the turning ``b₂`` allows, and positions within reach of the scene's bars.
    """
    for check in CHECKS:
        reason = check(scene)
        if reason is not None:
            return reason
    return None


def check_feasible(scene: Scene) -> None:
    """Raise ``ValueError`` naming the scene and the reason when :func:`infeasibility` finds one."""
    reason = infeasibility(scene)
    if reason is not None:
        label = f"scene {scene.name!r}" if scene.name else "scene"
        raise ValueError(f"{label} is infeasible: {reason}.")
