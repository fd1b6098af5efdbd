"""Insertion through the shipped vessels: per-step and cold-solve times against IPOPT on the same program.

What is measured
----------------
For each vessel of ``guidewire/scenes/vessels/`` (bend, tortuous, aortic arch; 1 bar per mm), the wire is inserted
from 5 mm to the vessel's span in ``--step`` mm steps by :func:`guidewire.insert` (the default ``"track"`` predictor:
each step warm-started from the previous shape and multipliers). Per step: our time (``Solution.solve_time_s``:
formulation, every round of the lumen rows, solution assembly), iterations and success.

IPOPT (cyipopt, exact Hessians) solves the same program from the same start: the rows of our last round (the lumen's
quadratic models, exact at the answer: our rounds exist only to find where those rows sit, which IPOPT is spared) from
our warm start of that step. Its time is the ``minimize_ipopt`` call. Answers are compared by energy. The cold solve
at the final length (ours from the default start only, ``branches="first"``: the multi-start of a branched vessel
would time three more starts than IPOPT gets; IPOPT on our final rows from that start) is timed too.

A second table times insertion steps of wires of about 1 000 bars (:data:`FINE`: a few 1 mm steps at a fine bar
density, started by a cold solve with the default ``branches="lowest"``), against warm-started IPOPT the same way.

Goals (from the vessel issue): per step ≤ 1 ms median at 100 bars and ≤ 3 ms at 1 000 bars, ≥ 3× faster than
warm-started IPOPT; the whole 250 mm arch insertion at 1 mm steps in ≤ 0.5 s; no step slower than 10× the median.

Usage: ``python benchmarks/vessels.py [--quick] [--step MM] [--no-fine] [--out DIR]``; writes
``vessels.{md,csv,png}`` and ``vessels_fine.csv`` (``vessels_quick.*`` with ``--quick``, which skips the fine
wires). BLAS is pinned to one thread.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import _environment as env  # noqa: I001  (first: pins BLAS threads before numpy loads)
import numpy as np
from _arguments import parse, parser
from _guidewire import step_problem
from _peers import run_ipopt
from _tables import cell, markdown_table, output_stem, pyplot, write_csv, write_markdown

import guidewire

VESSELS = Path(__file__).resolve().parents[1] / "guidewire" / "scenes" / "vessels"
#: (vessel, last inserted length in mm): each about the span the shipped scene is built for.
SPANS = {"bend": 90.0, "tortuous": 45.0, "aortic_arch": 250.0}
QUICK_SPANS = {"bend": 40.0, "tortuous": 25.0}
FIRST = 5.0
#: Wires of about 1 000 bars: (vessel, first inserted length in mm, bars per mm, 1 mm steps after the first).
FINE = {"bend": (80.0, 12.5, 8), "tortuous": (40.0, 25.0, 8), "aortic_arch": (240.0, 4.0, 8)}


def insertion(name: str, span: float, step: float, ipopt: bool) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    scene = guidewire.load_scene(VESSELS / f"{name}.toml")
    lengths = np.arange(FIRST, span + 0.5 * step, step)
    start = scene.with_wire(length=FIRST, bars=scene.wire.bars_at(FIRST))
    rows, total, last = steps(name, start, lengths, ipopt)
    cold = guidewire.solve(last, branches="first")
    summary: dict[str, Any] = {"vessel": name, "steps": len(rows), "total_s": total,
                               "cold_ms": 1e3 * cold.solve_time_s, "cold_energy": cold.energy,
                               "cold_ipopt_ms": math.nan}
    if ipopt and cold.success:
        res = run_ipopt(step_problem(cold, guidewire.formulate(last).x0))
        summary["cold_ipopt_ms"] = 1e3 * res["time"]
    return rows, summary


def steps(name: str, start: guidewire.Scene, lengths: Any,
          ipopt: bool) -> tuple[list[dict[str, Any]], float, guidewire.Scene]:
    """Insert ``start``'s wire through ``lengths`` (its bar density kept): a row per step (ours, and IPOPT from
    our warm start on our last round's rows), the insertion's wall time (s) and its last step's scene."""
    wall = time.perf_counter()
    out = guidewire.insert(start, lengths)
    total = time.perf_counter() - wall
    rows = []
    for k, sol in enumerate(out.steps):
        row: dict[str, Any] = {"vessel": name, "inserted_mm": sol.scene.wire.length, "bars": sol.n_bars,
                               "success": sol.success, "iterations": sol.iterations, "rounds": sol.rounds,
                               "ours_ms": 1e3 * sol.solve_time_s, "energy": sol.energy,
                               "contacts": len(sol.contacts()), "ipopt_ms": math.nan, "ipopt_energy": math.nan}
        if ipopt and k > 0 and sol.success:
            from guidewire.march.insertion import _tracked_angles  # the same warm start as ours

            prob = step_problem(sol, _tracked_angles(out.steps[k - 1], sol.scene, sol.n_bars))
            res = run_ipopt(prob)
            row.update(ipopt_ms=1e3 * res["time"], ipopt_energy=float(res["f"]) if res["success"] else math.nan)
        rows.append(row)
    return rows, total, out.steps[-1].scene


def _step_statistics(steps: list[dict[str, Any]]) -> tuple[np.ndarray, str, float, str]:
    """Our times (ms) of ``steps``, IPOPT's median time (a cell), the geometric mean of IPOPT's time over ours and
    how many of the steps IPOPT solved end at our energy (to 1e-6 relative, or 1e-9 N·mm)."""
    ours = np.array([r["ours_ms"] for r in steps])
    ip = np.array([r["ipopt_ms"] for r in steps])
    both = np.isfinite(ip)
    ratio = float(np.exp(np.mean(np.log(ip[both] / ours[both])))) if both.any() else math.nan
    compared = [r for r in steps if np.isfinite(r["ipopt_energy"])]
    same = sum(abs(r["energy"] - r["ipopt_energy"]) <= 1e-6 * max(abs(r["energy"]), 1e-3) for r in compared)
    return ours, cell(np.median(ip[both])) if both.any() else "-", ratio, f"{same}/{len(compared)}"


def fine_table(rows: list[dict[str, Any]]) -> list[str]:
    """The table of the ~1 000-bar wires' steps (the first, a cold solve, left out of the statistics)."""
    header = ["vessel", "bars", "steps", "solved", "cold ms", "ours median ms/step", "ours max ms", "median it",
              "IPOPT median ms/step", "IPOPT/ours (geo. mean)", "same energy"]
    table = []
    for name in dict.fromkeys(r["vessel"] for r in rows):
        mine = [r for r in rows if r["vessel"] == name]
        ours, ip_median, ratio, agree = _step_statistics(mine[1:])
        table.append([name, f"{mine[1]['bars']}-{mine[-1]['bars']}", len(mine) - 1,
                      sum(r["success"] for r in mine[1:]), cell(mine[0]["ours_ms"]), cell(np.median(ours)),
                      cell(ours.max()), cell(np.median([r["iterations"] for r in mine[1:]])), ip_median,
                      cell(ratio), agree])
    return ["## Insertion steps of wires of about 1 000 bars", "",
            "1 mm steps at a fine bar density after a cold solve (default `branches=\"lowest\"`), IPOPT from our warm "
            "start of each step on our last round's rows, as above.", "", *markdown_table(header, table), ""]


def report(rows: list[dict[str, Any]], summaries: list[dict[str, Any]], step: float) -> list[str]:
    header = ["vessel", "steps", "solved", "ours median ms/step", "ours max ms", "max/median", "median it",
              "insertion total s", "IPOPT median ms/step", "IPOPT/ours (geo. mean)", "same energy",
              "cold: ours ms", "cold: IPOPT ms"]
    table = []
    for summ in summaries:
        mine = [r for r in rows if r["vessel"] == summ["vessel"]]
        ours, ip_median, ratio, agree = _step_statistics(mine[1:])
        table.append([summ["vessel"], summ["steps"], sum(r["success"] for r in mine), cell(np.median(ours)),
                      cell(ours.max()), cell(ours.max() / np.median(ours)),
                      cell(np.median([r["iterations"] for r in mine[1:]])), cell(summ["total_s"]),
                      ip_median, cell(ratio), agree,
                      cell(summ["cold_ms"]), cell(summ["cold_ipopt_ms"])])
    return [f"# Insertion through the shipped vessels ({step:g} mm steps, 1 bar per mm)", "",
            *(f"- {line}" for line in env.environment()), "",
            "Per step after the first (the first is a cold solve). *IPOPT/ours*: geometric mean of the per-step "
            "time ratios; *same energy*: steps where IPOPT's energy equals ours to 1e-6 (relative, or 1e-9 N·mm "
            "absolute); a difference means another local minimum of the same rows (IPOPT may move far from where the "
            "lumen rows are modelled, so its answer is not checked against the true lumen).", "",
            *markdown_table(header, table), ""]


def main() -> None:
    ap = parser(__doc__, quick_help="bend and tortuous, shorter spans, 5 mm steps", repeats=1)
    ap.add_argument("--step", type=float, default=1.0, help="insertion step (mm)")
    ap.add_argument("--no-ipopt", action="store_true", help="ours only")
    ap.add_argument("--no-fine", action="store_true", help="skip the ~1 000-bar wires")
    args = parse(ap)
    step = 5.0 if args.quick else args.step
    spans = QUICK_SPANS if args.quick else SPANS
    ipopt = env.ipopt_available() and not args.no_ipopt
    print("\n".join(env.environment()))
    guidewire.solve(guidewire.paper_scenes()["table1_pi_4"].with_bars(10))  # warm-up: first calls load libraries
    rows, summaries = [], []
    with env.one_thread():
        for name, span in spans.items():
            r, summ = insertion(name, span, step, ipopt)
            rows += r
            summaries.append(summ)
            print(f"{name}: {summ['steps']} steps in {summ['total_s']:.2f} s", flush=True)
        fine: list[dict[str, Any]] = []
        for name, (first, density, count) in ({} if (args.quick or args.no_fine) else FINE).items():
            scene = guidewire.load_scene(VESSELS / f"{name}.toml")
            start = scene.with_wire(length=first, bars=round(first * density))
            fine += steps(name, start, first + np.arange(count + 1.0), ipopt)[0]
            print(f"{name} at {density:g} bars/mm: {count} steps", flush=True)
    stem = output_stem(args.out, "vessels", args.quick)
    lines = report(rows, summaries, step) + (fine_table(fine) if fine else [])
    if fine:
        write_csv(fine, stem.with_name(stem.name + "_fine").with_suffix(".csv"))
    write_markdown(lines, stem.with_suffix(".md"))
    write_csv(rows, stem.with_suffix(".csv"))
    plt = pyplot()
    if plt is not None:
        fig, ax = plt.subplots(figsize=(8, 4.5), layout="constrained")
        for summ in summaries:
            mine = [r for r in rows if r["vessel"] == summ["vessel"]][1:]
            ax.plot([r["inserted_mm"] for r in mine], [r["ours_ms"] for r in mine], "-",
                    label=f"{summ['vessel']}: ours")
            if ipopt:
                ax.plot([r["inserted_mm"] for r in mine], [r["ipopt_ms"] for r in mine], ":",
                        label=f"{summ['vessel']}: IPOPT")
        ax.set_yscale("log")
        ax.set_xlabel("inserted length (mm)")
        ax.set_ylabel("time per step (ms)")
        ax.legend(fontsize=8)
        ax.grid(True, lw=0.3, alpha=0.5)
        fig.savefig(stem.with_suffix(".png"), dpi=120)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
