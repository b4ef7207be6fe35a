#!/usr/bin/env python3
"""Writes tests/fixtures/motors_{dc,stepper}_arm.json: Pinocchio's closed-loop wave of
tests/urdf/motor_arm.urdf with the torque-speed envelopes of tests/motors/{dc,stepper}_arm.toml
(pin_closed_loop.py's loop with --motors; docs/motors.md), fast enough that the envelopes clip.

The gains are pin_closed_loop.py's auto_tune with E = ratio x efficiency x the motor's largest
torque; tests/it/motors.rs runs faze4 with the same --kp, --kd and --effort, so both sides run the
same controller, and compares the trail (t, tool xyz, q) to 1e-9 and the share of steps beyond
the envelope.

    python tools/oracle/motor_fixtures.py        (from the repository root, oracle venv)
"""

import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pin_closed_loop as pcl  # noqa: E402

REPO = pcl.REPO_ROOT
URDF = "tests/urdf/motor_arm.urdf"
CASES = {
    # name: (motors file, wave freq rad/s, amplitude deg, duration s)
    "motors_dc_arm": ("tests/motors/dc_arm.toml", 6.0, 60.0, 3.0),
    "motors_stepper_arm": ("tests/motors/stepper_arm.toml", 3.0, 60.0, 3.0),
}
DT = 2e-4
RECORD_PERIOD = 0.02


def main():
    for name, (toml, freq, amp_deg, duration) in CASES.items():
        arm = pcl.PinArm(os.path.join(REPO, URDF))
        motors, ratios = pcl.read_motors(os.path.join(REPO, toml), arm.urdf)
        effort = np.array([ratios[i] * m.efficiency * m.max_torque() for i, m in enumerate(motors)])
        A, c = pcl.wave_setup(arm, amp_deg=amp_deg)
        command = pcl.wave_command(A, c, freq)
        _, kp, kd = pcl.auto_tune(arm, command(0.0)[0], DT, effort)
        summary, trail = pcl.run_closed_loop(
            arm, command, kp, kd, effort, duration=duration, dt=DT, record_period=RECORD_PERIOD,
            tool="tool_link", verbose=False, envelope=pcl.envelope_of(motors, ratios, effort))
        assert summary["diverged"] is None, summary["diverged"]
        assert max(summary["envelope_pct"]) > 5.0, summary["envelope_pct"]
        fixture = {
            "source": "tools/oracle/motor_fixtures.py (Pinocchio " + pcl.pin.__version__ + ")",
            "urdf": URDF,
            "motors": toml,
            "args": {"freq": freq, "amp_deg": amp_deg, "duration": duration, "dt": DT,
                     "record_period": RECORD_PERIOD},
            "kp": list(map(float, kp)),
            "kd": list(map(float, kd)),
            "effort": list(map(float, effort)),
            "summary": {k: summary[k] for k in ("max_tracking_error_rad", "saturation_pct", "envelope_pct")},
            "trail": {"columns": pcl.trail_columns(len(kp)), "rows": trail.tolist()},
        }
        out = os.path.join(REPO, "tests", "fixtures", name + ".json")
        with open(out, "w") as f:
            json.dump(fixture, f, indent=1)
        print(f"{name}: envelope {np.round(summary['envelope_pct'], 2)} % -> {out}")


if __name__ == "__main__":
    main()
