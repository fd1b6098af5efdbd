"""What the PyElastica benchmarks share: the import, the simulator, the stable time step, damping and the stopping rule.

PyElastica (``pip install pyelastica``, imported as ``elastica``) is set up in consistent units mm, N, MPa, s and
tonne (1 N = 1 t·mm/s²). A rod is relaxed to its static state by the ``PositionVerlet`` stepper with an
``AnalyticalLinearDamper`` of uniform damping constant ``DAMPING_OVER_OMEGA · ω₁`` (ω₁ the problem's first mode) and
stopped by :func:`relax`'s rule on node speeds and tip motion.
"""

from __future__ import annotations

import math
import statistics
import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np


def round_section(diameter: float) -> tuple[float, float, float]:
    """Radius (mm), area (mm²) and second moment of area (mm⁴) of a round wire of ``diameter`` (mm)."""
    r = diameter / 2.0
    return r, math.pi * r * r, math.pi * diameter**4 / 64.0


def cantilever_first_mode(youngs: float, diameter: float, density: float, length: float) -> float:
    """ω₁ (rad/s) of a straight round cantilever: 1.875² √(EI / (ρ A L⁴)) (MPa, mm, t/mm³, mm)."""
    _, area, inertia = round_section(diameter)
    return 1.875**2 * math.sqrt(youngs * inertia / (density * area * length**4))

try:
    import elastica as ea
except ImportError:  # pragma: no cover - exercised only without the bench extra
    ea = None

#: PyElastica's time step as a fraction of the stable estimate (:func:`time_step`).
CFL = 0.9
#: Damping constant over ω₁.
DAMPING_OVER_OMEGA = 2.0
#: Stopping rule: node speed below VELOCITY_TOL_MM · ω₁, tip moved less than TIP_TOL_MM over 1/ω₁.
VELOCITY_TOL_MM, TIP_TOL_MM = 1e-4, 1e-4
#: Steps between two checks of the stopping rule.
CHECK_STEPS = 500
#: A run not settled after MAX_PERIODS / ω₁ of simulated time is reported as not settled.
MAX_PERIODS = 60.0
#: PyElastica's shear correction factor (``CosseratRod`` sets the shear stiffness to α G A).
ALPHA_SHEAR = 27.0 / 28.0


def require(script: str) -> None:
    """Exit with the install hint when PyElastica is missing."""
    if ea is None:
        sys.exit(f"{script} needs PyElastica: pip install pyelastica (or the bench extra: pip install -e '.[bench]').")


def simulator() -> Any:
    """An empty PyElastica simulator with constraints, forcing and damping."""

    class Simulator(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping):
        pass

    return Simulator()


def time_step(dl: float, radius: float, density: float, youngs: float, shear: float, stiffen: float = 1.0,
              cfl: float = CFL) -> float:
    """``cfl / √(1/dt_a² + 1/dt_s²)``: ``dt_a = dl √(ρ / (K E))`` (the axial wave across an element) and
    ``dt_s = r √(ρ / (K α G))`` (an element's rotation, rotary inertia ρ I, against its shear stiffness).

    Parameters
    ----------
    dl, radius : float
        Element length and wire radius (mm).
    density, youngs, shear : float
        t/mm³, MPa, MPa.
    stiffen : float
        The factor K on PyElastica's stretch and shear stiffness.
    cfl : float
        The fraction of the estimate (:data:`CFL` by default).
    """
    axial = dl * math.sqrt(density / (stiffen * youngs))
    rotation = radius * math.sqrt(density / (stiffen * ALPHA_SHEAR * shear))
    return cfl / math.hypot(1.0 / axial, 1.0 / rotation)


@dataclass(frozen=True)
class Relaxation:
    """How a damped run ended: simulated time (s), steps, and whether the stopping rule (not the cap) ended it."""

    time: float
    steps: int
    settled: bool


def relax(sim: Any, rod: Any, dt: float, omega: float, *, max_periods: float = MAX_PERIODS,
          after_check: Callable[[], None] | None = None) -> Relaxation:
    """Step ``sim`` (finalized) by ``dt`` until ``rod`` is at rest.

    Checked every :data:`CHECK_STEPS` steps: the largest node speed below ``VELOCITY_TOL_MM · ω`` and the tip moved
    less than ``TIP_TOL_MM`` over the last ``1/ω`` of simulated time; at most ``max_periods / ω`` of simulated time.
    A non-finite tip (the run diverged) ends it unsettled. ``after_check`` runs after every check.
    """
    stepper = ea.PositionVerlet()
    window = max(1, round(1.0 / (omega * dt) / CHECK_STEPS))  # checks per 1/ω
    max_steps = int(max_periods / (omega * dt))
    tips: list[np.ndarray] = []
    t, steps, settled = np.float64(0.0), 0, False
    while steps < max_steps:
        for _ in range(CHECK_STEPS):
            t = stepper.step(sim, t, dt)
        steps += CHECK_STEPS
        tip = rod.position_collection[:, -1].copy()
        if not np.all(np.isfinite(tip)):
            break
        if after_check is not None:
            after_check()
        tips.append(tip)
        speed = float(np.max(np.linalg.norm(rod.velocity_collection, axis=0)))
        if (speed < VELOCITY_TOL_MM * omega and len(tips) > window
                and np.linalg.norm(tip - tips[-1 - window]) < TIP_TOL_MM):
            settled = True
            break
    return Relaxation(float(t), steps, settled)


def median_run(fn: Any, repeats: int, *args: Any) -> tuple[dict[str, Any], list[float]]:
    """``fn(*args)`` ``repeats`` times: the first run's record with the median ``wall_s`` (and ``solve_s``), and
    every run's wall time."""
    runs = [fn(*args) for _ in range(repeats)]
    walls = [r["wall_s"] for r in runs]
    out = dict(runs[0])
    out["wall_s"] = statistics.median(walls)
    if "solve_s" in out:
        out["solve_s"] = statistics.median(r["solve_s"] for r in runs)
    return out, walls
