"""Timing of the benchmarks: per-solve time limits, repeats and medians, solve-time budgets, the shifted geometric mean.

- :func:`time_limit`: SIGALRM raising :class:`SolveTimeout`, a ``BaseException``, so no ``except Exception`` inside
  a solver can swallow it;
- :func:`measure`: the median time over repeats of one solve (the solver reports its own ``"time"``), with a single
  run once a solve takes more than :data:`SINGLE_RUN_S` and more runs while they are fast;
- :class:`Budget`: when not to start a solve (after a timeout, when one is predicted, when a budget is spent);
- :func:`sgm`: the shifted geometric mean of run times.
"""

from __future__ import annotations

import contextlib
import math
import signal
import time
import warnings
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import numpy as np

#: Shift (seconds) of the shifted geometric mean of run times, as qpbenchmark uses.
TIME_SHIFT = 1e-3
#: After a solve longer than this (s), the remaining repeats of that point are skipped (median of what ran).
SINGLE_RUN_S = 1.0
#: Fast solves are repeated beyond ``--repeats`` (up to this many runs) while all of them fit in :data:`FAST_TOTAL_S`.
FAST_REPEATS, FAST_TOTAL_S = 15, 0.15


def sgm(values: Sequence[float], shift: float = TIME_SHIFT) -> float:
    """Shifted geometric mean of the finite ``values`` (``nan`` for none)."""
    arr = np.asarray([v for v in values if np.isfinite(v)], dtype=float)
    if arr.size == 0:
        return math.nan
    return float(np.exp(np.mean(np.log(arr + shift))) - shift)


class SolveTimeout(BaseException):
    """Raised by the alarm when one solve exceeds its time limit (a BaseException: solvers do not catch it)."""


@contextlib.contextmanager
def time_limit(seconds: float | None) -> Iterator[None]:
    """Raise :class:`SolveTimeout` inside the block after ``seconds`` (main thread, POSIX; no limit for None)."""
    if not seconds or not hasattr(signal, "SIGALRM"):
        yield
        return

    def _alarm(_signum: int, _frame: Any) -> None:
        raise SolveTimeout

    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)


def skipped(message: str) -> dict[str, Any]:
    """The result of a solve that was not started (``outcome`` ``"skipped"``)."""
    return {"outcome": "skipped", "time": math.nan, "x": None, "success": False, "message": message, "nit": 0,
            "nfev": 0, "repeats": 0}


def measure(run: Callable[[Any], dict[str, Any]], problem: Any, repeats: int, limit: float | None = None, *,
            adaptive: bool = True) -> dict[str, Any]:
    """``run(problem)`` ``repeats`` times; the last answer with the median of the times the runs report (``"time"``).

    With ``adaptive``: one run once a solve takes > :data:`SINGLE_RUN_S`, and more, up to :data:`FAST_REPEATS`, while
    they are fast and together take less than :data:`FAST_TOTAL_S` (so that a few-millisecond median is not at the
    mercy of one disturbed run on a shared machine); without it exactly ``repeats`` runs.

    ``outcome`` is ``"ran"``, ``"timeout"`` (one solve passed ``limit`` s) or ``"error"`` (the solver raised: a
    result, not a crash of the benchmark).
    """
    times: list[float] = []
    out: dict[str, Any] = {}
    target = max(1, repeats)
    while len(times) < target:
        wall = time.perf_counter()
        try:
            with warnings.catch_warnings(), time_limit(limit):
                warnings.simplefilter("ignore")
                out = run(problem)
        except SolveTimeout:
            return {"outcome": "timeout", "time": time.perf_counter() - wall, "x": None, "success": False,
                    "message": f"stopped: one solve took > {limit:g} s", "nit": 0, "nfev": 0, "repeats": len(times)}
        except Exception as exc:  # a solver raising is a finding, not the end of the benchmark
            return {"outcome": "error", "time": time.perf_counter() - wall, "x": None, "success": False,
                    "message": f"raised {type(exc).__name__}: {exc}", "nit": 0, "nfev": 0, "repeats": len(times)}
        times.append(float(out["time"]))
        if not adaptive:
            continue
        if out["time"] > SINGLE_RUN_S:
            break
        if repeats > 1 and len(times) == repeats and sum(times) < FAST_TOTAL_S:
            target = max(target, min(FAST_REPEATS, repeats + int((FAST_TOTAL_S - sum(times)) / max(times))))
    return {**out, "outcome": "ran", "time": float(np.median(times)), "repeats": len(times)}


class Budget:
    """When not to start a solve: after a timeout, when one is predicted, or when a solver's time budget is spent.

    Rules, per solver and key (a scene, or a sweep and scheme), n increasing:

    1. after a solve passes ``limit`` s the solver is not run at larger n for that key ("stopped: > limit s at n");
    2. once a solve takes more than ``limit / 20`` s, the next n is predicted from the solver's own growth per
       doubling of n over its last two points (at least ×2) and not started when the prediction exceeds the limit;
    3. once a solver has spent ``solver_budget`` s of solve time on one ``group`` of keys (e.g. the wall scenes, or
       the contact scenes; repeats included), it is not started again on that group (loops run n in the outer loop,
       so this cuts the largest n first). Solvers in ``exempt`` (``ours``, the yardstick of every ratio) have no
       budget.
    """

    def __init__(self, limit: float, solver_budget: float = math.inf, exempt: Sequence[str] = ("ours",)) -> None:
        self.limit = limit
        self.solver_budget = solver_budget
        self.exempt = tuple(exempt)
        self.stopped: dict[tuple[str, str], str] = {}
        self.history: dict[tuple[str, str], list[tuple[int, float]]] = {}
        self.spent: dict[tuple[str, str], float] = {}

    def reason_to_skip(self, solver: str, key: str, n: int, group: str = "") -> str | None:
        """Why ``solver`` should not run at ``n`` on ``key`` (in ``group``), or None."""
        if (solver, key) in self.stopped:
            return self.stopped[(solver, key)]
        if solver not in self.exempt and self.spent.get((solver, group), 0.0) >= self.solver_budget:
            where = f" on the {group}" if group else ""
            return f"skipped: the solver's time budget{where} ({self.solver_budget:g} s of solves) was spent"
        hist = self.history.get((solver, key), [])
        if hist and hist[-1][1] > self.limit / 20:
            (n1, t1) = hist[-1]
            growth = 2.0
            if len(hist) >= 2 and hist[-2][1] > 0:
                (n0, t0) = hist[-2]
                growth = max(2.0, (t1 / t0) ** (1.0 / max(math.log2(n1 / n0), 1e-9)))
            predicted = t1 * growth ** math.log2(n / n1)
            if predicted > self.limit:
                self.stopped[(solver, key)] = (
                    f"skipped: predicted {predicted:.0f} s > {self.limit:g} s at n = {n} (×{growth:.1f} per doubling "
                    f"from {t1:.1f} s at n = {n1})")
                return self.stopped[(solver, key)]
        return None

    def measure(self, solver: str, key: str, n: int, run: Callable[[Any], dict[str, Any]], problem: Any,
                repeats: int, group: str = "") -> dict[str, Any]:
        """:func:`measure` ``run(problem)`` with :attr:`limit` and :meth:`record` it, or :func:`skipped` with the
        reason when :meth:`reason_to_skip` gives one."""
        skip = self.reason_to_skip(solver, key, n, group)
        if skip is not None:
            return skipped(skip)
        result = measure(run, problem, repeats, self.limit)
        self.record(solver, key, n, result, group)
        return result

    def record(self, solver: str, key: str, n: int, result: dict[str, Any], group: str = "") -> None:
        """Account for one measured result."""
        if result["outcome"] == "timeout":
            self.stopped[(solver, key)] = f"stopped: > {self.limit:g} s at n = {n}"
        elif result["outcome"] == "ran":
            self.history.setdefault((solver, key), []).append((n, float(result["time"])))
        spent = float(result["time"]) * max(1, int(result.get("repeats", 1)))
        self.spent[(solver, group)] = self.spent.get((solver, group), 0.0) + (spent if np.isfinite(spent) else 0.0)


def repeats_note(repeats: int) -> str:
    """How :func:`measure` (adaptive) repeats, in words, for the settings line."""
    return (f"median of {repeats} repeat(s) (one run once a solve takes > {SINGLE_RUN_S:g} s; up to {FAST_REPEATS} "
            f"while they take < {FAST_TOTAL_S:g} s in all)")
