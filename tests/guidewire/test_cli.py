"""``python -m guidewire``: exit statuses 0/1/2, the JSON it writes, one clear line on bad input, the paper run."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from guidewire import cli, reproduction
from guidewire.paper import paper_scenes, scene_path

REQUIRED = {"success", "status", "message", "energy", "nodes", "s", "tangent_angles", "bending_stress_mpa",
            "contact_reactions", "iterations", "solve_time_s", "max_violation"}


def test_solve_success_writes_json_and_plot(tmp_path, capsys):
    out, png = tmp_path / "sol.json", tmp_path / "sol.png"
    code = cli.main(["solve", str(scene_path("table1_pi_4")), "--json", str(out), "--plot", str(png), "--reference"])
    assert code == 0
    data = json.loads(out.read_text())
    assert REQUIRED <= set(data) and data["success"] is True and data["status"] == 0
    assert data["energy"] == pytest.approx(4.5533, abs=1e-3)
    assert png.stat().st_size > 10_000
    printed = capsys.readouterr().out
    assert "energy" in printed and "converged" in printed


def test_solve_options_bars_and_scheme(tmp_path):
    out = tmp_path / "sol.json"
    args = ["solve", str(scene_path("table1_pi_4")), "--bars", "40", "--scheme", "paper", "--json", str(out)]
    assert cli.main(args) == 0
    data = json.loads(out.read_text())
    assert data["bars"] == 40 and data["scheme"] == "paper" and len(data["nodes"]) == 41


def test_not_converged_exits_1_and_still_writes_json(tmp_path):
    out = tmp_path / "sol.json"
    assert cli.main(["solve", str(scene_path("table1_pi_4")), "--max-iter", "1", "--json", str(out)]) == 1
    data = json.loads(out.read_text())
    assert data["success"] is False and data["status"] == 1 and "iteration" in data["message"]


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["solve", "missing.toml"], "no such scene file"),
        (["solve", "TABLE5"], "22.80 mm apart with only 21.0 mm of wire"),
        (["solve", "BAD"], "wire.length"),
        (["solve", "TABLE1", "--bars", "0"], "--bars"),
        (["solve", "TABLE1", "--scheme", "third"], "--scheme"),
        (["frobnicate"], "invalid choice"),
        ([], "required"),
    ],
)
def test_bad_input_exits_2_with_one_line(tmp_path, capsys, args, words):
    bad = tmp_path / "bad.toml"
    bad.write_text("[wire]\nlength = -1\nbars = 3\n[base]\npoint = [0, 0]\n")
    paths = {"TABLE5": str(scene_path("table5")), "BAD": str(bad), "TABLE1": str(scene_path("table1_pi_4"))}
    assert cli.main([paths.get(a, a) for a in args]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err and "Traceback" not in err


def test_module_entry_point_runs_without_traceback(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "guidewire", "solve", str(scene_path("table5"))], capture_output=True, text=True
    )
    assert proc.returncode == 2
    assert proc.stderr.strip().startswith("error:") and "Traceback" not in proc.stderr


def test_paper_run_writes_tables_and_figures_and_reports_table5(tmp_path, monkeypatch, capsys):
    scenes = paper_scenes()
    small = {"fig4": (scenes["table1_pi_4"],), "fig13": (scenes["table4"], scenes["table5"])}
    monkeypatch.setattr(reproduction, "paper_groups", lambda: small)
    assert cli.main(["paper", "--out", str(tmp_path), "--qp-solver", "daqp"]) == 0
    table = (tmp_path / "paper_results.md").read_text()
    assert "22.80 mm apart with only 21.0 mm of wire" in table and "infeasible" in table
    rows = (tmp_path / "paper_results.csv").read_text().splitlines()
    assert len(rows) == 1 + 2 * 2 + 1  # header, two scenes × two schemes, Table 5
    assert (tmp_path / "fig4.png").stat().st_size > 10_000 and (tmp_path / "fig13.png").exists()
    assert "table5" in capsys.readouterr().out
