#!/usr/bin/env python3
"""Drake's contact closed loop: the oracle of `faze4 --self-collisions` (docs/contact.md).

The closed loop is drake_closed_loop.py's (one copy: the same controller, commands, metrics and
trail); this script only changes the plant:

* the model's collision geometry is kept (Drake's default collision filtering: geometries on
  different bodies, not on the two bodies a joint connects, not welded together);
* contact model "point" (compliant point contact; per-geometry hydroelastic off), with Drake's
  default contact parameters, which SceneGraph gives every geometry that sets none: point
  stiffness k = 1e6 N/m per geometry, combined in series (k = k_A k_B / (k_A + k_B) = 5e5 N/m),
  Hunt–Crossley dissipation d = 50 s/m, and Coulomb friction μ = 1.0 (what Drake's URDF parser
  gives a <collision> without friction). --friction MU writes
  <drake:proximity_properties> with mu_dynamic = mu_static = MU into every <collision>;
* meshes: Drake 1.51 replaces each collision mesh by its convex hull for point contact, and only
  hulls .obj/.vtk/.gltf files; the STL meshes are written once as .obj with the same vertices
  (clearance_fixtures.prepare).

Which discrete contact approximation: the issue's figures (circle, μ = 1: J3 saturated 93.9 %,
tracking error 0.487 rad, deviation 152.8 / 57.5 mm, J4 never saturated; μ = 0: J4 99 %, deviation
1.6 / 0.9 mm) come from discrete_contact_approximation = "sap" — the approximation faze4's own
closed loop already matches (drake_closed_loop.build) — and equally from "lagged" (Drake 1.51's
default) and "similar": the three give the same figures within a few tenths (run with
--approximation to see; the table is in docs/contact.md). The outcome is decided by stiction and
the hulls' geometry, not by the contact law. faze4 implements "lagged"'s constraint
(SapHuntCrossleyConstraint, the only one of the three that uses the issue's Hunt–Crossley
dissipation d = 50 s/m; "sap" ignores d and uses a relaxation time of 0.1 s instead), so the
fixtures are written with "lagged".

Usage (from the repository root, with the oracle venv):

    tools/oracle/.venv/bin/python tools/oracle/drake_contact_loop.py circle [--friction 1.0]
        [--approximation lagged|similar|sap] [--duration 12] [--summary F.json]
    tools/oracle/.venv/bin/python tools/oracle/drake_contact_loop.py arm|limit-arm [--approximation A]
    tools/oracle/.venv/bin/python tools/oracle/drake_contact_loop.py fixtures

`circle` runs the circle shape (tests/fixtures/shape_circle_q.npy as the periodic command, 5 s per
loop, 12 s, dt 2e-4) on urdf/faze4_real.urdf with the official meshes (assets/faze4_description,
or $FAZE4_DESCRIPTION) and prints the figures and the loop's wall time. `fixtures` writes

    tests/fixtures/contact_circle_mu1.json   the circle, μ = 1
    tests/fixtures/contact_circle_mu0.json   the circle, μ = 0
    tests/fixtures/contact_arm.json          tests/urdf/contact_arm.urdf: a planar two-link arm
                                             whose tip sphere is driven into a box welded to the
                                             base (wave, 3 s), with the whole trail
    tests/fixtures/contact_limit_arm.json    tests/urdf/contact_limit_arm.urdf: the same arm and
                                             wave with the wall turned so that the contact pushes
                                             j2 onto its upper limit (μ = 0), with the whole trail

Joint limits: the URDF's position limits are kept. Drake's discrete SAP plant (all three
approximations) puts a limit constraint into the same convex problem as the contacts whenever a
limit lies within 2 Δt max(|v|, |v*|) of q: "near-rigid" (stiffness 1e12, dissipation time scale
Δt, β = 0.1), so a joint pressed onto its limit sits beyond it by about 1e-9 rad here.

Each fixture holds the summary (per-joint saturation %, max tracking error, path deviation
max/mean for the circle, tool range), trail rows, and the contacts Drake reports at the trail
rows (count, the link pairs, the deepest penetration, the largest normal force and slip speed).
"""

import argparse
import importlib.metadata
import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import clearance_fixtures as cf  # noqa: E402
import closed_loop_fixtures as clf  # noqa: E402
import drake_closed_loop as dcl  # noqa: E402
import shape_fixtures as sf  # noqa: E402

REPO = Path(dcl.REPO_ROOT)
FIXTURES = REPO / "tests" / "fixtures"
GENERATOR = "tools/oracle/drake_contact_loop.py"
CIRCLE_Q = "tests/fixtures/shape_circle_q.npy"
CIRCLE = dict(duration=12.0, dt=2e-4, record_period=0.02, period=5.0)
ARM_URDF = "tests/urdf/contact_arm.urdf"
# contact_arm: the wave command of drake_closed_loop.py (q_i = A sin(w t + i pi/3)), its limits
ARM = dict(duration=3.0, dt=2e-4, record_period=0.02, freq=2.0, amp_deg=25.0)
ARM_EFFORT = [4.0, 2.0]
# contact_limit_arm: the same wave; the contact pushes j2 onto its upper limit (frictionless: with
# friction the tip sticks to the face before j2 gets there), its URDF's efforts
LIMIT_ARM_URDF = "tests/urdf/contact_limit_arm.urdf"
LIMIT_ARM_EFFORT = [4.0, 0.5]
LIMIT_ARM_FRICTION = 0.0
ARM_TOOL = "tip_link"
# every trail row of the circle is kept in the summary's figures; the fixture stores every 25th
CIRCLE_ROW_STRIDE = 25


def with_friction(text, mu):
    """URDF text with every <collision> given Coulomb friction mu (static = dynamic)."""
    props = (f'<drake:proximity_properties><drake:mu_dynamic value="{mu!r}"/>'
             f'<drake:mu_static value="{mu!r}"/></drake:proximity_properties></collision>')
    return text.replace("</collision>", props)


def prepared_urdf(urdf_rel, friction, tmp):
    """The model as Drake reads it: meshes as .obj hulls, friction set if given."""
    path = REPO / urdf_rel
    if "package://" in path.read_text():
        path, _meshes = cf.prepare(path, tmp)
    text = path.read_text()
    if friction is not None:
        text = with_friction(text, friction)
    out = tmp / ("contact_" + Path(urdf_rel).name)
    out.write_text(text)
    return str(out)


class ContactLog:
    """record_hook: Drake's contact results at each trail row."""

    def __init__(self):
        self.counts = []
        self.pairs = set()
        self.deepest = 0.0
        self.max_normal_force = 0.0
        self.max_slip = 0.0

    def __call__(self, plant, context, count):
        results = plant.get_contact_results_output_port().Eval(context)
        n = results.num_point_pair_contacts()
        self.counts.append(n)
        for i in range(n):
            info = results.point_pair_contact_info(i)
            a = plant.get_body(info.bodyA_index()).name()
            b = plant.get_body(info.bodyB_index()).name()
            self.pairs.add(tuple(sorted((a, b))))
            self.deepest = max(self.deepest, info.point_pair().depth)
            normal = info.point_pair().nhat_BA_W
            self.max_normal_force = max(self.max_normal_force, abs(float(info.contact_force() @ normal)))
            self.max_slip = max(self.max_slip, info.slip_speed())

    def summary(self):
        return {
            "rows_in_contact": int(sum(c > 0 for c in self.counts)),
            "rows": len(self.counts),
            "max_count": int(max(self.counts, default=0)),
            "pairs": [list(p) for p in sorted(self.pairs)],
            "max_depth_m": self.deepest,
            "max_normal_force_n": self.max_normal_force,
            "max_slip_speed_m_s": self.max_slip,
        }


def plant_config(approximation):
    return {"contact_model": "point", "discrete_contact_approximation": approximation}


def run_circle(friction=None, approximation="lagged", duration=CIRCLE["duration"], verbose=False):
    """The circle with self-contact; returns (summary with path_deviation_mm, trail, contacts)."""
    Q = np.load(REPO / CIRCLE_Q)
    targets = np.array([sf.shape_point("circle", k / len(Q)) for k in range(len(Q))])
    log = ContactLog()
    with tempfile.TemporaryDirectory() as tmp:
        urdf = prepared_urdf("urdf/faze4_real.urdf", friction, Path(tmp))
        summary, trail = dcl.run_closed_loop(
            dcl.periodic_command(Q, CIRCLE["period"]), duration=duration, dt=CIRCLE["dt"],
            record_period=CIRCLE["record_period"], urdf=urdf, verbose=verbose,
            plant_config=plant_config(approximation), record_hook=log)
    d = np.array([sf.distance_to_closed_path(row[1:4], targets) for row in trail])
    summary["path_deviation_mm"] = {"max": float(d.max() * 1e3), "mean": float(d.mean() * 1e3)}
    return summary, trail, log.summary()


def run_arm(approximation="lagged", urdf=ARM_URDF, friction=None, effort=ARM_EFFORT):
    """A small arm of tests/urdf/ on ARM's wave (tool ARM_TOOL); returns (summary, trail, contacts).
    friction None: Drake's default μ (1.0) from the URDF as it is."""
    log = ContactLog()
    saved = dcl.TOOL_BODY
    dcl.TOOL_BODY = ARM_TOOL
    try:
        with tempfile.TemporaryDirectory() as tmp:
            path = str(REPO / urdf) if friction is None else prepared_urdf(urdf, friction, Path(tmp))
            summary, trail = dcl.run_closed_loop(
                dcl.wave_command(ARM["amp_deg"], ARM["freq"], dof=2), duration=ARM["duration"],
                dt=ARM["dt"], record_period=ARM["record_period"], urdf=path,
                effort=effort, verbose=False, plant_config=plant_config(approximation),
                record_hook=log)
    finally:
        dcl.TOOL_BODY = saved
    return summary, trail, log.summary()


def run_limit_arm(approximation="lagged"):
    """tests/urdf/contact_limit_arm.urdf: contact and j2's upper limit in the same steps."""
    return run_arm(approximation, LIMIT_ARM_URDF, LIMIT_ARM_FRICTION, LIMIT_ARM_EFFORT)


def report(name, summary, contacts):
    sat = " ".join(f"{x:.1f}" for x in summary["saturation_pct"])
    err = " ".join(f"{x:.3g}" for x in summary["max_tracking_error_rad"])
    dev = summary.get("path_deviation_mm")
    dev = f"; deviation max {dev['max']:.1f} mean {dev['mean']:.1f} mm" if dev else ""
    print(f"{name}: saturation % [{sat}]; max error rad [{err}]{dev}; "
          f"contact at {contacts['rows_in_contact']}/{contacts['rows']} rows, pairs {contacts['pairs']}, "
          f"deepest {contacts['max_depth_m'] * 1e3:.3f} mm; loop wall time {summary['wall_time_s']:.2f} s")


def fixture(name, urdf, command, args, summary, trail, contacts, approximation, stride=1):
    summary = dict(summary)
    summary.pop("wall_time_s")
    rows = trail[::stride].tolist()
    if stride > 1 and (len(trail) - 1) % stride:
        rows.append(trail[-1].tolist())
    data = {
        "generator": GENERATOR,
        "drake_version": importlib.metadata.version("drake"),
        "urdf": urdf,
        "command": command,
        "args": args,
        "contact": {"model": "point", "discrete_contact_approximation": approximation,
                    "point_stiffness_n_m": 1e6, "hunt_crossley_dissipation_s_m": 50.0,
                    "friction": args["friction"]},
        "summary": summary,
        "contacts": contacts,
        "trail": {"columns": dcl.TRAIL_COLUMNS, "row_stride": stride, "rows": rows},
    }
    clf.dump_fixture(FIXTURES / name, data)
    print(f"[write] tests/fixtures/{name}")


def write_fixtures():
    for mu, name in ((1.0, "contact_circle_mu1.json"), (0.0, "contact_circle_mu0.json")):
        summary, trail, contacts = run_circle(mu)
        report(name, summary, contacts)
        args = {"shape": "circle", "q_samples": CIRCLE_Q, "friction": mu, **CIRCLE}
        fixture(name, "urdf/faze4_real.urdf", "shape", args, summary, trail, contacts, "lagged",
                CIRCLE_ROW_STRIDE)
    summary, trail, contacts = run_arm()
    report("contact_arm", summary, contacts)
    args = {**ARM, "effort": ARM_EFFORT, "tool_link": ARM_TOOL, "friction": 1.0}
    fixture("contact_arm.json", ARM_URDF, "wave", args, summary, trail, contacts, "lagged")
    summary, trail, contacts = run_limit_arm()
    report("contact_limit_arm", summary, contacts)
    args = {**ARM, "effort": LIMIT_ARM_EFFORT, "tool_link": ARM_TOOL, "friction": LIMIT_ARM_FRICTION}
    fixture("contact_limit_arm.json", LIMIT_ARM_URDF, "wave", args, summary, trail, contacts, "lagged")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    c = sub.add_parser("circle", help="the circle with self-contact")
    c.add_argument("--friction", type=float, default=None, help="μ (default: Drake's, 1.0)")
    c.add_argument("--approximation", default="lagged", choices=["lagged", "similar", "sap"])
    c.add_argument("--duration", type=float, default=CIRCLE["duration"])
    c.add_argument("--summary", metavar="F.json")
    c.add_argument("--verbose", action="store_true")
    a = sub.add_parser("arm", help="tests/urdf/contact_arm.urdf against its wall")
    a.add_argument("--approximation", default="lagged", choices=["lagged", "similar", "sap"])
    a = sub.add_parser("limit-arm", help="tests/urdf/contact_limit_arm.urdf: contact and a joint limit")
    a.add_argument("--approximation", default="lagged", choices=["lagged", "similar", "sap"])
    sub.add_parser("fixtures", help="write tests/fixtures/contact_*.json")
    args = ap.parse_args(argv)
    if args.mode == "fixtures":
        write_fixtures()
        return 0
    if args.mode == "arm":
        summary, _trail, contacts = run_arm(args.approximation)
        report(f"contact_arm ({args.approximation})", summary, contacts)
        return 0
    if args.mode == "limit-arm":
        summary, _trail, contacts = run_limit_arm(args.approximation)
        report(f"contact_limit_arm ({args.approximation})", summary, contacts)
        return 0
    summary, _trail, contacts = run_circle(args.friction, args.approximation, args.duration, args.verbose)
    report(f"circle (μ={args.friction if args.friction is not None else 'default'}, {args.approximation})",
           summary, contacts)
    if args.summary:
        with open(args.summary, "w") as f:
            json.dump({**summary, "contacts": contacts}, f, indent=1)
    print(json.dumps({"wall_time_s": summary["wall_time_s"]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
