"""Validated scene values: the wire, its base, the contacts and the walls (units mm, rad, MPa = N/mm²).

A scene is what the paper's Tables 1, 2, 4 and 5 and Fig. 6 specify: a wire of inserted length ``L`` split into ``n``
rigid bars (§2.1), a base at arc length ``s = 0`` (the vessel entrance, point ``A``/``O``), zero or more contacts at
arc lengths ``s`` with a known position and/or tangent angle (§2.3.2), and zero or more straight walls (Eqs. 23–24).
Every value is checked when it is built; a bad field raises ``ValueError``/``TypeError`` naming the field and the fix.
Whether the contacts can be reached at all (:func:`~guidewire.program.feasibility.check_feasible`) is a
separate check, run before solving, so that an infeasible scene such as the printed Table 5 can still be held, drawn
and reported.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from ..fields import fmt as _fmt
from ..fields import point as _point
from ..fields import real as _real
from ..fields import warn_angle
from ..vessel.vessel import Vessel
from ..wire import S_ROUNDING, SCHEMES, Section, Wire, WireProperties, piece_count  # noqa: F401  (part of this module's API)


@dataclass(frozen=True)
class Base:
    """The wire's start at ``s = 0`` (vessel entrance): a fixed point and, if clamped, a fixed tangent angle.

    Parameters
    ----------
    point : (float, float)
        Position in mm.
    angle : float or None
        Tangent angle in rad (counter-clockwise from +x); None leaves the wire free to rotate about ``point``. Above
        2π in magnitude a :class:`~guidewire.fields.SuspiciousValueWarning` says it is probably in degrees.
    name : str
        Label used in messages and figures (the paper's ``A`` or ``O``).
    """

    point: tuple[float, float]
    angle: float | None = None
    name: str = "base"

    def __post_init__(self) -> None:
        object.__setattr__(self, "point", _point(self.point, "base.point"))
        if self.angle is not None:
            object.__setattr__(self, "angle", _real(self.angle, "base.angle"))
            warn_angle(self.angle, "base.angle")


@dataclass(frozen=True)
class Contact:
    """A point of the wire at arc length ``s`` with a known position and/or tangent angle (§2.3.2).

    Parameters
    ----------
    s : float
        Arc length from the base in mm, ``0 < s ≤ L``.
    point : (float, float) or None
        Position in mm (Eqs. 20–21); None leaves it free.
    angle : float or None
        Tangent angle in rad (Eqs. 16–18); None leaves it free. Taken literally (``θ + 2π`` asks for a loop);
        above 2π in magnitude a :class:`~guidewire.fields.SuspiciousValueWarning` says it is probably in degrees.
    name : str
        Label used in messages and figures (the paper's ``B``, ``C``, ``P1``...).
    """

    s: float
    point: tuple[float, float] | None = None
    angle: float | None = None
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "s", _real(self.s, "contact.s"))
        if self.point is not None:
            object.__setattr__(self, "point", _point(self.point, "contact.point"))
        if self.angle is not None:
            object.__setattr__(self, "angle", _real(self.angle, "contact.angle"))
            warn_angle(self.angle, "contact.angle")
        if self.point is None and self.angle is None:
            raise ValueError(f"contact at s = {_fmt(self.s)} has neither point nor angle; give at least one.")

    def label(self, index: int) -> str:
        """The name, or ``contact <index>`` (1-based) when unnamed."""
        return self.name or f"contact {index + 1}"


@dataclass(frozen=True)
class Wall:
    """A straight wall: every node ``p`` of the wire must satisfy ``normal · p ≤ offset`` (Eqs. 23–24).

    Parameters
    ----------
    normal : (float, float)
        Outward normal (pointing out of the allowed region); need not be a unit vector.
    offset : float
        Right-hand side in the units of ``normal`` × mm.
    """

    normal: tuple[float, float]
    offset: float

    def __post_init__(self) -> None:
        normal = _point(self.normal, "wall.normal")
        if math.hypot(*normal) == 0.0:
            raise ValueError("wall.normal is [0, 0]; give a nonzero outward normal, e.g. [1, 0] for x ≤ offset.")
        object.__setattr__(self, "normal", normal)
        object.__setattr__(self, "offset", _real(self.offset, "wall.offset"))

    def unit(self) -> tuple[tuple[float, float], float]:
        """The same half-plane with a unit normal: ``(n̂, offset / |normal|)``."""
        norm = math.hypot(*self.normal)
        return (self.normal[0] / norm, self.normal[1] / norm), self.offset / norm

    def signed_distance(self, point: Sequence[float]) -> float:
        """``n̂ · p − offset`` in mm: negative inside the allowed region, positive when violated."""
        (nx, ny), off = self.unit()
        return nx * point[0] + ny * point[1] - off


@dataclass(frozen=True)
class Scene:
    """A wire, its base, its contacts (increasing ``s``) and walls.

    Parameters
    ----------
    wire : Wire
    base : Base
    contacts : sequence of Contact
        Strictly increasing arc lengths in ``(0, L]``; wire beyond the last contact is a free end.
    walls : sequence of Wall
    name : str
    notes : str
        Free text (not compared).
    vessel : Vessel or None
        A lumen every node must stay inside (see :mod:`guidewire.vessel`); :meth:`in_vessel` puts the base at its
        entrance.
    """

    wire: Wire
    base: Base
    contacts: tuple[Contact, ...] = ()
    walls: tuple[Wall, ...] = ()
    name: str = ""
    notes: str = field(default="", compare=False)
    vessel: Vessel | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.wire, Wire):
            raise TypeError(f"scene.wire is {type(self.wire).__name__}; expected guidewire.Wire.")
        if not isinstance(self.base, Base):
            raise TypeError(f"scene.base is {type(self.base).__name__}; expected guidewire.Base.")
        contacts = self._checked_contacts()
        walls = tuple(self.walls)
        for i, wall in enumerate(walls):
            if not isinstance(wall, Wall):
                raise TypeError(f"scene.walls[{i}] is {type(wall).__name__}; expected guidewire.Wall.")
        if self.vessel is not None and not isinstance(self.vessel, Vessel):
            raise TypeError(f"scene.vessel is {type(self.vessel).__name__}; expected guidewire.Vessel or None.")
        object.__setattr__(self, "contacts", tuple(contacts))
        if self.wire.bars < len(self.segment_ends()):
            raise ValueError(
                f"wire.bars is {self.wire.bars} but the contacts split the wire into {len(self.segment_ends())} "
                "segments; use at least one bar per segment."
            )
        pieces = piece_count(self.wire.length, [c.s for c in contacts], self.wire.section_boundaries())
        if self.wire.bars < pieces:
            raise ValueError(
                f"wire.bars is {self.wire.bars} but the contacts and section boundaries split the wire into {pieces} "
                "pieces; use at least one bar per piece."
            )
        object.__setattr__(self, "walls", walls)

    def _checked_contacts(self) -> list[Contact]:
        """The contacts, checked: each a :class:`Contact` with ``0 < s ≤ L`` (an ``s`` within rounding of ``L`` set
        to ``L``), in strictly increasing ``s``."""
        contacts = list(self.contacts)
        for i, contact in enumerate(contacts):
            if not isinstance(contact, Contact):
                raise TypeError(f"scene.contacts[{i}] is {type(contact).__name__}; expected guidewire.Contact.")
            if contact.s != self.wire.length and abs(contact.s - self.wire.length) <= S_ROUNDING * self.wire.length:
                # at the end up to rounding (e.g. s = k·(L/n) with k = n): at the end, not a zero-length last bar
                contact = contacts[i] = replace(contact, s=self.wire.length)
            if not 0.0 < contact.s <= self.wire.length:
                raise ValueError(
                    f"{contact.label(i)} has s = {_fmt(contact.s)}; contacts need 0 < s ≤ wire.length = "
                    f"{_fmt(self.wire.length)} (the base is s = 0; lengthen the wire or move the contact)."
                )
            if i and contact.s == contacts[i - 1].s:
                raise ValueError(
                    f"{contacts[i - 1].label(i - 1)} and {contact.label(i)} are both at s = {_fmt(contact.s)}; give "
                    "each arc length one contact (merge them: one contact may carry both a point and an angle)."
                )
            if i and contact.s < contacts[i - 1].s:
                raise ValueError(
                    f"{contact.label(i)} has s = {_fmt(contact.s)} after {contacts[i - 1].label(i - 1)} at "
                    f"s = {_fmt(contacts[i - 1].s)}; list contacts by strictly increasing s."
                )
        return contacts

    @classmethod
    def in_vessel(
        cls,
        wire: Wire,
        vessel: Vessel,
        *,
        base: Base | None = None,
        contacts: Sequence[Contact] = (),
        walls: Sequence[Wall] = (),
        name: str = "",
        notes: str = "",
    ) -> Scene:
        """A wire inserted into ``vessel``: the base is the vessel's entrance (its point and the centreline's
        tangent there, pointing in; named ``"entrance"``) unless ``base`` is given; ``wire.length`` is the inserted
        length (mm)."""
        if not isinstance(vessel, Vessel):
            raise TypeError(f"scene.vessel is {type(vessel).__name__}; expected guidewire.Vessel.")
        if base is None:
            base = Base(vessel.entrance_point, vessel.entrance_angle, name="entrance")
        return cls(wire, base, tuple(contacts), tuple(walls), name=name, notes=notes, vessel=vessel)

    # ----------------------------------------------------------------------------------------------------------
    def segment_ends(self) -> tuple[float, ...]:
        """Arc lengths where segments end: every contact's ``s`` and ``L`` (once), increasing."""
        ends = [c.s for c in self.contacts]
        if not ends or ends[-1] < self.wire.length:
            ends.append(self.wire.length)
        return tuple(ends)

    # ----------------------------------------------------------------------------------------------------------
    def with_bars(self, bars: int) -> Scene:
        """The same scene with ``bars`` rigid bars."""
        return replace(self, wire=replace(self.wire, bars=bars))

    def with_scheme(self, scheme: str) -> Scene:
        """The same scene with another energy discretisation (``"second_order"`` or ``"paper"``)."""
        return replace(self, wire=replace(self.wire, scheme=scheme))

    def with_wire(self, **changes: Any) -> Scene:
        """The same scene with fields of the wire replaced, e.g. ``with_wire(max_relative_angle=0.1)``."""
        return replace(self, wire=replace(self.wire, **changes))

    def mirrored(self) -> Scene:
        """The scene reflected in the x-axis: ``y → −y``, angles ``θ → −θ``, wall normals ``(a, b) → (a, −b)``, the
        vessel's points reflected, rest curvatures negated (a J-tip becomes its mirror image)."""

        def flip(p: tuple[float, float] | None) -> tuple[float, float] | None:
            return None if p is None else (p[0], -p[1])

        def negate(a: float | None) -> float | None:
            return None if a is None else -a

        base = replace(self.base, point=flip(self.base.point), angle=negate(self.base.angle))
        contacts = tuple(replace(c, point=flip(c.point), angle=negate(c.angle)) for c in self.contacts)
        walls = tuple(Wall((w.normal[0], -w.normal[1]), w.offset) for w in self.walls)
        name = f"{self.name} (mirrored)" if self.name else ""
        vessel = None if self.vessel is None else self.vessel.mirrored()
        wire = self.wire
        if any(sec.rest_curvature for sec in wire.sections):  # the other J
            wire = replace(wire, sections=tuple(replace(sec, rest_curvature=-sec.rest_curvature)
                                                for sec in wire.sections))
        return replace(self, wire=wire, base=base, contacts=contacts, walls=walls, name=name, vessel=vessel)

    def rotated(self, angle: float, center: tuple[float, float] = (0.0, 0.0)) -> Scene:
        """The scene turned counter-clockwise by ``angle`` (rad) about ``center``: points rotate, tangent angles
        gain ``angle``, wall normals rotate and wall offsets follow the moved boundary, the vessel turns with them."""
        angle = _real(angle, "angle")
        cx, cy = _point(center, "center")
        c, s = math.cos(angle), math.sin(angle)

        def turn(p: tuple[float, float] | None) -> tuple[float, float] | None:
            if p is None:
                return None
            dx, dy = p[0] - cx, p[1] - cy
            return (cx + c * dx - s * dy, cy + s * dx + c * dy)

        def add(a: float | None) -> float | None:
            return None if a is None else a + angle

        base = replace(self.base, point=turn(self.base.point), angle=add(self.base.angle))
        contacts = tuple(replace(k, point=turn(k.point), angle=add(k.angle)) for k in self.contacts)
        walls = []
        for w in self.walls:  # a·p ≤ b  →  (R a)·p' ≤ b + (R a)·center − a·center
            a = (c * w.normal[0] - s * w.normal[1], s * w.normal[0] + c * w.normal[1])
            shift = a[0] * cx + a[1] * cy - (w.normal[0] * cx + w.normal[1] * cy)
            walls.append(Wall(a, w.offset + shift))
        name = f"{self.name} (rotated)" if self.name else ""
        vessel = None if self.vessel is None else self.vessel.rotated(angle, (cx, cy))
        return replace(self, base=base, contacts=contacts, walls=tuple(walls), name=name, vessel=vessel)
