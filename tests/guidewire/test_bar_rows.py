"""A bar's row (``NodeRows.turns``: a point's distance from a bar's line): its value is that distance, its derivatives
match finite differences in both layouts, and its force goes to the bar's two nodes with the foot's moment."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import LinearConstraint

from guidewire import Base, Scene, Wire
from guidewire.blocks.base import NodeRows
from guidewire.program.full_space import FullLayout
from guidewire.program.model import build_model
from guidewire.program.reduced import ReducedLayout


def _fd(fun, x, h=1e-6):
    return np.column_stack([(np.atleast_1d(fun(x + h * e)) - np.atleast_1d(fun(x - h * e))) / (2 * h)
                            for e in np.eye(x.size)])


def _model(n, seed):
    rng = np.random.default_rng(seed)
    wire = Wire(40.0, n, moment_of_inertia=0.01816)
    model = build_model(Scene(wire, Base((1.0, -2.0), 0.3)), initial_angles=0.3 + 0.4 * rng.standard_normal(n))
    return model, rng


def _rows(model, rng):
    """Four quadratic node rows and four bar rows about random points."""
    n = model.n
    nodes = np.concatenate((rng.choice(np.arange(1, n + 1), 4), rng.choice(np.arange(1, n), 4)))
    h = rng.standard_normal((8, 2, 2))
    h = h + h.transpose(0, 2, 1)
    h[4:] = 0.0
    turns = np.concatenate((np.zeros(4), rng.choice([-1.0, 1.0], 4) / model.chain.lengths[nodes[4:]]))
    tau = np.concatenate((np.zeros(4), rng.uniform(0.05, 0.95, 4)))
    return NodeRows(nodes, rng.standard_normal((8, 2)), rng.standard_normal(8) - 5.0, np.full(8, np.inf),
                    hessians=h, centres=rng.standard_normal((8, 2)), fractions=tau,
                    pivots=10.0 * rng.standard_normal((8, 2)), turns=turns)


def _dense(matrix):
    return matrix.toarray() if hasattr(matrix, "toarray") else np.asarray(matrix)


def _as_functions(con, lb):
    """The rows' values (not less ``lb``, as an ``ineq`` dict states them), Jacobian and Hessian functions."""
    if isinstance(con, LinearConstraint):
        A = con.A.toarray()
        return (lambda x: A @ x), (lambda x: A), None
    return (lambda x: con["fun"](x) + lb), con["jac"], con["hess"]


@pytest.mark.parametrize("seed", range(6))
def test_a_bar_rows_derivatives_match_finite_differences_in_both_layouts(seed):
    model, rng = _model(12, seed)
    rows = _rows(model, rng)
    reduced, full = ReducedLayout(model), FullLayout.build(model)
    phi = model.x0 + 0.2 * rng.standard_normal(model.n)
    for layout, x in ((reduced, phi), (full, full.pack(phi) + 1e-3 * rng.standard_normal(full.size))):
        fun, jac, hess = _as_functions(layout.node_rows(rows), rows.lb)
        scale = 1.0 + np.abs(_dense(jac(x))).max()
        np.testing.assert_allclose(_dense(jac(x)), _fd(fun, x), rtol=0, atol=1e-7 * scale)
        v = rng.standard_normal(rows.nodes.size)
        fd = _fd(lambda y, jac=jac, v=v: _dense(jac(y)).T @ v, x)
        np.testing.assert_allclose(_dense(hess(x, v)), fd, rtol=0, atol=1e-6 * (1.0 + np.abs(fd).max()))
    # the two layouts hold the same rows: equal values at the same wire
    f_reduced, _, _ = _as_functions(reduced.node_rows(rows), rows.lb)
    f_full, _, _ = _as_functions(full.node_rows(rows), rows.lb)
    np.testing.assert_allclose(f_reduced(phi), f_full(full.pack(phi)), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_a_bar_rows_value_is_the_points_distance_from_the_bars_line(seed):
    """At any wire, ``|g|`` is the distance of the pivot from the bar's line; turning the bar about the pivot's foot
    by ``δ`` leaves ``g cos δ`` (the bar's length kept), and sliding the pivot along the bar leaves ``g``."""
    model, rng = _model(10, seed)
    points = model.chain.nodes(model.x0 + 0.3 * rng.standard_normal(model.n))
    k = int(rng.integers(1, model.n))
    p, q = points[k], points[k + 1]
    t = (q - p) / np.linalg.norm(q - p)
    normal = np.array([-t[1], t[0]])
    foot, distance = p + rng.uniform(0.1, 0.9) * (q - p), rng.uniform(0.1, 2.0)
    pivot = foot + distance * normal

    def row(pivot, points=points):
        rows = NodeRows(np.array([k]), np.zeros((1, 2)), np.zeros(1), np.full(1, np.inf), hessians=np.zeros((1, 2, 2)),
                        centres=np.zeros((1, 2)), fractions=np.array([0.5]), pivots=pivot[None],
                        turns=np.array([1.0 / model.chain.lengths[k]]))
        return float(rows.values(points)[0])

    np.testing.assert_allclose(row(pivot), distance, rtol=1e-12)
    np.testing.assert_allclose(row(pivot + rng.uniform(-3, 3) * t), distance, rtol=1e-12)
    np.testing.assert_allclose(row(foot - distance * normal), -distance, rtol=1e-12)  # the other side: negative
    for delta in rng.uniform(-0.5, 0.5, 3):
        c, s = np.cos(delta), np.sin(delta)
        turned = points.copy()
        turned[[k, k + 1]] = foot + (points[[k, k + 1]] - foot) @ np.array([[c, s], [-s, c]])
        np.testing.assert_allclose(row(pivot, turned), distance * c, rtol=1e-12)


@pytest.mark.parametrize("seed", range(3))
def test_a_bar_rows_force_goes_to_its_nodes_with_the_foots_moment(seed):
    model, rng = _model(10, seed)
    rows = _rows(model, rng)
    forces = rng.standard_normal((rows.nodes.size, 2))
    total = rows.add_to_nodes(forces, np.zeros((model.n + 1, 2)))
    np.testing.assert_allclose(total.sum(axis=0), forces.sum(axis=0), rtol=1e-12, atol=1e-12)
    points = model.chain.nodes(model.x0)

    def moment(arm, f):  # about the origin
        return float(np.sum(arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0]))

    np.testing.assert_allclose(moment(points, total), moment(rows.row_points(points), forces), rtol=1e-10,
                               atol=1e-10)


def test_a_bar_row_is_refused_without_what_it_needs():
    k, d, lb, ub = np.array([2]), np.ones((1, 2)), np.zeros(1), np.full(1, np.inf)
    zero, pivot = np.zeros((1, 2, 2)), np.zeros((1, 2))
    bar = {"centres": pivot, "pivots": pivot, "turns": np.array([1.0])}
    with pytest.raises(ValueError, match="need hessians"):
        NodeRows(k, d, lb, ub, fractions=np.array([0.5]), **bar)
    with pytest.raises(ValueError, match="no H"):
        NodeRows(k, d, lb, ub, hessians=np.ones((1, 2, 2)), fractions=np.array([0.5]), **bar)
    with pytest.raises(ValueError, match="base node"):
        NodeRows(np.array([0]), d, lb, ub, hessians=zero, fractions=np.array([0.5]), **bar)
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        NodeRows(k, d, lb, ub, hessians=zero, fractions=np.array([1.5]), **bar)
    with pytest.raises(ValueError, match="belong to bar rows"):
        NodeRows(k, d, lb, ub, fractions=np.array([0.5]))
