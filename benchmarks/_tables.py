"""Output of the benchmarks: table cells, Markdown tables, CSV files, the output stem, pyplot."""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np


def output_stem(out: Path, name: str, quick: bool) -> Path:
    """``out/name`` (``out/name_quick`` with ``quick``), without suffix; creates ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    return out / (f"{name}_quick" if quick else name)


def cell(value: Any, digits: int = 4) -> str:
    """A table cell: short floats, ``—`` for missing values, no ``|`` or newlines."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float | np.floating):
        value = float(value)
        if value == 0.0:
            return "0"
        if math.isinf(value):
            return "inf"
        return f"{value:.{digits}g}"
    return str(value).replace("|", "/").replace("\n", " ")


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> list[str]:
    """A Markdown table (every value through :func:`cell`)."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in rows]
    return lines


def write_csv(rows: Sequence[dict[str, Any]], path: Path) -> None:
    """All rows (the union of their keys, in first-seen order)."""
    names: list[str] = []
    for row in rows:
        names += [k for k in row if k not in names]
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=names)
        writer.writeheader()
        writer.writerows(rows)


def write_markdown(lines: Sequence[str], path: Path) -> None:
    """The lines as one Markdown file (trailing newline)."""
    path.write_text("\n".join(lines) + "\n")


def pyplot() -> Any:
    """``matplotlib.pyplot`` on the Agg backend, or None when matplotlib is missing."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    return plt
