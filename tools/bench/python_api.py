#!/usr/bin/env python3
"""The Python binding's costs, side by side with what it is compared to:

* call overhead: `faze4.wave(...)` timed from Python, minus the time the binary's own code
  (scenario, run, outputs) took inside it (`Run._engine_s`): what the binding adds (keywords →
  words, clap's parse, the worker thread, the arrays and the summary dict). Medians over runs
  of a short wave (0.01 s, 50 steps) and of the default 8 s wave;
* `robot.rnea(q, v, a)` against `pin.rnea(model, data, q, v, a)` (Pinocchio) per call, and
  `robot.mass_matrix(q)` against `pin.crba`, on urdf/faze4_arm.urdf, random states, median of
  batches of calls;
* `faze4.sweep` against the binary's `faze4 sweep` on the same grid: runs per second (wall
  clock, the binary's process start included).

Pinocchio's part runs in the interpreter given by --pin-python, a second process (default: the
oracle's environment, tools/oracle/setup.sh, which pins pin==4.1.0), so faze4 need not be
installed next to Pinocchio. Usage (repository root, with faze4 installed in this interpreter and
`cargo build --release` done):

    python tools/bench/python_api.py [--pin-python PYTHON] [--faze4-bin target/release/faze4]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
URDF = os.path.join(ROOT, "urdf", "faze4_arm.urdf")
CALLS = 20000


def states(dof: int, count: int = 64):
    import numpy as np

    rng = np.random.default_rng(7)
    return [tuple(rng.uniform(-1.0, 1.0, dof) for _ in range(3)) for _ in range(count)]


def per_call(function, args_list, batches: int = 15) -> float:
    """Median over batches of the time per call (s)."""
    times = []
    per_batch = CALLS // batches
    for b in range(batches):
        t0 = time.perf_counter()
        for k in range(per_batch):
            function(*args_list[k % len(args_list)])
        times.append((time.perf_counter() - t0) / per_batch)
    return statistics.median(times)


def part_faze4() -> dict:
    import faze4

    robot = faze4.Robot.from_urdf(URDF)
    xs = states(robot.dof)
    return {
        "rnea": per_call(robot.rnea, xs),
        "crba": per_call(robot.mass_matrix, [(q,) for q, _, _ in xs]),
    }


def part_pin() -> dict:
    import pinocchio as pin

    model = pin.buildModelFromUrdf(URDF)
    data = model.createData()
    xs = states(model.nv)
    return {
        "rnea": per_call(lambda q, v, a: pin.rnea(model, data, q, v, a), xs),
        "crba": per_call(lambda q: pin.crba(model, data, q), [(q,) for q, _, _ in xs]),
        "version": pin.__version__,
    }


def overhead(runs: int) -> dict:
    import faze4

    robot = faze4.Robot.faze4()
    result = {}
    for label, options in (("wave 0.01 s", {"duration": 0.01}), ("wave 8 s", {})):
        extra = []
        for _ in range(runs):
            t0 = time.perf_counter()
            run = faze4.wave(robot, **options)
            extra.append(time.perf_counter() - t0 - run._engine_s)
        result[label] = (statistics.median(extra), run._engine_s)
    return result


def sweep_rates(binary: str, runs: int, duration: float) -> tuple[float, float]:
    import numpy as np

    import faze4

    payloads = np.linspace(0.0, 1.4, runs)
    t0 = time.perf_counter()
    faze4.sweep(faze4.Robot.faze4(), "wave", vary={"payload_kg": payloads}, duration=duration)
    python_rate = runs / (time.perf_counter() - t0)
    values = ",".join(repr(float(p)) for p in payloads)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        subprocess.run(
            [binary, "sweep", "--vary", f"payload-kg={values}", "-q", "--", "wave", "--duration", str(duration)],
            check=True,
            stdout=subprocess.DEVNULL,
            cwd=tmp,
        )
        binary_rate = runs / (time.perf_counter() - t0)
    return python_rate, binary_rate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=["faze4", "pin"], help=argparse.SUPPRESS)
    oracle = os.path.join(ROOT, "tools", "oracle", ".venv", "bin", "python")
    parser.add_argument("--pin-python", default=oracle if os.path.exists(oracle) else sys.executable)
    parser.add_argument("--faze4-bin", default=os.environ.get("FAZE4_BIN", os.path.join(ROOT, "target", "release", "faze4")))
    parser.add_argument("--runs", type=int, default=15, help="runs per overhead median")
    parser.add_argument("--sweep-runs", type=int, default=16)
    parser.add_argument("--sweep-duration", type=float, default=2.0)
    args = parser.parse_args()
    if args.part:
        print(json.dumps(part_faze4() if args.part == "faze4" else part_pin()))
        return

    ours = part_faze4()
    pin_out = subprocess.run(
        [args.pin_python, __file__, "--part", "pin"], check=True, capture_output=True, text=True
    ).stdout
    pin = json.loads(pin_out)
    print(f"dynamics per call, {CALLS} calls in batches, median (Pinocchio {pin['version']}):")
    for key, name in (("rnea", "rnea"), ("crba", "mass_matrix / crba")):
        print(
            f"  {name:20s} faze4 {ours[key] * 1e6:7.2f} µs   pin {pin[key] * 1e6:7.2f} µs   ratio {ours[key] / pin[key]:.2f}"
        )
    print("Python call overhead beyond the binary's own scenario+run code, median:")
    for label, (extra, engine) in overhead(args.runs).items():
        print(f"  {label:12s} {extra * 1e3:7.3f} ms   (the run itself {engine * 1e3:9.2f} ms)")
    python_rate, binary_rate = sweep_rates(args.faze4_bin, args.sweep_runs, args.sweep_duration)
    print(f"sweep, {args.sweep_runs} waves of {args.sweep_duration} s on every core:")
    print(
        f"  faze4.sweep {python_rate:6.2f} runs/s   binary {binary_rate:6.2f} runs/s   ratio {python_rate / binary_rate:.2f}"
    )


if __name__ == "__main__":
    main()
