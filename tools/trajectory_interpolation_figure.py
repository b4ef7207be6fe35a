#!/usr/bin/env python3
"""docs/trajectory_interpolation.svg: one MoveIt-style trajectory (TOPP-RA through four waypoints
of the UR5, 23 points at uneven times: tests/fixtures/trajectories/ur5_toppra.*) played by faze4
three ways, as joint_trajectory_controller would play it given positions only (linear), positions
and velocities (cubic Hermite), or positions, velocities and accelerations (quintic Hermite).
Linear interpolation steps the commanded velocity at every point; the PD's kd term turns each step
into a torque spike. The torques and velocities are faze4's trail (`--debug`, a row every 2 ms);
the commanded velocity is drawn from the same interpolation (tools/oracle/pin_closed_loop.py's
spline_command, which equals faze4's, tests/it/trajectories.rs).

Run from the repository root with the oracle venv (numpy, matplotlib), after `cargo build --release`:

    tools/oracle/.venv/bin/python tools/trajectory_interpolation_figure.py [--faze4 target/release/faze4]

Prints, per interpolation, the largest |τ| and the largest tracking error of each joint (the
table in docs/trajectories.md).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools/oracle"))
import trajectory_fixtures as tf  # noqa: E402
import pin_closed_loop as pcl  # noqa: E402

URDF = "tests/urdf/example_robot_data/ur5_robot.urdf"
RUNS = [  # label, input file, options, level
    ("linear (positions)", "tests/fixtures/trajectories/ur5_toppra.yaml", ["--message", "1"], 1),
    ("cubic (+ velocities)", "tests/fixtures/trajectories/ur5_toppra.json", [], 2),
    ("quintic (+ accelerations)", "tests/fixtures/trajectories/ur5_toppra.yaml", ["--message", "2"], 3),
]
COLOURS = ["#d62728", "#1f77b4", "#2ca02c"]
WIDTHS = [1.0, 2.4, 1.0]  # cubic drawn wide under quintic: the two nearly coincide
JOINT = 1  # J2, the shoulder: the largest inertia
PERIOD = "0.002"


def trail(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header, data = rows[0], np.array([[float(x) for x in r] for r in rows[1:]])
    return {name: data[:, i] for i, name in enumerate(header)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--faze4", default=os.path.join(ROOT, "target/release/faze4"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs/trajectory_interpolation.svg"))
    args = ap.parse_args()
    plan = tf.toppra_ur5()
    plt.rcParams["svg.hashsalt"] = "faze4"
    fig, (ax_v, ax_tau) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    print("| interpolation | max abs tau per joint (N m) | max tracking error per joint (mrad) |")
    print("|---|---|---|")
    for (label, path, options, level), colour, width in zip(RUNS, COLOURS, WIDTHS):
        with tempfile.TemporaryDirectory() as tmp:
            out, summary = os.path.join(tmp, "trail.csv"), os.path.join(tmp, "s.json")
            subprocess.run([args.faze4, "replay", "--urdf", URDF, "--q-traj", path, "--no-collisions", "-q",
                            "--debug", "--record-period", PERIOD, "--trail", out, "--summary", summary] + options,
                           cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
            run, s = trail(out), json.load(open(summary))
        assert s["interpolation"] == label.split()[0], s["interpolation"]
        times, q, v, a = tf.model_order(URDF, plan, level)
        command = pcl.spline_command(times, q, v, a)
        v_cmd = np.array([command(x)[1][JOINT] for x in run["t"]])
        ax_v.plot(run["t"], v_cmd, color=colour, lw=width, ls="--")
        ax_v.plot(run["t"], run[f"v{JOINT + 1}"], color=colour, lw=width, label=label)
        ax_tau.plot(run["t"], run[f"tau{JOINT + 1}"], color=colour, lw=width, label=label)
        taus = [np.max(np.abs(run[f"tau{i + 1}"])) for i in range(6)]
        print(f"| {label} | {', '.join(f'{x:.1f}' for x in taus)} | "
              f"{', '.join(f'{1e3 * e:.2f}' for e in s['max_tracking_error_rad'])} |")
    for k in plan.t:
        ax_v.axvline(k, color="#dddddd", lw=0.4, zorder=0)
    ax_v.set_ylabel("J2 velocity (rad/s)\ncommanded dashed, measured solid")
    ax_tau.set_ylabel("J2 torque τ (N·m)")
    ax_tau.set_xlabel("t (s)   (grey lines: the trajectory's points)")
    ax_v.legend(loc="upper right", fontsize=8)
    ax_v.set_title(f"UR5, a TOPP-RA trajectory ({len(plan.ns)} points at uneven times) played as"
                   " joint_trajectory_controller plays it", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.out, metadata={"Date": None})
    print(f"{os.path.relpath(args.out, ROOT)} written")


if __name__ == "__main__":
    main()
