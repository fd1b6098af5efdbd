"""Every benchmark script runs in its --quick mode (so the scripts never rot) and writes its tables."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: Scripts that need the optional PyElastica (the bench extra): run only where it is installed. pyelastica.py has its
#: own test as well (tests/test_benchmark_pyelastica.py).
NEEDS_PYELASTICA = ("pyelastica.py", "pyelastica_tube.py")
SCRIPTS = sorted(p.name for p in (ROOT / "benchmarks").glob("*.py")
                 if not p.name.startswith("_") and p.name not in NEEDS_PYELASTICA)


@pytest.mark.parametrize("script", SCRIPTS)
def test_quick_mode_runs(script, tmp_path):
    proc = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / script), "--quick", "--out", str(tmp_path)],
        capture_output=True, text=True, timeout=240, cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    written = list(tmp_path.glob("*.md"))
    assert written, f"{script} --quick wrote no Markdown table"
    assert "|" in written[0].read_text()


def test_quick_mode_of_the_pyelastica_tube_runs(tmp_path):
    pytest.importorskip("elastica", reason="benchmarks/pyelastica_tube.py needs PyElastica (the bench extra)")
    test_quick_mode_runs("pyelastica_tube.py", tmp_path)
