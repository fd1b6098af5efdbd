"""``layout="auto"`` keeps contact scenes in the reduced program at every n (the engine's structured KKT solve,
:mod:`sqp.structured`), and the answer is the full-space program's."""

from __future__ import annotations

import pytest

import guidewire
from guidewire.solve.options import FULL_SPACE_BARS, choose_layout

SCENES = guidewire.paper_scenes()


def test_contact_scenes_stay_reduced_and_wall_scenes_go_full_above_the_limit():
    big = 4 * FULL_SPACE_BARS
    assert choose_layout(big, "exact", SCENES["table2_pi_4"]) == "reduced"
    assert choose_layout(big, "exact", SCENES["fig6a"]) == "full"
    assert choose_layout(FULL_SPACE_BARS, "exact", SCENES["fig6a"]) == "reduced"
    assert choose_layout(big, "bfgs", SCENES["fig6a"]) == "reduced"


@pytest.mark.parametrize("name", ["table1_pi_4", "table2_pi_4"])
def test_a_large_contact_scene_takes_newton_steps_in_the_reduced_program_to_the_full_space_answer(name):
    scene = SCENES[name]
    bars = 2 * FULL_SPACE_BARS  # above sqp.DENSE_LIMIT: a sparse, indefinite model Hessian
    sol = guidewire.solve(scene, bars=bars)
    assert sol.success and sol.layout == "reduced" and sol.result.x.size == bars
    assert sol.iterations <= 5  # Newton's step, not a shifted Hessian's (14 iterations at 1000 bars before)
    assert any(rec.qp_status == "kkt" for rec in sol.result.history)
    full = guidewire.solve(scene, bars=bars, layout="full")
    assert full.success
    # both stop at tol = 1e-8; the full space's closure rows leave its energy 2e-9 relative off
    assert sol.energy == pytest.approx(full.energy, rel=1e-8)
    assert abs(sol.nodes - full.nodes).max() < 1e-5  # mm
