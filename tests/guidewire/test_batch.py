"""``solve_many`` on a process pool and a Dask cluster gives what serial ``solve`` gives; one scene's error is its
result; the JSON-lines run resumes; the exports load (the B-spline reproduces the nodes)."""

from __future__ import annotations

import importlib.util
import json
import multiprocessing
import pickle
import shutil
from concurrent.futures import Executor, Future, ProcessPoolExecutor

import numpy as np
import pytest
from scipy.interpolate import BSpline

import guidewire
from guidewire import SceneError, solve, solve_many
from guidewire.app import cli
from guidewire.app.export import load_shapes, read_records, save_shapes, wire_spline
from guidewire.batch.files import done_files, solve_files
from guidewire.batch.scenes import slim, solve_iter, solve_one
from guidewire.chain import spline as spline_module
from guidewire.scene.paper import paper_scenes, scene_path

INFEASIBLE = "table5"


def _scenes() -> list[guidewire.Scene]:
    """20 scenes: the 13 feasible paper scenes at 25 bars, the infeasible Table 5, six variants."""
    paper = paper_scenes()
    scenes = [s.with_bars(25) for name, s in paper.items() if name != INFEASIBLE]
    scenes.insert(7, paper[INFEASIBLE])
    scenes += [
        paper["table1_pi_4"].with_bars(20), paper["table1_pi_4"].with_bars(40),
        paper["table2_zero"].with_bars(30).with_wire(youngs_modulus=2000.0),
        paper["fig6a"].with_bars(30).with_wire(scheme="paper"),
        paper["fig6b"].with_bars(35).with_wire(diameter=0.5),
        paper["table4"].with_bars(30).with_wire(max_relative_angle=0.2),
    ]
    return scenes


SCENES = _scenes()


@pytest.fixture(scope="module")
def serial() -> list[guidewire.Solution | ValueError]:
    out: list[guidewire.Solution | ValueError] = []
    for scene in SCENES:
        try:
            out.append(solve(scene))
        except ValueError as exc:
            out.append(exc)
    return out


class InlineExecutor(Executor):
    """Runs each task at submit (in this process); ``fail`` names scenes whose task the 'executor' loses."""

    def __init__(self, fail: str = "") -> None:
        self.fail, self.tasks = fail, 0

    def submit(self, fn, /, *args, **kwargs):  # noqa: ANN001, ANN201 - the Executor interface
        self.tasks += 1
        future: Future = Future()
        scenes = args[0] if isinstance(args[0], list) else [args[0]]
        if self.fail and any(s.name == self.fail for s in scenes):
            future.set_exception(RuntimeError("worker lost"))
        else:
            future.set_result(fn(*args, **kwargs))
        return future


def assert_same_as_serial(results, serial) -> None:
    assert len(results) == len(serial) == len(SCENES)
    for scene, got, want in zip(SCENES, results, serial, strict=True):
        assert got.scene == scene
        if isinstance(want, ValueError):
            assert isinstance(got, SceneError) and got.success is False
            assert (got.error, got.error_type, got.stage) == (str(want), "ValueError", "solve")
            continue
        assert isinstance(got, guidewire.Solution) and got.success == want.success
        assert got.energy == want.energy  # bit for bit: the same solve in another process
        assert np.array_equal(got.nodes, want.nodes) and np.array_equal(got.bar_angles, want.bar_angles)
        assert got.iterations == want.iterations and got.message == want.message


def test_serial_reference_has_one_raising_scene_and_converges_elsewhere(serial):
    raised = [i for i, r in enumerate(serial) if isinstance(r, ValueError)]
    assert raised == [7] and "infeasible" in str(serial[7])
    assert all(r.success for r in serial if not isinstance(r, ValueError))


def test_process_pool_gives_the_serial_results_and_records_the_failure(serial):
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("forkserver")) as pool:
        results = solve_many(SCENES, executor=pool, progress=False)
    assert_same_as_serial(results, serial)


def test_dask_local_cluster_gives_the_serial_results(serial):
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster,
        distributed.Client(cluster) as client,
    ):
        results = solve_many(SCENES, executor=client.get_executor(), progress=False)
    assert_same_as_serial(results, serial)


def test_default_pool_as_completed_with_progress_bar(serial, capsys):
    picked = [0, 7, 13]
    results = solve_many([SCENES[i] for i in picked], workers=2, ordered=False, progress=True)
    assert sorted(SCENES.index(r.scene) for r in results) == picked  # each result says which scene it is
    for result in results:
        want = serial[SCENES.index(result.scene)]
        if isinstance(want, ValueError):
            assert isinstance(result, SceneError) and result.error == str(want)
        else:
            assert result.energy == want.energy and np.array_equal(result.nodes, want.nodes)
    if importlib.util.find_spec("tqdm") is not None:  # the bar is optional
        assert "3/3" in capsys.readouterr().err  # it counted every scene


def test_chunks_and_a_lost_task_become_results(serial):
    executor = InlineExecutor(fail="table1_zero")
    results = solve_many(SCENES, executor=executor, progress=False, chunksize=3)
    assert executor.tasks == 7  # 20 scenes in tasks of 3
    lost = [i for i, r in enumerate(results) if isinstance(r, SceneError) and r.stage == "executor"]
    assert lost == [0, 1, 2]  # table1_zero's chunk: every scene in it, and only those
    assert results[0].error == "worker lost" and results[0].error_type == "RuntimeError"
    for i, (got, want) in enumerate(zip(results, serial, strict=True)):
        if i in lost:
            continue
        if isinstance(want, ValueError):
            assert isinstance(got, SceneError) and got.stage == "solve" and got.error == str(want)
        else:
            assert got.energy == want.energy and np.array_equal(got.nodes, want.nodes)


def test_solve_options_reach_every_scene_and_bad_arguments_raise_before_solving():
    results = solve_many(SCENES[:2], executor=InlineExecutor(), progress=False, bars=12, scheme="paper")
    assert [r.n_bars for r in results] == [12, 12] and {r.scheme for r in results} == {"paper"}
    with pytest.raises(TypeError, match="'max_iters' is not an option"):
        solve_many(SCENES[:1], executor=InlineExecutor(), max_iters=3)
    with pytest.raises(TypeError, match=r"scenes\[1\] is str"):
        solve_many([SCENES[0], "table1.toml"], executor=InlineExecutor())
    with pytest.raises(ValueError, match="workers"):
        solve_many(SCENES[:1], executor=InlineExecutor(), workers=2)
    with pytest.raises(ValueError, match="chunksize"):
        solve_many(SCENES[:1], executor=InlineExecutor(), chunksize=0)
    with pytest.raises(TypeError, match="executor is int"):
        solve_many(SCENES[:1], executor=4)
    with pytest.raises(ValueError, match="workers"):
        solve_iter(SCENES[:1], workers=0)  # checked at the call, not when iterated


def test_a_solution_travels_slim_and_still_warm_starts(serial):
    full = serial[0]
    light = slim(full)
    assert "hess" in full.result and "hess" not in light.result
    assert light.result["x"] is full.result["x"] and light.energy == full.energy
    size = len(pickle.dumps(light))
    assert len(pickle.dumps(full)) - size >= 8 * 25 * 25 and size < 7_000  # 25 bars: the dense 25 × 25 Hessian gone
    again = pickle.loads(pickle.dumps(light))
    assert np.array_equal(again.nodes, full.nodes) and again.to_dict() == full.to_dict()
    warm = solve(SCENES[0], multipliers0=again)
    assert warm.success and warm.iterations <= full.iterations


def _scene_dir(tmp_path, names):
    folder = tmp_path / "scenes"
    folder.mkdir(exist_ok=True)
    for name in names:
        shutil.copy(scene_path(name), folder / f"{name}.toml")
    return folder


def test_solve_files_resumes_and_retries_only_what_did_not_run(tmp_path):
    folder = _scene_dir(tmp_path, ["table1_pi_4", "table4", INFEASIBLE])
    (folder / "broken.toml").write_text("[wire\nlength = 100\n")
    out = tmp_path / "out" / "results.jsonl"
    seen: list[str] = []
    first = solve_files([folder], out, executor=InlineExecutor(), progress=False, bars=20,
                        on_result=lambda r: seen.append(r["name"]))
    assert (first.converged, first.not_converged, first.errors, first.skipped) == (2, 0, 2, 0)
    assert sorted(seen) == ["broken", "table1_pi_4", "table4", INFEASIBLE]
    records = {r["name"]: r for r in read_records(out)}
    assert records[INFEASIBLE]["error"].startswith("scene 'table5' is infeasible")
    assert records[INFEASIBLE]["stage"] == "solve" and records["broken"]["stage"] == "load"
    assert "not valid TOML" in records["broken"]["error"]
    assert records["table4"]["file"] == str((folder / "table4.toml").resolve())
    assert records["table4"]["bars"] == 20 and records["table4"]["success"] is True
    assert set(records["table4"]) >= {"name", "file", "energy", "nodes", "s", "bar_angles", "scene", "units"}

    # a new file, a fixed broken one, a run killed while writing its last line: only those run again
    shutil.copy(scene_path("fig6b"), folder / "fig6b.toml")
    (folder / "broken.toml").write_text(scene_path("table1_zero").read_text())
    lines = out.read_text().splitlines(keepends=True)
    cut = next(i for i, line in enumerate(lines) if '"name": "table4"' in line)
    out.write_text("".join(lines[:cut] + lines[cut + 1:]) + lines[cut][:40])
    seen.clear()
    second = solve_files([folder, folder / "fig6b.toml"], out, executor=InlineExecutor(), progress=False, bars=20,
                         on_result=lambda r: seen.append(r["name"]))
    assert sorted(seen) == ["fig6b", "table1_zero", "table4"] and second.skipped == 2
    assert all(json.loads(line) for line in out.read_text().splitlines())  # the cut line is gone
    latest = read_records(out)
    assert len(latest) == 5 and len(read_records(out, latest=False)) == 6
    assert {r["name"]: r["success"] for r in latest}["table1_zero"] is True
    assert done_files(out) == {str(p.resolve()) for p in folder.glob("*.toml")}
    third = solve_files([folder], out, executor=InlineExecutor(), progress=False)
    assert third.ran == 0 and third.skipped == 5


def test_cli_batch_runs_every_scene_resumes_and_exports(tmp_path, capsys):
    folder = _scene_dir(tmp_path, ["table1_pi_4", "table2_pi_4", INFEASIBLE])
    out, npz = tmp_path / "results.jsonl", tmp_path / "shapes.npz"
    args = ["batch", str(folder), "--out", str(out), "--workers", "2", "--bars", "30", "--no-progress"]
    assert cli.main([*args, "--npz", str(npz)]) == 0  # a scene that raised is a result, not a failed run
    printed = capsys.readouterr().out
    assert "3 scenes" in printed and "2 converged" in printed and "shapes and B-splines of 2 scenes" in printed
    records = read_records(out)
    assert [r["name"] for r in sorted(records, key=lambda r: r["name"])] == ["table1_pi_4", "table2_pi_4", INFEASIBLE]
    bad = next(r for r in records if r["name"] == INFEASIBLE)
    assert bad["success"] is False and "22.80 mm apart" in bad["error"]
    good = next(r for r in records if r["name"] == "table1_pi_4")
    want = solve(paper_scenes()["table1_pi_4"].with_bars(30))
    assert good["energy"] == want.energy and np.array_equal(np.array(good["nodes"]), want.nodes)
    assert cli.main(args) == 0
    assert "0 scenes" in capsys.readouterr().out and len(out.read_text().splitlines()) == 3


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        (["missing.toml"], "no such scene file or directory"),
        (["EMPTY"], "without scene files"),
        (["SCENE", "--workers", "2", "--scheduler", "tcp://127.0.0.1:8786"], "not both"),
        (["SCENE", "--workers", "0"], "--workers"),
        (["SCENE", "--out-is-dir"], "a directory"),
        (["SCENE", "--not-jsonl"], "not JSON"),
    ],
)
def test_cli_batch_bad_arguments_exit_2(tmp_path, capsys, extra, words):
    (tmp_path / "empty").mkdir()
    out = tmp_path / "out.jsonl"
    if "--out-is-dir" in extra:
        out = tmp_path / "empty"
    if "--not-jsonl" in extra:
        out.write_text("energy,nodes\n1,2\n")
    names = {"EMPTY": str(tmp_path / "empty"), "SCENE": str(scene_path("table1_pi_4"))}
    argv = ["batch", *(names.get(a, a) for a in extra if not a.startswith("--out-is") and a != "--not-jsonl"),
            "--out", str(out), "--no-progress"]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and words in err and len(err.strip().splitlines()) == 1


def test_cli_batch_without_dask_says_how_to_install(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(__import__("sys").modules, "distributed", None)  # as if not installed
    argv = ["batch", str(scene_path("table1_pi_4")), "--out", str(tmp_path / "o.jsonl"), "--scheduler", "tcp://x:1"]
    assert cli.main(argv) == 2
    assert "guidewire-sqp[cluster]" in capsys.readouterr().err


def test_spline_export_reproduces_the_nodes(tmp_path, serial, monkeypatch):
    solved = [r for r in serial if not isinstance(r, ValueError)]
    assert save_shapes([*solved, SceneError(SCENES[7], "infeasible", "ValueError")], tmp_path / "shapes") == 19
    with np.load(tmp_path / "shapes", allow_pickle=False) as data:  # plain arrays; the name as given
        assert data["node_offsets"][-1] == data["nodes"].shape[0] == sum(r.nodes.shape[0] for r in solved)
        assert list(data["names"][:2]) == [solved[0].scene.name, solved[1].scene.name]
    shapes = load_shapes(tmp_path / "shapes")
    for sol, shape in zip(solved, shapes, strict=True):
        assert np.array_equal(shape["nodes"], sol.nodes) and np.array_equal(shape["bar_angles"], sol.bar_angles)
        spline = shape["spline"]
        assert spline.degree == 3 and spline.coefficients.shape == (sol.nodes.shape[0], 2)
        points = BSpline(spline.knots, spline.coefficients, spline.degree)(sol.s)  # as a user would
        assert np.abs(points - sol.nodes).max() < 1e-6  # mm
        fine = spline(np.linspace(0.0, sol.s[-1], 20 * sol.n_bars + 1))  # the wire, not only its nodes:
        length = np.hypot(*np.diff(fine, axis=0).T).sum()  # as long as the wire (arc length is its parameter)
        assert length == pytest.approx(sol.scene.wire.length, rel=1e-2)  # ≤ 0.6 % longer here
    # the older scipy path (splprep) gives the same spline
    modern = wire_spline(solved[0].nodes, solved[0].s)
    monkeypatch.setattr(spline_module, "make_splprep", None)
    legacy = wire_spline(solved[0].nodes, solved[0].s)
    assert np.array_equal(legacy.knots, modern.knots)
    assert np.allclose(legacy.coefficients, modern.coefficients, rtol=0, atol=1e-9)
    short = wire_spline([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], [0.0, 1.5, 3.0])
    assert short.degree == 2 and np.allclose(short([0.0, 1.5, 3.0]), [[0, 0], [1, 1], [2, 0]])
    with pytest.raises(ValueError, match="s must increase"):
        wire_spline(solved[0].nodes, solved[0].s[::-1])
    with pytest.raises(ValueError, match="nodes has shape"):
        wire_spline([1.0, 2.0], [0.0, 1.0])


def test_default_pool_workers_run_one_blas_thread():
    threadpoolctl = pytest.importorskip("threadpoolctl")
    from guidewire.batch.scenes import default_executor

    with default_executor(1) as pool:
        assert pool.submit(solve_one, SCENES[0], {}).result().success  # numpy and its BLAS are loaded
        pools = pool.submit(threadpoolctl.threadpool_info).result()
    assert pools and all(p["num_threads"] == 1 for p in pools)  # numpy's BLAS is loaded and held to one thread


def test_insertions_on_a_process_pool_match_serial_inserts():
    from concurrent.futures import ProcessPoolExecutor

    from guidewire import insert
    from guidewire.batch.insertions import insert_many

    fig6b = guidewire.paper_scenes()["fig6b"].with_wire(length=40.0, bars=40)
    jobs = [(fig6b, [40.0, 45.0, 50.0, 55.0]), (fig6b, [40.0, 50.0, 60.0]), (fig6b, [50.0, 40.0])]
    with ProcessPoolExecutor(2) as pool:
        out = insert_many(jobs, executor=pool, progress=False)
    assert isinstance(out[2], SceneError) and "strictly increasing" in out[2].error
    for (scene, lengths), got in zip(jobs[:2], out[:2], strict=True):
        want = insert(scene, lengths)
        assert [s.energy for s in got.steps] == [s.energy for s in want.steps]
        assert all(np.array_equal(a.nodes, b.nodes) for a, b in zip(got.steps, want.steps, strict=True))
