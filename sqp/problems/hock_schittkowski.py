"""The Hock–Schittkowski collection: every problem with its start, bounds, analytic derivatives and best-known f*.

Definitions follow W. Hock and K. Schittkowski, *Test Examples for Nonlinear Programming Codes*, Lecture Notes in
Economics and Mathematical Systems 187, Springer 1981, and K. Schittkowski, *More Test Examples for Nonlinear
Programming Codes*, LNEMS 282, 1987 (HS268); f* comes from ``data/hs_optima.csv`` (corrected values).
The problems themselves live in two modules split by number only to keep each file readable.
"""

from __future__ import annotations

from collections.abc import Callable

from sqp.problems.hs_001_056 import BUILDERS as _BUILDERS_LOW
from sqp.problems.hs_057_268 import BUILDERS as _BUILDERS_HIGH
from sqp.problems.problem import TestProblem

BUILDERS: dict[str, Callable[[], TestProblem]] = {**_BUILDERS_LOW, **_BUILDERS_HIGH}


def problem(name: str) -> TestProblem:
    """The Hock–Schittkowski problem called ``name`` (e.g. ``"HS71"``)."""
    try:
        return BUILDERS[name.upper()]()
    except KeyError:
        raise ValueError(f"unknown Hock-Schittkowski problem {name!r}; known: {', '.join(BUILDERS)}") from None


def all_problems() -> list[TestProblem]:
    """Every problem of the collection, in collection order."""
    return [build() for build in BUILDERS.values()]
