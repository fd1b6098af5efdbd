"""3-D vessels: the lumen row's exact derivatives, its zero set, insertion in a helix (nodes in the lumen, contact
forces normal and non-negative, balance), the J-tip's whip under rotation, and bad input named."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from guidewire import Section, Wire
from guidewire.solve3d import Scene3D
from guidewire.solve3d.insert import insert3d
from guidewire.solve3d.program import node_radii
from guidewire.vessel3d import Vessel3D
from guidewire.vessel3d.shapes import helix, tortuous

STEVE_J = (Section.arc(12.1, 0.4 * math.pi, youngs_modulus=17000.0, diameter=0.7),)


def _points_in(vessel: Vessel3D, count: int, seed: int, radius: float) -> np.ndarray:
    """Random points inside the main tube shrunk by ``radius``: near the axis and near the wall."""
    rng = np.random.default_rng(seed)
    tube = vessel.tubes[0]
    u = rng.uniform(0.05 * tube.end, 0.95 * tube.end, count)
    e = tube.evaluate(u)
    t = e.d1 / np.linalg.norm(e.d1, axis=1, keepdims=True)
    n = rng.normal(size=(count, 3))
    n -= np.einsum("ij,ij->i", n, t)[:, None] * t
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    depth = rng.uniform(0.0, 0.95, count) * (e.radius - radius)
    return e.centre + depth[:, None] * n


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("shape", ["helix", "tortuous"])
def test_lumen_row_gradient_and_hessian_match_central_differences(shape, seed):
    """``∇g`` and ``∇²g`` (envelope theorem over the closest ball) against central differences of ``g`` and ``∇g``
    (step 1e-5 mm: truncation ~h² |g'''| ≈ 1e-10 with curvatures ≲ 1/a, rounding ~eps |g| / h ≈ 1e-11)."""
    vessel = helix() if shape == "helix" else tortuous()  # (the tortuous one tapers: R' ≠ 0)
    r = 0.2
    p = _points_in(vessel, 12, seed, r)
    radii = np.full(len(p), r)
    g, grad, hess = (np.array(a) for a in vessel.lumen_rows(p, radii))
    h = 1e-5
    for i in range(3):
        step = np.zeros(3)
        step[i] = h
        gp, dp, _ = (np.array(a) for a in vessel.lumen_rows(p + step, radii))
        gm, dm, _ = (np.array(a) for a in vessel.lumen_rows(p - step, radii))
        assert np.allclose((gp - gm) / (2 * h), grad[:, i], rtol=0, atol=1e-8)
        assert np.allclose((dp - dm) / (2 * h), hess[:, :, i], rtol=0, atol=1e-5 * max(1.0, np.abs(hess).max()))
    assert np.all(g > 0.0)  # (inside by construction)


@pytest.mark.parametrize("angle", np.linspace(0.0, 2 * math.pi, 7)[:-1])
def test_lumen_row_vanishes_on_the_shrunk_wall_with_unit_gradient(angle):
    """On the wall shrunk by the wire radius, ``g = 0`` and ``|∇g| = 1``: the multiplier is the wall's force in N and
    the row's value the clearance to first order (a helix: curvature 1/11.6 mm, lumen 2 mm, every direction)."""
    vessel = helix()
    tube = vessel.tubes[0]
    u = np.linspace(0.2, 0.8, 5) * tube.end
    e = tube.evaluate(u)
    t = e.d1 / np.linalg.norm(e.d1, axis=1, keepdims=True)
    a = np.cross(t, [0.0, 0.0, 1.0])
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    b = np.cross(t, a)
    r = 0.3
    p = e.centre + (e.radius - r)[:, None] * (math.cos(angle) * a + math.sin(angle) * b)
    g, grad, _ = vessel.lumen_rows(p, np.full(len(p), r))
    assert np.max(np.abs(g)) < 1e-9
    assert np.max(np.abs(np.linalg.norm(grad, axis=1) - 1.0)) < 1e-9


@pytest.fixture(scope="module")
def helix_insertion():
    wire = Wire(length=10.0, bars=20, youngs_modulus=80000.0, diameter=0.89)
    vessel = helix()
    out = insert3d(Scene3D.in_vessel(wire, vessel), np.arange(10.0, 51.0, 2.0))
    return vessel, wire, out


def test_insertion_in_a_helix_keeps_every_node_in_the_lumen(helix_insertion):
    vessel, wire, out = helix_insertion
    assert out.complete, out.error
    for sol in out.steps:
        clearance, _ = vessel.clearance(sol.nodes[1:], wire.diameter / 2)
        assert clearance.min() > -1e-6, (float(np.sum(sol.lengths)), clearance.min())


def test_helix_contact_forces_are_normal_non_negative_and_balance(helix_insertion):
    _, _, out = helix_insertion
    touching = 0
    for sol in out.steps:
        for f in sol.forces:
            if f.kind != "lumen":
                continue
            touching += 1
            along = float(f.force @ f.normal)
            assert along >= 0.0
            assert np.linalg.norm(f.force - along * f.normal) <= 1e-9 * max(1.0, along)
        force, moment = sol.balance()
        scale = max(1.0, abs(sol.entrance_force))
        assert force < 1e-7 * scale and moment < 1e-6 * scale * 50.0
    assert touching > 10  # (the wire does lean on the helix's wall)
    pushes = [sol.entrance_force for sol in out.steps[-5:]]
    assert min(pushes) > 0.0  # pushing a wire through a coil takes a positive push


@pytest.fixture(scope="module")
def whip():
    """A stEVE J inserted 40 mm into the helix, then the clamp turned two full turns in 15° steps."""
    wire = Wire(length=10.0, bars=20, youngs_modulus=80000.0, diameter=0.89, sections=STEVE_J)
    lengths = list(np.arange(10.0, 40.5, 2.0))
    turns = np.radians(np.arange(15.0, 721.0, 15.0))
    out = insert3d(Scene3D.in_vessel(wire, helix()), lengths + [40.0] * len(turns),
                   [0.0] * len(lengths) + list(turns))
    return out, len(lengths), turns


def test_j_tip_roll_lags_the_clamp_then_snaps_releasing_energy(whip):
    """The whip users see: turning the clamp in a curved tube, the tip's roll falls behind (the wire stores twist and
    bending), then jumps ahead in one step, and the step of the jump lowers the energy."""
    out, first, turns = whip
    assert out.complete, out.error
    rolls = np.array([s.tip_roll for s in out.steps[first - 1:]])
    base = np.concatenate(([0.0], turns))
    lag = rolls - base  # (the tip's roll behind the clamp's: the twist the wire stores)
    assert lag.min() < -math.radians(30.0)
    jumps = np.diff(rolls)
    snap = int(np.argmax(jumps))
    assert jumps[snap] > math.radians(60.0)  # one 15° step of the clamp, a much larger turn of the tip
    energies = np.array([s.energy for s in out.steps[first - 1:]])
    assert energies[snap + 1] < energies[snap]


def test_j_tip_rotation_is_periodic(whip):
    """Turning the clamp by a full turn gives the same shape again (the same branch, lag and snap included): the
    second turn's energies and tip rolls repeat the first's, to the solve's tolerance and to 2π."""
    out, first, _ = whip
    per_turn = 24
    steps = out.steps[first:]
    energies = np.array([s.energy for s in steps])
    rolls = np.array([s.tip_roll for s in steps])
    assert np.allclose(energies[:per_turn], energies[per_turn:], rtol=1e-6, atol=1e-9)
    assert np.allclose(rolls[per_turn:] - rolls[:per_turn], 2 * math.pi, atol=1e-5)


def test_tight_bend_and_self_overlap_are_named():
    with pytest.raises(ValueError, match="bends tighter than the lumen radius near point"):
        Vessel3D.from_centreline([[0, 0, 0], [5, 0, 0], [6, 1, 0], [5, 2, 0], [0, 2, 0]], 1.5)
    coil = [[10 * math.cos(t), 10 * math.sin(t), 0.3 * t] for t in np.linspace(0, 4 * math.pi, 60)]
    with pytest.raises(ValueError, match="comes back within the lumen radius of itself"):
        Vessel3D.from_centreline(coil, 1.0)


def _arch() -> Vessel3D:
    from guidewire.vessel3d.arch import aortic_arch

    return aortic_arch("I")


@pytest.mark.parametrize("shape", ["helix", "tortuous", "arch"])
def test_piecewise_evaluation_is_scipys(shape):
    """The tube's own evaluation of its pieces gives scipy's spline and PCHIP values bit for bit (at random
    parameters, every break and both ends)."""
    vessel = {"helix": helix, "tortuous": tortuous, "arch": _arch}[shape]()
    rng = np.random.default_rng(5)
    for tube in vessel.tubes:
        u = np.concatenate((rng.uniform(0.0, tube.end, 500), tube.breaks))
        value, first, second = tube._pieces(u)
        for k, part in enumerate((value, first, second)):
            assert np.array_equal(part[:, :3], tube.spline(u, k))
            if tube.radius_curve is not None:
                assert np.array_equal(part[:, 3], tube.radius_curve(u, k))


def test_branch_row_bound_holds_and_lumen_rows_are_the_best_tube():
    """``Tube.row_bound`` (with or without a floor) is at least the row of its tube at points all over and around
    the arch's tubes, and the lumen rows (which skip a branch wherever its bound loses) are the best tube's row at
    every point no crease holds (and above it where one does: beside a crease the wire's ball stands over the
    opening)."""
    vessel = _arch()
    rng = np.random.default_rng(3)
    line = np.vstack(vessel.centrelines(0.5))
    rim = np.vstack([c.points for c in vessel.creases])  # (and beside the creases around the openings)
    p = np.vstack((line[rng.integers(0, len(line), 2000)] + rng.normal(0.0, 6.0, (2000, 3)),
                   rim[rng.integers(0, len(rim), 500)] + rng.normal(0.0, 0.5, (500, 3))))
    r = np.full(len(p), 0.35)
    rows = [tube.rows(p, r)[0] for tube in vessel.tubes]
    floor = rng.uniform(-20.0, 2.0, len(p))  # (with a floor: the bounding box's weaker bound where it is below)
    for tube, g in zip(vessel.tubes, rows, strict=True):
        assert np.all(tube.row_bound(p, r) >= g)
        assert np.all(tube.row_bound(p, r, floor) >= g)
    held = np.zeros(len(p), dtype=bool)
    for crease in vessel.creases:
        held[crease.rows(p, r).index] = True
    lumen = vessel.lumen_rows(p, r)[0]
    assert np.array_equal(lumen[~held], np.max(rows, axis=0)[~held])
    assert np.all(lumen[held] >= np.max(rows, axis=0)[held]) and held.sum() > 50


@pytest.mark.parametrize("shape", ["helix", "tortuous", "arch"])
def test_closest_ball_search_stops_at_the_maximiser(shape, monkeypatch):
    """The closest-ball search that stops a point after a Newton step below ``NEWTON_TOL`` spacings ends where the
    search that takes all its ``NEWTON_STEPS`` steps ends (``u`` to 1e-9 mm, rows to 1e-12 relative, gradients to
    1e-10: the error the early stop leaves is of the order of its last step squared), at points inside, on and
    outside the lumen of every tube (points that do not converge take the same steps in both)."""
    import guidewire.vessel3d.tube as tube_module

    vessel = {"helix": helix, "tortuous": tortuous, "arch": _arch}[shape]()
    rng = np.random.default_rng(11)
    line = np.vstack(vessel.centrelines(0.5))
    p = line[rng.integers(0, len(line), 600)] + rng.normal(0.0, 1.5, (600, 3))
    r = np.full(len(p), 0.3)
    fast = [tube.rows(p, r) for tube in vessel.tubes]
    monkeypatch.setattr(tube_module, "NEWTON_TOL", 0.0)
    full = [tube.rows(p, r) for tube in vessel.tubes]
    for (g, grad, _, e), (g_ref, grad_ref, _, e_ref) in zip(fast, full, strict=True):
        assert np.max(np.abs(e.u - e_ref.u)) < 1e-9
        assert np.max(np.abs(g - g_ref)) < 1e-12 * max(1.0, float(np.max(np.abs(g_ref))))
        assert np.max(np.abs(grad - grad_ref)) < 1e-10


def test_a_touching_tip_carries_its_force_to_the_new_tip(helix_insertion):
    """The track predictor's multipliers: where the tip presses on the wall, its lumen force goes to the new tip
    node of a pushed (or pulled) wire, and the converged next step holds the new tip's row — the guess that spares
    the step's first QP a backend. Every other node keeps its place's force."""
    from guidewire.solve3d.insert import advance, scene_at, tracked_multipliers

    vessel, wire, out = helix_insertion
    scene = Scene3D.in_vessel(wire, vessel)
    density = wire.bars / wire.length
    touching = [s for s in out.steps if s.success and s.extras["multipliers"][-1][-1] > 0.0]
    assert len(touching) >= 5
    for previous in touching[-5:]:
        before = float(np.sum(previous.lengths))
        for length in (before + 1.0, before - 1.0):
            target = scene_at(scene, length, 0.0, density)
            n = target.wire.bars
            lumen = tracked_multipliers(previous, target, n)[-1]
            old = previous.extras["multipliers"][-1]
            assert lumen[-1] == old[-1]
            keep = min(n, previous.n_bars) - 1
            assert np.array_equal(lumen[:keep], old[:keep])
        step = advance(scene, previous, before + 1.0, 0.0, density, {})
        assert step.success and step.extras["multipliers"][-1][-1] > 0.0


@pytest.mark.parametrize("pick", [0, 1, 2, 3])
def test_push_is_the_energy_rate_with_the_moment_carried_through_the_entrance(whip, helix_insertion, pick):
    """Virtual work, as in the plane: pushing ΔL more through a frictionless entrance costs ΔE, so the push is dE/dL —
    the axial force less the energy per length of the wire that enters, |M⊥|²/(2EI) + M∥²/(2GJ). Checked against
    the energy of the same chain ΔL longer (warm-started), for the straight wire in the helix and the J wire turned
    in it (its clamp twisted), where the axial force alone is off by 3-15 %."""
    import dataclasses

    from guidewire.solve3d.solve import solve3d

    out, pushed, _ = whip
    states = [helix_insertion[2].steps[-1], out.steps[pushed - 1], out.steps[pushed + 8], out.steps[pushed + 30]]
    a = states[pick]
    assert a.success
    length = float(np.sum(a.lengths))
    h = 1e-3
    wire = (helix_insertion[1] if pick == 0 else
            Wire(length=10.0, bars=20, youngs_modulus=80000.0, diameter=0.89, sections=STEVE_J))
    longer = Scene3D.in_vessel(dataclasses.replace(wire.with_length(length + h), bars=a.n_bars, bar_lengths=None),
                               helix()).with_rotation(a.base_rotation)
    b = solve3d(longer, initial_frames=a.quaternions)
    assert b.success
    rate = (b.energy - a.energy) / h
    assert a.push == pytest.approx(rate, abs=5e-3 * abs(a.entrance_force))
    assert abs(a.entrance_force - rate) > 4 * 5e-3 * abs(a.entrance_force)  # (the configurational term matters)


def test_a_smooth_tube_holds_the_wire_along_its_normal_only(helix_insertion):
    """In the helix (one smooth tube) every interior contact is normal to the wire up to the chain's discreteness
    (at 2 bars/mm the bars turn by ``l κ`` ≈ 0.02-0.05 rad): the lengthwise hold stays below 2 % of the contact
    forces (0.75 % measured), where a node row on a branch's ridge holds the wire with most of its contact force."""
    _, _, out = helix_insertion
    touching = 0
    for sol in out.steps:
        forces = [f.magnitude for f in sol.forces if f.kind == "lumen" and 0 < f.node < sol.n_bars]
        touching += len(forces)
        assert abs(sol.tangential_contact_force()) <= 0.02 * sum(forces) + 1e-12
    assert touching > 10


def test_the_wire_slides_over_a_branchs_ridge():
    """stEVE's J wire steered into the type I arch's left subclavian artery (the committed schedule, to 220 mm):
    where the wire crosses from the aorta into the branch it rests on the crease around the opening, which holds a
    bar normal to it — the contacts' lengthwise force stays below 5 mN (the tubes' node rows alone held it with
    0.79 N of its 1.19 N of contact force) and the crease's force balances."""
    from pathlib import Path

    from guidewire.solve3d.file import load_scene

    root = Path(__file__).resolve().parents[2]
    scene = load_scene(root / "guidewire" / "scenes" / "vessels3d" / "aortic_arch_I.toml")
    schedule = np.loadtxt(root / "examples" / "steer_left_subclavian.txt")
    upto = schedule[: int(np.flatnonzero(schedule[:, 0] >= 220.0)[0]) + 1]
    out = insert3d(scene, upto[:, 0], np.radians(upto[:, 1]))
    assert out.complete
    held = max(abs(s.tangential_contact_force()) for s in out.steps)
    assert held <= 5e-3
    crease = [f for s in out.steps for f in s.forces if f.kind == "crease"]
    assert len(crease) >= 3 and max(f.magnitude for f in crease) > 0.3
    for s in out.steps[-3:]:
        force, moment = s.balance()
        assert force <= 1e-6 * sum(f.magnitude for f in s.forces) and moment <= 1e-6 * 250.0 * max(
            f.magnitude for f in s.forces)
    # every bar of every step keeps its radius from every crease (the crease is on the lumen's boundary: no bar
    # passes over it closer, nor behind it through the wall), and every node is in the lumen
    for s in out.steps:
        middle = np.cumsum(s.lengths) - 0.5 * s.lengths
        radius = 0.5 * scene.wire.with_length(float(np.sum(s.lengths))).properties_at(middle).diameter
        for crease in scene.vessel.creases:
            a, b = s.nodes[:-1], s.nodes[1:]
            tau, phi = crease._segments(a, b)
            gap = np.linalg.norm(a + tau[:, None] * (b - a) - crease.spline(phi), axis=1)
            assert np.min(gap - radius) >= -1e-6
        node_radius = np.maximum(radius, np.append(radius[1:], radius[-1]))  # (as the program: the larger)
        assert scene.vessel.lumen_rows(s.nodes[1:], node_radius)[0].min() >= -1e-6


@pytest.mark.parametrize("length", [35.0, 45.0, 55.0, 65.0, 75.0])
@pytest.mark.parametrize("diameter", [0.36, 0.6])
def test_cold_solves_in_the_tortuous_vessel_converge(length, diameter):
    """From the built-in start along the centreline, in the coronary-scale tortuous vessel: where the closure rows'
    augmented-Lagrangian term leaves the Hessian indefinite (a compressed wire, held by the walls), every held row
    joins the term rather than an identity shift, which made the steps crawl (117 iterations at 45 mm, none
    converged at 60 mm); every node ends inside the lumen."""
    from guidewire.solve3d.solve import solve3d

    vessel = tortuous()
    wire = Wire(length=length, bars=int(2 * length), youngs_modulus=60000.0, diameter=diameter)
    sol = solve3d(Scene3D.in_vessel(wire, vessel))
    assert sol.success and sol.iterations <= 100
    assert vessel.lumen_rows(sol.nodes[1:], np.full(sol.n_bars, diameter / 2))[0].min() > -1e-9
    force, moment = sol.balance()
    assert force <= 1e-6 * max(1.0, sum(f.magnitude for f in sol.forces))


def test_a_refined_j_tip_keeps_its_bars_through_a_3d_insertion():
    """stEVE's J wire with its tip's bars 2.9 times finer (its 22 tip and 218 shaft beams), pushed along the helix at
    0.5 bar per refined mm: every step converged with every node in the lumen, the tip's 15.2 mm arc always within
    1.5 bars of its ``0.5 · 15.2 · 2.9 ≈ 22`` bars, and the shaft's bars within rounding of 2 mm."""
    tip = replace(STEVE_J[0], refinement=2.9)
    wire = Wire(length=20.0, bars=1, youngs_modulus=80000.0, diameter=0.89, sections=(tip,))
    wire = replace(wire, bars=wire.bars_at(20.0, 0.5))
    vessel = helix()
    lengths = np.arange(20.0, 51.0, 3.0)
    out = insert3d(Scene3D.in_vessel(wire, vessel), lengths)
    assert out.complete, out.error
    for length, sol in zip(lengths, out.steps, strict=True):
        s = np.concatenate(([0.0], np.cumsum(sol.lengths)))
        bars_in_tip = int(np.sum(s > length - tip.length + 1e-9))
        # (the step's bars are its refined length times the density rounded, ±1/2, shared by largest remainder, ±1)
        assert abs(bars_in_tip - 0.5 * tip.length * 2.9) < 1.5
        shaft = sol.lengths[: sol.n_bars - bars_in_tip]
        assert np.all(np.abs(shaft - 2.0) <= 3.0 / shaft.size)  # (2 mm · |c − c_ideal| / c, |c − c_ideal| < 1.5)
        radii = node_radii(Scene3D.in_vessel(wire.with_length(length), vessel), sol.lengths)
        clearance, _ = vessel.clearance(sol.nodes[1:], radii)
        assert clearance.min() > -1e-6
