"""The command line every benchmark shares: ``--quick``, ``--out``, ``--repeats`` and, where a script times solves
against a limit, ``--limit`` and ``--budget``; ``--solvers`` where it compares solvers. Scripts add their own options
to the returned parser and read the result through :func:`parse`."""

from __future__ import annotations

import argparse
from pathlib import Path

#: Default ``--out``: the committed results next to the scripts.
RESULTS = Path(__file__).resolve().parent / "results"
#: In ``--quick`` mode the time limit of one solve is at most this (s).
QUICK_LIMIT = 20.0


def parser(doc: str, *, quick_help: str, repeats: int, repeats_help: str = "timing repeats per solve (median "
           "reported)", limit: float | None = None, budget: float | None = None, budget_help: str = "",
           solvers: bool = False) -> argparse.ArgumentParser:
    """The shared options (``limit``/``budget``: their defaults, None for a script without them)."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help=quick_help)
    ap.add_argument("--repeats", type=int, default=repeats, help=repeats_help)
    ap.add_argument("--out", type=Path, default=RESULTS)
    if limit is not None:
        ap.add_argument("--limit", type=float, default=limit, help="time limit of one solve (s)")
    if budget is not None:
        ap.add_argument("--budget", type=float, default=budget, help=budget_help)
    if solvers:
        ap.add_argument("--solvers", type=str, default="", help="comma-separated substrings of solver names")
    return ap


def parse(ap: argparse.ArgumentParser) -> argparse.Namespace:
    """Parsed arguments with ``--quick`` applied: one repeat (at least one in any case), the limit capped at
    :data:`QUICK_LIMIT`."""
    a = ap.parse_args()
    a.repeats = 1 if a.quick else max(1, a.repeats)
    if getattr(a, "limit", None) is not None and a.quick:
        a.limit = min(a.limit, QUICK_LIMIT)
    return a


def names(text: str) -> list[str]:
    """The non-empty items of a comma-separated option."""
    return [item for item in text.split(",") if item]
