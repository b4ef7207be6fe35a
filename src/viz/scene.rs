//! What the viewer draws: per visual, the frame it is attached to, its placement there, a
//! mesh and a colour; for shapes the board and the reference path. Encoded once per run into
//! one binary blob; the motion is a stream of fixed-size f32 records (see [`SampleEncoder`]),
//! which also say which links' collision geometry intersects (the viewer tints them red).
//!
//! Scene blob, little-endian: `b"F4VZ"`, u32 format version, u32 JSON length, the JSON header,
//! zero padding to a multiple of 4, then the mesh arrays the header points into (byte offsets
//! from the start of that binary part, each 4-byte aligned).

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

use serde_json::json;

use super::mesh::{CompactMesh, Indices, TriMesh, load_mesh};
use crate::algo::{Data, forward_kinematics};
use crate::error::{escape_controls, to_stderr};
use crate::geometry::GeometryModel;
use crate::geometry::mesh::Rgba;
use crate::model::{FrameId, Geometry, Model};
use crate::sim::{RunInfo, Sample};
use crate::spatial::{Mat3, Pose, Vec3};
use crate::traj::shape::Board;

/// Version of the scene blob and sample record layout (2: a collision flag per slot).
pub const FORMAT_VERSION: u32 = 2;
/// Radius of the reference path spheres (m), as the original drew them.
pub const REFERENCE_RADIUS: f64 = 0.0045;
/// Radius of the tool trail spheres (m), as the original drew them.
pub const TRAIL_RADIUS: f64 = 0.0055;
/// Radius of the current-target sphere (m).
pub const TARGET_RADIUS: f64 = 0.008;
/// Largest gap between reference spheres (m): the path is resampled so they touch.
const REFERENCE_SPACING: f64 = 0.003;
/// Colour of visuals whose URDF gives none (the official Faze4 grey-blue).
pub const DEFAULT_COLOR: [f32; 4] = [0.792, 0.820, 0.933, 1.0];
/// Colour of the drawing board.
const BOARD_COLOR: [f32; 4] = [0.94, 0.92, 0.86, 1.0];
/// Thickness of the drawing board (m); its face is the board plane.
const BOARD_THICKNESS: f64 = 0.006;

/// One drawn object.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneVisual {
    /// What it is (the link name, or `board`).
    pub name: String,
    /// Index into [`Scene::slots`] of the frame it moves with; `None`: fixed in the world.
    pub slot: Option<usize>,
    /// Its placement in that frame.
    pub placement: Pose,
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// RGBA in 0..1.
    pub color: [f32; 4],
}

/// Everything static the viewer needs.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The model's name.
    pub name: String,
    /// Joint names, in q order.
    pub joints: Vec<String>,
    /// The model frames whose world poses each sample carries (those with visuals).
    pub slots: Vec<usize>,
    /// Their names.
    pub slot_names: Vec<String>,
    /// The meshes, compacted.
    pub meshes: Vec<CompactMesh>,
    /// The objects.
    pub visuals: Vec<SceneVisual>,
    /// A unit sphere mesh (for the trail, the reference path and the target).
    pub sphere_mesh: usize,
    /// For shapes: the drawing board.
    pub board: Option<Board>,
    /// For shapes: centres of the reference path spheres (resampled so they touch).
    pub reference: Vec<Vec3>,
    /// Mesh references whose file was not found (drawn as boxes).
    pub missing: Vec<String>,
    /// Mesh files that could not be read, with the reason (drawn as boxes).
    pub unreadable: Vec<String>,
    /// The run: command, dt, duration, recording period (JSON).
    pub run: serde_json::Value,
}

impl Scene {
    /// The scene of `model` alone (no board, no run). Meshes whose file is missing or
    /// unreadable become boxes spanning the link to its children (listed in `missing` and
    /// `unreadable`).
    pub fn from_model(model: &Model, geometry: &GeometryModel) -> Scene {
        let mut scene = Scene {
            name: model.name.clone(),
            joints: model.joints.iter().map(|j| j.name.clone()).collect(),
            slots: Vec::new(),
            slot_names: Vec::new(),
            meshes: Vec::new(),
            visuals: Vec::new(),
            sphere_mesh: 0,
            board: None,
            reference: Vec::new(),
            missing: Vec::new(),
            unreadable: Vec::new(),
            run: json!({}),
        };
        scene.meshes.push(CompactMesh::new(&TriMesh::sphere(1.0, 10, 16)));
        // mesh index in the scene and the file's own colour, per file and scale
        let mut loaded: HashMap<(PathBuf, [u32; 3]), (usize, Option<Rgba>)> = HashMap::new();
        for visual in &geometry.visuals {
            let frame = visual.frame;
            let slot = scene.slot(model, frame);
            let color = visual.rgba.map_or(DEFAULT_COLOR, |c| c.map(|x| x as f32));
            let name = visual.link.clone();
            let add = |scene: &mut Scene, mesh: CompactMesh, placement: Pose, color: [f32; 4]| {
                scene.meshes.push(mesh);
                scene.visuals.push(SceneVisual {
                    name: name.clone(),
                    slot,
                    placement,
                    mesh: scene.meshes.len() - 1,
                    color,
                });
            };
            match &visual.geometry {
                Geometry::Box { size } => add(&mut scene, box_mesh(size), visual.placement, color),
                Geometry::Cylinder { radius, length } => add(
                    &mut scene,
                    CompactMesh::new(&TriMesh::cylinder(*radius as f32, *length as f32, 40)),
                    visual.placement,
                    color,
                ),
                Geometry::Capsule { radius, length } => add(
                    &mut scene,
                    CompactMesh::new(&TriMesh::capsule(*radius as f32, *length as f32, 16, 24)),
                    visual.placement,
                    color,
                ),
                Geometry::Sphere { radius } => add(
                    &mut scene,
                    CompactMesh::new(&TriMesh::sphere(*radius as f32, 16, 24)),
                    visual.placement,
                    color,
                ),
                Geometry::Mesh { uri, path, scale } => {
                    let scale = [scale.x as f32, scale.y as f32, scale.z as f32];
                    let key = (
                        path.clone().unwrap_or_else(|| PathBuf::from(uri)),
                        scale.map(f32::to_bits),
                    );
                    // the URDF's <material> colour, else the file's own, else the default (rviz)
                    let color_of = |file: Option<[f32; 4]>| visual.rgba.map(|c| c.map(|x| x as f32)).or(file);
                    if let Some(&(m, file_color)) = loaded.get(&key) {
                        scene.visuals.push(SceneVisual {
                            name: name.clone(),
                            slot,
                            placement: visual.placement,
                            mesh: m,
                            color: color_of(file_color).unwrap_or(DEFAULT_COLOR),
                        });
                        continue;
                    }
                    let mesh = match load_mesh(uri, path.as_deref(), geometry.built_in_meshes) {
                        None => {
                            scene.missing.push(uri.clone());
                            None
                        }
                        Some(Ok((m, file_color))) if m.triangles() > 0 => {
                            loaded.insert(key, (scene.meshes.len(), file_color));
                            Some((CompactMesh::new(&m.scaled(scale)), color_of(file_color)))
                        }
                        Some(Ok(_)) => {
                            scene.unreadable.push(format!("{}: no triangles", key.0.display()));
                            None
                        }
                        Some(Err(e)) => {
                            scene.unreadable.push(e.to_string());
                            None
                        }
                    };
                    match mesh {
                        Some((m, mesh_color)) => add(&mut scene, m, visual.placement, mesh_color.unwrap_or(color)),
                        None => {
                            for (placement, size) in fallback_boxes(model, frame) {
                                add(&mut scene, box_mesh(&size), placement, color);
                            }
                        }
                    }
                }
            }
        }
        scene
    }

    /// The scene of a run: the model's, plus the board and reference path of a shape, and
    /// the run's facts (`period`: the recording period in s).
    pub fn for_run(run: &RunInfo, period: f64) -> Scene {
        let mut scene = Scene::from_model(run.model, run.geometry);
        if let Some(board) = run.board {
            let c = board.center;
            scene
                .meshes
                .push(box_mesh(&Vec3::new(board.width, BOARD_THICKNESS, board.height)));
            scene.visuals.push(SceneVisual {
                name: "board".into(),
                slot: None,
                // the face towards the arm (+y) lies 0.5 mm behind the board plane
                placement: Pose::new(
                    Mat3::identity(),
                    Vec3::new(c.x, c.y - 0.0005 - BOARD_THICKNESS / 2.0, c.z),
                ),
                mesh: scene.meshes.len() - 1,
                color: BOARD_COLOR,
            });
            scene.board = Some(*board);
        }
        if let Some(path) = run.reference_path {
            scene.reference = resample_closed(path, REFERENCE_SPACING);
        }
        scene.run = json!({
            "command": run.command,
            "dt": run.dt,
            "duration": run.steps as f64 * run.dt,
            "period": period,
            "tool_frame": escape_controls(&run.model.frame(run.tool_frame).name),
        });
        scene
    }

    /// Index into `slots` of model frame `frame`, adding it; `None` for frames welded to the
    /// world (their pose never changes).
    fn slot(&mut self, model: &Model, FrameId(frame): FrameId) -> Option<usize> {
        model.frames[frame].body?;
        Some(match self.slots.iter().position(|&f| f == frame) {
            Some(k) => k,
            None => {
                self.slots.push(frame);
                self.slot_names.push(model.frames[frame].name.clone());
                self.slots.len() - 1
            }
        })
    }

    /// Prints, at most once per process, one line on stderr when meshes are drawn as boxes.
    pub fn warn_fallbacks(&self) {
        static MISSING: AtomicBool = AtomicBool::new(false);
        static UNREADABLE: AtomicBool = AtomicBool::new(false);
        if !self.missing.is_empty() && !MISSING.swap(true, Ordering::Relaxed) {
            let names: Vec<&str> = self.missing.iter().map(|u| u.rsplit('/').next().unwrap_or(u)).collect();
            to_stderr(&format!(
                "viz: meshes not found ({}); drawing boxes ({})",
                names.join(", "),
                crate::model::not_found_advice(&self.missing[0])
            ));
        }
        if !self.unreadable.is_empty() && !UNREADABLE.swap(true, Ordering::Relaxed) {
            to_stderr(&format!(
                "viz: meshes unreadable ({}); drawing boxes",
                self.unreadable.join("; ")
            ));
        }
    }

    /// The scene blob (see the module documentation).
    pub fn encode(&self) -> Vec<u8> {
        let mut blob: Vec<u8> = Vec::new();
        let mut put = |bytes: &[u8]| {
            let at = blob.len();
            blob.extend_from_slice(bytes);
            while !blob.len().is_multiple_of(4) {
                blob.push(0);
            }
            at
        };
        let meshes: Vec<serde_json::Value> = self
            .meshes
            .iter()
            .map(|m| {
                let pos: Vec<u8> = m.positions.iter().flat_map(|v| v.to_le_bytes()).collect();
                let nrm: Vec<u8> = m.normals.iter().map(|&v| v as u8).collect();
                let (idx, width) = match &m.indices {
                    Indices::U16(i) => (i.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>(), 2),
                    Indices::U32(i) => (i.iter().flat_map(|v| v.to_le_bytes()).collect(), 4),
                };
                json!({
                    "vertices": m.vertices(),
                    "indices": idx.len() / width,
                    "index_bytes": width,
                    "min": m.min,
                    "max": m.max,
                    "pos": put(&pos),
                    "nrm": put(&nrm),
                    "idx": put(&idx),
                })
            })
            .collect();
        let visuals: Vec<serde_json::Value> = self
            .visuals
            .iter()
            .map(|v| {
                json!({
                    "name": escape_controls(&v.name),
                    "slot": v.slot.map_or(-1, |s| s as i64),
                    "mesh": v.mesh,
                    "placement": pose12(&v.placement),
                    "color": v.color,
                })
            })
            .collect();
        let round = |x: f64| (x * 1e5).round() / 1e5;
        let header = json!({
            "format": FORMAT_VERSION,
            // names as shown: no control or bidirectional character (escape_controls)
            "name": escape_controls(&self.name),
            "joints": self.joints.iter().map(|j| escape_controls(j)).collect::<Vec<_>>(),
            "slots": self.slot_names.iter().map(|s| escape_controls(s)).collect::<Vec<_>>(),
            "stride": SampleEncoder::stride_for(self.joints.len(), self.slots.len()),
            "meshes": meshes,
            "visuals": visuals,
            "sphere_mesh": self.sphere_mesh,
            "board": self.board.map(|b| json!({
                "center": [b.center.x, b.center.y, b.center.z],
                "width": b.width,
                "height": b.height,
            })),
            "reference": self.reference.iter().flat_map(|p| [round(p.x), round(p.y), round(p.z)]).collect::<Vec<f64>>(),
            "radii": {"reference": REFERENCE_RADIUS, "trail": TRAIL_RADIUS, "target": TARGET_RADIUS},
            "run": self.run,
        });
        let header = serde_json::to_vec(&header).expect("JSON of plain values");
        let mut out = Vec::with_capacity(16 + header.len() + blob.len());
        out.extend_from_slice(b"F4VZ");
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&(header.len() as u32).to_le_bytes());
        out.extend_from_slice(&header);
        while !out.len().is_multiple_of(4) {
            out.push(b' ');
        }
        out.extend_from_slice(&blob);
        out
    }
}

/// A pose as 12 floats, column-major 3×4: the rotation's columns, then the translation.
fn pose12(p: &Pose) -> [f32; 12] {
    let r = &p.rot;
    [
        r[(0, 0)],
        r[(1, 0)],
        r[(2, 0)],
        r[(0, 1)],
        r[(1, 1)],
        r[(2, 1)],
        r[(0, 2)],
        r[(1, 2)],
        r[(2, 2)],
        p.pos.x,
        p.pos.y,
        p.pos.z,
    ]
    .map(|x| x as f32)
}

fn box_mesh(size: &Vec3) -> CompactMesh {
    CompactMesh::new(&TriMesh::cuboid([size.x as f32, size.y as f32, size.z as f32]))
}

/// Stand-ins for a link whose mesh is missing: one box from the link's origin to each of its
/// children's joint origins (each a bit longer than the span, as thick as a quarter of it
/// within 2–6 cm), or a 4 cm cube for a link without children.
fn fallback_boxes(model: &Model, FrameId(frame): FrameId) -> Vec<(Pose, Vec3)> {
    let f = &model.frames[frame];
    let inv = f.placement.inverse();
    let mut ends: Vec<Vec3> = (0..model.num_bodies())
        .filter(|&j| model.parent[j] == f.body.map(|b| b.0))
        .map(|j| inv.compose(&model.tree_pose[j]).pos)
        .collect();
    if ends.is_empty() {
        // a leaf: frames welded to it further out (e.g. a tool point)
        ends = (0..model.frames.len())
            .filter(|&g| g != frame && model.frames[g].body == f.body && f.body.is_some())
            .map(|g| inv.compose(&model.frames[g].placement).pos)
            .collect();
    }
    ends.retain(|p| p.norm() > 1e-4);
    if ends.is_empty() {
        return vec![(Pose::IDENTITY, Vec3::new(0.04, 0.04, 0.04))];
    }
    ends.iter()
        .map(|p| {
            let len = p.norm();
            let t = (0.25 * len).clamp(0.02, 0.06);
            let x = p / len;
            let helper = if x.z.abs() < 0.9 { Vec3::z() } else { Vec3::x() };
            let y = helper.cross(&x).normalize();
            let z = x.cross(&y);
            (
                Pose::new(Mat3::from_columns(&[x, y, z]), p / 2.0),
                Vec3::new(len + t, t, t),
            )
        })
        .collect()
}

/// Points along the closed polyline through `path` no further apart than `spacing`.
fn resample_closed(path: &[Vec3], spacing: f64) -> Vec<Vec3> {
    let n = path.len();
    let mut out = Vec::new();
    for k in 0..n {
        let (a, b) = (path[k], path[(k + 1) % n]);
        let pieces = ((b - a).norm() / spacing).ceil().max(1.0) as usize;
        out.extend((0..pieces).map(|i| a + (b - a) * (i as f64 / pieces as f64)));
    }
    out
}

/// Turns samples into the viewer's fixed-size f32 records:
/// `t, tool xyz, target xyz (NaN: none), q (dof), then per slot its world pose (12 floats,
/// column-major 3×4), then per slot 1 if its link's collision geometry intersects another
/// (see [`SampleEncoder::collision_pairs`]), else 0`.
#[derive(Clone, Debug)]
pub struct SampleEncoder {
    model: Model,
    data: Data,
    slots: Vec<usize>,
    /// Per checked collision pair, the slots of its two links (`None`: a link not drawn or
    /// fixed to the world).
    pair_slots: Vec<[Option<usize>; 2]>,
    /// Per slot, whether its link intersects at the sample being encoded.
    colliding: Vec<bool>,
}

impl SampleEncoder {
    /// An encoder for `model` and the frames `slots` (a scene's [`Scene::slots`]); no link is
    /// flagged as colliding unless [`SampleEncoder::collision_pairs`] says which pairs are
    /// checked.
    pub fn new(model: &Model, slots: &[usize]) -> SampleEncoder {
        SampleEncoder {
            model: model.clone(),
            data: Data::new(model),
            slots: slots.to_vec(),
            pair_slots: Vec::new(),
            colliding: vec![false; slots.len()],
        }
    }

    /// This encoder flagging the links of the pairs that intersect: `pairs` are the link
    /// frames of the checked pairs ([`RunInfo::collision_pairs`]), in the order of
    /// [`Sample::intersecting`].
    pub fn collision_pairs(mut self, pairs: &[[FrameId; 2]]) -> SampleEncoder {
        let slot = |FrameId(f): FrameId| self.slots.iter().position(|&s| s == f);
        self.pair_slots = pairs.iter().map(|&[a, b]| [slot(a), slot(b)]).collect();
        self
    }

    /// Floats per record for `dof` joints and `slots` frames.
    pub fn stride_for(dof: usize, slots: usize) -> usize {
        7 + dof + 13 * slots
    }

    /// Floats per record.
    pub fn stride(&self) -> usize {
        Self::stride_for(self.model.dof(), self.slots.len())
    }

    /// Appends the record of `sample` to `out`.
    pub fn push(&mut self, sample: &Sample, out: &mut Vec<f32>) {
        forward_kinematics(&self.model, &mut self.data, sample.q);
        out.push(sample.t as f32);
        out.extend(sample.tool.iter().map(|&x| x as f32));
        match sample.target {
            Some(p) => out.extend(p.iter().map(|&x| x as f32)),
            None => out.extend([f32::NAN; 3]),
        }
        out.extend(sample.q.iter().map(|&x| x as f32));
        for &f in &self.slots {
            out.extend(pose12(&self.data.frame_pose[f]));
        }
        self.colliding.fill(false);
        for (slots, _) in (self.pair_slots.iter().zip(sample.intersecting)).filter(|(_, on)| **on) {
            for slot in slots.iter().flatten() {
                self.colliding[*slot] = true;
            }
        }
        out.extend(self.colliding.iter().map(|&c| f32::from(u8::from(c))));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Robot;
    use crate::model::PackagePaths;
    use std::path::Path;

    fn load(rel: &str, packages: &PackagePaths) -> Robot {
        Robot::from_urdf_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join(rel), packages).unwrap()
    }

    #[test]
    fn box_model_scene_has_one_box_per_link() {
        let robot = load("urdf/faze4_arm.urdf", &PackagePaths::default());
        let scene = Scene::from_model(&robot.model, &robot.geometry);
        assert!(scene.missing.is_empty());
        assert_eq!(scene.visuals.len(), 7);
        assert_eq!(scene.visuals[0].slot, None, "base_link is welded to the world");
        assert_eq!(
            scene.slot_names,
            ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"]
        );
        assert!(scene.visuals.iter().all(|v| scene.meshes[v.mesh].vertices() == 24));
    }

    #[test]
    fn missing_meshes_become_boxes_towards_the_children() {
        // the real arm with meshes of a package that exists nowhere (and is not built in)
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("urdf/faze4_real.urdf");
        let text = std::fs::read_to_string(&path)
            .unwrap()
            .replace("package://faze4_description/", "package://no_such_package/");
        let robot = Robot::from_urdf_str(&text, "renamed", None, &PackagePaths::default()).unwrap();
        let scene = Scene::from_model(&robot.model, &robot.geometry);
        assert_eq!(scene.missing.len(), 6);
        assert!(scene.missing[0].ends_with("rotary_base.STL"));
        // one box per link: each link has one child (hvataljka: the tool point)
        let rotary: Vec<_> = scene.visuals.iter().filter(|v| v.name == "rotary_base").collect();
        assert_eq!(rotary.len(), 1);
        // J2 is 0.20182 m down rotary_base's y axis: the box is centred half-way
        let p = rotary[0].placement.pos;
        assert!((p - Vec3::new(0.0, -0.10091, 0.0)).norm() < 1e-12, "{p:?}");
        let mesh = scene.meshes[rotary[0].mesh].expand();
        let (lo, hi) = mesh.bounds();
        assert!(((hi[0] - lo[0]) as f64 - 1.25 * 0.20182).abs() < 1e-6);
        let hand = scene.visuals.iter().find(|v| v.name == "hvataljka").unwrap();
        assert!((hand.placement.pos - Vec3::new(0.0, 0.0, 0.00735)).norm() < 1e-12);
    }

    #[test]
    fn official_meshes_not_on_disk_are_the_built_in_copies() {
        let robot = load("urdf/faze4_real.urdf", &PackagePaths::default());
        let scene = Scene::from_model(&robot.model, &robot.geometry);
        assert!(scene.missing.is_empty() && scene.unreadable.is_empty());
        for v in scene.visuals.iter().filter(|v| v.name != "base_link") {
            let built_in = crate::faze4::meshes::mesh(&v.name).unwrap();
            let expected = CompactMesh::new(&TriMesh::from_soup(&built_in.corners()));
            assert_eq!(scene.meshes[v.mesh], expected, "{}", v.name);
        }
    }

    #[test]
    fn records_flag_the_links_of_intersecting_pairs() {
        let robot = crate::geometry::Robot::faze4();
        let model = &robot.model;
        let scene = Scene::from_model(model, &robot.geometry);
        let frame = |name: &str| model.frame_index(name).unwrap();
        let pairs = [
            [frame("nadlaktica"), frame("podlaktica")],
            [frame("base_link"), frame("saka")],
        ];
        let mut encoder = SampleEncoder::new(model, &scene.slots).collision_pairs(&pairs);
        let zeros = vec![0.0; model.dof()];
        let record = |encoder: &mut SampleEncoder, intersecting: &[bool]| {
            let sample = Sample {
                step: 0,
                t: 0.0,
                q: &zeros,
                v: &zeros,
                q_cmd: &zeros,
                v_cmd: &zeros,
                tau: &zeros,
                tau_raw: &zeros,
                g: &zeros,
                tool: Vec3::zeros(),
                target: None,
                intersecting,
            };
            let mut out = Vec::new();
            encoder.push(&sample, &mut out);
            assert_eq!(out.len(), encoder.stride());
            out[out.len() - scene.slots.len()..].to_vec()
        };
        let flagged = |flags: Vec<f32>| -> Vec<&str> {
            (scene.slot_names.iter().zip(flags))
                .filter(|(_, f)| *f == 1.0)
                .map(|(n, _)| n.as_str())
                .collect()
        };
        assert_eq!(
            flagged(record(&mut encoder, &[true, false])),
            ["nadlaktica", "podlaktica"]
        );
        // base_link is welded to the world (no slot): only saka is drawn red
        assert_eq!(flagged(record(&mut encoder, &[false, true])), ["saka"]);
        assert!(flagged(record(&mut encoder, &[false, false])).is_empty());
        // a run that checks no clearance flags nothing
        assert!(flagged(record(&mut SampleEncoder::new(model, &scene.slots), &[])).is_empty());
    }

    #[test]
    fn resampled_reference_spheres_touch() {
        let square = [Vec3::zeros(), Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.1, 0.0, 0.05)];
        let r = resample_closed(&square, 0.003);
        let gaps = (0..r.len()).map(|k| (r[(k + 1) % r.len()] - r[k]).norm());
        assert!(gaps.fold(0.0, f64::max) <= 0.003 + 1e-12);
        assert_eq!(r[0], square[0]);
    }
}
