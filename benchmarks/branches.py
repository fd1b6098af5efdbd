"""Branch misses on random feasible scenes: how often ``guidewire.solve`` ends on a local minimum above the chain the
scene was generated from (:mod:`guidewire.scene.generated`), and what it costs to avoid it.

Usage: ``python benchmarks/branches.py [--scenes N] [--seed S] [--modes first,lowest] [--repeats K] [--quick]
[--out DIR]`` (default 800 scenes, seed 2019, both modes, 15 repeats); writes ``branches.md`` and ``branches.csv``
(one row per scene and mode) in ``--out`` (``branches_quick.*`` with ``--quick``: 100 scenes, one repeat). BLAS
pinned to one thread.

The paper scenes (every ``guidewire/scenes/*.toml`` but ``j_tip``, at their default bars) are timed too: each solved
``--repeats`` times with ``branches="first"`` and ``"lowest"`` alternately, the ratio of the medians per scene
(Table 5 as printed is infeasible and refused before any solve: not timed).

A *miss* is a successful solve whose energy exceeds the generating chain's by more than :data:`MISS_TOLERANCE`
(relative); a *failure* is a solve that does not report success. Times are each solve's ``solve_time_s``; the modes
are run alternately scene by scene, so machine load hits both alike.
"""

from __future__ import annotations

import statistics
from pathlib import Path

import _environment  # noqa: F401  (pins BLAS to one thread before numpy loads)
import numpy as np
from _arguments import names, parse, parser
from _environment import environment, one_thread
from _tables import markdown_table, output_stem, write_csv, write_markdown

from guidewire import load_scene, solve
from guidewire.program.formulation import formulate
from guidewire.scene.generated import random_chain_scene

#: The paper scenes timed (the scene files but the J tip, which is not a paper scene).
SCENES = sorted(p for p in (Path(__file__).resolve().parents[1] / "guidewire" / "scenes").glob("*.toml")
                if p.stem != "j_tip")

#: Relative excess over the generating chain's energy that counts as a miss.
MISS_TOLERANCE = 1e-6

#: Energy (N·mm) below which an excess is rounding (a straight generating chain has energy 0).
ENERGY_FLOOR = 1e-12


def main() -> None:
    ap = parser(__doc__, quick_help="100 scenes, one repeat", repeats=15)
    ap.add_argument("--scenes", type=int, default=800, help="number of random scenes")
    ap.add_argument("--seed", type=int, default=2019, help="seed of the scene generator")
    ap.add_argument("--modes", type=str, default="first,lowest", help="values of solve(branches=...) to compare")
    args = parse(ap)
    count = 100 if args.quick else args.scenes
    modes = names(args.modes)
    rng = np.random.default_rng(args.seed)
    rows = []
    with one_thread():
        for index in range(count):
            case = random_chain_scene(rng)
            scene = case.scene
            generating = float(formulate(scene, initial_angles=case.angles).fun(case.angles))
            for mode in modes:
                sol = solve(scene, **({} if mode == "default" else {"branches": mode}))
                excess = max(sol.energy - generating - ENERGY_FLOOR, 0.0) / max(generating, 1e-300)
                rows.append({
                    "scene": index, "mode": mode, "bars": scene.wire.bars, "contacts": len(scene.contacts),
                    "angles": sum(c.angle is not None for c in scene.contacts), "walls": len(scene.walls),
                    "b2": scene.wire.max_relative_angle is not None, "generating_energy": generating,
                    "energy": sol.energy, "excess": excess, "success": sol.success,
                    "miss": bool(sol.success and excess > MISS_TOLERANCE),
                    "starts": getattr(sol, "starts", 1), "time_s": sol.solve_time_s,
                })
            if (index + 1) % 100 == 0:
                print(f"{index + 1}/{count} scenes", flush=True)
    stem = output_stem(args.out, "branches", args.quick)
    write_csv(rows, stem.with_suffix(".csv"))
    summary, misses = [], []
    for mode in modes:
        mine = [r for r in rows if r["mode"] == mode]
        missed = [r for r in mine if r["miss"]]
        summary.append([mode, len(mine), len(missed), sum(not r["success"] for r in mine),
                        max((r["excess"] for r in missed), default=0.0),
                        sum(r["starts"] > 1 for r in mine), statistics.median(r["time_s"] for r in mine) * 1e3,
                        statistics.mean(r["time_s"] for r in mine) * 1e3])
        misses += [[mode, r["scene"], r["bars"], r["contacts"], r["angles"], r["walls"], r["generating_energy"],
                    r["energy"], r["excess"], r["starts"]] for r in missed]
    lines = [f"# Branch misses on {count} random feasible scenes (seed {args.seed})", "", *environment(), "",
             f"A miss: success with an energy more than {MISS_TOLERANCE:g} (relative) above the generating chain's "
             "(a feasible point). Modes alternate scene by scene.", "",
             *markdown_table(["branches", "scenes", "misses", "failures", "largest excess", "multi-start",
                              "median time (ms)", "mean time (ms)"], summary), ""]
    if misses:
        lines += ["## Misses", "", *markdown_table(["branches", "scene", "bars", "contacts", "with angle", "walls",
                                                    "generating E", "E", "excess", "starts"], misses), ""]
    lines += ["## Paper scenes", "", f"Median of {args.repeats} solves per mode, run alternately; time ratio "
              "lowest / first.", "", *markdown_table(["scene", "bars", "starts", "first (ms)", "lowest (ms)", "ratio"],
                                                      paper_times(args.repeats)), ""]
    write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines))


def paper_times(repeats: int) -> list[list[object]]:
    """Per paper scene: bars, starts, median time with ``branches="first"`` and ``"lowest"`` (ms), their ratio; the
    last row the median over scenes."""
    rows = []
    with one_thread():
        for path in SCENES:
            scene = load_scene(path)
            try:
                solve(scene, branches="first")
            except ValueError:  # the printed Table 5 is infeasible: refused before solving
                continue
            times: dict[str, list[float]] = {"first": [], "lowest": []}
            for _ in range(repeats):
                for mode in times:
                    sol = solve(scene, branches=mode)
                    times[mode].append(sol.solve_time_s)
            first, lowest = (statistics.median(times[m]) * 1e3 for m in ("first", "lowest"))
            rows.append([path.stem, scene.wire.bars, sol.starts, first, lowest, lowest / first])
    rows.append(["median", "", "", statistics.median(r[3] for r in rows), statistics.median(r[4] for r in rows),
                 statistics.median(r[5] for r in rows)])
    return rows


if __name__ == "__main__":
    main()
