#!/usr/bin/env python3
"""Drake reference of faze4's closed-loop experiment (docs/model.md).

A plain pydrake re-implementation of the original ``arm_wave_drake_faze4.py``: a discrete
MultibodyPlant (SAP, time step dt) of ``urdf/faze4_arm.urdf``, driven by a Python-loop PD +
gravity-feed-forward controller with zero-order hold, torque clipping and the seed's auto-tuning.
It is the oracle for the Rust side; ``closed_loop_fixtures.py`` turns its runs into fixtures.

Usage (from the repository root, with the oracle venv; see tools/oracle/README.md):

    python tools/oracle/drake_closed_loop.py wave [--duration 8 --freq 0.5 --amp-deg 25 --dt 2e-4
        --no-ff --no-gravity --record-period 0.02 --trail F.csv --summary F.json]
    python tools/oracle/drake_closed_loop.py replay --q-traj F.npy [--traj-period 5] [same options]
    python tools/oracle/drake_closed_loop.py periodic --q-samples F.npy [--period 5] [same options]

Exact definitions (the Rust side implements the same):

* Step k = 0..steps-1, steps = round(duration/dt), t_k = k*dt (a product, never a running sum).
  Read (q_k, v_k); command (q_cmd, v_cmd) at t_k;
  tau_raw = kp*(q_cmd - q) + kd*(v_cmd - v) [+ g(q) unless --no-ff], g(q) = -CalcGravityGeneralizedForces;
  tau = clip(tau_raw, -E, E); joint i is saturated in step k iff |tau_raw_i| >= E_i;
  tau is fixed on the applied-generalized-force port and the simulator advances to (k+1)*dt.
* Tuning: I_i = M_ii(q_start); kp_i = min(E_i/0.05, 0.4*I_i/dt^2); kd_i = min(1.6*sqrt(kp_i*I_i), I_i/(2*dt)).
* Commands (i = 0..5 is the joint index):
  wave:     q_i = A*sin(w*t + i*pi/3), v_i = A*w*cos(w*t + i*pi/3), A = radians(amp_deg), w = freq [rad/s].
  replay:   N frames, frame j at t = j*h, h = T/(N-1); tm = fmod(t, T); s = tm/h; j = min(floor(s), N-2);
            a = s - j; q = Q[j] + a*(Q[j+1] - Q[j]); v = (Q[j+1] - Q[j])/h.
  periodic: N samples, sample j at t = j*h, h = P/N; tm = fmod(t, P); s = tm/h; j = min(floor(s), N-1);
            a = s - j; n = (j+1) mod N; q = Q[j] + a*(Q[n] - Q[j]); v = (Q[n] - Q[j])/h.
  Every run starts at q = q_cmd(0), v = v_cmd(0).
* Metrics: e_k = q_cmd(t_k) - q_k for k = 0..steps-1 (the error the controller sees);
  max_tracking_error_rad_i = max_k |e_k,i|; saturation_pct_i = 100 * #saturated steps / steps.
* Trail: r = max(1, round(record_period/dt)); a row after step counts 0, r, 2r, ... and after the
  final step (no duplicate); row = [t = count*dt, x, y, z (tool_link origin in world), q1..q6].
  tool_range_m = per axis [min, max] over the trail rows.
* Divergence: if the state becomes non-finite (or Drake's solver throws) the run stops; summary
  "diverged" = {t, joint (1-based, first non-finite joint or null), stiffness_b (dt^2*kp/I per joint)};
  metrics then cover the steps that completed.
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DEFAULT_URDF = os.path.join(REPO_ROOT, "urdf", "faze4_arm.urdf")

# Faze4 motor torque limits (0.315 N*m at each NEMA17 times its reduction ratio; docs/model.md), N*m.
EFFORT = np.array([7.9, 8.5, 4.7, 3.7, 3.5, 6.0])
GRAVITY = 9.81
TOOL_BODY = "tool_link"
TRAIL_COLUMNS = ["t", "x", "y", "z", "q1", "q2", "q3", "q4", "q5", "q6"]


# --------------------------------------------------------------------------------------------
# Commands: each is a function t -> (q_cmd, v_cmd).
# --------------------------------------------------------------------------------------------

def wave_command(amp_deg=25.0, freq=0.5, dof=6):
    """q_i = A sin(w t + i pi/3); w is in rad/s (the original's convention)."""
    A = math.radians(amp_deg)
    w = float(freq)
    phase = np.arange(dof) * (math.pi / 3.0)

    def command(t):
        arg = w * t + phase
        return A * np.sin(arg), A * w * np.cos(arg)

    return command


def replay_command(Q, period=5.0):
    """N frames spread over [0, T] (frame N-1 at T), linear interpolation, repeating past T."""
    Q = np.asarray(Q, dtype=float)
    if Q.ndim != 2 or Q.shape[0] < 2:
        raise ValueError(f"replay needs an N x dof array with N >= 2, got shape {Q.shape}")
    n = Q.shape[0]
    T = float(period)
    h = T / (n - 1)

    def command(t):
        tm = math.fmod(t, T)
        s = tm / h
        j = min(int(math.floor(s)), n - 2)
        a = s - j
        dq = Q[j + 1] - Q[j]
        return Q[j] + a * dq, dq / h

    return command


def periodic_command(Q, period=5.0):
    """N samples, sample j at j*P/N, linear interpolation, wrapping from sample N-1 to sample 0."""
    Q = np.asarray(Q, dtype=float)
    if Q.ndim != 2 or Q.shape[0] < 2:
        raise ValueError(f"periodic needs an N x dof array with N >= 2, got shape {Q.shape}")
    n = Q.shape[0]
    P = float(period)
    h = P / n

    def command(t):
        tm = math.fmod(t, P)
        s = tm / h
        j = min(int(math.floor(s)), n - 1)
        a = s - j
        dq = Q[(j + 1) % n] - Q[j]
        return Q[j] + a * dq, dq / h

    return command


# --------------------------------------------------------------------------------------------
# Plant and controller.
# --------------------------------------------------------------------------------------------

def build(urdf=DEFAULT_URDF, dt=2e-4, gravity=True, plant_config=None):
    """Discrete SAP MultibodyPlant in a diagram, wrapped in a Simulator. ``plant_config``: extra
    MultibodyPlantConfig fields (drake_contact_loop.py sets the contact model and approximation).

    Returns (plant, simulator, plant_context)."""
    builder = DiagramBuilder()
    config = MultibodyPlantConfig(**{"time_step": dt, "discrete_contact_approximation": "sap",
                                     **(plant_config or {})})
    plant, _scene_graph = AddMultibodyPlant(config, builder)
    Parser(plant).AddModels(urdf)
    if not gravity:
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
    else:
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -GRAVITY])
    plant.Finalize()
    diagram = builder.Build()
    simulator = Simulator(diagram)
    plant_context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    return plant, simulator, plant_context


def auto_tune(plant, context, q_start, dt, effort=EFFORT):
    """Seed auto-tuning: I_i = M_ii(q_start) (kinetic-energy method), then kp, kd."""
    plant.SetPositions(context, q_start)
    inertia = np.diag(plant.CalcMassMatrix(context)).copy()
    kp = np.minimum(effort / 0.05, 0.4 * inertia / dt**2)
    kd = np.minimum(1.6 * np.sqrt(kp * inertia), inertia / (2.0 * dt))
    return inertia, kp, kd


def gravity_torque(plant, context):
    """g(q) in M v' + C v + g = tau: minus Drake's gravity generalized force."""
    return -plant.CalcGravityGeneralizedForces(context)


def _fmt(a, f="{:.3f}"):
    return " ".join(f.format(x) for x in a)


def run_closed_loop(command, duration=8.0, dt=2e-4, feed_forward=True, gravity=True,
                    record_period=0.02, urdf=DEFAULT_URDF, effort=EFFORT, verbose=True,
                    print_period=0.5, step_hook=None, plant_config=None, record_hook=None):
    """Run the closed loop; returns (summary dict, trail ndarray with TRAIL_COLUMNS).

    step_hook(k, q, v, tau_raw, tau), if given, is called every step with the state the controller
    read, the unclipped torque and the torque it applied (used by the fixture generator's checks).
    record_hook(plant, context, count), if given, is called at every trail row (drake_contact_loop.py
    reads the contact results there). plant_config: see build()."""
    effort = np.asarray(effort, dtype=float)
    plant, simulator, ctx = build(urdf, dt, gravity, plant_config)
    dof = plant.num_velocities()
    tool = plant.GetBodyByName(TOOL_BODY)
    port = plant.get_applied_generalized_force_input_port()

    q0, v0 = command(0.0)
    inertia, kp, kd = auto_tune(plant, ctx, q0, dt, effort)
    stiffness_b = dt**2 * kp / inertia
    plant.SetPositions(ctx, q0)
    plant.SetVelocities(ctx, v0)
    port.FixValue(ctx, np.zeros(dof))
    simulator.get_mutable_context().SetTime(0.0)
    simulator.Initialize()

    steps = int(round(duration / dt))
    r = max(1, int(round(record_period / dt)))
    p = max(1, int(round(print_period / dt)))

    if verbose:
        gz = plant.gravity_field().gravity_vector()[2]
        print(f"[faze4] plant={dof} dof · gravity={gz:g} m/s² · dt={dt:g} s · "
              f"feed-forward={'on' if feed_forward else 'off'} · SAP discrete")
        print(f"[faze4] effort limit (N·m) = {effort}")
        print(f"[faze4] effective inertia (kg·m²) = {np.array2string(inertia, precision=4)}")
        print(f"[faze4] kp = {np.array2string(kp, precision=4)}")
        print(f"[faze4] kd = {np.array2string(kd, precision=4)}")
        print(f"[faze4] stiffness b = dt²·kp/I = {np.array2string(stiffness_b, precision=3)}")
        print(f"[faze4] start pose (deg) = {np.array2string(np.degrees(q0), precision=2)}")

    max_err = np.zeros(dof)
    sat_steps = np.zeros(dof, dtype=np.int64)
    trail = []
    diverged = None

    def record(count, q):
        xyz = plant.EvalBodyPoseInWorld(ctx, tool).translation()
        trail.append([count * dt, *xyz, *q])
        if record_hook is not None:
            record_hook(plant, ctx, count)
        if verbose and count % p == 0:
            print(f"t={count * dt:5.2f}s  q(rad): {_fmt(q)}  tool XYZ(m): {_fmt(xyz)}")

    done = 0
    wall0 = time.perf_counter()
    q = plant.GetPositions(ctx)
    v = plant.GetVelocities(ctx)
    record(0, q)
    for k in range(steps):
        t = k * dt
        q_cmd, v_cmd = command(t)
        err = q_cmd - q
        tau_raw = kp * err + kd * (v_cmd - v)
        if feed_forward:
            tau_raw = tau_raw + gravity_torque(plant, ctx)
        tau = np.clip(tau_raw, -effort, effort)
        np.maximum(max_err, np.abs(err), out=max_err)
        sat_steps += np.abs(tau_raw) >= effort
        if step_hook is not None:
            step_hook(k, q, v, tau_raw, tau)
        port.FixValue(ctx, tau)
        try:
            simulator.AdvanceTo((k + 1) * dt)
            q = plant.GetPositions(ctx)
            v = plant.GetVelocities(ctx)
            bad = ~(np.isfinite(q) & np.isfinite(v))
        except RuntimeError as exc:  # SAP refuses a non-finite state
            bad = None
            if verbose:
                print(f"[faze4] Drake stopped at t={(k + 1) * dt:.4f}s: {exc}")
        done = k + 1
        if bad is None or bad.any():
            joint = int(np.argmax(bad)) + 1 if bad is not None else None
            diverged = {"t": done * dt, "joint": joint, "stiffness_b": stiffness_b.tolist()}
            if verbose:
                print(f"[faze4] DIVERGED at t={done * dt:.4f}s, joint J{joint}; "
                      f"stiffness b = dt²·kp/I = {np.array2string(stiffness_b, precision=3)} "
                      f"(b must stay below ~0.5; lower --dt)")
            break
        if done % r == 0 or done == steps:
            record(done, q)
    wall = time.perf_counter() - wall0

    trail = np.array(trail)
    denom = max(done, 1)
    summary = {
        "dof": dof,
        "dt": dt,
        "steps": steps,
        "effective_inertia": inertia.tolist(),
        "kp": kp.tolist(),
        "kd": kd.tolist(),
        "effort": effort.tolist(),
        "max_tracking_error_rad": max_err.tolist(),
        "saturation_pct": (100.0 * sat_steps / denom).tolist(),
        "tool_range_m": {ax: [float(np.min(trail[:, c])), float(np.max(trail[:, c]))]
                         for ax, c in (("x", 1), ("y", 2), ("z", 3))},
        "diverged": diverged,
        "wall_time_s": wall,
    }
    if verbose:
        rng = summary["tool_range_m"]
        print(f"[summary] max tracking error (rad): {_fmt(max_err, '{:.3g}')}")
        print(f"[summary] saturation (%): {_fmt(summary['saturation_pct'], '{:.2f}')}")
        print(f"[summary] tool range (m): x[{rng['x'][0]:.3f}, {rng['x'][1]:.3f}] "
              f"y[{rng['y'][0]:.3f}, {rng['y'][1]:.3f}] z[{rng['z'][0]:.3f}, {rng['z'][1]:.3f}]")
        print(f"[summary] {done} steps, loop wall time {wall:.2f} s")
    return summary, trail


def write_trail_csv(path, trail):
    with open(path, "w") as f:
        f.write(",".join(TRAIL_COLUMNS) + "\n")
        for row in trail:
            f.write(",".join(repr(float(x)) for x in row) + "\n")


# --------------------------------------------------------------------------------------------
# CLI
# --------------------------------------------------------------------------------------------

def make_command(args):
    if args.mode == "wave":
        return wave_command(args.amp_deg, args.freq)
    if args.mode == "replay":
        return replay_command(np.load(args.q_traj), args.traj_period)
    return periodic_command(np.load(args.q_samples), args.period)


def main(argv=None):
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--duration", type=float, default=8.0, help="simulated seconds (8)")
    common.add_argument("--dt", type=float, default=2e-4, help="plant and control step, s (2e-4)")
    common.add_argument("--no-ff", action="store_true", help="no gravity feed-forward")
    common.add_argument("--no-gravity", action="store_true", help="gravity field set to zero")
    common.add_argument("--record-period", type=float, default=0.02, help="trail period, s (0.02)")
    common.add_argument("--trail", metavar="F.csv", help="write the trail CSV here")
    common.add_argument("--summary", metavar="F.json", help="write the summary JSON here")
    common.add_argument("--urdf", default=DEFAULT_URDF, help="model (urdf/faze4_arm.urdf)")
    common.add_argument("--quiet", action="store_true", help="no terminal output but the summary")

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    w = sub.add_parser("wave", parents=[common], help="sine wave on every joint")
    w.add_argument("--freq", type=float, default=0.5, help="rad/s (0.5)")
    w.add_argument("--amp-deg", type=float, default=25.0, help="amplitude, degrees (25)")
    r = sub.add_parser("replay", parents=[common], help="replay an N x 6 joint trajectory")
    r.add_argument("--q-traj", required=True, metavar="F.npy")
    r.add_argument("--traj-period", type=float, default=5.0, help="s (5)")
    p = sub.add_parser("periodic", parents=[common], help="play N periodic joint samples")
    p.add_argument("--q-samples", required=True, metavar="F.npy")
    p.add_argument("--period", type=float, default=5.0, help="s (5)")
    args = ap.parse_args(argv)

    summary, trail = run_closed_loop(
        make_command(args), duration=args.duration, dt=args.dt, feed_forward=not args.no_ff,
        gravity=not args.no_gravity, record_period=args.record_period, urdf=args.urdf,
        verbose=not args.quiet)
    if args.trail:
        write_trail_csv(args.trail, trail)
        print(f"[done] trail -> {args.trail}")
    if args.summary:
        with open(args.summary, "w") as f:
            json.dump(summary, f, indent=1)
        print(f"[done] summary -> {args.summary}")
    if args.quiet:
        print(json.dumps(summary))
    return 1 if summary["diverged"] else 0


if __name__ == "__main__":
    sys.exit(main())
