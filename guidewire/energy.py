"""The bending energy of the bar chain: a sum of weighted squared joint angles (paper Eqs. 14–15), two schemes.

Every term is one joint angle ``Δ_t = D_t φ − r_t`` (right-hand tangent minus left-hand tangent at a node) with a
weight ``c_t = EI / (2 w_t)``, where ``w_t`` is the arc length the joint stands for (its *dual length*)::

    E(φ) = Σ_t c_t Δ_t² = Σ_t (EI / 2) (Δ_t / w_t)² w_t          (∫ EI κ² / 2 ds with κ ≈ Δ_t / w_t)

so the energy is quadratic in ``φ``: gradient ``2 Dᵀ C (Dφ − r)``, constant Hessian ``2 Dᵀ C D`` (tridiagonal).

Interior joint between bars ``k`` and ``k+1`` (both schemes)
    ``Δ = φ_{k+1} − φ_k``, ``w = (l_k + l_{k+1}) / 2``, i.e. ``c = EI / (l_k + l_{k+1})`` (= the paper's
    ``ε = EI / (2L/n)`` for equal bars).

``scheme = "paper"`` (reproduces the paper; first order)
    The clamp at the base is a full joint of weight ``ε`` between the base tangent ``θ_A`` and bar 1
    (``Δθ_1 = φ_1 − θ_A``, ``w = l_1``), as Eq. 16 counts ``Δθ_1`` from the base direction. A prescribed contact
    angle ``θ_H`` is imposed on the bar ending at the contact node, ``φ_H = θ_H`` (Eqs. 16–18): a linear equality
    row in :mod:`~guidewire.program.formulation`, not an energy term. Of the two readings of the paper this is
    the one that reproduces its accuracy: mean node error 0.243 mm on Table 1 (θ_B = π/4, n = 100) and 0.257 mm over
    the five
    θ_B, against the paper's 0.2556 mm vs ABAQUS (imposing θ_A on bar 1 as well gives 0.145 mm).

``scheme = "second_order"`` (default)
    A prescribed tangent ``θ*`` at a node is a *half joint* between ``θ*`` and each adjoining bar, standing for half
    that bar (``w = l/2``, weight ``EI / l`` = ``2ε`` for equal bars): base clamp ``(EI/l_1)(φ_1 − θ_A)²``, interior
    contact ``(EI/l_k)(θ* − φ_k)² + (EI/l_{k+1})(φ_{k+1} − θ*)²``, contact at the tip ``(EI/l_n)(θ* − φ_n)²``. The
    node positions then sample the continuum curve at second order in ``L/n``; prescribed angles enter the energy
    and need no constraint rows.

A free base angle adds no clamp term; a free end adds nothing after the last bar.

Sections (variable ``EI``) and rest curvature
    Every bar ``j`` has its own ``EI_j`` and rest curvature ``κ⁰_j`` (:meth:`guidewire.Wire.properties_at`; a
    section boundary is always a node). A term covers half of each adjoining bar, so its rest angle is
    ``Δθ⁰ = Σ κ⁰_j l_j / 2`` over those halves (``κ⁰_1 l_1`` for the paper scheme's full clamp joint) and the term
    becomes ``c (Δ − Δθ⁰)²``: ``Δθ⁰`` is part of the offset ``r``. The stiffness of an interior joint is the
    half-bar-weighted harmonic mean ``EI = (l_k + l_{k+1}) / (l_k/EI_k + l_{k+1}/EI_{k+1})`` (the two halves are
    springs in series), so ``c = 1 / (l_k/EI_k + l_{k+1}/EI_{k+1})``; with equal ``EI`` it is exactly ``EI`` (the
    uniform wire's numbers are unchanged bit for bit). A half joint takes its bar's ``EI``. A chain whose bar angles
    follow the rest angles at every term has zero energy: a free J-tipped wire rests in its J.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]


@dataclass(frozen=True)
class EnergyTerms:
    """``E(φ) = Σ_t c_t (D_t φ − r_t)²`` with each term attached to a node.

    Attributes
    ----------
    matrix : scipy.sparse.csr_matrix, shape (m, n)
        ``D``: row ``t`` picks the joint angle's bar angles (+1 right bar, −1 left bar); sparse, at most two
        entries a row, so that energy, gradient and Hessian cost O(n).
    offset : ndarray, shape (m,)
        ``r``: the prescribed tangents entering the joint angle (rad).
    weight : ndarray, shape (m,)
        ``c_t = EI / (2 w_t)`` in N·mm.
    dual_length : ndarray, shape (m,)
        ``w_t`` in mm, so that ``κ_t = Δ_t / w_t``.
    node : ndarray of int, shape (m,)
        Node index of the joint (0 = base).
    rest : ndarray, shape (m,), or None
        ``Δθ⁰_t``, the rest angle of the term (rad), already included in ``offset``; None means zeros.
    """

    matrix: sp.csr_matrix
    offset: FloatArray
    weight: FloatArray
    dual_length: FloatArray
    node: IntArray
    rest: FloatArray | None = None

    @property
    def rest_angles(self) -> FloatArray:
        """``Δθ⁰_t`` (rad), shape (m,): zeros for a straight wire."""
        return np.zeros(self.offset.size) if self.rest is None else self.rest

    @cached_property
    def coo(self) -> tuple[IntArray, IntArray, FloatArray]:
        """The difference matrix ``D`` as (term row, bar column, coefficient) triplets: which bars each joint
        term reads, used to evaluate the terms and to map them to the bars and nodes they involve."""
        D = self.matrix  # canonical CSR: the (row, column) order of ``tocoo``, without building the COO matrix
        rows = np.repeat(np.arange(D.shape[0], dtype=np.intp), np.diff(D.indptr))
        return rows, D.indices.astype(np.intp), D.data

    def joint_angles(self, phi: FloatArray) -> FloatArray:
        """``Δ_t = D_t φ − r_t`` in rad, shape (m,): the bend away from the rest shape (the elastic part)."""
        rows, cols, data = self.coo
        return np.bincount(rows, data * phi[cols], minlength=self.offset.size) - self.offset

    def value(self, phi: FloatArray) -> float:
        """Bending energy in N·mm."""
        delta = self.joint_angles(phi)
        return float(np.dot(self.weight, delta * delta))

    def gradient(self, phi: FloatArray) -> FloatArray:
        """``2 Dᵀ C (Dφ − r)``, shape (n,), N·mm/rad."""
        rows, cols, data = self.coo
        return np.bincount(cols, 2.0 * data * (self.weight * self.joint_angles(phi))[rows],
                           minlength=self.matrix.shape[1])

    def hessian(self) -> sp.csc_matrix:
        """``2 Dᵀ C D``, shape (n, n), constant and tridiagonal (sparse CSC).

        A term couples at most two bars, and two adjacent ones (a joint between bars ``k`` and ``k+1``), so the
        Hessian is tridiagonal: its diagonal and off-diagonal are sums over the terms (``bincount``), written
        straight into CSC arrays with only the entries some term touches (the same matrix as the former COO
        assembly, 1.5x faster at n = 100)."""
        D = self.matrix
        n = D.shape[1]
        counts = np.diff(D.indptr)
        term, cols, data = self.coo
        w2 = 2.0 * self.weight
        diag = np.bincount(cols, w2[term] * data * data, minlength=n)
        touched = np.bincount(cols, minlength=n) > 0
        pair = np.flatnonzero(counts == 2)
        first = D.indptr[pair]
        left = np.minimum(cols[first], cols[first + 1])
        if np.any(np.abs(cols[first] - cols[first + 1]) != 1):  # not a chain's terms: the general assembly
            return _general_hessian(D, self.weight)
        off = np.bincount(left, w2[pair] * data[first] * data[first + 1], minlength=max(n - 1, 0))
        coupled = np.bincount(left, minlength=max(n - 1, 0)) > 0
        # column j holds rows j-1 (off[j-1]), j (diag[j]), j+1 (off[j]), each where some term touches it
        values = np.zeros((n, 3))
        values[1:, 0], values[:, 1], values[:-1, 2] = off, diag, off
        if n > 1 and touched.all() and coupled.all():  # every entry of the band: its pattern is the same at every n
            rows, indptr = _full_band(n)  # (copies: the matrix owns its arrays, as scipy's operations expect)
            return sp.csc_matrix((values.ravel()[1:-1], rows.copy(), indptr.copy()), shape=(n, n))
        keep = np.zeros((n, 3), dtype=bool)
        keep[1:, 0], keep[:, 1], keep[:-1, 2] = coupled, touched, coupled
        rows = np.arange(n)[:, None] + np.array([-1, 0, 1])
        indptr = np.concatenate(([0], np.cumsum(keep.sum(axis=1))))
        return sp.csc_matrix((values[keep], rows[keep].astype(np.int32), indptr.astype(np.int32)), shape=(n, n))

    @property
    def row_sum(self) -> FloatArray:
        """``D_t 1`` per term: 0 for a joint between two bars, ±1 for a term with a prescribed tangent."""
        rows, _, data = self.coo
        return np.bincount(rows, data, minlength=self.offset.size)

    def node_rows(self, n_nodes: int) -> tuple[sp.csr_matrix, FloatArray]:
        """Terms summed per node: ``(D_node, r_node)`` with ``D_node φ − r_node`` the node's total angle jump.

        Shapes (n_nodes, n) (sparse CSR) and (n_nodes,); nodes without a term give zero rows.
        """
        m = self.node.size
        pick = sp.csr_matrix((np.ones(m), (self.node, np.arange(m))), shape=(n_nodes, m))
        offsets = np.zeros(n_nodes)
        np.add.at(offsets, self.node, self.offset)
        return sp.csr_matrix(pick @ self.matrix), offsets


@functools.lru_cache(maxsize=8)
def _full_band(n: int) -> tuple[NDArray[np.int32], NDArray[np.int32]]:
    """Row indices and column pointers (read-only) of a full tridiagonal (n, n) CSC matrix, n ≥ 2."""
    rows = (np.arange(n)[:, None] + np.array([-1, 0, 1])).ravel()[1:-1].astype(np.int32)
    indptr = np.concatenate(([0], np.arange(2, 3 * n - 1, 3), [3 * n - 2])).astype(np.int32)
    for array in (rows, indptr):
        array.flags.writeable = False
    return rows, indptr


def _general_hessian(D: sp.csr_matrix, weight: FloatArray) -> sp.csc_matrix:
    """``2 Dᵀ C D`` for any ``D`` (a COO assembly of the products within each row)."""
    return sp.csc_matrix(2.0 * (D.T @ sp.diags(weight) @ D))


def bending_terms(
    lengths: FloatArray,
    stiffness: float | FloatArray,
    scheme: str,
    base_angle: float | None,
    angle_nodes: Sequence[int],
    angles: Sequence[float],
    rest_curvature: FloatArray | None = None,
) -> EnergyTerms:
    """The energy terms of one scheme for a chain with prescribed tangents.

    Parameters
    ----------
    lengths : ndarray, shape (n,)
        Bar lengths in mm.
    stiffness : float or ndarray, shape (n,)
        ``EI`` in N·mm², one value or one per bar.
    scheme : {"second_order", "paper"}
    base_angle : float or None
        Clamp tangent ``θ_A`` at node 0, or None for a free base.
    angle_nodes, angles : sequences
        Nodes (1..n) with a prescribed tangent and the tangents in rad. In the paper scheme they add no terms (they
        are constraint rows); in the second-order scheme they split the joint into two half joints.
    rest_curvature : ndarray, shape (n,), or None
        ``κ⁰`` per bar (1/mm); None is a straight wire.

    Returns
    -------
    EnergyTerms
    """
    n = lengths.size
    half = scheme == "second_order"
    k_angle = np.asarray(angle_nodes, dtype=np.int_)
    theta = np.asarray(angles, dtype=float)
    split = k_angle < n if half else np.zeros(k_angle.size, dtype=bool)  # interior nodes made of two half joints
    tip = k_angle == n if half else np.zeros(k_angle.size, dtype=bool)
    k_split = k_angle[split]
    plain = np.ones(n, dtype=bool)  # nodes 1..n−1 that are one joint between two bars
    plain[0] = False
    plain[k_split] = False
    k_plain = np.flatnonzero(plain)
    # Each block: (left bar column or -1, right bar column or -1, offset r, dual length w, node); the empty ones left
    # out.
    blocks = [(k_plain - 1, k_plain, np.zeros(k_plain.size), 0.5 * (lengths[k_plain - 1] + lengths[k_plain]), k_plain)]
    if k_split.size:
        blocks += [(k_split - 1, np.full(k_split.size, -1), -theta[split], lengths[k_split - 1] / 2.0, k_split),
                   (np.full(k_split.size, -1), k_split, theta[split], lengths[k_split] / 2.0, k_split)]
    if tip.any():
        k_tip = k_angle[tip]
        blocks.append((k_tip - 1, np.full(k_tip.size, -1), -theta[tip], lengths[k_tip - 1] / 2.0, k_tip))
    if base_angle is not None:
        dual = lengths[:1] / 2.0 if half else lengths[:1]
        blocks.insert(0, (np.array([-1]), np.array([0]), np.array([float(base_angle)]), dual, np.array([0])))
    left, right, offset, dual, node = (np.concatenate(parts) for parts in zip(*blocks, strict=True))
    if k_split.size or tip.any():  # (else already by node: the base clamp, then the joints in order)
        order = np.lexsort((np.arange(node.size), node))  # by node; at a split node the left half first
        left, right, offset, dual, node = left[order], right[order], offset[order], dual[order], node[order]
    # D straight in CSR: a row holds its left bar (−1) before its right one (+1), the order a COO assembly gives
    has = np.column_stack((left >= 0, right >= 0))
    indptr = np.concatenate(([0], np.cumsum(has.sum(axis=1)))).astype(np.int32)
    indices = np.column_stack((left, right))[has].astype(np.int32)
    data = np.broadcast_to(np.array([-1.0, 1.0]), has.shape)[has]
    matrix = sp.csr_matrix((data, indices, indptr), shape=(node.size, n))
    if np.ndim(stiffness) == 0:
        weight = float(stiffness) / (2.0 * dual)  # the uniform wire: EI / (2 w) on every joint
    else:
        ei = np.asarray(stiffness, dtype=float)
        both = (left >= 0) & (right >= 0)
        ei_left, ei_right = ei[np.maximum(left, 0)], ei[np.maximum(right, 0)]
        single = np.where(left >= 0, ei_left, ei_right)  # a half (or clamp) joint: its one bar
        series = 1.0 / (lengths[np.maximum(left, 0)] / ei_left + lengths[np.maximum(right, 0)] / ei_right)
        weight = np.where(both & (ei_left != ei_right), series, single / (2.0 * dual))
    rest = None
    if rest_curvature is not None and np.any(np.asarray(rest_curvature) != 0.0):
        kappa0 = np.asarray(rest_curvature, dtype=float)
        # the halves of the adjoining bars a term covers: dual = l/2 each (second order), or all of bar 1 for the
        # paper scheme's clamp; a joint between two bars covers half of each
        left_part = np.where(left >= 0, kappa0[np.maximum(left, 0)] * lengths[np.maximum(left, 0)] / 2.0, 0.0)
        right_part = np.where(right >= 0, kappa0[np.maximum(right, 0)] * lengths[np.maximum(right, 0)] / 2.0, 0.0)
        rest = left_part + right_part
        clamp = (left < 0) & (node == 0)
        rest = np.where(clamp, kappa0[0] * dual, rest)
        offset = offset + rest
    return EnergyTerms(
        matrix=matrix, offset=offset, weight=weight, dual_length=dual, node=node.astype(np.int_), rest=rest
    )
