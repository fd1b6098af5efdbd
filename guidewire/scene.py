"""Validated scene values: the wire, its base, the contacts and the walls (units mm, rad, MPa = N/mm²).

A scene is what the paper's Tables 1, 2, 4 and 5 and Fig. 6 specify: a wire of inserted length ``L`` split into ``n``
rigid bars (§2.1), a base at arc length ``s = 0`` (the vessel entrance, point ``A``/``O``), zero or more contacts at
arc lengths ``s`` with a known position and/or tangent angle (§2.3.2), and zero or more straight walls (Eqs. 23–24).
Every value is checked when it is built; a bad field raises ``ValueError``/``TypeError`` naming the field and the fix.
Whether the contacts can be reached at all (:func:`guidewire.feasibility.check_feasible`) is a separate check, run
before solving, so that an infeasible scene such as the printed Table 5 can still be held, drawn and reported.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .chain import piece_count
from .fields import fmt as _fmt
from .fields import point as _point
from .fields import real as _real
from .fields import warn_angle, warn_modulus
from .vessel import Vessel

SCHEMES = ("second_order", "paper")
"""Discretisations of the bending energy; see :mod:`guidewire.formulation`."""

S_ROUNDING = 1e-12
"""A contact within this fraction of the wire length of its end is at the end (rounding in ``k·(L/n)``)."""

@dataclass(frozen=True)
class Section:
    """A stretch of the wire with its own material, cross-section and rest shape, measured from the tip.

    Sections are listed from the tip (:attr:`Wire.sections`): the first covers the last ``length`` mm of wire, the
    next the ``length`` mm before it, and so on; the wire's own values hold from the last section to the base (and
    fill every field a section leaves None). Measured from the tip, a section moves with the material as the wire is
    inserted (:meth:`Wire.with_length`).

    Parameters
    ----------
    length : float
        Length along the wire in mm (> 0).
    youngs_modulus : float or None
        ``E`` in MPa; None takes the wire's.
    diameter : float or None
        ``d`` in mm; None takes the wire's.
    moment_of_inertia : float or None
        ``I`` in mm⁴; None gives ``π d⁴ / 64`` of the section's diameter when the section sets one, else the wire's
        ``I``.
    rest_curvature : float
        Curvature of the unloaded section in 1/mm, signed like the tangent angle's change from base to tip
        (positive turns counter-clockwise towards the tip). A J-tip of radius ``R`` over an angle ``α`` is a tip
        section of length ``R·α`` and rest curvature ``±1/R``; the sign picks which of the two mirror images.
    """

    length: float
    youngs_modulus: float | None = None
    diameter: float | None = None
    moment_of_inertia: float | None = None
    rest_curvature: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "length", _real(self.length, "section.length", positive=True))
        for name in ("youngs_modulus", "diameter", "moment_of_inertia"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _real(getattr(self, name), f"section.{name}", positive=True))
        if self.youngs_modulus is not None:
            warn_modulus(self.youngs_modulus, "section.youngs_modulus")
        object.__setattr__(self, "rest_curvature", _real(self.rest_curvature, "section.rest_curvature"))

    @classmethod
    def arc(cls, radius: float, angle: float, **properties: Any) -> Section:
        """A section bent at rest into a circular arc of ``radius`` (mm) over ``angle`` (rad; its sign is the turn's
        sense from base to tip, e.g. ``Section.arc(12.1, 0.4 * math.pi)`` turns counter-clockwise)."""
        radius = _real(radius, "section radius", positive=True)
        angle = _real(angle, "section angle")
        if angle == 0.0:
            raise ValueError("section angle is 0; give the arc's turning angle in rad (its sign is the J's side).")
        return cls(length=radius * abs(angle), rest_curvature=math.copysign(1.0, angle) / radius, **properties)


@dataclass(frozen=True)
class WireProperties:
    """Per-bar material values of a wire (arrays over bars, base first).

    Attributes
    ----------
    youngs_modulus, diameter, second_moment, rest_curvature : ndarray, shape (n,)
        ``E`` (MPa), ``d`` (mm), ``I`` (mm⁴) and ``κ⁰`` (1/mm) of every bar.
    """

    youngs_modulus: NDArray[np.float64]
    diameter: NDArray[np.float64]
    second_moment: NDArray[np.float64]
    rest_curvature: NDArray[np.float64]

    @property
    def bending_stiffness(self) -> NDArray[np.float64]:
        """``EI`` in N·mm² per bar."""
        return self.youngs_modulus * self.second_moment


@dataclass(frozen=True)
class Wire:
    """The guidewire: material, cross-section and discretisation.

    Parameters
    ----------
    length : float
        Inserted length ``L`` in mm (> 0).
    bars : int
        Number ``n`` of rigid bars (≥ 1).
    youngs_modulus : float
        ``E`` in MPa (N/mm²); default the paper's 3.56 GPa. Below 100 MPa a
        :class:`~guidewire.fields.SuspiciousValueWarning` says it is probably in GPa.
    diameter : float
        ``d`` in mm; default the paper's 0.78 mm. Used for the bending stress ``σ = E·(d/2)·|κ|`` and, when
        ``moment_of_inertia`` is None, for ``I = π d⁴ / 64``.
    moment_of_inertia : float or None
        Second moment of area ``I`` in mm⁴; the paper's measured 1.816e-14 m⁴ is 0.01816 mm⁴.
    max_relative_angle : float or None
        The paper's ``b₂`` (Eq. 19): ``|Δθ| ≤ b₂`` at every joint, in rad. None (default) adds no such rows. With a
        rest curvature it bounds the bend away from the rest shape, ``|Δθ − Δθ⁰| ≤ b₂``.
    scheme : {"second_order", "paper"}
        Discretisation of the bending energy (see :mod:`guidewire.formulation`).
    sections : sequence of Section
        Stretches with their own properties, listed from the tip (see :class:`Section`); empty (default) is the
        uniform wire. Sections longer in total than ``length`` are allowed: only the inserted part counts.
    """

    length: float
    bars: int
    youngs_modulus: float = 3560.0
    diameter: float = 0.78
    moment_of_inertia: float | None = None
    max_relative_angle: float | None = None
    scheme: str = "second_order"
    sections: tuple[Section, ...] = ()

    def __post_init__(self) -> None:
        length = _real(self.length, "wire.length")
        if length <= 0.0:
            raise ValueError(f"wire.length is {length}; the inserted length must be positive (mm).")
        if isinstance(self.bars, bool) or not isinstance(self.bars, int | float) or self.bars != int(self.bars):
            raise TypeError(f"wire.bars is {self.bars!r}; expected a whole number of bars.")
        if int(self.bars) < 1:
            raise ValueError(f"wire.bars is {self.bars}; use at least 1 bar (the paper uses 100).")
        for name in ("youngs_modulus", "diameter"):
            value = _real(getattr(self, name), f"wire.{name}")
            if value <= 0.0:
                raise ValueError(f"wire.{name} is {value}; it must be positive.")
            object.__setattr__(self, name, value)
        warn_modulus(self.youngs_modulus, "wire.youngs_modulus")
        if self.moment_of_inertia is not None:
            inertia = _real(self.moment_of_inertia, "wire.moment_of_inertia")
            if inertia <= 0.0:
                raise ValueError(f"wire.moment_of_inertia is {inertia}; give a positive I in mm⁴ or omit it.")
            object.__setattr__(self, "moment_of_inertia", inertia)
        if self.max_relative_angle is not None:
            b2 = _real(self.max_relative_angle, "wire.max_relative_angle")
            if b2 <= 0.0:
                raise ValueError(f"wire.max_relative_angle is {b2}; give a positive bound in rad or omit it.")
            object.__setattr__(self, "max_relative_angle", b2)
        if self.scheme not in SCHEMES:
            raise ValueError(f"wire.scheme is {self.scheme!r}; expected one of {', '.join(map(repr, SCHEMES))}.")
        object.__setattr__(self, "length", length)
        object.__setattr__(self, "bars", int(self.bars))
        if isinstance(self.sections, Section) or not isinstance(self.sections, Sequence):
            raise TypeError(f"wire.sections is {self.sections!r}; expected a sequence of guidewire.Section.")
        for i, section in enumerate(self.sections):
            if not isinstance(section, Section):
                raise TypeError(f"wire.sections[{i}] is {type(section).__name__}; expected guidewire.Section.")
        object.__setattr__(self, "sections", tuple(self.sections))

    def with_length(self, length: float) -> Wire:
        """The same wire inserted to ``length`` mm: the sections stay anchored at the tip (they move with the
        material), so a longer wire has more of the base-side material."""
        return replace(self, length=length)

    def section_boundaries(self) -> tuple[float, ...]:
        """Arc lengths from the base (mm, increasing, inside ``(0, L)``) where one section meets the next."""
        ends = self.length - np.cumsum([sec.length for sec in self.sections])
        return tuple(float(s) for s in sorted(ends) if S_ROUNDING * self.length < s < self.length * (1 - S_ROUNDING))

    def properties_at(self, s: Any) -> WireProperties:
        """Material values at arc lengths ``s`` (mm from the base; vectorised, shape of ``s`` ravelled).

        A point exactly on a section boundary takes the tip-side section's values; callers evaluate bar midpoints.
        """
        s = np.atleast_1d(np.asarray(s, dtype=float)).ravel()
        own = (self.youngs_modulus, self.diameter, self.second_moment, 0.0)
        table = [own]
        for sec in self.sections:
            diameter = self.diameter if sec.diameter is None else sec.diameter
            if sec.moment_of_inertia is not None:
                inertia = sec.moment_of_inertia
            elif sec.diameter is not None:
                inertia = math.pi * sec.diameter**4 / 64.0
            else:
                inertia = self.second_moment
            modulus = self.youngs_modulus if sec.youngs_modulus is None else sec.youngs_modulus
            table.append((modulus, diameter, inertia, sec.rest_curvature))
        values = np.array(table)  # row 0 the wire's own, row i section i (from the tip)
        tip_distance = np.cumsum([0.0, *(sec.length for sec in self.sections)])  # section i: [start, end) from tip
        from_tip = self.length - s
        index = np.searchsorted(tip_distance, from_tip, side="left")  # 1..m inside a section, m+1 past them
        index = np.where(index > len(self.sections), 0, np.maximum(index, 1) if self.sections else 0)
        picked = values[index]
        return WireProperties(picked[:, 0], picked[:, 1], picked[:, 2], picked[:, 3])

    @property
    def second_moment(self) -> float:
        """``I`` in mm⁴: ``moment_of_inertia`` if given, else ``π d⁴ / 64``."""
        if self.moment_of_inertia is not None:
            return self.moment_of_inertia
        return math.pi * self.diameter**4 / 64.0

    @property
    def bending_stiffness(self) -> float:
        """``EI`` in N·mm²."""
        return self.youngs_modulus * self.second_moment


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
        contacts = list(self.contacts)
        walls = tuple(self.walls)
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
