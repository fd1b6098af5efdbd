"""The default starting shape: a smooth curve through the contact poses, re-sampled onto the bar chain.

Several equilibria exist (for Table 1 with θ_B = 0 a straight start and an arc start reach different local minima), so
the start decides which one the solver finds. The default start aims at the lowest-energy one:

1. Poses: the base and every contact with a point, each with a tangent. A prescribed tangent is taken literally
   (angles are not reduced modulo 2π: the difference of two prescribed angles is the turning asked for). A missing
   tangent is estimated: at an interior pose, the direction from the previous to the next pose; at an end, the
   circular-arc reflection ``2·chord − θ_neighbour`` (exact for a circular arc), or the chord when the neighbour's
   tangent is unknown too; an estimate is unwrapped to within π of its neighbour.
2. Between consecutive poses: a curve exactly as long as the wire between them, with the poses' tangents at both
   ends and passing through both points. Its tangent angle is ``θ(s) = θ₀ + (θ₁ − θ₀) s/ℓ + c₁ sin(πs/ℓ) +
   c₂ sin(2πs/ℓ)``; the two coefficients that close the curve on the next point are found by Newton's method from a
   5 × 5 grid of starts (vectorised), and of the closing curves the one with the least ``∫ θ'² ds`` is taken — a
   two-mode elastica, so the start sits in the basin of the lowest-energy equilibrium. (A cubic Hermite curve,
   the obvious alternative, is shorter than the wire unless its tangents are so long that it loops.) Each bar takes
   the curve's angle at its midpoint, so the start satisfies the position constraints to O((L/n)²).
0. In a vessel without contacts: the centreline from the entrance (a wire advanced along the lumen), never an arc
   that merely clears the walls (in a channel that is a coil).
3. Beyond the last pose (a free end, or the whole wire when there is no contact): a circular arc continuing the last
   tangent with the smallest curvature ``|κ|`` (either sign, 0 included) whose nodes satisfy every wall, times a 5 %
   margin. Without walls this is a straight continuation, the free end's exact minimum. With walls it is a curved,
   strictly feasible start: a straight wire pressed against a wall would have zero wall gradients (the linearised
   constraint is blind to which way to bend) and stall the first QP.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..chain.kinematics import BarChain
from ..scene.scene import Scene
from .newton import curve_lines, curve_tables, newton

FloatArray = NDArray[np.float64]

CURVE_SAMPLES = 64
"""Quadrature points per segment for the end point of a trial curve (midpoint rule)."""

NEWTON_GRID, NEWTON_GRID_POINTS, NEWTON_STEPS = 2.0 * math.pi, 5, 12
"""Starts ``(c₁, c₂) ∈ [−2π, 2π]²`` on a 5 × 5 grid, 12 damped Newton steps each (on every paper scene the same
start as a 9 × 9 grid with 40 steps, at a fifth of the cost)."""

COARSE_SAMPLES, COARSE_STEPS, POLISH_MISS = 16, 8, 1e-2
"""The first 8 Newton steps of every start on a 16-point rule (a quarter of the cosines); the starts then within
1e-2 (of ℓ) of closing get the last 4 on the full rule (quadratic convergence: 1e-2 → 1e-16 in 3 steps)."""

CLOSURE_TOLERANCE = 1e-9
"""A trial curve counts as reaching the next pose when it misses by at most this fraction of its length."""

WALL_MARGIN = 1.05
"""Factor on the smallest wall-feasible curvature of the free part, so the start is strictly inside the walls."""

MAX_FREE_TURNING = 2.0 * math.pi
"""The free part's start arc turns at most this much (rad): a longer arc of constant curvature overlaps itself (the
coil a channel's walls once produced, reported as success at 300 times the energy)."""

_TRIAL_CURVATURES = np.concatenate(([0.0], np.geomspace(1e-4, 10.0, 125)))
"""Trial curvatures of the free part, as fractions of ``4π / L_free`` (two full turns; up to 20 turns, for a long
wire in front of a near wall); 0 first."""


def _wrap(angle: float) -> float:
    """``angle`` in (−π, π]."""
    return math.remainder(angle, 2.0 * math.pi)


def _chord_angle(a: FloatArray, b: FloatArray) -> float:
    return math.atan2(b[1] - a[1], b[0] - a[0])


def _pose_angles(points: list[FloatArray], angles: list[float | None]) -> list[float]:
    """Fill the missing tangents of the poses (step 1 of the module docstring), continuous from one to the next."""
    m = len(points)
    filled: list[float | None] = list(angles)
    for i in range(1, m - 1):  # interior poses: previous-to-next direction (the tangent of the circle through the
        if filled[i] is None:  # three points did as well: 5 vs 4 of 800 random scenes on a higher local minimum)
            filled[i] = _chord_angle(points[i - 1], points[i + 1])
    for i, j in ((0, 1), (m - 1, m - 2)):  # the two ends: arc reflection of the neighbour's tangent
        if m > 1 and filled[i] is None:
            chord = _chord_angle(points[min(i, j)], points[max(i, j)])
            filled[i] = chord if filled[j] is None else chord + _wrap(chord - filled[j])  # type: ignore[operator]
    out = [0.0 if filled[0] is None else float(filled[0])]
    if angles[0] is None and m > 1 and angles[1] is not None:  # an estimate takes its neighbour's winding
        out[0] = float(angles[1]) + _wrap(out[0] - float(angles[1]))
    for value, given in zip(filled[1:], angles[1:], strict=True):
        # a prescribed angle is literal (its difference from the previous one is the turning the scene asks for);
        # an estimated one is unwrapped to within π of the previous tangent
        out.append(float(value) if given is not None else out[-1] + _wrap(float(value) - out[-1]))  # type: ignore[arg-type]
    return out


#: The grid of starts ``[c₁, c₂]`` of :func:`_segment_curves` (read-only; each call copies it).
_STARTS = np.stack(np.meshgrid(*(2 * [np.linspace(-NEWTON_GRID, NEWTON_GRID, NEWTON_GRID_POINTS)]), indexing="ij"),
                   axis=-1).reshape(-1, 2)
_STARTS.flags.writeable = False


Segment = tuple[FloatArray, FloatArray, float, float, float]
"""``(p0, p1, a0, a1, ℓ)``: the end points, end tangents and length of a segment between two poses."""


def _segment_curves(
    p0: FloatArray, p1: FloatArray, a0: float, a1: float, length: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """All curves of the family ``θ(s) = a0 + (a1 − a0) s/ℓ + c₁ sin(πs/ℓ) + c₂ sin(2πs/ℓ)`` from ``p0`` that end at
    ``p1``, found by Newton's method from a grid of ``(c₁, c₂)`` (all starts at once).

    The first :data:`COARSE_STEPS` steps use a :data:`COARSE_SAMPLES`-point rule (they only bring the starts into
    a basin); the starts then within :data:`POLISH_MISS` of closing get the remaining steps on the
    :data:`CURVE_SAMPLES`-point rule, which decides the closure (the others cannot close to 1e-9 in so few steps
    and are dropped: miss ``inf``).

    Returns
    -------
    coefficients : ndarray, shape (G, 2)
    residual : ndarray, shape (G,)
        End-point miss in mm of each start after the Newton steps (``inf`` for a dropped start; below 1e-12 ℓ for a
        start whose last step was below 1e-13).
    energy : ndarray, shape (G,)
        ``∫ θ'² ds`` of each curve (1/mm), the bending energy over ``EI/2`` (``inf`` for a dropped start).
    """
    return _many_segment_curves([(p0, p1, a0, a1, length)])[0]


def _many_segment_curves(segments: list[Segment]) -> list[tuple[FloatArray, FloatArray, FloatArray]]:
    """:func:`_segment_curves` of several segments, their grids as the rows of one Newton iteration (a step costs
    little more for two segments than for one). For one segment the same arithmetic, bit for bit; for several, the
    same up to rounding (the matrix products over more rows may round differently), and the iteration stops early
    only when every segment's rows settled."""
    count, starts = len(segments), _STARTS.shape[0]
    p0, p1 = np.array([seg[0] for seg in segments], dtype=float), np.array([seg[1] for seg in segments], dtype=float)
    a0, a1, length = (np.array([seg[k] for seg in segments], dtype=float) for k in (2, 3, 4))
    target = (p1 - p0) / length[:, None]
    offset = np.zeros((count, 6))
    offset[:, 0], offset[:, 3] = target[:, 0], target[:, 1]
    c = np.tile(_STARTS, (count, 1))  # (S G, 2): the grid of each segment in turn
    row_segment = np.repeat(np.arange(count), starts)
    lines = curve_lines(COARSE_SAMPLES, a0, a1)
    coarse, _ = newton(c, lines[row_segment] if count > 1 else lines, offset[row_segment] if count > 1 else offset,
                        COARSE_SAMPLES, COARSE_STEPS)
    near = np.flatnonzero(coarse <= POLISH_MISS)
    seg = row_segment[near]
    lines = curve_lines(CURVE_SAMPLES, a0, a1)[seg]
    fine = c[near]
    last, settled = newton(fine, lines, offset[seg], CURVE_SAMPLES, NEWTON_STEPS - COARSE_STEPS)
    c[near] = fine
    _, basis, blocks, (cos1, cos2) = curve_tables(CURVE_SAMPLES)
    if not settled:  # the end points' own miss (when every step settled, the last one decides the same)
        args = fine @ basis
        args += lines
        m = np.cos(args, out=args) @ blocks[:, ::3]
        last = np.hypot(m[:, 0] - target[seg, 0], m[:, 1] - target[seg, 1])
    miss, energy = np.full(c.shape[0], np.inf), np.full(c.shape[0], np.inf)
    miss[near] = last * length[seg]
    slope = (a1 - a0)[seg, None] + np.pi * fine[:, :1] * cos1 + 2.0 * np.pi * fine[:, 1:2] * cos2
    energy[near] = np.mean(slope**2, axis=1) / length[seg]  # ∫ (dθ/ds)² ds
    rows = c.reshape(count, starts, 2)
    miss, energy = miss.reshape(count, starts), energy.reshape(count, starts)
    return [(rows[k], miss[k], energy[k]) for k in range(count)]


def least_bending(segments: list[Segment]) -> FloatArray:
    """``∫ θ'² ds`` (1/mm) of the least-bending closing start curve of each segment ``(p0, p1, a0, a1, ℓ)`` (all
    grids in one Newton iteration, :func:`_many_segment_curves`): ``inf`` where no curve closes, 0 for a nearly
    taut segment (its start is the chord or arc whatever the tangents). Used to compare trial tangents of a pose
    (:mod:`guidewire.solve.branches`)."""
    out = np.zeros(len(segments))
    curved = [k for k, seg in enumerate(segments) if _curved(float(np.hypot(*(seg[1] - seg[0]))), float(seg[4]))]
    if curved:
        for k, (_, miss, energy) in zip(curved, _many_segment_curves([segments[k] for k in curved]), strict=True):
            closing = energy[miss <= CLOSURE_TOLERANCE * segments[k][4]]
            out[k] = closing.min() if closing.size else np.inf
    return out


def _least(c: FloatArray, energy: FloatArray) -> int:
    """Index of the least ``energy``; a near tie (within :data:`TIE_TOLERANCE`, as for the two mirror-image curves of
    a symmetric segment) goes to the least ``c₂``, then ``c₁``, rather than to rounding."""
    k = int(np.argmin(energy))
    if not np.isfinite(energy[k]):
        return k
    tied = np.flatnonzero(energy <= energy[k] * (1.0 + TIE_TOLERANCE))
    return int(tied[np.lexsort((c[tied, 0], c[tied, 1]))[0]])


TIE_TOLERANCE = 1e-12
"""Relative energy difference below which two closing curves count as tied (see :func:`_least`)."""


def _segment_angles(
    p0: FloatArray, p1: FloatArray, a0: float, a1: float, lengths: FloatArray, a1_free: bool = False,
    curves: tuple[FloatArray, FloatArray, FloatArray] | None = None,
) -> tuple[FloatArray, float]:
    """Angles of the bars between two poses: the least-energy curve of :func:`_segment_curves` at each bar's
    midpoint (the straight chord if the wire is taut; the straight-line-in-angle curve if no curve closes).

    When ``a1_free`` (the end tangent is only an estimate) and no curve closes with it, the estimate plus each of
    :data:`END_TANGENT_OFFSETS` is tried and the least-energy closing curve kept. ``curves``: the grid of
    :func:`_segment_curves` for this segment with the end tangent ``a1``, when already computed. Returns the angles
    and the end tangent used."""
    length = float(lengths.sum())
    u_mid = (np.cumsum(lengths) - 0.5 * lengths) / length
    chord = np.hypot(*(p1 - p0))
    if not _curved(chord, length):
        straight = a0 + _wrap(math.atan2(p1[1] - p0[1], p1[0] - p0[0]) - a0)  # the chord, in a0's winding
        if chord >= length * (1.0 - TAUT_ROUNDING):  # taut up to rounding: the straight chord
            return np.full(lengths.size, straight), (straight if a1_free else a1)
        # nearly taut: the circular arc of this length through both points (turning 2x, sin(x)/x = chord/length),
        # bulging towards the given end tangent; a straight start would make the position rows' Jacobian lose rank
        x = math.sqrt(6.0 * (1.0 - chord / length))
        for _ in range(3):
            x -= (math.sin(x) / x - chord / length) / ((x * math.cos(x) - math.sin(x)) / (x * x))
        side = 1.0 if _wrap(straight - a0) >= 0.0 else -1.0
        angles = straight + side * x * (2.0 * u_mid - 1.0)
        return angles, (straight + side * x if a1_free else a1)
    best, best_energy, end = np.zeros(2), np.inf, a1
    for offset in (0.0, *END_TANGENT_OFFSETS) if a1_free else (0.0,):
        c, miss, energy = curves if offset == 0.0 and curves is not None else _segment_curves(p0, p1, a0, a1 + offset,
                                                                                             length)
        energy = np.where(miss <= CLOSURE_TOLERANCE * length, energy, np.inf)
        k = _least(c, energy)
        if energy[k] < best_energy:
            best, best_energy, end = c[k], float(energy[k]), a1 + offset
        if offset == 0.0 and np.isfinite(best_energy):  # the estimate closes: keep it
            break
    angles = a0 + (end - a0) * u_mid + best[0] * np.sin(np.pi * u_mid) + best[1] * np.sin(2.0 * np.pi * u_mid)
    return angles, end


NEARLY_TAUT, TAUT_ROUNDING = 1e-6, 1e-14
"""A segment whose chord is within ``NEARLY_TAUT`` of its length starts as the circular arc through its end points,
unless it is within ``TAUT_ROUNDING`` (taut up to rounding): then as the straight chord."""


def _curved(chord: float, length: float) -> bool:
    """Whether a segment of this chord and length takes a curve of the grid (it is not nearly taut)."""
    return bool(chord < length * (1.0 - NEARLY_TAUT))


def _grids_ahead(points: list[FloatArray], tangents: list[float], spans: list[FloatArray]
                 ) -> dict[int, tuple[tuple[float, float], tuple[FloatArray, FloatArray, FloatArray]]]:
    """The grids of every curved segment at once (:func:`_many_segment_curves`), each with the end tangents it used
    (those estimated before any segment ran; a segment that changes its end tangent invalidates the next one's), or
    nothing for fewer than two curved segments (one grid gains nothing from it)."""
    curved = [i for i, span in enumerate(spans)
              if _curved(float(np.hypot(*(points[i + 1] - points[i]))), float(span.sum()))]
    if len(curved) < 2:
        return {}
    grids = _many_segment_curves([(points[i], points[i + 1], tangents[i], tangents[i + 1], float(spans[i].sum()))
                                  for i in curved])
    return {i: ((tangents[i], tangents[i + 1]), grid) for i, grid in zip(curved, grids, strict=True)}

END_TANGENT_OFFSETS = np.pi * np.array([0.25, -0.25, 0.5, -0.5, 0.75, -0.75, 1.0])
"""Offsets from an estimated end tangent tried when no start curve closes with the estimate itself."""


def _free_part_angles(scene: Scene, start: FloatArray, angle: float, lengths: FloatArray) -> FloatArray:
    """Angles of the bars after the last pose: the least-curved wall-feasible arc (step 3 of the docstring)."""
    if lengths.size == 0:
        return np.zeros(0)
    s_mid = np.cumsum(lengths) - 0.5 * lengths  # arc length of each bar's midpoint from the pose
    if not scene.walls:
        return np.full(lengths.size, angle)
    total = float(lengths.sum())
    kappa = _trial_curvatures(total)
    kappa = kappa[np.abs(kappa) * total <= MAX_FREE_TURNING]  # a longer arc overlaps itself: a coil, not a wire
    gap = _wall_gaps(scene, start, angle, kappa, s_mid, lengths)
    feasible = gap >= 0.0
    if not feasible.any():  # nothing clears the walls without looping: the least violating arc that does not loop
        gap = _wall_gaps(scene, start, angle, kappa, s_mid, lengths, lazy=False)
        return angle + kappa[int(np.argmax(gap))] * s_mid
    # the least |κ| that clears the walls; of its two signs (when both do) the one farther from them, so that the
    # start of a mirrored scene is the mirrored start
    least = np.flatnonzero(feasible & (np.abs(kappa) == np.abs(kappa[int(np.argmax(feasible))])))
    pick = int(least[np.argmax(gap[least])])
    return angle + min(WALL_MARGIN * abs(kappa[pick]), MAX_FREE_TURNING / total) * np.sign(kappa[pick]) * s_mid


def _trial_curvatures(total: float) -> FloatArray:
    """The trial curvatures (1/mm) for a free part of length ``total``, by increasing ``|κ|`` (0, then each magnitude
    positive before negative)."""
    magnitudes = _TRIAL_CURVATURES * 4.0 * math.pi / total
    kappa = np.concatenate((magnitudes, -magnitudes[1:]))  # (T,)
    return kappa[np.argsort(np.abs(kappa), kind="stable")]


FREE_CHUNK_NODES = 32
"""Nodes per pass of the lazy wall check of :func:`_wall_gaps` (the first pass; each later one twice the last)."""


def _wall_gaps(scene: Scene, start: FloatArray, angle: float, kappa: FloatArray, s_mid: FloatArray,
               lengths: FloatArray, lazy: bool = True) -> FloatArray:
    """The least distance inside every wall of the nodes of each trial arc ``φ = angle + κ s`` from ``start`` (mm).

    Lazy (default): the nodes are visited from the pose outwards in passes (:data:`FREE_CHUNK_NODES`, doubling), and
    an arc leaves the search at the first pass that puts a node outside a wall; its gap is then the (negative)
    least distance seen so far, which decides infeasibility as well as the full one does. The arcs that clear every
    wall get their exact gap: bit for bit the one of the eager evaluation (``lazy=False``, every arc over every
    node), since every node is the same running sum of the same bar vectors."""
    m = lengths.size
    walls = [wall.unit() for wall in scene.walls]
    gap = np.full(kappa.size, np.inf)
    rows = np.arange(kappa.size)
    last = np.zeros((kappa.size, 2))  # the running sum of bar vectors up to the previous pass
    lo, width = 0, (FREE_CHUNK_NODES if lazy else m)
    while lo < m and rows.size:
        part = slice(lo, lo + width)
        # x and y apart, in place (no (rows, nodes, 2) temporaries): per element the arithmetic of
        # start + cumsum(l (cos φ, sin φ)) continued from ``last``, and offset − n̂ · p
        phi = kappa[rows, None] * s_mid[None, part]
        phi += angle
        x = np.cos(phi)
        y = np.sin(phi, out=phi)
        x *= lengths[None, part]
        y *= lengths[None, part]
        x[:, 0] += last[rows, 0]
        y[:, 0] += last[rows, 1]
        np.cumsum(x, axis=1, out=x)
        np.cumsum(y, axis=1, out=y)
        last[rows, 0], last[rows, 1] = x[:, -1], y[:, -1]
        x += start[0]
        y += start[1]
        for (nx, ny), offset in walls:
            reach = x * nx
            reach += y * ny
            gap[rows] = np.minimum(gap[rows], offset - reach.max(axis=1))  # (min of offset − reach, rounding kept)
        lo, width = lo + width, 2 * width
        if lazy:
            rows = rows[gap[rows] >= 0.0]
    return gap


def _lumen_angles(vessel: Any, chain: BarChain, base_angle: float | None) -> FloatArray:
    """Step 0 for a wire in a vessel (no contacts): follow the centreline from the entrance — each bar takes the
    centreline's tangent at its midpoint's arc length — unwrapped to within π of the base angle."""
    return route_angles(vessel, chain, base_angle)


def route_angles(vessel: Any, chain: BarChain, base_angle: float | None, branch: int | None = None) -> FloatArray:
    """Bar angles (rad) of a start that follows a vessel's centreline from the entrance: the main centreline, or
    with ``branch`` the way through that branch (:meth:`guidewire.Vessel.route`). Each bar takes the centreline's
    tangent at its midpoint's arc length, unwrapped to within π of the base angle (or of the first bar's)."""
    s_mid = chain.arc_lengths[:-1] + 0.5 * chain.lengths
    _, angles = vessel.path(s_mid) if branch is None else vessel.route(s_mid, branch)
    angles = np.unwrap(np.asarray(angles, dtype=float))
    reference = angles[0] if base_angle is None else base_angle
    return angles + 2.0 * math.pi * round((reference - angles[0]) / (2.0 * math.pi))


def _poses(scene: Scene, contact_nodes: NDArray[np.int_]) -> tuple[list[int], list[FloatArray], list[float | None]]:
    """The poses (step 1 of the module docstring): the base and every contact with a point, as their nodes, their
    points and their prescribed angles (None where free; a free base without positions takes the first known
    angle)."""
    base = scene.base
    pose_nodes = [0] + [int(k) for k, c in zip(contact_nodes, scene.contacts, strict=True) if c.point is not None]
    points = [np.asarray(base.point, dtype=float)]
    points += [np.asarray(c.point, dtype=float) for c in scene.contacts if c.point is not None]
    angles: list[float | None] = [base.angle] + [c.angle for c in scene.contacts if c.point is not None]
    if len(points) == 1 and angles[0] is None:  # a free base and no position: start along the first known angle
        angles[0] = next((c.angle for c in scene.contacts if c.angle is not None), 0.0)
    return pose_nodes, points, angles


def initial_angles(scene: Scene, chain: BarChain, contact_nodes: NDArray[np.int_]) -> FloatArray:
    """The default start ``φ0`` for ``scene`` on ``chain`` (see the module docstring).

    Parameters
    ----------
    scene : Scene
    chain : BarChain
        The chain the formulation built (bar lengths with a node at every contact).
    contact_nodes : ndarray of int
        Node index of each contact of ``scene``.

    Returns
    -------
    ndarray, shape (n,)
        Bar angles in rad.
    """
    base = scene.base
    vessel = getattr(scene, "vessel", None)
    if vessel is not None and not scene.contacts:
        return _lumen_angles(vessel, chain, base.angle)
    pose_nodes, points, angles = _poses(scene, contact_nodes)
    tangents = _pose_angles(points, angles)
    lengths = chain.lengths
    spans = [lengths[pose_nodes[i] : pose_nodes[i + 1]] for i in range(len(points) - 1)]
    ahead = _grids_ahead(points, tangents, spans)
    parts = []
    for i, span in enumerate(spans):  # one curve per pair of consecutive poses (a handful, not nodes)
        used, grid = ahead.get(i, (None, None))
        part, tangents[i + 1] = _segment_angles(points[i], points[i + 1], tangents[i], tangents[i + 1], span,
                                                a1_free=angles[i + 1] is None,
                                                curves=grid if used == (tangents[i], tangents[i + 1]) else None)
        parts.append(part)
    last = pose_nodes[-1]
    parts.append(_free_part_angles(scene, points[-1], tangents[-1], lengths[last:]))
    return np.concatenate(parts)
