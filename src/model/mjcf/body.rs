//! The body tree of `<worldbody>`: each body a link, its joint the joint that moves it from its
//! parent (a body without one is welded to its parent), its `<inertial>` (or its geoms'
//! inertia), its geoms as visuals and collision elements, its named sites as welded links.

use super::classes::MAIN;
use super::context::{Attrs, Context, FromGeom, label};
use super::frames::{fromto_pose, unit_inertia};
use super::xml::Element;
use crate::error::{Error, Result};
use crate::input::MAX_LINKS;
use crate::model::{Collision, Geometry, InertialDesc, JointDesc, JointType, LinkDesc, Visual};
use crate::spatial::{Inertia, Mat3, Pose, Vec3, rotation_about_axis};

/// MuJoCo's colour of a geom that gives none.
const DEFAULT_RGBA: [f64; 4] = [0.5, 0.5, 0.5, 1.0];

/// The links and joints read so far, and what the model's other sections need of them.
pub(super) struct Tree {
    /// Links in document order (the world first).
    pub links: Vec<LinkDesc>,
    /// Joints in document order, welds included.
    pub joints: Vec<JointDesc>,
    /// Each moving joint's `armature` (kg·m² or kg), in document order.
    pub armature: Vec<(String, f64)>,
    /// The moving joints' names in MuJoCo's order (that of `qpos`).
    pub moving: Vec<String>,
    /// Each moving joint's `ref` (its position at the placement the file gives).
    references: Vec<f64>,
    /// Bodies and joints met so far (MuJoCo's ids, for unnamed ones).
    bodies: usize,
    joint_count: usize,
}

/// An element inside a body and what it inherits from the frames around it.
struct Item<'a> {
    element: &'a Element,
    /// The placement of the frames around it in the body's frame.
    frame: Pose,
    /// The class its children take when they name none.
    childclass: &'a str,
}

impl Tree {
    /// No links yet.
    pub fn new() -> Tree {
        Tree {
            links: Vec::new(),
            joints: Vec::new(),
            armature: Vec::new(),
            moving: Vec::new(),
            references: Vec::new(),
            bodies: 0,
            joint_count: 0,
        }
    }

    /// The `ref` of moving joint `name`, if the model has it.
    pub fn reference(&self, name: &str) -> Option<f64> {
        self.moving.iter().position(|j| j == name).map(|i| self.references[i])
    }

    /// A `<worldbody>`: the world link (once), its bodies; its own geoms are left out.
    pub fn world(&mut self, world: &Element, ctx: &Context) -> Result<()> {
        if self.links.is_empty() {
            self.links.push(LinkDesc {
                name: "world".into(),
                ..LinkDesc::default()
            });
            self.bodies = 1;
        }
        for item in items(world, Pose::IDENTITY, MAIN, ctx)? {
            match item.element.name.as_str() {
                "body" => self.body(&item, "world", ctx)?,
                "geom" => {
                    let name = item.element.get("name").unwrap_or("unnamed").to_string();
                    ctx.note("world geom", "left out: the environment, not the arm", &name, false);
                }
                "site" => self.site(&item, "world", ctx)?,
                _ => {}
            }
        }
        Ok(())
    }

    /// Body `item` (and its subtree) under link `parent`.
    fn body(&mut self, item: &Item, parent: &str, ctx: &Context) -> Result<()> {
        let element = item.element;
        let id = self.bodies;
        self.bodies += 1;
        if self.links.len() >= MAX_LINKS {
            return Err(Error::model(
                ctx.file,
                label(element, ctx.file),
                format!("is one body more than the {MAX_LINKS} faze4 reads (docs/development.md, Caps)"),
            ));
        }
        let name = element.get("name").map_or_else(|| format!("body{id}"), str::to_string);
        let childclass = element.get("childclass").unwrap_or(item.childclass);
        if !ctx.classes.has(childclass) {
            return Err(Error::model(
                ctx.file,
                label(element, ctx.file),
                format!("childclass '{childclass}' is not defined"),
            ));
        }
        let placement = item
            .frame
            .compose(&ctx.attrs(element, MAIN).pose(&ctx.compiler.angles)?);
        if element.get("gravcomp").is_some_and(|g| g.trim() != "0") {
            ctx.note(
                "gravcomp",
                "not simulated: faze4 compensates gravity in its PD (feed-forward)",
                &name,
                true,
            );
        }
        self.joint(element, childclass, &name, parent, placement, ctx)?;
        let children = items(element, Pose::IDENTITY, childclass, ctx)?;
        let link = self.link(&name, element, &children, ctx)?;
        self.links.push(link);
        for child in &children {
            match child.element.name.as_str() {
                "body" => self.body(child, &name, ctx)?,
                "site" => self.site(child, &name, ctx)?,
                _ => {}
            }
        }
        Ok(())
    }

    /// The joint that attaches body `name` to link `parent` at `placement`: a weld without a
    /// `<joint>`, else the one hinge or slide (a body with several, a ball or a free joint is
    /// refused). A hinge's axis passes through its `pos`: a joint away from the body's origin
    /// moves a massless link there, to which the body is welded.
    fn joint(
        &mut self,
        body: &Element,
        class: &str,
        name: &str,
        parent: &str,
        placement: Pose,
        ctx: &Context,
    ) -> Result<()> {
        if let Some(free) = body.all("freejoint").next() {
            return Err(free_joint(ctx, free, name));
        }
        let joints: Vec<&Element> = body.all("joint").collect();
        let element = match joints.as_slice() {
            [] => {
                self.weld(format!("{name} (welded)"), parent, name, placement);
                return Ok(());
            }
            [one] => *one,
            many => {
                let names: Vec<String> = many.iter().map(|j| label(j, ctx.file)).collect();
                return Err(Error::model(
                    ctx.file,
                    label(body, ctx.file),
                    format!(
                        "has {} joints ({}): faze4 moves a body by one joint; give each its own body",
                        many.len(),
                        names.join(", ")
                    ),
                ));
            }
        };
        let class = ctx.classes.class_of(element, class, ctx.file)?;
        let a = ctx.attrs(element, class);
        let id = self.joint_count;
        self.joint_count += 1;
        let joint = element.get("name").map_or_else(|| format!("joint{id}"), str::to_string);
        let hinge = match a.text("type").unwrap_or("hinge") {
            "hinge" => true,
            "slide" => false,
            "free" => return Err(free_joint(ctx, element, name)),
            other => {
                return Err(a.error(format!(
                    "type=\"{other}\" is not simulated: faze4 reads hinge and slide joints"
                )));
            }
        };
        let mut desc = joint_desc(&a, &joint, ctx, hinge)?;
        desc.parent = parent.to_string();
        let reference = self.attach(desc, &a, name, placement, ctx, hinge)?;
        self.moving.push(joint.clone());
        self.references.push(reference);
        self.armature.push((joint.clone(), a.number("armature", 0.0)?));
        if a.number("frictionloss", 0.0)? > 0.0 {
            ctx.note("frictionloss", "joint Coulomb friction", &joint, false);
        }
        if a.number("stiffness", 0.0)? != 0.0 {
            ctx.note("stiffness", "not simulated: faze4 has no joint springs", &joint, true);
        }
        Ok(())
    }

    /// Adds moving joint `desc` (its axis, limits and parent set) that moves body `name` placed
    /// at `placement` in its parent: the file places the body at q = `ref`, so faze4's q = 0 is
    /// a motion of −ref from there; a hinge at `pos` ≠ 0 moves a massless link there, to which
    /// the body is welded. Returns the `ref` (rad or m).
    fn attach(
        &mut self,
        mut desc: JointDesc,
        a: &Attrs,
        name: &str,
        placement: Pose,
        ctx: &Context,
        hinge: bool,
    ) -> Result<f64> {
        let axis = Vec3::from(desc.axis);
        let unit = if axis.norm() > 0.0 { axis / axis.norm() } else { axis };
        let reference = a.number("ref", 0.0)?;
        let (undo, reference) = match hinge {
            true => {
                let reference = ctx.compiler.angles.radians(reference);
                let (s, c) = (-reference).sin_cos();
                (Pose::new(rotation_about_axis(&unit, s, c), Vec3::zeros()), reference)
            }
            false => (Pose::new(Mat3::identity(), -unit * reference), reference),
        };
        let pos = Vec3::from(a.vector("pos", [0.0; 3])?);
        let through = Pose::new(Mat3::identity(), pos);
        if hinge && pos != Vec3::zeros() {
            let axis_link = format!("{name}:{}", desc.name);
            let weld = format!("{name} (on {})", desc.name);
            desc.child = axis_link.clone();
            desc.origin = placement.compose(&through).compose(&undo);
            self.links.push(LinkDesc {
                name: axis_link.clone(),
                ..LinkDesc::default()
            });
            self.joints.push(desc);
            self.weld(weld, &axis_link, name, through.inverse());
        } else {
            desc.child = name.to_string();
            desc.origin = placement.compose(&undo);
            self.joints.push(desc);
        }
        Ok(reference)
    }

    /// A fixed joint `name` welding link `child` to `parent` at `origin`.
    fn weld(&mut self, name: String, parent: &str, child: &str, origin: Pose) {
        self.joints.push(JointDesc {
            name,
            kind: JointType::Fixed,
            parent: parent.to_string(),
            child: child.to_string(),
            origin,
            axis: [0.0, 0.0, 1.0],
            limits: None,
            effort: None,
            velocity: None,
            damping: 0.0,
            friction: 0.0,
            mimic: None,
        });
    }

    /// A named site: a link welded to its body (`parent`), a frame to take as the tool. One
    /// named as a body is left out.
    fn site(&mut self, item: &Item, parent: &str, ctx: &Context) -> Result<()> {
        let Some(name) = item.element.get("name") else {
            return Ok(());
        };
        if self.links.iter().any(|l| l.name == name) {
            ctx.note("site", "left out: a body has its name", name, false);
            return Ok(());
        }
        let class = ctx.classes.class_of(item.element, item.childclass, ctx.file)?;
        let placement = item
            .frame
            .compose(&ctx.attrs(item.element, class).pose(&ctx.compiler.angles)?);
        self.links.push(LinkDesc {
            name: name.to_string(),
            ..LinkDesc::default()
        });
        self.weld(format!("{name} (site)"), parent, name, placement);
        Ok(())
    }

    /// Body `name`'s link: its inertial, its geoms as visuals and collision elements.
    fn link(&mut self, name: &str, body: &Element, items: &[Item], ctx: &Context) -> Result<LinkDesc> {
        let mut link = LinkDesc {
            name: name.to_string(),
            ..LinkDesc::default()
        };
        let inertial = body.all("inertial").next();
        let from_geoms = match ctx.compiler.from_geom {
            FromGeom::Always => true,
            FromGeom::Auto => inertial.is_none(),
            FromGeom::Never => false,
        };
        link.inertial = match (from_geoms, inertial) {
            (false, Some(element)) => Some(inertial_desc(&ctx.attrs(element, MAIN), ctx)?),
            _ => None,
        };
        let mut geoms_inertia = Inertia::ZERO;
        for item in items.iter().filter(|i| i.element.name == "geom") {
            let class = ctx.classes.class_of(item.element, item.childclass, ctx.file)?;
            let a = ctx.attrs(item.element, class);
            let Some(GeomShape {
                placement,
                shape,
                kind,
                size,
            }) = geom_shape(&a, item.frame, name, ctx)?
            else {
                continue;
            };
            if from_geoms {
                geoms_inertia += geom_inertia(&a, &placement, kind, &size, name, ctx)?;
            }
            let Some(shape) = shape else { continue };
            let group = a.number("group", 0.0)?;
            if (0.0..=2.0).contains(&group) {
                link.visuals.push(Visual {
                    origin: placement,
                    geometry: shape.clone(),
                    rgba: Some(geom_rgba(&a, ctx)?),
                });
            }
            if a.number("contype", 1.0)? != 0.0 || a.number("conaffinity", 1.0)? != 0.0 {
                link.collisions.push(Collision {
                    origin: placement,
                    geometry: shape,
                });
            }
        }
        if from_geoms && geoms_inertia.mass > 0.0 {
            link.inertial = Some(InertialDesc {
                origin: Pose::new(Mat3::identity(), geoms_inertia.com()),
                mass: geoms_inertia.mass,
                inertia: {
                    let i = geoms_inertia.rot_about_com();
                    [i[(0, 0)], i[(0, 1)], i[(0, 2)], i[(1, 1)], i[(1, 2)], i[(2, 2)]]
                },
            });
        }
        Ok(link)
    }
}

/// The refusal of a free joint (a floating base) on body `body`.
fn free_joint(ctx: &Context, element: &Element, body: &str) -> Error {
    Error::model(
        ctx.file,
        label(element, ctx.file),
        format!(
            "body '{body}' floats on a free joint (a floating base): faze4 simulates an arm fixed to the world; remove the free joint to fix its base"
        ),
    )
}

/// A hinge's or slide's axis, limits and damping (its parent, child and origin are set by the
/// caller).
fn joint_desc(a: &Attrs, name: &str, ctx: &Context, hinge: bool) -> Result<JointDesc> {
    let range = a.list("range", Some(2))?;
    let limited = a.flag("limited")?.unwrap_or(ctx.compiler.autolimits && range.is_some());
    let limits = match (limited, range) {
        (false, _) => None,
        (true, None) => return Err(a.error("is limited but gives no range")),
        (true, Some(r)) if hinge => Some((ctx.compiler.angles.radians(r[0]), ctx.compiler.angles.radians(r[1]))),
        (true, Some(r)) => Some((r[0], r[1])),
    };
    let force = a.list("actuatorfrcrange", Some(2))?;
    let force_limited = a
        .flag("actuatorfrclimited")?
        .unwrap_or(ctx.compiler.autolimits && force.is_some());
    Ok(JointDesc {
        name: name.to_string(),
        kind: match (hinge, limits) {
            (true, None) => JointType::Continuous,
            (true, Some(_)) => JointType::Revolute,
            (false, _) => JointType::Prismatic,
        },
        parent: String::new(),
        child: String::new(),
        origin: Pose::IDENTITY,
        axis: a.vector("axis", [0.0, 0.0, 1.0])?,
        limits,
        effort: force
            .filter(|_| force_limited)
            .map(|r| (-r[0]).min(r[1]))
            .filter(|&e| e > 0.0),
        velocity: None,
        damping: a.number("damping", 0.0)?,
        friction: a.number("frictionloss", 0.0)?,
        mimic: None,
    })
}

/// An `<inertial>`: `pos`, `mass`, and `diaginertia` (in the frame its orientation gives) or
/// `fullinertia` (in the body's axes).
fn inertial_desc(a: &Attrs, ctx: &Context) -> Result<InertialDesc> {
    let origin = a.pose(&ctx.compiler.angles)?;
    let mass = a.number("mass", f64::NAN)?;
    if mass.is_nan() {
        return Err(a.error("gives no mass"));
    }
    let inertia = match (a.list("diaginertia", Some(3))?, a.list("fullinertia", Some(6))?) {
        (Some(d), None) => [d[0], 0.0, 0.0, d[1], 0.0, d[2]],
        (None, Some(f)) => [f[0], f[3], f[4], f[1], f[5], f[2]],
        (None, None) => return Err(a.error("gives neither diaginertia nor fullinertia")),
        (Some(_), Some(_)) => return Err(a.error("gives both diaginertia and fullinertia: give one")),
    };
    Ok(InertialDesc { origin, mass, inertia })
}

/// A geom as its body's link holds it.
struct GeomShape {
    /// Its placement in the body's frame.
    placement: Pose,
    /// Its shape for the views and the clearance (`None`: one faze4 does not draw).
    shape: Option<Geometry>,
    /// Its MJCF type.
    kind: &'static str,
    /// Its MJCF size (half sizes, radius and half length), at least three numbers.
    size: Vec<f64>,
}

/// A geom read; `None` for a plane or height field (left out).
fn geom_shape(a: &Attrs, frame: Pose, body: &str, ctx: &Context) -> Result<Option<GeomShape>> {
    let kind = match a.text("type").unwrap_or("sphere") {
        "sphere" => "sphere",
        "capsule" => "capsule",
        "cylinder" => "cylinder",
        "ellipsoid" => "ellipsoid",
        "box" => "box",
        "mesh" => "mesh",
        other => {
            let name = a
                .element
                .get("name")
                .map_or_else(|| format!("{other} on {body}"), str::to_string);
            ctx.note(
                &format!("{other} geom"),
                "left out: no extent faze4 draws or checks",
                &name,
                false,
            );
            return Ok(None);
        }
    };
    let mut size = a.list("size", None)?.unwrap_or_default();
    size.resize(3, 0.0);
    let placement = match a
        .list("fromto", Some(6))?
        .filter(|_| kind != "sphere" && kind != "mesh")
    {
        Some(p) => {
            let (pose, half) = fromto_pose([p[0], p[1], p[2], p[3], p[4], p[5]]);
            let along = if kind == "capsule" || kind == "cylinder" { 1 } else { 2 };
            size[along] = half;
            frame.compose(&pose)
        }
        None => frame.compose(&a.pose(&ctx.compiler.angles)?),
    };
    let name = || {
        a.element
            .get("name")
            .map_or_else(|| format!("{kind} on {body}"), str::to_string)
    };
    let shape = match kind {
        "sphere" => Some(Geometry::Sphere { radius: size[0] }),
        "box" => Some(Geometry::Box {
            size: Vec3::new(size[0], size[1], size[2]) * 2.0,
        }),
        "cylinder" => Some(Geometry::Cylinder {
            radius: size[0],
            length: 2.0 * size[1],
        }),
        "capsule" => Some(Geometry::Capsule {
            radius: size[0],
            length: 2.0 * size[1],
        }),
        "ellipsoid" => {
            ctx.note("ellipsoid geom", "the box around it", &name(), false);
            Some(Geometry::Box {
                size: Vec3::new(size[0], size[1], size[2]) * 2.0,
            })
        }
        _ => mesh_shape(a, ctx)?,
    };
    Ok(Some(GeomShape {
        placement,
        shape,
        kind,
        size,
    }))
}

/// A mesh geom's file (located, not read) and scale; `None` for a mesh given by its vertices.
fn mesh_shape(a: &Attrs, ctx: &Context) -> Result<Option<Geometry>> {
    let Some(name) = a.text("mesh") else {
        return Err(a.error("is a mesh geom without a mesh"));
    };
    let Some(asset) = ctx.meshes.get(name) else {
        return Err(a.error(format!("names mesh '{name}', which no <mesh> asset defines")));
    };
    let Some(asset) = asset.clone() else {
        ctx.note("mesh without a file", "left out: faze4 reads mesh files", name, false);
        return Ok(None);
    };
    let (reference, path) = ctx.mesh_path(&asset.file);
    Ok(Some(Geometry::Mesh {
        uri: reference.display().to_string(),
        path,
        scale: asset.scale,
    }))
}

/// A geom's mass properties about its body's origin, for a body whose inertia comes from its
/// geoms: its `mass`, else `density` (1000 kg/m³) times its volume; a geom outside the compiler's
/// `inertiagrouprange` adds nothing, a mesh geom is refused (faze4 does not integrate meshes).
fn geom_inertia(a: &Attrs, placement: &Pose, kind: &str, size: &[f64], body: &str, ctx: &Context) -> Result<Inertia> {
    let group = a.number("group", 0.0)? as i64;
    if group < ctx.compiler.groups.0 || group > ctx.compiler.groups.1 {
        return Ok(Inertia::ZERO);
    }
    let Some((volume, unit)) = unit_inertia(kind, size) else {
        return Err(a.error(format!(
            "body '{body}' has no <inertial>, so MuJoCo takes its inertia from its geoms, and faze4 does not compute a mesh's: give the body an <inertial>"
        )));
    };
    if a.flag("shellinertia")? == Some(true) {
        return Err(
            a.error("shellinertia=\"true\": faze4 computes solid geoms' inertia only; give the body an <inertial>")
        );
    }
    let density = match a.list("mass", Some(1))? {
        Some(m) if volume > 0.0 => m[0] / volume,
        Some(_) => 0.0,
        None => a.number("density", 1000.0)?,
    };
    let i_com = placement.rot * Mat3::from_diagonal(&Vec3::from(unit.map(|x| x * density))) * placement.rot.transpose();
    Ok(Inertia::from_com(density * volume, placement.pos, i_com))
}

/// A geom's colour as MuJoCo documents it: its `rgba` (its own or its class's) where that is not
/// MuJoCo's grey, else its material's, else the grey.
fn geom_rgba(a: &Attrs, ctx: &Context) -> Result<[f64; 4]> {
    let rgba = (a.list("rgba", Some(4))?).map_or(DEFAULT_RGBA, |c| [c[0], c[1], c[2], c[3]]);
    let material = (a.text("material")).and_then(|m| ctx.materials.get(m).copied());
    Ok(match (rgba == DEFAULT_RGBA, material) {
        (true, Some(m)) => m,
        _ => rgba,
    })
}

/// The elements of `parent` with the frames around them: a `<frame>`'s children take its
/// placement and `childclass`, nested frames compose.
fn items<'a>(parent: &'a Element, frame: Pose, childclass: &'a str, ctx: &Context) -> Result<Vec<Item<'a>>> {
    let mut found = Vec::new();
    for element in &parent.children {
        if element.name == "frame" {
            let inner = element.get("childclass").unwrap_or(childclass);
            let placement = frame.compose(&ctx.attrs(element, MAIN).pose(&ctx.compiler.angles)?);
            found.extend(items(element, placement, inner, ctx)?);
        } else {
            found.push(Item {
                element,
                frame,
                childclass,
            });
        }
    }
    Ok(found)
}
