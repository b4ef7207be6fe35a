#!/usr/bin/env python3
"""What self-clearance costs a whole process, at the default tolerance, exactly, on hulls and
not at all, side by side; and what it costs a sweep.

For each job (the Faze4's `wave` (8 s) and `shape --shape circle` (12 s), and an 8 s
`wave --center mid` on each `--arm URDF` given), runs alternately, `--runs` times each
(release build, trail off, `--quiet`):

* the default (`--clearance-tolerance` at its default),
* `--clearance-tolerance 0` (exact),
* `--collision-geometry hull`,
* `--no-collisions`,
* and each `--tolerances MM,...` (the curve of the ratio against the tolerance),

and prints each variant's median whole-process wall time and its ratio to `--no-collisions`
(the issue's targets: default ≤ 1.25× on the Faze4, ≤ 1.5× on other arms). Where the time
goes: the median of the summary's `clearance_wall_time_s` (the samples and the final search),
and of a one-step run (loading the meshes and building their hulls and BVHs, and starting up).

Then a sweep (`sweep --vary payload-kg=0:0.9:0.1 -- wave --duration 2`) with and without
clearance, alternately: runs per second of each and their ratio (target ≥ 0.5).

Usage (repository root, after `cargo build --release`):

    python3 tools/bench/clearance_speed.py [--runs 5] [--tolerances 0.01,0.1,0.3,1]
        [--arm URDF [--package-path DIR]]... [--erd] [--no-faze4] [--no-sweep]

`--erd` adds every fixed-base arm of the `example-robot-data` pip package, as
tools/robots_survey.py lists them (needs that package and Pinocchio: tools/oracle/setup.sh's
venv). At the end, a Markdown table of every job's medians and ratios.
"""

import argparse
import glob
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FAZE4 = os.path.join(ROOT, "target", "release", "faze4")
SWEEP = ["sweep", "--vary", "payload-kg=0:0.9:0.1", "--quiet", "--", "wave", "--duration", "2"]


def timed(cmd, cwd):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=cwd)
    return time.perf_counter() - t0


def clearance_time(cmd, cwd):
    summary = os.path.join(cwd, "s.json")
    subprocess.run([*cmd, "--summary", summary], check=True, stdout=subprocess.DEVNULL, cwd=cwd)
    with open(summary) as f:
        s = json.load(f)
    return s.get("clearance_wall_time_s") or 0.0, s.get("clearance", {})


def bench_job(name, base, duration, variants, runs, tmp):
    job = [*base, "--duration", duration]
    times = {v: [] for v in variants}
    for _ in range(runs):
        for v, extra in variants.items():  # alternate, so all see the same machine load
            times[v].append(timed([FAZE4, *job, *extra, "--trail", "none", "--quiet"], tmp))
    samples = [clearance_time([FAZE4, *job, "--trail", "none", "--quiet"], tmp) for _ in range(runs)]
    loading = [timed([FAZE4, *base, "--duration", "0.0002", "--trail", "none", "--quiet"], tmp) for _ in range(runs)]
    alone = statistics.median(times["--no-collisions"])
    print(f"\n{name}: faze4 {' '.join(job)} (medians of {runs}, whole process)")
    print(f"  {'variant':28s} {'median':>9s} {'ratio':>7s}")
    for v, t in times.items():
        m = statistics.median(t)
        print(f"  {v:28s} {m:8.3f}s {m / alone:6.2f}×")
    c = samples[-1][1]
    print(
        f"  default: clearance in the loop {statistics.median(s for s, _ in samples):.3f} s (samples and final"
        f" search); a one-step run (loading, start-up) {statistics.median(loading):.3f} s;"
        f" min {1e3 * (c.get('min_m') or float('nan')):.3f} mm, tolerance {1e3 * c.get('tolerance_m', 0):.2f} mm"
    )
    return {v: statistics.median(t) for v, t in times.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--tolerances", default="", help="extra tolerances (mm), comma-separated")
    ap.add_argument("--arm", action="append", default=[], help="a URDF to wave (8 s, --center mid)")
    ap.add_argument("--package-path", action="append", default=[])
    ap.add_argument("--erd", action="store_true", help="every fixed-base example-robot-data arm")
    ap.add_argument("--no-faze4", action="store_true", help="leave out the Faze4's two jobs")
    ap.add_argument("--no-sweep", action="store_true")
    args = ap.parse_args()
    if not os.path.exists(FAZE4):
        sys.exit(f"missing {FAZE4}: run `cargo build --release` first")
    variants = {
        "default": [],
        "--clearance-tolerance 0": ["--clearance-tolerance", "0"],
        "--collision-geometry hull": ["--collision-geometry", "hull"],
        "--no-collisions": ["--no-collisions"],
    }
    for mm in filter(None, args.tolerances.split(",")):
        variants[f"--clearance-tolerance {mm}"] = ["--clearance-tolerance", mm]
    jobs = {}
    if not args.no_faze4:
        jobs = {"Faze4 wave": (["wave"], "8"), "Faze4 circle": (["shape", "--shape", "circle"], "12")}
    packages = [x for p in args.package_path for x in ("--package-path", p)]
    arms = list(args.arm)
    if args.erd:
        sys.path.insert(0, os.path.join(ROOT, "tools"))
        from robots_survey import FIXED, ROBOTS, SHARE  # noqa: E402

        packages += ["--package-path", SHARE]
        for folder in sorted(FIXED):
            arms += sorted(glob.glob(os.path.join(ROBOTS, folder, "**", "*.urdf"), recursive=True))
    for urdf in arms:
        jobs[os.path.basename(urdf)] = (["wave", "--center", "mid", "--urdf", urdf, *packages], "8")
    table = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, (base, duration) in jobs.items():
            try:
                table.append((name, bench_job(name, base, duration, variants, args.runs, tmp)))
            except subprocess.CalledProcessError as e:
                print(f"\n{name}: faze4 failed (exit {e.returncode}); left out")
        names = list(variants)
        print("\n| job | " + " | ".join(f"{v} (s, ×)" for v in names) + " |")
        print("|---|" + "---|" * len(names))
        for name, medians in table:
            alone = medians["--no-collisions"]
            cells = [f"{medians[v]:.3f} ({medians[v] / alone:.2f}×)" for v in names]
            print(f"| {name} | " + " | ".join(cells) + " |")
        if args.no_sweep:
            return
        with_c, without = [], []
        for _ in range(args.runs):
            with_c.append(timed([FAZE4, *SWEEP], tmp))
            without.append(timed([FAZE4, *SWEEP, "--no-collisions"], tmp))
        rows = 10
        a, b = rows / statistics.median(with_c), rows / statistics.median(without)
        print(f"\nsweep: faze4 {' '.join(SWEEP)} ({rows} runs, medians of {args.runs})")
        print(f"  with clearance      {a:7.1f} runs/s")
        print(f"  --no-collisions     {b:7.1f} runs/s")
        print(f"  ratio               {a / b:7.2f}  (target ≥ 0.5)")


if __name__ == "__main__":
    main()
