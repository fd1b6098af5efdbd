"""Starting frames of a 3-D solve: along the vessel's centreline, through the contact points, or straight.

A start is a frame per bar (quaternions, :mod:`guidewire.rod.quaternion`); its nodes are the running sum of the bar
vectors, so the closure rows hold exactly at the start. Frames are carried from the clamp by parallel transport along
the start's bar directions (no twist): with a J-tip the start is straight where the rest shape is curved, and the
solve bends it.

- ``initial_nodes`` given: the bar directions of that polyline (``n + 1`` points, the clamp first).
- In a vessel without contacts: the centreline from the entrance (a wire advanced along the lumen), continued straight
  past the far end.
- With contacts that prescribe points: the polyline through the clamp and those points, each piece's bars spread
  evenly along its chord (the nodes then overshoot the points by the wire's slack; the solve closes the gap).
- Otherwise: straight along the clamp's tangent (a free wire's exact answer without rest curvature).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..rod import quaternion as quat
from .scene import Scene3D

FloatArray = NDArray[np.float64]


CENTRELINE_SAMPLE = 0.05
"""Spacing (mm) of the centreline samples over which arc length is measured for the start."""


def along_centreline(vessel: Any, s: FloatArray) -> FloatArray:
    """Points (m, 3) of the vessel's main centreline at arc lengths ``s`` (mm) from the entrance, measured on the
    spline itself (its parameter is the chord length of the given points, shorter than the arc on a bend: nodes
    placed by it would drift off the centreline by the difference, millimetres over a tortuous vessel)."""
    top = float(np.max(s, initial=0.0))
    u = np.linspace(0.0, top, max(2, int(np.ceil(top / CENTRELINE_SAMPLE)) + 1))
    points = vessel.path(u)[0]
    arc = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))))
    while arc[-1] < top:  # (the arc is longer than the parameter: sample on until it covers s)
        extra = np.linspace(u[-1], u[-1] + (top - arc[-1]) + 1.0, 64)[1:]
        more = vessel.path(extra)[0]
        arc = np.concatenate((arc, arc[-1] + np.cumsum(np.linalg.norm(np.diff(np.vstack((points[-1:], more)),
                                                                                axis=0), axis=1))))
        points, u = np.vstack((points, more)), np.concatenate((u, extra))
    return np.column_stack([np.interp(s, arc, points[:, i]) for i in range(3)])


def start_frames(scene: Scene3D, lengths: FloatArray, contact_nodes: NDArray[np.int_],
                 initial_nodes: Any = None) -> FloatArray:
    """Quaternions (n, 4) of the start (see the module docstring)."""
    n = lengths.size
    base = quat.from_frames(scene.base.frame())[0]
    t0 = np.asarray(scene.base.tangent, dtype=float)
    if initial_nodes is not None:
        p = np.asarray(initial_nodes, dtype=float)
        if p.shape != (n + 1, 3) or not np.all(np.isfinite(p)):
            raise ValueError(f"initial_nodes has shape {p.shape}; expected ({n + 1}, 3) finite points (mm), the clamp "
                             "first.")
        directions = np.diff(p, axis=0)
    elif scene.vessel is not None and not scene.contacts:
        directions = np.diff(along_centreline(scene.vessel, np.concatenate(([0.0], np.cumsum(lengths)))), axis=0)
    else:
        directions = np.tile(t0, (n, 1))
        pinned = [(k, c.point) for k, c in zip(contact_nodes, scene.contacts, strict=True) if c.point is not None]
        start_node, start_point = 0, np.asarray(scene.base.point, dtype=float)
        for k, point in pinned:
            if k > start_node:
                chord = np.asarray(point, dtype=float) - start_point
                if np.linalg.norm(chord) > 0.0:
                    directions[start_node:k] = chord
                start_node, start_point = k, np.asarray(point, dtype=float)
        if pinned and start_node < n:
            directions[start_node:] = directions[start_node - 1]
    norms = np.linalg.norm(directions, axis=1, keepdims=True)
    directions = np.where(norms > 0.0, directions / np.where(norms > 0.0, norms, 1.0), t0)
    reverse = np.einsum("ij,ij->i", directions, np.vstack((t0, directions[:-1]))) < -1.0 + 1e-9
    directions[reverse] = np.vstack((t0, directions[:-1]))[reverse]  # (a reversal cannot be transported)
    return quat.transported_frames(base, directions)
