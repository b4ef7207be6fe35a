#!/usr/bin/env python3
"""Writes tests/fixtures/mjcf_*.json: MuJoCo (the `mujoco` package) on MJCF models faze4 reads.

    tools/oracle/.venv/bin/python tools/oracle/mjcf_fixtures.py --so-arm100 DIR

DIR is a checkout of TheRobotStudio/SO-ARM100 (its Simulation/SO101/assets hold the SO-101's STL
meshes, which MuJoCo reads; they are not committed, tests/mjcf/README.md says why). The models:

  * tests/mjcf/so101/so101_new_calib.xml (TheRobotStudio's SO-101, unmodified) with its meshes;
  * tests/mjcf/menagerie/ur5e.xml and panda.xml (MuJoCo Menagerie, unmodified): their OBJ/STL
    meshes are not here, so MuJoCo is handed a small tetrahedron for each mesh file (every body
    of these arms gives its <inertial>, so no mass comes from a mesh; said in the README);
  * tests/mjcf/feature_arm.xml (ours: every construct faze4 reads, meshes from tests/urdf);
  * tests/mjcf/friction_arm.xml (ours: frictionloss that sticks and slips).

For each: faze4's coordinates (MuJoCo's joints in order, less the joint1 of each <equality joint>,
which follows its joint2: q1 = ref1 + c0 + c1 (q2 - ref2)), their limits, damping G^T diag(d) G,
effort limits (each joint actuator's |gear| x force limit: min(-lo, hi) of a forcerange that
spans 0, else a motor's or fixed-gain general's ctrlrange x gain; summed per joint, bounded by
the joint's actuatorfrcrange), the home keyframe; and at 8 seeded random states (q uniform in
the limits, [-pi, pi] where unlimited; v uniform in [-1, 1]) M = G^T qM G (mj_fullM, armature
included) and bias = G^T qfrc_bias (C v + g), g = bias at v = 0.

Closed loop: pin_closed_loop.py's run_closed_loop on MjArm (MuJoCo's M, C v, g in faze4's
coordinates; the discrete step of docs/model.md; damping from MuJoCo's dof_damping; frictionloss as
faze4's joint Coulomb friction, the clamped stopping torque of docs/model.md 2.3) for the SO-101,
the feature arm and the friction arm: wave --center mid, 2 deg (the slides 2 mm), 2 s at dt 2e-4,
gains by faze4's tuning rule from the efforts above; `rounding_sensitivity`, how far the trail moves
when M changes by one rounding. For the SO-101 and the friction arm also `mujoco_step`: the same
loop on MuJoCo's own mj_step (frictionloss solved by its constraint solver), as the file writes it
and made hard, with the differences to docs/model.md's step that explain tests/it/mjcf.rs's tolerance.

Deterministic: fixed seeds; the same mujoco/numpy versions write the same bytes.
"""

import argparse
import importlib.metadata
import math
import os
import shutil
import subprocess
import sys
import tempfile

import mujoco
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pin_closed_loop as pcl  # noqa: E402
from closed_loop_fixtures import dump_fixture  # noqa: E402

REPO = pcl.REPO_ROOT
GRAVITY = pcl.GRAVITY
WAVE = dict(amp_deg=2.0, freq=0.5, center="mid")
RUN = dict(duration=2.0, dt=2e-4, record_period=0.02)
# (name, model file, tool frame for the closed loop or None)
MODELS = [
    ("so101", "tests/mjcf/so101/so101_new_calib.xml", "gripperframe"),
    ("ur5e", "tests/mjcf/menagerie/ur5e.xml", None),
    ("panda", "tests/mjcf/menagerie/panda.xml", None),
    ("feature_arm", "tests/mjcf/feature_arm.xml", "tool"),
    ("friction_arm", "tests/mjcf/friction_arm.xml", "tool"),
]
# the models whose closed loop is also run on MuJoCo's own step (mj_step: frictionloss solved as
# its soft constraint), with and without frictionloss
MUJOCO_STEP = ["so101", "friction_arm"]
# a closed tetrahedron, standing in for a mesh file that is not here
TETRA_OBJ = b"v 0 0 0\nv 0.01 0 0\nv 0 0.01 0\nv 0 0 0.01\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


class Coords:
    """faze4's coordinates of a compiled MuJoCo model: G (nv x n), o, and the joint map."""

    def __init__(self, m):
        self.m = m
        names = [m.joint(j).name for j in range(m.njnt)]
        for j in range(m.njnt):
            assert m.jnt_type[j] in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
        follow = {}
        for e in range(m.neq):
            if m.eq_type[e] == int(mujoco.mjtEq.mjEQ_JOINT) and m.eq_active0[e]:
                follow[m.eq_obj1id[e]] = (m.eq_obj2id[e], m.eq_data[e][:5].copy())
        self.leaders = [j for j in range(m.njnt) if j not in follow]
        self.joint_names = [names[j] for j in self.leaders]
        self.coords = [type("Joint", (), {"name": names[j], "type": "prismatic" if int(m.jnt_type[j]) ==
                                          mujoco.mjtJoint.mjJNT_SLIDE else "revolute"})
                       for j in self.leaders]
        n = len(self.leaders)
        self.G, self.o = np.zeros((m.nv, n)), np.zeros(m.nq)
        for c, j in enumerate(self.leaders):
            self.G[m.jnt_dofadr[j], c] = 1.0
        for f, (l, coef) in follow.items():
            assert not coef[2:].any() and l not in follow
            ref1, ref2 = m.qpos0[m.jnt_qposadr[f]], m.qpos0[m.jnt_qposadr[l]]
            self.G[m.jnt_dofadr[f], self.leaders.index(l)] = coef[1]
            self.o[m.jnt_qposadr[f]] = ref1 + coef[0] - coef[1] * ref2
        lo = np.full(n, -math.inf)
        hi = np.full(n, math.inf)
        for j in range(m.njnt):
            if not m.jnt_limited[j]:
                continue
            a, b = m.jnt_range[j]
            if j in self.leaders:
                c, mult, off = self.leaders.index(j), 1.0, 0.0
            else:
                l, _ = follow[j]
                c = self.leaders.index(l)
                mult, off = self.G[m.jnt_dofadr[j], c], self.o[m.jnt_qposadr[j]]
            x, y = (a - off) / mult, (b - off) / mult
            lo[c], hi[c] = max(lo[c], min(x, y)), min(hi[c], max(x, y))
        self.lower, self.upper = lo, hi
        self.damping = self.G.T @ np.diag(m.dof_damping) @ self.G
        # a follower's friction reaches its leader as |m| f (the range of m tau_f, |tau_f| <= f)
        self.friction = np.abs(self.G).T @ m.dof_frictionloss
        self.effort = efforts(m, self)

    def names(self):
        return self.joint_names

    def center_mid(self):
        return pcl.UrdfArm.center_mid(self)

    def qpos(self, q):
        return self.G @ np.asarray(q) + self.o  # hinge and slide: nq == nv, qpos index == dof index


def efforts(m, coords):
    """Each coordinate's effort limit from the compiled actuators (see the module docstring)."""
    per_joint = {}
    for a in range(m.nu):
        if m.actuator_trntype[a] != mujoco.mjtTrn.mjTRN_JOINT:
            continue
        j = m.actuator_trnid[a][0]
        gear = abs(m.actuator_gear[a][0])
        if m.actuator_forcelimited[a]:
            r = m.actuator_forcerange[a]
        elif (m.actuator_ctrllimited[a] and m.actuator_gaintype[a] == mujoco.mjtGain.mjGAIN_FIXED
              and m.actuator_biastype[a] == mujoco.mjtBias.mjBIAS_NONE):
            r = m.actuator_ctrlrange[a] * abs(m.actuator_gainprm[a][0])
        else:
            continue
        span = min(-r[0], r[1]) if r[0] < 0 < r[1] else max(abs(r[0]), abs(r[1]))
        per_joint[j] = per_joint.get(j, 0.0) + gear * span
    for j in range(m.njnt):
        if m.jnt_actfrclimited[j]:
            r = m.jnt_actfrcrange[j]
            per_joint[j] = min(per_joint.get(j, math.inf), min(-r[0], r[1]))
    return np.array([per_joint.get(j, math.inf) for j in coords.leaders])


class MjArm:
    """MuJoCo's model in faze4's coordinates, with PinArm's interface (pin_closed_loop.py)."""

    def __init__(self, m, name):
        self.m, self.d = m, mujoco.MjData(m)
        m.opt.gravity[:] = [0.0, 0.0, -GRAVITY]
        self.urdf = Coords(m)
        self.urdf.name = name

    def terms(self, q, v):
        G = self.urdf.G
        d = self.d
        d.qpos[:] = self.urdf.qpos(q)
        d.qvel[:] = G @ np.asarray(v)
        mujoco.mj_forward(self.m, d)
        M = np.zeros((self.m.nv, self.m.nv))
        mujoco.mj_fullM(self.m, d, M)
        bias = d.qfrc_bias.copy()
        d.qvel[:] = 0.0
        mujoco.mj_forward(self.m, d)
        g = d.qfrc_bias.copy()
        return G.T @ M @ G, G.T @ (bias - g), G.T @ g

    def gravity(self, q):
        return self.terms(q, np.zeros(len(q)))[2]

    def rnea(self, q, v, a):
        M, cv, g = self.terms(q, v)
        return M @ np.asarray(a) + cv + g

    def frame_position(self, q, frame):
        self.d.qpos[:] = self.urdf.qpos(q)
        mujoco.mj_kinematics(self.m, self.d)
        site = mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_SITE, frame)
        if site >= 0:
            return self.d.site_xpos[site].copy()
        return self.d.xpos[mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_BODY, frame)].copy()

    def step(self, q, v, tau, dt):
        M, cv, g = self.terms(q, v)
        tau = np.array(tau, dtype=float)
        bias = cv + g
        for i, f in enumerate(self.urdf.friction):
            # faze4's joint friction (docs/model.md 2.3), operation for operation as step.rs
            if f != 0.0:
                stop = -(M[i, i] * v[i] / dt + tau[i] - bias[i])
                tau[i] = tau[i] + min(max(stop, -f), f)
        v_next = np.linalg.solve(M + dt * self.urdf.damping, M @ v + dt * (tau - bias))
        return q + dt * v_next, v_next


class MjStepArm(MjArm):
    """MuJoCo's own step: mj_step from (q, v) with tau as qfrc_applied; frictionloss is solved by
    MuJoCo's constraint solver as a soft constraint (solreffriction, solimpfriction); actuators
    and contacts off (the loop's torque is the actuation). `frictionloss=False` turns it off."""

    def __init__(self, m, name, frictionloss=True):
        super().__init__(m, name)
        assert m.neq == 0, "an equality constraint would be MuJoCo's soft one, not faze4's exact map"
        m.opt.timestep = RUN["dt"]
        m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_ACTUATION) | int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
        if not frictionloss:
            m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_FRICTIONLOSS)
            self.urdf.friction = np.zeros_like(self.urdf.friction)
        self.stepper = mujoco.MjData(m)

    def step(self, q, v, tau, dt):
        assert dt == self.m.opt.timestep
        d = self.stepper
        d.qpos[:] = self.urdf.qpos(q)
        d.qvel[:] = self.urdf.G @ np.asarray(v)
        d.qfrc_applied[:] = self.urdf.G @ np.asarray(tau)
        mujoco.mj_step(self.m, d)
        return d.qpos.copy(), d.qvel.copy()


def load(rel, so_arm100, work):
    """The compiled model of `rel`: the SO-101 beside its real meshes, a Menagerie arm with a
    tetrahedron for each mesh file, the feature arm as it is."""
    path = os.path.join(REPO, rel)
    if "so101" in rel:
        shutil.copy(path, os.path.join(work, "so101.xml"))
        os.symlink(os.path.join(so_arm100, "Simulation", "SO101", "assets"), os.path.join(work, "assets"))
        return mujoco.MjModel.from_xml_path(os.path.join(work, "so101.xml")), "real meshes"
    if "menagerie" in rel:
        spec = mujoco.MjSpec.from_file(path)
        assets = {m.file: TETRA_OBJ for m in spec.meshes}
        for mesh in spec.meshes:
            mesh.file = mesh.file.rsplit(".", 1)[0] + ".obj"
        assets = {f.rsplit(".", 1)[0] + ".obj": TETRA_OBJ for f in assets}
        spec.meshdir = ""
        spec.assets = assets
        return spec.compile(), "a tetrahedron for each mesh"
    if "friction_arm" in rel:
        return mujoco.MjModel.from_xml_path(path), "no meshes"
    return mujoco.MjModel.from_xml_path(path), "meshes of tests/urdf/mesh_arms"


def states(arm, rng, count=8):
    c = arm.urdf
    n = len(c.joint_names)
    out = []
    for _ in range(count):
        lo = np.where(np.isfinite(c.lower), c.lower, -math.pi)
        hi = np.where(np.isfinite(c.upper), c.upper, math.pi)
        q, v = rng.uniform(lo, hi), rng.uniform(-1.0, 1.0, n)
        M, cv, g = arm.terms(q, v)
        out.append({"q": q.tolist(), "v": v.tolist(), "m": M.tolist(), "bias": (cv + g).tolist(),
                    "g": g.tolist()})
    return out


def closed_loop(arm, tool):
    A, c = pcl.wave_setup(arm, WAVE["amp_deg"], amp_m=0.002, center=WAVE["center"])
    command = pcl.wave_command(A, c, WAVE["freq"])
    effort = arm.urdf.effort
    _, kp, kd = pcl.auto_tune(arm, command(0.0)[0], RUN["dt"], effort)
    margin = [math.inf]

    def hook(k, q, v, tau_raw, tau):
        finite = np.isfinite(effort)
        if finite.any():
            margin[0] = min(margin[0], float(np.min(np.abs(np.abs(tau_raw[finite]) - effort[finite]))))

    summary, trail = pcl.run_closed_loop(arm, command, kp, kd, effort, duration=RUN["duration"], dt=RUN["dt"],
                                         record_period=RUN["record_period"], tool=tool, verbose=False,
                                         step_hook=hook)
    assert summary["diverged"] is None
    assert margin[0] >= 1e-6, margin[0]
    summary.pop("wall_time_s")
    summary.pop("envelope_pct")
    return {"args": {**WAVE, **RUN, "amp_m": 0.002, "tool_link": tool}, "center": c.tolist(),
            "summary": summary, "trail": {"columns": pcl.trail_columns(len(c)), "rows": trail.tolist()}}


class NudgedArm(MjArm):
    """MjArm with M one rounding larger (1 + 4e-16): how far rounding alone moves the closed loop."""

    def terms(self, q, v):
        M, cv, g = super().terms(q, v)
        return M * (1.0 + 4e-16), cv, g


def rounding_sensitivity(m, name, tool, loop):
    """The trail's change when M changes by one rounding: about 0 where the loop damps rounding;
    large where two coupled joints stick together and faze4's joint-alone stopping torque chatters
    (docs/model.md 2.3), which amplifies rounding (the test's tolerance against this replica)."""
    return trail_difference(closed_loop(NudgedArm(m, name), tool), loop)


def trail_difference(a, b):
    """The largest difference of two closed loops' trails (tool xyz in m, q in rad or m)."""
    a, b = np.array(a["trail"]["rows"]), np.array(b["trail"]["rows"])
    assert a.shape == b.shape and (a[:, 0] == b[:, 0]).all()
    return float(np.max(np.abs(a[:, 1:] - b[:, 1:])))


def mujoco_step(name, rel, tool, so_arm100, faze4_step):
    """The closed loop on MuJoCo's own step with frictionloss, twice: `as_written` (the file's
    solreffriction/solimpfriction, MuJoCo's defaults 0.02 s and 0.9 here) and `hard` (every dof's
    solref (2 dt, 1), MuJoCo's shortest safe time constant, and solimp 0.9999, its largest
    impedance: the nearest MuJoCo's soft constraint comes to a hard friction). With each, the
    differences that explain the test's tolerance: MuJoCo's step against docs/model.md's step
    with friction on both sides (`friction_models_difference`; `faze4_step` is the closed loop
    with faze4's friction), with friction on MuJoCo's side alone (`without_friction_difference`),
    and with none on either (`integrators_difference`: rounding)."""
    def run(make, hard=False):
        with tempfile.TemporaryDirectory() as work:
            m, _ = load(rel, os.path.abspath(so_arm100), work)
            if hard:
                m.dof_solref[:] = [2 * RUN["dt"], 1.0]
                m.dof_solimp[:, :2] = 0.9999
            return make(m), closed_loop(make(m), tool)

    def faze4_without(m):
        arm = MjArm(m, name)
        arm.urdf.friction = np.zeros_like(arm.urdf.friction)
        return arm

    arm, without = run(lambda m: MjStepArm(m, name, frictionloss=False))
    _, faze4_free = run(faze4_without)
    integrators = trail_difference(without, faze4_free)
    out = {"friction": MjArm(load_plain(rel, so_arm100), name).urdf.friction.tolist(),
           "integrators_difference": integrators}
    for key, hard in [("as_written", False), ("hard", True)]:
        _, loop = run(lambda m: MjStepArm(m, name), hard)
        loop["friction_models_difference"] = trail_difference(loop, faze4_step)
        loop["without_friction_difference"] = trail_difference(loop, faze4_free)
        out[key] = loop
        print(f"[{name}] MuJoCo's step ({key}) vs docs/model.md's step: with friction on both "
              f"{loop['friction_models_difference']:.1e}, on MuJoCo's alone {loop['without_friction_difference']:.1e}, "
              f"on neither {integrators:.1e}")
    return out


def load_plain(rel, so_arm100):
    with tempfile.TemporaryDirectory() as work:
        return load(rel, os.path.abspath(so_arm100), work)[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--so-arm100", required=True, help="a checkout of TheRobotStudio/SO-ARM100")
    args = ap.parse_args()
    for name, rel, tool in MODELS:
        with tempfile.TemporaryDirectory() as work:
            m, meshes = load(rel, os.path.abspath(args.so_arm100), work)
            arm = MjArm(m, name)
            c = arm.urdf
            home = None
            k = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_KEY, "home")
            if k >= 0:
                home = [float(m.key_qpos[k][m.jnt_qposadr[j]]) for j in c.leaders]
            fixture = {
                "generator": "tools/oracle/mjcf_fixtures.py",
                "mujoco_version": importlib.metadata.version("mujoco"),
                "model": rel,
                "meshes": meshes,
                "coordinates": c.joint_names,
                "lower": [x if math.isfinite(x) else None for x in c.lower.tolist()],
                "upper": [x if math.isfinite(x) else None for x in c.upper.tolist()],
                "damping": c.damping.tolist(),
                "effort": [x if math.isfinite(x) else None for x in c.effort.tolist()],
                "armature": (c.G.T @ np.diag(m.dof_armature) @ c.G).tolist(),
                "home": home,
                "states": states(arm, np.random.default_rng(20261128)),
            }
            if tool:
                fixture["closed_loop"] = closed_loop(arm, tool)
                fixture["closed_loop"]["rounding_sensitivity"] = rounding_sensitivity(m, name, tool, fixture["closed_loop"])
            if name in MUJOCO_STEP:
                fixture["mujoco_step"] = mujoco_step(name, rel, tool, args.so_arm100, fixture["closed_loop"])
            out = f"tests/fixtures/mjcf_{name}.json"
            dump_fixture(os.path.join(REPO, out), fixture)
            print(f"[write] {out}: {len(c.joint_names)} coordinates {c.joint_names}, {meshes}")


if __name__ == "__main__":
    main()
