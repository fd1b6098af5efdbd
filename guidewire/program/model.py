"""The layout-independent part of a scene's program: bar chain, energy, contact nodes, start angles."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from ..chain.kinematics import BarChain, scene_bars
from ..energy import EnergyTerms, bending_terms
from ..initial_shape import initial_angles as default_initial_angles
from ..scene.scene import Scene

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
    keys: tuple[Any, ...] = field(default=(), compare=False, repr=False)
    """What the bar layout and the energy were built from (:func:`_model_keys`), for :class:`ModelReuse`."""

    @property
    def n(self) -> int:
        """Number of bars."""
        return self.chain.n_bars


@dataclass
class ModelReuse:
    """The last model :func:`build_model` built through this object, so that the next scene's build keeps what the
    two scenes share (a quasi-static sequence: consecutive scenes differ in a few targets).

    What is kept, each only when everything it is made of is unchanged (compared exactly, no tolerance):

    - the bar layout (lengths and contact nodes: :func:`guidewire.chain.scene_bars`) when the wire, its bar count
      and the contacts' arc lengths and kinds are the same, and the chain when the base point is the same too;
    - the energy (:class:`EnergyTerms`) when, in addition, the scheme, the base angle and the prescribed contact
      angles are the same, and its Hessian ``hess0`` when only those angles' *values* moved (the Hessian depends on
      which tangents are prescribed, not on their values).

    So a reused model is the model a fresh build gives, bit for bit; only its start ``x0`` is always new. One object
    serves one sequence of solves (it is not shared between threads).

    Attributes
    ----------
    model : Model or None
        The last model built (None before the first).
    hits : dict of str to int
        How often each part was kept: ``"layout"``, ``"energy"``, ``"hessian"``.
    """

    model: Model | None = None
    hits: dict[str, int] = field(default_factory=lambda: {"layout": 0, "energy": 0, "hessian": 0})


def _check_initial(x0: Any, n: int, name: str, shape: tuple[int, ...]) -> FloatArray:
    arr = np.asarray(x0, dtype=float)
    if arr.shape != shape:
        raise ValueError(f"{name} has shape {arr.shape}; expected {shape} for {n} bars.")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or inf; pass finite values.")
    return arr


def _model_keys(scene: Scene) -> tuple[Any, ...]:
    """(layout, energy structure, energy values) of ``scene``: what its bar layout, the structure of its energy
    (hence ``hess0``) and the energy's prescribed angles are made of."""
    contacts = scene.contacts
    layout = (scene.wire, tuple((c.s, c.point is None, c.angle is None) for c in contacts))
    structure = (scene.base.angle is None,)
    values = (scene.base.angle, tuple(c.angle for c in contacts))
    return layout, structure, values


def _shared_parts(old: tuple[Any, ...], new: tuple[Any, ...]) -> list[str]:
    """What a model with keys ``old`` can give one with keys ``new``: ``[]``, ``["layout"]``, ``["layout",
    "hessian"]`` (the prescribed angles' values moved) or ``["layout", "energy"]``."""
    if old[0] != new[0]:
        return []
    if old[1] != new[1]:
        return ["layout"]
    return ["layout", "energy"] if old[2] == new[2] else ["layout", "hessian"]


def build_model(scene: Scene, initial_angles: Any = None, initial_nodes: Any = None,
                reuse: ModelReuse | None = None) -> Model:
    """Chain, energy and start of ``scene`` (``bars`` and ``scheme`` already applied).

    ``initial_angles`` (shape (n,), rad) or ``initial_nodes`` (shape (n + 1, 2), mm; only bar directions are used)
    replace the default start of :mod:`guidewire.initial_shape`. With ``reuse``, the parts its last model shares
    with ``scene`` are kept (see :class:`ModelReuse`) and the model built becomes its last one.
    """
    if initial_angles is not None and initial_nodes is not None:
        raise ValueError("pass initial_angles or initial_nodes, not both.")
    keys = _model_keys(scene)
    prev = reuse.model if reuse is not None else None
    kept = [] if prev is None else _shared_parts(prev.keys, keys)
    if reuse is not None:
        for part in kept:
            reuse.hits[part] += 1
    chain, contact_nodes = _chain(scene, prev if "layout" in kept else None)
    n = chain.n_bars
    if prev is not None and "energy" in kept:
        energy, hess0 = prev.energy, prev.hess0
    else:
        energy = _energy(scene, chain, contact_nodes)
        hess0 = prev.hess0 if prev is not None and "hessian" in kept else _hessian(energy, n)
    x0 = _start(scene, chain, contact_nodes, initial_angles, initial_nodes)
    model = Model(scene=scene, chain=chain, contact_nodes=contact_nodes, energy=energy, hess0=hess0, x0=x0,
                  keys=keys)
    if reuse is not None:
        reuse.model = model
    return model


def _chain(scene: Scene, prev: Model | None) -> tuple[BarChain, IntArray]:
    """The bar chain and contact nodes of ``scene``: ``prev``'s layout when given (it is the same), on the scene's
    base point."""
    base = np.asarray(scene.base.point, dtype=float)
    if prev is not None:
        lengths, contact_nodes = prev.chain.lengths, prev.contact_nodes
        chain = prev.chain if np.array_equal(prev.chain.base_point, base) else BarChain(base, lengths)
    else:
        lengths, contact_nodes = scene_bars(scene)
        chain = BarChain(base, lengths)
    return chain, contact_nodes


def _start(scene: Scene, chain: BarChain, contact_nodes: IntArray, initial_angles: Any,
           initial_nodes: Any) -> FloatArray:
    """The start angles: the given ones, the directions of the given nodes, or the default start."""
    n = chain.n_bars
    if initial_angles is not None:
        return _check_initial(initial_angles, n, "initial_angles", (n,))
    if initial_nodes is not None:
        return chain.angles_from_nodes(_check_initial(initial_nodes, n, "initial_nodes", (n + 1, 2)))
    return default_initial_angles(scene, chain, contact_nodes)


def _energy(scene: Scene, chain: BarChain, contact_nodes: IntArray) -> EnergyTerms:
    """The bending energy of ``scene`` on ``chain`` (:func:`guidewire.energy.bending_terms`)."""
    wire, contacts, lengths = scene.wire, scene.contacts, chain.lengths
    angle_ids = [i for i, c in enumerate(contacts) if c.angle is not None]
    stiffness: float | FloatArray = wire.bending_stiffness
    rest = None
    if wire.sections:  # per-bar values at the bar midpoints (a section boundary is always a node)
        props = wire.properties_at(chain.arc_lengths[:-1] + 0.5 * lengths)
        stiffness, rest = props.bending_stiffness, props.rest_curvature
    return bending_terms(lengths, stiffness, wire.scheme, scene.base.angle, contact_nodes[angle_ids],
                         np.array([contacts[i].angle for i in angle_ids], dtype=float), rest)


def _hessian(energy: EnergyTerms, n: int) -> sp.csc_matrix:
    """``energy``'s constant Hessian, shifted by :data:`HESSIAN_REGULARISATION` when it is singular."""
    hess0 = energy.hessian()
    if not np.any(np.abs(energy.row_sum) > 0.0):  # only differences: rigid rotation is a null direction
        shift = HESSIAN_REGULARISATION * max(float(hess0.diagonal().max(initial=0.0)), 1.0)
        hess0 = sp.csc_matrix(hess0 + shift * sp.identity(n, format="csc"))
    return hess0
