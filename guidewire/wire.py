"""The wire: material, cross-section and discretisation, and its sections from the tip (units mm, MPa, rad)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .fields import real as _real
from .fields import warn_diameter, warn_modulus

SCHEMES = ("second_order", "paper")
"""Discretisations of the bending energy; see :mod:`guidewire.program.formulation`."""

DENSITIES = ("uniform", "curvature")
"""Bar layouts :func:`guidewire.solve` can choose (:mod:`~.chain.density`): equal bars within every piece, or bars
graded by the curvature of a coarse solve (the paper's closing "discrete density by curvature")."""

LAYOUT_ROUNDING = 1e-9
"""Explicit ``bar_lengths`` may miss ``L`` by this fraction (and put a node this close to a contact)."""

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
    refinement : float
        Bars per mm here relative to the wire's own stretch (> 0; default 1): the uniform layout shares the wire's
        ``bars`` out in proportion to length times refinement (:func:`guidewire.chain.place_bars`), so a J tip with
        ``refinement = 3`` has bars a third as long as the shaft's — as SOFA BeamAdapter's beam density per section
        and stEVE's J wire (22 beams on its 15.2 mm tip, 218 on the 434.8 mm shaft: ``refinement ≈ 2.9``). An
        insertion keeps the bars per refined mm (:attr:`Wire.bar_density`), so the tip keeps its bars as more shaft
        goes in. Explicit ``bar_lengths`` and the curvature-graded layout choose their own bars.
    """

    length: float
    youngs_modulus: float | None = None
    diameter: float | None = None
    moment_of_inertia: float | None = None
    rest_curvature: float = 0.0
    refinement: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "length", _real(self.length, "section.length", positive=True))
        for name in ("youngs_modulus", "diameter", "moment_of_inertia"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _real(getattr(self, name), f"section.{name}", positive=True))
        if self.youngs_modulus is not None:
            warn_modulus(self.youngs_modulus, "section.youngs_modulus")
        if self.diameter is not None:
            warn_diameter(self.diameter, "section.diameter")
        object.__setattr__(self, "rest_curvature", _real(self.rest_curvature, "section.rest_curvature"))
        object.__setattr__(self, "refinement", _real(self.refinement, "section.refinement", positive=True))

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
        Discretisation of the bending energy (see :mod:`guidewire.program.formulation`).
    sections : sequence of Section
        Stretches with their own properties, listed from the tip (see :class:`Section`); empty (default) is the
        uniform wire. Sections longer in total than ``length`` are allowed: only the inserted part counts.
    density : {"uniform", "curvature"} or None
        How :func:`guidewire.solve` lays out the bars when ``bar_lengths`` is None: ``"uniform"`` (equal bars
        within every piece the contacts and sections cut, :func:`guidewire.chain.place_bars`), ``"curvature"``
        (graded by a coarse solve's curvature, :mod:`guidewire.chain.density`), or None (default): uniform for a given
        bar count, curvature-graded when solving to a tolerance (``tol_mm``).
    bar_lengths : sequence of float or None
        Explicit bar lengths (mm, base first): ``bars`` positive values summing to ``length``, with a node at every
        contact and section boundary (checked when solved). None (default): laid out by ``density``. A solve's
        ``Solution.to_dict()["bar_lengths"]`` can be given back here.
    """

    length: float
    bars: int
    youngs_modulus: float = 3560.0
    diameter: float = 0.78
    moment_of_inertia: float | None = None
    max_relative_angle: float | None = None
    scheme: str = "second_order"
    sections: tuple[Section, ...] = ()
    density: str | None = None
    bar_lengths: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        length = _real(self.length, "wire.length")
        if length <= 0.0:
            raise ValueError(f"wire.length is {length}; the inserted length must be positive (mm).")
        if isinstance(self.bars, bool) or not isinstance(self.bars, int | float) or self.bars != int(self.bars):
            raise TypeError(f"wire.bars is {self.bars!r}; expected a whole number of bars.")
        if int(self.bars) < 1:
            raise ValueError(f"wire.bars is {self.bars}; use at least 1 bar (the paper uses 100).")
        self._check_material()
        if self.scheme not in SCHEMES:
            raise ValueError(f"wire.scheme is {self.scheme!r}; expected one of {', '.join(map(repr, SCHEMES))}.")
        object.__setattr__(self, "length", length)
        object.__setattr__(self, "bars", int(self.bars))
        self._check_layout(length)

    def _check_material(self) -> None:
        """Check (and store as floats) the modulus, diameter, optional ``I`` and optional b₂."""
        for name in ("youngs_modulus", "diameter"):
            value = _real(getattr(self, name), f"wire.{name}")
            if value <= 0.0:
                raise ValueError(f"wire.{name} is {value}; it must be positive.")
            object.__setattr__(self, name, value)
        warn_modulus(self.youngs_modulus, "wire.youngs_modulus")
        warn_diameter(self.diameter, "wire.diameter")
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

    def _check_layout(self, length: float) -> None:
        """Check (and store) the sections, the density and the optional explicit bar lengths."""
        if isinstance(self.sections, Section) or not isinstance(self.sections, Sequence):
            raise TypeError(f"wire.sections is {self.sections!r}; expected a sequence of guidewire.Section.")
        for i, section in enumerate(self.sections):
            if not isinstance(section, Section):
                raise TypeError(f"wire.sections[{i}] is {type(section).__name__}; expected guidewire.Section.")
        object.__setattr__(self, "sections", tuple(self.sections))
        if self.density is not None and self.density not in DENSITIES:
            raise ValueError(f"wire.density is {self.density!r}; expected one of "
                             f"{', '.join(map(repr, DENSITIES))} or None (uniform bars; graded with tol_mm).")
        if self.bar_lengths is not None:
            object.__setattr__(self, "bar_lengths", _bar_lengths(self.bar_lengths, self.bars, length))

    def with_length(self, length: float) -> Wire:
        """The same wire inserted to ``length`` mm: the sections stay anchored at the tip (they move with the
        material), so a longer wire has more of the base-side material. Explicit ``bar_lengths`` belong to one
        inserted length: a new length drops them (the bars are laid out again by ``density``)."""
        if self.bar_lengths is not None and length != self.length:
            return replace(self, length=length, bar_lengths=None)
        return replace(self, length=length)

    def section_boundaries(self) -> tuple[float, ...]:
        """Arc lengths from the base (mm, increasing, inside ``(0, L)``) where one section meets the next."""
        ends = self.length - np.cumsum([sec.length for sec in self.sections])
        return tuple(float(s) for s in sorted(ends) if S_ROUNDING * self.length < s < self.length * (1 - S_ROUNDING))

    def properties_at(self, s: Any) -> WireProperties:
        """Material values at arc lengths ``s`` (mm from the base; vectorised, shape of ``s`` ravelled).

        A point exactly on a section boundary takes the tip-side section's values; callers evaluate bar midpoints.
        """
        index = self._section_index(s)
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
        picked = values[index]
        return WireProperties(picked[:, 0], picked[:, 1], picked[:, 2], picked[:, 3])

    def _section_index(self, s: Any) -> NDArray[np.intp]:
        """Which stretch holds each arc length ``s`` (mm from the base; ravelled): 0 the wire's own, ``i`` its
        section ``i`` counted from the tip (1-based); a point on a boundary is the tip-side section's."""
        s = np.atleast_1d(np.asarray(s, dtype=float)).ravel()
        tip_distance = np.cumsum([0.0, *(sec.length for sec in self.sections)])  # section i: [start, end) from tip
        from_tip = self.length - s
        index = np.searchsorted(tip_distance, from_tip, side="left")  # 1..m inside a section, m+1 past them
        return np.where(index > len(self.sections), 0, np.maximum(index, 1) if self.sections else 0)

    @property
    def refined(self) -> bool:
        """Whether some section sets a :attr:`Section.refinement` other than 1."""
        return any(sec.refinement != 1.0 for sec in self.sections)

    def refinement_at(self, s: Any) -> NDArray[np.float64]:
        """The :attr:`Section.refinement` at arc lengths ``s`` (mm from the base; 1 on the wire's own stretch)."""
        return np.array([1.0, *(sec.refinement for sec in self.sections)])[self._section_index(s)]

    @property
    def refined_length(self) -> float:
        """The inserted length weighted by the refinement of each stretch (mm): the measure the uniform layout
        shares the bars by. The length itself when no section is refined."""
        if not self.refined:
            return self.length
        ends = np.concatenate(([0.0], self.section_boundaries(), [self.length]))
        return float(np.sum(np.diff(ends) * self.refinement_at(0.5 * (ends[:-1] + ends[1:]))))

    @property
    def bar_density(self) -> float:
        """Bars per refined mm (``bars / refined_length``; bars per mm without refined sections): what an
        insertion keeps at every length (:meth:`bars_at`)."""
        return self.bars / self.refined_length

    def bars_at(self, length: float, density: float | None = None) -> int:
        """The bars of this wire inserted to ``length`` mm at ``density`` bars per refined mm (default
        :attr:`bar_density`): ``round(refined length × density)``, at least one."""
        density = self.bar_density if density is None else density
        return max(1, int(round(self.with_length(length).refined_length * density)))

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


def _bar_lengths(value: Any, bars: int, length: float) -> tuple[float, ...]:
    """``wire.bar_lengths`` checked: ``bars`` finite positive values summing to ``length`` (within rounding)."""
    if isinstance(value, str) or not isinstance(value, Sequence | np.ndarray):
        raise TypeError(f"wire.bar_lengths is {value!r}; expected a sequence of bar lengths in mm, or None.")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"wire.bar_lengths is {value!r}; expected numbers (mm).") from None
    if arr.ndim != 1 or arr.size != bars:
        raise ValueError(f"wire.bar_lengths has shape {arr.shape} but wire.bars is {bars}; give one length per bar "
                         "(or set bars to their number).")
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise ValueError("wire.bar_lengths must be finite and positive (mm); "
                         f"got {arr[~(np.isfinite(arr) & (arr > 0.0))][:3].tolist()}.")
    total = float(arr.sum())
    if abs(total - length) > LAYOUT_ROUNDING * length:
        raise ValueError(f"wire.bar_lengths sum to {total:.12g} mm but wire.length is {length:.12g} mm; the bars "
                         "must cover the inserted wire exactly.")
    return tuple(float(v) for v in arr)


def piece_ends(length: float, contact_s: NDArray[np.float64], breakpoints: Sequence[float]) -> NDArray[np.float64]:
    """Increasing ends of the pieces: every contact, every breakpoint not within rounding of a contact or an end,
    and ``L``."""
    extra = np.asarray(breakpoints, dtype=float)
    tol = BREAK_ROUNDING * length
    marks = np.concatenate((contact_s, [0.0, length]))
    keep = (extra > tol) & (extra < length - tol)
    if marks.size and extra.size:
        keep &= np.min(np.abs(extra[:, None] - marks[None, :]), axis=1) > tol
    ends = np.unique(np.concatenate((contact_s, extra[keep], [length])))
    return ends[ends <= length]


BREAK_ROUNDING = 1e-12
"""A breakpoint within this fraction of ``L`` of a contact or an end is that contact or end (no sliver bar)."""


def piece_count(length: float, contact_s: Sequence[float], breakpoints: Sequence[float] = ()) -> int:
    """Number of pieces the contacts and breakpoints cut a wire of ``length`` into (the fewest bars it needs)."""
    if len(breakpoints) == 0:  # the distinct ends up to L among the contacts and L (what piece_ends counts)
        return len({float(s) for s in contact_s if s <= length} | {float(length)})
    return int(piece_ends(length, np.asarray(contact_s, dtype=float), breakpoints).size)
