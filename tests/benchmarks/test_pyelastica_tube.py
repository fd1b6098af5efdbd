"""The tube geometry of ``benchmarks/pyelastica_tube.py``'s penalty contact against a helix's analytic normal planes.

A point ``c(t) + ρ (cos φ N(t) + sin φ B(t))`` (``N``, ``B`` the helix's principal normal and binormal) with ``ρ``
below the radius of curvature and half the pitch has ``c(t)`` as its nearest centreline point and ``ρ`` as its
distance: the polyline search must return both, up to the chord's sagitta ``κ h² / 8``. The penalty kernel must push
exactly the nodes beyond the margin, by ``k · gap`` along the inward normal.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import pyelastica_tube as B  # noqa: E402

A, PITCH = 10.0, 25.0  # the shipped helix: coil radius and pitch (mm)
SPACING = 0.05  # polyline spacing (mm)


def helix_frame(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points, principal normals and binormals of ``(a cos t, a sin t, b t)``."""
    b = PITCH / (2.0 * math.pi)
    speed = math.hypot(A, b)
    c = np.column_stack((A * np.cos(t), A * np.sin(t), b * t))
    tangent = np.column_stack((-A * np.sin(t), A * np.cos(t), np.full_like(t, b))) / speed
    normal = np.column_stack((-np.cos(t), -np.sin(t), np.zeros_like(t)))
    return c, normal, np.cross(tangent, normal)


@pytest.fixture(scope="module")
def polyline() -> np.ndarray:
    b = PITCH / (2.0 * math.pi)
    t_end = 4.0 * math.pi
    count = int(math.ceil(t_end * math.hypot(A, b) / SPACING))
    return helix_frame(np.linspace(0.0, t_end, count + 1))[0]


@pytest.fixture(scope="module")
def offset_points() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(7)
    t = rng.uniform(0.5, 4.0 * math.pi - 0.5, 200)
    rho = rng.uniform(0.0, 2.0, t.size)
    phi = rng.uniform(0.0, 2.0 * math.pi, t.size)
    c, n, bn = helix_frame(t)
    p = c + rho[:, None] * (np.cos(phi)[:, None] * n + np.sin(phi)[:, None] * bn)
    return p, c, rho


def test_distances_and_feet_match_the_helix(polyline, offset_points):
    points, centres, rho = offset_points
    sagitta = (A / (A**2 + (PITCH / (2 * math.pi)) ** 2)) * SPACING**2 / 8.0  # 2.7e-5 mm
    distance, foot = B.nearest_on_polyline(points, polyline)
    assert np.max(np.abs(distance - rho)) < 2.0 * sagitta
    # along the curve the chord (turned by up to κ h / 2 from the tangent) shifts the foot by up to ρ κ h / 2 (4.3 µm)
    assert np.max(np.linalg.norm(foot - centres, axis=1)) < 5e-3


def test_windowed_search_from_a_nearby_hint_agrees_with_the_full_search(polyline, offset_points):
    points, _, _ = offset_points
    hint = np.full(len(points), -1, dtype=np.int64)
    full, _ = B.nearest_on_polyline(points, polyline, hint)
    moved = points + 0.05  # a small step: the hint from before still brackets the nearest segment
    local, _ = B.nearest_on_polyline(moved, polyline, hint, window=8)
    assert np.allclose(local, B.nearest_on_polyline(moved, polyline)[0], atol=1e-12)
    assert not np.allclose(local, full)  # the points did move


def test_penalty_pushes_exactly_the_nodes_beyond_the_margin(polyline):
    t = np.array([1.0, 2.0, 3.0, 4.0])
    c, n, _ = helix_frame(t)
    rho = np.array([0.0, 1.0, 1.7, 1.9])  # the first node is clamped: never pushed
    position = (c + rho[:, None] * n).T.copy()
    forces = np.zeros_like(position)
    m = position.shape[1]
    margin, k = 1.65, 100.0
    gap, distance, foot = np.zeros(m), np.zeros(m), np.zeros((m, 3))
    B._penalty_kernel(position, np.zeros_like(position), forces, polyline, np.full(m, -1, dtype=np.int64), 8,
                      margin, k, np.zeros(m), gap, distance, foot)
    magnitude = np.linalg.norm(forces, axis=0)
    assert np.count_nonzero(magnitude) == 2
    gap_expected = np.maximum(rho - margin, 0.0)
    gap_expected[0] = 0.0
    assert np.allclose(magnitude, k * gap_expected, atol=k * 1e-4)  # the gap to the sagitta (2.7e-5 mm)
    pushed = magnitude > 0.0
    cosine = np.einsum("ij,ij->i", -forces.T[pushed] / magnitude[pushed, None], n[pushed])
    assert np.all(cosine > math.cos(5e-3))  # along the normal, to the foot's shift over ρ (module docstring)
