#!/usr/bin/env python3
"""Fixtures for time-stamped trajectories (issue 31, docs/trajectories.md): trajectories made by
TOPP-RA (`toppra`) on example-robot-data's UR5 and by Ruckig (`ruckig`) on its SO-101, saved as
ROS 2 tools save them (YAML as `ros2 topic echo` prints it, JSON, rosbag2 MCAP written with
`mcap` + `mcap-ros2-support`, CSV), played by the faze4 binary and by a Pinocchio closed loop
with the same interpolation (pin_closed_loop.spline_command: joint_trajectory_controller's
linear / cubic / quintic Hermite rule) and faze4's gains, for both feed-forwards.

Run from the repository root with the oracle venv, after `cargo build --example convert_trajectory`
(and `cargo build`):

    tools/oracle/.venv/bin/python tools/oracle/trajectory_fixtures.py [--faze4 target/debug/faze4]

Writes:

* tests/fixtures/trajectories/ur5_toppra.{yaml,json,mcap,csv}, so101_ruckig.{csv,mcap}: the
  input files (the YAML holds two messages: positions only, then positions, velocities and
  accelerations; the SO-101 MCAP holds a JointTrajectory topic and a recorded JointState
  topic, stamps at an epoch time, joints in another order, the gripper too);
  bad_topics.mcap: two JointState topics and a std_msgs/msg/String one (the refusals);
* tests/fixtures/messages/*: messages as people send and record them (issue 43; the files
  others published, beside them, are read here, not written): UR's example goal, a one-point
  goal, a MoveIt DisplayTrajectory, ROS 1's layout (YAML and JSON), SO-101 /joint_states from an
  arm, a gripper and a camera published apart (zero, true and noisy velocities; YAML, MCAP,
  JSON). Pinocchio plays each as joint_trajectory_controller plays a message it receives
  (pin_closed_loop.played_command: from the start, the approach to the first point, the
  positions_upsampling spline under --interpolation cubic); a stream as faze4 is documented to
  read it, merged here from its messages (merged());
* tests/fixtures/trajectories/bags/: the same trajectories in bags as `rosbags` (PyPI, a writer
  of ROS 1 and rosbag2 bags without ROS) writes them: rosbag2 folders with SQLite (.db3, as
  ROS 2 Humble records) and MCAP storage, uncompressed, zstd per message and zstd per file;
  ROS 1 bags with bz2 and lz4 chunks. Each is read back with rosbags' readers (the oracle) and
  must hold the messages written;
* tests/fixtures/trajectories/lerobot/: the SO-101 plan as LeRobot datasets, written with
  pyarrow (what LeRobot writes its Parquet tables with) in LeRobot's layout and schema (those of
  a dataset LeRobot recorded on an SO-101: fixed-size lists of float32, Snappy, one row group
  per episode, the `huggingface` schema metadata): so101_v3 (v3.0, three episodes in one file,
  the joints normalised −100…100 by so101_calibration.json, LeRobot's calibration file, with
  a motor in drive mode 1) and so101_v21 (v2.1, one file per episode, `observation.state` in
  degrees as an arm recorded with `use_degrees` stores it); frames at 30 fps;
* tests/fixtures/trajectory_<case>.json: per case, faze4's arguments, the interpolation and
  feed-forward it must report, and Pinocchio's trail (t, tool x y z, q1..qn);
* tests/fixtures/trajectories/written/ur5_toppra.{yaml,json,mcap,csv}: the quintic UR5
  trajectory as faze4 writes it (examples/convert_trajectory.rs from the MCAP), each read back
  here with PyYAML, json, csv and mcap_ros2's reader (the rosbag2 profile, the ros2msg schema)
  and checked equal to the trajectory to the last bit; tests/it/trajectories.rs checks that faze4
  still writes those bytes.

Times are whole nanoseconds (as ROS stores them) from the start: t = ns / 1e9. The URDFs are the
copies in tests/urdf/example_robot_data/ (see its README.md); the runs use --no-collisions.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import pinocchio as pin
import ruckig
import toppra
import toppra.algorithm
import toppra.constraint
import yaml
from mcap.reader import make_reader
from mcap_ros2.reader import read_ros2_messages
from mcap_ros2.writer import Writer
import pyarrow as pa
import pyarrow.compute  # noqa: F401  (pa.compute)
import pyarrow.parquet as pq
from rosbags.rosbag1 import Reader as Ros1Reader
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin
from rosbags.rosbag2 import Reader as Ros2Reader
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools/oracle"))
import pin_closed_loop as pcl  # noqa: E402

FIXTURES = os.path.join(ROOT, "tests/fixtures")
FILES = os.path.join(FIXTURES, "trajectories")
BAGS = os.path.join(FILES, "bags")
LEROBOT = os.path.join(FILES, "lerobot")
UR5 = "tests/urdf/example_robot_data/ur5_robot.urdf"
SO101 = "tests/urdf/example_robot_data/so101.urdf"
TOL = 1e-9

SEPARATOR = "=" * 80
TIME = "int32 sec\nuint32 nanosec\n"
HEADER = f"builtin_interfaces/Time stamp\nstring frame_id\n{SEPARATOR}\nMSG: builtin_interfaces/Time\n{TIME}"
JOINT_TRAJECTORY = (
    "std_msgs/Header header\nstring[] joint_names\nJointTrajectoryPoint[] points\n"
    f"{SEPARATOR}\nMSG: std_msgs/Header\n{HEADER}"
    f"{SEPARATOR}\nMSG: trajectory_msgs/JointTrajectoryPoint\n"
    "float64[] positions\nfloat64[] velocities\nfloat64[] accelerations\nfloat64[] effort\n"
    "builtin_interfaces/Duration time_from_start\n"
    f"{SEPARATOR}\nMSG: builtin_interfaces/Duration\n{TIME}")
JOINT_STATE = (
    "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\nfloat64[] effort\n"
    f"{SEPARATOR}\nMSG: std_msgs/Header\n{HEADER}")
STRING = "string data\n"


# --------------------------------------------------------------------------------------------
# The trajectories.
# --------------------------------------------------------------------------------------------

class Plan:
    """A sampled trajectory: joint names, times (whole ns), positions, velocities, accelerations."""

    def __init__(self, names, ns, q, v, a):
        self.names, self.ns = list(names), [int(x) for x in ns]
        self.q, self.v, self.a = np.asarray(q), np.asarray(v), np.asarray(a)

    @property
    def t(self):
        return [n / 1e9 for n in self.ns]


def uneven_times(duration, seed, low, high):
    """Whole-nanosecond times from 0 to `duration` with seeded uneven steps in [low, high] s."""
    rng = np.random.default_rng(seed)
    end = int(round(duration * 1e9))
    ns = [0]
    while True:
        step = int(round(rng.uniform(low, high) * 1e9))
        if ns[-1] + step >= end - int(low * 1e9) // 2:
            break
        ns.append(ns[-1] + step)
    return ns + [end]


def toppra_ur5():
    """TOPP-RA through four joint-space waypoints of the UR5 (|v| ≤ 1.5 rad/s, |a| ≤ 3 rad/s²),
    sampled at uneven times as a planner's points are."""
    toppra.setup_logging("WARNING")
    names = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
             "wrist_3_joint"]
    way = np.array([[0.0, -1.2, 1.0, -1.4, -1.57, 0.0], [0.6, -1.5, 1.4, -1.2, -1.3, 0.4],
                    [1.1, -1.0, 0.8, -1.6, -1.0, 0.9], [0.4, -0.8, 0.5, -1.3, -1.57, 0.2]])
    path = toppra.SplineInterpolator(np.linspace(0.0, 1.0, len(way)), way)
    vlim = np.array([[-1.5, 1.5]] * 6)
    alim = np.array([[-3.0, 3.0]] * 6)
    instance = toppra.algorithm.TOPPRA(
        [toppra.constraint.JointVelocityConstraint(vlim), toppra.constraint.JointAccelerationConstraint(alim)],
        path, parametrizer="ParametrizeConstAccel")
    trajectory = instance.compute_trajectory()
    ns = uneven_times(trajectory.duration, 31, 0.05, 0.2)
    ts = np.array([n / 1e9 for n in ns])
    return Plan(names, ns, trajectory(ts), trajectory(ts, 1), trajectory(ts, 2))


def ruckig_so101():
    """Ruckig (jerk-limited) on the SO-101's five arm joints: rest → a pose passed through at
    speed → rest at another pose; sampled at uneven times. The gripper is not named."""
    names = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll"]
    legs = [([0.0, 0.0, 0.0, 0.0, 0.0], [0.0] * 5, [0.5, -0.4, 0.6, 0.3, -0.8], [0.3, 0.0, -0.2, 0.2, 0.0]),
            ([0.5, -0.4, 0.6, 0.3, -0.8], [0.3, 0.0, -0.2, 0.2, 0.0], [1.0, 0.3, -0.2, -0.5, 0.4], [0.0] * 5)]
    pieces = []
    for start, v0, goal, v1 in legs:
        otg, inp, out = ruckig.Ruckig(5), ruckig.InputParameter(5), ruckig.Trajectory(5)
        inp.current_position, inp.current_velocity, inp.current_acceleration = start, v0, [0.0] * 5
        inp.target_position, inp.target_velocity, inp.target_acceleration = goal, v1, [0.0] * 5
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = [2.0] * 5, [6.0] * 5, [40.0] * 5
        assert otg.calculate(inp, out) in (ruckig.Result.Working, ruckig.Result.Finished)
        pieces.append(out)
    total = sum(p.duration for p in pieces)
    ns = uneven_times(total, 101, 0.04, 0.12)

    def at(t):
        for p in pieces:
            if t <= p.duration:
                return p.at_time(t)
            t -= p.duration
        return pieces[-1].at_time(pieces[-1].duration)

    samples = [at(n / 1e9) for n in ns]
    plan = Plan(names, ns, [s[0] for s in samples], [s[1] for s in samples], [s[2] for s in samples])
    plan.at, plan.duration = at, total  # the motion itself, for the recorded streams
    return plan


# --------------------------------------------------------------------------------------------
# The files, as ROS 2 tools write them.
# --------------------------------------------------------------------------------------------

def message(plan, level, order=None):
    """A JointTrajectory dict: positions, + velocities (level >= 2), + accelerations (3)."""
    order = list(range(len(plan.names))) if order is None else order
    points = []
    for k, n in enumerate(plan.ns):
        points.append({
            "positions": [float(plan.q[k][i]) for i in order],
            "velocities": [float(plan.v[k][i]) for i in order] if level >= 2 else [],
            "accelerations": [float(plan.a[k][i]) for i in order] if level >= 3 else [],
            "effort": [],
            "time_from_start": {"sec": n // 10**9, "nanosec": n % 10**9},
        })
    return {"header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""},
            "joint_names": [plan.names[i] for i in order], "points": points}


def echo_yaml(messages):
    """Messages as `ros2 topic echo` prints them (rosidl_runtime_py's message_to_yaml: PyYAML
    block style, insertion order, each message followed by ---)."""
    return "".join(yaml.dump(m, default_flow_style=False, sort_keys=False, width=sys.maxsize) + "---\n"
                   for m in messages)


def write_csv(path, plan, level, order):
    columns = ["time_from_start"] + [plan.names[i] for i in order]
    rows_of = [plan.q]
    if level >= 2:
        columns += [plan.names[i] + ".velocity" for i in order]
        rows_of.append(plan.v)
    if level >= 3:
        columns += [plan.names[i] + ".acceleration" for i in order]
        rows_of.append(plan.a)
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(columns)
        for k, t in enumerate(plan.t):
            w.writerow([repr(t)] + [repr(float(x[k][i])) for x in rows_of for i in order])


def write_mcap(path, topics):
    """A rosbag2 MCAP: topics = [(name, type, msgdef, [(log_time_ns, message dict)])]."""
    with open(path, "wb") as f:
        writer = Writer(f)
        for name, kind, definition, messages in topics:
            schema = writer.register_msgdef(kind, definition)
            for log_time, msg in messages:
                writer.write_message(name, schema, msg, log_time=log_time, publish_time=log_time)
        writer.finish()


def joint_states(plan, hold, epoch_ns):
    """The plan as a recorded /joint_states: every joint (the held ones too), in reverse order,
    header stamps from `epoch_ns`, positions and velocities."""
    names = list(reversed(plan.names + list(hold)))
    out = []
    for k, n in enumerate(plan.ns):
        q = dict(zip(plan.names, plan.q[k]))
        v = dict(zip(plan.names, plan.v[k]))
        q.update(hold)
        stamp = epoch_ns + n
        out.append((stamp, {"header": {"stamp": {"sec": stamp // 10**9, "nanosec": stamp % 10**9}, "frame_id": ""},
                            "name": names, "position": [float(q[j]) for j in names],
                            "velocity": [float(v.get(j, 0.0)) for j in names], "effort": []}))
    return out


# --------------------------------------------------------------------------------------------
# Bags, as rosbags writes them.
# --------------------------------------------------------------------------------------------

ROS2_STORE = get_typestore(Stores.ROS2_HUMBLE)
ROS1_STORE = get_typestore(Stores.ROS1_NOETIC)
JS, JT, STR = "sensor_msgs/msg/JointState", "trajectory_msgs/msg/JointTrajectory", "std_msgs/msg/String"


def ros_message(store, kind, m):
    """The rosbags message object of the dict `m` (message() or joint_states())."""
    t = store.types
    arr = lambda xs: np.array(xs, dtype=np.float64)  # noqa: E731
    if kind == STR:
        return t[STR](data=m["data"])
    h = m["header"]
    header = {"stamp": t["builtin_interfaces/msg/Time"](sec=h["stamp"]["sec"], nanosec=h["stamp"]["nanosec"]),
              "frame_id": h["frame_id"]}
    if store is ROS1_STORE:
        header["seq"] = 0
    header = t["std_msgs/msg/Header"](**header)
    if kind == JS:
        return t[JS](header=header, name=m["name"], position=arr(m["position"]), velocity=arr(m["velocity"]),
                     effort=arr(m["effort"]))
    point = t["trajectory_msgs/msg/JointTrajectoryPoint"]
    duration = t["builtin_interfaces/msg/Duration"]
    return t[JT](header=header, joint_names=m["joint_names"], points=[
        point(positions=arr(p["positions"]), velocities=arr(p["velocities"]), accelerations=arr(p["accelerations"]),
              effort=arr(p["effort"]), time_from_start=duration(sec=p["time_from_start"]["sec"],
                                                                nanosec=p["time_from_start"]["nanosec"]))
        for p in m["points"]])


def as_dict(msg):
    """A read-back message as the dicts written (floats compared bit for bit)."""
    if hasattr(msg, "data"):
        return {"data": msg.data}
    h = {"stamp": {"sec": msg.header.stamp.sec, "nanosec": msg.header.stamp.nanosec},
         "frame_id": msg.header.frame_id}
    if hasattr(msg, "position"):
        return {"header": h, "name": list(msg.name), "position": msg.position.tolist(),
                "velocity": msg.velocity.tolist(), "effort": msg.effort.tolist()}
    return {"header": h, "joint_names": list(msg.joint_names), "points": [
        {"positions": p.positions.tolist(), "velocities": p.velocities.tolist(),
         "accelerations": p.accelerations.tolist(), "effort": p.effort.tolist(),
         "time_from_start": {"sec": p.time_from_start.sec, "nanosec": p.time_from_start.nanosec}}
        for p in msg.points]}


def write_rosbag2(name, storage, compression, topics):
    """A rosbag2 folder tests/fixtures/trajectories/bags/NAME; topics as write_mcap's (type,
    messages); read back with rosbags' reader, every message as written."""
    path = os.path.join(BAGS, name)
    if os.path.exists(path):
        import shutil
        shutil.rmtree(path)
    writer = Ros2Writer(path, version=8, storage_plugin=storage)
    if compression is not None:
        writer.set_compression(compression, CompressionFormat.ZSTD)
    with writer:
        for topic, kind, _, messages in topics:
            conn = writer.add_connection(topic, kind, typestore=ROS2_STORE)
            for log_time, m in messages:
                writer.write(conn, log_time, ROS2_STORE.serialize_cdr(ros_message(ROS2_STORE, kind, m), kind))
    with Ros2Reader(path) as reader:
        check_read_back(topics, [(c.topic, ROS2_STORE.deserialize_cdr(raw, c.msgtype), t)
                                 for c, t, raw in reader.messages()], name)


def write_rosbag1(name, compression, topics):
    """A ROS 1 bag tests/fixtures/trajectories/bags/NAME.bag, chunks compressed with
    `compression` (bz2, lz4), read back with rosbags' ROS 1 reader."""
    path = os.path.join(BAGS, f"{name}.bag")
    if os.path.exists(path):
        os.remove(path)
    writer = Ros1Writer(path)
    writer.set_compression(Ros1Writer.CompressionFormat[compression.upper()])
    with writer:
        for topic, kind, _, messages in topics:
            conn = writer.add_connection(topic, kind, typestore=ROS1_STORE)
            for log_time, m in messages:
                writer.write(conn, log_time, ROS1_STORE.serialize_ros1(ros_message(ROS1_STORE, kind, m), kind))
    with Ros1Reader(path) as reader:
        check_read_back(topics, [(c.topic, ROS1_STORE.deserialize_ros1(raw, c.msgtype), t)
                                 for c, t, raw in reader.messages()], name)


def check_read_back(topics, read, name):
    for topic, _, _, messages in topics:
        got = [(t, as_dict(m)) for tp, m, t in read if tp == topic]
        assert got == messages, f"{name}: {topic} does not read back as written"
    print(f"{os.path.relpath(os.path.join(BAGS, name), ROOT)}: read back by rosbags exactly")


def write_bags(ur5, so101, epoch):
    """The bags of the cases below (names as the cases give them)."""
    os.makedirs(BAGS, exist_ok=True)
    states = joint_states(so101, {"gripper": 0.0}, epoch)
    chatter = [(epoch + k * 10**8, {"data": f"hello {k}"}) for k in range(3)]
    so101_topics = [("/arm_controller/joint_trajectory", JT, None, [(epoch, message(so101, 3))]),
                    ("/joint_states", JS, None, states), ("/chatter", STR, None, chatter)]
    write_rosbag2("so101_humble_db3", StoragePlugin.SQLITE3, None, so101_topics)
    write_rosbag2("so101_mcap_zstd_per_message", StoragePlugin.MCAP, CompressionMode.MESSAGE, so101_topics)
    write_rosbag2("ur5_db3_zstd_per_file", StoragePlugin.SQLITE3, CompressionMode.FILE,
                  [("/scaled_joint_trajectory_controller/joint_trajectory", JT, None, [(0, message(ur5, 1))])])
    write_rosbag2("ur5_mcap_zstd_per_file", StoragePlugin.MCAP, CompressionMode.FILE,
                  [("/scaled_joint_trajectory_controller/joint_trajectory", JT, None, [(0, message(ur5, 2))])])
    write_rosbag1("so101_noetic_bz2", "bz2", so101_topics)
    write_rosbag1("ur5_noetic_lz4", "lz4",
                  [("/arm_controller/command", JT, None, [(epoch, message(ur5, 3, [2, 0, 5, 1, 4, 3]))])])


# --------------------------------------------------------------------------------------------
# LeRobot datasets, as LeRobot lays them out.
# --------------------------------------------------------------------------------------------

SO101_MOTORS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]
# A calibration of our own making in LeRobot's format (counts of a 4096-step turn), one motor
# in drive mode 1.
SO101_CALIBRATION = {
    "shoulder_pan": {"id": 1, "drive_mode": 0, "homing_offset": -1520, "range_min": 745, "range_max": 3385},
    "shoulder_lift": {"id": 2, "drive_mode": 0, "homing_offset": 1213, "range_min": 820, "range_max": 3250},
    "elbow_flex": {"id": 3, "drive_mode": 1, "homing_offset": -1005, "range_min": 880, "range_max": 3080},
    "wrist_flex": {"id": 4, "drive_mode": 0, "homing_offset": 318, "range_min": 850, "range_max": 3210},
    "wrist_roll": {"id": 5, "drive_mode": 0, "homing_offset": -1402, "range_min": 150, "range_max": 3950},
    "gripper": {"id": 6, "drive_mode": 0, "homing_offset": 1407, "range_min": 2030, "range_max": 3470},
}
FPS = 30


def normalised(rad, c):
    """LeRobot's RANGE_M100_100 value of an angle (rad): the inverse of faze4's
    MotorCalibration::radians (n·(max − min)/200·2π/4095, n negated in drive mode 1)."""
    n = rad / (2.0 * math.pi / 4095.0) * 200.0 / (c["range_max"] - c["range_min"])
    return -n if c["drive_mode"] else n


def radians(n, c):
    """faze4's MotorCalibration::radians, in its order of operations."""
    n = -n if c["drive_mode"] else n
    return n * (c["range_max"] - c["range_min"]) / 200.0 * 2.0 * math.pi / (4096.0 - 1.0)


def frames_at(plan, seconds):
    """The plan's positions (linear between its points) at `seconds`."""
    return np.array([[np.interp(t, plan.t, plan.q[:, i]) for i in range(len(plan.names))] for t in seconds])


def lerobot_table(episodes, key_values):
    """A LeRobot data table: per episode (index, timestamps, {key: rows}), the columns in
    LeRobot's order and types."""
    rows = {k: [] for k in list(key_values) + ["timestamp", "frame_index", "episode_index", "index", "task_index"]}
    index = 0
    for e, times, columns in episodes:
        for k, t in enumerate(times):
            for key in key_values:
                rows[key].append([float(x) for x in columns[key][k]])
            rows["timestamp"].append(float(t))
            rows["frame_index"].append(k)
            rows["episode_index"].append(e)
            rows["index"].append(index)
            rows["task_index"].append(0)
            index += 1
    vec = pa.list_(pa.float32(), 6)
    fields = [pa.field(k, vec) for k in key_values] + [
        pa.field("timestamp", pa.float32()), pa.field("frame_index", pa.int64()), pa.field("episode_index", pa.int64()),
        pa.field("index", pa.int64()), pa.field("task_index", pa.int64())]
    hf = {"info": {"features": {**{k: {"feature": {"dtype": "float32", "_type": "Value"}, "length": 6, "_type": "List"}
                                    for k in key_values},
                                 "timestamp": {"dtype": "float32", "_type": "Value"},
                                 **{k: {"dtype": "int64", "_type": "Value"}
                                    for k in ("frame_index", "episode_index", "index", "task_index")}}}}
    schema = pa.schema(fields, metadata={"huggingface": json.dumps(hf)})
    return pa.table([rows[f.name] for f in fields], schema=schema)


def lerobot_info(version, episodes, frames, key_values, data_path):
    features = {k: {"dtype": "float32", "shape": [6], "names": [f"{m}.pos" for m in SO101_MOTORS]} for k in key_values}
    features["timestamp"] = {"dtype": "float32", "shape": [1], "names": None}
    for k in ("frame_index", "episode_index", "index", "task_index"):
        features[k] = {"dtype": "int64", "shape": [1], "names": None}
    info = {"codebase_version": version, "robot_type": "so101_follower", "total_episodes": episodes,
            "total_frames": frames, "total_tasks": 1, "chunks_size": 1000, "fps": FPS,
            "splits": {"train": f"0:{episodes}"}, "data_path": data_path, "features": features}
    if version == "v2.1":
        info["total_chunks"] = 1
    return info


def write_lerobot(so101):
    """so101_v3 (episode 1 the plan, normalised by SO101_CALIBRATION) and so101_v21 (its
    episode 0 the plan in degrees in observation.state); returns the plans as faze4 must read
    them: (names, times, q) per dataset."""
    import shutil
    if os.path.exists(LEROBOT):
        shutil.rmtree(LEROBOT)
    os.makedirs(LEROBOT)
    with open(os.path.join(LEROBOT, "so101_calibration.json"), "w") as f:
        json.dump(SO101_CALIBRATION, f, indent=4)
    n = int(math.floor(plan_end(so101) * FPS)) + 1
    times = np.array([k / FPS for k in range(n)], dtype=np.float32)
    q = frames_at(so101, times.astype(np.float64))
    gripper = np.linspace(0.0, 100.0, n)  # the gripper closing, 0–100 %
    cal = [SO101_CALIBRATION[m] for m in SO101_MOTORS[:5]]
    norm = np.array([[normalised(q[k, i], cal[i]) for i in range(5)] + [gripper[k]] for k in range(n)], np.float32)
    still = np.tile(norm[:1], (20, 1))
    t20 = np.array([k / FPS for k in range(20)], dtype=np.float32)
    episodes = [(0, t20, {"action": still, "observation.state": still}),
                (1, times, {"action": norm, "observation.state": norm}),
                (2, t20, {"action": still[::-1], "observation.state": still})]
    v3 = os.path.join(LEROBOT, "so101_v3")
    os.makedirs(os.path.join(v3, "data/chunk-000"))
    os.makedirs(os.path.join(v3, "meta"))
    table = lerobot_table(episodes, ["action", "observation.state"])
    # one row group per episode, as LeRobot's to_parquet_one_row_group_per_episode writes
    with pq.ParquetWriter(os.path.join(v3, "data/chunk-000/file-000.parquet"), table.schema,
                          compression="snappy") as w:
        for e, _, _ in episodes:
            w.write_table(table.filter(pa.compute.equal(table["episode_index"], e)))
    with open(os.path.join(v3, "meta/info.json"), "w") as f:
        json.dump(lerobot_info("v3.0", 3, int(table.num_rows), ["action", "observation.state"],
                               "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"), f, indent=4)
    v21 = os.path.join(LEROBOT, "so101_v21")
    os.makedirs(os.path.join(v21, "data/chunk-000"))
    os.makedirs(os.path.join(v21, "meta"))
    degrees = np.array([[math.degrees(q[k, i]) for i in range(5)] + [gripper[k]] for k in range(n)], np.float32)
    table = lerobot_table([(0, times, {"action": degrees, "observation.state": degrees})],
                          ["action", "observation.state"])
    pq.write_table(table, os.path.join(v21, "data/chunk-000/episode_000000.parquet"), compression="snappy")
    with open(os.path.join(v21, "meta/info.json"), "w") as f:
        json.dump(lerobot_info("v2.1", 1, n, ["action", "observation.state"],
                               "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet"), f, indent=4)
    # what faze4 must read: the float32 values back through the calibration, or in degrees
    t = [float(x) for x in times]
    q_cal = np.array([[radians(float(norm[k, i]), cal[i]) for i in range(5)] for k in range(n)])
    q_deg = np.array([[math.radians(float(degrees[k, i])) for i in range(5)] for k in range(n)])
    names = SO101_MOTORS[:5]
    print(f"{os.path.relpath(LEROBOT, ROOT)}: so101_v3 (3 episodes), so101_v21 (1 episode), {n} frames")
    return Frames(names, t, q_cal), Frames(names, t, q_deg)


def plan_end(plan):
    return plan.t[-1]


class Frames(Plan):
    """A dataset's frames: times in s (float32 values), positions only."""

    def __init__(self, names, seconds, q):
        super().__init__(names, [round(x * 1e9) for x in seconds], q, np.zeros_like(q), np.zeros_like(q))
        self.seconds = list(seconds)

    @property
    def t(self):
        return self.seconds


# --------------------------------------------------------------------------------------------
# The runs.
# --------------------------------------------------------------------------------------------

def model_order(urdf_path, plan, level, hold=None):
    """(times, q, v, a) in faze4's order, the joints the plan does not name holding `hold`
    (the start given), else 0 clamped into their limits, as faze4's TimedCommand does."""
    arm = pcl.UrdfArm(os.path.join(ROOT, urdf_path), mimic=True)
    n, rows = len(arm.coords), len(plan.ns)
    q, v, a = np.zeros((rows, n)), np.zeros((rows, n)), np.zeros((rows, n))
    for i, j in enumerate(arm.coords):
        if j.name in plan.names:
            c = plan.names.index(j.name)
            q[:, i], v[:, i], a[:, i] = plan.q[:, c], plan.v[:, c], plan.a[:, c]
        else:
            q[:, i] = min(max(0.0, j.lower), j.upper) if hold is None else hold[i]
    return plan.t, q, (v if level >= 2 else None), (a if level >= 3 else None)


def run_case(faze4, case):
    """faze4 (for its gains), then Pinocchio's loop with them, the message played as
    joint_trajectory_controller plays it from the start (pin_closed_loop.played_command); the
    fixture. A case: (name, URDF, input, options, plan, level, feed-forward[, start,
    interpolation]), the level what the plan's points give (1 positions, 2 + velocities, 3 +
    accelerations)."""
    name, urdf, input_file, extra, plan, level, ff = case[:7]
    start, interpolation = (case[7:] + (None, None))[:2]
    args = ["replay", "--urdf", urdf, "--q-traj", input_file, "--no-collisions"] + extra
    if start is not None:
        args += ["--start", ",".join(repr(float(x)) for x in start)]
    if interpolation is not None:
        args += ["--interpolation", interpolation]
    if ff == "full":
        args += ["--ff", "full"]
    with tempfile.TemporaryDirectory() as tmp:
        summary_path = os.path.join(tmp, "s.json")
        subprocess.run([faze4] + args + ["-q", "--trail", "none", "--summary", summary_path],
                       cwd=ROOT, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        summary = json.load(open(summary_path))
    arm = pcl.PinArm(os.path.join(ROOT, urdf), mimic=True)
    t, q, v, a = model_order(urdf, plan, level, hold=start)
    command, start_state = pcl.played_command(t, q, v, a, start=start, interpolation=interpolation)
    effort = [math.inf if e is None else e for e in summary["effort"]]
    duration = command.duration
    pin_summary, trail = pcl.run_closed_loop(
        arm, command, summary["kp"], summary["kd"], effort, duration=duration, dt=summary["dt"],
        feed_forward=ff, tool=summary["tool_link"], verbose=False, start_state=start_state)
    assert summary["steps"] == pin_summary["steps"], (summary["steps"], pin_summary["steps"])
    return {
        "generator": "tools/oracle/trajectory_fixtures.py",
        "pinocchio_version": pin.__version__,
        "faze4_args": args,
        "interpolation": command.kind,
        "feed_forward": ff,
        "max_tracking_error_rad": pin_summary["max_tracking_error_rad"],
        "trail": {"columns": pcl.trail_columns(pin_summary["dof"]), "rows": trail.tolist()},
    }


# --------------------------------------------------------------------------------------------
# What faze4 writes, read by the ROS 2 readers.
# --------------------------------------------------------------------------------------------

def check_written(convert, plan):
    """faze4 converts the quintic UR5 MCAP into every format; each is read back here and must
    hold the plan exactly (names, whole-ns times, every float to the last bit)."""
    out = os.path.join(FILES, "written")
    os.makedirs(out, exist_ok=True)
    want = message(plan, 3)

    def same(got, what):
        assert got["joint_names"] == want["joint_names"], what
        assert len(got["points"]) == len(want["points"]), what
        for p, w in zip(got["points"], want["points"]):
            for key in ("positions", "velocities", "accelerations", "time_from_start"):
                assert p[key] == w[key], f"{what}: {key} {p[key]} != {w[key]}"

    for ext in ("yaml", "json", "mcap", "csv"):
        path = os.path.join(out, f"ur5_toppra.{ext}")
        subprocess.run([convert, os.path.join(FILES, "ur5_toppra.mcap"), path], cwd=ROOT, check=True)
        if ext == "yaml":
            docs = [d for d in yaml.safe_load_all(open(path)) if d is not None]
            assert len(docs) == 1
            same(docs[0], "PyYAML")
        elif ext == "json":
            same(json.load(open(path)), "json")
        elif ext == "csv":
            rows = list(csv.reader(open(path)))
            names = want["joint_names"]
            assert rows[0] == ["time_from_start"] + names + [j + ".velocity" for j in names] + \
                [j + ".acceleration" for j in names], rows[0]
            got = {"joint_names": names, "points": []}
            for r in rows[1:]:
                x = [float(s) for s in r]
                n = len(names)
                ns = int(round(x[0] * 1e9))
                assert ns / 1e9 == x[0]
                got["points"].append({"positions": x[1:1 + n], "velocities": x[1 + n:1 + 2 * n],
                                      "accelerations": x[1 + 2 * n:], "time_from_start":
                                      {"sec": ns // 10**9, "nanosec": ns % 10**9}})
            same(got, "csv")
        else:
            with open(path, "rb") as f:
                reader = make_reader(f)
                assert reader.get_header().profile == "ros2"
                summary = reader.get_summary()
                (schema,) = summary.schemas.values()
                (channel,) = summary.channels.values()
                assert (schema.name, schema.encoding) == ("trajectory_msgs/msg/JointTrajectory", "ros2msg")
                assert channel.message_encoding == "cdr"
            (msg,) = list(read_ros2_messages(path))
            m = msg.ros_msg
            got = {"joint_names": list(m.joint_names), "points": [
                {"positions": list(p.positions), "velocities": list(p.velocities),
                 "accelerations": list(p.accelerations),
                 "time_from_start": {"sec": p.time_from_start.sec, "nanosec": p.time_from_start.nanosec}}
                for p in m.points]}
            same(got, "mcap_ros2")
        print(f"{os.path.relpath(path, ROOT)}: read back exactly ({ext})")

# --------------------------------------------------------------------------------------------
# Messages as people send them (issue 43): goals, MoveIt's messages, ROS 1's layout, recorded
# JointState streams from several publishers.
# --------------------------------------------------------------------------------------------

MESSAGES = os.path.join(FIXTURES, "messages")
PANDA = "tests/urdf/example_robot_data/panda.urdf"

# UR's own example (Universal_Robots_ROS2_Driver, ur_robot_driver/scripts/example_move.py,
# BSD-3-Clause, at 696e1a7): its first trajectory, two points at rest, the first at 4 s.
UR_EXAMPLE = [([0.043128, -1.28824, 1.37179, -1.82208, -1.63632, -0.18], 4),
              ([-0.195016, -1.70093, 0.902027, -0.944217, -1.52982, -0.195171], 8)]
# The UR driver's goal publisher (ur_robot_driver/config/test_goal_publishers_config.yaml, the
# parameters of ros2_controllers' publisher_joint_trajectory_controller): one point a goal,
# reached in 4 s (its log in UniversalRobots/Universal_Robots_ROS2_Driver issue 625).
UR_POS1, UR_POS2 = [0.785, -1.57, 0.785, 0.785, 0.785, 0.785], [0.0, -1.57, 0.0, 0.0, 0.0, 0.0]
UR_NAMES = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
            "wrist_3_joint"]


def flow_yaml(msg):
    """A message as `ros2 topic pub` / `ros2 action send_goal` take it: one flow mapping."""
    return yaml.dump(msg, default_flow_style=True, sort_keys=False, width=sys.maxsize)


def ros1(msg):
    """A ROS 2 message dict in ROS 1's layout: {secs, nsecs} times, a header with `seq`."""
    if isinstance(msg, list):
        return [ros1(m) for m in msg]
    if not isinstance(msg, dict):
        return msg
    if set(msg) == {"sec", "nanosec"}:
        return {"secs": msg["sec"], "nsecs": msg["nanosec"]}
    out = {k: ros1(v) for k, v in msg.items()}
    if "stamp" in out and "frame_id" in out:
        out = {"seq": 0, **out}
    return out


def ros1_echo_yaml(messages):
    """Messages in `rostopic echo`'s layout (ROS 1): block mappings, flow lists, `---` after each."""
    return "".join(yaml.dump(m, default_flow_style=None, sort_keys=False, width=sys.maxsize) + "---\n"
                   for m in messages)


def plan_of(names, points):
    """A Plan of message points [(positions, whole seconds)] at rest."""
    ns = [s * 10**9 for _, s in points]
    q = [p for p, _ in points]
    return Plan(names, ns, q, np.zeros_like(q), np.zeros_like(q))


def split(plan, k):
    """The plan's points from k on, its times from the k-th (a second MoveIt segment)."""
    ns = [n - plan.ns[k] for n in plan.ns[k:]]
    return Plan(plan.names, ns, plan.q[k:], plan.v[k:], plan.a[k:])


def head(plan, k):
    """The plan's points up to k (included)."""
    return Plan(plan.names, plan.ns[:k + 1], plan.q[:k + 1], plan.v[:k + 1], plan.a[:k + 1])


def robot_trajectory(msg):
    """A moveit_msgs/RobotTrajectory holding the JointTrajectory `msg`."""
    empty = {"header": msg["header"], "joint_names": [], "points": []}
    return {"joint_trajectory": msg, "multi_dof_joint_trajectory": empty}


def stamped(ns):
    return {"sec": ns // 10**9, "nanosec": ns % 10**9}


def state(ns, names, q, v):
    """A sensor_msgs/JointState dict at stamp `ns`; efforts NaN, as drivers that do not measure
    them publish."""
    return {"header": {"stamp": stamped(ns), "frame_id": ""}, "name": list(names),
            "position": [float(x) for x in q], "velocity": [float(x) for x in v],
            "effort": [float("nan")] * len(names)}


def so101_streams(plan, epoch, arm_hz, velocities, seed):
    """A recorded SO-101 motion as its JointState publishers give it, in log order: the arm
    (the plan's five joints) at `arm_hz` with seeded jitter, the gripper apart at 10 Hz (opening
    from 0.2 to 1.2 rad at a constant rate), and a camera's pan/tilt the arm's model lacks at
    15 Hz. `velocities` gives the arm's recorded velocities from (t, true v) and the gripper's
    from its true rate: zeros, the truth, or noise. Returns [(log_ns, JointState dict)]."""
    rng = np.random.default_rng(seed)
    end = int(round(plan.duration * 1e9))
    out = []
    k, t = 0, 0
    while t <= end:
        q, v, _ = plan.at(t / 1e9)
        out.append((epoch + t, state(epoch + t, plan.names, q, velocities(t, np.asarray(v)))))
        k += 1
        t = int(round(k * 1e9 / arm_hz + rng.uniform(-2e6, 2e6)))
    rate = 1.0 / (end / 1e9)
    for k in range(int(end / 1e8) + 1):
        t = 13_000_000 + k * 100_000_000
        g = 0.2 + rate * t / 1e9
        out.append((epoch + t, state(epoch + t, ["gripper"], [g], velocities(t, np.array([rate])))))
    for k in range(int(end * 15 / 1e9) + 1):
        t = 31_000_000 + k * 66_666_667
        out.append((epoch + t, state(epoch + t, ["camera_pan", "camera_tilt"], [0.1 * k, -0.05 * k], [0.0, 0.0])))
    out.sort(key=lambda m: m[0])
    return out


def merged(stream, keep, use_velocities):
    """faze4's recorded motion of a JointState stream, built here from the messages: the joints
    `keep` names, each sampled at every stamp of the stream (its own where it has one, between
    its samples by its own spline through them — linear, or cubic Hermite with its recorded
    velocities —, held at rest outside them); times in whole ns from the first stamp."""
    series, order = {}, []
    for _, msg in stream:
        ns = msg["header"]["stamp"]["sec"] * 10**9 + msg["header"]["stamp"]["nanosec"]
        for i, name in enumerate(msg["name"]):
            if name in keep:
                if name not in series:
                    series[name], order = [], order + [name]
                series[name].append((ns, msg["position"][i], msg["velocity"][i]))
    grid = sorted({s[0] for name in order for s in series[name]})
    q, v = np.zeros((len(grid), len(order))), np.zeros((len(grid), len(order)))
    for j, name in enumerate(order):
        own = sorted(series[name])
        t0 = own[0][0]
        times = [(s[0] - t0) / 1e9 for s in own]
        spline = pcl.spline_command(times, [[s[1]] for s in own], [[s[2]] for s in own] if use_velocities else None)
        at = {s[0]: s for s in own}
        for k, t in enumerate(grid):
            if t in at:
                q[k, j], v[k, j] = at[t][1], at[t][2] if use_velocities else 0.0
            elif t < own[0][0]:
                q[k, j] = own[0][1]
            elif t > own[-1][0]:
                q[k, j] = own[-1][1]
            else:
                qq, vv, _ = spline((t - t0) / 1e9)
                q[k, j], v[k, j] = qq[0], vv[0]
    return Plan(order, [t - grid[0] for t in grid], q, v, np.zeros_like(q))


def write_messages(ur5, so101):
    """The message files; returns the cases that play them."""
    os.makedirs(MESSAGES, exist_ok=True)
    rel = lambda name: f"tests/fixtures/messages/{name}"  # noqa: E731
    out = lambda name, text: open(os.path.join(MESSAGES, name), "w").write(text)  # noqa: E731
    cases = []
    # a FollowJointTrajectory goal as `ros2 action send_goal` takes it: UR's example, the first
    # point at 4 s: held there, then from a start
    example = plan_of(UR_NAMES, UR_EXAMPLE)
    goal = message(example, 2)
    del goal["header"]
    out("ur5_example_goal.yaml", flow_yaml({"trajectory": goal}))
    cases += [("ur5_goal_held_cubic_gravity", UR5, rel("ur5_example_goal.yaml"), [], example, 2, "gravity"),
              ("ur5_goal_from_start_cubic_full", UR5, rel("ur5_example_goal.yaml"), [], example, 2, "full",
               [0.0, -1.57, 1.57, -1.57, -1.57, 0.0])]
    # one point, positions only, reached in 4 s from the start (the goal publisher's pos1 from pos2)
    one = plan_of(UR_NAMES, [(UR_POS1, 4)])
    point = message(one, 1)
    out("ur5_one_point_goal.yaml", flow_yaml({"trajectory": {"joint_names": point["joint_names"],
                                                              "points": [{"positions": UR_POS1,
                                                                          "time_from_start": {"sec": 4}}]}}))
    cases.append(("ur5_one_point_linear_gravity", UR5, rel("ur5_one_point_goal.yaml"), [], one, 1, "gravity", UR_POS2))
    # MoveIt: a DisplayTrajectory of two RobotTrajectories (the TOPP-RA plan cut at point 9), as
    # `ros2 topic echo /display_planned_path` prints it; the second picked
    first, second = head(ur5, 9), split(ur5, 9)
    display = {"model_id": "ur5", "trajectory": [robot_trajectory(message(first, 3)), robot_trajectory(message(second, 3))],
               "trajectory_start": {"joint_state": state(0, ur5.names, ur5.q[0], ur5.v[0])}}
    del display["trajectory_start"]["joint_state"]["effort"]
    out("ur5_display_trajectory.yaml", echo_yaml([display]))
    cases.append(("ur5_display_trajectory_quintic_full", UR5, rel("ur5_display_trajectory.yaml"), ["--message", "2"],
                  second, 3, "full"))
    # ROS 1: a RobotTrajectory as `rostopic echo` prints it; a FollowJointTrajectoryGoal as JSON
    # (secs/nsecs), positions only, played cubic by positions_upsampling's spline
    out("ur5_ros1_robot_trajectory.yaml", ros1_echo_yaml([ros1(robot_trajectory(message(ur5, 2)))]))
    cases.append(("ur5_ros1_robot_trajectory_cubic_gravity", UR5, rel("ur5_ros1_robot_trajectory.yaml"), [], ur5, 2,
                  "gravity"))
    with open(os.path.join(MESSAGES, "ur5_ros1_goal.json"), "w") as f:
        json.dump(ros1({"trajectory": message(ur5, 1), "goal_time_tolerance": {"sec": 0, "nanosec": 0}}), f, indent=1)
    cases.append(("ur5_ros1_goal_upsampled_cubic_full", UR5, rel("ur5_ros1_goal.json"), [], ur5, 1, "full", None,
                  "cubic"))
    # an FR3's JointTrajectory as ros2 topic echo printed it (frankarobotics/franka_ros2 issue
    # 172; tests/fixtures/messages/README.md), on the Panda, its prefix renamed
    fr3 = yaml.safe_load(open(os.path.join(MESSAGES, "fr3_joint_trajectory_echo.yaml")))
    names = [n.replace("fr3_joint", "panda_joint") for n in fr3["joint_names"]]
    pts = [(p["positions"], p["time_from_start"]["sec"]) for p in fr3["points"]]
    cases.append(("panda_fr3_echo_renamed_linear_gravity", PANDA, rel("fr3_joint_trajectory_echo.yaml"),
                  ["--rename", "fr3_joint=panda_joint"], plan_of(names, pts), 1, "gravity"))
    # recorded JointState streams of the SO-101 (arm, gripper apart, a camera it lacks)
    epoch = 1_767_225_600_123_456_789
    keep = set(so101.names) | {"gripper"}
    zeros = so101_streams(so101, epoch, 30, lambda t, v: np.zeros_like(v), 7)
    out("so101_joint_states_echo.yaml", echo_yaml([m for _, m in zeros]))
    cases.append(("so101_echo_zero_velocities_linear_gravity", SO101, rel("so101_joint_states_echo.yaml"), [],
                  merged(zeros, keep, False), 1, "gravity"))
    true = so101_streams(so101, epoch, 50, lambda t, v: v, 11)
    write_mcap(os.path.join(MESSAGES, "so101_publishers.mcap"), [
        ("/joint_states", "sensor_msgs/msg/JointState", JOINT_STATE, true)])
    cases.append(("so101_mcap_publishers_cubic_full", SO101, rel("so101_publishers.mcap"), [],
                  merged(true, keep, True), 2, "full"))
    rng = np.random.default_rng(5)
    noisy = so101_streams(so101, epoch, 30, lambda t, v: v + rng.normal(0.0, 0.5, len(v)), 13)
    with open(os.path.join(MESSAGES, "so101_ros1_joint_states.json"), "w") as f:
        json.dump([{**ros1(m), "effort": []} for _, m in noisy], f)  # JSON has no NaN
    cases += [("so101_ros1_noisy_velocities_linear_gravity", SO101, rel("so101_ros1_joint_states.json"), [],
               merged(noisy, keep, False), 1, "gravity"),
              ("so101_ros1_noisy_upsampled_cubic_gravity", SO101, rel("so101_ros1_joint_states.json"), [],
               merged(noisy, keep, False), 1, "gravity", None, "cubic")]
    return cases



def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--faze4", default=os.path.join(ROOT, "target/debug/faze4"))
    ap.add_argument("--convert", default=os.path.join(ROOT, "target/debug/examples/convert_trajectory"))
    ap.add_argument("--only", nargs="*", help="the cases to run (default: all)")
    args = ap.parse_args()
    os.makedirs(FILES, exist_ok=True)
    ur5, so101 = toppra_ur5(), ruckig_so101()
    rel = lambda name: f"tests/fixtures/trajectories/{name}"  # noqa: E731
    shuffled = [2, 0, 5, 1, 4, 3]

    with open(os.path.join(FILES, "ur5_toppra.yaml"), "w") as f:
        f.write(echo_yaml([message(ur5, 1), message(ur5, 3)]))
    with open(os.path.join(FILES, "ur5_toppra.json"), "w") as f:
        json.dump(message(ur5, 2, shuffled), f, indent=1)
    write_mcap(os.path.join(FILES, "ur5_toppra.mcap"),
               [("/scaled_joint_trajectory_controller/joint_trajectory", "trajectory_msgs/msg/JointTrajectory",
                 JOINT_TRAJECTORY, [(0, message(ur5, 3))])])
    write_csv(os.path.join(FILES, "ur5_toppra.csv"), ur5, 1, shuffled)
    write_csv(os.path.join(FILES, "so101_ruckig.csv"), so101, 2, [3, 1, 4, 0, 2])
    epoch = 1_767_225_600_123_456_789
    write_mcap(os.path.join(FILES, "so101_ruckig.mcap"), [
        ("/arm_controller/joint_trajectory", "trajectory_msgs/msg/JointTrajectory", JOINT_TRAJECTORY,
         [(epoch, message(so101, 3))]),
        ("/joint_states", "sensor_msgs/msg/JointState", JOINT_STATE, joint_states(so101, {"gripper": 0.0}, epoch)),
    ])
    states = joint_states(so101, {"gripper": 0.0}, epoch)
    write_mcap(os.path.join(FILES, "bad_topics.mcap"), [
        ("/chatter", "std_msgs/msg/String", STRING, [(epoch, {"data": "hello"})]),
        ("/left_arm/joint_states", "sensor_msgs/msg/JointState", JOINT_STATE, states[:3]),
        ("/right_arm/joint_states", "sensor_msgs/msg/JointState", JOINT_STATE, states[:3]),
    ])

    write_bags(ur5, so101, epoch)
    so101_calibrated, so101_degrees = write_lerobot(so101)
    lerobot = lambda name: f"tests/fixtures/trajectories/lerobot/{name}"  # noqa: E731
    bag = lambda name: f"tests/fixtures/trajectories/bags/{name}"  # noqa: E731

    # name, URDF, input, options, plan, level (1 linear, 2 cubic, 3 quintic), feed-forward
    cases = [
        ("so101_db3_joint_states_cubic_full", SO101, bag("so101_humble_db3"), ["--topic", "/joint_states"], so101, 2,
         "full"),
        ("so101_mcap_zstd_per_message_quintic_gravity", SO101, bag("so101_mcap_zstd_per_message"), [], so101, 3,
         "gravity"),
        ("ur5_db3_zstd_per_file_linear_gravity", UR5, bag("ur5_db3_zstd_per_file"), [], ur5, 1, "gravity"),
        ("ur5_mcap_zstd_per_file_cubic_full", UR5, bag("ur5_mcap_zstd_per_file"), [], ur5, 2, "full"),
        ("so101_ros1_bz2_joint_states_cubic_gravity", SO101, bag("so101_noetic_bz2.bag"),
         ["--topic", "/joint_states"], so101, 2, "gravity"),
        ("ur5_ros1_lz4_quintic_full", UR5, bag("ur5_noetic_lz4.bag"), [], ur5, 3, "full"),
        ("so101_lerobot_v3_calibrated_linear_gravity", SO101, lerobot("so101_v3"),
         ["--episode", "1", "--calibration", lerobot("so101_calibration.json")], so101_calibrated, 1, "gravity"),
        ("so101_lerobot_v21_degrees_linear_full", SO101, lerobot("so101_v21"),
         ["--units", "deg", "--lerobot-key", "observation.state"], so101_degrees, 1, "full"),
        ("ur5_yaml_linear_full", UR5, rel("ur5_toppra.yaml"), [], ur5, 1, "full"),
        ("ur5_yaml_quintic_gravity", UR5, rel("ur5_toppra.yaml"), ["--message", "2"], ur5, 3, "gravity"),
        ("ur5_json_cubic_gravity", UR5, rel("ur5_toppra.json"), [], ur5, 2, "gravity"),
        ("ur5_mcap_quintic_full", UR5, rel("ur5_toppra.mcap"), [], ur5, 3, "full"),
        ("ur5_csv_linear_gravity", UR5, rel("ur5_toppra.csv"), [], ur5, 1, "gravity"),
        ("so101_csv_cubic_full", SO101, rel("so101_ruckig.csv"), [], so101, 2, "full"),
        ("so101_mcap_quintic_gravity", SO101, rel("so101_ruckig.mcap"), [], so101, 3, "gravity"),
        ("so101_mcap_joint_states_cubic_full", SO101, rel("so101_ruckig.mcap"), ["--topic", "/joint_states"],
         so101, 2, "full"),
    ]
    cases += write_messages(ur5, so101)
    only = set(args.only or [])
    for case in cases:
        if only and case[0] not in only:
            continue
        fixture = run_case(args.faze4, case)
        out = os.path.join(FIXTURES, f"trajectory_{case[0]}.json")
        with open(out, "w") as f:
            json.dump(fixture, f)
        print(f"{os.path.relpath(out, ROOT)}: {len(fixture['trail']['rows'])} rows, {fixture['interpolation']}, "
              f"ff {fixture['feed_forward']}")
    check_written(args.convert, ur5)


if __name__ == "__main__":
    main()
