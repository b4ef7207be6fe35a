#!/usr/bin/env python3
"""Prints docs/motors.md's table: the Faze4 with and without its motors (--motors faze4).

    cargo build --release && python3 tools/motors_table.py [path/to/faze4]

Runs, each once without and once with --motors faze4 (defaults otherwise): the wave at 5 kHz and
at 1 kHz (8 s), and the three shapes (12 s). Prints, per run, kp, b_max, the spectral radius,
the max tracking error and the saturation per joint, as Markdown table rows.
"""

import json
import os
import subprocess
import sys
import tempfile

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
BINARY = sys.argv[1] if len(sys.argv) > 1 else os.path.join(REPO, "target", "release", "faze4")

CASES = [
    ("wave, 5 kHz", ["wave"]),
    ("wave, 1 kHz", ["wave", "--dt", "1e-3"]),
    ("shape sine", ["shape", "--shape", "sine"]),
    ("shape circle", ["shape", "--shape", "circle"]),
    ("shape tri", ["shape", "--shape", "tri"]),
]


def fmt(values, spec):
    return " ".join(spec.format(v) for v in values)


def main():
    print("| run | motors | kp (J1…J6) | b_max | ρ | max tracking error (mrad, J1…J6) | saturation (%, J1…J6) |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, args in CASES:
            for motors in ([], ["--motors", "faze4"]):
                out = os.path.join(tmp, "s.json")
                cmd = [BINARY, *args, *motors, "--trail", "none", "--summary", out]
                run = subprocess.run(cmd, cwd=tmp, capture_output=True, text=True)
                if run.returncode not in (0, 1):
                    sys.exit(f"{' '.join(cmd)} failed: {run.stderr}")
                with open(out) as f:
                    s = json.load(f)
                st = s["stability"]
                err = [1e3 * e for e in s["max_tracking_error_rad"]]
                diverged = " (diverged)" if s["diverged"] else ""
                print(f"| {name}{diverged} | {'faze4' if motors else 'none'} | {fmt(s['kp'], '{:.4g}')} | "
                      f"{st['b_max']:.3f} | {st['spectral_radius']:.4f} | {fmt(err, '{:.3g}')} | "
                      f"{fmt(s['saturation_pct'], '{:.2f}')} |")


if __name__ == "__main__":
    main()
