"""The wire as a parametric B-spline in arc length ``s`` (mm, 0 at the base) that interpolates the nodes
(:func:`wire_spline`): with ``spline = wire_spline(sol.nodes, sol.s)``, ``scipy.interpolate.BSpline(spline.knots,
spline.coefficients, spline.degree)(sol.s)`` is ``sol.nodes`` to rounding (1e-14 mm). It is fitted by
``scipy.interpolate.make_splprep`` (SciPy ≥ 1.15) or, in older SciPy, ``splprep``; both give the same knots and
coefficients. Refinement interpolates a fine solve with it; exports save it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

try:
    from scipy.interpolate import make_splprep
except ImportError:  # SciPy < 1.15
    make_splprep = None

FloatArray = NDArray[np.float64]

#: Degree of the wire's B-spline (cubic; lower when the wire has fewer than four nodes).
DEGREE = 3


@dataclass(frozen=True)
class WireSpline:
    """The wire as a parametric B-spline in arc length: ``BSpline(knots, coefficients, degree)(s)`` → points (mm).

    Attributes
    ----------
    knots : ndarray, shape (m + degree + 1,)
        Knot vector in mm of arc length (clamped: the first and last ``degree + 1`` are 0 and L).
    coefficients : ndarray, shape (m, 2)
        Control points (mm).
    degree : int
    """

    knots: FloatArray
    coefficients: FloatArray
    degree: int

    def __call__(self, s: ArrayLike) -> FloatArray:
        """Points of the wire at arc lengths ``s`` (mm), shape ``(len(s), 2)``."""
        from scipy.interpolate import BSpline

        return np.asarray(BSpline(self.knots, self.coefficients, self.degree, extrapolate=False)(s), dtype=float)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready values."""
        return {"knots": self.knots.tolist(), "coefficients": self.coefficients.tolist(), "degree": self.degree}


def wire_spline(nodes: ArrayLike, s: ArrayLike, degree: int = DEGREE) -> WireSpline:
    """The interpolating B-spline through ``nodes`` (shape (n + 1, 2), mm) at arc lengths ``s`` (increasing, mm).

    ``degree`` is lowered to ``n`` when the wire has fewer than ``degree + 1`` nodes.

    Raises
    ------
    ValueError
        For nodes that are not an (m, 2) array of at least two finite points, or ``s`` that does not match them or
        does not increase.
    """
    nodes = np.asarray(nodes, dtype=float)
    s = np.asarray(s, dtype=float)
    if nodes.ndim != 2 or nodes.shape[1] != 2 or nodes.shape[0] < 2:
        raise ValueError(f"nodes has shape {nodes.shape}; expected (n + 1, 2) with at least two nodes.")
    if s.shape != (nodes.shape[0],):
        raise ValueError(f"s has shape {s.shape}; expected ({nodes.shape[0]},), one arc length per node.")
    if not (np.all(np.isfinite(nodes)) and np.all(np.isfinite(s))):
        raise ValueError("nodes and s must be finite.")
    if np.any(np.diff(s) <= 0.0):
        raise ValueError("s must increase strictly from node to node.")
    if isinstance(degree, bool) or not isinstance(degree, int) or not 1 <= degree <= 5:
        raise ValueError(f"degree is {degree!r}; expected a whole number from 1 to 5.")
    k = min(degree, nodes.shape[0] - 1)
    knots, coefficients = _fit(nodes, s, k, legacy=make_splprep is None)
    return WireSpline(knots, coefficients, k)


def _fit(nodes: FloatArray, s: FloatArray, k: int, *, legacy: bool) -> tuple[FloatArray, FloatArray]:
    """Knots and (m, 2) coefficients of the interpolating spline, by ``make_splprep`` or (``legacy``) ``splprep``."""
    if not legacy:
        spline, _ = make_splprep(nodes.T, u=s, k=k, s=0)
        return np.array(spline.t, dtype=float), np.array(spline.c, dtype=float).reshape(-1, 2)
    from scipy.interpolate import splprep

    (knots, coefficients, _), _ = splprep(nodes.T, u=s, k=k, s=0)
    m = len(knots) - k - 1  # splprep pads its coefficients to the knots' length
    return np.array(knots, dtype=float), np.array(coefficients, dtype=float).T[:m].copy()
