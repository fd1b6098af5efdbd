"""The full-space program (angles and nodes as variables): derivatives, start, same answers as the reduced one."""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import LinearConstraint

import sqp
from guidewire import Base, Contact, Scene, Wall, Wire, formulate, paper_scenes, solve
from guidewire.program.full_space import POLISH_TOLERANCE
from guidewire.solve.result import build_solution
from sqp.hessian import convexify

SCENES = paper_scenes()


def _rich_scene(scheme):
    """Unequal bars, interior and end angles, a position-only and an angle-only contact, two walls, b₂ bounds."""
    contacts = (
        Contact(33.3, (25.0, 12.0), 0.5, name="C1"),
        Contact(50.0, angle=0.3, name="C2"),
        Contact(70.0, (50.0, 25.0), name="C3"),
        Contact(100.0, (70.0, 40.0), 0.8, name="C4"),
    )
    walls = (Wall((0.0, 1.0), 60.0), Wall((1.5, -1.0), 100.0))
    wire = Wire(100.0, 20, moment_of_inertia=0.01816, max_relative_angle=0.5, scheme=scheme)
    return Scene(wire, Base((0.0, 0.0), 0.1), contacts, walls)


def formulate_full(scene, **kw):
    return formulate(scene, layout="full", **kw)


def solve_full(scene, **kw):
    return solve(scene, layout="full", **kw)


def wall_gaps(chain, phi, walls):
    """``offset − n̂·p_k`` for every wall and node 1..n (negative: violated)."""
    pts = chain.nodes(phi)[1:]
    return np.array([w.unit()[1] - pts @ np.asarray(w.unit()[0]) for w in walls])


def _fd_jacobian(fun, x, h=1e-6):
    cols = [(np.atleast_1d(fun(x + h * e)) - np.atleast_1d(fun(x - h * e))) / (2 * h) for e in np.eye(x.size)]
    return np.column_stack(cols)


@pytest.mark.parametrize("scheme", ["second_order", "paper"])
def test_derivatives_match_finite_differences(scheme):
    full = formulate_full(_rich_scene(scheme))
    closure = full.constraints[0]
    rng = np.random.default_rng(1)
    z = full.x0 + 0.2 * rng.standard_normal(full.size)
    J = closure["jac"](z)
    assert sp.issparse(J) and J.shape == (2 * full.n, 3 * full.n) and J.nnz <= 3 * 2 * full.n
    assert np.allclose(J.toarray(), _fd_jacobian(closure["fun"], z), rtol=1e-6, atol=1e-8)
    v = rng.standard_normal(2 * full.n)
    H = closure["hess"](z, v)
    assert sp.issparse(H) and H.format == "csc"
    assert np.allclose(H.toarray(), _fd_jacobian(lambda x: closure["jac"](x).T @ v, z), rtol=1e-6, atol=1e-7)
    assert np.allclose(full.jac(z), _fd_jacobian(full.fun, z)[0], rtol=1e-6, atol=1e-7)
    assert np.allclose(full.hess0.toarray(), _fd_jacobian(full.jac, z), rtol=1e-6, atol=1e-5)


@pytest.mark.parametrize("scheme", ["second_order", "paper"])
def test_blocks_and_start(scheme):
    """The reduced blocks after the closure, sparse linear rows, and a start on every linear row (no projection)."""
    full = formulate_full(_rich_scene(scheme))
    kinds = [b.kind for b in full.blocks]
    assert kinds == [b.kind for b in formulate(_rich_scene(scheme)).blocks]
    assert [b.index for b in full.blocks] == list(range(1, len(kinds) + 1))  # the closure first
    assert kinds.count("wall") == 2 and ("angle" in kinds) == (scheme == "paper")
    for block in full.block("wall"):
        assert np.array_equal(block.nodes, np.arange(1, full.n + 1))
    for con in full.constraints[1:]:
        assert isinstance(con, LinearConstraint) and sp.issparse(con.A)
        az = con.A @ full.x0
        assert np.all(az >= con.lb - 1e-12) and np.all(az <= con.ub + 1e-12)
    assert np.allclose(full.angles(full.x0)[: full.n], full.x0[0::3])
    assert np.allclose(full.layout.pack(full.angles(full.x0), full.nodes(full.x0)), full.x0)


@cache
def _pair(name, scheme, bars=100):
    """(full-space result, its Solution, the reduced Solution) of one paper scene."""
    scene = SCENES[name]
    full = formulate_full(scene, scheme=scheme, bars=bars)
    res = sqp.minimize(**full.arguments(), hess=full.hess)
    ref = solve(scene, scheme=scheme, bars=bars, layout="reduced")
    return full, res, build_solution(full, res, 0.0), ref


CASES = [(name, scheme) for name in ("table1_pi_4", "fig6a", "table4") for scheme in ("second_order", "paper")]


@pytest.mark.parametrize(("name", "scheme"), CASES)
def test_same_answer_as_reduced(name, scheme):
    full, res, sol, ref = _pair(name, scheme)
    assert res.success and ref.success and sol.success
    assert res.nit <= 8
    # both stop at a KKT residual of tol = 1e-8; a contact is then met to within tol·L = 1e-6 mm (the full space's
    # closure residuals add up along the chain below the polish threshold 1e-9·L = 1e-7 mm; measured 4.9e-8 mm on
    # Table 1 second order, < 3e-10 mm on the others) and the energy to ~λ·violation
    assert sol.energy == pytest.approx(ref.energy, rel=1e-8)
    assert np.max(np.abs(sol.nodes - ref.nodes)) < 1e-6
    assert np.max(np.abs(full.nodes(res.x) - sol.nodes)) < 1e-6  # the variables' nodes: the chain's nodes, to tol
    assert sol.max_violation < POLISH_TOLERANCE * SCENES[name].wire.length
    force_scale = max(np.max(np.abs(r.force)) for r in ref.reactions if r.force is not None)
    moment_scale = max(abs(r.moment) for r in ref.reactions if r.moment is not None)
    for mine, theirs in zip(sol.reactions, ref.reactions, strict=True):
        assert (mine.force is None) == (theirs.force is None) and (mine.moment is None) == (theirs.moment is None)
        if theirs.force is not None:
            assert np.allclose(mine.force, theirs.force, rtol=0, atol=1e-6 * force_scale)
        if theirs.moment is not None:
            assert mine.moment == pytest.approx(theirs.moment, rel=0, abs=1e-6 * moment_scale)
    assert np.allclose(sol.wall_forces, ref.wall_forces, rtol=0, atol=1e-6 * force_scale)
    assert abs(sol.moment_balance()) < 1e-6 * moment_scale


def test_walls_hold_at_every_node():
    full, res, sol, _ = _pair("fig6a", "second_order")
    scene = full.scene
    assert np.min(wall_gaps(full.chain, sol.bar_angles, scene.walls)) > -1e-9
    (normal, offset), = [w.unit() for w in scene.walls]
    assert np.max(full.nodes(res.x)[1:] @ np.asarray(normal) - offset) < 1e-9
    (wall,) = full.block("wall")
    lam = full.multipliers(res)[full.blocks.index(wall)]
    assert lam.size == full.n and np.min(lam) > -1e-9 and np.max(lam) > 0  # one convention: λ ≥ 0, in contact
    # the same multipliers as the reduced program's (one sign convention in both layouts)
    reduced = formulate(scene, wall_nodes=None)
    red = sqp.minimize(**reduced.arguments(), hess=reduced.hess)
    assert np.allclose(reduced.multipliers(red)[0], lam, rtol=0, atol=1e-6 * np.max(lam))


def test_multiplier_maps_round_trip():
    """``multipliers0`` (closure multipliers from stationarity in the nodes) inverts ``multipliers``."""
    for name in ("table1_pi_4", "fig6a"):
        full, res, _, _ = _pair(name, "second_order")
        back = full.multipliers0(full.blocks, full.multipliers(res))
        scale = np.max(np.abs(res.constraint_multipliers[0]))
        for a, b in zip(back, res.constraint_multipliers, strict=True):
            assert np.allclose(a, b, rtol=0, atol=1e-6 * scale)


def test_sparse_path_and_solve_full():
    """Above 100 bars the engine works sparsely: a sparse backend, Newton convergence, and the augmented-Lagrangian
    convexification of the sparse Lagrangian Hessian (no identity shift); ``solve_full`` gives the reduced answer."""
    # Fig. 6a's free tail pivots about a tangential wall contact: its shape is determined only to ~1e-4 mm by a
    # KKT residual of 1e-10 (measured: the two formulations differ by 9.2e-5 mm at the tip at tol 1e-8 and 1e-10,
    # with energies equal to 2e-11), well inside the 1e-3 mm discretisation error at this n.
    for name, node_tol in (("table1_pi_4", 1e-6), ("fig6a", 2e-4)):
        scene = SCENES[name]
        sol = solve_full(scene, bars=120)
        ref = solve(scene, bars=120, layout="reduced")
        assert sol.success and sol.iterations <= 8
        assert sol.energy == pytest.approx(ref.energy, rel=1e-8)
        assert np.max(np.abs(sol.nodes - ref.nodes)) < node_tol
        assert sol.layout == "full" and sol.result.x.size == 3 * 120
    full = formulate_full(SCENES["table1_pi_4"], bars=120)
    first = solve_full(SCENES["table1_pi_4"], bars=120)
    res = first.result
    z, mu = res.x, res.constraint_multipliers[0]
    W = sp.csc_matrix(full.hess0 - full.constraints[0]["hess"](z, mu))
    # the rows the engine keeps as equalities: the closure and the contact's position rows
    C = sp.vstack([full.constraints[0]["jac"](z), full.constraints[full.block("position")[0].index].A], format="csr")
    B, delta, rho = convexify(W, 0.0, C, 0.0)
    assert sp.issparse(B) and delta == 0.0 and rho > 0.0
    again = solve_full(SCENES["table1_pi_4"], bars=120, initial_angles=first.bar_angles, multipliers0=first)
    assert again.success and again.iterations <= 2


def test_solve_routes_large_scenes_to_the_full_space():
    """``layout="auto"`` is the full space above FULL_SPACE_BARS bars (exact Hessian), the reduced program
    below and for BFGS; the full-space answer holds every wall at every node and approaches the continuum energy."""
    scene = SCENES["fig6a"]
    sol = solve(scene, bars=400)
    assert sol.success and sol.iterations <= 8
    assert sol.layout == "full" and sol.result.x.size == 3 * 400
    chain = formulate_full(scene, bars=400).chain
    assert min(np.min(g) for g in wall_gaps(chain, sol.bar_angles, scene.walls)) > -1e-6
    assert sol.energy == pytest.approx(0.764230, rel=1e-4)  # the continuum energy (guidewire.reference)
    assert solve(scene, bars=40).layout == "reduced"
    assert solve(scene, bars=40, layout="full").layout == "full"


def test_layout_option_is_validated():
    scene = SCENES["table1_pi_4"]
    with pytest.raises(ValueError, match="layout"):
        solve(scene, layout="dense")
    with pytest.raises(ValueError, match="layout"):
        formulate(scene, layout="dense")
    with pytest.raises(ValueError, match="hessian='exact'"):
        solve(scene, layout="full", hessian="bfgs")


def test_wire_pushed_head_on_into_a_near_wall():
    """A 300 mm wire clamped along +x with the wall x ≤ 10 straight ahead: the straight start's linearisation is
    inconsistent (x increments are l to first order), so the start must coil inside the wall (trial curvatures up to
    20 turns) and the first QPs are elastic (kept sparse in the full space). Both formulations find the same shape."""
    wire = Wire(300.0, 300, moment_of_inertia=0.01816)
    scene = Scene(wire, Base((0.0, 0.0), 0.0), walls=(Wall((1.0, 0.0), 10.0),))
    full = solve(scene, layout="full")
    reduced = solve(scene)
    assert full.success and reduced.success, (full.message, reduced.message)
    assert full.layout == "full" and reduced.layout == "reduced"  # (300 bars: FULL_SPACE_BARS, reduced by default)
    assert full.energy == pytest.approx(reduced.energy, rel=1e-8)
    assert np.max(full.nodes[:, 0]) <= 10.0 + 1e-6 and np.max(reduced.nodes[:, 0]) <= 10.0 + 1e-6
