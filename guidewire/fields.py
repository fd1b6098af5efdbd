"""Field validators and number formats shared by every module that takes user values (scenes, scene files, the
continuum reference, feasibility messages).

Each validator returns the cleaned value or raises ``TypeError``/``ValueError`` whose message names the field and
says what was expected, so a bad value is refused before any work.
"""

from __future__ import annotations

import math
import numbers
import warnings
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np


class SuspiciousValueWarning(UserWarning):
    """A value that is valid but probably in the wrong unit (degrees for radians, GPa for MPa)."""


def real(value: Any, name: str, *, positive: bool = False) -> float:
    """``value`` as a finite float.

    Parameters
    ----------
    value : int or float
        Booleans and strings are refused (``True`` is not a length).
    name : str
        The field's name in messages, e.g. ``"wire.length"``.
    positive : bool
        Also require ``value > 0``.

    Raises
    ------
    TypeError
        Not a real number.
    ValueError
        NaN or inf, or not positive when ``positive``.
    """
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} is {value!r} of type {type(value).__name__}; expected a real number.")
    out = float(value)
    if not math.isfinite(out):
        raise ValueError(f"{name} is {out}; expected a finite number.")
    if positive and out <= 0.0:
        raise ValueError(f"{name} is {fmt(out)}; it must be positive.")
    return out


def point(value: Any, name: str) -> tuple[float, float]:
    """``value`` as an ``(x, y)`` tuple of finite floats in mm.

    Raises
    ------
    TypeError
        Not a sequence (or a string).
    ValueError
        Not two entries, or an entry NaN/inf.
    """
    if isinstance(value, str) or not isinstance(value, Sequence | Iterable):
        raise TypeError(f"{name} is {value!r}; expected two numbers [x, y] in mm.")
    items = list(value)
    if len(items) != 2:
        raise ValueError(f"{name} has {len(items)} entries; expected two numbers [x, y] in mm.")
    return (real(items[0], f"{name}[0]"), real(items[1], f"{name}[1]"))


def fmt(value: float) -> str:
    """A number as the paper prints it: ``80``, ``28.5``."""
    return f"{value:g}"


def fmt_point(p: Sequence[float]) -> str:
    """A point as ``(x, y)`` with :func:`fmt`'s numbers."""
    return f"({fmt(float(p[0]))}, {fmt(float(p[1]))})"


ANGLE_WARNING_RAD = 2.0 * math.pi
"""An angle above this magnitude (rad) is probably in degrees: warn (it stays literal: θ + 2π asks for a loop)."""

MODULUS_WARNING_MPA = 100.0
"""A Young's modulus below this (MPa) is probably in GPa (guidewire alloys are 10-200 GPa; polymers ≥ 1 GPa): warn."""


def warn_angle(value: float, name: str) -> None:
    """Warn (:class:`SuspiciousValueWarning`) when ``|value| > 2π``: likely degrees, not radians."""
    if abs(value) > ANGLE_WARNING_RAD:
        warnings.warn(
            f"{name} is {fmt(value)} rad, more than a full turn: if it is in degrees give {math.radians(value):.6g} "
            "rad instead (angles are literal, so this asks the wire to loop).", SuspiciousValueWarning, stacklevel=4)


#: Wire diameters outside this range (mm) are no guidewire or catheter: the finest neurovascular wires are 0.2 mm
#: (0.008 in), the thickest catheters about 3 mm (9 F); a value below the range is most likely metres or inches.
DIAMETER_RANGE_MM = (0.05, 5.0)

#: Lumen radii above this (mm) exceed the largest human vessel (the aortic root, about 20 mm): most likely µm.
RADIUS_WARNING_MM = 50.0


def warn_diameter(value: float, name: str) -> None:
    """Warn (:class:`SuspiciousValueWarning`) when a wire diameter lies outside :data:`DIAMETER_RANGE_MM`."""
    lo, hi = DIAMETER_RANGE_MM
    if value < lo:
        warnings.warn(f"{name} is {fmt(value)} mm, thinner than any guidewire: if it is in metres give "
                      f"{value * 1e3:g} mm, if in inches {value * 25.4:g} mm.", SuspiciousValueWarning, stacklevel=4)
    elif value > hi:
        warnings.warn(f"{name} is {fmt(value)} mm, thicker than any guidewire or catheter: if it is in µm give "
                      f"{value * 1e-3:g} mm.", SuspiciousValueWarning, stacklevel=4)


def warn_radius(value: float, name: str) -> None:
    """Warn (:class:`SuspiciousValueWarning`) when a lumen radius exceeds :data:`RADIUS_WARNING_MM`."""
    if value > RADIUS_WARNING_MM:
        warnings.warn(f"{name} is {fmt(value)} mm, wider than any blood vessel (the aorta: about 15 mm): if it is in "
                      f"µm give {value * 1e-3:g} mm; if it is a diameter give half of it.", SuspiciousValueWarning,
                      stacklevel=4)


def warn_modulus(value: float, name: str) -> None:
    """Warn (:class:`SuspiciousValueWarning`) when a Young's modulus is below 100 MPa: likely GPa, not MPa."""
    if value < MODULUS_WARNING_MPA:
        warnings.warn(
            f"{name} is {fmt(value)} MPa, softer than any guidewire material: if it is in GPa give "
            f"{value * 1e3:g} MPa instead.", SuspiciousValueWarning, stacklevel=4)
