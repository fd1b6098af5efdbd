"""Our 3-D rod (``guidewire.solve3d``) beside PyElastica relaxed to its static state: a wire in a helical tube.

What is compared
----------------
A wire pushed into the shipped helical tube (``guidewire.vessel3d.shapes.helix()``: coil radius 10 mm, pitch 25 mm,
lumen radius 2 mm, a 20 mm straight lead-in; curvature 1/11.6 mm) to an inserted length L = 50 mm, so that it leans on
the wall: clamped at the entrance along the tangent, the rest of the wire does not exist. The wire is stEVE's tip
material, uniform: d = 0.7 mm, E = 17 000 MPa, ν = 0.33 (G = E / (2(1 + ν))), density 6.45e-3 g/mm³; frictionless.

- Case (a): a straight wire. It touches the outer wall at three nodes (near s = 16 mm, 40 mm and the tip).
- Case (b): a load that twists the rod (``Scene3D`` still takes no tip moment, and a straight rod turned at the base
  keeps its twist uniform and its shape): the last 10 mm bent at rest to a 12.1 mm radius (stEVE's J) towards the
  material d1, the clamp turned by 90° about the tangent, so the J must leave its rest plane against the wall and the
  wire stores twist energy.

Both codes have n elements (bars) with nodes at ``s_i = i L/n`` (n = 25, 50, 100), the same EI and GJ, the lumen held
at the nodes only (every node within lumen radius − wire radius of the centreline), and the same start: the bars laid
along the centreline, their frames parallel-transported from the (turned) clamp frame -- our ``solve3d``'s own start
in a vessel (``guidewire.solve3d.start``).

Ours: a discrete inextensible Kirchhoff rod (bending + twist), quasi-static, the lumen as hard constraints solved by
SQP. Timed two ways: *cold* (``Scene3D`` + ``solve3d`` from that start, the same start as PyElastica) and *insertion*
(``insert3d`` pushed in 2 mm steps to L with the clamp at the case's rotation, each step warm-started: how the code is
used). Both give the same shape (to 1e-9 mm). The reference shape for the errors is our cold solve at n = 200, whose
nodes include those of every compared n (so "err" is the distance to our finer shape; ours at n = 100 is within
0.001 mm of it).

PyElastica (``pip install pyelastica``; the shared setup in ``_pyelastica_common.py``, units mm, N, MPa, s, tonne): a
``CosseratRod.straight_rod`` given our start as ``position`` and ``directors`` (rest lengths L/n, rest curvature zero;
case (b): ``rest_kappa[1]`` = κ⁰ times the share of each interior node's Voronoi domain inside the J, our joint rest
angle ``Σ κ⁰ l/2``; ``rest_kappa[1] > 0`` bends towards d1, checked on an arc), its own EA and (27/28) G A (a Cosserat
rod stretches and shears: strain ~2e-4 here), ``OneEndFixedBC`` on node 0 and element 0 (the clamp frame turned in
case (b)). Tube contact is not built into PyElastica, so it is written as a user would: ``TubePenalty``, a
``NoForces`` subclass whose ``apply_forces`` runs a numba kernel (numba comes with PyElastica, whose own forcings are
numba kernels): each node's nearest point on the centreline sampled
every 0.05 mm (a polyline: the chord sagitta is 3e-5 mm; the nearest segment searched ± 8 around the last one, all
of them at the first call), and a node farther than ``R − r`` by ``gap > 0`` pushed back by ``k · gap + c · v_n``
along the normal (never pulled), ``c = 0.25 · 2 √(k m_node)``; two stiffnesses k = 100 and 10 000 N/mm (penetration
≈ F / k). Relaxed with the ``AnalyticalLinearDamper`` (2 ω₁, ω₁ = 1.875² √(EI / (ρ A L⁴)) = 400 rad/s) and
``PositionVerlet``, ``dt = min(0.7 × the rod's stability estimate of pyelastica.py (whose 0.9 diverged in case (b) at
n = 50), √(m_min / k))`` (the contact spring of the
lightest node; never the smaller one here, so both k run with the same dt), stopped when the largest node speed
< 1e-4 mm · ω₁ and the tip moved < 1e-4 mm over 1/ω₁ (checked every 500 steps). Its time: building,
``finalize`` and stepping.

Measured per (case, n, k): time to equilibrium (median of ``--repeats``, BLAS on one thread) of ours (cold, with its
SQP iterations, and insertion) and of PyElastica (with steps and dt); the shape difference between the two codes
(largest, mean and tip distance between corresponding nodes, mm); each code's distance to the reference; each code's
largest lumen violation on the exact tube (mm); the contacts found (node:force in N: our lumen multipliers,
PyElastica's k · gap); our energy (and its twist part).

Where they differ: hard constraints against a penalty (PyElastica's nodes sit F/k outside the lumen); inextensible
and unshearable bars against a Cosserat rod; PyElastica's element 0 rigid along the clamp and no bending spring on the
end half-elements (its first-order offset, ``pyelastica.md``), ours second order; a static minimum against the rest
state of damped dynamics (the same equilibrium here: both start from the same shape and the tube leaves one).

Conclusion (``results/pyelastica_tube.md``, median of 3): both codes find the same equilibrium. At n = 100 the
shapes differ by at most 0.043–0.046 mm (a) and 0.031–0.032 mm (b), mean 0.02 mm; PyElastica's distance to our
n = 200 shape (0.04 mm) is mostly its own discretisation (its rigid clamp element; ours at n = 100 is within 0.001 mm)
and its stretch (strain 2e-4). Both find the same contact nodes with the tip force within 2 % (1.30–1.41 N); the
first contact, near the clamp, differs most (0.25 against 0.11–0.22 N: PyElastica's rigid first element). Energies
agree to 1.4 % (case b twist energy 2.53 against 2.51–2.52 N·mm). PyElastica's nodes sit 0.014 mm outside the lumen
at k = 100 N/mm and 0.00014 mm at k = 10 000 (F/k; ours: < 1e-10 mm), and k barely changes its time (the rod's own
time step binds). Time to equilibrium (the last run, on a loaded machine: both codes slower than the run before):
PyElastica 4.0–28 s (117 500–186 000 steps); ours cold 95–530 ms in 10–14 SQP iterations, PyElastica / ours
cold = 18–116; by insertion in 25 warm-started steps ours takes 0.49–2.8 s, 4.3–22× less than PyElastica. (The run
before the ``robust3d`` fixes: ours cold 57 ms–1.2 s in 8–44 iterations except case (a) at n = 25, 12 s in 386
iterations, PyElastica 4× faster there: the centreline start hid the lumen from the first QP, whose first steps
are now bounded.) In the tube the gap is smaller than on the free cantilever (110–450×, ``pyelastica.md``): our solve
pays for contact (more iterations), PyElastica's settling time does not grow. Our J wire pushed in at 0° and then
turned in 15° steps failed at the 60° step (a fold: the J snaps); the insertion now solves such a step from the
built-in start and turns on, but the insertion here is still done with the clamp already turned.

Usage: ``python benchmarks/pyelastica_tube.py [--quick] [--repeats K] [--out DIR] [--stiffness K1,K2] [--cases ab]``;
writes ``pyelastica_tube.{md,csv}`` (``pyelastica_tube_quick.*`` with ``--quick``: case (a), n = 25, the stiffest k,
one run of each code) in ``--out``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import _arguments as A
import _environment as E  # first: pins BLAS to one thread before numpy loads
import _pyelastica_common as P
import _tables as T
import numpy as np

from guidewire import Wire
from guidewire.rod import quaternion as quat
from guidewire.solve3d import Scene3D, solve3d
from guidewire.solve3d.insert import insert3d
from guidewire.solve3d.start import start_frames
from guidewire.vessel3d.shapes import helix
from guidewire.wire import Section

try:
    import numba
except ImportError:  # pragma: no cover - numba comes with PyElastica
    numba = None

ea = P.ea

LENGTH, DIAMETER, YOUNGS, POISSON = 50.0, 0.7, 17000.0, 0.33  # mm, mm, MPa, -
SHEAR = YOUNGS / (2.0 * (1.0 + POISSON))  # MPa
DENSITY = 6.45e-9  # t/mm³ (6.45e-3 g/mm³)
#: Case (b): the last J_LENGTH mm of the wire bent at rest with curvature J_CURVATURE (stEVE's J: 12.1 mm radius),
#: the clamp turned by J_ROTATION about the entrance tangent.
J_LENGTH, J_CURVATURE, J_ROTATION = 10.0, 1.0 / 12.1, math.pi / 2
#: Our insertion: steps of INSERT_STEP mm from INSERT_STEP to LENGTH, the clamp at the case's rotation throughout.
INSERT_STEP = 2.0
#: Bars of our converged reference shape (a multiple of every compared n, so its nodes include theirs).
REFERENCE_N = 200
#: Spacing (mm) of the centreline polyline of the penalty contact; chord sagitta κ h²/8 ≈ 3e-5 mm on this helix.
POLYLINE_SPACING = 0.05
#: Segments searched on either side of a node's previous nearest segment (a node moves far less per step).
WINDOW = 8
#: Damping of the penalty: this fraction of the critical damping 2 √(k m) of each node on the contact spring.
CONTACT_ZETA = 0.25
#: PyElastica's time step as a fraction of the rod's stable estimate: pyelastica.py's 0.9 diverged in case (b) at
#: n = 50 within 3 500 steps (k = 100 N/mm); 0.7 settles every row.
TUBE_CFL = 0.7
#: The time step also keeps ω_c dt ≤ CONTACT_CFL, ω_c = √(k / m) of the lightest node on the contact spring.
CONTACT_CFL = 1.0


# -- the tube of the penalty contact ---------------------------------------------------------------------------------
def _nearest_kernel(points: np.ndarray, polyline: np.ndarray, hint: np.ndarray, window: int,
                    distance: np.ndarray, foot: np.ndarray) -> None:
    """Closest point of ``polyline`` (M, 3) to each of ``points`` (m, 3): ``distance`` (m,) and ``foot`` (m, 3).

    ``hint[i]`` ≥ 0: only segments ``hint[i] ± window`` are searched; < 0: all of them. ``hint`` is overwritten by
    the nearest segment.
    """
    m, segments = points.shape[0], polyline.shape[0] - 1
    for i in range(m):
        lo, hi = 0, segments
        if hint[i] >= 0:
            lo, hi = max(0, hint[i] - window), min(segments, hint[i] + window + 1)
        best, best_j, best_t = np.inf, lo, 0.0
        for j in range(lo, hi):
            e0 = polyline[j + 1, 0] - polyline[j, 0]
            e1 = polyline[j + 1, 1] - polyline[j, 1]
            e2 = polyline[j + 1, 2] - polyline[j, 2]
            v0 = points[i, 0] - polyline[j, 0]
            v1 = points[i, 1] - polyline[j, 1]
            v2 = points[i, 2] - polyline[j, 2]
            t = min(1.0, max(0.0, (v0 * e0 + v1 * e1 + v2 * e2) / (e0 * e0 + e1 * e1 + e2 * e2)))
            d0, d1, d2 = v0 - t * e0, v1 - t * e1, v2 - t * e2
            d = d0 * d0 + d1 * d1 + d2 * d2
            if d < best:
                best, best_j, best_t = d, j, t
        hint[i] = best_j
        distance[i] = math.sqrt(best)
        for k in range(3):
            foot[i, k] = polyline[best_j, k] + best_t * (polyline[best_j + 1, k] - polyline[best_j, k])


def _penalty_kernel(position: np.ndarray, velocity: np.ndarray, forces: np.ndarray, polyline: np.ndarray,
                    hint: np.ndarray, window: int, margin: float, stiffness: float, damping: np.ndarray,
                    gap: np.ndarray, distance: np.ndarray, foot: np.ndarray) -> None:
    """Add to ``forces`` (3, m) the penalty ``−(k gap + c v·n) n`` of every node (but the clamped first) whose
    distance to the centreline exceeds ``margin`` by ``gap`` > 0 (``n`` pointing out of the lumen; never pulling)."""
    _nearest_kernel(position.T, polyline, hint, window, distance, foot)
    for i in range(1, position.shape[1]):
        gap[i] = distance[i] - margin
        if gap[i] <= 0.0 or distance[i] == 0.0:
            continue
        n0 = (position[0, i] - foot[i, 0]) / distance[i]
        n1 = (position[1, i] - foot[i, 1]) / distance[i]
        n2 = (position[2, i] - foot[i, 2]) / distance[i]
        push = stiffness * gap[i] + damping[i] * (velocity[0, i] * n0 + velocity[1, i] * n1 + velocity[2, i] * n2)
        push = max(push, 0.0)
        forces[0, i] -= push * n0
        forces[1, i] -= push * n1
        forces[2, i] -= push * n2


if numba is not None:
    _nearest_kernel = numba.njit(cache=True)(_nearest_kernel)
    _penalty_kernel = numba.njit(cache=True)(_penalty_kernel)


def centreline_polyline(vessel: Any, reach: float, spacing: float = POLYLINE_SPACING) -> np.ndarray:
    """The vessel's main centreline sampled every ``spacing`` of its parameter from the entrance to ``reach`` (mm)
    past it: points (M, 3)."""
    return vessel.path(np.linspace(0.0, reach, int(math.ceil(reach / spacing)) + 1))[0]


def nearest_on_polyline(points: Any, polyline: Any, hint: np.ndarray | None = None,
                        window: int = WINDOW) -> tuple[np.ndarray, np.ndarray]:
    """Distance (m,) of each of ``points`` (m, 3) to the polyline (M, 3) and the closest point on it (m, 3).

    Parameters
    ----------
    points, polyline : array_like
    hint : ndarray of int, shape (m,), optional
        Each point's nearest segment before (searched ± ``window``; negative: everywhere); overwritten by the new
        one. None searches every segment.
    window : int
    """
    p = np.ascontiguousarray(points, dtype=float).reshape(-1, 3)
    line = np.ascontiguousarray(polyline, dtype=float)
    if hint is None:
        hint = np.full(len(p), -1, dtype=np.int64)
    distance, foot = np.empty(len(p)), np.empty((len(p), 3))
    _nearest_kernel(p, line, hint, window, distance, foot)
    return distance, foot


_ZERO_TIME = np.float64(0.0)

if ea is not None:

    class TubePenalty(ea.NoForces):
        """Frictionless tube contact as a PyElastica forcing: every node (but the clamped first) farther than
        ``margin`` (lumen radius − wire radius, mm) from the centreline polyline is pushed back by
        ``k · gap + c · v_n`` along the outward normal, ``c = CONTACT_ZETA · 2 √(k m_node)``.

        Parameters
        ----------
        polyline : ndarray, shape (M, 3)
            The centreline, densely sampled (mm).
        margin : float
        stiffness : float
            ``k`` (N/mm).
        masses : ndarray, shape (m,)
            The rod's node masses (t).
        """

        def __init__(self, polyline: np.ndarray, margin: float, stiffness: float, masses: np.ndarray) -> None:
            super().__init__()
            m = len(masses)
            self.polyline = np.ascontiguousarray(polyline, dtype=float)
            self.margin, self.stiffness = float(margin), float(stiffness)
            self.damping = CONTACT_ZETA * 2.0 * np.sqrt(self.stiffness * np.asarray(masses, dtype=float))
            self.hint = np.full(m, -1, dtype=np.int64)
            self.gap, self.distance, self.foot = np.zeros(m), np.zeros(m), np.zeros((m, 3))

        def apply_forces(self, system: Any, time: np.float64 = _ZERO_TIME) -> None:
            _penalty_kernel(system.position_collection, system.velocity_collection, system.external_forces,
                            self.polyline, self.hint, WINDOW, self.margin, self.stiffness, self.damping, self.gap,
                            self.distance, self.foot)


# -- the problem -----------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Case:
    """One compared problem: a name, whether the wire has the J tip, and the clamp rotation (rad)."""

    name: str
    j_tip: bool
    rotation: float


CASES = (Case("a: straight wire in the helix", False, 0.0),
         Case("b: J wire in the helix, clamp turned 90°", True, J_ROTATION))


def section() -> tuple[float, float, float]:
    """Radius (mm), area (mm²) and second moment of area (mm⁴) of the round wire."""
    return P.round_section(DIAMETER)


def first_mode() -> float:
    """ω₁ (rad/s) of the straight cantilever of length L: 1.875² √(EI / (ρ A L⁴))."""
    return P.cantilever_first_mode(YOUNGS, DIAMETER, DENSITY, LENGTH)


def vessel() -> Any:
    """The shipped helix (coil radius 10 mm, pitch 25 mm, lumen radius 2 mm, 20 mm straight lead-in)."""
    return helix()


def scene(n: int, case: Case, tube: Any) -> Scene3D:
    sections = (Section(length=J_LENGTH, rest_curvature=J_CURVATURE),) if case.j_tip else ()
    wire = Wire(length=LENGTH, bars=n, youngs_modulus=YOUNGS, diameter=DIAMETER, scheme="second_order",
                sections=sections)
    return Scene3D.in_vessel(wire, tube, rotation=case.rotation, shear_modulus=SHEAR)


def start_state(sc: Scene3D) -> tuple[np.ndarray, np.ndarray]:
    """Our start (the bars along the centreline, frames transported from the clamp): nodes (n + 1, 3) and frames
    ``[d1; d2; d3]`` (n, 3, 3)."""
    n = sc.wire.bars
    frames = quat.to_frames(start_frames(sc, np.full(n, LENGTH / n), np.zeros(0, dtype=int)))
    bars = frames[:, 2] * (LENGTH / n)
    nodes = np.vstack((np.asarray(sc.base.point), np.asarray(sc.base.point) + np.cumsum(bars, axis=0)))
    return nodes, frames


def rest_curvature(n: int) -> np.ndarray:
    """PyElastica's ``rest_kappa`` (3, n − 1): ``κ⁰`` about ``d2`` (a bend towards ``d1``, as ours) times the part of
    node i's Voronoi domain ``[s_i − dl/2, s_i + dl/2]`` inside the J (our joint rest angle ``Σ κ⁰ l/2``)."""
    dl = LENGTH / n
    s = dl * np.arange(1, n)
    inside = np.clip((s + dl / 2) - (LENGTH - J_LENGTH), 0.0, dl) / dl
    kappa = np.zeros((3, n - 1))
    kappa[1] = J_CURVATURE * inside
    return kappa


def lumen_violation(tube: Any, nodes: np.ndarray) -> float:
    """The deepest node outside the lumen shrunk by the wire's radius (mm, 0 when all are inside), on the exact
    tube (its spline, not the polyline)."""
    if not np.all(np.isfinite(nodes)):
        return math.nan
    clearance, _ = tube.clearance(nodes, DIAMETER / 2.0)
    return float(max(0.0, -clearance.min()))


# -- the runs --------------------------------------------------------------------------------------------------------
def run_ours(n: int, case: Case, tube: Any) -> dict[str, Any]:
    """One cold ``solve3d`` from the centreline start (scene construction included)."""
    start = time.perf_counter()
    sol = solve3d(scene(n, case, tube))
    wall = time.perf_counter() - start
    contacts = [(f.node, f.magnitude) for f in sol.forces if f.kind != "clamp"]
    return {"nodes": sol.nodes.copy(), "success": bool(sol.success), "iterations": sol.iterations, "wall_s": wall,
            "solve_s": sol.solve_time_s, "energy": sol.energy, "twist_energy": sol.twist_energy,
            "contacts": contacts}


def run_ours_insertion(n: int, case: Case, tube: Any) -> dict[str, Any]:
    """Our insertion: pushed in :data:`INSERT_STEP` mm steps with the clamp at the case's rotation (warm starts)."""
    start = time.perf_counter()
    out = insert3d(scene(n, case, tube), np.arange(INSERT_STEP, LENGTH + INSERT_STEP / 2, INSERT_STEP),
                   case.rotation)
    wall = time.perf_counter() - start
    last = out.steps[-1]
    return {"nodes": last.nodes.copy(), "success": out.complete, "steps": len(out.steps), "wall_s": wall,
            "iterations": sum(s.iterations for s in out.steps), "energy": last.energy}


def run_pyelastica(n: int, case: Case, tube: Any, stiffness: float) -> dict[str, Any]:
    """Build PyElastica's rod on our start, add the tube penalty, damp and step it until it settles."""
    start = time.perf_counter()
    r, _, _ = section()
    omega = first_mode()
    sc = scene(n, case, tube)
    nodes, frames = start_state(sc)
    rod = ea.CosseratRod.straight_rod(n, nodes[0].copy(), frames[0, 2].copy(), frames[0, 0].copy(), LENGTH, r,
                                      DENSITY, youngs_modulus=YOUNGS, shear_modulus=SHEAR,
                                      position=np.ascontiguousarray(nodes.T),
                                      directors=np.ascontiguousarray(frames.transpose(1, 2, 0)))
    if case.j_tip:
        rod.rest_kappa[...] = rest_curvature(n)
    masses = rod.mass.copy()
    dt = min(P.time_step(LENGTH / n, r, DENSITY, YOUNGS, SHEAR, cfl=TUBE_CFL),
             CONTACT_CFL * math.sqrt(float(masses[1:].min()) / stiffness))
    sim = P.simulator()
    sim.append(rod)
    sim.constrain(rod).using(ea.OneEndFixedBC, constrained_position_idx=(0,), constrained_director_idx=(0,))
    polyline = centreline_polyline(tube, LENGTH + 10.0)
    radius = float(np.min(np.asarray(tube.radius)))
    sim.add_forcing_to(rod).using(TubePenalty, polyline, radius - r, stiffness, masses)
    sim.dampen(rod).using(ea.AnalyticalLinearDamper, uniform_damping_constant=P.DAMPING_OVER_OMEGA * omega,
                          time_step=dt)
    sim.finalize()
    setup = time.perf_counter() - start
    run = P.relax(sim, rod, dt, omega)
    wall = time.perf_counter() - start
    final = rod.position_collection.T.copy()
    distance, _ = nearest_on_polyline(np.nan_to_num(final), polyline)
    gap = distance - (radius - r)
    contacts = [(int(i), float(stiffness * gap[i])) for i in np.flatnonzero(gap > 0.0) if i > 0]
    twist = rod.kappa[2] - rod.rest_kappa[2]
    return {"nodes": final, "success": run.settled, "steps": run.steps, "wall_s": wall, "setup_s": setup,
            "dt_s": dt, "sim_time_s": run.time, "max_stretch": float(np.max(np.abs(rod.dilatation - 1.0))),
            "contacts": contacts, "energy": float(rod.compute_bending_energy()),
            "twist_energy": float(0.5 * np.sum(rod.bend_matrix[2, 2] * twist**2 * rod.rest_voronoi_lengths)),
            "shear_energy": float(rod.compute_shear_energy())}


def contact_list(contacts: list[tuple[int, float]], floor: float = 1e-3) -> str:
    """``node:force`` (N) of the contacts carrying more than ``floor`` N."""
    return " ".join(f"{i}:{f:.3g}" for i, f in contacts if f > floor)


def compare(quick: bool, repeats: int, stiffnesses: tuple[float, ...], cases: tuple[Case, ...]
            ) -> list[dict[str, Any]]:
    tube = vessel()
    ns = (25,) if quick else (25, 50, 100)
    rows: list[dict[str, Any]] = []
    for case in cases:
        reference = run_ours(REFERENCE_N, case, tube)
        if not reference["success"]:
            raise RuntimeError(f"our reference at n = {REFERENCE_N} failed ({case.name})")
        for n in ns:
            ref_nodes = reference["nodes"][:: REFERENCE_N // n]
            ours, ours_walls = P.median_run(run_ours, repeats, n, case, tube)
            inserted, _ = P.median_run(run_ours_insertion, repeats, n, case, tube)
            ours_err = np.linalg.norm(ours["nodes"] - ref_nodes, axis=1)
            base = {"case": case.name, "n": n, "ours_success": ours["success"], "ours_ms": 1e3 * ours["wall_s"],
                    "ours_iterations": ours["iterations"], "ours_walls": ";".join(f"{w:.3f}" for w in ours_walls),
                    "ours_insert_ms": 1e3 * inserted["wall_s"], "ours_insert_steps": inserted["steps"],
                    "ours_insert_success": inserted["success"],
                    "insert_vs_cold_mm": float(np.linalg.norm(inserted["nodes"] - ours["nodes"], axis=1).max()),
                    "ours_energy": ours["energy"], "ours_twist_energy": ours["twist_energy"],
                    "ours_err_max_mm": float(ours_err.max()), "ours_err_mean_mm": float(ours_err.mean()),
                    "ours_violation_mm": lumen_violation(tube, ours["nodes"]),
                    "ours_contacts": contact_list(ours["contacts"])}
            for k in stiffnesses:
                pe, walls = P.median_run(run_pyelastica, repeats, n, case, tube, k)
                diff = np.linalg.norm(pe["nodes"] - ours["nodes"], axis=1)
                pe_err = np.linalg.norm(pe["nodes"] - ref_nodes, axis=1)
                row = dict(base, stiffness=k, pe_success=pe["success"], pe_s=pe["wall_s"], pe_setup_s=pe["setup_s"],
                           pe_steps=pe["steps"], pe_dt_s=pe["dt_s"], pe_sim_time_s=pe["sim_time_s"],
                           pe_max_stretch=pe["max_stretch"], pe_err_max_mm=float(pe_err.max()),
                           pe_err_mean_mm=float(pe_err.mean()), pe_violation_mm=lumen_violation(tube, pe["nodes"]),
                           pe_contacts=contact_list(pe["contacts"]), pe_energy=pe["energy"],
                           pe_twist_energy=pe["twist_energy"], pe_shear_energy=pe["shear_energy"],
                           diff_max_mm=float(diff.max()),
                           diff_mean_mm=float(diff.mean()), diff_tip_mm=float(diff[-1]),
                           time_ratio=pe["wall_s"] / ours["wall_s"],
                           time_ratio_insertion=pe["wall_s"] / inserted["wall_s"],
                           pe_walls=";".join(f"{w:.2f}" for w in walls))
                rows.append(row)
                print(case.name, "n", n, "k", k, ", ".join(f"{key} {T.cell(v)}" for key, v in row.items()
                                                         if key not in ("case", "n", "stiffness")), flush=True)
    return rows


def report(rows: list[dict[str, Any]], repeats: int) -> list[str]:
    omega = first_mode()
    r, area, inertia = section()
    tube = vessel()
    lines = ["# Our 3-D rod beside PyElastica relaxed to its static state: a wire in a helical tube", "",
             *[f"- {x}" for x in E.environment(guidewire=False)],
             f"- pyelastica {E.version('pyelastica')}, numba {E.version('numba')}", "",
             f"Wire: L = {LENGTH:g} mm inserted, d = {DIAMETER} mm, E = {YOUNGS:g} MPa, G = E/(2(1+{POISSON})) = "
             f"{SHEAR:.0f} MPa (EI = {YOUNGS * inertia:.1f} N·mm², GJ = {2 * SHEAR * inertia:.1f} N·mm²), clamped at "
             f"the entrance of the shipped helix (coil radius 10 mm, pitch 25 mm, lumen radius "
             f"{float(np.min(tube.radius)):g} mm, 20 mm straight lead-in) along its tangent; frictionless. Case (b): "
             f"the last {J_LENGTH:g} mm bent at rest to a {1 / J_CURVATURE:g} mm radius towards d1, the clamp turned "
             f"by {math.degrees(J_ROTATION):g}° about the tangent. Both codes: n elements with nodes at s_i = i L/n, "
             "the lumen held at the nodes only, the same start (the bars along the centreline, frames transported "
             "from the clamp).", "",
             f"Ours: cold = Scene3D + solve3d from that start (defaults); insertion = insert3d pushed in "
             f"{INSERT_STEP:g} mm steps (warm starts) to L, clamp at the case's rotation throughout. Reference: our "
             f"cold solve at n = {REFERENCE_N} (its nodes include every compared n's); 'err' = distance to it.", "",
             f"PyElastica: CosseratRod.straight_rod(position, directors = our start) with the same E, G, d, ρ = "
             f"{DENSITY:g} t/mm³, its own EA and (27/28) G A; case (b) rest_kappa[1] = κ⁰ × the share of each "
             "interior node's Voronoi domain inside the J; OneEndFixedBC (node 0, element 0); a TubePenalty forcing "
             f"(NoForces subclass, numba kernel): nodes farther than {float(np.min(tube.radius)):g} − {r:g} mm from "
             f"the centreline polyline (sampled every {POLYLINE_SPACING} mm, nearest segment searched ± {WINDOW} "
             f"around the last) pushed back by k·gap + c·v_n, c = {CONTACT_ZETA} × 2√(k m_node); "
             f"AnalyticalLinearDamper {P.DAMPING_OVER_OMEGA:g} ω₁ = {P.DAMPING_OVER_OMEGA * omega:.0f} 1/s "
             f"(ω₁ = {omega:.0f} rad/s, the straight cantilever's first mode); PositionVerlet; dt = min({TUBE_CFL} × "
             f"the rod's estimate (pyelastica.md), {CONTACT_CFL:g} · √(m_min / k)); stopped when the largest node "
             f"speed < "
             f"{P.VELOCITY_TOL_MM:g} mm · ω₁ and the tip moved < {P.TIP_TOL_MM:g} mm over 1/ω₁. Its time includes "
             "building and finalize; numba's kernels are cached on disk (the first run of a session pays their "
             "loading, in 'setup').", "",
             f"Times: median of {repeats} (wall, BLAS on one thread). Violations: the deepest node outside the lumen "
             "(shrunk by the wire radius) on the exact tube (mm). Contacts: node:force (N) above 1 mN (ours: the "
             "lumen multipliers; PyElastica: k · penetration at the end). Energies: bending + twist (PyElastica's "
             "compute_bending_energy, which holds both; its twist part from κ₃; its shear/stretch energy in the CSV).",
             "",
             "## Time to equilibrium", ""]
    header = ["case", "n", "k (N/mm)", "ours cold (ms)", "ours iters", "ours insertion (ms)", "PyE (s)",
              "PyE setup (s)", "PyE steps", "PyE dt (s)", "PyE settled", "PyE / ours cold", "PyE / ours insertion"]
    table = [[x["case"], x["n"], x["stiffness"], x["ours_ms"], x["ours_iterations"], x["ours_insert_ms"], x["pe_s"],
              x["pe_setup_s"], x["pe_steps"], x["pe_dt_s"], x["pe_success"], x["time_ratio"],
              x["time_ratio_insertion"]] for x in rows]
    lines += T.markdown_table(header, table)
    lines += ["", "## Shape, lumen and contacts", ""]
    header = ["case", "n", "k (N/mm)", "diff max (mm)", "diff mean (mm)", "tip diff (mm)", "ours err max (mm)",
              "PyE err max (mm)", "ours violation (mm)", "PyE violation (mm)", "PyE max stretch",
              "energy ours / PyE (N·mm)", "twist energy ours / PyE (N·mm)", "ours contacts", "PyE contacts"]
    table = [[x["case"], x["n"], x["stiffness"], x["diff_max_mm"], x["diff_mean_mm"], x["diff_tip_mm"],
              x["ours_err_max_mm"], x["pe_err_max_mm"], x["ours_violation_mm"], x["pe_violation_mm"],
              x["pe_max_stretch"], f"{T.cell(x['ours_energy'])} / {T.cell(x['pe_energy'])}",
              f"{T.cell(x['ours_twist_energy'], 3)} / {T.cell(x['pe_twist_energy'], 3)}", x["ours_contacts"],
              x["pe_contacts"]]
             for x in rows]
    lines += T.markdown_table(header, table)
    lines += ["", "## Summary", ""]
    for name in dict.fromkeys(x["case"] for x in rows):
        sub = [x for x in rows if x["case"] == name]

        def span(key: str, rows_: list[dict[str, Any]] = sub) -> str:
            values = [x[key] for x in rows_]
            return f"{T.cell(min(values), 2)}–{T.cell(max(values), 2)}"

        finest = [x for x in sub if x["n"] == max(y["n"] for y in sub)]
        violations = ", ".join(f"{T.cell(x['pe_violation_mm'], 2)} mm at k = {x['stiffness']:g}" for x in finest)
        lines.append(f"- {name}: PyElastica takes {span('pe_s')} s ({span('pe_steps')} steps) to equilibrium, "
                     f"ours {span('ours_ms')} ms cold ({span('ours_iterations')} SQP iterations) and "
                     f"{span('ours_insert_ms')} ms by insertion: PyElastica / ours = {span('time_ratio')} (cold), "
                     f"{span('time_ratio_insertion')} (insertion). Shape difference at n = {finest[0]['n']}: largest "
                     f"{span('diff_max_mm', finest)} mm, mean {span('diff_mean_mm', finest)} mm; PyElastica's largest "
                     f"lumen violation {violations}"
                     f" (ours {T.cell(max(x['ours_violation_mm'] for x in sub), 2)} mm).")
    failed = [(x["case"][:2], x["n"], x["stiffness"]) for x in rows
              if not (x["pe_success"] and x["ours_success"] and x["ours_insert_success"])]
    if failed:
        lines += ["", f"Not settled or failed (case, n, k): {failed}."]
    return lines


def main() -> None:
    ap = A.parser(__doc__, quick_help="case (a), n = 25, one stiffness, one run of each code", repeats=3)
    ap.add_argument("--stiffness", type=str, default="100,10000",
                    help="comma-separated penalty stiffnesses k (N/mm) of PyElastica's tube contact")
    ap.add_argument("--cases", type=str, default="ab", help="which cases: a, b or ab")
    args = A.parse(ap)
    P.require("benchmarks/pyelastica_tube.py")
    stiffnesses = tuple(float(k) for k in A.names(args.stiffness))
    cases = tuple(c for c in CASES if c.name[0] in args.cases)
    if args.quick:
        stiffnesses, cases = stiffnesses[-1:], CASES[:1]
    with E.one_thread():
        rows = compare(args.quick, args.repeats, stiffnesses, cases)
    stem = T.output_stem(args.out, "pyelastica_tube", args.quick)
    T.write_csv(rows, stem.with_suffix(".csv"))
    lines = report(rows, args.repeats)
    T.write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
