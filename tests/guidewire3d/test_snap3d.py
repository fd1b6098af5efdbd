"""A J-tip turned at the clamp in a curved tube (stEVE's J wire 100 mm into the helix) lags, then snaps over (issue
29): the step of the snap is followed by the warm start like every other, converges, and lowers the energy.

At the snap the tip's roll, behind the clamp's by about 95°, jumps about 190° ahead within one step: the branch
followed ends at a fold, and the warm start sits next to a saddle of the energy on the rows it holds. Each step must
converge from the last one's answer (no cold re-solve, which could land on any equilibrium), and the energy must
fall across the snap.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from guidewire import Section, Wire
from guidewire.solve3d import Scene3D
from guidewire.solve3d.insert import insert3d
from guidewire.vessel3d.shapes import helix

STEVE_J = (Section.arc(12.1, 0.4 * math.pi, youngs_modulus=17000.0, diameter=0.7),)


@pytest.mark.parametrize(("density", "turn_deg"), [(1.0, 10.0), (1.0, 15.0), (2.0, 15.0), (1.0, 20.0)])
def test_a_j_tip_snaps_over_in_one_converged_warm_step_that_lowers_the_energy(density, turn_deg):
    """Pushed 10 → 100 mm in 5 mm steps, then turned to 180° in ``turn_deg`` steps, at ``density`` bars per mm:
    every step converges warm; the tip's roll stays behind the clamp's, the lag growing by more than 45° to more
    than 60°; then, in one step, the roll jumps by more than 120° (every other step turns it by less than 45°),
    the tip ends ahead of the clamp, and the energy of that step is below the last one's."""
    wire = Wire(length=10.0, bars=round(10 * density), youngs_modulus=80000.0, diameter=0.89, sections=STEVE_J)
    push = np.arange(10.0, 100.5, 5.0)
    turns = np.radians(np.arange(turn_deg, 180.0 + 0.5 * turn_deg, turn_deg))
    out = insert3d(Scene3D.in_vessel(wire, helix()), np.concatenate((push, np.full(turns.size, 100.0))),
                   np.concatenate((np.zeros(push.size), turns)))
    assert out.complete, out.error
    assert all(s.success for s in out.steps)
    assert not any(s.extras.get("cold", False) for s in out.steps)
    steps = out.steps[push.size - 1:]  # (the last push, then every turn)
    rolls = np.array([s.tip_roll for s in steps])
    base = np.array([s.base_rotation for s in steps])
    energies = np.array([s.energy for s in steps])
    jumps = np.diff(rolls)
    snap = int(np.argmax(np.abs(jumps)))
    assert jumps[snap] > math.radians(120.0)
    assert np.all(np.abs(np.delete(jumps, snap)) < math.radians(45.0))
    lag = base - rolls
    assert np.all(lag[:snap + 1] > 0.0) and lag[snap] > max(lag[0] + math.radians(45.0), math.radians(60.0))
    assert lag[snap + 1] < 0.0
    assert energies[snap + 1] < energies[snap]
