#!/usr/bin/env python3
"""Writes the closed-loop fixtures in tests/fixtures/ from the Drake reference (drake_closed_loop.py).

    tools/oracle/.venv/bin/python tools/oracle/closed_loop_fixtures.py

Deterministic: no randomness; the same drake/numpy versions (tools/oracle/requirements.txt)
write the same bytes. Writes

    tests/fixtures/closed_loop_wave_default.json     wave, 8 s, dt 2e-4, defaults
    tests/fixtures/closed_loop_wave_no_ff.json       same, --no-ff
    tests/fixtures/closed_loop_wave_no_gravity.json  same, --no-gravity
    tests/fixtures/replay_q_traj.npy                 60 x 6 replay input (generated here)
    tests/fixtures/closed_loop_replay.json           replay of it, 8 s, traj-period 5 (wraps once)

Before writing, it checks that Drake's discrete plant is the discrete step of docs/model.md along the runs:
  * free-running: the first 200 steps of the default wave integrated in numpy
      v+ = (M + dt D)^-1 [M v + dt (tau - C v - g)],  q+ = q + dt v+
    from Drake's M (CalcMassMatrix), C v (CalcBiasTerm), g (-CalcGravityGeneralizedForces) and the
    URDF joint damping D = 0.1, with the controller recomputed from the numpy state; it must match
    Drake's state to <= 1e-13;
  * one step: every step of every fixture run (k = 0..steps-2), the formula from Drake's state k predicts
    Drake's state k+1 (also <= 1e-13);
  * no step has |tau_raw| within 1e-6 N*m of the limit E, so the saturation counts are robust to
    round-off in another implementation.
"""

import importlib.metadata
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import drake_closed_loop as dcl  # noqa: E402

REPO = dcl.REPO_ROOT
FIXTURES = os.path.join(REPO, "tests", "fixtures")
URDF_REL = "urdf/faze4_arm.urdf"
GENERATOR = "tools/oracle/closed_loop_fixtures.py"
REPLAY_REL = "tests/fixtures/replay_q_traj.npy"

TOL_STATE = 1e-13
TOL_SAT_MARGIN = 1e-6
SANITY_STEPS = 200

DEFAULTS = dict(duration=8.0, dt=2e-4, record_period=0.02)


def replay_trajectory(n=60):
    """Smooth 60 x 6 joint trajectory (rad) starting exactly at the wave start pose.

    Joint i: q0_i + a_i (sin(2 pi c_i s + p_i) - sin p_i), s = k/(n-1). J1-J3 and J5 run whole
    cycles (continuous at the wrap); J4 (1.05 cycles) and J6 (1.1 cycles) end away from their
    start, so when the 5 s replay wraps, those two see a step in the command and saturate briefly.
    Peak segment speeds are below 1 rad/s; everything stays well inside the joint limits."""
    s = np.linspace(0.0, 1.0, n)[:, None]
    q0 = dcl.wave_command()(0.0)[0]
    amp = np.array([0.45, 0.30, 0.35, 0.50, 0.40, 0.40])
    cycles = np.array([1.0, 1.0, 2.0, 1.05, 1.0, 1.1])
    phase = np.array([0.0, 0.5, 1.0, 0.0, 2.0, 0.0])
    return q0 + amp * (np.sin(2.0 * np.pi * cycles * s + phase) - np.sin(phase))


class Recorder:
    """step_hook collecting states, torques and the saturation margin."""

    def __init__(self, effort):
        self.effort = np.asarray(effort)
        self.q, self.v, self.tau = [], [], []
        self.margin = math.inf

    def __call__(self, k, q, v, tau_raw, tau):
        self.q.append(q.copy())
        self.v.append(v.copy())
        self.tau.append(tau.copy())
        self.margin = min(self.margin, float(np.min(np.abs(np.abs(tau_raw) - self.effort))))


class SpecStep:
    """The discrete step of docs/model.md, evaluated with Drake's M, C v and g."""

    def __init__(self, dt, gravity):
        self.dt = dt
        self.plant, _sim, self.ctx = dcl.build(dcl.DEFAULT_URDF, dt, gravity)
        damping = [self.plant.get_joint(j).default_damping()
                   for j in self.plant.GetJointIndices() if self.plant.get_joint(j).num_velocities()]
        assert np.allclose(damping, 0.1), damping
        self.D = np.diag(damping)

    def terms(self, q, v):
        self.plant.SetPositions(self.ctx, q)
        self.plant.SetVelocities(self.ctx, v)
        M = self.plant.CalcMassMatrix(self.ctx)
        Cv = self.plant.CalcBiasTerm(self.ctx)
        g = -self.plant.CalcGravityGeneralizedForces(self.ctx)
        return M, Cv, g

    def step(self, q, v, tau):
        M, Cv, g = self.terms(q, v)
        v_next = np.linalg.solve(M + self.dt * self.D, M @ v + self.dt * (tau - Cv - g))
        return q + self.dt * v_next, v_next


def check_free_running(dt=2e-4):
    """First SANITY_STEPS steps of the default wave: numpy closed loop vs Drake's."""
    command = dcl.wave_command()
    rec = Recorder(dcl.EFFORT)
    summary, _ = dcl.run_closed_loop(command, duration=(SANITY_STEPS + 1) * dt, dt=dt,
                                     verbose=False, step_hook=rec)
    kp, kd = np.array(summary["kp"]), np.array(summary["kd"])
    spec = SpecStep(dt, gravity=True)
    q, v = command(0.0)
    worst = 0.0
    for k in range(SANITY_STEPS + 1):
        worst = max(worst, np.max(np.abs(q - rec.q[k])), np.max(np.abs(v - rec.v[k])))
        q_cmd, v_cmd = command(k * dt)
        _, _, g = spec.terms(q, v)
        tau = np.clip(kp * (q_cmd - q) + kd * (v_cmd - v) + g, -dcl.EFFORT, dcl.EFFORT)
        q, v = spec.step(q, v, tau)
    print(f"[check] free-running step vs Drake, {SANITY_STEPS} steps: max |diff| = {worst:.3g}")
    assert worst <= TOL_STATE, worst


def check_one_step(rec, dt, gravity, name):
    spec = SpecStep(dt, gravity)
    worst = 0.0
    for k in range(len(rec.q) - 1):
        q, v = spec.step(rec.q[k], rec.v[k], rec.tau[k])
        worst = max(worst, np.max(np.abs(q - rec.q[k + 1])), np.max(np.abs(v - rec.v[k + 1])))
    print(f"[check] {name}: one-step vs Drake over {len(rec.q) - 1} steps: "
          f"max |diff| = {worst:.3g}; saturation margin {rec.margin:.3g} N*m")
    assert worst <= TOL_STATE, worst
    assert rec.margin >= TOL_SAT_MARGIN, rec.margin


def to_json(value, indent=0):
    """JSON with full float precision (repr); a list of numbers, e.g. one trail row, on one line."""
    pad, inner = " " * indent, " " * (indent + 1)
    if isinstance(value, dict):
        items = [f"{inner}{json.dumps(k)}: {to_json(v, indent + 1)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, list) and any(isinstance(x, (list, dict)) for x in value):
        return "[\n" + ",\n".join(inner + to_json(x, indent + 1) for x in value) + "\n" + pad + "]"
    return json.dumps(value)


def dump_fixture(path, fixture):
    text = to_json(fixture)
    assert json.loads(text) == fixture
    with open(path, "w") as f:
        f.write(text + "\n")


def make_fixture(name, mode, args, command):
    rec = Recorder(dcl.EFFORT)
    summary, trail = dcl.run_closed_loop(
        command, duration=args["duration"], dt=args["dt"], feed_forward=not args["no_ff"],
        gravity=not args["no_gravity"], record_period=args["record_period"], verbose=False,
        step_hook=rec)
    assert summary["diverged"] is None, summary["diverged"]
    check_one_step(rec, args["dt"], not args["no_gravity"], name)
    summary.pop("wall_time_s")
    fixture = {
        "generator": GENERATOR,
        "drake_version": importlib.metadata.version("drake"),
        "urdf": URDF_REL,
        "command": mode,
        "args": args,
        "summary": summary,
        "trail": {"columns": dcl.TRAIL_COLUMNS, "rows": trail.tolist()},
    }
    path = os.path.join(FIXTURES, name)
    dump_fixture(path, fixture)
    print(f"[write] {os.path.relpath(path, REPO)}: max err {dcl._fmt(summary['max_tracking_error_rad'], '{:.3g}')}, "
          f"sat % {dcl._fmt(summary['saturation_pct'], '{:.3g}')}, {len(trail)} trail rows")


def main():
    os.makedirs(FIXTURES, exist_ok=True)
    check_free_running()

    wave = dict(freq=0.5, amp_deg=25.0, **DEFAULTS)
    for name, no_ff, no_gravity in (("closed_loop_wave_default.json", False, False),
                                    ("closed_loop_wave_no_ff.json", True, False),
                                    ("closed_loop_wave_no_gravity.json", False, True)):
        args = dict(wave, no_ff=no_ff, no_gravity=no_gravity)
        make_fixture(name, "wave", args, dcl.wave_command(args["amp_deg"], args["freq"]))

    Q = replay_trajectory()
    lo = np.array([-np.pi, -2 * np.pi / 3, -5 * np.pi / 6, -np.pi, -2 * np.pi / 3, -np.pi])
    assert np.all(Q > lo + 0.5) and np.all(Q < -lo - 0.5), "replay trajectory near a joint limit"
    np.save(os.path.join(REPO, REPLAY_REL), Q)
    print(f"[write] {REPLAY_REL}: {Q.shape}")
    args = dict(q_traj=REPLAY_REL, traj_period=5.0, no_ff=False, no_gravity=False, **DEFAULTS)
    make_fixture("closed_loop_replay.json", "replay", args,
                 dcl.replay_command(np.load(os.path.join(REPO, REPLAY_REL)), args["traj_period"]))


if __name__ == "__main__":
    main()
