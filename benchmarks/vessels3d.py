"""3-D insertion and rotation steps: our per-step time against IPOPT on the same program, and the growth with n.

What is measured
----------------
Scenes (``guidewire/scenes/vessels3d/`` and the shipped shapes): a straight 0.89 mm wire and stEVE's J wire pushed
through the helix, the J then turned at the clamp, and a 0.36 mm wire through the out-of-plane S-bend, at
``--density`` bars per mm, in 1 mm steps (rotation in 15° steps) by :func:`guidewire.solve3d.insert.insert3d`, each
step warm-started by the track predictor (the previous shape, frames and multipliers); and stEVE's J wire in its type
I aortic arch (``aortic_arch_I.toml``, 2 bars per mm) pushed 20 → 120 mm in 2 mm steps (240 bars at the end:
stEVE's size) and turned to 90° in 15° steps. Per step: our time (``Solution3D.solve_time_s``: the program, every
round, the answer with its forces), iterations, success.

IPOPT (cyipopt, exact sparse Hessians of the energy and of every row, on fixed patterns) solves the same program of
each step from the same start point (our predictor's frames and nodes); its time is the ``minimize_ipopt`` call,
answers compared by energy. IPOPT gets no multiplier warm start (its warm-start options need tuned bound pushes).

Navigation: the committed steering schedules (``examples/steer_<branch>.txt``, stEVE's J wire pushed and turned into
each supra-aortic branch of the type I arch, 104-149 steps, up to 536 bars) replayed at the scene's 2 bars per mm and
in stEVE's own beam layout (``aortic_arch_I_steve_beams.toml``: 22 bars on the tip, ~2 mm bars on the shaft, by
``Section.refinement``); the whole replay's wall time, where the tip ends, and the two layouts' tip gap. The arch's
push-and-turn case is run in both layouts too.

Bifurcation: stEVE's J wire solved cold from a start along the centrelines through the brachiocephalic trunk into
the right common carotid and subclavian arteries (tip 10 / 20 / 30 mm in): iterations, time, energy and the contacts'
force along the wire against their total (the creases at the trunk's end meet three walls).

Growth: the straight wire at 60 mm in the helix, carried to 100 … 3200 bars by the predictor (bars resampled along
arc length), each size from the converged one before it (the first from a 2 bars per mm insertion), and converged;
then the median of three 0.5 mm steps at that density. (Carried from the coarse insertion in one jump, 1 600 bars
started from 120 straight pieces of 13 bars each and did not converge within 400 s.)

Goals (3-D issue): ≤ 5 ms median per step at stEVE's size (~240 bars), ≥ 3× faster than warm-started IPOPT, a
navigation into a branch in ≤ 2 s, growth ≤ n^1.2 up to 3200 bars.

Usage: ``python benchmarks/vessels3d.py [--quick] [--out DIR]``; writes ``vessels3d.{md,csv}`` (``_quick`` with
``--quick``). BLAS is pinned to one thread.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import _environment as env  # noqa: I001  (first: pins BLAS threads before numpy loads)
import numpy as np
import scipy.sparse as sp
from _arguments import parse, parser
from _tables import markdown_table, output_stem, write_csv, write_markdown

from guidewire import Section, Wire
from guidewire.solve3d import Scene3D
from guidewire.solve3d.file import load_scene
from guidewire.solve3d.insert import advance, insert3d, scene_at, tracked_frames
from guidewire.solve3d.program import Program, bar_layout
from guidewire.solve3d.solve import solve3d
from guidewire.vessel3d.shapes import helix

SCENES = Path(__file__).resolve().parents[1] / "guidewire" / "scenes" / "vessels3d"
STEVE_BEAMS = SCENES / "aortic_arch_I_steve_beams.toml"
"""The type I arch with stEVE's J wire in its own beam layout (22 tip bars, ~2 mm shaft bars)."""
STEVE_J = (Section.arc(12.1, 0.4 * math.pi, youngs_modulus=17000.0, diameter=0.7),)
GROWTH_BARS = (100, 200, 400, 800, 1600, 3200)
QUICK_GROWTH = (60, 120)


def cases(quick: bool, density: float) -> list[tuple[str, Scene3D, np.ndarray, np.ndarray]]:
    """(name, scene at its first length, lengths, rotations) of every insertion."""
    top = 16.0 if quick else 100.0
    straight = Wire(length=10.0, bars=round(10 * density), youngs_modulus=80000.0, diameter=0.89)
    j_wire = Wire(length=10.0, bars=round(10 * density), youngs_modulus=80000.0, diameter=0.89, sections=STEVE_J)
    push = np.arange(10.0, top + 0.5, 1.0)
    turns = np.radians(np.arange(15.0, 361.0 if not quick else 31.0, 15.0))
    s_bend = load_scene(SCENES / "s_bend_3d.toml")
    s_wire = Wire(length=10.0, bars=round(10 * density), youngs_modulus=60000.0, diameter=0.36)
    s_push = np.arange(10.0, (16.0 if quick else 80.0) + 0.5, 1.0)
    arch = load_scene(SCENES / "aortic_arch_I.toml")
    a_push = np.arange(20.0, (30.0 if quick else 120.0) + 0.5, 2.0)
    a_turns = np.radians(np.arange(15.0, (30.0 if quick else 90.0) + 1.0, 15.0))
    return [
        ("helix, straight wire", Scene3D.in_vessel(straight, helix()), push, np.zeros(push.size)),
        ("helix, J wire, push then turn", Scene3D.in_vessel(j_wire, helix()),
         np.concatenate((push, np.full(turns.size, push[-1]))), np.concatenate((np.zeros(push.size), turns))),
        ("S-bend 3D", Scene3D.in_vessel(s_wire, s_bend.vessel), s_push, np.zeros(s_push.size)),
        ("aortic arch I, stEVE's J wire, push then turn", arch,
         np.concatenate((a_push, np.full(a_turns.size, a_push[-1]))), np.concatenate((np.zeros(a_push.size), a_turns))),
        ("aortic arch I, stEVE's J wire and beam layout, push then turn", load_scene(STEVE_BEAMS),
         np.concatenate((a_push, np.full(a_turns.size, a_push[-1]))), np.concatenate((np.zeros(a_push.size), a_turns))),
    ]


def _structure(matrix: Any) -> tuple[np.ndarray, np.ndarray]:
    """Rows and columns of a sparse matrix's stored entries (explicit zeros included: the program stores whole
    3 × 3 blocks, some of whose entries vanish at particular points)."""
    coo = sp.coo_matrix(matrix)
    return coo.row, coo.col


def run_ipopt_program(program: Program) -> dict[str, Any]:
    """IPOPT (cyipopt's low-level ``Problem``) on ``program`` from its start, with the exact sparse Jacobians and
    Lagrangian Hessian on the program's own block patterns."""
    import cyipopt

    z0 = program.start()
    rows = program.constraints()
    m = [int(np.size(r["fun"](z0))) for r in rows]
    jac0 = sp.vstack([r["jac"](z0) for r in rows], format="coo")
    j_rows, j_cols = jac0.row, jac0.col
    union = sp.csc_matrix(program.hess(z0), copy=True)
    for r, size in zip(rows, m, strict=True):
        union = union + abs(r["hess"](z0, np.ones(size)))
    if program.has_creases:
        # (the creases' rows follow the wire: their entries move from bar to bar, so IPOPT is given every place they
        # can take — each row over all node columns, the Hessian over every pair of neighbouring nodes)
        node_cols = (program.width * np.arange(program.n)[:, None] + 3 + np.arange(3)).ravel()
        first = sum(m[:-1])
        keep = j_rows < first
        crease = np.arange(first, first + m[-1])
        j_rows = np.concatenate((j_rows[keep], np.repeat(crease, node_cols.size)))
        j_cols = np.concatenate((j_cols[keep], np.tile(node_cols, crease.size)))
        blocks = node_cols.reshape(-1, 3)
        pairs = [(a, b) for k in range(program.n) for a in blocks[k] for b in blocks[max(k - 1, 0):k + 2].ravel()]
        reach = sp.coo_matrix((np.ones(len(pairs)), tuple(np.array(pairs).T)), shape=union.shape)
        union = union + reach
    h_all = sp.coo_matrix(union)
    lower = h_all.row >= h_all.col
    h_rows, h_cols = h_all.row[lower], h_all.col[lower]

    def pick(matrix: Any, r_idx: np.ndarray, c_idx: np.ndarray) -> np.ndarray:
        return np.asarray(sp.csr_matrix(matrix)[r_idx, c_idx]).ravel()

    class Adapter:
        def objective(self, z: np.ndarray) -> float:
            return program.fun(z)

        def gradient(self, z: np.ndarray) -> np.ndarray:
            return program.jac(z)

        def constraints(self, z: np.ndarray) -> np.ndarray:
            return np.concatenate([np.atleast_1d(r["fun"](z)) for r in rows])

        def jacobianstructure(self) -> tuple[np.ndarray, np.ndarray]:
            return j_rows, j_cols

        def jacobian(self, z: np.ndarray) -> np.ndarray:
            return pick(sp.vstack([r["jac"](z) for r in rows]), j_rows, j_cols)

        def hessianstructure(self) -> tuple[np.ndarray, np.ndarray]:
            return h_rows, h_cols

        def hessian(self, z: np.ndarray, lam: np.ndarray, obj: float) -> np.ndarray:
            H = obj * program.hess(z)
            start = 0
            for r, size in zip(rows, m, strict=True):
                H = H + r["hess"](z, lam[start:start + size])
                start += size
            return pick(H, h_rows, h_cols)

    lower_c = np.concatenate([np.zeros(size) for size in m])
    upper_c = np.concatenate([np.zeros(size) if r["type"] == "eq" else np.full(size, 1e20)
                              for r, size in zip(rows, m, strict=True)])
    nlp = cyipopt.Problem(n=z0.size, m=lower_c.size, problem_obj=Adapter(), lb=np.full(z0.size, -1e20),
                          ub=np.full(z0.size, 1e20), cl=lower_c, cu=upper_c)
    for key, value in {"print_level": 0, "sb": "yes", "tol": 1e-8, "max_iter": 3000}.items():
        nlp.add_option(key, value)
    start = time.perf_counter()
    z, info = nlp.solve(z0)
    return {"time": time.perf_counter() - start, "f": float(info["obj_val"]), "success": info["status"] in (0, 1)}


def ipopt_step(previous: Any, scene: Scene3D, length: float, turn: float, density: float) -> dict[str, Any]:
    """IPOPT on the step's program from our predictor's start."""
    target = scene_at(scene, length, turn, density)
    return run_ipopt_program(Program.build(target, tracked_frames(previous, target)))


def insertion(name: str, scene: Scene3D, lengths: np.ndarray, turns: np.ndarray, ipopt: bool) -> list[dict[str, Any]]:
    density = scene.wire.bar_density  # (as insert3d keeps it)
    wall = time.perf_counter()
    out = insert3d(scene, lengths, turns)
    total = time.perf_counter() - wall
    rows = []
    for k, sol in enumerate(out.steps):
        row: dict[str, Any] = {"case": name, "step": k, "inserted_mm": float(np.sum(sol.lengths)),
                               "rotation_deg": math.degrees(sol.base_rotation), "bars": sol.n_bars,
                               "success": sol.success, "iterations": sol.iterations,
                               "substeps": sol.extras.get("substeps", 1), "ours_ms": 1e3 * sol.solve_time_s,
                               "energy": sol.energy, "ipopt_ms": math.nan, "ipopt_energy": math.nan,
                               "ipopt_ok": False, "total_s": total}
        if ipopt and k > 0 and sol.success and sol.extras.get("substeps", 1) == 1:
            peer = ipopt_step(out.steps[k - 1], scene, lengths[k], turns[k], density)
            row.update(ipopt_ms=1e3 * peer["time"], ipopt_energy=peer["f"], ipopt_ok=peer["success"])
        rows.append(row)
    if out.error:
        print(f"  {name}: {out.error}")
    return rows


def growth(sizes: tuple[int, ...]) -> list[dict[str, Any]]:
    """Per-step time of the straight wire in the helix at 60 mm, by bar count (each size carried from the last)."""
    wire = Wire(length=10.0, bars=20, youngs_modulus=80000.0, diameter=0.89)
    scene = Scene3D.in_vessel(wire, helix())
    sol = insert3d(scene, np.arange(10.0, 60.5, 2.0)).steps[-1]
    rows = []
    for n in sizes:
        density = n / 60.0
        start = advance(scene, sol, 60.0, 0.0, density, {})  # (resampled to n bars, converged)
        sol, times, its = start, [], []
        for length in (60.5, 61.0, 61.5):
            sol = advance(scene, sol, length, 0.0, density, {})
            times.append(sol.solve_time_s)
            its.append(sol.iterations)
        rows.append({"bars": n, "ours_ms": 1e3 * float(np.median(times)), "iterations": float(np.median(its)),
                     "success": bool(sol.success)})
        print(f"  growth n = {n}: {rows[-1]['ours_ms']:.1f} ms, {rows[-1]['iterations']:.0f} iterations")
        sol = start
    return rows


EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
NAVIGATION = ("left_subclavian", "left_common_carotid", "brachiocephalic")


def navigation(quick: bool) -> list[dict[str, Any]]:
    """The committed steering schedules (``examples/steer_<branch>.txt``: stEVE's J wire into each supra-aortic
    branch of the type I arch by pushing and turning) replayed by :func:`insert3d` with the scene's 2 bars per mm and
    with stEVE's beam layout (:data:`STEVE_BEAMS`): steps, the whole replay's wall time, per-step median and slowest,
    iterations (every solve of a step), bars at the end, the tube the tip ends in and how far along it, and the
    distance between the two layouts' tips after each step."""
    scene = load_scene(SCENES / "aortic_arch_I.toml")
    vessel = scene.vessel
    vessel.creases  # noqa: B018  (found once, before the clock)
    lines = vessel.centrelines(0.5)
    out = []
    for name in NAVIGATION[:1] if quick else NAVIGATION:
        table = np.loadtxt(EXAMPLES / f"steer_{name}.txt", ndmin=2)
        if quick:
            table = table[:20]
        tips = {}
        for layout, chosen in (("2 bars per mm", scene), ("stEVE's beams", replace(load_scene(STEVE_BEAMS),
                                                                                   vessel=vessel))):
            result = insert3d(chosen, table[:, 0], np.radians(table[:, 1]))
            times = np.array([s.solve_time_s for s in result.steps])
            tip = result.steps[-1].nodes[-1]
            tube = int(vessel.tube_of(tip[None])[0])
            line = lines[tube]
            k = int(np.argmin(np.linalg.norm(line - tip, axis=1)))
            tips[layout] = np.array([s.nodes[-1] for s in result.steps])
            gap = (np.linalg.norm(tips[layout] - tips["2 bars per mm"], axis=1)
                   if len(tips[layout]) == len(tips["2 bars per mm"]) else np.full(1, math.nan))
            out.append({"branch": name, "layout": layout, "steps": len(result.steps),
                        "solved": sum(s.success for s in result.steps), "total_s": result.seconds,
                        "median_ms": 1e3 * float(np.median(times)), "max_ms": 1e3 * float(times.max()),
                        "iterations": sum(s.extras.get("step_iterations", s.iterations) for s in result.steps),
                        "bars": result.steps[-1].n_bars, "tip_in": vessel.tube_names[tube],
                        "tip_along_mm": float(np.sum(np.linalg.norm(np.diff(line[:k + 1], axis=0), axis=1))),
                        "tip_gap_median_mm": float(np.median(gap)), "tip_gap_max_mm": float(np.max(gap))})
            print(f"  navigation {name}, {layout}: {out[-1]['total_s']:.2f} s, {out[-1]['steps']} steps")
    return out


BIFURCATION = (("right_common_carotid", (10.0, 20.0, 30.0)), ("right_subclavian", (10.0, 20.0, 30.0)))
"""The branches at the brachiocephalic trunk's end, and how deep (mm) the tip is placed in each."""
QUICK_BIFURCATION = (("right_subclavian", (30.0,)),)


def bifurcation(quick: bool) -> list[dict[str, Any]]:
    """stEVE's J wire solved cold (:func:`solve3d`) from a start along the centrelines through the brachiocephalic
    trunk into each branch at its end: iterations, time, energy, and the contacts' force along the wire against
    their total (frictionless: ~0 where the wire slides over the rims)."""
    scene = load_scene(SCENES / "aortic_arch_I.toml")
    vessel = scene.vessel
    vessel.creases  # noqa: B018  (found once, before the clock)
    out = []
    for child, depths in QUICK_BIFURCATION if quick else BIFURCATION:
        names = vessel.tube_names
        lines = vessel.centrelines(0.1)
        main, trunk = lines[0], lines[names.index("brachiocephalic")]
        k = int(np.argmin(np.linalg.norm(main - trunk[0], axis=1)))
        to_kid = float(np.sum(np.linalg.norm(np.diff(np.vstack((main[:k], trunk)), axis=0), axis=1)))
        for depth in depths:
            target = scene_at(scene, to_kid + depth, 0.0, scene.wire.bar_density)
            lengths, _ = bar_layout(target)
            sol = solve3d(target, initial_nodes=vessel.route(np.concatenate(([0.0], np.cumsum(lengths))), child))
            total = sum(f.magnitude for f in sol.forces)
            out.append({"branch": child, "depth_mm": depth, "bars": sol.n_bars, "success": bool(sol.success),
                        "iterations": sol.iterations, "ours_s": sol.solve_time_s, "energy": sol.energy,
                        "tip_in": names[int(vessel.tube_of(sol.nodes[-1:])[0])],
                        "lengthwise_N": sol.tangential_contact_force(), "contact_N": total})
            print(f"  bifurcation {child} {depth:g} mm: {sol.iterations} iterations, {sol.solve_time_s:.2f} s")
    return out


def main() -> None:
    ap = parser(__doc__, quick_help="short insertions, growth to 200 bars", repeats=1)
    ap.add_argument("--density", type=float, default=2.0, help="bars per mm (default 2: 240 bars at 120 mm)")
    args = parse(ap)
    ipopt = env.ipopt_available()
    rows: list[dict[str, Any]] = []
    for name, scene, lengths, turns in cases(args.quick, args.density):
        print(f"{name}: {lengths.size} steps")
        rows += insertion(name, scene, lengths, turns, ipopt)
    grow = growth(QUICK_GROWTH if args.quick else GROWTH_BARS)
    navigate = navigation(args.quick)
    fork = bifurcation(args.quick)
    stem = output_stem(args.out, "vessels3d", args.quick)
    write_csv(rows, stem.with_suffix(".csv"))
    lines = [f"# 3-D insertion and rotation steps{' (quick)' if args.quick else ''}", "",
             *(f"- {line}" for line in env.environment(guidewire=False)), "",
             f"{args.density:g} bars per mm, 1 mm push steps, 15° turns; medians over the steps after the first "
             "(the first is a cold solve).", ""]
    table = []
    for name in dict.fromkeys(r["case"] for r in rows):
        mine = [r for r in rows if r["case"] == name and r["step"] > 0]
        ok = [r for r in mine if r["success"]]
        pairs = [r for r in ok if r["ipopt_ok"] and np.isfinite(r["ipopt_ms"])]
        ours = float(np.median([r["ours_ms"] for r in ok])) if ok else math.nan
        peer = float(np.median([r["ipopt_ms"] for r in pairs])) if pairs else math.nan
        ratio = float(np.median([r["ipopt_ms"] / r["ours_ms"] for r in pairs])) if pairs else math.nan
        gap = max((abs(r["energy"] - r["ipopt_energy"]) / max(1.0, abs(r["ipopt_energy"])) for r in pairs),
                  default=math.nan)
        table.append([name, f"{len(ok)}/{len(mine)}", max(r["bars"] for r in mine), ours,
                      max(r["ours_ms"] for r in ok) if ok else math.nan,
                      float(np.median([r["iterations"] for r in ok])) if ok else math.nan, peer, ratio,
                      f"{sum(r['ipopt_ok'] for r in mine)}/{len(pairs) + sum(not r['ipopt_ok'] for r in mine)}",
                      gap, mine[0]["total_s"]])
    lines += markdown_table(["case", "steps solved", "bars (last)", "ours median ms", "ours max ms",
                             "median iterations", "IPOPT median ms", "IPOPT/ours (median of ratios)",
                             "IPOPT solved", "max energy gap (rel.)", "whole insertion s"], table)
    lines += ["", "## Navigation (the committed steering schedules replayed: `examples/steer_<branch>.txt`)", "",
              "stEVE's J wire in the type I arch pushed and turned into each supra-aortic branch (the schedules "
              "`examples/steer_arch.py` found at 2 bars per mm), at the scene's 2 bars per mm and with stEVE's beam "
              "layout (`aortic_arch_I_steve_beams.toml`: 22 bars on the 15.2 mm tip, 2.03 mm bars on the shaft, "
              "`Section.refinement` 2.886); the whole replay's wall time, where the tip ends (the tube, and how far "
              "along its centreline), and the distance between the two layouts' tips after each step.", ""]
    lines += markdown_table(["branch", "layout", "steps solved", "bars (last)", "whole replay s",
                             "median ms per step", "slowest step ms", "iterations", "tip ends in",
                             "tip along mm", "tip gap median mm", "tip gap max mm"],
                            [[r["branch"], r["layout"], f"{r['solved']}/{r['steps']}", r["bars"], r["total_s"],
                              r["median_ms"], r["max_ms"], r["iterations"], r["tip_in"], r["tip_along_mm"],
                              r["tip_gap_median_mm"], r["tip_gap_max_mm"]] for r in navigate])
    lines += ["", "## Through the trunk's bifurcation (cold solves)", "",
              "stEVE's J wire solved cold from a start along the centrelines through the brachiocephalic trunk into "
              "each branch at its end (2 bars per mm): the creases there meet three walls at their corners "
              "(`guidewire/vessel3d/crease.py`); the contacts' force along the wire against their total.", ""]
    lines += markdown_table(["branch", "tip depth mm", "bars", "solved", "tip in", "iterations", "ours s",
                             "energy N·mm", "lengthwise N", "contact N"],
                            [[r["branch"], r["depth_mm"], r["bars"], r["success"], r["tip_in"], r["iterations"],
                              r["ours_s"], r["energy"], r["lengthwise_N"], r["contact_N"]] for r in fork])
    lines += ["", "## Growth (straight wire, helix, 60 mm; median of three 0.5 mm steps)", ""]
    lines += markdown_table(["bars", "ours ms per step", "iterations", "solved"],
                            [[g["bars"], g["ours_ms"], g["iterations"], g["success"]] for g in grow])
    if len(grow) >= 2:
        slope = np.polyfit(np.log([g["bars"] for g in grow]), np.log([g["ours_ms"] for g in grow]), 1)[0]
        lines += ["", f"Fitted growth: time ∝ n^{slope:.2f} over {grow[0]['bars']}…{grow[-1]['bars']} bars."]
    write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
