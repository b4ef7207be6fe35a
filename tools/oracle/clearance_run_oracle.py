#!/usr/bin/env python3
"""coal's exact self-clearance over a whole run, against faze4's reported per-pair minimum
(`--clearance-tolerance`, docs/clearance.md "Checked against coal over a run").

    /work/venv/bin/python tools/oracle/clearance_run_oracle.py [--faze4 target/release/faze4]
        [--duration 8] [--tolerances 1,0] [--erd [--only SUBSTRING]] [--sweep PAYLOADS] [--fixtures]

What it does, per arm:

1. runs `faze4 <args> --summary S --trail T --clearance-tolerance τ` for each τ of --tolerances
   (mm). The self-clearance is measured at exactly the trail's samples (src/sim/run.rs: step 0,
   every `record_every` steps and the last step; the trail is written at the same steps with
   the same period, and its numbers are the simulation's exact values, shortest round-trip
   decimals), so the trail's q columns are the poses faze4 measured;
2. at each of those q, places every collision shape with Pinocchio's forward kinematics
   (`pin_closed_loop.PinArm`, faze4's coordinate order, mimic joints as followers) and the URDF
   `<collision><origin>`, and asks coal for each checked pair's exact value:
     mesh–mesh            coal.distance between BVHModelOBBRSS of the mesh's triangles (the file's
                          exact f32 vertices, welded by value as faze4 welds them, times the
                          URDF scale in f64), coal.collide for an intersection;
     mesh–primitive       the primitive against each triangle, a coal.Convex of its three
                          corners (coal's BVH-versus-shape distance came out below the hulls'
                          distance on the Faze4, see clearance_fixtures.py), GJK run to
                          round-off; a triangle is tried only when a lower bound of its
                          distance (its nearest corner's less its longest edge; its centroid's
                          less its radius; the tangent plane of the distance at its centroid) is
                          at most the smallest distance so far (of a corner or centroid, of a
                          triangle tried, of the pair at an earlier sample: a sample that cannot
                          hold the pair's minimum is not searched to the end);
     primitive–primitive  coal's signed distance, GJK/EPA run to round-off; intersecting when
                          coal.collide says so (faze4: when the gap is ≤ 0);
   every coal answer that is a distance is checked (its nearest points on the shapes within
   1e-9 m, that far apart) and a contact confirmed by coal.collide; else the next GJK variant
   is asked (GJK_VARIANTS), and a pair coal never answers at a sample is listed as not checked;
   the pair's exact minimum over the samples is the smallest of these;
3. compares with the summary's `clearance.pairs` (the pairs faze4 checks, in its order: the
   pairs are read from the summary, so the filtering is faze4's; a link with several shapes
   has one entry per pair of shapes, in document order): each pair's reported `min_m` R is
   the distance of two actual parts at one sample, and the true minimum E is at least R − τ, so
       E ≤ R + slack     and     R − τ ≤ E + slack,
   and the pair intersected in faze4's run exactly when coal finds it intersecting at a sample.
   slack is SLACK_EXACT (1e-9 m) for meshes, boxes and spheres (coal's triangle distances are
   closed-form, GJK is exact on polytopes and spheres), and SLACK_GJK (1e-5 m) for a pair with
   a cylinder (GJK and EPA on a curved surface converge slowly: faze4's parry and coal agree
   to a few µm there, docs/clearance.md "Agreement with the oracle"). The penetration depth of
   two primitives one of which is a cylinder is not compared (coal's EPA there gives up, or
   answers 0 for shapes that coal.collide finds overlapping): only that they intersect.

Arms: the bundled Faze4 (`faze4 wave`, geometry of urdf/faze4_real.urdf and the meshes of
assets/faze4_description); with --erd every fixed-base arm of example-robot-data that
tools/robots_survey.py runs (`wave --center mid`, same URDFs). --duration shortens every run.

--sweep PAYLOADS checks sweeps instead (docs/clearance.md "Sweeps"): per arm and tolerance,
`faze4 sweep --vary payload-kg=PAYLOADS --trails DIR --out T.json -- <args>` (whose rows follow one
commanded path's clearance, computed once), and per row coal's exact minimum of every checked
pair over the row's own trail. The table gives the clearance of the closest pair only, so per
row: the reported `clearance_min_m` R is an actual distance of the pair of links it names
(coal's minimum of that pair E_l ≤ R + slack) and at most τ above the smallest of all pairs
(R − τ ≤ E + slack); and the verdict names the pairs of links that coal finds intersecting, in
the order they first do, from the same sample (the first three by name and time, the others
counted). Without --erd the arms are the Faze4 wave and the Faze4 folding into itself
(`--amp-deg 90 --freq 2`, intersecting pairs).

--fixtures writes tests/fixtures/clearance_run_*.json for tests/it/clearance_run_oracle.rs: the
faze4 arguments, the trail's q rows, and per pair its links, kind, coal's exact minimum and
whether it intersects (the Rust test reruns the binary and checks the same inequalities at
the default tolerance and at 0).

Prints a Markdown table: arm, tolerance, pairs checked, the worst pair (faze4 min, coal min,
difference R − E), the tolerance, the verdict, the pairs coal could not check, and the time
coal took. Exit status 1 when a check fails.
"""
import argparse
import csv
import glob
import importlib.metadata
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import coal
import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(REPO, "tools"))
from clearance_fixtures import tight_request  # noqa: E402
from pin_closed_loop import PinArm  # noqa: E402

SHARE = os.path.realpath(os.path.join(os.path.dirname(pin.__file__), "..", "..", "..", "..", "share"))
ROBOTS = os.path.join(SHARE, "example-robot-data", "robots")
SLACK_EXACT = 1e-9
# GJK/EPA with a box, cylinder or sphere: parry (faze4) and coal (tolerance 1e-13) agree within
# 3e-6 m apart and 1e-5 m penetrating on our primitive arm (docs/clearance.md)
SLACK_GJK = 1e-5
# coal.collide is asked only when a pair is closer than this (a distance above it is apart)
TOUCH = 1e-6


# ------------------------------------------------------------------------------------------
# The URDF's collision elements, as faze4 reads them
# ------------------------------------------------------------------------------------------

def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def origin_of(el):
    X = np.eye(4)
    o = el.find("origin")
    if o is not None:
        xyz = [float(v) for v in o.get("xyz", "0 0 0").split()]
        rpy = [float(v) for v in o.get("rpy", "0 0 0").split()]
        X[:3, :3] = rpy_matrix(*rpy)
        X[:3, 3] = xyz
    return X


def resolve(uri, urdf, package_dirs):
    """The file a mesh reference names (package:// searched in package_dirs), or None."""
    if uri.startswith("package://"):
        rest = uri[len("package://"):]
        for d in package_dirs:
            p = os.path.join(d, rest)
            if os.path.isfile(p):
                return p
        return None
    if uri.startswith("file://"):
        uri = uri[len("file://"):]
    p = uri if os.path.isabs(uri) else os.path.join(os.path.dirname(urdf), uri)
    return p if os.path.isfile(p) else None


def collisions(urdf, package_dirs):
    """{link: [shape, ...]} in document order; a shape is a dict (kind, origin, ...)."""
    root = ET.parse(urdf).getroot()
    out = {}
    for link in root.findall("link"):
        shapes = []
        for c in link.findall("collision"):
            g = c.find("geometry")
            s = {"origin": origin_of(c)}
            if g.find("box") is not None:
                s.update(kind="box", size=[float(v) for v in g.find("box").get("size").split()])
            elif g.find("cylinder") is not None:
                e = g.find("cylinder")
                s.update(kind="cylinder", radius=float(e.get("radius")), length=float(e.get("length")))
            elif g.find("sphere") is not None:
                s.update(kind="sphere", radius=float(g.find("sphere").get("radius")))
            elif g.find("mesh") is not None:
                e = g.find("mesh")
                s.update(kind="mesh", uri=e.get("filename"), path=resolve(e.get("filename"), urdf, package_dirs),
                         scale=[float(v) for v in e.get("scale", "1 1 1").split()])
            else:
                raise ValueError(f"{urdf}: link {link.get('name')}: unknown collision geometry")
            shapes.append(s)
        out[link.get("name")] = shapes
    return out


# ------------------------------------------------------------------------------------------
# Meshes: the file's f32 corners, welded by value (geometry/mesh.rs, Mesh::from_soup)
# ------------------------------------------------------------------------------------------

def stl_corners(path):
    b = open(path, "rb").read()
    if len(b) >= 84:
        n = int.from_bytes(b[80:84], "little")
        if len(b) == 84 + 50 * n:
            rec = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
            return np.frombuffer(b[84:], dtype=rec)["v"].reshape(-1, 3)
    text = b.decode("ascii", "replace")
    vals = re.findall(r"vertex\s+(\S+)\s+(\S+)\s+(\S+)", text)
    return np.array([[float(x) for x in v] for v in vals], dtype=np.float64).astype(np.float32)


def dae_corners(path):
    """COLLADA: every <instance_geometry> of the visual scene, its triangles (<triangles>,
    <polylist> of triangles) with the node transforms and <unit meter> applied. The transforms
    are applied in float64 and rounded to f32 (mesh-loader's own arithmetic is f32): exact only
    for identity transforms and unit 1, which is what example-robot-data's arms have."""
    tree = ET.parse(path).getroot()
    ns = {"c": tree.tag.split("}")[0].strip("{")} if tree.tag.startswith("{") else {"c": ""}
    q = (lambda t: f"c:{t}") if ns["c"] else (lambda t: t)
    unit = tree.find(f"{q('asset')}/{q('unit')}", ns)
    meter = float(unit.get("meter", "1")) if unit is not None else 1.0
    sources = {}
    geoms = {}
    for geom in tree.iter(f"{{{ns['c']}}}geometry" if ns["c"] else "geometry"):
        mesh = geom.find(q("mesh"), ns)
        if mesh is None:
            continue
        for src in mesh.findall(q("source"), ns):
            fa = src.find(q("float_array"), ns)
            if fa is not None:
                sources[src.get("id")] = np.array([float(x) for x in fa.text.split()]).reshape(-1, 3)
        vert_of = {}
        for v in mesh.findall(q("vertices"), ns):
            for inp in v.findall(q("input"), ns):
                if inp.get("semantic") == "POSITION":
                    vert_of[v.get("id")] = inp.get("source").lstrip("#")
        corners = []
        for prim in list(mesh.findall(q("triangles"), ns)) + list(mesh.findall(q("polylist"), ns)):
            inputs = prim.findall(q("input"), ns)
            stride = max(int(i.get("offset")) for i in inputs) + 1
            vin = next(i for i in inputs if i.get("semantic") == "VERTEX")
            pos = sources[vert_of[vin.get("source").lstrip("#")]]
            idx = np.array([int(x) for x in prim.find(q("p"), ns).text.split()]).reshape(-1, stride)[:, int(vin.get("offset"))]
            if prim.tag.endswith("polylist"):
                vc = [int(x) for x in prim.find(q("vcount"), ns).text.split()]
                assert all(c == 3 for c in vc), f"{path}: polygons other than triangles"
            corners.append(pos[idx])
        geoms[geom.get("id")] = np.concatenate(corners) if corners else np.zeros((0, 3))
    out = []

    def walk(node, X):
        for m in node.findall(q("matrix"), ns):
            X = X @ np.array([float(x) for x in m.text.split()]).reshape(4, 4)
        for t in node.findall(q("translate"), ns):
            T = np.eye(4)
            T[:3, 3] = [float(x) for x in t.text.split()]
            X = X @ T
        assert node.find(q("rotate"), ns) is None and node.find(q("scale"), ns) is None, f"{path}: rotate/scale nodes"
        for ig in node.findall(q("instance_geometry"), ns):
            c = geoms[ig.get("url").lstrip("#")]
            out.append((c @ X[:3, :3].T + X[:3, 3]) * meter)
        for child in node.findall(q("node"), ns):
            walk(child, X)

    for vs in tree.iter(f"{{{ns['c']}}}visual_scene" if ns["c"] else "visual_scene"):
        for node in vs.findall(q("node"), ns):
            walk(node, np.eye(4))
    return np.concatenate(out).astype(np.float32)


def weld(corners):
    """(vertices (n, 3) float64, triangles (m, 3)): bit-identical f32 positions welded (−0 = 0),
    triangles whose corners weld together dropped; vertices in first-seen order."""
    c = np.ascontiguousarray(corners, dtype=np.float32) + np.float32(0.0)
    keys = c.view(np.uint32).reshape(-1, 3)
    _, first, inv = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    t = rank[inv.reshape(-1)].reshape(-1, 3)
    keep = (t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 0] != t[:, 2])
    return c[first[order]].astype(np.float64), t[keep]


MESHES = {}


def read_mesh(path, scale):
    key = (path, tuple(scale))
    if key not in MESHES:
        ext = os.path.splitext(path)[1].lower()
        if ext == ".stl":
            corners = stl_corners(path)
        elif ext == ".dae":
            corners = dae_corners(path)
        else:
            raise ValueError(f"{path}: this oracle reads STL and COLLADA meshes")
        v, t = weld(corners)
        v = v * np.array(scale, dtype=np.float64)
        m = coal.BVHModelOBBRSS()
        m.beginModel(len(t), len(v))
        m.addVertices(v)
        m.addTriangles(t.astype(np.int64))
        m.endModel()
        tri = v[t]
        longest_edge = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=-1).max(axis=1)
        MESHES[key] = (v, t, m, longest_edge)
    return MESHES[key]


# ------------------------------------------------------------------------------------------
# Shapes and pairs in coal
# ------------------------------------------------------------------------------------------

# GJK/EPA to 1e-13, signed distances (clearance_fixtures.py's request)
REQ = tight_request()
# (GJK variant, convergence criterion, tolerance) asked in turn until one gives a checked answer
# (see dist): the duality gap bounds the answer's error, but on two boxes it never closes to 1e-13
# (coal gives up), where van den Bergen's criterion (coal's default) stops at the exact answer
_V, _C = coal.GJKVariant, coal.GJKConvergenceCriterion
GJK_VARIANTS = [(_V.DefaultGJK, _C.DualityGap, 1e-13), (_V.DefaultGJK, _C.Default, 1e-13),
                (_V.NesterovAcceleration, _C.DualityGap, 1e-13), (_V.PolyakAcceleration, _C.DualityGap, 1e-13),
                (_V.NesterovAcceleration, _C.Default, 1e-13), (_V.DefaultGJK, _C.DualityGap, 1e-10)]
MESH_REQ = coal.DistanceRequest()


def primitive(s):
    if s["kind"] == "box":
        return coal.Box(*s["size"])
    if s["kind"] == "cylinder":
        return coal.Cylinder(s["radius"], s["length"])
    return coal.Sphere(s["radius"])


def closest_point(s, p):
    """The point of primitive s nearest each of the points p (n, 3, primitive's frame)."""
    if s["kind"] == "box":
        h = np.array(s["size"]) / 2
        return np.clip(p, -h, h)
    if s["kind"] == "sphere":
        n = np.linalg.norm(p, axis=-1, keepdims=True)
        return np.where(n > s["radius"], p * (s["radius"] / np.maximum(n, 1e-300)), p)
    rho = np.hypot(p[..., 0], p[..., 1])[..., None]
    xy = np.where(rho > s["radius"], p[..., :2] * (s["radius"] / np.maximum(rho, 1e-300)), p[..., :2])
    z = np.clip(p[..., 2:], -s["length"] / 2, s["length"] / 2)
    return np.concatenate([xy, z], axis=-1)


def point_distance(s, p):
    """Distance (≥ 0, 0 inside) from points p (n, 3, primitive's frame) to primitive s."""
    return np.linalg.norm(p - closest_point(s, p), axis=-1)


def transform(X):
    return coal.Transform3s(X[:3, :3].copy(), X[:3, 3].copy())


def dist(o1, X1, o2, X2, req, stats=None, inside1=None, inside2=None):
    """coal's distance. With `inside1`/`inside2` (the distance from a point, in the object's own
    frame, to the object) an answer whose nearest points are not on the objects (within 1e-9 m)
    or not that far apart is refused: coal's default GJK once returned 0.112 m for a sliver
    triangle and the Faze4's base cylinder, 0.155 m apart (its point on the cylinder was 32 mm
    off it), once 0 for two shapes 0.47 m apart, and sometimes gives up (±DBL_MAX): a contact
    (d ≤ 0) must be confirmed by coal.collide. Each GJK variant of GJK_VARIANTS is asked in
    turn; NaN (counted in stats["failed"]) when none gives a checked answer."""
    for variant, criterion, tolerance in GJK_VARIANTS:
        req.gjk_variant = variant
        req.gjk_convergence_criterion = criterion
        req.gjk_tolerance = tolerance
        r = coal.DistanceResult()
        coal.distance(o1, transform(X1), o2, transform(X2), req, r)
        d = r.min_distance
        ok = abs(d) < 1e3
        if ok and d > 0 and inside1 is not None:
            p1, p2 = r.getNearestPoint1(), r.getNearestPoint2()
            l1 = np.linalg.solve(X1, np.append(p1, 1.0))[:3]
            l2 = np.linalg.solve(X2, np.append(p2, 1.0))[:3]
            ok = inside1(l1) <= 1e-9 and inside2(l2) <= 1e-9 and abs(np.linalg.norm(p1 - p2) - d) <= 1e-12
        elif ok and d <= 0 and inside1 is not None:  # a contact that coal.collide must confirm
            ok = collide(o1, X1, o2, X2)
        if ok:
            return d
        if stats is not None:
            stats["retried"] += 1
    if stats is not None:
        stats["failed"] += 1
    return math.nan


def triangle_point_distance(tri, p):
    """Distance from point p to the triangle with corners tri (3, 3) (Ericson, Real-Time
    Collision Detection, 5.1.5)."""
    a, b, c = tri
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = ab @ ap, ac @ ap
    if d1 <= 0 and d2 <= 0:
        return np.linalg.norm(p - a)
    bp = p - b
    d3, d4 = ab @ bp, ac @ bp
    if d3 >= 0 and d4 <= d3:
        return np.linalg.norm(p - b)
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        return np.linalg.norm(p - (a + d1 / (d1 - d3) * ab))
    cp = p - c
    d5, d6 = ab @ cp, ac @ cp
    if d6 >= 0 and d5 <= d6:
        return np.linalg.norm(p - c)
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        return np.linalg.norm(p - (a + d2 / (d2 - d6) * ac))
    va = d3 * d6 - d5 * d4
    if va <= 0 and (d4 - d3) >= 0 and (d5 - d6) >= 0:
        return np.linalg.norm(p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b)))
    denom = 1.0 / (va + vb + vc)
    return np.linalg.norm(p - (a + ab * vb * denom + ac * vc * denom))


def collide(o1, X1, o2, X2):
    r = coal.CollisionResult()
    coal.collide(o1, transform(X1), o2, transform(X2), coal.CollisionRequest(), r)
    return r.isCollision()


def triangle(corners):
    """One triangle as a coal.Convex (coal has no distance between a TriangleP and a box,
    cylinder or sphere)."""
    pts = coal.StdVec_Vec3s()
    for c in corners:
        pts.append(np.array(c, dtype=np.float64))
    tris = coal.StdVec_Triangle()
    tris.append(coal.Triangle(0, 1, 2))
    return coal.Convex(pts, tris)


def mesh_primitive(mesh, Xm, s, Xs, bound, stats):
    """(distance, intersecting) of a mesh (v, t, BVH, longest edges) at Xm and primitive s at Xs, exact when
    below `bound` (else some value ≥ bound: the sample cannot hold the pair's minimum)."""
    v, t = mesh[0], mesh[1]
    X = np.linalg.solve(Xs, Xm)  # mesh frame -> primitive frame
    # the mesh's bounding sphere (about its box's centre) first
    lo, hi = v.min(axis=0), v.max(axis=0)
    c = X[:3, :3] @ ((lo + hi) / 2) + X[:3, 3]
    far = float(point_distance(s, c[None])[0]) - np.linalg.norm(hi - lo) / 2
    if far > bound:
        return far, False
    p = v @ X[:3, :3].T + X[:3, 3]
    d_vert = point_distance(s, p)
    upper = float(d_vert.min())
    if upper <= 0.0:  # a corner inside the primitive: they touch
        return 0.0, True
    # f ≥ f(corner) − the triangle's longest edge, first
    first = d_vert[t].min(axis=1) - mesh[3]
    keep = np.nonzero(first <= min(upper, bound))[0]
    if len(keep) == 0:  # every triangle is beyond the bound
        return float(first.min()), False
    tri = p[t[keep]]  # (m, 3, 3)
    # lower bounds of each triangle's distance: the distance f to a convex set is convex and
    # 1-Lipschitz, so over the triangle f ≥ f(c) − (its radius about the centroid c) and
    # f ≥ f(c) + ∇f(c)·(x − c) ≥ f(c) + min over the corners of ∇f(c)·(v − c)
    centre = tri.mean(axis=1)
    radius = np.linalg.norm(tri - centre[:, None, :], axis=-1).max(axis=1)
    near = closest_point(s, centre)
    fc = np.linalg.norm(centre - near, axis=-1)
    grad = (centre - near) / np.maximum(fc, 1e-300)[:, None]
    tangent = fc + np.einsum("mk,mjk->mj", grad, tri - centre[:, None, :]).min(axis=1)
    lower = np.where(fc > 0, np.maximum(fc - radius, tangent), fc - radius)
    upper = min(upper, float(fc.min()))
    cand = np.nonzero(lower <= min(upper, bound))[0]
    shape = primitive(s)
    eye = np.eye(4)
    best, inter = upper, False
    for i in cand[np.argsort(lower[cand])]:
        if lower[i] > min(best, bound):
            break
        stats["triangles"] += 1
        tp = triangle(tri[i])
        d = dist(tp, eye, shape, eye, REQ, stats, lambda x, c=tri[i]: triangle_point_distance(c, x),
                 lambda x: point_distance(s, x))
        if math.isnan(d):
            return math.nan, False
        if d <= TOUCH and collide(tp, eye, shape, eye):
            return 0.0, True
        best = min(best, max(d, 0.0))
    return best, inter


class Shape:
    def __init__(self, link, index, s):
        self.link, self.index, self.s = link, index, s
        self.mesh = read_mesh(s["path"], s["scale"]) if s["kind"] == "mesh" else None
        self.coal = self.mesh[2] if self.mesh else primitive(s)


def pair_kind(a, b):
    if a.mesh is not None and b.mesh is not None:
        return "mesh-mesh"
    if a.mesh is not None or b.mesh is not None:
        return "mesh-primitive"
    return "primitive-primitive"


def pair_value(a, Xa, b, Xb, bound, stats):
    """(distance, intersecting) at one sample, exact when below `bound` (the pair's smallest
    so far): the exact value faze4 is compared with. NaN when coal gives up."""
    kind = pair_kind(a, b)
    if kind == "mesh-mesh":
        d = dist(a.coal, Xa, b.coal, Xb, MESH_REQ, stats)
        if d <= TOUCH and collide(a.coal, Xa, b.coal, Xb):
            return 0.0, True
        return d, False
    if kind == "mesh-primitive":
        if a.mesh is not None:
            return mesh_primitive(a.mesh, Xa, b.s, Xb, bound, stats)
        return mesh_primitive(b.mesh, Xb, a.s, Xa, bound, stats)
    d = dist(a.coal, Xa, b.coal, Xb, REQ, stats, lambda x: point_distance(a.s, x), lambda x: point_distance(b.s, x))
    if d <= TOUCH and collide(a.coal, Xa, b.coal, Xb):
        return min(d, 0.0), True
    return d, False


# ------------------------------------------------------------------------------------------
# One run
# ------------------------------------------------------------------------------------------

def run_faze4(faze4, args, tolerance_mm, tmp):
    summary, trail = os.path.join(tmp, "s.json"), os.path.join(tmp, "t.csv")
    cmd = [faze4, *args, "--quiet", "--summary", summary, "--trail", trail]
    if tolerance_mm is not None:
        cmd += ["--clearance-tolerance", repr(tolerance_mm)]
    t0 = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    wall = time.time() - t0
    if r.returncode not in (0, 3):
        last = (r.stderr.strip().splitlines() or ["?"])[-1]
        raise RuntimeError(f"faze4 exit {r.returncode}: {last[-200:]}")
    s = json.load(open(summary))
    with open(trail) as f:
        rows = list(csv.reader(f))
    header = rows[0]
    qcols = [i for i, h in enumerate(header) if re.fullmatch(r"q\d+", h)]
    table = [[float(r[i]) for i in [0] + qcols] for r in rows[1:]]
    return s, np.array(table), wall


def match_pairs(report_pairs, shapes_of):
    """faze4's summary pairs (in its order; a link with several shapes gives one entry per
    pair of shapes, in document order) -> [(shape a, shape b)]."""
    groups = {}
    for k, p in enumerate(report_pairs):
        groups.setdefault(tuple(p["links"]), []).append(k)
    out = [None] * len(report_pairs)
    for (la, lb), ks in groups.items():
        sa, sb = shapes_of[la], shapes_of[lb]
        combos = [(x, y) for x in sa for y in sb]
        if len(combos) != len(ks):
            raise RuntimeError(f"{la}-{lb}: faze4 reports {len(ks)} pairs, the URDF has {len(combos)} shape pairs")
        for k, c in zip(ks, combos):
            out[k] = c
    return out


def exact_over_samples(arm, pairs, samples, times):
    """Per pair: (exact minimum, its time, intersecting at some sample, samples coal gave up
    on, time of the first intersecting sample or None); and coal's counts."""
    stats = {"queries": 0, "triangles": 0, "retried": 0, "failed": 0}
    links = sorted({s.link for pr in pairs for s in pr})
    best = [[math.inf, None, False, 0, None] for _ in pairs]
    for q, t in zip(samples, times):
        poses = arm.frame_poses(q)
        world = {ln: poses[ln] for ln in links}
        for k, (a, b) in enumerate(pairs):
            Xa, Xb = world[a.link] @ a.s["origin"], world[b.link] @ b.s["origin"]
            d, inter = pair_value(a, Xa, b, Xb, best[k][0], stats)
            stats["queries"] += 1
            if math.isnan(d):
                best[k][3] += 1
                continue
            if d < best[k][0]:
                best[k][:2] = d, t
            best[k][2] |= bool(inter)
            if inter and best[k][4] is None:
                best[k][4] = t
    return [tuple(b) for b in best], stats


class Arm:
    def __init__(self, name, args, urdf, package_dirs):
        self.name, self.args, self.urdf, self.package_dirs = name, args, urdf, package_dirs


def faze4_arm(duration, extra=()):
    return Arm("faze4 wave" + "".join(" " + e for e in extra), ["wave", *extra, "--duration", repr(duration)],
               os.path.join(REPO, "urdf/faze4_real.urdf"), [os.path.join(REPO, "assets")])


def erd_arms(duration):
    import robots_survey  # noqa: E402 - the survey's list of arms
    arms = []
    for folder in sorted(os.listdir(ROBOTS)):
        if folder not in robots_survey.FIXED:
            continue
        for urdf in sorted(glob.glob(os.path.join(ROBOTS, folder, "**", "*.urdf"), recursive=True)):
            arms.append(Arm(os.path.relpath(urdf, ROBOTS),
                            ["wave", "--urdf", urdf, "--package-path", SHARE, "--center", "mid",
                             "--duration", repr(duration)], urdf, [SHARE]))
    return arms


def check(arm, faze4, tolerance_mm, tmp):
    """One run at one tolerance: the rows of the table, and the fixture's content."""
    s, table, wall = run_faze4(faze4, arm.args, tolerance_mm, tmp)
    c = s.get("clearance")
    if not c or not c["pairs"]:
        return {"arm": arm.name, "note": "no pair checked" if c else "no collision geometry"}, None
    tau = c["tolerance_m"]
    shapes_of = {}
    for link, ss in collisions(arm.urdf, arm.package_dirs).items():
        found = [(k, x) for k, x in enumerate(ss) if x["kind"] != "mesh" or x["path"]]
        shapes_of[link] = [Shape(link, k, x) for k, x in found]
    pin_arm = PinArm(arm.urdf, mimic=True)
    pairs = match_pairs(c["pairs"], shapes_of)
    t0 = time.time()
    exact, stats = exact_over_samples(pin_arm, pairs, table[:, 1:], table[:, 0])
    coal_s = time.time() - t0
    rows, worst, failures, gave_up, depth_unchecked = [], {}, [], [], 0
    for p, (a, b), (e, te, ei, failed, _) in zip(c["pairs"], pairs, exact):
        kind = pair_kind(a, b)
        curved = "cylinder" in (a.s["kind"], b.s["kind"])
        slack = SLACK_GJK if curved else SLACK_EXACT
        r = p["min_m"]
        fi = bool(p.get("intersecting", False))
        if failed:
            gave_up.append(f"{a.link}–{b.link} (coal gave up at {failed} of {len(table)} samples)")
            continue
        if ei and curved and kind == "primitive-primitive":
            # a penetration depth with a cylinder (EPA): coal's is not trusted (it gives up, or
            # answers 0 for shapes coal.collide finds overlapping); only the intersection and
            # the sign of faze4's minimum are checked
            e = None
            ok = fi and r <= 0.0
        else:
            ok = e <= r + slack and r - tau <= e + slack and fi == ei
        if not ok:
            failures.append(f"{a.link}[{a.index}]–{b.link}[{b.index}] ({kind}): faze4 {r!r}{' intersecting' if fi else ''},"
                            f" coal {e!r}{' intersecting' if ei else ''} at t = {te}")
        if e is not None:
            diff = r - e
            if kind not in worst or abs(diff) > abs(worst[kind][2]):
                worst[kind] = (f"{a.link}–{b.link}", r, diff, e)
        else:
            depth_unchecked += 1
        rows.append({"links": p["links"], "shapes": [a.index, b.index], "kind": kind, "exact_min_m": e,
                     "exact_t": te, "intersecting": ei, "slack_m": slack, "faze4_min_m": r})
    result = {
        "arm": arm.name, "tolerance_m": tau, "gave_up": gave_up, "pairs": len(rows), "samples": len(table), "worst": worst,
        "failures": failures, "intersecting": sum(r["intersecting"] for r in rows),
        "kinds": sorted({r["kind"] for r in rows}), "coal_s": coal_s, "faze4_s": wall, "stats": stats,
        "unchecked": [f"{ln} (mesh not found)" for ln in c.get("unchecked", [])] + gave_up
        + ([f"{depth_unchecked} intersecting pairs with a cylinder: depth not compared"] if depth_unchecked else []),
    }
    fixture = {"args": arm.args, "q": table[:, 1:].tolist(), "t": table[:, 0].tolist(), "pairs": rows}
    return result, fixture


# ------------------------------------------------------------------------------------------
# A sweep (--sweep): each row against coal over its own trail
# ------------------------------------------------------------------------------------------

def run_sweep(faze4, args, payloads, tolerance_mm, tmp):
    """`faze4 sweep --vary payload-kg=PAYLOADS --trails DIR --out T.json -- ARGS`: its rows and
    each row's trail as [[t, q...]]."""
    trails, table = os.path.join(tmp, "trails"), os.path.join(tmp, "t.json")
    os.makedirs(trails)
    base = [*args] + (["--clearance-tolerance", repr(tolerance_mm)] if tolerance_mm is not None else [])
    cmd = [faze4, "sweep", "--vary", f"payload-kg={payloads}", "--trails", trails, "--out", table, "-q", "--", *base]
    t0 = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    wall = time.time() - t0
    if r.returncode != 0:
        last = (r.stderr.strip().splitlines() or ["?"])[-1]
        raise RuntimeError(f"faze4 sweep exit {r.returncode}: {last[-200:]}")
    rows = json.load(open(table))
    tables = []
    for row in rows:
        with open(os.path.join(trails, f"run_{row['run']:07d}.csv")) as f:
            lines = list(csv.reader(f))
        qcols = [i for i, h in enumerate(lines[0]) if re.fullmatch(r"q\d+", h)]
        tables.append(np.array([[float(x[i]) for i in [0] + qcols] for x in lines[1:]]))
    return rows, tables, wall


def intersections_named(reasons):
    """The verdict's intersecting pairs of links as the sweep's `reasons` name them: [(link a,
    link b, from t text)] and how many more pairs it only counts."""
    named = re.findall(r"'([^']+)'–'([^']+)' intersect from t = ([0-9.]+) s", reasons)
    more = re.search(r"\(and (\d+) more pairs?\)", reasons)
    return named, int(more.group(1)) if more else 0


def check_sweep(arm, faze4, tolerance_mm, payloads, tmp):
    """A sweep of `arm` over the payloads: per row, coal's exact minimum of every checked pair
    over the row's own trail. The row's `clearance_min_m` R is an actual distance of the pair of
    links it names (coal's minimum of that link pair E_l ≤ R + slack) and at most τ above the
    smallest of all (R − τ ≤ E + slack); its verdict names the pairs of links coal finds
    intersecting, in the order they first do, with the same first times."""
    s, _, _ = run_faze4(faze4, arm.args, tolerance_mm, tmp)
    c = s.get("clearance")
    if not c or not c["pairs"]:
        return {"arm": arm.name + " (sweep)", "note": "no pair checked" if c else "no collision geometry"}
    shapes_of = {}
    for link, ss in collisions(arm.urdf, arm.package_dirs).items():
        found = [(k, x) for k, x in enumerate(ss) if x["kind"] != "mesh" or x["path"]]
        shapes_of[link] = [Shape(link, k, x) for k, x in found]
    pin_arm = PinArm(arm.urdf, mimic=True)
    pairs = match_pairs(c["pairs"], shapes_of)
    rows, tables, wall = run_sweep(faze4, arm.args, payloads, tolerance_mm, tmp)
    failures, worst, coal_s, samples, intersecting = [], {}, 0.0, 0, 0
    totals = {"queries": 0, "triangles": 0, "retried": 0, "failed": 0}
    for row, table in zip(rows, tables):
        t0 = time.time()
        exact, stats = exact_over_samples(pin_arm, pairs, table[:, 1:], table[:, 0])
        coal_s += time.time() - t0
        samples += len(table)
        for key in totals:
            totals[key] += stats[key]
        where = f"payload {row['payload-kg']}"
        if any(x[3] for x in exact):
            failures.append(f"{where}: coal gave up at some samples")
            continue
        tau, r = row["clearance_tolerance_m"], row["clearance_min_m"]
        slack = max(SLACK_GJK if "cylinder" in (a.s["kind"], b.s["kind"]) else SLACK_EXACT for a, b in pairs)
        e = min(x[0] for x in exact)
        named = (row["clearance_links_1"], row["clearance_links_2"])
        e_named = min(x[0] for p, x in zip(c["pairs"], exact) if tuple(p["links"]) == named)
        curved_depth = e < 0 and slack == SLACK_GJK
        if not (e_named <= r + slack and (curved_depth or r - tau <= e + slack)):
            failures.append(f"{where}: faze4 {r!r} ({named[0]}–{named[1]}), coal {e_named!r} for that pair, {e!r} overall")
        diff = r - e
        if "overall" not in worst or abs(diff) > abs(worst["overall"][2]):
            worst["overall"] = (f"{named[0]}–{named[1]} at {where}", r, diff, e)
        # the verdict's pairs of links, by their first intersecting sample (pair order among equals)
        first = {}
        for k, (p, x) in enumerate(zip(c["pairs"], exact)):
            if x[4] is not None:
                links = tuple(p["links"])
                if links not in first or (x[4], k) < first[links]:
                    first[links] = (x[4], k)
        order = sorted(first.items(), key=lambda item: item[1])
        intersecting += len(order)
        named_pairs, more = intersections_named(row["reasons"])
        expected = [(a, b, f"{t:.2f}") for (a, b), (t, _) in order[:3]]
        if named_pairs != expected or len(named_pairs) + more != len(order):
            failures.append(f"{where}: faze4's verdict names {named_pairs} (and {more} more), coal finds {expected}"
                            f" ({len(order)} pairs of links)")
    return {"arm": arm.name + f" (sweep, {len(rows)} rows: payload-kg {payloads})", "tolerance_m": rows[0]["clearance_tolerance_m"],
            "pairs": len(pairs), "samples": samples, "worst": worst, "failures": failures, "intersecting": intersecting,
            "coal_s": coal_s, "faze4_s": wall, "stats": totals, "unchecked": [], "gave_up": []}


def print_row(r):
    if "note" in r:
        print(f"| {r['arm']} | – | – | – | – | {r['note']} | – | – |", flush=True)
        return
    verdict = "ok" if not r["failures"] else "FAIL: " + "; ".join(r["failures"][:3])
    unchecked = ", ".join(r["unchecked"]) or "none"
    worst = "; ".join(f"{kind}: {name} {fmin * 1e3:.6f} / {emin * 1e3:.6f} ({diff:+.1e})"
                      for kind, (name, fmin, diff, emin) in sorted(r["worst"].items()))
    print(f"| {r['arm']} | {r['tolerance_m'] * 1e3:g} mm | {r['pairs']} | {r['intersecting']} | {worst} |"
          f" {verdict} | {unchecked} | {r['samples']} samples, {r['stats']['queries']} queries,"
          f" {r['stats']['triangles']} triangle GJKs ({r['stats']['retried']} retried): {r['coal_s']:.1f} s"
          f" (faze4 {r['faze4_s']:.1f} s) |", flush=True)


FIXTURES = [
    # mesh pairs (and the base cylinder against the meshes)
    ("faze4_wave", lambda: faze4_arm(2.0)),
    # the Faze4 folding into itself: meshes that intersect
    ("faze4_fold", lambda: faze4_arm(2.0, ("--amp-deg", "90", "--freq", "2"))),
    # primitive pairs: boxes, cylinders, spheres, every pair (intersecting ones too)
    ("collision_arm", lambda: Arm("collision_arm wave", ["wave", "--urdf", os.path.join(REPO, "tests/urdf/collision_arm.urdf"),
                                                         "--collision-pairs", "all", "--amp-deg", "60", "--duration", "2"],
                                  os.path.join(REPO, "tests/urdf/collision_arm.urdf"), [])),
]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--faze4", default=os.path.join(REPO, "target/release/faze4"))
    ap.add_argument("--duration", type=float, default=8.0)
    ap.add_argument("--tolerances", default="1,0", help="mm, comma-separated; 'default' leaves the option out")
    ap.add_argument("--erd", action="store_true", help="every example-robot-data arm of tools/robots_survey.py")
    ap.add_argument("--only", default="", help="with --erd: only the URDFs whose path contains this")
    ap.add_argument("--fixtures", action="store_true", help="write tests/fixtures/clearance_run_*.json")
    ap.add_argument("--sweep", default="", metavar="PAYLOADS",
                    help="check `faze4 sweep --vary payload-kg=PAYLOADS` row by row instead of single runs"
                         " (the Faze4 wave and its folding wave, or with --erd each arm)")
    args = ap.parse_args()
    tolerances = [None if x == "default" else float(x) for x in args.tolerances.split(",")]
    print("| arm | tolerance | pairs checked | intersecting | largest faze4 − coal per kind: pair, faze4 / coal (mm)"
          " (difference, m) | verdict | not checked | coal's time |")
    print("|---|---|---|---|---|---|---|---|")
    failed = False
    if args.fixtures:
        versions = {p: importlib.metadata.version(p) for p in ("coal", "pin")}
        for name, make in FIXTURES:
            arm = make()
            fixture = None
            for tol in tolerances:
                with tempfile.TemporaryDirectory() as tmp:
                    result, run = check(arm, args.faze4, tol, tmp)
                print_row(result)
                failed |= bool(result["failures"] or result["gave_up"])
                # the tolerance changes what is reported, never the run: the same samples
                assert fixture is None or (fixture["q"], fixture["t"]) == (run["q"], run["t"])
                fixture = run
            args_rel = [os.path.relpath(a, REPO) if os.path.isabs(a) else a for a in fixture["args"]]
            out = {"generator": "tools/oracle/clearance_run_oracle.py", **versions, "args": args_rel,
                   "t": fixture["t"], "q": fixture["q"],
                   "pairs": [{k: v for k, v in p.items() if k != "faze4_min_m"} for p in fixture["pairs"]]}
            path = os.path.join(REPO, f"tests/fixtures/clearance_run_{name}.json")
            with open(path, "w") as f:
                json.dump(out, f, indent=1)
                f.write("\n")
            print(f"  -> {os.path.relpath(path, REPO)}", flush=True)
        sys.exit(1 if failed else 0)
    arms = [a for a in erd_arms(args.duration) if args.only in a.name] if args.erd else [faze4_arm(args.duration)]
    if args.sweep and not args.erd:
        arms += [faze4_arm(args.duration, ("--amp-deg", "90", "--freq", "2"))]
    for arm in arms:
        for tol in tolerances:
            with tempfile.TemporaryDirectory() as tmp:
                try:
                    if args.sweep:
                        result = check_sweep(arm, args.faze4, tol, args.sweep, tmp)
                    else:
                        result, _ = check(arm, args.faze4, tol, tmp)
                except (RuntimeError, ValueError, AssertionError) as e:
                    print(f"| {arm.name} | {tol:g} mm | – | – | – | could not check: {str(e)[:200]} | – | – |", flush=True)
                    failed = True
                    continue
            print_row(result)
            failed |= bool(result.get("failures"))
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
