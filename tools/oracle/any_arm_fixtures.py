#!/usr/bin/env python3
"""Pinocchio fixtures for the small arms of issue 21 ("any arm, first run"): each arm under
tests/urdf/ that loads only since faze4 reads URDFs as Drake and Pinocchio do (zero-mass links,
a massless dummy leaf, a transmission on a fixed joint, an inertia balanced by
--balance-inertia, COLLADA and OBJ meshes, a prismatic joint) runs `faze4 wave --center mid`
for 2 s, and pin_closed_loop.py runs the same closed loop with faze4's gains (--gains, from
faze4's --summary). The fixture holds Pinocchio's trail; tests/it/any_arm.rs reruns faze4 with
the fixture's arguments and compares the trails to 1e-9 (m, rad).

Run from the repository root with the oracle venv (tools/oracle/setup.sh), after `cargo build`:

    python tools/oracle/any_arm_fixtures.py [--faze4 target/debug/faze4]

Writes tests/fixtures/any_arm_<arm>.json. For the balanced arm, Pinocchio reads a copy of the
URDF with the hand's inertia replaced by what --balance-inertia gives (docs/model.md 1.3: the
three principal moments set to their mean about the same centre of mass).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import pinocchio as pin

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PIN = os.path.join(ROOT, "tools/oracle/pin_closed_loop.py")
DURATION = "2"

# arm, tool link, faze4 options beyond the common ones
CASES = [
    ("zero_mass_welded_arm", "hand", []),
    ("dummy_leaf_arm", "tool_frame", []),
    ("fixed_transmission_arm", "tool", []),
    ("invalid_inertia_arm", "hand", ["--balance-inertia"]),
    ("mesh_arm_dae", "hand", ["--package-path", "tests/urdf"]),
    ("mesh_arm_obj", "hand", ["--package-path", "tests/urdf"]),
    ("arm_prismatic", "tool", []),
]


def amplitudes(urdf, skip_mimic=False):
    """faze4's per-joint amplitude (docs/model.md 4.1): 25° in rad, a prismatic joint a quarter
    of its range (else 0.05 m); moving joints depth-first in document order (followers of a
    <mimic> left out with skip_mimic)."""
    root = ET.parse(urdf).getroot()
    joints = root.findall("joint")
    children = {}
    for j in joints:
        children.setdefault(j.find("parent").get("link"), []).append(j)
    child_links = {j.find("child").get("link") for j in joints}
    top = [l.get("name") for l in root.findall("link") if l.get("name") not in child_links][0]
    out = []
    order = []

    def visit(link):
        for j in children.get(link, []):
            order.append(j)
            visit(j.find("child").get("link"))

    visit(top)
    for j in order:
        kind = j.get("type")
        if kind in ("fixed", "floating", "planar") or (skip_mimic and j.find("mimic") is not None):
            continue
        if kind == "prismatic":
            lim = j.find("limit")
            lo, hi = float(lim.get("lower", "-inf")), float(lim.get("upper", "inf"))
            out.append(0.25 * (hi - lo) if math.isfinite(lo) and math.isfinite(hi) else 0.05)
        else:
            out.append(25.0 * (math.pi / 180.0))
    return out


def balanced_copy(urdf, link, directory):
    """`urdf` with `link`'s (diagonal, unrotated) inertia set to the mean of its moments."""
    tree = ET.parse(urdf)
    for l in tree.getroot().findall("link"):
        if l.get("name") == link:
            i = l.find("inertial/inertia")
            mean = (float(i.get("ixx")) + float(i.get("iyy")) + float(i.get("izz"))) / 3.0
            for k in ("ixx", "iyy", "izz"):
                i.set(k, repr(mean))
    path = os.path.join(directory, os.path.basename(urdf))
    tree.write(path)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--faze4", default=os.path.join(ROOT, "target/debug/faze4"))
    args = ap.parse_args()
    for arm, tool, extra in CASES:
        urdf = f"tests/urdf/{arm}.urdf"
        faze4_args = ["wave", "--urdf", urdf, "--center", "mid", "--duration", DURATION,
                      "--tool-link", tool, "--no-collisions"] + extra
        with tempfile.TemporaryDirectory() as tmp:
            summary = os.path.join(tmp, "faze4.json")
            subprocess.run([args.faze4] + faze4_args + ["-q", "--trail", "none", "--summary", summary],
                           cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
            pin_urdf = os.path.join(ROOT, urdf)
            if "--balance-inertia" in extra:
                pin_urdf = balanced_copy(pin_urdf, "hand", tmp)
            amp = amplitudes(os.path.join(ROOT, urdf))
            trail = os.path.join(tmp, "pin.csv")
            subprocess.run([sys.executable, PIN, "--urdf", pin_urdf, "--gains", summary, "--center", "mid",
                            "--amplitude", ",".join(repr(a) for a in amp), "--duration", DURATION,
                            "--tool-link", tool, "--trail", trail, "--quiet"],
                           cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
            gains = json.load(open(summary))
            lines = open(trail).read().split()
            fixture = {
                "generator": "tools/oracle/any_arm_fixtures.py",
                "pinocchio_version": pin.__version__,
                "urdf": urdf,
                "faze4_args": faze4_args,
                "amplitude": amp,
                "gains": {k: gains[k] for k in ("dt", "kp", "kd", "effort")},
                "trail": {"columns": lines[0].split(","),
                          "rows": [[float(x) for x in l.split(",")] for l in lines[1:]]},
            }
        out = os.path.join(ROOT, f"tests/fixtures/any_arm_{arm}.json")
        with open(out, "w") as f:
            json.dump(fixture, f)
        print(f"{out}: {len(fixture['trail']['rows'])} rows")


if __name__ == "__main__":
    main()
