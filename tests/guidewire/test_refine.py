"""solve(tol_mm=...): curvature-graded pairs (default) or doubled uniform layouts, with an honest Richardson estimate of
the mean node error (issue 14, part 4)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from guidewire import paper_scenes, solve
from guidewire.app import cli
from guidewire.chain.kinematics import scene_bars
from guidewire.reference import continuum_reference
from guidewire.reference.scene_reference import node_errors
from guidewire.scene.paper import scene_path

SCENES = paper_scenes()
WITH_REFERENCE = [name for name in SCENES if name != "table5"]


@pytest.mark.parametrize("name", WITH_REFERENCE)
def test_tol_mm_is_met_and_its_estimate_is_honest_against_the_continuum(name):
    reference, why = continuum_reference(SCENES[name])
    assert reference is not None, why
    sol = solve(SCENES[name], tol_mm=0.01)
    assert sol.success and sol.error_estimate_mm <= 0.01
    true = float(np.mean(node_errors(sol, reference)))
    assert true < 0.01
    assert 0.5 * sol.error_estimate_mm <= true <= 2.0 * sol.error_estimate_mm


@pytest.mark.parametrize("name", ["table1_pi_4", "table4"])
def test_tol_mm_with_uniform_doubling_is_still_honoured_and_graded_pairs_use_fewer_bars(name):
    reference, _ = continuum_reference(SCENES[name])
    uniform = solve(SCENES[name], tol_mm=0.01, density="uniform")
    graded = solve(SCENES[name], tol_mm=0.01)
    assert uniform.n_bars in (40, 80, 160)
    np.testing.assert_allclose(np.diff(uniform.s), scene_bars(SCENES[name].with_bars(uniform.n_bars))[0])
    true = float(np.mean(node_errors(uniform, reference)))
    assert true < 0.01 and 0.5 * uniform.error_estimate_mm <= true <= 2.0 * uniform.error_estimate_mm
    assert graded.n_bars < uniform.n_bars


def test_tol_mm_refuses_a_fixed_bar_count():
    with pytest.raises(ValueError, match="tol_mm"):
        solve(SCENES["table1_pi_4"], tol_mm=0.01, bars=40)


def test_tol_mm_from_the_cli(tmp_path, capsys):
    out = tmp_path / "s.json"
    assert cli.main(["solve", str(scene_path("j_tip")), "--tol-mm", "0.01", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["error_estimate_mm"] <= 0.01 and data["bars"] == len(data["bar_lengths"])
    assert "estimated mean node error" in capsys.readouterr().out


def test_density_from_the_cli(tmp_path):
    out = tmp_path / "g.json"
    assert cli.main(["solve", str(scene_path("table4")), "--bars", "30", "--density", "curvature",
                     "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["bars"] == 30 and np.ptp(data["bar_lengths"]) > 0.1
