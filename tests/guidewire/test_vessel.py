"""Vessel geometry: exact distances, normals and curvatures where the answer is known, smoothness, unions, bad input
refused naming the field, scene files and transformations."""

from __future__ import annotations

import math
import pickle
import re
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from guidewire import Base, Contact, Scene, Wire, load_scene, scene_to_toml
from guidewire.program.feasibility import check_feasible, infeasibility
from guidewire.vessel.vessel import Branch, Vessel

RHO, R = 30.0, 2.0  # the circular bend: centreline radius, lumen radius (mm)
VESSELS = Path(str(resources.files("guidewire") / "scenes" / "vessels"))
SHIPPED = sorted(VESSELS.glob("*.toml"))


def _bend(step_deg: float = 1.0) -> Vessel:
    a = np.radians(np.arange(0.0, 90.0 + step_deg / 2, step_deg))
    return Vessel.from_centreline(np.column_stack((RHO * np.sin(a), RHO * (1.0 - np.cos(a)))), R)


def _channel() -> Vessel:
    return Vessel.from_walls([[0.0, 2.0], [100.0, 2.0]], [[0.0, -2.0], [100.0, -2.0]])


def _branched() -> Vessel:
    return Vessel.from_centreline([[0.0, 0.0], [40.0, 0.0], [80.0, 10.0]], [3.0, 2.5, 2.0],
                                  [([[40.0, 0.0], [45.0, 20.0], [50.0, 40.0]], 1.5)])


def _inside(vessel: Vessel, rng: np.random.Generator, count: int, box: tuple[float, ...]) -> np.ndarray:
    """Random points of ``box`` (xmin, xmax, ymin, ymax) with 0 < distance, off the medial axis."""
    p = rng.uniform(box[::2], box[1::2], size=(20 * count, 2))
    c = vessel.clearance(p)
    keep = (c.distance > 0.05) & (np.hypot(*(p - c.boundary).T) > 0.05)
    return p[keep][:count]


# ----------------------------------------------------------------------------------------------------------------
def test_two_wall_channel_distances_are_exact_everywhere():
    rng = np.random.default_rng(1)
    p = np.column_stack((rng.uniform(-20.0, 150.0, 500), rng.uniform(-3.0, 3.0, 500)))
    c = _channel().clearance(p)
    np.testing.assert_allclose(c.distance, 2.0 - np.abs(p[:, 1]), atol=1e-12)
    np.testing.assert_allclose(c.normal, np.column_stack((np.zeros(500), np.sign(p[:, 1]))), atol=1e-12)
    np.testing.assert_allclose(c.boundary, np.column_stack((p[:, 0], 2.0 * np.sign(p[:, 1]))), atol=1e-12)
    assert np.all(c.curvature == 0.0)
    assert _channel().entrance_point == (0.0, 0.0) and _channel().entrance_angle == 0.0
    np.testing.assert_allclose(_channel().radius_at([0.0, 50.0, 100.0]), 2.0)


def test_straight_tube_is_open_at_the_far_end_and_capped_at_the_entrance():
    tube = Vessel.from_centreline([[0.0, 0.0], [50.0, 0.0]], 2.0)
    p = np.array([[10.0, 1.5], [49.0, -0.5], [80.0, 1.0], [90.0, -2.5], [-1.0, 0.0], [-1.0, 1.0]])
    c = tube.clearance(p)
    expected = [0.5, 1.5, 1.0, -0.5, 1.0, 2.0 - math.sqrt(2.0)]
    np.testing.assert_allclose(c.distance, expected, atol=1e-12)
    np.testing.assert_allclose(c.curvature, [0.0, 0.0, 0.0, 0.0, -0.5, -0.5], atol=1e-12)  # the cap is concave
    assert tube.length == pytest.approx(50.0, abs=1e-12)


def test_circular_bend_distance_normal_and_wall_curvature_are_exact():
    bend = _bend()
    phi = np.radians(np.linspace(5.0, 85.0, 17))
    offsets = np.array([-1.9, -1.0, -0.3, 0.4, 1.2, 1.9, 2.6, -2.4])  # radial offset from the centreline
    ph, off = np.meshgrid(phi, offsets)
    radial = np.column_stack((np.sin(ph.ravel()), -np.cos(ph.ravel())))  # from the bend's centre (0, ρ)
    p = np.array([0.0, RHO]) + (RHO + off.ravel())[:, None] * radial
    c = bend.clearance(p)
    np.testing.assert_allclose(c.distance, R - np.abs(off.ravel()), atol=1e-6)
    outward = np.sign(off.ravel())[:, None] * radial
    np.testing.assert_allclose(c.normal, outward, atol=1e-6)
    np.testing.assert_allclose(c.boundary, np.array([0.0, RHO]) + (RHO + R * np.sign(off.ravel()))[:, None] * radial,
                               atol=1e-6)
    inner = off.ravel() < 0.0  # the inner wall bulges into the lumen
    np.testing.assert_allclose(c.curvature[inner], 1.0 / (RHO - R), rtol=1e-4)
    np.testing.assert_allclose(c.curvature[~inner], -1.0 / (RHO + R), rtol=1e-4)


def test_bend_path_and_radius_follow_the_arc_and_continue_straight():
    bend = _bend()
    s = np.array([0.0, 10.0, 30.0, RHO * math.pi / 2])
    points, angles = bend.path(s)
    np.testing.assert_allclose(points, np.column_stack((RHO * np.sin(s / RHO), RHO * (1 - np.cos(s / RHO)))),
                               atol=1e-6)
    np.testing.assert_allclose(angles, s / RHO, atol=1e-5)
    assert bend.length == pytest.approx(RHO * math.pi / 2, rel=1e-8)
    beyond, angle = bend.path([bend.length + 5.0])
    np.testing.assert_allclose(beyond[0], [RHO, RHO + 5.0], atol=1e-5)
    assert angle[0] == pytest.approx(math.pi / 2, abs=1e-5)
    np.testing.assert_allclose(bend.radius_at([0.0, 20.0, 100.0]), R)


@pytest.mark.parametrize("name", ["bend", "tortuous", "aortic_arch", "straight_channel"])
def test_normals_are_unit_outward_and_the_gradient_of_minus_distance(name):
    vessel = load_scene(VESSELS / f"{name}.toml").vessel
    pts = np.vstack([c for c in vessel.centrelines()])
    lo, hi = pts.min(axis=0) - 3.0, pts.max(axis=0) + 3.0
    p = _inside(vessel, np.random.default_rng(7), 60, (lo[0], hi[0], lo[1], hi[1]))
    assert len(p) >= 30
    c = vessel.clearance(p)
    np.testing.assert_allclose(np.hypot(*c.normal.T), 1.0, atol=1e-12)
    np.testing.assert_allclose(c.boundary, p + c.distance[:, None] * c.normal, atol=1e-9)
    # moved a little along +normal, a point loses distance at rate 1 (outward); the gradient matches differences
    eps = 1e-3
    moved = vessel.clearance(p + eps * c.normal).distance
    np.testing.assert_allclose((c.distance - moved) / eps, 1.0, atol=1e-3)
    h = 1e-6
    grad = np.column_stack([(vessel.clearance(p + h * e).distance - vessel.clearance(p - h * e).distance) / (2 * h)
                            for e in np.eye(2)])
    np.testing.assert_allclose(grad, -c.normal, atol=2e-5)


def test_branch_union_is_the_larger_distance_of_its_tubes():
    vessel = _branched()
    main = Vessel.from_centreline(vessel.centreline, vessel.radius)
    branch = Vessel.from_centreline(vessel.branches[0].centreline, vessel.branches[0].radius)
    rng = np.random.default_rng(3)
    p = rng.uniform([-5.0, -8.0], [90.0, 45.0], size=(400, 2))
    c, a, b = vessel.clearance(p), main.clearance(p), branch.clearance(p)
    np.testing.assert_allclose(c.distance, np.maximum(a.distance, b.distance), atol=1e-12)
    from_branch = b.distance > a.distance
    np.testing.assert_allclose(c.normal[from_branch], b.normal[from_branch], atol=1e-12)
    # a point up the branch is inside only thanks to the branch
    up = vessel.clearance([[50.0, 40.0]])
    assert up.distance[0] == pytest.approx(1.5, abs=1e-9) and main.clearance([[50.0, 40.0]]).distance[0] < -30.0


# ----------------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("build", "error", "words"),
    [
        (lambda: Vessel.from_centreline([[0.0, 0.0]], 1.0), ValueError, r"vessel\.centreline has 1 point"),
        (lambda: Vessel.from_centreline([[0, 0], [1, 0], [1, 0], [2, 0]], 1.0), ValueError,
         r"vessel\.centreline\[2\] repeats"),
        (lambda: Vessel.from_centreline([[0, 0, 0], [1, 0, 0]], 1.0), ValueError, "only 2-D"),
        (lambda: Vessel.from_centreline([[0, 0], [10, 0]], 0.0), ValueError, r"vessel\.radius is 0"),
        (lambda: Vessel.from_centreline([[0, 0], [10, 0]], [1.0, -1.0]), ValueError, r"vessel\.radius\[1\]"),
        (lambda: Vessel.from_centreline([[0, 0], [5, 0], [10, 0]], [1.0, 2.0]), ValueError, "one per centreline"),
        (lambda: Vessel.from_centreline([[0, 0], [10, 0]], "wide"), TypeError, r"vessel\.radius"),
        (lambda: Vessel.from_centreline([[0, 0], [5, 0], [5, 5], [0, 5]], 3.0), ValueError,
         r"vessel\.centreline bends tighter than the lumen radius near point \d"),
        (lambda: Vessel.from_centreline([[0, 0], [30, 0], [40, 5], [30, 10], [0, 10]], 4.0), ValueError,
         r"overlaps itself"),
        (lambda: Vessel.from_centreline([[0, 0], [10, 0]], 1.0, [([[5, 5], [5, 20]], 1.0)]), ValueError,
         r"vessel\.branch\[0\]\.centreline starts .* outside the main lumen"),
        (lambda: Vessel.from_centreline([[0, 0], [10, 0]], 1.0, [([[5, 0]], 1.0)]), ValueError,
         r"vessel\.branch\[0\]\.centreline has 1 point"),
        (lambda: Vessel.from_walls([[0, 0], [10, 0], [10, 5], [5, -5]], [[0, 10], [10, 10]]), ValueError,
         r"vessel\.walls\[0\] crosses itself"),
        (lambda: Vessel.from_walls([[0, 0], [10, 0]], [[0, 4], [10, -4]]), ValueError, r"walls\[0\].*crosses"),
        (lambda: Vessel.from_walls([[0, 0]], [[0, 4], [10, 4]]), ValueError, r"vessel\.walls\[0\] has 1 point"),
        (lambda: Vessel(), ValueError, "no centreline and no walls"),
        (lambda: Scene(Wire(10.0, 10), Base((0.0, 0.0)), vessel="tube"), TypeError, r"scene\.vessel"),
    ],
)
def test_bad_vessels_are_refused_naming_the_field(build, error, words):
    with pytest.raises(error, match=words):
        build()


@pytest.mark.parametrize(
    ("scene", "words"),
    [
        (lambda: Scene.in_vessel(Wire(10.0, 10), Vessel.from_centreline([[0, 0], [20, 0]], 0.3)),
         r"vessel\.radius is 0\.3 mm, not larger than the wire's radius d/2 = 0\.39"),
        (lambda: Scene.in_vessel(Wire(10.0, 10), Vessel.from_centreline([[0, 0], [20, 0]], [1.0, 0.2])),
         r"vessel\.radius\[1\] at \(20, 0\) is 0\.2 mm"),
        (lambda: Scene.in_vessel(Wire(10.0, 10), _channel(), base=Base((5.0, 3.0), 0.0)),
         r"base \(5, 3\) at s = 0 is outside the lumen"),
        (lambda: Scene.in_vessel(Wire(10.0, 10), _channel(), base=Base((5.0, 1.8), 0.0)), "too close"),
        (lambda: Scene.in_vessel(Wire(30.0, 30), _bend(), contacts=(Contact(20.0, (10.0, 5.0)),)),
         r"contact 1 \(10, 5\) at s = 20 is outside the lumen"),
        (lambda: Scene.in_vessel(Wire(10.0, 10), _bend(), base=Base((0.0, 0.0), math.pi)),
         r"base\.angle 3\.14159 rad points out of the vessel"),
    ],
)
def test_wire_specific_vessel_checks_say_why(scene, words):
    with pytest.raises(ValueError, match=words):
        check_feasible(scene())


def test_a_clamp_across_the_entrance_or_elsewhere_is_allowed():
    assert infeasibility(Scene.in_vessel(Wire(10.0, 10), _bend(), base=Base((0.0, 0.0), 1.2))) is None
    assert infeasibility(Scene.in_vessel(Wire(10.0, 10), _channel(), base=Base((5.0, 0.0), math.pi))) is None


# ----------------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_shipped_vessels_load_pass_the_checks_and_keep_the_tip_inside(path, tmp_path):
    scene = load_scene(path)
    assert scene.vessel is not None and infeasibility(scene) is None
    assert scene.wire.bars == round(scene.wire.length)  # one bar per mm inserted
    assert scene.wire.length < scene.vessel.length
    tip, _ = scene.vessel.path([scene.wire.length])
    assert scene.vessel.clearance(tip).distance[0] > scene.wire.diameter
    copy = tmp_path / path.name
    copy.write_text(scene_to_toml(scene))
    assert load_scene(copy) == scene


def test_aortic_arch_has_the_issue_dimensions():
    arch = load_scene(VESSELS / "aortic_arch.toml").vessel
    assert arch.length == pytest.approx(256.5, abs=0.5)
    assert len(arch.branches) == 3
    assert 2 * arch.radius[0] == pytest.approx(17.0) and 2 * arch.radius[-1] == pytest.approx(29.0)
    s = np.linspace(0.0, arch.length, 2001)
    pts, angles = arch.path(s)
    bend_radius = np.diff(s) / np.abs(np.diff(np.unwrap(angles)))
    assert bend_radius.min() == pytest.approx(25.5, abs=0.5)


def test_toml_round_trip_of_branches_radius_lists_and_an_explicit_base(tmp_path):
    vessel = _branched()
    for scene in (Scene.in_vessel(Wire(60.0, 60), vessel, name="tree"),
                  Scene.in_vessel(Wire(60.0, 60), vessel, base=Base((1.0, 0.5), 0.1, name="A"), name="tree")):
        path = tmp_path / "tree.toml"
        path.write_text(scene_to_toml(scene))
        assert load_scene(path) == scene
    assert "[base]" not in scene_to_toml(Scene.in_vessel(Wire(60.0, 60), vessel))


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("[vessel]\ncentreline = [[0, 0], [10, 0]]\nradus = 1\n", "did you mean 'radius'"),
        ("[vessel]\ncentreline = [[0, 0], [10, 0]]\n", "missing the required key 'radius'"),
        ("[vessel]\ncentreline = [[0, 0], [10, 0]]\nradius = 1\nwalls = [[[0, 1], [1, 1]], [[0, -1], [1, -1]]]\n",
         "both walls and"),
        ("[vessel]\nwalls = [[[0, 1], [1, 1]]]\n", "two polylines"),
        ("[vessel]\ncentreline = [[0, 0], [10, 0]]\nradius = 1\n[[vessel.branch]]\ncentreline = [[5, 0], [5, 9]]\n"
         "radious = 1\n", "did you mean 'radius'"),
        ("[vessel]\ncentreline = [[0, 0], [10, 0]]\nradius = 1\n[[vessel.branch]]\ncentreline = [[5, 0], [5, 0]]\n"
         "radius = 1\n", r"\[\[vessel.branch\]\] number 1: vessel\.branch\.centreline\[1\] repeats"),
        ("[vessel]\ncentreline = [[0, 0], [10, 0]]\nradius = -1\n", r"vessel\.radius is -1"),
    ],
)
def test_bad_vessel_tables_are_refused_naming_the_key(tmp_path, text, words):
    path = tmp_path / "bad.toml"
    path.write_text("[wire]\nlength = 5\nbars = 5\n" + text)
    with pytest.raises(ValueError, match=words):
        load_scene(path)


def test_a_vessel_scene_without_base_starts_at_the_entrance_along_the_centreline(tmp_path):
    path = tmp_path / "arch.toml"
    path.write_text("[wire]\nlength = 5\nbars = 5\n[vessel]\ncentreline = [[1, 2], [1, 12], [1, 30]]\nradius = 3\n")
    scene = load_scene(path)
    assert scene.base.point == (1.0, 2.0) and scene.base.angle == pytest.approx(math.pi / 2, abs=1e-12)


# ----------------------------------------------------------------------------------------------------------------
def test_mirrored_and_rotated_scenes_carry_their_vessel():
    scene = load_scene(VESSELS / "tortuous.toml")
    rng = np.random.default_rng(5)
    p = _inside(scene.vessel, rng, 50, (-5.0, 40.0, -5.0, 40.0))
    c = scene.vessel.clearance(p)
    mirrored = scene.mirrored()
    m = mirrored.vessel.clearance(p * [1.0, -1.0])
    np.testing.assert_allclose(m.distance, c.distance, atol=1e-9)
    np.testing.assert_allclose(m.normal, c.normal * [1.0, -1.0], atol=1e-9)
    np.testing.assert_allclose(m.curvature, c.curvature, rtol=1e-6, atol=1e-9)  # bulging in stays bulging in
    assert mirrored.base.angle == pytest.approx(mirrored.vessel.entrance_angle, abs=1e-9)
    angle, centre = 0.7, np.array([3.0, -2.0])
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    turned = scene.rotated(angle, tuple(centre))
    t = turned.vessel.clearance((p - centre) @ rot.T + centre)
    np.testing.assert_allclose(t.distance, c.distance, atol=1e-9)
    np.testing.assert_allclose(t.normal, c.normal @ rot.T, atol=1e-9)
    assert turned.base.angle == pytest.approx(turned.vessel.entrance_angle, abs=1e-9)
    assert infeasibility(turned) is None and infeasibility(mirrored) is None


def test_vessels_are_values():
    vessel = _branched()
    assert pickle.loads(pickle.dumps(vessel)) == vessel
    assert hash(Vessel.from_centreline(vessel.centreline, vessel.radius, vessel.branches)) == hash(vessel)
    assert vessel != Vessel.from_centreline(vessel.centreline, 2.0)
    again = pickle.loads(pickle.dumps(vessel))
    np.testing.assert_array_equal(again.clearance([[10.0, 1.0]]).distance, vessel.clearance([[10.0, 1.0]]).distance)
    assert isinstance(vessel.branches[0], Branch)


def test_a_tube_continues_straight_past_its_far_end_then_closes():
    tube = Vessel.from_centreline([[0.0, 0.0], [50.0, 0.0]], 2.0)
    c = tube.clearance([[95.0, 1.5], [101.0, 0.5], [103.0, 0.0]])  # reach 50 mm past the end, then a cap
    np.testing.assert_allclose(c.distance, [0.5, 2.0 - math.hypot(1.0, 0.5), -1.0], atol=1e-12)
    np.testing.assert_allclose(c.curvature, [0.0, -0.5, -0.5], atol=1e-12)
    # the arch's root does not reach back to its entrance: outside the descending aorta is outside
    arch = load_scene(VESSELS / "aortic_arch.toml").vessel
    assert arch.clearance([[-12.0, 5.0]]).distance[0] < 0.0 < arch.clearance([[-8.0, 5.0]]).distance[0]


# ----------------------------------------------------------------------------------------------------------------
# the fast paths of clearance and past_end answer exactly as searching every tube
def _every_tube(vessel: Vessel, p: np.ndarray) -> tuple[dict[str, np.ndarray], np.ndarray]:
    tubes = vessel._geometry.tubes
    m, t = len(p), len(tubes.curves)
    best = tubes.closest(p)
    return best, np.argmax((best["radius"] - best["r"]).reshape(t, m), axis=0) * m + np.arange(m)


@pytest.mark.parametrize("name", ["aortic_arch", "branched"])
@pytest.mark.parametrize("floor", [np.inf, 5.0, -np.inf])
def test_pruned_tube_search_is_exact_whatever_its_lower_bound_says(name, floor, monkeypatch):
    """``best`` searches the other tubes that could reach the lower bound of the largest distance, then, where no
    answer reached it (a local search stopping short far outside), those that could reach the largest answer found:
    with a bound no answer reaches (inf, 5 mm: above every depth), or one every tube does, the same answer as
    searching every tube."""
    vessel = _branched() if name == "branched" else load_scene(VESSELS / f"{name}.toml").vessel
    rng = np.random.default_rng(9)
    lines = np.concatenate(vessel.wall_lines())
    p = np.concatenate([rng.uniform(lines.min(axis=0) - 10.0, lines.max(axis=0) + 10.0, size=(3000, 2)),
                        lines + rng.normal(scale=0.2, size=lines.shape)])
    reference, flat = _every_tube(vessel, p)
    tubes = vessel._geometry.tubes
    monkeypatch.setattr(tubes, "lower_bound", lambda q: np.full(len(q), floor))
    best, pick = vessel._geometry.best(p)
    for key in ("u", "k", "centre", "radius", "v", "r", "source", "t", "kappa"):
        np.testing.assert_array_equal(best[key][pick], reference[key][flat], err_msg=key)


@pytest.mark.parametrize("name", ["aortic_arch", "tortuous", "branched"])
def test_pruned_tube_search_gives_the_answer_of_searching_every_tube(name):
    vessel = _branched() if name == "branched" else load_scene(VESSELS / f"{name}.toml").vessel
    rng = np.random.default_rng(5)
    lines = np.concatenate(vessel.wall_lines())
    tubes = vessel._geometry.tubes
    p = np.concatenate([
        rng.uniform(lines.min(axis=0) - 10.0, lines.max(axis=0) + 10.0, size=(4000, 2)),  # inside and outside
        lines + rng.normal(scale=0.2, size=lines.shape),  # near the walls and the branch mouths
        *(point + rng.normal(size=(500, 2)) * 3.0 * radius + direction * rng.uniform(-20.0, 80.0, size=(500, 1))
          for point, direction, radius in zip(tubes.tail_point, tubes.tail_tangent, tubes.tail_radius, strict=True)),
    ])
    reference, flat = _every_tube(vessel, p)
    best, pick = vessel._geometry.best(p)
    for key in ("u", "k", "centre", "radius", "v", "r", "source", "t", "kappa"):
        np.testing.assert_array_equal(best[key][pick], reference[key][flat], err_msg=key)
    np.testing.assert_array_equal(vessel.past_end(p), np.isin(reference["source"][flat], (2, 3)))
    assert np.all(tubes.upper_bound(p) >= (reference["radius"] - reference["r"]).reshape(len(tubes.curves), -1).T
                  - 1e-12)


def test_clearance_answers_are_kept_read_only_and_exact():
    vessel = load_scene(VESSELS / "aortic_arch.toml").vessel
    p = np.array([[0.0, 5.0], [10.0, 40.0]])
    first = vessel.clearance(p)
    assert vessel.clearance(p.copy()) is first  # the same points: the kept answer
    assert not first.distance.flags.writeable and not first.normal.flags.writeable
    moved = vessel.clearance(p + 1e-12)  # other points: a new answer
    assert moved is not first and moved.distance[0] != first.distance[0]
    for _ in range(8):  # the memo stays small
        vessel.clearance(np.random.default_rng(1).normal(size=(3, 2)))
    assert len(vessel._geometry.answers._answers) <= 4
    again = Vessel.from_centreline(vessel.centreline, vessel.radius, vessel.branches)
    np.testing.assert_array_equal(again.clearance(p).distance, first.distance)  # a new vessel computes its own


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_nearest_corner_with_the_callers_opening_flags_equals_its_own_search(seed):
    """The caller's :meth:`Vessel.opening` flags for all its points give each point the corner it finds asking for
    its own few (the arch's openings; points near its corners and across the lumen)."""
    vessel = load_scene(VESSELS / "aortic_arch.toml").vessel
    rng = np.random.default_rng(seed)
    corners = vessel.corners
    p = np.concatenate([corners[rng.integers(len(corners), size=150)] + rng.normal(scale=2.0, size=(150, 2)),
                        _inside(vessel, rng, 50, (-60.0, 40.0, 0.0, 220.0))])
    near = vessel.clearance(p)
    flags = vessel.opening(near.boundary, near.distance)
    own = vessel.nearest_corner(p, near)
    given = vessel.nearest_corner(p, near, flags)
    assert np.any(own[0] >= 0) and np.any(flags)  # (the case is not empty)
    np.testing.assert_array_equal(given[0], own[0])
    np.testing.assert_array_equal(given[1], own[1])


def test_forgetting_the_kept_queries_searches_again_with_the_same_answer():
    vessel = load_scene(VESSELS / "aortic_arch.toml").vessel
    p = np.array([[0.0, 5.0], [10.0, 40.0]])
    first = vessel.clearance(p)
    corners = vessel.corners
    vessel.forget_queries()
    again = vessel.clearance(p)
    assert again is not first and vessel.corners is corners  # searched anew; the built geometry kept
    for name in ("distance", "normal", "boundary", "curvature"):
        np.testing.assert_array_equal(getattr(again, name), getattr(first, name), err_msg=name)


def test_clearance_of_points_extending_a_kept_query_equals_a_fresh_one():
    scene = load_scene(VESSELS / "aortic_arch.toml")
    vessel, fresh = scene.vessel, Vessel.from_centreline(scene.vessel.centreline, scene.vessel.radius,
                                                         scene.vessel.branches)
    rng = np.random.default_rng(11)
    p = _inside(vessel, rng, 60, (-60.0, 40.0, 0.0, 220.0))
    vessel.clearance(p[:40])
    longer = vessel.clearance(p)  # the first 40 rows kept, 20 computed
    direct = fresh.clearance(p)
    for name in ("distance", "normal", "boundary", "curvature"):
        np.testing.assert_array_equal(getattr(longer, name), getattr(direct, name), err_msg=name)


def _fresh(vessel: Vessel) -> Vessel:
    """The same vessel built anew (its own memo)."""
    if vessel.walls:
        return Vessel.from_walls(*vessel.walls)
    return Vessel.from_centreline(vessel.centreline, vessel.radius, vessel.branches)


@pytest.mark.parametrize("name", ["aortic_arch", "tortuous", "bend", "s_bend_branch", "straight_channel", "branched"])
def test_near_and_far_walls_from_one_kept_search_equal_separate_fresh_queries(name):
    """The memo searches once for the near and the far wall of the same points, extends a kept query by its new rows
    only (its record and each answer derived so far), in any order of asking: every answer equals that of a fresh
    vessel's geometry asked directly, bit for bit."""
    vessel = _branched() if name == "branched" else load_scene(VESSELS / f"{name}.toml").vessel
    lines = np.concatenate(vessel.wall_lines())
    box = (*np.sort([lines[:, 0].min(), lines[:, 0].max()]), *np.sort([lines[:, 1].min(), lines[:, 1].max()]))
    p = _inside(vessel, np.random.default_rng(3), 90, box)
    p[::7] += 0.5 * np.random.default_rng(4).normal(size=p[::7].shape)  # some outside or near the walls
    geometry = _fresh(vessel)._geometry
    expected = {"near": geometry.clearance(p), "far": geometry.far_side(p)}
    for order in (("near", "far"), ("far", "near")):
        memo = _fresh(vessel)
        ask = {"near": memo.clearance, "far": memo.far_side}
        for cut in (30, 60):  # a kept query, then one extending it, with both answers asked in ``order``
            for kind in order:
                ask[kind](p[:cut])
        for kind in order[::-1]:
            got, direct = ask[kind](p), expected[kind]
            for field in ("distance", "normal", "boundary", "curvature"):
                np.testing.assert_array_equal(getattr(got, field), getattr(direct, field), err_msg=f"{kind} {field}")
            assert ask[kind](p.copy()) is got  # asked again: the kept answer


@pytest.mark.parametrize("name", ["aortic_arch", "tortuous", "straight_channel", "branched"])
@pytest.mark.parametrize("cut", [1, 35, 89])
def test_points_sharing_leading_rows_with_a_kept_query_are_answered_as_fresh_ones(name, cut):
    """A query whose first ``cut`` rows are a kept query's (its tail moved: the lumen's rows at the predictor's nodes
    with the new tip turned), and one that is a kept query's first rows (shorter): each answer, near and far, equals a
    fresh vessel's, bit for bit, asked before or after the other kind."""
    vessel = _branched() if name == "branched" else load_scene(VESSELS / f"{name}.toml").vessel
    lines = np.concatenate(vessel.wall_lines())
    box = (*np.sort([lines[:, 0].min(), lines[:, 0].max()]), *np.sort([lines[:, 1].min(), lines[:, 1].max()]))
    p = _inside(vessel, np.random.default_rng(5), 90, box)
    moved = p.copy()
    moved[cut:] += 0.3 * np.random.default_rng(6).normal(size=moved[cut:].shape)
    geometry = _fresh(vessel)._geometry
    for query in (moved, p[:cut]):
        expected = {"near": geometry.clearance(query), "far": geometry.far_side(query)}
        for order in (("near", "far"), ("far", "near")):
            memo = _fresh(vessel)
            ask = {"near": memo.clearance, "far": memo.far_side}
            ask[order[0]](p)  # the kept query (one answer derived so far)
            searched: list[int] = []
            geo = memo._geometry
            search, derive = geo.search, geo.derive
            geo.search = lambda q, log=searched, search=search: log.append(len(q)) or search(q)
            geo.derive = lambda record, kind, log=searched, derive=derive: derive(record, kind) if not log.append(
                -1) else None
            for i, kind in enumerate(order[::-1]):
                got = ask[kind](query)
                # only the rows the kept query lacks are searched, once for both kinds (what a derivation searches is
                # not counted: the far wall's check searches its own points)
                primary = searched[:searched.index(-1)] if -1 in searched else searched
                assert primary == ([len(query) - cut] if len(query) > cut and i == 0 else []), searched
                searched.clear()
                for field in ("distance", "normal", "boundary", "curvature"):
                    np.testing.assert_array_equal(getattr(got, field), getattr(expected[kind], field),
                                                  err_msg=f"{kind} {field}")


@pytest.mark.parametrize("shift", [0.0, 5.0, -5.0, 10.0])
def test_a_centreline_coming_back_onto_itself_names_the_two_distant_stretches(shift):
    """A loop that returns across its own start: the message names one point at each stretch (points 1 and 6 or
    7 here, whichever the crossing is nearer along the curve), never one point twice, whatever the loop's offset."""
    pts = [[0, 0], [30, 0], [60, 0], [70, 10], [70, 30], [60, 40], [40 + shift, 30], [30 + shift, -20],
           [30 + shift, -50]]
    with pytest.raises(ValueError, match="comes back within the lumen radius") as err:
        Vessel(centreline=pts, radius=2.0)
    named = [int(k) for k in re.findall(r"point (\d+) \(", str(err.value))]
    assert len(named) == 2 and named[0] in (0, 1, 2) and named[1] in (6, 7), str(err.value)
