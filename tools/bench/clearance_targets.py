#!/usr/bin/env python3
"""Issue 47's targets for self-clearance, side by side in one run: what the default
self-clearance costs against `--no-collisions` (and against the Drake loop).

Each pair of commands runs alternately (A B A B ...), `--runs` times, whole processes (release
build, trail off, `--quiet`); the ratio of each pair is taken run by run and its median is
printed, with the medians of A and B:

* `wave` (8 s): default ≤ 2× `--no-collisions`;
* `shape --shape circle` (12 s): default ≤ 1.5×;
* a payload sweep (`sweep --vary payload-kg=0:0.9:0.1 -q -- wave`, 10 runs): throughput with
  clearance ≥ 0.7× without (the ratio printed is B's time over A's, a throughput ratio);
* the marginal cost of a recorded step: `wave --duration 16` less `wave --duration 8`, per
  step (40,000 steps, 400 recorded samples), with clearance and without; target: with
  clearance at most Pinocchio's step (`--pinocchio-us`, issue 47's 1.5 µs);
* with `--drake`: the default wave against the Drake loop
  (`tools/oracle/drake_closed_loop.py wave`, the oracle venv; target ≥ 50×).

Usage (repository root, after `cargo build --release`):

    python3 tools/bench/clearance_targets.py [--runs 7] [--drake [--oracle-python PY]] [--nice -5]

`--nice N` runs every command at that niceness (negative needs root): the machine is shared.
The load average at the start and the end is printed: read the figures with it.
"""

import argparse
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FAZE4 = os.path.join(ROOT, "target", "release", "faze4")
DRAKE_PY = os.path.join(ROOT, "tools", "oracle", ".venv", "bin", "python")
DRAKE_LOOP = os.path.join(ROOT, "tools", "oracle", "drake_closed_loop.py")
QUIET = ["--trail", "none", "-q"]


def timed(cmd, niceness):
    """Wall seconds of one whole process."""
    prefix = ["nice", "-n", str(niceness)] if niceness else []
    t0 = time.perf_counter()
    subprocess.run(prefix + cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def paired(a, b, runs, niceness):
    """A and B alternately: (median A, median B, median of the runs' A/B)."""
    ta, tb = [], []
    for _ in range(runs):
        ta.append(timed(a, niceness))
        tb.append(timed(b, niceness))
    return statistics.median(ta), statistics.median(tb), statistics.median(x / y for x, y in zip(ta, tb))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--drake", action="store_true", help="also the default wave against the Drake loop")
    ap.add_argument("--nice", type=int, default=0)
    ap.add_argument("--oracle-python", default=DRAKE_PY, help="the oracle venv's python (pydrake)")
    ap.add_argument("--pinocchio-us", type=float, default=1.5, help="Pinocchio's step (µs), the target")
    args = ap.parse_args()
    if not os.path.exists(FAZE4):
        sys.exit(f"missing {FAZE4}: run `cargo build --release` first")
    print(f"load average at the start: {os.getloadavg()[0]:.1f}", flush=True)
    off = ["--no-collisions"]
    sweep = [FAZE4, "sweep", "--vary", "payload-kg=0:0.9:0.1", "-q", "--"]
    rows = []

    def row(name, a, b, target, kind="time"):
        ma, mb, ratio = paired(a, b, args.runs, args.nice)
        if kind == "throughput":
            ratio = 1.0 / ratio
        rows.append((name, ma, mb, ratio, target))
        print(f"  {name}: {ma:.3f} s against {mb:.3f} s, {ratio:.2f}x (target {target})", flush=True)

    row("wave (8 s), default / --no-collisions", [FAZE4, "wave"] + QUIET, [FAZE4, "wave"] + QUIET + off, "≤ 2x")
    circle = [FAZE4, "shape", "--shape", "circle"] + QUIET
    row("circle (12 s), default / --no-collisions", circle, circle + off, "≤ 1.5x")
    row("payload sweep of the wave (10 runs), throughput with / without", sweep + ["wave"],
        sweep + ["wave", "--no-collisions"], "≥ 0.7x", kind="throughput")

    # the marginal step: 16 s less 8 s (40,000 steps), with and without clearance
    per_step = {}
    for name, extra in (("with clearance", []), ("without", off)):
        long, short, _ = paired([FAZE4, "wave", "--duration", "16"] + QUIET + extra,
                                [FAZE4, "wave", "--duration", "8"] + QUIET + extra, args.runs, args.nice)
        per_step[name] = (long - short) / 40000 * 1e6
    print(f"  marginal step (16 s wave less 8 s): {per_step['with clearance']:.2f} µs with clearance, "
          f"{per_step['without']:.2f} µs without (target with ≤ Pinocchio's {args.pinocchio_us} µs)", flush=True)

    if args.drake:
        if not os.path.exists(args.oracle_python):
            sys.exit(f"missing {args.oracle_python}: tools/oracle/setup.sh, or --oracle-python")
        drake = [args.oracle_python, DRAKE_LOOP, "wave", "--duration", "8", "--quiet"]
        md, mf, ratio = paired(drake, [FAZE4, "wave"] + QUIET, args.runs, args.nice)
        rows.append(("Drake loop / default wave", md, mf, ratio, "≥ 50x"))
        print(f"  Drake loop {md:.3f} s, default wave {mf:.3f} s: {ratio:.1f}x (target ≥ 50x)", flush=True)

    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    print(f"\nmedians of {args.runs} paired runs:\n")
    print("| comparison | A (s) | B (s) | ratio | target |")
    print("|---|---|---|---|---|")
    for name, ma, mb, ratio, target in rows:
        print(f"| {name} | {ma:.3f} | {mb:.3f} | {ratio:.2f}x | {target} |")
    print(f"| marginal step, µs (with / without clearance) | {per_step['with clearance']:.2f} | "
          f"{per_step['without']:.2f} | | with ≤ {args.pinocchio_us} |")


if __name__ == "__main__":
    main()
