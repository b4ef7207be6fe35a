#!/usr/bin/env python3
"""Runs `faze4 wave --center mid` over the fixed-base arms of the `example-robot-data` pip package
(6.0.0, pinned in tools/oracle/requirements.txt) and prints a Markdown table: whether Pinocchio
loads the URDF, whether faze4 runs it (exit status), whether every collision mesh was read (no
`unchecked` link in the summary), and the largest difference between faze4's trail and
Pinocchio's closed loop with faze4's gains (tools/oracle/pin_closed_loop.py --mimic).

    /work/venv/bin/python tools/robots_survey.py [--faze4 target/debug/faze4] [--duration 1]

Robots whose base floats (legged robots, humanoids, aerial and mobile bases: example-robot-data's
own loaders build them with a free-flyer joint) are skipped and listed as such: faze4 simulates
an arm fixed to the world, so their dynamics would not be theirs.
"""
import argparse
import csv
import glob
import json
import os
import subprocess
import sys
import tempfile

import pinocchio as pin

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools/oracle"))
from any_arm_fixtures import amplitudes  # noqa: E402

SHARE = os.path.join(os.path.dirname(pin.__file__), "..", "..", "..", "..", "share")
ROBOTS = os.path.join(SHARE, "example-robot-data", "robots")
# fixed-base manipulators (and fixed-base pendulums and hands) of example-robot-data
FIXED = {"ur_description", "panda_description", "kinova_description", "z1_description",
         "so_arm_description", "xarm_description", "double_pendulum_description",
         "finger_edu_description", "asr_twodof_description", "baxter_description",
         "allegro_hand_description"}


def trail(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return [[float(x) for x in r] for r in rows[1:]]


def survey_one(faze4, urdf, duration):
    rel = os.path.relpath(urdf, ROBOTS)
    try:
        pin.buildModelFromUrdf(urdf, mimic=True)
        pin_loads = "yes"
    except Exception as e:  # noqa: BLE001 - any refusal is a row
        return [rel, f"no ({str(e).splitlines()[0][:60]})", "-", "-", "-"]
    with tempfile.TemporaryDirectory() as tmp:
        summary, ours = os.path.join(tmp, "s.json"), os.path.join(tmp, "f.csv")
        run = subprocess.run([faze4, "wave", "--urdf", urdf, "--package-path", SHARE, "--center", "mid",
                              "--duration", str(duration), "--summary", summary, "--trail", ours],
                             capture_output=True, text=True, timeout=900)
        if run.returncode != 0:
            last = (run.stderr.strip().splitlines() or ["?"])[-1]
            return [rel, pin_loads, f"exit {run.returncode}: {last[:90]}", "-", "-"]
        s = json.load(open(summary))
        unchecked = (s.get("clearance") or {}).get("unchecked", [])
        meshes = "all read" if not unchecked else f"unchecked: {', '.join(unchecked)}"
        tool = s["tool_link"]
        theirs = os.path.join(tmp, "p.csv")
        amp = amplitudes(urdf, skip_mimic=True)
        ref = subprocess.run([sys.executable, os.path.join(ROOT, "tools/oracle/pin_closed_loop.py"), "--urdf", urdf,
                              "--mimic", "--gains", summary, "--center", "mid", "--amplitude",
                              ",".join(repr(a) for a in amp), "--duration", str(duration), "--tool-link", tool,
                              "--trail", theirs, "--quiet"], capture_output=True, text=True, timeout=900)
        v = s["verdict"]
        verdict = v if isinstance(v, str) else ("follows" if v.get("follows") else "cannot follow") + (
            ", collides" if v.get("collides") else "")
        if ref.returncode != 0:
            return [rel, pin_loads, f"exit 0 ({verdict})", meshes,
                    f"reference failed: {(ref.stderr.strip().splitlines() or ['?'])[-1][:60]}"]
        a, b = trail(ours), trail(theirs)
        worst = max(abs(x - y) for r, q in zip(a, b) for x, y in zip(r, q)) if len(a) == len(b) else float("nan")
        return [rel, pin_loads, f"exit 0 ({verdict})", meshes, f"{worst:.1e}" + (" ✓" if worst <= 1e-9 else " ✗")]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--faze4", default=os.path.join(ROOT, "target/debug/faze4"))
    ap.add_argument("--duration", type=float, default=1.0)
    args = ap.parse_args()
    print("| URDF | Pinocchio loads | faze4 wave --center mid | meshes | max |faze4 − Pinocchio| (trail) |")
    print("|---|---|---|---|---|")
    skipped = []
    for folder in sorted(os.listdir(ROBOTS)):
        urdfs = sorted(glob.glob(os.path.join(ROBOTS, folder, "**", "*.urdf"), recursive=True))
        if folder not in FIXED:
            if urdfs:
                skipped.append(folder)
            continue
        for urdf in urdfs:
            print("| " + " | ".join(survey_one(args.faze4, urdf, args.duration)) + " |", flush=True)
    print(f"\nSkipped, floating base: {', '.join(skipped)}")


if __name__ == "__main__":
    main()
