"""Bending and twist energy of a framed bar chain in 3D, with its exact gradient and block-tridiagonal Hessian.

Every bar ``k`` carries a material frame (a quaternion ``q_k``, :mod:`guidewire.rod.quaternion`, in the chart
``q_k = q⁰_k + E_k ω_k``); the base carries the clamp's frame ``q_B`` (tangent and rotation angle imposed). The terms
are those of the planar second-order scheme (:func:`guidewire.energy.bending_terms`: the same joints, nodes, weights
``c = EI / (2 w)``, series stiffness across a section boundary, rest angles ``Δθ⁰ = Σ κ⁰ l / 2`` over the half bars a
term covers), with the joint angle replaced by the strains of :mod:`guidewire.rod.strain`::

    E = Σ_joints  c_EI |κ − (0, Δθ⁰)|²  +  c_GJ τ²        joints: clamp (q_B, q_1), interior (q_k, q_{k+1})
      + Σ_halves  c_EI |κ_half − (0, Δθ⁰)|²               at a node with a prescribed tangent t*

``κ`` is the bending vector in material axes (mid-frame of the joint), ``τ`` the twist (DER: transported ``d1``
against the next ``d1``); the rest curvature bends a bar towards its ``d1`` (Darboux vector ``κ⁰ d2``), so a planar
chain with ``d2`` normal to its plane is the 2-D model term for term. A node with a prescribed tangent splits its
bending into two half joints against a frame ``q*`` with ``d3 = t*`` (as the 2-D scheme does), each in its bar's own
axes (so the arbitrary roll of ``q*`` drops out); the twist across that node stays one term between the two bars.

Cost: one pass over the joints with 4-variable jets (:mod:`guidewire.rod.jet`) in the relative rotation ``r``,
carried to the joint's six chart variables by the chain rule, O(n); the Hessian is block tridiagonal with 3 × 3
blocks (a joint couples its two bars only).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..energy import bending_terms
from . import quaternion as quat
from .jet import Jet
from .strain import joint_strain

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]


@dataclass(frozen=True)
class EnergyParts:
    """The energy at one point: total and split, gradient per bar and the Hessian's blocks.

    Attributes
    ----------
    bending, twist : float
        N·mm.
    gradient : ndarray, shape (n, 3)
        ``∂E/∂ω_k`` (N·mm).
    diagonal : ndarray, shape (n, 3, 3)
        ``∂²E/∂ω_k²``.
    off_diagonal : ndarray, shape (n − 1, 3, 3)
        ``∂²E/∂ω_k ∂ω_{k+1}``.
    """

    bending: float
    twist: float
    gradient: FloatArray
    diagonal: FloatArray
    off_diagonal: FloatArray

    @property
    def total(self) -> float:
        return self.bending + self.twist


@dataclass(frozen=True)
class StrainEnergy:
    """The terms of a clamped rod (see the module docstring), built once per bar layout.

    Attributes
    ----------
    lengths : ndarray, shape (n,)
    base : ndarray, shape (4,)
        Clamp frame ``q_B``.
    joint_bending, joint_twist, joint_rest : ndarray, shape (n,)
        Per full joint ``j`` (``j = 0`` the clamp between ``q_B`` and bar 1, ``j ≥ 1`` between bars ``j`` and
        ``j + 1`` in 1-based numbering): ``c_EI`` (0 at a node with a prescribed tangent), ``c_GJ`` (N·mm) and
        ``Δθ⁰`` (rad).
    half_bar, half_side, half_weight, half_rest, half_twist, half_frame : ndarrays, shape (h,) / (h, 4)
        Half joints at prescribed tangents: the bar (0-based), ``+1`` for the bar before the node (bar → t*),
        ``−1`` for the bar after it (t* → bar), ``c_EI``, ``Δθ⁰``, ``c_GJ`` (0 unless the contact also holds the
        roll: then ``GJ / l`` of the bar, a half joint, and the interior twist term at that node is dropped) and the
        frame ``q*``.
    """

    lengths: FloatArray
    base: FloatArray
    joint_bending: FloatArray
    joint_twist: FloatArray
    joint_rest: FloatArray
    half_bar: IntArray
    half_side: FloatArray
    half_weight: FloatArray
    half_rest: FloatArray
    half_twist: FloatArray
    half_frame: FloatArray

    @classmethod
    def build(cls, lengths: FloatArray, bending_stiffness: float | FloatArray, twist_stiffness: float | FloatArray,
              base_frame: FloatArray, rest_curvature: FloatArray | None = None,
              tangent_nodes: IntArray | None = None, tangents: FloatArray | None = None,
              normals: FloatArray | None = None) -> StrainEnergy:
        """Terms for bar ``lengths`` (mm), ``EI`` and ``GJ`` (N·mm², scalar or per bar), the clamp's frame (a
        quaternion, or rows ``[d1; d2; d3]``), ``κ⁰`` per bar (1/mm) and prescribed unit ``tangents`` (m, 3) at
        ``tangent_nodes`` (1..n); a row of ``normals`` (m, 3) that is finite also holds the roll there (the
        material ``d1``), a row of NaN leaves it free."""
        lengths = np.asarray(lengths, dtype=float)
        n = lengths.size
        base = np.asarray(base_frame, dtype=float)
        base = quat.from_frames(base)[0] if base.shape == (3, 3) else quat.normalised(base)[0]
        nodes = np.zeros(0, dtype=int) if tangent_nodes is None else np.asarray(tangent_nodes, dtype=int)
        t_star = np.zeros((0, 3)) if tangents is None else np.asarray(tangents, dtype=float).reshape(-1, 3)
        bend = bending_terms(lengths, bending_stiffness, "second_order", 0.0, nodes, np.zeros(nodes.size),
                             rest_curvature)
        twist = bending_terms(lengths, twist_stiffness, "second_order", 0.0, [], [])
        left, right = _columns(bend)
        rest = bend.rest_angles
        joint_bending, joint_rest = np.zeros(n), np.zeros(n)
        full = right >= 0
        full &= (left >= 0) | (bend.node == 0)
        joint_bending[right[full]] = bend.weight[full]
        joint_rest[right[full]] = rest[full]
        half = ~full
        half_bar = np.where(left >= 0, left, right)[half]
        half_side = np.where(left >= 0, 1.0, -1.0)[half]
        d1 = np.full(t_star.shape, np.nan) if normals is None else np.asarray(normals, dtype=float).reshape(-1, 3)
        frames = {int(k): quat.from_frames(quat.frame_from_tangent(t, None if np.isnan(h).any() else h))[0]
                  for k, t, h in zip(nodes, t_star, d1, strict=True)}
        held = {int(k) for k, h in zip(nodes, d1, strict=True) if not np.isnan(h).any()}
        half_frame = np.array([frames[int(k)] for k in bend.node[half]]).reshape(-1, 4)
        _, t_right = _columns(twist)
        joint_twist = np.zeros(n)
        joint_twist[t_right] = twist.weight
        gj = np.broadcast_to(np.asarray(twist_stiffness, dtype=float), (n,))
        rolls = np.isin(bend.node[half], list(held))
        half_twist = np.where(rolls, gj[half_bar] / lengths[half_bar], 0.0)
        interior_held = np.array(sorted(k for k in held if k < n), dtype=int)
        joint_twist[interior_held] = 0.0  # (joint j = node j between bars j and j+1: two half twists instead)
        return cls(lengths, base, joint_bending, joint_twist, joint_rest, half_bar.astype(int), half_side,
                   bend.weight[half], rest[half], half_twist, half_frame)

    @property
    def n(self) -> int:
        return int(self.lengths.size)

    def aligned(self, q: FloatArray) -> StrainEnergy:
        """The same terms with every prescribed frame ``q*`` signed like its bar's frame in ``q`` (n, 4): ``q*`` and
        ``−q*`` are one frame, but the twist ``2 atan2(rz, r0)`` of ``q̄ ⊗ q*`` is measured on the branch ``r0 > 0``."""
        if not self.half_bar.size:
            return self
        sign = np.where(np.einsum("ij,ij->i", self.half_frame, q[self.half_bar]) < 0.0, -1.0, 1.0)
        return replace(self, half_frame=self.half_frame * sign[:, None])

    def evaluate(self, q0: FloatArray, basis: FloatArray, omega: FloatArray, derivatives: bool = True) -> EnergyParts:
        """Energy at ``q_k = q0_k + basis_k ω_k`` (shapes (n, 4), (n, 4, 3), (n, 3))."""
        q = q0 + np.einsum("kij,kj->ki", basis, omega)
        # full joints: the strains as jets in the four components of r = q̄_a ⊗ q_b, carried to the joint's
        # variables (ω_left, ω_right) by the chain rule (r is bilinear in the two frames, each affine in its ω): the
        # jets then hold 4 × 4 Hessians instead of 6 × 6; the clamp's left side is a constant
        left_value = np.vstack((self.base, q[:-1]))
        left_slope = np.concatenate((np.zeros((1, 4, 3)), basis[:-1]))
        r, jac_left, jac_right = quat.relative_jacobians(left_value, left_slope, q, basis)
        k1, k2, tau = joint_strain(Jet.variables(r), "mid")
        bend = (k1.square() + (k2 - self.joint_rest).square()) * self.joint_bending
        twist = tau.square() * self.joint_twist
        joint = bend + twist
        bending = float(bend.value.sum())
        twisting = float(twist.value.sum())
        grad_left = np.einsum("mi,mia->ma", joint.grad, jac_left)
        grad_right = np.einsum("mi,mia->ma", joint.grad, jac_right)
        # Hessian: Jᵀ H J over (ω_left, ω_right), plus Σ_i ∂E/∂r_i ∂²r_i, whose only block is the cross one
        # (∂²r/∂ω_left∂ω_right = Σ_jk RELATIVE_ijk E_left,j ⊗ E_right,k)
        h_jr = joint.hess @ jac_right
        weights = np.einsum("mi,ijk->mjk", joint.grad, quat.RELATIVE)
        cross = jac_left.transpose(0, 2, 1) @ h_jr + left_slope.transpose(0, 2, 1) @ (weights @ basis)
        gradient = grad_right.copy()
        gradient[:-1] += grad_left[1:]
        diagonal = jac_right.transpose(0, 2, 1) @ h_jr
        diagonal[:-1] += (jac_left[1:].transpose(0, 2, 1) @ joint.hess[1:]) @ jac_left[1:]
        off = cross[1:]
        if self.half_bar.size:
            b = self.half_bar
            qk = [Jet.affine(q[b, c], basis[b, c]) for c in range(4)]
            star = [Jet.constant(self.half_frame[:, c], 3) for c in range(4)]
            before = self.half_side > 0
            parts = []
            for mask, pair, axes in ((before, (qk, star), "a"), (~before, (star, qk), "b")):
                if np.any(mask):  # bar → t* in the bar's axes (a); t* → bar in the bar's axes (b): both along s
                    h1, h2, h3 = joint_strain([_take(j, mask) for j in quat.relative_affine(*pair)], axes)
                    e = (h1.square() + (h2 - self.half_rest[mask]).square()) * self.half_weight[mask]
                    parts.append((np.flatnonzero(mask), e, h3.square() * self.half_twist[mask]))
            for index, e, t in parts:
                bending += float(e.value.sum())
                twisting += float(t.value.sum())
                np.add.at(gradient, b[index], e.grad + t.grad)
                np.add.at(diagonal, b[index], e.hess + t.hess)
        return EnergyParts(bending, twisting, gradient, diagonal, off)

    def value(self, q: FloatArray) -> tuple[float, float]:
        """``(bending, twist)`` in N·mm of frames ``q`` (n, 4), without derivatives."""
        return self.values(q, np.zeros((self.n, 4, 3)), np.zeros((self.n, 3)))

    def values(self, q0: FloatArray, basis: FloatArray, omega: FloatArray) -> tuple[float, float]:
        """``(bending, twist)`` of :meth:`evaluate` at the same point without its derivatives (a line search's trial
        point): the same operations on the values, so the same numbers bit for bit, at a fraction of the cost."""
        q = q0 + np.einsum("kij,kj->ki", basis, omega)
        r = np.einsum("ijk,mj,mk->mi", quat.RELATIVE, np.vstack((self.base, q[:-1])), q)
        k1, k2, tau = joint_strain([Jet.constant(r[:, i], 0) for i in range(4)], "mid")
        bending = float(((k1.square() + (k2 - self.joint_rest).square()) * self.joint_bending).value.sum())
        twisting = float((tau.square() * self.joint_twist).value.sum())
        if self.half_bar.size:
            qk = [Jet.constant(q[self.half_bar, c], 0) for c in range(4)]
            star = [Jet.constant(self.half_frame[:, c], 0) for c in range(4)]
            before = self.half_side > 0
            for mask, pair, axes in ((before, (qk, star), "a"), (~before, (star, qk), "b")):
                if np.any(mask):
                    h1, h2, h3 = joint_strain([_take(j, mask) for j in quat.relative_affine(*pair)], axes)
                    bending += float(((h1.square() + (h2 - self.half_rest[mask]).square())
                                      * self.half_weight[mask]).value.sum())
                    twisting += float((h3.square() * self.half_twist[mask]).value.sum())
        return bending, twisting


def _columns(terms) -> tuple[IntArray, IntArray]:  # noqa: ANN001  (guidewire.energy.EnergyTerms)
    """Left and right bar (0-based, −1 for none) of every term of a planar :class:`~guidewire.energy.EnergyTerms`."""
    D = terms.matrix
    m = D.shape[0]
    left, right = np.full(m, -1), np.full(m, -1)
    rows = np.repeat(np.arange(m), np.diff(D.indptr))
    neg = D.data < 0
    left[rows[neg]] = D.indices[neg]
    right[rows[~neg]] = D.indices[~neg]
    return left, right


def _take(jet: Jet, mask: NDArray[np.bool_]) -> Jet:
    return Jet(jet.value[mask], jet.grad[mask], jet.hess[mask])
