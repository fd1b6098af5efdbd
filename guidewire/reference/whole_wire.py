"""The continuum reference of a whole wire: base clamp, fully clamped contacts, a straight free tail, walls.

:func:`reference_shape` solves each segment between consecutive clamps (they decouple), or the one-wall free-end
case; :func:`reference_shapes` lists every tied minimiser of a symmetric scene (mirror twins).
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .. import fields
from .clamped_segment import clamped_segment_equilibria, segment_feasibility
from .pieces import assemble, shifted_piece, straight_piece, straight_shape, ties
from .sectioned import StiffnessProfile, sectioned_shapes
from .shapes import Array, ContinuumShape, ElasticaPiece
from .wall import max_wall_violation, unit_wall, wall_shapes

__all__ = ["MAX_TIES", "reference_shape", "reference_shapes"]

#: At most this many tied whole-wire minimisers are assembled by :func:`reference_shapes`.
MAX_TIES = 64


def _field(item: Any, index: int, name: str) -> Any:
    """Read ``name`` from a tuple ``(s, point, angle)``, a mapping or an object with attributes."""
    if isinstance(item, dict):
        return item.get(name)
    if hasattr(item, name):
        return getattr(item, name)
    if isinstance(item, Sequence) and not isinstance(item, str):
        order = {"s": 0, "point": 1, "angle": 2, "normal": 0, "offset": 1}
        return item[order[name]] if order[name] < len(item) else None
    raise ValueError(f"{index}: expected a tuple, a mapping or an object with .{name}, got {item!r}")


def _contacts(contacts: Iterable[Any], total_length: float) -> list[tuple[float, Array, float]]:
    """Validated ``(s, point, angle)`` of fully clamped contacts, in strictly increasing ``s ≤ total_length``."""
    out: list[tuple[float, Array, float]] = []
    for i, item in enumerate(contacts):
        label = f"contacts[{i}]"
        s = fields.real(_field(item, i, "s"), f"{label}.s")
        point, angle = _field(item, i, "point"), _field(item, i, "angle")
        if point is None or angle is None:
            missing = " and ".join(k for k, v in (("point", point), ("angle", angle)) if v is None)
            raise NotImplementedError(
                f"{label} at s = {s:g} has no {missing}: the continuum reference only handles fully clamped "
                "contacts (position and angle given)"
            )
        point = np.asarray(fields.point(point, f"{label}.point"))
        angle = fields.real(angle, f"{label}.angle")
        previous = out[-1][0] if out else 0.0
        if s <= previous:
            raise ValueError(f"{label}.s = {s:g} must exceed the previous arc length {previous:g}")
        if s > total_length * (1.0 + 1e-12):
            raise ValueError(f"{label}.s = {s:g} exceeds total_length = {total_length:g}")
        out.append((min(s, total_length), point, angle))
    return out


def _check_segments(base_point: Array, base_angle: float, clamps: list[tuple[float, Array, float]]) -> None:
    """Every segment between consecutive clamps is checked before any is solved (ValueError naming it)."""
    s_prev, p_prev, a_prev = 0.0, base_point, base_angle
    for i, (s, point, angle) in enumerate(clamps):
        try:
            segment_feasibility(p_prev, a_prev, point, angle, s - s_prev)
        except ValueError as exc:
            raise ValueError(f"segment s = {s_prev:g} .. {s:g} (to contacts[{i}]): {exc}") from exc
        s_prev, p_prev, a_prev = s, point, angle


def reference_shape(
    base_point: ArrayLike,
    base_angle: float | None,
    contacts: Iterable[Any],
    total_length: float,
    EI: float | StiffnessProfile,
    walls: Iterable[Any] = (),
) -> ContinuumShape:
    """Continuum reference of a whole scene: base clamp, fully clamped contacts, free tail, walls.

    Parameters
    ----------
    base_point : array_like, shape (2,)
        Clamp at ``s = 0`` (mm).
    base_angle : float
        Clamp angle (rad).  ``None`` (free rotation) is not supported.
    contacts : iterable
        Contacts ``(s, point, angle)`` in increasing ``s`` (tuples, mappings or objects with attributes ``s``,
        ``point``, ``angle``), each fully clamped.  Consecutive clamps decouple; each segment is the
        lowest-energy :func:`clamped_segment`.  Beyond the last contact the wire is a straight free tail.
    total_length : float
        Inserted length ``L`` (mm).
    EI : float or StiffnessProfile
        Bending stiffness (N·mm²), or the sections of the wire (piecewise-constant ``EI`` and rest curvature,
        :mod:`~guidewire.reference.sectioned`: the same cases, a wall only where it touches the free end).
    walls : iterable, optional
        Walls ``(normal, offset)`` (tuples, mappings or objects), allowed side ``normal · p ≤ offset``.

    Returns
    -------
    ContinuumShape
        The whole wire from ``s = 0`` to ``total_length``, with the reactions of the base and every support.
        When the minimiser is not unique (mirror twins, see :func:`reference_shapes`) the first one.

    Raises
    ------
    TypeError
        A value of the wrong type (a string or a bool for a number, a non-sequence for a point), as
        :mod:`guidewire.fields` reports it.
    ValueError
        For malformed input, contacts out of order or beyond ``total_length``, or an infeasible segment
        (two contacts farther apart than the wire between them; the message says by how much).  Every
        segment is checked before any is solved.
    NotImplementedError
        For a contact without position or angle, a free base angle, or walls that are active together with
        contacts or with each other (walls that the wall-free solution respects are accepted).

    Notes
    -----
    Supported cases: no contacts and no wall (straight wire); no contacts and one active wall
    (:func:`clamp_wall_free_end`); fully clamped contacts with inactive walls.  With a
    :class:`~guidewire.reference.sectioned.StiffnessProfile` the same cases (the free wire rests in its rest
    shape), a wall only where it touches the free end alone.
    """
    return reference_shapes(base_point, base_angle, contacts, total_length, EI, walls)[0]


def reference_shapes(
    base_point: ArrayLike,
    base_angle: float | None,
    contacts: Iterable[Any],
    total_length: float,
    EI: float | StiffnessProfile,
    walls: Iterable[Any] = (),
) -> list[ContinuumShape]:
    """Every lowest-energy continuum shape of a scene (ties within ``TIE_RTOL``), the default one first.

    Symmetric scenes have several minimisers of equal energy: a segment with equal end angles (Table 1 with
    ``θ_B = 0``, both segments of Table 2 with ``θ_C = 0``) has mirror twins, and Fig. 6b can turn either
    way.  A discrete solution should be compared with the nearest of them.  Parameters, errors and
    supported cases as :func:`reference_shape`; at most ``MAX_TIES`` combinations are assembled.

    Returns
    -------
    list of ContinuumShape
        One shape per combination of tied segment minimisers; a single element when the minimiser is unique.
    """
    base_point = np.asarray(fields.point(base_point, "base_point"))
    if base_angle is None:
        raise NotImplementedError(
            "base_angle = None (a freely rotating base) is not supported by the reference"
        )
    base_angle = fields.real(base_angle, "base_angle")
    total_length = fields.real(total_length, "total_length", positive=True)
    profile = EI if isinstance(EI, StiffnessProfile) else None
    EI = profile.bending_stiffness[0] if profile is not None else fields.real(EI, "EI", positive=True)
    clamps = _contacts(contacts, total_length)
    wall_list = [
        unit_wall(_field(w, i, "normal"), _field(w, i, "offset"), f"walls[{i}]") for i, w in enumerate(walls)
    ]
    for i, (n, c) in enumerate(wall_list):
        if float(n @ base_point) > c + 1e-12 * max(1.0, abs(c)):
            raise ValueError(f"base_point lies beyond walls[{i}] by {float(n @ base_point) - c:.6g} mm")
    _check_segments(base_point, base_angle, clamps)

    if profile is not None:
        shapes = sectioned_shapes(base_point, base_angle, clamps, total_length, profile, wall_list, MAX_TIES)
    elif not clamps:
        shapes = _free_shapes(base_point, base_angle, total_length, EI, wall_list)
    else:
        shapes = _clamped_shapes(base_point, base_angle, clamps, total_length, EI)
    _check_walls(shapes, wall_list, 1e-9 * max(1.0, total_length))
    return shapes


def _free_shapes(base_point: Array, base_angle: float, total_length: float, EI: float,
                 wall_list: list[Any]) -> list[ContinuumShape]:
    """No contacts: the straight wire, or the shapes against the one wall it would cross."""
    straight = straight_shape(base_point, base_angle, total_length, EI)
    active = [i for i, (n, c) in enumerate(wall_list) if max_wall_violation(straight, n, c, 3) > 0.0]
    if len(active) > 1:
        raise NotImplementedError(
            f"the straight wire crosses {len(active)} walls ({active}); only one active wall is supported"
        )
    if not active:
        return [straight]
    n, c = wall_list[active[0]]
    return ties(wall_shapes(base_point, base_angle, total_length, n, c, EI))


def _clamped_shapes(base_point: Array, base_angle: float, clamps: list[Any], total_length: float,
                    EI: float) -> list[ContinuumShape]:
    """Fully clamped contacts: every combination (at most ``MAX_TIES``) of each segment's tied minimisers, and a
    straight free end."""
    options: list[list[list[ElasticaPiece]]] = []  # per segment: the pieces of each tied minimiser
    s_prev, p_prev, a_prev = 0.0, base_point, base_angle
    for s, point, angle in clamps:
        segment = ties(clamped_segment_equilibria(p_prev, a_prev, point, angle, s - s_prev, EI))
        options.append([[shifted_piece(piece, s_prev) for piece in sh.pieces] for sh in segment])
        s_prev, p_prev, a_prev = s, point, angle
    tail = []
    if total_length - s_prev > 1e-12 * total_length:
        tail = [straight_piece(s_prev, total_length - s_prev, p_prev, a_prev)]
    supports = [(s, "clamp") for s, _, _ in clamps]
    return [
        assemble([p for seg in combo for p in seg] + tail, total_length, EI, base_point, supports)
        for combo in itertools.islice(itertools.product(*options), MAX_TIES)
    ]


def _check_walls(shapes: list[ContinuumShape], wall_list: list[Any], tol: float) -> None:
    """Refuse shapes that cross a wall by more than ``tol`` (walls combined with contacts are not supported)."""
    for shape in shapes:
        for i, (n, c) in enumerate(wall_list):
            excess = max_wall_violation(shape, n, c)
            if excess > tol:
                raise NotImplementedError(
                    f"walls[{i}] is crossed by {excess:.4g} mm by the wall-free solution: active walls "
                    "combined with contacts (or with other walls) are not supported by the reference"
                )
