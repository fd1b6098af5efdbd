"""The problem as the engine sees it: bounds, linear rows and nonlinear rows, checked before any work.

Every user constraint (an SLSQP dict, a ``NonlinearConstraint`` or a ``LinearConstraint``) becomes a block of rows
``lb <= c(x) <= ub``; rows with ``lb == ub`` are equalities. The engine works with the stacked rows and maps the
multipliers back to the user's blocks at the end (:meth:`Problem.split_multipliers`).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import Bounds, LinearConstraint, NonlinearConstraint

Array = NDArray[np.float64]

#: A start this close to a bound (relative to ``max(1, |bound|)``) is rounding, and is clipped without a warning.
START_ROUNDING = 1e-12


class StartPointWarning(UserWarning):
    """``x0`` lies outside the bounds; the solve starts from its projection onto them (``clip(x0, lb, ub)``)."""


def format_point(x: Array) -> str:
    """A short rendering of a point for messages (the first and last few entries of a long one)."""
    return np.array2string(np.asarray(x, dtype=float), precision=6, threshold=8, edgeitems=3, separator=", ")


def call_user(name: str, fn: Callable[..., Any], x: Array, where: str, *extra: Any) -> Any:
    """``fn(x.copy(), *extra)``; an exception it raises propagates unchanged (same object, same type) with a note
    naming ``name``, ``where`` (e.g. ``"iteration 3"``) and ``x``."""
    try:
        return fn(x.copy(), *extra)
    except Exception as exc:
        exc.add_note(f"sqp.minimize: raised by {name} at {where} (x = {format_point(x)}).")
        raise


#: ``where`` of the evaluations made while the input is checked.
AT_START = "iteration 0 (the start point)"


@dataclass(frozen=True)
class NonlinearBlock:
    """One user constraint with nonlinear rows ``lb <= fun(x) <= ub``.

    ``name`` is the constraint as the user gave it (``"constraints[1]"``); ``dict_style`` says whether it was an
    SLSQP dict (its parts are then named ``constraints[1]['fun']``, otherwise ``constraints[1].fun``).
    """

    fun: Callable[[Array], Array]
    jac: Callable[[Array], Array] | None  # None: finite differences
    lb: Array
    ub: Array
    hess: Callable[[Array, Array], Any] | None = None  # hess(x, v) = sum_i v_i * Hessian of row i
    name: str = "constraints[?]"
    dict_style: bool = True

    @property
    def size(self) -> int:
        return self.lb.size

    def part(self, attr: str) -> str:
        """How the user names one of this constraint's callables, e.g. ``constraints[1]['jac']``."""
        return f"{self.name}[{attr!r}]" if self.dict_style else f"{self.name}.{attr}"


@dataclass(frozen=True)
class Rows:
    """Index sets of stacked rows ``lb <= r <= ub``: equalities, finite lower sides, finite upper sides."""

    lb: Array
    ub: Array
    eq: NDArray[np.intp]
    lower: NDArray[np.intp]
    upper: NDArray[np.intp]

    @classmethod
    def from_bounds(cls, lb: Array, ub: Array) -> Rows:
        is_eq = lb == ub
        return cls(
            lb=lb,
            ub=ub,
            eq=np.flatnonzero(is_eq),
            lower=np.flatnonzero(~is_eq & np.isfinite(lb)),
            upper=np.flatnonzero(~is_eq & np.isfinite(ub)),
        )

    @cached_property
    def inequality_without_lower(self) -> NDArray[np.intp]:
        """Inequality rows with no finite lower side (a positive multiplier there has the wrong sign)."""
        return np.flatnonzero((self.lb != self.ub) & ~np.isfinite(self.lb))

    @cached_property
    def inequality_without_upper(self) -> NDArray[np.intp]:
        """Inequality rows with no finite upper side (a negative multiplier there has the wrong sign)."""
        return np.flatnonzero((self.lb != self.ub) & ~np.isfinite(self.ub))

    def violation(self, r: Array) -> Array:
        """Row-wise violation ``max(lb - r, r - ub, 0)`` (``|r - lb|`` for equalities)."""
        with np.errstate(invalid="ignore"):
            return np.maximum(np.maximum(self.lb - r, r - self.ub), 0.0)


@dataclass(frozen=True)
class Problem:
    """A validated nonlinear program ``min f(x)`` s.t. bounds, linear rows and nonlinear rows.

    Attributes
    ----------
    n : int
        Number of variables.
    lower, upper : ndarray, shape (n,)
        Variable bounds (``-inf``/``inf`` where absent).
    A : ndarray or sparse matrix, shape (m_lin, n)
        Stacked linear rows with their :class:`Rows` ``linear``.
    blocks : tuple of NonlinearBlock
        Nonlinear user constraints in the order given; their rows stack into ``nonlinear``.
    kinds : tuple of str
        For every user constraint, ``"linear"`` or ``"nonlinear"``, in the order given.
    """

    fun: Callable[[Array], Any]
    grad: Callable[[Array], Array] | None
    x0: Array
    lower: Array
    upper: Array
    A: Any
    linear: Rows
    blocks: tuple[NonlinearBlock, ...]
    nonlinear: Rows
    kinds: tuple[str, ...]
    linear_sizes: tuple[int, ...]
    hess: Callable[[Array], Any] | None = None

    @property
    def n(self) -> int:
        return self.x0.size

    @cached_property
    def bound_rows(self) -> Rows:
        """The bounds as rows ``lower <= x <= upper``."""
        return Rows.from_bounds(self.lower, self.upper)

    @cached_property
    def has_bounds(self) -> bool:
        return bool(np.any(np.isfinite(self.lower)) or np.any(np.isfinite(self.upper)))

    def stack_nonlinear_multipliers(self, per_constraint: Any) -> Array:
        """The nonlinear rows' multipliers from one array per user constraint (the inverse of the nonlinear part of
        :meth:`split_multipliers`); ValueError when the shapes do not match."""
        per_constraint = list(per_constraint)
        if len(per_constraint) != len(self.kinds):
            raise ValueError(f"multipliers0 has {len(per_constraint)} arrays; expected {len(self.kinds)} (one per "
                             "constraint, as in res.constraint_multipliers).")
        parts = [np.asarray(v, dtype=float).ravel() for v, k in zip(per_constraint, self.kinds, strict=True)
                 if k == "nonlinear"]
        out = np.concatenate(parts) if parts else np.zeros(0)
        if out.size != self.nonlinear.lb.size or not np.all(np.isfinite(out)):
            raise ValueError(f"multipliers0 holds {out.size} nonlinear multipliers; expected "
                             f"{self.nonlinear.lb.size} finite values.")
        return out

    def split_multipliers(self, lam_lin: Array, lam_nl: Array) -> list[Array]:
        """The stacked row multipliers as one array per user constraint, in the order given."""
        out: list[Array] = []
        i_lin = i_nl = 0
        sizes_nl = [b.size for b in self.blocks]
        k_lin = k_nl = 0
        for kind in self.kinds:
            if kind == "linear":
                m = self.linear_sizes[k_lin]
                out.append(lam_lin[i_lin : i_lin + m].copy())
                i_lin += m
                k_lin += 1
            else:
                m = sizes_nl[k_nl]
                out.append(lam_nl[i_nl : i_nl + m].copy())
                i_nl += m
                k_nl += 1
        return out


def _as_vector(value: Any, m: int, name: str) -> Array:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(m, float(arr))
    if arr.shape != (m,):
        raise ValueError(f"{name} has shape {arr.shape}; expected ({m},) or a scalar.")
    return arr


def _check_x0(x0: Any) -> Array:
    try:
        x = np.array(x0, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"x0 must be a 1-D array of numbers; got {type(x0).__name__}.") from exc
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"x0 has shape {x.shape}; expected a non-empty 1-D array (n,). Pass one value per variable.")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"x0 has non-finite entries at indices {np.flatnonzero(~np.isfinite(x)).tolist()}; "
                         "start from finite values.")
    return x


def _check_bounds(bounds: Any, n: int) -> tuple[Array, Array]:
    if bounds is None:
        return np.full(n, -np.inf), np.full(n, np.inf)
    if isinstance(bounds, Bounds):
        lo = _as_vector(bounds.lb, n, "bounds.lb")
        hi = _as_vector(bounds.ub, n, "bounds.ub")
    else:
        try:
            pairs = list(bounds)
        except TypeError:
            raise TypeError("bounds must be scipy.optimize.Bounds or a sequence of (lo, hi) pairs.") from None
        if len(pairs) != n:
            raise ValueError(f"bounds has {len(pairs)} pairs; expected {n} (one (lo, hi) per variable, "
                             "None for an unbounded side).")
        lo = np.empty(n)
        hi = np.empty(n)
        for i, pair in enumerate(pairs):
            try:
                a, b = pair
            except (TypeError, ValueError):
                raise ValueError(f"bounds[{i}] = {pair!r} is not a (lo, hi) pair.") from None
            lo[i] = -np.inf if a is None else float(a)
            hi[i] = np.inf if b is None else float(b)
    if np.any(np.isnan(lo)) or np.any(np.isnan(hi)):
        raise ValueError("bounds contain NaN; use None or +-inf for an unbounded side.")
    bad = np.flatnonzero(lo > hi)
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"bounds[{i}] has lo = {lo[i]} > hi = {hi[i]}; every lower bound must be <= its upper bound.")
    return lo, hi


def _start_values(name: str, fun: Callable[[Array], Any], x0: Array) -> Array:
    """A constraint function's values at the start: it must return a scalar or a 1-D array."""
    arr = np.asarray(call_user(name, fun, x0, AT_START), dtype=float)
    if arr.ndim > 1:
        raise ValueError(f"{name} returned an array of shape {arr.shape} at x0; a constraint function must return a "
                         "scalar or a 1-D array (m,).")
    return np.atleast_1d(arr)


def _constraint_side(value: Any, m: int, side: str, con_name: str, fun_name: str) -> Array:
    """``lb`` or ``ub`` of a NonlinearConstraint: a scalar or one entry per value its fun returns."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        return np.full(m, float(arr))
    if arr.shape != (m,):
        raise ValueError(f"{fun_name} returned {m} value(s) at x0 but {con_name}.{side} has {arr.size} (shape "
                         f"{arr.shape}); give lb and ub as scalars or with one entry per value of fun.")
    return arr


def _dict_block(con: dict[str, Any], i: int, x0: Array) -> NonlinearBlock:
    kind = con.get("type")
    if kind not in ("eq", "ineq"):
        raise ValueError(f"constraints[{i}]['type'] = {kind!r}; expected 'eq' or 'ineq' ('ineq' means fun(x) >= 0).")
    fun = con.get("fun")
    if not callable(fun):
        raise TypeError(f"constraints[{i}]['fun'] must be callable.")
    args = tuple(con.get("args", ()))
    f = (lambda x, _f=fun, _a=args: _f(x, *_a)) if args else fun
    jac = con.get("jac")
    if jac is not None and not callable(jac):
        if jac in ("2-point", "3-point", "cs"):
            jac = None
        else:
            raise TypeError(f"constraints[{i}]['jac'] must be callable or None.")
    j = (lambda x, _j=jac, _a=args: _j(x, *_a)) if (args and jac is not None) else jac
    hess = con.get("hess")
    if hess is not None and not callable(hess):
        raise TypeError(f"constraints[{i}]['hess'] must be callable: hess(x, v) = sum_i v_i * Hessian of row i.")
    m = _start_values(f"constraints[{i}]['fun']", f, x0).size
    lb = np.zeros(m)
    ub = np.zeros(m) if kind == "eq" else np.full(m, np.inf)
    return NonlinearBlock(fun=f, jac=j, lb=lb, ub=ub, hess=hess, name=f"constraints[{i}]", dict_style=True)


def _nonlinear_object_block(con: NonlinearConstraint, i: int, x0: Array) -> NonlinearBlock:
    name = f"constraints[{i}]"
    m = _start_values(f"{name}.fun", con.fun, x0).size
    jac = con.jac if callable(con.jac) else None
    lb = _constraint_side(con.lb, m, "lb", name, f"{name}.fun")
    ub = _constraint_side(con.ub, m, "ub", name, f"{name}.fun")
    if np.any(lb > ub):
        raise ValueError(f"constraints[{i}] has lb > ub in rows {np.flatnonzero(lb > ub).tolist()}.")
    hess = con.hess if callable(con.hess) else None
    return NonlinearBlock(fun=con.fun, jac=jac, lb=lb, ub=ub, hess=hess, name=name, dict_style=False)


def _project_start(x: Array, lower: Array, upper: Array) -> Array:
    """``x0`` clipped into the bounds, with a :class:`StartPointWarning` when it was genuinely outside them (a start
    within rounding of a bound, :data:`START_ROUNDING`, is clipped silently)."""
    xs = np.clip(x, lower, upper)
    outside = np.flatnonzero(np.abs(xs - x) > START_ROUNDING * np.maximum(1.0, np.abs(xs)))  # xs: the bound
    if outside.size:
        shown = ", ".join(f"x0[{i}] = {x[i]:.6g} not in [{lower[i]:.6g}, {upper[i]:.6g}]" for i in outside[:3])
        more = f" and {outside.size - 3} more" if outside.size > 3 else ""
        indices = outside[:5].tolist()
        warnings.warn(f"x0 is outside the bounds at indices {indices}{'...' if outside.size > 5 else ''} ({shown}"
                      f"{more}); it was projected onto the bounds (clipped) and the solve starts from there.",
                      StartPointWarning, stacklevel=4)
    return xs


def build_problem(
    fun: Callable[..., Any],
    x0: Any,
    jac: Any,
    bounds: Any,
    constraints: Any,
    args: tuple[Any, ...] = (),
    hess: Any = None,
) -> Problem:
    """Validate the user's input and stack it into a :class:`Problem` (raises before any solve).

    Raises
    ------
    TypeError, ValueError
        Naming the argument at fault and how to fix it.
    """
    if not callable(fun):
        raise TypeError("fun must be callable: fun(x) -> float.")
    x = _check_x0(x0)
    n = x.size
    f = (lambda z: fun(z, *args)) if args else fun
    if jac is True:
        raise ValueError("jac=True (fun returning (f, g)) is not supported; pass the gradient as a callable.")
    if jac is None or (isinstance(jac, str) and jac in ("2-point", "3-point", "cs")):
        grad = None
    elif callable(jac):
        grad = (lambda z: jac(z, *args)) if args else jac
    else:
        raise TypeError(f"jac must be callable, None or '2-point'; got {jac!r}.")
    lower, upper = _check_bounds(bounds, n)
    xs = _project_start(x, lower, upper)

    if isinstance(constraints, dict | LinearConstraint | NonlinearConstraint):
        constraints = (constraints,)
    blocks: list[NonlinearBlock] = []
    lin_A: list[Any] = []
    lin_lb: list[Array] = []
    lin_ub: list[Array] = []
    kinds: list[str] = []
    for i, con in enumerate(constraints or ()):
        if isinstance(con, LinearConstraint):
            A = con.A
            A = A if sp.issparse(A) else np.atleast_2d(np.asarray(A, dtype=float))
            if A.shape[1] != n:
                raise ValueError(f"constraints[{i}] (LinearConstraint) has A with {A.shape[1]} columns; expected {n}.")
            m = A.shape[0]
            lb = _as_vector(con.lb, m, f"constraints[{i}].lb")
            ub = _as_vector(con.ub, m, f"constraints[{i}].ub")
            if np.any(lb > ub):
                raise ValueError(f"constraints[{i}] has lb > ub in rows {np.flatnonzero(lb > ub).tolist()}.")
            lin_A.append(A)
            lin_lb.append(lb)
            lin_ub.append(ub)
            kinds.append("linear")
        elif isinstance(con, NonlinearConstraint):
            blocks.append(_nonlinear_object_block(con, i, xs))
            kinds.append("nonlinear")
        elif isinstance(con, dict):
            blocks.append(_dict_block(con, i, xs))
            kinds.append("nonlinear")
        else:
            raise TypeError(f"constraints[{i}] is a {type(con).__name__}; expected a dict "
                            "{'type': 'eq'|'ineq', 'fun': ..., 'jac': ...}, "
                            "a NonlinearConstraint or a LinearConstraint.")
    if lin_A:
        if any(sp.issparse(a) for a in lin_A):
            A_all = sp.vstack([sp.csr_matrix(a) for a in lin_A], format="csr")
        else:
            A_all = np.vstack(lin_A)
        linear = Rows.from_bounds(np.concatenate(lin_lb), np.concatenate(lin_ub))
    else:
        A_all = np.zeros((0, n))
        linear = Rows.from_bounds(np.zeros(0), np.zeros(0))
    nl_lb = np.concatenate([b.lb for b in blocks]) if blocks else np.zeros(0)
    nl_ub = np.concatenate([b.ub for b in blocks]) if blocks else np.zeros(0)
    if hess is not None:
        if not callable(hess):
            raise TypeError("hess must be callable: hess(x) -> (n, n) Hessian of fun (array or sparse matrix).")
        missing = [i for i, b in enumerate(blocks) if b.hess is None]
        if missing:
            raise ValueError(f"hess is given but nonlinear constraint block(s) {missing} have no Hessian; give each a "
                             "'hess' (dict key or NonlinearConstraint.hess) as hess(x, v), or drop hess to use BFGS.")
        hess_f = (lambda z: hess(z, *args)) if args else hess
    else:
        hess_f = None
    problem = Problem(
        fun=f,
        grad=grad,
        x0=xs,
        lower=lower,
        upper=upper,
        A=A_all,
        linear=linear,
        blocks=tuple(blocks),
        nonlinear=Rows.from_bounds(nl_lb, nl_ub),
        kinds=tuple(kinds),
        linear_sizes=tuple(a.shape[0] for a in lin_A),
        hess=hess_f,
    )
    _check_shapes(problem, xs)
    return problem


def _check_shapes(problem: Problem, x: Array) -> None:
    """Evaluate once at the (projected) start to catch non-scalar objectives and wrong Jacobian shapes early."""
    n = problem.n
    f = np.asarray(call_user("fun", problem.fun, x, AT_START))
    if f.size != 1:
        raise ValueError(f"fun returned an array of shape {f.shape}; it must return a scalar (the objective value).")
    if problem.grad is not None:
        g = np.asarray(call_user("jac", problem.grad, x, AT_START), dtype=float)
        if g.shape != (n,):
            raise ValueError(f"jac returned shape {g.shape}; expected ({n},): the gradient of fun.")
    for block in problem.blocks:
        if block.jac is not None:
            check_jacobian_shape(block, call_user(block.part("jac"), block.jac, x, AT_START), n, "x0")


def check_jacobian_shape(block: NonlinearBlock, J: Any, n: int, where: str) -> Any:
    """``J`` as CSR (sparse) or a dense ``(m, n)`` array; ValueError naming the constraint when its shape is wrong.

    A dense answer may be 1-D for a single row."""
    if sp.issparse(J):
        shape = J.shape
    else:
        J = np.atleast_2d(np.asarray(J, dtype=float))
        shape = J.shape
    if shape != (block.size, n):
        raise ValueError(f"{block.part('jac')} returned shape {shape} at {where}; expected ({block.size}, {n}): one "
                         "row per value of its fun, one column per variable.")
    return sp.csr_matrix(J) if sp.issparse(J) else J
