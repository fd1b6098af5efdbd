"""What an insertion step keeps instead of recomputing — the far wall's check, a block's rows and last slack, the
row matching of the warm multipliers, the base's clearance, the memory check of a small program — gives the answers
the full computation gives, for every input of a family, and none of it leaks into what a solution pickles."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

import guidewire
from guidewire import insert, load_scene
from guidewire.blocks.lumen import Lumen
from guidewire.program.formulation import _row_positions, formulate
from guidewire.program.model import build_model
from guidewire.solve import options as solve_options
from guidewire.vessel.geometry import FAR_WALL_TOLERANCE

VESSELS = Path(guidewire.__file__).resolve().parent / "scenes" / "vessels"


def _points_in(vessel, rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` points near the centreline of ``vessel`` (some outside the lumen, some past its ends)."""
    s = rng.uniform(-2.0, vessel.length + 2.0, count)
    centre, _ = vessel.path(s)
    return centre + rng.normal(scale=1.5, size=(count, 2))


@pytest.mark.parametrize("name", ["bend", "tortuous", "aortic_arch", "s_bend_branch", "straight_channel"])
def test_far_side_is_gone_exactly_where_its_wall_point_lies_inside_the_lumen(name):
    """The far wall's distance is inf exactly where the point across lies deeper in the lumen than
    ``FAR_WALL_TOLERANCE`` of that distance by the vessel's full clearance there (the signed distance the check
    reads is that clearance's, bit for bit), and the wall's distance everywhere else; a two-wall vessel has no such
    points."""
    vessel = load_scene(VESSELS / f"{name}.toml").vessel
    geometry = vessel._geometry
    points = _points_in(vessel, np.random.default_rng(7), 400)
    far = vessel.far_side(points)
    if vessel.walls:
        assert np.all(np.isfinite(far.distance))
        return
    wall = geometry._wall(geometry.search(points), -1.0)  # the wall across, before the check
    depth = geometry.clearance(wall.boundary).distance  # the full clearance of the point across
    expected = np.where(depth > FAR_WALL_TOLERANCE * wall.distance, np.inf, wall.distance)
    assert np.array_equal(far.distance, expected)
    assert np.array_equal(far.boundary, wall.boundary)


@pytest.mark.parametrize("seed", range(40))
def test_block_rows_are_matched_by_key_as_a_mapping_would(seed):
    """Every key of the new block finds the last row of the old one with that key, or none (-1): the positions a
    dictionary from key to row gives, for keys drawn with repeats, gaps and empty sides."""
    rng = np.random.default_rng(seed)
    keys = rng.integers(0, 25, rng.integers(0, 30))
    wanted = rng.integers(0, 30, rng.integers(0, 30))
    where = {int(k): i for i, k in enumerate(keys)}
    assert _row_positions(keys, wanted).tolist() == [where.get(int(k), -1) for k in wanted]


@pytest.mark.parametrize(("name", "length"), [("bend", 60.0), ("aortic_arch", 120.0), ("s_bend_branch", 50.0)])
def test_lumen_rows_and_slack_kept_equal_a_fresh_build_and_are_not_pickled(name, length):
    """A lumen block's rows, built once, equal a fresh block's at any time, read-only; its kept slack is the slack of
    the points asked (another set of points recomputes it); a solution carrying the block pickles its fields only."""
    scene = load_scene(VESSELS / f"{name}.toml")
    scene = scene.with_wire(length=length, bars=int(round(length * scene.wire.bars / scene.wire.length)))
    model = build_model(scene)
    block = Lumen.build(model)[0]
    fresh = Lumen.build(model)[0]
    first, again = block.rows(model), block.rows(model)
    assert first is again and not first.lb.flags.writeable
    other = fresh._build_rows(model.scene.vessel.corners)
    for a, b in ((first.directions, other.directions), (first.lb, other.lb), (first.hessians, other.hessians)):
        assert np.array_equal(a, b)
    rng = np.random.default_rng(3)
    for _ in range(4):
        phi = model.x0 + rng.normal(scale=0.05, size=model.n)
        points = model.chain.nodes(phi)
        slack, wall = fresh._slack(model, points)
        assert np.array_equal(block.slack(model, points), slack)
        assert np.array_equal(block.wall_slack(model, points), wall)
        assert np.array_equal(block.violation(model, phi), np.maximum(-slack, 0.0))
    sol = guidewire.solve(scene)
    kept = pickle.loads(pickle.dumps(sol))
    for b in kept.blocks:
        assert not {"_kept_rows", "_kept_slack"} & set(vars(b))
    assert kept.energy == sol.energy


def test_a_program_this_small_is_never_refused_for_memory(monkeypatch):
    """Below ``ALWAYS_FITS`` bytes a vessel scene is solved without asking the system (even one saying no memory
    is left); above it the answer is the system's."""
    monkeypatch.setattr(solve_options, "available_memory", lambda: 0)
    scene = load_scene(VESSELS / "bend.toml")
    small = int((solve_options.ALWAYS_FITS / (solve_options.DENSE_COPIES * 8.0)) ** 0.5)
    solve_options.check_memory(scene, small, "reduced")
    with pytest.raises(ValueError, match="GiB"):
        solve_options.check_memory(scene, small + 1, "reduced")


@pytest.mark.parametrize(("name", "first", "last"), [("bend", 20.0, 40.0), ("aortic_arch", 170.0, 180.0)])
def test_insertion_steps_equal_steps_solved_alone(name, first, last):
    """Each warm insertion step (its start and multipliers from the step before, its vessel queries answered from
    what the steps before asked) equals the same step solved alone from that start in a fresh copy of the scene:
    the same energy, iterations and nodes, bit for bit."""
    scene = load_scene(VESSELS / f"{name}.toml")
    density = scene.wire.bars / scene.wire.length
    out = insert(scene.with_wire(length=first, bars=round(first * density)), np.arange(first, last + 0.5, 1.0))
    assert out.complete
    from guidewire.march.insertion import _tracked_angles, _tracked_multipliers

    for prev, step in zip(out.steps[:-1], out.steps[1:], strict=True):
        alone_scene = load_scene(VESSELS / f"{name}.toml").with_wire(length=step.scene.wire.length,
                                                                     bars=step.n_bars)  # (a new vessel: no memo)
        start = _tracked_angles(prev, alone_scene, step.n_bars)
        alone = guidewire.solve(alone_scene, initial_angles=start, multipliers0=_tracked_multipliers(prev, step.n_bars))
        assert alone.iterations == step.iterations and alone.energy == step.energy
        assert np.array_equal(alone.nodes, step.nodes)
    assert formulate(out.steps[-1].scene).n == out.steps[-1].n_bars
