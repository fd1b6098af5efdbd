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

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from ..scene.scene import Scene

from ..wire import Wire, piece_ends

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]


def place_bars(length: float, bars: int, contact_s: Sequence[float], breakpoints: Sequence[float] = (),
               pinned: Sequence[bool] | None = None,
               refinement: Callable[[FloatArray], FloatArray] | None = None) -> tuple[FloatArray, IntArray]:
    """Bar lengths that put a node at every contact and every breakpoint.

    The contacts and breakpoints cut the wire into pieces; the ``n`` bars are shared out in proportion to the
    pieces' lengths (times their ``refinement``; largest-remainder rounding, at least one bar each), equal within a
    piece. A piece running from one prescribed position to the next (the base, or a contact with ``pinned`` True)
    gets at least two bars when ``n`` allows, so that two positions closer than a bar are bridged by short bars that
    can bend, not by one rigid bar that must span their distance exactly. Without breakpoints and without such a
    one-bar piece this is exactly the uniform chain of the paper when every contact sits at a multiple of ``L/n``.

    Parameters
    ----------
    length : float
        Wire length ``L`` (mm).
    bars : int
        Number ``n`` of bars, at least the number of pieces.
    contact_s : sequence of float
        Strictly increasing contact arc lengths in ``(0, L]``.
    breakpoints : sequence of float
        Further arc lengths that must be nodes (section boundaries), mm; those outside ``(0, L)`` or within
        :data:`~guidewire.wire.BREAK_ROUNDING` of a contact are ignored.
    pinned : sequence of bool or None
        Per contact: whether it prescribes a position (default: none does, no bridging).
    refinement : callable or None
        Bars per mm relative to the rest at arc lengths ``s`` (vectorised; :meth:`guidewire.Wire.refinement_at`),
        read at each piece's middle: the bars are shared in proportion to length times refinement. None (default):
        in proportion to length.

    Returns
    -------
    lengths : ndarray, shape (n,)
        Bar lengths (mm), summing to ``L``; equal within each piece.
    contact_nodes : ndarray of int, shape (len(contact_s),)
        Node index (0 = base, n = tip) of each contact.
    """
    s = np.asarray(contact_s, dtype=float)
    ends = piece_ends(length, s, breakpoints)
    seg = np.diff(np.concatenate(([0.0], ends)))
    if bars < seg.size:
        raise ValueError(f"bars is {bars} but there are {seg.size} pieces; use at least one bar per piece.")
    minimum = np.ones(seg.size, dtype=int)
    if pinned is not None and s.size:
        held = np.concatenate(([0.0], s[np.asarray(pinned, dtype=bool)]))  # positions: the base and pinned contacts
        starts = np.concatenate(([0.0], ends[:-1]))
        bridge = np.isin(starts, held) & np.isin(ends, held[1:])
        if bars >= seg.size + int(bridge.sum()):
            minimum = minimum + bridge
    if refinement is None:
        ideal = bars * seg / length
    else:
        weighted = seg * refinement(ends - 0.5 * seg)
        ideal = bars * weighted / float(np.sum(weighted))
    near = np.round(ideal)
    ideal = np.where(np.abs(ideal - near) < 1e-9 * max(1.0, bars), near, ideal)
    count = np.maximum(np.floor(ideal).astype(int), minimum)
    while count.sum() > bars:  # the "at least" floor overshot: take from the most over-served piece
        count[np.argmax(np.where(count > minimum, count - ideal, -np.inf))] -= 1
    remainder = ideal - count
    order = np.argsort(-remainder, kind="stable")
    count[order[: bars - count.sum()]] += 1
    lengths = np.repeat(seg / count, count)
    node_at_end = np.cumsum(count)
    return lengths, node_at_end[np.searchsorted(ends, s)].astype(np.int_)


def scene_bars(scene: Scene) -> tuple[FloatArray, IntArray]:
    """The bars of a scene: the wire's explicit ``bar_lengths`` (checked by :func:`explicit_bars`), else
    :func:`place_bars` (a node at every contact and section boundary, positions bridged).

    They depend only on the wire and the contacts' arc lengths and kinds, so the last few layouts are kept
    (:func:`_wire_bars`): the steps of a sequence moving contact points, and repeated solves of one scene, reuse
    them. The arrays returned are read-only (shared)."""
    contacts = scene.contacts
    return _wire_bars(scene.wire, tuple(c.s for c in contacts), tuple(c.point is not None for c in contacts))


@functools.lru_cache(maxsize=32)
def _wire_bars(wire: Wire, contact_s: tuple[float, ...], pinned: tuple[bool, ...]) -> tuple[FloatArray, IntArray]:
    """:func:`scene_bars` of a wire with contacts at ``contact_s`` (``pinned``: the contact prescribes a point)."""
    if wire.bar_lengths is not None:
        out = explicit_bars(wire.bar_lengths, contact_s, wire.section_boundaries())
    else:
        out = place_bars(wire.length, wire.bars, contact_s, wire.section_boundaries(), pinned,
                         wire.refinement_at if wire.refined else None)
    for array in out:
        array.flags.writeable = False
    return out


def explicit_bars(lengths: Sequence[float], contact_s: Sequence[float], breakpoints: Sequence[float] = (),
                  rounding: float = 1e-9) -> tuple[FloatArray, IntArray]:
    """Given bar lengths and the node of every contact; a contact or breakpoint that is not a node (within
    ``rounding`` of the wire length) is a ValueError naming it.

    Parameters
    ----------
    lengths : sequence of float
        Bar lengths (mm), base first.
    contact_s, breakpoints : sequence of float
        Arc lengths that must be nodes: the contacts and the section boundaries (mm).
    rounding : float
        Relative tolerance on the node positions.

    Returns
    -------
    lengths : ndarray, shape (n,)
    contact_nodes : ndarray of int, shape (len(contact_s),)
    """
    lengths = np.asarray(lengths, dtype=float)
    s_nodes = np.concatenate(([0.0], np.cumsum(lengths)))
    tol = rounding * s_nodes[-1]
    nodes = []
    for what, values in (("contact", contact_s), ("section boundary", breakpoints)):
        values = np.asarray(values, dtype=float)
        k = np.clip(np.searchsorted(s_nodes, values), 1, s_nodes.size - 1)
        k = np.where(np.abs(s_nodes[k - 1] - values) < np.abs(s_nodes[k] - values), k - 1, k)
        off = np.abs(s_nodes[k] - values) > tol
        if np.any(off):
            i = int(np.argmax(off))
            raise ValueError(f"wire.bar_lengths put no node at the {what} at s = {values[i]:.12g} mm (nearest node "
                             f"at {s_nodes[k[i]]:.12g} mm); give lengths whose running sums hit every contact and "
                             "section boundary, or omit bar_lengths.")
        nodes.append(k)
    return lengths, nodes[0].astype(np.int_)


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
        return self.nodes_from_steps(self.lengths * np.cos(phi), self.lengths * np.sin(phi))

    def nodes_from_steps(self, dx: FloatArray, dy: FloatArray) -> FloatArray:
        """Node positions from the bar vectors ``l_j (cos φ_j, sin φ_j)`` given as their components ``dx``, ``dy``
        (shape (n,) each), shape (n + 1, 2): the running sum from the base, written straight into one array."""
        out = np.empty((dx.size + 1, 2))
        out[0] = self.base_point
        steps = out[1:]
        steps[:, 0], steps[:, 1] = dx, dy
        np.cumsum(steps, axis=0, out=steps)
        steps += self.base_point
        return out

    def node_jacobian(self, phi: FloatArray, node_index: IntArray) -> FloatArray:
        """``∂p_k/∂φ`` for the nodes ``k`` in ``node_index``, shape (len(node_index), 2, n).

        Row ``k`` holds ``l_j (−sin φ_j, cos φ_j)`` in columns ``j ≤ k`` (1-based bars) and zeros elsewhere.
        """
        node_index = np.asarray(node_index, dtype=int)
        d = self.lengths[None, :] * np.vstack((-np.sin(phi), np.cos(phi)))  # (2, n)
        mask = np.arange(self.n_bars)[None, :] < node_index[:, None]  # (m, n): bar j+1 ≤ node k
        return mask[:, None, :] * d[None, :, :]

    def node_hessian_diagonal(self, phi: FloatArray, node_index: IntArray, weights: FloatArray,
                              trig: tuple[FloatArray, FloatArray] | None = None) -> FloatArray:
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
        trig : (ndarray, ndarray), optional
            ``(cos φ, sin φ)`` when the caller has them.
        """
        index, w = np.asarray(node_index, dtype=np.intp), np.asarray(weights, dtype=float).reshape(-1, 2)
        size = self.n_bars + 1  # per coordinate, the sum over the nodes ≥ j of bar j's rows (a reversed running sum)
        sx = np.cumsum(np.bincount(index, w[:, 0], minlength=size)[::-1])[::-1][1:]
        sy = np.cumsum(np.bincount(index, w[:, 1], minlength=size)[::-1])[::-1][1:]
        cos, sin = (np.cos(phi), np.sin(phi)) if trig is None else trig
        return -self.lengths * (cos * sx + sin * sy)

    def angles_from_nodes(self, nodes: FloatArray) -> FloatArray:
        """Bar angles of a polyline with ``n + 1`` points, unwrapped (continuous), shape (n,)."""
        steps = np.diff(np.asarray(nodes, dtype=float), axis=0)
        return np.unwrap(np.arctan2(steps[:, 1], steps[:, 0]))
