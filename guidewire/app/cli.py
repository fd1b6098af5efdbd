"""Command line: ``python -m guidewire solve SCENE.toml``, ``python -m guidewire insert SCENE.toml --to L --step DL``
and ``python -m guidewire paper --out DIR``.

Exit status: 0 success; 1 the solver did not converge (the JSON is still written; its ``status``/``message`` say
why) or, for ``paper``, some feasible scene did not converge; 2 bad input (one line on stderr, no traceback), checked
before any solve (including a ``--plot`` file type matplotlib cannot write and an unknown ``--qp-solver``).

When stdout is a pipe that closes early (``python -m guidewire solve SCENE | head -1``) the run ends quietly, as the
Python documentation recommends (stdout redirected to ``os.devnull``): the exit status is the command's when it had
finished, else 1.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..solve3d.file import load_scene
from ..solve3d.scene import Scene3D
from .cli3d import insert_3d, solve_3d
from .parser import BadInput, build_parser, check_output_dir, check_size, push_lengths, qp_solver_choice

if TYPE_CHECKING:
    from ..scene.scene import Scene
    from ..solve.result import Solution

EXIT_OK, EXIT_NOT_CONVERGED, EXIT_BAD_INPUT = 0, 1, 2


def _summary(sol: Solution) -> str:
    """A few lines: outcome, energy, iterations, time, peak stress, support reactions."""
    lines = [
        f"scene {sol.scene.name!r}: {sol.n_bars} bars, scheme {sol.scheme}",
        f"  {'converged' if sol.success else 'NOT converged'} (status {sol.status}): {sol.message}",
        f"  energy {sol.energy:.6g} N·mm, {sol.iterations} iterations"
        + (f" (from the answer at {' then '.join(map(str, sol.coarse_bars))} bars)" if sol.coarse_bars else "")
        + f", {sol.solve_time_s:.3f} s, max violation {sol.max_violation:.2e}",
        f"  max bending stress {sol.bending_stress_mpa.max():.4g} MPa "
        f"at s = {sol.s[sol.bending_stress_mpa.argmax()]:.4g} mm",
    ]
    for r in sol.reactions:
        force = "" if r.force is None else f" force ({r.force[0]:+.4g}, {r.force[1]:+.4g}) N"
        moment = "" if r.moment is None else f" moment {r.moment:+.4g} N·mm"
        lines.append(f"  {r.kind} {r.name} at s = {r.s:g}:{force}{moment}")
    if not sol.success:
        lines.append("  no forces reported: multipliers mean forces only at a converged answer")
    if sol.scene.walls and sol.wall_forces is not None:
        magnitude = np.hypot(*sol.wall_forces.T)
        lines.append(f"  walls push {magnitude.sum():.4g} N in total on {int((magnitude > 0).sum())} nodes")
    return "\n".join(lines)


def _load(path: Path) -> Scene:
    try:
        return load_scene(path)
    except FileNotFoundError:
        raise BadInput(f"{path}: no such scene file") from None
    except OSError as exc:
        raise BadInput(f"{path}: {exc.strerror}") from None
    except ValueError as exc:  # the message already names the file and the field
        raise BadInput(str(exc)) from None
    except ImportError as exc:  # an optional extra the file needs (vtk for a .vtp vessel): the message says which
        raise BadInput(f"{path}: {exc}") from None


def _insert(args: argparse.Namespace) -> int:
    from ..march.insertion import insert

    scene = _load(args.scene)
    if isinstance(scene, Scene3D):
        return insert_3d(args, scene)
    first, lengths = _planar_lengths(args, scene)
    start_scene = scene.with_wire(length=first, bars=scene.wire.bars_at(first))
    flagged = [0]
    report = _step_printer(args.quiet, flagged)
    try:
        out = insert(start_scene, lengths, qp_solver=qp_solver_choice(args), tol=args.tol, max_iter=args.max_iter,
                     progress=report)
    except (ValueError, TypeError) as exc:
        raise BadInput(f"{args.scene}: {exc}") from None
    if flagged[0]:
        print(f"{flagged[0]} of {len(out.steps)} steps flagged (lines marked !)")
    if out.error is not None:
        print(f"stopped: {out.error}", file=sys.stderr)
    if args.json is not None:
        args.json.write_text(json.dumps(out.to_dict(), indent=1))
    if out.steps and (args.plot is not None or args.gif is not None):
        _insertion_figures(out, args.plot, args.gif)
    return EXIT_OK if out.complete and all(s.success for s in out.steps) else EXIT_NOT_CONVERGED


def _planar_lengths(args: argparse.Namespace, scene: Scene) -> tuple[float, np.ndarray]:
    """The first inserted length and every step's of a planar ``insert``, its options checked before any work."""
    if args.rotate is not None or args.schedule is not None or args.html is not None:
        raise BadInput(f"{args.scene} is a planar scene: --rotate, --schedule and --html need a 3-D scene (a vessel "
                       "centreline with three columns, a shipped 3-D shape or a .vtp file)")
    first, lengths = push_lengths(args, scene.wire.length, "give --to and --step (mm)")
    for flag in ("json", "plot", "gif"):
        check_output_dir(getattr(args, flag), f"--{flag}")
    check_size(args, lengths, scene.wire.bars / scene.wire.length)
    return first, lengths


def _step_printer(quiet: bool, flagged: list[int]) -> Any:
    """The ``progress`` callback of ``insert``: one line per step (only the flagged ones when ``quiet``), counting
    the flagged steps in ``flagged[0]``."""
    from ..march.insertion import step_flags, step_record

    def report(sol: Any, how: str, index: int, total: int) -> None:
        flags = step_flags(sol, how)
        flagged[0] += bool(flags)
        if quiet and not flags:
            return
        rec = step_record(sol)
        force = rec["entrance_force_n"]
        line = (f"[{index + 1}/{total}] L = {rec['inserted_length']:8.3f} mm  {'ok' if sol.success else 'FAILED':6s}  "
                f"E = {sol.energy:10.5g} N·mm  contacts {len(rec['contacts']):3d}  push "
                f"{'-' if force is None else f'{force:+.4g} N':>11s}  {sol.iterations:3d} it  "
                f"{1e3 * sol.solve_time_s:7.1f} ms  ({how})")
        print(line + "".join(f"\n    ! {flag}" for flag in flags), flush=True)

    return report


def _insertion_figures(out: Any, plot: Path | None, gif: Path | None) -> None:
    """The insertion's figure (``--plot``) and animation (``--gif``); matplotlib is imported only here."""
    from .plot_insertion import plot_insertion, save_animation

    if plot is not None:
        plot_insertion(out).savefig(plot, dpi=130)
    if gif is not None:
        save_animation(out, gif)


def _solve(args: argparse.Namespace) -> int:
    from ..solve import solve

    scene = _load(args.scene)
    if isinstance(scene, Scene3D):
        return solve_3d(args, scene)
    if args.html is not None:
        raise BadInput(f"--html draws 3-D scenes; {args.scene} is planar (use --plot)")
    for flag in ("json", "plot"):
        check_output_dir(getattr(args, flag), f"--{flag}")
    try:
        sol = solve(scene, scheme=args.scheme, bars=args.bars, qp_solver=qp_solver_choice(args), tol=args.tol,
                    max_iter=args.max_iter, verbose=args.verbose, tol_mm=args.tol_mm,
                    density=args.density)
    except (ValueError, TypeError) as exc:
        raise BadInput(f"{args.scene}: {exc}") from None
    print(_summary(sol))
    if sol.error_estimate_mm is not None:
        print(f"estimated mean node error {sol.error_estimate_mm:.3g} mm with {sol.n_bars} bars "
              f"({sol.solve_time_s * 1e3:.1f} ms in all)")
    if args.json is not None:
        args.json.write_text(json.dumps(sol.to_dict(), indent=1))
    if args.reference and args.plot is None:
        print("note: --reference only draws into --plot's figure; no figure was asked for", file=sys.stderr)
    if args.plot is not None:
        from .plot import plot_solution

        reference = None
        if args.reference:
            from ..reference import continuum_reference

            reference, why = continuum_reference(sol.scene)
            if reference is None:
                reason = why.removeprefix("no reference: ")
                print(f"note: --reference: no continuum reference drawn for scene {sol.scene.name!r}: {reason}",
                      file=sys.stderr)
        plot_solution(sol, reference=reference).savefig(args.plot, dpi=130)
    return EXIT_OK if sol.success else EXIT_NOT_CONVERGED


def _paper(args: argparse.Namespace) -> int:
    from .reproduction import failures, reproduce

    rows = reproduce(args.out, qp_solver=qp_solver_choice(args), figures=not args.no_figures)
    print(f"wrote {args.out / 'paper_results.md'} and {args.out / 'paper_results.csv'}"
          + ("" if args.no_figures else " and figures fig4/fig5/fig6/fig13.png"))
    return EXIT_NOT_CONVERGED if failures(rows) else EXIT_OK


#: Exit status of a batch stopped by SIGINT or SIGTERM (the shell's 128 + SIGINT).
EXIT_INTERRUPTED = 130


def _print_flagged(item: dict[str, Any]) -> None:
    """A line on stderr, as it arrives, for each batch record that is not a converged solve (the bar counts all)."""
    if "error" in item:
        line = f"{item['name']}: no solution ({item.get('stage', 'solve')}): {item['error']}"
    elif not item.get("success"):
        line = f"{item['name']}: FAILED (status {item.get('status')}): {item.get('message', '')}"
    else:
        return
    try:
        from tqdm import tqdm
    except ImportError:
        print(line, file=sys.stderr, flush=True)
    else:
        tqdm.write(line, file=sys.stderr)  # above the progress bar, not through it


def _interrupt(signum: int, frame: Any) -> None:
    """SIGTERM as Ctrl-C: the batch stops its workers, keeps what it wrote and says how to resume."""
    raise KeyboardInterrupt


def _batch(args: argparse.Namespace) -> int:
    """``batch``: every scene runs (a failure is a record), so the status is 0 unless the arguments are bad."""
    from ..batch.files import solve_files
    from .export import read_records, save_shapes

    if args.workers is not None and args.scheduler is not None:
        raise BadInput("give --workers (local processes) or --scheduler (a Dask cluster), not both")
    if args.out.is_dir():
        raise BadInput(f"--out {args.out}: a directory; give the JSON-lines file to write")
    client = None
    if args.scheduler is not None:
        try:
            from distributed import Client
        except ImportError:
            raise BadInput("--scheduler needs Dask: pip install 'guidewire-sqp[cluster]'") from None
        try:
            client = Client(args.scheduler, timeout="10s")
        except (OSError, ValueError, TypeError) as exc:
            raise BadInput(f"--scheduler {args.scheduler}: cannot connect ({exc})") from None
    options = {"bars": args.bars, "scheme": args.scheme, "qp_solver": qp_solver_choice(args), "tol": args.tol,
               "max_iter": args.max_iter}
    written = [0]

    def count(item: dict[str, Any]) -> None:
        written[0] += 1
        _print_flagged(item)

    previous = signal.signal(signal.SIGTERM, _interrupt)
    try:
        summary = solve_files(args.scenes, args.out, executor=None if client is None else client.get_executor(),
                              workers=args.workers, progress=not args.no_progress, chunksize=args.chunksize,
                              on_result=count, **options)
    except (ValueError, TypeError) as exc:
        raise BadInput(str(exc)) from None
    except KeyboardInterrupt:
        print(f"interrupted: {written[0]} scenes of this run are in {args.out}; run the same command again to solve "
              "the rest (the scenes already there are skipped)", file=sys.stderr)
        return EXIT_INTERRUPTED
    finally:
        signal.signal(signal.SIGTERM, previous)
        if client is not None:
            client.close()
    print(f"{args.out}: {summary}")
    if args.npz is not None:
        count = save_shapes(read_records(args.out), args.npz)
        print(f"{args.npz}: shapes and B-splines of {count} scenes")
    return EXIT_OK


def _run(argv: Sequence[str] | None) -> int:
    try:
        args = build_parser().parse_args(argv)
        return {"solve": _solve, "insert": _insert, "batch": _batch, "paper": _paper}[args.command](args)
    except BadInput as exc:
        print("error: " + " ".join(str(exc).split()), file=sys.stderr)
        return EXIT_BAD_INPUT


def entry() -> None:
    """The ``guidewire`` command and ``python -m guidewire``: :func:`main`, then exit with its status.

    An interrupted batch (:data:`EXIT_INTERRUPTED`) leaves at once (``os._exit``, the standard streams flushed):
    its records are written and synced and its pool's workers are terminated and reaped already, and the
    interpreter's normal exit would still join the process pool's manager thread, which can be blocked for good
    reading a result that a worker was writing when it was terminated (seen once in CI, the process still alive 25
    minutes later: the manager thread in ``os.read`` of an 18 493-byte message on the result pipe, whose write end
    this process itself holds, so no end of file ever comes; the main thread joining it)."""
    status = main()
    if status == EXIT_INTERRUPTED:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        os._exit(status)
    sys.exit(status)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status.

    A closed stdout pipe ends the run quietly (the recipe of the Python documentation, "Note on SIGPIPE"): stdout
    is pointed at ``os.devnull`` so that the interpreter's final flush does not fail again. The status is the
    command's when it had finished, else :data:`EXIT_NOT_CONVERGED` (Python's own status on EPIPE).
    """
    status = EXIT_NOT_CONVERGED
    try:
        status = _run(argv)
        sys.stdout.flush()  # a closed pipe shows here rather than as "Exception ignored" at exit
    except BrokenPipeError:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    return status
