"""Quasi-static insertion: a head-on push into a wall runs through, warm steps agree with cold solves, forces
balance, every step is data, bad input is refused; the CLI's insert command."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from guidewire import insert, paper_scenes, solve
from guidewire.chain.crossing import crossing_bars

FIG6B = paper_scenes()["fig6b"]  # clamp at O along +x, the wall x ≤ 45 straight ahead


@pytest.fixture(scope="module")
def head_on():
    return insert(FIG6B.with_wire(length=30.0, bars=30), np.arange(30.0, 101.0, 5.0))


def test_head_on_push_into_a_wall_runs_through(head_on):
    """The issue's sequence once ended every step after contact INFEASIBLE in 0 iterations with E = 0 and wall
    "forces" of 2e11 N; now every step converges to the cold solve's answer."""
    assert head_on.complete and all(s.success for s in head_on.steps)
    for sol in head_on.steps:
        cold = solve(sol.scene)
        assert sol.energy == pytest.approx(cold.energy, rel=1e-7, abs=1e-12)
        assert np.max(sol.nodes[:, 0]) <= 45.0 + 1e-9 and crossing_bars(sol.nodes) is None
    energies = [s.energy for s in head_on.steps]
    assert energies[0] == 0.0 and all(b >= a - 1e-12 for a, b in zip(energies, energies[1:], strict=False))


def test_forces_of_an_insertion_step_balance(head_on):
    sol = head_on.steps[-1]
    contacts = sol.contacts()
    assert contacts and all(c["force_n"] > 0 and c["normal"] == [1.0, 0.0] for c in contacts)
    total = sum(-c["force_n"] * np.asarray(c["normal"]) for c in contacts)
    assert np.allclose(total + sol.reactions[0].force, 0.0, atol=1e-9)  # the base balances the wall
    assert abs(sol.moment_balance()) < 1e-6
    assert sol.axial_force() > 0  # the wire is compressed against the wall
    # at 100 mm the tip slides along the wall and the energy has levelled off (1.031 N·mm): the push dE/dL is ~0
    assert sol.entrance_force() == pytest.approx(0.0, abs=1e-4 * sol.axial_force())
    assert head_on.steps[5].entrance_force() > 0.01  # 55 mm: bending up against the wall costs energy
    before_contact = head_on.steps[1]  # 35 mm: the wire has not reached the wall
    assert before_contact.contacts() == [] and before_contact.entrance_force() == pytest.approx(0.0, abs=1e-12)


def test_insertion_json_has_the_step_keys(head_on):
    data = json.loads(json.dumps(head_on.to_dict()))
    step = data["steps"][-1]
    for key in ("inserted_length", "success", "status", "message", "energy", "nodes", "contacts", "tip",
                "entrance_force_n", "iterations", "solve_time_s"):
        assert key in step
    assert data["units"]["force"] == "N" and step["inserted_length"] == 100.0 and len(step["nodes"]) == 101
    assert set(step["contacts"][0]) == {"node", "s", "point", "normal", "force_n"}


def test_bad_insertions_are_refused():
    with pytest.raises(ValueError, match="strictly increasing"):
        insert(FIG6B, [50.0, 40.0])
    with pytest.raises(ValueError, match="strictly increasing"):
        insert(FIG6B, [-1.0, 10.0])
    with pytest.raises(ValueError, match="lengths is empty"):
        insert(FIG6B, [])
    with pytest.raises(ValueError, match="bars is set by insert"):
        insert(FIG6B, [50.0], bars=10)


def test_cli_insert(tmp_path):
    scene = "guidewire/scenes/fig6b.toml"
    run = subprocess.run([sys.executable, "-m", "guidewire", "insert", scene, "--from", "40", "--to", "50",
                          "--step", "5", "--json", str(tmp_path / "ins.json")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    steps = [line for line in run.stdout.splitlines() if line.startswith("[")]
    assert [line.split("]")[0] for line in steps] == ["[1/3", "[2/3", "[3/3"]  # a line per step, as it goes
    flags = [line for line in run.stdout.splitlines() if line.lstrip().startswith("!")]
    assert all("cold re-solve" in f or "FAILED" in f or "past" in f or "push" in f or "strain" in f for f in flags)
    assert len(json.loads((tmp_path / "ins.json").read_text())["steps"]) == 3
    # outputs and sizes are checked before any work
    missing = subprocess.run([sys.executable, "-m", "guidewire", "insert", scene, "--from", "40", "--to", "50",
                              "--step", "5", "--json",
                              str(tmp_path / "no" / "ins.json")], capture_output=True, text=True)
    assert missing.returncode == 2 and "does not exist" in missing.stderr and not (tmp_path / "no").exists()
    tiny = subprocess.run([sys.executable, "-m", "guidewire", "insert", scene, "--from", "40", "--to", "50",
                           "--step", "0.0001"],
                          capture_output=True, text=True, timeout=60)
    assert tiny.returncode == 2 and "--yes" in tiny.stderr and "steps" in tiny.stderr
    bad = subprocess.run([sys.executable, "-m", "guidewire", "insert", scene, "--to", "50", "--step", "0"],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and "positive length" in bad.stderr
    gif = subprocess.run([sys.executable, "-m", "guidewire", "insert", scene, "--to", "120", "--step", "5", "--gif",
                          str(tmp_path / "a.png")], capture_output=True, text=True)
    assert gif.returncode == 2 and "not a .gif" in gif.stderr


def test_insertion_with_a_shared_model_reuse_matches_building_every_step_anew():
    """Through the bend vessel: ``insert`` with its :class:`ModelReuse` (the default) gives the shapes (to 1e-9 mm),
    energies and iteration counts of ``reuse=None``, and every step is inside the lumen without crossing bars."""
    from pathlib import Path

    import guidewire

    scene = guidewire.load_scene(Path(guidewire.__file__).parent / "scenes" / "vessels" / "bend.toml")
    start = scene.with_wire(length=5.0, bars=5)
    lengths = np.arange(5.0, 41.0, 5.0)
    kept, fresh = insert(start, lengths), insert(start, lengths, reuse=None)
    assert kept.complete and fresh.complete
    for a, b in zip(kept.steps, fresh.steps, strict=True):
        assert a.success and b.success and a.n_bars == b.n_bars
        np.testing.assert_allclose(a.nodes, b.nodes, rtol=0.0, atol=1e-9)
        assert a.energy == pytest.approx(b.energy, rel=1e-12) and a.iterations == b.iterations
        assert a.max_violation <= 1e-8  # every node inside the lumen by the wire's radius (checked at every node)
        assert np.all(scene.vessel.clearance(a.nodes[1:]).distance >= 0.5 * scene.wire.diameter - 1e-6)
        assert crossing_bars(a.nodes) is None


def test_step_flags_name_what_a_user_must_notice(monkeypatch):
    """A step that failed, needed a cold re-solve or bends beyond the strain limit is flagged; a quiet step is not.
    Fig. 6b bends its wire to a strain of 1.04 %: quiet at the 8 % limit, flagged at its node under a 0.5 % one."""
    from dataclasses import replace

    import guidewire
    from guidewire.march import insertion
    from guidewire.march.insertion import step_flags

    sol = guidewire.solve(guidewire.paper_scenes()["fig6b"])
    assert sol.success and step_flags(sol, "warm") == []
    assert any("cold re-solve" in f for f in step_flags(sol, "warm, then cold"))
    failed = replace(sol, success=False, message="The line search failed.")
    assert step_flags(failed, "warm")[0].startswith("FAILED: The line search failed.")
    monkeypatch.setattr(insertion, "STRAIN_LIMIT", 0.005)
    kink = [f for f in step_flags(sol, "warm") if "would kink" in f]
    k = int(np.argmax(sol.bending_stress_mpa))
    assert len(kink) == 1 and f"s = {sol.s[k]:.4g} mm" in kink[0]
