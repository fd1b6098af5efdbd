"""Shipped 3-D vessels: a helix and a tortuous coronary-scale vessel, and by name the aortic arches of
:mod:`guidewire.vessel3d.arch` (``aortic_arch``). Each is a :class:`~guidewire.vessel3d.vessel.Vessel3D` built from
sampled centreline points, with a straight lead-in along the entrance tangent so that a clamp at the entrance meets a
straight lumen.
"""

from __future__ import annotations

import math

import numpy as np

from .arch import aortic_arch
from .vessel import Vessel3D

__all__ = ["SHAPES", "aortic_arch", "helix", "tortuous"]

SHAPES = ("aortic_arch", "helix", "tortuous")
"""The shapes a scene file may name (``[vessel] shape = "helix"``)."""


def helix(coil_radius: float = 10.0, pitch: float = 25.0, turns: float = 2.0, radius: float = 2.0,
          lead_in: float = 20.0, spacing: float = 2.0) -> Vessel3D:
    """A helical tube about the z axis: ``(a cos t, a sin t, p t / 2π)`` for ``t`` in ``[0, 2π turns]``, entered
    along its tangent at ``t = 0`` after a straight ``lead_in`` (mm). Its curvature is ``a / (a² + (p/2π)²)``
    (1/11.6 mm with the defaults) and its torsion ``(p/2π) / (a² + (p/2π)²)``."""
    b = pitch / (2.0 * math.pi)
    speed = math.hypot(coil_radius, b)
    count = max(8, int(math.ceil(2.0 * math.pi * turns * speed / spacing)))
    t = np.linspace(0.0, 2.0 * math.pi * turns, count + 1)
    coil = np.column_stack((coil_radius * np.cos(t), coil_radius * np.sin(t), b * t))
    tangent = np.array([0.0, coil_radius, b]) / speed
    lead = coil[0] - np.outer(np.linspace(lead_in, spacing, max(1, int(lead_in // spacing))), tangent)
    return Vessel3D.from_centreline(np.vstack((lead, coil)), radius, name="helix")


def tortuous(length: float = 80.0, radius: float = 1.5, amplitude: float = 4.0, wavelength: float = 22.0,
             spacing: float = 1.0) -> Vessel3D:
    """A coronary-scale tortuous vessel (lumen radius 1.5 mm, an LAD's): it runs along +x and winds in both ``y``
    and ``z`` with incommensurate wavelengths (``λ`` and ``1.37 λ``), tapering to 70 % of its radius, after a 10 mm
    straight lead-in. The tightest bend radius is about 3 mm with the defaults (``λ² / (4π² A)`` over the two
    modes), twice the lumen radius."""
    x = np.arange(0.0, length + spacing, spacing)
    t = np.clip((x - 10.0) / 20.0, 0.0, 1.0)
    ramp = t**3 * (10.0 - 15.0 * t + 6.0 * t**2)  # the lead-in, then the windings fading in (C² smootherstep)
    y = amplitude * ramp * np.sin(2 * math.pi * (x - 10.0) / wavelength)
    z = 0.6 * amplitude * ramp * np.sin(2 * math.pi * (x - 10.0) / (1.37 * wavelength))
    r = radius * (1.0 - 0.3 * x / x[-1])
    return Vessel3D.from_centreline(np.column_stack((x, y, z)), r, name="tortuous")
