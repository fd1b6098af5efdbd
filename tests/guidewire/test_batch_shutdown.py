"""A batch stops cleanly: SIGTERM and Ctrl-C leave no process behind, keep what was written and say how to resume;
a script without a ``__main__`` guard still gets its process pool."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from importlib import resources
from pathlib import Path

import pytest

from guidewire.app.export import read_records

BEND = Path(str(resources.files("guidewire") / "scenes" / "vessels" / "bend.toml"))


def _descendants(pid: int) -> set[int]:
    """Every process below ``pid`` (from /proc)."""
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            parent = int(stat[stat.rindex(")") + 2:].split()[1])
            children.setdefault(parent, []).append(int(entry.name))
    out, todo = set(), [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            out.add(child)
            todo.append(child)
    return out


def _alive(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat[stat.rindex(")") + 2] != "Z"


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads the process tree from /proc")
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_signalled_batch_leaves_no_process_and_resumes(tmp_path, sig):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    count = 60  # (signalled at the first record written: the rest is still to do on any machine)
    for i in range(count):
        (scenes / f"bend{i:03d}.toml").write_text(BEND.read_text())
    out = tmp_path / "out.jsonl"
    command = [sys.executable, "-m", "guidewire", "batch", str(scenes), "--out", str(out), "--workers", "2",
               "--no-progress"]
    # (a signal the caller ignores stays ignored in its children: a test run started in the background, `pytest &`,
    # ignores SIGINT; the command is tested as a terminal starts it)
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 120.0
    while not (out.exists() and out.stat().st_size) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    below = _descendants(proc.pid)
    assert len(below) >= 3, "the pool never started"  # two workers and the fork server (or their spawn parents)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "run the same command again" in err, err
    deadline = time.monotonic() + 10.0
    while any(_alive(p) for p in below) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not [p for p in below if _alive(p)], "processes left behind"
    # resumed: every scene once in the reader, the finished ones not solved again
    kept = len(read_records(out))
    assert 0 < kept < count
    done = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    records = read_records(out)
    assert sorted(Path(r["file"]).name for r in records) == sorted(f"bend{i:03d}.toml" for i in range(count))
    assert f"{kept} already in the output" in done.stdout


def test_a_script_without_a_main_guard_gets_its_process_pool(tmp_path):
    """The workers do not run the caller's script again (which, unguarded, broke the pool: every scene an
    executor error)."""
    script = tmp_path / "unguarded.py"
    script.write_text(
        "import guidewire\n"
        "scenes = [s.with_bars(20) for s in list(guidewire.paper_scenes().values())[:4]]\n"
        "results = guidewire.solve_many(scenes, workers=2, progress=False)\n"
        "print('RESULTS', [type(r).__name__ for r in results], flush=True)\n")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=180,
                          cwd=tmp_path, env={**os.environ, "PYTHONWARNINGS": "error"})
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.count("RESULTS") == 1  # (printed by this process only, never by a worker)
    assert "RESULTS ['Solution', 'Solution', 'Solution', 'Solution']" in done.stdout, done.stdout + done.stderr


def test_the_batch_command_names_each_scene_without_a_solution_as_it_arrives(tmp_path):
    """The paper's scenes: Table 5 as printed is infeasible; its line (stage and reason) is on stderr."""
    scenes = Path(str(resources.files("guidewire") / "scenes"))
    done = subprocess.run([sys.executable, "-m", "guidewire", "batch", str(scenes), "--out", str(tmp_path / "o.jsonl"),
                           "--workers", "1", "--no-progress"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    flagged = [line for line in done.stderr.splitlines() if "no solution" in line]
    assert len(flagged) == 1 and flagged[0].startswith("table5: no solution (solve):") and "infeasible" in flagged[0]


def test_the_pools_manager_thread_drops_only_its_invalid_state_error():
    """The race behind a rare traceback on SIGTERM (CPython's executor setting an exception on a task cancelled
    meanwhile): ``InvalidStateError`` from the pool's manager thread is dropped, any other error of that thread and
    any error of another thread still reach the previous hook."""
    import threading
    from concurrent.futures import InvalidStateError

    from guidewire.batch.scenes import _quiet_manager

    seen = []
    saved = threading.excepthook
    threading.excepthook = lambda args: seen.append((args.thread.name, args.exc_type))
    try:
        def raising(exc):
            def run():
                raise exc
            return run

        manager = threading.Thread(target=raising(InvalidStateError("cancelled")), name="manager")

        class Pool:
            _executor_manager_thread = manager

        _quiet_manager(Pool())
        manager.start()
        manager.join()
        other = threading.Thread(target=raising(InvalidStateError("x")), name="other")
        other.start()
        other.join()
        Pool._executor_manager_thread = again = threading.Thread(target=raising(ValueError("y")), name="again")
        _quiet_manager(Pool())
        again.start()
        again.join()
    finally:
        threading.excepthook = saved
    assert seen == [("other", InvalidStateError), ("again", ValueError)]


def test_an_interrupted_command_exits_though_a_thread_would_block_the_exit():
    """``guidewire.app.cli.entry``: with the interrupted status the process leaves at once, its output flushed, even
    while a non-daemon thread would block the interpreter's exit (the stand-in for a process pool's manager thread
    left waiting on its dead workers' pipe); any other status exits normally."""
    code = ("import threading, guidewire.app.cli as cli\n"
            "threading.Thread(target=threading.Event().wait).start()\n"
            "cli.main = lambda: (print('written', flush=False), cli.EXIT_INTERRUPTED)[1]\n"
            "cli.entry()\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 130
    assert done.stdout == "written\n"
    plain = subprocess.run([sys.executable, "-c", "import guidewire.app.cli as cli\ncli.main = lambda: 3\ncli.entry()"],
                           capture_output=True, text=True, timeout=60)
    assert plain.returncode == 3
