"""The *full-space* layout: bar angles and node positions are both variables.

Why. In the reduced layout (:mod:`guidewire.program.formulation`) the bar angles ``φ`` are the only variables, so a node
position depends on every earlier angle: each position or wall row is a dense row of the Jacobian, and the
augmented-Lagrangian convexification of the (indefinite, for a wire under compression) Lagrangian Hessian is dense.
Here the nodes are variables too and the chain is closed by nonlinear equalities, one pair per bar, so every row has
at most three nonzeros, the Lagrangian Hessian is diagonal plus the tridiagonal energy Hessian, and with the
interleaved ordering below ``W + ρ CᵀC`` is banded: Newton–SQP (3-6 iterations) with O(n) sparse QPs.

Variables (3n), interleaved per bar: ``z = [φ_1, u_1, v_1, φ_2, u_2, v_2, …, φ_n, u_n, v_n]`` with the node
``p_k = s (u_k, v_k)`` in units of the length scale ``s`` (:func:`length_scale`); node 0 (the base point) is a
constant.

What this module adds to the blocks of :mod:`guidewire.blocks` (which it states like the reduced layout, with the
same rows and multipliers):

``closure``  (the first constraint: an SLSQP ``eq`` dict, sparse CSR ``jac``, diagonal ``hess``)
    ``x_k − x_{k−1} − l_k cos φ_k = 0``, ``y_k − y_{k−1} − l_k sin φ_k = 0``, rows ``x_1, y_1, x_2, y_2, …``.
    Multiplier: minus the force bar ``k`` transmits (the sum of every support force beyond it).
node rows
    linear here: ``lb ≤ s d · (u_k, v_k) ≤ ub`` (``LinearConstraint``, two nonzeros a row), so every iterate satisfies
    them up to the QP tolerance and no working set is needed.
angle rows
    the same ``LinearConstraint`` at the ``φ`` columns.

Objective: the same :class:`~guidewire.energy.EnergyTerms` on ``φ = z[0::3]`` (gradient and constant Hessian embedded at
the ``φ`` columns). The start is the model's ``φ0`` moved onto the angle rows, with ``P0 = chain.nodes(φ0)[1:]`` moved
onto the node rows (a wall's rows strictly inside), so the start satisfies all linear rows and the engine never
projects it (that projection is a dense QP).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint

import sqp

from ..blocks import AngleRows, Block, NodeRows
from ..scene.scene import Scene
from .model import Model
from .reduced import nonlinear_rows

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]

WALL_START_MARGIN = 1e-9
"""Start nodes are moved at least this fraction of the wire length inside every inequality node row (the engine
projects a start that violates a linear row by more than 1e-12, by a QP with a dense identity Hessian)."""

START_MARGIN = 1e-9
"""A start violating an inequality angle row (the b₂ bound) is projected onto the rows shrunk by this many radians."""

AUGMENTED_RUNGS = 5
"""Weights of the engine's augmented-Lagrangian ladder tried on a vessel's full-space program before an identity
shift goes on top of the term (``sqp.minimize(augmented_rungs=...)``; weights up to 1e4 times the first): measured
on the S-bend and tortuous vessels at 320-800 bars, 5 and 7 rungs gave the same energies in 18-74 iterations, 7 once
took 10 s where 5 took 2.1 s (tortuous, 800 bars), the engine's 12 took 2.8-20 s (:meth:`FullLayout.newton_options`)."""

POLISH_TOLERANCE = 1e-9
""":meth:`FullLayout.answer` leaves ``φ`` alone when no row is violated by more than this times the length scale
(1e-7 mm for a 100 mm wire; the answer is checked against ``tol · L`` = 1e-6 mm): the dense Gauss–Newton correction
costs O(m n²) (0.6 s for Fig. 6a at n = 1600, whose line contact makes m large) and is needed only when the closure
residuals accumulate along a long chain beyond that."""


def _phi(i: Any) -> Any:
    """Column of ``φ_i`` (0-based bar ``i``)."""
    return 3 * np.asarray(i)


def _x(k: Any) -> Any:
    """Column of ``x_k`` (1-based node ``k``)."""
    return 3 * (np.asarray(k) - 1) + 1


def _y(k: Any) -> Any:
    """Column of ``y_k`` (1-based node ``k``)."""
    return 3 * (np.asarray(k) - 1) + 2


@dataclass(frozen=True)
class _Closure:
    """The closure rows ``s u_k − s u_{k−1} − l_k (cos φ_k, sin φ_k)`` (node ``p_k = s u_k``, ``p_0`` the base), with
    a fixed sparsity pattern: only the ``φ`` entries change."""

    base: FloatArray
    lengths: FloatArray
    scale: float
    indptr: IntArray
    indices: IntArray
    template: FloatArray
    at_phi_x: IntArray
    at_phi_y: IntArray

    @classmethod
    def build(cls, base: FloatArray, lengths: FloatArray, scale: float) -> _Closure:
        n = lengths.size
        k = np.arange(1, n + 1)
        own = np.stack((_x(k), _y(k)), axis=1)  # (n, 2): the row's own node column, rows x_k, y_k
        cols = np.stack((own - 3, np.repeat(_phi(k - 1)[:, None], 2, axis=1), own), axis=2)  # (n, 2, 3), sorted
        data = np.broadcast_to(np.array([-scale, 0.0, scale]), cols.shape)
        keep = np.ones(cols.shape, dtype=bool)
        keep[0, :, 0] = False  # node 0 is the base point, a constant: no column
        counts = keep.sum(axis=2).ravel()
        indptr = np.concatenate(([0], np.cumsum(counts))).astype(np.int32)
        at_phi = indptr[:-1] + counts - 2  # the φ entry is the second to last of each row
        return cls(np.asarray(base, dtype=float), np.asarray(lengths, dtype=float), float(scale), indptr,
                   cols[keep].astype(np.int32), data[keep].copy(), at_phi[0::2].copy(), at_phi[1::2].copy())

    @property
    def n(self) -> int:
        return int(self.lengths.size)

    def fun(self, z: FloatArray) -> FloatArray:
        phi = z[0::3]
        p = self.scale * np.column_stack((z[1::3], z[2::3]))
        prev = np.vstack((self.base, p[:-1]))
        out = p - prev
        out[:, 0] -= self.lengths * np.cos(phi)
        out[:, 1] -= self.lengths * np.sin(phi)
        return out.ravel()

    def jac(self, z: FloatArray) -> sp.csr_matrix:
        phi = z[0::3]
        data = self.template.copy()
        data[self.at_phi_x] = self.lengths * np.sin(phi)
        data[self.at_phi_y] = -self.lengths * np.cos(phi)
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(2 * self.n, 3 * self.n))

    def hess(self, z: FloatArray, v: FloatArray) -> sp.csc_matrix:
        """``Σ v_i ∇²c_i``: diagonal, ``l_k (v_x cos φ_k + v_y sin φ_k)`` at the ``φ_k`` columns."""
        phi = z[0::3]
        v = np.reshape(v, (-1, 2))
        d = self.lengths * (v[:, 0] * np.cos(phi) + v[:, 1] * np.sin(phi))
        m = 3 * self.n
        return sp.csc_matrix((d, _phi(np.arange(self.n)).astype(np.int32),
                              ((np.arange(m + 1) + 2) // 3).astype(np.int32)), shape=(m, m))

    def constraint(self) -> dict[str, Any]:
        return {"type": "eq", "fun": self.fun, "jac": self.jac, "hess": self.hess}


def length_scale(scene: Scene) -> float:
    """``s = max(1 mm, |base| + L)``: every node lies within ``s`` of the origin, so the scaled node variables are
    at most 1 in magnitude, like the angles."""
    return max(1.0, float(np.hypot(*scene.base.point)) + scene.wire.length)


def _fixed_columns(A: sp.csr_matrix, lb: FloatArray, ub: FloatArray) -> tuple[IntArray, FloatArray]:
    """Columns set by equality rows with a single entry (a prescribed bar angle), and their values."""
    A = sp.csr_matrix(A)
    single = (np.diff(A.indptr) == 1) & (lb == ub)
    rows = np.flatnonzero(single)
    return A.indices[A.indptr[rows]], lb[rows] / A.data[A.indptr[rows]]


@dataclass(frozen=True)
class FullLayout:
    """Bar angles and (scaled) node positions as variables; see the module docstring."""

    model: Model
    scale: float
    closure: _Closure
    name: str = "full"

    @classmethod
    def build(cls, model: Model) -> FullLayout:
        scale = length_scale(model.scene)
        return cls(model, scale, _Closure.build(model.chain.base_point, model.chain.lengths, scale))

    # -- variables -----------------------------------------------------------------------------------------------
    @property
    def size(self) -> int:
        return 3 * self.model.n

    def angles(self, z: FloatArray) -> FloatArray:
        """Bar angles ``φ``, shape (n,)."""
        return np.asarray(z, dtype=float)[0::3].copy()

    def nodes(self, z: FloatArray) -> FloatArray:
        """Node positions as variables, shape (n + 1, 2), base first."""
        z = np.asarray(z, dtype=float)
        return np.vstack((self.model.chain.base_point, self.scale * np.column_stack((z[1::3], z[2::3]))))

    def pack(self, phi: FloatArray, nodes: FloatArray | None = None) -> FloatArray:
        """``z`` from bar angles and node positions (shape (n + 1, 2), base first; default ``chain.nodes(φ)``)."""
        phi = np.asarray(phi, dtype=float)
        p = self.model.chain.nodes(phi) if nodes is None else np.asarray(nodes, dtype=float)
        z = np.empty(3 * phi.size)
        z[0::3], z[1::3], z[2::3] = phi, p[1:, 0] / self.scale, p[1:, 1] / self.scale
        return z

    # -- objective -----------------------------------------------------------------------------------------------
    def fun(self, z: FloatArray) -> float:
        return self.model.energy.value(z[0::3])

    def jac(self, z: FloatArray) -> FloatArray:
        g = np.zeros(self.size)
        g[0::3] = self.model.energy.gradient(z[0::3])
        return g

    @property
    def hess0(self) -> sp.csc_matrix:
        H = sp.coo_matrix(self.model.hess0)
        m = self.size
        return sp.csc_matrix((H.data, (_phi(H.row), _phi(H.col))), shape=(m, m))

    # -- rows ----------------------------------------------------------------------------------------------------
    def own_constraints(self) -> list[Any]:
        return [self.closure.constraint()]

    def newton_options(self, blocks: Sequence[Block]) -> dict[str, Any]:
        """Options of :func:`sqp.minimize` with exact Hessians for this layout: with curved (lumen) rows, each QP
        first solved on the active set its last multipliers guess (``active_set_guess``: one banded KKT solve), and
        the augmented-Lagrangian weight's ladder cut to :data:`AUGMENTED_RUNGS` with an identity shift on top of the
        term beyond (``augmented_rungs``).

        A wire compressed in a vessel has a Lagrangian Hessian that is positive definite only on the null space of
        the closure rows *and* the lumen rows it presses on (free, it would buckle): the augmented-Lagrangian term
        on those rows (the engine's default, on the rows the QP held) makes it definite, at weights up to ~1e12 where
        the reduced curvature is small, which an interior-point QP does not solve reliably — on the guessed active set
        the step is the KKT solve, where that term is constant. Measured (auto layout, ``branches="first"``): S-bend
        at 400 bars 130 s (30 iterations here, then the dense program) → 3.3 s; tortuous at 400 bars > 150 s →
        2.8 s; the 250 mm arch at 400 bars 0.50 → 0.21 s; the bend at 800 bars 4 iterations either way. The weights
        that certify definiteness there (model diagonals up to 1e15) still failed the guessed active set's residual
        check and PIQP's iteration limit: with the ladder cut, S-bend 400 / 800 bars 3.0 / 20 s → 0.25 / 0.47 s,
        tortuous 400 / 640 / 800 bars 2.8 / 18 / 5.3 s → 0.72 / 1.1 / 2.1 s (a step extended along the shifted
        direction while the merit keeps falling, :func:`sqp.linesearch.expanded`, recovers what the shift shortens)."""
        curved = any(isinstance(r, NodeRows) and not r.linear for r in (b.rows(self.model) for b in blocks))
        return {"active_set_guess": True, "augmented_rungs": AUGMENTED_RUNGS} if curved else {}

    def node_rows(self, rows: NodeRows) -> Any:
        """Linear rows as a ``LinearConstraint``; quadratic ones (a curved boundary) as a constraint with a sparse
        Jacobian (two entries a row, four for a bar's row) and a 2 × 2 Hessian block per node (a bar's row: between
        its two nodes, the constant ``ω (p_k × p_{k+1})`` term)."""
        k, m, scale = rows.nodes, rows.nodes.size, self.scale
        cols = np.column_stack((_x(k), _y(k))).ravel()
        row_index = np.repeat(np.arange(m), 2)
        if rows.linear:
            A = sp.csr_matrix((scale * rows.directions.ravel(), (row_index, cols)), shape=(m, self.size))
            A.eliminate_zeros()
            return LinearConstraint(A, rows.lb, rows.ub)
        size = self.size
        hess_rows, hess_cols = np.repeat(cols.reshape(m, 2), 2, axis=1).ravel(), np.tile(cols.reshape(m, 2), 2).ravel()
        bar = rows.bars
        if bar.size:  # a bar's row: its second node's entries, and its cross term's blocks (k, k+1) and (k+1, k)
            first, second = k[bar], k[bar] + 1
            row_index = np.concatenate((row_index, np.repeat(bar, 2)))
            cols = np.concatenate((cols, np.column_stack((_x(second), _y(second))).ravel()))
            # ω (p_k × p_{k+1}): ∂²/∂x_k∂y_{k+1} = ω, ∂²/∂y_k∂x_{k+1} = −ω, and their mirror images
            hess_rows = np.concatenate((hess_rows, _x(first), _y(first), _y(second), _x(second)))
            hess_cols = np.concatenate((hess_cols, _y(second), _x(second), _x(first), _y(first)))

        def value(z: FloatArray) -> FloatArray:
            return rows.values(self.nodes(z))

        def jac(z: FloatArray) -> sp.csr_matrix:
            p = self.nodes(z)
            data = rows.gradients(p).ravel()
            if bar.size:
                data = np.concatenate((data, rows.next_gradients(p).ravel()))
            return sp.csr_matrix((scale * data, (row_index, cols)), shape=(m, size))

        def hess(z: FloatArray, v: FloatArray) -> sp.csc_matrix:
            v = np.asarray(v, dtype=float)
            data = (scale**2 * v[:, None, None] * rows.hessians).ravel()
            if bar.size:
                w = scale**2 * v[bar] * rows.turns[bar]
                data = np.concatenate((data, w, -w, w, -w))
            return sp.csc_matrix((data, (hess_rows, hess_cols)), shape=(size, size))

        return nonlinear_rows(value, jac, hess, rows.lb, rows.ub)

    def angle_rows(self, rows: AngleRows) -> LinearConstraint:
        A = sp.coo_matrix(rows.A)
        return LinearConstraint(sp.csr_matrix((A.data, (A.row, _phi(A.col))), shape=(A.shape[0], self.size)),
                                rows.lb, rows.ub)

    # -- start ---------------------------------------------------------------------------------------------------
    def start(self, blocks: Sequence[Block]) -> FloatArray:
        """The model's start moved onto every angle row and node row (inequalities strictly inside)."""
        model = self.model
        specs = [b.rows(model) for b in blocks]
        phi = _onto_angle_rows(np.asarray(model.x0, dtype=float), [r for r in specs if isinstance(r, AngleRows)])
        p = model.chain.nodes(phi)
        node_specs = [r for r in specs if isinstance(r, NodeRows) and r.linear]  # only linear rows must hold
        margin = WALL_START_MARGIN * model.scene.wire.length
        for _ in range(10):  # alternating projections (one round when the rows do not interact)
            moved = False
            for r in node_specs:
                equal = r.lb == r.ub
                lo = np.where(equal, r.lb, r.lb + margin)
                hi = np.where(equal, r.ub, r.ub - margin)
                value = r.values(p)
                delta = np.clip(value, lo, hi) - value
                if np.any(delta != 0.0):  # (a row's direction is nonzero: a unit normal or a coordinate axis)
                    np.add.at(p, r.nodes, (delta / np.einsum("ij,ij->i", r.directions, r.directions))[:, None]
                              * r.directions)
                    moved = moved or bool(np.any((value < lo) & ~equal | (value > hi) & ~equal))
            if not moved:
                break
        return self.pack(phi, p)

    # -- multipliers ---------------------------------------------------------------------------------------------
    def block_multipliers(self, raw: Sequence[Any]) -> list[FloatArray]:
        """Drop the closure's multipliers: the blocks' rows and signs are those of the reduced layout."""
        return [np.asarray(v, dtype=float).copy() for v in raw[1:]]

    def raw_multipliers(self, blocks: Sequence[Block], per_block: Sequence[FloatArray]) -> list[FloatArray]:
        """The inverse of :meth:`block_multipliers`: the closure multipliers follow from stationarity in the node
        positions, ``μ_k = μ_{k+1} − f_k`` (a suffix sum of the node forces ``f = λ d`` beyond bar ``k``)."""
        force = np.zeros((self.model.n + 1, 2))
        for block, lam in zip(blocks, per_block, strict=True):
            rows = block.rows(self.model)
            if isinstance(rows, NodeRows):
                rows.add_to_nodes(np.asarray(lam, dtype=float)[:, None] * rows.directions, force)
        closure = -np.cumsum(force[::-1], axis=0)[::-1][1:].ravel()
        return [closure, *(np.asarray(v, dtype=float) for v in per_block)]

    # -- answer --------------------------------------------------------------------------------------------------
    def answer(self, blocks: Sequence[Block], z: FloatArray, per_block: Sequence[FloatArray]) -> FloatArray:
        """``φ = z[0::3]`` moved (least norm, Gauss–Newton) onto the equality rows and the active inequality rows
        (``λ ≠ 0``) in the chain's own kinematics ``chain.nodes(φ)``; prescribed bar angles stay fixed.

        Why: the engine stops at the iterate whose rows are within ``tol``. The closure residuals of a Newton step
        all have one sign (they are the second-order terms ``½ l_k (cos φ_k, sin φ_k) dφ_k²``), so in the reduced
        kinematics they add up along the chain: ``n`` bars each closed to ``ε`` can miss a contact by ``n ε``
        (5e-8 mm at n = 1600). The correction costs O(m n) for ``m`` such rows, changes the energy at second order
        only (``∇E·δφ = −λ·r`` at a KKT point) and is kept only if it reduces the residual."""
        model = self.model
        phi = self.angles(z)
        worst = max((float(np.max(b.violation(model, phi), initial=0.0)) for b in blocks), default=0.0)
        if worst <= POLISH_TOLERANCE * self.scale:
            return phi
        specs = [(b.rows(model), np.asarray(lam, dtype=float)) for b, lam in zip(blocks, per_block, strict=True)]
        free = np.ones(model.n, dtype=bool)
        for rows, _ in specs:
            if isinstance(rows, AngleRows):
                free[_fixed_columns(rows.A, rows.lb, rows.ub)[0]] = False
        J, r = self._active_rows(phi, specs)
        if r.size == 0 or not np.any(r):
            return phi
        best = float(np.max(np.abs(r)))
        for _ in range(2):
            step = np.zeros(model.n)
            step[free] = -np.linalg.lstsq(J[:, free], r, rcond=None)[0]
            trial = phi + step
            J_t, r_t = self._active_rows(trial, specs)
            worst = float(np.max(np.abs(r_t)))
            if not worst < best:
                break
            phi, J, r, best = trial, J_t, r_t, worst
        return phi

    def _active_rows(self, phi: FloatArray, specs: Sequence[tuple[Any, FloatArray]]) -> tuple[FloatArray, FloatArray]:
        """Jacobian (dense, m × n) and residual of the rows :meth:`answer` restores."""
        chain, n = self.model.chain, self.model.n
        points = chain.nodes(phi)
        J_parts, r_parts = [np.zeros((0, n))], [np.zeros(0)]
        for rows, lam in specs:
            equal = rows.lb == rows.ub
            if isinstance(rows, AngleRows):
                single = np.diff(sp.csr_matrix(rows.A).indptr) == 1
                active = np.flatnonzero(~(equal & single) & (equal | (lam != 0)))
            else:
                active = np.flatnonzero(equal | (lam != 0))
            if not active.size:
                continue
            bound = np.where(equal[active] | (lam[active] > 0), rows.lb[active], rows.ub[active])
            if isinstance(rows, AngleRows):
                A = sp.csr_matrix(rows.A)[active].toarray()
                J_parts.append(A)
                r_parts.append(A @ phi - bound)
            else:
                d = rows.gradients(points)[active]
                J = np.einsum("mi,min->mn", d, chain.node_jacobian(phi, rows.nodes[active]))
                bar = rows.bars
                if bar.size:  # a bar's row: its second node's part
                    pick = np.flatnonzero(np.isin(active, bar))
                    second = rows.next_gradients(points)[np.searchsorted(bar, active[pick])]
                    J[pick] += np.einsum("mi,min->mn", second, chain.node_jacobian(phi, rows.nodes[active[pick]] + 1))
                J_parts.append(J)
                r_parts.append(rows.values(points)[active] - bound)
        return np.vstack(J_parts), np.concatenate(r_parts)


def _onto_angle_rows(phi: FloatArray, specs: Sequence[AngleRows]) -> FloatArray:
    """``phi`` with the prescribed bar angles set and, when it violates an inequality angle row, the nearest angles
    (least squares) within those rows shrunk by :data:`START_MARGIN` (a QP in ``n`` variables, by :mod:`sqp`)."""
    if not specs:
        return phi
    phi = phi.copy()
    for rows in specs:
        cols, values = _fixed_columns(rows.A, rows.lb, rows.ub)
        phi[cols] = values
    if all(np.all(row_ok) for row_ok in (((r.A @ phi) >= r.lb) & ((r.A @ phi) <= r.ub) for r in specs)):
        return phi
    n = phi.size
    constraints = []
    for rows in specs:
        equal = rows.lb == rows.ub
        margin = np.where(equal, 0.0, np.minimum(START_MARGIN, 0.25 * (rows.ub - rows.lb)))
        constraints.append(LinearConstraint(rows.A, rows.lb + margin, rows.ub - margin))
    target = phi.copy()
    res = sqp.minimize(lambda x: 0.5 * float((x - target) @ (x - target)), phi, jac=lambda x: x - target,
                       hess=lambda x: sp.identity(n, format="csc"), constraints=constraints)
    return np.asarray(res.x, dtype=float) if res.success else phi
