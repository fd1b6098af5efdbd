"""Twist stiffness ``GJ`` of a wire's bars, from a shear modulus or a Poisson ratio.

For a solid round section ``J = 2 I`` (the polar moment: ``π d⁴ / 32``), and an isotropic material has
``G = E / (2 (1 + ν))``. The default ``ν = 0.3`` is that of stainless steel (0.27–0.30) and within the range reported
for nitinol (0.30–0.33); it gives ``GJ = EI / 1.3``. A wire whose core is not a solid round section (a coil over a
core) should give its measured ``shear_modulus`` (or a ratio fitted to a torsion test).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..fields import real
from ..wire import Wire

FloatArray = NDArray[np.float64]

POISSON_RATIO = 0.3
"""Default Poisson ratio ``ν`` (stainless steel; nitinol 0.30–0.33)."""


def check_twist_material(poisson_ratio: Any, shear_modulus: Any) -> tuple[float, float | None]:
    """The two fields validated: ``-1 < ν < 0.5`` and ``G > 0`` (MPa) when given."""
    nu = real(poisson_ratio, "poisson_ratio")
    if not -1.0 < nu < 0.5:
        raise ValueError(f"poisson_ratio is {nu}; an isotropic material has -1 < ν < 0.5 (steel 0.3, nitinol 0.33).")
    g = None if shear_modulus is None else real(shear_modulus, "shear_modulus", positive=True)
    return nu, g


def twist_stiffness(wire: Wire, s: FloatArray, poisson_ratio: float = POISSON_RATIO,
                    shear_modulus: float | None = None) -> FloatArray:
    """``GJ`` in N·mm² at arc lengths ``s`` (mm, bar midpoints): ``G · 2I`` of the section there, with
    ``G = shear_modulus`` if given (one value for every section) else ``E / (2 (1 + ν))`` of the section's ``E``."""
    props = wire.properties_at(s)
    g = props.youngs_modulus / (2.0 * (1.0 + poisson_ratio)) if shear_modulus is None else np.full(props.diameter.size,
                                                                                                     shear_modulus)
    return g * 2.0 * props.second_moment
