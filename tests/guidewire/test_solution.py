"""The Solution value: fields, units, JSON, starts supplied by the user, failures as data, unequal bars."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import sqp
from guidewire import Solution, paper_scenes, solve

SCENES = paper_scenes()


@pytest.fixture(scope="module")
def table2():
    return solve(SCENES["table2_pi_4"])


def test_fields_have_the_documented_shapes_and_meaning(table2):
    sol = table2
    n = sol.n_bars
    assert isinstance(sol, Solution) and sol.success and sol.status == 0 and sol.scheme == "second_order"
    assert sol.nodes.shape == (n + 1, 2) and sol.s.shape == (n + 1,) and sol.bar_angles.shape == (n,)
    for arr in (sol.tangent_angles, sol.relative_angles, sol.curvature, sol.bending_stress_mpa):
        assert arr.shape == (n + 1,)
    assert sol.nodes[0] == pytest.approx([0.0, 0.0]) and sol.s[-1] == pytest.approx(100.0)
    c, b = sol.reactions[1], sol.reactions[2]  # contacts C (s = 50) and B (s = 100)
    assert sol.nodes[c.node] == pytest.approx([30.0, 20.0], abs=1e-9) and c.node == 50
    assert sol.tangent_angles[[0, 50, 100]] == pytest.approx([0.0, math.pi / 4, 0.0])
    interior = np.setdiff1d(np.arange(1, n), [50])
    assert np.allclose(sol.tangent_angles[interior], 0.5 * (sol.bar_angles[interior - 1] + sol.bar_angles[interior]))
    wire = sol.scene.wire
    assert np.allclose(sol.bending_stress_mpa, wire.youngs_modulus * wire.diameter / 2 * np.abs(sol.curvature))
    assert np.allclose(sol.paper_stress_measure, np.abs(sol.relative_angles))
    assert sol.max_violation < 1e-9 and sol.iterations > 0 and sol.solve_time_s > 0
    assert sol.energy == pytest.approx(sol.result.fun)
    assert b.force is not None and b.moment is not None and sol.reactions[0].kind == "base"


def test_curvature_integrates_to_the_energy(table2):
    """E = Σ EI/2 κ² w over the joints: w = 1 mm at ordinary joints, 0.5 mm at the half joints of the clamp, of B
    and on each side of C (where the reported κ is the larger side's)."""
    sol = table2
    ei = sol.scene.wire.bending_stiffness
    w = np.ones(sol.n_bars + 1)
    w[[0, 100]] = 0.5
    regular = np.setdiff1d(np.arange(sol.n_bars + 1), [50])
    rest = sol.energy - np.sum(0.5 * ei * sol.curvature[regular] ** 2 * w[regular])
    at_c = 0.5 * ei * sol.curvature[50] ** 2 * 0.5  # the larger half joint at C
    assert at_c * (1 - 1e-9) <= rest <= 2 * at_c * (1 + 1e-9)


def test_to_dict_is_json_with_the_required_keys(table2):
    data = json.loads(json.dumps(table2.to_dict()))
    required = {"success", "status", "message", "energy", "nodes", "s", "tangent_angles", "bending_stress_mpa",
                "contact_reactions", "iterations", "solve_time_s", "max_violation"}
    assert required <= set(data)
    assert len(data["nodes"]) == 101 and data["base_reaction"]["kind"] == "base"
    assert [r["kind"] for r in data["contact_reactions"]] == ["contact", "contact"]
    assert data["units"]["length"] == "mm" and data["units"]["force"] == "N"
    assert data["scene"]["contact"][0]["point"] == [30.0, 20.0] and data["scene"]["wire"]["length"] == 100.0
    assert data["bars"] == 100 and data["layout"] == "reduced" and data["rounds"] == 1 and data["fallback"] is None
    assert data["starts"] == table2.starts == 1


def test_iteration_limit_is_a_result_not_an_exception():
    sol = solve(SCENES["table1_pi_4"], max_iter=1)
    assert not sol.success and sol.status == sqp.Status.MAX_ITER.code and "iteration" in sol.message


def test_user_supplied_starts(table2):
    again = solve(SCENES["table2_pi_4"], initial_nodes=table2.nodes)
    assert again.success and again.iterations <= 2
    assert again.energy == pytest.approx(table2.energy, rel=1e-10)
    also = solve(SCENES["table2_pi_4"], initial_angles=table2.bar_angles, qp_solver="daqp")
    assert also.success and np.allclose(also.nodes, table2.nodes, atol=1e-7)


def test_contacts_off_the_uniform_grid_are_nodes_exactly():
    """n = 99 on L = 100: C at s = 50 is not a multiple of L/n; the bars are re-shared, C stays exact."""
    sol = solve(SCENES["table2_pi_4"], bars=99)
    assert sol.success
    c = sol.reactions[1]
    assert sol.s[c.node] == pytest.approx(50.0, abs=1e-12)
    assert sol.nodes[c.node] == pytest.approx([30.0, 20.0], abs=1e-9)
    lengths = np.diff(sol.s)
    assert lengths.size == 99 and np.ptp(lengths[: c.node]) < 1e-12 and np.ptp(lengths[c.node :]) < 1e-12


def test_relative_angle_bound_b2_is_honoured():
    scene = SCENES["table1_pi_4"].with_wire(max_relative_angle=0.045)
    free = solve(SCENES["table1_pi_4"])
    assert np.abs(free.relative_angles).max() > 0.045  # the bound is active ...
    sol = solve(scene)
    assert sol.success, sol.message
    assert np.abs(sol.relative_angles).max() <= 0.045 + 1e-9  # ... and honoured
    assert sol.energy > free.energy


def test_infeasible_scene_raises_before_solving():
    with pytest.raises(ValueError, match="22.80 mm apart"):
        solve(SCENES["table5"])
    with pytest.raises(TypeError, match="guidewire.Scene"):
        solve("table1.toml")
