"""Rod energy: gradients against finite differences, twist energy of a straight wire, planar agreement."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from guidewire.rod import RodEnergy


def _rod(n: int, seed: int) -> tuple[RodEnergy, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    lengths = 1.0 + 0.3 * rng.random(n)
    rod = RodEnergy(lengths, EI=2.0, GJ=1.5, base_tangent=np.array([1.0, 0.0, 0.0]), base_angle=0.4)
    x = np.vstack([np.zeros(3), np.cumsum(rng.normal(size=(n, 3)) + [2.0, 0, 0], axis=0)])
    return rod, x, rng.normal(size=n)


@pytest.mark.parametrize("n", [3, 8, 20])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_gradients_match_central_differences(n: int, seed: int) -> None:
    rod, x, theta = _rod(n, seed)
    h = 1e-6
    fd = np.zeros(x.size)
    for i in range(x.size):
        dx = np.zeros(x.size)
        dx[i] = h
        fd[i] = (rod.bending(x + dx.reshape(x.shape)) - rod.bending(x - dx.reshape(x.shape))) / (2 * h)
    # central differences: error O(h² |E'''|) + rounding O(eps |E| / h) ~ 1e-9 here
    assert np.max(np.abs(fd - rod.bending_gradient(x).ravel())) < 1e-6
    fd_t = np.array([(rod.twist(theta + h * e) - rod.twist(theta - h * e)) / (2 * h) for e in np.eye(n)])
    assert np.max(np.abs(fd_t - rod.twist_gradient(theta))) < 1e-6


@pytest.mark.parametrize("n", [1, 5, 40])
def test_straight_wire_twisted_stores_gj_psi2_over_2l(n: int) -> None:
    L, GJ, psi = 7.0, 3.0, 1.3
    lengths = np.full(n, L / n)
    rod = RodEnergy(lengths, EI=1.0, GJ=GJ, base_tangent=np.array([0.0, 0.0, 1.0]), base_angle=psi)
    # tip's twist held at 0, interior angles at equilibrium: linear in arc length of the dual lengths
    s = np.concatenate([[lengths[0] / 2], lengths[0] / 2 + np.cumsum((lengths[:-1] + lengths[1:]) / 2)])
    # the base half joint spans l_1/2, so the held tip angle sits at arc length s_n + l_n/2 = L
    theta = psi * (1.0 - s / L)
    energy = rod.twist(theta) + GJ / lengths[-1] * theta[-1] ** 2  # tip half joint to the held angle 0
    assert abs(energy - GJ * psi**2 / (2 * L)) < 1e-12 * GJ * psi**2 / L


@pytest.mark.parametrize("seed", range(5))
def test_planar_chain_bending_equals_2d_scheme_under_random_rotation(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = 12
    lengths = 1.0 + rng.random(n)
    phi = np.cumsum(rng.uniform(-0.5, 0.5, n))
    x2 = np.vstack([np.zeros(2), np.cumsum(lengths[:, None] * np.c_[np.cos(phi), np.sin(phi)], axis=0)])
    EI = 3.0
    e2d = EI / lengths[0] * phi[0] ** 2 + np.sum(EI / (lengths[:-1] + lengths[1:]) * np.diff(phi) ** 2)
    R = Rotation.random(random_state=seed).as_matrix()
    x3 = np.c_[x2, np.zeros(n + 1)] @ R.T
    rod = RodEnergy(lengths, EI=EI, GJ=1.0, base_tangent=R[:, 0])
    assert abs(rod.bending(x3) - e2d) < 1e-12 * e2d
    assert abs(rod.bending(x3 + rng.normal(size=3)) - e2d) < 1e-12 * e2d


def test_bad_lengths_raise() -> None:
    with pytest.raises(ValueError, match="lengths"):
        RodEnergy(np.array([1.0, -1.0]), EI=1.0, GJ=1.0, base_tangent=np.array([1.0, 0, 0]))
