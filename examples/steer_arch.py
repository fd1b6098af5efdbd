"""Steer stEVE's J wire into each supra-aortic branch of the type I arch by pushing and turning it, and write what
worked as schedule files and figures.

The three branches leave the outer (upper) wall of the arch; from the descending-aorta entrance the wire meets the
left subclavian first (its ostium 218 mm along the aorta), then the left common carotid (246 mm) and the
brachiocephalic trunk (262 mm, on the ascending limb). The last two leave pointing back over the arch, about 145
and 165 degrees from the way the wire travels there. The search is this clinician's manoeuvre, in four phases:

1. approach: push at clamp rotation 0 to :data:`APPROACH_SHORT` mm short of the first ostium. At 0 the J points at
   the outer wall (its tip tangent has +0.64 upward there).
2. the first branch (left subclavian): push on at 0; the J drops into the first ostium it meets.
3. pass: for a later branch, turn the clamp to one of :data:`PASS_ROTATIONS` (the J then points along the arch,
   away from the ostia) and push on past the ostia before the target (tried by hand: at 90 degrees the tip still
   enters the left subclavian).
4. hook: once the tip is within :data:`HOOK_FROM` mm of the target's ostium, after each push step, turn the clamp
   back to :data:`HOOK_ROTATION` (the J swings up to the outer wall and into the ostium) and push on until the tip
   is :data:`GOAL` mm deep. A hook that ends in another branch, or not :data:`DEPTH` mm deep and heading in, is
   abandoned and the pass goes on.

A schedule reaches the branch when the tip ends more than :data:`DEPTH` mm along the branch inside its tube and its
tangent heads into the branch (pushed at 180 degrees the tip slides down the ascending aorta to the trunk's mouth,
where the trunk's wide tube holds it 15 mm "deep" while it points down: not counted). The first schedule found is
written to ``examples/steer_<branch>.txt`` (``length_mm rotation_deg`` per line: the command line's ``--schedule``
format) with a figure ``examples/images/steer_<branch>.png``.

Found at the scene's 2 bars per mm (452-536 bars at the end), each with the first pass rotation (180) and its first
hook: the left common carotid hooked at 232 mm (tip 32 mm deep at 242 mm), the brachiocephalic trunk at 258 mm
(tip 29 mm deep at 268 mm, 15 mm beyond the aorta's wall); the left subclavian by pushing at 0 to 226 mm (25 mm
deep). For the trunk an earlier hook fails: turned back at 236 mm the J snaps into the left common carotid (checked by
hand). These schedules were found before the lumen had its creases (:mod:`guidewire.vessel3d.crease`: the rims of the
branches' openings, over which the wire now slides where the tubes' own rows held it lengthwise); replayed with them,
all three still reach their branches (the tips 28, 34 and 40 mm in) and are kept (the tests, benchmarks and figures
replay them). Run again (session 16), the search finds all three: the left subclavian at 222 mm (102 steps), the
left common carotid hooked at 240 mm (250 mm, 140 steps), and — since a pass may dip :data:`PASS_DIP` mm into an
ostium before the target and come out, as the committed trunk schedule does (15.5 mm into the left common carotid at
238 mm) — the trunk hooked at 288 mm (tip 37 mm in at 298 mm, 164 steps; without the dip every pass was given up
there). On that trunk schedule one step (274 mm, clamp at 180 degrees, the tip sliding down the ascending aorta past
the trunk's mouth) has a node of the wire on the aorta's wall just beside the trunk's rim, outside the crease's
cone, pressed with 1.07 N of which 0.51 N along the wire (the polyline kinks over the rim at that node); the
committed schedules stay within 10 mN at every step.

Usage: ``python examples/steer_arch.py [--branches NAME ...]`` (BLAS pinned to one thread). Replay from the
repository root::

    python -m guidewire insert guidewire/scenes/vessels3d/aortic_arch_I.toml \
        --schedule examples/steer_left_common_carotid.txt --plot lcca.png
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
APPROACH_SHORT = 18.0
"""The wire is pushed at rotation 0 until its length is this far (mm) short of the first ostium's arc length."""
PASS_ROTATIONS = (180.0, 150.0, 210.0)
"""Clamp rotations (degrees) tried, in order, to carry the tip past the ostia before the target: at 0 the J points
to the outer wall, where the branches leave (and enters the first one); at 180 it points along the arch, away from
them."""
HOOK_ROTATION = 0.0
"""The clamp rotation that turns the J back toward the outer wall, into the target's ostium."""
HOOK_FROM = 16.0
"""Hooks are tried once the tip is this close (mm of aorta) to the target's ostium, after every push step."""
HOOK_TRIES = 8
PUSH_STEP, TURN_STEP = 2.0, 15.0
MIN_PUSH, MAX_PUSH = 10.0, 40.0
"""After the hook the wire is pushed at least MIN_PUSH and at most MAX_PUSH mm, until the tip is GOAL mm deep."""
DEPTH, GOAL = 10.0, 25.0
"""A tip more than DEPTH mm (along the branch) inside the branch's tube and heading into it has entered it; pushing
stops at GOAL mm."""
PASS_DIP = 20.0
"""While passing, the J may dip this deep (mm along the branch) into an ostium before the target and come out as the
wire is pushed on; deeper, the pass is given up."""
TRIAL_SECONDS = 150.0
"""A pass or hook trial that takes longer than this is abandoned."""

Step = tuple[float, float]


def ostium_arc_length(vessel: Vessel3D, index: int) -> float:
    """Arc length (mm) along the main centreline of where branch ``index - 1`` leaves (its first point's nearest
    main-centreline sample; a branch of a branch: its parent's ostium)."""
    start = np.asarray(vessel.branches[index - 1].centreline[0])
    line = vessel.centrelines(0.5)[0]
    return float(_arc(line)[int(np.argmin(np.linalg.norm(line - start, axis=1)))])


def _arc(line: np.ndarray) -> np.ndarray:
    return np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(line, axis=0), axis=1))))


def tip_place(vessel: Vessel3D, sol: guidewire.Solution3D) -> tuple[int, float, float]:
    """The tube the tip is in (index into ``tube_names``), the arc length (mm) of the nearest centreline sample of
    that tube, and the cosine between the tip's tangent and that tube's centreline there (> 0: heading on)."""
    tip = sol.nodes[-1]
    index = int(vessel.tube_of(tip[None])[0])
    line = vessel.centrelines(0.5)[index]
    k = int(np.argmin(np.linalg.norm(line - tip, axis=1)))
    along = line[min(k + 1, len(line) - 1)] - line[max(k - 1, 0)]
    return index, float(_arc(line)[k]), float(sol.frames[-1, 2] @ along / np.linalg.norm(along))


def run(scene: guidewire.Scene3D, steps: list[Step], density: float, start: guidewire.Solution3D,
        stop=None) -> tuple[guidewire.Solution3D, list[Step], bool]:
    """Solve ``steps`` from ``start`` (each warm-started from the last); stop after a step that fails or for which
    ``stop(solution)`` is true, or after :data:`TRIAL_SECONDS`. Returns the last solution, the steps solved and
    whether all of them succeeded."""
    sol, done, began = start, [], time.perf_counter()
    for length, degrees in steps:
        sol = advance(scene, sol, length, np.radians(degrees), density, {})
        done.append((length, degrees))
        if not sol.success:
            return sol, done, False
        if (stop is not None and stop(sol)) or time.perf_counter() - began > TRIAL_SECONDS:
            break
    return sol, done, True


def turn(length: float, start: float, end: float) -> list[Step]:
    """The clamp turned from ``start`` to ``end`` (degrees) in :data:`TURN_STEP` steps at ``length``."""
    count = int(np.ceil(abs(end - start) / TURN_STEP - 1e-9))
    return [(length, float(a)) for a in np.linspace(start, end, count + 1)[1:]]


def push(start: float, distance: float, degrees: float) -> list[Step]:
    return [(float(x), degrees) for x in np.arange(start + PUSH_STEP, start + distance + 1e-9, PUSH_STEP)]


def search(scene: guidewire.Scene3D, target: str) -> tuple[list[Step], guidewire.Solution3D] | None:
    """Approach, (pass, hook,) push on: the first schedule whose tip ends :data:`GOAL` mm (at least :data:`DEPTH`)
    inside ``target``, heading in."""
    vessel = scene.vessel
    index = vessel.tube_names.index(target)
    density = scene.wire.bar_density
    ostia = {name: ostium_arc_length(vessel, vessel.tube_names.index(name)) for name in TARGETS}
    to = PUSH_STEP * np.floor((min(ostia.values()) - APPROACH_SHORT) / PUSH_STEP)
    approach = push(scene.wire.length, to - scene.wire.length, 0.0)
    base, approach, ok = run(scene, approach, density, guidewire.solve3d(scene))
    if not ok:
        print(f"  {target}: the approach to {to:.0f} mm failed: {base.message}")
        return None

    def depth_in_target(sol: guidewire.Solution3D) -> float:
        tube, s, heading = tip_place(vessel, sol)
        return s if tube == index and heading > 0.0 else -1.0

    def lost(sol: guidewire.Solution3D) -> bool:  # deep in a branch that is not the target
        tube, s, _ = tip_place(vessel, sol)
        return tube not in (0, index) and s > DEPTH

    def push_on(sol: guidewire.Solution3D, degrees: float) -> tuple[guidewire.Solution3D, list[Step], bool]:
        length = float(np.sum(sol.lengths))
        pushed, done = sol, []
        for step in push(length, MAX_PUSH, degrees):
            pushed, more, ok = run(scene, [step], density, pushed)
            done += more
            if not ok or lost(pushed):
                return pushed, done, False
            if step[0] - length >= MIN_PUSH - 1e-9 and depth_in_target(pushed) >= GOAL:
                break
        return pushed, done, depth_in_target(pushed) > DEPTH

    if ostia[target] == min(ostia.values()):  # the first branch: the J already points at the outer wall
        sol, steps, ok = push_on(base, 0.0)
        report(vessel, target, "push at 0°", sol, ok)
        return (approach + steps, sol) if ok else None
    for passing in PASS_ROTATIONS:
        turned, turning, ok = run(scene, turn(to, 0.0, passing), density, base)
        if not ok:
            continue
        sol, steps, hooks = turned, approach + turning, 0
        while hooks < HOOK_TRIES:
            tube, s, _ = tip_place(vessel, sol)
            if tube == 0 and s >= ostia[target] - HOOK_FROM:
                hooks += 1
                length = float(np.sum(sol.lengths))
                hooked, twist, ok = run(scene, turn(length, passing, HOOK_ROTATION), density, sol)
                if ok and not lost(hooked):
                    final, more, ok = push_on(hooked, HOOK_ROTATION)
                    report(vessel, target, f"pass at {passing:g}°, hook at {length:g} mm", final, ok)
                    if ok:
                        return steps + twist + more, final
                else:
                    report(vessel, target, f"pass at {passing:g}°, hook at {length:g} mm (the turn)", hooked, False)
            elif tube != 0 and tube != index and s > PASS_DIP or s > ostia[target] + DEPTH and tube == 0:
                break  # the tip went deep into another branch, or past the ostium
            sol, more, ok = run(scene, push(float(np.sum(sol.lengths)), PUSH_STEP, passing), density, sol)
            steps += more
            if not ok:
                break
        tube, s, _ = tip_place(vessel, sol)
        print(f"  {target}: passing at {passing:g}° ends with the tip in {vessel.tube_names[tube]} at {s:.0f} mm",
              flush=True)
    return None


def report(vessel: Vessel3D, target: str, what: str, sol: guidewire.Solution3D, ok: bool) -> None:
    tube, s, heading = tip_place(vessel, sol)
    print(f"  {target}: {what}, pushed to {np.sum(sol.lengths):g} mm -> tip {s:.0f} mm into "
          f"{vessel.tube_names[tube]} (heading {heading:+.2f}){'' if ok else ': no'}", flush=True)


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
            print(f"{target}: no schedule found ({len(PASS_ROTATIONS)} passing turns, {HOOK_TRIES} hooks each)")
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
