#!/usr/bin/env python3
"""Writes tests/fixtures/rotor_arm.json: Drake reading the motors of tests/urdf/rotor_arm.urdf.

    tools/oracle/.venv/bin/python tools/oracle/rotor_fixtures.py

The URDF's <transmission> elements carry drake:rotor_inertia and drake:gear_ratio; Drake adds
each motor's reflected inertia r^2 * I_rotor to its joint's diagonal of M. The fixture holds

  * "reflected_inertia": Drake's JointActuator::default_reflected_inertia() per joint (0 without
    a motor), in joint order;
  * "mass_matrix": M(q) (CalcMassMatrix) at 8 seeded random configurations within the limits;
  * "closed_loop": drake_closed_loop.py's wave on this arm (4 joints, the URDF's effort limits,
    2 s at dt 2e-4, trail every 0.02 s) with its summary and trail.

Deterministic: a fixed seed, and the same drake/numpy versions write the same bytes.
"""

import importlib.metadata
import json
import os
import sys

import numpy as np
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import drake_closed_loop as dcl  # noqa: E402
from closed_loop_fixtures import to_json  # noqa: E402

REPO = dcl.REPO_ROOT
URDF_REL = "tests/urdf/rotor_arm.urdf"
OUT_REL = "tests/fixtures/rotor_arm.json"
EFFORT = [20.0, 15.0, 30.0, 3.0]  # the URDF's <limit effort>, which faze4 uses by default
WAVE = dict(amp_deg=25.0, freq=0.5)
RUN = dict(duration=2.0, dt=2e-4, record_period=0.02)


def main():
    urdf = os.path.join(REPO, URDF_REL)
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(urdf)
    plant.Finalize()
    ctx = plant.CreateDefaultContext()
    n = plant.num_positions()

    reflected = [0.0] * n
    for a in plant.GetJointActuatorIndices():
        actuator = plant.get_joint_actuator(a)
        reflected[actuator.joint().position_start()] = actuator.default_reflected_inertia()

    rng = np.random.default_rng(20261123)
    lower, upper = plant.GetPositionLowerLimits(), plant.GetPositionUpperLimits()
    lower = np.where(np.isfinite(lower), lower, -np.pi)
    upper = np.where(np.isfinite(upper), upper, np.pi)
    samples = []
    for _ in range(8):
        q = rng.uniform(lower, upper)
        plant.SetPositions(ctx, q)
        samples.append({"q": q.tolist(), "m": plant.CalcMassMatrix(ctx).tolist()})

    summary, trail = dcl.run_closed_loop(
        dcl.wave_command(WAVE["amp_deg"], WAVE["freq"], dof=n), duration=RUN["duration"], dt=RUN["dt"],
        record_period=RUN["record_period"], urdf=urdf, effort=EFFORT, verbose=False)
    if summary["diverged"]:
        sys.exit("the Drake run diverged")
    summary.pop("wall_time_s")

    fixture = {
        "generator": "tools/oracle/rotor_fixtures.py",
        "drake_version": importlib.metadata.version("drake"),
        "urdf": URDF_REL,
        "reflected_inertia": reflected,
        "mass_matrix": samples,
        "closed_loop": {
            "args": {**WAVE, **RUN, "effort": EFFORT},
            "summary": summary,
            "trail": {"columns": ["t", "x", "y", "z"] + [f"q{i + 1}" for i in range(n)],
                      "rows": trail.tolist()},
        },
    }
    with open(os.path.join(REPO, OUT_REL), "w") as f:
        f.write(to_json(fixture) + "\n")
    print(f"[done] {OUT_REL}: reflected inertia {reflected}, {len(trail)} trail rows")


if __name__ == "__main__":
    main()
