"""The answer of a 3-D solve: shape, frames, energy split, and the forces and moments that hold the wire.

Forces are read from the program's multipliers (:mod:`guidewire.solve3d.program` gives their meaning): the clamp's
force is the first closure multiplier, a contact's force its row's multiplier, the vessel wall's force at node ``k``
is ``λ_k ∇D`` (normal to the wall, pointing into the lumen, ``λ_k ≥ 0``). The clamp's moment is the derivative of the
energy with respect to a rotation of the clamp's frame (``M · δθ = δE``: the work the clamp does), so force and moment
balance are checks of the answer (:meth:`Solution3D.balance`), not identities.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..rod import quaternion as quat
from ..rod.jet import Jet
from ..rod.strain import joint_strain

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ContactForce3D:
    """A force on the wire: ``kind`` ("lumen", "wall", "contact", "tip" on a node; "crease", where the crease around
    a branch's opening holds a bar: ``node`` is the bar's far end and ``point`` its foot on the bar), the node, its
    point (mm), the unit normal (for the lumen, walls and creases: the direction the wall pushes) and the force
    vector (N)."""

    kind: str
    node: int
    point: FloatArray
    normal: FloatArray
    force: FloatArray

    @property
    def magnitude(self) -> float:
        return float(np.linalg.norm(self.force))

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "node": self.node, "point": self.point.tolist(), "normal": self.normal.tolist(),
                "force_n": self.force.tolist(), "magnitude_n": self.magnitude}


@dataclass(frozen=True)
class Solution3D:
    """One solve's answer (also when it failed: then ``success`` is False and ``status``/``message`` say why).

    Attributes
    ----------
    nodes : ndarray, shape (n + 1, 3)
        Node positions (mm), the clamp first.
    frames : ndarray, shape (n, 3, 3)
        Material frames ``[d1; d2; d3]`` of the bars (``d3`` the tangent).
    quaternions : ndarray, shape (n, 4)
    bending_energy, twist_energy : float
        N·mm.
    twist : ndarray, shape (n,)
        Twist ``τ`` of every joint (rad), the clamp's first.
    forces : list of ContactForce3D
        Every external force but the clamp's (empty for a failed solve).
    clamp_force, clamp_moment : ndarray, shape (3,)
        What the clamp exerts on the wire (N, N·mm).
    """

    success: bool
    status: int
    message: str
    nodes: FloatArray
    frames: FloatArray
    quaternions: FloatArray
    bending_energy: float
    twist_energy: float
    twist: FloatArray
    base_rotation: float
    forces: list[ContactForce3D]
    clamp_force: FloatArray
    clamp_moment: FloatArray
    iterations: int
    rounds: int
    solve_time_s: float
    lengths: FloatArray
    extras: dict[str, Any] = field(default_factory=dict)

    @property
    def energy(self) -> float:
        return self.bending_energy + self.twist_energy

    @property
    def n_bars(self) -> int:
        return int(self.lengths.size)

    @property
    def tip_point(self) -> FloatArray:
        return self.nodes[-1]

    @property
    def tip_direction(self) -> FloatArray:
        return self.frames[-1, 2]

    @property
    def tip_roll(self) -> float:
        """The tip frame's roll (rad): the clamp's rotation plus the twist summed along the wire, i.e. the angle of
        the tip's ``d1`` about the tangent against the clamp's zero-rotation ``d1`` carried along by parallel
        transport."""
        return float(self.base_rotation + np.sum(self.twist))

    @property
    def entrance_force(self) -> float:
        """The clamp's force along the entrance tangent (N), the axial force at the entrance: > 0 pushes the wire
        in. (The push a hand needs is :attr:`push`.)"""
        return float(self.clamp_force @ self.frames_base_tangent)

    @property
    def push(self) -> float:
        """The push (N) needed to insert the wire further through a frictionless entrance: ``dE/dL``, the energy's
        rate with the inserted length. It is the axial force (:attr:`entrance_force`) less the configurational force
        of the moment the wire carries through the entrance, ``|M⊥|²/(2 EI) + M∥²/(2 GJ)`` (bending about the two
        axes across the tangent, twist about it: the energy per length of the wire that enters; the planar
        ``Solution.entrance_force``'s ``M₀²/(2EI)``). Tested against finite differences of the energy; 0 for a
        failed solve."""
        if not self.success:
            return 0.0
        tangent = self.frames_base_tangent
        twist = float(self.clamp_moment @ tangent)
        bending = self.clamp_moment - twist * tangent
        ei, gj = self.extras["entrance_stiffness"]
        return self.entrance_force - float(bending @ bending) / (2.0 * ei) - twist**2 / (2.0 * gj)

    @property
    def entrance_torque(self) -> float:
        """The clamp's moment about the entrance tangent (N·mm)."""
        return float(self.clamp_moment @ self.frames_base_tangent)

    def tangential_contact_force(self) -> float:
        """The net force (N) the wall and lumen contacts at the wire's interior nodes exert along it, against the push
        (positive: they resist a further insertion). Zero for a frictionless wire on a smooth wall, which touches it
        along its normal, and over the crease around a branch's opening, which holds a bar at its foot, normal to it
        (:mod:`guidewire.vessel3d.crease`). The tip's contact is left out (a tip pressed head-on into a wall is pushed
        back along the wire by right). 0 for a failed solve."""
        total = 0.0
        for f in self.forces:
            if f.kind == "crease" and not np.array_equal(f.point, self.nodes[f.node]):  # (inside a bar: along it)
                total -= float(f.force @ self.frames[f.node - 1, 2])
                continue
            if f.kind not in ("lumen", "wall", "crease") or not 0 < f.node < self.n_bars:
                continue
            t = self.frames[f.node - 1, 2] + self.frames[f.node, 2]
            total -= float(f.force @ t) / float(np.linalg.norm(t))
        return total

    @property
    def frames_base_tangent(self) -> FloatArray:
        return np.asarray(self.extras["base_tangent"], dtype=float)

    def balance(self) -> tuple[float, float]:
        """``(|ΣF|, |ΣM|)``: the residual force (N) and moment about the clamp (N·mm) of every external load."""
        total_f = self.clamp_force.copy()
        total_m = self.clamp_moment.copy()
        origin = self.nodes[0]
        for f in self.forces:
            total_f += f.force
            total_m += np.cross(f.point - origin, f.force)
        total_m += self.extras.get("contact_moment", np.zeros(3))
        return float(np.linalg.norm(total_f)), float(np.linalg.norm(total_m))

    def to_dict(self) -> dict[str, Any]:
        return {"success": self.success, "status": self.status, "message": self.message,
                "energy": self.energy, "bending_energy": self.bending_energy, "twist_energy": self.twist_energy,
                "nodes": self.nodes.tolist(), "frames": self.frames.tolist(), "bar_lengths": self.lengths.tolist(),
                "tip": {"point": self.tip_point.tolist(), "direction": self.tip_direction.tolist(),
                        "roll": self.tip_roll, "d1": self.frames[-1, 0].tolist()},
                "entrance_force_n": self.entrance_force, "push_n": self.push,
                "tangential_contact_force_n": self.tangential_contact_force(),
                "entrance_torque_nmm": self.entrance_torque,
                "clamp_force_n": self.clamp_force.tolist(), "clamp_moment_nmm": self.clamp_moment.tolist(),
                "contacts": [f.to_dict() for f in self.forces], "iterations": self.iterations,
                "solve_time_s": self.solve_time_s}


def clamp_moment(base: FloatArray, q1: FloatArray, bending_weight: float, twist_weight: float,
                 rest: float) -> FloatArray:
    """``∂E₀/∂θ`` (N·mm, world axes) of the clamp's joint energy under a rotation ``θ`` of the clamp frame,
    ``q_B(θ) = (1, θ/2) ⊗ q_B`` to first order: the moment the clamp exerts on the wire."""
    slope = 0.5 * np.stack([np.array(quat.multiply(e, base)) for e in np.eye(4)[1:]], axis=1)  # (4, 3)
    qa = [Jet.affine(np.array([base[c]]), slope[c][None, :]) for c in range(4)]
    qb = [Jet.constant(np.array([q1[c]]), 3) for c in range(4)]
    k1, k2, tau = joint_strain(quat.relative(qa, qb), "mid")
    e = (k1.square() + (k2 - rest).square()) * bending_weight + tau.square() * twist_weight
    return e.grad[0]


def half_joint_moment(star: FloatArray, q: FloatArray, weight: float, rest: float, twist_weight: float,
                      before: bool) -> FloatArray:
    """``∂E/∂θ`` of a half joint under a rotation of its prescribed frame ``q*``: the moment a contact that holds the
    tangent exerts on the wire (N·mm, world axes)."""
    slope = 0.5 * np.stack([np.array(quat.multiply(e, star)) for e in np.eye(4)[1:]], axis=1)
    qs = [Jet.affine(np.array([star[c]]), slope[c][None, :]) for c in range(4)]
    qk = [Jet.constant(np.array([q[c]]), 3) for c in range(4)]
    pair, axes = ((qk, qs), "a") if before else ((qs, qk), "b")
    k1, k2, tau = joint_strain(quat.relative(*pair), axes)
    return ((k1.square() + (k2 - rest).square()) * weight + tau.square() * twist_weight).grad[0]
