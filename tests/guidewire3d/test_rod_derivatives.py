"""Finite-difference checks of every analytic derivative of the framed rod: strains, energy, tangents.

Central differences with step ``h`` have truncation error ``~h² |f'''|`` and rounding error ``~ε |f| / h``; with
``h = 1e-5`` on functions of unit scale both are below 1e-8, so the tolerances below (1e-6 relative to the largest
entry) hold with two orders of margin and still catch any wrong term (which would be of the size of the entry).
"""

from __future__ import annotations

import numpy as np
import pytest

from guidewire.rod import kinematics
from guidewire.rod import quaternion as quat
from guidewire.rod.strain_energy import StrainEnergy

H = 1e-5
RTOL = 1e-6


def _random_rod(n: int, seed: int, rest: bool = True, tangent_nodes: tuple[int, ...] = (), held: bool = False):
    rng = np.random.default_rng(seed)
    lengths = rng.uniform(0.5, 2.0, n)
    ei = rng.uniform(1.0, 3.0, n)
    gj = rng.uniform(0.5, 2.0, n)
    kappa0 = rng.uniform(-0.5, 0.5, n) if rest else None
    base = quat.normalised(rng.normal(size=4))[0]
    tangents = quat.normalised(rng.normal(size=(len(tangent_nodes), 4)))[:, 1:]
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    normals = rng.normal(size=tangents.shape) if held else None
    energy = StrainEnergy.build(lengths, ei, gj, base, kappa0, np.array(tangent_nodes, dtype=int), tangents, normals)
    # frames: a random walk of moderate relative rotations from the clamp
    steps = quat.rotation_about(quat.normalised(rng.normal(size=(n, 4)))[:, 1:] / np.linalg.norm(
        quat.normalised(rng.normal(size=(n, 4)))[:, 1:], axis=1, keepdims=True), rng.uniform(0.0, 0.8, n))
    q = np.empty((n, 4))
    prev = base
    for k in range(n):
        prev = np.array(quat.multiply(prev, steps[k]))
        q[k] = prev
    q0 = quat.continuous(q, base)
    basis = quat.chart_basis(q0)
    omega = rng.normal(scale=0.2, size=(n, 3))
    return energy, q0, basis, omega


def _dense_hessian(parts, n):
    H3 = np.zeros((3 * n, 3 * n))
    for k in range(n):
        H3[3 * k:3 * k + 3, 3 * k:3 * k + 3] = parts.diagonal[k]
    for k in range(n - 1):
        H3[3 * k:3 * k + 3, 3 * k + 3:3 * k + 6] = parts.off_diagonal[k]
        H3[3 * k + 3:3 * k + 6, 3 * k:3 * k + 3] = parts.off_diagonal[k].T
    return H3


@pytest.mark.parametrize("n, seed, nodes, held", [(1, 0, (), False), (4, 1, (), False), (9, 2, (3,), False),
                                                  (12, 3, (5, 12), False), (7, 4, (7,), False), (8, 5, (4, 8), True),
                                                  (1, 6, (1,), True)])
def test_energy_gradient_and_hessian_match_differences(n, seed, nodes, held):
    energy, q0, basis, omega = _random_rod(n, seed, tangent_nodes=nodes, held=held)
    assert (energy.half_twist > 0).any() == held
    parts = energy.evaluate(q0, basis, omega)
    g = parts.gradient.ravel()
    Hm = _dense_hessian(parts, n)
    assert np.allclose(Hm, Hm.T, atol=1e-12 * np.abs(Hm).max())
    fd_g = np.zeros(3 * n)
    fd_H = np.zeros((3 * n, 3 * n))
    for i in range(3 * n):
        e = np.zeros(3 * n)
        e[i] = H
        up = energy.evaluate(q0, basis, omega + e.reshape(n, 3))
        dn = energy.evaluate(q0, basis, omega - e.reshape(n, 3))
        fd_g[i] = (up.total - dn.total) / (2 * H)
        fd_H[:, i] = (up.gradient.ravel() - dn.gradient.ravel()) / (2 * H)
    assert np.max(np.abs(fd_g - g)) <= RTOL * max(1.0, np.abs(g).max())
    assert np.max(np.abs(fd_H - Hm)) <= RTOL * max(1.0, np.abs(Hm).max())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_tangent_derivatives_match_differences(seed):
    _, q0, basis, omega = _random_rod(6, seed)
    t, dt, ddt = kinematics.tangents(q0, basis, omega)
    assert np.allclose(np.linalg.norm(t, axis=1), 1.0, atol=1e-14)
    for i in range(3):
        e = np.zeros((6, 3))
        e[:, i] = H
        tp, dtp, _ = kinematics.tangents(q0, basis, omega + e)
        tm, dtm, _ = kinematics.tangents(q0, basis, omega - e)
        assert np.max(np.abs((tp - tm) / (2 * H) - dt[:, :, i])) < RTOL
        assert np.max(np.abs((dtp - dtm) / (2 * H) - ddt[:, :, :, i])) < RTOL


def test_energy_is_invariant_under_a_rigid_rotation_of_every_frame():
    energy, q0, basis, omega = _random_rod(8, 5)
    q = q0 + np.einsum("kij,kj->ki", basis, omega)
    rng = np.random.default_rng(11)
    spin = quat.normalised(rng.normal(size=4))[0]
    turned = np.stack(quat.multiply(spin, q.T), axis=1)
    base = np.array(quat.multiply(spin, energy.base))
    rotated = StrainEnergy(**{**energy.__dict__, "base": base})
    if energy.half_bar.size == 0:
        assert np.allclose(rotated.value(turned), energy.value(q), rtol=1e-12)


@pytest.mark.parametrize("seed", [0, 1])
def test_relative_of_affine_jets_is_the_jet_product(seed):
    """``relative_affine`` (the bilinear form at once) gives the jet arithmetic's value, gradient and Hessian of
    ``q̄_a ⊗ q_b`` to rounding, for affine jets in the joint's six variables and for a constant second frame."""
    from guidewire.rod.jet import Jet

    rng = np.random.default_rng(seed)
    m = 50
    qa = [Jet.affine(rng.normal(size=m), np.concatenate((rng.normal(size=(m, 3)), np.zeros((m, 3))), axis=1))
          for _ in range(4)]
    qb = [Jet.affine(rng.normal(size=m), np.concatenate((np.zeros((m, 3)), rng.normal(size=(m, 3))), axis=1))
          for _ in range(4)]
    star = [Jet.constant(rng.normal(size=m), 6) for _ in range(4)]
    for a, b in ((qa, qb), (qa, star), (star, qb)):
        for fast, slow in zip(quat.relative_affine(a, b), quat.relative(a, b), strict=True):
            for x, y in ((fast.value, slow.value), (fast.grad, slow.grad), (fast.hess, slow.hess)):
                np.testing.assert_allclose(x, y, rtol=0.0, atol=1e-13 * max(1.0, np.abs(y).max()))


@pytest.mark.parametrize("n, seed, nodes, held", [(1, 0, (), False), (9, 2, (3,), False), (12, 3, (5, 12), False),
                                                  (8, 5, (4, 8), True), (30, 7, (), False)])
def test_values_without_derivatives_are_the_evaluated_ones(n, seed, nodes, held):
    """The energy and the tangents at a point without derivatives (a line search's trial point) are those of the
    full evaluation bit for bit, so a trial point and the iterate it becomes agree exactly."""
    energy, q0, basis, omega = _random_rod(n, seed, tangent_nodes=nodes, held=held)
    parts = energy.evaluate(q0, basis, omega)
    assert energy.values(q0, basis, omega) == (parts.bending, parts.twist)
    t, dt, ddt = kinematics.tangents(q0, basis, omega, derivatives=False)
    assert dt is None and ddt is None
    assert np.array_equal(t, kinematics.tangents(q0, basis, omega)[0])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_energy_through_the_relative_rotation_is_the_six_variable_jet_energy(seed):
    """The joint energy's derivatives by the chain rule through ``r = q̄_a ⊗ q_b`` (4-variable jets) are those of
    the strains as jets in the joint's six chart variables, to rounding."""
    from guidewire.rod.jet import Jet
    from guidewire.rod.strain import joint_strain

    energy, q0, basis, omega = _random_rod(10, seed)
    n = energy.n
    parts = energy.evaluate(q0, basis, omega)
    q = q0 + np.einsum("kij,kj->ki", basis, omega)
    left = np.vstack((energy.base, q[:-1]))
    slope = np.concatenate((np.zeros((1, 4, 3)), basis[:-1]))
    zeros = np.zeros((n, 4, 3))
    qa = [Jet.affine(left[:, c], np.concatenate((slope[:, c], zeros[:, c]), axis=1)) for c in range(4)]
    qb = [Jet.affine(q[:, c], np.concatenate((zeros[:, c], basis[:, c]), axis=1)) for c in range(4)]
    k1, k2, tau = joint_strain(quat.relative_affine(qa, qb), "mid")
    joint = ((k1.square() + (k2 - energy.joint_rest).square()) * energy.joint_bending
             + tau.square() * energy.joint_twist)
    gradient = joint.grad[:, 3:].copy()
    gradient[:-1] += joint.grad[1:, :3]
    diagonal = joint.hess[:, 3:, 3:].copy()
    diagonal[:-1] += joint.hess[1:, :3, :3]
    scale = max(1.0, np.abs(joint.hess).max())
    np.testing.assert_allclose(parts.gradient, gradient, rtol=0.0, atol=1e-12 * scale)
    np.testing.assert_allclose(parts.diagonal, diagonal, rtol=0.0, atol=1e-12 * scale)
    np.testing.assert_allclose(parts.off_diagonal, joint.hess[1:, :3, 3:], rtol=0.0, atol=1e-12 * scale)
