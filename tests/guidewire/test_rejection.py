"""A rejected shape says which block, which node, its arc length and by how much."""

from __future__ import annotations

import re
from importlib import resources

import numpy as np
import pytest

import guidewire
from guidewire.solve.result import shape_defect

VESSELS = resources.files("guidewire") / "scenes" / "vessels"


@pytest.mark.parametrize("name", ["bend.toml", "tortuous.toml", "s_bend.toml", "s_bend_branch.toml"])
def test_a_node_pushed_out_of_the_lumen_is_named_with_its_excess(name):
    """Bend the solved wire at a random joint by a random angle: the message names the lumen, the node that is
    farthest outside (found here from the vessel's own clearance) and its excess in mm."""
    scene = guidewire.load_scene(str(VESSELS / name))
    sol = guidewire.solve(scene)
    assert sol.success, sol.message
    form = guidewire.formulate(scene)
    rng = np.random.default_rng(len(name))
    checked = 0
    for _ in range(5):
        phi = sol.bar_angles.copy()
        joint = int(rng.integers(phi.size // 3, phi.size - 2))
        phi[joint:] += rng.choice([-1.0, 1.0]) * rng.uniform(0.2, 0.5)
        nodes = form.model.chain.nodes(phi)
        lumen = next(b for b in form.blocks if b.kind == "lumen")
        excess = lumen.violation(form.model, phi, nodes)
        if excess.max() <= 1e-3:
            continue
        node = int(np.argmax(excess)) + 1
        message = shape_defect(form, phi, nodes, form.max_violation(phi, nodes), 1e-8)
        assert message is not None and message.startswith("the lumen"), message
        found = re.search(r"node (\d+) \(s = ([0-9.]+) mm\) by ([0-9.e+-]+) mm", message)
        assert found, message
        assert int(found.group(1)) == node
        assert float(found.group(2)) == pytest.approx(sol.s[node], rel=1e-3)
        assert float(found.group(3)) == pytest.approx(excess.max(), rel=1e-2)
        checked += 1
    assert checked >= 3  # (a kink too small to leave the lumen is skipped, not passed)


def test_a_violation_is_always_named_by_its_block_even_when_not_a_number():
    """``max_violation`` is ``worst_violation``'s amount, so a rejection always names a block, node and arc length
    (never "a constraint is violated by X"): a NaN node position counts as an infinite violation of the wall."""
    form = guidewire.formulate(guidewire.paper_scenes()["fig6b"])
    for bad in (3, form.n // 2, form.n - 1):
        phi = form.x0.copy()
        phi[bad] = np.nan
        nodes = form.model.chain.nodes(phi)
        amount, block, node = form.worst_violation(phi, nodes)
        assert amount == form.max_violation(phi, nodes) == np.inf
        assert block is not None and block.kind == "wall" and node == bad + 1
        message = shape_defect(form, phi, nodes, form.max_violation(phi, nodes), 1e-8)
        assert message.startswith(f"the wall 0 (the wire beyond it) is violated at node {bad + 1} (s = ")


@pytest.mark.parametrize("available_gib", [0.5, 4.0, 23.0])
def test_a_vessel_too_large_for_memory_is_refused_before_any_work(monkeypatch, capsys, available_gib):
    """With ``available_gib`` of memory, the largest bar count each program of a vessel scene fits (the dense one of
    bar angles: ``DENSE_COPIES n²`` doubles; the full space: ``FULL_BYTES_PER_BAR`` a bar, what ``"auto"`` takes
    above ``FULL_SPACE_BARS``) is refused one bar above it (ValueError giving the memory needed and the bars that
    fit) and accepted at it; the command line says the same in one line with exit status 2, no traceback, in well
    under a second."""
    import importlib
    import time

    from guidewire.app import cli

    front = importlib.import_module("guidewire.solve.options")

    monkeypatch.setattr(front, "available_memory", lambda: int(available_gib * 2**30))
    scene = guidewire.load_scene(str(VESSELS / "bend.toml"))
    fits = int((available_gib * 2**30 / (front.DENSE_COPIES * 8.0)) ** 0.5)
    front.check_memory(scene, fits, "reduced")
    with pytest.raises(ValueError, match=rf"{fits + 1} bars needs about .* GiB .* dense .* use at most {fits} bars"):
        front.check_memory(scene, fits + 1, "reduced")
    full = int(available_gib * 2**30 / front.FULL_BYTES_PER_BAR)
    assert full > front.FULL_SPACE_BARS
    front.check_memory(scene, full)
    with pytest.raises(ValueError, match=rf"{full + 1} bars needs about .* GiB .* full-space .* use at most {full} "):
        front.check_memory(scene, full + 1)
    started = time.perf_counter()
    code = cli.main(["solve", str(VESSELS / "bend.toml"), "--bars", str(4 * full)])
    err = capsys.readouterr().err
    assert code == 2 and "GiB" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert time.perf_counter() - started < 2.0
