"""What every constraint block has in common: its rows as data, its loads on the wire, its violation.

A block is one kind of constraint of a scene (a contact position, a contact angle, a wall, the b₂ bound, …) written
once as *rows*, in one of two forms that both program layouts know how to state
(:mod:`~guidewire.program.formulation` for the reduced program in the bar angles ``φ``,
:mod:`guidewire.program.full_space` for angles and node positions):

:class:`NodeRows`
    ``lb ≤ d_r · p_{k_r} ≤ ub`` — linear in a node position ``p_k`` (mm), one direction ``d_r`` per row. Nonlinear
    in ``φ`` (``p_k`` is a sum of ``l_j (cos φ_j, sin φ_j)``), linear in the full space. A row may instead hold a
    point of a bar, ``(1 − τ) p_k + τ p_{k+1}`` (a bar's contact with a vessel's corner).
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


@dataclass(frozen=True)
class NodeRows:
    """Rows ``lb ≤ d_r · q_r + ½ (q_r − c_r)ᵀ H_r (q_r − c_r) ≤ ub`` on points ``q_r`` of the wire: linear (``H``
    None: walls, contact positions) or a quadratic model of a curved boundary around ``c_r`` (a lumen).

    ``q_r`` is the node ``p_{k_r}``, or with :attr:`fractions` the point ``(1 − τ_r) p_{k_r} + τ_r p_{k_r + 1}`` of the
    bar between nodes ``k_r`` and ``k_r + 1`` (a bar's contact with a vessel's corner, whose force the two nodes share
    as ``1 − τ`` and ``τ``). A bar's row is linear (its ``H_r`` zero): the layouts' Hessians blend its two nodes'
    second derivatives, not their products.

    Attributes
    ----------
    nodes : ndarray of int, shape (m,)
        Node ``k_r`` of every row (1..n; the base node is fixed and never a row; a bar's row: its first node, 1..n−1).
    directions : ndarray, shape (m, 2)
        ``d_r`` (dimensionless; a unit vector or a coordinate axis).
    lb, ub : ndarray, shape (m,)
        Bounds in mm (``-inf``/``inf`` for none; ``lb == ub`` for an equality row).
    hessians : ndarray, shape (m, 2, 2), or None
        ``H_r`` (1/mm), symmetric; None for linear rows.
    centres : ndarray, shape (m, 2), or None
        ``c_r`` (mm), where the quadratic model is taken; None for linear rows.
    fractions : ndarray, shape (m,), or None
        ``τ_r`` in [0, 1] (0: the node itself); None: every row on its node.
    """

    nodes: IntArray
    directions: FloatArray
    lb: FloatArray
    ub: FloatArray
    hessians: FloatArray | None = None
    centres: FloatArray | None = None
    fractions: FloatArray | None = None

    def __post_init__(self) -> None:
        tau = self.fractions
        if tau is None:
            return
        if tau.shape != self.nodes.shape or np.any((tau < 0.0) | (tau > 1.0)):
            raise ValueError("NodeRows.fractions: one τ in [0, 1] per row")
        if np.any(self.nodes[tau > 0.0] < 1):
            raise ValueError("NodeRows.fractions: a bar's row starts at node 1 or later (the base node is fixed)")
        if self.hessians is not None and np.any(self.hessians[tau > 0.0]):
            raise ValueError("NodeRows.fractions: a bar's row (τ > 0) must be linear (its Hessian zero)")

    @property
    def linear(self) -> bool:
        """Whether the rows are linear in the node positions."""
        return self.hessians is None

    def row_points(self, nodes: FloatArray) -> FloatArray:
        """The rows' points ``q_r`` for node positions ``nodes`` (shape (n + 1, 2)), shape (m, 2)."""
        p = nodes[self.nodes]
        tau = self.fractions
        if tau is None:
            return p
        bar = np.flatnonzero(tau)
        p[bar] += tau[bar, None] * (nodes[self.nodes[bar] + 1] - p[bar])
        return p

    def values(self, points: FloatArray) -> FloatArray:
        """Row values at node positions ``points`` (shape (n + 1, 2)), shape (m,)."""
        p = self.row_points(points)
        out = np.einsum("ij,ij->i", p, self.directions)
        if self.hessians is not None:
            q = p - self.centres
            out = out + 0.5 * np.einsum("ia,iab,ib->i", q, self.hessians, q)
        return out

    def gradients(self, points: FloatArray) -> FloatArray:
        """``∂ row / ∂q_r`` at ``points``: ``d + H (q − c)``, shape (m, 2) (the gradient in ``p_{k_r}`` and
        ``p_{k_r + 1}`` is this times ``1 − τ_r`` and ``τ_r``: :meth:`spread`)."""
        if self.hessians is None:
            return self.directions
        return self.directions + np.einsum("iab,ib->ia", self.hessians, self.row_points(points) - self.centres)

    def spread(self) -> tuple[IntArray, IntArray, FloatArray]:
        """The rows' nodes with their weights in ``q_r``: ``(row, node, weight)`` arrays, one entry per row and node
        (a node row: its node, weight 1; a bar's row: ``k_r`` with ``1 − τ_r`` and ``k_r + 1`` with ``τ_r``)."""
        rows = np.arange(self.nodes.size)
        tau = self.fractions
        if tau is None:
            return rows, self.nodes, np.ones(self.nodes.size)
        bar = np.flatnonzero(tau)
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

    def add_loads(self, model: Model, lam: FloatArray, loads: Loads) -> None:
        """Add what the multipliers ``lam`` of this block exert on the wire to ``loads`` (default: nothing)."""

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
