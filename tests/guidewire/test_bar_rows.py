"""Rows on a point of a bar (``NodeRows.fractions``): the same row in both layouts, derivatives against finite
differences, and the limits τ = 0 and τ = 1 equal to the node rows they meet."""

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


def _rows(model, rng, curved):
    """Four node rows and four bar rows at random τ, linear or with quadratic node rows (bar rows stay linear)."""
    n = model.n
    nodes = np.concatenate((rng.choice(np.arange(1, n + 1), 4), rng.choice(np.arange(1, n), 4)))
    tau = np.concatenate((np.zeros(4), rng.uniform(0.05, 0.95, 4)))
    d = rng.standard_normal((8, 2))
    lb, ub = rng.standard_normal(8) - 5.0, np.full(8, np.inf)
    if not curved:
        return NodeRows(nodes, d, lb, ub, fractions=tau)
    h = rng.standard_normal((8, 2, 2))
    h = h + h.transpose(0, 2, 1)
    h[4:] = 0.0
    return NodeRows(nodes, d, lb, ub, hessians=h, centres=rng.standard_normal((8, 2)), fractions=tau)


def _dense(matrix):
    return matrix.toarray() if hasattr(matrix, "toarray") else np.asarray(matrix)


def _as_functions(con, lb):
    """The rows' values (not less ``lb``, as an ``ineq`` dict states them), Jacobian and Hessian functions."""
    if isinstance(con, LinearConstraint):
        A = con.A.toarray()
        return (lambda x: A @ x), (lambda x: A), None
    return (lambda x: con["fun"](x) + lb), con["jac"], con["hess"]


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("curved", [False, True])
def test_a_bar_rows_derivatives_match_finite_differences_in_both_layouts(seed, curved):
    model, rng = _model(12, seed)
    rows = _rows(model, rng, curved)
    reduced, full = ReducedLayout(model), FullLayout.build(model)
    phi = model.x0 + 0.2 * rng.standard_normal(model.n)
    for layout, x in ((reduced, phi), (full, full.pack(phi) + 1e-3 * rng.standard_normal(full.size))):
        fun, jac, hess = _as_functions(layout.node_rows(rows), rows.lb)
        J = jac(x)
        J = J.toarray() if hasattr(J, "toarray") else J
        np.testing.assert_allclose(J, _fd(fun, x), rtol=1e-6, atol=1e-7)
        if hess is not None:
            v = rng.standard_normal(rows.nodes.size)
            fd = _fd(lambda y, jac=jac, v=v: _dense(jac(y)).T @ v, x)
            np.testing.assert_allclose(_dense(hess(x, v)), fd, rtol=1e-5, atol=1e-6)
    # the two layouts hold the same rows: equal values at the same wire
    f_reduced, _, _ = _as_functions(reduced.node_rows(rows), rows.lb)
    f_full, _, _ = _as_functions(full.node_rows(rows), rows.lb)
    assert np.allclose(f_reduced(phi), f_full(full.pack(phi)), rtol=0, atol=1e-12 * (1 + np.abs(rows.lb).max()))


@pytest.mark.parametrize("seed", range(3))
def test_a_bar_row_at_its_ends_is_the_node_row_there(seed):
    """τ → 0 and τ → 1 give the rows of nodes ``k`` and ``k + 1`` (values and Jacobians in both layouts), and a
    force on the bar's point moves the same load to the nodes as its two shares."""
    model, rng = _model(10, seed)
    k = rng.choice(np.arange(1, model.n), 3)
    d, lb = rng.standard_normal((3, 2)), np.zeros(3)
    ub = np.full(3, np.inf)
    phi = model.x0 + 0.2 * rng.standard_normal(model.n)
    for tau, node in ((0.0, k), (1.0, k + 1)):
        bar = NodeRows(k, d, lb, ub, fractions=np.full(3, tau))
        plain = NodeRows(node, d, lb, ub)
        for layout, x in ((ReducedLayout(model), phi), (FullLayout.build(model), FullLayout.build(model).pack(phi))):
            fa, ja, _ = _as_functions(layout.node_rows(bar), lb)
            fb, jb, _ = _as_functions(layout.node_rows(plain), lb)
            Ja, Jb = ja(x), jb(x)
            Ja, Jb = (M.toarray() if hasattr(M, "toarray") else M for M in (Ja, Jb))
            np.testing.assert_allclose(fa(x), fb(x), rtol=0, atol=1e-12)
            np.testing.assert_allclose(Ja, Jb, rtol=0, atol=1e-12)
    tau = rng.uniform(0.1, 0.9, 3)
    rows = NodeRows(k, d, lb, ub, fractions=tau)
    force = rows.add_to_nodes(d, np.zeros((model.n + 1, 2)))
    np.testing.assert_allclose(force.sum(axis=0), d.sum(axis=0), rtol=1e-12, atol=1e-12)
    points = model.chain.nodes(phi)
    def moment(arm, f):  # about the origin
        return float(np.sum(arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0]))

    # the two shares have the moment of the force at the bar's point
    np.testing.assert_allclose(moment(points, force), moment(rows.row_points(points), d), rtol=1e-10, atol=1e-10)


def test_a_bar_row_must_be_linear_and_off_the_base():
    k, d, lb, ub = np.array([2]), np.ones((1, 2)), np.zeros(1), np.full(1, np.inf)
    with pytest.raises(ValueError, match="linear"):
        NodeRows(k, d, lb, ub, hessians=np.ones((1, 2, 2)), centres=np.zeros((1, 2)), fractions=np.array([0.5]))
    with pytest.raises(ValueError, match="base node"):
        NodeRows(np.array([0]), d, lb, ub, fractions=np.array([0.5]))
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        NodeRows(k, d, lb, ub, fractions=np.array([1.5]))
