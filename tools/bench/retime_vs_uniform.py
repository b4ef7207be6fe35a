#!/usr/bin/env python3
"""retime against the answer it replaces: one uniform time scale of a timing, the smallest that
faze4's loop follows, found by bisection as `faze4 sweep --find-min` finds a value.

On the Faze4's circle (tests/fixtures/shape_circle_q.npy, `--motors faze4`), two rest-to-rest
timings of the same not-a-knot spline over chord length that retime uses:

* toppra's, with each motor's holding torque and top speed as constant limits less faze4's
  margin (tools/bench/toppra_retime.py's `circle` case): what a toppra user would start from;
* the quintic time scaling s(t) = L (10 τ³ − 15 τ⁴ + 6 τ⁵), τ = t / T, over T = 1 s: the
  textbook rest-to-rest profile.

Each is written as a JointTrajectory JSON (positions, velocities, accelerations at 201 times)
with its times multiplied by k (velocities divided by k, accelerations by k²), and played by
`faze4 replay --q-traj F.json --motors faze4 --quiet`; the smallest k that follows is found to
within 0.2 % of the duration. Then `faze4 retime --q-traj … --motors faze4` on the same points,
and the speed-up of retime's timing over each uniformly scaled one.

Usage (repository root; needs `cargo build --release` and tools/oracle/setup.sh):

    tools/oracle/.venv/bin/python tools/bench/retime_vs_uniform.py
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.interpolate import CubicSpline

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FAZE4 = os.path.join(ROOT, "target", "release", "faze4")
PATH = os.path.join(ROOT, "tests", "fixtures", "shape_circle_q.npy")
sys.path.insert(0, os.path.join(ROOT, "tools", "bench"))
sys.path.insert(0, os.path.join(ROOT, "tools", "oracle"))
from retime_fixtures import chord_knots  # noqa: E402

JOINTS = ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"]
SAMPLES = 201


def toppra_timing():
    """toppra's timing of the circle under the holding torques: (t, q, qd, qdd) at SAMPLES times."""
    from toppra_retime import case, solve

    trajectory = solve(*case("circle"))
    t = np.linspace(0.0, trajectory.duration, SAMPLES)
    return t, trajectory(t), trajectory(t, 1), trajectory(t, 2)


def quintic_timing(duration=1.0):
    """The quintic rest-to-rest time scaling of the spline over `duration`: (t, q, qd, qdd)."""
    waypoints = np.load(PATH)
    knots = chord_knots(waypoints)
    spline = CubicSpline(knots, waypoints, bc_type="not-a-knot")
    length = knots[-1]
    t = np.linspace(0.0, duration, SAMPLES)
    tau = t / duration
    s = length * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)
    sd = length * (30 * tau**2 - 60 * tau**3 + 30 * tau**4) / duration
    sdd = length * (60 * tau - 180 * tau**2 + 120 * tau**3) / duration**2
    d1, d2 = spline(s, 1), spline(s, 2)
    return t, spline(s), d1 * sd[:, None], d2 * (sd**2)[:, None] + d1 * sdd[:, None]


def write(timing, k, path):
    """The timing with its times scaled by k, as a JointTrajectory JSON."""
    t, q, qd, qdd = timing
    points = []
    for i in range(len(t)):
        ns = round(t[i] * k * 1e9)
        points.append({
            "positions": q[i].tolist(),
            "velocities": (qd[i] / k).tolist(),
            "accelerations": (qdd[i] / k**2).tolist(),
            "time_from_start": {"sec": ns // 10**9, "nanosec": ns % 10**9},
        })
    with open(path, "w") as f:
        json.dump({"joint_names": JOINTS, "points": points}, f)


def follows(path):
    out = subprocess.run([FAZE4, "replay", "--q-traj", path, "--motors", "faze4", "--trail", "none", "--quiet"],
                         capture_output=True, text=True, cwd=ROOT)
    verdict = [line for line in out.stdout.splitlines() if line.startswith("verdict:")]
    if not verdict:
        sys.exit(f"faze4 replay {path}: no verdict\n{out.stderr}")
    return verdict[0] == "verdict: follows", verdict[0]


def smallest_scale(timing, tmp, name):
    """The smallest k ≥ some lower bound at which the timing scaled by k follows (bisection)."""
    path = os.path.join(tmp, f"{name}.json")
    lo, hi = 0.5, 1.0
    write(timing, hi, path)
    while not follows(path)[0]:
        lo, hi = hi, hi * 2
        write(timing, hi, path)
    write(timing, lo, path)
    if follows(path)[0]:
        sys.exit(f"{name}: follows at {lo}x: widen the bracket")
    runs = 0
    while (hi - lo) / hi > 0.002:
        mid = 0.5 * (lo + hi)
        write(timing, mid, path)
        ok, _ = follows(path)
        runs += 1
        lo, hi = (lo, mid) if ok else (mid, hi)
    return hi, runs


def main():
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "retimed.json")
        subprocess.run([FAZE4, "retime", "--q-traj", PATH, "--motors", "faze4", "--out", out, "--trail", "none",
                        "--quiet"],
                       check=True, capture_output=True, cwd=ROOT)
        with open(out) as f:
            last = json.load(f)["points"][-1]["time_from_start"]
        retimed = last["sec"] + last["nanosec"] * 1e-9
        _, retimed_verdict = follows(out)
        print("| timing | its duration (s) | in faze4's loop | smallest uniform scale that follows (s) | "
              "retime (s) | retime's speed-up |")
        print("|---|---|---|---|---|---|")
        for name, timing in (("toppra, holding torques", toppra_timing()), ("quintic, 1 s", quintic_timing())):
            own = timing[0][-1]
            path = os.path.join(tmp, "own.json")
            write(timing, 1.0, path)
            _, verdict = follows(path)
            k, _ = smallest_scale(timing, tmp, name.split(",")[0])
            print(f"| {name} | {own:.3f} | {verdict.removeprefix('verdict: ')} | {own * k:.3f} | "
                  f"{retimed:.3f} | {own * k / retimed:.2f}× |")
        print(f"\nretime's own timing in faze4's loop: {retimed_verdict}")


if __name__ == "__main__":
    main()
