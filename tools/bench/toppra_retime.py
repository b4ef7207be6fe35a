#!/usr/bin/env python3
"""toppra's half of tools/bench/retime_vs_toppra.py: one timing of a fixture's path, timed in
the process from the waypoints to toppra's trajectory (the spline, the constraints with
Pinocchio's RNEA, TOPP-RA's passes on the 200-interval grid, compute_trajectory), printed as

    duration_s <T> wall_ms <ms>

    tools/oracle/.venv/bin/python tools/bench/toppra_retime.py circle|ur5

`circle`: the Faze4's circle with each motor's holding torque and top speed as constant limits
(the fixture tests/fixtures/retime_toppra_circle.json's `holding` case, less faze4's margin);
`ur5`: tests/fixtures/retime_toppra_ur5.json's path and limits.
"""
import json
import os
import sys
import time

import numpy as np
import pinocchio as pin
import toppra
import toppra.algorithm as algo
import toppra.constraint as constraint

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools", "oracle"))
from retime_fixtures import FAZE4_RATIO, FAZE4_ROTOR, INTERVALS, chord_knots  # noqa: E402


def fixture(name):
    with open(os.path.join(ROOT, "tests", "fixtures", f"retime_toppra_{name}.json")) as f:
        return json.load(f)


def case(name):
    """(model, armature, waypoints, velocity limits, torque limits) of a bench case."""
    if name == "circle":
        f = fixture("circle")
        model = pin.buildModelFromUrdf(os.path.join(ROOT, f["urdf"]))
        armature = np.array([r * r * FAZE4_ROTOR for r in FAZE4_RATIO])
        waypoints = np.load(os.path.join(ROOT, f["path"]))
        return model, armature, waypoints, f["holding"]["velocity_limit"], f["holding"]["torque_limit"]
    f = fixture(name)
    model = pin.buildModelFromXML(f["urdf_text"])
    return model, np.zeros(model.nv), np.array(f["waypoints"]), f["velocity_limit"], f["torque_limit"]


def solve(model, armature, waypoints, vlim, tau):
    """toppra's trajectory of the waypoints' not-a-knot spline over chord length, on the
    200-interval grid, under the velocity limits `vlim` and torque limits `tau` (RNEA plus the
    armature's torque)."""
    data = model.createData()
    knots = chord_knots(waypoints)
    path = toppra.SplineInterpolator(knots, waypoints, bc_type="not-a-knot")
    grid = np.linspace(0.0, knots[-1], INTERVALS + 1)
    pc_v = constraint.JointVelocityConstraint(np.column_stack([-np.asarray(vlim), np.asarray(vlim)]))
    pc_t = constraint.JointTorqueConstraint(
        lambda q, v, a: pin.rnea(model, data, q, v, a) + armature * a,
        np.column_stack([-np.asarray(tau), np.asarray(tau)]), np.zeros(len(tau)))
    instance = algo.TOPPRA([pc_v, pc_t], path, gridpoints=grid, solver_wrapper="seidel")
    return instance.compute_trajectory(0.0, 0.0)


def main():
    limits = case(sys.argv[1] if len(sys.argv) > 1 else "circle")
    started = time.perf_counter()
    trajectory = solve(*limits)
    wall = time.perf_counter() - started
    print(f"duration_s {trajectory.duration} wall_ms {wall * 1e3:.3f}")


if __name__ == "__main__":
    main()
