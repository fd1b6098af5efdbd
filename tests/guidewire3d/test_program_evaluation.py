"""The 3-D program's evaluations at a line search's trial points: derivatives taken ahead only while trial points
are accepted, and the same values whichever way a point is evaluated."""

from __future__ import annotations

import numpy as np

from guidewire import Section, Wire
from guidewire.solve3d import Scene3D
from guidewire.solve3d.program import Program
from guidewire.solve3d.solve import _first_frames
from guidewire.vessel3d.shapes import helix


def _program() -> Program:
    wire = Wire(length=20.0, bars=20, youngs_modulus=17000.0, diameter=0.7, scheme="second_order",
                sections=(Section(length=10.0, rest_curvature=1.0 / 12.1),))
    scene = Scene3D.in_vessel(wire, helix(), shear_modulus=17000.0 / 2.66)
    return Program.build(scene, _first_frames(scene, None, None))


def _points(program: Program, count: int) -> list[np.ndarray]:
    rng = np.random.default_rng(3)
    z0 = program.start()
    return [z0 + 1e-2 * rng.standard_normal(z0.size) for _ in range(count)]


def _evaluated_in_full(program: Program, z: np.ndarray) -> bool:
    return program._cache.get("key") == np.asarray(z, dtype=float).tobytes()


def test_trial_points_get_derivatives_ahead_only_after_an_accepted_one():
    """The start and a trial point after one whose derivatives were asked for are evaluated in full; a trial point
    after a rejected one (values only asked for) by its values alone."""
    program = _program()
    closure = program.constraints()[0]
    z0, z1, z2, z3 = _points(program, 4)
    program.fun(z0), closure["fun"](z0)
    assert _evaluated_in_full(program, z0)
    program.jac(z0), closure["jac"](z0)
    program.fun(z1), closure["fun"](z1)
    assert _evaluated_in_full(program, z1)
    assert program._cache.get("tangent_key") == z1.tobytes()
    program.fun(z2), closure["fun"](z2)  # (z1 rejected: its derivatives never asked for)
    assert not _evaluated_in_full(program, z2)
    assert program._cache.get("tangent_key") != z2.tobytes()
    program.jac(z2)  # (z2 accepted)
    program.fun(z3)
    assert _evaluated_in_full(program, z3)


def test_values_are_the_same_evaluated_in_full_or_alone():
    """Objective and closure rows at a point bit for bit the same from a full evaluation and from the values
    alone."""
    full, alone = _program(), _program()
    z0, z1, z2 = _points(full, 3)
    for program in (full, alone):
        program.fun(z0), program.jac(z0)
    alone.fun(z1)  # (rejected: alone now evaluates trial points by their values)
    full_closure, alone_closure = full.constraints()[0], alone.constraints()[0]
    assert _evaluated_in_full(full, z2) is False
    f_full, c_full = full.fun(z2), full_closure["fun"](z2)
    f_alone, c_alone = alone.fun(z2), alone_closure["fun"](z2)
    assert _evaluated_in_full(full, z2) and not _evaluated_in_full(alone, z2)
    assert f_full == f_alone
    assert np.array_equal(c_full, c_alone)


def test_joint_twists_are_the_jet_strains_twists_bit_for_bit():
    """The answer's joint twists from the values alone are :func:`joint_strain`'s twists, bit for bit, on frames
    turned far from one another (both branches of ``atan2``, twists of either sign)."""
    from guidewire.rod import quaternion as quat
    from guidewire.rod.jet import Jet
    from guidewire.rod.strain import joint_strain
    from guidewire.solve3d.solve import joint_twists

    rng = np.random.default_rng(5)
    q = rng.standard_normal((50, 4))
    base = rng.standard_normal(4)
    left = np.vstack((base, q[:-1]))
    jets = quat.relative([Jet.constant(left[:, c], 1) for c in range(4)], [Jet.constant(q[:, c], 1) for c in range(4)])
    expected = joint_strain(jets, "mid")[2].value
    assert np.any(expected > 0.0) and np.any(expected < 0.0)
    assert np.array_equal(joint_twists(base, q), expected)


def test_tangents_from_kept_chart_forms_are_the_same_numbers():
    """:func:`kinematics.tangents` with the charts' forms kept (:func:`kinematics.chart_forms`) gives its values and
    derivatives bit for bit as computing them afresh; the program's closure rows read them so."""
    from guidewire.rod import kinematics

    program = _program()
    rng = np.random.default_rng(7)
    omega = 0.3 * rng.standard_normal((program.n, 3))
    fresh = kinematics.tangents(program.q0, program.basis, omega)
    kept = kinematics.tangents(program.q0, program.basis, omega, forms=kinematics.chart_forms(program.basis))
    assert np.any(fresh[2] != 0.0)
    for a, b in zip(fresh, kept, strict=True):
        assert np.array_equal(a, b)
    z = program.start().reshape(program.n, program.width).copy()
    z[:, :3] = omega
    assert all(np.array_equal(a, b) for a, b in zip(program.tangents(z.ravel()), fresh, strict=True))
