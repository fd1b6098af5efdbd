"""Where a warm insertion step's time goes, phase by phase: the profile behind the missed per-step speed goals.

What is measured
----------------
Three insertions, each run twice, BLAS on one thread:

- *planar*: the shipped aortic arch (1 bar per mm) pushed from 5 mm to 250 mm in 1 mm steps (``vessels.py``'s
  insertion), by :func:`guidewire.insert`;
- *planar, fine*: the tortuous vessel at 25 bars per mm (1 000-1 200 bars) pushed from 40 mm to 48 mm in 1 mm steps
  (``vessels.py``'s ~1 000-bar case);
- *3-D*: stEVE's J wire in the type I arch at 2 bars per mm, pushed 20 → 120 mm in 2 mm steps and then turned
  (``vessels3d.py``'s case), by :func:`guidewire.solve3d.insert.insert3d`.

The first run is plain: the wall time per step (the median and the mean over the steps after the first). The second
runs under :mod:`cProfile`, whose cumulative times of named functions split the steps into phases: each phase's
share of the profiled steps is applied to the plain run's mean step (the profiler slows Python-level code more than
compiled code, so the split is an estimate; the shares, not the profiled milliseconds, are what carries over). Phases
nest only where the table says so (*of which*). Counts: iterations, Python function calls and sparse matrices built
(``scipy.sparse`` compressed-matrix constructions) per step, the profiled run's first step included.

Goals this explains (vessel and 3-D issues): planar insertion steps ≤ 1 ms median at 100 bars and ≤ 3 ms at 1 000
bars, the 250 mm arch insertion ≤ 0.5 s; a 3-D step ≤ 5 ms median at stEVE's size (~240 bars).

Usage: ``python benchmarks/step_profile.py [--quick] [--out DIR]``; writes ``step_profile.{md,csv}``
(``_quick`` with ``--quick``: shorter insertions).
"""

from __future__ import annotations

import cProfile
import pstats
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import _environment as env  # noqa: I001  (first: pins BLAS threads before numpy loads)
import numpy as np
from _arguments import parse, parser
from _tables import cell, markdown_table, output_stem, write_csv, write_markdown

import guidewire
from guidewire.solve3d.insert import insert3d

VESSELS = Path(__file__).resolve().parents[1] / "guidewire" / "scenes" / "vessels"

#: (phase, [(file suffix, function name), ...] whose cumulative times add up to it, the phase it is part of or "").
Phase = tuple[str, list[tuple[str, str]], str]

SQP_PHASES: list[Phase] = [
    ("sqp set-up (checks, first evaluation)", [("sqp/build.py", "build_problem")], ""),
    ("model Hessian (Lagrangian, convexified)", [("sqp/hessian_strategy.py", "model")], ""),
    ("QP subproblems", [("sqp/solver.py", "subproblem")], ""),
    ("line search (trial points, derivatives)", [("sqp/linesearch.py", "merit_search")], ""),
]

PLANAR_PHASES: list[Phase] = [
    ("predictor (tracked start, multipliers)", [("guidewire/march/insertion.py", "_tracked_angles"),
                                                ("guidewire/march/insertion.py", "_tracked_multipliers")], ""),
    ("formulate (model, lumen rows)", [("guidewire/program/formulation.py", "formulate")], ""),
    *SQP_PHASES,
    ("working-set refinement", [("guidewire/blocks/lumen.py", "refine"), ("guidewire/blocks/wall.py", "refine")], ""),
    ("answer and its checks", [("guidewire/solve/result.py", "build_solution")], ""),
    ("vessel queries (closest points)", [("guidewire/vessel/geometry.py", "get")], "all phases"),
]

SPATIAL_PHASES: list[Phase] = [
    ("predictor (tracked frames, multipliers)", [("guidewire/solve3d/insert.py", "tracked_frames"),
                                                 ("guidewire/solve3d/insert.py", "tracked_multipliers")], ""),
    ("program build", [("guidewire/solve3d/program.py", "build")], ""),
    *SQP_PHASES,
    ("answer (frames, forces, checks)", [("guidewire/solve3d/solve.py", "answer")], ""),
    ("lumen rows (closest tube points)", [("guidewire/vessel3d/vessel.py", "lumen_rows")], "sqp phases"),
    ("strain energy and derivatives", [("guidewire/rod/strain_energy.py", "evaluate"),
                                       ("guidewire/rod/strain_energy.py", "values")], "sqp phases"),
]

SPARSE_INIT = ("scipy/sparse/_compressed.py", "__init__")


def fresh_insertion(start: guidewire.Scene, lengths: Any) -> list[Any]:
    """The steps of ``guidewire.insert(start, lengths)`` run as the first time: the vessel's kept query answers
    dropped first (the run before left its last ones)."""
    start.vessel.forget_queries()
    return list(guidewire.insert(start, lengths).steps)


def planar(quick: bool) -> tuple[Callable[[], list[Any]], list[Phase]]:
    """The planar insertion (a callable returning its steps) and its phases."""
    scene = guidewire.load_scene(VESSELS / "aortic_arch.toml")
    lengths = np.arange(5.0, (60.0 if quick else 250.0) + 0.5, 1.0)
    start = scene.with_wire(length=5.0, bars=scene.wire.bars_at(5.0))
    return (lambda: fresh_insertion(start, lengths)), PLANAR_PHASES


def planar_fine(quick: bool) -> tuple[Callable[[], list[Any]], list[Phase]]:
    """The ~1 000-bar planar insertion (``vessels.py``'s fine tortuous case: 40 → 48 mm at 25 bars per mm) and its
    phases."""
    scene = guidewire.load_scene(VESSELS / "tortuous.toml")
    lengths = 40.0 + np.arange((3 if quick else 8) + 1.0)
    start = scene.with_wire(length=40.0, bars=round(40.0 * 25.0))
    return (lambda: fresh_insertion(start, lengths)), PLANAR_PHASES


def spatial(quick: bool) -> tuple[Callable[[], list[Any]], list[Phase]]:
    """The 3-D insertion (a callable returning its steps) and its phases."""
    import vessels3d

    name, scene, lengths, turns = vessels3d.cases(quick, 2.0)[3]
    return (lambda: list(insert3d(scene, lengths, turns).steps)), SPATIAL_PHASES


def cumulative(stats: pstats.Stats, names: list[tuple[str, str]]) -> float:
    """The summed cumulative time (s) of the functions ``names`` ((file suffix, function name) pairs)."""
    total = 0.0
    for (file, _, function), (_, _, _, cum, _) in stats.stats.items():  # type: ignore[attr-defined]
        if any(file.endswith(suffix) and function == name for suffix, name in names):
            total += cum
    return total


def calls(stats: pstats.Stats, names: list[tuple[str, str]]) -> int:
    """How many times the functions ``names`` were called (primitive calls)."""
    return sum(cc for (file, _, function), (cc, *_rest) in stats.stats.items()  # type: ignore[attr-defined]
               if any(file.endswith(suffix) and function == name for suffix, name in names))


def phase_rows(stats: pstats.Stats, phases: list[Phase], label: str, profiled_s: float, plain_ms: float,
               whole: str, unit: str) -> list[dict[str, Any]]:
    """A row per phase (its share of the ``profiled_s`` seconds the profiler saw, cumulative times, and that share of
    ``plain_ms``, the plain run's time per unit, under the key ``unit``), then the rest of ``whole`` as *other*."""
    rows = []
    for name, names, part_of in phases:
        share = cumulative(stats, names) / profiled_s
        rows.append({"case": label, "phase": name, "part of": part_of or whole, "share": share,
                     unit: share * plain_ms})
    top = sum(r["share"] for r in rows if r["part of"] == whole)
    rows.append({"case": label, "phase": "other (glue, solution objects)", "part of": whole,
                 "share": max(0.0, 1.0 - top), unit: max(0.0, 1.0 - top) * plain_ms})
    return rows


def profile_case(label: str, make: Callable[[bool], tuple[Callable[[], list[Any]], list[Phase]]],
                 quick: bool) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """One insertion, plain and profiled: a row per phase and the case's summary."""
    run, phases = make(quick)
    run()  # (warm-up: imports, caches)
    steps = run()
    times = np.array([s.solve_time_s for s in steps[1:]])
    iterations = np.array([s.iterations for s in steps[1:]])
    profiler = cProfile.Profile()
    wall = time.perf_counter()
    profiler.enable()
    profiled_steps = run()
    profiler.disable()
    profiled = time.perf_counter() - wall
    stats = pstats.Stats(profiler)
    n_steps = len(profiled_steps)
    mean_ms = 1e3 * float(np.mean(times))
    per_step = profiled / n_steps
    rows = phase_rows(stats, phases, label, n_steps * per_step, mean_ms, "step", "ms per step")
    summary = {"case": label, "steps": len(steps), "bars (last)": steps[-1].n_bars,
               "median ms per step": 1e3 * float(np.median(times)), "mean ms per step": mean_ms,
               "median iterations": float(np.median(iterations)), "mean iterations": float(np.mean(iterations)),
               "mean ms, steps with 0 iterations": (1e3 * float(np.mean(times[iterations == 0]))
                                                    if np.any(iterations == 0) else float("nan")),
               "Python calls per step": stats.total_calls / n_steps,  # type: ignore[attr-defined]
               "sparse matrices built per step": calls(stats, [SPARSE_INIT]) / n_steps}
    return rows, summary


def report(rows: list[dict[str, Any]], summaries: list[dict[str, Any]]) -> list[str]:
    keys = list(summaries[0])
    lines = ["# Where a warm insertion step's time goes", "", *(f"- {item}" for item in env.environment()), "",
             "Each phase's share of the profiled steps (cProfile's cumulative times) applied to the plain run's mean "
             "step; *part of* says where a phase nests. See the script's docstring.", ""]
    lines += markdown_table(keys, [[cell(s[k]) for k in keys] for s in summaries])
    lines += ["", "## Phases", ""]
    cols = ["case", "phase", "part of", "share", "ms per step"]
    lines += markdown_table(cols, [[r["case"], r["phase"], r["part of"], f"{100 * r['share']:.1f} %",
                                    cell(r["ms per step"])] for r in rows])
    return lines


def main() -> None:
    ap = parser(__doc__, quick_help="shorter insertions", repeats=1)
    args = parse(ap)
    with env.one_thread():
        print("\n".join(env.environment()))
        rows, summaries = [], []
        for label, make in (("planar arch, 1 bar/mm", planar), ("planar tortuous, 25 bars/mm", planar_fine),
                            ("3-D arch I, stEVE's J wire", spatial)):
            case_rows, summary = profile_case(label, make, args.quick)
            rows += case_rows
            summaries.append(summary)
            print(summary)
    stem = output_stem(args.out, "step_profile", args.quick)
    write_csv(rows, stem.with_suffix(".csv"))
    write_markdown(report(rows, summaries), stem.with_suffix(".md"))
    print(f"wrote {stem}.md")


if __name__ == "__main__":
    main()
