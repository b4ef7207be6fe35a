#!/usr/bin/env python3
"""Throughput of `faze4 sweep` against single runs and against MuJoCo's multi-threaded rollout.

The family: `wave --duration D` with `payload-kg` = 0, 0.01, …, (N−1)·0.01 (N = 200 runs by
default) on the bundled Faze4, Δt = 2e-4 s (5 kHz). Each faze4 figure is the median of
--repeats runs; the three faze4 ways alternate so they see the same machine load.

* sweep: `faze4 sweep --vary payload-kg=… --out T.csv -- wave --duration D --no-collisions` on every core;
* sweep --jobs 1: the same on one thread;
* processes: the same N runs as N `faze4 wave --payload-kg p` processes, one at a time.

Printed: runs per second of the sweep; its speed-up over the processes (the goal: at least
0.9 × the number of cores) and over `--jobs 1` (the parallel efficiency proper); the cores the
sweep actually had (its CPU time over its wall time: on a busy machine fewer than it asked for,
and then the speed-ups measure the machine, not the sweep); the cost per run beyond its steps: (`--jobs 1` process wall time − Σ the runs' own loop times) / N (the goal:
at most 1 ms).

MuJoCo: the same family with `mujoco.rollout` (pip `mujoco`, pinned in
tools/bench/sweep_requirements.txt, installed by this script into tools/bench/.venv): the
Faze4 URDF loaded by MuJoCo's own URDF importer (static bodies kept, so the tool link is a body),
the payload a point mass added at the tool link's origin (where its inertial is centred), Δt = 2e-4 s, Euler (semi-implicit, joint
damping implicit: faze4's step), contacts off, and per joint the PD + feed-forward law
τ = clip(kp (q_cmd − q) + kd (v_cmd − v) + g(q), ±E): a position actuator (gain kp, no damping)
and a velocity actuator (gain kd) whose forces are summed with the gravity compensation
(`gravcomp` 1 on every body, `actuatorgravcomp` on every joint) and clipped by the joint's
`actuatorfrcrange` ±E. kp, kd and E are each run's own, read from the faze4 table (tuned by
faze4 at the start pose with the payload). The command is given as open-loop controls per step
(q_cmd, v_cmd at t_k), the start state is the command's. What differs: MuJoCo's joint limits are
soft constraints (the wave stays inside them, so they never act), its step reports q after each
step (faze4's tracking error is taken before each step: the same series shifted by one step), and
rollout runs every model with all its pipeline stages (sensors, constraint checks), which faze4
does not have. Rollout threads: one per core; the models are compiled before the timer starts.

Usage (repository root; needs `cargo build --release`; --no-mujoco skips the comparison):

    python3 tools/bench/sweep_throughput.py [--runs 200] [--duration 2] [--repeats 3]
"""

import argparse
import csv
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FAZE4 = os.path.join(ROOT, "target", "release", "faze4")
URDF = os.path.join(ROOT, "urdf", "faze4_arm.urdf")
VENV = os.path.join(ROOT, "tools", "bench", ".venv")
VENV_PY = os.path.join(VENV, "bin", "python")
REQUIREMENTS = os.path.join(ROOT, "tools", "bench", "sweep_requirements.txt")
DT = 2e-4
AMPLITUDE = 25.0 * 3.141592653589793 / 180.0  # faze4 wave's defaults
OMEGA = 0.5


def cpu_of_children():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def wall(cmd, cwd, cpu=None):
    """Wall time of `cmd`; appends its CPU time (user + system) to the list `cpu` if given."""
    c0, t0 = cpu_of_children(), time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, cwd=cwd)
    elapsed = time.perf_counter() - t0
    if cpu is not None:
        cpu.append(cpu_of_children() - c0)
    return elapsed


def read_table(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def faze4_side(args, tmp):
    last = (args.runs - 1) / 100
    vary = ["--vary", f"payload-kg=0:{last:.2f}:0.01"]
    # the dynamics' throughput: no self-clearance (its exact meshes cost 100 times a run)
    base = ["--", "wave", "--duration", str(args.duration), "--no-collisions"]
    table = os.path.join(tmp, "sweep.csv")
    times = {"sweep": [], "jobs1": [], "processes": []}
    loop_sums = []
    cpu = []  # CPU time of each all-core sweep
    for r in range(args.repeats):
        times["sweep"].append(wall([FAZE4, "sweep", *vary, "--out", table, "-q", *base], tmp, cpu))
        rows = read_table(table)
        assert len(rows) == args.runs, f"{len(rows)} rows"
        times["jobs1"].append(wall([FAZE4, "sweep", "--jobs", "1", *vary, "--out", table, "-q", *base], tmp))
        loop_sums.append(sum(float(row["wall_time_s"]) for row in read_table(table)))
        t0 = time.perf_counter()
        for row in rows:
            subprocess.run([FAZE4, "wave", "--duration", str(args.duration), "--payload-kg", row["payload-kg"],
                            "--trail", "none", "-q", "--no-collisions"], check=True, stdout=subprocess.DEVNULL, cwd=tmp)
        times["processes"].append(time.perf_counter() - t0)
        print(f"repeat {r + 1}/{args.repeats}: sweep {times['sweep'][-1]:.3f} s, --jobs 1 "
              f"{times['jobs1'][-1]:.3f} s (loops {loop_sums[-1]:.3f} s), processes "
              f"{times['processes'][-1]:.3f} s", file=sys.stderr)
    med = {k: statistics.median(v) for k, v in times.items()}
    # cores the all-core sweep had on average: below the machine's when other work competes
    med["cores_had"] = statistics.median(c / w for c, w in zip(cpu, times["sweep"]))
    # the overhead of the repeat whose --jobs 1 time is the median
    i = times["jobs1"].index(sorted(times["jobs1"])[len(times["jobs1"]) // 2])
    overhead = (times["jobs1"][i] - loop_sums[i]) / args.runs
    return med, overhead, read_table(table)


def ensure_venv():
    if not os.path.exists(VENV_PY):
        print(f"creating {VENV} (mujoco, numpy; tools/bench/sweep_requirements.txt)", file=sys.stderr)
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
        subprocess.run([VENV_PY, "-m", "pip", "install", "--quiet", "-r", REQUIREMENTS], check=True)


def mujoco_side(table_path, duration, threads):
    """Runs inside the venv: the family with mujoco.rollout; prints a JSON line."""
    import re
    import numpy as np
    import mujoco
    from mujoco import rollout

    rows = read_table(table_path)
    with open(URDF) as f:
        urdf = f.read()
    # keep static links as bodies (the tool link carries the payload)
    urdf = re.sub(r"(<robot[^>]*>)", r'\1<mujoco><compiler fusestatic="false" discardvisual="true"/></mujoco>',
                  urdf, count=1)
    dof = 6
    steps = round(duration / DT)

    def model(row):
        spec = mujoco.MjSpec.from_string(urdf)
        spec.option.timestep = DT
        spec.option.integrator = mujoco.mjtIntegrator.mjINT_EULER
        spec.option.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
        payload = float(row["payload-kg"])
        # a point mass at the tool link's origin, where its own inertial is centred
        spec.body("tool_link").mass += payload
        for body in spec.bodies:
            body.gravcomp = 1
        joints = [j for j in spec.joints if j.type == mujoco.mjtJoint.mjJNT_HINGE]
        assert len(joints) == dof, len(joints)
        for i, joint in enumerate(joints):
            effort = float(row[f"effort_{i + 1}"])
            joint.actgravcomp = True
            joint.actfrclimited = True
            joint.actfrcrange = [-effort, effort]
        for kind, gain in (("position", "kp"), ("velocity", "kd")):
            for i, joint in enumerate(joints):
                act = spec.add_actuator()
                act.name = f"{kind}_{i + 1}"
                act.target = joint.name
                act.trntype = mujoco.mjtTrn.mjTRN_JOINT
                if kind == "position":
                    act.set_to_position(kp=float(row[f"{gain}_{i + 1}"]), kv=0.0)
                else:
                    act.set_to_velocity(kv=float(row[f"{gain}_{i + 1}"]))
        return spec.compile()

    models = [model(row) for row in rows]
    t = np.arange(steps + 1) * DT
    phase = np.arange(dof) * np.pi / 3
    q_cmd = AMPLITUDE * np.sin(OMEGA * t[:, None] + phase)
    v_cmd = AMPLITUDE * OMEGA * np.cos(OMEGA * t[:, None] + phase)
    control = np.concatenate([q_cmd[:steps], v_cmd[:steps]], axis=1)[None]  # 1 × steps × 12
    data = [mujoco.MjData(models[0]) for _ in range(threads)]
    spec_full = mujoco.mjtState.mjSTATE_FULLPHYSICS
    initial = []
    for m in models:
        d = mujoco.MjData(m)
        d.qpos[:] = q_cmd[0]
        d.qvel[:] = v_cmd[0]
        state = np.empty(mujoco.mj_stateSize(m, spec_full))
        mujoco.mj_getState(m, d, state, spec_full)
        initial.append(state)
    initial = np.array(initial)
    batch = 25  # the state output of a batch: batch × steps × nstate floats
    nstate = initial.shape[1]
    out = np.empty((batch, steps, nstate))
    errors = []
    elapsed = 0.0
    for start in range(0, len(models), batch):
        ms = models[start:start + batch]
        n = len(ms)
        t0 = time.perf_counter()
        state, _ = rollout.rollout(ms, data, initial[start:start + n], control, state=out[:n],
                                   persistent_pool=True)
        elapsed += time.perf_counter() - t0
        qpos = state[:, :, 1:1 + dof]  # after each step, at t_{k+1}
        errors.extend(np.abs(qpos - q_cmd[None, 1:steps + 1]).max(axis=1).tolist())
    faze4_errors = [[float(row[f"max_tracking_error_rad_{j + 1}"]) for j in range(dof)] for row in rows]
    rel = [abs(m - f) / f for me, fe in zip(errors, faze4_errors) for m, f in zip(me, fe) if f > 1e-6]
    print(json.dumps({"seconds": elapsed, "threads": threads, "version": mujoco.__version__,
                      "median_relative_error_difference": statistics.median(rel),
                      "max_relative_error_difference": max(rel)}))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--duration", type=float, default=2.0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--no-mujoco", action="store_true")
    ap.add_argument("--mujoco-side", help=argparse.SUPPRESS)  # internal: the venv half
    args = ap.parse_args()
    cores = os.cpu_count() or 1
    if args.mujoco_side:
        mujoco_side(args.mujoco_side, args.duration, cores)
        return
    if not os.path.exists(FAZE4):
        sys.exit(f"missing {FAZE4}: run `cargo build --release` first")

    with tempfile.TemporaryDirectory() as tmp:
        med, overhead, rows = faze4_side(args, tmp)
        mj = None
        if not args.no_mujoco:
            ensure_venv()
            table = os.path.join(tmp, "sweep.csv")
            out = subprocess.run([VENV_PY, os.path.abspath(__file__), "--mujoco-side", table,
                                  "--duration", str(args.duration)], check=True, capture_output=True, text=True)
            mj = json.loads(out.stdout.strip().splitlines()[-1])

    steps = round(args.duration / DT)
    loops = sum(float(r["wall_time_s"]) for r in rows)
    print(f"{args.runs} runs of wave --duration {args.duration:g} ({steps} steps each), payload-kg 0…"
          f"{(args.runs - 1) / 100:.2f}, {cores} cores, median of {args.repeats}:")
    print(f"  sweep (all cores)       {med['sweep']:8.3f} s  {args.runs / med['sweep']:8.1f} runs/s")
    print(f"  sweep --jobs 1          {med['jobs1']:8.3f} s  {args.runs / med['jobs1']:8.1f} runs/s")
    print(f"  one process per run     {med['processes']:8.3f} s  {args.runs / med['processes']:8.1f} runs/s")
    speedup = med["processes"] / med["sweep"]
    print(f"  speed-up over one process per run: {speedup:.2f}x = {speedup / cores:.2f} x {cores} cores "
          f"(goal ≥ 0.9 x cores: {'met' if speedup >= 0.9 * cores else 'NOT met'})")
    print(f"  parallel efficiency (sweep --jobs 1 / sweep) / cores: {med['jobs1'] / med['sweep'] / cores:.2f}")
    print(f"  cores the sweep had on average (its CPU time / wall time): {med['cores_had']:.2f} of {cores}"
          f"{'' if med['cores_had'] > 0.9 * cores else ': other work took the rest, so the speed-ups above are not the sweep’s'}")
    print(f"  per-run cost beyond the steps (--jobs 1 wall − Σ loop times) / runs: {overhead * 1e3:.3f} ms "
          f"(goal ≤ 1 ms: {'met' if overhead <= 1e-3 else 'NOT met'}); the loops: "
          f"{loops / args.runs / steps * 1e6:.2f} µs/step")
    if mj:
        print(f"  MuJoCo {mj['version']} rollout ({mj['threads']} threads): {mj['seconds']:.3f} s "
              f"{args.runs / mj['seconds']:8.1f} runs/s; faze4 sweep is {mj['seconds'] / med['sweep']:.1f}x faster "
              f"(rollout alone, models compiled before; the sweep's time is its whole process)")
        print(f"  same family? max tracking error per joint, MuJoCo vs faze4: median relative difference "
              f"{mj['median_relative_error_difference']:.1e}, largest {mj['max_relative_error_difference']:.1e}")


if __name__ == "__main__":
    main()
