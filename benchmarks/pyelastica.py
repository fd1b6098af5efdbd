"""Our 3-D rod (``guidewire.solve3d``) beside PyElastica relaxed to its static state, both against the elastica.

What is compared
----------------
Case (a): a nitinol-like wire (L = 100 mm, d = 0.89 mm, E = 80 000 MPa, ν = 0.33 so G = E / (2(1 + ν)), density
6.45e-3 g/mm³) clamped at the origin along +x, with a dead tip force F = (-0.15, 0.40, 0.30) N: a compressive
axial part and a transverse part of 0.5 N at 36.9° out of the x-y plane (F⊥ L²/EI = 2.03; tip deflection about half
of L). A round rod under a dead tip force stays in the plane of the clamp's tangent and the force, so the reference
is the planar elastica (``scipy.integrate.solve_bvp`` as in ``tests/guidewire3d/test_rod_physics.py``) evaluated at
the nodes ``s_i = i L / n`` and mapped into that plane.

Both codes use n elements (bars) with nodes at ``s_i``; corresponding nodes are compared. Ours is solved at
n = 25, 50, 100, 200, 400, PyElastica at n = 25, 50, 100. Not compared: (b) a load that twists the rod (a dead tip
force on a straight round rod leaves the twist zero, and ``Scene3D`` takes no tip moment); (c) rod-cylinder contact
(not done in the time available).

PyElastica (``pip install pyelastica``, imported as ``elastica``) is set up in consistent units mm, N, MPa, s and
tonne (1 N = 1 t·mm/s², so 6.45e-3 g/mm³ = 6.45e-9 t/mm³): ``CosseratRod.straight_rod`` with the same E and G, its
own EA (stretch) and (27/28) G A (shear) -- already stiff: the stretch strain under this load is ~1e-5 -- optionally
multiplied by ``--stiffen K`` (the full run adds one row with K = 10 to show the effect), ``OneEndFixedBC`` on node
0 and element 0, ``EndpointForces`` on the last node (applied at once), ``AnalyticalLinearDamper`` with a uniform
damping constant γ = 2 ω₁ (ω₁ = 1.875² √(EI / (ρ A L⁴)), the first cantilever mode: critically damped), and the
``PositionVerlet`` stepper. Its time step is ``CFL / √(1/dt_a² + 1/dt_s²)`` with ``dt_a = dl √(ρ / (K E))`` (the
axial wave across an element) and ``dt_s = r √(ρ / (K · 27/28 · G))`` (an element's rotation, rotary inertia ρ I,
against its shear stiffness: independent of n, the binding limit at n = 25), CFL = 0.9 (measured stable at n = 25,
50, 100; ``min(dt_a, dt_s)`` in place of the combination diverged at n = 100, where the element's bending spring
adds to its rotational stiffness). Stopping rule, checked every
:data:`CHECK_STEPS` steps: the largest node speed below ``1e-4 mm · ω₁`` and the tip moved less than 1e-4 mm over
the last ``1/ω₁`` of simulated time; a run not settled after :data:`MAX_PERIODS` ``/ω₁`` is reported as such (these
settings and the loop are shared with ``pyelastica_tube.py`` in ``_pyelastica_common.py``).

Measured per (code, n): tip error and largest and mean node error against the elastica (mm); for the pair at equal
n the largest node distance and the tip distance between the two (mm); time to equilibrium (wall time, median of
``--repeats``, BLAS on one thread): ours ``solve3d`` including the scene's construction, with its SQP iterations;
PyElastica's simulator construction and ``finalize`` plus the time stepping, with the number of steps (numba's
compiled kernels are cached on disk by PyElastica, so only a cold cache pays the compilation, reported apart as the
setup time of the first run).

PyElastica holds element 0 rigidly along the clamp, and its bending springs sit at the interior nodes 1 … n−1 with
Voronoi domains covering ``[dl/2, L − dl/2]``: its continuum limit at a given n is the elastica with rigid end
pieces of length dl/2 (the first one along the clamp), which misses the clamp-end rotation ``≈ κ₀ dl/2`` (κ₀ the
clamp curvature) -- a first-order error in dl. The table gives that "rigid-ends elastica" (same ``solve_bvp``, the
tip piece carrying F's moment) as the tip offset from the elastica, and PyElastica's tip error against it (what is
left: its second-order discretisation error and the stopping rule).

Usage: ``python benchmarks/pyelastica.py [--quick] [--repeats K] [--out DIR] [--stiffen K]``; writes
``pyelastica.{md,csv}`` (``pyelastica_quick.*`` with ``--quick``: n = 25 only, one run each) in ``--out``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import _arguments as A
import _environment as E  # first: pins BLAS to one thread before numpy loads
import _pyelastica_common as P
import _tables as T
import numpy as np
from scipy.integrate import solve_bvp

from guidewire import Wire
from guidewire.solve3d import Base3D, Scene3D, solve3d

LENGTH, DIAMETER, YOUNGS, POISSON = 100.0, 0.89, 80000.0, 0.33  # mm, mm, MPa, -
SHEAR = YOUNGS / (2.0 * (1.0 + POISSON))  # MPa
DENSITY = 6.45e-9  # t/mm³ (6.45e-3 g/mm³): with mm, N and s the mass unit is the tonne
TANGENT = np.array([1.0, 0.0, 0.0])
NORMAL = np.array([0.0, 0.0, 1.0])  # d1 at the clamp (both codes)
FORCE = np.array([-0.15, 0.40, 0.30])  # N
ea = P.ea
CFL, DAMPING_OVER_OMEGA, ALPHA_SHEAR = P.CFL, P.DAMPING_OVER_OMEGA, P.ALPHA_SHEAR
VELOCITY_TOL_MM, TIP_TOL_MM, CHECK_STEPS, MAX_PERIODS = P.VELOCITY_TOL_MM, P.TIP_TOL_MM, P.CHECK_STEPS, P.MAX_PERIODS
median_run = P.median_run


def section() -> tuple[float, float, float]:
    """Radius (mm), area (mm²) and second moment of area (mm⁴) of the round wire."""
    return P.round_section(DIAMETER)


def first_mode() -> float:
    """ω₁ (rad/s) of the straight cantilever: 1.875² √(EI / (ρ A L⁴))."""
    return P.cantilever_first_mode(YOUNGS, DIAMETER, DENSITY, LENGTH)


@dataclass(frozen=True)
class Reference:
    """The elastica in the plane of the tangent and the force: nodes at any n, and the clamp's curvature."""

    sol: Any
    across: np.ndarray
    clamp_curvature: float

    def nodes(self, n: int) -> np.ndarray:
        xy = self.sol(np.linspace(0.0, LENGTH, n + 1))[:2].T
        return np.outer(xy[:, 0], TANGENT) + np.outer(xy[:, 1], self.across)


def elastica_reference(rigid: float = 0.0) -> Reference:
    """``x' = cos θ, y' = sin θ, EI θ' = m, m' = F_x sin θ − F_y cos θ``, ``θ(0) = 0``, ``m(L) = 0``.

    ``rigid`` > 0: the rod is rigid on ``[0, rigid]`` and ``[L − rigid, L]`` (PyElastica's continuum limit at
    ``rigid = dl/2``: its bending springs cover ``[dl/2, L − dl/2]``); the nodes there lie on the straight ends.
    """
    _, _, inertia = section()
    ei = YOUNGS * inertia
    fx = float(FORCE @ TANGENT)
    perp = FORCE - fx * TANGENT
    fy = float(np.linalg.norm(perp))
    a, b = rigid, LENGTH - rigid

    def rhs(s, u):
        return np.vstack((np.cos(u[2]), np.sin(u[2]), u[3] / ei, fx * np.sin(u[2]) - fy * np.cos(u[2])))

    def bc(ua, ub):  # the rigid tip segment carries F's moment about its root
        return np.array([ua[0] - a, ua[1], ua[2], ub[3] - rigid * (fy * np.cos(ub[2]) - fx * np.sin(ub[2]))])

    s = np.linspace(a, b, 401)
    out = solve_bvp(rhs, bc, s, np.vstack((s, 0 * s, 0 * s, 0 * s)), tol=1e-11, max_nodes=200000)
    if not out.success:
        raise RuntimeError(f"elastica reference failed: {out.message}")

    def sol(q: np.ndarray) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        u = out.sol(np.clip(q, a, b))
        before, after = q < a, q > b
        u[0, before], u[1, before] = q[before], 0.0
        u[0, after] += (q[after] - b) * np.cos(u[2, after])
        u[1, after] += (q[after] - b) * np.sin(u[2, after])
        return u

    return Reference(sol, perp / fy, abs(float(out.sol(a)[3])) / ei)


def errors(nodes: np.ndarray, ref: np.ndarray) -> dict[str, float]:
    dist = np.linalg.norm(nodes - ref, axis=1)
    return {"tip_mm": float(dist[-1]), "max_mm": float(dist.max()), "mean_mm": float(dist.mean())}


def run_ours(n: int) -> dict[str, Any]:
    """One ``solve3d`` (scene construction included)."""
    start = time.perf_counter()
    scene = Scene3D(wire=Wire(length=LENGTH, bars=n, youngs_modulus=YOUNGS, diameter=DIAMETER),
                    base=Base3D((0.0, 0.0, 0.0), tuple(TANGENT), tuple(NORMAL)), tip_force=tuple(FORCE),
                    shear_modulus=SHEAR)
    sol = solve3d(scene)
    wall = time.perf_counter() - start
    return {"nodes": sol.nodes.copy(), "success": bool(sol.success), "iterations": sol.iterations, "wall_s": wall,
            "solve_s": sol.solve_time_s}


def pyelastica_time_step(n: int, stiffen: float) -> float:
    r, _, _ = section()
    return P.time_step(LENGTH / n, r, DENSITY, YOUNGS, SHEAR, stiffen)


def run_pyelastica(n: int, stiffen: float = 1.0) -> dict[str, Any]:
    """Build, damp and step PyElastica's rod until it settles (module docstring)."""
    start = time.perf_counter()
    r, _, _ = section()
    omega = first_mode()
    dt = pyelastica_time_step(n, stiffen)
    sim = P.simulator()
    rod = ea.CosseratRod.straight_rod(n, np.zeros(3), TANGENT.copy(), NORMAL.copy(), LENGTH, r, DENSITY,
                                      youngs_modulus=YOUNGS, shear_modulus=SHEAR)
    rod.shear_matrix[...] *= stiffen  # diag(α G A, α G A, E A) per element
    sim.append(rod)
    sim.constrain(rod).using(ea.OneEndFixedBC, constrained_position_idx=(0,), constrained_director_idx=(0,))
    sim.add_forcing_to(rod).using(ea.EndpointForces, np.zeros(3), FORCE.copy(), ramp_up_time=1e-12)
    sim.dampen(rod).using(ea.AnalyticalLinearDamper, uniform_damping_constant=DAMPING_OVER_OMEGA * omega,
                          time_step=dt)
    sim.finalize()
    setup = time.perf_counter() - start
    run = P.relax(sim, rod, dt, omega)
    wall = time.perf_counter() - start
    return {"nodes": rod.position_collection.T.copy(), "success": run.settled, "steps": run.steps, "wall_s": wall,
            "setup_s": setup, "dt_s": dt, "sim_time_s": run.time,
            "max_stretch": float(np.max(np.abs(rod.dilatation - 1.0)))}


def compare(quick: bool, repeats: int, stiffen_row: float | None) -> list[dict[str, Any]]:
    ref = elastica_reference()
    rows: list[dict[str, Any]] = []
    ns_pe = (25,) if quick else (25, 50, 100)
    ns_ours = (25,) if quick else (25, 50, 100, 200, 400)
    first_setup = None
    plan: list[tuple[int, float]] = [(n, 1.0) for n in ns_ours]
    if stiffen_row and not quick:
        plan.append((25, stiffen_row))
    for n, stiffen in plan:
        ref_nodes = ref.nodes(n)
        row: dict[str, Any] = {"case": "a: oblique tip force", "n": n, "stiffen": stiffen}
        ours, _ = median_run(run_ours, repeats, n)
        row.update({f"ours_{k}": v for k, v in errors(ours["nodes"], ref_nodes).items()})
        row.update(ours_success=ours["success"], ours_ms=1e3 * ours["wall_s"], ours_solve_ms=1e3 * ours["solve_s"],
                   ours_iterations=ours["iterations"])
        if n in ns_pe:
            rigid_nodes = elastica_reference(LENGTH / n / 2).nodes(n)
            pe, walls = median_run(run_pyelastica, repeats, n, stiffen)
            first_setup = pe["setup_s"] if first_setup is None else first_setup
            row.update({f"pe_{k}": v for k, v in errors(pe["nodes"], ref_nodes).items()})
            diff = np.linalg.norm(pe["nodes"] - ours["nodes"], axis=1)
            row.update(pe_success=pe["success"], pe_s=pe["wall_s"], pe_setup_s=pe["setup_s"], pe_steps=pe["steps"],
                       pe_dt_s=pe["dt_s"], pe_sim_time_s=pe["sim_time_s"], pe_max_stretch=pe["max_stretch"],
                       **{f"pe_rigid_{k}": v for k, v in errors(pe["nodes"], rigid_nodes).items()},
                       rigid_offset_tip_mm=float(np.linalg.norm(rigid_nodes[-1] - ref_nodes[-1])),
                       diff_max_mm=float(diff.max()), diff_tip_mm=float(diff[-1]),
                       time_ratio=pe["wall_s"] / ours["wall_s"], pe_walls=";".join(f"{w:.2f}" for w in walls))
        rows.append(row)
        print(T.cell(row["n"]), f"stiffen {stiffen:g}:",
              ", ".join(f"{k} {T.cell(v)}" for k, v in row.items() if k not in ("case", "n", "stiffen")), flush=True)
    return rows


def report(rows: list[dict[str, Any]], repeats: int) -> list[str]:
    omega = first_mode()
    r, area, inertia = section()
    lines = ["# Our 3-D rod beside PyElastica relaxed to its static state", "",
             *[f"- {x}" for x in E.environment(guidewire=False)],
             f"- pyelastica {E.version('pyelastica')}, numba {E.version('numba')}", "",
             f"Case (a): L = {LENGTH:g} mm, d = {DIAMETER} mm, E = {YOUNGS:g} MPa, G = E/(2(1+{POISSON})) = "
             f"{SHEAR:.0f} MPa, EI = {YOUNGS * inertia:.1f} N·mm², GJ = {2 * SHEAR * inertia:.1f} N·mm², clamped "
             f"along +x, dead tip force F = {tuple(FORCE.tolist())} N. Reference: the planar elastica in the plane of "
             "the tangent and F (solve_bvp, tol 1e-11), at the nodes s_i = i L/n. Errors are distances between "
             f"corresponding nodes (mm). Times: median of {repeats} (wall, BLAS on one thread, "
             "OPENBLAS_NUM_THREADS=1): ours = Scene3D + solve3d with its defaults; PyElastica = simulator "
             "construction + finalize + time stepping to the stopping rule.", "",
             f"PyElastica settings: units mm, N, s, t (ρ = {DENSITY:g} t/mm³ = 6.45e-3 g/mm³); EA = "
             f"{YOUNGS * area:.0f} N and (27/28) G A = {ALPHA_SHEAR * SHEAR * area:.0f} N times `stiffen`; "
             f"OneEndFixedBC (node 0, element 0); EndpointForces at once; AnalyticalLinearDamper, uniform damping "
             f"constant 2 ω₁ = {DAMPING_OVER_OMEGA * omega:.1f} 1/s (ω₁ = {omega:.1f} rad/s); PositionVerlet; "
             f"dt = {CFL} / √(1/dt_a² + 1/dt_s²), dt_a = dl √(ρ/(K E)), dt_s = r √(ρ/(K α G)) (K = stiffen); "
             f"stop when the largest node speed < "
             f"{VELOCITY_TOL_MM:g} mm · ω₁ = {VELOCITY_TOL_MM * omega:.4f} mm/s and the tip moved < {TIP_TOL_MM:g} "
             f"mm over the last 1/ω₁ = {1e3 / omega:.2f} ms (checked every {CHECK_STEPS} steps).", ""]
    header = ["case", "n", "stiffen", "ours tip err (mm)", "ours max err (mm)", "ours time (ms)", "ours iters",
              "PyE tip err (mm)", "PyE max err (mm)", "rigid-ends elastica tip offset (mm)",
              "PyE tip err vs rigid-ends elastica (mm)", "PyE time (s)",
              "PyE setup (s)", "PyE steps", "PyE dt (s)", "PyE max stretch", "shape diff max (mm)",
              "tip diff (mm)", "time ratio PyE/ours"]
    table = [[r["case"], r["n"], r["stiffen"] if "pe_s" in r else None, r["ours_tip_mm"], r["ours_max_mm"],
              r["ours_ms"], r["ours_iterations"], r.get("pe_tip_mm"), r.get("pe_max_mm"),
              r.get("rigid_offset_tip_mm"), r.get("pe_rigid_tip_mm"), r.get("pe_s"), r.get("pe_setup_s"),
              r.get("pe_steps"), r.get("pe_dt_s"), r.get("pe_max_stretch"), r.get("diff_max_mm"), r.get("diff_tip_mm"),
              r.get("time_ratio")] for r in rows]
    lines += T.markdown_table(header, table)
    unsettled = [r["n"] for r in rows if "pe_success" in r and not r["pe_success"]]
    failed = [r["n"] for r in rows if not r["ours_success"]]
    if unsettled or failed:
        lines += ["", f"Not settled (PyElastica) at n = {unsettled}; ours failed at n = {failed}."]
    paired = [r for r in rows if "pe_s" in r and r["stiffen"] == 1.0]
    if paired:
        ratios = ", ".join(f"{r['time_ratio']:.0f}× at n = {r['n']}" for r in paired)
        best = min(paired, key=lambda r: r["pe_tip_mm"])
        cheaper = [r for r in rows if r["stiffen"] == 1.0 and r["ours_tip_mm"] <= best["pe_tip_mm"]]
        line = (f"Conclusion: at equal n PyElastica takes {ratios} our time to equilibrium (BLAS on one thread), "
                "and its tip error is first order in dl (its rigid end pieces) where ours is second order")
        if cheaper:
            ours = min(cheaper, key=lambda r: r["ours_ms"])
            line += (f"; at equal accuracy the ratio is {1e3 * best['pe_s'] / ours['ours_ms']:.0f}× (PyElastica "
                     f"n = {best['n']}: tip error {best['pe_tip_mm']:.3g} mm in {best['pe_s']:.3g} s; ours n = "
                     f"{ours['n']}: {ours['ours_tip_mm']:.3g} mm in {ours['ours_ms']:.3g} ms)")
        lines += ["", line + ". (Our times vary up to 2× between runs on this shared 2-core machine: compare the "
                      "n = 25 rows.)"]
    return lines


def main() -> None:
    ap = A.parser(__doc__, quick_help="n = 25 only, one run of each code", repeats=3)
    ap.add_argument("--stiffen", type=float, default=10.0,
                    help="factor on PyElastica's shear/stretch stiffness for the extra n = 25 row of the full run "
                         "(0: no such row)")
    args = A.parse(ap)
    P.require("benchmarks/pyelastica.py")
    with E.one_thread():
        rows = compare(args.quick, args.repeats, args.stiffen or None)
    stem = T.output_stem(args.out, "pyelastica", args.quick)
    T.write_csv(rows, stem.with_suffix(".csv"))
    lines = report(rows, args.repeats)
    T.write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
