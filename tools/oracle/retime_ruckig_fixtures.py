#!/usr/bin/env python3
"""Ruckig's time-optimal jerk-limited single segments (pantor/ruckig; Berscheid & Kröger 2021,
"Jerk-limited Real-time Trajectory Generation with Arbitrary Target States", RSS), for
tests/it/retime_vs_ruckig.rs and docs/retime.md's Ruckig column.

Each case moves one joint by `distance` from rest to rest (zero acceleration at both ends) under
a speed, acceleration and jerk limit; Ruckig's duration is the shortest any timing can have that
keeps the three. faze4's retime times the same straight move (the other joints at rest) with
`--max-speed`, `--max-accel`, `--max-jerk` and torque limits that do not bind; its duration
must be no shorter, within the stated factor.

Run from the repository root:

    tools/oracle/.venv/bin/python tools/oracle/retime_ruckig_fixtures.py

Writes tests/fixtures/retime_ruckig.json.
"""
import json
import os
from importlib.metadata import version

from ruckig import InputParameter, Result, Ruckig, Trajectory

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "tests", "fixtures", "retime_ruckig.json")

# (name, distance rad, max speed rad/s, max acceleration rad/s², max jerk rad/s³)
CASES = [
    ("long: speed, acceleration and jerk reached", 1.0, 1.0, 2.0, 10.0),
    ("short: the speed limit not reached", 0.2, 1.0, 2.0, 10.0),
    ("jerk-bound: the acceleration limit not reached", 0.5, 2.0, 10.0, 5.0),
    ("acceleration-bound: a high speed limit", 0.8, 5.0, 1.5, 20.0),
]


def ruckig_duration(distance, v, a, j):
    """Ruckig's duration of a rest-to-rest move of one joint."""
    otg = Ruckig(1)
    inp = InputParameter(1)
    inp.current_position = [0.0]
    inp.current_velocity = [0.0]
    inp.current_acceleration = [0.0]
    inp.target_position = [distance]
    inp.target_velocity = [0.0]
    inp.target_acceleration = [0.0]
    inp.max_velocity = [v]
    inp.max_acceleration = [a]
    inp.max_jerk = [j]
    trajectory = Trajectory(1)
    result = otg.calculate(inp, trajectory)
    assert result == Result.Working, result
    return trajectory.duration


def main():
    cases = [
        {
            "name": name,
            "distance": distance,
            "max_speed": v,
            "max_accel": a,
            "max_jerk": j,
            "duration": ruckig_duration(distance, v, a, j),
        }
        for name, distance, v, a, j in CASES
    ]
    with open(OUT, "w") as f:
        json.dump({"ruckig": version("ruckig"), "cases": cases}, f, indent=1)
        f.write("\n")
    for c in cases:
        print(f"{c['name']}: {c['duration']:.6f} s")


if __name__ == "__main__":
    main()
