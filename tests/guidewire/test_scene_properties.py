"""Property-based tests on random feasible scenes (hypothesis; profiles in tests/conftest.py).

A scene is generated from a random smooth bar chain: its tangent angle is ``θ(u) = θ₀ + c₀u + c₁ sin πu + c₂ sin 2πu +
c₃ (1 − cos πu)`` (``u = s/L``, turning rate ``|dθ/du|`` at most :data:`MAX_TURNING_RATE` rad over the wire), sampled at
the bar midpoints. Two to six contacts sit on its nodes (position and tangent taken from the chain, some with the
position only), optionally a wall the chain does not cross, optionally a b₂ the chain satisfies. The chain itself is
then a feasible point, so the solver's minimum cannot have a higher energy.

Contacts are at least :data:`MIN_GAP` of the wire apart: closer contacts on a random curve make the bar chain's
energy landscape hold several nearby local minima, and a local method (ours, like SLSQP or IPOPT) may then stop at one
above the generating chain. Measured with this generator and the default start (800 random scenes each): contacts
≥ 0.15 L apart, 4 end on such a local minimum (0.5 %); ≥ 0.10 L apart, 6 (0.01–136 % above the chain's energy). The
ci profile's examples pass; a nightly run may report such a scene: a local-minimum finding, not a false success.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from guidewire import Base, Contact, Scene, Wall, Wire, solve
from guidewire.formulation import formulate

MAX_TURNING_RATE = 4.0
"""Largest ``|dθ/du|`` of the generating curve (rad per wire length)."""

MIN_GAP = 0.15
"""Smallest distance between contacts (and from the base to the first), as a fraction of the wire length."""

finite = {"allow_nan": False, "allow_infinity": False}

EXAMPLES = 3 * settings.default.max_examples
"""Examples per test: 60 with the ci profile (about 5 s), 1500 with nightly."""


@st.composite
def chain_scenes(draw):
    """(scene, bar angles of the generating chain)."""
    n = draw(st.integers(20, 60), label="bars")
    length = draw(st.floats(40.0, 200.0, **finite), label="length")
    scheme = draw(st.sampled_from(["second_order", "paper"]), label="scheme")
    c = np.array(draw(st.lists(st.floats(-2.0, 2.0, **finite), min_size=4, max_size=4), label="modes"))
    theta0 = draw(st.floats(-math.pi, math.pi, **finite), label="theta0")
    uu = np.linspace(0.0, 1.0, 201)
    rate = np.abs(c[0] + np.pi * c[1] * np.cos(np.pi * uu) + 2 * np.pi * c[2] * np.cos(2 * np.pi * uu)
                  + np.pi * c[3] * np.sin(np.pi * uu)).max()
    c = c * min(1.0, MAX_TURNING_RATE / max(rate, 1e-12))

    def theta(u):
        return (theta0 + c[0] * u + c[1] * np.sin(np.pi * u) + c[2] * np.sin(2 * np.pi * u)
                + c[3] * (1 - np.cos(np.pi * u)))

    phi = theta((np.arange(n) + 0.5) / n)
    base = np.array(draw(st.lists(st.floats(-50.0, 50.0, **finite), min_size=2, max_size=2), label="base"))
    nodes = np.vstack([base, base + np.cumsum(length / n * np.column_stack([np.cos(phi), np.sin(phi)]), axis=0)])

    gap = max(3, math.ceil(MIN_GAP * n))
    m = draw(st.integers(2, 6), label="contacts")
    ks = sorted(draw(st.sets(st.integers(gap, n), min_size=1, max_size=m), label="contact nodes"))
    ks = [k for i, k in enumerate(ks) if i == 0 or k - ks[i - 1] >= gap]
    if np.ptp(phi) > 0.0:  # a chain straight to rounding is kept: its stretches are exactly taut, a clean case
        # a stretch between two positions with a relative slack below 1e-10 leaves a feasible set that is nearly a
        # single point, where no constraint qualification holds (multipliers need not exist): not a fair demand
        held = [0, *ks]
        chords = np.hypot(*(nodes[held[1:]] - nodes[held[:-1]]).T)
        spans = np.diff(held) * (length / n)
        assume(bool(np.all(1.0 - chords / spans >= 1e-10)))
    contacts = []
    for k in ks:
        with_angle = draw(st.booleans(), label=f"angle at node {k}")
        angle = float(phi[k - 1]) if scheme == "paper" else float(theta(k / n))  # paper: φ_k = θ* is a row
        contacts.append(Contact(k * (length / n), (float(nodes[k, 0]), float(nodes[k, 1])),
                                angle if with_angle else None))
    walls = ()
    if draw(st.booleans(), label="wall"):
        psi = draw(st.floats(0.0, 2 * math.pi, **finite), label="wall direction")
        margin = draw(st.floats(0.0, 0.2, **finite), label="wall margin")
        normal = (math.cos(psi), math.sin(psi))
        walls = (Wall(normal, float((nodes @ np.array(normal)).max() + margin * length)),)
    b2 = None
    if draw(st.booleans(), label="b2"):
        b2 = float(max(np.abs(np.diff(phi)).max(), 0.01) * draw(st.floats(1.2, 3.0, **finite), label="b2 factor"))
    wire = Wire(length, n, scheme=scheme, max_relative_angle=b2)
    scene = Scene(wire, Base((float(base[0]), float(base[1])), float(theta(0.0))), tuple(contacts), walls)
    return scene, phi


@settings(max_examples=EXAMPLES)
@given(chain_scenes())
def test_random_feasible_scene_is_solved_at_or_below_the_generating_energy(case):
    scene, phi = case
    form = formulate(scene, initial_angles=phi)
    assert form.violations(phi).max(initial=0.0) <= 1e-9 * scene.wire.length  # the generator is feasible
    generating_energy = form.fun(phi)
    sol = solve(scene)
    assert sol.success, sol.message
    kkt = sol.result.kkt
    assert max(kkt["stationarity"], kkt["complementarity"]) <= 1e-6 and sol.max_violation <= 1e-7 * scene.wire.length
    assert sol.energy <= generating_energy * (1.0 + 1e-7) + 1e-12


@settings(max_examples=EXAMPLES)
@given(chain_scenes(), st.floats(-math.pi, math.pi, **finite), st.tuples(st.floats(-30, 30), st.floats(-30, 30)))
def test_mirrored_and_rotated_scenes_give_mirrored_and_rotated_shapes(case, angle, center):
    scene, _ = case
    sol = solve(scene)
    assert sol.success, sol.message
    tol = 1e-6 * scene.wire.length

    mirrored = solve(scene.mirrored())
    assert mirrored.success, mirrored.message
    np.testing.assert_allclose(mirrored.nodes, sol.nodes * [1.0, -1.0], atol=tol)
    np.testing.assert_allclose(mirrored.bar_angles, -sol.bar_angles, atol=1e-6)
    energy_tol = 1e-9 * scene.wire.bending_stiffness / scene.wire.length
    assert mirrored.energy == pytest.approx(sol.energy, rel=1e-7, abs=energy_tol)

    rotated = solve(scene.rotated(angle, center))
    assert rotated.success, rotated.message
    turn = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    np.testing.assert_allclose(rotated.nodes, (sol.nodes - center) @ turn.T + center, atol=tol)
    np.testing.assert_allclose(rotated.bar_angles, sol.bar_angles + angle, atol=1e-6)
    assert rotated.energy == pytest.approx(sol.energy, rel=1e-7, abs=energy_tol)


@pytest.mark.xfail(strict=True, reason=(
    "found by hypothesis (nightly): two position-only contacts on a gently arched chain; the default start bends the "
    "wire into an S and Newton-SQP converges to that local minimum (energy 8.36 N·mm, a strict minimum: success is "
    "right) while the generating chain, feasible, has 6.09 and another minimum 5.93 — a local method's limit"))
def test_known_local_minimum_above_the_generating_chain():
    scene = Scene(Wire(40.0, 20), Base((0.0, 0.0), 0.0),
                  (Contact(28.0, (25.419008962750265, 5.066330248772704)),
                   Contact(40.0, (36.04866403108162, -2.220446049250313e-16))))
    sol = solve(scene)
    assert sol.success, sol.message
    assert sol.energy <= 6.0946257379933
