"""Drake oracle for faze4's rigid-body core (kinematics, M, Cv, g, Jacobian, discrete step).

Run from the repo root:  tools/oracle/.venv/bin/python tools/oracle/core_fixtures.py
Writes tests/fixtures/core_{faze4_arm,arm_prismatic,tree_arm}.json (deterministic: fixed seeds).

What it asks pydrake's MultibodyPlant, per model and per random state (q, v):
  frames          X_WB of every body (= every URDF link, world included): R row-major, p in metres.
  M               plant.CalcMassMatrix.
  Cv              plant.CalcBiasTerm: C(q,v) v only (no gravity, no joint damping).
  g               -plant.CalcGravityGeneralizedForces, so that  M vdot + Cv + g = tau - D v.
  jacobian_tool   plant.CalcJacobianSpatialVelocity(kV, tool body frame, point [0,0,0], world, world):
                  6 x n, rows [angular; translational]. The tool is the last <link> of the URDF.
  step            1000 updates of a DISCRETE plant (time_step = dt, SAP solver, no contact) under a
                  constant generalized force tau on the applied-generalized-force input port.
                  tau = g(q_start) + a random part (+-0.5 x RMS |g_i|): holding gravity at the start
                  keeps the 0.2 s runs gentle (|v| of a few rad/s instead of a free fall), which
                  keeps the round-off growth over 1000 steps about 3x smaller.
Conventions: gravity [0, 0, -9.81] (world z up); q, v in Drake's order (all joints are 1-dof, so
the position and velocity orders agree); revolute/continuous in rad, prismatic in m.

Self-check: the discrete run is re-integrated in numpy with the discrete step of docs/model.md, using Drake's
M, Cv, g at every step and D = diag(joint damping) read from the plant:
    v+ = (M + dt D)^-1 [M v + dt (tau - Cv - g)],   q+ = q + dt v+
and must agree with Drake's discrete plant to <= 1e-12. A draw whose run comes near a joint limit
(SAP then adds limit constraints, which the plain step does not model) or fails the check is redrawn.
"""

import importlib.metadata
import json
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
from pydrake.all import (
    AddMultibodyPlant,
    BodyIndex,
    DiagramBuilder,
    JacobianWrtVariable,
    JointIndex,
    MultibodyPlantConfig,
    Parser,
    Simulator,
)

DT = 2e-4
STEPS = 1000
N_SAMPLES = 25
GRAVITY = [0.0, 0.0, -9.81]
Q_FRACTION = 0.7         # q drawn in the central 70 % of each joint's range
V_MAX_REVOLUTE = 1.0     # rad/s
V_MAX_PRISMATIC = 0.1    # m/s (prismatic strokes are short)
TAU_FRACTION = 0.5       # tau_i = g_i(q_start) + uniform in +-0.5 x typical |g_i|
LIMIT_MARGIN = 0.02      # rad or m: the whole run stays this far from every limit
SELF_CHECK_TOL = 1e-12

MODELS = [
    # (urdf relative to repo root, fixture name, seed)
    ("urdf/faze4_arm.urdf", "core_faze4_arm.json", 20240601),
    ("tests/urdf/arm_prismatic.urdf", "core_arm_prismatic.json", 20240602),
    ("tests/urdf/tree_arm.urdf", "core_tree_arm.json", 20240603),
]

# docs/model.md: tool_link origin at three q (printed digits) and diag M at the wave start.
SPEC_TOOL_POSITIONS = [
    ([0, 0.378, 0.378, 0, -0.378, -0.378], [0.079, -0.521, 0.395], 3),
    ([0.435, 0.244, -0.191, -0.435, -0.244, 0.191], [0.220, -0.495, 0.600], 3),
    ([0.0104, 0.1795, -0.5049, 0, -0.0938, 0], [0.0800, -0.4799, 0.7099], 4),
]
SPEC_DIAG_M_Q0 = [7.4957e-02, 3.5653e-01, 4.3554e-02, 1.3999e-03, 2.5971e-04, 6.4520e-06]


# ---------------------------------------------------------------------------------------------
# Model loading


class Model:
    """A discrete SAP MultibodyPlant for one URDF, plus what the URDF says about its joints."""

    def __init__(self, urdf):
        self.urdf = urdf
        config = MultibodyPlantConfig(time_step=DT, discrete_contact_approximation="sap")
        builder = DiagramBuilder()
        self.plant, _scene_graph = AddMultibodyPlant(config, builder)
        Parser(self.plant).AddModels(urdf)
        self.plant.Finalize()
        self.diagram = builder.Build()
        plant = self.plant
        assert plant.get_discrete_contact_approximation().name == "kSap"
        assert plant.num_positions() == plant.num_velocities()
        self.n = plant.num_velocities()

        # Moving joints in Drake's position order.
        moving = [plant.get_joint(JointIndex(i)) for i in range(plant.num_joints())]
        moving = [j for j in moving if j.num_velocities() > 0]
        moving.sort(key=lambda j: j.position_start())
        assert all(j.num_positions() == 1 and j.num_velocities() == 1 for j in moving)
        assert [j.position_start() for j in moving] == list(range(self.n))
        assert [j.velocity_start() for j in moving] == list(range(self.n))
        self.joints = moving

        root = ET.parse(urdf).getroot()
        urdf_types = {j.get("name"): j.get("type") for j in root.findall("joint")}
        self.joint_names = [j.name() for j in moving]
        self.joint_types = [urdf_types[name] for name in self.joint_names]
        for joint, kind in zip(moving, self.joint_types):
            expected = "prismatic" if kind == "prismatic" else "revolute"
            assert joint.type_name() == expected, (joint.name(), joint.type_name(), kind)

        self.lower = np.array([j.position_lower_limits()[0] for j in moving])
        self.upper = np.array([j.position_upper_limits()[0] for j in moving])
        for kind, lo, hi in zip(self.joint_types, self.lower, self.upper):
            assert (kind == "continuous") == (math.isinf(lo) and math.isinf(hi))
        self.damping = np.array([j.default_damping_vector()[0] for j in moving])

        # Every body (= every URDF link, world included), in Drake's body order.
        self.frame_names = [plant.get_body(BodyIndex(i)).name() for i in range(plant.num_bodies())]
        urdf_links = [link.get("name") for link in root.findall("link")]
        assert sorted(urdf_links) == sorted(self.frame_names), (urdf_links, self.frame_names)
        self.tool_name = urdf_links[-1]
        self.tool_frame = plant.GetBodyByName(self.tool_name).body_frame()

        # A context to query kinematics/dynamics at arbitrary states (stepping uses its own).
        self.query_root = self.diagram.CreateDefaultContext()
        self.query = plant.GetMyMutableContextFromRoot(self.query_root)
        assert list(plant.gravity_field().gravity_vector()) == GRAVITY

    def set_state(self, q, v=None):
        self.plant.SetPositions(self.query, q)
        self.plant.SetVelocities(self.query, np.zeros(self.n) if v is None else v)


# ---------------------------------------------------------------------------------------------
# One function per quantity (all at the state last given to Model.set_state)


def frame_poses(model):
    poses = {}
    for name in model.frame_names:
        X = model.plant.EvalBodyPoseInWorld(model.query, model.plant.GetBodyByName(name))
        poses[name] = {"R": X.rotation().matrix().tolist(), "p": X.translation().tolist()}
    return poses


def mass_matrix(model):
    return model.plant.CalcMassMatrix(model.query)


def bias_term(model):
    return model.plant.CalcBiasTerm(model.query)


def gravity_term(model):
    return -model.plant.CalcGravityGeneralizedForces(model.query)


def tool_jacobian(model):
    plant = model.plant
    world = plant.world_frame()
    return plant.CalcJacobianSpatialVelocity(
        model.query, JacobianWrtVariable.kV, model.tool_frame, np.zeros(3), world, world)


def tool_position(model):
    return model.plant.EvalBodyPoseInWorld(
        model.query, model.plant.GetBodyByName(model.tool_name)).translation()


def drake_discrete_run(model, q, v, tau):
    """STEPS updates of the discrete SAP plant, driven by a Simulator one period at a time
    (MultibodyPlant 1.51 declares its step as a periodic unrestricted update).
    Returns the final (q, v) and the q trajectory."""
    plant = model.plant
    simulator = Simulator(model.diagram)
    ctx = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    plant.get_applied_generalized_force_input_port().FixValue(ctx, tau)
    plant.SetPositions(ctx, q)
    plant.SetVelocities(ctx, v)
    simulator.Initialize()
    qs = [np.array(q)]
    for k in range(STEPS):
        simulator.AdvanceTo((k + 1) * DT)
        qs.append(plant.GetPositions(ctx))
    assert simulator.get_num_unrestricted_updates() + simulator.get_num_discrete_updates() == STEPS
    x = plant.GetPositionsAndVelocities(ctx)
    return x[: model.n], x[model.n:], np.array(qs)


def spec_discrete_run(model, q, v, tau):
    """The discrete step of docs/model.md in numpy, with Drake's M, Cv, g at each step."""
    q, v = np.array(q, dtype=float), np.array(v, dtype=float)
    D = np.diag(model.damping)
    for _ in range(STEPS):
        model.set_state(q, v)
        M, Cv, g = mass_matrix(model), bias_term(model), gravity_term(model)
        v = np.linalg.solve(M + DT * D, M @ v + DT * (tau - Cv - g))
        q = q + DT * v
    return q, v


# ---------------------------------------------------------------------------------------------
# Sampling


def q_bounds(model):
    """The central Q_FRACTION of each joint's range; continuous joints in +-pi."""
    lo, hi = model.lower.copy(), model.upper.copy()
    cont = np.isinf(lo) | np.isinf(hi)
    lo[cont], hi[cont] = -math.pi, math.pi
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    return mid - Q_FRACTION * half, mid + Q_FRACTION * half


def typical_gravity(model, rng):
    """RMS of g_i over 200 random configurations (floor 0.05) -> scale of the random tau."""
    lo, hi = q_bounds(model)
    gs = []
    for _ in range(200):
        model.set_state(rng.uniform(lo, hi))
        gs.append(gravity_term(model))
    return np.maximum(np.sqrt(np.mean(np.square(gs), axis=0)), 0.05)


def draw_state(model, rng, tau_scale):
    lo, hi = q_bounds(model)
    q = rng.uniform(lo, hi)
    vmax = np.array([V_MAX_PRISMATIC if t == "prismatic" else V_MAX_REVOLUTE
                     for t in model.joint_types])
    v = rng.uniform(-vmax, vmax)
    model.set_state(q)
    tau = gravity_term(model) + rng.uniform(-TAU_FRACTION * tau_scale, TAU_FRACTION * tau_scale)
    return q, v, tau


def limit_clearance(model, qs):
    """Smallest distance from any q in the run to any joint limit (continuous: +-inf, never near).
    SAP only adds a limit constraint when the limit is within 2 dt max(|v|, |v*|) of q."""
    return float(min(np.min(qs - model.lower), np.min(model.upper - qs)))


def make_sample(model, q, v, tau, step):
    model.set_state(q, v)
    return {
        "q": q.tolist(),
        "v": v.tolist(),
        "frames": frame_poses(model),
        "M": mass_matrix(model).tolist(),
        "Cv": bias_term(model).tolist(),
        "g": gravity_term(model).tolist(),
        "jacobian_tool": tool_jacobian(model).tolist(),
        "step": step,
    }


def samples(model, seed):
    rng = np.random.default_rng(seed)
    tau_scale = typical_gravity(model, rng)
    out, worst_q, worst_v, redrawn = [], 0.0, 0.0, 0
    while len(out) < N_SAMPLES:
        q, v, tau = draw_state(model, rng, tau_scale)
        q_end, v_end, qs = drake_discrete_run(model, q, v, tau)
        q_ref, v_ref = spec_discrete_run(model, q, v, tau)
        dq, dv = np.max(np.abs(q_end - q_ref)), np.max(np.abs(v_end - v_ref))
        if limit_clearance(model, qs) < LIMIT_MARGIN or not np.all(np.isfinite(qs)) \
                or max(dq, dv) > SELF_CHECK_TOL:
            redrawn += 1
            continue
        worst_q, worst_v = max(worst_q, dq), max(worst_v, dv)
        step = {"tau": tau.tolist(), "dt": DT, "steps": STEPS,
                "q": q_end.tolist(), "v": v_end.tolist()}
        out.append(make_sample(model, q, v, tau, step))
    return out, (worst_q, worst_v), redrawn


# ---------------------------------------------------------------------------------------------
# docs/model.md checks (faze4_arm only)


def spec_checks(model):
    assert model.joint_names == ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka",
                                 "hvataljka"]
    assert model.tool_name == "tool_link"
    tool_positions = []
    for q, printed, digits in SPEC_TOOL_POSITIONS:
        model.set_state(np.array(q, dtype=float))
        p = tool_position(model)
        assert np.all(np.abs(p - printed) <= 0.5 * 10.0 ** -digits + 1e-12), (q, p, printed)
        tool_positions.append({"q": [float(x) for x in q], "p": p.tolist()})
    q0 = np.deg2rad(25.0) * np.sin(np.arange(6) * math.pi / 3.0)
    model.set_state(q0)
    diag = np.diag(mass_matrix(model))
    for i, (d, printed) in enumerate(zip(diag, SPEC_DIAG_M_Q0)):
        unit = 10.0 ** (math.floor(math.log10(abs(printed))) - 4)  # last of 5 printed digits
        # docs/model.md publishes M44 = 1.3999e-03 where Drake gives 1.39995833e-03 (rounds to 1.4000e-03):
        # accept one unit of the last printed digit, and say so when it is more than rounding.
        assert abs(d - printed) <= unit, (i, d, printed)
        if abs(d - printed) > 0.5 * unit:
            print(f"  note: diag M(q0)[{i}] = {d:.9e}, published {printed:.4e} (not rounded)")
    return {"tool_positions": tool_positions, "q0": q0.tolist(), "diag_M_q0": diag.tolist()}


# ---------------------------------------------------------------------------------------------


def build_fixture(urdf, seed):
    model = Model(urdf)
    sample_list, worst, redrawn = samples(model, seed)
    fixture = {
        "generator": "tools/oracle/core_fixtures.py",
        "drake_version": importlib.metadata.version("drake"),
        "urdf": urdf,
        "gravity": GRAVITY,
        "joint_names": model.joint_names,
        "joint_types": model.joint_types,
        "frame_names": model.frame_names,
        "tool_frame": model.tool_name,
        "damping": model.damping.tolist(),
        "samples": sample_list,
    }
    if urdf == "urdf/faze4_arm.urdf":
        fixture["spec_checks"] = spec_checks(model)
    max_m = max(abs(x) for s in sample_list for row in s["M"] for x in row)
    print(f"{urdf}: n={model.n} dofs, {len(model.frame_names)} frames, max|M|={max_m:.6g}, "
          f"{len(sample_list)} samples ({redrawn} redrawn), "
          f"self-check worst |drake - spec step|: q {worst[0]:.3e}, v {worst[1]:.3e}")
    print(f"  joints (Drake order): {model.joint_names}")
    return fixture


def main():
    os.makedirs("tests/fixtures", exist_ok=True)
    for urdf, name, seed in MODELS:
        fixture = build_fixture(urdf, seed)
        with open(os.path.join("tests/fixtures", name), "w") as f:
            json.dump(fixture, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
