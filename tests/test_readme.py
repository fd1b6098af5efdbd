"""The README's Python snippets run as printed (from the repository root, each in a fresh interpreter), and its
shell commands name options the command line has."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
SNIPPETS = re.findall(r"```python\n(.*?)```", README, re.S)


def test_the_readme_has_its_six_tasks_and_links_that_exist():
    tasks = ("Solve a scene", "Insert a wire", "Write your own vessel", "Batch many scenes", "in place of SLSQP",
             "A 3-D wire")
    for heading in tasks:
        assert heading in README
    for link in re.findall(r"\]\(((?:docs)/[^)#]+)\)", README):
        assert (ROOT / link).is_file(), link
    assert 'pip install -e ".[dev,plot]"' in README and "python -m pytest" in README  # what .ci/run runs


@pytest.mark.parametrize("index", range(len(SNIPPETS)))
def test_a_readme_snippet_runs_as_printed(index):
    code = SNIPPETS[index]
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    # the values a snippet's comments promise are the values it prints
    for line in code.splitlines():
        promise = re.search(r"print\(.*\)\s+# (True [^(:]*)", line)
        if promise:
            assert promise.group(1).split()[1] in done.stdout, (promise.group(1), done.stdout)


def test_the_readme_toml_is_a_scene_that_solves(tmp_path):
    import guidewire

    toml = re.findall(r"```toml\n(.*?)```", README, re.S)
    assert len(toml) == 2
    path = tmp_path / "mine.toml"
    path.write_text(toml[0])
    sol = guidewire.solve(guidewire.load_scene(path))
    assert sol.success, sol.message
    assert sol.scene.vessel is not None and len(sol.contacts()) > 0


def test_the_readme_3d_toml_is_a_3d_scene_that_solves(tmp_path):
    import guidewire

    path = tmp_path / "mine3d.toml"
    path.write_text(re.findall(r"```toml\n(.*?)```", README, re.S)[1])
    scene = guidewire.load_scene(path)
    assert isinstance(scene, guidewire.Scene3D) and len(scene.vessel.branches) == 1
    sol = guidewire.solve3d(scene)
    assert sol.success, sol.message
    clearance, _ = scene.vessel.clearance(sol.nodes[1:], scene.wire.diameter / 2)
    assert clearance.min() > -1e-6


def test_the_readme_commands_use_options_the_cli_has():
    from guidewire.app.cli import build_parser

    parser = build_parser()
    for command in re.findall(r"^python -m guidewire (.+)$", README, re.M):
        words = command.split()
        options = [w for w in words if w.startswith("--")]
        sub = parser._subparsers._group_actions[0].choices[words[0]]  # (argparse has no public lookup)
        known = {o for action in sub._actions for o in action.option_strings}
        assert set(options) <= known, (command, set(options) - known)
