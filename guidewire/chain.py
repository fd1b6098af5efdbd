"""Bar-chain kinematics (paper §2.1, Eqs. 16 and 20–21), in absolute bar angles.

Variables. The paper's design vector is the relative angles ``Δθ`` (Eq. 18). We use the absolute bar angles
``φ_j = Σ_{i≤j} Δθ_i`` instead (Eq. 16: the angle of bar ``j`` from the +x axis), a linear, invertible change of
variables, because then the bending energy has a tridiagonal Hessian, a prescribed tangent is one variable, and
node ``k`` depends on bars ``1..k`` only through ``(cos φ_j, sin φ_j)``.

Nodes. Node ``0`` is the base; bar ``j`` (1-based, length ``l_j``) runs from node ``j − 1`` to node ``j``::

    p_k = p_0 + Σ_{j ≤ k} l_j (cos φ_j, sin φ_j)                      (Eq. 20–21, a cumulative sum)
    ∂p_k / ∂φ_j = l_j (−sin φ_j, cos φ_j)  for j ≤ k, else 0           (a lower-triangular mask)

Node placement. Every contact must be a node exactly. The contacts cut the wire into segments (base → first contact
→ ... → last contact → free end); :func:`place_bars` shares the ``n`` bars out over the segments in proportion to
their lengths (largest-remainder rounding, at least one bar each) and makes the bars equal within a segment. When
every contact sits at a multiple of ``L/n`` this is exactly the paper's uniform chain; otherwise bar lengths differ
between segments, never a contact moved.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]


def place_bars(length: float, bars: int, contact_s: Sequence[float]) -> tuple[FloatArray, IntArray]:
    """Bar lengths that put a node at every contact.

    Parameters
    ----------
    length : float
        Wire length ``L`` (mm).
    bars : int
        Number ``n`` of bars, at least the number of segments.
    contact_s : sequence of float
        Strictly increasing contact arc lengths in ``(0, L]``.

    Returns
    -------
    lengths : ndarray, shape (n,)
        Bar lengths (mm), summing to ``L``; equal within each segment.
    contact_nodes : ndarray of int, shape (len(contact_s),)
        Node index (0 = base, n = tip) of each contact.
    """
    s = np.asarray(contact_s, dtype=float)
    ends = s if (s.size and s[-1] >= length) else np.append(s, length)
    seg = np.diff(np.concatenate(([0.0], ends)))
    if bars < seg.size:
        raise ValueError(f"bars is {bars} but there are {seg.size} segments; use at least one bar per segment.")
    ideal = bars * seg / length
    near = np.round(ideal)
    ideal = np.where(np.abs(ideal - near) < 1e-9 * max(1.0, bars), near, ideal)
    count = np.maximum(np.floor(ideal).astype(int), 1)
    while count.sum() > bars:  # the "at least one" floor overshot: take from the most over-served segment
        count[np.argmax(np.where(count > 1, count - ideal, -np.inf))] -= 1
    remainder = ideal - count
    order = np.argsort(-remainder, kind="stable")
    count[order[: bars - count.sum()]] += 1
    lengths = np.repeat(seg / count, count)
    node_at_end = np.cumsum(count)
    return lengths, node_at_end[: s.size].astype(np.int_)


@dataclass(frozen=True)
class BarChain:
    """A planar chain of rigid bars hinged end to end, starting at a fixed base point.

    Attributes
    ----------
    base_point : ndarray, shape (2,)
        Node 0 (mm).
    lengths : ndarray, shape (n,)
        Bar lengths ``l_j`` (mm).
    """

    base_point: FloatArray
    lengths: FloatArray

    @property
    def n_bars(self) -> int:
        """Number of bars ``n``."""
        return int(self.lengths.size)

    @property
    def arc_lengths(self) -> FloatArray:
        """Arc length of every node, shape (n + 1,), from 0 to ``L``."""
        return np.concatenate(([0.0], np.cumsum(self.lengths)))

    def bar_vectors(self, phi: FloatArray) -> FloatArray:
        """``l_j (cos φ_j, sin φ_j)``, shape (n, 2)."""
        return self.lengths[:, None] * np.column_stack((np.cos(phi), np.sin(phi)))

    def nodes(self, phi: FloatArray) -> FloatArray:
        """Node positions, shape (n + 1, 2), base first (Eqs. 20–21)."""
        steps = np.cumsum(self.bar_vectors(phi), axis=0)
        return np.vstack((self.base_point, self.base_point + steps))

    def node_jacobian(self, phi: FloatArray, node_index: IntArray) -> FloatArray:
        """``∂p_k/∂φ`` for the nodes ``k`` in ``node_index``, shape (len(node_index), 2, n).

        Row ``k`` holds ``l_j (−sin φ_j, cos φ_j)`` in columns ``j ≤ k`` (1-based bars) and zeros elsewhere.
        """
        node_index = np.asarray(node_index, dtype=int)
        d = self.lengths[None, :] * np.vstack((-np.sin(phi), np.cos(phi)))  # (2, n)
        mask = np.arange(self.n_bars)[None, :] < node_index[:, None]  # (m, n): bar j+1 ≤ node k
        return mask[:, None, :] * d[None, :, :]

    def node_hessian_diagonal(self, phi: FloatArray, node_index: IntArray, weights: FloatArray) -> FloatArray:
        """``Σ_m w_m · ∂²p_{k_m}/∂φ²``, which is diagonal: the diagonal, shape (n,).

        ``∂²p_k/∂φ_j² = −l_j (cos φ_j, sin φ_j)`` for ``j ≤ k`` (and no mixed terms), so the weighted sum over nodes is
        ``−l_j (cos φ_j W_x,j + sin φ_j W_y,j)`` with ``W_j = Σ_{k_m ≥ j} w_m`` — a suffix sum, O(n + m).

        Parameters
        ----------
        phi : ndarray, shape (n,)
        node_index : ndarray of int, shape (m,)
            Nodes ``k_m`` (1..n).
        weights : ndarray, shape (m, 2)
            ``w_m`` (a multiplier per coordinate).
        """
        acc = np.zeros((self.n_bars + 1, 2))
        np.add.at(acc, np.asarray(node_index, dtype=int), np.asarray(weights, dtype=float).reshape(-1, 2))
        suffix = np.cumsum(acc[::-1], axis=0)[::-1][1:]  # row j-1: Σ over nodes ≥ j
        return -self.lengths * (np.cos(phi) * suffix[:, 0] + np.sin(phi) * suffix[:, 1])

    def angles_from_nodes(self, nodes: FloatArray) -> FloatArray:
        """Bar angles of a polyline with ``n + 1`` points, unwrapped (continuous), shape (n,)."""
        steps = np.diff(np.asarray(nodes, dtype=float), axis=0)
        return np.unwrap(np.arctan2(steps[:, 1], steps[:, 0]))
