"""From the user's input to a validated :class:`~sqp.problem.Problem`: every check made before any iteration.

:func:`build_problem` stacks the user's constraints (SLSQP dicts, ``NonlinearConstraint`` and ``LinearConstraint``)
into nonlinear and linear rows, clips the start into the bounds and evaluates every user function once at the start
to catch wrong shapes early (the solve's first evaluation of the start reuses those values:
:class:`~sqp.problem.StartValues`); it also records the structure the QP backend choice (``qp_solver="auto"``) reads.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import Bounds, LinearConstraint, NonlinearConstraint

from sqp.derivatives import FD_METHODS, FiniteDifferences
from sqp.hessian import DENSE_LIMIT
from sqp.problem import NonlinearBlock, Problem, Rows, StartValues, call_user, check_jacobian_shape

Array = NDArray[np.float64]

#: ``where`` of the evaluations made while the input is checked.
AT_START = "iteration 0 (the start point)"

def _as_vector(value: Any, m: int, name: str) -> Array:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(m, float(arr))
    if arr.shape != (m,):
        raise ValueError(f"{name} has shape {arr.shape}; expected ({m},) or a scalar.")
    return arr


def _check_x0(x0: Any) -> Array:
    """``x0`` as a float vector; a scalar is one variable (as in scipy)."""
    try:
        x = np.atleast_1d(np.array(x0, dtype=float))
    except (TypeError, ValueError) as exc:
        raise TypeError(f"x0 must be a 1-D array of numbers; got {type(x0).__name__}.") from exc
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"x0 has shape {x.shape}; expected a scalar or a non-empty 1-D array (n,). Pass one value "
                         "per variable.")
    if not np.isfinite(x).all():
        raise ValueError(f"x0 has non-finite entries at indices {np.flatnonzero(~np.isfinite(x)).tolist()}; "
                         "start from finite values.")
    return x


def _broadcast_side(value: Any, n: int, name: str) -> Array:
    """One side of the bounds broadcast to ``(n,)`` as scipy does (a scalar or a 1-element array for every
    variable); ``None`` entries of a pair sequence are already infinities here."""
    arr = np.asarray(value, dtype=float)
    try:
        return np.array(np.broadcast_to(arr, (n,)), dtype=float)
    except ValueError:
        raise ValueError(f"{name} has shape {arr.shape}; expected ({n},), a 1-element array or a scalar.") from None


def _check_bounds(bounds: Any, n: int) -> tuple[Array, Array]:
    """Lower and upper bounds of shape ``(n,)`` from ``Bounds`` or ``(lo, hi)`` pairs, broadcast as scipy does (a
    ``Bounds(0, np.inf)`` or a single pair applies to every variable)."""
    if bounds is None:
        return np.full(n, -np.inf), np.full(n, np.inf)
    if isinstance(bounds, Bounds):
        lo = _broadcast_side(bounds.lb, n, "bounds.lb")
        hi = _broadcast_side(bounds.ub, n, "bounds.ub")
    else:
        try:
            pairs = list(bounds)
        except TypeError:
            raise TypeError("bounds must be scipy.optimize.Bounds or a sequence of (lo, hi) pairs.") from None
        if len(pairs) == 0:
            return np.full(n, -np.inf), np.full(n, np.inf)
        if len(pairs) not in (1, n):
            raise ValueError(f"bounds has {len(pairs)} pairs; expected {n} (one (lo, hi) per variable, "
                             "None for an unbounded side) or one pair for every variable.")
        lo = np.empty(len(pairs))
        hi = np.empty(len(pairs))
        for i, pair in enumerate(pairs):
            try:
                a, b = pair
                lo[i] = -np.inf if a is None else _scalar(a)
                hi[i] = np.inf if b is None else _scalar(b)
            except (TypeError, ValueError):
                raise ValueError(f"bounds[{i}] = {pair!r} is not a (lo, hi) pair of numbers or None.") from None
        lo, hi = _broadcast_side(lo, n, "bounds (lower sides)"), _broadcast_side(hi, n, "bounds (upper sides)")
    if np.any(np.isnan(lo)) or np.any(np.isnan(hi)):
        raise ValueError("bounds contain NaN; use None or +-inf for an unbounded side.")
    bad = np.flatnonzero(lo > hi)
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"bounds[{i}] has lo = {lo[i]} > hi = {hi[i]}; every lower bound must be <= its upper bound.")
    return lo, hi


def _start_values(name: str, fun: Callable[[Array], Any], x0: Array) -> Array:
    """A constraint function's values at the start (a copy): it must return a scalar or a 1-D array."""
    arr = np.array(call_user(name, fun, x0, AT_START), dtype=float)
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


def _dict_block(con: dict[str, Any], i: int, x0: Array) -> tuple[NonlinearBlock, Array]:
    """The block of an SLSQP dict and its values at ``x0``."""
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
    c0 = _start_values(f"constraints[{i}]['fun']", f, x0)
    m = c0.size
    lb = np.zeros(m)
    ub = np.zeros(m) if kind == "eq" else np.full(m, np.inf)
    return NonlinearBlock(fun=f, jac=j, lb=lb, ub=ub, hess=hess, name=f"constraints[{i}]", dict_style=True), c0


def _nonlinear_object_block(con: NonlinearConstraint, i: int, x0: Array) -> tuple[NonlinearBlock, Array]:
    """The block of a ``NonlinearConstraint`` and its values at ``x0``."""
    name = f"constraints[{i}]"
    c0 = _start_values(f"{name}.fun", con.fun, x0)
    m = c0.size
    jac = con.jac if callable(con.jac) else None
    lb = _constraint_side(con.lb, m, "lb", name, f"{name}.fun")
    ub = _constraint_side(con.ub, m, "ub", name, f"{name}.fun")
    if np.any(lb > ub):
        raise ValueError(f"constraints[{i}] has lb > ub in rows {np.flatnonzero(lb > ub).tolist()}.")
    hess = con.hess if callable(con.hess) else None
    return NonlinearBlock(fun=con.fun, jac=jac, lb=lb, ub=ub, hess=hess, name=name, dict_style=False), c0


def _scalar(value: Any) -> float:
    """A bound given as a number or a one-element array (scipy accepts both); ValueError for anything larger."""
    arr = np.asarray(value, dtype=float)
    if arr.size != 1:
        raise ValueError(f"{value!r} is not one number")
    return float(arr.reshape(-1)[0])


def build_problem(
    fun: Callable[..., Any],
    x0: Any,
    jac: Any,
    bounds: Any,
    constraints: Any,
    args: tuple[Any, ...] = (),
    hess: Any = None,
    differences: FiniteDifferences | None = None,
    dense_limit: int = DENSE_LIMIT,
) -> Problem:
    """Validate the user's input and stack it into a :class:`Problem` (raises before any solve).

    ``x0`` is clipped into the bounds silently, as SLSQP does (``Problem.x0_clipped`` records where); ``jac=True``
    means that ``fun`` returns ``(f, g)``; a string ``jac`` names a finite-difference scheme, whose settings are
    ``differences`` (default: SLSQP's for that ``jac``).

    Raises
    ------
    TypeError, ValueError
        Naming the argument at fault and how to fix it.
    """
    if not callable(fun):
        raise TypeError("fun must be callable: fun(x) -> float.")
    x = _check_x0(x0)
    n = x.size
    differences = FiniteDifferences.for_jac(jac) if differences is None else differences
    f, grad = _objective(fun, jac, args)
    lower, upper = _check_bounds(bounds, n)
    if bounds is None:  # (x is this function's own copy; nothing to clip)
        xs, clipped = x, np.zeros(0, dtype=np.intp)
    else:
        xs = np.clip(x, lower, upper)
        clipped = np.flatnonzero(xs != x)
    split = _split_constraints(constraints, n, xs)
    A_all, linear = _stack_linear(split, n, n <= dense_limit)
    blocks = split.blocks
    nl_lb = np.concatenate([b.lb for b in blocks]) if blocks else np.zeros(0)
    nl_ub = np.concatenate([b.ub for b in blocks]) if blocks else np.zeros(0)
    start = _check_shapes(f, grad, blocks, xs, split.c0)
    return Problem(
        fun=f,
        grad=grad,
        x0=xs,
        lower=lower,
        upper=upper,
        A=A_all,
        linear=linear,
        blocks=tuple(blocks),
        nonlinear=Rows.from_bounds(nl_lb, nl_ub),
        kinds=tuple(split.kinds),
        linear_sizes=tuple(a.shape[0] for a in split.lin_A),
        hess=_objective_hessian(hess, blocks, args),
        differences=differences,
        dense_limit=dense_limit,
        x0_clipped=clipped,
        sparse_jacobians=(all(J is not None and sp.issparse(J) for J in start.J)
                          and all(sp.issparse(a) for a in split.lin_A)),
        start=start,
    )


def _objective(fun: Callable[..., Any], jac: Any, args: tuple[Any, ...]) -> tuple[Callable[[Array], Any],
                                                                                  Callable[[Array], Any] | None]:
    """The objective and its gradient as functions of ``x`` alone (None: finite differences); ``jac=True`` splits a
    ``fun`` returning ``(f, g)``."""
    if jac is True:
        both = ValueAndGradient(fun)
        fun, jac = both.value, both.gradient
    f = (lambda z: fun(z, *args)) if args else fun
    if jac is None or jac is False or (isinstance(jac, str) and jac in FD_METHODS):
        return f, None
    if callable(jac):
        return f, (lambda z: jac(z, *args)) if args else jac
    raise TypeError(f"jac must be callable, True (fun returns (f, g)), None/False or one of {FD_METHODS}; "
                    f"got {jac!r}.")


@dataclass
class _Split:
    """The user's constraints sorted: nonlinear blocks with their values at the start, linear rows, and the kind of
    each constraint in the order given."""

    blocks: list[NonlinearBlock] = field(default_factory=list)
    c0: list[Array] = field(default_factory=list)
    lin_A: list[Any] = field(default_factory=list)
    lin_lb: list[Array] = field(default_factory=list)
    lin_ub: list[Array] = field(default_factory=list)
    kinds: list[str] = field(default_factory=list)


def _split_constraints(constraints: Any, n: int, xs: Array) -> _Split:
    """Check each constraint and sort it into :class:`_Split` (nonlinear ones are evaluated at ``xs``)."""
    if isinstance(constraints, dict | LinearConstraint | NonlinearConstraint):
        constraints = (constraints,)
    out = _Split()
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
            out.lin_A.append(A)
            out.lin_lb.append(lb)
            out.lin_ub.append(ub)
            out.kinds.append("linear")
        elif isinstance(con, NonlinearConstraint | dict):
            block, values = (_nonlinear_object_block if isinstance(con, NonlinearConstraint) else _dict_block)(
                con, i, xs)
            out.blocks.append(block)
            out.c0.append(values)
            out.kinds.append("nonlinear")
        else:
            raise TypeError(f"constraints[{i}] is a {type(con).__name__}; expected a dict "
                            "{'type': 'eq'|'ineq', 'fun': ..., 'jac': ...}, "
                            "a NonlinearConstraint or a LinearConstraint.")
    return out


def _stack_linear(split: _Split, n: int, dense: bool) -> tuple[Any, Rows]:
    """The linear rows stacked into one matrix and their :class:`Rows`: dense where the engine works densely
    (``dense``: up to :attr:`Problem.dense_limit` variables), as the
    engine keeps every matrix there (a sparse A would make each iteration's rows sparse, sending an equality QP to a
    backend instead of the direct KKT solve and costing scipy.sparse stacking: the paper scheme's Table 1 at 100
    bars 8.8 -> 3 ms), sparse above it when any block is."""
    if not split.lin_A:
        return np.zeros((0, n)), Rows.from_bounds(np.zeros(0), np.zeros(0))
    if dense:
        A_all = np.vstack([a.toarray() if sp.issparse(a) else a for a in split.lin_A])
    elif any(sp.issparse(a) for a in split.lin_A):
        A_all = sp.vstack([sp.csr_matrix(a) for a in split.lin_A], format="csr")
    else:
        A_all = np.vstack(split.lin_A)
    return A_all, Rows.from_bounds(np.concatenate(split.lin_lb), np.concatenate(split.lin_ub))


def _objective_hessian(hess: Any, blocks: list[NonlinearBlock], args: tuple[Any, ...]) -> Callable[[Array], Any] | None:
    """``hess`` as a function of ``x`` alone, checked: callable, and every nonlinear block carries its own Hessian."""
    if hess is None:
        return None
    if not callable(hess):
        raise TypeError("hess must be callable: hess(x) -> (n, n) Hessian of fun (array or sparse matrix).")
    missing = [i for i, b in enumerate(blocks) if b.hess is None]
    if missing:
        raise ValueError(f"hess is given but nonlinear constraint block(s) {missing} have no Hessian; give each a "
                         "'hess' (dict key or NonlinearConstraint.hess) as hess(x, v), or drop hess to use BFGS.")
    return (lambda z: hess(z, *args)) if args else hess


class ValueAndGradient:
    """``fun`` returning ``(f, g)`` (``jac=True``) as a value and a gradient function, one call per point: the
    gradient at the point last evaluated is the one that call returned."""

    def __init__(self, fun: Callable[..., Any]) -> None:
        self.fun = fun
        self.x: Array | None = None
        self.g: Array | None = None

    def value(self, x: Array, *args: Any) -> Any:
        out = self.fun(x, *args)
        try:
            f, g = out
        except (TypeError, ValueError):
            raise TypeError("jac=True means that fun returns a pair (f, g), the value and the gradient; it returned "
                            f"{type(out).__name__}.") from None
        self.x, self.g = np.array(x, dtype=float), np.asarray(g, dtype=float)
        return f

    def gradient(self, x: Array, *args: Any) -> Array:
        if self.x is None or self.g is None or not np.array_equal(x, self.x):
            self.value(x, *args)
        assert self.g is not None
        return self.g


def _check_shapes(fun: Callable[[Array], Any], grad: Callable[[Array], Any] | None,
                  blocks: list[NonlinearBlock], x: Array, c0: list[Array]) -> StartValues:
    """Evaluate the objective, its gradient and the constraint Jacobians once at the (clipped) start ``x`` to catch
    non-scalar objectives and wrong shapes early.

    Returns what they gave, with the constraint values ``c0`` (copies: a function that reuses its output buffer
    cannot change them), for the solve's first evaluation of ``x``."""
    n = x.size
    f = np.array(call_user("fun", fun, x, AT_START))
    if f.size != 1:
        raise ValueError(f"fun returned an array of shape {f.shape}; it must return a scalar (the objective value).")
    g = None
    if grad is not None:
        g = np.array(call_user("jac", grad, x, AT_START), dtype=float)
        if g.shape != (n,):
            raise ValueError(f"jac returned shape {g.shape}; expected ({n},): the gradient of fun.")
    J = tuple(None if block.jac is None  # (finite differences: dense, evaluated by the solve)
              else check_jacobian_shape(block, call_user(block.part("jac"), block.jac, x, AT_START), n, "x0").copy()
              for block in blocks)
    return StartValues(x=x, f=f, g=g, c=tuple(c0), J=J)
