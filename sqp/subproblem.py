"""The QP subproblem (paper Eqs. 9–10) and its elastic relaxation, assembled and solved (:mod:`sqp.qp_call` asks the
qpsolvers backends and checks every answer).

At an iterate ``x`` with nonlinear rows ``lb <= c(x) <= ub`` (Jacobian ``J``), linear rows ``lb <= A x <= ub`` and
bounds ``lower <= x <= upper`` the step ``d`` solves

    min  1/2 d^T B d + g^T d
    s.t. lb <= c + J d <= ub,   lb <= A (x + d) <= ub,   lower <= x + d <= upper.

Linear rows and bounds are exact (never relaxed). When the linearised nonlinear rows are inconsistent the *elastic*
QP (SNOPT's and fmincon's remedy) relaxes them with nonnegative slacks ``t`` priced at ``rho`` in the objective,
``min 1/2 d^T B d + g^T d + rho * sum(t)``, which is always feasible when ``x`` satisfies the linear rows and bounds.

Multipliers follow one convention throughout the engine (Nocedal & Wright): ``grad f = J^T lam + A^T lam_lin + z``,
``lam >= 0`` on an active lower side, ``<= 0`` on an active upper side, ``z > 0`` at an active lower bound.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from sqp.active_set import FIRST_GUESSES, MAX_GUESSES, RESCUE_GUESSES, corrected_guess, guessed_qp
from sqp.backends import elastic_backends
from sqp.compressed import as_csr
from sqp.kkt import inf_norm
from sqp.problem import Rows
from sqp.qp_call import QP_RESIDUAL_TOL, Backends, solve_qp
from sqp.structured import equality_kkt, needs_convexification, range_space_kkt

Array = NDArray[np.float64]

#: A backend's answer to a QP with a guessed active set is polished on the rows whose multiplier exceeds this times
#: ``max(1, max z)`` (an interior point leaves ~1e-11 on the rows it does not hold).
POLISH_HELD = 1e-9


@dataclass(frozen=True)
class LinearisedRows:
    """Rows ``lo <= M d <= hi`` of one kind (nonlinear or linear), with their row index sets."""

    M: Array
    lo: Array
    hi: Array
    rows: Rows


@dataclass(frozen=True)
class QPStep:
    """What a subproblem solve gave: a step and multipliers, or a reason it gave none.

    Attributes
    ----------
    d : ndarray (n,)
        The step (zeros when ``found`` is False).
    lam_nl, lam_lin, z : ndarray
        Multipliers of the nonlinear rows, the linear rows and the bounds (engine convention).
    found : bool
        Whether a checked solution was found.
    elastic : bool
        Whether the elastic (relaxed) QP produced it.
    slack : float
        Sum of elastic slacks (0 for the ordinary QP): the linearised violation the step leaves.
    status : str
        Short description for the iteration table.
    v_lin : ndarray or None
        The nonlinear rows' violations linearised at the step, ``v(c + J d)``, set by :func:`sqp.step.qp_step`.
    """

    d: Array
    lam_nl: Array
    lam_lin: Array
    z: Array
    found: bool
    elastic: bool
    slack: float
    status: str
    v_lin: Array | None = None


def linearise(J: Array, c: Array, rows: Rows) -> LinearisedRows:
    """Rows ``lb - c <= J d <= ub - c``."""
    return LinearisedRows(M=J, lo=rows.lb - c, hi=rows.ub - c, rows=rows)


def _stack_rows(parts: list[LinearisedRows], n: int,
                compressed: str = "csc") -> tuple[Any, Array, Any, Array, list[tuple[int, ...]]]:
    """Equalities ``E d = e`` and inequalities ``G d <= h`` of several row kinds, and where each kind's rows went
    (sparse ones in the ``compressed`` format)."""
    E_list, e_list, G_list, where = [], [], [], []
    n_eq = n_in = 0
    for part in parts:  # (only the kinds of rows present: most problems have one or two)
        r = part.rows
        M = part.M
        if r.eq.size:
            E_list.append(_rows_of(M, r.eq))
            e_list.append(part.lo[r.eq])
        if r.lower.size:
            G_list.append(_rows_of(M, r.lower, negate=True))
        if r.upper.size:
            G_list.append(_rows_of(M, r.upper))
        where.append((n_eq, n_in, n_in + r.lower.size))
        n_eq += r.eq.size
        n_in += r.lower.size + r.upper.size
    inputs = {id(part.M) for part in parts}  # (blocks that are these are not the caller's to keep: copy them)
    E = _vstack(E_list, n, compressed, inputs)
    G = _vstack(G_list, n, compressed, inputs)
    e = _concatenate(e_list)
    return E, e, G, inequality_bounds(parts), where


def inequality_bounds(parts: list[LinearisedRows]) -> Array:
    """``h`` of the inequalities ``G d <= h`` of :func:`_stack_rows` (per kind, the lower sides, then the upper
    ones): the rows' slack at ``d = 0``."""
    return _concatenate([h for part in parts for h in (-part.lo[part.rows.lower], part.hi[part.rows.upper])
                         if h.size])


def _rows_of(M: Any, index: NDArray[np.intp], negate: bool = False) -> Any:
    """``M[index]`` (``-M[index]`` when ``negate``); a sparse ``M`` itself when ``index`` is all its rows and
    ``negate`` is False (:func:`_vstack` copies it anyway), a slice of it when ``index`` is a run of consecutive rows
    (the same matrix, without fancy indexing's work): of a CSR matrix, built at once from the run's entries
    (:func:`_csr_run`)."""
    if sp.issparse(M) and index.size == M.shape[0]:
        return -M if negate else M
    if sp.issparse(M) and index.size and int(index[-1]) - int(index[0]) + 1 == index.size:
        if type(M) is sp.csr_matrix:
            return _csr_run(M, int(index[0]), int(index[-1]) + 1, negate)
        rows = M[int(index[0]) : int(index[-1]) + 1]
    else:
        rows = M[index]
    return -rows if negate else rows


def _csr_run(M: sp.csr_matrix, start: int, stop: int, negate: bool) -> sp.csr_matrix:
    """``M[start:stop]`` (``-M[start:stop]`` when ``negate``) of the CSR matrix ``M``: its entries' arrays copied
    (negated) in their order, as slicing then negating would give them, with one matrix built instead of two or
    three."""
    first, last = int(M.indptr[start]), int(M.indptr[stop])
    data = -M.data[first:last] if negate else M.data[first:last].copy()
    return sp.csr_matrix((data, M.indices[first:last].copy(), M.indptr[start : stop + 1] - first),
                         shape=(stop - start, M.shape[1]))


def _concatenate(parts: list[Array]) -> Array:
    """The vectors end to end (a single one as it is: every part is a fresh array)."""
    return parts[0] if len(parts) == 1 else np.concatenate(parts) if parts else np.zeros(0)


def _vstack(blocks: list[Any], n: int, compressed: str = "csc", shared: set[int] | frozenset[int] = frozenset()) -> Any:
    """The nonempty blocks stacked (a single one as it is); ``compressed`` (CSC or CSR) when any is sparse.

    A single sparse block already a CSR matrix, when CSR is asked, is returned itself (the same arrays as
    ``sp.vstack`` would copy) unless it is one of the matrices ``shared`` (their ``id``): those belong to the caller
    and are copied, so that the result never aliases them."""
    if not blocks:
        return np.zeros((0, n))
    if (len(blocks) == 1 and compressed == "csr" and type(blocks[0]) is sp.csr_matrix
            and id(blocks[0]) not in shared):
        return as_csr(blocks[0])
    if any(sp.issparse(b) for b in blocks):
        return sp.vstack(blocks, format=compressed)
    return blocks[0] if len(blocks) == 1 else np.vstack(blocks)


#: :func:`active_guess` counts a multiplier above this times ``max(1, largest multiplier)`` in size (an interior-point
#: backend leaves tiny positive multipliers on the rows it does not hold).
ACTIVE_MULTIPLIER = 1e-7


def active_guess(nonlinear: Rows, linear: Rows, lam_nl: Array, lam_lin: Array) -> NDArray[np.bool_]:
    """The inequality rows ``G d <= h`` of the QP (in :func:`_stack_rows`' order: per kind, the lower sides, then
    the upper ones) that multipliers ``lam_nl``, ``lam_lin`` (engine convention) hold active: a positive multiplier
    on a lower side, a negative one on an upper side, larger than :data:`ACTIVE_MULTIPLIER` relative."""
    t = ACTIVE_MULTIPLIER * max(1.0, inf_norm(lam_nl) if lam_nl.size else 0.0,
                                inf_norm(lam_lin) if lam_lin.size else 0.0)
    return np.concatenate((lam_nl[nonlinear.lower] > t, lam_nl[nonlinear.upper] < -t,
                           lam_lin[linear.lower] > t, lam_lin[linear.upper] < -t))


def _row_multipliers(rows: Rows, y: Array, z: Array, where: tuple[int, ...]) -> Array:
    """Per-row multipliers in the engine convention from qpsolvers' ``y`` (equalities) and ``z`` (``G d <= h``)."""
    i_eq, i_lo, i_up = where
    if rows.eq.size == rows.lb.size:  # (equalities only: their multipliers in order)
        return -y[i_eq : i_eq + rows.eq.size]
    lam = np.zeros(rows.lb.size)
    lam[rows.eq] = -y[i_eq : i_eq + rows.eq.size]
    lam[rows.lower] += z[i_lo : i_lo + rows.lower.size]
    lam[rows.upper] -= z[i_up : i_up + rows.upper.size]
    return lam


def solve_subproblem(
    B: Any,
    g: Array,
    nonlinear: LinearisedRows,
    linear: LinearisedRows,
    box_lo: Array,
    box_hi: Array,
    *,
    backends: Backends,
    initvals: Array | None = None,
    elastic_penalty: float | None = None,
    active: NDArray[np.bool_] | None = None,
    first: bool = False,
) -> QPStep:
    """Solve the QP (Eqs. 9–10); with ``elastic_penalty`` solve its elastic relaxation instead.

    Parameters
    ----------
    B : (n, n) array or sparse matrix
        Positive-definite model Hessian, or an indefinite :class:`sqp.structured.FactoredHessian`, which only an
        equality-only QP whose KKT matrix has the right inertia can use (any other QP fails at once with status
        ``"indefinite"``: the caller convexifies it and asks again).
    g : (n,) array
        Objective gradient.
    nonlinear, linear : LinearisedRows
        Linearised nonlinear rows and the (exact) linear rows, both as ``lo <= M d <= hi``.
    box_lo, box_hi : (n,) arrays
        ``lower - x`` and ``upper - x``.
    backends : sequence of (name, settings)
        qpsolvers backends to ask in turn: the chosen one first, then the fallbacks.
    initvals : (n,) array, optional
        Warm start for the primal step.
    elastic_penalty : float, optional
        Price ``rho`` of a unit of slack; solves the elastic QP when given.
    active : ndarray of bool, optional
        The inequality rows guessed active (:func:`active_guess`): a QP with a sparse ``B`` and no
        bounds is first solved on that guess (:func:`sqp.active_set.guessed_qp`), the backends asked only when it
        fails. Not used by the elastic QP.
    first : bool
        Whether ``active`` comes from starting multipliers, not a QP of this solve (tried once, not corrected).
    """
    n = g.size
    scale = max(1.0, inf_norm(g))
    if elastic_penalty is None:
        return _solve_plain(B, g, nonlinear, linear, box_lo, box_hi, backends, initvals, scale, active, first)
    if needs_convexification(B):
        return _failed(n, nonlinear, linear, "indefinite")
    return _solve_elastic(B, g, nonlinear, linear, box_lo, box_hi, backends, initvals, elastic_penalty, scale)


def _solve_plain(B: Any, g: Array, nonlinear: LinearisedRows, linear: LinearisedRows, box_lo: Array, box_hi: Array,
                 backends: Backends, initvals: Array | None, scale: float,
                 active: NDArray[np.bool_] | None = None, first: bool = False) -> QPStep:
    """The QP itself (not elastic): an equality-only one by its KKT system directly (:func:`_equality_qp`, or the
    structured solve of a sparse ``B``), one with a guessed active set on that guess (:func:`guessed_qp`), any
    other, or one the direct solves refused, by the backends in turn."""
    n = g.size
    has_box = bool(np.isfinite(box_lo).any() or np.isfinite(box_hi).any())
    guess = active is not None and sp.issparse(B) and not has_box
    factored = (active is not None and not has_box and not sp.issparse(B)
                and getattr(B, "cholesky", None) is not None)  # a dense B with its factor: the range-space guess
    # (CSR for the guessed active set's row picks; a backend asked after all gets the same matrices in CSC)
    E, e, G, h, where = _stack_rows([nonlinear, linear], n, "csr" if guess else "csc")
    if not has_box and G.shape[0] == 0:
        step = _checked(B, g, E, e, scale, equality_kkt(B, g, E, e)) if sp.issparse(B) else _equality_qp(
            B, g, E, e, scale)
        if step is not None:
            d, y = step
            return QPStep(d=d, lam_nl=_row_multipliers(nonlinear.rows, y, np.zeros(0), where[0]),
                          lam_lin=_row_multipliers(linear.rows, y, np.zeros(0), where[1]), z=np.zeros(n),
                          found=True, elastic=False, slack=0.0, status="kkt")
    if needs_convexification(B):
        return _failed(n, nonlinear, linear, "indefinite")
    guessing = guess or (factored and not sp.issparse(E) and not sp.issparse(G))

    def on_guess(solves: int) -> QPStep | None:
        """The QP solved on the guessed active set corrected for at most ``solves`` solves, or None."""
        assert active is not None  # (guessing)
        found = (guessed_qp(B, g, E, e, G, h, active, scale, solves) if guess
                 else _factored_guess(B, g, E, e, G, h, active, scale, solves))
        if found is None:
            return None
        d, y, z = found
        return QPStep(d=d, lam_nl=_row_multipliers(nonlinear.rows, y, z, where[0]),
                      lam_lin=_row_multipliers(linear.rows, y, z, where[1]), z=np.zeros(n), found=True,
                      elastic=False, slack=0.0, status="active set")

    if guessing:
        # (with no inequality rows: the equality QP by one banded KKT solve, or the range-space one)
        # (the first QP's guess, from starting multipliers, is tried once on a banded solve, whose corrections
        # wandered on the 3-D program; a range-space correction costs O(n² k), a fraction of DAQP's set-up, and
        # the first QP of a warm insertion step usually needs one: 61 of 166 QPs to DAQP on the bend, 16 so)
        step = on_guess(FIRST_GUESSES if first and guess else MAX_GUESSES)
        if step is not None:
            return step
    lo, hi = (box_lo, box_hi) if has_box else (None, None)
    sol, used = solve_qp(backends[:1], B, g, G, h, E, e, lo, hi, initvals, scale)
    if sol is None and used != "QP infeasible":
        # the first backend failed (a certified infeasibility aside): the guess corrected further, a direct KKT
        # solve each, is checked like any answer (the QP's solution is unique: the next backend's answer would be
        # the same), and spares the elastic QP a consistent linearisation; then the other backends
        rescued = on_guess(RESCUE_GUESSES) if guessing else None
        if rescued is not None:
            return rescued
        if len(backends) > 1:
            sol, used = solve_qp(backends[1:], B, g, G, h, E, e, lo, hi, initvals, scale)
    if sol is None:
        return _failed(n, nonlinear, linear, used)
    y = np.zeros(0) if sol.y is None else np.asarray(sol.y, dtype=float).ravel()
    z = np.zeros(0) if sol.z is None else np.asarray(sol.z, dtype=float).ravel()
    zb = -np.asarray(sol.z_box, dtype=float) if (has_box and sol.z_box is not None) else np.zeros(n)
    if guess and z.size:
        # polished: the rows the backend's answer holds, solved exactly (banded KKT solves, the rows it left tiny
        # multipliers on dropped as any guess's are); an interior point's multipliers carry its own tolerance,
        # which an SQP near its solution cannot get its KKT residual below (a wire pushed straight out of a branch's
        # open end: |KKT| stuck at ~1e-6 for 30 iterations, then the dense program); kept only when it passes the
        # same checks as any guess (else the backend's answer stands)
        held = z > POLISH_HELD * max(1.0, float(np.max(z)))
        polished = guessed_qp(B, g, E, e, G, h, held, scale, MAX_GUESSES)
        if polished is not None:
            d, y, z = polished
            return QPStep(d=d, lam_nl=_row_multipliers(nonlinear.rows, y, z, where[0]),
                          lam_lin=_row_multipliers(linear.rows, y, z, where[1]), z=np.zeros(n), found=True,
                          elastic=False, slack=0.0, status="polished")
    return QPStep(
        d=sol.x, lam_nl=_row_multipliers(nonlinear.rows, y, z, where[0]),
        lam_lin=_row_multipliers(linear.rows, y, z, where[1]), z=zb, found=True, elastic=False, slack=0.0,
        status="optimal" if used == backends[0][0] else f"opt[{used}]",
    )


def _factored_guess(B: Any, g: Array, E: Array, e: Array, G: Array, h: Array, active: NDArray[np.bool_],
                    scale: float, solves: int) -> tuple[Array, Array, Array] | None:
    """:func:`sqp.active_set.guessed_qp` for a dense ``B`` that carries its Cholesky factor
    (:class:`sqp.hessian.CholeskyHessian`): each guess's equality QP on ``E`` and the rows ``G_A`` guessed active by
    the range-space method (:func:`sqp.structured.range_space_kkt`, ``O(n² k)`` for ``k`` rows), corrected as the
    primal-dual active-set method does for at most ``solves`` solves; ``(d, y, z)`` when a guess's step meets every
    row, its multipliers are nonnegative and it passes a backend's residual check (then it is the QP's unique
    solution: the KKT conditions of a strictly convex QP), else None.

    A backend in the factor's coordinates (DAQP on ``G L^-T``) transforms every row, active or not (``O(n² m)``);
    with few of the ``m`` rows active, as in an SQP near its solution or warm-started from a neighbour's answer, the
    guess costs a fraction of that."""
    L = B.cholesky
    return corrected_guess(lambda rows, rhs: range_space_kkt(L, g, np.vstack((E, G[rows])) if rows.size else E, rhs),
                           B, g, E, e, G, h, active, scale, solves)


def _equality_qp(B: Any, g: Array, E: Any, e: Array, scale: float) -> tuple[Array, Array] | None:
    """An equality-only QP with a dense model Hessian, solved directly: its KKT system
    ``[[B, E^T], [E, 0]] [d; y] = [-g; e]`` (qpsolvers' sign for ``y``).

    When ``B`` carries its Cholesky factor (a :class:`sqp.hessian.CholeskyHessian`, as the convexification of an
    exact Hessian hands it over) by the range-space method (:func:`sqp.structured.range_space_kkt`), else by one
    dense LU solve of the whole system (also the fallback when the range-space answer fails the check below).

    Any backend would return this same unique answer; the direct solve skips the backend's set-up (at 100 variables
    and a few rows: 0.1 ms against DAQP's 0.5 ms). Returns None, so that the backends are asked, when ``B`` or ``E``
    is sparse (a large model: the sparse backends are faster there), when LU finds the system exactly singular, or
    when the answer fails the same residual check as a backend's (dependent but consistent rows usually pass it:
    the step is then still unique, the multipliers one valid choice)."""
    if sp.issparse(B) or sp.issparse(E):
        return None
    L = getattr(B, "cholesky", None)
    if L is not None:
        step = _checked(B, g, E, e, scale, range_space_kkt(L, g, E, e))
        if step is not None:
            return step
    n, m = g.size, e.size
    K = np.zeros((n + m, n + m))
    K[:n, :n] = B
    K[:n, n:] = E.T
    K[n:, :n] = E
    try:
        sol = np.linalg.solve(K, np.concatenate((-g, e)))
    except np.linalg.LinAlgError:
        return None
    return _checked(B, g, E, e, scale, (sol[:n], sol[n:]))


def _checked(B: Any, g: Array, E: Any, e: Array, scale: float,
             step: tuple[Array, Array] | None) -> tuple[Array, Array] | None:
    """``step = (d, y)`` when it is finite and passes the residual check of a backend's answer, else None."""
    if step is None:
        return None
    d, y = step
    if not (np.isfinite(d).all() and np.isfinite(y).all()):
        return None
    dual = inf_norm(B @ d + g + E.T @ y)
    prim = inf_norm(E @ d - e)
    if prim > QP_RESIDUAL_TOL * scale or dual > QP_RESIDUAL_TOL * scale:
        return None
    return d, y


def _failed(n: int, nonlinear: LinearisedRows, linear: LinearisedRows, status: str) -> QPStep:
    return QPStep(d=np.zeros(n), lam_nl=np.zeros(nonlinear.rows.lb.size), lam_lin=np.zeros(linear.rows.lb.size),
                  z=np.zeros(n), found=False, elastic=False, slack=np.inf, status=status)


def _solve_elastic(
    B: Any, g: Array, nonlinear: LinearisedRows, linear: LinearisedRows, box_lo: Array, box_hi: Array,
    backends: Backends, initvals: Array | None, rho: float, scale: float,
) -> QPStep:
    """Elastic QP in variables ``(d, t)``: every nonlinear side gets its own slack ``t >= 0``.

    Equality row ``i``: ``lo_i <= M_i d + t_i+ - t_i-`` … written as two one-sided rows with two slacks.
    """
    n = g.size
    r = nonlinear.rows
    # one-sided nonlinear rows S d >= s_lo, each with its own slack: eq rows give both sides
    low_idx = np.concatenate([r.eq, r.lower])
    up_idx = np.concatenate([r.eq, r.upper])
    k = low_idx.size + up_idx.size
    h_nl = np.concatenate([-nonlinear.lo[low_idx], nonlinear.hi[up_idx]])
    El, el, Gl, hl, where_lin = _stack_rows([linear], n)
    if sp.issparse(B):  # a large sparse model: the elastic QP stays sparse (a dense one of n + k variables is slow)
        G, E, P = _elastic_matrices_sparse(B, nonlinear.M, low_idx, up_idx, El, Gl)
    else:
        G, E, P = _elastic_matrices_dense(B, nonlinear.M, low_idx, up_idx, El, Gl)
    h = np.concatenate([h_nl, hl])
    q = np.concatenate([g, np.full(k, rho)])
    lo = np.concatenate([box_lo, np.zeros(k)])
    hi = np.concatenate([box_hi, np.full(k, np.inf)])
    x0 = None if initvals is None else np.concatenate([initvals, np.zeros(k)])
    sol, used = solve_qp(elastic_backends(backends, n + k), P, q, G, h, E, el, lo, hi, x0, max(scale, rho))
    if sol is None:
        return _failed(n, nonlinear, linear, "elastic QP failed")
    z = np.zeros(0) if sol.z is None else np.asarray(sol.z, dtype=float).ravel()
    y = np.zeros(0) if sol.y is None else np.asarray(sol.y, dtype=float).ravel()
    lam_nl = np.zeros(r.lb.size)
    np.add.at(lam_nl, low_idx, z[: low_idx.size])
    np.subtract.at(lam_nl, up_idx, z[low_idx.size : k])
    lam_lin = _row_multipliers(linear.rows, y, z[k:], where_lin[0])
    zb = -sol.z_box[:n] if sol.z_box is not None else np.zeros(n)
    t = np.maximum(sol.x[n:], 0.0)
    return QPStep(d=sol.x[:n], lam_nl=lam_nl, lam_lin=lam_lin, z=zb, found=True, elastic=True,
                  slack=float(np.sum(t)), status="elastic" if used == backends[0][0] else f"elastic[{used}]")


def _elastic_matrices_dense(B: Any, M: Any, low_idx: Array, up_idx: Array, El: Any, Gl: Any) -> tuple[Any, Any, Any]:
    """``G [d; t] <= h`` (``-M_low d - t_low <= -lo_low``, ``M_up d - t_up <= hi_up``, then the linear rows), the
    equalities ``[E 0]`` and ``P = diag(B, reg I)``, dense."""
    M = M.toarray() if sp.issparse(M) else np.asarray(M)
    nl, nu = low_idx.size, up_idx.size
    k, n = nl + nu, M.shape[1]
    G_nl = np.block([
        [-M[low_idx], -np.eye(nl), np.zeros((nl, nu))],
        [M[up_idx], np.zeros((nu, nl)), -np.eye(nu)],
    ])
    El = El.toarray() if sp.issparse(El) else El
    Gl = Gl.toarray() if sp.issparse(Gl) else Gl
    G = np.vstack([G_nl, np.hstack([Gl, np.zeros((Gl.shape[0], k))])])
    E = np.hstack([El, np.zeros((El.shape[0], k))])
    Bd = np.asarray(B)
    reg = 1e-10 * max(1.0, float(np.max(np.abs(np.diag(Bd)))))  # keeps P positive definite for quadprog
    P = np.block([[Bd, np.zeros((n, k))], [np.zeros((k, n)), reg * np.eye(k)]])
    return G, E, P


def _elastic_matrices_sparse(B: Any, M: Any, low_idx: Array, up_idx: Array, El: Any, Gl: Any) -> tuple[Any, Any, Any]:
    """As :func:`_elastic_matrices_dense`, in CSC."""
    M = sp.csr_matrix(M)
    nl, nu = low_idx.size, up_idx.size
    k = nl + nu
    G_nl = sp.vstack([
        sp.hstack([-M[low_idx], -sp.identity(nl), sp.csr_matrix((nl, nu))]),
        sp.hstack([M[up_idx], sp.csr_matrix((nu, nl)), -sp.identity(nu)]),
    ])
    G = sp.vstack([G_nl, sp.hstack([sp.csr_matrix(Gl), sp.csr_matrix((Gl.shape[0], k))])], format="csc")
    E = sp.hstack([sp.csr_matrix(El), sp.csr_matrix((El.shape[0], k))], format="csc")
    reg = 1e-10 * max(1.0, float(np.max(np.abs(B.diagonal()), initial=0.0)))
    P = sp.block_diag([sp.csc_matrix(B), reg * sp.identity(k, format="csc")], format="csc")
    return G, E, P
