"""A scene as a nonlinear program for :func:`sqp.minimize`: energy, constraint rows, start, bookkeeping.

Variables: the absolute bar angles ``φ`` (n,) of :mod:`guidewire.chain`. Objective: the bending energy of
:mod:`guidewire.energy` (N·mm), quadratic in ``φ``; its exact constant Hessian is passed as ``hess0``.

Constraint blocks, in this order, each present only when the scene needs it ("leave out what a scene does not
need"):

``position``  (SLSQP ``eq`` dict; Eqs. 20–21)
    ``p_k(φ) − P = 0``: two rows (x, y) per contact with a point, in contact order. Multiplier = the force (N) the
    contact exerts on the wire.
``angle``  (``LinearConstraint``, lb = ub; Eqs. 16–18; ``scheme = "paper"`` only)
    ``φ_k = θ*``: one row per contact with an angle, on the bar ending at the contact node. Multiplier = the
    moment (N·mm, counter-clockwise) the contact exerts on the wire. In the second-order scheme prescribed angles
    are energy terms and this block does not exist.
``wall``  (SLSQP ``ineq`` dict, one block per wall; Eqs. 23–24)
    ``offset/|a| − â · p_k ≥ 0`` for nodes ``k = 1..n`` (the base node is fixed and checked once, before solving),
    a distance in mm. Multiplier = the magnitude (N) of the wall's push on the node, along ``−â``.
``relative_angle``  (``LinearConstraint``, two-sided; Eq. 19, only with ``wire.max_relative_angle``)
    ``−b₂ ≤ Δθ_node ≤ b₂`` for every node with a joint: the paper's bounds on ``Δθ``, which in absolute angles are
    differences of neighbours (still exact and linear).

No variable bounds are used. Multiplier signs follow :func:`sqp.minimize`: ``∇E = Σ_i J_iᵀ λ_i``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint

from .chain import BarChain, place_bars
from .energy import EnergyTerms, bending_terms
from .initial_shape import initial_angles as default_initial_angles
from .scene import SCHEMES, Scene

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]

HESSIAN_REGULARISATION = 1e-6
"""Relative shift ``δ·max diag`` added to ``hess0`` when no prescribed angle anchors the rotation of the wire (then
the energy Hessian is singular along a rigid rotation about the base)."""


@dataclass(frozen=True)
class ConstraintBlock:
    """Which entry of the ``constraints`` list holds what.

    Attributes
    ----------
    kind : {"position", "angle", "wall", "relative_angle"}
    index : int
        Position in ``Formulation.constraints`` (and in ``res.constraint_multipliers``).
    members : tuple of int
        Contact indices (``position``: one per contact, two rows each; ``angle``: one row each), the wall index
        (``wall``), or the nodes (``relative_angle``).
    nodes : ndarray of int
        The node of every row.
    """

    kind: str
    index: int
    members: tuple[int, ...]
    nodes: IntArray

    @property
    def rows(self) -> int:
        """Number of constraint rows."""
        return int(self.nodes.size)


DENSE_BARS = 300
"""Up to this many bars Hessians are returned as dense arrays (cheaper than scipy.sparse's per-call overhead)."""


def _diagonal(d: FloatArray) -> Any:
    """A diagonal matrix: dense for small chains, sparse CSC for long ones."""
    return np.diag(d) if d.size <= DENSE_BARS else sp.diags(d, format="csc")


def _position_constraint(chain: BarChain, nodes: IntArray, targets: FloatArray) -> dict[str, Any]:
    """``p_k(φ) − P`` for the contact nodes, rows (x₁, y₁, x₂, y₂, ...)."""

    def fun(phi: FloatArray) -> FloatArray:
        return (chain.nodes(phi)[nodes] - targets).ravel()

    def jac(phi: FloatArray) -> FloatArray:
        return chain.node_jacobian(phi, nodes).reshape(2 * nodes.size, chain.n_bars)

    def hess(phi: FloatArray, v: FloatArray) -> Any:
        return _diagonal(chain.node_hessian_diagonal(phi, nodes, np.reshape(v, (-1, 2))))

    return {"type": "eq", "fun": fun, "jac": jac, "hess": hess}


def _wall_constraint(
    chain: BarChain, normal: tuple[float, float], offset: float, nodes: IntArray
) -> dict[str, Any]:
    """``offset − n̂ · p_k ≥ 0`` for the nodes ``k`` in ``nodes`` (unit normal, mm)."""
    nx, ny = normal
    n_hat = np.array([nx, ny])
    mask = np.arange(chain.n_bars)[None, :] < nodes[:, None]  # bar j+1 ≤ node k

    def fun(phi: FloatArray) -> FloatArray:
        return offset - chain.nodes(phi)[nodes] @ n_hat

    def jac(phi: FloatArray) -> FloatArray:
        row = chain.lengths * (-nx * np.sin(phi) + ny * np.cos(phi))  # n̂ · ∂p/∂φ_j
        return -(mask * row[None, :])

    def hess(phi: FloatArray, v: FloatArray) -> Any:
        return _diagonal(chain.node_hessian_diagonal(phi, nodes, -np.outer(v, n_hat)))

    return {"type": "ineq", "fun": fun, "jac": jac, "hess": hess}


@dataclass(frozen=True)
class Formulation:
    """The nonlinear program of one scene (see the module docstring for the blocks).

    Attributes
    ----------
    scene : Scene
        The scene, with ``bars`` and ``scheme`` as solved.
    scheme : str
    chain : BarChain
    contact_nodes : ndarray of int, shape (len(scene.contacts),)
    energy : EnergyTerms
    blocks : tuple of ConstraintBlock
    constraints : tuple
        Arguments for ``sqp.minimize(constraints=...)``, in the order of ``blocks``.
    hess0 : ndarray, shape (n, n)
        The exact energy Hessian (plus a tiny shift when it is singular).
    x0 : ndarray, shape (n,)
        Starting bar angles.
    """

    scene: Scene
    scheme: str
    chain: BarChain
    contact_nodes: IntArray
    energy: EnergyTerms
    blocks: tuple[ConstraintBlock, ...]
    constraints: tuple[Any, ...]
    hess0: FloatArray
    x0: FloatArray

    @property
    def n(self) -> int:
        """Number of variables (bars)."""
        return self.chain.n_bars

    def fun(self, phi: FloatArray) -> float:
        """Bending energy in N·mm."""
        return self.energy.value(phi)

    def jac(self, phi: FloatArray) -> FloatArray:
        """Gradient of the energy, shape (n,)."""
        return self.energy.gradient(phi)

    def hess(self, phi: FloatArray) -> Any:
        """Exact Hessian of the energy, shape (n, n): constant and tridiagonal (``hess0``; dense up to
        :data:`DENSE_BARS` bars, sparse CSC above)."""
        return self._dense_hess0 if self.n <= DENSE_BARS else self.hess0

    @cached_property
    def _dense_hess0(self) -> FloatArray:
        return self.hess0.toarray()

    def block(self, kind: str) -> tuple[ConstraintBlock, ...]:
        """The blocks of one kind (possibly none)."""
        return tuple(b for b in self.blocks if b.kind == kind)

    def arguments(self) -> dict[str, Any]:
        """Keyword arguments for ``sqp.minimize`` (and, without ``hess0``, ``scipy.optimize.minimize``)."""
        return {
            "fun": self.fun, "x0": self.x0, "jac": self.jac, "bounds": None,
            "constraints": list(self.constraints), "hess0": self.hess0,
        }

    def violations(self, phi: FloatArray) -> FloatArray:
        """Constraint violation of every row at ``phi`` (≥ 0), concatenated in block order."""
        parts = [np.zeros(0)]
        for con in self.constraints:
            if isinstance(con, LinearConstraint):
                ax = con.A @ phi
                parts.append(np.maximum(np.maximum(con.lb - ax, ax - con.ub), 0.0))
            else:
                c = np.asarray(con["fun"](phi), dtype=float)
                parts.append(np.abs(c) if con["type"] == "eq" else np.maximum(-c, 0.0))
        return np.concatenate(parts)


WALL_WORKING_DISTANCE = 0.25
"""Nodes of the start closer to a wall than this fraction of the wire length get a wall row in the working set."""


def near_wall_nodes(nodes: FloatArray, normal: tuple[float, float], offset: float, length: float) -> IntArray:
    """Nodes 1..n within ``WALL_WORKING_DISTANCE · L`` of the wall ``n̂·p ≤ offset`` (at least the closest one)."""
    gap = offset - nodes[1:] @ np.asarray(normal)
    near = np.flatnonzero(gap <= WALL_WORKING_DISTANCE * length) + 1
    return near if near.size else np.array([int(np.argmin(gap)) + 1])


def wall_gaps(chain: BarChain, phi: FloatArray, walls: Any) -> FloatArray:
    """``offset − n̂·p_k`` for every wall and node 1..n, shape (walls, n) (negative: violated)."""
    pts = chain.nodes(phi)[1:]
    return np.array([w.unit()[1] - pts @ np.asarray(w.unit()[0]) for w in walls]).reshape(len(walls), -1)


def _check_initial(x0: Any, n: int, name: str, shape: tuple[int, ...]) -> FloatArray:
    arr = np.asarray(x0, dtype=float)
    if arr.shape != shape:
        raise ValueError(f"{name} has shape {arr.shape}; expected {shape} for {n} bars.")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or inf; pass finite values.")
    return arr


def formulate(
    scene: Scene,
    *,
    scheme: str | None = None,
    bars: int | None = None,
    initial_angles: Any = None,
    initial_nodes: Any = None,
    wall_nodes: Any = None,
) -> Formulation:
    """Turn ``scene`` into the arguments of :func:`sqp.minimize`.

    Parameters
    ----------
    scene : Scene
    scheme : {"second_order", "paper"}, optional
        Overrides ``scene.wire.scheme``.
    bars : int, optional
        Overrides ``scene.wire.bars``.
    initial_angles : array_like, shape (n,), optional
        Starting bar angles (rad).
    initial_nodes : array_like, shape (n + 1, 2), optional
        Starting node positions (base first); only their directions are used.
    wall_nodes : "near" or sequence of int arrays, optional
        For every wall, the nodes that get a row (default: nodes 1..n). ``"near"``: the nodes of the start within
        :data:`WALL_WORKING_DISTANCE` ``× L`` of the wall (the paper's remark that only a few points of a line contact
        need constraining). :func:`guidewire.solve` uses ``"near"`` and adds any node found violating a wall, then
        solves again from the answer, so no node of the returned shape violates a wall.

    Returns
    -------
    Formulation

    Raises
    ------
    ValueError
        For an unknown scheme, a bad start, or an infeasible scene (:meth:`Scene.check_feasible`).
    """
    if scheme is not None:
        if scheme not in SCHEMES:
            raise ValueError(f"scheme is {scheme!r}; expected one of {', '.join(map(repr, SCHEMES))}.")
        scene = scene.with_scheme(scheme)
    if bars is not None:
        scene = scene.with_bars(bars)
    if initial_angles is not None and initial_nodes is not None:
        raise ValueError("pass initial_angles or initial_nodes, not both.")
    scene.check_feasible()
    wire, contacts = scene.wire, scene.contacts
    lengths, contact_nodes = place_bars(wire.length, wire.bars, [c.s for c in contacts])
    chain = BarChain(np.asarray(scene.base.point, dtype=float), lengths)
    n = chain.n_bars

    angle_ids = [i for i, c in enumerate(contacts) if c.angle is not None]
    angle_nodes = contact_nodes[angle_ids]
    angle_values = np.array([contacts[i].angle for i in angle_ids], dtype=float)
    energy = bending_terms(lengths, wire.bending_stiffness, wire.scheme, scene.base.angle, angle_nodes, angle_values)

    if initial_angles is not None:
        x0 = _check_initial(initial_angles, n, "initial_angles", (n,))
    elif initial_nodes is not None:
        x0 = chain.angles_from_nodes(_check_initial(initial_nodes, n, "initial_nodes", (n + 1, 2)))
    else:
        x0 = default_initial_angles(scene, chain, contact_nodes)

    blocks: list[ConstraintBlock] = []
    constraints: list[Any] = []

    def add(kind: str, members: list[int] | tuple[int, ...], nodes: IntArray, con: Any) -> None:
        blocks.append(ConstraintBlock(kind, len(constraints), tuple(int(m) for m in members), nodes))
        constraints.append(con)

    pos_ids = [i for i, c in enumerate(contacts) if c.point is not None]
    if pos_ids:
        targets = np.array([contacts[i].point for i in pos_ids], dtype=float)
        nodes = contact_nodes[pos_ids]
        add("position", pos_ids, np.repeat(nodes, 2), _position_constraint(chain, nodes, targets))
    if wire.scheme == "paper" and angle_ids:
        rows = np.zeros((len(angle_ids), n))
        rows[np.arange(len(angle_ids)), angle_nodes - 1] = 1.0
        add("angle", angle_ids, angle_nodes, LinearConstraint(rows, angle_values, angle_values))
    start_nodes = chain.nodes(x0)
    for j, wall in enumerate(scene.walls):
        normal, offset = wall.unit()
        if wall_nodes is None:
            nodes = np.arange(1, n + 1)
        elif isinstance(wall_nodes, str) and wall_nodes == "near":
            nodes = near_wall_nodes(start_nodes, normal, offset, wire.length)
        else:
            nodes = np.unique(np.asarray(wall_nodes[j], dtype=int))
        add("wall", (j,), nodes, _wall_constraint(chain, normal, offset, nodes))
    if wire.max_relative_angle is not None:
        node_rows, node_offsets = energy.node_rows(n + 1)
        joint_nodes = np.unique(energy.node)
        b2 = wire.max_relative_angle
        lin = LinearConstraint(node_rows[joint_nodes], node_offsets[joint_nodes] - b2, node_offsets[joint_nodes] + b2)
        add("relative_angle", tuple(joint_nodes), joint_nodes, lin)

    hess0 = energy.hessian()
    if not np.any(np.abs(energy.row_sum) > 0.0):  # only differences: rigid rotation is a null direction
        hess0 = hess0 + HESSIAN_REGULARISATION * max(float(hess0.diagonal().max(initial=0.0)), 1.0) * sp.identity(
            n, format="csc")

    return Formulation(
        scene=scene, scheme=wire.scheme, chain=chain, contact_nodes=contact_nodes, energy=energy,
        blocks=tuple(blocks), constraints=tuple(constraints), hess0=hess0, x0=x0,
    )


