#!/usr/bin/env python3
"""Pinocchio reference of faze4's closed-loop `wave` (docs/model.md), in reduced coordinates.

Drake is faze4's oracle wherever it has an equivalent; this script is the oracle where it has not:
mimic joints (`<mimic joint multiplier offset>`, Pinocchio 4's `buildModelFromUrdf(path, mimic=True)`,
where a follower is no degree of freedom) and any URDF run with faze4's own gains. It integrates
the discrete step of docs/model.md §2.3 in numpy from Pinocchio's M, C v and g, with faze4's
controller, and records the trail as faze4 does. `drake_closed_loop.py` is the same experiment on
Drake's plant; this file mirrors its structure and its summary and trail formats.

Usage (from the repository root, with the oracle venv; see tools/oracle/README.md):

    python tools/oracle/pin_closed_loop.py --urdf F.urdf --gains faze4_summary.json [--mimic]
        [--center mid | --center c1,c2,...] [--amp-deg 25] [--amp-m A] [--amplitude a1,a2,...]
        [--freq 0.5] [--duration 8] [--dt 2e-4] [--record-period 0.02] [--tool-link L]
        [--no-ff] [--no-gravity] [--trail F.csv] [--summary F.json] [--quiet]

Exact definitions (the Rust side implements the same):

* Coordinates: faze4's. The moving joints in faze4's order (depth-first from the root link,
  children in document order, docs/model.md 1.3); with --mimic a joint carrying `<mimic>` is not
  a coordinate: q_f = m q_l + o, v_f = m v_l (multiplier m defaults to 1, offset o to 0). q[i] is
  an angle (rad) or a length (m); a continuous joint's angle is mapped to Pinocchio's (cos, sin).
* Terms from Pinocchio, in reduced coordinates: M = crba (symmetrised) plus the motors' reflected
  inertia, g = computeGeneralizedGravity, C v = rnea(q, v, 0) - g. A `<transmission>` with
  drake:rotor_inertia I and drake:gear_ratio r on joint j adds r^2 I to M_jj; on a follower it adds
  m^2 r^2 I to its leader's diagonal entry (G^T diag G). Damping D = G^T diag(d) G, diag(d) the
  URDF `<dynamics damping>` of every moving joint, followers included (Pinocchio itself keeps only
  the leaders' d; its dynamics do not use it).
* Step k = 0..steps-1, steps = round(duration/dt), t_k = k*dt (a product, never a running sum).
  (q_cmd, v_cmd) at t_k; tau_raw = kp*(q_cmd - q) + kd*(v_cmd - v) [+ g(q) unless --no-ff];
  tau = clip(tau_raw, -E, E) (E = inf where faze4's summary says null); joint i is saturated iff
  |tau_raw_i| >= E_i;  v+ = (M + dt D)^-1 [M v + dt (tau - C v - g)],  q+ = q + dt v+.
  No joint-limit constraint: the run stops with an error if a state leaves a coordinate's limits
  (faze4 then clamps, which this reference does not model). With --mimic the limits of a leader
  are its own intersected with each follower's mapped through q_f = m q_l + o.
* wave: q_i = c_i + A_i sin(w t + i pi/3), v_i = A_i w cos(w t + i pi/3), w = --freq in rad/s.
  A_i = radians(--amp-deg), or --amp-m for a prismatic coordinate when given, or --amplitude per
  coordinate. c = 0, or --center mid: the middle of each coordinate's limits (the lower or upper
  one where only one is finite, 0 where none), or a list. A faze4 summary that holds "center" or
  "amplitude" gives them unless the options do.
  The run starts at q = q_cmd(0), v = v_cmd(0).
* Gains: kp, kd, effort (and dt unless --dt) from a faze4 `--summary` JSON (--gains), so that the
  reference runs faze4's gains; without --gains, drake_closed_loop.py's tuning on Pinocchio's M
  (I_i = M_ii(q_start), kp = min(E/0.05, 0.4 I/dt^2), kd = min(1.6 sqrt(kp I), I/(2 dt))) with E
  from the URDF's effort limits.
* Metrics and trail exactly as drake_closed_loop.py: max_tracking_error_rad_i = max_k |e_k,i|,
  saturation_pct_i, a trail row after step counts 0, r, 2r, ... and after the final step, row =
  [t, x, y, z (the tool link's origin in world), q1..qn]; tool_range_m per axis over the rows.
"""

import argparse
import bisect
import json
import math
import os
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import drake_closed_loop as dcl  # noqa: E402

REPO_ROOT = dcl.REPO_ROOT
GRAVITY = dcl.GRAVITY
MOVING = ("revolute", "continuous", "prismatic")


# --------------------------------------------------------------------------------------------
# The URDF as faze4 reads it: joint order, mimic map, damping, limits, motors.
# --------------------------------------------------------------------------------------------

def _floats(text, default):
    return [float(x) for x in text.split()] if text else default


class UrdfJoint:
    def __init__(self, el):
        self.name = el.get("name")
        self.type = el.get("type")
        self.parent = el.find("parent").get("link")
        self.child = el.find("child").get("link")
        limit = el.find("limit")
        lower = upper = None
        effort = None
        if limit is not None:
            lower = float(limit.get("lower", "0")) if self.type != "continuous" else None
            upper = float(limit.get("upper", "0")) if self.type != "continuous" else None
            effort = float(limit.get("effort")) if limit.get("effort") is not None else None
        self.lower = -math.inf if lower is None else lower
        self.upper = math.inf if upper is None else upper
        self.effort = effort if effort and effort > 0 else None
        dyn = el.find("dynamics")
        self.damping = float(dyn.get("damping", "0")) if dyn is not None else 0.0
        mimic = el.find("mimic")
        self.mimic = None if mimic is None else (
            mimic.get("joint"), float(mimic.get("multiplier", "1")), float(mimic.get("offset", "0")))
        self.reflected = 0.0


class UrdfArm:
    """The URDF's moving joints in faze4's order and, with mimic, the map to the coordinates.

    joints: every moving joint (followers included), depth-first from the root link, children in
    document order. coords: the joints that are coordinates. For each moving joint j,
    coord_of[j] = (coordinate index, multiplier, offset)."""

    def __init__(self, path, mimic):
        root = ET.parse(path).getroot()
        self.name = root.get("name")
        by_parent = {}
        all_joints = [UrdfJoint(el) for el in root.findall("joint")]
        children = {j.child for j in all_joints}
        for j in all_joints:
            by_parent.setdefault(j.parent, []).append(j)
        roots = [link.get("name") for link in root.findall("link") if link.get("name") not in children]
        assert len(roots) == 1, f"{path}: {len(roots)} root links"
        ns = "{http://drake.mit.edu}"
        for tr in root.findall("transmission"):
            jel = tr.find("joint")
            act = tr.find("actuator")
            if jel is None or act is None:
                continue
            rotor = act.find(ns + "rotor_inertia")
            gear = act.find(ns + "gear_ratio")
            if rotor is None:
                rotor = tr.find(ns + "rotor_inertia")
            if gear is None:
                gear = tr.find(ns + "gear_ratio")
            i_r = float(rotor.get("value")) if rotor is not None else 0.0
            r = float(gear.get("value")) if gear is not None else 1.0
            for j in all_joints:
                if j.name == jel.get("name") and j.type in MOVING:
                    j.reflected = r * r * i_r
        self.joints = []

        def walk(link):
            for j in by_parent.get(link, []):
                if j.type in MOVING:
                    self.joints.append(j)
                walk(j.child)

        walk(roots[0])
        by_name = {j.name: j for j in self.joints}
        self.coords = [j for j in self.joints if not (mimic and j.mimic)]
        index = {j.name: i for i, j in enumerate(self.coords)}
        self.coord_of = []
        for j in self.joints:
            if mimic and j.mimic:
                leader, m, o = j.mimic
                assert leader in index, f"{j.name} mimics {leader}, which is not a coordinate"
                self.coord_of.append((index[leader], m, o))
            else:
                self.coord_of.append((index[j.name], 1.0, 0.0))
        n, nb = len(self.coords), len(self.joints)
        self.G = np.zeros((nb, n))
        self.offset = np.zeros(nb)
        for b, (i, m, o) in enumerate(self.coord_of):
            self.G[b, i] = m
            self.offset[b] = o
        self.damping = self.G.T @ np.diag([j.damping for j in self.joints]) @ self.G
        self.reflected = self.G.T @ np.diag([j.reflected for j in self.joints]) @ self.G
        self.lower = np.array([j.lower for j in self.coords])
        self.upper = np.array([j.upper for j in self.coords])
        for b, j in enumerate(self.joints):
            i, m, o = self.coord_of[b]
            if j is self.coords[i] or m == 0.0:
                continue
            lo, hi = (j.lower - o) / m, (j.upper - o) / m
            lo, hi = min(lo, hi), max(lo, hi)
            self.lower[i] = max(self.lower[i], lo)
            self.upper[i] = min(self.upper[i], hi)
        self.effort = np.array([j.effort if j.effort else math.inf for j in self.coords])
        self.by_name = by_name

    def names(self):
        return [j.name for j in self.coords]

    def center_mid(self):
        c = []
        for lo, hi in zip(self.lower, self.upper):
            if math.isfinite(lo) and math.isfinite(hi):
                c.append(0.5 * (lo + hi))
            elif math.isfinite(lo):
                c.append(lo)
            elif math.isfinite(hi):
                c.append(hi)
            else:
                c.append(0.0)
        return np.array(c)


# --------------------------------------------------------------------------------------------
# Pinocchio in faze4's coordinates.
# --------------------------------------------------------------------------------------------

class PinArm:
    """Pinocchio's model of a URDF, evaluated at faze4's (reduced) q and v."""

    def __init__(self, urdf, mimic=False, gravity=True):
        self.urdf = UrdfArm(urdf, mimic)
        self.model = pin.buildModelFromUrdf(urdf, mimic=mimic)
        if not gravity:
            self.model.gravity.linear = np.zeros(3)
        else:
            self.model.gravity.linear = np.array([0.0, 0.0, -GRAVITY])
        self.data = self.model.createData()
        n = len(self.urdf.coords)
        assert self.model.nv == n, f"Pinocchio has {self.model.nv} velocities, faze4 {n} coordinates"
        # faze4 coordinate i -> Pinocchio joint (idx_q, nq, idx_v)
        self.slots = []
        for j in self.urdf.coords:
            jid = self.model.getJointId(j.name)
            jm = self.model.joints[jid]
            self.slots.append((jm.idx_q, jm.nq, jm.idx_v))
        self.perm = np.array([s[2] for s in self.slots])  # pin velocity index of coordinate i

    def pin_q(self, q):
        out = pin.neutral(self.model)
        for (iq, nq, _), x in zip(self.slots, q):
            if nq == 1:
                out[iq] = x
            else:  # continuous joint: (cos, sin)
                out[iq], out[iq + 1] = math.cos(x), math.sin(x)
        return out

    def pin_v(self, v):
        out = np.zeros(self.model.nv)
        out[self.perm] = v
        return out

    def ours(self, x):
        """A Pinocchio velocity-space vector in faze4's order."""
        return np.asarray(x)[self.perm]

    def terms(self, q, v):
        """(M with the motors' reflected inertia, C v, g) in faze4's order."""
        pq, pv = self.pin_q(q), self.pin_v(v)
        # a fresh Data: Pinocchio 4.1.0's crba on a model with mimic joints gives a different
        # (wrong) M when called again on the same Data (the first call equals G^T M G of the
        # model without mimic, which pin_fixtures.py checks)
        M = pin.crba(self.model, self.model.createData(), pq)
        M = np.triu(M) + np.triu(M, 1).T
        M = M[np.ix_(self.perm, self.perm)] + self.urdf.reflected
        g = self.ours(pin.computeGeneralizedGravity(self.model, self.data, pq))
        cv = self.ours(pin.rnea(self.model, self.data, pq, pv, np.zeros(self.model.nv))) - g
        return M, cv, g

    def gravity(self, q):
        return self.ours(pin.computeGeneralizedGravity(self.model, self.data, self.pin_q(q)))

    def rnea(self, q, v, a):
        """tau = M a + C v + g, reflected inertia included (as faze4's rnea)."""
        tau = pin.rnea(self.model, self.data, self.pin_q(q), self.pin_v(v), self.pin_v(a))
        return self.ours(tau) + self.urdf.reflected @ np.asarray(a)

    def frame_position(self, q, frame):
        pin.framesForwardKinematics(self.model, self.data, self.pin_q(q))
        return self.data.oMf[self.model.getFrameId(frame)].translation.copy()

    def frame_poses(self, q):
        """{frame name: 4x4 world pose} of every frame (links and joints) at q."""
        pin.framesForwardKinematics(self.model, self.data, self.pin_q(q))
        return {f.name: self.data.oMf[i].homogeneous.copy() for i, f in enumerate(self.model.frames)}

    def step(self, q, v, tau, dt):
        M, cv, g = self.terms(q, v)
        v_next = np.linalg.solve(M + dt * self.urdf.damping, M @ v + dt * (tau - cv - g))
        return q + dt * v_next, v_next


# --------------------------------------------------------------------------------------------
# The command and the loop.
# --------------------------------------------------------------------------------------------

def wave_command(amplitude, center, freq=0.5):
    """q_i = c_i + A_i sin(w t + i pi/3); w in rad/s."""
    A = np.asarray(amplitude, dtype=float)
    c = np.asarray(center, dtype=float)
    w = float(freq)
    phase = np.arange(len(c)) * (math.pi / 3.0)

    def command(t):
        arg = w * t + phase
        return c + A * np.sin(arg), A * w * np.cos(arg)

    return command


def spline_command(times, q, v=None, a=None):
    """A time-stamped trajectory played as joint_trajectory_controller plays it, exactly as
    faze4's src/traj/spline.rs does (the same coefficients of `interpolate_between_points`, the
    same order of floating-point operations): times shifted so the first is 0; segment i for
    t_i <= t < t_i+1, tau = t - t_i; linear with positions only (v the slope, a = 0), cubic
    Hermite with velocities, quintic Hermite with velocities and accelerations; from the last
    time on, the last positions with zero velocity and acceleration. times: N, q (and v, a):
    N x n in faze4's joint order. Returns command(t) -> (q, v, a)."""
    q = np.asarray(q, dtype=float)
    n_points, n = q.shape
    times = [float(x) for x in times]
    t0 = times[0]
    times = [t - t0 for t in times]
    kind = "linear" if v is None else ("cubic" if a is None else "quintic")
    v = None if v is None else np.asarray(v, dtype=float)
    a = None if a is None else np.asarray(a, dtype=float)
    coefficients = []
    for i in range(n_points - 1):
        T = times[i + 1] - times[i]
        t = [1.0]
        for _ in range(5):
            t.append(t[-1] * T)
        sp, ep = q[i], q[i + 1]
        c = np.zeros((6, n))
        c[0] = sp
        if kind == "linear":
            c[1] = (ep - sp) / T
        elif kind == "cubic":
            sv, ev = v[i], v[i + 1]
            c[1] = sv
            c[2] = (-3.0 * sp + 3.0 * ep - 2.0 * sv * t[1] - ev * t[1]) / t[2]
            c[3] = (2.0 * sp - 2.0 * ep + sv * t[1] + ev * t[1]) / t[3]
        else:
            sv, ev, sa, ea = v[i], v[i + 1], a[i], a[i + 1]
            c[1] = sv
            c[2] = 0.5 * sa
            c[3] = (-20.0 * sp + 20.0 * ep - 3.0 * sa * t[2] + ea * t[2] - 12.0 * sv * t[1]
                    - 8.0 * ev * t[1]) / (2.0 * t[3])
            c[4] = (30.0 * sp - 30.0 * ep + 3.0 * sa * t[2] - 2.0 * ea * t[2] + 16.0 * sv * t[1]
                    + 14.0 * ev * t[1]) / (2.0 * t[4])
            c[5] = (-12.0 * sp + 12.0 * ep - sa * t[2] + ea * t[2] - 6.0 * sv * t[1]
                    - 6.0 * ev * t[1]) / (2.0 * t[5])
        coefficients.append(c)
    last, end = q[-1].copy(), times[-1]
    zeros = np.zeros(n)

    def command(time):
        if time >= end:
            return last.copy(), zeros.copy(), zeros.copy()
        i = max(bisect.bisect_right(times, time) - 1, 0)
        tau = time - times[i]
        p1 = 1.0 * tau
        p2 = p1 * tau
        p3 = p2 * tau
        p4 = p3 * tau
        c = coefficients[i]
        if kind == "linear":
            return 1.0 * c[0] + p1 * c[1], 1.0 * c[1], zeros.copy()
        if kind == "cubic":
            return (1.0 * c[0] + p1 * c[1] + p2 * c[2] + p3 * c[3],
                    1.0 * c[1] + p1 * 2.0 * c[2] + p2 * 3.0 * c[3],
                    1.0 * 2.0 * c[2] + p1 * 6.0 * c[3])
        return (1.0 * c[0] + p1 * c[1] + p2 * c[2] + p3 * c[3] + p4 * c[4] + p4 * tau * c[5],
                1.0 * c[1] + p1 * 2.0 * c[2] + p2 * 3.0 * c[3] + p3 * 4.0 * c[4] + p4 * 5.0 * c[5],
                1.0 * 2.0 * c[2] + p1 * 6.0 * c[3] + p2 * 12.0 * c[4] + p3 * 20.0 * c[5])

    command.kind = kind
    command.duration = end
    return command


def fill_cubic_spline_velocities(times, q):
    """ros2_controllers' fill_cubic_spline_velocities (joint_trajectory_controller/src/
    trajectory.cpp, what `positions_upsampling` gives positions-only points): per joint the knot
    velocities of the global cubic spline through q at `times`, at rest at both ends, by the
    Thomas algorithm in the controller's order of operations. q: N x n; returns N x n."""
    q = np.asarray(q, dtype=float)
    n, joints = q.shape
    out = np.zeros((n, joints))
    if n < 2:
        return out
    for j in range(joints):
        lower, diagonal, upper, rhs = [0.0] * n, [0.0] * n, [0.0] * n, [0.0] * n
        diagonal[0], upper[0], rhs[0] = 1.0, 0.0, 0.0
        lower[n - 1], diagonal[n - 1], rhs[n - 1] = 0.0, 1.0, 0.0
        for i in range(1, n - 1):
            before, after = times[i] - times[i - 1], times[i + 1] - times[i]
            lower[i] = 1.0 / before
            diagonal[i] = 2.0 * (1.0 / before + 1.0 / after)
            upper[i] = 1.0 / after
            rhs[i] = 3.0 * ((q[i + 1, j] - q[i, j]) / (after * after) + (q[i, j] - q[i - 1, j]) / (before * before))
        sweep, v = [0.0] * n, [0.0] * n
        sweep[0] = upper[0] / diagonal[0]
        v[0] = rhs[0] / diagonal[0]
        for i in range(1, n):
            pivot = diagonal[i] - lower[i] * sweep[i - 1]
            sweep[i] = upper[i] / pivot if i + 1 < n else 0.0
            v[i] = (rhs[i] - lower[i] * v[i - 1]) / pivot
        for i in range(n - 2, -1, -1):
            v[i] -= sweep[i] * v[i + 1]
        out[:, j] = v
    return out


def played_command(times, q, v=None, a=None, start=None, interpolation=None):
    """A message as joint_trajectory_controller plays it when it receives it at t = 0 with the
    arm at rest at `start` (trajectory.cpp: `set_point_before_trajectory_msg` with the arm's
    state, zero velocities and accelerations where the first point gives them; `sample` before
    the first point's time interpolates from that state to it): `interpolation` forces the rule
    ("linear" leaves out v and a, "cubic" leaves out a and fills v by
    fill_cubic_spline_velocities where the points give none), `start` defaults to the first
    point's positions, a first time > 0 is reached from the start over that time. Returns
    (command, start state): the state the arm starts in, at rest at the start when there is an
    approach or a start given, else None (the command's own at t = 0)."""
    times = [float(t) for t in times]
    q = np.asarray(q, dtype=float)
    if interpolation == "linear":
        v = a = None
    elif interpolation == "cubic":
        a = None
        if v is None:
            v = fill_cubic_spline_velocities(times, q)
    elif interpolation == "quintic":
        assert v is not None and a is not None, "quintic needs the points' accelerations"
    given = start is not None
    start = q[0].copy() if start is None else np.asarray(start, dtype=float)
    if times[0] > 0.0:
        times = [0.0] + times
        q = np.vstack([start, q])
        v = None if v is None else np.vstack([np.zeros(q.shape[1]), v])
        a = None if a is None else np.vstack([np.zeros(q.shape[1]), a])
        at_rest = True
    else:
        at_rest = given
    command = spline_command(times, q, v, a)  # one point: held from t = 0
    state = (start.copy(), np.zeros(q.shape[1])) if at_rest else None
    return command, state


def auto_tune(arm, q_start, dt, effort):
    M, _, _ = arm.terms(q_start, np.zeros(len(q_start)))
    inertia = np.diag(M).copy()
    kp = np.minimum(effort / 0.05, 0.4 * inertia / dt**2)
    kd = np.minimum(1.6 * np.sqrt(kp * inertia), inertia / (2.0 * dt))
    return inertia, kp, kd


# --------------------------------------------------------------------------------------------
# --motors F.toml: the torque-speed envelopes of docs/motors.md, as faze4 applies them.
# --------------------------------------------------------------------------------------------

def _clamp(x, lo, hi):
    """Rust's f64::clamp: lo if x < lo, hi if x > hi, else x."""
    return lo if x < lo else (hi if x > hi else x)


class Motor:
    """One [[joint]] of a motors file: ratio r, efficiency eta, rotor inertia, and its envelope at
    the shaft (dc: stall torque, no-load speed, peak; stepper: the pull-out curve)."""

    def __init__(self, entry):
        self.kind = entry["kind"]
        self.ratio = entry.get("gear_ratio")
        self.rotor = entry.get("rotor_inertia")
        self.efficiency = entry.get("efficiency", 1.0)
        if self.kind == "dc":
            self.stall = entry["stall_torque"]
            self.no_load = entry["no_load_speed"]
            self.peak = entry.get("peak_torque", self.stall)
        else:
            self.curve = [(float(w), float(t)) for w, t in entry["curve"]]

    def bounds(self, omega):
        """Motor torque [lo, hi] at shaft speed omega."""
        if self.kind == "dc":
            back = omega / self.no_load
            return (_clamp(self.stall * (-1.0 - back), -self.peak, self.peak),
                    _clamp(self.stall * (1.0 - back), -self.peak, self.peak))
        t = self.pull_out(abs(omega))
        return -t, t

    def pull_out(self, w):
        c = self.curve
        if w > c[-1][0]:
            return 0.0
        if w <= c[0][0]:
            return c[0][1]
        for (w0, t0), (w1, t1) in zip(c, c[1:]):
            if w == w1:
                return t1
            if w < w1:
                return t0 + (t1 - t0) * (w - w0) / (w1 - w0)
        return c[-1][1]

    def max_torque(self):
        return self.peak if self.kind == "dc" else max(t for _, t in self.curve)


def read_motors(path, urdf):
    """[Motor or None] per coordinate from a motors TOML (by name, or one per coordinate in order);
    each motor's ratio and rotor replace the joint's, and its reflected inertia r^2 I goes on M."""
    import tomllib
    with open(path, "rb") as f:
        entries = tomllib.load(f)["joint"]
    names = [j.name for j in urdf.coords]
    motors = [None] * len(names)
    if all("name" in e for e in entries):
        for e in entries:
            motors[names.index(e["name"])] = Motor(e)
    else:
        assert len(entries) == len(names), (len(entries), names)
        motors = [Motor(e) for e in entries]
    ratios = np.ones(len(names))
    for i, (m, j) in enumerate(zip(motors, urdf.coords)):
        if m is None:
            continue
        r = m.ratio if m.ratio is not None else 1.0
        ratios[i] = r
        if m.rotor is not None:
            urdf.reflected[i, i] = r * r * m.rotor
    return motors, ratios


def envelope_of(motors, ratios, effort):
    """The actuation of docs/motors.md: tau_i = min(max(tau_raw_i, lo_i), hi_i) with
    [lo_i, hi_i] = [r eta lo_m, r eta hi_m](r v_i) intersected with [-E_i, E_i]."""
    def bounds(v):
        lo, hi = -np.asarray(effort, dtype=float), np.asarray(effort, dtype=float)
        lo, hi = lo.copy(), hi.copy()
        for i, m in enumerate(motors):
            if m is None:
                continue
            k = ratios[i] * m.efficiency
            l, h = m.bounds(ratios[i] * v[i])
            lo[i], hi[i] = max(k * l, -effort[i]), min(k * h, effort[i])
        return lo, hi
    return bounds


def run_closed_loop(arm, command, kp, kd, effort, duration=8.0, dt=2e-4, feed_forward=True,
                    record_period=0.02, tool="tool_link", verbose=True, step_hook=None,
                    envelope=None, start_state=None):
    """Run the closed loop on a PinArm; returns (summary dict, trail ndarray). The arm starts in
    `start_state` (q, v) when given, else in the command's state at t = 0.

    feed_forward: True or "gravity" adds g(q) at the measured q; "full" adds the inverse
    dynamics of the command, rnea(q_cmd, v_cmd, a_cmd) with the motors' reflected inertia (faze4's
    --ff full), the command then returning (q, v, a); False or "none" adds nothing."""
    kp, kd = np.asarray(kp, dtype=float), np.asarray(kd, dtype=float)
    effort = np.asarray(effort, dtype=float)
    dof = len(kp)
    full = feed_forward == "full"
    gravity_ff = feed_forward is True or feed_forward == "gravity"
    q, v = command(0.0)[:2] if start_state is None else (np.array(start_state[0]), np.array(start_state[1]))
    M0, _, _ = arm.terms(q, np.zeros(dof))
    inertia = np.diag(M0).copy()
    steps = int(round(duration / dt))
    r = max(1, int(round(record_period / dt)))
    max_err = np.zeros(dof)
    sat_steps = np.zeros(dof, dtype=np.int64)
    env_steps = np.zeros(dof, dtype=np.int64)
    trail = []
    diverged = None
    lo, hi = arm.urdf.lower, arm.urdf.upper

    def record(count, q):
        trail.append([count * dt, *arm.frame_position(q, tool), *q])

    wall0 = time.perf_counter()
    record(0, q)
    done = 0
    for k in range(steps):
        cmd = command(k * dt)
        q_cmd, v_cmd = cmd[0], cmd[1]
        err = q_cmd - q
        tau_raw = kp * err + kd * (v_cmd - v)
        if full:
            tau_raw = tau_raw + arm.rnea(q_cmd, v_cmd, cmd[2])
        elif gravity_ff:
            tau_raw = tau_raw + arm.gravity(q)
        if envelope is None:
            tau = np.clip(tau_raw, -effort, effort)
        else:
            t_lo, t_hi = envelope(v)
            tau = np.minimum(np.maximum(tau_raw, t_lo), t_hi)
            env_steps += (tau_raw > t_hi) | (tau_raw < t_lo)
        np.maximum(max_err, np.abs(err), out=max_err)
        sat_steps += np.abs(tau_raw) >= effort
        if step_hook is not None:
            step_hook(k, q, v, tau_raw, tau)
        q, v = arm.step(q, v, tau, dt)
        done = k + 1
        bad = ~(np.isfinite(q) & np.isfinite(v))
        if bad.any():
            diverged = {"t": done * dt, "joint": int(np.argmax(bad)) + 1,
                        "stiffness_b": (dt**2 * kp / inertia).tolist()}
            break
        out = (q < lo) | (q > hi)
        if out.any():
            raise RuntimeError(f"J{int(np.argmax(out)) + 1} leaves its limits at t={done * dt:.4f} s; "
                               "faze4 clamps there, which this reference does not model")
        if done % r == 0 or done == steps:
            record(done, q)
    wall = time.perf_counter() - wall0
    trail = np.array(trail)
    summary = {
        "dof": dof,
        "dt": dt,
        "steps": steps,
        "effective_inertia": inertia.tolist(),
        "kp": kp.tolist(),
        "kd": kd.tolist(),
        "effort": [None if not math.isfinite(e) else e for e in effort.tolist()],
        "max_tracking_error_rad": max_err.tolist(),
        "saturation_pct": (100.0 * sat_steps / max(done, 1)).tolist(),
        "tool_range_m": {ax: [float(np.min(trail[:, c])), float(np.max(trail[:, c]))]
                         for ax, c in (("x", 1), ("y", 2), ("z", 3))},
        "diverged": diverged,
        "wall_time_s": wall,
        "envelope_pct": (100.0 * env_steps / max(done, 1)).tolist() if envelope else None,
    }
    if verbose:
        rng = summary["tool_range_m"]
        print(f"[pin] {arm.urdf.name}: {dof} coordinates {arm.urdf.names()}, tool {tool}, dt {dt:g} s")
        print(f"[summary] max tracking error: {dcl._fmt(max_err, '{:.3g}')}")
        print(f"[summary] saturation (%): {dcl._fmt(summary['saturation_pct'], '{:.2f}')}")
        print(f"[summary] tool range (m): x[{rng['x'][0]:.3f}, {rng['x'][1]:.3f}] "
              f"y[{rng['y'][0]:.3f}, {rng['y'][1]:.3f}] z[{rng['z'][0]:.3f}, {rng['z'][1]:.3f}]")
        print(f"[summary] {done} steps, loop wall time {wall:.2f} s")
    return summary, trail


def trail_columns(dof):
    return ["t", "x", "y", "z"] + [f"q{i + 1}" for i in range(dof)]


def _list(text):
    return [float(x) for x in text.split(",")]


def wave_setup(arm, amp_deg=25.0, amp_m=None, amplitude=None, center=None, gains=None):
    """(amplitude, center) per coordinate from the options and a faze4 summary (see the docstring)."""
    n = len(arm.urdf.coords)
    gains = gains or {}
    if amplitude is not None:
        A = np.asarray(amplitude, dtype=float)
    elif "amplitude" in gains and amp_m is None:
        A = np.asarray(gains["amplitude"], dtype=float)
    else:
        A = np.full(n, math.radians(amp_deg))
        if amp_m is not None:
            A = np.array([amp_m if j.type == "prismatic" else a for j, a in zip(arm.urdf.coords, A)])
    if center == "mid":
        c = arm.urdf.center_mid()
    elif center is not None:
        c = np.asarray(_list(center) if isinstance(center, str) else center, dtype=float)
    elif "center" in gains:
        c = np.asarray(gains["center"], dtype=float)
    else:
        c = np.zeros(n)
    assert len(A) == n and len(c) == n, (A, c, n)
    return A, c


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--urdf", required=True)
    ap.add_argument("--mimic", action="store_true", help="mimic joints are not coordinates")
    ap.add_argument("--gains", metavar="F.json", help="faze4 --summary JSON: kp, kd, effort, dt")
    ap.add_argument("--center", help="'mid' or c1,c2,... (0)")
    ap.add_argument("--amp-deg", type=float, default=25.0, help="amplitude, degrees (25)")
    ap.add_argument("--amp-m", type=float, help="amplitude of prismatic coordinates, m")
    ap.add_argument("--amplitude", help="a1,a2,... per coordinate (rad or m)")
    ap.add_argument("--freq", type=float, default=0.5, help="rad/s (0.5)")
    ap.add_argument("--duration", type=float, default=8.0)
    ap.add_argument("--dt", type=float, help="s (the summary's, else 2e-4)")
    ap.add_argument("--record-period", type=float, default=0.02)
    ap.add_argument("--tool-link", help="traced frame (tool_link, else the summary's tool_link)")
    ap.add_argument("--no-ff", action="store_true")
    ap.add_argument("--no-gravity", action="store_true")
    ap.add_argument("--trail", metavar="F.csv")
    ap.add_argument("--summary", metavar="F.json")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--motors", metavar="F.toml", help="torque-speed envelopes (docs/motors.md)")
    args = ap.parse_args(argv)

    arm = PinArm(args.urdf, mimic=args.mimic, gravity=not args.no_gravity)
    gains = json.load(open(args.gains)) if args.gains else None
    A, c = wave_setup(arm, args.amp_deg, args.amp_m,
                      _list(args.amplitude) if args.amplitude else None, args.center, gains)
    command = wave_command(A, c, args.freq)
    dt = args.dt or (gains["dt"] if gains else 2e-4)
    if gains:
        kp, kd = gains["kp"], gains["kd"]
        effort = [math.inf if e is None else e for e in gains["effort"]]
    else:
        effort = arm.urdf.effort
        _, kp, kd = auto_tune(arm, command(0.0)[0], dt, effort)
    tool = args.tool_link or (gains or {}).get("tool_link") or "tool_link"
    envelope = None
    if args.motors:
        motors, ratios = read_motors(args.motors, arm.urdf)
        if not gains:
            effort = [ratios[i] * m.efficiency * m.max_torque() if m else e
                      for i, (m, e) in enumerate(zip(motors, effort))]
            _, kp, kd = auto_tune(arm, command(0.0)[0], dt, np.asarray(effort))
        envelope = envelope_of(motors, ratios, np.asarray(effort, dtype=float))
    summary, trail = run_closed_loop(arm, command, kp, kd, effort, duration=args.duration, dt=dt,
                                     feed_forward=not args.no_ff, record_period=args.record_period,
                                     tool=tool, verbose=not args.quiet, envelope=envelope)
    if args.trail:
        with open(args.trail, "w") as f:
            f.write(",".join(trail_columns(summary["dof"])) + "\n")
            for row in trail:
                f.write(",".join(repr(float(x)) for x in row) + "\n")
    if args.summary:
        with open(args.summary, "w") as f:
            json.dump(summary, f, indent=1)
    if args.quiet:
        print(json.dumps(summary))
    return 1 if summary["diverged"] else 0


if __name__ == "__main__":
    sys.exit(main())
