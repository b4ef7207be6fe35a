#!/usr/bin/env python3
"""Peak memory of long runs: `faze4 wave --duration D --no-collisions` for D = 60, 600, 3600 s
(default outputs: the trail CSV streamed to disk, the summary), or with `--clearance` the
default self-clearance on (an hour's wave then takes several minutes). Memory must not grow
with the duration (issue 47: the longest run's peak within 1.1× of the shortest's, printed
last); the trail file does. Needs `cargo build --release`.

    python3 tools/bench/long_run.py [--durations 60 600 3600] [--clearance]

Prints per run: simulated seconds, steps, wall time, peak resident memory (the kernel's
ru_maxrss of that one process) and the trail's size.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FAZE4 = os.path.join(ROOT, "target", "release", "faze4")


def run(duration, workdir, clearance):
    trail = os.path.join(workdir, f"trail_{duration}.csv")
    summary = os.path.join(workdir, f"summary_{duration}.json")
    args = [FAZE4, "wave", "--duration", str(duration), "--trail", trail, "--summary", summary]
    args += [] if clearance else ["--no-collisions"]
    start = time.perf_counter()
    child = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    stderr = child.stderr.read().decode()
    child.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"{' '.join(args)} failed: {stderr}")
    size = os.path.getsize(trail)
    os.remove(trail)
    os.remove(summary)
    return wall, usage.ru_maxrss / 1024.0, size / 1e6  # ru_maxrss is in KiB on Linux


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--durations", type=float, nargs="+", default=[60, 600, 3600])
    parser.add_argument("--clearance", action="store_true", help="self-clearance on (the default run's)")
    args = parser.parse_args()
    if not os.path.exists(FAZE4):
        sys.exit(f"missing {FAZE4}: run `cargo build --release` first")
    print(f"{'simulated':>10} {'steps':>10} {'wall':>8} {'peak RSS':>10} {'trail':>9}")
    with tempfile.TemporaryDirectory() as workdir:
        peaks = []
        for d in args.durations:
            wall, rss_mib, trail_mb = run(d, workdir, args.clearance)
            peaks.append(rss_mib)
            print(f"{d:>9.0f}s {round(d / 2e-4):>10} {wall:>7.1f}s {rss_mib:>7.1f} MiB {trail_mb:>6.1f} MB",
                  flush=True)
        print(f"peak of the longest over the shortest: {peaks[-1] / peaks[0]:.2f}x")


if __name__ == "__main__":
    main()
