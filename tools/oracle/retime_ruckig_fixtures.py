#!/usr/bin/env python3
"""Ruckig's time-optimal jerk-limited single segments (pantor/ruckig; Berscheid & Kröger 2021,
"Jerk-limited Real-time Trajectory Generation with Arbitrary Target States", RSS), for
tests/it/retime_vs_ruckig.rs and docs/retime.md's Ruckig column.

Each case moves one joint by `distance` under a speed, acceleration and jerk limit, from rest
to rest, or (the chaining cases) from a `start_velocity` and/or to an `end_velocity`, with zero
acceleration at both ends; Ruckig's duration is the shortest any timing can have that keeps the
three. faze4's retime times the same straight move (the other joints at rest) with
`--max-speed`, `--max-accel`, `--max-jerk` (and `--start-velocity`, `--end-velocity`) and
torque limits that do not bind; its duration must be no shorter, within the stated factor.

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

# (name, distance rad, max speed rad/s, max acceleration rad/s², max jerk rad/s³, start and
# end velocity rad/s)
CASES = [
    ("long: speed, acceleration and jerk reached", 1.0, 1.0, 2.0, 10.0, 0.0, 0.0),
    ("short: the speed limit not reached", 0.2, 1.0, 2.0, 10.0, 0.0, 0.0),
    ("jerk-bound: the acceleration limit not reached", 0.5, 2.0, 10.0, 5.0, 0.0, 0.0),
    ("acceleration-bound: a high speed limit", 0.8, 5.0, 1.5, 20.0, 0.0, 0.0),
    ("chained in: from 0.5 rad/s to rest", 1.0, 1.0, 2.0, 10.0, 0.5, 0.0),
    ("chained out: from rest to 0.5 rad/s", 1.0, 1.0, 2.0, 10.0, 0.0, 0.5),
    ("chained through: from 0.8 to 0.3 rad/s", 1.0, 1.0, 2.0, 10.0, 0.8, 0.3),
    ("chained near the speed limit: 0.9 rad/s in and out", 1.0, 1.0, 2.0, 10.0, 0.9, 0.9),
    ("chained, jerk-bound: from 0.5 rad/s to rest", 0.5, 2.0, 10.0, 5.0, 0.5, 0.0),
]


def ruckig_duration(distance, v, a, j, v0=0.0, vf=0.0):
    """Ruckig's duration of a move of one joint from v0 to vf (zero acceleration at both ends)."""
    otg = Ruckig(1)
    inp = InputParameter(1)
    inp.current_position = [0.0]
    inp.current_velocity = [v0]
    inp.current_acceleration = [0.0]
    inp.target_position = [distance]
    inp.target_velocity = [vf]
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
            "start_velocity": v0,
            "end_velocity": vf,
            "duration": ruckig_duration(distance, v, a, j, v0, vf),
        }
        for name, distance, v, a, j, v0, vf in CASES
    ]
    with open(OUT, "w") as f:
        json.dump({"ruckig": version("ruckig"), "cases": cases}, f, indent=1)
        f.write("\n")
    for c in cases:
        print(f"{c['name']}: {c['duration']:.6f} s")


if __name__ == "__main__":
    main()
