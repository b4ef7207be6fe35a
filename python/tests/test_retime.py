"""faze4.retime: the fastest timing of a path, as arrays and its checked run, equal to what
`faze4 retime` writes and reports."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest

import faze4
from conftest import run_binary, without_wall_times

JOINTS = ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"]


def path(points: int = 12) -> np.ndarray:
    """A reach of every joint, bent through a middle pose (rad)."""
    s = np.linspace(0.0, 1.0, points)[:, None]
    start = np.array([0.0, 0.3, 0.3, 0.0, -0.3, 0.0])
    middle = np.array([0.6, 0.1, 0.6, 0.4, -0.1, 0.5])
    end = np.array([1.0, 0.4, 0.2, 0.8, -0.5, 1.0])
    return (1 - s) ** 2 * start + 2 * s * (1 - s) * middle + s**2 * end


@pytest.fixture(scope="module")
def retimed() -> faze4.Retimed:
    return faze4.retime(faze4.Robot.faze4(), path(), no_collisions=True)


def test_the_timing_as_arrays_and_its_run(retimed):
    r = retimed
    m = len(r.t)
    assert r.q.shape == r.qd.shape == r.qdd.shape == (m, 6)
    assert r.joint_names == JOINTS
    assert r.t[0] == 0.0 and np.all(np.diff(r.t) > 0)
    assert r.t[-1] == pytest.approx(r.duration, abs=1e-9)
    # the timing runs along the path, from its first point to its last, at rest at both ends
    assert np.allclose(r.q[0], path()[0]) and np.allclose(r.q[-1], path()[-1])
    assert np.all(r.qd[0] == 0.0) and np.allclose(r.qd[-1], 0.0, atol=1e-9)
    assert r.follows and r.run.follows and r.verdict == r.run.verdict
    # frames given as an array are timed as a .npy's: traj_period (5 s by default)
    assert r.own_duration == 5.0 and r.speedup == 5.0 / r.duration
    # the check runs to the timing's end, in whole steps of dt
    assert abs(r.run.t[-1] - r.duration) <= r.run.summary["dt"] and r.run.q.shape[1] == 6
    assert "checked in the closed loop" in r.lines
    assert repr(r).startswith("<faze4.Retimed ")
    back = pickle.loads(pickle.dumps(r))
    assert np.array_equal(back.qdd, r.qdd) and back.run.summary == r.run.summary and back.speedup == r.speedup


def test_played_back_the_timing_follows(retimed):
    r = retimed
    run = faze4.replay(faze4.Robot.faze4(), r.q, t=r.t, v=r.qd, a=r.qdd, joint_names=r.joint_names, no_collisions=True)
    assert run.follows, run.reasons


def test_equals_the_binarys_retime(retimed, binary, tmp_path):
    np.save(tmp_path / "p.npy", path())
    proc, summary = run_binary(
        binary, ["retime", "--q-traj", str(tmp_path / "p.npy"), "--out", str(tmp_path / "t.json"), "--no-collisions"], tmp_path
    )
    assert summary is not None, proc.stderr
    assert without_wall_times(retimed.run.summary) == without_wall_times(summary)
    assert proc.stdout.strip().splitlines()[-1] == retimed.verdict_line
    written = json.loads((tmp_path / "t.json").read_text())
    points = written["points"]
    assert written["joint_names"] == retimed.joint_names
    assert [p["positions"] for p in points] == retimed.q.tolist()
    assert [p["velocities"] for p in points] == retimed.qd.tolist()
    assert [p["accelerations"] for p in points] == retimed.qdd.tolist()
    # the file: its own duration, and the speed-up over it
    again = faze4.retime(faze4.Robot.faze4(), tmp_path / "t.json", no_collisions=True)
    assert again.own_duration == pytest.approx(retimed.duration, abs=1e-9)
    assert again.speedup == pytest.approx(1.0, abs=0.05)


def test_bad_paths_and_nothing_that_follows():
    robot = faze4.Robot.faze4()
    with pytest.raises(faze4.Error, match="^q_path: shape"):
        faze4.retime(robot, np.zeros(6))
    with pytest.raises(TypeError, match="q_path: dtype"):
        faze4.retime(robot, [["a"] * 6] * 2)
    with pytest.raises(TypeError, match="unexpected keyword argument 'q_traj'"):
        faze4.retime(robot, path(), q_traj="p.npy")
    with pytest.raises(TypeError, match="unexpected keyword argument 'amp_deg'"):
        faze4.retime(robot, path(), amp_deg=3.0)
    with pytest.raises(faze4.Error) as plain:
        faze4.retime(robot, path(), payload_kg=40.0, no_collisions=True)
    assert type(plain.value) is faze4.Error and "nothing follows" in str(plain.value)
    with pytest.raises(faze4.CannotFollow, match="nothing follows"):
        faze4.retime(robot, path(), payload_kg=40.0, no_collisions=True, strict=True)


def test_documented_as_the_binarys_retime():
    keywords = [o.name for o in faze4.options("retime")]
    assert {"grid", "margin", "attempts", "out"} <= set(keywords)
    import inspect

    parameters = inspect.signature(faze4.retime).parameters
    assert list(parameters)[:2] == ["robot", "q_path"] and "q_traj" not in parameters
    assert parameters["margin"].default == float(next(o.default for o in faze4.options("retime") if o.name == "margin"))
    assert "Retimed" in faze4.retime.__doc__


def test_no_check_is_refused_here():
    """`no_check` (the binary's `--no-check`) plays no run, and Python's retime returns the
    checked run: it is refused, naming the keyword."""
    with pytest.raises(faze4.Error, match="no_check"):
        faze4.retime(faze4.Robot.faze4(), path(), no_collisions=True, no_check=True)


def test_start_and_end_velocities_chain_segments():
    """`start_velocity`, `end_velocity` (the binary's `--start-velocity`, `--end-velocity`): the
    timing starts and ends at them with zero acceleration; off the path's tangent, refused naming
    the keyword (docs/retime.md, "Chaining segments")."""
    a = np.array([0.0, 0.3, -0.4, 0.0, 0.3, 0.0])
    d = np.array([0.25, -0.2, 0.3, 0.15, -0.2, 0.25])
    line = np.array([a, a + d])
    tangent = d / np.linalg.norm(d)
    robot = faze4.Robot.faze4()
    r = faze4.retime(robot, line, no_collisions=True, start_velocity=0.5 * tangent, end_velocity=0.2 * tangent)
    assert np.allclose(r.qd[0], 0.5 * tangent, atol=1e-9) and np.allclose(r.qd[-1], 0.2 * tangent, atol=1e-9)
    assert np.allclose(r.qdd[0], 0.0, atol=1e-9) and np.allclose(r.qdd[-1], 0.0, atol=1e-9)
    assert r.follows and "starts moving at" in r.lines and "start_velocity" in r.lines
    off = 0.5 * tangent + np.array([0.0, 0.01, 0.0, 0.0, 0.0, 0.0])
    with pytest.raises(faze4.Error, match="start_velocity.*not along the path.s tangent"):
        faze4.retime(robot, line, no_collisions=True, start_velocity=off)
