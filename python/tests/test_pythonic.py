"""Python that behaves like Python (issue 36): strict runs raise CannotFollow carrying the run,
wrong types are TypeErrors, quiet=False prints what the binary prints, find() returns a small
object, a Robot pickles, copies and goes to a multiprocessing pool, dir(faze4) is its API; and
time-stamped arrays replay as the same trajectory in a file does (issue 31)."""

from __future__ import annotations

import copy
import functools
import multiprocessing
import pickle
import re
import subprocess

import numpy as np
import pytest

import faze4
from conftest import ROOT, run_binary, without_wall_times

# a short run the Faze4 follows by any measure: no thresholds to cross, no clearance to search
EASY = dict(duration=0.2, max_error=10.0, max_saturation_pct=100.0, max_deviation_mm=1e6, no_collisions=True)


def test_strict_raises_cannot_follow_carrying_the_run():
    robot = faze4.Robot.faze4()
    with pytest.raises(faze4.CannotFollow) as caught:
        faze4.wave(robot, duration=0.2, no_collisions=True, max_error=1e-9, strict=True)
    error = caught.value
    assert isinstance(error, faze4.Error) and isinstance(error, ValueError)
    assert isinstance(error.run, faze4.Run) and not error.run.follows
    assert str(error) == error.run.verdict_line and str(error).startswith("verdict: cannot follow — ")
    assert error.run.verdict == "cannot follow"
    # it pickles with its run (a pool's worker can raise it)
    again = pickle.loads(pickle.dumps(error))
    assert str(again) == str(error) and again.run.summary == error.run.summary
    # without strict the same run returns; with strict a run that follows returns
    assert not faze4.wave(robot, duration=0.2, no_collisions=True, max_error=1e-9).follows
    assert faze4.wave(robot, strict=True, **EASY).follows


@pytest.mark.parametrize(
    "keyword",
    [dict(duration="2"), dict(payload_kg=[1.0]), dict(quiet=1), dict(shape_points=2.5), dict(dt=True)],
)
def test_a_wrong_type_is_a_type_error(keyword):
    robot = faze4.Robot.faze4()
    name = next(iter(keyword))
    with pytest.raises(TypeError, match=f"^{name}: "):
        if name == "shape_points":
            faze4.shape(robot, "circle", **keyword)
        else:
            faze4.wave(robot, **keyword)


# the figures of a [done] line that differ between two runs: the wall time and the speed
DONE_TIMES = re.compile(
    r" in [0-9.]+ s \((dynamics )?[0-9.]+ µs/step(; self-clearance [0-9.]+ s, [0-9]+ % of the time)?\)"
)


def test_quiet_false_prints_what_the_binary_prints(binary, tmp_path, capfd):
    words = ["wave", "--duration", "0.6", "--trail", "none", "--motors", "faze4", "--sizing"]
    proc = subprocess.run([binary, *words], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    capfd.readouterr()
    faze4.wave(faze4.Robot.faze4(), duration=0.6, motors="faze4", sizing=True, quiet=False)
    printed = capfd.readouterr()
    mask = lambda text: DONE_TIMES.sub(" in … s", text)  # noqa: E731
    assert "[done]" in printed.out and "verdict" not in printed.out.splitlines()[0]
    assert mask(printed.out) == mask(proc.stdout)
    assert printed.err == proc.stderr
    # quiet (Python's default) prints nothing
    faze4.wave(faze4.Robot.faze4(), duration=0.2)
    assert capfd.readouterr() == ("", "")


def test_find_returns_a_small_readable_result():
    robot = faze4.Robot.faze4()
    found = faze4.find(robot, "wave", "payload_kg", 0.0, 40.0, resolution=2.0, jobs=2, duration=0.5, no_collisions=True)
    assert isinstance(found, faze4.Found) and found.found == "boundary"
    assert found.value < found.fails_at <= found.value + 2.0
    assert found.follows["payload_kg"] == found.value and found.follows["verdict"]["follows"]
    assert found.fails["payload_kg"] == found.fails_at and not found.fails["verdict"]["follows"]
    text = repr(found)
    assert text.startswith("<faze4.Found payload_kg = ") and repr(found.value) in text
    assert repr(found.fails_at) in text and found.reason in text and found.reason


def test_a_robot_pickles_and_copies_by_its_options():
    robot = faze4.Robot.from_urdf(ROOT / "tests" / "urdf" / "motor_arm.urdf", payload_kg=0.3, kp=[50.0, None, 20.0])
    for other in (pickle.loads(pickle.dumps(robot)), copy.copy(robot), copy.deepcopy(robot)):
        assert type(other) is faze4.Robot and other is not robot
        assert other.dof == robot.dof and other.joint_names == robot.joint_names
        q = np.linspace(0.1, 0.5, robot.dof)
        assert np.array_equal(other.mass_matrix(q), robot.mass_matrix(q))
        a = faze4.wave(robot, duration=0.3, no_collisions=True).summary
        b = faze4.wave(other, duration=0.3, no_collisions=True).summary
        assert without_wall_times(a) == without_wall_times(b)


def test_a_robot_goes_to_a_multiprocessing_pool():
    robot = faze4.Robot.faze4(payload_kg=0.2)
    payloads = [0.0, 0.5]
    runs = [functools.partial(faze4.wave, duration=0.3, no_collisions=True, payload_kg=p) for p in payloads]
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        remote = pool.map(_call, [(run, robot) for run in runs])
    local = [run(robot) for run in runs]
    assert [without_wall_times(r.summary) for r in remote] == [without_wall_times(r.summary) for r in local]
    assert all(np.array_equal(r.q, l.q) for r, l in zip(remote, local))


def _call(job):
    run, robot = job
    return run(robot)


def test_dir_shows_the_public_api_only():
    assert dir(faze4) == sorted(faze4.__all__)
    for name in faze4.__all__:
        assert hasattr(faze4, name), name
    assert {"wave", "replay", "shape", "retime", "sweep", "find", "Robot", "Run", "Retimed", "Found", "Error", "CannotFollow"} <= set(dir(faze4))
    assert "np" not in dir(faze4) and "json" not in dir(faze4)


def test_time_stamped_arrays_replay_as_their_file(binary, tmp_path):
    """t= makes q a time-stamped trajectory: the run equals the binary's replay of the same
    points in a CSV file, with the joints named in another order and one left out."""
    robot = faze4.Robot.faze4()
    names = robot.joint_names
    t = np.array([0.0, 0.4, 0.9, 1.3])
    # J1..J5 named in reverse; J6 left out (it holds its start position)
    chosen = names[:5][::-1]
    q = np.array([[0.0, 0.1, -0.2, 0.15, 0.05], [0.1, 0.2, -0.1, 0.1, 0.0], [0.0, 0.25, 0.0, 0.2, 0.1], [0.05, 0.1, 0.1, 0.0, 0.0]])
    v = np.gradient(q, t, axis=0)
    csv = tmp_path / "plan.csv"
    header = ["time_from_start", *chosen, *(f"{n}.velocity" for n in chosen)]
    rows = [",".join(repr(float(x)) for x in (t[k], *q[k], *v[k])) for k in range(len(t))]
    csv.write_text(",".join(header) + "\n" + "\n".join(rows) + "\n")
    proc, expected = run_binary(binary, ["replay", "--q-traj", str(csv), "--no-collisions"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    run = faze4.replay(robot, q, t=t, v=v, joint_names=chosen, no_collisions=True)
    assert without_wall_times(run.summary) == without_wall_times(expected)
    assert any("holds its start position" in w for w in run.warnings)
    # the duration defaults to the last time stamp, as the file's does
    assert run.t[-1] == pytest.approx(1.3)
    # a time per row, and t goes with arrays only
    with pytest.raises(faze4.Error, match="times for 4 rows"):
        faze4.replay(robot, q, t=t[:3], joint_names=chosen)
    with pytest.raises(faze4.Error, match="^t: "):
        faze4.replay(robot, str(csv), t=t)
    with pytest.raises(faze4.Error, match="^v: goes with"):
        faze4.replay(robot, np.zeros((3, 6)), v=np.zeros((3, 6)))
