"""Constraint blocks: one type per kind, one sign convention in both layouts, a new kind in one class plus one
registration; what a solution records (counts, rounds, fallback, no forces from a failed solve)."""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np
import pytest

import guidewire
import guidewire.program.formulation
from guidewire import Base, Scene, Wall, Wire, formulate, paper_scenes, solve, solve_sequence
from guidewire.blocks import BLOCK_TYPES, Block, Loads, NodeRows
from guidewire.fields import SuspiciousValueWarning
from guidewire.scene.file import scene_from_dict

SCENES = paper_scenes()


def test_registry_holds_one_type_per_kind():
    assert [t.kind for t in BLOCK_TYPES] == ["position", "angle", "wall", "lumen", "relative_angle"]


@pytest.mark.parametrize(("name", "scheme", "b2"), [("table1_pi_4", "paper", 0.05), ("fig6a", "second_order", None),
                                                    ("table4", "paper", None)])
def test_both_layouts_give_the_same_multipliers(name, scheme, b2):
    """One sign convention: every block's multipliers agree between the reduced and the full-space program (the old
    code flipped the wall rows' sign between them)."""
    scene = SCENES[name].with_scheme(scheme)
    if b2 is not None:
        scene = scene.with_wire(max_relative_angle=b2)
    reduced, full = solve(scene, layout="reduced"), solve(scene, layout="full")
    assert reduced.success and full.success
    kinds = {b.kind for b in reduced.blocks}
    assert kinds == {b.kind for b in full.blocks}
    scale = max(float(np.max(np.abs(m), initial=0.0)) for m in reduced.multipliers)
    for block, lam in zip(full.blocks, full.multipliers, strict=True):
        (mine,) = [(b, m) for b, m in zip(reduced.blocks, reduced.multipliers, strict=True) if b.key == block.key]
        where = {int(k): i for i, k in enumerate(mine[0].row_keys)}
        for k, value in zip(block.row_keys, lam, strict=True):
            assert mine[1][where[int(k)]] == pytest.approx(value, abs=1e-6 * scale) if int(k) in where else \
                abs(value) <= 1e-9 * scale  # a wall row outside the reduced working set is inactive
    if b2 is not None:  # the b₂ bound is active and its multipliers carry over too
        (rb,) = [m for b, m in zip(reduced.blocks, reduced.multipliers, strict=True) if b.kind == "relative_angle"]
        assert np.max(np.abs(rb)) > 0.1
    if "wall" in kinds:
        (lam,) = [m for b, m in zip(full.blocks, full.multipliers, strict=True) if b.kind == "wall"]
        assert np.min(lam) > -1e-9 and np.max(lam) > 0  # λ ≥ 0 at the active lower bound, in both layouts


@dataclass(frozen=True)
class Floor(Block):
    """A kind the package does not have: every node above a horizontal floor, ``y_k ≥ level``, written as one class
    (rows linear in the node positions, the push ``λ d`` on the node) — as a lumen kind would be."""

    kind: ClassVar[str] = "floor"
    level: ClassVar[float] = -5.0

    @classmethod
    def build(cls, model, working_set=None):
        return [cls((0,), np.arange(1, model.n + 1))]

    def rows(self, model):
        m = self.size
        return NodeRows(self.nodes, np.tile([0.0, 1.0], (m, 1)), np.full(m, self.level), np.full(m, np.inf))

    def add_loads(self, model, lam, loads: Loads, points):
        np.add.at(loads.node_forces, self.nodes, np.asarray(lam)[:, None] * np.array([0.0, 1.0]))


@pytest.mark.parametrize("layout", ["reduced", "full"])
def test_a_new_kind_is_one_class_and_one_registration(monkeypatch, layout):
    """Registering ``Floor`` (one line) makes both layouts, the solve pipeline and the reactions use it; it gives the
    same answer as the equivalent wall ``−y ≤ 5``."""
    clamped = Scene(Wire(60.0, 30), Base((0.0, 0.0), -0.6))  # clamped pointing down: the free wire crosses y = -5
    walled = solve(replace(clamped, walls=(Wall((0.0, -1.0), 5.0),)), layout=layout)
    monkeypatch.setattr(guidewire.program.formulation, "BLOCK_TYPES", (*BLOCK_TYPES, Floor))
    floored = solve(clamped, layout=layout)
    assert walled.success and floored.success, (walled.message, floored.message)
    assert [b.kind for b in floored.blocks] == ["floor"]
    assert floored.energy == pytest.approx(walled.energy, rel=1e-8) and floored.energy > 0.01
    np.testing.assert_allclose(floored.nodes, walled.nodes, atol=1e-6)
    assert np.min(floored.nodes[:, 1]) >= -5.0 - 1e-9
    np.testing.assert_allclose(floored.wall_forces, walled.wall_forces, atol=1e-6 * np.abs(walled.wall_forces).max())
    assert abs(floored.moment_balance()) < 1e-6


def test_failed_solve_reports_no_forces_and_counts_every_run():
    sol = solve(SCENES["fig6b"], max_iter=1)
    assert not sol.success and sol.fallback is None
    assert sol.rounds == 2 and sol.iterations == 2  # the exact-Hessian run and the damped-BFGS retry, one each
    assert "damped BFGS retry failed too" in sol.message
    assert sol.wall_forces is None and all(r.force is None and r.moment is None for r in sol.reactions)
    assert np.isnan(sol.moment_balance())
    data = json.loads(json.dumps(sol.to_dict()))
    assert data["wall_forces"] is None and data["base_reaction"]["force"] is None


def test_iterations_cover_every_working_set_round():
    """From a curled start Fig. 6b's wall working set misses the nodes that end up on the wall, so a second round is
    needed: the reported iterations are the sum over the rounds, as the reported time is."""
    scene = SCENES["fig6b"]
    sol = solve(scene, initial_angles=np.linspace(0.0, 3.0, scene.wire.bars))
    assert sol.success and sol.fallback is None
    assert sol.rounds == 2 and sol.iterations > sol.result.nit
    assert sol.energy == pytest.approx(solve(scene).energy, rel=1e-8)


def test_warm_start_from_a_solution():
    scene = SCENES["fig6b"]
    cold = solve(scene)
    warm = solve(scene, initial_angles=cold.bar_angles, multipliers0=cold)
    assert warm.success and warm.iterations <= 1 < cold.iterations
    assert warm.energy == pytest.approx(cold.energy, rel=1e-10)
    with pytest.raises(ValueError, match="multipliers0 must be a Solution or 1 arrays"):
        solve(scene, multipliers0=[np.zeros(3), np.zeros(2)])


def test_sequence_keeps_the_solved_steps_when_one_is_refused():
    scene = SCENES["table1_pi_4"]
    far = replace(scene, contacts=(replace(scene.contacts[0], point=(500.0, 0.0)),))
    out = solve_sequence([scene, far, scene])
    assert len(out) == 1 and out[0].success and not out.complete
    assert out.failed_step == 1 and "500.00 mm apart" in out.error
    assert out.status is guidewire.Status.SCENE_REFUSED


def test_runs_of_steps_report_one_status():
    """Solve, insertion, sequence and batch results all carry a :class:`guidewire.Status`: SUCCESS when every step
    converged, a failed step's own status, SCENE_REFUSED for a scene refused before solving."""
    scene = SCENES["table1_pi_4"]
    assert solve_sequence([scene, scene]).status is guidewire.Status.SUCCESS
    failing = solve_sequence([scene], max_iter=1)
    assert not failing[0].success and failing.status == failing[0].status == guidewire.Status.MAX_ITER
    far = replace(scene, contacts=(replace(scene.contacts[0], point=(500.0, 0.0)),))
    refused = guidewire.solve_many([far], workers=1, progress=False)[0]
    assert refused.status is guidewire.Status.SCENE_REFUSED and not refused.success


def test_json_carries_units_and_the_scene():
    sol = solve(SCENES["fig6b"])
    data = json.loads(json.dumps(sol.to_dict()))
    assert scene_from_dict(data["scene"]) == sol.scene
    assert data["units"]["moment"] == "N*mm" and data["layout"] == "reduced"


def test_suspicious_units_warn_naming_the_field():
    with pytest.warns(SuspiciousValueWarning, match="wire.youngs_modulus is 3.56 MPa.*3560 MPa"):
        Wire(100.0, 10, youngs_modulus=3.56)
    with pytest.warns(SuspiciousValueWarning, match="base.angle is 90 rad.*1.5708 rad"):
        Base((0.0, 0.0), 90.0)


def test_formulate_is_public_and_leaves_out_what_the_scene_does_not_need():
    form = formulate(SCENES["fig6b"], layout="full")
    assert [b.kind for b in form.blocks] == ["wall"] and form.size == 3 * form.n
    assert len(form.constraints) == 2  # the closure and the wall
