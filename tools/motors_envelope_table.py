#!/usr/bin/env python3
"""Prints docs/motors.md's envelope table: the original's sine, circle and wave (and a fast wave)
with the constant clip and with --motors faze4 and --motors faze4-bom.

    cargo build --release && python3 tools/motors_envelope_table.py [path/to/faze4]

Per run and motor set: the verdict, saturation per joint (%), and under --motors the share of
steps beyond the envelope (%), the RMS torque at the shaft (N·m) and when a stepper first loses
steps (s), as Markdown table rows.
"""

import json
import os
import subprocess
import sys
import tempfile

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
BINARY = sys.argv[1] if len(sys.argv) > 1 else os.path.join(REPO, "target", "release", "faze4")

CASES = [
    ("shape sine", ["shape", "--shape", "sine"]),
    ("shape circle", ["shape", "--shape", "circle"]),
    ("wave", ["wave"]),
    ("wave --freq 2", ["wave", "--freq", "2"]),
    ("wave --freq 4", ["wave", "--freq", "4"]),
]


def fmt(values, spec):
    return " ".join("-" if v is None else spec.format(v) for v in values)


def main():
    print("| run | motors | follows | saturation (%) | beyond envelope (%) | RMS torque (N·m at the shaft) | loses steps at (s) |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, args in CASES:
            for motors in ([], ["--motors", "faze4"], ["--motors", "faze4-bom"]):
                out = os.path.join(tmp, "s.json")
                cmd = [BINARY, *args, *motors, "--no-collisions", "--trail", "none", "--summary", out, "--quiet"]
                run = subprocess.run(cmd, cwd=tmp, capture_output=True, text=True)
                if run.returncode not in (0, 1):
                    sys.exit(f"{' '.join(cmd)} failed: {run.stderr}")
                with open(out) as f:
                    s = json.load(f)
                m = s.get("motors") or []
                env = fmt([x and x["envelope_pct"] for x in m], "{:.2f}") if m else "-"
                rms = fmt([x and x["rms_torque"] for x in m], "{:.3f}") if m else "-"
                lost = " ".join("-" if x is None or "loses_steps_at" not in x else
                                ("never" if x["loses_steps_at"] is None else f"{x['loses_steps_at']:.2f}")
                                for x in m) if m else "-"
                label = motors[1] if motors else "constant clip"
                print(f"| {name} | {label} | {'yes' if s['verdict']['follows'] else 'no'} | "
                      f"{fmt(s['saturation_pct'], '{:.2f}')} | {env} | {rms} | {lost} |")


if __name__ == "__main__":
    main()
