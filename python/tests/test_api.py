"""The Python API: the robot's dynamics against Drake's fixtures, arrays in and out, errors,
panics, Ctrl-C, the docs and the stubs."""

from __future__ import annotations

import ast
import json
import os
import signal
import threading
import time

import numpy as np
import pytest

import faze4
from conftest import ROOT

FIXTURES = ["core_faze4_arm.json", "core_arm_prismatic.json", "core_tree_arm.json"]


def fixture(name: str) -> dict:
    return json.loads((ROOT / "tests" / "fixtures" / name).read_text())


@pytest.mark.parametrize("name", FIXTURES)
def test_dynamics_agree_with_drake(name):
    fx = fixture(name)
    robot = faze4.Robot.from_urdf(ROOT / fx["urdf"], tool_link=fx["tool_frame"])
    # Drake's joint order → ours
    order = [robot.joint_names.index(j) for j in fx["joint_names"]]
    n = robot.dof
    assert sorted(order) == list(range(n))

    def ours(drake):
        v = np.zeros(n)
        v[order] = drake
        return v

    damping = ours(fx["damping"])
    for s in fx["samples"]:
        q, v = ours(s["q"]), ours(s["v"])
        m_drake = np.zeros((n, n))
        m_drake[np.ix_(order, order)] = np.array(s["M"])
        scale = np.abs(m_drake).max()
        m = robot.mass_matrix(q)
        assert m.shape == (n, n) and m.dtype == np.float64
        assert np.abs(m - m_drake).max() / scale < 1e-10
        g, cv = ours(s["g"]), ours(s["Cv"])
        assert np.abs(robot.gravity(q) - g).max() / np.abs(g).max() < 1e-10
        # rnea(q, v, 0) = C v + g; rnea(q, 0, a) - g = M a
        tau = robot.rnea(q, v, np.zeros(n))
        assert np.abs(tau - (cv + g)).max() / np.abs(cv + g).max() < 1e-10
        a = np.linspace(-1.0, 1.0, n)
        assert np.allclose(robot.rnea(q, np.zeros(n), a) - g, m_drake @ a, rtol=0, atol=1e-10 * scale)
        # aba = M⁻¹ (τ − D v − C v − g), with Drake's M, C v and g
        tau = ours(s["step"]["tau"])
        expected = np.linalg.solve(m_drake, tau - damping * v - cv - g)
        qdd = robot.aba(q, v, tau)
        assert np.abs(qdd - expected).max() / np.abs(expected).max() < 1e-9
        # frame poses
        for link, pose in s["frames"].items():
            t = robot.frame_pose(q, link)
            assert t.shape == (4, 4)
            assert np.abs(t[:3, :3] - np.array(pose["R"])).max() < 1e-12
            assert np.abs(t[:3, 3] - np.array(pose["p"])).max() < 1e-12
            assert np.array_equal(t[3], [0, 0, 0, 1])


def test_robot_properties():
    robot = faze4.Robot.faze4()
    assert robot.dof == 6 and len(robot.joint_names) == 6 and "tool_link" in robot.link_names
    for name in ("effort", "lower", "upper"):
        array = getattr(robot, name)
        assert array.shape == (6,) and array.dtype == np.float64
    assert np.all(robot.lower < robot.upper)
    # the bundled arm's motors (docs/motors.md): 0.315 N·m × the reducers' ratios
    motors = faze4.Robot.faze4(motors="faze4")
    assert not np.array_equal(motors.effort, robot.effort)
    prismatic = faze4.Robot.from_urdf(ROOT / "tests" / "urdf" / "arm_prismatic.urdf")
    assert prismatic.dof == len(fixture("core_arm_prismatic.json")["joint_names"])


def test_the_summary_says_what_was_simulated():
    # mimic_gripper_arm: the followers wrist_follow and finger_right are no degrees of freedom
    robot = faze4.Robot.from_urdf(ROOT / "tests" / "urdf" / "mimic_gripper_arm.urdf")
    summary = faze4.wave(robot, duration=0.05, center="mid").summary
    assert summary["robot"] == "mimic_gripper_arm"
    assert [(j["name"], j["unit"]) for j in summary["joints"]] == [
        ("shoulder_yaw", "rad"),
        ("shoulder_pitch", "rad"),
        ("elbow", "rad"),
        ("finger_left", "m"),
    ]
    assert (summary["tool_link"], summary["tool_choice"], summary["meshes"]) == ("tool_link", "named_tool_link", [])
    # the bundled arm's meshes are built into the binary, listed without the clearance too
    summary = faze4.wave(faze4.Robot.faze4(), duration=0.05, no_collisions=True, tool_link="saka").summary
    assert summary["robot"] == "faze4_arm" and summary["tool_choice"] == "given"
    assert [(m["link"], m["source"]) for m in summary["meshes"]] == [(j["name"], "built-in") for j in summary["joints"]]


def test_a_xacro_robot_is_read_by_keywords_as_the_binary_reads_it():
    """``faze4.Robot(robot=…, xacro_arg=…)``: the official UR description expanded equals
    xacro's expansion (tests/fixtures/xacro, by tools/oracle/xacro_fixtures.py)."""
    import pickle

    ur = ROOT / "tests" / "xacro" / "ur_description" / "urdf" / "ur.urdf.xacro"
    expanded = ROOT / "tests" / "fixtures" / "xacro" / "ur5e.urdf"
    robot = faze4.Robot(robot=ur, xacro_arg=["name:=ur5e", "ur_type:=ur5e"], package_path=[ROOT / "tests" / "xacro"])
    oracle = faze4.Robot(urdf=expanded)  # the old name of robot
    assert robot.dof == 6 and robot.joint_names == oracle.joint_names
    q = np.linspace(-1.0, 1.0, 6)
    assert np.array_equal(robot.mass_matrix(q), oracle.mass_matrix(q))
    assert np.array_equal(robot.gravity(q), oracle.gravity(q))
    ours, theirs = faze4.wave(robot, duration=0.2, no_collisions=True), faze4.wave(oracle, duration=0.2, no_collisions=True)
    assert np.array_equal(ours.q, theirs.q)
    assert ours.summary["robot_source"] == f"{ur}, name:=ur5e, ur_type:=ur5e"
    assert ours.summary["format"] == "xacro" and theirs.summary["format"] == "urdf"
    assert pickle.loads(pickle.dumps(robot)).joint_names == robot.joint_names
    with pytest.raises(faze4.Error, match="xacro_arg: .* takes no xacro arguments"):
        faze4.Robot(robot=expanded, xacro_arg="a:=1")
    with pytest.raises(faze4.Error, match="urdf: is robot's old name"):
        faze4.Robot(robot=expanded, urdf=expanded)
    with pytest.raises(TypeError, match="xacro_arg: takes texts"):
        faze4.Robot(robot=ur, xacro_arg=[1])


def test_an_mjcf_model_runs_from_its_home_keyframe():
    # Menagerie's UR5e: MuJoCo's home keyframe is the wave's centre, its actuators' forcerange the
    # torque limits, and the summary says the format and what the reading mapped
    robot = faze4.Robot.from_urdf(ROOT / "tests" / "mjcf" / "menagerie" / "ur5e.xml")
    run = faze4.wave(robot, duration=0.05, center="home", amp_deg=1, no_collisions=True)
    summary = run.summary
    assert summary["format"] == "mjcf" and summary["effort"] == [150.0, 150.0, 150.0, 28.0, 28.0, 28.0]
    assert {m["from"] for m in summary["mapped"]} >= {"armature", "actuator forcerange", "keyframe home"}
    # the command starts at the centre plus A sin(i pi/3) (A = 1 degree)
    home = np.array(fixture("mjcf_ur5e.json")["home"])
    start = home + np.radians(1.0) * np.sin(np.arange(6) * np.pi / 3)
    assert np.allclose(run.q_cmd[0], start, rtol=0, atol=1e-12)
    # robot= reads an MJCF model as from_urdf does; a xacro argument for it is refused
    by_keyword = faze4.Robot(robot=ROOT / "tests" / "mjcf" / "menagerie" / "ur5e.xml")
    assert by_keyword.joint_names == robot.joint_names
    q = np.linspace(-1.0, 1.0, 6)
    assert np.array_equal(by_keyword.mass_matrix(q), robot.mass_matrix(q))
    with pytest.raises(faze4.Error, match="xacro_arg: .* is an MJCF file, not a xacro file"):
        faze4.Robot(robot=ROOT / "tests" / "mjcf" / "menagerie" / "ur5e.xml", xacro_arg="a:=1")
    with pytest.raises(ValueError, match="offers no start pose"):
        faze4.wave(faze4.Robot.from_urdf(ROOT / "tests" / "mjcf" / "so101" / "scene.xml"), center="home")


def test_an_mjcf_models_frictionloss_is_simulated(tmp_path):
    # TheRobotStudio's SO-101 by robot=: its frictionloss is the joints' Coulomb friction, and the
    # fixture's wave equals MuJoCo's M, C v and g stepped with faze4's friction (tests/it/mjcf.rs)
    fx = fixture("mjcf_so101.json")
    cl = fx["closed_loop"]
    a = cl["args"]
    def wave(robot):
        return faze4.wave(robot, center="mid", amp_deg=a["amp_deg"], amp_m=a["amp_m"], freq=a["freq"],
                          duration=a["duration"], dt=a["dt"], record_period=a["record_period"],
                          tool_link=a["tool_link"], no_collisions=True)

    run = wave(faze4.Robot(robot=ROOT / fx["model"]))
    mapped = {m["from"]: m for m in run.summary["mapped"]}
    assert mapped["frictionloss"]["to"] == "joint Coulomb friction"
    assert not mapped["frictionloss"]["changes_dynamics"]
    rows = np.array(cl["trail"]["rows"])
    assert run.q.shape == rows[:, 4:].shape
    assert np.max(np.abs(run.q - rows[:, 4:])) <= 1e-9
    # the same file without its frictionloss runs another wave
    text = (ROOT / fx["model"]).read_text()
    (tmp_path / "so101.xml").write_text(text.replace('frictionloss="', 'frictionloss="0" was="'))
    free = wave(faze4.Robot(robot=tmp_path / "so101.xml"))
    assert "frictionloss" not in {m["from"] for m in free.summary["mapped"]}
    assert np.max(np.abs(free.q - rows[:, 4:])) > 1e-4


def test_model_options_change_the_model():
    q = np.zeros(6)
    plain, heavy = faze4.Robot.faze4(), faze4.Robot.faze4(payload_kg=1.0)
    assert np.abs(heavy.gravity(q)).sum() > np.abs(plain.gravity(q)).sum()
    assert not np.any(faze4.Robot.faze4(no_gravity=True).gravity(q))
    rotors = faze4.Robot.faze4(rotor_inertia=[1e-5] * 6, gear_ratio=[50.0] * 6)
    assert np.allclose(np.diag(rotors.mass_matrix(q)) - np.diag(plain.mass_matrix(q)), 1e-5 * 2500)
    with pytest.raises(faze4.Error, match="^amp_deg: "):
        faze4.Robot.faze4(amp_deg=3.0)


def test_arrays_in_are_checked_or_read_exactly():
    robot = faze4.Robot.faze4()
    q = np.array([0.1, -0.4, 0.7, 0.2, -0.3, 0.5])
    expected = robot.gravity(q)
    # the same values any way they come: list, ints, float32-exact, strided, reversed, read-only
    wide = np.zeros(12)
    wide[::2] = q
    reversed_view = q[::-1].copy()[::-1]
    frozen = q.copy()
    frozen.flags.writeable = False
    for same in (q.tolist(), tuple(q), wide[::2], reversed_view, frozen, np.asfortranarray(q)):
        assert np.array_equal(robot.gravity(same), expected)
    assert np.array_equal(robot.gravity(np.arange(6)), robot.gravity(np.arange(6.0)))
    q32 = q.astype(np.float32)
    assert np.array_equal(robot.gravity(q32), robot.gravity(q32.astype(np.float64)))
    # wrong shape, NaN, wrong type: an error naming the argument
    for bad, error in (
        (np.zeros(5), faze4.Error),
        (np.zeros((6, 1)), faze4.Error),
        (np.zeros((2, 6)), faze4.Error),
        (np.full(6, np.nan), faze4.Error),
        (np.array([0, 0, 0, 0, 0, np.inf]), faze4.Error),
        (np.zeros(6, dtype=complex), TypeError),
        (np.array(["a"] * 6), TypeError),
        ("abcdef", TypeError),
        (None, TypeError),
    ):
        with pytest.raises(error, match="q"):
            robot.gravity(bad)
    with pytest.raises(faze4.Error, match="tau"):
        robot.aba(q, q, np.zeros(7))
    with pytest.raises(faze4.Error, match="no link 'nowhere'"):
        robot.frame_pose(q, "nowhere")
    # outputs are fresh arrays, not views of a workspace
    first = robot.rnea(q, q, q)
    robot.rnea(np.zeros(6), np.zeros(6), np.zeros(6))
    assert np.array_equal(first, robot.rnea(q, q, q))


def test_trajectories_are_checked():
    robot = faze4.Robot.faze4()
    with pytest.raises(faze4.Error, match="columns; the model has 6 joints"):
        faze4.replay(robot, np.zeros((10, 5)))
    with pytest.raises(faze4.Error, match="at least 2 frames"):
        faze4.replay(robot, np.zeros((1, 6)))
    with pytest.raises(faze4.Error, match="frame 3, joint 2 is NaN"):
        frames = np.zeros((5, 6))
        frames[3, 1] = np.nan
        faze4.replay(robot, frames)
    with pytest.raises(faze4.Error, match="shape"):
        faze4.replay(robot, np.zeros(6))
    with pytest.raises(TypeError):
        faze4.replay(robot, np.zeros((4, 6), dtype=complex))
    with pytest.raises(faze4.Error, match="beyond its limits"):
        faze4.replay(robot, np.full((4, 6), 10.0))


def test_a_divergence_is_a_result_not_an_exception():
    run = faze4.wave(faze4.Robot.faze4(), kp=[None] * 5 + [40000.0], effort=[7.9, 8.5, 4.7, 3.7, 3.5, 1e9], duration=1.0)
    assert run.summary["diverged"]["joint"] == 6 and not run.follows
    assert run.reasons and run.t[-1] < 0.1


def test_a_panic_does_not_take_the_interpreter_down():
    for on_worker in (False, True):
        with pytest.raises(BaseException, match="a test panic") as caught:
            faze4._faze4._panic(on_worker)
        assert type(caught.value).__name__ == "PanicException"
    assert faze4.wave(faze4.Robot.faze4(), duration=0.01).follows


def _interrupt_after(seconds: float) -> list[float]:
    sent = []

    def send():
        time.sleep(seconds)
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=send, daemon=True).start()
    return sent


@pytest.mark.parametrize("call", ["wave", "sweep", "retime"])
def test_ctrl_c_raises_keyboard_interrupt_within_a_tenth_of_a_second(call, tmp_path):
    # Python's own Ctrl-C handler, as in a terminal: a process a shell starts in the background
    # without job control inherits SIGINT ignored, and Python then installs no handler
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        robot = faze4.Robot.faze4()
        sent = _interrupt_after(0.5)
        with pytest.raises(KeyboardInterrupt):
            if call == "wave":
                faze4.wave(robot, duration=3600.0, no_collisions=True)
            elif call == "sweep":
                faze4.sweep(robot, "wave", vary={"payload_kg": [0.0, 0.1, 0.2, 0.3]}, duration=3600.0, no_collisions=True)
            else:
                # jerk limits this small time the circle over about 5,400 s: the check runs for
                # minutes; a check a signal ends early writes nothing, `force` or not
                circle = ROOT / "tests" / "fixtures" / "shape_circle_q.npy"
                out = tmp_path / "c.yaml"
                faze4.retime(robot, circle, motors="faze4", max_jerk=[1e-3] * 6, out=out, force=True)
        latency = time.perf_counter() - sent[0]
        assert latency < 0.1, f"KeyboardInterrupt {latency:.3f} s after SIGINT"
        assert list(tmp_path.iterdir()) == []
    finally:
        signal.signal(signal.SIGINT, previous)


def test_files_stay_available(tmp_path):
    robot = faze4.Robot.faze4()
    run = faze4.shape(
        robot,
        "circle",
        duration=1.0,
        html=tmp_path / "c.html",
        plot=tmp_path / "c.svg",
        trail=tmp_path / "t.csv",
        summary=tmp_path / "s.json",
        save_q=tmp_path / "q.npy",
    )
    for name in ("c.html", "c.svg", "t.csv", "s.json", "q.npy"):
        assert (tmp_path / name).stat().st_size > 0, name
    assert json.loads((tmp_path / "s.json").read_text())["steps"] == run.summary["steps"]
    assert len((tmp_path / "t.csv").read_text().splitlines()) == len(run.t) + 1
    # the shape's IK samples replay as the binary's `faze4 replay --q-traj q.npy` would
    assert faze4.replay(robot, np.load(tmp_path / "q.npy"), duration=0.5).summary["dof"] == 6


def test_help_lists_every_option():
    for command, function in (("wave", faze4.wave), ("replay", faze4.replay), ("shape", faze4.shape)):
        doc = function.__doc__
        names = [o.name for o in faze4.options(command)]
        assert names and all(f"    {name} (" in doc or name in ("q_traj", "shape", "robot") for name in names)
        import inspect

        parameters = inspect.signature(function).parameters
        assert set(names) <= set(parameters)
        for option in faze4.options(command):
            # a run's `robot` is the Robot, whose own option the robot file is
            if option.name not in ("q_traj", "shape", "robot"):
                assert parameters[option.name].default == faze4._default(option)


def _stub_keywords(tree: ast.Module, function: str, cls: str | None = None) -> list[tuple[str, object]]:
    body = tree.body
    if cls:
        body = next(n for n in body if isinstance(n, ast.ClassDef) and n.name == cls).body
    node = next(n for n in body if isinstance(n, ast.FunctionDef) and n.name == function)
    return [(a.arg, ast.literal_eval(d)) for a, d in zip(node.args.kwonlyargs, node.args.kw_defaults)]


def test_stub_keywords_are_the_binarys_options():
    """python/faze4/__init__.pyi is static: after an option changes, tools/python/stubs.py
    rewrites it."""
    tree = ast.parse((ROOT / "python" / "faze4" / "__init__.pyi").read_text())
    expect = {
        ("wave", None): ("wave", ("robot",)),
        ("replay", None): ("replay", ("q_traj", "robot")),
        ("shape", None): ("shape", ("shape", "robot")),
        ("retime", None): ("retime", ("q_traj", "robot")),
        ("__new__", "Robot"): ("run", ()),
        ("faze4", "Robot"): ("run", ()),
        ("from_urdf", "Robot"): ("run", ("robot", "package_path", "tool_link")),
    }
    for (function, cls), (command, skip) in expect.items():
        options = [(o.name, faze4._default(o)) for o in faze4.options(command) if o.name not in skip]
        assert _stub_keywords(tree, function, cls) == options, (
            f"{function}: the stub's keywords differ from the binary's options: run tools/python/stubs.py"
        )


def test_python_defaults_are_the_only_ones_that_differ():
    assert set(faze4.PYTHON_DEFAULTS) == {"quiet"}
    # the library writes no trail file unless asked: faze4_trail.csv is the binary's own default
    declared = {o.name: o.default for o in faze4.options("wave")}
    assert declared["trail"] is None


def test_motors_as_a_dict_equal_the_motors_file():
    # issue 23: motors= takes a path, a preset name or a dict of the file's schema
    import tomllib

    path = ROOT / "tests" / "motors" / "dc_arm.toml"
    table = tomllib.loads(path.read_text())
    urdf = ROOT / "tests" / "urdf" / "motor_arm.urdf"
    common = dict(duration=0.5, no_collisions=True)
    by_file = faze4.wave(faze4.Robot.from_urdf(urdf, motors=str(path)), **common)
    by_dict = faze4.wave(faze4.Robot.from_urdf(urdf, motors=table), **common)
    by_run = faze4.wave(faze4.Robot.from_urdf(urdf), motors=table, **common)
    strip = lambda s: {k: v for k, v in s.items() if "wall_time" not in k}  # noqa: E731
    assert "motors" in by_file.summary
    assert strip(by_dict.summary) == strip(by_file.summary)
    assert strip(by_run.summary) == strip(by_file.summary)
    preset = faze4.wave(faze4.Robot.faze4(motors="faze4"), **common)
    assert [m["kind"] for m in preset.summary["motors"]] == ["stepper"] * 6
    with pytest.raises(faze4.Error, match="^motors: "):
        faze4.Robot.from_urdf(urdf, motors={"joints": []})


def test_the_servo_drive_runs_sweeps_and_finds_from_python():
    # issue 45: drive="servo" through the option's declaration; SO-ARM100 #134's 10 cm lever
    lever = faze4.Robot.from_urdf(ROOT / "tests" / "urdf" / "servo_lever.urdf", motors="sts3215")
    common = dict(drive="servo", amp_deg=0.0, duration=3.0, no_collisions=True)
    held = faze4.wave(lever, payload_kg=1.0, **common)
    fell = faze4.wave(lever, payload_kg=2.0, **common)
    assert held.summary["motors"][0]["drive"] == "servo"
    assert held.summary["motors"][0]["servo"]["trip"] is None
    trip = fell.summary["motors"][0]["servo"]["trip"]
    assert trip["kind"] == "overload" and 2.0 < trip["t"] < 2.2, trip
    assert "J1's servo trips its overload protection at t = 2.09 s" in fell.verdict_line
    assert any("protection registers (J1) are assumed" in w for w in fell.warnings), fell.warnings
    rows = faze4.sweep(lever, "wave", vary={"payload_kg": [1.0, 2.0]}, jobs=2, **common)
    assert [r["motors"][0]["servo"]["trip"] is None for r in rows] == [True, False]
    found = faze4.find(lever, "wave", "payload_kg", 0.0, 3.0, resolution=0.01, jobs=2, max_error=0.5, **common)
    assert found.found == "boundary" and 1.55 < found.value < 1.8, found
    assert "servo trips its overload protection" in found.reason
    with pytest.raises(faze4.Error, match="^servo_rate: "):
        faze4.wave(lever, servo_rate=0.0, **common)
    with pytest.raises(faze4.Error, match="^drive: "):
        faze4.wave(faze4.Robot.faze4(motors="faze4"), drive="servo", duration=0.1, no_collisions=True)
