"""``solve3d(scene)``: start → sparse program → :func:`sqp.minimize` (exact Hessian) → re-centred rounds → answer.

The chart of every bar's frame is centred on its start (:mod:`guidewire.rod.quaternion`); a bar that turns by more
than :data:`RECENTRE_ANGLE` within a solve is far out in its chart (whose Hessian grows like ``|ω|²``), so the answer
is taken as the next round's reference frames and solved again (usually converged in one or two iterations), up to
:data:`MAX_ROUNDS` times. A failed solve returns a :class:`Solution3D` with ``success`` False, its status and
message, and no forces; bad input raises ``ValueError`` before any work.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

import sqp
from sqp.backends import auto_choice

from ..rod import kinematics
from ..rod import quaternion as quat
from ..rod.material import twist_stiffness
from ..vessel3d.vessel import CREASE_SLOTS
from .program import Program, bar_layout, node_radii
from .result import ContactForce3D, Solution3D, clamp_moment, half_joint_moment
from .scene import Scene3D
from .start import start_frames

FloatArray = NDArray[np.float64]

RECENTRE_ANGLE = np.pi / 2
"""A round ends with re-centring when some bar turned by more than this within it (``|ω| > tan(angle/2)``)."""

MAX_ROUNDS = 4
"""Solves of one scene at most (the first and the re-centred ones)."""

CHART_LIMIT_ANGLE = 3 * np.pi / 4
"""A round is ended early, and re-centred, as soon as an iterate turns some bar by more than this within it
(``|ω| > tan(angle/2)``): a bar that turns towards a half turn in its chart heads for the chart's pole (``|ω| → ∞``),
where the Hessian grows like ``|ω|²`` and Newton's steps only ever halve the remaining angle. A J-tip that rolls over
in a snap did so: after the snap, 50 iterations of steps growing 1.5-fold (``|ω|`` from 2 to 1e9) while the energy
had converged to 1e-7; re-centred, the round converged in five."""

COLD_STEP_BOUND = 0.1
"""Largest change of any variable (``ω``, and nodes in units of the length scale) in each of the first ten steps of a
solve from the built-in start (:func:`sqp.minimize`'s ``step_bound``). The start lays the nodes on the vessel's
centreline, where every lumen row's gradient vanishes (``∇g = −v/a``, ``v`` the offset from the axis): the first QP
does not see the lumen, straightens the wire in one step 25-70 mm out of it, and the iteration crawled back in elastic
QPs (helix, 50 mm, 25 bars: 386-587 iterations, 12-28 s; 70 mm at 50 bars: 401-431, 78-94 s). With the bound:
10-17 iterations, the same energies to 1e-10. (0.03 took 11-17 iterations, 0.01 26-30.)"""

EXTEND_SHIFTED_STEPS = True
"""The engine's extension of shifted steps (``sqp.minimize(extend_shifted_steps=...)``: a full step of a model that
needed an identity shift is doubled while the merit keeps falling). A wire pressed on a branch's rim can roll off
it: the crease row's curvature (``−λ/r``: 1.6 N over a 0.35 mm tip radius) exceeds the wire's bending stiffness
there, the Lagrangian is indefinite on the held rows' null space, and the shifted model's steps are ``|g| / δ``
long: stEVE's J wire solved cold through the brachiocephalic trunk into the right subclavian (20 mm in, from
``Vessel3D.route``'s start; ``benchmarks/vessels3d.py``) crept ~1e-5 mm a step for 200 iterations (373 in all; with
the extension 157, the same energy; 10 and 30 mm into the common carotid 100 → 85 and 104 → 73). The benchmark
insertions (helix, J wire turned through 360 degrees, S-bend, arch) take the same iterations either way, the three
steering replays 434 / 653 / 796 against 434 / 640 / 803. (It was off while the shift went on W alone: turning the
J wire in the helix did not end within 7 min with it; the shift now covers the reduced Hessian only,
:func:`sqp.hessian.shifted_augmented`.)"""

STALL_ITERATIONS = 15
STALL_DECREASE = 0.9
STALL_VIOLATION = 1e-3
"""A round is also ended early, and re-centred, when its largest constraint violation, still above ``STALL_VIOLATION``
times the length scale, has not fallen below ``STALL_DECREASE`` times its least value for ``STALL_ITERATIONS``
iterations: its QPs are inconsistent (elastic mode) and the iterates sit at a local minimum of the violation, the
node variables far from where the frames put them (the closure rows ~20 mm off). The re-centred program starts from
the frames' own nodes, closure exact. Cold J wires in the helix at 100 mm (200 bars): the shipped one sat at a
violation of 20 mm, a bar turned 94°, from iteration 12 to the round's limit of 300 (31 s), then converged in a
re-centred round of 11; a stiffer one (0.89 mm, 80 GPa) the same at 81°, where no round was re-centred and the solve
failed after 300 iterations (18 s). Now 55 iterations and 2-3 s each, the first one at the same answer."""

DENSE_LIMIT = 0
"""The engine's ``dense_limit`` for this program (:func:`sqp.minimize`): sparse at every size. Its derivatives are
block-banded (six variables a bar, rows local to a bar), so the banded KKT solves of the guessed active set serve
every QP, where below the engine's default (300 variables, 50 bars) the dense path formed ``W`` and the QP densely and
sent every QP to DAQP. Measured (BLAS on one thread, medians of 3, alternating): the first 41 steps of stEVE's J
wire pushed into the type I arch at 0.5 bar/mm (10-50 bars) 1.05 → 0.62 s, every step the same iterations; a step
at 10 bars 13 ms either way, at 50 bars 45 → 14 ms."""

SPARSE_FALLBACKS = ("clarabel",)

PIQP_OPTIONS = {"preconditioner_iter": 0}
"""PIQP's settings for this program (over the engine's): no Ruiz equilibration. Measured on 51 subproblems of helix
and arch steps at 200-800 bars: 8-18 iterations instead of 16-31, all solved, where with the default 10 scaling
passes one stalled at the iteration limit (250; a 0.5-1.3 s detour through the looser retry and Clarabel at
800-1600 bars); steps agree to 5e-11."""
"""QP backends asked when the chosen one fails a subproblem: sparse only (the program has thousands of variables)."""

TOUCHING = 1e-6
"""A node whose lumen row is below this fraction of the wire length touches the wall (its force is reported; an
interior-point QP leaves tiny positive multipliers on the rows it does not hold)."""


def solve3d(scene: Scene3D, *, initial_nodes: Any = None, initial_frames: Any = None,
            initial_multipliers: list[Any] | None = None, tol: float = 1e-8, max_iter: int = 300,
            qp_solver: str | None = None, verbose: bool = False) -> Solution3D:
    """The minimum-energy shape of the wire in ``scene``.

    Parameters
    ----------
    scene : Scene3D
    initial_nodes : array_like, shape (n + 1, 3), optional
        A starting polyline (the clamp first); its bar directions set the start frames.
    initial_frames : array_like, shape (n, 4), optional
        Starting frames as quaternions (a previous solve's ``quaternions``: the warm start).
    initial_multipliers : list of arrays, optional
        Starting multipliers, one array per row block of the program (closure, contacts, walls, lumen: a previous
        solve's ``extras["multipliers"]`` carried to this layout, :func:`guidewire.solve3d.insert.tracked_multipliers`):
        with them the first Newton step already sees the wire's internal forces.
    tol, max_iter, qp_solver, verbose
        Passed to :func:`sqp.minimize`.

    Returns
    -------
    Solution3D
    """
    if not isinstance(scene, Scene3D):
        raise TypeError(f"scene is {type(scene).__name__}; expected guidewire.solve3d.Scene3D.")
    start = time.perf_counter()
    program = Program.build(scene, _first_frames(scene, initial_nodes, initial_frames))
    # (the augmented-Lagrangian convexification on the closure equalities only: a wire in a vessel changes its
    # touching nodes at every iteration, and the term on released lumen rows made convergence linear)
    # (no dense quadprog among the fallbacks: on the type I arch at 484 bars one QP PIQP failed took quadprog 55 s,
    # where Clarabel's answer, or none, gave the same converged step in 1.1 s)
    # (each QP first on the active set the last multipliers guess: the wire's contacts change little between
    # iterations and steps, and one banded KKT solve then replaces an interior-point QP)
    # (but on the creases' rows, a convex edge whose row's curvature makes W indefinite along it where it holds a bar;
    # and where the closure and crease rows leave W indefinite, on every held row before any identity shift: a shift
    # the size of a soft mode the wall contacts stabilise made the steps crawl — the tortuous coronary vessel's
    # insertion stopped at 46 mm, a cold solve there took 117 iterations at 45 mm and failed at 60, now 12 and 54)
    options: dict[str, Any] = {"tol": tol, "max_iter": max_iter, "verbose": verbose,
                               "convexify_inequalities": program.crease_rows(),
                               "qp_fallbacks": SPARSE_FALLBACKS,
                               "active_set_guess": True, "extend_shifted_steps": EXTEND_SHIFTED_STEPS,
                               "dense_limit": DENSE_LIMIT}
    if qp_solver is not None:
        options["qp_solver"] = qp_solver
    if initial_frames is None and initial_multipliers is None:
        options["step_bound"] = COLD_STEP_BOUND
    if (qp_solver or auto_choice(program.size, True, dense_limit=DENSE_LIMIT)[0]) == "piqp":
        options["qp_options"] = dict(PIQP_OPTIONS)
    z0 = program.start()
    iterations, rounds = 0, 0
    multipliers = initial_multipliers
    while True:
        rounds += 1
        kw = {"multipliers0": multipliers} if multipliers is not None else {}
        if rounds > 1:
            options.pop("step_bound", None)  # (a re-centred round starts from the last one's answer)
        chart = _ChartLimit(program) if rounds < MAX_ROUNDS else None
        res = sqp.minimize(program.fun, z0, jac=program.jac, hess=program.hess,
                           constraints=program.constraints(), callback=chart, **options, **kw)
        iterations += int(res.nit)
        omega, _ = program.split(res.x)
        turned = float(np.max(np.linalg.norm(omega, axis=1), initial=0.0))
        if rounds >= MAX_ROUNDS or (res.success and turned <= np.tan(RECENTRE_ANGLE / 2)):
            break
        if not res.success and turned <= np.tan(RECENTRE_ANGLE / 2) and not (chart is not None and chart.reached):
            break
        program = Program.build(scene, program.frames(res.x))
        z0 = program.start()
        # (a round the chart ended keeps its last multipliers, as a converged one does: the wire's forces)
        multipliers = res.constraint_multipliers if res.success or (chart and chart.reached) else None
    return answer(program, res, iterations, rounds, time.perf_counter() - start)


class _ChartLimit:
    """The callback of a round: ``StopIteration`` once an iterate turns some bar by more than
    :data:`CHART_LIMIT_ANGLE` in the round's chart (``reached`` then True), so that it is re-centred there."""

    def __init__(self, program: Program) -> None:
        self.program = program
        self.limit = float(np.tan(CHART_LIMIT_ANGLE / 2))
        self.reached = False
        self.least = np.inf  # (the least violation of the round so far, and when it was reached)
        self.since = 0

    def __call__(self, intermediate_result: Any) -> None:
        omega = np.reshape(intermediate_result.x, (self.program.n, self.program.width))[:, :3]
        turned = float(np.max(np.einsum("ij,ij->i", omega, omega), initial=0.0))
        violation = float(intermediate_result.maxcv)
        if violation < STALL_DECREASE * self.least:
            self.least, self.since = violation, 0
        else:
            self.since += 1
        stalled = self.since >= STALL_ITERATIONS and violation > STALL_VIOLATION * self.program.scale
        if turned > self.limit * self.limit or stalled:
            self.reached = True
            raise StopIteration


def _first_frames(scene: Scene3D, initial_nodes: Any, initial_frames: Any) -> FloatArray:
    """The frames the first round starts from: ``initial_frames`` (checked), else :func:`start_frames`."""
    if initial_nodes is not None and initial_frames is not None:
        raise ValueError("give initial_nodes or initial_frames, not both.")
    lengths, contact_nodes = bar_layout(scene)
    if initial_frames is None:
        return start_frames(scene, lengths, contact_nodes, initial_nodes)
    q0 = np.asarray(initial_frames, dtype=float)
    if q0.shape != (lengths.size, 4) or not np.all(np.isfinite(q0)):
        raise ValueError(f"initial_frames has shape {q0.shape}; expected ({lengths.size}, 4) finite quaternions.")
    return q0


def answer(program: Program, res: Any, iterations: int, rounds: int, seconds: float) -> Solution3D:
    """The :class:`Solution3D` of ``program`` at ``res`` (forces only for a success)."""
    scene = program.scene
    z = np.asarray(res.x, dtype=float)
    q = program.frames(z)
    _, nodes_var = program.split(z)
    nodes = kinematics.nodes(program.base_point, program.lengths, q)  # the chain's own kinematics
    bending, twist_energy = program.energy_values(z)  # (the last point the solve evaluated: no new evaluation)
    twist = joint_twists(program.energy.base, q)
    forces: list[ContactForce3D] = []
    clamp_f, clamp_m = np.zeros(3), np.zeros(3)
    first = np.array([0.5 * program.lengths[0]])
    extras: dict[str, Any] = {"base_tangent": np.asarray(scene.base.tangent), "closure_gap_mm":
                              float(np.max(np.abs(nodes - nodes_var))),
                              "entrance_stiffness": (float(scene.wire.properties_at(first).bending_stiffness[0]),
                                                     float(twist_stiffness(scene.wire, first, scene.poisson_ratio,
                                                                           scene.shear_modulus)[0]))}
    success = bool(res.success)
    if success:
        clamp_f, clamp_m, forces = external_forces(program, list(res.constraint_multipliers), nodes, nodes_var, q,
                                                   extras, z)
    return Solution3D(success=success, status=int(res.status), message=str(res.message), nodes=nodes,
                      frames=quat.to_frames(q), quaternions=q, bending_energy=bending,
                      twist_energy=twist_energy, twist=twist, base_rotation=scene.base.rotation, forces=forces,
                      clamp_force=clamp_f, clamp_moment=clamp_m, iterations=iterations, rounds=rounds,
                      solve_time_s=seconds, lengths=program.lengths, extras=extras)


def external_forces(program: Program, lam: list[Any], nodes: FloatArray, nodes_var: FloatArray, q: FloatArray,
                    extras: dict[str, Any], z: FloatArray) -> tuple[FloatArray, FloatArray, list[ContactForce3D]]:
    """The clamp's force and moment and every other external force of a converged solve, from its multipliers
    ``lam`` (one array per row block, in the program's order); sets ``extras["multipliers"]`` and
    ``extras["contact_moment"]`` (the moments that contacts holding a tangent exert)."""
    scene = program.scene
    forces: list[ContactForce3D] = []
    extras["multipliers"] = [np.asarray(v, dtype=float) for v in lam]
    clamp_f = np.asarray(lam[0], dtype=float)[:3].copy()
    e = program.energy
    clamp_m = clamp_moment(e.base, q[0], e.joint_bending[0], e.joint_twist[0], e.joint_rest[0])
    index = 1
    pinned = [(int(k), c) for k, c in zip(program.contact_nodes, scene.contacts, strict=True)
              if c.point is not None]
    if pinned:
        values = np.asarray(lam[index], dtype=float).reshape(-1, 3)
        for (k, _), f in zip(pinned, values, strict=True):
            norm = float(np.linalg.norm(f))
            forces.append(ContactForce3D("contact", k, nodes[k], f / norm if norm > 0 else np.zeros(3), f))
        index += 1
    if scene.walls:
        values = np.asarray(lam[index], dtype=float).reshape(len(scene.walls), program.n)
        for w, row in zip(scene.walls, values, strict=True):
            normal = np.asarray(w.normal, dtype=float)
            for k in np.flatnonzero(row != 0.0):  # (λ ≤ 0 on an upper side: the wall pushes along −n̂)
                forces.append(ContactForce3D("wall", int(k) + 1, nodes[k + 1], -normal, row[k] * normal))
        index += 1
    if scene.vessel is not None:
        values = np.asarray(lam[index], dtype=float)
        mode = "held" if program.has_creases else "rows"  # (the rows the program had)
        g = scene.vessel.lumen_rows(nodes_var[1:], node_radii(scene, program.lengths), mode)[0]
        active = np.flatnonzero((values > 0.0) & (g <= TOUCHING * scene.wire.length))
        grad = scene.vessel.lumen_rows(nodes_var[1:], node_radii(scene, program.lengths), mode)[1][active]
        for j, k in enumerate(active):
            norm = float(np.linalg.norm(grad[j]))
            forces.append(ContactForce3D("lumen", int(k) + 1, nodes[k + 1], grad[j] / norm,
                                         values[k] * grad[j]))
        index += 1
        if program.has_creases:
            # (a crease's contact: at the wire's nearest point to it, on a bar or a node; node = the bar's far end)
            values = np.asarray(lam[index], dtype=float).reshape(-1, CREASE_SLOTS)
            for found, held in zip(program.crease_contacts(z), values, strict=True):
                for j in range(found.bar.size):
                    if held[j] > 0.0 and found.value[j] <= TOUCHING * scene.wire.length:
                        k, tau = int(found.bar[j]), float(found.fraction[j])
                        normal = found.gradient[j, :3] + found.gradient[j, 3:]  # ((1 − τ) ŵ + τ ŵ)
                        point = nodes[k + 1].copy() if tau >= 1.0 else nodes[k] + tau * (nodes[k + 1] - nodes[k])
                        forces.append(ContactForce3D("crease", k + 1, point, normal, held[j] * normal))
    if scene.tip_force is not None:
        f = np.asarray(scene.tip_force, dtype=float)
        norm = float(np.linalg.norm(f))
        forces.append(ContactForce3D("tip", program.n, nodes[-1], f / norm if norm > 0 else np.zeros(3), f))
    moment = np.zeros(3)
    for b, side, w, r, g, star in zip(e.half_bar, e.half_side, e.half_weight, e.half_rest, e.half_twist,
                                      e.half_frame, strict=True):
        moment += half_joint_moment(star, q[b], w, r, g, side > 0)
    extras["contact_moment"] = moment
    return clamp_f, clamp_m, forces


def joint_twists(base: FloatArray, q: FloatArray) -> FloatArray:
    """Twist ``τ`` (rad) of every joint: the clamp's (``q_B`` to bar 1), then between consecutive bars.

    ``τ = 2 atan2(r_z, r_0)`` of :func:`guidewire.rod.strain.joint_strain` on the values alone (its jets' value
    arithmetic, the same numbers, without the bending's and the derivatives' work)."""
    left = np.vstack((base, q[:-1]))
    r = quat.relative([left[:, c] for c in range(4)], [q[:, c] for c in range(4)])
    return 2.0 * np.arctan2(r[3], r[0])
