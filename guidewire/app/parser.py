"""The argument parser of ``python -m guidewire`` (:func:`build_parser`) and the user error it raises
(:class:`BadInput`: one line on stderr, exit status 2)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import NoReturn

import numpy as np

from sqp import installed_solvers

from ..scene.scene import SCHEMES
from ..solve.options import MAX_ITER, TOL

#: ``insert`` asks for ``--yes`` above this many steps (a --step in µm by mistake runs for minutes)...
MAX_STEPS = 10_000

#: ...or when its JSON would exceed this many megabytes.
MAX_JSON_MB = 100


class BadInput(Exception):
    """A user error reported as one line on stderr with exit status 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        raise BadInput(f"{self.prog}: {message} (see --help)")


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} must be at least 1")
    return value


AUTO_QP_SOLVER = "auto"
"""``--qp-solver`` value that lets the engine choose the QP backend by size and sparsity."""

QP_SOLVER_HELP = (
    "QP backend: 'auto' (default) picks DAQP up to 300 variables, PIQP for larger programs whose rows are all "
    "sparse, DAQP again for larger programs with dense rows; or an installed qpsolvers backend: {}"
)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (value > 0 and np.isfinite(value)):
        raise argparse.ArgumentTypeError(f"{text} must be a positive length in mm")
    return value


def _gif_path(text: str) -> Path:
    """``--gif``'s file: a ``.gif`` (written by matplotlib's Pillow writer)."""
    path = Path(text)
    if path.suffix.lower() != ".gif":
        raise argparse.ArgumentTypeError(f"{text!r} is not a .gif file")
    _figure_path(str(path.with_suffix(".png")))  # matplotlib is needed
    return path


def _figure_path(text: str) -> Path:
    """``--plot``'s file, refused (before any solve) unless matplotlib is installed and writes its file type."""
    path = Path(text)
    try:
        from matplotlib.backend_bases import FigureCanvasBase
    except ImportError:
        message = "writing a figure needs matplotlib: pip install 'guidewire-sqp[plot]'"
        raise argparse.ArgumentTypeError(message) from None
    formats = FigureCanvasBase.get_supported_filetypes()
    suffix = path.suffix.lower().removeprefix(".")
    if suffix not in formats:
        kind = f"file type {path.suffix!r}" if path.suffix else "no file extension"
        raise argparse.ArgumentTypeError(
            f"{text!r} has {kind}; matplotlib writes {', '.join('.' + f for f in sorted(formats))}")
    return path


def qp_solver_choice(args: argparse.Namespace) -> str | None:
    """The ``qp_solver`` for :func:`guidewire.solve`: ``None`` (its automatic choice) for ``auto``."""
    return None if args.qp_solver == AUTO_QP_SOLVER else args.qp_solver


def _add_qp_solver(parser: argparse.ArgumentParser) -> None:
    choices = [AUTO_QP_SOLVER, *installed_solvers()]
    parser.add_argument("--qp-solver", choices=choices, default=AUTO_QP_SOLVER, metavar="NAME",
                        help=QP_SOLVER_HELP.format(", ".join(choices[1:])))


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``python -m guidewire``."""
    parser = _Parser(prog="guidewire", description="Bar-chain guidewire deformation by SQP (Li et al. 2019).")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    run = sub.add_parser("solve", help="solve one scene file")
    run.add_argument("scene", type=Path, help="scene file (TOML)")
    run.add_argument("--json", type=Path, help="write the solution as JSON")
    run.add_argument("--plot", type=_figure_path, help="write a figure (.png, .pdf, .svg, ...: the file type "
                     "from the extension; needs matplotlib)")
    run.add_argument("--bars", type=_positive_int, help="number of bars (default: the file's)")
    run.add_argument("--scheme", choices=SCHEMES, help="energy discretisation (default: the file's)")
    run.add_argument("--tol-mm", type=float, help="solve to this estimated mean node error (mm) with bars graded by "
                     "curvature (or doubled uniform bars with --density uniform; instead of --bars); the JSON "
                     "reports error_estimate_mm")
    run.add_argument("--density", choices=("uniform", "curvature"), help="bar layout: equal bars per piece, or "
                     "graded by the curvature of a coarse solve (default: the file's wire.density)")
    _add_qp_solver(run)
    run.add_argument("--max-iter", type=_positive_int, default=MAX_ITER, help="SQP iteration limit")
    run.add_argument("--tol", type=float, default=TOL, help="SQP tolerance")
    run.add_argument("--reference", action="store_true", help="overlay the continuum reference in --plot")
    run.add_argument("--html", type=Path, help="3-D scenes: write an interactive view (needs plotly, the [html] "
                     "extra)")
    run.add_argument("--verbose", action="store_true", help="print the SQP iteration table")
    ins = sub.add_parser("insert", help="advance the wire of a scene quasi-statically (a vessel, walls, contacts)")
    ins.add_argument("scene", type=Path, help="scene file (TOML); its wire.length is the first inserted length "
                     "unless --from says otherwise, its bars per mm are kept")
    ins.add_argument("--to", type=_positive_float, help="last inserted length (mm); with --step, or give --schedule")
    ins.add_argument("--step", type=_positive_float, help="insertion step (mm)")
    ins.add_argument("--rotate", type=float, metavar="DEG_PER_MM", help="3-D scenes: turn the clamp by this many "
                     "degrees per mm inserted (negative: the other way)")
    ins.add_argument("--schedule", type=Path, metavar="FILE", help="3-D scenes: a text file of steps, one per line: "
                     "inserted length (mm) and clamp rotation (degrees), both absolute ('#' starts a comment); "
                     "pushes, pulls and turns in any order (instead of --to/--step)")
    ins.add_argument("--html", type=Path, help="3-D scenes: write an interactive view of the last step (needs "
                     "plotly, the [html] extra)")
    ins.add_argument("--from", dest="start", type=_positive_float, help="first inserted length (mm)")
    ins.add_argument("--json", type=Path, help="write every step as JSON (units, steps: contacts, tip, forces)")
    ins.add_argument("--plot", type=_figure_path, help="write the last shape and force/energy against length")
    ins.add_argument("--gif", type=_gif_path, help="write an animation of the insertion (.gif)")
    _add_qp_solver(ins)
    ins.add_argument("--yes", action="store_true", help=f"run even more than {MAX_STEPS} steps or a JSON file "
                     f"over {MAX_JSON_MB} MB")
    ins.add_argument("--quiet", action="store_true", help="no line per step (flagged steps are still printed)")
    ins.add_argument("--max-iter", type=_positive_int, default=MAX_ITER, help="SQP iteration limit per step")
    ins.add_argument("--tol", type=float, default=TOL, help="SQP tolerance")
    paper = sub.add_parser("paper", help="reproduce every scene of the paper (figures + table)")
    paper.add_argument("--out", type=Path, required=True, help="output directory")
    _add_qp_solver(paper)
    paper.add_argument("--no-figures", action="store_true", help="tables only")
    batch = sub.add_parser("batch", help="solve many scene files, one JSON line each (resumable)")
    batch.add_argument("scenes", type=Path, nargs="+", help="scene files (TOML) or directories of them (*.toml)")
    batch.add_argument("--out", type=Path, required=True, help="JSON-lines output, appended to: scenes already in "
                       "it are skipped")
    batch.add_argument("--workers", type=_positive_int, help="local worker processes (default: one per CPU)")
    batch.add_argument("--scheduler", metavar="ADDRESS", help="solve on the Dask cluster of this scheduler "
                       "(tcp://host:8786; needs pip install 'guidewire-sqp[cluster]')")
    batch.add_argument("--npz", type=Path, help="then write the shapes and B-splines of every scene in --out")
    batch.add_argument("--chunksize", type=_positive_int, default=1, help="scenes per task (default 1)")
    batch.add_argument("--bars", type=_positive_int, help="number of bars (default: each file's)")
    batch.add_argument("--scheme", choices=SCHEMES, help="energy discretisation (default: each file's)")
    _add_qp_solver(batch)
    batch.add_argument("--max-iter", type=_positive_int, default=MAX_ITER, help="SQP iteration limit")
    batch.add_argument("--tol", type=float, default=TOL, help="SQP tolerance")
    batch.add_argument("--no-progress", action="store_true", help="no progress bar")
    return parser


#: Bytes of one node in an insertion's JSON (two coordinates printed at full precision, indent 1).
JSON_BYTES_PER_NODE = 60


def check_output_dir(path: Path | None, flag: str) -> None:
    """An output whose directory does not exist is a mistake (a typo, or a path meant elsewhere): said before any
    work rather than creating directories the user did not ask for."""
    if path is not None and not path.parent.is_dir():
        raise BadInput(f"{flag} {path}: the directory {path.parent} does not exist; create it or give another path")


def check_size(args: argparse.Namespace, lengths: np.ndarray, bars_per_mm: float) -> None:
    """Refuse, unless ``--yes``, an insertion of more than :data:`MAX_STEPS` steps or whose JSON would exceed
    :data:`MAX_JSON_MB` megabytes (estimated from the nodes of every step)."""
    if args.yes:
        return
    if lengths.size > MAX_STEPS:
        raise BadInput(f"--step {args.step:g} mm makes {lengths.size} steps (more than {MAX_STEPS}); give a larger "
                       "--step (it is in mm), or --yes to run them all")
    if args.json is not None:
        megabytes = JSON_BYTES_PER_NODE * float(np.sum(lengths * bars_per_mm + 1.0)) / 1e6
        if megabytes > MAX_JSON_MB:
            raise BadInput(f"--json would hold about {megabytes:.0f} MB ({lengths.size} steps of up to "
                           f"{lengths[-1] * bars_per_mm:.0f} bars); give a larger --step, fewer bars per mm, or "
                           "--yes to write it")


def push_lengths(args: argparse.Namespace, wire_length: float, missing: str) -> tuple[float, np.ndarray]:
    """``insert``'s first inserted length (``--from``, else the scene's) and every step's from ``--to``/``--step``
    (mm); ``missing`` is the message when either is not given."""
    if args.to is None or args.step is None:
        raise BadInput(missing)
    first = wire_length if args.start is None else args.start
    if args.to < first:
        raise BadInput(f"--to {args.to:g} is shorter than the first inserted length {first:g} mm")
    return first, np.arange(first, args.to + 0.5 * args.step, args.step)
