"""A planar clamped rod with a prescribed end point, rotated rigidly in 3D, gives rotated nodes and the same energy."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from guidewire.rod import RodEnergy
from guidewire.rod.static import solve_clamped


def _planar(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    lengths = np.full(n, 10.0 / n)
    phi = np.linspace(0.05, 0.6, n)
    x = np.vstack([np.zeros(2), np.cumsum(lengths[:, None] * np.c_[np.cos(phi), np.sin(phi)], axis=0)])
    return lengths, np.c_[x, np.zeros(n + 1)], np.array([8.5, 3.5, 0.0])


@pytest.mark.parametrize("seed", range(3))
def test_rotated_planar_solve_is_rotated(seed: int) -> None:
    n = 10
    lengths, x0, tip = _planar(n)
    flat = solve_clamped(RodEnergy(lengths, 1.0, 1.0, np.array([1.0, 0, 0])), x0, tip)
    assert flat.success, flat.message
    R = Rotation.random(random_state=seed).as_matrix()
    rod = RodEnergy(lengths, 1.0, 1.0, R[:, 0])
    res = solve_clamped(rod, x0 @ R.T, tip @ R.T)
    assert res.success, res.message
    assert abs(res.fun - flat.fun) < 1e-12 * flat.fun
    assert np.max(np.abs(res.x.reshape(n, 3) - flat.x.reshape(n, 3) @ R.T)) < 1e-6
    # stays in the plane of the rotated scene
    assert np.max(np.abs(res.x.reshape(n, 3) @ R[:, 2])) < 1e-6


@pytest.mark.parametrize("seed", range(3))
def test_rotated_planar_solve_equals_2d_guidewire_solve(seed: int) -> None:
    from guidewire import Base, Contact, Scene, Wire, solve

    n = 10
    wire = Wire(10.0, n)
    planar = solve(Scene(wire, Base((0.0, 0.0), 0.0), (Contact(10.0, point=(8.5, 3.5)),)))
    lengths, x0, tip = _planar(n)
    R = Rotation.random(random_state=seed).as_matrix()
    rod = RodEnergy(lengths, float(np.atleast_1d(wire.bending_stiffness)[0]), 1.0, R[:, 0])
    res = solve_clamped(rod, x0 @ R.T, tip @ R.T)
    assert res.success, res.message
    # both solvers stop at a KKT residual ~1e-10: issue 29 asks energy 1e-9 relative, nodes 1e-7 mm
    assert abs(res.fun - planar.energy) < 1e-9 * planar.energy
    nodes = np.c_[planar.nodes[1:], np.zeros(n)] @ R.T
    assert np.max(np.abs(res.x.reshape(n, 3) - nodes)) < 1e-7


def test_cantilever_under_tip_force_converges_at_order_two() -> None:
    R = Rotation.random(random_state=3).as_matrix()
    force = np.array([0.3, 1.0, 0.5]) @ R.T
    tips = []
    for n in (10, 20, 40):
        x0 = np.c_[np.linspace(0.0, 10.0, n + 1), np.zeros((n + 1, 2))] @ R.T
        res = solve_clamped(RodEnergy(np.full(n, 10.0 / n), 1.0, 1.0, R[:, 0]), x0, tip_force=force)
        assert res.success, res.message
        tips.append(res.x[-3:])
    coarse, fine = np.linalg.norm(tips[0] - tips[1]), np.linalg.norm(tips[1] - tips[2])
    # second-order scheme: successive differences shrink by 4 (measured ratio 2^1.90 at these n)
    assert 1.7 < np.log2(coarse / fine) < 2.3


@pytest.mark.parametrize("seed", range(3))
def test_clamp_reaction_balances_the_tip_force(seed: int) -> None:
    n = 12
    R = Rotation.random(random_state=seed).as_matrix()
    force = np.random.default_rng(seed).normal(size=3)
    rod = RodEnergy(np.full(n, 10.0 / n), 2.0, 1.0, R[:, 0])
    x0 = np.c_[np.linspace(0.0, 10.0, n + 1), np.zeros((n + 1, 2))] @ R.T
    res = solve_clamped(rod, x0, tip_force=force)
    assert res.success, res.message
    x = np.vstack([x0[0], res.x.reshape(n, 3)])
    grad = rod.bending_gradient(x)
    e = 2.0 * np.diff(x, axis=0)  # gradient of |e_k|² - l_k² with respect to node k+1 (minus for node k)
    J = np.zeros((n, 3 * (n + 1)))
    for k in range(n):
        J[k, 3 * k + 3 : 3 * k + 6], J[k, 3 * k : 3 * k + 3] = e[k], -e[k]
    external = np.zeros(3 * (n + 1))
    external[-3:] = force
    lam = np.linalg.lstsq(J[:, 3:].T, -(grad.ravel()[3:] - external[3:]), rcond=None)[0]
    stationarity = grad.ravel()[3:] - external[3:] + J[:, 3:].T @ lam
    assert np.max(np.abs(stationarity)) < 1e-6
    # node 0: the clamp balances the internal force -(dE/dx_0 + J_0^T lam) the rod exerts on it
    reaction = grad[0] + J[:, :3].T @ lam
    np.testing.assert_allclose(reaction + force, 0.0, atol=1e-6 * np.linalg.norm(force))


def test_free_straight_wire_rotated_at_base_turns_rigidly() -> None:
    rod = RodEnergy(np.full(8, 0.5), 1.0, 2.0, np.array([0.0, 1.0, 0.0]), base_angle=0.9)
    assert rod.twist(np.full(8, 0.9)) == 0.0
    np.testing.assert_array_equal(rod.twist_gradient(np.full(8, 0.9)), 0.0)
