#!/usr/bin/env python3
"""TOPP-RA's timings (toppra, hungpham2511/toppra; Pham & Pham 2018) of the paths faze4's retime
times, on the same spline and grid, for tests/it/retime_vs_toppra.rs and docs/retime.md.

The path is the not-a-knot cubic spline through the waypoints over their cumulative chord length
in joint space (toppra.SplineInterpolator, i.e. SciPy's CubicSpline), the grid 200 equal
intervals of it, TOPP-RA's collocation discretisation (its default), the seidel solver, from
rest to rest. Joint torque comes from Pinocchio's RNEA of the same URDF (plus r² I_rotor q̈ where
the Faze4's motors add their rotors), velocity limits from JointVelocityConstraint.

1. Constant limits on arms of example-robot-data (ur5, panda; panda read with mimic=True, so its
   second finger follows the first as in faze4) and on the Faze4 (urdf/faze4_arm.urdf, its
   original's torque limits, 3 rad/s given as the speed limit since its URDF's velocity is a
   placeholder): seeded waypoints inside the joint limits (the Faze4's closer to its upright
   pose, where its shoulder can hold the arm with the margin left); toppra's profile x = ṡ² on the grid,
   its duration (Σ 2Δs/(ṡ_i + ṡ_i+1), TOPP-RA's constant-s̈ reading) and toppra's own
   trajectory's, and the torque coefficients a, b, c at every 20th grid point.
2. The Faze4's circle (tests/fixtures/shape_circle_q.npy) with the stepper motors of
   `--motors faze4` (a 17HS16-2004S1 at 2.0 A and 24 V behind each reducer): two ways a toppra
   user would give it constant limits, each less faze4's default margin:
   * `holding`: each joint's holding torque r·T(0);
   * `top_speed`: the envelope r·T(ω) at one motor speed ω, with ω/r as every joint's speed
     limit (so the torque holds wherever the timing goes), ω chosen (a scan of 40 speeds up to
     the curve's last, then golden section) to give the shortest duration: the best constant a
     user can pick.
   The stepper's pull-out curve is computed here as src/control/motor.rs computes it
   (StepperWinding::pull_out_torque, pull_out_curve); the test checks every constant against
   faze4's envelope.

Run from the repository root:

    tools/oracle/.venv/bin/python tools/oracle/retime_fixtures.py

Writes tests/fixtures/retime_toppra_{ur5,panda,faze4_arm}.json and
tests/fixtures/retime_toppra_circle.json.
"""
import json
import math
import os
import sys

import numpy as np
import pinocchio as pin
import toppra
import toppra.algorithm as algo
import toppra.constraint as constraint
from importlib.metadata import version

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHARE = os.path.join(os.path.dirname(pin.__file__), "..", "..", "..", "..", "share")
ERD = os.path.join(SHARE, "example-robot-data", "robots")
FIXTURES = os.path.join(ROOT, "tests", "fixtures")

INTERVALS = 200
# faze4's retime::DEFAULT_MARGIN (the test checks they agree)
MARGIN = 0.3
# every 20th grid point's torque coefficients go in the fixture
COEFFICIENT_EVERY = 20

# the Faze4 (src/faze4/mod.rs EFFORT; src/faze4/motors.rs GEAR_RATIO, ROTOR_INERTIA)
FAZE4_EFFORT = [7.9, 8.5, 4.7, 3.7, 3.5, 6.0]
FAZE4_RATIO = [25.0, 27.0, 15.0, 11.846, 11.0, 19.19]
FAZE4_ROTOR = 54e-7
FAZE4_SPEED = 3.0
# src/control/catalog.rs: NEMA17_17HS16_2004S1 at 2.0 A, 24 V; CURVE_POINTS, CURVE_TAIL
WINDING = dict(holding_torque=0.45, rated_current=2.0, resistance=1.1, inductance=2.6e-3, rotor_teeth=50.0)
CURRENT, SUPPLY = 2.0, 24.0
CURVE_POINTS, CURVE_TAIL = 256, 0.05
# src/control/motor.rs: the top speed a timing may reach (retime's TOP_SPEED_SHARE)
TOP_SPEED_SHARE = 1.0 - 1e-9


def pull_out_torque(omega, current, supply, w=WINDING):
    """StepperWinding::pull_out_torque (src/control/motor.rs, docs/motors.md)."""
    k = w["holding_torque"] / (math.sqrt(2.0) * w["rated_current"])
    r, x = w["resistance"], w["rotor_teeth"] * omega * w["inductance"]
    z2 = r * r + x * x
    e = k * omega
    cx, cy = -e * x / z2, -e * r / z2
    rho = supply / math.sqrt(z2)

    def within(px, py):
        return (px - cx) ** 2 + (py - cy) ** 2 <= rho * rho * (1.0 + 1e-12)

    if within(0.0, current):
        return k * current
    tx, ty = cx, cy + rho
    if tx * tx + ty * ty <= current * current:
        return max(k * ty, 0.0)
    d = math.sqrt(cx * cx + cy * cy)
    if d > current + rho or d < abs(current - rho) or d == 0.0:
        return 0.0
    a = (current * current - rho * rho + d * d) / (2.0 * d)
    h = math.sqrt(max(current * current - a * a, 0.0))
    my = a * cy / d
    y1 = my + h * cx / d
    y2 = my - h * cx / d
    return max(k * max(y1, y2), 0.0)


def pull_out_curve(current, supply, points, tail):
    """StepperWinding::pull_out_curve: `points` evenly spaced speeds up to the tail speed."""
    t0 = pull_out_torque(0.0, current, supply)
    lo, hi = 0.0, 1.0
    while pull_out_torque(hi, current, supply) > tail * t0 and hi < 1e7:
        hi *= 2.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if pull_out_torque(mid, current, supply) > tail * t0:
            lo = mid
        else:
            hi = mid
    return [(hi * i / (points - 1), pull_out_torque(hi * i / (points - 1), current, supply)) for i in range(points)]


def curve_torque(curve, w):
    """Envelope::bounds' pull-out torque at shaft speed w ≥ 0 (linear between points, zero past
    the last)."""
    if w > curve[-1][0]:
        return 0.0
    if w <= curve[0][0]:
        return curve[0][1]
    for (w0, t0), (w1, t1) in zip(curve, curve[1:]):
        if w == w1:
            return t1
        if w < w1:
            return t0 + (t1 - t0) * (w - w0) / (w1 - w0)
    return curve[-1][1]


def chord_knots(points):
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])


class Arm:
    """A Pinocchio model and the inverse dynamics toppra calls (plus reflected rotors)."""

    def __init__(self, urdf, mimic=False, armature=None):
        self.model = pin.buildModelFromUrdf(urdf, mimic=mimic)
        self.data = self.model.createData()
        self.armature = np.zeros(self.model.nv) if armature is None else np.asarray(armature)

    def inv_dyn(self, q, v, a):
        return pin.rnea(self.model, self.data, q, v, a) + self.armature * a

    def names(self):
        return [n for n, j in zip(self.model.names[1:], self.model.joints[1:]) if j.nq > 0]


def toppra_profile(arm, waypoints, vlim, tau_lim):
    """toppra on the chord-length not-a-knot spline of `waypoints`, INTERVALS equal intervals:
    (gridpoints, x, duration by the constant-s̈ sum, toppra's trajectory duration, coefficients),
    or None when toppra finds no parameterization."""
    knots = chord_knots(waypoints)
    path = toppra.SplineInterpolator(knots, waypoints, bc_type="not-a-knot")
    grid = np.linspace(0.0, knots[-1], INTERVALS + 1)
    pc_v = constraint.JointVelocityConstraint(np.column_stack([-np.asarray(vlim), np.asarray(vlim)]))
    pc_t = constraint.JointTorqueConstraint(
        arm.inv_dyn, np.column_stack([-np.asarray(tau_lim), np.asarray(tau_lim)]), np.zeros(len(tau_lim)),
        discretization_scheme=constraint.DiscretizationType.Collocation)
    instance = algo.TOPPRA([pc_v, pc_t], path, gridpoints=grid, solver_wrapper="seidel")
    _, sd, _, _ = instance.compute_parameterization(0.0, 0.0, return_data=True)
    if sd is None or np.isnan(sd).any():
        return None
    x = sd ** 2
    duration = float(np.sum(2.0 * np.diff(grid) / (sd[:-1] + sd[1:])))
    trajectory = instance.compute_trajectory(0.0, 0.0)
    a, b, c, *_ = pc_t.compute_constraint_params(path, grid)
    picked = list(range(0, INTERVALS + 1, COEFFICIENT_EVERY))
    coefficients = [{"i": i, "a": a[i].tolist(), "b": b[i].tolist(), "c": c[i].tolist()} for i in picked]
    return grid, x, duration, float(trajectory.duration), coefficients


def write(name, fixture):
    path = os.path.join(FIXTURES, f"retime_toppra_{name}.json")
    with open(path, "w") as f:
        json.dump(fixture, f, indent=1)
        f.write("\n")
    print(f"wrote {os.path.relpath(path, ROOT)}")


def constant_case(name, urdf, mimic, vlim, tau_lim, limits, fixed, seed, spread=0.3):
    """Six seeded waypoints within ±`spread` of each joint's range (its limits cut to ±2.5 rad)
    about its middle, `fixed` joints held at the given value."""
    arm = Arm(urdf, mimic=mimic)
    rng = np.random.default_rng(seed)
    lo = np.maximum(np.asarray(limits[0]), -2.5)
    hi = np.minimum(np.asarray(limits[1]), 2.5)
    mid, half = 0.5 * (lo + hi), spread * (hi - lo)
    waypoints = mid + half * rng.uniform(-1.0, 1.0, size=(6, len(lo)))
    for j, value in fixed.items():
        waypoints[:, j] = value
    found = toppra_profile(arm, waypoints, vlim, tau_lim)
    if found is None:
        sys.exit(f"{name}: toppra found no parameterization")
    grid, x, duration, toppra_duration, coefficients = found
    with open(urdf) as f:
        text = f.read()
    write(name, {
        "toppra": version("toppra"),
        "robot": name,
        "urdf": os.path.relpath(urdf, ROOT) if urdf.startswith(ROOT) else None,
        "urdf_text": None if urdf.startswith(ROOT) else text,
        "joints": arm.names(),
        "waypoints": waypoints.tolist(),
        "velocity_limit": list(vlim),
        "torque_limit": list(tau_lim),
        "intervals": INTERVALS,
        "gridpoints": grid.tolist(),
        "x": x.tolist(),
        "duration": duration,
        "toppra_trajectory_duration": toppra_duration,
        "coefficients": coefficients,
    })


def circle_case():
    urdf = os.path.join(ROOT, "urdf", "faze4_arm.urdf")
    armature = [r * r * FAZE4_ROTOR for r in FAZE4_RATIO]
    arm = Arm(urdf, armature=armature)
    waypoints = np.load(os.path.join(FIXTURES, "shape_circle_q.npy"))
    curve = pull_out_curve(CURRENT, SUPPLY, CURVE_POINTS, CURVE_TAIL)
    top = curve[-1][0]
    keep = 1.0 - MARGIN

    def run(omega):
        """toppra with every joint's torque r·T(ω) less the margin, its speed limit ω/r."""
        tau = [keep * r * curve_torque(curve, omega) for r in FAZE4_RATIO]
        vlim = [TOP_SPEED_SHARE * omega / r for r in FAZE4_RATIO]
        found = toppra_profile(arm, waypoints, vlim, tau)
        if found is None:  # too little torque to hold the arm anywhere on the path
            return dict(omega=omega, duration=math.inf)
        _, x, duration, toppra_duration, _ = found
        return dict(omega=omega, torque_limit=tau, velocity_limit=vlim, x=x.tolist(), duration=duration,
                    toppra_trajectory_duration=toppra_duration)

    # the holding torque, the motors' top speed as the speed limit
    holding_tau = [keep * r * curve[0][1] for r in FAZE4_RATIO]
    vlim = [TOP_SPEED_SHARE * top / r for r in FAZE4_RATIO]
    grid, x, duration, toppra_duration, _ = toppra_profile(arm, waypoints, vlim, holding_tau)
    holding = dict(omega=0.0, torque_limit=holding_tau, velocity_limit=vlim, x=x.tolist(), duration=duration,
                   toppra_trajectory_duration=toppra_duration)
    # the shortest duration over ω in (0, top]: a scan, then golden section about its best
    scan = [run(top * k / 40) for k in range(1, 41)]
    k = min(range(40), key=lambda i: scan[i]["duration"])
    phi = (math.sqrt(5.0) - 1.0) / 2.0
    lo, hi = top * k / 40, top * (k + 2) / 40
    a, b = hi - phi * (hi - lo), lo + phi * (hi - lo)
    fa, fb = run(a), run(b)
    for _ in range(30):
        if fa["duration"] < fb["duration"]:
            hi, b, fb = b, a, fa
            a = hi - phi * (hi - lo)
            fa = run(a)
        else:
            lo, a, fa = a, b, fb
            b = lo + phi * (hi - lo)
            fb = run(b)
    best = fa if fa["duration"] < fb["duration"] else fb
    write("circle", {
        "toppra": version("toppra"),
        "robot": "faze4_arm",
        "urdf": "urdf/faze4_arm.urdf",
        "path": "tests/fixtures/shape_circle_q.npy",
        "motors": "faze4",
        "margin": MARGIN,
        "intervals": INTERVALS,
        "gridpoints": grid.tolist(),
        "gear_ratio": FAZE4_RATIO,
        "holding": holding,
        "top_speed": best,
    })


def main():
    ur5 = os.path.join(ERD, "ur_description", "urdf", "ur5_robot.urdf")
    model = pin.buildModelFromUrdf(ur5)
    constant_case("ur5", ur5, False, model.velocityLimit.tolist(), model.effortLimit.tolist(),
                  (model.lowerPositionLimit, model.upperPositionLimit), {}, seed=5)
    panda = os.path.join(ERD, "panda_description", "urdf", "panda.urdf")
    model = pin.buildModelFromUrdf(panda, mimic=True)
    constant_case("panda", panda, True, model.velocityLimit.tolist(), model.effortLimit.tolist(),
                  (model.lowerPositionLimit, model.upperPositionLimit), {7: 0.02}, seed=7)
    faze4 = os.path.join(ROOT, "urdf", "faze4_arm.urdf")
    model = pin.buildModelFromUrdf(faze4)
    constant_case("faze4_arm", faze4, False, [FAZE4_SPEED] * 6, FAZE4_EFFORT,
                  (model.lowerPositionLimit, model.upperPositionLimit), {}, seed=9, spread=0.15)
    circle_case()


if __name__ == "__main__":
    main()
