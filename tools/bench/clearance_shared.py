#!/usr/bin/env python3
"""A sweep whose runs share their commanded path's clearance, against the same sweep with each
run's own, and against the same sweep without clearance, side by side.

For each sweep (payload 0 to 0.9 kg in steps of 0.1, 10 runs; release build, `--quiet`):

* `faze4 sweep --vary payload-kg=0:0.9:0.1 -q -- shape --shape circle` (12 s each), and
* `faze4 sweep --vary payload-kg=0:0.9:0.1 -q -- wave` (8 s each),

runs, alternately, `--runs` times each:

* shared: the default (the path's clearance computed once, each run's derived from it;
  docs/clearance.md "Sweeps"),
* own: `--own-clearance` (each run computes its own, as alone),
* none: the base command with `--no-collisions`,

and prints each variant's median whole-process wall time, runs per second, and the medians of
the per-round ratios own/shared (the speed-up of sharing) and none/shared (the issue's target:
a payload sweep of the circle with clearance at ≥ 0.5× the throughput without).

Usage (repository root, after `cargo build --release`):

    python3 tools/bench/clearance_shared.py [--runs 5] [--jobs N] [--only circle|wave]
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FAZE4 = os.path.join(ROOT, "target", "release", "faze4")
PAYLOADS = "payload-kg=0:0.9:0.1"
ROWS = 10
SWEEPS = {
    "circle": ["shape", "--shape", "circle"],
    "wave": ["wave"],
}


def timed(cmd, cwd):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=cwd)
    return time.perf_counter() - t0


def bench(name, base, runs, jobs, tmp):
    sweep = [FAZE4, "sweep", "--vary", PAYLOADS, "-q", *(["--jobs", str(jobs)] if jobs else [])]
    variants = {
        "shared": [*sweep, "--", *base],
        "own (--own-clearance)": [*sweep, "--own-clearance", "--", *base],
        "none (--no-collisions)": [*sweep, "--", *base, "--no-collisions"],
    }
    times = {v: [] for v in variants}
    for _ in range(runs):
        for v, cmd in variants.items():  # alternated, so all see the same machine load
            times[v].append(timed(cmd, tmp))
    print(f"\n{name}: faze4 sweep --vary {PAYLOADS} -q -- {' '.join(base)}  ({ROWS} runs; medians of {runs})")
    print(f"  {'variant':24s} {'median':>9s} {'runs/s':>8s}")
    for v, t in times.items():
        m = statistics.median(t)
        print(f"  {v:24s} {m:8.3f}s {ROWS / m:8.2f}")
    shared = times["shared"]
    own = statistics.median(o / s for o, s in zip(times["own (--own-clearance)"], shared))
    none = statistics.median(n / s for n, s in zip(times["none (--no-collisions)"], shared))
    own_none = statistics.median(n / o for n, o in zip(times["none (--no-collisions)"], times["own (--own-clearance)"]))
    print(f"  sharing's speed-up (own / shared, median of the {runs} rounds): {own:.2f}×")
    print(f"  throughput with clearance / without: shared {none:.2f}×, own {own_none:.2f}× (target ≥ 0.5)")
    return {v: statistics.median(t) for v, t in times.items()}, own, none, own_none


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--jobs", type=int, default=0, help="the sweeps' --jobs (default: one per core)")
    ap.add_argument("--only", choices=sorted(SWEEPS), help="one sweep only")
    args = ap.parse_args()
    if not os.path.exists(FAZE4):
        sys.exit(f"missing {FAZE4}: run `cargo build --release` first")
    table = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, base in SWEEPS.items():
            if args.only in (None, name):
                table.append((name, *bench(name, base, args.runs, args.jobs, tmp)))
    print("\n| sweep (10 runs) | shared (s) | own (s) | none (s) | own / shared | clearance / none: shared | own |")
    print("|---|---|---|---|---|---|---|")
    for name, medians, own, none, own_none in table:
        s, o, n = medians.values()
        print(f"| {name} | {s:.3f} | {o:.3f} | {n:.3f} | {own:.2f}× | {none:.2f}× | {own_none:.2f}× |")


if __name__ == "__main__":
    main()
