"""Steer stEVE's J wire into each supra-aortic branch of the type I arch by pushing and turning it, and write what
worked as schedule files and figures.

For each target branch the search pushes the wire up the descending aorta to a few lengths short of the branch's
ostium (its arc length along the aorta), turns the clamp there to each of a set of angles, then pushes on; a schedule
reaches the branch when the tip ends more than :data:`DEPTH` mm inside the branch's tube. The first schedule found
(the shortest turn first) is written to ``examples/steer_<branch>.txt`` (``length_mm rotation_deg`` per line: the
command line's ``--schedule`` format) with a figure ``examples/images/steer_<branch>.png``.

Usage: ``python examples/steer_arch.py [--branches NAME ...]`` (a few minutes; BLAS pinned to one thread). Replay
from the repository root::

    python -m guidewire insert guidewire/scenes/vessels3d/aortic_arch_I.toml \
        --schedule examples/steer_left_subclavian.txt
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import guidewire  # noqa: E402
from guidewire.app.plot3d import plot_solution3d  # noqa: E402
from guidewire.solve3d.insert import advance  # noqa: E402
from guidewire.vessel3d import Vessel3D  # noqa: E402

HERE = Path(__file__).resolve().parent
SCENE = HERE.parent / "guidewire" / "scenes" / "vessels3d" / "aortic_arch_I.toml"
TARGETS = ("left_subclavian", "left_common_carotid", "brachiocephalic")
ANGLES = tuple(range(0, 360, 45))
"""Clamp rotations tried at the ostium (degrees)."""
SHORT_OF = (12.0, 4.0)
"""How far short of the ostium (mm of wire) the turn is made."""
PUSH_STEP, TURN_STEP = 2.0, 15.0
PUSH_ON = 40.0
"""How far the wire is pushed after the turn (mm)."""
DEPTH = 10.0
"""A tip this far (mm along the branch) inside the branch's tube has entered it."""


def ostium_arc_length(vessel: Vessel3D, index: int) -> float:
    """Arc length (mm) along the main centreline of where branch ``index - 1`` leaves (its first point's nearest
    main-centreline sample; a branch of a branch: its parent's ostium)."""
    start = np.asarray(vessel.branches[index - 1].centreline[0])
    line = vessel.centrelines(0.5)[0]
    arc = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(line, axis=0), axis=1))))
    return float(arc[int(np.argmin(np.linalg.norm(line - start, axis=1)))])


def run(scene: guidewire.Scene3D, steps: list[tuple[float, float]], density: float, start: guidewire.Solution3D):
    sol = start
    for length, degrees in steps:
        sol = advance(scene, sol, length, np.radians(degrees), density, {})
        if not sol.success:
            return sol, False
    return sol, True


def search(scene: guidewire.Scene3D, target: str) -> tuple[list[tuple[float, float]], guidewire.Solution3D] | None:
    vessel = scene.vessel
    index = vessel.tube_names.index(target)
    density = scene.wire.bars / scene.wire.length
    ostium = ostium_arc_length(vessel, index)
    first = scene.wire.length
    start = guidewire.solve3d(scene)
    for short in SHORT_OF:
        turn_at = ostium - short
        approach = [(float(x), 0.0) for x in np.arange(first + PUSH_STEP, turn_at + 1e-9, PUSH_STEP)]
        base, ok = run(scene, approach, density, start)
        if not ok:
            print(f"  {target}: the approach to {turn_at:.0f} mm failed: {base.message}")
            continue
        for angle in sorted(ANGLES, key=lambda a: min(a, 360 - a)):
            sign = 1.0 if angle <= 180 else -1.0
            turns = [(approach[-1][0], sign * float(a)) for a in np.arange(TURN_STEP, min(angle, 360 - angle) + 1e-9,
                                                                           TURN_STEP)]
            final = turns[-1][1] if turns else 0.0
            push = [(float(x), final) for x in np.arange(approach[-1][0] + PUSH_STEP, turn_at + PUSH_ON + 1e-9,
                                                          PUSH_STEP)]
            sol, ok = run(scene, turns + push, density, base)
            tube = vessel.tube_names[int(vessel.tube_of(sol.nodes[-1:])[0])]
            print(f"  {target}: turn {final:+5.0f}° at {turn_at:5.1f} mm -> tip in {tube}{'' if ok else ' (failed)'}",
                  flush=True)
            if ok and tube == target and _depth(vessel, index, sol.nodes[-1]) > DEPTH:
                return approach + turns + push, sol
    return None


def _depth(vessel: Vessel3D, index: int, point: np.ndarray) -> float:
    """Arc length (mm) along the branch's centreline of the point nearest ``point``."""
    line = vessel.centrelines(0.5)[index]
    arc = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(line, axis=0), axis=1))))
    return float(arc[int(np.argmin(np.linalg.norm(line - point, axis=1)))])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--branches", nargs="+", default=list(TARGETS), choices=TARGETS)
    args = ap.parse_args()
    scene = guidewire.load_scene(SCENE)
    (HERE / "images").mkdir(exist_ok=True)
    for target in args.branches:
        began = time.perf_counter()
        found = search(scene, target)
        if found is None:
            print(f"{target}: no schedule found among {len(ANGLES)} turns x {len(SHORT_OF)} places")
            continue
        steps, sol = found
        path = HERE / f"steer_{target}.txt"
        lines = [f"# stEVE's J wire into the {target.replace('_', ' ')} of the type I arch (examples/steer_arch.py)",
                 "# length_mm rotation_deg", f"{scene.wire.length:g} 0"]
        lines += [f"{length:g} {degrees:g}" for length, degrees in steps]
        path.write_text("\n".join(lines) + "\n")
        plot_solution3d(sol, scene, title=f"J wire into the {target.replace('_', ' ')}").savefig(
            HERE / "images" / f"steer_{target}.png", dpi=110)
        print(f"{target}: {len(steps) + 1} steps, {time.perf_counter() - began:.0f} s -> {path.name}")


if __name__ == "__main__":
    main()
