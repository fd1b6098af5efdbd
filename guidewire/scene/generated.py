"""Random feasible scenes built from a generating bar chain: the property test's and the branch benchmark's scenes.

A scene is generated from a smooth bar chain: its tangent angle is ``θ(u) = θ₀ + c₀u + c₁ sin πu + c₂ sin 2πu +
c₃ (1 − cos πu)`` (``u = s/L``, turning rate ``|dθ/du|`` at most :data:`MAX_TURNING_RATE` rad over the wire), sampled
at the bar midpoints. Two to six contacts sit on its nodes (position and tangent taken from the chain, some with the
position only), optionally a wall the chain does not cross, optionally a b₂ the chain satisfies. The chain itself is
then a feasible point, so the minimum of the scene cannot have a higher energy: a solve that ends above it found a
higher local minimum (a *branch miss*, see :mod:`guidewire.solve.branches`).

Contacts are at least :data:`MIN_GAP` of the wire apart (and from the base): closer contacts on a random curve make
the energy landscape hold several nearby local minima.

:func:`chain_scene` builds a scene from its parameters (the property test draws them with hypothesis);
:func:`random_chain_scene` draws them from a numpy generator (``benchmarks/branches.py``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..wire import Wire
from .scene import Base, Contact, Scene, Wall

FloatArray = NDArray[np.float64]

MAX_TURNING_RATE = 4.0
"""Largest ``|dθ/du|`` of the generating curve (rad per wire length)."""

MIN_GAP = 0.15
"""Smallest distance between contacts (and from the base to the first), as a fraction of the wire length."""

MIN_SLACK = 1e-10
"""Least relative slack ``1 − chord/span`` of a stretch between two positions on a curved chain: below it the
feasible set is nearly a single point where no constraint qualification holds (multipliers need not exist)."""


@dataclass(frozen=True)
class ChainScene:
    """A scene and the chain it was generated from.

    Attributes
    ----------
    scene : Scene
    angles : ndarray, shape (bars,)
        Bar angles of the generating chain (rad): a feasible point of ``scene``.
    """

    scene: Scene
    angles: FloatArray


def min_gap_nodes(bars: int) -> int:
    """Least number of bars between two contacts (and from the base to the first) for ``bars`` bars."""
    return max(3, math.ceil(MIN_GAP * bars))


def chain_scene(bars: int, length: float, scheme: str, modes: Sequence[float], theta0: float,
                base: Sequence[float], contact_nodes: Sequence[int], with_angle: Sequence[bool],
                wall: tuple[float, float] | None = None, b2_factor: float | None = None) -> ChainScene | None:
    """The scene of a generating chain, or None when its stretches are nearly taut (see :data:`MIN_SLACK`).

    Parameters
    ----------
    bars : int
    length : float
        Wire length (mm).
    scheme : {"second_order", "paper"}
    modes : sequence of 4 floats
        ``c₀ … c₃`` of the module docstring, scaled down so that ``|dθ/du| ≤ MAX_TURNING_RATE``.
    theta0 : float
        Base angle (rad).
    base : (float, float)
        Base point (mm).
    contact_nodes : sequence of int
        Candidate contact nodes in ``[1, bars]``; sorted, and one closer than :func:`min_gap_nodes` to the previous
        kept one is dropped.
    with_angle : sequence of bool
        Per kept contact (in order; missing entries False): whether it prescribes the chain's tangent too.
    wall : (float, float), optional
        ``(direction ψ, margin)``: a wall with outward normal ``(cos ψ, sin ψ)`` at ``margin · length`` beyond the
        chain's farthest node.
    b2_factor : float, optional
        A b₂ bound of this many times the chain's largest joint angle (at least 0.01 rad).
    """
    c = np.asarray(modes, dtype=float)
    uu = np.linspace(0.0, 1.0, 201)
    rate = np.abs(c[0] + np.pi * c[1] * np.cos(np.pi * uu) + 2 * np.pi * c[2] * np.cos(2 * np.pi * uu)
                  + np.pi * c[3] * np.sin(np.pi * uu)).max()
    c = c * min(1.0, MAX_TURNING_RATE / max(rate, 1e-12))

    def theta(u: FloatArray | float) -> FloatArray:
        return np.asarray(theta0 + c[0] * u + c[1] * np.sin(np.pi * u) + c[2] * np.sin(2 * np.pi * u)
                          + c[3] * (1 - np.cos(np.pi * u)))

    n = bars
    phi = theta((np.arange(n) + 0.5) / n)
    origin = np.asarray(base, dtype=float)
    nodes = np.vstack([origin, origin + np.cumsum(length / n * np.column_stack([np.cos(phi), np.sin(phi)]), axis=0)])
    gap = min_gap_nodes(n)
    ks: list[int] = []
    for k in sorted(set(int(k) for k in contact_nodes)):
        if k >= gap and (not ks or k - ks[-1] >= gap):
            ks.append(k)
    if np.ptp(phi) > 0.0:  # a chain straight to rounding is kept: its stretches are exactly taut, a clean case
        held = [0, *ks]
        chords = np.hypot(*(nodes[held[1:]] - nodes[held[:-1]]).T)
        spans = np.diff(held) * (length / n)
        if not bool(np.all(1.0 - chords / spans >= MIN_SLACK)):
            return None
    flags = list(with_angle) + [False] * len(ks)
    contacts = []
    for k, angled in zip(ks, flags, strict=False):
        angle = float(phi[k - 1]) if scheme == "paper" else float(theta(k / n))  # paper: φ_k = θ* is a row
        contacts.append(Contact(k * (length / n), (float(nodes[k, 0]), float(nodes[k, 1])),
                                angle if angled else None))
    walls: tuple[Wall, ...] = ()
    if wall is not None:
        psi, margin = wall
        normal = (math.cos(psi), math.sin(psi))
        walls = (Wall(normal, float((nodes @ np.array(normal)).max() + margin * length)),)
    b2 = None if b2_factor is None else float(max(np.abs(np.diff(phi)).max(), 0.01) * b2_factor)
    wire = Wire(length, n, scheme=scheme, max_relative_angle=b2)
    scene = Scene(wire, Base((float(origin[0]), float(origin[1])), float(theta(0.0))), tuple(contacts), walls)
    return ChainScene(scene, phi)


def random_chain_scene(rng: np.random.Generator) -> ChainScene:
    """A random :func:`chain_scene` (redrawn until its stretches have slack), its parameters uniform over the ranges
    the property test draws from: 20–60 bars, 40–200 mm, either scheme, modes in [−2, 2], 2–6 candidate contacts,
    each with its tangent or not, a wall (margin 0–0.2 L) and a b₂ (1.2–3 times the chain's) each with probability ½.
    """
    while True:
        bars = int(rng.integers(20, 61))
        gap = min_gap_nodes(bars)
        m = int(rng.integers(2, 7))
        case = chain_scene(
            bars, float(rng.uniform(40.0, 200.0)), str(rng.choice(["second_order", "paper"])),
            rng.uniform(-2.0, 2.0, 4).tolist(), float(rng.uniform(-math.pi, math.pi)),
            rng.uniform(-50.0, 50.0, 2).tolist(), rng.integers(gap, bars + 1, m).tolist(),
            (rng.random(m) < 0.5).tolist(),
            wall=(float(rng.uniform(0.0, 2 * math.pi)), float(rng.uniform(0.0, 0.2))) if rng.random() < 0.5 else None,
            b2_factor=float(rng.uniform(1.2, 3.0)) if rng.random() < 0.5 else None)
        if case is not None:
            return case
