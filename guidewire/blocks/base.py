"""What every constraint block has in common: its rows as data, its loads on the wire, its violation.

A block is one kind of constraint of a scene (a contact position, a contact angle, a wall, the b₂ bound, …) written
once as *rows*, in one of two forms that both program layouts know how to state
(:mod:`~guidewire.program.formulation` for the reduced program in the bar angles ``φ``,
:mod:`guidewire.program.full_space` for angles and node positions):

:class:`NodeRows`
    ``lb ≤ d_r · p_{k_r} ≤ ub`` — linear in a node position ``p_k`` (mm), one direction ``d_r`` per row. Nonlinear
    in ``φ`` (``p_k`` is a sum of ``l_j (cos φ_j, sin φ_j)``), linear in the full space. A row may instead be a
    bar's distance from a point (a vessel's corner), quadratic in the bar's two nodes.
:class:`AngleRows`
    ``lb ≤ A φ ≤ ub`` — linear in the bar angles in both layouts.

Sign convention of the multipliers (the same in both layouts, the one of :func:`sqp.minimize`): at a KKT point
``∇E = Σ_r λ_r ∇(row_r)``, with ``λ_r ≥ 0`` at an active lower bound and ``λ_r ≤ 0`` at an active upper bound
(an equality row: any sign). For node rows this makes ``λ_r d_r`` the force (N) the constraint exerts on node
``k_r`` — by virtual work, ``δE = F · δp``; for angle rows ``λ_r`` is a moment (N·mm) on the bars of the row.

Adding a kind of constraint is one new module with one :class:`Block` subclass (its ``build`` reads the scene and
returns its blocks, empty when the scene does not need the kind) and one line in ``guidewire.blocks.BLOCK_TYPES``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

if TYPE_CHECKING:
    from ..program.model import Model

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]


def perp(v: FloatArray) -> FloatArray:
    """``v`` turned a quarter counter-clockwise, ``(−v_y, v_x)``, for (…, 2) arrays."""
    return np.stack((-v[..., 1], v[..., 0]), axis=-1)


#: ``∂² (a × b) / ∂a ∂b`` for 2-vectors (``a × b = a_x b_y − a_y b_x``).
CROSS = np.array([[0.0, 1.0], [-1.0, 0.0]])


@dataclass(frozen=True)
class NodeRows:
    """Rows ``lb ≤ g_r ≤ ub`` on the wire's nodes, of two forms:

    a node's row
        ``g_r = d_r · p_k + ½ (p_k − c_r)ᵀ H_r (p_k − c_r)`` at node ``k = k_r``: linear (``H`` None: walls,
        contact positions) or a quadratic model of a curved boundary around ``c_r`` (a lumen);
    a bar's row (:attr:`turns` ``ω_r ≠ 0``)
        ``g_r = ω_r (p_{k+1} − p_k) × (a_r − p_k)``: with ``ω_r = ±1/l`` the signed distance of the point ``a_r``
        (a vessel's corner) from the line of the bar from node ``k`` to ``k + 1`` — exact, and quadratic in the two
        nodes, wherever the bar keeps its length ``l`` (always in the reduced layout; where the closure rows hold in
        the full space). Its force acts at the foot ``(1 − τ_r) p_k + τ_r p_{k+1}`` along ``d_r``, which the two nodes
        share as ``1 − τ`` and ``τ`` (:meth:`add_to_nodes`).

    Attributes
    ----------
    nodes : ndarray of int, shape (m,)
        Node ``k_r`` of every row (1..n; the base node is fixed and never a row; a bar's row: its first node, 1..n−1).
    directions : ndarray, shape (m, 2)
        ``d_r`` (dimensionless; a unit vector or a coordinate axis); of a bar's row, its force's direction.
    lb, ub : ndarray, shape (m,)
        Bounds in mm (``-inf``/``inf`` for none; ``lb == ub`` for an equality row).
    hessians : ndarray, shape (m, 2, 2), or None
        ``H_r`` (1/mm), symmetric (zero for a bar's row); None for linear rows.
    centres : ndarray, shape (m, 2), or None
        ``c_r`` (mm), where the quadratic model is taken; None for linear rows.
    fractions : ndarray, shape (m,), or None
        ``τ_r`` in [0, 1] of a bar's row (0 for a node's row); None without bar rows.
    pivots, turns : ndarray, shapes (m, 2) and (m,), or None
        ``a_r`` (mm) and ``ω_r`` (1/mm; 0 for a node's row) of the bar rows; None without.
    """

    nodes: IntArray
    directions: FloatArray
    lb: FloatArray
    ub: FloatArray
    hessians: FloatArray | None = None
    centres: FloatArray | None = None
    fractions: FloatArray | None = None
    pivots: FloatArray | None = None
    turns: FloatArray | None = None

    def __post_init__(self) -> None:
        if self.turns is None:
            if self.fractions is not None or self.pivots is not None:
                raise ValueError("NodeRows: fractions and pivots belong to bar rows (turns)")
            return
        bar = self.turns != 0.0
        if self.hessians is None or self.fractions is None or self.pivots is None:
            raise ValueError("NodeRows: bar rows (turns) need hessians (zero for them), fractions and pivots")
        tau = self.fractions
        if tau.shape != self.nodes.shape or np.any((tau < 0.0) | (tau > 1.0)) or np.any(tau[~bar]):
            raise ValueError("NodeRows.fractions: one τ in [0, 1] per bar row, 0 for a node row")
        if np.any(self.nodes[bar] < 1):
            raise ValueError("NodeRows.turns: a bar's row starts at node 1 or later (the base node is fixed)")
        if np.any(self.hessians[bar]):
            raise ValueError("NodeRows.hessians: a bar's row has no H (its quadratic term is its own)")

    @property
    def linear(self) -> bool:
        """Whether the rows are linear in the node positions."""
        return self.hessians is None

    @property
    def bars(self) -> IntArray:
        """The bar rows (indices, empty without)."""
        return np.zeros(0, dtype=int) if self.turns is None else np.flatnonzero(self.turns)

    def row_points(self, nodes: FloatArray) -> FloatArray:
        """Where each row's force acts for node positions ``nodes`` (shape (n + 1, 2)): its node, or a bar row's
        foot, shape (m, 2)."""
        p = nodes[self.nodes]
        bar = self.bars
        if bar.size:
            p[bar] += self.fractions[bar, None] * (nodes[self.nodes[bar] + 1] - p[bar])
        return p

    def values(self, points: FloatArray) -> FloatArray:
        """Row values at node positions ``points`` (shape (n + 1, 2)), shape (m,)."""
        p = points[self.nodes]
        out = np.einsum("ij,ij->i", p, self.directions)
        if self.hessians is not None:
            q = p - self.centres
            out = out + 0.5 * np.einsum("ia,iab,ib->i", q, self.hessians, q)
        bar = self.bars
        if bar.size:
            first, second = p[bar], points[self.nodes[bar] + 1]
            e, w = second - first, self.pivots[bar] - first
            out[bar] = self.turns[bar] * (e[:, 0] * w[:, 1] - e[:, 1] * w[:, 0])
        return out

    def gradients(self, points: FloatArray) -> FloatArray:
        """``∂g_r/∂p_{k_r}`` at ``points``: ``d + H (p − c)``, of a bar's row ``ω ⊥(a − p_{k+1})``; shape (m, 2)."""
        if self.hessians is None:
            return self.directions
        out = self.directions + np.einsum("iab,ib->ia", self.hessians, points[self.nodes] - self.centres)
        bar = self.bars
        if bar.size:
            out[bar] = self.turns[bar, None] * perp(self.pivots[bar] - points[self.nodes[bar] + 1])
        return out

    def next_gradients(self, points: FloatArray) -> FloatArray:
        """``∂g_r/∂p_{k_r + 1}`` of the bar rows (:attr:`bars`) at ``points``: ``−ω ⊥(a − p_k)``, shape (bars, 2)."""
        bar = self.bars
        return -self.turns[bar, None] * perp(self.pivots[bar] - points[self.nodes[bar]])

    def spread(self) -> tuple[IntArray, IntArray, FloatArray]:
        """Where the rows' forces go: ``(row, node, weight)`` arrays, one entry per row and node (a node row: its
        node, weight 1; a bar's row: ``k_r`` with ``1 − τ_r`` and ``k_r + 1`` with ``τ_r``)."""
        rows = np.arange(self.nodes.size)
        bar = self.bars
        if not bar.size:
            return rows, self.nodes, np.ones(self.nodes.size)
        tau = self.fractions
        return (np.concatenate((rows, bar)), np.concatenate((self.nodes, self.nodes[bar] + 1)),
                np.concatenate((1.0 - tau, tau[bar])))

    def add_to_nodes(self, per_row: FloatArray, out: FloatArray) -> FloatArray:
        """``out`` (shape (n + 1, 2)) with each row's vector of ``per_row`` (shape (m, 2): a force ``λ_r d_r``) added
        to its node, or shared between its bar's two nodes (:meth:`spread`); returns ``out``."""
        rows, nodes, weights = self.spread()
        np.add.at(out, nodes, weights[:, None] * per_row[rows])
        return out


@dataclass(frozen=True)
class AngleRows:
    """Rows ``lb ≤ A φ ≤ ub``, linear in the bar angles.

    Attributes
    ----------
    A : scipy.sparse.csr_matrix, shape (m, n)
    lb, ub : ndarray, shape (m,)
        Bounds in rad.
    """

    A: sp.csr_matrix
    lb: FloatArray
    ub: FloatArray

    def values(self, phi: FloatArray) -> FloatArray:
        """``A φ``, shape (m,)."""
        return self.A @ phi


Rows = NodeRows | AngleRows


@dataclass
class Loads:
    """Loads the supports exert on the wire, filled by :meth:`Block.add_loads` (N, N·mm, counter-clockwise).

    Attributes
    ----------
    forces : dict of int to ndarray, shape (2,)
        Force of contact ``i`` (by contact index).
    moments : dict of int to float
        Moment of contact ``i`` where it is a constraint row (paper scheme).
    node_forces : ndarray, shape (n + 1, 2)
        Distributed forces on the nodes that belong to no contact (walls, a lumen).
    """

    forces: dict[int, FloatArray]
    moments: dict[int, float]
    node_forces: FloatArray

    @classmethod
    def empty(cls, n_bars: int) -> Loads:
        return cls({}, {}, np.zeros((n_bars + 1, 2)))


def row_violation(values: FloatArray, lb: FloatArray, ub: FloatArray) -> FloatArray:
    """``max(lb − v, v − ub, 0)`` per row."""
    return np.maximum(np.maximum(lb - values, values - ub), 0.0)


#: What a kind with a node working set constrains (:meth:`Block.build`): None (every node), ``"near"`` (the start's
#: nodes near the constraint) or a mapping from :attr:`Block.key` to the nodes to constrain.
WorkingSet = str | Mapping[tuple[str, tuple[int, ...]], Any] | None


def grown_by_neighbours(nodes: IntArray, violated: IntArray, n: int) -> IntArray:
    """``nodes`` with every ``violated`` node and its two neighbours added (nodes 1..n), sorted: how a block with a
    node working set grows when the answer violates it."""
    extra = np.clip(np.concatenate([violated - 1, violated, violated + 1]), 1, n)
    return np.union1d(nodes, extra)


@dataclass(frozen=True)
class Block:
    """One constraint block: a kind, what it constrains, and its rows (see the module docstring).

    Attributes
    ----------
    members : tuple of int
        What the rows belong to: contact indices (``position``, ``angle``), the wall index (``wall``), the joint
        nodes (``relative_angle``).
    nodes : ndarray of int, shape (rows,)
        The node of every row.
    index : int
        Position of the block's constraint in ``Formulation.constraints`` (set by the formulation; -1 before).
    """

    kind: ClassVar[str] = ""
    #: The unit of the rows' values and violations (``"mm"``, or ``"rad"`` for angle rows).
    unit: ClassVar[str] = "mm"
    members: tuple[int, ...]
    nodes: IntArray
    index: int = field(default=-1, compare=False)

    # -- what every kind provides ------------------------------------------------------------------------------
    @classmethod
    def build(cls, model: Model, working_set: WorkingSet = None) -> list[Block]:
        """The blocks of this kind ``model.scene`` needs (none when it needs none).

        ``working_set`` is None (every node), ``"near"`` (kinds with a node working set: the start's nodes near the
        constraint) or a mapping from :attr:`key` to the nodes to constrain.
        """
        raise NotImplementedError

    def rows(self, model: Model) -> Rows:
        """The rows, in the form both layouts state."""
        raise NotImplementedError

    def add_loads(self, model: Model, lam: FloatArray, loads: Loads, points: FloatArray) -> None:
        """Add what the multipliers ``lam`` of this block exert on the wire, at node positions ``points`` (the
        answer's), to ``loads`` (default: nothing)."""

    # -- shared ---------------------------------------------------------------------------------------------------
    @property
    def key(self) -> tuple[str, tuple[int, ...]]:
        """Identifies the block across formulations of the same scene (kind and members)."""
        return (self.kind, self.members)

    @property
    def size(self) -> int:
        """Number of rows."""
        return int(self.nodes.size)

    @property
    def row_keys(self) -> IntArray:
        """Identifies each row within the block across formulations of the same scene (default: its node), for
        carrying multipliers over from a neighbouring solve."""
        return self.nodes

    def violation(self, model: Model, phi: FloatArray, points: FloatArray | None = None,
                  rows: Rows | None = None) -> FloatArray:
        """Violation (mm or rad, ≥ 0) of every row at the bar angles ``phi`` (node positions ``points`` when given,
        else ``model.chain.nodes(phi)``; the block's :meth:`rows` on ``model`` when given, else built)."""
        rows = self.rows(model) if rows is None else rows
        if isinstance(rows, NodeRows):
            values = rows.values(model.chain.nodes(phi) if points is None else points)
        else:
            values = rows.values(phi)
        return row_violation(values, rows.lb, rows.ub)

    def violation_nodes(self, model: Model) -> IntArray:
        """The node each entry of :meth:`violation` belongs to (default: the rows' nodes)."""
        return self.nodes

    def describe(self, model: Model) -> str:
        """What the block constrains, for messages: the kind and its members (a contact's label, a wall's index)."""
        return f"{self.kind.replace('_', ' ')} {', '.join(str(m) for m in self.members)}".strip()

    def refine(self, model: Model, phi: FloatArray, tolerance: float) -> Block | None:
        """A block whose rows fit the answer ``phi`` better — its working set grown by the rows ``phi`` violates, or
        its linearisation moved to ``phi`` — or None when its rows are right at ``phi`` (default: always right).
        :func:`guidewire.solve` solves again from ``phi`` while any block refines."""
        return None

    def mismatch(self, model: Model, phi: FloatArray) -> tuple[float, int] | None:
        """Where the rows stand least for the constraint they model at ``phi``: the largest difference (in
        :attr:`unit`) between a row's value and the true constraint's at a row that holds the wire (its node
        touching), and that node; None when the rows are exact (default). Names the defect of an answer whose
        working-set rounds ran out before :meth:`refine` settled."""
        return None

    def contact_normals(self, scene: Any) -> FloatArray | None:
        """Outward unit normals (shape (rows, 2)) of a block whose multipliers are normal contact forces at its
        nodes (walls, lumens), for :meth:`Solution.contacts`; None for the other kinds (default)."""
        return None

    def contact_frames(self, scene: Any, points: FloatArray) -> tuple[FloatArray, FloatArray] | None:
        """Outward unit normals (shape (rows, 2)) of a block whose multipliers are normal contact forces (walls,
        lumens), and where on its bar each row touches the wire (``τ``, shape (rows,): the point ``(1 − τ) p_k + τ
        p_{k+1}`` for the row's node ``k``; 0 at the node), at node positions ``points``, for
        :meth:`Solution.contacts`; None for the other kinds (default: :meth:`contact_normals` at the nodes)."""
        normals = self.contact_normals(scene)
        return None if normals is None else (normals, np.zeros(normals.shape[0]))

    def advanced(self, bars: int) -> Block:
        """This block on the same wire ``bars`` bars longer at the entrance (insertion's warm start): rows that
        follow the material move ``bars`` nodes on (walls, lumens); contact and angle rows stay (default)."""
        return self

    def with_tip(self, old: int, new: int) -> Block:
        """This block with the rows of node ``old``, the tip of a wire now ending at node ``new`` (insertion's warm
        start by the track predictor), moved to node ``new``: a tip pressed on a wall stays on it while the wire is
        pushed, where the other contacts stay in place (walls, lumens); other kinds are unchanged (default)."""
        return self

    def with_index(self, index: int) -> Block:
        return replace(self, index=index)
