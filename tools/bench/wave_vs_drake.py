#!/usr/bin/env python3
"""faze4 against the Drake Python loop of the same experiment, side by side in one run.

Runs, alternately, `faze4 wave --duration D --no-collisions` (release build; Drake's loop
measures no self-clearance either) and
`tools/oracle/drake_closed_loop.py wave --duration D` (pydrake, the original's Python loop),
N times each, and prints the medians and their ratio:

* process: the whole command, start to exit (what a user waits for);
* loop: the simulation loop alone, as each program reports it in its summary (`wall_time_s`).

Usage (repository root; needs `cargo build --release` and tools/oracle/setup.sh):

    python3 tools/bench/wave_vs_drake.py [--runs 5] [--duration 8]
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
DRAKE_LOOP = os.path.join(ROOT, "tools", "oracle", "drake_closed_loop.py")


def timed(cmd, summary_path):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, cwd=os.path.dirname(summary_path))
    process = time.perf_counter() - t0
    with open(summary_path) as f:
        loop = json.load(f)["wall_time_s"]
    return process, loop


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--duration", type=float, default=8.0)
    args = ap.parse_args()
    for path in (FAZE4, DRAKE_PY):
        if not os.path.exists(path):
            sys.exit(f"missing {path}: run `cargo build --release` and tools/oracle/setup.sh first")

    results = {"faze4": [], "drake": []}
    with tempfile.TemporaryDirectory() as tmp:
        s = os.path.join(tmp, "summary.json")
        d = str(args.duration)
        commands = {
            "faze4": [FAZE4, "wave", "--duration", d, "--trail", "none", "--summary", s, "--no-collisions"],
            "drake": [DRAKE_PY, DRAKE_LOOP, "wave", "--duration", d, "--quiet", "--summary", s],
        }
        for run in range(args.runs):
            for name, cmd in commands.items():  # alternate, so both see the same machine load
                results[name].append(timed(cmd, s))
                print(f"run {run + 1}/{args.runs} {name:6s} process {results[name][-1][0]:.3f} s, "
                      f"loop {results[name][-1][1]:.4f} s", file=sys.stderr)

    steps = round(args.duration / 2e-4)
    med = {n: (statistics.median(r[0] for r in rs), statistics.median(r[1] for r in rs))
           for n, rs in results.items()}
    print(f"wave --duration {args.duration:g} ({steps} steps), median of {args.runs} runs each:")
    print(f"  {'':8s}{'process (s)':>14s}{'loop (s)':>12s}{'µs/step':>10s}")
    for n in ("drake", "faze4"):
        print(f"  {n:8s}{med[n][0]:14.3f}{med[n][1]:12.4f}{med[n][1] / steps * 1e6:10.2f}")
    print(f"  ratio   {med['drake'][0] / med['faze4'][0]:14.1f}x{med['drake'][1] / med['faze4'][1]:11.1f}x")


if __name__ == "__main__":
    main()
