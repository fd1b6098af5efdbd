"""Physics of the 3-D rod: pure twist, a free J turned at the clamp, convergence, and balance of forces and moments."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_bvp
from scipy.spatial.transform import Rotation

from guidewire import Section, Wire
from guidewire.rod.material import twist_stiffness
from guidewire.solve3d import Base3D, Contact3D, Scene3D, solve3d

PAPER_WIRE = {"youngs_modulus": 3560.0, "diameter": 0.78, "moment_of_inertia": 0.01816}


def _random_frame(seed: int) -> tuple[np.ndarray, np.ndarray]:
    R = Rotation.random(random_state=seed).as_matrix()
    return R[:, 0], R[:, 1]  # a tangent and a normal across it


@pytest.mark.parametrize("bars", [1, 5, 40])
@pytest.mark.parametrize("psi", [0.3, -1.7])
def test_straight_wire_twisted_by_psi_stores_gj_psi2_over_2l(bars, psi):
    """Clamped at both ends, the far clamp's roll 0 and the near one's ``ψ``: the twist is uniform (the joints are
    springs in series, dual lengths summing to ``L``), ``E = GJ ψ² / (2L)`` exactly, and the wire stays straight."""
    tangent, normal = _random_frame(bars)
    wire = Wire(length=50.0, bars=bars, **PAPER_WIRE)
    base = Base3D((1.0, 2.0, 3.0), tuple(tangent), tuple(normal), rotation=psi)
    tip = Contact3D(50.0, tangent=tuple(tangent), normal=tuple(normal))
    sol = solve3d(Scene3D(wire=wire, base=base, contacts=(tip,)), tol=1e-12)
    assert sol.success, sol.message
    gj = float(twist_stiffness(wire, np.array([1.0]))[0])
    assert sol.twist_energy == pytest.approx(gj * psi**2 / (2 * 50.0), rel=1e-10)
    assert sol.bending_energy < 1e-20
    straight = np.asarray(base.point) + np.outer(np.linspace(0.0, 50.0, bars + 1), tangent)
    assert np.max(np.abs(sol.nodes - straight)) < 1e-9
    assert sol.entrance_torque == pytest.approx(gj * psi / 50.0, rel=1e-8)  # the torque that holds the twist


def _j_wire(bars: int, length: float = 30.0) -> Wire:
    """stEVE's J: tip arc of radius 12.1 mm over 0.4π, E 17 GPa / OD 0.7 mm on a shaft of E 80 GPa / OD 0.89 mm."""
    return Wire(length=length, bars=bars, youngs_modulus=80000.0, diameter=0.89,
                sections=(Section.arc(12.1, 0.4 * math.pi, youngs_modulus=17000.0, diameter=0.7),))


def _axis_rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    return Rotation.from_rotvec(angle * axis).as_matrix()


def test_free_j_tip_turned_at_the_clamp_turns_rigidly():
    """No load: the J rests in its rest shape at every clamp rotation ``ψ`` (zero energy), rotated rigidly about the
    clamp's tangent by ``ψ``, and the tip's roll is ``ψ``. Each rotation is warm-started from the previous answer's
    frames (the step an insertion takes), so the solver must turn every bar."""
    tangent, normal = _random_frame(3)
    base = Base3D((0.0, 0.0, 0.0), tuple(tangent), tuple(normal))
    scene = Scene3D(wire=_j_wire(40), base=base)
    first = solve3d(scene, tol=1e-10)
    assert first.success and first.energy < 1e-16
    previous = first
    for psi in (0.7, 2.0, -2.5, 3.0):
        sol = solve3d(scene.with_rotation(psi), initial_frames=previous.quaternions, tol=1e-10)
        assert sol.success, sol.message
        assert sol.energy < 1e-14
        expected = first.nodes @ _axis_rotation(tangent, psi).T
        assert np.max(np.abs(sol.nodes - expected)) < 1e-7
        assert math.remainder(sol.tip_roll - psi, 2 * math.pi) == pytest.approx(0.0, abs=1e-8)
        previous = sol


def _cantilever_reference(length: float, ei: float, force: np.ndarray) -> np.ndarray:
    """Tip of the planar elastica clamped along +x with a dead tip load ``force`` (N, in-plane components):
    ``x' = cos θ, y' = sin θ, EI θ' = m, m' = F_x sin θ − F_y cos θ``, ``θ(0) = 0``, ``m(L) = 0``."""
    fx, fy = force

    def rhs(s, u):
        return np.vstack((np.cos(u[2]), np.sin(u[2]), u[3] / ei, fx * np.sin(u[2]) - fy * np.cos(u[2])))

    def bc(a, b):
        return np.array([a[0], a[1], a[2], b[3]])

    s = np.linspace(0.0, length, 401)
    guess = np.vstack((s, np.zeros_like(s), np.zeros_like(s), np.zeros_like(s)))
    out = solve_bvp(rhs, bc, s, guess, tol=1e-11, max_nodes=200000)
    assert out.success
    return out.sol(length)[:2]


def test_cantilever_under_an_oblique_tip_load_converges_at_order_two():
    """A clamped wire under a dead tip load in a random 3-D orientation against the continuum elastica (the answer
    is planar in the plane of the clamp's tangent and the load): the tip error falls by 4 per halving of the bars."""
    tangent, across = _random_frame(11)
    force = 0.02 * across - 0.005 * tangent  # N: F L²/EI ≈ 3, a large deflection
    wire_args = dict(length=100.0, **PAPER_WIRE)
    ei = PAPER_WIRE["youngs_modulus"] * PAPER_WIRE["moment_of_inertia"]
    ref = _cantilever_reference(100.0, ei, np.array([force @ tangent, force @ across]))
    errors = []
    for bars in (10, 20, 40):
        scene = Scene3D(wire=Wire(bars=bars, **wire_args), base=Base3D((0, 0, 0), tuple(tangent)),
                        tip_force=tuple(force))
        sol = solve3d(scene, tol=1e-12)
        assert sol.success, sol.message
        tip = sol.nodes[-1]
        assert abs(tip @ np.cross(tangent, across)) < 1e-9  # planar
        errors.append(np.hypot(tip @ tangent - ref[0], tip @ across - ref[1]))
        fb, mb = sol.balance()
        assert fb < 1e-9 and mb < 1e-7
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all((orders > 1.9) & (orders < 2.1)), orders


def test_j_wire_with_twist_and_bending_converges_at_order_two():
    """Genuinely 3-D: a J-tipped wire rolled by 1 rad at the clamp, its tip pulled by a load out of the J's plane,
    so bending and twist couple along the whole wire. Against twice-finer chains the tip moves by ``~C h²``: the
    successive differences fall by 4 per halving. (The wire is twice its J's arc, so the section boundary is a node
    of every uniform chain and each chain halves the last one's bars.)"""
    tangent, normal = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    tips, rolls = [], []
    for bars in (20, 40, 80):
        base = Base3D((0, 0, 0), tuple(tangent), tuple(normal), rotation=1.0)
        scene = Scene3D(wire=_j_wire(bars, 2 * 12.1 * 0.4 * math.pi), base=base,
                        tip_force=(0.0, 0.05, -0.02))
        sol = solve3d(scene, tol=1e-12)
        assert sol.success, sol.message
        assert sol.twist_energy > 1e-3 * sol.bending_energy
        tips.append(sol.nodes[-1])
        rolls.append(sol.tip_roll)
    d1, d2 = np.linalg.norm(tips[0] - tips[1]), np.linalg.norm(tips[1] - tips[2])
    assert 1.9 < math.log2(d1 / d2) < 2.1
    r1, r2 = abs(rolls[0] - rolls[1]), abs(rolls[1] - rolls[2])
    assert 1.8 < math.log2(r1 / r2) < 2.2


@pytest.mark.parametrize(("refinement", "bars"), [(2.0, (30, 60, 120)), (3.0, (20, 40, 80))])
def test_a_refined_j_tip_still_converges_at_order_two(refinement, bars):
    """The twisted, loaded J wire of the test above with its tip's bars ``refinement`` times finer than the shaft's
    (:attr:`guidewire.Section.refinement`): the graded chains, each halving the last one's bars in both pieces (the
    bar counts split exactly, 1 : refinement), still move the tip by ``~C h²``, and the layout is the one asked."""
    tangent, normal = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    arc = 12.1 * 0.4 * math.pi
    tips = []
    for n in bars:
        wire = _j_wire(n, 2 * arc)
        wire = replace(wire, sections=(replace(wire.sections[0], refinement=refinement),))
        base = Base3D((0, 0, 0), tuple(tangent), tuple(normal), rotation=1.0)
        sol = solve3d(Scene3D(wire=wire, base=base, tip_force=(0.0, 0.05, -0.02)), tol=1e-12)
        assert sol.success, sol.message
        shaft, tip = n // (1 + int(refinement)), n - n // (1 + int(refinement))
        np.testing.assert_allclose(sol.lengths, np.repeat([arc / shaft, arc / tip], [shaft, tip]), rtol=1e-12)
        tips.append(sol.nodes[-1])
    d1, d2 = np.linalg.norm(tips[0] - tips[1]), np.linalg.norm(tips[1] - tips[2])
    assert 1.9 < math.log2(d1 / d2) < 2.1


def test_forces_and_moments_balance_in_3d():
    """Clamp, a contact point out of the J's plane, a tip held in direction and roll, and a tip load: the clamp's
    force and moment, the contacts' forces and moments and the load sum to zero (to the solver's tolerance times
    the force scale)."""
    scene = Scene3D(
        wire=_j_wire(40, 40.0),
        base=Base3D((0, 0, 0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), rotation=0.4),
        contacts=(Contact3D(20.0, point=(3.0, -2.0, 19.0)),
                  Contact3D(40.0, point=(8.0, 4.0, 33.0), tangent=(0.6, 0.0, 0.8), normal=(0.0, 1.0, 0.0))),
        tip_force=(0.0, 0.3, 0.0))
    sol = solve3d(scene, tol=1e-10)
    assert sol.success, sol.message
    scale = max(f.magnitude for f in sol.forces)
    assert scale > 0.01
    f, m = sol.balance()
    assert f < 1e-8 * scale and m < 1e-8 * scale * 40.0
