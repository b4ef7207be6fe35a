#!/usr/bin/env python3
"""Writes the small mesh arms of the tests (tests/urdf/mesh_arm_{stl,dae,obj}.urdf) and their
meshes (tests/urdf/mesh_arms/meshes/), and the seeds of the `mesh_file` fuzz target
(fuzz/seeds/mesh_file/). Standard library only; run from the repository root:

    python3 tools/make_mesh_arms.py

The three arms are the same three-joint arm: every link's visual and collision is a box mesh,
written once per format. The STL files are in metres. The COLLADA files are in millimetres with
`<unit meter="0.001">` and `<up_axis>Y_UP</up_axis>` (which ROS tools ignore, as faze4 does) and a
diffuse colour; the OBJ files are in metres, in two groups, with a `.mtl` colour. One link's mesh
is scaled by `<mesh scale>` in the URDF. Nothing here is a real robot.
"""
import os
import struct

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MESHES = os.path.join(ROOT, "tests/urdf/mesh_arms/meshes")
SEEDS = os.path.join(ROOT, "fuzz/seeds/mesh_file")

# link name → box half-sizes (m), centre (m), in the link frame
BOXES = {
    "base": ((0.08, 0.08, 0.05), (0.0, 0.0, 0.05)),
    "upper": ((0.03, 0.03, 0.14), (0.0, 0.0, 0.15)),
    "forearm": ((0.025, 0.025, 0.12), (0.0, 0.0, 0.13)),
    "hand": ((0.04, 0.02, 0.02), (0.0, 0.0, 0.03)),
}


def box(half, centre):
    """8 corners and 12 outward triangles (0-based)."""
    hx, hy, hz = half
    cx, cy, cz = centre
    v = [(cx + sx * hx, cy + sy * hy, cz + sz * hz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    # corner index = 4*ix + 2*iy + iz
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, c, d in quads:
        tris += [(a, b, c), (a, c, d)]
    return v, tris


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def write_stl(path, v, tris):
    with open(path, "wb") as f:
        f.write(b"binary STL written by tools/make_mesh_arms.py".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<3f", 0, 0, 0))
            for i in t:
                f.write(struct.pack("<3f", *v[i]))
            f.write(b"\0\0")


def write_dae(path, v, tris, rgba):
    mm = [repr(round(c * 1000.0, 6)) for p in v for c in p]
    idx = " ".join(str(i) for t in tris for i in t)
    text = f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="millimeter" meter="0.001"/><up_axis>Y_UP</up_axis></asset>
  <library_effects><effect id="paint"><profile_COMMON><technique sid="common"><phong>
    <diffuse><color>{' '.join(repr(c) for c in rgba)}</color></diffuse>
  </phong></technique></profile_COMMON></effect></library_effects>
  <library_materials><material id="paint-material" name="paint"><instance_effect url="#paint"/></material></library_materials>
  <library_geometries><geometry id="part" name="part"><mesh>
    <source id="part-positions"><float_array id="part-positions-array" count="{len(mm)}">{' '.join(mm)}</float_array>
      <technique_common><accessor source="#part-positions-array" count="{len(v)}" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="part-vertices"><input semantic="POSITION" source="#part-positions"/></vertices>
    <triangles material="paint" count="{len(tris)}"><input semantic="VERTEX" source="#part-vertices" offset="0"/><p>{idx}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene" name="scene">
    <node id="part-node" name="part"><matrix sid="transform">1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix>
      <instance_geometry url="#part"><bind_material><technique_common>
        <instance_material symbol="paint" target="#paint-material"/>
      </technique_common></bind_material></instance_geometry>
    </node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"""
    with open(path, "w") as f:
        f.write(text)
    return text


def write_obj(path, name, v, tris, rgba):
    mtl = f"{name}.mtl"
    with open(os.path.join(os.path.dirname(path), mtl), "w") as f:
        f.write(f"newmtl paint\nKd {rgba[0]!r} {rgba[1]!r} {rgba[2]!r}\nd {rgba[3]!r}\n")
    lines = [f"mtllib {mtl}"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in v]
    for k, t in enumerate(tris):
        if k % 6 == 0:
            # usemtl after each g, as Blender writes it (mesh-loader 0.1 drops the material at a g)
            lines += [f"g side{k // 6}", "usemtl paint"]
        lines.append("f " + " ".join(str(i + 1) for i in t))
    text = "\n".join(lines) + "\n"
    with open(path, "w") as f:
        f.write(text)
    return text


URDF = """<?xml version="1.0"?>
<!--
  mesh_arm_{ext}: faze4's mesh-format test arm (not a real robot), written by
  tools/make_mesh_arms.py. Same arm as mesh_arm_stl.urdf / _dae / _obj but for the format of its
  meshes (package://mesh_arms/meshes/, give tests/urdf to package-path). The hand's mesh is the
  base's box scaled by <mesh scale>.
-->
<robot name="mesh_arm_{ext}">
  <link name="world"/>
  <joint name="world_joint" type="fixed"><parent link="world"/><child link="base"/></joint>
  <link name="base">
    <inertial><origin xyz="0 0 0.05"/><mass value="3"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>
{base}
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="upper"/><origin xyz="0 0 0.12"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="30" velocity="3"/>
  </joint>
  <link name="upper">
    <inertial><origin xyz="0 0 0.15"/><mass value="1.5"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial>
{upper}
  </link>
  <joint name="j2" type="revolute">
    <parent link="upper"/><child link="forearm"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" effort="20" velocity="3"/>
  </joint>
  <link name="forearm">
    <inertial><origin xyz="0 0 0.13"/><mass value="1"/><inertia ixx="0.006" ixy="0" ixz="0" iyy="0.006" iyz="0" izz="0.001"/></inertial>
{forearm}
  </link>
  <joint name="j3" type="revolute">
    <parent link="forearm"/><child link="hand"/><origin xyz="0 0 0.26"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" effort="5" velocity="3"/>
  </joint>
  <link name="hand">
    <inertial><origin xyz="0 0 0.03"/><mass value="0.3"/><inertia ixx="0.0003" ixy="0" ixz="0" iyy="0.0003" iyz="0" izz="0.0003"/></inertial>
{hand}
  </link>
</robot>
"""

# the hand is the base's box scaled: base half (0.08, 0.08, 0.05) at z 0.05 → (0.04, 0.02, 0.02) at z 0.02
HAND_SCALE = (0.5, 0.25, 0.4)


def geometry(ext, link):
    name, scale = (link, None) if link != "hand" else ("base", HAND_SCALE)
    s = "" if scale is None else f' scale="{scale[0]} {scale[1]} {scale[2]}"'
    mesh = f'<geometry><mesh filename="package://mesh_arms/meshes/{name}.{ext}"{s}/></geometry>'
    return f"    <visual>{mesh}</visual>\n    <collision>{mesh}</collision>"


def main():
    os.makedirs(MESHES, exist_ok=True)
    os.makedirs(SEEDS, exist_ok=True)
    colours = {"base": (0.2, 0.2, 0.25, 1.0), "upper": (0.9, 0.5, 0.1, 1.0), "forearm": (0.1, 0.5, 0.9, 1.0)}
    for link in ("base", "upper", "forearm"):
        half, centre = BOXES[link]
        v, tris = box(half, centre)
        v = [tuple(f32(c) for c in p) for p in v]
        write_stl(os.path.join(MESHES, f"{link}.stl"), v, tris)
        dae = write_dae(os.path.join(MESHES, f"{link}.dae"), v, tris, colours[link])
        obj = write_obj(os.path.join(MESHES, f"{link}.obj"), link, v, tris, colours[link])
        if link == "base":
            with open(os.path.join(SEEDS, "box.dae"), "wb") as f:
                f.write(b"\x01" + dae.encode())
            with open(os.path.join(SEEDS, "box.obj"), "wb") as f:
                f.write(b"\x02" + obj.encode())
            with open(os.path.join(MESHES, f"{link}.stl"), "rb") as src, open(os.path.join(SEEDS, "box.stl"), "wb") as f:
                f.write(b"\x00" + src.read())
    for ext in ("stl", "dae", "obj"):
        parts = {link: geometry(ext, link) for link in BOXES}
        with open(os.path.join(ROOT, f"tests/urdf/mesh_arm_{ext}.urdf"), "w") as f:
            f.write(URDF.format(ext=ext, **parts))


if __name__ == "__main__":
    main()
