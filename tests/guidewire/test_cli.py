"""``python -m guidewire``: exit statuses 0/1/2, the JSON it writes, one clear line on bad input, the paper run."""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys

import pytest

import sqp
from guidewire.app import cli, reproduction
from guidewire.scene.paper import paper_scenes, scene_path
from sqp import installed_solvers
from sqp.backends import auto_choice
from sqp.hessian import DENSE_LIMIT

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
    assert data["success"] is False and data["status"] == sqp.Status.MAX_ITER.code and "iteration" in data["message"]


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


POSITION_ONLY = """name = "position_only"
[wire]
length = 100.0
bars = 30
[base]
point = [0.0, 0.0]
angle = 0.0
[[contact]]
s = 100.0
point = [60.0, 40.0]
"""


@pytest.fixture
def solve_calls(monkeypatch):
    """Record the ``qp_solver`` every ``guidewire.solve`` call from the CLI gets (the real solve still runs)."""
    module = importlib.import_module("guidewire.solve")
    real, calls = module.solve, []

    def recording(scene, **kwargs):
        calls.append(kwargs.get("qp_solver"))
        return real(scene, **kwargs)

    monkeypatch.setattr(module, "solve", recording)
    return calls


def test_reference_without_a_continuum_reference_says_why(tmp_path, capsys):
    scene, png = tmp_path / "position_only.toml", tmp_path / "out.png"
    scene.write_text(POSITION_ONLY)
    assert cli.main(["solve", str(scene), "--plot", str(png), "--reference"]) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no continuum reference drawn for scene 'position_only'" in err
    assert "has no angle" in err and "fully clamped contacts" in err  # the reason: a contact without an angle
    assert png.stat().st_size > 10_000  # the figure is still written


def test_reference_note_only_when_nothing_is_drawn(tmp_path, capsys):
    png = tmp_path / "out.png"
    assert cli.main(["solve", str(scene_path("table1_pi_4")), "--plot", str(png), "--reference"]) == 0
    assert capsys.readouterr().err == ""
    assert cli.main(["solve", str(scene_path("table1_pi_4")), "--reference"]) == 0
    assert "--reference only draws into --plot" in capsys.readouterr().err


@pytest.mark.parametrize(("name", "words"), [("out.jpg2", "file type '.jpg2'"), ("out", "no file extension")])
def test_plot_file_type_is_checked_before_solving(tmp_path, capsys, solve_calls, name, words):
    target = tmp_path / name
    assert cli.main(["solve", str(scene_path("table1_pi_4")), "--plot", str(target)]) == 2
    captured = capsys.readouterr()
    assert solve_calls == [] and captured.out == "" and not target.exists()
    assert captured.err.count("\n") == 1 and "argument --plot" in captured.err and words in captured.err
    assert ".png" in captured.err and ".pdf" in captured.err and "Traceback" not in captured.err


def test_plot_file_type_from_the_extension_any_case(tmp_path):
    target = tmp_path / "out.SVG"
    assert cli.main(["solve", str(scene_path("table1_pi_4")), "--plot", str(target)]) == 0
    assert target.read_text().lstrip().startswith("<?xml")


def _run_with_stdout_closed(args, *, unbuffered):
    """Run ``python -m guidewire ARGS`` with a stdout pipe whose reader closes before anything is written."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    if unbuffered:
        env["PYTHONUNBUFFERED"] = "1"
    proc = subprocess.Popen([sys.executable, "-m", "guidewire", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=env)
    proc.stdout.close()  # the reader is gone (like `| head` after its lines) before the child prints
    err = proc.stderr.read().decode()
    proc.stderr.close()
    return proc.wait(timeout=120), err


def test_closed_stdout_pipe_after_the_run_exits_quietly_with_its_status(tmp_path):
    out = tmp_path / "sol.json"
    code, err = _run_with_stdout_closed(["solve", str(scene_path("table1_pi_4")), "--json", str(out)],
                                        unbuffered=False)
    assert err == ""  # no BrokenPipeError traceback, no "Exception ignored" at exit
    assert code == 0 and json.loads(out.read_text())["success"] is True  # the run had finished


def test_closed_stdout_pipe_mid_run_exits_quietly_with_1():
    code, err = _run_with_stdout_closed(["solve", str(scene_path("table1_pi_4")), "--verbose"], unbuffered=True)
    assert err == "" and code == 1  # the first line of the iteration table hit the closed pipe


@pytest.mark.parametrize("command", ["solve", "paper"])
def test_qp_solver_help_describes_the_automatic_choice(capsys, command):
    with pytest.raises(SystemExit) as stop:
        cli.build_parser().parse_args([command, "--help"])
    assert stop.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "'auto' (default) picks DAQP up to 300 variables, PIQP for larger programs whose rows are all sparse, " \
           "DAQP again for larger programs with dense rows" in text
    # (the text is the engine's rule: the three choices it names are the ones sqp makes)
    choices = [auto_choice(n, sparse, ["daqp", "piqp", "clarabel"])[0] for n, sparse in
               ((DENSE_LIMIT, True), (DENSE_LIMIT + 1, True), (DENSE_LIMIT + 1, False))]
    assert choices == ["daqp", "piqp", "daqp"]
    assert all(name in text for name in installed_solvers())


def test_qp_solver_auto_is_the_default_and_every_installed_backend_is_accepted(solve_calls, monkeypatch):
    scene = str(scene_path("table1_pi_4"))
    assert cli.main(["solve", scene]) == 0 and cli.main(["solve", scene, "--qp-solver", "auto"]) == 0
    assert solve_calls == [None, None]  # "auto" is guidewire.solve's own automatic choice
    assert cli.main(["solve", scene, "--qp-solver", "clarabel"]) == 0 and solve_calls[-1] == "clarabel"
    for name in installed_solvers():
        assert cli.build_parser().parse_args(["solve", scene, "--qp-solver", name]).qp_solver == name
    seen = []
    monkeypatch.setattr(reproduction, "reproduce", lambda out, qp_solver, figures: seen.append(qp_solver) or [])
    assert cli.main(["paper", "--out", "unused", "--no-figures"]) == 0
    assert cli.main(["paper", "--out", "unused", "--no-figures", "--qp-solver", "daqp"]) == 0
    assert seen == [None, "daqp"]


def test_unknown_qp_solver_exits_2_before_solving(capsys, solve_calls):
    assert cli.main(["solve", str(scene_path("table1_pi_4")), "--qp-solver", "gurobi-ish"]) == 2
    err = capsys.readouterr().err
    assert solve_calls == [] and err.count("\n") == 1
    assert "--qp-solver" in err and "'gurobi-ish'" in err and "'auto'" in err
