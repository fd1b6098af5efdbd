"""Before/after timing of 3-D insertion steps: this tree against another commit's, in the same run, alternating.

What is measured
----------------
The same step sequences under two source trees (``--before DIR``: another commit's files, e.g. from
``git archive <commit> | tar -x -C DIR``; "after": this repository), each in its own child process that imports
``guidewire`` and ``sqp`` from its tree; children of the two trees alternate, ``--rounds`` times each, and every child
repeats its sequence ``--repeats`` times. Per step: CPU time of :func:`guidewire.solve3d.insert.advance` (process time,
less sensitive than wall time to other load on a shared machine; BLAS on one thread) and ``solve_time_s`` (wall),
medians over every repeat of every round; iterations; and the two trees' answers compared (relative energy gap,
largest node distance in mm).

Sequences: the straight 0.89 mm wire in the helix at 60 mm, resampled to ``n`` bars (each size carried from the
converged one before it, as :mod:`vessels3d` grows it) and pushed 0.5 mm three times; stEVE's J wire in the type I
aortic arch (``aortic_arch_I.toml``, 2 bars per mm) inserted to 120 mm in 2 mm steps, then pushed 2 mm three times
(244-252 bars: stEVE's size) and turned 15° twice. The converged start of each sequence is made once per tree and
cached in ``--cache``.

Usage: ``python benchmarks/vessels3d_ab.py --before DIR [--label TEXT] [--sizes 100 200 ...] [--rounds 3]
[--repeats 3]``; writes ``vessels3d_ab.{md,json}`` to ``--out`` (``--quick``: this tree against itself at 60 and 120
bars, ``vessels3d_ab_quick.*``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pickle
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import _environment as env  # noqa: I001  (first: pins BLAS threads before numpy loads)
import numpy as np
from _tables import markdown_table, output_stem, write_markdown

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
ARCH = ROOT / "guidewire" / "scenes" / "vessels3d" / "aortic_arch_I.toml"
SIZES = (100, 200, 400, 800, 1600, 3200)
QUICK_SIZES = (60, 120)


# -- the child: one tree, one sequence -----------------------------------------------------------------------------
def _helix_start(n: int, cache: Path, tag: str, sizes: tuple[int, ...]) -> tuple[Any, Any]:
    from guidewire import Wire
    from guidewire.solve3d import Scene3D
    from guidewire.solve3d.insert import advance, insert3d
    from guidewire.vessel3d.shapes import helix

    scene = Scene3D.in_vessel(Wire(length=10.0, bars=20, youngs_modulus=80000.0, diameter=0.89), helix())
    path = cache / f"{tag}_helix_{n}.pkl"
    if path.exists():
        return scene, pickle.loads(path.read_bytes())
    smaller = sorted(m for m in sizes if m < n)
    sol = (_helix_start(smaller[-1], cache, tag, sizes)[1] if smaller
           else insert3d(scene, np.arange(10.0, 60.5, 2.0)).steps[-1])
    sol = advance(scene, sol, 60.0, 0.0, n / 60.0, {})
    if not sol.success:
        raise RuntimeError(f"the {n}-bar start did not converge: {sol.message}")
    path.write_bytes(pickle.dumps(sol))
    return scene, sol


def _arch_start(cache: Path, tag: str) -> tuple[Any, Any]:
    import guidewire
    from guidewire.solve3d.insert import insert3d

    scene = guidewire.load_scene(ARCH)
    path = cache / f"{tag}_arch_120.pkl"
    if path.exists():
        return scene, pickle.loads(path.read_bytes())
    ins = insert3d(scene, np.arange(20.0, 120.1, 2.0))
    if not ins.complete:
        raise RuntimeError(f"the arch insertion stopped: {ins.error}")
    path.write_bytes(pickle.dumps(ins.steps[-1]))
    return scene, ins.steps[-1]


def child(case: str, repeats: int, cache: Path, tag: str, sizes: tuple[int, ...]) -> dict[str, Any]:
    """Time ``case``'s sequence ``repeats`` times under the tree on ``sys.path`` (``sizes``: the helix sizes, each
    start carried from the one below it)."""
    from guidewire.solve3d.insert import advance

    if case == "arch":
        scene, start = _arch_start(cache, tag)
        density = scene.wire.bar_density
        steps = [(122.0, 0.0), (124.0, 0.0), (126.0, 0.0), (126.0, 15.0), (126.0, 30.0)]
    else:
        n = int(case.split("_")[1])
        scene, start = _helix_start(n, cache, tag, sizes)
        density = n / 60.0
        steps = [(60.5, 0.0), (61.0, 0.0), (61.5, 0.0)]
    cpu: list[list[float]] = [[] for _ in steps]
    wall: list[list[float]] = [[] for _ in steps]
    answers: list[dict[str, Any]] = []
    for r in range(repeats + 1):  # (the first pass warms caches and imports: not timed)
        sol = start
        for k, (length, degrees) in enumerate(steps):
            t = time.process_time()
            sol = advance(scene, sol, length, math.radians(degrees), density, {})
            if r:
                cpu[k].append(time.process_time() - t)
                wall[k].append(sol.solve_time_s)
            if r == repeats:
                answers.append({"energy": sol.energy, "nodes": sol.nodes.tolist(), "iterations": sol.iterations,
                                "success": bool(sol.success), "bars": sol.n_bars})
    return {"cpu": cpu, "wall": wall, "answers": answers}


# -- the parent: alternate the trees -------------------------------------------------------------------------------
def run_child(tree: Path, case: str, repeats: int, cache: Path, tag: str, sizes: list[int]) -> dict[str, Any]:
    environ = dict(os.environ, PYTHONPATH=f"{tree}{os.pathsep}{HERE}")
    out = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--child", case, "--repeats", str(repeats),
                          "--cache", str(cache), "--tag", tag, "--sizes", *map(str, sizes)], env=environ,
                         capture_output=True, text=True, check=True, cwd=HERE)
    return json.loads(out.stdout.strip().splitlines()[-1])


def compare(case: str, before: list[dict[str, Any]], after: list[dict[str, Any]]) -> dict[str, Any]:
    """Medians of each tree over all rounds (per step, then over steps) and the answers' gaps."""
    def med(runs: list[dict[str, Any]], key: str) -> float:
        per_step = [np.median(np.concatenate([run[key][k] for run in runs])) for k in range(len(runs[0][key]))]
        return 1e3 * float(np.median(per_step))

    a, b = before[-1]["answers"], after[-1]["answers"]
    gap_e = max(abs(x["energy"] - y["energy"]) / max(abs(x["energy"]), 1e-300) for x, y in zip(a, b, strict=True))
    gap_n = max(float(np.max(np.abs(np.array(x["nodes"]) - np.array(y["nodes"])))) for x, y in zip(a, b, strict=True))
    return {"case": case, "bars": b[0]["bars"], "before_ms": med(before, "cpu"), "after_ms": med(after, "cpu"),
            "before_wall_ms": med(before, "wall"), "after_wall_ms": med(after, "wall"),
            "iterations_before": [x["iterations"] for x in a], "iterations_after": [x["iterations"] for x in b],
            "all_success": all(x["success"] for x in a + b), "energy_gap": gap_e, "node_gap_mm": gap_n}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", type=Path, help="source tree of the commit to compare against (--quick: this one)")
    ap.add_argument("--label", help="what the before tree is (default: its path), for the table's header")
    ap.add_argument("--sizes", type=int, nargs="+", default=None, help=f"helix bar counts (default {SIZES})")
    ap.add_argument("--quick", action="store_true", help="this tree against itself, 60 and 120 bars, once each")
    ap.add_argument("--no-arch", action="store_true", help="helix sizes only")
    ap.add_argument("--rounds", type=int, default=3, help="alternating child runs per tree")
    ap.add_argument("--repeats", type=int, default=3, help="repeats of the sequence in each child")
    ap.add_argument("--cache", type=Path, default=None, help="where the converged starts are kept (default: a "
                    "new temporary directory; a kept one must be emptied when either tree changes)")
    ap.add_argument("--out", type=Path, default=HERE / "results")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    ap.add_argument("--tag", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        print(json.dumps(child(args.child, args.repeats, args.cache, args.tag, tuple(args.sizes))))
        return
    if args.quick:
        args.before, args.label, args.no_arch = ROOT, "this tree (--quick)", True
        args.sizes, args.rounds, args.repeats = args.sizes or list(QUICK_SIZES), 1, 1
    if args.before is None:
        ap.error("--before DIR is required (a source tree of the commit to compare against)")
    args.sizes = sorted(args.sizes or SIZES)
    args.cache = args.cache or Path(tempfile.mkdtemp(prefix="vessels3d_ab_"))
    args.cache.mkdir(parents=True, exist_ok=True)
    cases = [f"helix_{n}" for n in args.sizes] + ([] if args.no_arch else ["arch"])
    rows = []
    for case in cases:
        runs: dict[str, list[dict[str, Any]]] = {"before": [], "after": []}
        for _ in range(args.rounds):
            for tag, tree in (("before", args.before), ("after", ROOT)):
                runs[tag].append(run_child(tree.resolve(), case, args.repeats, args.cache, tag, args.sizes))
        rows.append(compare(case, runs["before"], runs["after"]))
        r = rows[-1]
        print(f"{case}: {r['bars']} bars, before {r['before_ms']:.1f} ms, after {r['after_ms']:.1f} ms "
              f"({r['before_ms'] / r['after_ms']:.2f}x), energy gap {r['energy_gap']:.1e}, "
              f"nodes {r['node_gap_mm']:.1e} mm", flush=True)
    stem = output_stem(args.out, "vessels3d_ab", args.quick)
    stem.parent.mkdir(parents=True, exist_ok=True)
    stem.with_suffix(".json").write_text(json.dumps(rows, indent=1))
    lines = ["# 3-D steps before and after (same run, alternating)", "",
             *(f"- {line}" for line in env.environment(guidewire=False)),
             f"- before: {args.label or f'the tree at `{args.before}`'}; after: this repository", "",
             f"CPU ms per step (process time), median over {args.rounds} alternating child runs per tree x "
             f"{args.repeats} repeats of each sequence, per step and then over the steps; wall ms the same way "
             "(`solve_time_s`).", ""]
    lines += markdown_table(
        ["case", "bars (first step)", "before ms", "after ms", "speed-up", "before wall ms", "after wall ms",
         "iterations before", "iterations after", "all solved", "energy gap (rel.)", "node gap mm"],
        [[r["case"], r["bars"], r["before_ms"], r["after_ms"], r["before_ms"] / r["after_ms"], r["before_wall_ms"],
          r["after_wall_ms"], " ".join(map(str, r["iterations_before"])), " ".join(map(str, r["iterations_after"])),
          r["all_success"], r["energy_gap"], r["node_gap_mm"]] for r in rows])
    helix = [r for r in rows if r["case"].startswith("helix")]
    if len(helix) >= 2:
        for key, name in (("before_ms", "before"), ("after_ms", "after")):
            slope = np.polyfit(np.log([r["bars"] for r in helix]), np.log([r[key] for r in helix]), 1)[0]
            lines.append(f"\nFitted growth {name}: time ∝ n^{slope:.2f} over {helix[0]['bars']}…{helix[-1]['bars']} "
                         "bars (helix).")
    write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
