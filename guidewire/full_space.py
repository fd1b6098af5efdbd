"""A scene as a *full-space* nonlinear program: bar angles and node positions are both variables.

Why. In the reduced formulation (:mod:`guidewire.formulation`) the bar angles ``φ`` are the only variables, so a node
position depends on every earlier angle: each position or wall row is a dense row of the Jacobian, and the
augmented-Lagrangian convexification of the (indefinite, for a wire under compression) Lagrangian Hessian is dense.
Here the nodes are variables too and the chain is closed by nonlinear equalities, one pair per bar, so every row has
at most three nonzeros, the Lagrangian Hessian is diagonal plus the tridiagonal energy Hessian, and with the
interleaved ordering below ``W + ρ CᵀC`` is banded: Newton–SQP (3-6 iterations) with O(n) sparse QPs.

Variables (3n), interleaved per bar: ``z = [φ_1, x_1, y_1, φ_2, x_2, y_2, …, φ_n, x_n, y_n]``; node 0 (the base point)
is a constant.

Constraint blocks, in this order (the ones after ``closure`` exactly as the reduced formulation has them, with the
same multipliers except the sign of the wall rows, see :meth:`FullSpaceFormulation.reduced_multipliers`):

``closure``  (SLSQP ``eq`` dict, sparse CSR ``jac``, diagonal ``hess``)
    ``x_k − x_{k−1} − l_k cos φ_k = 0``, ``y_k − y_{k−1} − l_k sin φ_k = 0``, rows ``x_1, y_1, x_2, y_2, …``.
    Multiplier: minus the force bar ``k`` transmits (the sum of every support force beyond it).
``position``  (``LinearConstraint``) ``x_k = P_x``, ``y_k = P_y`` per contact with a point. Multiplier = the force.
``angle``  (``LinearConstraint``; scheme "paper" only) ``φ_k = θ*``. Multiplier = the moment.
``wall``  (``LinearConstraint``, one block per wall) ``n̂ · p_k ≤ offset`` for every node 1..n. Linear, so every
    iterate satisfies it (up to the QP tolerance) and no working set is needed. Multiplier ``≤ 0`` (upper side).
``relative_angle``  (``LinearConstraint``) the reduced ``−b₂ ≤ Δθ ≤ b₂`` rows at the ``φ`` columns.

Objective: the same :class:`~guidewire.energy.EnergyTerms` on ``φ = z[0::3]`` (gradient and constant Hessian embedded at
the ``φ`` columns). The start is the reduced formulation's start ``φ0`` with ``P0 = chain.nodes(φ0)[1:]``, the
contact nodes moved onto their targets and every node into the walls, so the start satisfies all linear rows and
the engine never projects it (that projection is a dense QP).

Use::

    full = formulate_full(scene, bars=1600)
    res = sqp.minimize(**full.arguments(), hess=full.hess, qp_solver=full.qp_solver)
    sol = build_solution(full.reduced, full.as_reduced_result(res), time)
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
import qpsolvers
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint, OptimizeResult

import sqp
from sqp.hessian import DENSE_LIMIT

from .formulation import ConstraintBlock, Formulation, formulate
from .result import Solution, build_solution
from .scene import Scene

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]

WALL_START_MARGIN = 1e-9
"""Start nodes are moved at least this fraction of the wire length inside every wall (the engine projects a start
that violates a linear row by more than 1e-12, by a QP with a dense identity Hessian)."""

START_MARGIN = 1e-9
"""A start violating the b₂ rows is projected onto them shrunk by this many radians."""

SPARSE_QP_SOLVER = "piqp"
"""The qpsolvers backend for the sparse subproblems (more than :data:`DENSE_BARS` bars). Measured per subproblem on
Fig. 6a, n = 1600 (4800 variables, 3200 equalities, 1600 wall rows): PIQP's sparse backend 13-16 ms, Clarabel 48-54 ms,
OSQP fails (not converged in 4000 iterations, ~350 ms), ProxQP's sparse backend takes minutes. Whole solves at
n = 1600: Fig. 6a 0.70 s with PIQP against 1.08 s with Clarabel (both before the polish was made conditional),
Table 1 (π/4) 53 ms against 73 ms."""

POLISH_TOLERANCE = 1e-9
""":meth:`FullSpaceFormulation.polished_angles` leaves ``φ`` alone when no reduced row is violated by more than this
times the length scale (1e-7 mm for a 100 mm wire; the answer is checked against ``tol · L`` = 1e-6 mm): the dense
Gauss–Newton correction costs O(m n²) (0.6 s for Fig. 6a at n = 1600, whose line contact makes m large) and is needed
only when the closure residuals accumulate along a long chain beyond that."""

DENSE_BARS = DENSE_LIMIT // 3
"""Up to this many bars (``3n ≤`` :data:`sqp.hessian.DENSE_LIMIT` variables) the engine works densely: DAQP."""


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


def _embed_columns(A: Any, n_bars: int) -> sp.csr_matrix:
    """Rows over ``φ`` (n columns) as rows over ``z`` (3n columns)."""
    A = sp.coo_matrix(A)
    return sp.csr_matrix((A.data, (A.row, _phi(A.col))), shape=(A.shape[0], 3 * n_bars))


@dataclass(frozen=True)
class FullSpaceFormulation:
    """The full-space program of one scene (see the module docstring).

    Attributes
    ----------
    reduced : Formulation
        The reduced formulation of the same scene (every wall on every node): its chain, energy, contact nodes, start
        and blocks. :func:`guidewire.result.build_solution` takes it with :meth:`as_reduced_result`.
    blocks : tuple of ConstraintBlock
        ``closure`` first (members: the bars, nodes: the node of every row), then the reduced blocks' kinds,
        members and nodes in the reduced order; ``index`` into :attr:`constraints`.
    constraints : tuple
        Arguments for ``sqp.minimize(constraints=...)``.
    hess0 : scipy.sparse.csc_matrix, shape (3n, 3n)
        The reduced ``hess0`` (energy Hessian) at the ``φ`` rows and columns.
    x0 : ndarray, shape (3n,)
        The start; it satisfies every linear row.
    length_scale : float
        ``s`` (mm): the node variables are ``x_k / s``, ``y_k / s`` (see the module docstring).
    """

    reduced: Formulation
    blocks: tuple[ConstraintBlock, ...]
    constraints: tuple[Any, ...]
    hess0: sp.csc_matrix
    x0: FloatArray
    length_scale: float

    @property
    def n(self) -> int:
        """Number of bars."""
        return self.reduced.n

    @property
    def size(self) -> int:
        """Number of variables, ``3n``."""
        return 3 * self.n

    @property
    def scene(self) -> Scene:
        return self.reduced.scene

    @property
    def qp_solver(self) -> str:
        """The backend to use: DAQP while the engine works densely, else :data:`SPARSE_QP_SOLVER`."""
        return "daqp" if self.n <= DENSE_BARS else SPARSE_QP_SOLVER

    # -- variables -----------------------------------------------------------------------------------------------
    def angles(self, z: FloatArray) -> FloatArray:
        """Bar angles ``φ``, shape (n,)."""
        return np.asarray(z, dtype=float)[0::3].copy()

    def nodes(self, z: FloatArray) -> FloatArray:
        """Node positions as variables, shape (n + 1, 2), base first."""
        z = np.asarray(z, dtype=float)
        return np.vstack((self.reduced.chain.base_point, self.length_scale * np.column_stack((z[1::3], z[2::3]))))

    def pack(self, phi: FloatArray, nodes: FloatArray | None = None) -> FloatArray:
        """``z`` from bar angles and node positions (shape (n + 1, 2), base first; default ``chain.nodes(φ)``)."""
        return _pack(self.reduced, self.length_scale, phi, nodes)

    # -- objective -----------------------------------------------------------------------------------------------
    def fun(self, z: FloatArray) -> float:
        """Bending energy in N·mm."""
        return self.reduced.energy.value(z[0::3])

    def jac(self, z: FloatArray) -> FloatArray:
        """Gradient, shape (3n,): the energy gradient at the ``φ`` entries."""
        g = np.zeros(self.size)
        g[0::3] = self.reduced.energy.gradient(z[0::3])
        return g

    def hess(self, z: FloatArray) -> Any:
        """The constant energy Hessian :attr:`hess0` (dense while the engine works densely)."""
        return self._dense_hess0 if self.size <= DENSE_LIMIT else self.hess0

    @cached_property
    def _dense_hess0(self) -> FloatArray:
        return self.hess0.toarray()

    def block(self, kind: str) -> tuple[ConstraintBlock, ...]:
        """The blocks of one kind (possibly none)."""
        return tuple(b for b in self.blocks if b.kind == kind)

    def arguments(self) -> dict[str, Any]:
        """Keyword arguments for ``sqp.minimize`` (add ``hess=self.hess`` for Newton–SQP)."""
        return {"fun": self.fun, "x0": self.x0, "jac": self.jac, "bounds": None,
                "constraints": list(self.constraints), "hess0": self.hess0}

    def violations(self, z: FloatArray) -> FloatArray:
        """Violation of every row at ``z`` (≥ 0), concatenated in block order."""
        parts = [np.zeros(0)]
        for con in self.constraints:
            if isinstance(con, LinearConstraint):
                az = con.A @ z
                parts.append(np.maximum(np.maximum(con.lb - az, az - con.ub), 0.0))
            else:
                parts.append(np.abs(con["fun"](z)))
        return np.concatenate(parts)

    # -- multipliers ---------------------------------------------------------------------------------------------
    def _partner(self, reduced_block: ConstraintBlock) -> ConstraintBlock:
        return self.blocks[reduced_block.index + 1]  # closure first, then the reduced blocks in order

    def reduced_multipliers(self, res: Any) -> list[FloatArray]:
        """The multipliers of ``res`` (a full-space ``sqp`` result) for the reduced formulation's blocks.

        Position (forces), angle (moments) and relative-angle rows carry over unchanged (eliminating the closure
        rows does not change the other rows' multipliers); wall rows change sign, to the reduced ``ineq``
        convention ``λ ≥ 0`` for ``offset − n̂·p ≥ 0``.
        """
        lam = res.constraint_multipliers
        out = []
        for rb in self.reduced.blocks:
            v = np.asarray(lam[self._partner(rb).index], dtype=float)
            out.append(-v if rb.kind == "wall" else v.copy())
        return out

    def full_multipliers(self, reduced: Any) -> list[FloatArray]:
        """The inverse of :meth:`reduced_multipliers`, for a warm start (``multipliers0``) from a reduced solve or a
        neighbouring full-space one: the closure multipliers follow from stationarity in the node positions,
        ``μ_k = μ_{k+1} − f_k`` (a suffix sum of the contact and wall forces ``f`` beyond bar ``k``)."""
        reduced = [np.asarray(v, dtype=float) for v in reduced]
        if [v.size for v in reduced] != [b.rows for b in self.reduced.blocks]:
            raise ValueError("the multipliers do not match the reduced formulation's blocks.")
        n = self.n
        force = np.zeros((n + 1, 2))  # force of the linear rows on node k, in the closure's sign convention
        out: list[FloatArray] = [np.zeros(0)]
        for rb, v in zip(self.reduced.blocks, reduced, strict=True):
            fb = self._partner(rb)
            if rb.kind == "position":
                np.add.at(force, fb.nodes[0::2], v.reshape(-1, 2))
            elif rb.kind == "wall":
                normal, _ = self.scene.walls[rb.members[0]].unit()
                np.add.at(force, fb.nodes, -v[:, None] * np.asarray(normal)[None, :])
            out.append(-v if rb.kind == "wall" else v.copy())
        out[0] = -np.cumsum(force[::-1], axis=0)[::-1][1:].ravel()
        return out

    def polished_angles(self, z: FloatArray, multipliers: list[FloatArray] | None = None) -> FloatArray:
        """``φ = z[0::3]`` moved (least norm, Gauss–Newton) onto the reduced formulation's equality rows: the
        position rows and, given the reduced ``multipliers``, the active wall and relative-angle rows; prescribed
        angles stay fixed.

        Why: the engine stops at the iterate whose rows are within ``tol``. The closure residuals of a Newton step
        all have one sign (they are the second-order terms ``½ l_k (cos φ_k, sin φ_k) dφ_k²``), so in the reduced
        kinematics ``chain.nodes(φ)`` they add up along the chain: ``n`` bars each closed to ``ε`` can miss a contact
        by ``n ε`` (5e-8 mm at n = 1600). The correction costs O(m n) for ``m`` such rows, changes the energy at second
        order only (``∇E·δφ = −λ·r`` at a KKT point) and is kept only if it reduces the residual."""
        phi = self.angles(z)
        free = np.ones(self.n, dtype=bool)
        for block in self.reduced.block("angle"):
            free[block.nodes - 1] = False
        if self.reduced_violation(phi) <= POLISH_TOLERANCE * self.length_scale:
            return phi
        J, r = self._reduced_rows(phi, multipliers)
        if r.size == 0 or not np.any(r):
            return phi
        best = float(np.max(np.abs(r)))
        for _ in range(2):
            step = np.zeros(self.n)
            step[free] = -np.linalg.lstsq(J[:, free], r, rcond=None)[0]
            trial = phi + step
            J_t, r_t = self._reduced_rows(trial, multipliers)
            worst = float(np.max(np.abs(r_t)))
            if not worst < best:
                break
            phi, J, r, best = trial, J_t, r_t, worst
        return phi

    def reduced_violation(self, phi: FloatArray) -> float:
        """Largest violation (mm or rad) of the reduced formulation's linear and position rows at ``φ``, O(n)."""
        chain, scene = self.reduced.chain, self.scene
        nodes = chain.nodes(phi)
        worst = 0.0
        for rb in self.reduced.blocks:
            if rb.kind == "position":
                targets = np.array([scene.contacts[i].point for i in rb.members], dtype=float)
                worst = max(worst, float(np.max(np.abs(nodes[rb.nodes[0::2]] - targets))))
            elif rb.kind == "wall":
                normal, offset = scene.walls[rb.members[0]].unit()
                worst = max(worst, float(np.max(nodes[rb.nodes] @ np.asarray(normal) - offset, initial=0.0)))
            elif rb.kind == "relative_angle":
                con = self.reduced.constraints[rb.index]
                v = con.A @ phi
                worst = max(worst, float(np.max(np.maximum(con.lb - v, v - con.ub), initial=0.0)))
        return worst

    def _reduced_rows(self, phi: FloatArray, multipliers: list[FloatArray] | None) -> tuple[FloatArray, FloatArray]:
        """Jacobian (dense, m × n) and residual of the rows :meth:`polished_angles` restores."""
        chain, scene, n = self.reduced.chain, self.scene, self.n
        nodes = chain.nodes(phi)
        J_parts, r_parts = [np.zeros((0, n))], [np.zeros(0)]
        for rb in self.reduced.blocks:
            lam = None if multipliers is None else np.asarray(multipliers[rb.index], dtype=float)
            if rb.kind == "position":
                k = rb.nodes[0::2]
                targets = np.array([scene.contacts[i].point for i in rb.members], dtype=float)
                r_parts.append((nodes[k] - targets).ravel())
                J_parts.append(chain.node_jacobian(phi, k).reshape(-1, n))
            elif rb.kind == "wall" and lam is not None and np.any(lam > 0):
                k = rb.nodes[lam > 0]
                normal, offset = scene.walls[rb.members[0]].unit()
                r_parts.append(nodes[k] @ np.asarray(normal) - offset)
                J_parts.append(np.einsum("j,mjn->mn", np.asarray(normal), chain.node_jacobian(phi, k)))
            elif rb.kind == "relative_angle" and lam is not None and np.any(lam != 0):
                con = self.reduced.constraints[rb.index]
                active = np.flatnonzero(lam)
                A = sp.csr_matrix(con.A)[active].toarray()
                r_parts.append(A @ phi - np.where(lam[active] > 0, con.lb[active], con.ub[active]))
                J_parts.append(A)
        return np.vstack(J_parts), np.concatenate(r_parts)

    def as_reduced_result(self, res: Any, *, polish: bool = True) -> OptimizeResult:
        """A copy of ``res`` as the reduced formulation's result, for :func:`guidewire.result.build_solution`:
        ``x = φ`` (:meth:`polished_angles` unless ``polish=False``), ``jac`` the energy gradient in ``φ``,
        ``constraint_multipliers`` from :meth:`reduced_multipliers`; the full-space ``x`` and multipliers are kept as
        ``full_x`` and ``full_constraint_multipliers``."""
        out = OptimizeResult(dict(res))
        z = np.asarray(res.x, dtype=float)
        multipliers = self.reduced_multipliers(res)
        out.x = self.polished_angles(z, multipliers) if polish else self.angles(z)
        out.jac = self.reduced.jac(out.x)
        out.constraint_multipliers = multipliers
        out.full_x = z.copy()
        out.full_constraint_multipliers = list(res.constraint_multipliers)
        return out


def _pack(reduced: Formulation, scale: float, phi: FloatArray, nodes: FloatArray | None = None) -> FloatArray:
    phi = np.asarray(phi, dtype=float)
    p = reduced.chain.nodes(phi) if nodes is None else np.asarray(nodes, dtype=float)
    z = np.empty(3 * phi.size)
    z[0::3], z[1::3], z[2::3] = phi, p[1:, 0] / scale, p[1:, 1] / scale
    return z


def _fix_angles(reduced: Formulation, phi: FloatArray) -> FloatArray:
    """``phi`` with the prescribed angles set (paper scheme)."""
    phi = phi.copy()
    for block in reduced.block("angle"):
        phi[block.nodes - 1] = [reduced.scene.contacts[i].angle for i in block.members]
    return phi


def _project_relative_angles(reduced: Formulation, phi: FloatArray) -> FloatArray:
    """The nearest angles (least squares) within the b₂ rows, shrunk by :data:`START_MARGIN`, and the prescribed
    angles; ``phi`` itself when it already satisfies them. A sparse QP in ``n`` variables."""
    rows = reduced.block("relative_angle")
    if not rows:
        return phi
    con = reduced.constraints[rows[0].index]
    A = sp.csr_matrix(con.A)
    value = A @ phi
    if np.all(value >= con.lb) and np.all(value <= con.ub):
        return phi
    margin = np.minimum(START_MARGIN, 0.25 * (con.ub - con.lb))
    n = reduced.n
    eq = [np.flatnonzero(np.abs(reduced.constraints[b.index].A).sum(axis=0)) for b in reduced.block("angle")]
    fixed = np.concatenate([np.zeros(0, dtype=int), *eq])
    E = sp.csr_matrix((np.ones(fixed.size), (np.arange(fixed.size), fixed)), shape=(fixed.size, n))
    solver = "clarabel" if "clarabel" in qpsolvers.available_solvers else "osqp"
    x = qpsolvers.solve_qp(sp.identity(n, format="csc"), -phi, sp.vstack([A, -A], format="csc"),
                           np.concatenate([con.ub - margin, margin - con.lb]), E if fixed.size else None,
                           phi[fixed] if fixed.size else None, solver=solver)
    return phi if x is None else _fix_angles(reduced, np.asarray(x, dtype=float))


def _start(reduced: Formulation, phi0: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Start angles and nodes satisfying every linear row."""
    scene, chain = reduced.scene, reduced.chain
    phi = _project_relative_angles(reduced, _fix_angles(reduced, np.asarray(phi0, dtype=float)))
    p = chain.nodes(phi)
    for i, k in enumerate(reduced.contact_nodes):
        if scene.contacts[i].point is not None:
            p[k] = scene.contacts[i].point
    if scene.walls:
        margin = WALL_START_MARGIN * scene.wire.length
        units = [(np.asarray(w.unit()[0]), w.unit()[1]) for w in scene.walls]
        for _ in range(10):  # alternating projections onto the walls' half-planes (one round for one wall)
            moved = False
            for normal, offset in units:
                excess = p[1:] @ normal - (offset - margin)
                bad = excess > 0.0
                if np.any(bad):
                    p[1:][bad] -= excess[bad, None] * normal[None, :]
                    moved = True
            if not moved:
                break
    return phi, p


def length_scale(scene: Scene) -> float:
    """``s = max(1 mm, |base| + L)``: every node lies within ``s`` of the origin, so the scaled node variables are
    at most 1 in magnitude, like the angles."""
    return max(1.0, float(np.hypot(*scene.base.point)) + scene.wire.length)


def formulate_full(
    scene: Scene,
    *,
    scheme: str | None = None,
    bars: int | None = None,
    initial_angles: Any = None,
    initial_nodes: Any = None,
) -> FullSpaceFormulation:
    """Turn ``scene`` into the full-space arguments of :func:`sqp.minimize` (see the module docstring).

    Parameters are those of :func:`guidewire.formulation.formulate`; the start is its ``x0``.

    Raises
    ------
    ValueError
        As :func:`~guidewire.formulation.formulate`.
    """
    reduced = formulate(scene, scheme=scheme, bars=bars, initial_angles=initial_angles, initial_nodes=initial_nodes)
    scene, chain, n = reduced.scene, reduced.chain, reduced.n
    scale = length_scale(scene)
    closure = _Closure.build(chain.base_point, chain.lengths, scale)
    blocks = [ConstraintBlock("closure", 0, tuple(range(1, n + 1)), np.repeat(np.arange(1, n + 1), 2))]
    constraints: list[Any] = [closure.constraint()]
    for rb in reduced.blocks:
        con = reduced.constraints[rb.index]
        if rb.kind == "position":
            ids = list(rb.members)
            k = reduced.contact_nodes[ids]
            cols = np.column_stack((_x(k), _y(k))).ravel()
            target = np.array([scene.contacts[i].point for i in ids], dtype=float).ravel()
            A = sp.csr_matrix((np.full(cols.size, scale), (np.arange(cols.size), cols)), shape=(cols.size, 3 * n))
            new = LinearConstraint(A, target, target)
        elif rb.kind == "wall":
            (nx, ny), offset = scene.walls[rb.members[0]].unit()
            k = rb.nodes
            rows = np.repeat(np.arange(k.size), 2)
            cols = np.column_stack((_x(k), _y(k))).ravel()
            A = sp.csr_matrix((np.tile([scale * nx, scale * ny], k.size), (rows, cols)), shape=(k.size, 3 * n))
            new = LinearConstraint(A, np.full(k.size, -np.inf), np.full(k.size, offset))
        elif rb.kind in ("angle", "relative_angle"):
            new = LinearConstraint(_embed_columns(con.A, n), con.lb, con.ub)
        else:  # pragma: no cover - a block kind added to formulate() must be added here
            raise NotImplementedError(f"no full-space form of the {rb.kind!r} block")
        blocks.append(ConstraintBlock(rb.kind, len(constraints), rb.members, rb.nodes))
        constraints.append(new)
    H = sp.coo_matrix(reduced.hess0)
    hess0 = sp.csc_matrix((H.data, (_phi(H.row), _phi(H.col))), shape=(3 * n, 3 * n))
    return FullSpaceFormulation(reduced=reduced, blocks=tuple(blocks), constraints=tuple(constraints), hess0=hess0,
                                x0=_pack(reduced, scale, *_start(reduced, reduced.x0)), length_scale=scale)


def solve_full(
    scene: Scene,
    *,
    scheme: str | None = None,
    bars: int | None = None,
    initial_angles: Any = None,
    initial_nodes: Any = None,
    multipliers0: Any = None,
    qp_solver: str | None = None,
    qp_options: dict[str, Any] | None = None,
    tol: float = 1e-8,
    max_iter: int = 500,
    verbose: bool = False,
) -> Solution:
    """:func:`guidewire.solve` (exact Hessian) through the full-space program: the same :class:`Solution`, with
    ``result`` the reduced view of the ``sqp`` result (:meth:`FullSpaceFormulation.as_reduced_result`).

    ``multipliers0`` are reduced multipliers (``solution.result.constraint_multipliers`` of a neighbouring solve, every
    wall on every node), used when their blocks match; ``qp_solver`` defaults to
    :attr:`FullSpaceFormulation.qp_solver`.
    """
    start = time.perf_counter()
    full = formulate_full(scene, scheme=scheme, bars=bars, initial_angles=initial_angles, initial_nodes=initial_nodes)
    args = full.arguments()
    args["hess"] = full.hess
    if multipliers0 is not None and [np.size(m) for m in multipliers0] == [b.rows for b in full.reduced.blocks]:
        args["multipliers0"] = full.full_multipliers(multipliers0)
    res = sqp.minimize(**args, qp_solver=qp_solver if qp_solver is not None else full.qp_solver,
                       qp_options=qp_options, tol=tol, max_iter=max_iter, verbose=verbose)
    return build_solution(full.reduced, full.as_reduced_result(res), time.perf_counter() - start)
