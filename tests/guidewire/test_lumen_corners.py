"""Lumen rows modelled at a shape are exact there, also where a vessel's corner holds a node.

A lumen block's rows are second-order models of the wall (or of a corner's distance) centred at the nodes where they
were made; :meth:`Lumen.refine` re-centres them until, at the answer, every row its node touches agrees with the
constraint it models. That agreement must hold right after re-centring, or the working-set rounds never settle: a node
held by a corner (its slack the corner's) whose wall row touches too was compared with the corner's slack and showed
a gap equal to its wall clearance, which re-centring cannot close (the aortic arch inserted at 4 bars per mm ran out
of rounds at 205-210 mm, warm and cold).
"""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

import guidewire
from guidewire.blocks.lumen import TOUCHING_BARS, Lumen, _corner_needed, _needed
from guidewire.program.model import build_model

VESSELS = resources.files("guidewire") / "scenes" / "vessels"


def _corner_point(model, corner: int, node: int, wall_slack: float) -> np.ndarray | None:
    """A point inside the lumen at exactly the distance ``node`` needs from ``corner`` (its corner slack 0) whose
    clearance from the nearest wall exceeds what the node needs there by ``wall_slack`` mm; None if the circle has
    none."""
    vessel = model.scene.vessel
    centre, radius = vessel.corners[corner], float(_corner_needed(model, np.array([node]))[0, corner])

    def excess(theta: np.ndarray) -> np.ndarray:
        points = centre + radius * np.column_stack((np.cos(theta), np.sin(theta)))
        c = vessel.clearance(points)
        return c.distance - _needed(model, c.curvature, np.full(theta.size, node)) - wall_slack

    theta = np.linspace(0.0, 2.0 * np.pi, 721)
    values = excess(theta)
    crossing = np.flatnonzero((values[:-1] < 0.0) & (values[1:] >= 0.0))
    if not crossing.size:
        return None
    lo, hi = theta[crossing[0]], theta[crossing[0] + 1]
    for _ in range(60):  # bisection on the wall clearance along the circle
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if excess(np.array([mid]))[0] < 0.0 else (lo, mid)
    return centre + radius * np.array([np.cos(hi), np.sin(hi)])


def _angles_through(model, node: int, point: np.ndarray) -> np.ndarray | None:
    """Bar angles whose chain has ``node`` (even) exactly at ``point``: its first half of bars turned ``+θ`` from the
    direction to the point, the second half ``−θ`` (equal bars), the rest straight on; None if out of reach."""
    base = np.asarray(model.chain.base_point, dtype=float)
    length = float(model.chain.lengths[0])
    reach = np.hypot(*(point - base))
    if reach > node * length:
        return None
    psi, theta = np.arctan2(*(point - base)[::-1]), np.arccos(reach / (node * length))
    phi = np.full(model.n, psi)
    phi[: node // 2] += theta
    phi[node // 2 : node] -= theta
    return phi


@pytest.mark.parametrize(
    ("name", "length", "bars"),
    [
        ("aortic_arch", 210.0, 420),
        ("aortic_arch", 205.0, 820),
        ("s_bend_branch", 60.0, 120),
        ("s_bend_branch", 60.0, 240),
    ],
)
def test_rows_remodelled_at_a_corner_held_node_fit_it(name, length, bars):
    """At shapes whose node sits exactly at a corner's needed distance while its wall row touches (wall slack 0 to
    ``TOUCHING_BARS`` bar lengths), over every corner of the vessel: the rows modelled there agree with the constraint
    they model at every touching row (``mismatch`` at most 1e-9 mm), so a refinement at that answer ends the rounds."""
    scene = guidewire.load_scene(str(VESSELS / f"{name}.toml")).with_wire(length=length, bars=bars)
    model = build_model(scene)
    bar = float(model.chain.lengths[0])
    checked = 0
    for corner in range(scene.vessel.corners.shape[0]):
        for fraction in (0.05, 0.5, 0.95):
            base = np.asarray(model.chain.base_point, dtype=float)
            reach = np.hypot(*(scene.vessel.corners[corner] - base))
            node = min(model.n - model.n % 2, 2 * int(np.ceil(0.5 * reach / bar)) + 4)
            point = _corner_point(model, corner, node, fraction * TOUCHING_BARS * bar)
            phi = None if point is None else _angles_through(model, node, point)
            if phi is None:
                continue
            points = model.chain.nodes(phi)
            block = Lumen._modelled(model, np.arange(1, model.n + 1), points)
            near = scene.vessel.clearance(points[node : node + 1])
            wall = float(near.distance[0] - _needed(model, near.curvature, np.array([node]))[0])
            held = float(block.slack(model, points)[node - 1])
            assert abs(held) < 1e-9 < wall <= TOUCHING_BARS * bar  # the corner holds the node, its wall row touches
            found = block.mismatch(model, phi)
            assert found is None or found[0] <= 1e-9, (corner, fraction, found)
            checked += 1
    assert checked >= 2 * scene.vessel.corners.shape[0]
