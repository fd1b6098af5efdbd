"""Shared machinery of the guidewire benchmarks (``discrete_density.py``, ``peers.py``, ``stability.py``).

Not a benchmark itself: the leading underscore keeps it out of ``tests/benchmarks/test_quick_modes.py``.

What it holds
-------------
- the environment report (machine, versions, BLAS pinned to one thread);
- the solvers, all called on one :class:`Case` (a scene formulated once, with its start ``x0``):
  ours (:func:`guidewire.solve`, any installed QP backend, exact or BFGS Hessian when that option exists), scipy
  SLSQP, scipy trust-constr and IPOPT through cyipopt, every one from the same ``x0`` with the same analytic
  derivatives of :class:`guidewire.formulation.Formulation`. Exact Hessians are given to trust-constr and IPOPT when
  the formulation offers them (``Formulation.hess`` and a ``"hess"`` key in every nonlinear constraint dict, scipy's
  ``NonlinearConstraint`` convention ``hess(x, v) = Σ v_i ∇²c_i``); otherwise trust-constr gets the exact (constant)
  energy Hessian with BFGS for the constraints and IPOPT its limited-memory quasi-Newton;
- timing: our time is ``Solution.solve_time_s`` as :func:`guidewire.solve` measures it (formulation from the given
  start, :func:`sqp.minimize` and any wall working-set rounds), a peer's the wall time of its ``minimize`` call (its
  callables, constraint conversions and sparsity patterns are prepared outside the timer); the median over
  repeats, with a single run once a solve takes more than :data:`SINGLE_RUN_S`; a per-solve time limit (SIGALRM
  raising a ``BaseException``, so no ``except Exception`` inside a solver can swallow it);
- evaluation of any answer ``x`` on the same scale: energy, largest constraint violation, node errors against the
  continuum reference (:func:`guidewire.reproduction.node_errors`, the paper's Eq. 25);
- Markdown/CSV writers and the shifted geometric mean.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import contextlib  # noqa: E402
import csv  # noqa: E402
import inspect  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import signal  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from collections.abc import Callable, Iterator, Sequence  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from importlib import metadata  # noqa: E402
from pathlib import Path  # noqa: E402
from types import SimpleNamespace  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import scipy  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from scipy.optimize import BFGS, LinearConstraint, NonlinearConstraint, minimize  # noqa: E402

import guidewire  # noqa: E402
import sqp  # noqa: E402
from guidewire.formulation import Formulation, formulate  # noqa: E402
from guidewire.reproduction import continuum_reference, node_errors  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
#: Shift (seconds) of the shifted geometric mean of run times, as qpbenchmark uses.
TIME_SHIFT = 1e-3
#: After a solve longer than this (s), the remaining repeats of that point are skipped (median of what ran).
SINGLE_RUN_S = 1.0

#: Fast solves are repeated beyond ``--repeats`` (up to this many runs) while all of them fit in :data:`FAST_TOTAL_S`.
FAST_REPEATS, FAST_TOTAL_S = 15, 0.15
#: An answer counts as feasible when no constraint is violated by more than this (mm or rad).
FEASIBILITY_TOL = 1e-6
#: Relative energy gap to the best feasible energy of the same problem below which an answer is on the lowest branch.
SAME_ENERGY_RTOL = 1e-6
#: Relative gap above which it is on another branch (in between: the same branch, not fully converged).
OTHER_BRANCH_RTOL = 1e-3
#: Iteration caps of the peers (generous: SLSQP needs about n iterations on these problems).
PEER_MAX_ITER = {"SLSQP": 5000, "trust-constr": 1000, "IPOPT": 3000}


# ----------------------------------------------------------------------------------------------------------------
# Environment
# ----------------------------------------------------------------------------------------------------------------
def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


def ipopt_available() -> bool:
    """Whether ``cyipopt.minimize_ipopt`` imports."""
    try:
        from cyipopt import minimize_ipopt  # noqa: F401
    except ImportError:
        return False
    return True


def environment() -> list[str]:
    """Machine and versions, one item per line (printed, and written at the top of every Markdown file)."""
    cpu = platform.processor() or platform.machine()
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    backends = ", ".join(f"{b} {_version(b if b != 'proxqp' else 'proxsuite')}" for b in sqp.installed_solvers())
    return [
        f"machine: {cpu}, {os.cpu_count()} logical cores, {platform.system()} {platform.release()}",
        f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
        f"qpsolvers {_version('qpsolvers')}, cyipopt {_version('cyipopt-wheels') if ipopt_available() else 'missing'}",
        f"QP backends: {backends}; ours = guidewire.solve defaults: qp_solver {default_qp_solver()}, hessian "
        + (repr(default_hessian()) if has_hessian_option() else "BFGS (no hessian option yet)"),
        "BLAS pinned to one thread (OPENBLAS/OMP/MKL_NUM_THREADS=1 and threadpoolctl)",
    ]


def progress(iterable: Any, **kwargs: Any) -> Any:
    """``tqdm`` progress bar when installed, the iterable itself otherwise."""
    try:
        from tqdm import tqdm
    except ImportError:
        return iterable
    return tqdm(iterable, **kwargs)


def sgm(values: Sequence[float], shift: float = TIME_SHIFT) -> float:
    """Shifted geometric mean (``nan`` for no values)."""
    arr = np.asarray([v for v in values if np.isfinite(v)], dtype=float)
    if arr.size == 0:
        return math.nan
    return float(np.exp(np.mean(np.log(arr + shift))) - shift)


# ----------------------------------------------------------------------------------------------------------------
# Time limits
# ----------------------------------------------------------------------------------------------------------------
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


# ----------------------------------------------------------------------------------------------------------------
# Problems
# ----------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Case:
    """One problem as every solver sees it: the scene (bars and scheme applied), its formulation and start."""

    scene: guidewire.Scene
    form: Formulation
    start: str  # "default" (the formulation's elastica-like start) or "straight" (all angles 0)

    @property
    def n(self) -> int:
        return self.form.n


def make_case(scene: guidewire.Scene, *, bars: int | None = None, scheme: str | None = None,
              start: str = "default") -> Case:
    """Formulate ``scene`` once; ``start="straight"`` starts every solver from all bar angles 0."""
    if scheme is not None:
        scene = scene.with_scheme(scheme)
    if bars is not None:
        scene = scene.with_bars(bars)
    initial = np.zeros(scene.wire.bars) if start == "straight" else None
    return Case(scene, formulate(scene, initial_angles=initial), start)


def dense(matrix: Any) -> np.ndarray:
    """A dense float array from an array or a scipy sparse matrix."""
    return matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix, dtype=float)


def has_exact_hessians(form: Formulation) -> bool:
    """Whether the formulation offers the energy Hessian and every nonlinear constraint its ``"hess"``."""
    return callable(getattr(form, "hess", None)) and all(
        isinstance(c, LinearConstraint) or "hess" in c for c in form.constraints
    )


def energy_hessian(form: Formulation) -> Any:
    """The exact energy Hessian (``Formulation.hess`` when offered, else the energy's constant matrix)."""
    if callable(getattr(form, "hess", None)):
        return form.hess(form.x0)
    return form.energy.hessian()


# ----------------------------------------------------------------------------------------------------------------
# Ours
# ----------------------------------------------------------------------------------------------------------------
def _solve_parameters() -> dict[str, inspect.Parameter]:
    return dict(inspect.signature(guidewire.solve).parameters)


def default_qp_solver() -> str:
    """The QP backend :func:`guidewire.solve` uses when none is named, in words."""
    default = _solve_parameters()["qp_solver"].default
    if isinstance(default, str):
        return repr(default)
    module = inspect.getmodule(guidewire.solve)
    chooser = getattr(module, "default_qp_solver", None)
    formulation = getattr(module, "choose_formulation", None)
    if callable(chooser) and callable(formulation):
        return "by size (" + ", ".join(f"n = {n}: {formulation(n)} formulation, {chooser(n, formulation(n))}"
                                       for n in (100, 1000)) + ")"
    if callable(chooser):
        return f"by size ({', '.join(f'n = {n}: {chooser(n)}' for n in (100, 1000))})"
    return "sqp.minimize's default"


def has_hessian_option() -> bool:
    """Whether :func:`guidewire.solve` takes ``hessian="exact"|"bfgs"``."""
    return "hessian" in _solve_parameters()


def default_hessian() -> str | None:
    """The default of ``guidewire.solve(hessian=...)``, or None without that option."""
    return _solve_parameters()["hessian"].default if has_hessian_option() else None


def run_ours(case: Case, *, qp_solver: str | None = None, hessian: str | None = None,
             max_iter: int = 500) -> dict[str, Any]:
    """:func:`guidewire.solve` from the case's start; time = ``Solution.solve_time_s``."""
    kwargs: dict[str, Any] = {"initial_angles": case.form.x0, "max_iter": max_iter}
    if qp_solver is not None:
        kwargs["qp_solver"] = qp_solver
    if hessian is not None:
        kwargs["hessian"] = hessian
    sol = guidewire.solve(case.scene, **kwargs)
    kkt = getattr(sol.result, "kkt", None) or {}
    return {"x": sol.bar_angles, "success": sol.success, "message": sol.message, "nit": sol.iterations,
            "nfev": int(getattr(sol.result, "nfev", 0)), "time": sol.solve_time_s, "solution": sol,
            "kkt": max((float(v) for v in kkt.values()), default=math.nan)}


def ours_variants(backends: bool = True) -> dict[str, Callable[[Case], dict[str, Any]]]:
    """Our solver: ``ours`` (every default of :func:`guidewire.solve`), ``ours[bfgs]`` (the other Hessian option, when
    there is one) and, with ``backends``, ``ours[<backend>]`` for every installed QP backend named explicitly."""
    out: dict[str, Callable[[Case], dict[str, Any]]] = {"ours": run_ours}
    if has_hessian_option():
        other = "bfgs" if default_hessian() != "bfgs" else "exact"
        out[f"ours[{other}]"] = lambda c, h=other: run_ours(c, hessian=h)
    if backends:
        for name in sqp.installed_solvers():
            out[f"ours[{name}]"] = lambda c, b=name: run_ours(c, qp_solver=b)
    return out


# ----------------------------------------------------------------------------------------------------------------
# Peers
# ----------------------------------------------------------------------------------------------------------------
def _linear_as_dicts(con: LinearConstraint, n: int, with_hess: bool) -> list[dict[str, Any]]:
    """``lb ≤ A x ≤ ub`` as SLSQP dicts (equalities, then finite lower and upper sides)."""
    A = dense(con.A).reshape(-1, n)
    lb = np.broadcast_to(np.asarray(con.lb, dtype=float), (A.shape[0],))
    ub = np.broadcast_to(np.asarray(con.ub, dtype=float), (A.shape[0],))
    zero = sp.coo_array((n, n))
    out: list[dict[str, Any]] = []
    eq = lb == ub
    lo = ~eq & np.isfinite(lb)
    up = ~eq & np.isfinite(ub)
    for kind, rows, sign, rhs in (("eq", eq, 1.0, lb), ("ineq", lo, 1.0, lb), ("ineq", up, -1.0, ub)):
        if rows.any():
            Ar, br = sign * A[rows], sign * rhs[rows]
            d = {"type": kind, "fun": lambda x, Ar=Ar, br=br: Ar @ x - br, "jac": lambda x, Ar=Ar: Ar}
            if with_hess:
                d["hess"] = lambda x, v, z=zero: z
            out.append(d)
    return out


def slsqp_constraints(form: Formulation) -> list[dict[str, Any]]:
    """Every constraint as an SLSQP dict with a dense Jacobian."""
    out: list[dict[str, Any]] = []
    for con in form.constraints:
        if isinstance(con, LinearConstraint):
            out += _linear_as_dicts(con, form.n, with_hess=False)
        else:
            out.append({"type": con["type"], "fun": con["fun"], "jac": lambda x, j=con["jac"]: dense(j(x))})
    return out


def trust_constr_constraints(form: Formulation, exact: bool) -> list[Any]:
    """``NonlinearConstraint`` objects (exact ``hess`` or scipy's BFGS) and the ``LinearConstraint`` s as they are."""
    out: list[Any] = []
    for con in form.constraints:
        if isinstance(con, LinearConstraint):
            out.append(con)
            continue
        ub = 0.0 if con["type"] == "eq" else np.inf
        hess = con["hess"] if exact else BFGS()
        out.append(NonlinearConstraint(con["fun"], 0.0, ub, jac=con["jac"], hess=hess))
    return out


class FixedPattern:
    """Matrices on one fixed sparsity pattern, as ``coo_array`` (cyipopt needs the same coordinates every call).

    The pattern is the union of the nonzeros of ``samples`` (plus the diagonal when ``diagonal``); a later matrix
    with a nonzero outside it raises ``ValueError`` rather than silently dropping it.
    """

    def __init__(self, samples: Sequence[Any], shape: tuple[int, int], *, diagonal: bool = False) -> None:
        mask = np.zeros(shape, dtype=bool)
        for sample in samples:
            mask |= dense(sample).reshape(shape) != 0.0
        if diagonal:
            mask[np.diag_indices(min(shape))] = True
        self.shape = shape
        self.rows, self.cols = np.nonzero(mask)
        self.linear = self.rows * shape[1] + self.cols  # increasing (row-major)

    def __call__(self, matrix: Any) -> sp.coo_array:
        if sp.issparse(matrix):
            coo = sp.coo_array(matrix)
            linear = coo.row.astype(np.int64) * self.shape[1] + coo.col
            pos = np.minimum(np.searchsorted(self.linear, linear), max(self.linear.size - 1, 0))
            inside = self.linear[pos] == linear if self.linear.size else np.zeros(linear.size, bool)
            if not np.all(inside | (coo.data == 0.0)):
                raise ValueError("a matrix has a nonzero outside the sampled sparsity pattern")
            data = np.bincount(pos[inside], weights=coo.data[inside], minlength=self.linear.size)
        else:
            data = np.asarray(matrix, dtype=float).reshape(self.shape)[self.rows, self.cols]
        return sp.coo_array((data, (self.rows, self.cols)), shape=self.shape)


def ipopt_problem(form: Formulation, exact: bool) -> tuple[list[dict[str, Any]], Callable[[Any], Any] | None]:
    """IPOPT's constraint dicts (sparse Jacobians and, if ``exact``, Hessians on fixed patterns) and objective Hessian.

    Patterns are sampled at two random perturbations of ``x0`` (so no entry is zero by accident there).
    """
    n = form.n
    rng = np.random.default_rng(0)
    points = [form.x0 + 0.1 * rng.standard_normal(n) for _ in range(2)]
    dicts: list[dict[str, Any]] = []
    for con in form.constraints:
        dicts += _linear_as_dicts(con, n, exact) if isinstance(con, LinearConstraint) else [dict(con)]
    out: list[dict[str, Any]] = []
    for con in dicts:
        m = int(np.atleast_1d(con["fun"](form.x0)).size)
        jp = FixedPattern([con["jac"](p) for p in points], (m, n))
        d = {"type": con["type"], "fun": con["fun"], "jac": lambda x, j=con["jac"], jp=jp: jp(j(x))}
        if exact:
            hp = FixedPattern([con["hess"](p, rng.standard_normal(m)) for p in points], (n, n))
            d["hess"] = lambda x, v, h=con["hess"], hp=hp: hp(h(x, v))
        out.append(d)
    if not exact:
        return out, None
    constant = None if callable(getattr(form, "hess", None)) else form.energy.hessian()
    hess = form.hess if constant is None else (lambda x: constant)
    op = FixedPattern([hess(p) for p in points], (n, n), diagonal=True)
    return out, lambda x: op(hess(x))


def _counted(fun: Callable[[Any], float]) -> tuple[Callable[[Any], float], list[int]]:
    count = [0]

    def wrapped(x: Any) -> float:
        count[0] += 1
        return fun(x)

    return wrapped, count


def run_slsqp(case: Case) -> dict[str, Any]:
    """scipy SLSQP (scipy's default tolerances, ``maxiter`` raised)."""
    form = case.form
    cons = slsqp_constraints(form)
    fun, count = _counted(form.fun)
    start = time.perf_counter()
    res = minimize(fun, form.x0, jac=form.jac, constraints=cons, method="SLSQP",
                   options={"maxiter": PEER_MAX_ITER["SLSQP"]})
    elapsed = time.perf_counter() - start
    return {"x": res.x, "success": bool(res.success), "message": str(res.message), "nit": int(res.nit),
            "nfev": count[0], "time": elapsed}


def run_trust_constr(case: Case) -> dict[str, Any]:
    """scipy trust-constr with exact Hessians when offered (else exact energy Hessian, BFGS for constraints)."""
    form = case.form
    exact = has_exact_hessians(form)
    cons = trust_constr_constraints(form, exact)
    constant = None if exact else energy_hessian(form)
    hess = form.hess if constant is None else (lambda x: constant)
    fun, count = _counted(form.fun)
    start = time.perf_counter()
    res = minimize(fun, form.x0, jac=form.jac, hess=hess, constraints=cons, method="trust-constr",
                   options={"maxiter": PEER_MAX_ITER["trust-constr"]})
    elapsed = time.perf_counter() - start
    return {"x": res.x, "success": bool(res.success), "message": str(res.message), "nit": int(res.nit),
            "nfev": count[0], "time": elapsed}


def run_ipopt(case: Case) -> dict[str, Any]:
    """IPOPT through cyipopt: exact Hessians when offered, else ``hessian_approximation = limited-memory``."""
    from cyipopt import minimize_ipopt

    form = case.form
    exact = has_exact_hessians(form)
    cons, hess = ipopt_problem(form, exact)
    options: dict[str, Any] = {"print_level": 0, "sb": "yes", "max_iter": PEER_MAX_ITER["IPOPT"], "tol": 1e-8}
    if not exact:
        options["hessian_approximation"] = "limited-memory"
    fun, count = _counted(form.fun)
    start = time.perf_counter()
    res = minimize_ipopt(fun, form.x0, jac=form.jac, hess=hess, constraints=cons, options=options)
    elapsed = time.perf_counter() - start
    message = res.message.decode() if isinstance(res.message, bytes) else str(res.message)
    return {"x": np.asarray(res.x), "success": bool(res.success), "message": message, "nit": int(res.nit),
            "nfev": count[0], "time": elapsed}


def peer_variants(names: Sequence[str] = ("SLSQP", "trust-constr", "IPOPT")) -> dict[str, Callable[[Case], Any]]:
    """The installed peers among ``names`` (IPOPT only when cyipopt imports), keyed by display name."""
    table: dict[str, Callable[[Case], Any]] = {}
    if "SLSQP" in names:
        table["scipy SLSQP"] = run_slsqp
    if "trust-constr" in names:
        table["scipy trust-constr"] = run_trust_constr
    if "IPOPT" in names and ipopt_available():
        table["IPOPT"] = run_ipopt
    return table


def peer_hessian_note(form: Formulation) -> str:
    """How the peers get second derivatives for this formulation (for the Markdown notes)."""
    if has_exact_hessians(form):
        return ("trust-constr and IPOPT get the exact Hessians of the formulation (energy and every constraint, "
                "IPOPT on fixed sparse patterns)")
    return ("the formulation offers no constraint Hessians: trust-constr gets the exact energy Hessian and scipy's "
            "BFGS for the constraints, IPOPT its limited-memory quasi-Newton")


# ----------------------------------------------------------------------------------------------------------------
# Measuring and judging
# ----------------------------------------------------------------------------------------------------------------
def measure(run: Callable[[Case], dict[str, Any]], case: Case, repeats: int, limit: float | None) -> dict[str, Any]:
    """Run ``repeats`` times (one run once a solve takes > :data:`SINGLE_RUN_S`; more, up to :data:`FAST_REPEATS`,
    while they are fast and together take less than :data:`FAST_TOTAL_S`, so that a few-millisecond median is not at
    the mercy of one disturbed run on a shared machine); median time, last answer.

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
                out = run(case)
        except SolveTimeout:
            return {"outcome": "timeout", "time": time.perf_counter() - wall, "x": None, "success": False,
                    "message": f"stopped: one solve took > {limit:g} s", "nit": 0, "nfev": 0, "repeats": len(times)}
        except Exception as exc:  # a solver raising is a finding, not the end of the benchmark
            return {"outcome": "error", "time": time.perf_counter() - wall, "x": None, "success": False,
                    "message": f"raised {type(exc).__name__}: {exc}", "nit": 0, "nfev": 0, "repeats": len(times)}
        times.append(float(out["time"]))
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

    def record(self, solver: str, key: str, n: int, result: dict[str, Any], group: str = "") -> None:
        """Account for one measured result."""
        if result["outcome"] == "timeout":
            self.stopped[(solver, key)] = f"stopped: > {self.limit:g} s at n = {n}"
        elif result["outcome"] == "ran":
            self.history.setdefault((solver, key), []).append((n, float(result["time"])))
        spent = float(result["time"]) * max(1, int(result.get("repeats", 1)))
        self.spent[(solver, group)] = self.spent.get((solver, group), 0.0) + (spent if np.isfinite(spent) else 0.0)


_REFERENCES: dict[Any, tuple[Any, str]] = {}


def reference(scene: guidewire.Scene) -> tuple[Any, str]:
    """:func:`guidewire.reproduction.continuum_reference` of ``scene`` (the equal-lowest continuum shapes; errors are
    taken against the nearest, so mirror twins count), or ``(None, why not)``. Independent of bars and scheme;
    cached."""
    key = (scene.base, scene.contacts, scene.walls, scene.wire.length, scene.wire.bending_stiffness)
    if key not in _REFERENCES:
        try:
            _REFERENCES[key] = continuum_reference(scene)
        except Exception as exc:  # the reference failing is recorded, not fatal
            _REFERENCES[key] = (None, f"reference raised {type(exc).__name__}: {exc}")
    return _REFERENCES[key]


def reference_errors(nodes: np.ndarray, s: np.ndarray, ref: Any) -> tuple[float, float]:
    """Mean and max node error (mm; Eq. 25 via :func:`guidewire.reproduction.node_errors`), nan without reference."""
    if ref is None:
        return math.nan, math.nan
    errors = node_errors(SimpleNamespace(nodes=nodes, s=s), ref)
    return float(errors.mean()), float(errors.max())


def evaluate(form: Formulation, x: Any, ref: Any) -> dict[str, float]:
    """Energy (N·mm), largest violation and node errors (mm) against the continuum reference at angles ``x``."""
    nan = {"energy": math.nan, "max_violation": math.nan, "mean_error_mm": math.nan, "max_error_mm": math.nan}
    if x is None:
        return nan
    x = np.asarray(x, dtype=float)
    if x.shape != (form.n,) or not np.all(np.isfinite(x)):
        return nan
    mean, worst = reference_errors(form.chain.nodes(x), form.chain.arc_lengths, ref)
    return {"energy": float(form.fun(x)), "max_violation": float(np.max(form.violations(x), initial=0.0)),
            "mean_error_mm": mean, "max_error_mm": worst}


def branch(energy: float, violation: float, best: float) -> str:
    """``lowest``, ``near (+δ)`` (same branch, not fully converged), ``other (+δ)``, ``infeasible`` or ``—``."""
    if not np.isfinite(energy) or not np.isfinite(violation):
        return "—"
    if violation > FEASIBILITY_TOL:
        return "infeasible"
    gap = (energy - best) / max(abs(best), 1e-300)
    if gap <= SAME_ENERGY_RTOL:
        return "lowest"
    return f"{'near' if gap <= OTHER_BRANCH_RTOL else 'other'} (+{gap:.1e})"


# ----------------------------------------------------------------------------------------------------------------
# Output
# ----------------------------------------------------------------------------------------------------------------
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


def write_csv(rows: Sequence[dict[str, Any]], path: Path) -> None:
    """All rows (the union of their keys, in first-seen order)."""
    names: list[str] = []
    for row in rows:
        names += [k for k in row if k not in names]
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=names)
        writer.writeheader()
        writer.writerows(rows)


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> list[str]:
    """A Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in rows]
    return lines


def pyplot() -> Any:
    """``matplotlib.pyplot`` on the Agg backend, or None when matplotlib is missing."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    return plt
