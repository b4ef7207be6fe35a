#!/usr/bin/env python3
"""Writes tests/fixtures/xacro/*.urdf: the official xacro descriptions of tests/xacro expanded by
ROS's `xacro` (the PyPI package, pinned in requirements.txt), without ROS.

    tools/oracle/.venv/bin/python tools/oracle/xacro_fixtures.py

The descriptions (their .xacro and .yaml files, fetched; README.md beside them says from where):
Universal Robots' ROS 2 description (`ur_description`, `urdf/ur.urdf.xacro`, every `ur_type`) and
Franka's (`franka_description`, `robots/fr3/fr3.urdf.xacro`, with and without the hand); and
`odd/odd.urdf.xacro`, of our own making (the constructs in odd combinations). xacro's
`$(find PKG)` asks ament's index, which needs ROS; here it is the folder under tests/xacro whose
package.xml names PKG (what xacrodoc does too: it replaces `substitution_args._eval_find`). The
arguments of each case are in CASES and written into each fixture's first line as a comment, so
`tests/it/xacro.rs` expands the same file with the same arguments and compares the documents
(every element, attribute and text), the models (every link, joint, inertia, limit and mesh
reference) and the runs. Deterministic: the same xacro
writes the same bytes.
"""

import importlib.metadata
import os
import pathlib
import re

import xacro
from xacro import substitution_args

REPO = pathlib.Path(__file__).resolve().parents[2]
SOURCES = REPO / "tests" / "xacro"
OUT = REPO / "tests" / "fixtures" / "xacro"

UR_TYPES = ["ur3", "ur3e", "ur5", "ur5e", "ur10", "ur10e", "ur16e", "ur20", "ur30"]
UR = "ur_description/urdf/ur.urdf.xacro"
FR3 = "franka_description/robots/fr3/fr3.urdf.xacro"
ODD = "odd/odd.urdf.xacro"

# (fixture name, xacro file under tests/xacro, arguments in the order given)
CASES = [(t, UR, [("name", t), ("ur_type", t)]) for t in UR_TYPES] + [
    ("ur5e_prefixed_safety", UR, [("name", "ur5e"), ("ur_type", "ur5e"), ("tf_prefix", "left_"), ("safety_limits", "true")]),
    ("fr3", FR3, []),
    ("fr3_no_hand", FR3, [("hand", "false"), ("arm_prefix", "left")]),
    # of our own making: the constructs in odd combinations (tests/xacro/odd)
    ("odd", ODD, [("name", "odd")]),
    ("odd_prefixed", ODD, [("name", "odd2"), ("prefix", "left"), ("with_tool", "false"), ("scale", "2")]),
]


def find(package):
    """The folder under tests/xacro whose package.xml names `package`."""
    for xml in sorted(SOURCES.glob("*/package.xml")):
        if re.search(rf"<name>\s*{re.escape(package)}\s*</name>", xml.read_text()):
            return str(xml.parent)
    raise RuntimeError(f"no package {package} under {SOURCES}")


def main():
    substitution_args._eval_find = find
    OUT.mkdir(parents=True, exist_ok=True)
    version = importlib.metadata.version("xacro")
    cwd = os.getcwd()
    os.chdir(REPO)  # the file names xacro prints are relative to the repository
    try:
        for name, rel, args in CASES:
            source = f"tests/xacro/{rel}"
            text = xacro.process(source, mappings=dict(args))
            arguments = " ".join(f"{k}:={v}" for k, v in args)
            # the banner xacro writes names the input; our first line names the case
            text = re.sub(r"^<\?xml[^>]*\?>\n", "", text)
            header = f'<?xml version="1.0" ?>\n<!-- faze4 fixture: xacro {version} on {source} {arguments} -->\n'
            (OUT / f"{name}.urdf").write_text(header + text)
            print(f"{name}: {source} {arguments}")
    finally:
        os.chdir(cwd)


if __name__ == "__main__":
    main()
