"""Bars graded by curvature (issue 14, part 4): layouts, second order on them, gain where curvature concentrates,
explicit ``bar_lengths``, bad input."""

from __future__ import annotations

import numpy as np
import pytest

from guidewire import Scene, Section, Wire, load_scene, paper_scenes, scene_to_toml, solve
from guidewire.chain.density import curvature_density, graded_bars
from guidewire.chain.kinematics import place_bars, scene_bars
from guidewire.reference import continuum_reference
from guidewire.reference.scene_reference import node_errors
from guidewire.solve.refine import graded_scene

SCENES = paper_scenes()


def _mean_error(sol, reference):
    return float(np.mean(node_errors(sol, reference)))


def test_a_constant_density_is_the_uniform_layout_and_a_graded_one_keeps_every_contact_and_boundary_a_node():
    contacts, breaks = [18.0, 71.0], [40.0]
    uniform, _ = place_bars(87.0, 29, contacts, breaks)
    flat = graded_bars(87.0, 29, contacts, breaks, np.array([0.0, 87.0]), np.array([3.0, 3.0]))
    np.testing.assert_allclose(flat, uniform, rtol=1e-12)
    grid = np.linspace(0.0, 87.0, 50)
    graded = graded_bars(87.0, 29, contacts, breaks, grid, 1.0 + np.exp(-((grid - 30.0) / 5.0) ** 2) * 8.0)
    nodes = np.concatenate(([0.0], np.cumsum(graded)))
    assert graded.size == 29 and np.all(graded > 0.0) and nodes[-1] == pytest.approx(87.0, rel=1e-14)
    for s in (*contacts, *breaks):
        assert np.min(np.abs(nodes - s)) < 1e-12
    inside = (nodes[1:] + nodes[:-1]) / 2
    assert np.min(graded[np.abs(inside - 30.0) < 3.0]) < 0.5 * np.max(graded[inside < 18.0])  # denser at the bump


def test_explicit_uniform_bar_lengths_reproduce_todays_solve_exactly():
    scene = SCENES["table4"].with_bars(29)
    lengths, _ = scene_bars(scene)
    today = solve(scene)
    again = solve(scene.with_wire(bar_lengths=tuple(lengths)))
    np.testing.assert_array_equal(again.nodes, today.nodes)
    assert again.energy == today.energy


@pytest.mark.parametrize("name", ["table4", "fig6a"])
def test_second_order_on_a_graded_layout_against_the_continuum(name):
    """One density (from a 20-bar solve), n = 20, 40, 80 bars: the mean node error falls as n⁻² (fitted order
    1.8–2.3), on layouts whose longest bar is several times the shortest."""
    scene = SCENES[name]
    reference, why = continuum_reference(scene)
    assert reference is not None, why
    coarse = solve(scene, bars=20)
    grid, rho = curvature_density(coarse.s, coarse.curvature)
    ns, errors = [20, 40, 80], []
    for n in ns:
        lengths = graded_bars(scene.wire.length, n, [c.s for c in scene.contacts], (), grid, rho)
        assert lengths.max() > 3.0 * lengths.min()
        sol = solve(scene.with_wire(bars=n, bar_lengths=tuple(lengths)))
        assert sol.success
        errors.append(_mean_error(sol, reference))
    order = -np.polyfit(np.log(ns), np.log(errors), 1)[0]
    assert 1.8 <= order <= 2.3, (order, errors)


@pytest.mark.parametrize("name", ["table4", "fig6a", "table2_minus_pi_2"])
def test_curvature_grading_beats_uniform_bars_where_the_curvature_concentrates(name):
    scene = SCENES[name]
    reference, _ = continuum_reference(scene)
    graded = solve(scene, bars=40, density="curvature")
    uniform = solve(scene, bars=40)
    assert graded.success and graded.n_bars == 40
    assert np.ptp(np.diff(graded.s)) > 0.1  # really graded
    assert _mean_error(graded, reference) < 0.9 * _mean_error(uniform, reference)
    for contact in scene.contacts:  # a node at every contact, which the graded wire meets
        k = int(np.argmin(np.abs(graded.s - contact.s)))
        assert graded.s[k] == pytest.approx(contact.s, abs=1e-9)
        np.testing.assert_allclose(graded.nodes[k], contact.point, atol=1e-6)


def test_a_graded_layout_keeps_the_section_boundaries_and_the_wires_own_density_option(tmp_path):
    scene = SCENES["table4"]
    wire = Wire(87.0, 30, sections=(Section(length=10.0, youngs_modulus=1000.0),), density="curvature")
    two = Scene(wire, scene.base, scene.contacts, name="two sections")
    sol = solve(two)
    assert sol.success and sol.n_bars == 30
    assert np.min(np.abs(sol.s - 77.0)) < 1e-9
    path = tmp_path / "graded.toml"
    path.write_text(scene_to_toml(graded_scene(two, sol, 30)), encoding="utf-8")
    back = load_scene(path)
    assert back.wire.bar_lengths is not None and len(back.wire.bar_lengths) == 30
    assert solve(back).success
    assert load_scene_density(two, tmp_path) == "curvature"


def load_scene_density(scene, tmp_path):
    path = tmp_path / "density.toml"
    path.write_text(scene_to_toml(scene), encoding="utf-8")
    return load_scene(path).wire.density


@pytest.mark.parametrize(("changes", "match"), [
    ({"density": "adaptive"}, "wire.density"),
    ({"bar_lengths": (50.0, 50.0)}, "wire.bar_lengths has shape"),
    ({"bars": 2, "bar_lengths": (60.0, 50.0)}, "sum to"),
    ({"bars": 2, "bar_lengths": (110.0, -10.0)}, "finite and positive"),
])
def test_bad_density_and_bar_lengths_name_the_field(changes, match):
    with pytest.raises(ValueError, match=match):
        SCENES["table1_pi_4"].with_wire(**changes)


def test_bar_lengths_without_a_node_at_a_contact_are_refused_before_solving():
    scene = SCENES["table2_zero"].with_wire(bars=3, bar_lengths=(40.0, 30.0, 30.0))
    with pytest.raises(ValueError, match="no node at the contact at s = 50"):
        solve(scene)


def test_bad_density_option_and_conflicting_options_are_value_errors():
    scene = SCENES["table1_pi_4"]
    with pytest.raises(ValueError, match="density is 'graded'"):
        solve(scene, density="graded")
    with pytest.raises(ValueError, match="initial_angles"):
        solve(scene, bars=20, density="curvature", initial_angles=np.zeros(20))
    with pytest.raises(ValueError, match="tol_mm"):
        solve(scene, tol_mm=-0.01)
    with pytest.raises(ValueError, match="tol_mm"):
        solve(scene, tol_mm=0.01, bars=40, density="curvature")
