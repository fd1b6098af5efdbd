"""The solved wire: shape, angles, energy, curvature and bending stress, support reactions, solver outcome.

Sign conventions (all on the wire, counter-clockwise positive, N and N·mm):

- A position contact's force is its multiplier: at a KKT point ``∇E = Σ Jᵀλ`` (:func:`sqp.minimize`), and by virtual
  work ``δE = F · δp_k``, so ``λ = F``, the force the contact exerts on the wire.
- An angle contact's moment: in the paper scheme the multiplier of its row ``φ_k = θ*`` (the moment on bar ``k``);
  in the second-order scheme, where the angle is in the energy, ``M = +∂E/∂θ*``. The base clamp's moment is
  ``∂E/∂θ_A`` in both schemes (``= −EI κ(0)``: the clamp resists the wire's bending moment). A rigid rotation of
  wire and supports leaves ``E`` unchanged, which makes these the moments that balance the forces' moments.
- A wall pushes node ``k`` with ``−λ_k n̂`` (``n̂`` the unit outward normal, ``λ_k ≥ 0``); in general a block's node
  rows push with ``λ_r d_r`` (:mod:`guidewire.blocks.base`: one sign convention in both layouts).
- Forces and moments come from multipliers, which mean something only at a KKT point: a failed solve carries none
  (every ``force``/``moment`` None, ``wall_forces`` None).
- The base point is not a variable, so its force follows from global balance: ``F_base = −Σ (contact + wall
  forces)``. The moments are *not* balanced by construction; :meth:`Solution.moment_balance` is a real check.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..blocks import Block, Loads
from ..chain.crossing import crossing_bars
from ..program.formulation import Formulation
from ..scene.file import scene_to_dict
from ..scene.scene import Scene
from ..status import SHAPE_REJECTED, Status
from .options import TOL

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Reaction:
    """What one support (the base or a contact) exerts on the wire.

    Attributes
    ----------
    name : str
    kind : {"base", "contact"}
    s : float
        Arc length (mm).
    node : int
        Node index.
    point : ndarray, shape (2,)
        Node position (mm).
    force : ndarray, shape (2,) or None
        Force in N; None when the support prescribes no position.
    moment : float or None
        Moment in N·mm, counter-clockwise; None when the support prescribes no angle.
    """

    name: str
    kind: str
    s: float
    node: int
    point: FloatArray
    force: FloatArray | None
    moment: float | None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready values."""
        return {
            "name": self.name, "kind": self.kind, "s": self.s, "node": self.node, "point": self.point.tolist(),
            "force": None if self.force is None else self.force.tolist(), "moment": self.moment,
        }


@dataclass(frozen=True)
class Solution:
    """A solved scene (see :func:`guidewire.solve`). Arrays over nodes have ``n + 1`` rows, the base first.

    Attributes
    ----------
    scene : Scene
        The scene as solved (``bars`` and ``scheme`` as used).
    nodes : ndarray, shape (n + 1, 2)
        Node positions (mm).
    s : ndarray, shape (n + 1,)
        Arc lengths of the nodes (mm).
    bar_angles : ndarray, shape (n,)
        Absolute bar angles ``φ`` (rad).
    tangent_angles : ndarray, shape (n + 1,)
        Wire tangent at each node (rad): a prescribed angle where there is one, else the mean of the adjoining
        bars (the only bar at a free end). These, not the bar angles, are the wire's angles.
    relative_angles : ndarray, shape (n + 1,)
        Total angle jump ``Δθ`` at each joint (rad), right minus left; 0 where the node has no joint.
    curvature : ndarray, shape (n + 1,)
        ``κ = Δθ / w`` (1/mm) with ``w`` the joint's dual length (:mod:`guidewire.energy`); at a node with two
        half joints (an interior angle contact, second-order scheme) the larger in magnitude.
    bending_stress_mpa : ndarray, shape (n + 1,)
        ``σ = E·(d/2)·|κ − κ⁰|`` in MPa, measured from the rest shape (``κ⁰`` the rest curvature), with the ``E``
        and ``d`` of the bars at the node (the larger value where two sections meet).
    paper_stress_measure : ndarray, shape (n + 1,)
        The paper's relative measure ``|Δθ − Δθ⁰|`` (rad; §2.4, Eq. 22, ``σ_b = k|Δθ|``), from the rest shape.
    energy : float
        Bending energy (N·mm).
    reactions : tuple of Reaction
        The base first, then every contact in order (forces and moments None after a failed solve).
    wall_forces : ndarray, shape (n + 1, 2), or None
        Total force of the walls on each node (N); None after a failed solve.
    success, status, message :
        The verdict: ``status`` a :class:`guidewire.Status`, the ``sqp`` status of the run that gave the answer,
        or ``SHAPE_REJECTED`` when that run converged but the shape fails a check a user would see (bars crossing
        each other, a node outside a wall); ``message`` says which, followed by what the fallback did when one ran.
    iterations : int
        SQP iterations summed over every run: every working-set round and the fallback.
    solve_time_s : float
        Wall-clock time of the whole solve (formulation, every run, assembly), s.
    max_violation : float
        Largest constraint violation at the answer, evaluated here (mm or rad; walls at every node).
    result : object
        The raw ``sqp`` result of the run that gave the answer (its ``x`` in that run's layout).
    layout : {"reduced", "full"}
        The program that gave the answer (:func:`guidewire.program.formulation.formulate`).
    rounds : int
        Number of ``sqp.minimize`` runs (working-set rounds and fallback included).
    fallback : str or None
        The fallback that gave the answer (``"damped BFGS"``), or None.
    blocks : tuple of Block
        The constraint blocks of the answer's formulation.
    multipliers : tuple of ndarray
        Their multipliers, one array per block (:mod:`guidewire.blocks.base` sign convention), for warm starts
        (``solve(multipliers0=solution)``).
    error_estimate_mm : float or None
        Estimated mean node error (mm) when solved with ``tol_mm`` (:mod:`guidewire.solve.refine`), else None.
    starts : int
        Starts solved (:mod:`guidewire.solve.branches`): 1, or 1 + the mirror starts tried where a free tangent left the
        branch in doubt. ``iterations`` and ``rounds`` are those of the start that gave the answer; ``solve_time_s``
        covers every start.
    coarse_bars : tuple of int
        Bars of the coarser solves of the same scene whose answer, interpolated, started this one (coarsest first;
        :func:`guidewire.solve.pipeline.nested_start`), empty when none did; ``iterations`` and ``rounds`` are this
        solve's own, ``solve_time_s`` includes theirs.
    """

    scene: Scene
    nodes: FloatArray
    s: FloatArray
    bar_angles: FloatArray
    tangent_angles: FloatArray
    relative_angles: FloatArray
    curvature: FloatArray
    bending_stress_mpa: FloatArray
    paper_stress_measure: FloatArray
    energy: float
    reactions: tuple[Reaction, ...]
    wall_forces: FloatArray | None
    success: bool
    status: Status
    message: str
    iterations: int
    solve_time_s: float
    max_violation: float
    result: Any
    layout: str = "reduced"
    rounds: int = 1
    fallback: str | None = None
    blocks: tuple[Block, ...] = ()
    multipliers: tuple[FloatArray, ...] = ()
    error_estimate_mm: float | None = None
    starts: int = 1
    coarse_bars: tuple[int, ...] = ()

    @property
    def scheme(self) -> str:
        """The energy discretisation used."""
        return self.scene.wire.scheme

    @property
    def n_bars(self) -> int:
        """Number of bars."""
        return int(self.bar_angles.size)

    def moment_balance(self) -> float:
        """Resultant moment about the base of every support force and moment (N·mm); ≈ 0 at equilibrium; nan after
        a failed solve (no forces)."""
        if self.wall_forces is None:
            return float("nan")
        base = self.nodes[0]
        total = 0.0
        for r in self.reactions:
            if r.force is not None:
                arm = r.point - base
                total += arm[0] * r.force[1] - arm[1] * r.force[0]
            if r.moment is not None:
                total += r.moment
        arms = self.nodes - base
        return float(total + np.sum(arms[:, 0] * self.wall_forces[:, 1] - arms[:, 1] * self.wall_forces[:, 0]))

    def contacts(self) -> list[dict[str, Any]]:
        """The wall and lumen contacts found: ``{node, s, point, normal, force_n}`` per touching node (force above
        :data:`CONTACT_FORCE`), ``normal`` the wall's outward unit normal and ``force_n`` the normal force (N) on
        the wire, along ``−normal``; a bar's contact with a vessel's corner also ``fraction``, where on the bar from
        ``node`` to the next it touches (``s`` and ``point`` are there). Empty for a failed solve (no forces)."""
        if not self.success:
            return []
        out = []
        for block, lam in zip(self.blocks, self.multipliers, strict=True):
            frames = block.contact_frames(self.scene, self.nodes)
            if frames is None:
                continue
            normals, fractions = frames
            for i in np.flatnonzero(np.asarray(lam) > CONTACT_FORCE):
                k, n = int(block.nodes[i]), normals[i]
                contact = {"node": k, "s": float(self.s[k]), "point": self.nodes[k].tolist(),
                           "normal": [float(n[0]), float(n[1])], "force_n": float(lam[i])}
                if fractions[i] > 0.0:
                    tau = float(fractions[i])
                    contact.update(fraction=tau, s=float((1.0 - tau) * self.s[k] + tau * self.s[k + 1]),
                                   point=((1.0 - tau) * self.nodes[k] + tau * self.nodes[k + 1]).tolist())
                out.append(contact)
        return sorted(out, key=lambda c: c["s"])

    def axial_force(self) -> float | None:
        """The axial force in the wire at the base (N, positive in compression): the tangential component of the
        force the base exerts on the wire; None for a failed solve."""
        base = self.reactions[0]
        if base.force is None:
            return None
        angle = self.scene.base.angle if self.scene.base.angle is not None else float(self.bar_angles[0])
        return float(base.force[0] * np.cos(angle) + base.force[1] * np.sin(angle))

    def entrance_force(self) -> float | None:
        """The push (N) needed to insert the wire further through a frictionless entrance: the axial force less the
        configurational (Eshelby-like) force ``M₀²/(2EI)`` the entrance exerts on a bent wire sliding through it
        (Bigoni et al., J. Mech. Phys. Solids 2015), which makes it ``dE/dL``, the energy's rate with the inserted
        length (tested against finite differences), as long as the contacts along the wire are normal to it
        (:meth:`tangential_contact_force` zero); otherwise ``dE/dL`` is this less that force. None for a failed
        solve."""
        axial = self.axial_force()
        if axial is None:
            return None
        moment = self.reactions[0].moment or 0.0
        stiffness = float(self.scene.wire.properties_at(0.5 * (self.s[0] + self.s[1])).bending_stiffness[0])
        return float(axial - moment**2 / (2.0 * stiffness))

    def tangential_contact_force(self) -> float | None:
        """The net force (N) the contacts at the wire's interior nodes exert along it, against the push (positive:
        they resist a further insertion). Zero for a frictionless wire on smooth walls, which touch it along its
        normal; not zero where a node's row meets the wire at an angle — the node rows of a vessel's corner (a
        branch's opening), which hold the wire where the real, smooth wire would slide: the entrance push then
        differs from ``dE/dL`` by this much (:meth:`entrance_force`), and the insertion flags the step
        (:func:`guidewire.march.insertion.step_flags`). The tip's contact is left out (a tip pressed head-on into a
        wall is pushed back along the wire by right). None for a failed solve."""
        if not self.success:
            return None
        angles = self.bar_angles
        total = 0.0
        for contact in self.contacts():
            k = contact["node"]
            if "fraction" in contact:  # a bar's contact: along its bar
                t = np.array([np.cos(angles[k]), np.sin(angles[k])])
            elif not 0 < k < angles.size:
                continue
            else:
                t = np.array([np.cos(angles[k - 1]) + np.cos(angles[k]), np.sin(angles[k - 1]) + np.sin(angles[k])])
            total += contact["force_n"] * float(np.dot(contact["normal"], t / np.linalg.norm(t)))
        return total

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready values (lists and numbers); ``units`` names the unit of every quantity, ``scene`` is the
        scene's geometry as a scene file holds it (:func:`guidewire.scene.file.scene_to_dict`)."""
        return {
            "units": UNITS, "scene": scene_to_dict(self.scene), "scheme": self.scheme, "bars": self.n_bars,
            "bar_lengths": np.diff(self.s).tolist(),
            "layout": self.layout, "success": self.success, "status": self.status, "message": self.message,
            "fallback": self.fallback, "energy": self.energy, "iterations": self.iterations, "rounds": self.rounds,
            "starts": self.starts, "coarse_bars": list(self.coarse_bars),
            "solve_time_s": self.solve_time_s, "max_violation": self.max_violation,
            "nodes": self.nodes.tolist(), "s": self.s.tolist(), "bar_angles": self.bar_angles.tolist(),
            "tangent_angles": self.tangent_angles.tolist(), "relative_angles": self.relative_angles.tolist(),
            "curvature": self.curvature.tolist(), "bending_stress_mpa": self.bending_stress_mpa.tolist(),
            "paper_stress_measure": self.paper_stress_measure.tolist(),
            "base_reaction": self.reactions[0].to_dict(),
            "contact_reactions": [r.to_dict() for r in self.reactions[1:]],
            "wall_forces": None if self.wall_forces is None else self.wall_forces.tolist(),
            "contacts": self.contacts(), "tip": {"point": self.nodes[-1].tolist(),
                                                 "angle": float(self.tangent_angles[-1])},
            "entrance_force_n": self.entrance_force(), "axial_force_n": self.axial_force(),
            "tangential_contact_force_n": self.tangential_contact_force(),
            **({} if self.error_estimate_mm is None else {"error_estimate_mm": self.error_estimate_mm}),
        }


#: A wall or lumen row carries a contact when its normal force exceeds this (N).
CONTACT_FORCE = 1e-9

#: The unit of every quantity in :meth:`Solution.to_dict` (and in the scene's geometry).
UNITS = {
    "length": "mm", "angle": "rad", "force": "N", "moment": "N*mm", "energy": "N*mm", "curvature": "1/mm",
    "stress": "MPa", "youngs_modulus": "MPa", "time": "s",
}


def _node_geometry(form: Formulation, phi: FloatArray, elastic: FloatArray | None = None
                   ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Tangent angles, relative angles, curvature, bending stress (MPa) and elastic angle jump at the nodes
    (``elastic``: the energy's joint angles at ``phi`` when the caller has them)."""
    n, scene, energy = form.n, form.scene, form.energy
    tangent = np.concatenate(([phi[0]], 0.5 * (phi[:-1] + phi[1:]), [phi[-1]]))
    if scene.base.angle is not None:
        tangent[0] = scene.base.angle
    for node, contact in zip(form.contact_nodes, scene.contacts, strict=True):  # contacts, not nodes
        if contact.angle is not None:
            tangent[node] = contact.angle
    elastic = energy.joint_angles(phi) if elastic is None else elastic
    delta = elastic + energy.rest_angles if energy.rest is not None else elastic
    relative = np.bincount(energy.node, delta, minlength=n + 1)  # (the sums np.add.at makes, in the same order)
    kappa_t = delta / energy.dual_length
    order = np.lexsort((np.abs(kappa_t), energy.node))  # per node, the largest |κ| assigned last
    curvature = np.zeros(n + 1)
    curvature[energy.node[order]] = kappa_t[order]
    wire = scene.wire
    if wire.sections:
        props = wire.properties_at(form.chain.arc_lengths[:-1] + 0.5 * form.chain.lengths)
        ends = form.chain.lengths[[0, -1]] * props.rest_curvature[[0, -1]] / 2.0  # a free end's half bar of rest turn
        if scene.base.angle is None:
            tangent[0] -= ends[0]
        if not (scene.contacts and form.contact_nodes[-1] == n and scene.contacts[-1].angle is not None):
            tangent[-1] += ends[1]
        fibre = props.youngs_modulus * 0.5 * props.diameter  # E·d/2 per bar
        rows, cols, _ = energy.coo
        term_fibre = np.zeros(energy.node.size)
        np.maximum.at(term_fibre, rows, fibre[cols])  # the larger of the term's bars
        stress_t = term_fibre * np.abs(elastic / energy.dual_length)
        stress = np.zeros(n + 1)
        np.maximum.at(stress, energy.node, stress_t)
        jump = np.bincount(energy.node, elastic, minlength=n + 1)
    else:
        stress = wire.youngs_modulus * 0.5 * wire.diameter * np.abs(curvature)
        jump = relative
    return tangent, relative, curvature, stress, jump


def _reactions(form: Formulation, phi: FloatArray, nodes: FloatArray, multipliers: list[FloatArray] | None,
               elastic: FloatArray | None = None) -> tuple[tuple[Reaction, ...], FloatArray | None]:
    """Support reactions and wall forces from the per-block multipliers (module docstring for the signs); without
    multipliers (a failed solve) the supports and their nodes, with no force or moment. ``elastic``: the energy's
    joint angles at ``phi`` when the caller has them."""
    scene, energy, n = form.scene, form.energy, form.n
    contacts = scene.contacts
    loads = Loads.empty(n)
    if multipliers is not None:
        for block, lam in zip(form.blocks, multipliers, strict=True):
            block.add_loads(form.model, lam, loads, nodes)
    forces, moments = loads.forces, loads.moments
    # ∂E/∂θ* per node from the terms that contain a prescribed tangent (∂r_t/∂θ* = row sum of D_t).
    elastic = energy.joint_angles(phi) if elastic is None else elastic
    node_moment = np.bincount(energy.node, -2.0 * energy.weight * elastic * energy.row_sum, minlength=n + 1)
    for i, (node, contact) in enumerate(zip(form.contact_nodes, contacts, strict=True)):
        if contact.angle is not None and i not in moments:
            moments[i] = float(node_moment[node])
    base = scene.base
    base_force = -(sum(forces.values(), np.zeros(2)) + loads.node_forces.sum(axis=0))
    base_moment = None if base.angle is None else float(node_moment[0])
    if multipliers is None:
        forces, moments, base_force, base_moment = {}, {}, None, None
    out = [Reaction(base.name, "base", 0.0, 0, nodes[0].copy(), base_force, base_moment)]
    for i, (node, contact) in enumerate(zip(form.contact_nodes, contacts, strict=True)):
        out.append(Reaction(contact.label(i), "contact", contact.s, int(node), nodes[node].copy(), forces.get(i),
                            moments.get(i)))
    return tuple(out), (None if multipliers is None else loads.node_forces)


#: A node may violate a constraint by this many times ``tol · max(1, L)`` before the shape is rejected.
VIOLATION_FACTOR = 10.0


def shape_defect(form: Formulation, phi: FloatArray, nodes: FloatArray, max_violation: float,
                 tol: float) -> str | None:
    """What a user would see wrong with a converged shape, or None: bars that cross each other
    (:func:`guidewire.chain.crossing.crossing_bars`), or a constraint violated beyond ``VIOLATION_FACTOR · tol · L``
    anywhere (walls and the lumen at every node, not only their working set), named by its block, node, arc length
    and excess (:meth:`Formulation.worst_violation`, which names a block for every positive or NaN violation).
    ``max_violation`` (``form.max_violation(phi, nodes)``) only decides whether to look."""
    crossing = crossing_bars(nodes)
    if crossing is not None:
        i, j = crossing
        return (f"bars {i + 1} and {j + 1} cross each other (s = {form.chain.arc_lengths[i]:.4g} and "
                f"{form.chain.arc_lengths[j]:.4g} mm): the shape intersects itself, which no wire can do")
    limit = VIOLATION_FACTOR * tol * max(1.0, form.scene.wire.length)
    if not max_violation <= limit:  # (NaN too)
        amount, block, node = form.worst_violation(phi, nodes)
        if block is None or amount <= limit:  # (a max_violation not from form.max_violation(phi, nodes))
            return None
        s = float(form.chain.arc_lengths[node]) if 0 <= node < form.chain.arc_lengths.size else float("nan")
        return (f"the {block.describe(form.model)} is violated at node {node} (s = {s:.4g} mm) by {amount:.3g} "
                f"{block.unit}, more than the {limit:.3g} allowed")
    return None


def unsettled_defect(form: Formulation, phi: FloatArray) -> str:
    """Why an answer whose working-set rounds ran out is rejected: the row standing farthest from the constraint it
    models (:meth:`Block.mismatch`), by block, node, arc length and distance."""
    worst = max(((m, block) for block in form.blocks if (m := block.mismatch(form.model, phi)) is not None),
                key=lambda item: item[0][0], default=None)
    where = ""
    if worst is not None:
        (amount, node), block = worst
        s = float(form.chain.arc_lengths[node])
        where = (f": the {block.describe(form.model)} row at node {node} (s = {s:.4g} mm) stands {amount:.3g} "
                 f"{block.unit} from the constraint it models")
    return (f"its working set of rows still moved when the rounds ran out{where}, so its contact forces are not "
            "the vessel's")


def build_solution(form: Formulation, res: Any, solve_time_s: float, *, iterations: int | None = None,
                   rounds: int = 1, fallback: str | None = None, message: str | None = None,
                   tol: float = TOL, settled: bool = True) -> Solution:
    """Assemble a :class:`Solution` from the formulation and the ``sqp`` result ``res`` of its program.

    The bar angles are :meth:`Formulation.answer`. A converged run whose shape fails :func:`shape_defect`, or whose
    working-set rounds ran out before its rows fit it (``settled`` False: a row may hold the wire where the wall it
    models is not, so the forces are not the vessel's), is reported as a failure (:data:`SHAPE_REJECTED`); forces
    and moments only for a success.
    """
    multipliers = form.multipliers(res)
    phi = form.answer(np.asarray(res.x, dtype=float), multipliers)
    nodes = form.nodes_at(phi)
    max_violation = form.max_violation(phi, nodes)
    success, status = bool(res.success), Status(int(res.status))
    message = str(res.message) if message is None else message
    defect = shape_defect(form, phi, nodes, max_violation, tol) if success else None
    if success and defect is None and not settled:
        defect = unsettled_defect(form, phi)
    vessel = form.scene.vessel
    if vessel is not None and bool(vessel.past_end(nodes[-1:])[0]):
        message = f"{message} The tip has left the vessel past its far end."
    if defect is not None:
        success, status = False, SHAPE_REJECTED
        message = f"The solver converged, but the shape is rejected: {defect}. ({message})"
    elastic = form.energy.joint_angles(phi)
    tangent, relative, curvature, stress, jump = _node_geometry(form, phi, elastic)
    reactions, wall_forces = _reactions(form, phi, nodes, multipliers if success else None, elastic)
    return Solution(
        scene=form.scene, nodes=nodes, s=form.chain.arc_lengths, bar_angles=phi, tangent_angles=tangent,
        relative_angles=relative, curvature=curvature, bending_stress_mpa=stress, paper_stress_measure=np.abs(jump),
        energy=float(np.dot(form.energy.weight, elastic * elastic)), reactions=reactions,  # (EnergyTerms.value)
        wall_forces=wall_forces, success=success, status=status, message=message,
        iterations=int(res.nit) if iterations is None else int(iterations), solve_time_s=float(solve_time_s),
        max_violation=max_violation, result=res, layout=form.layout.name, rounds=int(rounds),
        fallback=fallback, blocks=form.blocks, multipliers=tuple(multipliers),
    )
