#!/usr/bin/env python3
"""Writes tests/fixtures/mimic_gripper_arm.json: Pinocchio 4 on tests/urdf/mimic_gripper_arm.urdf.

    tools/oracle/.venv/bin/python tools/oracle/mimic_fixtures.py

Drake has no equivalent of URDF mimic joints in reduced coordinates, so the oracle is Pinocchio 4's
`buildModelFromUrdf(path, mimic=True)` (pin_closed_loop.py's PinArm), in faze4's coordinates
(shoulder_yaw, shoulder_pitch, elbow, finger_left; wrist_follow and finger_right follow). The
fixture holds

  * "coordinates", "lower", "upper", "damping": the leaders, their limits (each intersected with its
    followers' mapped through q_f = m q_l + o) and damping (G^T diag(d) G);
  * "states": 8 seeded random states (q within the limits, v, a) with M (crba, symmetrised), g
    (computeGeneralizedGravity), bias = C v + g (rnea(q, v, 0)), tau = rnea(q, v, a), the world
    pose (4x4) of every frame that is a link, and the tool_link's Jacobian (6 x n, rows angular then
    linear, world-aligned: faze4's order);
  * "closed_loop": pin_closed_loop.py's wave, --center mid, 1 deg (so 0.01745 m for the finger),
    4 s at dt 2e-4, gains tuned as drake_closed_loop.py tunes them (faze4's rule) from the URDF's
    effort limits: args, summary and trail.

Before writing it checks Pinocchio against itself: at every state its mimic model's M, g, bias and
tau equal G^T (.) G / G^T (.) of its model without mimic at (G q + o, G v, G a), every frame
pose equals the latter's and the tool Jacobian equals J G, to 1e-12. (Pinocchio 4.1.0's crba on a mimic model is wrong when called
again on the same Data; PinArm uses a fresh one, and this check would catch a relapse.)
Deterministic: a fixed seed; the same pin/numpy versions write the same bytes.
"""

import importlib.metadata
import math
import os
import sys

import numpy as np
import pinocchio as pin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pin_closed_loop as pcl  # noqa: E402
from closed_loop_fixtures import dump_fixture  # noqa: E402

REPO = pcl.REPO_ROOT
URDF_REL = "tests/urdf/mimic_gripper_arm.urdf"
OUT_REL = "tests/fixtures/mimic_gripper_arm.json"
TOOL = "tool_link"
WAVE = dict(amp_deg=1.0, freq=0.5, center="mid")
RUN = dict(duration=4.0, dt=2e-4, record_period=0.02)
TOL = 1e-12


def link_names(urdf):
    import xml.etree.ElementTree as ET
    return [link.get("name") for link in ET.parse(urdf).getroot().findall("link")]


def jacobian(arm, q, frame):
    """6 x n, rows angular then linear, world-aligned at the frame origin, faze4's column order."""
    model, data = arm.model, arm.model.createData()
    pq = arm.pin_q(q)
    pin.computeJointJacobians(model, data, pq)
    pin.updateFramePlacements(model, data)
    J = pin.getFrameJacobian(model, data, model.getFrameId(frame), pin.LOCAL_WORLD_ALIGNED)
    J = np.vstack([J[3:], J[:3]])
    return J[:, arm.perm]


def check_against_unreduced(arm, full, q, v, a, links):
    G, o = arm.urdf.G, arm.urdf.offset
    # the bodies in faze4's order -> the unreduced model's coordinates
    assert [j.name for j in full.urdf.coords] == [j.name for j in arm.urdf.joints]
    qb, vb, ab = G @ q + o, G @ v, G @ a
    M, cv, g = arm.terms(q, v)
    Mb, cvb, gb = full.terms(qb, vb)
    worst = max(np.abs(M - G.T @ Mb @ G).max(), np.abs(g - G.T @ gb).max(),
                np.abs(cv - G.T @ cvb).max(),
                np.abs(arm.rnea(q, v, a) - G.T @ full.rnea(qb, vb, ab)).max())
    poses, poses_b = arm.frame_poses(q), full.frame_poses(qb)
    worst = max(worst, max(np.abs(poses[n] - poses_b[n]).max() for n in links))
    worst = max(worst, np.abs(jacobian(arm, q, TOOL) - jacobian(full, qb, TOOL) @ G).max())
    assert worst <= TOL, worst
    return worst


def main():
    urdf = os.path.join(REPO, URDF_REL)
    arm = pcl.PinArm(urdf, mimic=True)
    full = pcl.PinArm(urdf, mimic=False)
    links = link_names(urdf)
    n = len(arm.urdf.coords)
    rng = np.random.default_rng(20261125)
    states, worst = [], 0.0
    for _ in range(8):
        q = rng.uniform(arm.urdf.lower, arm.urdf.upper)
        v = rng.uniform(-1.0, 1.0, n)
        a = rng.uniform(-2.0, 2.0, n)
        worst = max(worst, check_against_unreduced(arm, full, q, v, a, links))
        M, cv, g = arm.terms(q, v)
        poses = arm.frame_poses(q)
        states.append({
            "q": q.tolist(), "v": v.tolist(), "a": a.tolist(),
            "m": M.tolist(), "g": g.tolist(), "bias": (cv + g).tolist(),
            "tau": arm.rnea(q, v, a).tolist(),
            "frames": {name: poses[name].tolist() for name in links},
            "tool_jacobian": jacobian(arm, q, TOOL).tolist(),
        })
    print(f"[check] mimic model vs G^T (model without mimic) G over {len(states)} states: {worst:.3g}")

    A, c = pcl.wave_setup(arm, WAVE["amp_deg"], center=WAVE["center"])
    command = pcl.wave_command(A, c, WAVE["freq"])
    effort = arm.urdf.effort
    _, kp, kd = pcl.auto_tune(arm, command(0.0)[0], RUN["dt"], effort)
    margin = [math.inf]

    def hook(k, q, v, tau_raw, tau):
        margin[0] = min(margin[0], float(np.min(np.abs(np.abs(tau_raw) - effort))))

    summary, trail = pcl.run_closed_loop(arm, command, kp, kd, effort, duration=RUN["duration"],
                                         dt=RUN["dt"], record_period=RUN["record_period"], tool=TOOL,
                                         verbose=False, step_hook=hook)
    assert summary["diverged"] is None
    assert margin[0] >= 1e-6, margin[0]
    summary.pop("wall_time_s")

    fixture = {
        "generator": "tools/oracle/mimic_fixtures.py",
        "pin_version": importlib.metadata.version("pin"),
        "urdf": URDF_REL,
        "coordinates": arm.urdf.names(),
        "lower": arm.urdf.lower.tolist(),
        "upper": arm.urdf.upper.tolist(),
        "damping": np.diag(arm.urdf.damping).tolist(),
        "states": states,
        "closed_loop": {
            "args": {**WAVE, **RUN, "tool_link": TOOL},
            "center": c.tolist(),
            "summary": summary,
            "trail": {"columns": pcl.trail_columns(n), "rows": trail.tolist()},
        },
    }
    path = os.path.join(REPO, OUT_REL)
    dump_fixture(path, fixture)
    print(f"[write] {OUT_REL}: {len(states)} states, {len(trail)} trail rows, "
          f"max err {pcl.dcl._fmt(summary['max_tracking_error_rad'], '{:.3g}')}")


if __name__ == "__main__":
    main()
