"""3-D scene files and the command line on them: which files are 3-D, the shipped 3-D scenes, named errors, and
``insert`` with a push/turn schedule writing JSON (3-D points, frames, energy split, torque) and figures."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import guidewire
from guidewire.app.cli import main
from guidewire.solve3d import Scene3D
from guidewire.solve3d.file import load_scene

SCENES = Path(guidewire.__file__).parent / "scenes"


def test_shipped_3d_scenes_load_as_3d_and_planar_files_stay_planar():
    for path in sorted((SCENES / "vessels3d").glob("*.toml")):
        scene = load_scene(path)
        assert isinstance(scene, Scene3D), path
        assert scene.vessel is not None
    for path in sorted((SCENES / "vessels").glob("*.toml")):
        assert isinstance(load_scene(path), guidewire.Scene), path


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


WIRE = "[wire]\nlength = 20.0\nbars = 20\nyoungs_modulus = 60000.0\ndiameter = 0.36\n"


@pytest.mark.parametrize(("vessel", "match"), [
    ('shape = "helix"\ncentreline = [[0.0, 0.0, 0.0], [9.0, 0.0, 0.0]]\nradius = 1.0', "exactly one of"),
    ('shape = "spiral"', "choose one of"),
    ('centreline = [[0.0, 0.0, 0.0], [9.0, 0.0, 0.0]]\nradius = -1.0', "radius"),
    ('shape = "helix"\n[vessel.parameters]\nturns = "two"', "helix"),
])
def test_bad_3d_vessels_are_named(tmp_path, vessel, match):
    path = _write(tmp_path, WIRE + "[vessel]\n" + vessel + "\n")
    with pytest.raises(ValueError, match=match):
        load_scene(path)


def test_insert_with_a_schedule_writes_3d_json_and_figures(tmp_path, capsys):
    schedule = tmp_path / "steps.txt"
    schedule.write_text("# length_mm rotation_deg\n20 0\n24 0\n24 45\n26, 90\n")
    out_json, out_png = tmp_path / "ins.json", tmp_path / "ins.png"
    code = main(["insert", str(SCENES / "vessels3d" / "helix_j.toml"), "--schedule", str(schedule),
                 "--json", str(out_json), "--plot", str(out_png)])
    assert code == 0
    printed = capsys.readouterr().out
    assert printed.count("\n[") + printed.startswith("[") == 4
    data = json.loads(out_json.read_text())
    assert data["complete"]
    steps = data["steps"]
    assert [round(s["rotation"], 9) for s in steps] == [0.0, 0.0, round(math.radians(45), 9),
                                                        round(math.radians(90), 9)]
    last = steps[-1]
    assert np.asarray(last["nodes"]).shape[1] == 3
    assert np.asarray(last["frames"]).shape[1:] == (3, 3)
    assert last["energy"] == pytest.approx(last["bending_energy"] + last["twist_energy"])
    assert {"entrance_force_n", "entrance_torque_nmm", "tip"} <= set(last)
    assert set(last["tip"]) >= {"point", "direction", "roll"}
    assert out_png.stat().st_size > 10_000


@pytest.mark.parametrize(("line", "why"), [("20", "line 1"), ("-3 0", "line 1"), ("20 zero", "line 1")])
def test_malformed_schedule_exits_2_naming_the_line(tmp_path, capsys, line, why):
    schedule = tmp_path / "steps.txt"
    schedule.write_text(line + "\n")
    code = main(["insert", str(SCENES / "vessels3d" / "helix_j.toml"), "--schedule", str(schedule)])
    assert code == 2
    assert why in capsys.readouterr().err


def test_rotation_of_a_planar_scene_exits_2(capsys):
    code = main(["insert", str(SCENES / "vessels" / "bend.toml"), "--to", "45", "--step", "5", "--rotate", "3"])
    assert code == 2
    assert "planar" in capsys.readouterr().err


def test_solve_writes_an_interactive_html_view(tmp_path, capsys):
    pytest.importorskip("plotly")
    page = tmp_path / "view.html"
    code = main(["solve", str(SCENES / "vessels3d" / "s_bend_3d.toml"), "--html", str(page)])
    assert code == 0
    text = page.read_text()
    assert "plotly" in text.lower() and "s_bend_3d" in text
    assert "converged" in capsys.readouterr().out


def test_a_vtp_scene_without_vtk_exits_2_with_the_install_command(monkeypatch, capsys):
    """A new user without the [vtk] extra gets one line saying how to install it, not a traceback."""
    import sys

    monkeypatch.setitem(sys.modules, "vtkmodules", None)
    code = main(["solve", str(SCENES / "vessels3d" / "arch_from_vtp.toml")])
    assert code == 2
    assert "pip install" in capsys.readouterr().err
