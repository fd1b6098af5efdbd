"""The creases around 3-D branch openings: on both walls, the node's row is its exact distance from the crease in
the crease's cone, derivatives against central differences (nodes, bars, the program's block), and the places a
crease holds a wire follow the wire along it."""

from __future__ import annotations

import numpy as np
import pytest

from guidewire.vessel3d.arch import aortic_arch
from guidewire.vessel3d.crease import WALL_TOL, Crease, find_creases


@pytest.fixture(scope="module")
def arch():
    return aortic_arch("I")


def _cone_points(crease: Crease, count: int, seed: int, depth: tuple[float, float]) -> tuple[np.ndarray, ...]:
    """Points ``X + δ u`` in the cone of random crease points ``X``: ``u`` a random direction between the two walls'
    directions away from the crease (``−e_j``, ``−e_o``: the cone's sides) in the plane normal to the crease."""
    rng = np.random.default_rng(seed)
    sigma = _held_angles(crease, rng, count)
    x, k1 = crease.spline(sigma), crease.spline(sigma, 1)
    t = k1 / np.linalg.norm(k1, axis=1)[:, None]
    tubes = crease._tubes
    inward = []
    for which in (np.full(count, crease.branch), np.asarray(crease.others)[crease.arc_at(sigma)]):
        e = [tubes[i].closest(x[k:k + 1], np.zeros(1)) for k, i in enumerate(which)]
        v = np.array([ek.centre[0] for ek in e]) - x
        inward.append(v / np.linalg.norm(v, axis=1)[:, None])
    n_j, n_o = inward
    # the cone's sides: the walls' normals at the crease (a point at X + δ n_j is δ from wall j, its foot X)
    s = rng.uniform(0.05, 0.95, count)[:, None]
    u = s * n_j + (1.0 - s) * n_o
    u -= np.einsum("ij,ij->i", u, t)[:, None] * t
    u /= np.linalg.norm(u, axis=1)[:, None]
    delta = rng.uniform(*depth, count)
    return x + delta[:, None] * u, x, delta


def _held_angles(crease: Crease, rng: np.random.Generator, count: int) -> np.ndarray:
    """Random angles on the crease's owned arcs, away from its corners by 0.05 rad, where its cone opens at least
    30 degrees (beside the trunk's end the right common carotid's wall leaves the trunk's end ball almost
    tangentially, a cone of 9 degrees: a bowed wire's nearest point to the crease falls outside it)."""
    out = np.zeros(0)
    while out.size < count:
        sigma = rng.uniform(crease.lo, crease.hi, 4 * count)
        gap = np.min(np.abs(sigma[:, None] - np.append(crease.corners, crease.hi)[None, :]), axis=1, initial=np.inf)
        i = np.clip(np.searchsorted(crease.sigma, sigma), 0, crease.sigma.size - 1)
        narrow = np.einsum("ij,ij->i", crease._e_j[i], crease._e_o[i]) < np.cos(np.radians(150.0))
        keep = np.asarray(crease.owned)[crease.arc_at(sigma)] & (gap > 0.05) & ~narrow
        out = np.concatenate((out, sigma[keep]))
    return out[:count]


def test_the_shipped_arch_has_a_crease_round_each_branch_leaving_the_aorta(arch):
    """A crease around each of the brachiocephalic trunk, the left common carotid and the left subclavian, on the
    aorta's wall and the branch's to 1e-6 mm, each a closed curve."""
    side = [c for c in arch.creases if not c.corners.size]
    assert {arch.tube_names[c.branch] for c in side} == {"brachiocephalic", "left_common_carotid",
                                                         "left_subclavian"}
    for crease in side:
        assert crease.others == ("main",) and crease.owned == (True,) or arch.tube_names[crease.others[0]] == "main"
        x = crease.points
        zero = np.zeros(len(x))
        for tube in (arch.tubes[crease.branch], arch.tubes[crease.other]):
            assert np.max(np.abs(tube.rows(x, zero)[0])) < 1e-6
        assert np.linalg.norm(crease.spline(crease.lo) - crease.spline(crease.hi)) < 1e-12  # (closed)


def test_the_bifurcation_at_the_trunks_end_has_two_creases_with_corners(arch):
    """Where the trunk ends in the right common carotid and subclavian arteries, each leaves the trunk's end and
    its sibling: a closed crease of two arcs meeting at two corners, where the three walls meet (to 1e-12 mm); each
    arc on its two walls to its tolerance (``WALL_TOL``, 1e-5 mm; the knots twice as dense as the side creases' in
    the carotid's); the carina (the arc along both
    siblings' walls) held by one of the two creases only."""
    names = arch.tube_names
    forked = {names[c.branch]: c for c in arch.creases if c.corners.size}
    assert set(forked) == {"right_common_carotid", "right_subclavian"}
    trunk = names.index("brachiocephalic")
    owners = 0
    for name, crease in forked.items():
        sibling = names.index("right_subclavian" if name == "right_common_carotid" else "right_common_carotid")
        assert set(crease.others) == {trunk, sibling} and crease.corners.size == 2
        owners += crease.owned[crease.others.index(sibling)]
        assert crease.owned[crease.others.index(trunk)]
        corners = crease.spline(crease.corners)
        for i in (crease.branch, trunk, sibling):
            assert np.max(np.abs(arch.tubes[i].rows(corners, np.zeros(2))[0])) < 1e-12
        x, arc = crease.points, crease.arc_at(crease.sigma)
        for k, other in enumerate(crease.others):
            on = arc == k
            for i in (crease.branch, other):
                # (the tolerance holds halfway between knots, where an interpolant's error peaks to first order)
                assert np.max(np.abs(arch.tubes[i].rows(x[on], np.zeros(on.sum()))[0])) < 1.5 * WALL_TOL
        assert np.linalg.norm(crease.spline(crease.lo) - crease.spline(crease.hi)) < 1e-12  # (closed)
    assert owners == 1


def test_creases_are_found_again_the_same(arch):
    again = find_creases(arch.tubes)
    for a, b in zip(arch.creases, again, strict=True):
        assert np.array_equal(a.points, b.points)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_node_in_a_creases_cone_is_its_distance_from_the_crease(arch, seed):
    """At ``X + δ u`` in the cone the row is ``δ − r`` (the crease is its nearest boundary point), above both tubes'
    rows (each tube alone would put the ball against a wall that lies inside the other tube there)."""
    r = 0.35
    for crease in arch.creases:
        p, _, delta = _cone_points(crease, 40, seed, (0.2, 1.0))
        rows = crease.rows(p, np.full(len(p), r))
        assert rows.index.size >= 30  # (a few fall outside the reach or past a neighbour's nearest point)
        assert np.allclose(rows.value, delta[rows.index] - r, rtol=0, atol=1e-9)
        lumen = arch.lumen_rows(p, np.full(len(p), r))[0]
        tubes = np.max([t.rows(p, np.full(len(p), r))[0] for t in arch.tubes], axis=0)
        assert np.all(lumen[rows.index] == rows.value)
        assert np.all(tubes[rows.index] < rows.value)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_node_crease_rows_match_central_differences(arch, seed):
    """``∇g = ŵ`` and ``∇²g`` (the distance to a curve, envelope theorem) against central differences (h = 1e-5 mm:
    truncation ~h²/d³ ≈ 1e-9, rounding ~eps/h ≈ 1e-11)."""
    h = 1e-5
    for crease in arch.creases:
        p, _, _ = _cone_points(crease, 30, seed, (0.3, 1.0))
        r = np.full(len(p), 0.3)
        rows = crease.rows(p, r)
        q = p[rows.index]
        for i in range(3):
            step = np.zeros(3)
            step[i] = h
            plus, minus = crease.rows(q + step, r[rows.index]), crease.rows(q - step, r[rows.index])
            assert plus.index.size == minus.index.size == q.shape[0]
            assert np.allclose((plus.value - minus.value) / (2 * h), rows.gradient[:, i], rtol=0, atol=1e-8)
            assert np.allclose((plus.gradient - minus.gradient) / (2 * h), rows.hessian[:, :, i], rtol=0,
                               atol=1e-6 * max(1.0, float(np.abs(rows.hessian).max())))


def _crossing_wires(crease: Crease, count: int, seed: int, gap: float) -> tuple[np.ndarray, np.ndarray]:
    """Short polylines (5 nodes, 0.5 mm bars, a small bend) crossing the crease's cone ``gap`` mm from it."""
    rng = np.random.default_rng(seed)
    p, x, _ = _cone_points(crease, count, seed, (gap, gap))
    k1 = crease.spline(crease.closest(p), 1)
    t = k1 / np.linalg.norm(k1, axis=1)[:, None]
    w = p - x
    w /= np.linalg.norm(w, axis=1)[:, None]
    across = np.cross(t, w)  # (along the wire: normal to the crease and to the way to it)
    tilt = rng.uniform(-0.6, 0.6, count)
    direction = np.cos(tilt)[:, None] * across + np.sin(tilt)[:, None] * t
    shift = rng.uniform(-0.25, 0.25, count)
    s = 0.5 * (np.arange(5) - 2.0)
    bend = 0.08 * (s**2)[None, :, None] * w[:, None, :]  # (bowed away from the crease: one nearest place)
    nodes = p[:, None, :] + (s[None, :, None] + shift[:, None, None]) * direction[:, None, :] + bend
    return nodes, w


@pytest.mark.parametrize("seed", [0, 1])
def test_crease_minima_rows_match_central_differences(arch, seed):
    """The rows of the places a crease comes nearest a wire — inside a bar (the envelope theorem over ``(τ, φ)``)
    or at a node — against central differences of their values and gradients over both of the bar's nodes."""
    h = 1e-6
    checked = {"bar": 0, "node": 0}
    for crease in arch.creases:
        walls, _ = _crossing_wires(crease, 12, seed, 0.4)
        for nodes in walls:
            radius = np.full(len(nodes) - 1, 0.3)
            found = crease.minima(nodes, radius, radius)
            for j in range(found.bar.size):
                k = int(found.bar[j])
                kind = "node" if found.fraction[j] >= 1.0 else "bar"
                if kind == "bar" and min(found.fraction[j], 1.0 - found.fraction[j]) < 1e-4:
                    continue  # (the differences' steps would pass the bar's end: the place becomes the node)
                checked[kind] += 1
                for col in range(6):
                    if k == 0 and col < 3:
                        continue
                    step = np.zeros_like(nodes)
                    step[k + col // 3, col % 3] = h
                    plus = crease.minima(nodes + step, radius, radius)
                    minus = crease.minima(nodes - step, radius, radius)
                    jp = int(np.flatnonzero(plus.bar == k)[0])
                    jm = int(np.flatnonzero(minus.bar == k)[0])
                    assert (plus.value[jp] - minus.value[jm]) / (2 * h) == pytest.approx(found.gradient[j, col],
                                                                                           abs=1e-7)
                    fd = (plus.gradient[jp] - minus.gradient[jm]) / (2 * h)
                    assert np.allclose(fd, found.hessian[j, :, col], rtol=0,
                                       atol=2e-5 * max(1.0, float(np.abs(found.hessian[j]).max())))
    assert checked["bar"] >= 20


def test_a_wire_bowed_over_a_crease_has_one_place_inside_a_bar_at_its_distance(arch):
    """A wire crossing the cone ``gap`` from the crease and bowed away from it comes nearest once: inside a bar,
    ``gap − r`` from it to second order in the bow, the foot's ``τ`` in (0, 1) — and the place moves with the wire
    as it slides along itself (the same slot)."""
    r, gap = 0.3, 0.5
    for crease in arch.creases:
        walls, w = _crossing_wires(crease, 10, 3, gap)
        for nodes in walls:
            radius = np.full(len(nodes) - 1, r)
            found = crease.minima(nodes, radius, radius)
            assert found.bar.size == 1
            assert 0.0 < found.fraction[0] <= 1.0
            assert found.value[0] == pytest.approx(gap - r, abs=0.03)
            slid = nodes + 0.1 * (nodes[-1] - nodes[0]) / np.linalg.norm(nodes[-1] - nodes[0])
            moved = crease.minima(slid, radius, radius)
            assert moved.bar.size == 1 and abs(moved.bar[0] - found.bar[0]) <= 1


def test_a_pickled_vessel_finds_the_same_creases(arch):
    """Batch workers get vessels by pickle: the creases are found again there, the same."""
    import pickle

    again = pickle.loads(pickle.dumps(arch))
    assert len(again.creases) == len(arch.creases)
    for a, b in zip(arch.creases, again.creases, strict=True):
        assert np.array_equal(a.points, b.points)


@pytest.mark.parametrize("length", [230.0, 250.0, 270.0])
def test_cold_solves_across_the_openings_keep_every_bar_off_the_creases(length):
    """stEVE's J wire solved cold in the type I arch where it crosses the branches' openings: it converges, every
    bar keeps its radius from every crease (its nearest pair with the crease, not only the places the rows hold),
    every node is in the lumen, and the forces and moments balance."""
    from pathlib import Path

    from guidewire.solve3d.file import load_scene
    from guidewire.solve3d.insert import scene_at
    from guidewire.solve3d.solve import solve3d

    root = Path(__file__).resolve().parents[2]
    scene = load_scene(root / "guidewire" / "scenes" / "vessels3d" / "aortic_arch_I.toml")
    target = scene_at(scene, length, 0.0, scene.wire.bars / scene.wire.length)
    sol = solve3d(target)
    assert sol.success
    middle = np.cumsum(sol.lengths) - 0.5 * sol.lengths
    radius = 0.5 * target.wire.properties_at(middle).diameter
    a, b = sol.nodes[:-1], sol.nodes[1:]
    for crease in scene.vessel.creases:
        tau, phi = crease._segments(a, b)
        gap = np.linalg.norm(a + tau[:, None] * (b - a) - crease.spline(phi), axis=1)
        assert np.min(gap - radius) >= -1e-6
    node_radius = np.maximum(radius, np.append(radius[1:], radius[-1]))
    assert scene.vessel.lumen_rows(sol.nodes[1:], node_radius)[0].min() >= -1e-6
    force, moment = sol.balance()
    total = sum(f.magnitude for f in sol.forces)
    assert force <= 1e-6 * max(total, 1.0) and moment <= 1e-6 * 300.0 * max(total, 1.0)
