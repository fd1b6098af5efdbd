"""Peers on the paper's scenes: this solver (every QP backend) against scipy SLSQP, trust-constr and IPOPT.

What is measured
----------------
Every feasible paper scene (Tables 1 and 2 at all five angles, Fig. 6a, Fig. 6b, Table 4; Table 5 as printed is
infeasible and left out) in its default (second-order) scheme at n ∈ {25, 50, 100, 200, 400, 800, 1600} bars, solved
by ``ours`` (:func:`guidewire.solve` with its defaults), ``ours[bfgs]`` (the paper's damped BFGS), ``ours[<backend>]``
for every installed qpsolvers backend, and the peers of :mod:`_peers`: scipy SLSQP, scipy trust-constr and IPOPT
(cyipopt; left out when not installed), and on the contact scenes the "structure limit" (:mod:`_structure_limit`:
plain Newton-KKT steps by a banded solve, the cost floor the structure allows). Every solver starts
from the formulation's ``x0`` (the elastica-like start) with the same analytic derivatives; trust-constr and IPOPT get
the exact Hessians when the formulation offers them. One more row group starts everyone from the straight wire (all
angles 0) at one n, to show who fails from there.

Per solve: time (median of ``--repeats``; one run once a solve takes > 1 s), iterations, function evaluations,
energy, whether it is the lowest-energy branch (against the lowest feasible energy any solver reached on the same
problem, and the continuum reference energy), largest constraint violation (all rows of the full formulation, also
for ours, whose walls use a working set), mean and max node error against the continuum reference, the solver's
own success flag and message, and the time ratio to ``ours`` in the same run. A solver is *solved* on a problem when
it reports success at a feasible point (violation ≤ 1e-6) on the lowest branch (energy within 1e-6 relative).

Time limits: a solve longer than ``--limit`` s (default 60) is stopped (SIGALRM) and that solver is not run at larger
n on that scene ("stopped: > 60 s at n = …"). To keep the full run near 20 minutes, a solver whose last two times on
a scene predict more than the limit at the next n (its own measured growth per doubling, at least ×2, once it takes
> limit/20) is not started there ("skipped: predicted …"), and a solver other than ``ours`` that has spent ``--budget``
s (default 60) of solve time on the wall scenes, or on the contact scenes, is not started again on them (n is the
outer loop, so this cuts the largest n first); every skip is written in the tables (:class:`_timing.Budget`).

Usage: ``python benchmarks/peers.py [--quick] [--repeats K] [--out DIR] [--limit S] [--bars 25,100] [--solvers a,b]``
Writes ``peers.{md,csv,png}`` (``peers_quick.*`` with ``--quick``) in ``--out`` (default ``benchmarks/results``).
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import _arguments as A
import _environment as E  # first: pins BLAS to one thread before numpy loads
import _guidewire as G
import _tables as T
import _timing
import numpy as np
from _headline import growth, headline
from _peers import PEER_MAX_ITER, STRUCTURE_LIMIT
from _structure_limit import applicable

import guidewire

BARS = (25, 50, 100, 200, 400, 800, 1600, 3200)
QUICK_BARS = (25, 100)
#: The variants of ours (other QP backends, BFGS) run up to this n: above it the dense backends would face a dense
#: 9600-variable QP, which no time limit can interrupt (the limit is checked between Python calls; measured: quadprog
#: at n = 3200 had not finished one QP after 10 minutes).
VARIANT_MAX_BARS = 1600
QUICK_SCENES = ("table1_pi_4", "fig6b", "table4")
#: Bars of the straight-start group (full run / quick).
STRAIGHT_BARS, QUICK_STRAIGHT_BARS = 100, 25
#: Quasi-static sequence: steps (full / quick), bars, contact displacement per step.
SEQUENCE_STEPS, QUICK_SEQUENCE_STEPS, SEQUENCE_BARS, SEQUENCE_STEP_MM = 40, 5, 100, 0.5


def scenes(quick: bool, pattern: str) -> list[guidewire.Scene]:
    """The feasible paper scenes (a few with ``quick``), filtered by comma-separated name substrings."""
    out = [s for s in guidewire.paper_scenes().values() if G.feasible(s)]
    if quick:
        out = [s for s in out if s.name in QUICK_SCENES]
    names = A.names(pattern)
    return [s for s in out if not names or any(p in s.name for p in names)]


def is_wall_scene(scene: guidewire.Scene) -> bool:
    return bool(scene.walls)


def run_case(case: G.Case, solvers: dict[str, Any], budget: _timing.Budget | None, repeats: int,
             limit: float) -> dict[str, dict[str, Any]]:
    """Every solver on one case: the raw results by solver name."""
    out: dict[str, dict[str, Any]] = {}
    for name, run in solvers.items():
        group = "wall scenes" if is_wall_scene(case.scene) else "contact scenes"
        if name == STRUCTURE_LIMIT and not applicable(case.problem):
            out[name] = _timing.skipped("not applicable: inequality rows (walls)")
        elif name.startswith("ours[") and case.n > VARIANT_MAX_BARS:
            out[name] = _timing.skipped(f"skipped: the variants of ours are measured up to n = {VARIANT_MAX_BARS}")
        elif budget is None:
            out[name] = _timing.measure(run, case, repeats, limit)
        else:
            out[name] = budget.measure(name, case.scene.name, case.n, run, case, repeats, group)
    return out


def rows_for(group: str, case: G.Case, results: dict[str, dict[str, Any]], ref: Any, ref_note: str,
             best: float) -> list[dict[str, Any]]:
    """Table rows of one case (``best``: lowest feasible energy of this scene and n over both starts)."""
    ours_time = results.get("ours", {}).get("time", math.nan)
    rows = []
    for name, res in results.items():
        ev = G.evaluate(case, res.get("x"), ref)
        label = G.branch(ev["energy"], ev["max_violation"], best)
        solved = bool(res["success"]) and label == "lowest"
        ref_energy = float(ref.energy) if ref is not None else math.nan
        rows.append({
            "group": group, "scene": case.scene.name, "walls": is_wall_scene(case.scene), "n": case.n,
            "solver": name, "outcome": res["outcome"], "success": bool(res["success"]), "solved": solved,
            "branch": label, "energy": ev["energy"], "best_energy": best, "reference_energy": ref_energy,
            "energy_vs_reference": (ev["energy"] - ref_energy) / ref_energy if ref is not None else math.nan,
            "max_violation": ev["max_violation"], "mean_error_mm": ev["mean_error_mm"],
            "max_error_mm": ev["max_error_mm"], "nit": res["nit"], "nfev": res["nfev"], "time_s": res["time"],
            "repeats": res["repeats"],
            "ratio_to_ours": res["time"] / ours_time if res["outcome"] == "ran" else math.nan,
            "message": res["message"] if not res["success"] or res["outcome"] != "ran" else "",
            "reference_note": ref_note,
        })
    return rows


def sequence_scenes(steps: int) -> list[guidewire.Scene]:
    """Table 1 (θ_B = π/4) with contact B moving 0.5 mm per step towards the base along x (the wire is pushed in)."""
    scene = guidewire.paper_scenes()["table1_pi_4"]
    (b,) = scene.contacts
    return [replace(scene, contacts=(replace(b, point=(b.point[0] - SEQUENCE_STEP_MM * k, b.point[1])),),
                    name=f"table1_pi_4 B.x - {SEQUENCE_STEP_MM * k:g}") for k in range(steps + 1)]


def run_sequence(steps: int, bars: int, repeats: int, limit: float,
                 peers: dict[str, Any]) -> list[dict[str, Any]]:
    """Quasi-static advancement: per-step cost of a warm-started sequence, ours and the peers.

    ``ours (solve_sequence)``: :func:`guidewire.solve_sequence` (previous shape and multipliers), when it exists;
    ``ours (warm x)``: :func:`guidewire.solve` from the previous angles; ``ours (cold)``: every step from the default
    start; each peer from the previous answer's angles. The first step (cold for all) is left out of the statistics.
    Energies are compared with ``ours (cold)`` step by step.
    """
    scenes = sequence_scenes(steps)
    cold: list[dict[str, Any]] = []
    for scene in scenes:
        res = _timing.measure(G.run_ours, G.make_case(scene, bars=bars), repeats, limit)
        cold.append(res)
    reference = [float(G.make_case(sc, bars=bars).problem.fun(r["x"])) if r.get("x") is not None else math.nan
                 for sc, r in zip(scenes, cold, strict=True)]
    traces: dict[str, list[dict[str, Any]]] = {"ours (cold)": cold}
    if hasattr(guidewire, "solve_sequence"):
        runs = []
        try:
            for _ in range(repeats):
                with _timing.time_limit(limit * len(scenes)):
                    runs.append(guidewire.solve_sequence(scenes, bars=bars))
        except (Exception, _timing.SolveTimeout) as exc:  # recorded as failed steps
            print(f"solve_sequence raised {type(exc).__name__}: {exc}")
        if runs:
            last = runs[-1]
            traces["ours (solve_sequence)"] = [
                {"x": last[k].bar_angles, "success": last[k].success, "nit": last[k].iterations,
                 "time": float(np.median([run[k].solve_time_s for run in runs])), "outcome": "ran"}
                for k in range(len(scenes))]
    for name, run in {"ours (warm x)": G.run_ours, **peers}.items():
        trace, x_prev = [], None
        for scene in scenes:
            case = (G.make_case(scene, bars=bars) if x_prev is None
                    else G.make_case(scene, bars=bars, start="previous", initial_angles=x_prev))
            res = _timing.measure(run, case, repeats, limit)
            trace.append(res)
            if res.get("x") is not None and np.all(np.isfinite(res["x"])):
                x_prev = np.asarray(res["x"], dtype=float)
        traces[name] = trace
    rows = []
    for name, trace in traces.items():
        steps_ = trace[1:]
        times = np.array([r["time"] for r in steps_], dtype=float)
        gaps = []
        for k, r in enumerate(steps_, start=1):
            if r.get("x") is None:
                gaps.append(math.inf)
                continue
            ev = G.evaluate(G.make_case(scenes[k], bars=bars), r["x"], None)
            ok = ev["max_violation"] <= G.FEASIBILITY_TOL
            gaps.append(abs(ev["energy"] - reference[k]) / reference[k] if ok else math.inf)
        rows.append({"group": "sequence", "solver": name, "n": bars, "steps": len(steps_),
                     "median_step_ms": 1e3 * float(np.nanmedian(times)), "max_step_ms": 1e3 * float(np.nanmax(times)),
                     "mean_iterations": float(np.mean([r["nit"] for r in steps_])),
                     "failures": int(sum(not r["success"] for r in steps_)),
                     "off_cold_energy": int(sum(g > G.SAME_ENERGY_RTOL for g in gaps)),
                     "max_energy_gap": float(np.max(gaps)) if gaps else math.nan})
    return rows


def best_energy(results: list[dict[str, dict[str, Any]]], case: G.Case) -> float:
    """Lowest energy of any feasible answer among ``results`` (nan if none)."""
    energies = []
    for group in results:
        for res in group.values():
            ev = G.evaluate(case, res.get("x"), None)
            if np.isfinite(ev["energy"]) and ev["max_violation"] <= G.FEASIBILITY_TOL:
                energies.append(ev["energy"])
    return min(energies, default=math.nan)


def main() -> None:
    ap = A.parser(__doc__, quick_help="n in {25, 100}, three scenes, one repeat (< 1 minute)", repeats=3,
                  limit=60.0, budget=60.0, solvers=True,
                  budget_help="solve time (s) per peer on the wall scenes and again on the contact scenes")
    ap.add_argument("--bars", type=str, default="", help="comma-separated n values (default: the full grid)")
    ap.add_argument("--scenes", type=str, default="", help="comma-separated substrings of scene names")
    a = A.parse(ap)
    bars = tuple(int(b) for b in A.names(a.bars)) or (QUICK_BARS if a.quick else BARS)
    repeats, limit = a.repeats, a.limit
    straight_bars = QUICK_STRAIGHT_BARS if a.quick else STRAIGHT_BARS
    scene_list = scenes(a.quick, a.scenes)
    solvers = {**G.ours_variants(), **G.peer_variants(("SLSQP", "trust-constr", "IPOPT", STRUCTURE_LIMIT))}
    wanted = A.names(a.solvers)
    if wanted:
        solvers = {k: v for k, v in solvers.items() if k == "ours" or any(w in k for w in wanted)}
    env = E.environment()
    settings = (f"{len(scene_list)} scenes × n ∈ {list(bars)} (+ straight start at n = {straight_bars}); "
                f"{len(solvers)} solvers: {', '.join(solvers)}; {_timing.repeats_note(repeats)}; "
                f"time limit {limit:g} s per solve, {a.budget:g} s of solves per peer "
                "on the wall scenes and again on the contact scenes")
    print("\n".join(env + [settings]))
    hessian_note = G.peer_hessian_note(G.make_case(scene_list[0], bars=bars[0]))

    rows: list[dict[str, Any]] = []
    budget = _timing.Budget(limit, a.budget)
    start = time.perf_counter()
    with E.one_thread():
        G.warm_up(solvers, limit)
        jobs = [(scene, n) for n in bars for scene in scene_list]
        straight: dict[tuple[str, int], tuple[G.Case, dict[str, Any]]] = {}
        for scene, n in E.progress(jobs, desc="scene × n"):
            ref, note = G.reference(scene)
            case = G.make_case(scene, bars=n)
            results = run_case(case, solvers, budget, repeats, limit)
            group_results = [results]
            if n == straight_bars:
                s_case = G.make_case(scene, bars=n, start="straight")
                s_results = run_case(s_case, solvers, None, repeats, limit)
                straight[(scene.name, n)] = (s_case, s_results)
                group_results.append(s_results)
            best = best_energy(group_results, case)
            rows += rows_for("elastica start", case, results, ref, note, best)
            if n == straight_bars:
                s_case, s_results = straight[(scene.name, n)]
                rows += rows_for("straight start", s_case, s_results, ref, note, best)
        peers = {k: v for k, v in solvers.items() if not k.startswith("ours")}
        rows += run_sequence(QUICK_SEQUENCE_STEPS if a.quick else SEQUENCE_STEPS, SEQUENCE_BARS, repeats, limit, peers)
    print(f"total {time.perf_counter() - start:.0f} s")
    write(rows, list(solvers), bars, a.out, env, settings, hessian_note, quick=a.quick)


# --------------------------------------------------------------------------------------------------------------------
# Output
# --------------------------------------------------------------------------------------------------------------------
def _summary(rows: list[dict[str, Any]], solvers: list[str], bars: tuple[int, ...]) -> list[dict[str, Any]]:
    out = []
    for name in solvers:
        entry: dict[str, Any] = {"solver": name, "solved": 0, "problems": 0}
        for n in bars:
            rs = [r for r in rows if r["solver"] == name and r["n"] == n and r["group"] == "elastica start"]
            ok = [r for r in rs if r["solved"]]
            entry["solved"] += len(ok)
            entry["problems"] += len(rs)
            entry[n] = {"solved": len(ok), "of": len(rs), "sgm": _timing.sgm([r["time_s"] for r in ok]),
                        "ratio": _timing.sgm([r["ratio_to_ours"] for r in ok if np.isfinite(r["ratio_to_ours"])], 0.0)}
        out.append(entry)
    key_n = 100 if 100 in bars else bars[0]
    out.sort(key=lambda e: (-e["solved"], np.nan_to_num(e[key_n]["sgm"], nan=np.inf)))
    return out


def _detail_cell(r: dict[str, Any]) -> str:
    if r["outcome"] in ("skipped", "timeout"):
        return r["message"].split(" at n")[0].replace("stopped: ", "stopped ").replace("skipped: ", "skipped ")
    if r["outcome"] == "error":
        return "raised"
    text = f"{1e3 * r['time_s']:.3g} ms"
    if r["solver"] != "ours" and np.isfinite(r["ratio_to_ours"]):
        text += f" ×{r['ratio_to_ours']:.2g}"
    if not r["success"]:
        text += " F"
    if r["branch"] == "infeasible":
        text += " I"
    elif r["branch"].startswith("other"):
        text += " B"
    elif r["branch"].startswith("near"):
        text += " ~"
    return text


def _straight_cell(r: dict[str, Any]) -> str:
    if r["outcome"] != "ran":
        return r["outcome"]
    if r["solved"]:
        return f"✓ {1e3 * r['time_s']:.3g} ms"
    what = r["branch"] if r["branch"] != "lowest" else "lowest"
    flag = "" if r["success"] else "F, "
    return f"✗ {flag}{what}" + ("" if r["success"] else f": {r['message'][:40]}")


def write(rows: list[dict[str, Any]], solvers: list[str], bars: tuple[int, ...], out: Path, env: list[str],
          settings: str, hessian_note: str, *, quick: bool) -> None:
    stem = T.output_stem(out, "peers", quick)
    T.write_csv(rows, stem.with_suffix(".csv"))
    sequence = [r for r in rows if r["group"] == "sequence"]
    rows = [r for r in rows if r["group"] != "sequence"]
    summary = _summary(rows, solvers, bars)
    main_rows = [r for r in rows if r["group"] == "elastica start"]
    scene_names = list(dict.fromkeys(r["scene"] for r in main_rows))
    lines = [
        "# Peers on the paper scenes: ours against scipy SLSQP, trust-constr and IPOPT",
        "",
        *[f"- {e}" for e in env],
        f"- {settings}",
        f"- same start (the formulation's elastica-like `x0`) and the same analytic derivatives for every solver; "
        f"{hessian_note}; peers with scipy's default tolerances (IPOPT tol 1e-8), iteration caps "
        f"{', '.join(f'{k} {v}' for k, v in PEER_MAX_ITER.items())}",
        "- ours: `guidewire.solve` defaults; time = `Solution.solve_time_s` (formulation, solve and wall rounds; "
        "peers: the `minimize` call alone, their formulation prepared outside the timer)",
        f"- *solved*: success reported, violation ≤ {G.FEASIBILITY_TOL:g} on every row of the full formulation, "
        f"energy within {G.SAME_ENERGY_RTOL:g} (relative) of the lowest feasible energy any solver reached on the "
        "same problem (*lowest branch*); ratios are to `ours` on the same problem in the same run",
        "",
        "## Summary (elastica start): solved problems and shifted geometric mean time over them",
        "",
        f"Cell: `solved/problems · sgm ms · ×ours` (sgm shift {1e3 * _timing.TIME_SHIFT:g} ms; ×ours = geometric mean "
        "of the per-problem time ratios where both solved). Sorted by problems solved, then time at n = 100.",
        "",
    ]
    header = ["solver", "solved"] + [f"n = {n}" for n in bars]
    body = []
    for e in summary:
        cells = []
        for n in bars:
            d = e[n]
            text = f"{d['solved']}/{d['of']}"
            if d["solved"]:
                text += f" · {1e3 * d['sgm']:.3g}"
                if e["solver"] != "ours" and np.isfinite(d["ratio"]):
                    text += f" · ×{d['ratio']:.2g}"
            cells.append(text)
        body.append([e["solver"], f"{e['solved']}/{e['problems']}", *cells])
    lines += T.markdown_table(header, body)
    lines += ["", "## Headline: ours against the fastest peer that solved, and the distance to the structure limit, "
              "per problem", ""]
    lines += headline(main_rows, bars)
    lines += growth(main_rows, bars)
    lines += ["", "## Time per scene (elastica start)", "",
              "Cell: median time, ×ours; flags: F = solver reported failure, B = other (higher) branch, "
              "~ = same branch but energy off by 1e-6..1e-3, I = infeasible answer; *stopped* = one solve passed "
              "the time limit (not run at larger n), *skipped* = predicted to pass it.", ""]
    order = [e["solver"] for e in summary]
    for scene in scene_names:
        rs = [r for r in main_rows if r["scene"] == scene]
        ref = next((r for r in rs), None)
        ref_text = f"continuum energy {ref['reference_energy']:.6g} N·mm" if ref and np.isfinite(
            ref["reference_energy"]) else (ref["reference_note"] if ref else "")
        lines += [f"### {scene} ({ref_text})", ""]
        body = []
        for name in order:
            cells = []
            for n in bars:
                r = next((r for r in rs if r["solver"] == name and r["n"] == n), None)
                cells.append(_detail_cell(r) if r else "")
            body.append([name, *cells])
        lines += T.markdown_table(["solver"] + [f"n = {n}" for n in bars], body)
        ours = [r for r in rs if r["solver"] == "ours" and r["outcome"] == "ran"]
        if ours:
            lines += ["", "ours: " + "; ".join(
                f"n = {r['n']}: E = {r['energy']:.6g}, vs continuum {r['energy_vs_reference']:+.1e}, mean error "
                f"{T.cell(r['mean_error_mm'], 3)} mm, {r['nit']} it" for r in ours)]
        lines.append("")
    straight = [r for r in rows if r["group"] == "straight start"]
    if straight:
        n_s = straight[0]["n"]
        lines += [f"## Straight start (all angles 0), n = {n_s}", "",
                  "✓ = solved (time); ✗ = success flag false (F) and/or not the lowest branch / infeasible.", ""]
        body = []
        for scene in dict.fromkeys(r["scene"] for r in straight):
            cells = []
            for name in order:
                r = next((r for r in straight if r["scene"] == scene and r["solver"] == name), None)
                cells.append(_straight_cell(r) if r else "")
            body.append([scene, *cells])
        lines += T.markdown_table(["scene", *order], body)
        lines += ["", "Solved from the straight start: " + ", ".join(
            f"{name} {sum(r['solved'] for r in straight if r['solver'] == name)}/"
            f"{sum(r['solver'] == name for r in straight)}" for name in order), ""]
    if sequence:
        lines += [f"## Quasi-static sequence: Table 1 (θ_B = π/4), B moving {SEQUENCE_STEP_MM:g} mm per step towards "
                  f"the base, n = {sequence[0]['n']}, {sequence[0]['steps']} steps after a cold first step", "",
                  "`ours (solve_sequence)`: `guidewire.solve_sequence` (previous shape and multipliers); "
                  "`ours (warm x)`: `guidewire.solve` from the previous angles; `ours (cold)`: every step from the "
                  "default start; "
                  "peers: from the previous answer's angles. *off cold*: steps whose energy differs from ours (cold) "
                  f"by more than {G.SAME_ENERGY_RTOL:g} (relative) or that are infeasible.", ""]
        lines += T.markdown_table(
            ["solver", "median per step (ms)", "max per step (ms)", "mean iterations", "failures", "off cold"],
            [[r["solver"], r["median_step_ms"], r["max_step_ms"], r["mean_iterations"], r["failures"],
              r["off_cold_energy"]] for r in sorted(sequence, key=lambda r: r["median_step_ms"])])
        lines.append("")
    failed = [r for r in main_rows if not r["solved"] and r["outcome"] != "skipped"]
    lines += ["## Elastica start: every problem not solved", ""]
    lines += T.markdown_table(
        ["scene", "n", "solver", "success", "branch", "energy", "max violation", "time (s)", "message"],
        [[r["scene"], r["n"], r["solver"], r["success"], r["branch"], r["energy"], r["max_violation"], r["time_s"],
          r["message"][:90]] for r in failed],
    ) if failed else ["none"]
    T.write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines[: lines.index("## Time per scene (elastica start)")]))
    plot(main_rows, order, bars, stem.with_suffix(".png"))


def plot(rows: list[dict[str, Any]], solvers: list[str], bars: tuple[int, ...], path: Path) -> None:
    plt = T.pyplot()
    if plt is None:
        return
    panels = [("Tables 1, 2, 4 (contacts)", False), ("Fig. 6a, 6b (walls)", True)]
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2), sharey=True)
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    colour = {name: "k" if name == "ours" else cycle[i % len(cycle)] for i, name in enumerate(solvers)}
    for ax, (title, walls) in zip(axes, panels, strict=True):
        for name in solvers:
            xs, ys = [], []
            for n in bars:
                ok = [r["time_s"] for r in rows if r["solver"] == name and r["n"] == n and r["walls"] == walls
                      and r["solved"]]
                if ok:
                    xs.append(n)
                    ys.append(_timing.sgm(ok))
            if not xs:
                continue
            ours = name.startswith("ours")
            style = {"lw": 2.6} if name == "ours" else (
                {"lw": 0.9, "ls": "--", "alpha": 0.8} if ours else {"lw": 1.8})
            ax.loglog(xs, ys, marker="o", ms=3.5, label=name, color=colour[name], **style)
        ax.set_title(title)
        ax.set_xlabel("bars n")
        ax.set_xticks(list(bars), [str(n) for n in bars])
        ax.minorticks_off()
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("time per solve (s), shifted geometric mean over solved scenes")
    handles = {}  # one legend for both panels: every solver drawn in either (the structure limit: contacts only)
    for ax in axes:
        handles.update(zip(ax.get_legend_handles_labels()[1], ax.get_legend_handles_labels()[0], strict=True))
    axes[1].legend(list(handles.values()), list(handles), fontsize=7, ncol=2)
    fig.suptitle("Paper scenes, elastica start: time vs n (solved problems only)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
