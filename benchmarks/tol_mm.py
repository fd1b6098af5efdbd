"""solve(scene, tol_mm=…) on every paper scene with a continuum reference: bars used, estimated and true mean node
error, time (all solves together, median of 5), for the default curvature-graded pairs and for doubled uniform bars
(``density="uniform"``), against the paper's 100 uniform bars.

Usage: ``python benchmarks/tol_mm.py [--tol-mm TOL] [--quick] [--repeats K] [--out DIR]`` (default 0.01 mm, 5
repeats); writes ``tol_mm.md`` (``tol_mm_quick.md`` with ``--quick``: three scenes, one repeat) in ``--out``.
BLAS pinned to one thread.
"""

from __future__ import annotations

import statistics

import _environment  # noqa: F401  (pins BLAS to one thread before numpy loads)
import numpy as np
from _arguments import parse, parser
from _tables import output_stem, write_markdown

from guidewire import paper_scenes, solve
from guidewire.reference import continuum_reference
from guidewire.reference.scene_reference import node_errors


def main() -> None:
    ap = parser(__doc__, quick_help="three scenes, one repeat", repeats=5)
    ap.add_argument("--tol-mm", type=float, default=0.01, help="mean node error asked for (mm)")
    args = parse(ap)
    tol, repeats = args.tol_mm, args.repeats
    scenes = paper_scenes()
    if args.quick:
        scenes = {k: scenes[k] for k in ("table1_pi_4", "fig6b", "table4")}
    rows = ["| scene | density | bars | estimate (mm) | true (mm) | true/estimate | time (ms) | "
            "100 bars: error (mm) | 100 bars: time (ms) |", "|---|---|---|---|---|---|---|---|---|"]
    for name, scene in scenes.items():
        reference, _ = continuum_reference(scene)
        if reference is None:
            continue
        runs: dict[str, list] = {"curvature": [], "uniform": [], "100 bars": []}
        for _ in range(repeats):  # alternated: the machine's load hits all three alike
            runs["curvature"].append(solve(scene, tol_mm=tol))
            runs["uniform"].append(solve(scene, tol_mm=tol, density="uniform"))
            runs["100 bars"].append(solve(scene, bars=100))
        true100 = float(np.mean(node_errors(runs["100 bars"][-1], reference)))
        time100 = statistics.median(r.solve_time_s for r in runs["100 bars"]) * 1e3
        for density in ("curvature", "uniform"):
            sol = runs[density][-1]
            true = float(np.mean(node_errors(sol, reference)))
            rows.append(f"| {name} | {density} | {sol.n_bars} | {sol.error_estimate_mm:.4g} | {true:.4g} | "
                        f"{true / sol.error_estimate_mm:.3f} | "
                        f"{statistics.median(r.solve_time_s for r in runs[density]) * 1e3:.2f} | {true100:.4g} | "
                        f"{time100:.2f} |")
    text = (f"# solve(scene, tol_mm={tol:g}): curvature-graded pairs and doubled uniform layouts, Richardson "
            "estimate\n\n"
            f"Time is every solve together (median of {repeats}, the three kinds alternated, BLAS one thread). "
            "Table 5 has no continuum reference.\n\n"
            + "\n".join(rows) + "\n")
    write_markdown(text.splitlines(), output_stem(args.out, "tol_mm", args.quick).with_suffix(".md"))
    print(text)


if __name__ == "__main__":
    main()
