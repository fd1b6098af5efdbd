"""The paper's reduced program (:class:`ReducedLayout`): the bar angles ``φ`` are the variables, node rows are
nonlinear and dense.

A node-row block is an SLSQP dict (``eq`` when every row is an equality, ``ineq`` ``d·p − lb ≥ 0`` when only lower
bounds are finite, else a ``NonlinearConstraint``: :func:`nonlinear_rows`) with analytic ``jac`` (dense: a node
depends on every earlier angle) and ``hess(φ, v)`` (diagonal for linear rows: a dense array up to
:data:`sqp.STRUCTURED_MIN` variables, where the engine works densely anyway, a sparse one above); an
angle-row block is a ``LinearConstraint``. No variable bounds.

``sqp`` evaluates every block at the same point (values, then Jacobians, then Hessians), so the chain's kinematics at
the last point asked for (:class:`ChainPoint`) are kept once per program and shared by all its node-row blocks.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint, NonlinearConstraint

from sqp import STRUCTURED_MIN

from ..blocks import AngleRows, Block, NodeRows
from ..chain.kinematics import BarChain
from .model import Model

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]


class ChainPoint:
    """The chain's kinematics at the last bar angles asked for: ``cos φ``, ``sin φ``, the bar vectors' components
    ``l cos φ``, ``l sin φ`` and the nodes, recomputed only when the angles differ (compared exactly, against a copy
    of the last ones)."""

    __slots__ = ("chain", "cos", "lcos", "lsin", "nodes", "phi", "sin")

    def __init__(self, chain: BarChain) -> None:
        self.chain = chain
        self.phi: FloatArray | None = None

    def at(self, phi: Any) -> ChainPoint:
        """``self``, holding the kinematics at ``phi`` (shape (n,))."""
        phi = np.asarray(phi, dtype=float)
        seen = self.phi
        if seen is None or seen.shape != phi.shape or not (seen == phi).all():
            lengths = self.chain.lengths
            self.cos, self.sin = np.cos(phi), np.sin(phi)
            self.lcos, self.lsin = lengths * self.cos, lengths * self.sin
            self.nodes = self.chain.nodes_from_steps(self.lcos, self.lsin)
            self.phi = phi.copy()
        return self


def _diagonal(values: FloatArray) -> Any:
    """A diagonal matrix: a dense array up to :data:`sqp.STRUCTURED_MIN` rows (``sqp`` densifies every
    Hessian there; building a scipy matrix costs more than writing the array), else a CSC matrix built directly
    (``scipy.sparse.diags`` costs ~1 ms a call; above ``STRUCTURED_MIN`` ``sqp`` keeps the sparse energy Hessian's
    format, for its structured KKT path)."""
    n = values.size
    if n <= STRUCTURED_MIN:
        out = np.zeros((n, n))
        out.flat[:: n + 1] = values
        return out
    index = np.arange(n + 1, dtype=np.int32)
    return sp.csc_matrix((values, index[:-1], index), shape=(n, n))


def nonlinear_rows(value: Any, jac: Any, hess: Any, lb: FloatArray, ub: FloatArray) -> Any:
    """Rows ``lb ≤ value(x) ≤ ub`` for :func:`sqp.minimize`, in the sign convention of :mod:`guidewire.blocks.base`
    (λ ≥ 0 at an active lower bound): an SLSQP ``eq`` dict when every row is an equality, an ``ineq`` dict
    ``value − lb ≥ 0`` when only lower bounds are finite, else a ``NonlinearConstraint``."""
    if np.array_equal(lb, ub):
        return {"type": "eq", "fun": lambda x: value(x) - lb, "jac": jac, "hess": hess}
    if np.all(np.isposinf(ub)):
        return {"type": "ineq", "fun": lambda x: value(x) - lb, "jac": jac, "hess": hess}
    return NonlinearConstraint(value, lb, ub, jac=jac, hess=hess)


def _curvature_term(chain: Any, phi: FloatArray, nodes: IntArray, weighted: FloatArray) -> FloatArray:
    """``Σ_r (∂p_{k_r}/∂φ)ᵀ W_r (∂p_{k_r}/∂φ)`` for 2 × 2 matrices ``W_r``, dense (n, n): with
    ``e_j = l_j (−sin φ_j, cos φ_j)`` and ``S_j = Σ_{k_r ≥ j} W_r`` (a suffix sum), entry ``(i, j)`` is
    ``e_iᵀ S_{max(i, j)} e_j`` — O(n²), for the quadratic rows of a curved boundary."""
    n = chain.n_bars
    acc = np.zeros((n + 1, 2, 2))
    np.add.at(acc, nodes, weighted)
    suffix = np.cumsum(acc[::-1], axis=0)[::-1][1:]  # row j (bar j+1): rows at nodes ≥ j+1
    e = chain.lengths[:, None] * np.column_stack((-np.sin(phi), np.cos(phi)))
    w = np.einsum("jab,jb->ja", suffix, e)  # S_j e_j, (n, 2): O(n)
    out = e @ w.T  # e_iᵀ S_j e_j, one (n × 2)(2 × n) product: right for j ≥ i
    np.copyto(out, out.T.copy(), where=_below_diagonal(n))  # mirrored below (3.6x faster than np.where at n = 250)
    return out


def _add_bar_cross_terms(out: FloatArray, chain: Any, phi: FloatArray, after: IntArray, weights: FloatArray) -> None:
    """Add ``Σ_b w_b ∂²[(p_{k+1} − p_k) × (a − p_k)]/∂φ²``'s part from the product of the two nodes' derivatives to
    ``out`` (n, n): ``(p_k, p_{k+1})`` enter as ``p_k × p_{k+1}``, whose second derivative, with ``∂p_{k+1}/∂φ =
    ∂p_k/∂φ + e_{k+1}`` (``e_j = l_j (−sin φ_j, cos φ_j)`` in column ``j``) and ``e_i × e_i = 0``, is
    ``e_i × e_{k+1}`` at ``(i, k+1)`` and ``(k+1, i)`` for every ``i ≤ k`` — one row and column per bar row, O(n)
    each. ``after`` holds ``k`` (the 0-based column of bar ``k + 1``)."""
    e = chain.lengths[:, None] * np.column_stack((-np.sin(phi), np.cos(phi)))
    cross = e[None, :, 0] * e[after, None, 1] - e[None, :, 1] * e[after, None, 0]  # (bars, n): e_i × e_{k+1}
    cross *= (np.arange(e.shape[0])[None, :] < after[:, None]) * weights[:, None]
    np.add.at(out, (slice(None), after), cross.T)
    np.add.at(out, (after, slice(None)), cross)


@functools.lru_cache(maxsize=8)
def _below_diagonal(n: int) -> NDArray[np.bool_]:
    """The (n, n) mask of the entries below the diagonal, read-only (kept: a sequence solves at a few sizes)."""
    index = np.arange(n)
    mask = index[:, None] > index[None, :]
    mask.flags.writeable = False
    return mask


@dataclass(frozen=True)
class ReducedLayout:
    """The paper's program: the bar angles are the variables; node rows are nonlinear and dense."""

    model: Model
    name: str = "reduced"
    point: ChainPoint = field(init=False, compare=False, repr=False)
    """The chain at the last point any of its node-row blocks was evaluated at (shared by them)."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "point", ChainPoint(self.model.chain))

    @property
    def size(self) -> int:
        return self.model.n

    @property
    def hess0(self) -> sp.csc_matrix:
        return self.model.hess0

    def fun(self, x: FloatArray) -> float:
        return self.model.energy.value(x)

    def jac(self, x: FloatArray) -> FloatArray:
        return self.model.energy.gradient(x)

    def angles(self, x: FloatArray) -> FloatArray:
        return np.asarray(x, dtype=float)

    def nodes(self, x: FloatArray) -> FloatArray:
        return self.model.chain.nodes(np.asarray(x, dtype=float))

    def own_constraints(self) -> list[Any]:
        return []

    def newton_options(self, blocks: Sequence[Block]) -> dict[str, Any]:
        """Options of :func:`sqp.minimize` with exact Hessians for this layout: with curved (lumen) rows, each QP
        first solved on the active set its last multipliers guess (``active_set_guess``: for this dense program the
        range-space solve of the rows guessed, :func:`sqp.subproblem._factored_guess`, where DAQP transforms every
        row); else the engine's defaults."""
        curved = any(isinstance(r, NodeRows) and not r.linear for r in (b.rows(self.model) for b in blocks))
        return {"active_set_guess": True} if curved else {}

    def node_rows(self, rows: NodeRows) -> Any:
        chain, point = self.model.chain, self.point
        k = rows.nodes
        mask = np.arange(chain.n_bars)[None, :] < k[:, None]  # bar j+1 ≤ node k
        bar = rows.bars
        after = k[bar]  # a bar row's second node k + 1 adds bar k + 1 (column k)

        def value(phi: FloatArray) -> FloatArray:
            return rows.values(point.at(phi).nodes)

        def jac(phi: FloatArray) -> FloatArray:
            at = point.at(phi)
            d = rows.directions if rows.linear else rows.gradients(at.nodes)
            if bar.size:
                second = rows.next_gradients(at.nodes)
                d = d.copy()
                d[bar] += second  # (node k + 1 depends on the bars up to k, like node k, and on bar k + 1)
            # mask · (d_x · (−l sin φ) + d_y · l cos φ), written into one (m, n) array (the same operations in
            # the same order as the expression; the dense Jacobian is the largest array of an iteration)
            out = np.multiply(d[:, 0:1], -at.lsin[None, :])
            out += np.multiply(d[:, 1:2], at.lcos[None, :])
            out *= mask
            if bar.size:
                out[bar, after] = second[:, 0] * -at.lsin[after] + second[:, 1] * at.lcos[after]
            return out

        def hess(phi: FloatArray, v: FloatArray) -> Any:
            v = np.asarray(v, dtype=float)
            at = point.at(phi)
            if rows.linear:
                return _diagonal(chain.node_hessian_diagonal(phi, k, v[:, None] * rows.directions, (at.cos, at.sin)))
            d = rows.gradients(at.nodes)
            out = _curvature_term(chain, phi, k, v[:, None, None] * rows.hessians)
            if not bar.size:
                out[np.diag_indices_from(out)] += chain.node_hessian_diagonal(phi, k, v[:, None] * d, (at.cos, at.sin))
                return out
            nodes, weights = np.concatenate((k, after + 1)), np.concatenate((d, rows.next_gradients(at.nodes)))
            weights *= np.concatenate((v, v[bar]))[:, None]
            out[np.diag_indices_from(out)] += chain.node_hessian_diagonal(phi, nodes, weights, (at.cos, at.sin))
            _add_bar_cross_terms(out, chain, phi, after, v[bar] * rows.turns[bar])
            return out

        return nonlinear_rows(value, jac, hess, rows.lb, rows.ub)

    def angle_rows(self, rows: AngleRows) -> LinearConstraint:
        return LinearConstraint(rows.A, rows.lb, rows.ub)

    def start(self, blocks: Sequence[Block]) -> FloatArray:
        return self.model.x0

    def block_multipliers(self, raw: Sequence[Any]) -> list[FloatArray]:
        return [np.asarray(v, dtype=float).copy() for v in raw]

    def raw_multipliers(self, blocks: Sequence[Block], per_block: Sequence[FloatArray]) -> list[FloatArray]:
        return [np.asarray(v, dtype=float) for v in per_block]

    def answer(self, blocks: Sequence[Block], x: FloatArray, per_block: Sequence[FloatArray]) -> FloatArray:
        return np.asarray(x, dtype=float).copy()
