"""Physics and numerical analysis of the solved wire: exact answers, symmetry, walls, convergence order against the
continuum elastica, the lowest-energy branch, support reactions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from guidewire import Base, Contact, Scene, Wire, paper_scenes, solve
from guidewire.reference import continuum_reference, nearest_shape, reference_shape

SCENES = paper_scenes()
FEASIBLE = [name for name in SCENES if name != "table5"]


def _reference(scene):
    return reference_shape(
        scene.base.point, scene.base.angle, scene.contacts, scene.wire.length, scene.wire.bending_stiffness, scene.walls
    )


@pytest.fixture(scope="module")
def references():
    """All equal-lowest continuum shapes per scene (mirror twins: Table 1/2 with angle 0, Fig. 6b)."""
    return {name: continuum_reference(SCENES[name])[0] for name in FEASIBLE}


@pytest.fixture(scope="module")
def solutions():
    """Every feasible paper scene, both schemes, default options (n as in the paper)."""
    schemes = ("second_order", "paper")
    return {(name, scheme): solve(SCENES[name], scheme=scheme) for name in FEASIBLE for scheme in schemes}


# ------------------------------------------------------------------------------------------------------------------
def test_straight_wire_when_nothing_bends_it():
    t = 0.3
    direction = np.array([math.cos(t), math.sin(t)])
    contacts = (Contact(40.0, tuple(40.0 * direction), t), Contact(80.0, tuple(80.0 * direction)))
    for scheme in ("second_order", "paper"):
        sol = solve(Scene(Wire(100.0, 50), Base((0.0, 0.0), t), contacts), scheme=scheme)
        assert sol.success, sol.message
        assert sol.energy == pytest.approx(0.0, abs=1e-12)
        assert np.allclose(sol.nodes, sol.s[:, None] * direction, atol=1e-9)
        assert np.allclose(sol.tangent_angles, t) and np.allclose(sol.bending_stress_mpa, 0.0, atol=1e-9)
    free = solve(Scene(Wire(100.0, 20), Base((1.0, 2.0), -0.4)))  # no contact, no wall: a straight free wire
    assert free.success and free.energy == pytest.approx(0.0, abs=1e-12)
    assert np.allclose(free.bar_angles, -0.4)


@pytest.mark.parametrize("interior", [False, True])
def test_second_order_scheme_gives_an_exact_regular_polygon_on_a_circle(interior):
    """Clamp + end pose of a regular polygon (bar l, turn δ at each joint, δ/2 at each clamp): the discrete minimum
    is that polygon exactly, its nodes on the circle of radius l / (2 sin(δ/2)); pure bending, so no contact force,
    and the clamps' moments are ∓EI·δ/l with the continuum energy EI/2 κ² L."""
    n, length, turn, ei = 20, 50.0, 1.2, 64.65
    l, delta = length / n, turn / n
    phi = (np.arange(n) + 0.5) * delta
    end = l * np.array([np.cos(phi).sum(), np.sin(phi).sum()])
    contacts = [Contact(length, tuple(end), turn)]
    if interior:  # an interior angle contact at the middle node: two half joints there
        contacts.insert(0, Contact(length / 2, angle=turn / 2))
    wire = Wire(length, n, youngs_modulus=3560.0, moment_of_inertia=ei / 3560.0)
    sol = solve(Scene(wire, Base((0.0, 0.0), 0.0), tuple(contacts)), scheme="second_order")
    assert sol.success, sol.message
    rho = l / (2.0 * math.sin(delta / 2.0))
    assert np.allclose(np.hypot(sol.nodes[:, 0], sol.nodes[:, 1] - rho), rho, atol=1e-8)
    assert np.allclose(sol.curvature, delta / l, rtol=1e-7)
    assert sol.energy == pytest.approx(0.5 * ei * (turn / length) ** 2 * length, rel=1e-9)
    base, *_, tip = sol.reactions
    assert np.allclose(tip.force, 0.0, atol=1e-7) and np.allclose(base.force, 0.0, atol=1e-7)
    assert base.moment == pytest.approx(-ei * delta / l, rel=1e-6)
    assert tip.moment == pytest.approx(ei * delta / l, rel=1e-6)


@pytest.mark.parametrize("name", ["table4", "fig6a", "table2_pi_4"])
def test_mirrored_scene_gives_the_mirrored_shape(name):
    scene = SCENES[name]
    sol, mirror = solve(scene), solve(scene.mirrored())
    assert sol.success and mirror.success
    assert np.allclose(mirror.nodes, sol.nodes * [1.0, -1.0], atol=1e-6)
    assert mirror.energy == pytest.approx(sol.energy, rel=1e-8)
    assert np.allclose(mirror.tangent_angles, -sol.tangent_angles, atol=1e-6)


@pytest.mark.parametrize("name", ["fig6a", "fig6b"])
def test_walls_are_never_violated_at_any_node(name, solutions, references):
    (wall,) = SCENES[name].walls
    for scheme in ("second_order", "paper"):
        sol = solutions[(name, scheme)]
        assert sol.success, sol.message
        assert max(wall.signed_distance(p) for p in sol.nodes) <= 1e-9
        touching = np.hypot(*sol.wall_forces.T) > 1e-6
        assert touching.any()  # the wall bends the wire ...
        assert all(abs(wall.signed_distance(p)) < 1e-7 for p in sol.nodes[touching])  # ... only where it touches
    assert solutions[(name, "second_order")].energy == pytest.approx(references[name].energy, rel=1e-3)


def test_paper_scheme_converges_at_first_order_and_the_default_at_second():
    """Table 1, θ_B = π/4: mean node error (Eq. 25) against the exact elastica for n = 25..200, log–log slope."""
    scene = SCENES["table1_pi_4"]
    ref = _reference(scene)
    bars = np.array([25, 50, 100, 200])
    slopes, errors = {}, {}
    for scheme in ("paper", "second_order"):
        err = []
        for n in bars:
            sol = solve(scene, scheme=scheme, bars=int(n))
            assert sol.success, sol.message
            err.append(np.hypot(*(sol.nodes - ref.position(sol.s)).T).mean())
        errors[scheme] = err
        slopes[scheme] = -np.polyfit(np.log(bars), np.log(err), 1)[0]
    assert 0.85 < slopes["paper"] < 1.15, slopes
    assert 1.85 < slopes["second_order"] < 2.15, slopes
    assert errors["paper"][2] == pytest.approx(0.243, abs=0.002)  # the measurement at n = 100
    assert errors["second_order"][2] == pytest.approx(0.0028, abs=0.0002)


@pytest.mark.parametrize("name", FEASIBLE)
def test_every_paper_scene_reaches_the_lowest_energy_branch(name, solutions, references):
    """The continuum reference is the lowest-energy equilibrium (it enumerates the branches); the default start
    must lead to the discrete counterpart: energy within discretisation error, shape within a fraction of a mm."""
    ref = references[name]
    second, paper = solutions[(name, "second_order")], solutions[(name, "paper")]
    assert second.success and paper.success
    assert second.energy <= ref.energy * (1 + 1e-4)
    assert second.energy == pytest.approx(ref.energy, rel=1.5e-2)  # Table 4 (1 mm bars, tight S-bend): 1.0 %
    assert paper.energy == pytest.approx(ref.energy, rel=3e-2)
    twin = nearest_shape(second, ref)  # of mirror twins with equal energy, the one the solver chose
    assert np.hypot(*(second.nodes - twin.position(second.s)).T).max() < 0.02
    assert np.hypot(*(paper.nodes - nearest_shape(paper, ref).position(paper.s)).T).max() < 1.0


@pytest.mark.parametrize("name", ["table1_zero", "table2_zero", "table4", "fig6b"])
def test_default_start_beats_other_starts(name, solutions):
    """Other starts (straight along the base, bulges, a second mode) end in equilibria no lower than the default's;
    some end higher: the branches are real (Table 1, θ_B = 0 from a straight start: 9.43 vs 7.67 N·mm)."""
    scene = SCENES[name]
    best = solutions[(name, "second_order")].energy
    u = (np.arange(scene.wire.bars) + 0.5) / scene.wire.bars
    x0 = solutions[(name, "second_order")].bar_angles
    bulge, mode2 = np.sin(math.pi * u), np.sin(2 * math.pi * u)
    starts = [np.full(u.size, scene.base.angle + 1e-3), x0 + bulge, x0 - bulge, x0 + 2 * bulge, x0 + mode2]
    energies = []
    for start in starts:
        other = solve(scene, initial_angles=start, qp_solver="daqp")
        if other.success:
            energies.append(other.energy)
    assert len(energies) >= 3
    assert min(energies) >= best - 1e-7
    if name in ("table1_zero", "table2_zero"):
        assert energies[0] > best + 1.0  # the straight start lands on a higher branch


@pytest.mark.parametrize("name", ["table1_pi_4", "table2_minus_pi_4", "table4", "fig6a", "fig6b"])
def test_support_reactions_match_the_continuum_and_balance(name, solutions, references):
    sol = solutions[(name, "second_order")]
    ref = nearest_shape(sol, references[name])
    assert abs(sol.moment_balance()) < 1e-6
    ref_clamps = [r for r in ref.reactions if r.kind == "clamp"]
    scale_f = max(np.abs(r.force).max() for r in ref.reactions)
    scale_m = max(abs(r.moment) for r in ref.reactions)
    for mine, theirs in zip(sol.reactions, ref_clamps, strict=True):
        assert theirs.s == pytest.approx(mine.s)
        assert np.allclose(mine.force, theirs.force, atol=0.02 * scale_f), (mine, theirs)  # O(h²): 1.3 % on Table 4
        assert mine.moment == pytest.approx(theirs.moment, abs=0.02 * scale_m)
    walls = [r for r in ref.reactions if r.kind == "wall"]
    if walls:
        assert np.allclose(sol.wall_forces.sum(axis=0), walls[0].force, atol=0.02 * scale_f)
    total = sum(r.force for r in sol.reactions if r.force is not None) + sol.wall_forces.sum(axis=0)
    assert np.allclose(total, 0.0, atol=1e-12)


def test_base_force_from_balance_equals_the_multiplier_of_the_reversed_wire(solutions):
    """Solve Table 1 (θ_B = π/4) from B back to A: A's force is then a multiplier; it must equal the base force
    that the forward solve gets from global balance."""
    forward = solutions[("table1_pi_4", "second_order")]
    scene = SCENES["table1_pi_4"]
    reverse = Scene(
        scene.wire, Base((60.0, 40.0), math.pi / 4 + math.pi, name="B"), (Contact(100.0, (0.0, 0.0), math.pi),)
    )
    back = solve(reverse)
    assert back.success
    assert np.allclose(back.nodes[::-1], forward.nodes, atol=1e-6)
    assert np.allclose(back.reactions[1].force, forward.reactions[0].force, rtol=1e-5, atol=1e-9)
    assert back.reactions[1].moment == pytest.approx(forward.reactions[0].moment, rel=1e-5)


def test_free_end_beyond_the_last_contact_stays_straight(solutions):
    sol = solutions[("table4", "second_order")]
    last = sol.reactions[-1].node  # P2 at s = 71
    assert last == 71
    assert np.allclose(sol.bar_angles[last:], sol.bar_angles[last], atol=1e-9)
    assert np.allclose(sol.relative_angles[last + 1 :], 0.0, atol=1e-9)
