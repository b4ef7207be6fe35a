"""examples/python/check_trajectory.py runs from a fresh install and does what it says."""

from __future__ import annotations

import subprocess
import sys

from conftest import ROOT


def test_the_example_checks_plots_and_sweeps(tmp_path):
    proc = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "python" / "check_trajectory.py"), "--quick", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0].startswith("verdict: ")
    assert sum(line.startswith("payload ") for line in lines) == 8
    png = tmp_path / "trajectory.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
