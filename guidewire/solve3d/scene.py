"""A 3-D scene: the wire clamped at the entrance with an insertion rotation, contacts, walls, a vessel and a tip load.

Units mm, rad, MPa (N/mm²), N. Every value is checked when built; a bad field raises ``ValueError``/``TypeError``
naming the field and the fix. The wire is :class:`guidewire.Wire` (sections, J-tip rest curvature, bars); its
``scheme`` must be ``"second_order"`` (the 3-D energy is that scheme's, :mod:`guidewire.rod.strain_energy`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..fields import real
from ..rod import quaternion as quat
from ..rod.material import POISSON_RATIO, check_twist_material
from ..wire import S_ROUNDING, Wire

FloatArray = NDArray[np.float64]
Vector = tuple[float, float, float]


def vector(value: Any, name: str, *, unit: bool = False) -> Vector:
    """``value`` as three finite floats (normalised with ``unit``, which refuses the zero vector)."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence | np.ndarray):
        raise TypeError(f"{name} is {value!r}; expected three numbers [x, y, z].")
    if len(value) != 3:
        raise ValueError(f"{name} has {len(value)} entries; expected three [x, y, z] (a 2-D value belongs to "
                         "guidewire.Scene).")
    out = tuple(real(v, f"{name}[{i}]") for i, v in enumerate(value))
    if unit:
        norm = math.sqrt(sum(v * v for v in out))
        if norm == 0.0:
            raise ValueError(f"{name} is [0, 0, 0]; give a nonzero direction.")
        out = tuple(v / norm for v in out)
    return out  # type: ignore[return-value]


@dataclass(frozen=True)
class Base3D:
    """The clamp at ``s = 0``: a point, the tangent, and the material frame's roll about it.

    Parameters
    ----------
    point : (x, y, z)
        mm.
    tangent : (x, y, z)
        Direction the wire leaves the clamp (normalised).
    normal : (x, y, z) or None
        The material ``d1`` at zero rotation (its part across the tangent is used); None: the world axis least
        aligned with the tangent. A J-tip's rest curvature bends towards ``d1``.
    rotation : float
        The insertion rotation: the material frame turned by this angle (rad) about the tangent, right-handed.
    name : str
    """

    point: Vector = (0.0, 0.0, 0.0)
    tangent: Vector = (1.0, 0.0, 0.0)
    normal: Vector | None = None
    rotation: float = 0.0
    name: str = "base"

    def __post_init__(self) -> None:
        object.__setattr__(self, "point", vector(self.point, "base.point"))
        object.__setattr__(self, "tangent", vector(self.tangent, "base.tangent", unit=True))
        if self.normal is not None:
            normal = vector(self.normal, "base.normal", unit=True)
            if abs(float(np.dot(normal, self.tangent))) > 1.0 - 1e-9:
                raise ValueError("base.normal is parallel to base.tangent; give a direction across the tangent (the "
                                 "material d1 at zero rotation).")
            object.__setattr__(self, "normal", normal)
        object.__setattr__(self, "rotation", real(self.rotation, "base.rotation"))

    def frame(self) -> FloatArray:
        """The clamp's material frame ``[d1; d2; d3]`` (3, 3), with the rotation applied."""
        f = quat.frame_from_tangent(np.array(self.tangent), None if self.normal is None else np.array(self.normal))
        c, s = math.cos(self.rotation), math.sin(self.rotation)
        d1 = c * f[0] + s * f[1]
        return np.vstack((d1, np.cross(f[2], d1), f[2]))

    def rotated_by(self, angle: float) -> Base3D:
        return replace(self, rotation=self.rotation + angle)


@dataclass(frozen=True)
class Contact3D:
    """A point of the wire at arc length ``s`` with a prescribed position and/or tangent direction.

    With ``normal`` (only with ``tangent``) the contact holds the whole material frame there: ``d1`` is the part of
    ``normal`` across the tangent (a second clamp, e.g. a torque device or a wire end held in a vice).
    """

    s: float
    point: Vector | None = None
    tangent: Vector | None = None
    name: str = ""
    normal: Vector | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "s", real(self.s, "contact.s"))
        if self.point is not None:
            object.__setattr__(self, "point", vector(self.point, "contact.point"))
        if self.tangent is not None:
            object.__setattr__(self, "tangent", vector(self.tangent, "contact.tangent", unit=True))
        if self.point is None and self.tangent is None:
            raise ValueError(f"contact at s = {self.s:g} has neither point nor tangent; give at least one.")
        if self.normal is not None:
            if self.tangent is None:
                raise ValueError(f"contact at s = {self.s:g} has a normal but no tangent; the roll is held about the "
                                 "tangent, so give both.")
            normal = vector(self.normal, "contact.normal", unit=True)
            if abs(float(np.dot(normal, self.tangent))) > 1.0 - 1e-9:
                raise ValueError(f"contact at s = {self.s:g} has its normal along its tangent; give d1 across it.")
            object.__setattr__(self, "normal", normal)


@dataclass(frozen=True)
class Wall3D:
    """A plane: every node ``p`` must satisfy ``normal · p ≤ offset`` (normal pointing out of the allowed side)."""

    normal: Vector
    offset: float

    def __post_init__(self) -> None:
        raw = vector(self.normal, "wall.normal")
        norm = math.sqrt(sum(v * v for v in raw))
        if norm == 0.0:
            raise ValueError("wall.normal is [0, 0, 0]; give the outward normal, e.g. [0, 0, 1] for z ≤ offset.")
        object.__setattr__(self, "normal", tuple(v / norm for v in raw))
        object.__setattr__(self, "offset", real(self.offset, "wall.offset") / norm)


@dataclass(frozen=True)
class Scene3D:
    """A wire clamped at ``base``, with contacts (increasing ``s``), walls, a vessel and a tip force.

    Parameters
    ----------
    wire : guidewire.Wire
        ``scheme`` must be ``"second_order"``.
    base : Base3D
    contacts : sequence of Contact3D
    walls : sequence of Wall3D
    vessel : guidewire.vessel3d.Vessel3D or None
        Every node stays inside its lumen by the wire's radius.
    tip_force : (x, y, z) or None
        A dead load on the tip node (N).
    poisson_ratio, shear_modulus : float, float or None
        ``GJ`` of the bars (:mod:`guidewire.rod.material`).
    name : str
    """

    wire: Wire
    base: Base3D = field(default_factory=Base3D)
    contacts: tuple[Contact3D, ...] = ()
    walls: tuple[Wall3D, ...] = ()
    vessel: Any = None
    tip_force: Vector | None = None
    poisson_ratio: float = POISSON_RATIO
    shear_modulus: float | None = None
    name: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.wire, Wire):
            raise TypeError(f"scene.wire is {type(self.wire).__name__}; expected guidewire.Wire.")
        if self.wire.scheme != "second_order":
            raise ValueError(f"wire.scheme is {self.wire.scheme!r}; the 3-D model is the second-order scheme's, so "
                             "use scheme='second_order'.")
        if not isinstance(self.base, Base3D):
            raise TypeError(f"scene.base is {type(self.base).__name__}; expected guidewire.solve3d.Base3D.")
        contacts = list(self.contacts)
        length = self.wire.length
        for i, c in enumerate(contacts):
            if not isinstance(c, Contact3D):
                raise TypeError(f"scene.contacts[{i}] is {type(c).__name__}; expected Contact3D.")
            if abs(c.s - length) <= S_ROUNDING * length:
                contacts[i] = c = replace(c, s=length)
            if not 0.0 < c.s <= length:
                raise ValueError(f"scene.contacts[{i}] has s = {c.s:g}; contacts need 0 < s ≤ wire.length = "
                                 f"{length:g} mm.")
            if i and c.s <= contacts[i - 1].s:
                raise ValueError(f"scene.contacts[{i}] has s = {c.s:g} after s = {contacts[i - 1].s:g}; list "
                                 "contacts by strictly increasing s (one contact may carry a point and a tangent).")
        for i, w in enumerate(self.walls):
            if not isinstance(w, Wall3D):
                raise TypeError(f"scene.walls[{i}] is {type(w).__name__}; expected Wall3D.")
        if self.vessel is not None and not hasattr(self.vessel, "lumen_rows"):
            raise TypeError(f"scene.vessel is {type(self.vessel).__name__}; expected guidewire.vessel3d.Vessel3D.")
        if self.tip_force is not None:
            object.__setattr__(self, "tip_force", vector(self.tip_force, "scene.tip_force"))
        nu, g = check_twist_material(self.poisson_ratio, self.shear_modulus)
        object.__setattr__(self, "poisson_ratio", nu)
        object.__setattr__(self, "shear_modulus", g)
        object.__setattr__(self, "contacts", tuple(contacts))
        object.__setattr__(self, "walls", tuple(self.walls))

    @classmethod
    def in_vessel(cls, wire: Wire, vessel: Any, *, rotation: float = 0.0, normal: Vector | None = None,
                  **kw: Any) -> Scene3D:
        """A wire inserted into ``vessel`` to ``wire.length``: clamped at the entrance along the centreline's first
        tangent, rolled by ``rotation`` (rad)."""
        point, tangent = vessel.entrance
        base = Base3D(tuple(point), tuple(tangent), normal=normal if normal is not None else vessel.entrance_normal,
                      rotation=rotation, name="entrance")
        return cls(wire=wire, base=base, vessel=vessel, **kw)

    def with_length(self, length: float) -> Scene3D:
        return replace(self, wire=self.wire.with_length(length))

    def with_rotation(self, rotation: float) -> Scene3D:
        return replace(self, base=replace(self.base, rotation=rotation))
