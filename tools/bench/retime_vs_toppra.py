#!/usr/bin/env python3
"""faze4's retime against toppra on the same 6-dof path and 200-interval grid, side by side.

Runs, alternately, N times each:

* `target/release/examples/retime PATH.npy ...`: faze4's retime from the library, the closed-loop
  check included (the motors' envelopes under `--motors faze4`);
* `tools/bench/toppra_retime.py CASE` (the oracle venv): toppra with constant limits on the same
  spline and grid, from the waypoints to its trajectory;

and prints the medians and their ratio:

* in-process: the time each program reports for the retime itself (`wall_ms`: spline, limits,
  passes, and for faze4 the check runs; model loading and file reading excluded on both sides);
* process: the whole command, start to exit (Python's imports of toppra and Pinocchio included).

Cases: `circle` (the Faze4's circle, tests/fixtures/shape_circle_q.npy: faze4 with its stepper
envelopes, toppra with the holding torques as constants) and `ur5` (the path and URDF limits of
tests/fixtures/retime_toppra_ur5.json on both sides; faze4's check slows where the loop passes a
speed limit, so it plays the motion several times).

Usage (repository root; needs `cargo build --release --example retime` and tools/oracle/setup.sh):

    python3 tools/bench/retime_vs_toppra.py [--runs 9] [--case circle|ur5|all] [--python PY]

(`--python`: the oracle venv's interpreter, tools/oracle/.venv/bin/python by default.)
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
RETIME = os.path.join(ROOT, "target", "release", "examples", "retime")
PYTHON = os.path.join(ROOT, "tools", "oracle", ".venv", "bin", "python")
TOPPRA = os.path.join(ROOT, "tools", "bench", "toppra_retime.py")


def timed(cmd):
    t0 = time.perf_counter()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=ROOT).stdout
    process = time.perf_counter() - t0
    fields = out.split()
    values = dict(zip(fields[::2], fields[1::2]))
    return process, float(values["wall_ms"]) * 1e-3, float(values["duration_s"])


def commands(case, tmp, python):
    """faze4's and toppra's command lines for `case`."""
    if case == "circle":
        ours = [RETIME, "tests/fixtures/shape_circle_q.npy", "--motors", "faze4"]
    else:
        with open(os.path.join(ROOT, "tests", "fixtures", f"retime_toppra_{case}.json")) as f:
            fixture = json.load(f)
        urdf = os.path.join(tmp, f"{case}.urdf")
        with open(urdf, "w") as f:
            f.write(fixture["urdf_text"])
        path = os.path.join(tmp, f"{case}.npy")
        write_npy(path, fixture["waypoints"])
        ours = [RETIME, path, "--urdf", urdf]
    return {"faze4": ours, "toppra": [python, TOPPRA, case]}


def write_npy(path, rows):
    """rows as a little-endian f64 C-order .npy (format 1.0), without numpy."""
    import struct
    header = f"{{'descr': '<f8', 'fortran_order': False, 'shape': ({len(rows)}, {len(rows[0])}), }}"
    header += " " * ((64 - (10 + len(header) + 1) % 64) % 64) + "\n"
    with open(path, "wb") as f:
        f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode())
        for row in rows:
            f.write(struct.pack(f"<{len(row)}d", *row))


def bench(case, runs, tmp, python):
    results = {"faze4": [], "toppra": []}
    for run in range(runs):
        for name, cmd in commands(case, tmp, python).items():  # alternate: both see the same load
            results[name].append(timed(cmd))
            process, inner, duration = results[name][-1]
            print(f"{case} run {run + 1}/{runs} {name:6s} in-process {inner * 1e3:8.2f} ms, "
                  f"process {process:.3f} s, motion {duration:.3f} s", file=sys.stderr)
    med = {n: (statistics.median(r[1] for r in rs), statistics.median(r[0] for r in rs), rs[-1][2])
           for n, rs in results.items()}
    print(f"{case}: median of {runs} runs each, 200 grid intervals")
    print(f"  {'':8s}{'in-process (ms)':>17s}{'process (s)':>13s}{'motion (s)':>12s}")
    for n in ("toppra", "faze4"):
        print(f"  {n:8s}{med[n][0] * 1e3:17.2f}{med[n][1]:13.3f}{med[n][2]:12.3f}")
    print(f"  ratio   {med['toppra'][0] / med['faze4'][0]:16.2f}x{med['toppra'][1] / med['faze4'][1]:12.2f}x"
          "   (toppra / faze4: above 1, faze4 is faster)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=9)
    ap.add_argument("--case", default="all", choices=["circle", "ur5", "all"])
    ap.add_argument("--python", default=PYTHON)
    args = ap.parse_args()
    for path in (RETIME, args.python):
        if not os.path.exists(path):
            sys.exit(f"missing {path}: run `cargo build --release --example retime` and tools/oracle/setup.sh")
    with tempfile.TemporaryDirectory() as tmp:
        for case in (["circle", "ur5"] if args.case == "all" else [args.case]):
            bench(case, args.runs, tmp, args.python)


if __name__ == "__main__":
    main()
