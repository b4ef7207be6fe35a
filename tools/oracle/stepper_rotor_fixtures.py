#!/usr/bin/env python3
"""Writes tests/fixtures/stepper_rotor.json: an independent single-rotor simulation of the
Faze4's steppers driven open loop, integrated at 1 us from the winding and rotor equations, to
check faze4's `--drive stepper` (tests/it/stepper_oracle.rs; docs/motors.md, "The stepper's
damping").

It shares no code and no formula with faze4's drive beyond the equations themselves. faze4
takes the torque-angle curve -K I sin(N_r (theta - theta_cmd)) and folds the driver's current
loop into an electrical damping b_e = K^2 Re(1/Z); here the two phase currents are states:

    e_a = -K w sin(N_r theta),   e_b = K w cos(N_r theta)             (back-EMF)
    i_ref = I (cos N_r theta_cmd, sin N_r theta_cmd)                   (the driver's microstep)
    v = clamp(R i_ref + L w_c (i_ref - i), -V, V)                      (its current loop, bandwidth f_c)
    L di/dt = v - R i - e
    T = K (-i_a sin(N_r theta) + i_b cos(N_r theta))
    J dw/dt = T - b w - T_c sgn(w)   (sticking while |T| <= T_c at rest)

J the joint's inertia at the default wave's start pose (Pinocchio's CRBA on urdf/faze4_arm.urdf)
reflected to the shaft plus the rotor, b the joint's URDF damping reflected to the shaft plus the
rotor's and the reducer's viscous damping. Each phase current is advanced exactly over each
1 us step with the voltage and back-EMF held (a first-order linear equation, clamped or not);
the rotor by semi-implicit Euler.

Cases, for the motors of `--motors faze4` (J4, J6) and `--motors faze4-bom` (J3..J6):
  * ring-down: the rotor released one microstep off its command, 0.15 s: the damping ratio and
    the ringing frequency from the peaks of its swing;
  * wave: the joint commanded c + A sin(w t), A = 25 deg, w = 0.5 rad/s (the default wave's),
    from its command's speed at t = 0, for 8 s, at the driver's bandwidths 2, 5 and 20 kHz, with
    and without added rotor damping and reducer friction: whether it slips, when, the steps lost
    and the largest lag.

    tools/oracle/.venv/bin/python tools/oracle/stepper_rotor_fixtures.py    (repository root)
"""

import json
import math
import os

import numpy as np
import pinocchio as pin

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
URDF = "urdf/faze4_arm.urdf"
DT = 1e-6
WAVE_AMPLITUDE = math.radians(25.0)
WAVE_OMEGA = 0.5
WAVE_DURATION = 8.0
RING_DURATION = 0.15
URDF_DAMPING = 0.1  # the Faze4 URDF's <dynamics damping> on every joint (checked below)

# The published figures (docs/motors.md has each source): holding torque (N m), rated current
# (A), R (ohm), L (H), rotor teeth, rotor inertia (kg m^2).
MOTORS = {
    "17HS16-2004S1": (0.45, 2.0, 1.1, 2.6e-3, 50, 54e-7),
    "23HM22-2804S": (1.26, 2.8, 1.16, 4.2e-3, 100, 300e-7),
    "14HS13-0804S": (0.18, 0.8, 6.8, 10e-3, 50, 14e-7),
}
RATIO = [25.0, 27.0, 15.0, 11.846, 11.0, 19.19]
MICROSTEPS = [8, 8, 4, 2, 2, 2]

# (name, joint index, motor, current A, supply V)
JOINTS = [
    ("faze4 J4", 3, "17HS16-2004S1", 2.0, 24.0),
    ("faze4 J6", 5, "17HS16-2004S1", 2.0, 24.0),
    ("faze4-bom J3", 2, "23HM22-2804S", 2.2, 24.0),
    ("faze4-bom J4", 3, "17HS16-2004S1", 1.2, 24.0),
    ("faze4-bom J5", 4, "17HS16-2004S1", 1.2, 24.0),
    ("faze4-bom J6", 5, "14HS13-0804S", 0.7, 24.0),
]
# (driver bandwidth Hz, rotor damping N m s/rad, reducer friction as a share of K I)
VARIANTS = [
    (2000.0, 0.0, 0.0),
    (5000.0, 0.0, 0.0),
    (20000.0, 0.0, 0.0),
    (5000.0, 3e-4, 0.0),
    (20000.0, 0.0, 0.02),
]


def link_inertias():
    """M_ii of the Faze4's links at the default wave's start pose, q_i = A sin(i pi/3)."""
    model = pin.buildModelFromUrdf(os.path.join(REPO, URDF))
    assert model.nv == 6
    for j in range(1, model.njoints):
        assert abs(model.damping[model.joints[j].idx_v] - URDF_DAMPING) < 1e-12, model.damping
    q = np.array([WAVE_AMPLITUDE * math.sin(i * math.pi / 3.0) for i in range(6)])
    data = model.createData()
    m = pin.crba(model, data, q)
    return [float(m[i, i]) for i in range(6)]


def case(name, joint, motor, current, supply, link, kind, bandwidth, rotor_damping, friction_share):
    holding, rated, r, l, teeth, rotor = MOTORS[motor]
    k = holding / (math.sqrt(2.0) * rated)
    ratio = RATIO[joint]
    return {
        "name": name,
        "kind": kind,
        "joint": joint + 1,
        "motor": motor,
        "holding_torque": holding,
        "rated_current": rated,
        "resistance": r,
        "inductance": l,
        "rotor_teeth": teeth,
        "rotor_inertia": rotor,
        "current": current,
        "supply": supply,
        "gear_ratio": ratio,
        "microsteps": MICROSTEPS[joint],
        "link_inertia": link,
        "joint_damping": URDF_DAMPING,
        "driver_bandwidth": bandwidth,
        "rotor_damping": rotor_damping,
        "reducer_friction": friction_share * k * current,
        # at the shaft
        "inertia": rotor + link / ratio**2,
        "viscous": URDF_DAMPING / ratio**2 + rotor_damping,
        "k": k,
    }


def simulate(cases, duration, command, start):
    """Every case in lockstep for `duration` s: command(t) -> (theta_cmd at the shaft, its
    microstep), start(case) -> (theta, w) at t = 0. Returns per case the rotor angle's lag from
    the microstep at every step of `record` (a stride), the first slip, the cycles and the
    largest lag."""
    n = len(cases)
    col = lambda key: np.array([c[key] for c in cases], dtype=float)
    teeth, k, current, supply = col("rotor_teeth"), col("k"), col("current"), col("supply")
    r, l, w_c = col("resistance"), col("inductance"), 2.0 * math.pi * col("driver_bandwidth")
    inertia, viscous, friction = col("inertia"), col("viscous"), col("reducer_friction")
    ratio, microsteps = col("gear_ratio"), col("microsteps")
    micro = 2.0 * math.pi / (4.0 * teeth * microsteps)
    theta, w = np.zeros(n), np.zeros(n)
    for i, c in enumerate(cases):
        theta[i], w[i] = start(c)

    def held(t):
        angle = command(t) * ratio
        return np.round(angle / micro) * micro

    cmd = held(0.0)
    ia, ib = current * np.cos(teeth * cmd), current * np.sin(teeth * cmd)
    cycles = np.round(teeth * (theta - cmd) / (2.0 * math.pi))
    first = np.full(n, np.nan)
    max_lag = np.zeros(n)
    steps = int(round(duration / DT))
    stride = 10
    trace = np.zeros((steps // stride + 1, n))
    a_loop = np.exp(-DT * (w_c + r / l))  # the unclamped loop's decay over a step
    a_open = np.exp(-DT * r / l)  # a clamped phase's
    for s in range(steps + 1):
        t = s * DT
        cmd = held(t)
        e_lag = teeth * (theta - cmd)
        c_now = np.round(e_lag / (2.0 * math.pi))
        slipped = (c_now != cycles) & np.isnan(first)
        first[slipped] = t
        cycles = c_now
        lag = np.abs(e_lag - 2.0 * math.pi * c_now)
        np.maximum(max_lag, lag, out=max_lag)
        if s % stride == 0:
            trace[s // stride] = theta - cmd
        if s == steps:
            break
        sin, cos = np.sin(teeth * theta), np.cos(teeth * theta)
        ea, eb = -k * w * sin, k * w * cos
        ra, rb = current * np.cos(teeth * cmd), current * np.sin(teeth * cmd)
        for phase, (i_now, i_ref, e) in enumerate(((ia, ra, ea), (ib, rb, eb))):
            v = r * i_ref + l * w_c * (i_ref - i_now)
            clamped = np.abs(v) > supply
            # unclamped: L di/dt = (R + L w_c)(i_ref - i) - e -> i_inf = i_ref - e/(R + L w_c)
            inf_loop = i_ref - e / (r + l * w_c)
            # clamped: L di/dt = +-V - R i - e -> i_inf = (+-V - e)/R
            inf_open = (np.sign(v) * supply - e) / r
            new = np.where(clamped, inf_open + (i_now - inf_open) * a_open, inf_loop + (i_now - inf_loop) * a_loop)
            if phase == 0:
                ia = new
            else:
                ib = new
        torque = k * (-ia * sin + ib * cos) - viscous * w
        moving = w != 0.0
        w_new = w + DT * (torque - friction * np.sign(w)) / inertia
        # a moving rotor that friction would turn back stops; one at rest starts only past T_c
        w_new = np.where(moving & (np.sign(w_new) != np.sign(w)), 0.0, w_new)
        breaks = np.abs(torque) > friction
        w_new = np.where(~moving, np.where(breaks, DT * (torque - friction * np.sign(torque)) / inertia, 0.0), w_new)
        w = w_new
        theta = theta + DT * w
    return first, cycles, max_lag, trace, stride


def ring_down(trace, stride):
    """The damping ratio and the damped ringing frequency (rad/s) from the peaks of the lag
    about the microstep (the rotor's rest: no load)."""
    x = trace
    t = np.arange(len(x)) * DT * stride
    peaks = [i for i in range(1, len(x) - 1) if x[i] > x[i - 1] and x[i] >= x[i + 1] and x[i] > 0]
    first, last = peaks[1], peaks[min(8, len(peaks) - 1)]
    cycles = peaks.index(last) - peaks.index(first)
    w_d = 2.0 * math.pi * cycles / (t[last] - t[first])
    decrement = math.log(x[first] / x[last]) / cycles
    zeta = decrement / math.sqrt(4.0 * math.pi**2 + decrement**2)
    return zeta, w_d


def main():
    links = link_inertias()
    rings, waves = [], []
    for name, joint, motor, current, supply in JOINTS:
        for bandwidth, rotor_damping, share in VARIANTS:
            args = (name, joint, motor, current, supply, links[joint])
            waves.append(case(*args, "wave", bandwidth, rotor_damping, share))
            if share == 0.0 and bandwidth == 5000.0:
                rings.append(case(*args, "ring", bandwidth, rotor_damping, 0.0))

    # ring-down: the command still at 0, the rotor one microstep ahead of it, at rest
    def ring_start(c):
        return 2.0 * math.pi / (4.0 * c["rotor_teeth"] * c["microsteps"]), 0.0

    first, cycles, _, trace, stride = simulate(rings, RING_DURATION, lambda t: 0.0, ring_start)
    for i, c in enumerate(rings):
        assert np.isnan(first[i]), c["name"]
        c["zeta"], c["ring_rad_s"] = ring_down(trace[:, i], stride)

    # the wave: c + A sin(w t), from its command's position and speed at t = 0
    def wave(t):
        return WAVE_AMPLITUDE * math.sin(WAVE_OMEGA * t)

    def wave_start(c):
        return 0.0, c["gear_ratio"] * WAVE_AMPLITUDE * WAVE_OMEGA

    first, cycles, max_lag, _, _ = simulate(waves, WAVE_DURATION, wave, wave_start)
    for i, c in enumerate(waves):
        c["slips_at"] = None if np.isnan(first[i]) else float(first[i])
        c["steps_lost"] = int(abs(cycles[i])) * 4
        c["max_lag_steps"] = float(max_lag[i] / (math.pi / 2.0))
    fixture = {
        "source": "tools/oracle/stepper_rotor_fixtures.py (numpy " + np.__version__ + ", Pinocchio "
        + pin.__version__ + "; the winding and rotor at 1 us)",
        "urdf": URDF,
        "dt": DT,
        "wave": {"amplitude_rad": WAVE_AMPLITUDE, "omega": WAVE_OMEGA, "duration": WAVE_DURATION},
        "ring_duration": RING_DURATION,
        "rings": rings,
        "waves": waves,
    }
    out = os.path.join(REPO, "tests", "fixtures", "stepper_rotor.json")
    with open(out, "w") as f:
        json.dump(fixture, f, indent=1)
        f.write("\n")
    for c in rings:
        print(f"{c['name']:14} ring   zeta {c['zeta']:.4f}  {c['ring_rad_s']:.0f} rad/s")
    for c in waves:
        print(f"{c['name']:14} wave   f_c {c['driver_bandwidth']:6.0f}  b_r {c['rotor_damping']:.0e}  "
              f"T_c {c['reducer_friction']:.4f}  slips {c['slips_at']}  lost {c['steps_lost']}  "
              f"lag {c['max_lag_steps']:.2f}")
    print("wrote", os.path.relpath(out, REPO))


if __name__ == "__main__":
    main()
