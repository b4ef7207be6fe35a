"""Oracle for faze4's self-clearance (src/geometry/): Drake's SceneGraph on convex hulls, coal on
the exact meshes.

Run from the repo root:  tools/oracle/.venv/bin/python tools/oracle/clearance_fixtures.py
Reads the official Faze4 description (meshes) from the repository, assets/faze4_description
(or $FAZE4_DESCRIPTION), as the tests do.
Writes tests/fixtures/clearance_faze4_real.json and tests/fixtures/clearance_collision_arm.json
(deterministic: fixed seeds).

Models: urdf/faze4_real.urdf (the official STL meshes as collision geometry, and a cylinder under
J1) and tests/urdf/collision_arm.urdf (boxes, cylinders, spheres; a welded link).

Poses: for the Faze4 the 240 joint samples of the circle (tests/fixtures/shape_circle_q.npy, as
`faze4 shape --shape circle --save-q` writes them) and 12 random poses within the joint limits;
for collision_arm 40 random poses within the limits (many penetrate).

Per pose and per pair Drake checks with its default collision filtering (geometries on different
bodies, not parent and child, not welded together; this is also the list of pairs the fixture
holds):
  drake  QueryObject.ComputeSignedDistancePairwiseClosestPoints: Drake replaces each mesh by its
         convex hull for proximity queries; primitives are themselves. Signed distance (m),
         negative = penetration depth. Drake's GJK/EPA (FCL's) stop at a tolerance of 1e-6, so on
         curved shapes these are only good to about 2e-6 m.
  hull   the same signed distance from coal, hulls by qhull (coal's buildConvexHull) and GJK/EPA
         run to round-off (tolerance 1e-13) at Drake's world poses: what faze4 is tested against.
         The largest |drake - hull| is printed and stored (drake_vs_coal_hull_max_m).
  mesh   the exact triangles: for a pair involving a mesh, coal.distance between BVHModelOBBRSS
         meshes built from the STL's triangles (vertices exactly the file's float32 values), at
         the geometries' world poses from Drake; 0 when coal.collide reports a collision. For
         a mesh and a primitive: null. coal's BVH-versus-shape distance came out below the
         hulls' distance on the Faze4 (base_link's cylinder and podlaktica at "random 0": 87.8 mm
         against 146.0 mm; a mesh lies inside its hull, so that cannot be), and coal has no
         triangle-cylinder distance to do it triangle by triangle. For two primitives, the hull
         value (they are convex).
  intersecting  mesh reading: the shapes overlap.

Drake 1.51 only hulls .obj/.vtk/.gltf meshes: each STL is written once as an .obj with the same
vertices (welded by exact value; printed with repr, which round-trips) into a temporary folder,
and the URDF's mesh references are pointed there.
"""

import importlib.metadata
import json
import os
import re
import tempfile
from pathlib import Path

import coal
import numpy as np
from pydrake.all import AddMultibodyPlantSceneGraph, BodyIndex, DiagramBuilder, Parser, Role

REPO = Path(__file__).resolve().parents[2]
N_RANDOM_FAZE4 = 12
N_RANDOM_ARM = 40


def description() -> Path:
    if os.environ.get("FAZE4_DESCRIPTION"):
        return Path(os.environ["FAZE4_DESCRIPTION"])
    return REPO / "assets/faze4_description"


def read_stl(path: Path) -> np.ndarray:
    """Binary STL → (n, 3, 3) corners, float32 values as float64."""
    b = path.read_bytes()
    n = int.from_bytes(b[80:84], "little")
    assert len(b) == 84 + 50 * n, f"{path}: not a binary STL"
    rec = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    return np.frombuffer(b[84:], dtype=rec)["v"].astype(np.float64)


def indexed(tri: np.ndarray):
    v, inv = np.unique(tri.reshape(-1, 3), axis=0, return_inverse=True)
    t = inv.reshape(-1, 3)
    keep = (t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 0] != t[:, 2])
    return v, t[keep]


def prepare(urdf: Path, tmp: Path):
    """The URDF text with STL references replaced by .obj copies; {obj path: (vertices, triangles)}."""
    text = urdf.read_text()
    meshes = {}
    desc = description()

    def swap(m):
        stl = desc / "meshes" / f"{m.group(1)}.STL"
        obj = tmp / f"{m.group(1)}.obj"
        if str(obj) not in meshes:
            v, t = indexed(read_stl(stl))
            with open(obj, "w") as f:
                for p in v:
                    f.write("v %r %r %r\n" % tuple(float(x) for x in p))
                for tri in t:
                    f.write("f %d %d %d\n" % tuple(int(i) + 1 for i in tri))
            meshes[str(obj)] = (v, t)
        return str(obj)

    text = re.sub(r"package://faze4_description/meshes/(\w+)\.STL", swap, text)
    out = tmp / urdf.name
    out.write_text(text)
    return out, meshes


def coal_object(shape, meshes):
    """(exact shape, convex shape, is a mesh): a mesh as its triangles and as its convex hull
    (qhull through coal); a primitive is its own hull."""
    kind = type(shape).__name__
    if kind == "Mesh":
        path = str(shape.source().path()) if hasattr(shape, "source") else shape.filename()
        v, t = meshes[path]
        m = coal.BVHModelOBBRSS()
        m.beginModel(len(t), len(v))
        m.addVertices(v)
        m.addTriangles(t.astype(np.int64))
        m.endModel()
        hull = coal.BVHModelOBBRSS()
        hull.beginModel(len(t), len(v))
        hull.addVertices(v)
        hull.addTriangles(t.astype(np.int64))
        hull.endModel()
        hull.buildConvexHull(False, "Qt")
        return m, hull.convex, True, v, t
    if kind == "Box":
        s = coal.Box(shape.width(), shape.depth(), shape.height())
    elif kind == "Cylinder":
        s = coal.Cylinder(shape.radius(), shape.length())
    elif kind == "Sphere":
        s = coal.Sphere(shape.radius())
    else:
        raise ValueError(kind)
    return s, s, False, None, None


def tight_request():
    """coal's defaults stop GJK/EPA at 1e-6 (as FCL's, which Drake uses): far too coarse to test
    1e-6 agreement on curved shapes. These run them to round-off."""
    req = coal.DistanceRequest()
    req.gjk_tolerance = 1e-13
    req.epa_tolerance = 1e-13
    req.gjk_max_iterations = 10000
    req.epa_max_iterations = 10000
    req.enable_signed_distance = True
    return req


def tf(X):
    return coal.Transform3s(X.rotation().matrix(), X.translation())


def plant_of(urdf: Path):
    """A finalised MultibodyPlant of `urdf` with its SceneGraph (no time step):
    (diagram, root context, plant, plant context); the caller keeps the first two alive."""
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlantSceneGraph(builder, 0.0)
    Parser(plant).AddModels(str(urdf))
    plant.Finalize()
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    return diagram, context, plant, plant.GetMyContextFromRoot(context)


def proximity_geometries(plant, inspector):
    """Every proximity geometry, in body order then document order: (link name, index within
    the link, geometry id)."""
    for b in range(plant.num_bodies()):
        body = plant.get_body(BodyIndex(b))
        frame = plant.GetBodyFrameIdIfExists(body.index())
        if frame is None:
            continue
        for k, g in enumerate(inspector.GetGeometries(frame, Role.kProximity)):
            yield body.name(), k, g


def run(urdf_rel: str, poses: list, labels: list, tmp: Path):
    urdf, meshes = prepare(REPO / urdf_rel, tmp)
    _diagram, _context, plant, pc = plant_of(urdf)
    qo = plant.get_geometry_query_input_port().Eval(pc)
    inspector = qo.inspector()

    # every proximity geometry as (link, index within the link, document order)
    objects, index_of, coal_of = [], {}, {}
    for link, k, g in proximity_geometries(plant, inspector):
        index_of[g] = len(objects)
        objects.append({"link": link, "index": k})
        coal_of[g] = coal_object(inspector.GetShape(g), meshes)

    out_poses, pair_list, drake_gap, fallbacks = [], None, [0.0], [0]
    for q, label in zip(poses, labels):
        plant.SetPositions(pc, q)
        qo = plant.get_geometry_query_input_port().Eval(pc)
        found = {}
        for p in qo.ComputeSignedDistancePairwiseClosestPoints(np.inf):
            a, b = index_of[p.id_A], index_of[p.id_B]
            key = (min(a, b), max(a, b))
            (oa, ca, mesh_a, _, _), (ob, cb, mesh_b, _, _) = coal_of[p.id_A], coal_of[p.id_B]
            ta, tb = tf(qo.GetPoseInWorld(p.id_A)), tf(qo.GetPoseInWorld(p.id_B))
            dres = coal.DistanceResult()
            coal.distance(ca, ta, cb, tb, tight_request(), dres)
            hull = dres.min_distance
            if not abs(hull) < 1e3:
                # coal's GJK/EPA gives up on some deep overlaps of a cylinder (±DBL_MAX): Drake's
                # value stands in (counted in the printout)
                hull = p.distance
                fallbacks[0] += 1
            drake_gap[0] = max(drake_gap[0], abs(hull - p.distance))
            if mesh_a != mesh_b:
                mesh, inter = None, None
            elif mesh_a or mesh_b:
                cres = coal.CollisionResult()
                coal.collide(oa, ta, ob, tb, coal.CollisionRequest(), cres)
                if cres.isCollision():
                    mesh, inter = 0.0, True
                else:
                    dres = coal.DistanceResult()
                    coal.distance(oa, ta, ob, tb, tight_request(), dres)
                    mesh, inter = dres.min_distance, False
            else:
                mesh, inter = hull, hull < 0
            found[key] = (hull, mesh, inter, p.distance)
        keys = sorted(found)
        if pair_list is None:
            pair_list = keys
        assert keys == pair_list, "Drake's pair list does not depend on the pose"
        out_poses.append({
            "label": label,
            "q": [float(x) for x in q],
            "hull": [found[k][0] for k in keys],
            "drake": [found[k][3] for k in keys],
            "mesh": [found[k][1] for k in keys],
            "intersecting": [found[k][2] for k in keys],
        })
    return {
        "model": urdf_rel,
        "generator": "tools/oracle/clearance_fixtures.py",
        "drake": importlib.metadata.version("drake"),
        "coal": importlib.metadata.version("coal"),
        "objects": objects,
        "pairs": [list(k) for k in pair_list],
        "drake_vs_coal_hull_max_m": drake_gap[0],
        "coal_failures_replaced_by_drake": fallbacks[0],
        "poses": out_poses,
    }, plant


def random_poses(urdf_rel, n, seed, tmp):
    urdf, _ = prepare(REPO / urdf_rel, tmp)
    _diagram, _context, plant, _ = plant_of(urdf)
    lo, hi = plant.GetPositionLowerLimits(), plant.GetPositionUpperLimits()
    lo, hi = np.maximum(lo, -np.pi), np.minimum(hi, np.pi)
    rng = np.random.default_rng(seed)
    return [lo + (hi - lo) * rng.random(len(lo)) for _ in range(n)]


def summary(fixture, a, b, field):
    objs = fixture["objects"]
    for k, (i, j) in enumerate(fixture["pairs"]):
        if {objs[i]["link"], objs[j]["link"]} == {a, b}:
            vals = [p[field][k] for p in fixture["poses"] if p["label"].startswith("circle")]
            return min(vals), max(vals)


def main():
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        circle = np.load(REPO / "tests/fixtures/shape_circle_q.npy")
        rand = random_poses("urdf/faze4_real.urdf", N_RANDOM_FAZE4, 7, tmp)
        poses = list(circle) + rand
        labels = [f"circle {k}" for k in range(len(circle))] + [f"random {k}" for k in range(len(rand))]
        faze4, _ = run("urdf/faze4_real.urdf", poses, labels, tmp)
        arm_poses = random_poses("tests/urdf/collision_arm.urdf", N_RANDOM_ARM, 11, tmp)
        arm, _ = run("tests/urdf/collision_arm.urdf", arm_poses, [f"random {k}" for k in range(N_RANDOM_ARM)], tmp)
    for name, fixture in [("faze4_real", faze4), ("collision_arm", arm)]:
        path = REPO / f"tests/fixtures/clearance_{name}.json"
        path.write_text(json.dumps(fixture, indent=1) + "\n")
        print(f"{path.relative_to(REPO)}: {len(fixture['pairs'])} pairs, {len(fixture['poses'])} poses")
    lo, hi = summary(faze4, "nadlaktica", "podlaktica", "drake")
    print(f"circle, nadlaktica-podlaktica, hulls (Drake): signed distance {lo * 1e3:.2f} .. {hi * 1e3:.2f} mm")
    lo, hi = summary(faze4, "nadlaktica", "podlaktica", "hull")
    print(f"circle, nadlaktica-podlaktica, hulls (coal): signed distance {lo * 1e3:.4f} .. {hi * 1e3:.4f} mm")
    lo, hi = summary(faze4, "nadlaktica", "podlaktica", "mesh")
    print(f"circle, nadlaktica-podlaktica, meshes (coal): distance {lo * 1e3:.4f} .. {hi * 1e3:.4f} mm")
    first = faze4["poses"][0]
    k = next(k for k, (i, j) in enumerate(faze4["pairs"]) if {faze4["objects"][i]["link"], faze4["objects"][j]["link"]} == {"nadlaktica", "podlaktica"})
    print(f"circle sample 0, nadlaktica-podlaktica: Drake {first['drake'][k] * 1e3:.2f} mm, coal hull {first['hull'][k] * 1e3:.4f} mm")
    for name, fixture in [("faze4_real", faze4), ("collision_arm", arm)]:
        print(f"{name}: Drake vs coal on the hulls, largest difference {fixture['drake_vs_coal_hull_max_m']:.2e} m"
              f" ({fixture['coal_failures_replaced_by_drake']} coal failures replaced by Drake's value)")
    inter = sum(any(p["intersecting"]) for p in arm["poses"])
    print(f"collision_arm: {inter} of {len(arm['poses'])} poses with an intersecting pair")


if __name__ == "__main__":
    main()
