"""Shared fixtures: the repository, the binary the Python results are compared with."""

from __future__ import annotations

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]

# wall-clock times: the only fields of a summary that differ between two runs
WALL = ("wall_time_s", "dynamics_wall_time_s", "clearance_wall_time_s")


def without_wall_times(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if k not in WALL}


@pytest.fixture(scope="session")
def binary() -> str:
    """The faze4 binary: $FAZE4_BIN (.ci/run points it at the one it installed), else the
    release build of this clone (built here if needed)."""
    if os.environ.get("FAZE4_BIN"):
        return os.environ["FAZE4_BIN"]
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "faze4"], cwd=ROOT, check=True)
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    if not target.is_absolute():
        target = ROOT / target
    return str(target / "release" / "faze4")


def run_binary(binary: str, words: list[str], tmp: pathlib.Path) -> tuple[subprocess.CompletedProcess, dict | None]:
    """Runs `faze4 WORDS --summary s.json --trail none -q` in tmp; its result and summary."""
    out = tmp / "s.json"
    if out.exists():
        out.unlink()
    proc = subprocess.run(
        [binary, *words, "--summary", str(out), "--trail", "none", "--quiet"],
        cwd=tmp,
        capture_output=True,
        text=True,
    )
    return proc, (json.loads(out.read_text()) if out.exists() else None)
