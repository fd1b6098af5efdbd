"""Cold solves in the shipped planar vessels from 100 to 3 200 bars, against IPOPT on the same rows.

What is measured
----------------
For each vessel (bend, S-bend, aortic arch with 250 mm inserted, tortuous) and each bar count ``n``: our cold solve
``guidewire.solve(scene, bars=n, branches="first")`` from the default start (median of ``--repeats`` runs of
``Solution.solve_time_s`` after a warm-up solve that builds the vessel's corners and boundary samples, each run with
the vessel's kept query answers dropped first: ``Vessel.forget_queries``, or a repeat would find the closest points
of the run before it kept; the layout is :func:`guidewire.solve.options.choose_layout`'s: the dense program of bar
angles up to 300 bars, the sparse full space above), its iterations and rounds. From 200 bars that start is nested
(:func:`guidewire.solve.pipeline.nested_start`: the same scene solved at a quarter of the bars, at least 100, its
answer interpolated): the *coarse* column lists those solves' bars; their time is in ours, their iterations are
not in *it*.

IPOPT (cyipopt, exact Hessians) solves the rows of our last round (the lumen's models where our rounds left them,
exact at the answer: IPOPT is spared the rounds) from the plain default start (the centreline; not the nested one),
in its best formulation of them: the sparse full space (angles and nodes, the same closure rows and sparse exact
Hessians) at every ``n``, and also the dense program of bar angles up to 400 bars; its time is the faster of the
two. Answers are compared by energy.

Goals (from the vessel issue): ≥ 3× faster than IPOPT at every ``n``; growth of our time from 100 to 3 200 bars
≤ n^1.2; ≤ 20 ms at 400 bars and ≤ 150 ms at 3 200 bars on this machine.

Usage: ``python benchmarks/vessels_scale.py [--quick] [--cases NAME ...] [--bars N ...] [--repeats R]
[--out DIR]``; writes
``vessels_scale.{md,csv}`` (``vessels_scale_quick.*`` with ``--quick``: the bend, 100-800 bars). BLAS is
pinned to one thread.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import _environment as env  # noqa: I001  (first: pins BLAS threads before numpy loads)
import numpy as np
from _arguments import parse, parser
from _peers import run_ipopt
from _problems import Problem
from _tables import cell, markdown_table, output_stem, write_csv, write_markdown

import guidewire
from guidewire.program.formulation import assemble
from guidewire.program.model import build_model

VESSELS = Path(__file__).resolve().parents[1] / "guidewire" / "scenes" / "vessels"
#: (scene file, inserted length in mm or None for the file's own).
CASES = {"bend": ("bend", None), "s_bend": ("s_bend", None), "aortic_arch": ("aortic_arch", 250.0),
         "tortuous": ("tortuous", None)}
BARS = (100, 200, 400, 800, 1600, 3200)
QUICK = {"cases": ("bend",), "bars": (100, 200, 400, 800)}
#: IPOPT on the dense program of bar angles up to this many bars (above, only its sparse full-space formulation).
IPOPT_DENSE_MAX = 400


def scene_of(name: str) -> guidewire.Scene:
    file, length = CASES[name]
    scene = guidewire.load_scene(VESSELS / f"{file}.toml")
    return scene if length is None else scene.with_wire(length=length)


def ipopt_on(sol: Any, layout: str) -> dict[str, Any]:
    """IPOPT on the rows of ``sol``'s last round in ``layout`` from the default start."""
    start = guidewire.formulate(sol.scene).model.x0
    form = assemble(build_model(sol.scene, initial_angles=start), layout, sol.blocks)
    problem = Problem(fun=form.fun, jac=form.jac, x0=form.x0, constraints=tuple(form.constraints), bounds=None,
                      hess=form.hess)
    return run_ipopt(problem)


def measure(name: str, bars: int, repeats: int, ipopt: bool) -> dict[str, Any]:
    scene = scene_of(name)
    guidewire.solve(scene, bars=bars, branches="first")  # (warm-up: the vessel's corners and boundary samples)
    times, sol = [], None
    for _ in range(repeats):
        scene.vessel.forget_queries()  # (each run searches as the first does: no answers kept from the one before)
        sol = guidewire.solve(scene, bars=bars, branches="first")
        times.append(sol.solve_time_s)
    assert sol is not None
    row: dict[str, Any] = {"vessel": name, "bars": bars, "layout": sol.layout, "success": sol.success,
                           "status": sol.status.name, "ours_ms": 1e3 * float(np.median(times)),
                           "iterations": sol.iterations, "rounds": sol.rounds, "energy": sol.energy,
                           "coarse": "/".join(map(str, sol.coarse_bars)) or "-",
                           "ipopt_ms": math.nan, "ipopt_energy": math.nan, "ipopt_formulation": "-"}
    if ipopt and sol.success:
        best: tuple[float, float, str] | None = None
        for layout in ("full", "reduced") if bars <= IPOPT_DENSE_MAX else ("full",):
            res = run_ipopt_safely(sol, layout)
            if res is not None and res["success"] and (best is None or res["time"] < best[0]):
                best = (res["time"], float(res["f"]), layout)
        if best is not None:
            row.update(ipopt_ms=1e3 * best[0], ipopt_energy=best[1], ipopt_formulation=best[2])
    return row


def run_ipopt_safely(sol: Any, layout: str) -> dict[str, Any] | None:
    try:
        return ipopt_on(sol, layout)
    except Exception as exc:  # a peer failing is a result, not a crash of the benchmark
        print(f"  IPOPT ({layout}) failed: {exc}", flush=True)
        return None


def growth(rows: list[dict[str, Any]], name: str) -> float:
    """Exponent of our time's growth from the smallest to the largest ``n`` solved."""
    mine = [r for r in rows if r["vessel"] == name and r["success"]]
    if len(mine) < 2:
        return math.nan
    a, b = mine[0], mine[-1]
    return math.log(b["ours_ms"] / a["ours_ms"]) / math.log(b["bars"] / a["bars"])


def report(rows: list[dict[str, Any]], repeats: int) -> list[str]:
    header = ["vessel", "bars", "layout", "coarse", "status", "it", "rounds", "ours ms", "IPOPT ms", "IPOPT form",
              "IPOPT/ours", "energy gap"]
    table = []
    for r in rows:
        gap = abs(r["energy"] - r["ipopt_energy"]) / max(abs(r["energy"]), 1e-12) if math.isfinite(
            r["ipopt_energy"]) else math.nan
        table.append([r["vessel"], r["bars"], r["layout"], r["coarse"], r["status"], r["iterations"], r["rounds"],
                      cell(r["ours_ms"]), cell(r["ipopt_ms"]), r["ipopt_formulation"],
                      cell(r["ipopt_ms"] / r["ours_ms"]), "-" if math.isnan(gap) else f"{gap:.1e}"])
    names = list(dict.fromkeys(r["vessel"] for r in rows))
    growths = ", ".join(f"{n} n^{growth(rows, n):.2f}" for n in names)
    return ["# Cold solves in the planar vessels, 100 to 3 200 bars, against IPOPT", "",
            *(f"- {line}" for line in env.environment()), "",
            f"Ours: median of {repeats} cold solves from the default start (`branches=\"first\"`), nested from 200 "
            "bars (*coarse*: the bars of the coarser solves that made its start, their time included, their "
            "iterations not in *it*). IPOPT: the rows of our last round from the plain default start, exact "
            "Hessians, the faster of its sparse full-space and (up to "
            f"{IPOPT_DENSE_MAX} bars) dense bar-angle formulations; one run. *energy gap*: relative difference of "
            "the energies (a large one: another local minimum).", "",
            *markdown_table(header, table), "", f"Growth of our time from the smallest to the largest n: {growths}.",
            ""]


def main() -> None:
    ap = parser(__doc__, quick_help="the bend, 100-800 bars", repeats=3)
    ap.add_argument("--no-ipopt", action="store_true", help="ours only")
    ap.add_argument("--cases", nargs="+", choices=tuple(CASES), help="vessels (default: all)")
    ap.add_argument("--bars", nargs="+", type=int, help=f"bar counts (default: {' '.join(map(str, BARS))})")
    args = parse(ap)
    cases = tuple(args.cases) if args.cases else QUICK["cases"] if args.quick else tuple(CASES)
    bars = tuple(args.bars) if args.bars else QUICK["bars"] if args.quick else BARS
    ipopt = env.ipopt_available() and not args.no_ipopt
    print("\n".join(env.environment()))
    guidewire.solve(guidewire.paper_scenes()["table1_pi_4"].with_bars(10))  # warm-up: first calls load libraries
    rows = []
    with env.one_thread():
        for name in cases:
            for n in bars:
                row = measure(name, n, args.repeats, ipopt)
                rows.append(row)
                print(f"{name} {n}: {row['status']} ours {row['ours_ms']:.1f} ms ({row['iterations']} it), IPOPT "
                      f"{row['ipopt_ms']:.1f} ms", flush=True)
    stem = output_stem(args.out, "vessels_scale", args.quick)
    lines = report(rows, args.repeats)
    write_markdown(lines, stem.with_suffix(".md"))
    write_csv(rows, stem.with_suffix(".csv"))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
