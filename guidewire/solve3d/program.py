"""The 3-D scene as a sparse nonlinear program for :func:`sqp.minimize` (exact Hessian, O(n) per evaluation).

Variables, interleaved per bar ``k = 1..n`` (``6n``): the chart parameters ``ω_k`` of its frame
(:mod:`guidewire.rod.quaternion`, ``q_k = q⁰_k ⊗ (1, ω_k)``) and its end node ``p_k = s u_k`` in units of the length
scale ``s`` (so node variables are at most about 1, like ``ω``)::

    z = [ω_1, u_1, ω_2, u_2, …, ω_n, u_n]

Why this layout. The frames carry bending and twist (three degrees of freedom per bar, no unit-norm row: the chart is
homogeneous); the node positions make every row local. Each closure row involves one bar and its two nodes, each
lumen or wall row one node, so every Jacobian row has at most five nonzeros and the Lagrangian Hessian is block
tridiagonal (energy) plus block diagonal (closure, lumen): banded in this ordering, so a QP costs O(n) with a sparse
backend. Angle variables (two per tangent) would have poles; node positions alone would need reference frames for the
twist (discrete elastic rods' time-parallel transport); quaternions in a chart have neither problem.

Rows:

``closure`` (equalities, nonlinear): ``s u_k − s u_{k−1} − l_k t(q_k) = 0`` (3 per bar; ``u_0`` the clamp).
    Multiplier ``μ_k`` (N): the force the wire before bar ``k`` exerts on the wire from bar ``k`` on (``μ_1``: the
    clamp's force).
contact points (linear equalities): ``s u_k = p``. Multiplier: the contact force on the wire (N).
walls (linear inequalities): ``s n̂ · u_k ≤ b`` for every node. Multiplier ``≤ 0``: the wall pushes with ``λ n̂``.
lumen (nonlinear inequalities): ``g(p_k) ≥ 0``: node ``k`` inside the lumen shrunk by the wire's radius there
    (:mod:`guidewire.vessel3d.tube`; ``g`` is the clearance in mm to first order at the wall; beside a crease, the
    distance from it less the radius, :mod:`guidewire.vessel3d.crease`). Multiplier ``λ_k ≥ 0`` (N): the wall's
    force ``λ_k ∇g`` (normal to the wall, pointing in).
creases (nonlinear inequalities, a vessel whose lumen has creases): :data:`CREASE_SLOTS` rows per crease, one per
    place where it comes nearest the wire (in their order along it; an unused one a constant), ``|P − X| − r ≥ 0``
    with ``P = (1 − τ) p_{k−1} + τ p_k`` the wire's nearest point on a bar, or a node; the row follows the place as
    it slides from bar to bar, so a wire slides over the crease around a branch's opening as over a smooth wall.
    The node rows of nodes in a crease's cone are then inactive (these rows bound their distance from it).
    Multiplier ``λ ≥ 0`` (N): the crease's force at ``P``, normal to the bar, shared by its nodes as ``1 − τ``
    and ``τ``.

Objective: :class:`guidewire.rod.strain_energy.StrainEnergy` in ``ω`` minus the tip load's work ``F · p_n``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint

from ..chain import explicit_bars, place_bars
from ..rod import kinematics
from ..rod import quaternion as quat
from ..rod.material import twist_stiffness
from ..rod.strain_energy import EnergyParts, StrainEnergy
from ..vessel3d.vessel import CREASE_SLOTS
from .pattern import Pattern
from .scene import Scene3D

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]


def bar_layout(scene: Scene3D) -> tuple[FloatArray, IntArray]:
    """Bar lengths (n,) and the node of every contact: a node at every contact and section boundary
    (:func:`guidewire.chain.place_bars`, or the wire's explicit ``bar_lengths``)."""
    wire = scene.wire
    s = [c.s for c in scene.contacts]
    if wire.bar_lengths is not None:
        return explicit_bars(wire.bar_lengths, s, wire.section_boundaries())
    pinned = [c.point is not None for c in scene.contacts]
    return place_bars(wire.length, wire.bars, s, wire.section_boundaries(), pinned,
                      wire.refinement_at if wire.refined else None)


def length_scale(scene: Scene3D) -> float:
    """``max(1 mm, |base| + L)``: every node lies within it of the origin."""
    return max(1.0, float(np.linalg.norm(scene.base.point)) + scene.wire.length)


def node_radii(scene: Scene3D, lengths: FloatArray) -> FloatArray:
    """Wire radius (mm) at nodes ``1..n``: the larger of the two adjoining bars' (the tip: its bar's)."""
    s_mid = np.concatenate(([0.0], np.cumsum(lengths)))[:-1] + 0.5 * lengths
    d = scene.wire.properties_at(s_mid).diameter
    return 0.5 * np.maximum(d, np.append(d[1:], d[-1]))


@dataclass
class Program:
    """The program of one scene about reference frames ``q0`` (see the module docstring)."""

    scene: Scene3D
    lengths: FloatArray
    contact_nodes: IntArray
    energy: StrainEnergy
    q0: FloatArray
    scale: float
    basis: FloatArray = field(init=False)
    _cache: dict[str, Any] = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self) -> None:
        self.q0 = quat.continuous(self.q0, self.energy.base)
        self.energy = self.energy.aligned(self.q0)
        self.basis = quat.chart_basis(self.q0)

    @classmethod
    def build(cls, scene: Scene3D, q0: FloatArray) -> Program:
        lengths, contact_nodes = bar_layout(scene)
        wire = scene.wire
        s_mid = np.concatenate(([0.0], np.cumsum(lengths)))[:-1] + 0.5 * lengths
        props = wire.properties_at(s_mid)
        gj = twist_stiffness(wire, s_mid, scene.poisson_ratio, scene.shear_modulus)
        with_tangent = [i for i, c in enumerate(scene.contacts) if c.tangent is not None]
        energy = StrainEnergy.build(lengths, props.bending_stiffness, gj, scene.base.frame(), props.rest_curvature,
                                    contact_nodes[with_tangent],
                                    np.array([scene.contacts[i].tangent for i in with_tangent]).reshape(-1, 3),
                                    np.array([scene.contacts[i].normal or (np.nan,) * 3 for i in with_tangent],
                                             dtype=float).reshape(-1, 3))
        q0 = np.asarray(q0, dtype=float)
        if q0.shape != (lengths.size, 4):
            raise ValueError(f"initial frames have shape {q0.shape}; expected ({lengths.size}, 4), one per bar.")
        return cls(scene, lengths, contact_nodes, energy, q0, length_scale(scene))

    # -- variables -----------------------------------------------------------------------------------------------
    @property
    def n(self) -> int:
        return int(self.lengths.size)

    @property
    def base_point(self) -> FloatArray:
        return np.asarray(self.scene.base.point, dtype=float)

    def split(self, z: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``(ω (n, 3), nodes (n + 1, 3))`` of ``z`` (nodes in mm, the clamp first)."""
        w = np.asarray(z, dtype=float).reshape(self.n, self.width)
        return w[:, :3], np.vstack((self.base_point, self.scale * w[:, 3:]))

    def nodes(self, z: FloatArray) -> FloatArray:
        """The nodes of :meth:`split` (read-only), computed once per point: the closure, lumen and crease rows'
        values, Jacobians and Hessians all read them at one point."""
        key = np.asarray(z, dtype=float).tobytes()
        if self._cache.get("nodes_key") != key:
            nodes = self.split(z)[1]
            nodes.flags.writeable = False
            self._cache.update(nodes_key=key, nodes=nodes)
        return self._cache["nodes"]

    def frames(self, z: FloatArray) -> FloatArray:
        """Normalised quaternions (n, 4) at ``z``."""
        omega = np.asarray(z, dtype=float).reshape(self.n, self.width)[:, :3]
        return quat.normalised(self.q0 + np.einsum("kij,kj->ki", self.basis, omega))

    def start(self) -> FloatArray:
        """``z`` at the reference frames: ``ω = 0``, nodes the running sum of ``l_k t(q⁰_k)`` (closure exact)."""
        z = np.zeros((self.n, self.width))
        z[:, 3:] = kinematics.nodes(self.base_point, self.lengths, self.q0)[1:] / self.scale
        return z.ravel()

    width = 6
    """Variables per bar."""

    @property
    def size(self) -> int:
        return self.width * self.n

    def tangents(self, z: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """:func:`guidewire.rod.kinematics.tangents` at ``z``'s ``ω`` (the closure rows' values, Jacobian and Hessian
        all read them at one point: computed once per point)."""
        key = np.asarray(z, dtype=float).tobytes()
        self._derivatives_asked(key)
        return self._tangents(z, key)

    def _tangents(self, z: FloatArray, key: bytes) -> tuple[FloatArray, FloatArray, FloatArray]:
        """:meth:`tangents` at ``z`` of key ``key`` (its bytes), not recorded as a derivative request."""
        if self._cache.get("tangent_key") != key:
            omega, _ = self.split(z)
            if "chart_forms" not in self._cache:
                self._cache["chart_forms"] = kinematics.chart_forms(self.basis)
            self._cache.update(tangent_key=key, tangents=kinematics.tangents(self.q0, self.basis, omega,
                                                                             forms=self._cache["chart_forms"]))
        return self._cache["tangents"]

    def tangent_values(self, z: FloatArray) -> FloatArray:
        """The unit tangents of :meth:`tangents` without their derivatives (the closure rows' values at a trial point
        the line search may reject; the same numbers)."""
        key = np.asarray(z, dtype=float).tobytes()
        if self._cache.get("tangent_key") == key:
            return self._cache["tangents"][0]
        if self._speculates(key):
            return self._tangents(z, key)[0]
        if self._cache.get("tangent_value_key") != key:
            omega, _ = self.split(z)
            t = kinematics.tangents(self.q0, self.basis, omega, derivatives=False)[0]
            self._cache.update(tangent_value_key=key, tangent_values=t)
        return self._cache["tangent_values"]

    def _speculates(self, key: bytes) -> bool:
        """Whether a value-only request at ``key`` (a line search's trial point) is to be answered from the full
        evaluation with derivatives (:meth:`parts`, :meth:`tangents`; the same values bit for bit).

        A warm step accepts nearly every trial point and then asks for its derivatives: evaluating the values alone
        first computed them twice. So a new trial point is evaluated in full when the derivatives of the last one
        were asked for, and by values alone (the cheaper evaluation) after one that was rejected; a rejection costs
        at most one wasted set of derivatives. The first point seen is evaluated in full (the start, whose
        derivatives the solver always takes)."""
        cache = self._cache
        if cache.get("trial_key") != key:  # (a new point: decide once for all its value-only requests)
            cache.update(trial_key=key, speculate=cache.get("trial_used", True), trial_used=False)
        return bool(cache["speculate"])

    def _derivatives_asked(self, key: bytes) -> None:
        """Record a derivative request at ``key``: the last trial point's, if it is that point (see
        :meth:`_speculates`)."""
        if self._cache.get("trial_key") == key:
            self._cache["trial_used"] = True

    # -- objective -----------------------------------------------------------------------------------------------
    def parts(self, z: FloatArray) -> EnergyParts:
        key = np.asarray(z, dtype=float).tobytes()
        self._derivatives_asked(key)
        return self._parts(z, key)

    def _parts(self, z: FloatArray, key: bytes) -> EnergyParts:
        """:meth:`parts` at ``z`` of key ``key`` (its bytes), not recorded as a derivative request."""
        if self._cache.get("key") != key:
            omega, _ = self.split(z)
            self._cache.update(key=key, parts=self.energy.evaluate(self.q0, self.basis, omega))
        return self._cache["parts"]

    def energy_values(self, z: FloatArray) -> tuple[float, float]:
        """``(bending, twist)`` at ``z``: from :meth:`parts` when evaluated there, else without derivatives (a trial
        point of the line search, often rejected: its derivatives would be wasted; the same numbers)."""
        key = np.asarray(z, dtype=float).tobytes()
        if self._cache.get("key") == key:
            parts = self._cache["parts"]
            return parts.bending, parts.twist
        if self._speculates(key):
            parts = self._parts(z, key)
            return parts.bending, parts.twist
        if self._cache.get("value_key") != key:
            omega, _ = self.split(z)
            self._cache.update(value_key=key, values=self.energy.values(self.q0, self.basis, omega))
        return self._cache["values"]

    def fun(self, z: FloatArray) -> float:
        bending, twist = self.energy_values(z)
        value = bending + twist
        if self.scene.tip_force is not None:
            value -= self.scale * float(np.dot(self.scene.tip_force, np.asarray(z)[-3:]))
        return value

    def jac(self, z: FloatArray) -> FloatArray:
        g = np.zeros((self.n, self.width))
        g[:, :3] = self.parts(z).gradient
        if self.scene.tip_force is not None:
            g[-1, 3:] -= self.scale * np.asarray(self.scene.tip_force)
        return g.ravel()

    def hess(self, z: FloatArray) -> sp.csc_matrix:
        parts = self.parts(z)
        if "energy_pattern" not in self._cache:
            self._cache["energy_pattern"] = Pattern.of(*_energy_pattern(self.n, self.width), (self.size, self.size))
        data = np.concatenate((parts.diagonal.ravel(), parts.off_diagonal.ravel(),
                               parts.off_diagonal.transpose(0, 2, 1).ravel()))
        return self._cache["energy_pattern"].matrix(data)

    # -- rows ----------------------------------------------------------------------------------------------------
    def constraints(self) -> list[Any]:
        """Every row block, closure first (see the module docstring for signs)."""
        out: list[Any] = [self._closure()]
        linear = self._contact_rows()
        if linear is not None:
            out.append(linear)
        walls = self._wall_rows()
        if walls is not None:
            out.append(walls)
        if self.scene.vessel is not None:
            out.append(self._lumen_rows())
            if self.has_creases:
                out.append(self._crease_rows())
        return out

    @property
    def has_creases(self) -> bool:
        """Whether the program has the creases' rows (a vessel whose lumen has creases)."""
        return bool(getattr(self.scene.vessel, "creases", ()))

    def crease_rows(self) -> tuple[int, ...]:
        """The creases' rows among the program's nonlinear rows (closure 3n, lumen n, then the creases'; none
        without creases)."""
        if not self.has_creases:
            return ()
        return tuple(range(4 * self.n, 4 * self.n + CREASE_SLOTS * len(self.scene.vessel.creases)))

    def crease_contacts(self, z: FloatArray) -> Any:
        """Where each crease comes nearest the wire at ``z``
        (:meth:`guidewire.vessel3d.vessel.Vessel3D.crease_contacts`)."""
        if "radii" not in self._cache:
            self._cache["radii"] = (bar_radii(self.scene, self.lengths), node_radii(self.scene, self.lengths))
        return self.scene.vessel.crease_contacts(self.nodes(z), *self._cache["radii"])

    def _closure(self) -> dict[str, Any]:
        n, s, lengths, W = self.n, self.scale, self.lengths, self.width
        k = np.repeat(np.arange(n), 3)
        i = np.tile(np.arange(3), n)
        row = np.arange(3 * n)
        # entries per row: u_{k-1,i} (k ≥ 1), ω_k (3), u_{k,i}
        prev = k >= 1
        r_prev, c_prev = row[prev], W * (k[prev] - 1) + 3 + i[prev]
        r_om, c_om = np.repeat(row, 3), (W * k[:, None] + np.arange(3)).ravel()
        r_own, c_own = row, W * k + 3 + i
        rows = np.concatenate((r_prev, r_om, r_own))
        cols = np.concatenate((c_prev, c_om, c_own))
        m = self.size
        jacobian = Pattern.of(rows, cols, (3 * n, m), "csr")
        hessian = Pattern.of(*_block_diagonal_pattern(n, 0, W), (m, m))

        def fun(z: FloatArray) -> FloatArray:
            p = self.nodes(z)
            t = self.tangent_values(z)
            return (np.diff(p, axis=0) - lengths[:, None] * t).ravel()

        def jac(z: FloatArray) -> sp.csr_matrix:
            dt = self.tangents(z)[1]
            data = np.concatenate((np.full(r_prev.size, -s), (-lengths[:, None, None] * dt).ravel(),
                                   np.full(n * 3, s)))
            return jacobian.matrix(data)

        def hess(z: FloatArray, v: FloatArray) -> sp.csc_matrix:
            ddt = self.tangents(z)[2]
            blocks = -lengths[:, None, None] * np.einsum("ki,kiab->kab", np.reshape(v, (n, 3)), ddt)
            return hessian.matrix(blocks.ravel())

        return {"type": "eq", "fun": fun, "jac": jac, "hess": hess}

    def _contact_rows(self) -> LinearConstraint | None:
        pinned = [(k, c.point) for k, c in zip(self.contact_nodes, self.scene.contacts, strict=True)
                  if c.point is not None]
        if not pinned:
            return None
        k = np.array([p[0] for p in pinned])
        rows = np.arange(3 * k.size)
        cols = (self.width * (k[:, None] - 1) + 3 + np.arange(3)).ravel()
        A = sp.csr_matrix((np.full(rows.size, self.scale), (rows, cols)), shape=(rows.size, self.size))
        target = np.array([p[1] for p in pinned], dtype=float).ravel()
        return LinearConstraint(A, target, target)

    def _wall_rows(self) -> LinearConstraint | None:
        walls = self.scene.walls
        if not walls:
            return None
        n = self.n
        normals = np.array([w.normal for w in walls])
        offsets = np.array([w.offset for w in walls])
        rows = np.repeat(np.arange(len(walls) * n), 3)
        node = np.tile(np.arange(n), len(walls))
        cols = (self.width * node[:, None] + 3 + np.arange(3)).ravel()
        data = (self.scale * np.repeat(normals, n, axis=0)).ravel()
        A = sp.csr_matrix((data, (rows, cols)), shape=(len(walls) * n, self.size))
        return LinearConstraint(A, np.full(len(walls) * n, -np.inf), np.repeat(offsets, n))

    def _lumen_rows(self) -> dict[str, Any]:
        n, s, vessel, W = self.n, self.scale, self.scene.vessel, self.width
        radii = node_radii(self.scene, self.lengths)
        rows = np.repeat(np.arange(n), 3)
        cols = (W * np.arange(n)[:, None] + 3 + np.arange(3)).ravel()
        m = self.size
        jacobian = Pattern.of(rows, cols, (n, m), "csr")
        hessian = Pattern.of(*_block_diagonal_pattern(n, 3, W), (m, m))

        mode = "held" if self.has_creases else "rows"

        def fun(z: FloatArray) -> FloatArray:
            return vessel.lumen_rows(self.nodes(z)[1:], radii, mode)[0]

        def jac(z: FloatArray) -> sp.csr_matrix:
            grad = vessel.lumen_rows(self.nodes(z)[1:], radii, mode)[1]
            return jacobian.matrix(s * grad.ravel())

        def hess(z: FloatArray, v: FloatArray) -> sp.csc_matrix:
            lumen_hessian = vessel.lumen_rows(self.nodes(z)[1:], radii, mode)[2]
            blocks = s * s * np.asarray(v, dtype=float)[:, None, None] * lumen_hessian
            return hessian.matrix(blocks.ravel())

        return {"type": "ineq", "fun": fun, "jac": jac, "hess": hess}

    def _crease_rows(self) -> dict[str, Any]:
        s, W, m = self.scale, self.width, self.size
        slots = CREASE_SLOTS
        rows_count = slots * len(self.scene.vessel.creases)

        memo: dict[str, Any] = {}

        def places(z: FloatArray) -> tuple[FloatArray, NDArray[np.intp], FloatArray, FloatArray, FloatArray]:
            """Value, bar, gradient (6,) and Hessian (6, 6) of every row (unused slots: CREASE_FAR, no bar), found
            once per point (the rows' values, Jacobian and Hessian all read them)."""
            key = np.asarray(z, dtype=float).tobytes()
            if memo.get("key") != key:
                memo.update(key=key, value=gathered(z))
            return memo["value"]

        def gathered(z: FloatArray) -> tuple[FloatArray, NDArray[np.intp], FloatArray, FloatArray, FloatArray]:
            """:func:`places`, computed."""
            value = np.full(rows_count, CREASE_FAR)
            bar = np.full(rows_count, -1, dtype=np.intp)
            grad = np.zeros((rows_count, 6))
            hess = np.zeros((rows_count, 6, 6))
            for c, found in enumerate(self.crease_contacts(z)):
                k = slice(c * slots, c * slots + found.bar.size)
                value[k], bar[k], grad[k], hess[k] = found.value, found.bar, found.gradient, found.hessian
            return value, bar, grad, hess, np.flatnonzero(bar >= 0)

        def columns(bar: NDArray[np.intp]) -> NDArray[np.intp]:
            """The 6 columns of each bar's two nodes (−1 for the clamp's, which are not variables)."""
            first = np.where(bar[:, None] >= 1, W * (bar[:, None] - 1) + 3 + np.arange(3), -1)
            return np.concatenate((first, W * bar[:, None] + 3 + np.arange(3)), axis=1)

        def fun(z: FloatArray) -> FloatArray:
            return places(z)[0].copy()  # (the caller's own array: the memo's stays as found)

        def jac(z: FloatArray) -> sp.csr_matrix:
            _, bar, grad, _, used = places(z)
            cols = columns(bar[used])
            rows = np.repeat(used, 6).reshape(-1, 6)
            keep = cols >= 0
            return sp.csr_matrix((s * grad[used][keep], (rows[keep], cols[keep])), shape=(rows_count, m))

        def hess(z: FloatArray, v: FloatArray) -> sp.csc_matrix:
            _, bar, _, blocks, used = places(z)
            cols = columns(bar[used])
            weighted = (s * s * np.asarray(v, dtype=float)[used])[:, None, None] * blocks[used]
            r_idx = np.broadcast_to(cols[:, :, None], weighted.shape)
            c_idx = np.broadcast_to(cols[:, None, :], weighted.shape)
            keep = (r_idx >= 0) & (c_idx >= 0)
            return sp.csc_matrix((weighted[keep], (r_idx[keep], c_idx[keep])), shape=(m, m))  # (repeats summed)

        return {"type": "ineq", "fun": fun, "jac": jac, "hess": hess}


CREASE_FAR = 1.0
"""The value (mm) of a crease's row with no place to hold (any positive number: the row is inactive)."""


def bar_radii(scene: Scene3D, lengths: FloatArray) -> FloatArray:
    """Wire radius (mm) of every bar (its middle's)."""
    s_mid = np.concatenate(([0.0], np.cumsum(lengths)))[:-1] + 0.5 * lengths
    return 0.5 * scene.wire.properties_at(s_mid).diameter


def _energy_pattern(n: int, width: int) -> tuple[IntArray, IntArray]:
    """COO rows and columns of the energy Hessian's blocks: diagonal (n × 9), upper (n − 1) × 9, lower."""
    a = np.arange(3)
    d_rows = (width * np.arange(n)[:, None, None] + a[None, :, None]) + 0 * a[None, None, :]
    d_cols = (width * np.arange(n)[:, None, None] + a[None, None, :]) + 0 * a[None, :, None]
    o_rows = d_rows[:-1]
    o_cols = d_cols[:-1] + width
    return (np.concatenate((d_rows.ravel(), o_rows.ravel(), o_cols.transpose(0, 2, 1).ravel())),
            np.concatenate((d_cols.ravel(), o_cols.ravel(), o_rows.transpose(0, 2, 1).ravel())))


def _block_diagonal_pattern(n: int, offset: int, width: int) -> tuple[IntArray, IntArray]:
    """COO rows and columns of n 3 × 3 blocks at columns ``width k + offset``."""
    a = np.arange(3)
    base = width * np.arange(n)[:, None, None] + offset
    return (base + a[None, :, None] + 0 * a).ravel(), (base + a[None, None, :] + 0 * a[:, None]).ravel()
