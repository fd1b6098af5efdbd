"""The continuum reference of a wire with sections: piecewise-constant ``EI`` and rest curvature ``κ₀``.

:class:`StiffnessProfile` holds the sections along the arc length from the base.  The shapes solve the first-order
system of :mod:`~guidewire.reference.sectioned_ode` (``M = EI (θ' − κ₀)`` and ``θ`` continuous across a section
boundary) by Newton multiple shooting with a node at every section boundary:

* between two fully clamped poses (:func:`sectioned_segment_equilibria`): every branch of the uniform segment of the
  reference stiffness (:func:`~guidewire.reference.clamped_segment.clamped_segment_equilibria`) is continued in
  ``τ ∈ [0, 1]`` to the sectioned wire (``EI_j(τ) = EI_r^(1−τ) EI_j^τ``, ``κ₀(τ) = τ κ₀``), the lowest energy wins;
* a free stretch (no contact beyond it): unloaded, it rests in its rest shape (arcs of radius ``1/κ₀``);
* a free end pushed by one straight frictionless wall (:func:`sectioned_wall_shape`): continued from the rest shape
  with the wall moved in from the tip's rest position to its place; unknowns the base moment and the wall force
  ``f ≥ 0`` (internal force ``−f n``), conditions zero moment at the tip and the tip on the wall.  Covered when the
  free end is the only touching point (e.g. a J-tip curling towards the wall); a wire that would lie along the wall
  (tangential contact) is declined.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import fields
from .clamped_segment import clamped_segment_equilibria, segment_feasibility
from .pieces import assemble, lowest_first, shifted_piece, ties
from .sectioned_ode import Grid, Shot, integrate_free, pieces_of, shoot
from .shapes import Array, ContinuumShape, ElasticaPiece
from .wall import max_wall_violation

__all__ = ["StiffnessProfile", "free_pieces", "sectioned_segment_equilibria", "sectioned_wall_shape"]

#: Continuation gives up when its step falls below this fraction of the whole path.
MIN_STEP = 1.0 / 256.0


@dataclass(frozen=True)
class StiffnessProfile:
    """Piecewise-constant bending stiffness and rest curvature along the wire, from the base.

    Attributes
    ----------
    breaks : tuple of float
        Interior arc lengths (mm from the base, increasing) where the values change.
    bending_stiffness : tuple of float
        ``EI`` (N·mm²) on each of the ``len(breaks) + 1`` stretches, base first.
    rest_curvature : tuple of float
        ``κ₀`` (1/mm) on each stretch, signed like the tangent angle's change from base to tip.
    """

    breaks: tuple[float, ...]
    bending_stiffness: tuple[float, ...]
    rest_curvature: tuple[float, ...]

    def __post_init__(self) -> None:
        breaks = tuple(fields.real(b, f"breaks[{i}]") for i, b in enumerate(self.breaks))
        ei = tuple(fields.real(v, f"bending_stiffness[{i}]", positive=True)
                   for i, v in enumerate(self.bending_stiffness))
        k0 = tuple(fields.real(v, f"rest_curvature[{i}]") for i, v in enumerate(self.rest_curvature))
        if len(ei) != len(breaks) + 1 or len(k0) != len(breaks) + 1:
            raise ValueError(f"a profile with {len(breaks)} breaks needs {len(breaks) + 1} bending_stiffness and "
                             f"rest_curvature values, got {len(ei)} and {len(k0)}")
        if any(b <= a for a, b in zip(breaks[:-1], breaks[1:], strict=True)) or (breaks and breaks[0] <= 0.0):
            raise ValueError(f"breaks must be positive and strictly increasing, got {breaks}")
        object.__setattr__(self, "breaks", breaks)
        object.__setattr__(self, "bending_stiffness", ei)
        object.__setattr__(self, "rest_curvature", k0)

    @classmethod
    def of_wire(cls, wire: Any) -> StiffnessProfile:
        """The profile of a :class:`~guidewire.Wire` (its sections inside the inserted length)."""
        breaks = tuple(wire.section_boundaries())
        edges = np.array([0.0, *breaks, wire.length])
        props = wire.properties_at(0.5 * (edges[1:] + edges[:-1]))
        return cls(breaks, tuple(map(float, props.bending_stiffness)), tuple(map(float, props.rest_curvature)))

    @property
    def uniform(self) -> bool:
        """One stiffness and no rest curvature: the plain reference applies."""
        return len(set(self.bending_stiffness)) == 1 and not any(self.rest_curvature)

    def stretch(self, a: float, b: float) -> tuple[Array, Array, Array]:
        """The sections over ``[a, b]`` in ``u = (s − a) / (b − a)``: breaks, ``EI`` and ``κ₀`` (dimensional)."""
        inner = [x for x in self.breaks if a + 1e-12 * b < x < b * (1.0 - 1e-12)]
        edges = np.array([a, *inner, b])
        index = np.searchsorted(np.array(self.breaks), 0.5 * (edges[1:] + edges[:-1]))
        return ((edges - a) / (b - a), np.array(self.bending_stiffness)[index],
                np.array(self.rest_curvature)[index])


def _pose(point: Any, angle: Any, name: str) -> tuple[Array, float]:
    return np.asarray(fields.point(point, name)), fields.real(angle, f"{name} angle")


def _profile(profile: Any) -> None:
    if not isinstance(profile, StiffnessProfile):
        raise TypeError(f"profile is {type(profile).__name__}; expected a StiffnessProfile (e.g. "
                        "StiffnessProfile.of_wire(wire))")


def _grid(profile: StiffnessProfile, a: float, b: float, EI_ref: float, g: Array, tau: float = 1.0) -> Grid:
    breaks, ei, k0 = profile.stretch(a, b)
    return Grid.of(breaks, (ei / EI_ref) ** tau, tau * k0 * (b - a), g)


def free_pieces(profile: StiffnessProfile, a: float, b: float, point: Array, theta: float) -> list[ElasticaPiece]:
    """The unloaded stretch ``[a, b]`` from ``point`` at angle ``theta``: it rests in its rest shape (energy 0)."""
    EI_ref = max(profile.bending_stiffness)
    grid = _grid(profile, a, b, EI_ref, np.zeros(2))
    shot = integrate_free(grid, np.array([0.0, 0.0, theta, 0.0]), np.zeros(2))
    if shot is None:  # arcs of bounded curvature: should not happen
        raise RuntimeError("integration of the free rest shape failed")
    return pieces_of(shot, grid, a, b - a, point, EI_ref)


def _continue(path_end: float, solve_at: Any, state: Any) -> Any:
    """Adaptive continuation in a parameter ``t`` from 0 to ``path_end`` (``solve_at(t, state) -> state | None``)."""
    t, dt = 0.0, path_end
    while t < path_end:
        step = min(dt, path_end - t)
        new = solve_at(t + step, state)
        if new is None:
            dt = 0.5 * step
            if dt < MIN_STEP * path_end:
                return None
            continue
        t, state, dt = t + step, new, 2.0 * step
    return state


def _clamp_end(target: Array) -> Any:
    dz = np.zeros((3, 4))
    dz[0, 0] = dz[1, 1] = dz[2, 2] = 1.0

    def end(z: Array, _g: Array) -> tuple[Array, Array, Array]:
        return z[:3] - target, dz, np.zeros((3, 2))

    return end


def sectioned_segment_equilibria(
    p0: Array, theta0: float, p1: Array, theta1: float, s0: float, s1: float, profile: StiffnessProfile
) -> list[ContinuumShape]:
    """Equilibria of the stretch ``[s0, s1]`` of a sectioned wire between two fully clamped poses, lowest first.

    Each branch of the uniform segment (stiffness the stretch's largest ``EI``) is continued to the sectioned wire
    (see the module docstring); branches that fail to continue are dropped, distinct results kept.  Arc lengths of
    the result run from 0 at ``p0``.

    Raises
    ------
    ValueError
        For an infeasible segment (see :func:`~guidewire.reference.clamped_segment.segment_feasibility`).
    NotImplementedError
        For a taut segment with rest curvature (its forces are unbounded), or when no branch continues.
    """
    p0, theta0 = _pose(p0, theta0, "p0")
    p1, theta1 = _pose(p1, theta1, "p1")
    s0, s1 = fields.real(s0, "s0"), fields.real(s1, "s1")
    if s1 <= s0:
        raise ValueError(f"s1 = {s1:g} must exceed s0 = {s0:g}")
    _profile(profile)
    length = s1 - s0
    _, ei, k0 = profile.stretch(s0, s1)
    EI_ref = float(np.max(ei))
    if segment_feasibility(p0, theta0, p1, theta1, length):
        if np.any(k0 != 0.0):
            raise NotImplementedError(f"the stretch s = {s0:g} .. {s1:g} is taut and has rest curvature: no finite "
                                      "forces hold it straight")
        straight = [shifted_piece(p, -s0) for p in free_pieces(profile, s0, s1, p0, theta0)]
        return [assemble(straight, length, EI_ref, p0, [(length, "clamp")])]
    end = _clamp_end(np.concatenate([(p1 - p0) / length, [theta1]]))
    found: list[tuple[Shot, Grid]] = []
    for uniform in clamped_segment_equilibria(p0, theta0, p1, theta1, length, EI_ref):
        piece = uniform.pieces[0]
        g = piece.force * length**2 / EI_ref
        grid = _grid(profile, s0, s1, EI_ref, g)
        x, y, th, kap = piece.state(grid.breaks[:-1] * length)
        Z = np.column_stack([(x - p0[0]) / length, (y - p0[1]) / length, th, kap * length])

        def at(tau: float, state: tuple[Array, Array], base: Grid = grid) -> tuple[Array, Array] | None:
            shot = shoot(Grid(base.breaks, base.e ** tau, tau * base.k), state[0], np.zeros(2), np.eye(2), state[1],
                         end)
            return None if shot is None else (shot.Z, shot.g)

        done = _continue(1.0, at, (Z, g))
        if done is None:
            continue
        shot = shoot(grid, done[0], np.zeros(2), np.eye(2), done[1], end)
        if shot is None:
            continue
        q = np.array([shot.Z[0, 3], *shot.g])
        if all(np.max(np.abs(q - np.array([f.Z[0, 3], *f.g])) / (1.0 + np.abs(q))) > 1e-6 for f, _ in found):
            found.append((shot, grid))
    if not found:
        raise NotImplementedError(f"no equilibrium of the sectioned stretch s = {s0:g} .. {s1:g} was reached by "
                                  "continuation from the uniform wire")
    shapes = [assemble(pieces_of(shot, grid, 0.0, length, p0, EI_ref), length, EI_ref, p0, [(length, "clamp")])
              for shot, grid in found]
    return lowest_first(shapes)


def sectioned_wall_shape(
    p0: Array, theta0: float, length: float, n: Array, c: float, profile: StiffnessProfile
) -> ContinuumShape:
    """A clamped sectioned wire whose free end is pushed by the wall ``n · p ≤ c`` (unit ``n``).

    Returns the rest shape when it does not cross the wall.  Otherwise the shape continued from the rest shape as the
    wall moves in from the tip's rest position (module docstring), verified: wall force ``≥ 0``, no point beyond the
    wall.

    Raises
    ------
    NotImplementedError
        When the rest shape crosses the wall elsewhere than at its free end first, when the continuation fails
        (e.g. a straight wire buckling against a wall square to it), or when the continued shape touches the wall
        elsewhere than at its tip (tangential contact is not covered for sectioned wires).
    """
    p0, theta0 = _pose(p0, theta0, "p0")
    length = fields.real(length, "length", positive=True)
    n = np.asarray(fields.point(n, "wall normal"))
    if abs(float(np.linalg.norm(n)) - 1.0) > 1e-12:
        raise ValueError(f"the wall normal must be a unit vector, got |n| = {float(np.linalg.norm(n)):.6g}")
    c = fields.real(c, "wall offset")
    _profile(profile)
    rest = assemble(free_pieces(profile, 0.0, length, p0, theta0), length, profile.bending_stiffness[0], p0, [])
    scale = max(1.0, length)
    if max_wall_violation(rest, n, c) <= 0.0:
        return rest
    depth = c - float(n @ p0)
    if depth <= 0.0:
        raise ValueError(f"p0 = {fields.fmt_point(p0)} lies on or beyond the wall")
    s = np.linspace(0.0, length, 4001)
    heights = rest.position(s) @ n
    tip = float(heights[-1])
    if np.max(heights) > tip + 1e-12 * scale:
        raise NotImplementedError(f"the rest shape reaches the wall first at s = {s[np.argmax(heights)]:g} mm, not at "
                                  "its free end: the sectioned reference covers a wall touching the tip only")
    EI_ref = max(profile.bending_stiffness)
    grid = _grid(profile, 0.0, length, EI_ref, np.zeros(2))
    free = integrate_free(grid, np.array([0.0, 0.0, theta0, 0.0]), np.zeros(2))
    assert free is not None
    G = -n.reshape(2, 1)

    def at(t: float, state: tuple[Array, Array]) -> tuple[Array, Array] | None:
        target = (tip + t * (c - tip) - float(n @ p0)) / length
        dz = np.array([[0.0, 0.0, 0.0, 1.0], [n[0], n[1], 0.0, 0.0]])

        def end(z: Array, _g: Array) -> tuple[Array, Array, Array]:
            return np.array([z[3], n @ z[:2] - target]), dz, np.zeros((2, 2))

        shot = shoot(grid, state[0], np.zeros(2), G, state[1], end)
        return None if shot is None else (shot.Z, -(n @ shot.g) * np.ones(1))

    done = _continue(1.0, at, (free.Z, np.zeros(1)))
    if done is None:
        raise NotImplementedError("continuation of the sectioned wire against the wall failed (a straight wire square "
                                  "to the wall buckles: not covered)")
    shot = shoot(grid, done[0], np.zeros(2), G, done[1], lambda z, g: (
        np.array([z[3], n @ z[:2] - (c - float(n @ p0)) / length]),
        np.array([[0.0, 0.0, 0.0, 1.0], [n[0], n[1], 0.0, 0.0]]), np.zeros((2, 2))))
    if shot is None:
        raise NotImplementedError("the sectioned wall shape did not converge")
    shape = assemble(pieces_of(shot, grid, 0.0, length, p0, EI_ref), length, EI_ref, p0, [(length, "wall")])
    force = -float(n @ shot.g)
    if force < -1e-12 or max_wall_violation(shape, n, c) > 1e-9 * scale:
        raise NotImplementedError("the sectioned wire pushed by the wall would touch it elsewhere than at its tip "
                                  "(tangential contact): not covered for sectioned wires")
    return shape


def sectioned_shapes(
    base_point: Array, base_angle: float, clamps: Sequence[tuple[float, Array, float]], total_length: float,
    profile: StiffnessProfile, walls: Sequence[tuple[Array, float]], max_ties: int = 64,
) -> list[ContinuumShape]:
    """The tied lowest-energy shapes of a sectioned wire (validated input; see
    :func:`~guidewire.reference.whole_wire.reference_shapes`), at most ``max_ties`` of them."""
    EI0 = profile.bending_stiffness[0]
    if not clamps:
        rest = assemble(free_pieces(profile, 0.0, total_length, base_point, base_angle), total_length, EI0,
                        base_point, [])
        active = [i for i, (n, c) in enumerate(walls) if max_wall_violation(rest, n, c) > 0.0]
        if len(active) > 1:
            raise NotImplementedError(f"the rest shape crosses {len(active)} walls ({active}); only one active wall "
                                      "is supported")
        if not active:
            return [rest]
        n, c = walls[active[0]]
        return [sectioned_wall_shape(base_point, base_angle, total_length, n, c, profile)]
    options: list[list[list[ElasticaPiece]]] = []
    s_prev, p_prev, a_prev = 0.0, base_point, base_angle
    for s, point, angle in clamps:
        segment = ties(sectioned_segment_equilibria(p_prev, a_prev, point, angle, s_prev, s, profile))
        options.append([[shifted_piece(piece, s_prev) for piece in sh.pieces] for sh in segment])
        s_prev, p_prev, a_prev = s, point, angle
    tail = []
    if total_length - s_prev > 1e-12 * total_length:
        tail = free_pieces(profile, s_prev, total_length, p_prev, a_prev)
    supports = [(s, "clamp") for s, _, _ in clamps]
    return [assemble([p for seg in combo for p in seg] + tail, total_length, EI0, base_point, supports)
            for combo in itertools.islice(itertools.product(*options), max_ties)]

