"""A planar scene (:class:`guidewire.Scene`) placed in 3-D by a rigid motion: the same problem for the 3-D model.

The plane ``z = 0`` is mapped by ``p ↦ R (x, y, 0) + b``; tangent angles ``θ`` become ``R (cos θ, sin θ, 0)``; the
clamp's material ``d1`` is the in-plane normal ``R (−sin θ, cos θ, 0)`` so that ``d2 = R e_z`` is normal to the
plane and a positive planar rest curvature (counter-clockwise) bends towards ``d1`` as in 3-D; walls become the planes
through their lines, normal to the scene's plane. The 3-D answer of the lifted scene is the planar answer mapped the
same way (the energies are equal term by term, :mod:`guidewire.rod.strain_energy`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..chain import BarChain, scene_bars
from ..initial_shape import initial_angles
from ..scene import Scene
from .scene import Base3D, Contact3D, Scene3D, Wall3D

FloatArray = NDArray[np.float64]


def lift(scene: Scene, rotation: FloatArray | None = None, shift: FloatArray | None = None) -> Scene3D:
    """``scene`` placed in 3-D by the rotation matrix ``rotation`` (3, 3; default identity) and ``shift`` (3,).

    Raises
    ------
    ValueError
        The scene has a vessel (lift the vessel with :func:`guidewire.vessel3d.Vessel3D.from_centreline` instead), a
        free base angle, or the paper scheme.
    """
    if scene.vessel is not None:
        raise ValueError("lift takes contact and wall scenes; build a 3-D vessel with guidewire.vessel3d.")
    if scene.base.angle is None:
        raise ValueError("base.angle is None; the 3-D model clamps the base (give the base tangent).")
    R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
    b = np.zeros(3) if shift is None else np.asarray(shift, dtype=float)

    def point(p: tuple[float, float] | None) -> tuple[float, float, float] | None:
        return None if p is None else tuple(R @ np.array([p[0], p[1], 0.0]) + b)

    def direction(angle: float | None) -> tuple[float, float, float] | None:
        return None if angle is None else tuple(R @ np.array([math.cos(angle), math.sin(angle), 0.0]))

    theta = scene.base.angle
    base = Base3D(point(scene.base.point), direction(theta), normal=direction(theta + math.pi / 2),
                  name=scene.base.name)
    contacts = tuple(Contact3D(c.s, point(c.point), direction(c.angle), c.name) for c in scene.contacts)
    walls = []
    for w in scene.walls:
        (nx, ny), offset = w.unit()
        normal = R @ np.array([nx, ny, 0.0])
        walls.append(Wall3D(tuple(normal), offset + float(normal @ b)))
    return Scene3D(wire=scene.wire, base=base, contacts=contacts, walls=tuple(walls), name=scene.name)


def lifted_start(scene: Scene, rotation: FloatArray | None = None, shift: FloatArray | None = None) -> FloatArray:
    """The planar model's default start (:func:`guidewire.initial_shape.initial_angles`) as 3-D nodes
    (n + 1, 3), mapped like :func:`lift`."""
    R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
    b = np.zeros(3) if shift is None else np.asarray(shift, dtype=float)
    lengths, contact_nodes = scene_bars(scene)
    chain = BarChain(np.asarray(scene.base.point, dtype=float), np.asarray(lengths))
    p = chain.nodes(initial_angles(scene, chain, contact_nodes))
    return np.column_stack((p, np.zeros(len(p)))) @ R.T + b
