"""The continuum reference of a guidewire :class:`~guidewire.Scene` and the paper's node-error metric (Eq. 25).

:func:`continuum_reference` adapts a scene to :func:`~guidewire.reference.whole_wire.reference_shapes` and says
why when the reference does not cover it; :func:`node_errors` measures a discrete solution against the nearest of
the equal-lowest-energy continuum shapes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from .sectioned import StiffnessProfile
from .shapes import Array, ContinuumShape
from .whole_wire import reference_shapes

if TYPE_CHECKING:
    from ..scene.scene import Scene
    from ..solve.result import Solution

__all__ = ["ContinuumReference", "continuum_reference", "nearest_shape", "node_errors"]


@dataclass(frozen=True)
class ContinuumReference:
    """The exact continuum shapes of a scene that share the lowest energy (mirror twins of a symmetric scene, e.g.
    Table 1 with θ_B = 0 or Fig. 6b bending up or down); behaves like the first one.

    Attributes
    ----------
    shapes : tuple of ContinuumShape
        The tied lowest-energy shapes, the default one first.
    """

    shapes: tuple[ContinuumShape, ...]

    @property
    def energy(self) -> float:
        """Bending energy of the shapes (N·mm)."""
        return float(self.shapes[0].energy)

    def position(self, s: ArrayLike) -> Array:
        """Positions (mm) of the first shape at arc lengths ``s``, shape ``(k, 2)``."""
        return self.shapes[0].position(s)


def continuum_reference(scene: Scene) -> tuple[ContinuumReference | None, str]:
    """The exact continuum shape(s) of ``scene``, or ``(None, why not)``.

    Parameters
    ----------
    scene : Scene
        Base, contacts, wire and walls are read from it.

    Returns
    -------
    reference : ContinuumReference or None
        ``None`` when the reference does not cover the scene (e.g. position-only contacts, a free base angle,
        walls active together with contacts, a wall touching a sectioned wire elsewhere than at its free end) or
        the scene is infeasible.  A wire with sections is solved with its piecewise ``EI`` and rest curvature
        (:mod:`~guidewire.reference.sectioned`).
    reason : str
        ``""`` with a reference, else ``"no reference: "`` and the reason.
    """
    stiffness: float | StiffnessProfile = scene.wire.bending_stiffness
    if scene.wire.sections:
        profile = StiffnessProfile.of_wire(scene.wire)
        stiffness = profile.bending_stiffness[0] if profile.uniform else profile
    try:
        shapes = reference_shapes(
            scene.base.point, scene.base.angle, scene.contacts, scene.wire.length, stiffness, scene.walls,
        )
    except (NotImplementedError, ValueError) as exc:
        return None, f"no reference: {exc}"
    return ContinuumReference(tuple(shapes)), ""


def nearest_shape(solution: Solution, reference: ContinuumReference | ContinuumShape) -> ContinuumShape:
    """Of the equal-lowest-energy continuum shapes, the one nearest to ``solution`` (mean node distance)."""
    shapes = reference.shapes if isinstance(reference, ContinuumReference) else (reference,)
    return min(shapes, key=lambda shape: float(np.mean(np.hypot(*(solution.nodes - shape.position(solution.s)).T))))


def node_errors(solution: Solution, reference: ContinuumReference | ContinuumShape) -> Array:
    """Distance (mm) of every node from the continuum point at the same arc length (the paper's Eq. 25), against
    the nearest of the equal-lowest-energy continuum shapes, shape ``(n_bars + 1,)``."""
    return np.hypot(*(solution.nodes - nearest_shape(solution, reference).position(solution.s)).T)
