"""Every benchmark script runs in its --quick mode (so the scripts never rot) and writes its tables."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: pyelastica.py needs the optional PyElastica and has its own test (tests/test_benchmark_pyelastica.py).
SCRIPTS = sorted(p.name for p in (ROOT / "benchmarks").glob("*.py")
                 if not p.name.startswith("_") and p.name != "pyelastica.py")


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
