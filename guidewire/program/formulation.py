"""A scene as a nonlinear program for :func:`sqp.minimize`: one :class:`Formulation` type, two layouts.

``formulate(scene, layout="reduced")`` — the paper's program: the bar angles ``φ`` (n,) are the variables
(:class:`ReducedLayout`). ``layout="full"`` — bar angles and node positions, closed by sparse equalities
(:mod:`guidewire.program.full_space`). Both state the same constraint blocks (:mod:`guidewire.blocks`: ``position``,
``angle``, ``wall``, ``relative_angle``, each present only when the scene needs it) with the same rows and the same
multiplier signs (:mod:`guidewire.blocks.base`), so a solution reads the same whatever the layout.

Objective: the bending energy of :mod:`guidewire.energy` (N·mm), quadratic in ``φ``; its exact constant Hessian is
passed as ``hess0`` and returned by :meth:`Formulation.hess` (sparse: :mod:`sqp` decides how to store it).

In the reduced layout (:mod:`.reduced`) a node-row block is an SLSQP dict or a ``NonlinearConstraint`` with
analytic ``jac`` and ``hess``; an angle-row block is a ``LinearConstraint``. No variable bounds.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple, Protocol

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint, NonlinearConstraint

from ..blocks import BLOCK_TYPES, AngleRows, Block, NodeRows, Rows, WorkingSet
from ..blocks.base import row_violation
from ..scene.scene import SCHEMES, Scene
from .feasibility import check_feasible
from .full_space import FullLayout
from .model import Model, ModelReuse, build_model
from .reduced import ReducedLayout

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int_]

LAYOUTS = ("reduced", "full")


class Layout(Protocol):
    """How a program states the variables, the energy and the two kinds of rows (see the module docstring)."""

    name: str
    model: Model

    @property
    def size(self) -> int: ...
    @property
    def hess0(self) -> Any: ...
    def fun(self, x: FloatArray) -> float: ...
    def jac(self, x: FloatArray) -> FloatArray: ...
    def angles(self, x: FloatArray) -> FloatArray: ...
    def nodes(self, x: FloatArray) -> FloatArray: ...
    def own_constraints(self) -> list[Any]: ...
    def newton_options(self, blocks: Sequence[Block]) -> dict[str, Any]: ...
    def node_rows(self, rows: NodeRows) -> Any: ...
    def angle_rows(self, rows: AngleRows) -> Any: ...
    def start(self, blocks: Sequence[Block]) -> FloatArray: ...
    def block_multipliers(self, raw: Sequence[Any]) -> list[FloatArray]: ...
    def raw_multipliers(self, blocks: Sequence[Block], per_block: Sequence[FloatArray]) -> list[FloatArray]: ...
    def answer(self, blocks: Sequence[Block], x: FloatArray, per_block: Sequence[FloatArray]) -> FloatArray: ...


class BlockMultipliers(NamedTuple):
    """Multipliers of a neighbouring solve, one array per constraint block, with those blocks: what
    :meth:`Formulation.multipliers0` matches (``guidewire.solve(multipliers0=...)`` takes it as it takes a
    :class:`~guidewire.solve.result.Solution`)."""

    blocks: tuple[Block, ...]
    multipliers: tuple[FloatArray, ...]


@dataclass(frozen=True)
class Formulation:
    """The nonlinear program of one scene in one layout.

    Attributes
    ----------
    model : Model
        Chain, energy, contact nodes and start angles (layout-independent).
    layout : ReducedLayout or FullLayout
    blocks : tuple of Block
        The constraint blocks; ``block.index`` is the position of its constraint in :attr:`constraints`.
    constraints : tuple
        Arguments for ``sqp.minimize(constraints=...)``: the layout's own rows (the full space's closure) first,
        then one per block.
    x0 : ndarray, shape (size,)
        The start, in the layout's variables.
    rows : tuple of NodeRows or AngleRows
        Every block's :meth:`Block.rows` on :attr:`model`, in :attr:`blocks` order, as the constraints state them
        (built once: :meth:`max_violation` reads them too); empty when not given.
    """

    model: Model
    layout: Any
    blocks: tuple[Block, ...]
    constraints: tuple[Any, ...]
    x0: FloatArray
    rows: tuple[Rows, ...] = field(default=(), compare=False, repr=False)

    # -- what it is ----------------------------------------------------------------------------------------------
    @property
    def scene(self) -> Scene:
        return self.model.scene

    @property
    def chain(self) -> Any:
        return self.model.chain

    @property
    def energy(self) -> Any:
        return self.model.energy

    @property
    def contact_nodes(self) -> IntArray:
        return self.model.contact_nodes

    @property
    def scheme(self) -> str:
        return self.model.scene.wire.scheme

    @property
    def n(self) -> int:
        """Number of bars."""
        return self.model.n

    @property
    def size(self) -> int:
        """Number of variables (``n`` reduced, ``3n`` full)."""
        return int(self.layout.size)

    @property
    def hess0(self) -> Any:
        """The exact (constant) energy Hessian in the layout's variables, sparse."""
        return self.layout.hess0

    def block(self, kind: str) -> tuple[Block, ...]:
        """The blocks of one kind (possibly none)."""
        return tuple(b for b in self.blocks if b.kind == kind)

    # -- the program ---------------------------------------------------------------------------------------------
    def fun(self, x: FloatArray) -> float:
        """Bending energy in N·mm."""
        return self.layout.fun(x)

    def jac(self, x: FloatArray) -> FloatArray:
        """Gradient of the energy, shape (size,)."""
        return self.layout.jac(x)

    def hess(self, x: FloatArray) -> Any:
        """Exact Hessian of the energy: :attr:`hess0` (constant)."""
        return self.layout.hess0

    def arguments(self) -> dict[str, Any]:
        """Keyword arguments for ``sqp.minimize`` (and, without ``hess0``, ``scipy.optimize.minimize``); add
        ``hess=self.hess`` for Newton–SQP."""
        return {"fun": self.fun, "x0": self.x0, "jac": self.jac, "bounds": None,
                "constraints": list(self.constraints), "hess0": self.hess0}

    # -- reading answers ----------------------------------------------------------------------------------------
    def angles(self, x: FloatArray) -> FloatArray:
        """Bar angles ``φ`` at ``x``, shape (n,)."""
        return self.layout.angles(x)

    def nodes(self, x: FloatArray) -> FloatArray:
        """Node positions at ``x`` (the variables' own in the full space), shape (n + 1, 2), base first."""
        return self.layout.nodes(x)

    def violations(self, x: FloatArray) -> FloatArray:
        """Violation (≥ 0) of every row of :attr:`constraints` at ``x``, concatenated in order."""
        parts = [np.zeros(0)]
        for con in self.constraints:
            if isinstance(con, LinearConstraint):
                parts.append(row_violation(con.A @ x, con.lb, con.ub))
            elif isinstance(con, NonlinearConstraint):
                parts.append(row_violation(np.asarray(con.fun(x), dtype=float), con.lb, con.ub))
            else:
                c = np.asarray(con["fun"](x), dtype=float)
                parts.append(np.abs(c) if con["type"] == "eq" else np.maximum(-c, 0.0))
        return np.concatenate(parts)

    def nodes_at(self, phi: FloatArray) -> FloatArray:
        """The chain's nodes at the bar angles ``phi``, shape (n + 1, 2): those the program last evaluated when they
        are at ``phi`` (the same numbers), else computed."""
        point = getattr(self.layout, "point", None)
        if point is not None and point.phi is not None and np.array_equal(point.phi, phi):
            return point.nodes.copy()
        return self.model.chain.nodes(phi)

    def max_violation(self, phi: FloatArray, nodes: FloatArray | None = None) -> float:
        """Largest violation (mm or rad) of any block at the bar angles ``phi`` — walls at every node, not only
        their working set; inf where a violation is not a number. ``nodes``: the chain's nodes at ``phi`` when the
        caller has them."""
        return self.worst_violation(phi, nodes)[0]

    def worst_violation(self, phi: FloatArray, nodes: FloatArray | None = None) -> tuple[float, Block | None, int]:
        """The largest violation at ``phi`` (:meth:`max_violation`), the block it belongs to and its node: a block
        whenever the violation is positive (a NaN counts as inf, so a block is named for it too); 0, None and -1
        when nothing is violated."""
        points = self.model.chain.nodes(phi) if nodes is None else nodes
        rows: tuple[Rows | None, ...] = self.rows or (None,) * len(self.blocks)
        worst: tuple[float, Block | None, int] = (0.0, None, -1)
        for block, r in zip(self.blocks, rows, strict=True):
            v = np.asarray(block.violation(self.model, phi, points, r), dtype=float)
            if not v.size:
                continue
            v = np.where(np.isnan(v), np.inf, v)
            k = int(np.argmax(v))
            if v[k] > worst[0]:
                worst = (float(v[k]), block, int(block.violation_nodes(self.model)[k]))
        return worst

    def multipliers(self, res: Any) -> list[FloatArray]:
        """One array per block (in :attr:`blocks` order) from an ``sqp`` result, in the sign convention of
        :mod:`guidewire.blocks.base` (the same in both layouts)."""
        return self.layout.block_multipliers(res.constraint_multipliers)

    def answer(self, x: FloatArray, per_block: Sequence[FloatArray]) -> FloatArray:
        """The bar angles of the answer ``x`` (in the full space moved onto the active rows in the chain's own
        kinematics, see :meth:`guidewire.program.full_space.FullLayout.answer`)."""
        return self.layout.answer(self.blocks, x, per_block)

    def multipliers0(self, blocks: Sequence[Block], per_block: Sequence[Any]) -> list[FloatArray] | None:
        """Starting multipliers for ``sqp.minimize(multipliers0=...)`` from those of another formulation of a
        neighbouring scene (its ``blocks`` and :meth:`multipliers`): matched by block key and row key, rows without
        a match start at 0. None when no block matches."""
        known = {b.key: (b, np.asarray(v, dtype=float)) for b, v in zip(blocks, per_block, strict=True)}
        out, matched = [], False
        for block in self.blocks:
            lam = np.zeros(block.size)
            if block.key in known:
                other, values = known[block.key]
                if values.size == other.size:
                    matched = True
                    if np.array_equal(other.row_keys, block.row_keys):  # (the same rows: every one matches)
                        out.append(values.copy())
                        continue
                    pick = _row_positions(np.asarray(other.row_keys), np.asarray(block.row_keys))
                    lam = np.where(pick >= 0, values[np.maximum(pick, 0)] if values.size else 0.0, 0.0)
            out.append(lam)
        return self.layout.raw_multipliers(self.blocks, out) if matched else None


def _row_positions(keys: IntArray, wanted: IntArray) -> IntArray:
    """For every key of ``wanted``, its position in ``keys`` (the last one where a key repeats), or -1 where it is
    not there: a sorted search, O((m + k) log m), where a block's rows are matched at every insertion step."""
    order = np.argsort(keys, kind="stable")  # (equal keys in their order: the last of a run is the last position)
    ranked = keys[order]
    at = np.searchsorted(ranked, wanted, side="right") - 1
    inside = at >= 0
    found = inside & (ranked[np.maximum(at, 0)] == wanted) if ranked.size else np.zeros(wanted.shape, dtype=bool)
    return np.where(found, order[np.maximum(at, 0)] if ranked.size else 0, -1).astype(int)


def _working_set(wall_nodes: Any) -> WorkingSet:
    """``wall_nodes`` of :func:`formulate` as the blocks' :data:`~guidewire.blocks.base.WorkingSet`."""
    if wall_nodes is None or isinstance(wall_nodes, str | Mapping):
        return wall_nodes
    return {("wall", (j,)): np.asarray(nodes, dtype=int) for j, nodes in enumerate(wall_nodes)}


def formulate(
    scene: Scene,
    *,
    layout: str = "reduced",
    scheme: str | None = None,
    bars: int | None = None,
    initial_angles: Any = None,
    initial_nodes: Any = None,
    wall_nodes: Any = None,
    check: bool = True,
    reuse: ModelReuse | None = None,
) -> Formulation:
    """Turn ``scene`` into the arguments of :func:`sqp.minimize`.

    Parameters
    ----------
    scene : Scene
    layout : {"reduced", "full"}
        The variables: bar angles only (the paper's program), or bar angles and node positions
        (:mod:`guidewire.program.full_space`).
    scheme : {"second_order", "paper"}, optional
        Overrides ``scene.wire.scheme``.
    bars : int, optional
        Overrides ``scene.wire.bars``.
    initial_angles : array_like, shape (n,), optional
        Starting bar angles (rad).
    initial_nodes : array_like, shape (n + 1, 2), optional
        Starting node positions (base first); only their directions are used.
    wall_nodes : None, "near", sequence of int arrays, or mapping, optional
        The nodes that get a wall row (the working set). None: nodes 1..n. ``"near"``: the start's nodes within
        :data:`guidewire.blocks.wall.WORKING_DISTANCE` ``× L`` of each wall (the paper's remark that only a few
        points of a line contact need constraining). A sequence: one array per wall. A mapping: from block key
        (``("wall", (j,))``) to nodes. :func:`guidewire.solve` uses ``"near"`` in the reduced layout and grows the
        set with every node found violating a wall.
    check : bool
        Check the scene's feasibility first (:func:`guidewire.program.feasibility.check_feasible`).
    reuse : ModelReuse, optional
        Keep what the model of the scene formulated last through it shares with this one (bar layout, energy,
        energy Hessian; see :class:`guidewire.program.model.ModelReuse`): the same formulation, built faster.

    Returns
    -------
    Formulation

    Raises
    ------
    ValueError
        For an unknown layout or scheme, a bad start, or an infeasible scene.
    """
    if layout not in LAYOUTS:
        raise ValueError(f"layout is {layout!r}; expected one of {', '.join(map(repr, LAYOUTS))}.")
    if scheme is not None:
        if scheme not in SCHEMES:
            raise ValueError(f"scheme is {scheme!r}; expected one of {', '.join(map(repr, SCHEMES))}.")
        if scheme != scene.wire.scheme:
            scene = scene.with_scheme(scheme)
    if bars is not None and (type(bars) is not int or bars != scene.wire.bars):  # (the same bars: the same scene)
        scene = scene.with_bars(bars)
    if initial_angles is not None and initial_nodes is not None:
        raise ValueError("pass initial_angles or initial_nodes, not both.")
    if check:
        check_feasible(scene)
    model = build_model(scene, initial_angles, initial_nodes, reuse)
    working_set = _working_set(wall_nodes)
    blocks = [block for kind in BLOCK_TYPES for block in kind.build(model, working_set)]
    return assemble(model, layout, blocks)


def assemble(model: Model, layout: str, blocks: Sequence[Block]) -> Formulation:
    """The :class:`Formulation` of ``blocks`` on ``model`` in ``layout`` (e.g. after a block's working set grew)."""
    if layout == "full":
        lay: Any = FullLayout.build(model)
    else:
        lay = ReducedLayout(model)
    constraints = lay.own_constraints()
    placed, built = [], []
    for block in blocks:
        block = block.with_index(len(constraints))
        rows = block.rows(model)  # (on the block placed: a block that keeps its rows keeps them for the solve)
        placed.append(block)
        built.append(rows)
        constraints.append(lay.node_rows(rows) if isinstance(rows, NodeRows) else lay.angle_rows(rows))
    return Formulation(model=model, layout=lay, blocks=tuple(placed), constraints=tuple(constraints),
                       x0=lay.start(placed), rows=tuple(built))
