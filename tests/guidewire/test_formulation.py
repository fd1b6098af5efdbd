"""The nonlinear program: derivatives against finite differences, node placement, and rows only for what a scene has."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import LinearConstraint

from guidewire import Base, Contact, Scene, Wall, Wire, paper_scenes
from guidewire.chain.kinematics import BarChain, place_bars
from guidewire.energy import bending_terms
from guidewire.program.formulation import formulate

EI = 64.65


def _fd_jacobian(fun, x, h=1e-6):
    """Central differences, one column per variable."""
    cols = [(np.atleast_1d(fun(x + h * e)) - np.atleast_1d(fun(x - h * e))) / (2 * h) for e in np.eye(x.size)]
    return np.column_stack(cols)


def _rich_scene(scheme):
    """Unequal bars (contact at s = 33.3), interior and end angles, a position-only and an angle-only contact,
    two walls, b₂ bounds: every block at once."""
    contacts = (
        Contact(33.3, (25.0, 12.0), 0.5, name="C1"),
        Contact(50.0, angle=0.3, name="C2"),
        Contact(70.0, (50.0, 25.0), name="C3"),
        Contact(100.0, (70.0, 40.0), 0.8, name="C4"),
    )
    walls = (Wall((0.0, 1.0), 60.0), Wall((1.5, -1.0), 100.0))
    wire = Wire(100.0, 20, moment_of_inertia=0.01816, max_relative_angle=0.5, scheme=scheme)
    return Scene(wire, Base((0.0, 0.0), 0.1), contacts, walls)


@pytest.mark.parametrize("scheme", ["second_order", "paper"])
def test_derivatives_match_finite_differences(scheme):
    form = formulate(_rich_scene(scheme))
    rng = np.random.default_rng(0)
    for phi in (form.x0, form.x0 + 0.3 * rng.standard_normal(form.n)):
        assert np.allclose(form.jac(phi), _fd_jacobian(form.fun, phi)[0], rtol=1e-6, atol=1e-7)
        assert np.allclose(form.energy.hessian().toarray(), _fd_jacobian(form.jac, phi), rtol=1e-6, atol=1e-6)
        for con in form.constraints:
            if isinstance(con, LinearConstraint):
                continue
            assert np.allclose(con["jac"](phi), _fd_jacobian(con["fun"], phi), rtol=1e-6, atol=1e-7)


@pytest.mark.parametrize("scheme", ["second_order", "paper"])
def test_constraint_hessians_match_finite_differences(scheme):
    """``hess(phi, v) = Σ v_i ∇²c_i`` (scipy's convention) against differences of ``Jᵀ v``, for random ``v``."""
    form = formulate(_rich_scene(scheme), wall_nodes=[np.array([3, 7, 20]), np.arange(1, 21)])
    rng = np.random.default_rng(3)
    phi = form.x0 + 0.3 * rng.standard_normal(form.n)
    checked = 0
    for con in form.constraints:
        if isinstance(con, LinearConstraint):
            continue
        v = rng.standard_normal(np.size(con["fun"](phi)))
        h = con["hess"](phi, v)
        exact = h.toarray() if hasattr(h, "toarray") else np.asarray(h)
        assert np.count_nonzero(exact - np.diag(np.diag(exact))) == 0  # diagonal in absolute angles
        assert np.allclose(exact, _fd_jacobian(lambda p, c=con, v=v: c["jac"](p).T @ v, phi), rtol=1e-6, atol=1e-6)
        checked += 1
    assert checked == 3  # positions and two walls
    assert form.block("wall")[0].nodes.tolist() == [3, 7, 20]


def test_energy_hessian_is_tridiagonal_and_the_energy_quadratic():
    form = formulate(_rich_scene("second_order"))
    hess = form.hess0.toarray()
    assert np.allclose(hess, hess.T)
    assert np.count_nonzero(np.triu(hess, 2)) == 0
    rng = np.random.default_rng(1)
    a, d = rng.standard_normal(form.n), rng.standard_normal(form.n)
    exact = form.fun(a) + form.jac(a) @ d + 0.5 * d @ hess @ d
    assert form.fun(a + d) == pytest.approx(exact, rel=1e-12)


def test_node_kinematics_match_the_paper_sums():
    """Eqs. 20–21 in the paper's variables: p = L/n Σ_i (cos, sin)(Σ_{j≤i} Δθ_j)."""
    rng = np.random.default_rng(2)
    dtheta = 0.2 * rng.standard_normal(10)
    chain = BarChain(np.array([1.0, -2.0]), np.full(10, 10.0))
    nodes = chain.nodes(np.cumsum(dtheta))
    x = 1.0 + 10.0 * sum(np.cos(dtheta[: i + 1].sum()) for i in range(10))
    y = -2.0 + 10.0 * sum(np.sin(dtheta[: i + 1].sum()) for i in range(10))
    assert nodes[-1] == pytest.approx([x, y])


def test_every_contact_is_a_node_even_off_the_uniform_grid():
    lengths, nodes = place_bars(100.0, 100, [33.3, 50.0, 100.0])
    s = np.concatenate(([0.0], np.cumsum(lengths)))
    assert lengths.size == 100 and s[-1] == pytest.approx(100.0)
    assert s[nodes] == pytest.approx([33.3, 50.0, 100.0], abs=1e-12)
    assert np.ptp(lengths[: nodes[0]]) < 1e-12  # equal within a segment
    uniform, grid_nodes = place_bars(100.0, 100, [18.0, 71.0])
    assert np.allclose(uniform, 1.0) and list(grid_nodes) == [18, 71]  # multiples of L/n: the paper's chain
    few, few_nodes = place_bars(10.0, 3, [0.1, 0.2])  # one bar per segment is always kept
    assert list(few_nodes) == [1, 2] and few.sum() == pytest.approx(10.0)


def test_unequal_joint_weights():
    """ε_joint = EI / (l_left + l_right); half joints EI / l (= 2ε for equal bars)."""
    lengths = np.array([1.0, 1.0, 2.0, 2.0])
    terms = bending_terms(lengths, EI, "second_order", 0.0, [2], [0.3])
    assert list(terms.node) == [0, 1, 2, 2, 3]
    assert terms.weight == pytest.approx([EI / 1.0, EI / 2.0, EI / 1.0, EI / 2.0, EI / 4.0])
    paper = bending_terms(lengths, EI, "paper", 0.0, [2], [0.3])
    assert list(paper.node) == [0, 1, 2, 3]
    assert paper.weight == pytest.approx([EI / 2.0, EI / 2.0, EI / 3.0, EI / 4.0])


def _kinds(scene, **kw):
    form = formulate(scene, **kw)
    return [(b.kind, b.size) for b in form.blocks], form


def test_rows_only_for_what_the_scene_has():
    scenes = paper_scenes()
    kinds, form = _kinds(scenes["table1_pi_4"])
    assert kinds == [("position", 2)]  # second order: the angles are energy terms
    assert form.arguments()["bounds"] is None
    assert _kinds(scenes["table1_pi_4"], scheme="paper")[0] == [("position", 2), ("angle", 1)]
    assert _kinds(scenes["table2_zero"], scheme="paper")[0] == [("position", 4), ("angle", 2)]
    assert _kinds(scenes["fig6b"])[0] == [("wall", 100)]  # one row per node, the fixed base left out
    assert _kinds(scenes["fig6b"].with_wire(max_relative_angle=0.2))[0] == [("wall", 100), ("relative_angle", 100)]
    angle_only = Scene(Wire(50.0, 10), Base((0.0, 0.0), 0.0), (Contact(50.0, angle=1.0),))
    assert _kinds(angle_only)[0] == []
    assert _kinds(angle_only, scheme="paper")[0] == [("angle", 1)]
    position_only = Scene(Wire(50.0, 10), Base((0.0, 0.0)), (Contact(50.0, (30.0, 30.0)),))
    assert _kinds(position_only, scheme="paper")[0] == [("position", 2)]
    kinds, form = _kinds(_rich_scene("paper"))
    assert kinds == [("position", 6), ("angle", 3), ("wall", 20), ("wall", 20), ("relative_angle", 20)]


def test_relative_angle_rows_are_the_joint_angles():
    form = formulate(_rich_scene("second_order"))
    (block,) = form.block("relative_angle")
    con = form.constraints[block.index]
    phi = np.random.default_rng(3).standard_normal(form.n)
    jump = np.diff(np.concatenate(([0.1], phi, [0.8])))  # clamp at 0.1, bar to bar, end contact at 0.8
    assert np.allclose(con.A @ phi - 0.5 * (con.lb + con.ub), jump[block.nodes])
    assert np.allclose(con.ub - con.lb, 1.0)


def test_singular_energy_gets_a_tiny_shift_only_when_needed():
    free = Scene(Wire(50.0, 10), Base((0.0, 0.0)), (Contact(50.0, (30.0, 30.0)),))
    form = formulate(free)
    assert np.linalg.eigvalsh(form.hess0.toarray()).min() > 0
    clamped = formulate(paper_scenes()["table1_pi_4"])
    assert np.array_equal(clamped.hess0.toarray(), clamped.energy.hessian().toarray())


def test_bad_options():
    scene = paper_scenes()["table1_pi_4"]
    with pytest.raises(ValueError, match="scheme"):
        formulate(scene, scheme="first")
    with pytest.raises(ValueError, match=r"initial_angles has shape \(3,\)"):
        formulate(scene, initial_angles=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="initial_nodes"):
        formulate(scene, initial_nodes=np.zeros((5, 2)))
    with pytest.raises(ValueError, match="not both"):
        formulate(scene, initial_angles=np.zeros(100), initial_nodes=np.zeros((101, 2)))
    with pytest.raises(ValueError, match="infeasible"):
        formulate(paper_scenes()["table5"])


def test_curvature_term_is_the_sum_of_the_rows_jacobian_products():
    from guidewire.chain.kinematics import BarChain
    from guidewire.program.reduced import _curvature_term

    rng = np.random.default_rng(3)
    n = 12
    chain = BarChain(np.zeros(2), rng.uniform(0.5, 1.5, n))
    phi = rng.normal(size=n)
    nodes = np.array([3, 7, 7, 12])
    w = rng.normal(size=(len(nodes), 2, 2))
    w = w + w.transpose(0, 2, 1)
    jac = chain.node_jacobian(phi, nodes)  # (rows, 2, n)
    expected = np.einsum("ran,rab,rbm->nm", jac, w, jac)
    np.testing.assert_allclose(_curvature_term(chain, phi, nodes, w), expected, rtol=1e-12, atol=1e-12)


def _same_model(a, b):
    assert np.array_equal(a.chain.lengths, b.chain.lengths)
    assert np.array_equal(a.chain.base_point, b.chain.base_point)
    assert np.array_equal(a.contact_nodes, b.contact_nodes)
    assert (a.energy.matrix != b.energy.matrix).nnz == 0
    for name in ("offset", "weight", "dual_length", "node"):
        assert np.array_equal(getattr(a.energy, name), getattr(b.energy, name))
    assert abs(a.hess0 - b.hess0).max() == 0.0
    assert np.array_equal(a.x0, b.x0)


@pytest.mark.parametrize("scheme", ["second_order", "paper"])
def test_model_reuse_keeps_only_what_the_scenes_share(scheme):
    """A :class:`ModelReuse` keeps the layout and energy when only targets move, the Hessian when a prescribed angle's
    value moves, nothing when the wire changes — and every model it gives equals one built anew, bit for bit."""
    from dataclasses import replace

    from guidewire.program.model import ModelReuse, build_model

    base = paper_scenes()["table2_pi_4"].with_scheme(scheme)
    c = base.contacts[-1]
    steps = [
        base,
        replace(base, contacts=(*base.contacts[:-1], replace(c, point=(c.point[0] - 0.5, c.point[1])))),  # target
        replace(base, contacts=(*base.contacts[:-1], replace(c, angle=c.angle + 0.1))),  # an angle's value
        replace(base, base=replace(base.base, point=(1.0, -2.0), angle=0.2)),  # the base moves and turns
        base.with_bars(base.wire.bars + 10),  # a new layout
    ]
    reuse = ModelReuse()
    hits = []
    for scene in steps:
        before = dict(reuse.hits)
        _same_model(build_model(scene, reuse=reuse), build_model(scene))
        hits.append(tuple(k for k in reuse.hits if reuse.hits[k] > before[k]))
    assert hits[0] == () and hits[1] == ("layout", "energy") and hits[4] == ()
    assert hits[2] == hits[3] == ("layout", "hessian")


@pytest.mark.parametrize("scheme", ["second_order", "paper"])
def test_tridiagonal_energy_hessian_is_two_dt_c_d_exactly(scheme):
    """The bincount assembly of the energy Hessian equals ``2 Dᵀ C D`` entry for entry, on every scene file (clamps,
    split joints, sections, rest curvature), with no stored zeros and sorted indices."""
    from pathlib import Path

    import guidewire
    from guidewire.energy import _general_hessian
    from guidewire.program.model import build_model

    planar = [p for p in (Path(guidewire.__file__).parent / "scenes").rglob("*.toml") if "vessels3d" not in p.parts]
    for path in sorted(planar):  # (3-D scenes are tests/guidewire3d's)
        scene = guidewire.load_scene(path).with_scheme(scheme)
        energy = build_model(scene.with_bars(max(scene.wire.bars, 12))).energy
        fast, general = energy.hessian(), _general_hessian(energy.matrix, energy.weight)
        general.eliminate_zeros()
        assert fast.has_sorted_indices and fast.nnz == general.nnz, path.stem
        assert np.array_equal(fast.toarray(), general.toarray()), path.stem
