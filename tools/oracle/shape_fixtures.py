#!/usr/bin/env python3
"""Drake fixtures for `faze4 shape`: the drawing runs of docs/model.md.

For each shape (sine, circle, tri; 240 points):
  1. faze4's own IK writes the joint samples (`faze4 shape --shape S --save-q ...`, the release
     binary must be built) -> tests/fixtures/shape_<S>_q.npy;
  2. Drake plays them as the periodic command of drake_closed_loop.py (sample k at k*5/N s,
     wrapping), 12 s at dt 2e-4, trail every 0.02 s;
  3. Drake's forward kinematics checks every saved sample against its target (the largest
     distance is written as drake_fk_max_residual_m);
  4. the path deviation is computed here from docs/model.md's formulas, written independently of
     the Rust code (distance from the tool to the closed polyline through the 240 targets).
Writes tests/fixtures/closed_loop_shape_<S>.json in the closed-loop fixture format, with the
extra summary keys path_deviation_mm {max, mean} and the targets.

Run from the repository root:  tools/oracle/.venv/bin/python tools/oracle/shape_fixtures.py
"""

import importlib.metadata
import json
import math
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import drake_closed_loop as dcl  # noqa: E402

ROOT = dcl.REPO_ROOT
FAZE4 = os.path.join(ROOT, "target", "release", "faze4")
SHAPES = ("sine", "circle", "tri")
N = 240
PERIOD = 5.0
ARGS = {"duration": 12.0, "dt": 2e-4, "record_period": 0.02, "shape_points": N}

# docs/model.md: the board and the shapes
XC, YB, ZC, R = 0.08, -0.48, 0.55, 0.16
L, A = 0.19, 0.12


def shape_point(shape, s):
    if shape == "circle":
        u, w = R * math.cos(2 * math.pi * s), R * math.sin(2 * math.pi * s)
    elif shape == "tri":
        verts = [(R * math.cos(math.radians(a)), R * math.sin(math.radians(a))) for a in (90, 210, 330)]
        e = min(int(math.floor(3 * s)), 2)
        f = 3 * s - e
        (ax, az), (bx, bz) = verts[e], verts[(e + 1) % 3]
        u, w = ax + f * (bx - ax), az + f * (bz - az)
    else:
        u = -L + 4 * L * s if s < 0.5 else L - 4 * L * (s - 0.5)
        w = A * math.sin(math.pi / L * u)
    return np.array([XC + u, YB, ZC + w])


def distance_to_closed_path(p, path):
    best = math.inf
    for k in range(len(path)):
        a, b = path[k], path[(k + 1) % len(path)]
        ab = b - a
        t = np.clip(np.dot(p - a, ab) / np.dot(ab, ab), 0.0, 1.0)
        best = min(best, float(np.linalg.norm(a + t * ab - p)))
    return best


def drake_fk_max_residual(Q, targets):
    """Largest distance from Drake's tool_link origin at each sample of Q to its target (m)."""
    plant, _simulator, context = dcl.build()
    tool = plant.GetBodyByName(dcl.TOOL_BODY)
    worst = 0.0
    for q, target in zip(Q, targets):
        plant.SetPositions(context, q)
        p = plant.EvalBodyPoseInWorld(context, tool).translation()
        worst = max(worst, float(np.linalg.norm(p - target)))
    return worst


def main():
    if not os.path.exists(FAZE4):
        sys.exit(f"missing {FAZE4}: run `cargo build --release` first")
    for shape in SHAPES:
        q_path = os.path.join(ROOT, "tests", "fixtures", f"shape_{shape}_q.npy")
        subprocess.run([FAZE4, "shape", "--shape", shape, "--shape-points", str(N), "--save-q", q_path,
                        "--duration", "0.0002", "--trail", "none"], check=True, stdout=subprocess.DEVNULL)
        Q = np.load(q_path)
        assert Q.shape == (N, 6) and Q.dtype == np.float64, Q.shape
        targets = np.array([shape_point(shape, k / N) for k in range(N)])
        fk_residual = drake_fk_max_residual(Q, targets)
        summary, trail = dcl.run_closed_loop(
            dcl.periodic_command(Q, PERIOD), duration=ARGS["duration"], dt=ARGS["dt"],
            record_period=ARGS["record_period"], verbose=False)
        d = np.array([distance_to_closed_path(row[1:4], targets) for row in trail])
        summary.pop("wall_time_s")
        summary["path_deviation_mm"] = {"max": float(d.max() * 1e3), "mean": float(d.mean() * 1e3)}
        fixture = {
            "generator": "tools/oracle/shape_fixtures.py",
            "drake_version": importlib.metadata.version("drake"),
            "urdf": "urdf/faze4_arm.urdf",
            "command": "shape",
            "args": {"shape": shape, **ARGS, "q_samples": os.path.relpath(q_path, ROOT)},
            "targets": targets.tolist(),
            "drake_fk_max_residual_m": fk_residual,
            "summary": summary,
            "trail": {"columns": dcl.TRAIL_COLUMNS, "rows": trail.tolist()},
        }
        out = os.path.join(ROOT, "tests", "fixtures", f"closed_loop_shape_{shape}.json")
        with open(out, "w") as f:
            json.dump(fixture, f)
            f.write("\n")
        sat = ", ".join(f"{x:.2f}" for x in summary["saturation_pct"])
        print(f"{shape:6s}: Drake FK residual {fk_residual:.1e} m; deviation max {summary['path_deviation_mm']['max']:.2f} mm, "
              f"mean {summary['path_deviation_mm']['mean']:.2f} mm; saturation % [{sat}]; "
              f"x [{summary['tool_range_m']['x'][0]:.3f}, {summary['tool_range_m']['x'][1]:.3f}] -> {out}")


if __name__ == "__main__":
    main()
