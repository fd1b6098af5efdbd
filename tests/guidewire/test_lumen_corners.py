"""Lumen rows modelled at a shape are exact there, also where a bar passes a vessel's corner.

A lumen block's rows are models of the wall (second order), of a node's distance from a corner, or of a bar's distance
from a corner (exact while the corner's foot lies on the bar) made at the shape where they were built;
:meth:`Lumen.refine` re-models them until, at the answer, every row its node touches agrees with the constraint it
models — and a bar's row also with where its force acts (the foot) and its direction. That agreement must hold right
after re-modelling, or the working-set rounds never settle.
"""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

import guidewire
from guidewire.blocks.lumen import TOUCHING_BARS, Lumen
from guidewire.program.model import build_model

VESSELS = resources.files("guidewire") / "scenes" / "vessels"


def _angles_through(model, node: int, point: np.ndarray, then: float) -> np.ndarray | None:
    """Bar angles whose chain has ``node`` (even) exactly at ``point``: its first half of bars turned ``+θ`` from the
    direction to the point, the second half ``−θ`` (equal bars), the rest straight on at the angle ``then``; None if
    out of reach."""
    base = np.asarray(model.chain.base_point, dtype=float)
    length = float(model.chain.lengths[0])
    reach = np.hypot(*(point - base))
    if reach > node * length:
        return None
    psi, theta = np.arctan2(*(point - base)[::-1]), np.arccos(reach / (node * length))
    phi = np.full(model.n, then)
    phi[:node] = psi
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
def test_rows_remodelled_where_a_bar_passes_a_corner_fit_it(name, length, bars):
    """At shapes whose bar passes a corner on the lumen's side (at the wire's radius plus 0 to ``TOUCHING_BARS`` bar
    lengths, its foot a tenth, half and nine tenths along it), for every corner of the vessel: the bar gets the
    corner's bar row, its slack is that excess, and every touching row agrees with what it models (``mismatch`` at most
    1e-9 mm), so a refinement at that answer ends the rounds."""
    scene = guidewire.load_scene(str(VESSELS / f"{name}.toml")).with_wire(length=length, bars=bars)
    model = build_model(scene)
    vessel, bar, r = scene.vessel, float(model.chain.lengths[0]), 0.5 * scene.wire.diameter
    base = np.asarray(model.chain.base_point, dtype=float)
    checked = 0
    for corner, faces in zip(vessel.corners, vessel.corner_faces, strict=True):
        away = -(faces[0] + faces[1]) / np.linalg.norm(faces[0] + faces[1])  # from the wedge into the lumen
        along = np.array([-away[1], away[0]])
        along = along if along @ (corner - base) > 0.0 else -along
        node = min(model.n - 2 - model.n % 2, 2 * int(np.ceil(0.5 * np.hypot(*(corner - base)) / bar)) + 4)
        for excess in (0.0, 0.5 * TOUCHING_BARS * bar):
            for tau in (0.1, 0.5, 0.9):
                foot = corner + (r + excess) * away
                phi = _angles_through(model, node, foot - tau * bar * along, float(np.arctan2(along[1], along[0])))
                if phi is None:
                    continue
                points = model.chain.nodes(phi)
                block = Lumen._modelled(model, np.arange(1, model.n + 1), points)
                rows = block.rows(model)
                mine = np.flatnonzero((block.nodes == node) & (block.turns != 0.0))
                assert mine.size == 1, (corner, excess, tau)
                np.testing.assert_allclose(block.fractions[mine], tau, atol=1e-9)
                np.testing.assert_allclose(rows.values(points)[mine] - rows.lb[mine], excess, atol=1e-9)
                assert block.slack(model, points)[node - 1] <= excess + 1e-9
                found = block.mismatch(model, phi)
                assert found is None or found[0] <= 1e-9, (corner, excess, tau, found)
                checked += 1
    assert checked >= 6 * vessel.corners.shape[0] - 6


@pytest.mark.parametrize(("name", "length", "bars"), [("s_bend_branch", 60.0, 40), ("s_bend_branch", 60.0, 60),
                                                      ("aortic_arch", 210.0, 105), ("aortic_arch", 210.0, 210)])
def test_a_bar_behind_a_corner_is_a_violation_though_its_nodes_are_inside(name, length, bars):
    """A bar passing behind a corner's tip, through its wedge of wall (its foot from the corner r + 0.01 mm into the
    wedge, along the two walls' bisector), is outside the lumen: :meth:`Lumen.violation` flags its nodes by at least
    the depth of the bar's nearest point to the corner, also where both nodes clear the walls by the wire's radius
    (long bars: a node check alone passes that shape)."""
    scene = guidewire.load_scene(str(VESSELS / f"{name}.toml")).with_wire(length=length, bars=bars)
    model = build_model(scene)
    vessel, bar, r = scene.vessel, float(model.chain.lengths[0]), 0.5 * scene.wire.diameter
    base = np.asarray(model.chain.base_point, dtype=float)
    checked = hidden = 0
    for corner, faces in zip(vessel.corners, vessel.corner_faces, strict=True):
        into = (faces[0] + faces[1]) / np.linalg.norm(faces[0] + faces[1])
        along = np.array([-into[1], into[0]])
        along = along if along @ (corner - base) > 0.0 else -along
        node = min(model.n - 2 - model.n % 2, 2 * int(np.ceil(0.5 * np.hypot(*(corner - base)) / bar)) + 4)
        foot = corner + (r + 0.01) * into
        phi = _angles_through(model, node, foot - 0.5 * bar * along, float(np.arctan2(along[1], along[0])))
        if phi is None:
            continue
        points = model.chain.nodes(phi)
        depth = -float(vessel.lumen_clearance(foot[None])[0])
        assert depth > 0.0  # (the construction: the bar's middle is in the wall)
        violation = Lumen.build(model)[0].violation(model, phi, points)
        assert min(violation[node - 1], violation[node]) >= r + depth - 1e-9
        hidden += bool(np.all(vessel.lumen_clearance(points[node : node + 2]) >= r))
        checked += 1
    assert checked == vessel.corners.shape[0]
    if bar >= 1.5:
        assert hidden >= 1  # (1.5 mm bars span the wedge's tip of s_bend_branch with both nodes clear)


@pytest.mark.parametrize("name", ["s_bend_branch", "aortic_arch"])
def test_points_facing_a_corner_measure_their_clearance_from_it(name):
    """Straight out of a corner's wedge (along its two walls' bisector, away from the wall) the corner is the nearest
    point of the lumen's boundary: :meth:`Vessel.nearest_corner` names it and :meth:`Vessel.lumen_clearance` is the
    distance from it, where the deepest tube's :meth:`Vessel.clearance` (its wall running on through the opening)
    reads less; a point into the wedge is outside the lumen."""
    vessel = guidewire.load_scene(str(VESSELS / f"{name}.toml")).vessel
    narrowest = min(float(np.min(vessel.radius)), *(float(np.min(b.radius)) for b in vessel.branches))
    shorter = 0
    for c, (corner, faces) in enumerate(zip(vessel.corners, vessel.corner_faces, strict=True)):
        into = (faces[0] + faces[1]) / np.linalg.norm(faces[0] + faces[1])
        t = np.array([0.05, 0.1, 0.2]) * narrowest
        points = corner - t[:, None] * into
        index, distance = vessel.nearest_corner(points)
        assert np.all(index == c)
        np.testing.assert_allclose(distance, t, rtol=1e-12)
        np.testing.assert_allclose(vessel.lumen_clearance(points), t, rtol=1e-12)
        shorter += int(np.any(vessel.clearance(points).distance < t - 1e-9))
        assert np.all(vessel.lumen_clearance(corner + t[:, None] * into) < 0.0)
    assert shorter >= 1
