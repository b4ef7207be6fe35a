"""Each command through the binary and through Python with the same options: the summaries are
equal bit for bit (wall-clock times aside), and so are the errors' messages and a search's line."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import faze4
from conftest import ROOT, run_binary, without_wall_times

REPLAY = ROOT / "tests" / "fixtures" / "replay_q_traj.npy"
ROTOR_ARM = ROOT / "tests" / "urdf" / "rotor_arm.urdf"
ERD = ROOT / "tests" / "urdf" / "example_robot_data"
MESSAGES = ROOT / "tests" / "fixtures" / "messages"
LEROBOT = ROOT / "tests" / "fixtures" / "trajectories" / "lerobot"


def words_of(options: dict) -> list[str]:
    """Python keywords → command-line words, written out independently of faze4's own mapping."""
    words = []
    for name, value in options.items():
        option = "--" + name.replace("_", "-")
        if value is True:
            words.append(option)
        elif isinstance(value, (list, tuple)):
            words += [option, ",".join("auto" if x is None else repr(x) for x in value)]
        else:
            words += [option, str(value)]
    return words


# (command, robot keywords, run keywords (positional ones first))
CASES = {
    "wave, every default": ("wave", {}, {}),
    "wave, options": ("wave", {}, {"amp_deg": 40.0, "freq": 1.5, "duration": 3.0, "payload_kg": 0.8, "center": "mid"}),
    "wave, motors on the robot": ("wave", {"motors": "faze4"}, {"duration": 2.0}),
    "wave, gains and flags": (
        "wave",
        {},
        {"duration": 1.0, "no_ff": True, "no_gravity": True, "kp": [None, None, None, None, None, 30.0], "dt": 1e-4},
    ),
    "wave, diverges": (
        "wave",
        {},
        {"kp": [None] * 5 + [40000.0], "effort": [7.9, 8.5, 4.7, 3.7, 3.5, 1e9], "duration": 1.0},
    ),
    "replay, file": ("replay", {}, {"q_traj": str(REPLAY), "traj_period": 4.0, "duration": 3.0}),
    "shape circle, every default": ("shape", {}, {"shape": "circle"}),
    "shape tri, payload on the robot, hulls": (
        "shape",
        {"payload_kg": 0.5},
        {"shape": "tri", "duration": 3.0, "collision_geometry": "hull", "shape_points": 120},
    ),
    "urdf arm with rotors": ("wave", {"urdf": str(ROTOR_ARM)}, {"duration": 1.0, "amp_deg": 10.0}),
    "replay, a goal from a start, cubic by the spline": (
        "replay",
        {"urdf": str(ERD / "ur5_robot.urdf")},
        {
            "q_traj": str(MESSAGES / "ur5_one_point_goal.yaml"),
            "start": [0.0, -1.57, 0.0, 0.0, 0.0, 0.0],
            "interpolation": "cubic",
            "no_collisions": True,
        },
    ),
    "replay, an FR3 echo renamed onto the Panda": (
        "replay",
        {"urdf": str(ERD / "panda.urdf")},
        {"q_traj": str(MESSAGES / "fr3_joint_trajectory_echo.yaml"), "rename": "fr3_joint=panda_joint", "no_collisions": True},
    ),
    "replay, a LeRobot episode normalised by its calibration": (
        "replay",
        {"urdf": str(ERD / "so101.urdf")},
        {
            "q_traj": str(LEROBOT / "so101_v3"),
            "episode": 1,
            "calibration": str(LEROBOT / "so101_calibration.json"),
            "no_collisions": True,
        },
    ),
    "replay, a LeRobot v2.1 state in degrees": (
        "replay",
        {"urdf": str(ERD / "so101.urdf")},
        {
            "q_traj": str(LEROBOT / "so101_v21"),
            "episode": 0,
            "units": "deg",
            "lerobot_key": "observation.state",
            "no_collisions": True,
        },
    ),
}


def python_run(command: str, robot_options: dict, options: dict) -> faze4.Run:
    robot = faze4.Robot.faze4(**robot_options)
    options = dict(options)
    if command == "replay":
        return faze4.replay(robot, options.pop("q_traj"), **options)
    if command == "shape":
        return faze4.shape(robot, options.pop("shape"), **options)
    return faze4.wave(robot, **options)


@pytest.mark.parametrize("case", CASES)
def test_summaries_equal_the_binarys(case, binary, tmp_path):
    command, robot_options, options = CASES[case]
    proc, expected = run_binary(binary, [command, *words_of(robot_options), *words_of(options)], tmp_path)
    assert expected is not None, proc.stderr
    run = python_run(command, robot_options, options)
    assert without_wall_times(run.summary) == without_wall_times(expected)
    # the verdict is the binary's last line
    assert proc.stdout.strip().splitlines()[-1] == run.verdict_line
    assert run.follows == expected["verdict"]["follows"]
    # run.verdict is the word: the summary's follows and collides say which
    word = "follows" if run.follows else "collides" if expected["verdict"]["collides"] else "cannot follow"
    assert run.verdict == word and run.verdict_line.startswith(f"verdict: {word}")
    if case == "wave, diverges":
        assert proc.returncode == 1 and run.summary["diverged"]["joint"] == 6


def test_a_replay_from_a_numpy_array_equals_the_binarys_from_the_file(binary, tmp_path):
    proc, expected = run_binary(binary, ["replay", "--q-traj", str(REPLAY), "--duration", "3"], tmp_path)
    frames = np.load(REPLAY)
    robot = faze4.Robot.faze4()
    for array in (frames, np.asfortranarray(frames), frames.tolist(), np.ascontiguousarray(frames[::-1])[::-1]):
        run = faze4.replay(robot, array, duration=3.0)
        assert without_wall_times(run.summary) == without_wall_times(expected)
    # float32 frames: the binary reads a float32 file as these exact doubles
    path32 = tmp_path / "q32.npy"
    np.save(path32, frames.astype(np.float32))
    _, expected32 = run_binary(binary, ["replay", "--q-traj", str(path32), "--duration", "3"], tmp_path)
    run = faze4.replay(robot, frames.astype(np.float32), duration=3.0)
    assert without_wall_times(run.summary) == without_wall_times(expected32)


def test_the_trail_arrays_are_the_binarys_trail(binary, tmp_path):
    trail = tmp_path / "t.csv"
    proc = __import__("subprocess").run(
        [binary, "wave", "--duration", "1", "--trail", str(trail), "-q"], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    table = np.loadtxt(trail, delimiter=",", skiprows=1)
    run = faze4.wave(faze4.Robot.faze4(), duration=1.0)
    assert run.t.shape == (table.shape[0],)
    assert np.array_equal(run.t, table[:, 0])
    assert np.array_equal(run.tool_xyz, table[:, 1:4])
    assert np.array_equal(run.q, table[:, 4:10])
    assert run.q_cmd.shape == run.q.shape and np.abs(run.q_cmd - run.q).max() < 0.05


def keywords(line: str) -> str:
    """The binary's line with each flag written as Python's keyword (--payload-kg → payload_kg)."""
    return re.sub(r"--([a-z][a-z0-9-]*)", lambda m: m.group(1).replace("-", "_"), line)


@pytest.mark.parametrize(
    "options",
    [{"dt": -1.0}, {"amp_deg": -3.0}, {"effort": [1.0, 2.0]}, {"kp": [1.0, 2.0]}, {"urdf": "/no/such.urdf"}],
)
def test_bad_input_raises_the_binarys_message_in_keywords(options, binary, tmp_path):
    proc, _ = run_binary(binary, ["wave", *words_of(options)], tmp_path)
    assert proc.returncode == 2
    line = proc.stderr.strip().splitlines()[-1]
    robot_options = {k: v for k, v in options.items() if k == "urdf"}
    with pytest.raises(faze4.Error) as caught:
        robot = faze4.Robot.faze4(**robot_options)
        faze4.wave(robot, **{k: v for k, v in options.items() if k != "urdf"})
    assert isinstance(caught.value, ValueError)
    message = str(caught.value)
    name = next(iter(options))
    if name != "urdf":  # an option's value: named by the option; a file: by its path
        assert line.startswith(f"faze4: error: --{name.replace('_', '-')}: "), line
        assert message.startswith(f"{name}: ") and "--" not in message, message
    assert keywords(line) == f"faze4: error: {message}"


def test_what_clap_refuses_python_refuses_in_its_own_words():
    robot = faze4.Robot.faze4()
    with pytest.raises(TypeError, match="unexpected keyword argument 'amp_dgr'"):
        faze4.wave(robot, amp_dgr=3.0)
    with pytest.raises(faze4.Error, match="^collision_geometry: 'box' is not one of mesh, hull$"):
        faze4.wave(robot, collision_geometry="box")


def test_find_says_what_the_binary_says(binary, tmp_path):
    words = ["sweep", "--find", "payload-kg=0:3", "--resolution", "0.1", "-j", "2", "--", "shape", "--shape", "circle", "--duration", "2"]
    proc = __import__("subprocess").run([binary, *words], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    best = faze4.find(faze4.Robot.faze4(), "shape", "payload_kg", 0.0, 3.0, resolution=0.1, jobs=2, shape="circle", duration=2.0)
    # the line names the option as each caller wrote it
    assert best.line == proc.stdout.strip().splitlines()[-1].replace("payload-kg", "payload_kg")
    if best.found == "boundary":
        assert best.value < best.fails_at and best.reason in best.line


def without_clearance(summary: dict) -> dict:
    return {k: v for k, v in without_wall_times(summary).items() if k != "clearance"}


def test_sweep_rows_are_the_single_runs(binary, tmp_path):
    robot = faze4.Robot.faze4()
    payloads = np.linspace(0.0, 1.4, 3)
    own = faze4.sweep(robot, "wave", vary={"payload_kg": payloads}, duration=1.0, own_clearance=True)
    shared = faze4.sweep(robot, "wave", vary={"payload_kg": payloads}, duration=1.0)
    assert [r["payload_kg"] for r in own] == [r["payload_kg"] for r in shared] == payloads.tolist()
    for own_row, shared_row, payload in zip(own, shared, payloads):
        single = faze4.wave(robot, duration=1.0, payload_kg=float(payload))
        expected = dict(single.summary, payload_kg=float(payload))
        # each run its own clearance: the run alone, to the bit
        assert without_wall_times(own_row) == without_wall_times(expected)
        # the path's clearance shared: the same run but for the clearance, which is an actual
        # distance within the tolerance of the run alone's (both within it of the exact minimum)
        assert without_clearance(shared_row) == without_clearance(expected)
        # (the verdict, with its intersections, is compared above)
        mine, alone = shared_row["clearance"], expected["clearance"]
        tolerance = alone["tolerance_m"]
        assert mine["tolerance_m"] == tolerance
        assert abs(mine["min_m"] - alone["min_m"]) <= tolerance
        assert [p["links"] for p in mine["pairs"]] == [p["links"] for p in alone["pairs"]]
        for a, b in zip(mine["pairs"], alone["pairs"]):
            assert abs(a["min_m"] - b["min_m"]) <= tolerance, (a, b)
    # and the binary's table has the same runs
    out = tmp_path / "rows.json"
    values = ",".join(repr(float(p)) for p in payloads)
    proc = __import__("subprocess").run(
        [binary, "sweep", "--vary", f"payload-kg={values}", "--out", str(out), "-q", "--", "wave", "--duration", "1"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    table = json.loads(out.read_text())
    assert len(table) == len(shared)
    for flat, row in zip(table, shared):
        assert flat["payload-kg"] == row["payload_kg"] and flat["follows"] == row["verdict"]["follows"]
        for field in ("max_tracking_error_rad", "saturation_pct", "max_speed"):
            assert [flat[f"{field}_{i + 1}"] for i in range(6)] == row[field]
        # the binary's sweep shares the path's clearance as Python's does
        assert flat["clearance_min_m"] == row["clearance"]["min_m"]


def test_rename_takes_the_repeated_options_list():
    """`rename` is `--rename` given once per rule: a list of rules, or one text of rules
    separated by commas; each rule must rename some joint."""
    robot = faze4.Robot.faze4(urdf=str(ERD / "panda.urdf"))
    echo = str(MESSAGES / "fr3_joint_trajectory_echo.yaml")
    listed = faze4.replay(robot, echo, rename=["fr3_joint=panda_joint"], no_collisions=True)
    joined = faze4.replay(robot, echo, rename="fr3_joint=panda_joint", no_collisions=True)
    assert without_wall_times(listed.summary) == without_wall_times(joined.summary)
    with pytest.raises(faze4.Error, match="rename: franka_=panda_: no joint of .* starts with 'franka_'"):
        faze4.replay(robot, echo, rename=["fr3_joint=panda_joint", "franka_=panda_"], no_collisions=True)
