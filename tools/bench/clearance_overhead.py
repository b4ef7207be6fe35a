#!/usr/bin/env python3
"""What self-clearance adds to a run, and the same exact distances from coal, side by side.

Runs, alternately, N times each (release build):

* `faze4 shape --shape circle --duration 12 --no-collisions` (the run alone),
* the same with `--collision-geometry hull`,
* the same with the exact meshes (`--clearance-tolerance 0`),
* the same with the default (the meshes to within 1 mm),

and prints the medians of the whole process's wall time and each clearance's overhead over the
run alone (the issue's target: exact meshes add at most 20 %).

Then, on the very joint samples of that run's trail (600 rows, one every 0.02 s), it times coal
(the BVH library Pinocchio uses, `BVHModelOBBRSS`, exact triangles) asked for the distance of
every mesh pair faze4 checks, one query per pair and sample, as a reference for what an exact
distance costs: faze4 prunes pairs and samples with lower bounds, coal is asked every one.

Usage (repository root; needs `cargo build --release` and tools/oracle/setup.sh for coal):

    python3 tools/bench/clearance_overhead.py [--runs 5] [--no-coal]
"""

import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FAZE4 = os.path.join(ROOT, "target", "release", "faze4")
ORACLE_PY = os.path.join(ROOT, "tools", "oracle", ".venv", "bin", "python")
RUN = ["shape", "--shape", "circle", "--duration", "12", "--quiet"]
VARIANTS = {
    "run alone": ["--no-collisions"],
    "hull": ["--collision-geometry", "hull"],
    "exact mesh": ["--clearance-tolerance", "0"],
    "default (1 mm)": [],
}

COAL = r'''
import json, sys, time
from pathlib import Path
sys.path.insert(0, str(Path(sys.argv[1]) / "tools" / "oracle"))
import coal
import clearance_fixtures as cf
import tempfile

q_rows, pairs_wanted = json.load(open(sys.argv[2]))
tmp = Path(tempfile.mkdtemp())
urdf, meshes = cf.prepare(cf.REPO / "urdf" / "faze4_real.urdf", tmp)
_diagram, _context, plant, pc = cf.plant_of(urdf)
inspector = plant.get_geometry_query_input_port().Eval(pc).inspector()
geometry = {}
for link, _, g in cf.proximity_geometries(plant, inspector):
    exact, _, is_mesh, _, _ = cf.coal_object(inspector.GetShape(g), meshes)
    if is_mesh:
        geometry[link] = (g, exact)
pairs = [p for p in pairs_wanted if p[0] in geometry and p[1] in geometry]
poses = []
for q in q_rows:
    plant.SetPositions(pc, q)
    qo = plant.get_geometry_query_input_port().Eval(pc)
    poses.append({name: cf.tf(qo.GetPoseInWorld(g)) for name, (g, _) in geometry.items()})
request = coal.DistanceRequest()
smallest = {}
t0 = time.perf_counter()
for pose in poses:
    for a, b in pairs:
        result = coal.DistanceResult()
        coal.distance(geometry[a][1], pose[a], geometry[b][1], pose[b], request, result)
        key = f"{a}-{b}"
        smallest[key] = min(smallest.get(key, float("inf")), result.min_distance)
elapsed = time.perf_counter() - t0
print(json.dumps({"seconds": elapsed, "queries": len(poses) * len(pairs), "min_m": smallest}))
'''


def wall(cmd, cwd):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, cwd=cwd)
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--no-coal", action="store_true", help="skip the coal reference")
    args = ap.parse_args()
    if not os.path.exists(FAZE4):
        sys.exit(f"missing {FAZE4}: run `cargo build --release` first")

    times = {name: [] for name in VARIANTS}
    with tempfile.TemporaryDirectory() as tmp:
        for run in range(args.runs):
            for name, extra in VARIANTS.items():  # alternate, so all see the same machine load
                times[name].append(wall([FAZE4, *RUN, *extra, "--trail", "none"], tmp))
            print(f"run {run + 1}/{args.runs}: " + ", ".join(f"{n} {t[-1]:.3f} s" for n, t in times.items()))
        alone = statistics.median(times["run alone"])
        print(f"\nmedians of {args.runs} runs of faze4 {' '.join(RUN)}:")
        for name, t in times.items():
            m = statistics.median(t)
            over = "" if name == "run alone" else f"   +{100 * (m / alone - 1):.0f} % over the run alone"
            print(f"  {name:14s} {m:.3f} s{over}")

        if args.no_coal:
            return
        if not os.path.exists(ORACLE_PY):
            sys.exit(f"missing {ORACLE_PY}: run tools/oracle/setup.sh (or pass --no-coal)")
        trail, summary = os.path.join(tmp, "trail.csv"), os.path.join(tmp, "summary.json")
        subprocess.run([FAZE4, *RUN, "--clearance-tolerance", "0", "--trail", trail, "--summary", summary], check=True, cwd=tmp)
        with open(trail) as f:
            rows = [[float(r[f"q{i}"]) for i in range(1, 7)] for r in csv.DictReader(f)]
        with open(summary) as f:
            clearance = json.load(f)["clearance"]
        pairs = [p["links"] for p in clearance["pairs"]]
        job = os.path.join(tmp, "job.json")
        with open(job, "w") as f:
            json.dump([rows, pairs], f)
        out = subprocess.run([ORACLE_PY, "-c", COAL, ROOT, job], check=True, capture_output=True, text=True)
        coal = json.loads(out.stdout.strip().splitlines()[-1])
        mesh = statistics.median(times["exact mesh"]) - alone
        print(f"\ncoal, every mesh pair at every one of the {len(rows)} trail samples: {coal['queries']} queries, "
              f"{coal['seconds']:.3f} s ({1e3 * coal['seconds'] / coal['queries']:.3f} ms a query)")
        print(f"faze4's exact clearance over the same samples (median overhead above): {mesh:.3f} s "
              f"= {mesh / coal['seconds']:.2f} × coal's time")
        worst = max(abs(coal["min_m"][f"{a}-{b}"] - p["min_m"]) for (a, b), p in
                    ((p["links"], p) for p in clearance["pairs"]) if f"{a}-{b}" in coal["min_m"])
        print(f"largest difference of a pair's minimum, faze4 vs coal: {worst:.2e} m")


if __name__ == "__main__":
    main()
