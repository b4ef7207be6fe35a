#!/usr/bin/env python3
"""Can the Faze4's motors follow a trajectory planned in numpy? Check it, plot it, and find how
much payload it takes before they cannot.

    python3 -m venv v && v/bin/pip install . && v/bin/python examples/python/check_trajectory.py

Prints the verdict, the plan's torques by inverse dynamics and a payload sweep, and with
matplotlib installed (`v/bin/pip install matplotlib`) writes out/trajectory.png (the folder
`out/` under the current one, which the repository's .gitignore ignores): joint angles commanded
and followed, and the tool's path. `--out DIR` puts the figure elsewhere; `--quick` runs shorter
(the test does).
"""

from __future__ import annotations

import argparse
import pathlib

import numpy as np

import faze4


def planned_trajectory(robot: faze4.Robot, frames: int = 200) -> np.ndarray:
    """A smooth pick-and-place-like loop: every joint between two poses, inside its limits."""
    s = np.linspace(0.0, 1.0, frames)
    blend = 0.5 - 0.5 * np.cos(2 * np.pi * s)  # 0 → 1 → 0, zero speed at both ends
    start = np.zeros(robot.dof)
    goal = np.array([0.8, -0.5, 0.9, 0.6, -0.7, 1.2])[: robot.dof]
    goal = np.clip(goal, robot.lower + 0.1, robot.upper - 0.1)
    return start + blend[:, None] * (goal - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out"))
    parser.add_argument("--quick", action="store_true", help="shorter runs")
    args = parser.parse_args()
    duration = 2.0 if args.quick else 6.0

    robot = faze4.Robot.faze4()
    q_traj = planned_trajectory(robot)  # (N, dof) float64
    run = faze4.replay(robot, q_traj, traj_period=3.0, duration=duration)
    print(run.verdict_line)
    print("max tracking error (rad):", np.round(run.summary["max_tracking_error_rad"], 4))
    print("torque at the limit (% of steps):", np.round(run.summary["saturation_pct"], 2))

    # the same trajectory's torques by inverse dynamics, along the plan (no controller)
    dt = 3.0 / (len(q_traj) - 1)
    v = np.gradient(q_traj, dt, axis=0)
    a = np.gradient(v, dt, axis=0)
    tau = np.array([robot.rnea(q, qd, qdd) for q, qd, qdd in zip(q_traj, v, a)])
    print("peak |τ| of the plan by RNEA (N·m):", np.round(np.abs(tau).max(axis=0), 3))
    print("motor limits (N·m):               ", robot.effort)

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        plt = None
        print("no figure: matplotlib is not installed (pip install matplotlib)")
    if plt is not None:
        plot(robot, run, args.out)

    # how much payload before the motors cannot follow? all runs on every core
    payloads = np.linspace(0.0, 1.4, 8)
    rows = faze4.sweep(robot, "replay", vary={"payload_kg": payloads}, q_traj=q_traj, traj_period=3.0, duration=duration)
    for row in rows:
        reasons = "; ".join(row["verdict"]["reasons"]) if "verdict" in row else row["failed"]
        answer = "follows" if row.get("verdict", {}).get("follows") else f"cannot follow — {reasons}"
        print(f"payload {row['payload_kg']:.2f} kg: {answer}")


def plot(robot: faze4.Robot, run: faze4.Run, out: pathlib.Path) -> None:
    import matplotlib.pyplot as plt

    fig, (joints, tool) = plt.subplots(1, 2, figsize=(11, 4))
    for i in range(robot.dof):
        (line,) = joints.plot(run.t, run.q_cmd[:, i], "--", linewidth=1)
        joints.plot(run.t, run.q[:, i], color=line.get_color(), label=robot.joint_names[i])
    joints.set(xlabel="t (s)", ylabel="joint angle (rad)", title="commanded (dashed) and followed")
    joints.legend(fontsize=7)
    tool.plot(run.tool_xyz[:, 0], run.tool_xyz[:, 2])
    tool.set(xlabel="x (m)", ylabel="z (m)", title="tool path", aspect="equal")
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    figure = out / "trajectory.png"
    fig.savefig(figure, dpi=100)
    print(f"figure -> {figure}")


if __name__ == "__main__":
    main()
