"""What the arch's cold-solve tests check (``test_arch_cold.py``, ``test_arch_openings.py``): the shipped aortic arch,
every node inside its lumen, and the tube a point lies deepest in."""

from __future__ import annotations

from importlib import resources

import numpy as np

import guidewire

VESSELS = resources.files("guidewire") / "scenes" / "vessels"


def arch() -> guidewire.Scene:
    """The shipped aortic arch (``scenes/vessels/aortic_arch.toml``)."""
    return guidewire.load_scene(str(VESSELS / "aortic_arch.toml"))


def inside(scene: guidewire.Scene, solution: guidewire.Solution) -> None:
    """Every node keeps the wire's radius from the lumen's boundary, its corners included (within the solve's
    tolerance)."""
    clearance = scene.vessel.lumen_clearance(np.asarray(solution.nodes)[1:])
    assert clearance.min() >= 0.5 * scene.wire.diameter - 1e-5 * scene.wire.length


def tube(scene: guidewire.Scene, point: np.ndarray) -> int:
    """The tube (0 the arch, k the branch k) the point lies deepest in."""
    return int(np.argmax(scene.vessel.tube_depths(point)[0]))
