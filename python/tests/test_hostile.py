"""Bad input from Python (issue 35): each case raises a Python exception whose message is the
binary's one line, and the interpreter lives on to run the next; no file is changed."""

from __future__ import annotations

import os
import struct
import subprocess
import sys

import numpy as np
import pytest

import faze4
from conftest import ROOT

ARM = ROOT / "tests" / "urdf" / "mesh_arm_stl.urdf"


def _one_line(error: BaseException) -> str:
    message = str(error)
    assert message and "\n" not in message and "\r" not in message, repr(message)
    assert "panicked" not in message
    return message


def _mcap_claiming(length: int) -> bytes:
    """An MCAP file (https://mcap.dev/spec) whose JointState message, in a zstd chunk (one raw
    block), claims `length` bytes."""

    def record(op: int, body: bytes) -> bytes:
        return bytes([op]) + struct.pack("<Q", len(body)) + body

    def string(s: str) -> bytes:
        return struct.pack("<I", len(s)) + s.encode()

    magic = b"\x89MCAP0\r\n"
    message = bytes([5]) + struct.pack("<QH", length, 1) + bytes(20)
    frame = bytes([0x28, 0xB5, 0x2F, 0xFD, 0, 0x10]) + struct.pack("<I", 1 | len(message) << 3)[:3] + message
    chunk = struct.pack("<QQQI", 0, 0, length, 0) + string("zstd") + struct.pack("<Q", len(frame)) + frame
    return b"".join(
        [
            magic,
            record(1, string("ros2") + string("hostile")),
            record(3, struct.pack("<H", 1) + string("sensor_msgs/msg/JointState") + string("ros2msg") + bytes(4)),
            record(4, struct.pack("<HH", 1, 1) + string("/joint_states") + string("cdr") + bytes(4)),
            record(6, chunk),
            record(0x0F, bytes(4)),
            record(2, bytes(20)),
            magic,
        ]
    )


def test_bad_input_raises_one_line_and_the_interpreter_lives_on(tmp_path):
    (tmp_path / "zero.urdf").symlink_to("/dev/zero")
    (tmp_path / "zero.yaml").symlink_to("/dev/zero")
    (tmp_path / "zero.toml").symlink_to("/dev/zero")
    (tmp_path / "bomb.mcap").write_bytes(_mcap_claiming(1 << 40))
    robot = faze4.Robot.faze4()
    cases = [
        (lambda: faze4.Robot.from_urdf(tmp_path / "zero.urdf"), "a stream of more than the 16 MiB a URDF may hold"),
        (lambda: faze4.Robot.faze4(motors=str(tmp_path / "zero.toml")), "a stream of more than the 1 MiB"),
        (lambda: faze4.replay(robot, tmp_path / "zero.yaml"), "more than the 16 MiB a YAML trajectory may hold"),
        (lambda: faze4.replay(robot, tmp_path / "bomb.mcap"), "bomb.mcap: not a readable MCAP file"),
        (lambda: faze4.shape(robot, "circle", shape_points=100_000_000), "shape_points: 100000000 samples: at most 100000"),
        (lambda: faze4.wave(robot, freq=1e308), "freq: 1e308 rad/s turns the wave more than half a period"),
        (lambda: faze4.retime(robot, [[0.0] * 6, [0.1] * 6], grid=10**9), "grid: 1000000000 intervals: at most 100000"),
    ]
    for call, part in cases:
        with pytest.raises(faze4.Error) as caught:
            call()
        message = _one_line(caught.value)
        assert part in message, message
    assert faze4.wave(robot, duration=0.01).follows


def test_forward_dynamics_overflow_is_an_error_not_nan():
    robot = faze4.Robot.faze4()
    q = np.zeros(robot.dof)
    with pytest.raises(faze4.Error) as caught:
        robot.aba(q, q, np.full(robot.dof, 1e308))
    _one_line(caught.value)
    assert np.all(np.isfinite(robot.aba(q, q, np.zeros(robot.dof))))


def test_inverse_dynamics_overflow_is_an_error_not_nan():
    robot = faze4.Robot.faze4()
    q = np.zeros(robot.dof)
    with pytest.raises(faze4.Error) as caught:
        robot.rnea(q, np.full(robot.dof, 1e200), q)
    message = _one_line(caught.value)
    assert message.startswith("v: inverse dynamics overflows: the torque of joint"), message
    assert np.all(np.isfinite(robot.rnea(q, q, q)))


def test_an_output_never_replaces_an_input(tmp_path):
    urdf = tmp_path / "arm.urdf"
    urdf.write_bytes(ARM.read_bytes())
    before = urdf.read_bytes()
    robot = faze4.Robot.from_urdf(urdf, package_path=[ROOT / "tests" / "urdf"])
    with pytest.raises(faze4.Error) as caught:
        faze4.wave(robot, duration=0.01, summary=str(urdf))
    message = _one_line(caught.value)
    assert "is the robot input" in message, message
    assert urdf.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["arm.urdf"]


def test_a_urdf_path_of_none_is_refused():
    with pytest.raises(TypeError, match="path is NoneType"):
        faze4.Robot.from_urdf(None)


def _in_a_child(code: str) -> subprocess.CompletedProcess:
    """``code`` run by a fresh interpreter: a crash (a segfault) fails the test, not pytest."""
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)


def test_a_motors_dict_holding_itself_or_nested_deep_is_an_error_not_a_crash():
    """Issue 49: a self-referencing or 20,000-deep motors dict segfaulted the interpreter (the
    conversion recursed); each is now a faze4.Error naming the nesting, a dict of more values
    than its cap one naming the cap, and the interpreter lives on."""
    code = """
import faze4
cases = {}
d = {}
d["joint"] = [d]
cases["itself"] = lambda: faze4.Robot.faze4(motors=d)
deep = {"kind": "dc"}
for _ in range(20_000):
    deep = {"joint": [deep]}
cases["deep"] = lambda: faze4.Robot.faze4(motors=deep)
e = {}
e["motors"] = e
cases["options"] = lambda: faze4._faze4.Robot(e)
wide = {"joint": [None] * (2**20 + 1)}
cases["wide"] = lambda: faze4.Robot.faze4(motors=wide)
for name, call in cases.items():
    try:
        call()
    except faze4.Error as caught:
        print(name, caught)
    else:
        print(name, "no error")
print("alive")
"""
    child = _in_a_child(code)
    assert child.returncode == 0, (child.returncode, child.stderr[-2000:])
    lines = child.stdout.splitlines()
    assert lines[-1] == "alive", child.stdout
    for name in ("itself", "deep", "options"):
        line = next(line for line in lines if line.startswith(name + " "))
        assert "motors: nested more than 32 deep" in line, line
    # a wide one is read up to its cap of values, then refused (config::object::MAX_OBJECT_VALUES)
    line = next(line for line in lines if line.startswith("wide "))
    assert "motors: holds more than 1048576 values" in line, line


def test_arrays_have_the_caps_of_the_same_data_as_a_file():
    """Issue 49: a 960 MB array peaked at 11.4 GB. An array of more float64 values than a .npy
    trajectory may hold (256 MiB) is refused before a copy is made, as the file would be; a
    time-stamped one has a trajectory file's caps on its points and joints. The arrays here are
    views that take no memory (broadcast zeros)."""
    robot = faze4.Robot.faze4()
    huge = np.broadcast_to(np.float32(0.0), (6_000_000, robot.dof))  # 144 MB as float32, 288 MB as float64
    cases = [
        (lambda: faze4.replay(robot, huge), "q_traj: shape [6000000, 6]: 274.7 MiB of float64 values, more than the 256 MiB"),
        (
            lambda: faze4._faze4._run("replay", {}, np.broadcast_to(0.0, (6_000_000, robot.dof)), None),
            "q_traj: shape [6000000, 6]: 274.7 MiB of float64 values",
        ),
        (
            lambda: faze4.replay(robot, np.zeros((1_000_001, 1)), t=np.arange(1_000_001.0)),
            "q_traj: 1000001 rows: more than the 1000000 points a trajectory may have",
        ),
    ]
    for call, part in cases:
        with pytest.raises(faze4.Error) as caught:
            call()
        message = _one_line(caught.value)
        assert part in message, message


def test_complex_numbers_are_refused_not_cast_to_their_real_part():
    """numpy's complex scalars convert to float with only a ComplexWarning, dropping the imaginary
    part: a complex array, a numpy complex scalar or a Python complex is refused by name (issue 49)."""
    import warnings

    robot = faze4.Robot.faze4()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for kw, value, words in [
            ("kp", np.array([1 + 1j] * 6), "not ndarray of complex128"),
            ("kp", np.array([1 + 0j] * 6, dtype=np.complex64), "not ndarray of complex64"),
            ("kp", [np.complex128(1 + 1j)] * 6, "one value per joint"),
            ("payload_kg", np.complex128(1 + 1j), "not complex128"),
            ("payload_kg", np.complex64(1), "not complex64"),
            ("payload_kg", 1 + 1j, "not complex"),
        ]:
            with pytest.raises(TypeError, match=words) as refused:
                faze4.wave(robot, duration=0.01, **{kw: value})
            assert _one_line(refused.value).startswith(kw), refused.value


def test_an_option_varied_and_given_is_refused_not_dropped():
    """A keyword that a sweep or search varies and the call also gives was dropped at each run
    unsaid: refused naming it, as the command line refuses it (issue 49, fourth round)."""
    robot = faze4.Robot.faze4()
    for call, part in [
        (
            lambda: faze4.sweep(robot, "wave", vary={"dt": [0.001, 0.002]}, dt=0.0001, duration=0.01, no_collisions=True),
            "vary: 'dt' is varied and also given to the command (dt): the sweep sets it at each run",
        ),
        (
            lambda: faze4.find(robot, "wave", "payload_kg", 0, 1, payload_kg=0.5, duration=0.01),
            "find: 'payload_kg' is varied and also given to the command (payload_kg)",
        ),
        (
            lambda: faze4.find(robot, "wave", "payload_kg", 0, 1, smallest=True, payload_kg=0.5, duration=0.01),
            "find_min: 'payload_kg' is varied",
        ),
    ]:
        with pytest.raises(faze4.Error) as caught:
            call()
        message = _one_line(caught.value)
        assert part in message, message
    rows = faze4.sweep(robot, "wave", vary={"kp_scale": [1, 2]}, duration=0.01, no_collisions=True)
    assert [r["kp_scale"] for r in rows] == [1, 2]
