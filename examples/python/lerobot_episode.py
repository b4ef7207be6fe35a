#!/usr/bin/env python3
"""Does a LeRobot episode overload the SO-101's STS3215 servos with a 200 g object in the gripper?

    python3 -m venv v && v/bin/pip install . pyarrow && v/bin/python examples/python/lerobot_episode.py

LeRobot's SO-100/SO-101 community records episodes as Parquet in the LeRobotDataset v3 layout:
`meta/info.json` (the frame rate `fps` and the names of each feature's entries) and
`data/chunk-000/file-000.parquet`, one row per frame with `timestamp` (s), `episode_index`,
`frame_index`, `index`, `observation.state` and `action` (one value per motor: `shoulder_pan.pos`
… `gripper.pos`; joints in degrees as LeRobot's `use_degrees` mode records them, the gripper in
0–100 % of its travel). No dataset hub is reachable from here, so the example first WRITES such
an episode itself (a synthetic pick-and-place: a smooth reach, a lift, a carry and a return at
30 fps — not a recording of a real arm), then reads it back as it would read a downloaded one and
replays the commanded `action` on the SO-101 (tests/urdf/example_robot_data/so101.urdf) with
the `sts3215` motors preset and a 200 g payload at the gripper, as ros2_control's
joint_trajectory_controller would play the time-stamped points (velocities from the samples:
cubic Hermite). The gripper's percentage is not a joint angle: its column is left out, so the
gripper holds its start position (faze4 says so). Self-clearance is off: the SO-101's meshes are
not shipped with faze4.

`--out DIR` says where the episode is written (default `out/lerobot_episode/`; the repository
ignores `out/`); `--payload-kg` changes the object.
"""

from __future__ import annotations

import argparse
import json
import pathlib

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

import faze4

ROOT = pathlib.Path(__file__).resolve().parents[2]
URDF = ROOT / "tests" / "urdf" / "example_robot_data" / "so101.urdf"
MOTORS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]
FPS = 30


def synthetic_episode(seconds: float = 4.0) -> tuple[np.ndarray, np.ndarray]:
    """Frames' times (s) and the commanded action (degrees; gripper %): rest → reach → lift →
    carry → rest, each joint blended with zero speed at every waypoint."""
    waypoints = np.array(
        [
            # pan, lift, elbow, wrist flex, wrist roll (deg), gripper (%)
            [0.0, 0.0, 0.0, 0.0, 0.0, 30.0],
            [25.0, -35.0, 40.0, 30.0, 10.0, 30.0],
            [25.0, -20.0, 20.0, 40.0, 10.0, 5.0],
            [-30.0, -40.0, 35.0, 20.0, -15.0, 5.0],
            [0.0, 0.0, 0.0, 0.0, 0.0, 30.0],
        ]
    )
    t = np.arange(int(seconds * FPS) + 1) / FPS
    segment = seconds / (len(waypoints) - 1)
    k = np.minimum((t // segment).astype(int), len(waypoints) - 2)
    s = (t - k * segment) / segment
    blend = (0.5 - 0.5 * np.cos(np.pi * s))[:, None]
    return t, waypoints[k] + blend * (waypoints[k + 1] - waypoints[k])


def write_episode(root: pathlib.Path, t: np.ndarray, action: np.ndarray) -> pathlib.Path:
    """The episode in LeRobotDataset v3's layout under `root`; the Parquet file's path."""
    names = [f"{m}.pos" for m in MOTORS]
    info = {
        "codebase_version": "v3.0",
        "robot_type": "so101_follower",
        "fps": FPS,
        "total_episodes": 1,
        "total_frames": len(t),
        "data_path": "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet",
        "features": {
            "action": {"dtype": "float32", "shape": [len(names)], "names": names},
            "observation.state": {"dtype": "float32", "shape": [len(names)], "names": names},
            "timestamp": {"dtype": "float32", "shape": [1], "names": None},
            "frame_index": {"dtype": "int64", "shape": [1], "names": None},
            "episode_index": {"dtype": "int64", "shape": [1], "names": None},
            "index": {"dtype": "int64", "shape": [1], "names": None},
        },
    }
    (root / "meta").mkdir(parents=True, exist_ok=True)
    (root / "meta" / "info.json").write_text(json.dumps(info, indent=2))
    # the follower lags its leader by about a frame: the state is the action one frame late
    state = np.vstack([action[:1], action[:-1]])
    vectors = lambda a: pa.array(list(a.astype(np.float32)), type=pa.list_(pa.float32()))  # noqa: E731
    table = pa.table(
        {
            "action": vectors(action),
            "observation.state": vectors(state),
            "timestamp": pa.array(t.astype(np.float32)),
            "frame_index": pa.array(np.arange(len(t), dtype=np.int64)),
            "episode_index": pa.array(np.zeros(len(t), dtype=np.int64)),
            "index": pa.array(np.arange(len(t), dtype=np.int64)),
        }
    )
    path = root / "data" / "chunk-000" / "file-000.parquet"
    path.parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(table, path)
    return path


def read_episode(root: pathlib.Path, episode: int = 0) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """An episode's times (s), commanded joint angles (rad) and their URDF joint names, from a
    LeRobotDataset v3 folder; the gripper's percentage left out."""
    info = json.loads((root / "meta" / "info.json").read_text())
    names = info["features"]["action"]["names"]
    path = root / info["data_path"].format(chunk_index=0, file_index=0)
    table = pq.read_table(path, columns=["timestamp", "episode_index", "action"]).to_pydict()
    rows = [i for i, e in enumerate(table["episode_index"]) if e == episode]
    t = np.array([table["timestamp"][i] for i in rows], dtype=np.float64)
    action = np.array([table["action"][i] for i in rows], dtype=np.float64)
    joints = [i for i, n in enumerate(names) if n != "gripper.pos"]
    return t - t[0], np.radians(action[:, joints]), [names[i].removesuffix(".pos") for i in joints]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out") / "lerobot_episode")
    parser.add_argument("--payload-kg", type=float, default=0.2)
    args = parser.parse_args()

    path = write_episode(args.out, *synthetic_episode())
    print(f"episode -> {path}")
    t, q, names = read_episode(args.out)
    # velocities from the samples (central differences): joint_trajectory_controller's cubic
    v = np.gradient(q, t, axis=0)
    robot = faze4.Robot.from_urdf(URDF, motors="sts3215", payload_kg=args.payload_kg)
    run = faze4.replay(robot, q, t=t, v=v, joint_names=names, no_collisions=True)
    for warning in run.warnings:
        print(f"faze4: {warning}")
    for name, motor in zip(robot.joint_names, run.summary["motors"]):
        if motor is not None:
            print(
                f"{name:13s} beyond its envelope {motor['envelope_pct']:5.1f} % of the steps, "
                f"peak {motor['sizing']['peak_torque'] * 1e3:.2f} mN·m at the motor"
            )
    print(run.verdict_line)


if __name__ == "__main__":
    main()
