"""The command line's 3-D scenes: ``solve`` and ``insert`` (push, pull and turn), with JSON, figures, a GIF and an
interactive HTML view. Exit codes as :mod:`guidewire.app.cli`'s."""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ..march.insertion import TANGENTIAL_LIMIT_N
from ..solve3d.insert import insert3d
from ..solve3d.result import Solution3D
from ..solve3d.scene import Scene3D
from ..solve3d.solve import solve3d
from .parser import BadInput, check_output_dir, check_size, push_lengths, qp_solver_choice

EXIT_OK, EXIT_NOT_CONVERGED = 0, 1


def summary3d(sol: Solution3D, scene: Scene3D) -> str:
    """A few lines: outcome, energy split, iterations, time, the tip and the clamp's push and torque."""
    lines = [f"scene {scene.name!r}: {sol.n_bars} bars, 3-D",
             f"  {'converged' if sol.success else 'NOT converged'} (status {sol.status}): {sol.message}",
             f"  energy {sol.energy:.6g} N·mm (bending {sol.bending_energy:.6g}, twist {sol.twist_energy:.4g}), "
             f"{sol.iterations} iterations, {sol.solve_time_s:.3f} s"]
    if sol.success:
        tip = ", ".join(f"{v:.4g}" for v in sol.tip_point)
        lines += [f"  tip at ({tip}) mm, roll {math.degrees(sol.tip_roll):.1f}°",
                  f"  entrance push {sol.push:+.4g} N (= dE/dL; axial force {sol.entrance_force:+.4g} N), torque "
                  f"{sol.entrance_torque:+.4g} N·mm, "
                  f"{sum(f.kind == 'lumen' for f in sol.forces)} wall contacts"]
    else:
        lines.append("  no forces reported: multipliers mean forces only at a converged answer")
    return "\n".join(lines)


def solve_3d(args: argparse.Namespace, scene: Scene3D) -> int:
    """``python -m guidewire solve`` on a 3-D scene."""
    for flag in ("json", "plot", "html"):
        check_output_dir(getattr(args, flag), f"--{flag}")
    if args.bars is not None:
        scene = replace(scene, wire=replace(scene.wire, bars=args.bars, bar_lengths=None))
    try:
        sol = solve3d(scene, qp_solver=qp_solver_choice(args), tol=args.tol, max_iter=args.max_iter,
                      verbose=args.verbose)
    except (ValueError, TypeError) as exc:
        raise BadInput(f"{args.scene}: {exc}") from None
    print(summary3d(sol, scene))
    if args.json is not None:
        args.json.write_text(json.dumps(sol.to_dict(), indent=1))
    _figures(sol, scene, args.plot, args.html)
    return EXIT_OK if sol.success else EXIT_NOT_CONVERGED


def read_schedule(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Lengths (mm) and rotations (rad) of a schedule file: per line the inserted length (mm) and the clamp rotation
    (degrees), both absolute, separated by spaces or a comma; ``#`` starts a comment."""
    try:
        text = path.read_text()
    except OSError as exc:
        raise BadInput(f"--schedule {path}: {exc.strerror}") from None
    rows = []
    for number, line in enumerate(text.splitlines(), 1):
        line = line.split("#", 1)[0].replace(",", " ").strip()
        if not line:
            continue
        parts = line.split()
        try:
            values = [float(v) for v in parts]
        except ValueError:
            values = []
        if len(values) != 2 or not all(math.isfinite(v) for v in values) or values[0] <= 0.0:
            raise BadInput(f"--schedule {path}, line {number}: {line!r}; expected an inserted length (mm, > 0) and a "
                           "rotation (degrees), e.g. '12.5 90'")
        rows.append(values)
    if not rows:
        raise BadInput(f"--schedule {path} has no steps; write one 'length_mm rotation_deg' per line")
    table = np.array(rows)
    return table[:, 0], np.radians(table[:, 1])


def _steps(args: argparse.Namespace, scene: Scene3D) -> tuple[np.ndarray, np.ndarray]:
    if args.schedule is not None:
        if args.to is not None or args.step is not None or args.rotate is not None:
            raise BadInput("--schedule gives every step: leave out --to, --step and --rotate")
        return read_schedule(args.schedule)
    first, lengths = push_lengths(args, scene.wire.length, "give --to and --step (mm), or --schedule FILE")
    rate = 0.0 if args.rotate is None else math.radians(args.rotate)
    return lengths, scene.base.rotation + rate * (lengths - first)


def insert_3d(args: argparse.Namespace, scene: Scene3D) -> int:
    """``python -m guidewire insert`` on a 3-D scene: one line per step, then the outputs asked for."""
    lengths, rotations = _steps(args, scene)
    for flag in ("json", "plot", "gif", "html"):
        check_output_dir(getattr(args, flag), f"--{flag}")
    check_size(args, lengths, scene.wire.bars / scene.wire.length)
    report = None if args.quiet else _printer()
    try:
        out = insert3d(scene, lengths, rotations, qp_solver=qp_solver_choice(args), tol=args.tol,
                       max_iter=args.max_iter, progress=report)
    except (ValueError, TypeError) as exc:
        raise BadInput(f"{args.scene}: {exc}") from None
    if out.error is not None:
        print(f"stopped: {out.error}", file=sys.stderr)
    if args.json is not None:
        args.json.write_text(json.dumps(out.to_dict(), indent=1))
    if out.steps:
        _figures(out.steps[-1], scene, args.plot, args.html)
        if args.gif is not None:
            from .plot3d import save_animation3d

            save_animation3d(out, scene, args.gif)
    return EXIT_OK if out.complete else EXIT_NOT_CONVERGED


def _printer() -> Any:
    def report(sol: Solution3D, index: int, total: int) -> None:
        length = float(np.sum(sol.lengths))
        state = "ok" if sol.success else "FAILED"
        push = f"{sol.push:+.4g} N" if sol.success else "-"
        torque = f"{sol.entrance_torque:+.3g} N·mm" if sol.success else "-"
        print(f"[{index + 1}/{total}] L = {length:8.3f} mm  rot {math.degrees(sol.base_rotation):7.1f}°  {state:6s}  "
              f"E = {sol.energy:10.5g} N·mm  tip roll {math.degrees(sol.tip_roll):7.1f}°  push {push:>11s}  "
              f"torque {torque:>12s}  {sol.iterations:3d} it  {1e3 * sol.solve_time_s:7.1f} ms", flush=True)
        along = sol.tangential_contact_force()
        if abs(along) > TANGENTIAL_LIMIT_N:
            print(f"    ! contacts hold the wire along its length with {along:+.3g} N (node rows at an angle to it, as "
                  "at a branch's ridge; a frictionless wire has none)", flush=True)

    return report


def _figures(sol: Solution3D, scene: Scene3D, plot: Path | None, html: Path | None) -> None:
    if plot is not None:
        from .plot3d import plot_solution3d

        plot_solution3d(sol, scene).savefig(plot, dpi=130)
    if html is not None:
        from .plot3d import write_html

        write_html(sol, scene, html)
