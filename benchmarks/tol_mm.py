"""solve(scene, tol_mm=…) on every paper scene with a continuum reference: bars used, estimated and true mean node
error, time (all solves of the doubling together, median of 5), against the paper's 100 uniform bars.

Usage: ``python benchmarks/tol_mm.py [TOL_MM]`` (default 0.01); writes ``results/tol_mm.md``.
"""

from __future__ import annotations

import statistics
import sys
from pathlib import Path

import _environment  # noqa: F401  (pins BLAS to one thread before numpy loads)
import numpy as np

from guidewire import paper_scenes, solve
from guidewire.reference import continuum_reference
from guidewire.reference.scene_reference import node_errors


def main() -> None:
    tol = float(sys.argv[1]) if len(sys.argv) > 1 else 0.01
    rows = ["| scene | bars | estimate (mm) | true (mm) | true/estimate | time (ms) | 100 bars: error (mm) | "
            "100 bars: time (ms) |", "|---|---|---|---|---|---|---|---|"]
    for name, scene in paper_scenes().items():
        reference, _ = continuum_reference(scene)
        if reference is None:
            continue
        runs = [solve(scene, tol_mm=tol) for _ in range(5)]
        sol = runs[-1]
        uniform = [solve(scene, bars=100) for _ in range(5)]
        true = float(np.mean(node_errors(sol, reference)))
        true100 = float(np.mean(node_errors(uniform[-1], reference)))
        rows.append(f"| {name} | {sol.n_bars} | {sol.error_estimate_mm:.4g} | {true:.4g} | "
                    f"{true / sol.error_estimate_mm:.3f} | {statistics.median(r.solve_time_s for r in runs) * 1e3:.2f} "
                    f"| {true100:.4g} | {statistics.median(r.solve_time_s for r in uniform) * 1e3:.2f} |")
    text = (f"# solve(scene, tol_mm={tol:g}): doubled uniform layouts, Richardson estimate\n\n"
            "Time is every solve of the doubling together (median of 5). Table 5 has no continuum reference.\n\n"
            + "\n".join(rows) + "\n")
    out = Path(__file__).parent / "results" / "tol_mm.md"
    out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
