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


def test_the_lerobot_example_writes_reads_and_replays_an_episode(tmp_path):
    out = tmp_path / "episode"
    proc = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "python" / "lerobot_episode.py"), "--out", str(out)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[-1].startswith("verdict: ")
    # six servos, the gripper held (its column is a percentage, not an angle)
    assert sum("beyond its envelope" in line for line in lines) == 6
    assert any("gives no values for 'gripper'" in line for line in lines)
    assert (out / "meta" / "info.json").exists() and (out / "data" / "chunk-000" / "file-000.parquet").exists()
    # an object the servos cannot lift changes the answer
    heavy = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "python" / "lerobot_episode.py"), "--out", str(out), "--payload-kg", "3"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert heavy.returncode == 0, heavy.stderr
    assert heavy.stdout.splitlines()[-1].startswith("verdict: cannot follow")
