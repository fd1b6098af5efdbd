"""Where a planar cold solve's time goes: the profile behind the missed cold-solve speed goals.

What is measured
----------------
For each vessel whose cold solves miss a goal of ``vessels_scale.py`` (the S-bend, the aortic arch with 250 mm
inserted, the tortuous vessel) at 100, 400 and 3 200 bars, BLAS on one thread:

- *total*: ``guidewire.solve(scene, bars=n, branches="first")`` from the default start, as ``vessels_scale.py`` times it
  (median of ``--repeats`` runs of ``Solution.solve_time_s``);
- *coarse*: from 200 bars the solve starts from the same scene solved at a quarter of the bars
  (:func:`guidewire.solve.pipeline.nested_start`); that coarser solve timed on its own (itself nested when large
  enough), and
- *fine*: the solve at ``n`` bars from the coarse answer's nodes (``initial_nodes``: what the nested start gives it),
  timed on its own; its energy is checked against the total's (the same solve, split in two).

The fine solve (the whole solve at 100 bars) is then run under :mod:`cProfile` ``--repeats`` times; each phase's share
of the profiled time (cumulative times of named functions, as ``step_profile.py``) is applied to the plain fine time.
*ms per iteration* is the fine time over its SQP iterations (all rounds); *rounds* the working-set rounds (each
re-models the lumen's rows at the last answer and solves again, :func:`guidewire.solve.pipeline.rounds`).

Goals this explains (vessel issue): ≥ 3× faster than IPOPT at every ``n`` (missed at 100-200 bars on these vessels,
``vessels_scale.md``); ≤ 20 ms at 400 bars; ≤ 150 ms at 3 200 bars.

Usage: ``python benchmarks/cold_profile.py [--quick] [--repeats R] [--out DIR]``; writes ``cold_profile.{md,csv}``
(``_quick`` with ``--quick``: the S-bend at 100 and 400 bars).
"""

from __future__ import annotations

import cProfile
import pstats
import time
from pathlib import Path
from typing import Any

import _environment as env  # noqa: I001  (first: pins BLAS threads before numpy loads)
import numpy as np
from _arguments import parse, parser
from _tables import cell, markdown_table, output_stem, write_csv, write_markdown
from step_profile import PLANAR_PHASES, phase_rows

import guidewire
from guidewire.solve.pipeline import _along, _node_arc_lengths

VESSELS = Path(__file__).resolve().parents[1] / "guidewire" / "scenes" / "vessels"
#: (scene file, inserted length in mm or None for the file's own), as ``vessels_scale.py``.
CASES = {"s_bend": ("s_bend", None), "aortic_arch": ("aortic_arch", 250.0), "tortuous": ("tortuous", None)}
BARS = (100, 400, 3200)
QUICK = {"cases": ("s_bend",), "bars": (100, 400)}
#: The phases of a solve (``step_profile.py``'s planar ones without the insertion's predictor).
PHASES = [p for p in PLANAR_PHASES if not p[0].startswith("predictor")]


def scene_of(name: str) -> guidewire.Scene:
    file, length = CASES[name]
    scene = guidewire.load_scene(VESSELS / f"{file}.toml")
    return scene if length is None else scene.with_wire(length=length)


def median_solve(scene: guidewire.Scene, repeats: int, **options: Any) -> tuple[float, Any]:
    """Median ``solve_time_s`` (ms) of ``repeats`` solves and the last solution."""
    times, sol = [], None
    for _ in range(repeats):
        scene.vessel.forget_queries()  # (each run searches as a first one: no answers kept from the one before)
        sol = guidewire.solve(scene, branches="first", **options)
        times.append(sol.solve_time_s)
    return 1e3 * float(np.median(times)), sol


def measure(name: str, bars: int, repeats: int) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """One vessel at ``bars``: the summary row and its phase rows."""
    scene = scene_of(name)
    guidewire.solve(scene, bars=bars, branches="first")  # (warm-up: the vessel's corners and boundary samples)
    total_ms, whole = median_solve(scene, repeats, bars=bars)
    options: dict[str, Any] = {"bars": bars}
    coarse_ms, coarse_bars = 0.0, "-"
    if whole.coarse_bars:
        m = whole.coarse_bars[-1]
        coarse_ms, coarse = median_solve(scene, repeats, bars=m)
        coarse_bars = "/".join(map(str, whole.coarse_bars))
        options["initial_nodes"] = _along(coarse.nodes, coarse.s, _node_arc_lengths(scene, bars))
    fine_ms, fine = median_solve(scene, repeats, **options)
    profiler = cProfile.Profile()
    wall = 0.0
    for _ in range(repeats):
        scene.vessel.forget_queries()
        start = time.perf_counter()
        profiler.enable()
        guidewire.solve(scene, branches="first", **options)
        profiler.disable()
        wall += time.perf_counter() - start
    stats = pstats.Stats(profiler)
    label = f"{name}, {bars} bars"
    rows = phase_rows(stats, PHASES, label, wall, fine_ms, "fine solve", "ms")
    gap = abs(fine.energy - whole.energy) / max(abs(whole.energy), 1e-300)
    summary = {"vessel": name, "bars": bars, "status": whole.status.name, "total ms": total_ms,
               "coarse bars": coarse_bars, "coarse ms": coarse_ms, "fine ms": fine_ms, "layout": fine.layout,
               "it": fine.iterations, "rounds": fine.rounds, "ms per iteration": fine_ms / max(1, fine.iterations),
               "fine = total (energy)": gap <= 1e-9,
               "Python calls per fine solve": stats.total_calls / repeats}  # type: ignore[attr-defined]
    return summary, rows


def report(summaries: list[dict[str, Any]], rows: list[dict[str, Any]], repeats: int) -> list[str]:
    keys = list(summaries[0])
    lines = ["# Where a planar cold solve's time goes", "", *(f"- {item}" for item in env.environment()), "",
             f"Medians of {repeats} solves. *total* is `vessels_scale.py`'s solve; from 200 bars it is a *coarse* "
             "solve (its bars listed, itself nested) that makes the start of the *fine* one, each timed on its own "
             "(*fine = total*: the fine solve from the coarse answer ends at the total's energy). Phases: the fine "
             "solve profiled, each share applied to its plain time; *part of* says where a phase nests. See the "
             "script's docstring.", ""]
    lines += markdown_table(keys, [[s[k] for k in keys] for s in summaries])
    lines += ["", "## Phases of the fine solve", ""]
    cols = ["case", "phase", "part of", "share", "ms"]
    lines += markdown_table(cols, [[r["case"], r["phase"], r["part of"], f"{100 * r['share']:.1f} %", cell(r["ms"])]
                                   for r in rows])
    return lines


def main() -> None:
    ap = parser(__doc__, quick_help="the S-bend at 100 and 400 bars", repeats=3)
    args = parse(ap)
    cases = QUICK["cases"] if args.quick else tuple(CASES)
    bars = QUICK["bars"] if args.quick else BARS
    summaries, rows = [], []
    with env.one_thread():
        print("\n".join(env.environment()))
        for name in cases:
            for n in bars:
                summary, case_rows = measure(name, n, args.repeats)
                summaries.append(summary)
                rows += case_rows
                print({k: cell(v) for k, v in summary.items()})
    stem = output_stem(args.out, "cold_profile", args.quick)
    write_csv(summaries + rows, stem.with_suffix(".csv"))
    write_markdown(report(summaries, rows, args.repeats), stem.with_suffix(".md"))
    print(f"wrote {stem}.md")


if __name__ == "__main__":
    main()
