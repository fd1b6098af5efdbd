"""Wire sections (E, d, I and rest curvature along the wire), the J-tip, and non-uniform bars (issue 14, parts 1–3)."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import tomllib

import numpy as np
import pytest

from guidewire import Base, Contact, Scene, Section, Wall, Wire, insert, load_scene, paper_scenes, solve
from guidewire.chain.kinematics import place_bars, scene_bars
from guidewire.program.feasibility import infeasibility
from guidewire.program.model import build_model
from guidewire.scene.file import scene_from_dict, scene_to_toml
from guidewire.scene.paper import scene_path

# stEVE's J wire: a tip arc of radius 12.1 mm over 0.4π, tip E 17 GPa / OD 0.7 mm, shaft E 80 GPa / OD 0.89 mm.
J_RADIUS, J_ANGLE = 12.1, 0.4 * math.pi
SHAFT = {"youngs_modulus": 80_000.0, "diameter": 0.89}
TIP = {"youngs_modulus": 17_000.0, "diameter": 0.7}


def j_wire(length: float = 60.0, bars: int = 60, sign: float = 1.0) -> Wire:
    return Wire(length, bars, **SHAFT, sections=(Section.arc(J_RADIUS, sign * J_ANGLE, **TIP),))


# ------------------------------------------------------------------------------------------------------------------
def test_sections_are_measured_from_the_tip_and_filled_from_the_wire():
    wire = Wire(100.0, 50, youngs_modulus=3000.0, diameter=0.8,
                sections=(Section(10.0, youngs_modulus=1000.0), Section(20.0, diameter=0.5, rest_curvature=0.1)))
    assert wire.section_boundaries() == (70.0, 90.0)
    props = wire.properties_at([5.0, 75.0, 95.0, 100.0])
    np.testing.assert_array_equal(props.youngs_modulus, [3000.0, 3000.0, 1000.0, 1000.0])
    np.testing.assert_array_equal(props.diameter, [0.8, 0.5, 0.8, 0.8])
    np.testing.assert_allclose(props.second_moment, [math.pi * d**4 / 64 for d in (0.8, 0.5, 0.8, 0.8)])
    np.testing.assert_array_equal(props.rest_curvature, [0.0, 0.1, 0.0, 0.0])
    # inserting further keeps every section at the tip: the boundaries move with the material
    longer = wire.with_length(130.0)
    assert longer.section_boundaries() == (100.0, 120.0)
    assert Scene(wire, Base((0, 0), 0.0)).with_wire(length=130.0).wire.section_boundaries() == (100.0, 120.0)


def test_section_values_are_checked():
    with pytest.raises(ValueError, match="section.length"):
        Section(0.0)
    with pytest.raises(ValueError, match="section.diameter"):
        Section(1.0, diameter=-0.1)
    with pytest.raises(TypeError, match="wire.sections"):
        Wire(10.0, 10, sections=Section(1.0))


def test_energy_gradient_and_hessian_match_finite_differences_with_sections_and_rest_curvature():
    wire = Wire(50.0, 37, youngs_modulus=60_000.0, diameter=0.8,
                sections=(Section(7.3, youngs_modulus=15_000.0, diameter=0.6, rest_curvature=-0.09),
                          Section(11.1, diameter=0.7, rest_curvature=0.03)))
    scene = Scene(wire, Base((0.0, 0.0), 0.2), (Contact(21.4, angle=0.4), Contact(40.0, point=(30.0, 20.0))))
    model = build_model(scene)
    assert np.ptp(model.chain.lengths) > 0.1  # non-uniform bars
    rng = np.random.default_rng(3)
    phi = rng.normal(0.0, 0.5, model.n)
    h = 1e-6
    eye = np.eye(model.n)
    fd = np.array([(model.energy.value(phi + h * e) - model.energy.value(phi - h * e)) / (2 * h) for e in eye])
    grad = model.energy.gradient(phi)
    np.testing.assert_allclose(grad, fd, rtol=1e-6, atol=1e-6 * np.abs(grad).max())
    v = rng.normal(size=model.n)
    hv = (model.energy.gradient(phi + h * v) - model.energy.gradient(phi - h * v)) / (2 * h)
    np.testing.assert_allclose(model.energy.hessian() @ v, hv, rtol=1e-6, atol=1e-6 * np.abs(hv).max())


def test_a_free_j_tipped_wire_rests_exactly_in_its_j():
    for sign in (1.0, -1.0):  # the two mirror orientations
        sol = solve(Scene(j_wire(sign=sign), Base((0.0, 0.0), 0.0)))
        assert sol.success
        assert sol.energy < 1e-20
        np.testing.assert_allclose(sol.bending_stress_mpa, 0.0, atol=1e-9)  # stress is measured from the rest shape
        # the shaft is straight, the tip turns by ±0.4π
        shaft = sol.s <= 60.0 - J_RADIUS * J_ANGLE + 1e-9
        np.testing.assert_allclose(sol.nodes[shaft, 1], 0.0, atol=1e-12)
        assert sol.tangent_angles[-1] == pytest.approx(sign * J_ANGLE, abs=1e-12)
        # the tip nodes lie on the J's circle (radius 12.1 mm, centre above/below the start of the J), to O(h²)
        start = 60.0 - J_RADIUS * J_ANGLE
        centre = np.array([start, sign * J_RADIUS])
        radius = np.hypot(*(sol.nodes[~shaft] - centre).T)
        np.testing.assert_allclose(radius, J_RADIUS, rtol=2e-3)
        assert sign * sol.nodes[-1, 1] == pytest.approx(J_RADIUS * (1 - math.cos(J_ANGLE)), rel=2e-3)
        # the chain reproduces the curvature exactly: κ = 1/R at every joint inside the J
        inner = (sol.s > start + 1e-9) & (sol.s < 60.0 - 1e-9)
        np.testing.assert_allclose(sol.curvature[inner], sign / J_RADIUS, rtol=1e-12)


def _beam_deflection(x, length, boundary, ei_shaft, ei_tip, force):
    """Small-deflection cantilever (clamped at 0) with a transverse tip force: EI(x) v'' = F (L − x), piecewise
    cubic: v(x) = F ∫₀ˣ (x − ξ)(L − ξ) / EI(ξ) dξ."""

    def antiderivative(xi, at):  # ∫ (at − ξ)(L − ξ) dξ
        return at * length * xi - (at + length) * xi**2 / 2 + xi**3 / 3

    x = np.asarray(x, dtype=float)
    inside = np.minimum(x, boundary)
    v = antiderivative(inside, x) / ei_shaft
    v += np.where(x > boundary, (antiderivative(x, x) - antiderivative(boundary, x)) / ei_tip, 0.0)
    return force * v


def _cantilever(length, boundary, ei_shaft, ei_tip, tip):
    """The force that bends the beam theory's cantilever to a tip deflection ``tip`` and the tip's x, which follows
    from inextensibility: ``L − ∫ v'²/2``."""
    force = tip / _beam_deflection(length, length, boundary, ei_shaft, ei_tip, 1.0)
    fine = np.linspace(0.0, length, 20_001)
    slope = np.gradient(_beam_deflection(fine, length, boundary, ei_shaft, ei_tip, force), fine)
    return force, length - np.trapezoid(slope**2 / 2, fine)


def test_two_section_cantilever_matches_piecewise_cubic_beam_theory():
    length, boundary = 100.0, 70.0
    wire = Wire(length, 100, **SHAFT, sections=(Section(length - boundary, **TIP),))
    ei_shaft, ei_tip = wire.properties_at([0.0, length]).bending_stiffness
    assert ei_shaft / ei_tip == pytest.approx(12.30, abs=0.01)  # the stEVE wire's ratio of about 12
    tip = 0.5  # mm: small deflection
    force, tip_x = _cantilever(length, boundary, ei_shaft, ei_tip, tip)
    sol = solve(Scene(wire, Base((0.0, 0.0), 0.0), (Contact(length, point=(tip_x, tip)),)))
    assert sol.success
    expected = _beam_deflection(sol.s, length, boundary, ei_shaft, ei_tip, force)
    assert np.max(np.abs(sol.nodes[:, 1] - expected)) < 2e-3 * tip
    assert sol.reactions[1].force[1] == pytest.approx(force, rel=2e-3)
    # and the sections matter: the uniform shaft wire needs 3·EI/L³ per mm, 30 % more (the soft tip carries little
    # moment)
    uniform_force, uniform_x = _cantilever(length, boundary, ei_shaft, ei_shaft, tip)
    assert uniform_force == pytest.approx(3 * ei_shaft * tip / length**3)
    uniform = solve(Scene(Wire(length, 100, **SHAFT), Base((0.0, 0.0), 0.0),
                          (Contact(length, point=(uniform_x, tip)),)))
    assert uniform.reactions[1].force[1] == pytest.approx(uniform_force, rel=2e-3)
    assert uniform_force / force == pytest.approx(1.305, abs=0.001)


def test_a_section_that_changes_nothing_changes_nothing():
    scene = paper_scenes()["table1_pi_4"]
    plain = solve(scene)
    same = solve(scene.with_wire(sections=(Section(30.0),)))  # boundary at s = 70, a node of the uniform chain
    assert same.energy == pytest.approx(plain.energy, rel=1e-12)
    np.testing.assert_allclose(same.nodes, plain.nodes, atol=1e-9)


def test_two_contacts_half_a_millimetre_apart_are_bridged_by_shorter_bars():
    radius = 80.0

    def arc(s):
        return (radius * math.sin(s / radius), radius * (1.0 - math.cos(s / radius)))

    wire = Wire(100.0, 100)
    contacts = (Contact(60.0, point=arc(60.0)), Contact(60.5, point=arc(60.5)), Contact(100.0, point=arc(100.0)))
    scene = Scene(wire, Base((0.0, 0.0), 0.0), contacts)
    # one uniform bar of 0.5 mm could not span the 0.49999 mm chord; the layout puts two shorter bars there
    lengths, nodes = scene_bars(scene)
    assert nodes[1] - nodes[0] == 2 and lengths[nodes[0]:nodes[1]].sum() == pytest.approx(0.5)
    assert infeasibility(scene) is None
    sol = solve(scene)
    assert sol.success
    for contact, node in zip(contacts, nodes, strict=True):
        np.testing.assert_allclose(sol.nodes[node], contact.point, atol=1e-7)
    # the answer is converged in the bars: a 4× finer chain has the same energy within 0.5 %
    fine = solve(scene.with_bars(400))
    assert fine.success and sol.energy == pytest.approx(fine.energy, rel=5e-3)


def test_place_bars_puts_a_node_at_every_breakpoint_and_contact():
    lengths, nodes = place_bars(10.0, 10, [4.0], breakpoints=[2.5, 4.0, 7.25])
    s = np.concatenate(([0.0], np.cumsum(lengths)))
    for mark in (2.5, 4.0, 7.25, 10.0):
        assert np.min(np.abs(s - mark)) < 1e-12
    assert s[nodes[0]] == pytest.approx(4.0)
    # without breakpoints and bridging the uniform chain is untouched
    np.testing.assert_array_equal(place_bars(100.0, 100, [50.0])[0], np.full(100, 1.0))


def test_scene_file_sections_round_trip_and_typos_are_caught():
    scene = load_scene(scene_path("j_tip"))
    assert len(scene.wire.sections) == 1
    assert scene.wire.sections[0].rest_curvature == pytest.approx(1 / J_RADIUS)
    assert scene_from_dict(tomllib.loads(scene_to_toml(scene))) == scene
    bad = scene_to_toml(scene).replace("rest_curvature", "rest_curvatur")
    with pytest.raises(ValueError, match="did you mean 'rest_curvature'"):
        scene_from_dict(tomllib.loads(bad))


def test_j_tip_scene_solves_from_the_cli(tmp_path):
    out = tmp_path / "j.json"
    run = subprocess.run([sys.executable, "-m", "guidewire", "solve", str(scene_path("j_tip")), "--json", str(out)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    data = json.loads(out.read_text())
    assert data["success"] and data["bars"] == len(data["bar_lengths"]) == 60
    assert sum(data["bar_lengths"]) == pytest.approx(60.0)
    s = np.array(data["s"])
    assert np.min(np.abs(s - (60.0 - J_RADIUS * J_ANGLE))) < 1e-9  # a node at the section boundary
    nodes = np.array(data["nodes"])
    assert nodes[:, 1].max() <= 4.0 + 1e-7  # the wall flattens the J (free, it would rise 8.36 mm)
    assert data["energy"] > 0.0
    # the wall's force on the tip balances the clamp: moment about the base ≈ 0
    scene = load_scene(scene_path("j_tip"))
    sol = solve(scene)
    assert abs(sol.moment_balance()) < 1e-6 * max(1.0, abs(sol.reactions[0].moment))
    # stress from the rest shape in the tip's own E and d
    tip = sol.s > 60.0 - J_RADIUS * J_ANGLE + 1e-9
    inner = tip & (sol.s < 60.0 - 1e-9)
    expected = 17_000.0 * 0.35 * np.abs(sol.curvature[inner] - 1 / J_RADIUS)
    np.testing.assert_allclose(sol.bending_stress_mpa[inner], expected, rtol=1e-9)


def test_insertion_carries_the_j_with_the_material():
    scene = Scene(j_wire(30.0, 30), Base((0.0, 0.0), 0.0), walls=(Wall((0.0, 1.0), 3.0),))
    run = insert(scene, [20.0, 25.0, 30.0])
    assert run.complete
    for step in run.steps:
        boundary = step.scene.wire.length - J_RADIUS * J_ANGLE
        assert np.min(np.abs(step.s - boundary)) < 1e-9


def test_second_order_convergence_on_a_graded_sectioned_layout():
    """Three sections (a J-tip, a middle section, the shaft) whose boundaries fall between multiples of L/n, so every
    layout is graded; the section boundary node and the energy converge at order 2 (successive differences quarter)."""
    wire = Wire(60.0, 10, **SHAFT, sections=(Section.arc(J_RADIUS, J_ANGLE, **TIP), Section(10.0, youngs_modulus=4e4)))
    scene = Scene(wire, Base((0.0, 0.0), 0.0), (Contact(60.0, point=(45.0, -10.0)),))
    boundary = 60.0 - J_RADIUS * J_ANGLE
    points, energies = [], []
    for n in (40, 80, 160, 320):
        sol = solve(scene.with_bars(n), branches="first")  # one branch: at 40 bars a mirror start finds another
        assert sol.success and np.ptp(np.diff(sol.s)) > 1e-3  # non-uniform bars
        points.append(sol.nodes[np.argmin(np.abs(sol.s - boundary))])
        energies.append(sol.energy)
    for values in (np.array(points), np.array(energies)):
        steps = np.linalg.norm(np.diff(values, axis=0).reshape(3, -1), axis=1)
        order = np.log2(steps[:-1] / steps[1:])
        assert np.all((order > 1.8) & (order < 2.2)), order


def test_the_mirrored_j_tip_scene_gives_the_mirrored_shape():
    scene = load_scene(scene_path("j_tip"))
    sol, mirror = solve(scene), solve(scene.mirrored())
    assert mirror.scene.wire.sections[0].rest_curvature == -scene.wire.sections[0].rest_curvature
    assert mirror.success and mirror.energy == pytest.approx(sol.energy, rel=1e-9)
    np.testing.assert_allclose(mirror.nodes, sol.nodes * [1.0, -1.0], atol=1e-8)


def test_the_continuum_reference_covers_a_sectioned_wire():
    """A section that changes nothing keeps the uniform reference; a soft section changes it, and the chain with a
    node at the section boundary agrees with it."""
    from guidewire.reference import continuum_reference, node_errors

    scene = paper_scenes()["table1_pi_4"]
    plain = continuum_reference(scene)[0]
    same = continuum_reference(scene.with_wire(sections=(Section(30.0),)))[0]
    assert same.energy == plain.energy
    soft = scene.with_wire(sections=(Section(20.0, youngs_modulus=1000.0),))
    reference, why = continuum_reference(soft)
    assert why == "" and reference.energy < 0.9 * plain.energy  # a softer stretch stores less energy
    sol = solve(soft)
    assert sol.energy == pytest.approx(reference.energy, rel=1e-3)
    assert node_errors(sol, reference).mean() < 0.02


def test_the_reference_cantilever_with_two_sections_matches_piecewise_cubic_beam_theory():
    """The continuum reference (tip clamped at beam theory's tip pose) against EI(x) v'' = F (L − x): the deflection
    to O(tip³), the tip force, and a vanishing tip moment (the beam's tip is free to rotate)."""
    from guidewire.reference import continuum_reference

    length, boundary, tip = 100.0, 70.0, 0.05
    wire = Wire(length, 100, **SHAFT, sections=(Section(length - boundary, **TIP),))
    ei_shaft, ei_tip = wire.properties_at([0.0, length]).bending_stiffness
    force, tip_x = _cantilever(length, boundary, ei_shaft, ei_tip, tip)
    h = 1e-4
    slope = (_beam_deflection(length, length, boundary, ei_shaft, ei_tip, force)
             - _beam_deflection(length - h, length, boundary, ei_shaft, ei_tip, force)) / h
    reference, why = continuum_reference(Scene(wire, Base((0.0, 0.0), 0.0),
                                               (Contact(length, point=(tip_x, tip), angle=math.atan(slope)),)))
    assert why == ""
    s = np.linspace(0.0, length, 401)
    expected = _beam_deflection(s, length, boundary, ei_shaft, ei_tip, force)
    assert np.max(np.abs(reference.position(s)[:, 1] - expected)) < 1e-3 * tip
    tip_reaction = reference.shapes[0].reactions[1]
    assert tip_reaction.force[1] == pytest.approx(force, rel=1e-3)  # as the chain's reaction
    assert abs(tip_reaction.moment) < 1e-3 * force * length  # the base carries F·L, the tip nothing


def _mean_error_ratios(scene, bars):
    """Mean node error (the paper's Eq. 25) against the sectioned continuum reference at each ``bars``."""
    from guidewire.reference import continuum_reference, node_errors

    reference, why = continuum_reference(scene)
    assert why == ""
    errors = []
    for n in bars:
        sol = solve(scene.with_bars(n))
        assert sol.success and np.ptp(np.diff(sol.s)) > 1e-3  # graded: non-uniform bars
        errors.append(node_errors(sol, reference).mean())
    errors = np.array(errors)
    return errors[:-1] / errors[1:], np.polyfit(np.log(bars), np.log(errors), 1)[0]


def test_the_j_tip_scene_converges_at_order_two_to_the_sectioned_reference():
    """The J-tip pressed by its wall (guidewire/scenes/j_tip.toml; measured ratios 4.22, 3.90, 4.07)."""
    ratios, slope = _mean_error_ratios(load_scene(scene_path("j_tip")), [15, 30, 60, 120])
    assert np.all((ratios > 3.5) & (ratios < 4.5)), ratios
    assert -2.1 < slope < -1.9


def test_a_j_tipped_three_section_wire_between_two_contact_poses_converges_at_order_two():
    """Section boundaries (25.3 is a contact, 34.8 and 44.8 mm section ends) and contacts off the uniform grid, the J
    tail free beyond the last contact (measured ratios 4.04, 3.53, 4.19; fitted order 1.97)."""
    wire = Wire(60.0, 10, **SHAFT, sections=(Section.arc(J_RADIUS, J_ANGLE, **TIP), Section(10.0, youngs_modulus=4e4)))
    scene = Scene(wire, Base((0.0, 0.0), 0.0), (Contact(25.3, point=(25.0, -0.5), angle=-0.05),
                                                Contact(52.0, point=(50.5, 2.5), angle=0.6)))
    ratios, slope = _mean_error_ratios(scene, [20, 40, 80, 160])
    assert np.all((ratios > 3.3) & (ratios < 4.7)), ratios
    assert -2.1 < slope < -1.9


def test_entrance_force_is_de_dl_for_the_j_tip_pushed_in_with_its_sections():
    """Inserting further adds shaft at the base while the J moves with the tip: dE/dL from finite differences of
    solves (the sections anchored at the tip) equals the entrance force from the base reaction."""
    scene = load_scene(scene_path("j_tip")).with_bars(240)
    h = 0.05
    low, high = (solve(scene.with_wire(length=60.0 + d)).energy for d in (-h, h))
    assert solve(scene).entrance_force() == pytest.approx((high - low) / (2 * h), rel=1e-4)


def test_b2_bounds_the_bend_away_from_the_rest_shape():
    """A J turns 1/12.1 rad per mm at rest; b₂ = 0.01 rad per 1 mm joint still lets the free J rest in its J (b₂
    bounds Δθ − Δθ⁰), and a wall that flattens it keeps every joint's bend within b₂."""
    wire = j_wire()
    wire = Wire(wire.length, wire.bars, **SHAFT, max_relative_angle=0.01, sections=wire.sections)
    free = solve(Scene(wire, Base((0.0, 0.0), 0.0)))
    assert free.success and free.energy < 1e-20
    assert np.max(free.relative_angles) > 0.08  # the J's own turn per joint, far above b₂
    pressed = solve(Scene(wire, Base((0.0, 0.0), 0.0), walls=(Wall((0.0, 1.0), 7.0),)))
    assert pressed.success and pressed.nodes[:, 1].max() <= 7.0 + 1e-7
    assert np.max(pressed.paper_stress_measure) <= 0.01 + 1e-7  # |Δθ − Δθ⁰| per node
