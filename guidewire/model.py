"""The layout-independent part of a scene's program: bar chain, energy, contact nodes, start angles."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from .chain import BarChain, scene_bars
from .energy import EnergyTerms, bending_terms
from .initial_shape import initial_angles as default_initial_angles
from .scene import Scene

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]

HESSIAN_REGULARISATION = 1e-6
"""Relative shift ``δ·max diag`` added to ``hess0`` when no prescribed angle anchors the rotation of the wire (then
the energy Hessian is singular along a rigid rotation about the base)."""


@dataclass(frozen=True)
class Model:
    """What every layout of one scene's program shares.

    Attributes
    ----------
    scene : Scene
        The scene, with ``bars`` and ``scheme`` as solved.
    chain : BarChain
    contact_nodes : ndarray of int, shape (len(scene.contacts),)
        Node of every contact.
    energy : EnergyTerms
        The bending energy in the bar angles.
    hess0 : scipy.sparse.csc_matrix, shape (n, n)
        Its exact constant Hessian (plus a tiny shift when it is singular).
    x0 : ndarray, shape (n,)
        Starting bar angles.
    """

    scene: Scene
    chain: BarChain
    contact_nodes: IntArray
    energy: EnergyTerms
    hess0: sp.csc_matrix
    x0: FloatArray

    @property
    def n(self) -> int:
        """Number of bars."""
        return self.chain.n_bars


def _check_initial(x0: Any, n: int, name: str, shape: tuple[int, ...]) -> FloatArray:
    arr = np.asarray(x0, dtype=float)
    if arr.shape != shape:
        raise ValueError(f"{name} has shape {arr.shape}; expected {shape} for {n} bars.")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or inf; pass finite values.")
    return arr


def build_model(scene: Scene, initial_angles: Any = None, initial_nodes: Any = None) -> Model:
    """Chain, energy and start of ``scene`` (``bars`` and ``scheme`` already applied).

    ``initial_angles`` (shape (n,), rad) or ``initial_nodes`` (shape (n + 1, 2), mm; only bar directions are used)
    replace the default start of :mod:`guidewire.initial_shape`.
    """
    if initial_angles is not None and initial_nodes is not None:
        raise ValueError("pass initial_angles or initial_nodes, not both.")
    wire, contacts = scene.wire, scene.contacts
    lengths, contact_nodes = scene_bars(scene)
    chain = BarChain(np.asarray(scene.base.point, dtype=float), lengths)
    n = chain.n_bars
    angle_ids = [i for i, c in enumerate(contacts) if c.angle is not None]
    stiffness: float | FloatArray = wire.bending_stiffness
    rest = None
    if wire.sections:  # per-bar values at the bar midpoints (a section boundary is always a node)
        props = wire.properties_at(chain.arc_lengths[:-1] + 0.5 * lengths)
        stiffness, rest = props.bending_stiffness, props.rest_curvature
    energy = bending_terms(lengths, stiffness, wire.scheme, scene.base.angle, contact_nodes[angle_ids],
                           np.array([contacts[i].angle for i in angle_ids], dtype=float), rest)
    if initial_angles is not None:
        x0 = _check_initial(initial_angles, n, "initial_angles", (n,))
    elif initial_nodes is not None:
        x0 = chain.angles_from_nodes(_check_initial(initial_nodes, n, "initial_nodes", (n + 1, 2)))
    else:
        x0 = default_initial_angles(scene, chain, contact_nodes)
    hess0 = energy.hessian()
    if not np.any(np.abs(energy.row_sum) > 0.0):  # only differences: rigid rotation is a null direction
        shift = HESSIAN_REGULARISATION * max(float(hess0.diagonal().max(initial=0.0)), 1.0)
        hess0 = sp.csc_matrix(hess0 + shift * sp.identity(n, format="csc"))
    return Model(scene=scene, chain=chain, contact_nodes=contact_nodes, energy=energy, hess0=hess0, x0=x0)
