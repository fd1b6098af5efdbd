"""The problem as the engine sees it: bounds, linear rows and nonlinear rows (built and checked by :mod:`sqp.build`).

Every user constraint (an SLSQP dict, a ``NonlinearConstraint`` or a ``LinearConstraint``) becomes a block of rows
``lb <= c(x) <= ub``; rows with ``lb == ub`` are equalities. The engine works with the stacked rows and maps the
multipliers back to the user's blocks at the end (:meth:`Problem.split_multipliers`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from sqp.compressed import as_csr
from sqp.derivatives import FiniteDifferences
from sqp.hessian import DENSE_LIMIT

Array = NDArray[np.float64]


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


#: The (read-only) index set of no rows, shared by every empty :class:`Rows`.
_NO_ROWS = np.zeros(0, dtype=np.intp)
_NO_ROWS.setflags(write=False)


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
        if lb.size == 0:
            return cls(lb=lb, ub=ub, eq=_NO_ROWS, lower=_NO_ROWS, upper=_NO_ROWS)
        is_eq = lb == ub
        if is_eq.all():  # (an SLSQP eq dict: every row an equality)
            return cls(lb=lb, ub=ub, eq=np.arange(lb.size, dtype=np.intp), lower=_NO_ROWS, upper=_NO_ROWS)
        return cls(
            lb=lb,
            ub=ub,
            eq=np.flatnonzero(is_eq),
            lower=np.flatnonzero(~is_eq & np.isfinite(lb)),
            upper=np.flatnonzero(~is_eq & np.isfinite(ub)),
        )

    @cached_property
    def is_eq(self) -> NDArray[np.bool_]:
        """Which rows are equalities (``lb == ub``): the mask of :attr:`eq`."""
        mask = np.zeros(self.lb.size, dtype=bool)
        mask[self.eq] = True
        return mask

    @cached_property
    def inequality_without_lower(self) -> NDArray[np.intp]:
        """Inequality rows with no finite lower side (a positive multiplier there has the wrong sign)."""
        return np.flatnonzero((self.lb != self.ub) & ~np.isfinite(self.lb))

    @cached_property
    def inequality_without_upper(self) -> NDArray[np.intp]:
        """Inequality rows with no finite upper side (a negative multiplier there has the wrong sign)."""
        return np.flatnonzero((self.lb != self.ub) & ~np.isfinite(self.ub))

    @cached_property
    def finite_equalities(self) -> bool:
        """Whether every row is an equality with a finite side (:meth:`violation`'s shortcut)."""
        return bool(self.eq.size == self.lb.size and np.isfinite(self.lb).all())

    def violation(self, r: Array) -> Array:
        """Row-wise violation ``max(lb - r, r - ub, 0)`` (``|r - lb|`` for equalities)."""
        if self.lb.size == 0:
            return np.zeros(0)
        if self.finite_equalities:
            # (the same numbers: r - lb is exactly -(lb - r), so the maximum of the two and 0 is |r - lb|; a finite
            # lb raises no invalid-operation flag)
            return np.abs(r - self.lb)
        with np.errstate(invalid="ignore"):
            return np.maximum(np.maximum(self.lb - r, r - self.ub), 0.0)


@dataclass(frozen=True)
class StartValues:
    """What the user functions returned at the (clipped) start ``x`` when :func:`sqp.build.build_problem` called them
    to check their shapes (copies, converted as the checks converted them): the solve's first evaluation of that
    same point reuses them instead of calling again (:class:`sqp.iterate.Evaluator`).

    ``f`` is the objective's value, ``g`` the gradient (None with finite differences); ``c`` and ``J`` hold one entry
    per nonlinear block, its values and its checked Jacobian (None where it is differenced).
    """

    x: Array
    f: Any
    g: Array | None
    c: tuple[Array, ...]
    J: tuple[Any, ...]


#: One of SLSQP's constraint dicts as :attr:`Problem.slsqp_rows` builds it: its kind, the rows' places in the
#: concatenated multipliers, their signs and which of them are two-sided.
_SlsqpPart = tuple[str, Array, Array, NDArray[np.bool_]]


def _slsqp_parts(offset: int, lb: Array, ub: Array) -> tuple[_SlsqpPart | None, _SlsqpPart | None]:
    """The equality dict and the inequality dict scipy's SLSQP makes of one constraint with sides ``lb``, ``ub``
    whose rows start at ``offset`` (None where it makes none): ``lb == ub`` rows; then rows with a finite lower side
    (sign +1), then those with a finite upper side (sign -1)."""
    eq = lb == ub
    low = np.flatnonzero(~eq & np.isfinite(lb))
    up = np.flatnonzero(~eq & np.isfinite(ub))
    both = np.isfinite(lb) & np.isfinite(ub) & ~eq
    ineq = ("ineq", offset + np.concatenate([low, up]), np.concatenate([np.ones(low.size), -np.ones(up.size)]),
            np.concatenate([both[low], both[up]]))
    count = int(np.sum(eq))
    eq_part = ("eq", offset + np.flatnonzero(eq), np.ones(count), np.zeros(count, dtype=bool)) if count else None
    return eq_part, (ineq if ineq[1].size else None)


def _slsqp_order(sides: list[tuple[Array, Array]]) -> list[_SlsqpPart]:
    """SLSQP's dicts of constraints with these sides, in its order: every equality dict, then every inequality dict,
    an inequality dict placed with its constraint when that has no equality rows and appended after all otherwise."""
    offsets = np.cumsum([0] + [lb.size for lb, _ in sides])
    placed: list[_SlsqpPart] = []
    appended: list[_SlsqpPart] = []
    for k, (lb, ub) in enumerate(sides):
        eq, ineq = _slsqp_parts(int(offsets[k]), lb, ub)
        if eq is not None:
            placed.append(eq)
            if ineq is not None:
                appended.append(ineq)
        elif ineq is not None:
            placed.append(ineq)
    order = placed + appended
    return [p for p in order if p[0] == "eq"] + [p for p in order if p[0] == "ineq"]


def _stack_parts(parts: list[_SlsqpPart]) -> tuple[NDArray[np.intp], Array, NDArray[np.bool_]]:
    """The parts' indices, signs and two-sided flags, each concatenated."""
    if not parts:
        return np.zeros(0, dtype=np.intp), np.zeros(0), np.zeros(0, dtype=bool)
    return (np.concatenate([p[1] for p in parts]).astype(np.intp), np.concatenate([p[2] for p in parts]),
            np.concatenate([p[3] for p in parts]))


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
    differences : FiniteDifferences
        How the derivatives the user did not give are approximated (SLSQP's rule).
    x0_clipped : ndarray of int
        Indices where the user's ``x0`` lay outside the bounds and was clipped onto them (as SLSQP does, silently).
    start : StartValues or None
        The user functions' values at ``x0``, computed while the input was checked.
    sparse_jacobians : bool
        Whether every constraint Jacobian is a scipy.sparse matrix: each nonlinear constraint's ``jac`` at ``x0`` (a
        finite-difference one is dense) and each ``LinearConstraint.A``. True without constraints. Read once, by
        ``qp_solver="auto"`` (:func:`sqp.backends.choose_qp_solver`).
    dense_limit : int
        The most variables at which the engine works with dense matrices (:attr:`dense`; the ``dense_limit`` of
        :func:`sqp.minimize`, default :data:`sqp.DENSE_LIMIT`).
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
    sparse_jacobians: bool = True
    dense_limit: int = DENSE_LIMIT
    differences: FiniteDifferences = FiniteDifferences()
    x0_clipped: NDArray[np.intp] = field(default_factory=lambda: np.zeros(0, dtype=np.intp))
    start: StartValues | None = field(default=None, repr=False, compare=False)

    @property
    def n(self) -> int:
        return self.x0.size

    @property
    def dense(self) -> bool:
        """Whether the engine works with dense matrices here (``n <= dense_limit``): the Lagrangian Hessian, the
        linear rows and the QP backend ``"auto"`` picks (DAQP)."""
        return self.x0.size <= self.dense_limit

    @cached_property
    def differenced(self) -> bool:
        """Whether some derivative is a finite difference (the gradient or a nonlinear constraint's Jacobian)."""
        return self.grad is None or any(block.jac is None for block in self.blocks)

    @cached_property
    def bound_rows(self) -> Rows:
        """The bounds as rows ``lower <= x <= upper``."""
        return Rows.from_bounds(self.lower, self.upper)

    @cached_property
    def has_bounds(self) -> bool:
        return bool(np.any(np.isfinite(self.lower)) or np.any(np.isfinite(self.upper)))

    @cached_property
    def equality_only(self) -> bool:
        """No inequality side on any row and no finite bound: the problems whose QPs the structured KKT path serves."""
        return not (any(r.lower.size or r.upper.size for r in (self.nonlinear, self.linear)) or self.has_bounds)

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

    def constraint_sides(self) -> list[tuple[Array, Array]]:
        """``(lb, ub)`` of every user constraint, in the order given (an ``ineq`` dict is ``(0, inf)``)."""
        out: list[tuple[Array, Array]] = []
        blocks = iter(self.blocks)
        start = 0
        sizes = iter(self.linear_sizes)
        for kind in self.kinds:
            if kind == "linear":
                m = next(sizes)
                out.append((self.linear.lb[start : start + m], self.linear.ub[start : start + m]))
                start += m
            else:
                block = next(blocks)
                out.append((block.lb, block.ub))
        return out

    @cached_property
    def slsqp_rows(self) -> tuple[NDArray[np.intp], Array, NDArray[np.bool_]]:
        """Where SLSQP's multiplier array comes from: ``res.multipliers = sign * flat[index]`` (clipped at 0 on the
        rows of ``two_sided``), with ``flat`` the per-constraint multipliers concatenated in the order given.

        scipy's SLSQP turns each ``NonlinearConstraint``/``LinearConstraint`` into an equality dict (its ``lb == ub``
        rows, in its place) and an inequality dict (rows with a finite lower side as ``fun - lb >= 0``, then rows
        with a finite upper side as ``ub - fun >= 0``; in its place when there are no equality rows, else appended
        after every constraint); rows unbounded on both sides are dropped. It then lists every equality row, then
        every inequality row, and its multipliers are ``>= 0`` on ``g(x) >= 0`` with ``grad f = sum mu grad g``:
        ours on a lower side, and ours negated on an upper side; a row with both sides finite appears twice, its
        multiplier on the side its sign belongs to and 0 on the other.
        """
        if not self.linear_sizes and all(b.dict_style for b in self.blocks):
            return self._slsqp_rows_of_dicts()
        return _stack_parts(_slsqp_order(self.constraint_sides()))

    def _slsqp_rows_of_dicts(self) -> tuple[NDArray[np.intp], Array, NDArray[np.bool_]]:
        """:attr:`slsqp_rows` when every constraint is an SLSQP dict (``eq``: ``lb = ub = 0``, ``ineq``: ``lb = 0,
        ub = inf``): the rows of the ``eq`` dicts, then those of the ``ineq`` dicts, each in the order given, with
        sign +1 and none two-sided."""
        offsets = [0]
        for b in self.blocks:
            offsets.append(offsets[-1] + b.size)
        ranges = [np.arange(offsets[k], offsets[k + 1], dtype=np.intp) for k in range(len(self.blocks))]
        is_eq = [bool(b.size) and b.ub[0] < np.inf for b in self.blocks]
        eq = [r for r, e in zip(ranges, is_eq, strict=True) if e]
        ineq = [r for r, e in zip(ranges, is_eq, strict=True) if not e]
        index = eq[0] if len(eq) == 1 and not ineq else np.concatenate(eq + ineq + [np.zeros(0, np.intp)])
        return index, np.ones(index.size), np.zeros(index.size, dtype=bool)

    def slsqp_multipliers(self, per_constraint: list[Array]) -> Array:
        """The multipliers as scipy's SLSQP returns them (:attr:`slsqp_rows`) from one array per constraint."""
        flat = np.concatenate(per_constraint) if per_constraint else np.zeros(0)
        if self._slsqp_order_is_given:  # (index = all rows in order, sign = 1, none two-sided)
            return flat
        index, sign, two_sided = self.slsqp_rows
        out = sign * flat[index]
        return np.where(two_sided, np.maximum(out, 0.0), out) if two_sided.any() else out

    @property
    def _slsqp_order_is_given(self) -> bool:
        """Whether SLSQP's multipliers are the constraints' own, in the order given: every constraint an SLSQP dict,
        all of one type (:meth:`_slsqp_rows_of_dicts` lists the ``eq`` ones first)."""
        if self.linear_sizes or not all(b.dict_style for b in self.blocks):
            return False
        return len({bool(b.ub[0] < np.inf) for b in self.blocks if b.size}) <= 1

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
    return as_csr(J) if sp.issparse(J) else J
