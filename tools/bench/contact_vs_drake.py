#!/usr/bin/env python3
"""faze4 --self-collisions against Drake's contact closed loop, side by side in one run.

Runs, alternately, the circle with self-contact on the convex hulls

    faze4 shape --shape circle --urdf urdf/faze4_real.urdf --package-path assets
          --collision-geometry hull --self-collisions [--friction MU]          (release build)
    tools/oracle/drake_contact_loop.py circle [--friction MU]                 (pydrake, SAP)

N times each (12 s, 60,000 steps), and prints the medians and their ratio:

* process: the whole command, start to exit (faze4's includes the circle's IK and the hulls);
* loop: the simulation loop alone, as each program reports it (`wall_time_s`).

Usage (repository root; needs `cargo build --release` and tools/oracle/setup.sh):

    python3 tools/bench/contact_vs_drake.py [--runs 3] [--friction 1.0] [--python PY]

(--python: the oracle venv's interpreter, tools/oracle/.venv/bin/python by default)
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FAZE4 = os.path.join(ROOT, "target", "release", "faze4")
DRAKE_PY = os.path.join(ROOT, "tools", "oracle", ".venv", "bin", "python")
DRAKE_LOOP = os.path.join(ROOT, "tools", "oracle", "drake_contact_loop.py")
STEPS = 60_000


def timed(cmd, summary_path):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, cwd=ROOT)
    process = time.perf_counter() - t0
    with open(summary_path) as f:
        s = json.load(f)
    return process, s["wall_time_s"], s["saturation_pct"], s["path_deviation_mm"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--friction", type=float, default=1.0)
    ap.add_argument("--python", default=DRAKE_PY, help="the oracle venv's python")
    args = ap.parse_args()
    for path in (FAZE4, args.python):
        if not os.path.exists(path):
            sys.exit(f"missing {path}: run `cargo build --release` and tools/oracle/setup.sh first")

    results = {"faze4": [], "drake": []}
    with tempfile.TemporaryDirectory() as tmp:
        s = os.path.join(tmp, "summary.json")
        mu = repr(args.friction)
        commands = {
            "faze4": [FAZE4, "shape", "--shape", "circle", "--urdf", "urdf/faze4_real.urdf", "--package-path",
                      "assets", "--collision-geometry", "hull", "--self-collisions", "--friction", mu,
                      "--trail", "none", "--quiet", "--summary", s],
            "drake": [args.python, DRAKE_LOOP, "circle", "--friction", mu, "--summary", s],
        }
        for run in range(args.runs):
            for name, cmd in commands.items():  # alternate, so both see the same machine load
                results[name].append(timed(cmd, s))
                process, loop, sat, dev = results[name][-1]
                print(f"run {run + 1}/{args.runs} {name:6s} process {process:.3f} s, loop {loop:.4f} s; "
                      f"saturation % {' '.join(f'{x:.1f}' for x in sat)}; deviation max {dev['max']:.1f} "
                      f"mean {dev['mean']:.1f} mm", file=sys.stderr)

    med = {n: (statistics.median(r[0] for r in rs), statistics.median(r[1] for r in rs))
           for n, rs in results.items()}
    print(f"circle with self-contact on the hulls, friction {args.friction:g} ({STEPS} steps), "
          f"median of {args.runs} runs each:")
    print(f"  {'':8s}{'process (s)':>14s}{'loop (s)':>12s}{'µs/step':>10s}")
    for n in ("drake", "faze4"):
        print(f"  {n:8s}{med[n][0]:14.3f}{med[n][1]:12.4f}{med[n][1] / STEPS * 1e6:10.2f}")
    print(f"  ratio   {med['drake'][0] / med['faze4'][0]:14.1f}x{med['drake'][1] / med['faze4'][1]:11.1f}x")


if __name__ == "__main__":
    main()
