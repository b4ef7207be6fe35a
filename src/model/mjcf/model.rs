//! An MJCF model's sections around its body tree: `<compiler>`, `<option>`, `<asset>` (meshes,
//! materials), `<actuator>` (effort limits), `<equality>` (mimic joints), `<keyframe>` (the
//! `home` pose), `<tendon>`; and the attribute access the body tree shares.

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::body::Tree;
use super::classes::{ACTUATORS, Classes, MAIN};
use super::context::{Attrs, Compiler, Context, FromGeom, MeshAsset};
use super::frames::Angles;
use super::xml::Element;
use crate::error::Result;
use crate::model::{MimicDesc, RobotDescription, TransmissionDesc};
use crate::spatial::Vec3;

/// The description of the model `root` (`<mujoco>`) read from `file`.
pub(super) fn describe(root: &Element, file: &str, base_dir: Option<&Path>) -> Result<RobotDescription> {
    let classes = Classes::of(root, file)?;
    let mut ctx = Context {
        file,
        base_dir,
        compiler: compiler(root, &classes, file)?,
        classes,
        meshes: HashMap::new(),
        materials: HashMap::new(),
        mapped: RefCell::new(Vec::new()),
    };
    assets(root, &mut ctx)?;
    option(root, &ctx)?;
    let mut tree = Tree::new();
    for world in root.all("worldbody") {
        tree.world(world, &ctx)?;
    }
    let mut desc = RobotDescription {
        name: root.get("model").unwrap_or("MuJoCo Model").to_string(),
        file: file.to_string(),
        format: "mjcf".into(),
        ..RobotDescription::default()
    };
    actuators(root, &ctx, &mut tree)?;
    let followers = equalities(root, &ctx, &mut tree)?;
    desc.home = keyframe(root, &ctx, &tree)?;
    tendons(root, &ctx)?;
    armature(&ctx, &mut tree, &followers, &mut desc.transmissions);
    desc.links = tree.links;
    desc.joints = tree.joints;
    desc.mapped = ctx.mapped.into_inner();
    Ok(desc)
}

/// The `<compiler>` settings (several elements: the later ones win).
fn compiler(root: &Element, classes: &Classes, file: &str) -> Result<Compiler> {
    let mut c = Compiler {
        angles: Angles::default(),
        meshdir: None,
        autolimits: true,
        from_geom: FromGeom::Auto,
        groups: (0, 5),
        strippath: false,
    };
    for element in root.all("compiler") {
        let a = Attrs {
            element,
            class: MAIN,
            classes,
            file,
        };
        match a.text("angle") {
            None => {}
            Some("degree") => c.angles.degrees = true,
            Some("radian") => c.angles.degrees = false,
            Some(other) => return Err(a.error(format!("angle=\"{other}\" is not degree or radian"))),
        }
        if let Some(seq) = a.text("eulerseq") {
            let b = seq.as_bytes();
            if b.len() != 3 || !b.iter().all(|c| b"xyzXYZ".contains(c)) {
                return Err(a.error(format!("eulerseq=\"{seq}\" is not three of x, y, z, X, Y, Z")));
            }
            c.angles.eulerseq = [b[0], b[1], b[2]];
        }
        if let Some(dir) = a.text("meshdir").or(a.text("assetdir")) {
            c.meshdir = Some(PathBuf::from(dir));
        }
        c.autolimits = a.flag("autolimits")?.unwrap_or(c.autolimits);
        c.strippath = a.flag("strippath")?.unwrap_or(c.strippath);
        c.from_geom = match a.text("inertiafromgeom") {
            None => c.from_geom,
            Some("auto") => FromGeom::Auto,
            Some("true") => FromGeom::Always,
            Some("false") => FromGeom::Never,
            Some(other) => return Err(a.error(format!("inertiafromgeom=\"{other}\" is not true, false or auto"))),
        };
        if let Some(g) = a.list("inertiagrouprange", Some(2))? {
            c.groups = (g[0] as i64, g[1] as i64);
        }
        refuse_compiler(&a)?;
    }
    Ok(c)
}

/// The `<compiler>` settings that change masses or coordinates, which faze4 does not apply.
fn refuse_compiler(a: &Attrs) -> Result<()> {
    for key in ["boundmass", "boundinertia", "settotalmass"] {
        if a.number(key, 0.0)? > 0.0 {
            return Err(a.error(format!(
                "{key} changes the masses the file gives; faze4 does not apply it"
            )));
        }
    }
    if a.flag("balanceinertia")? == Some(true) {
        return Err(a.error("balanceinertia=\"true\": faze4 applies it only when asked (`balance_inertia`)"));
    }
    if a.text("coordinate").is_some_and(|c| c != "local") {
        return Err(a.error("coordinate=\"global\" is not read (MuJoCo itself dropped it in 2.3.3)"));
    }
    Ok(())
}

/// `<asset>`: meshes (name → file and scale) and materials (name → colour).
fn assets(root: &Element, ctx: &mut Context) -> Result<()> {
    for asset in root.all("asset") {
        for mesh in asset.all("mesh") {
            let class = ctx.classes.class_of(mesh, MAIN, ctx.file)?;
            let a = ctx.attrs(mesh, class);
            let file = a.text("file");
            let name = match (a.element.get("name"), file) {
                (Some(name), _) => name.to_string(),
                (None, Some(file)) => {
                    let stem = Path::new(file).file_stem().map(|s| s.to_string_lossy().into_owned());
                    stem.unwrap_or_else(|| file.to_string())
                }
                (None, None) => return Err(a.error("has neither a name nor a file")),
            };
            let scale = Vec3::from(a.vector("scale", [1.0; 3])?);
            let asset = file.map(|f| MeshAsset {
                file: f.to_string(),
                scale,
            });
            ctx.meshes.insert(name, asset);
        }
        for material in asset.all("material") {
            let class = ctx.classes.class_of(material, MAIN, ctx.file)?;
            let a = ctx.attrs(material, class);
            if let (Some(name), Some(rgba)) = (material.get("name"), a.list("rgba", Some(4))?) {
                ctx.materials
                    .insert(name.to_string(), [rgba[0], rgba[1], rgba[2], rgba[3]]);
            }
        }
    }
    Ok(())
}

/// `<option gravity>`: faze4 simulates standard gravity (9.81 m/s² down), so another is listed.
fn option(root: &Element, ctx: &Context) -> Result<()> {
    for element in root.all("option") {
        let a = ctx.attrs(element, MAIN);
        let g = a.vector("gravity", [0.0, 0.0, -9.81])?;
        if g != [0.0, 0.0, -9.81] {
            let item = format!("{} {} {}", g[0], g[1], g[2]);
            ctx.note(
                "option gravity",
                "not simulated: faze4's gravity is 9.81 m/s² down (`no_gravity`: none)",
                &item,
                true,
            );
        }
    }
    Ok(())
}

/// Each actuator on a joint: its force limit through its gear is the joint's effort limit
/// (several on one joint add up); a joint's own `actuatorfrcrange` bounds them.
fn actuators(root: &Element, ctx: &Context, tree: &mut Tree) -> Result<()> {
    let mut effort: HashMap<String, f64> = HashMap::new();
    for section in root.all("actuator") {
        for element in section.children.iter().filter(|c| ACTUATORS.contains(&c.name.as_str())) {
            let class = ctx.classes.class_of(element, MAIN, ctx.file)?;
            let a = ctx.attrs(element, class);
            let Some(joint) = a.text("joint").or(a.text("jointinparent")) else {
                let name = element.get("name").unwrap_or(&element.name).to_string();
                ctx.note(
                    "actuator on a tendon, site or body",
                    "left out: faze4 drives joints",
                    &name,
                    false,
                );
                continue;
            };
            if !tree
                .joints
                .iter()
                .any(|j| j.name == joint && j.kind != crate::model::JointType::Fixed)
            {
                return Err(a.error(format!(
                    "drives joint '{joint}', which is not a moving joint of the model"
                )));
            }
            let Some((limit, from)) = actuator_limit(&a, ctx.compiler.autolimits, &ctx.classes)? else {
                continue;
            };
            *effort.entry(joint.to_string()).or_default() += limit;
            ctx.note(from, "effort limit (× |gear|)", joint, false);
        }
    }
    for joint in tree.joints.iter_mut() {
        let limit = effort.get(&joint.name).copied();
        joint.effort = match (limit, joint.effort) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
    }
    Ok(())
}

/// An actuator's effort limit at its joint, |gear| times its force limit: its `forcerange`
/// when force-limited, else a torque actuator's (`motor`, or `general` with a fixed gain and no
/// bias) `ctrlrange` times its gain. A range lo…hi gives min(−lo, hi) when it spans 0 (faze4's
/// limit is symmetric), else its larger magnitude. `None`: no limit.
fn actuator_limit(a: &Attrs, autolimits: bool, classes: &Classes) -> Result<Option<(f64, &'static str)>> {
    let gear = a
        .list("gear", None)?
        .and_then(|g| g.first().copied())
        .unwrap_or(1.0)
        .abs();
    let span = |r: &[f64]| match r[0] < 0.0 && r[1] > 0.0 {
        true => (-r[0]).min(r[1]),
        false => r[0].abs().max(r[1].abs()),
    };
    let limited = |key: &str, range: &Option<Vec<f64>>| -> Result<bool> {
        Ok(a.flag(key)?.unwrap_or(autolimits && range.is_some()) && range.is_some())
    };
    let force = a.list("forcerange", Some(2))?;
    if limited("forcelimited", &force)? {
        return Ok(force.map(|r| (gear * span(&r), "actuator forcerange")));
    }
    let ctrl = a.list("ctrlrange", Some(2))?;
    let gain = match a.element.name.as_str() {
        "motor" => Some(1.0),
        "general" => general_gain(a, classes)?,
        _ => None,
    };
    match (gain, limited("ctrllimited", &ctrl)?) {
        (Some(gain), true) => Ok(ctrl.map(|r| (gear * gain.abs() * span(&r), "motor ctrlrange"))),
        _ => Ok(None),
    }
}

/// A `general` actuator's gain when its force is gain × control (a fixed gain and no bias), else
/// `None`. A class's default written as a shortcut (`<position>`, …) sets the gain and bias
/// types the shortcut stands for.
fn general_gain(a: &Attrs, classes: &Classes) -> Result<Option<f64>> {
    let own = |key: &str| a.element.get(key);
    let inherited = |key: &str| {
        classes
            .chain("actuator", a.class)
            .find_map(|d| match (d.name.as_str(), d.get(key)) {
                ("general", Some(v)) => Some(v),
                ("general", None) => None,
                ("motor", _) if key == "biastype" => Some("none"),
                ("motor", _) => Some("fixed"),
                (_, _) if key == "biastype" => Some("affine"),
                (_, _) => Some("fixed"),
            })
    };
    let gaintype = own("gaintype").or_else(|| inherited("gaintype")).unwrap_or("fixed");
    let biastype = own("biastype").or_else(|| inherited("biastype")).unwrap_or("none");
    if gaintype != "fixed" || biastype != "none" {
        return Ok(None);
    }
    Ok(Some(
        a.list("gainprm", None)?.and_then(|g| g.first().copied()).unwrap_or(1.0),
    ))
}

/// `<equality joint>` as mimic joints: `joint1` follows `joint2`,
/// q₁ − ref₁ = c₀ + c₁ (q₂ − ref₂); a polynomial of higher degree, a joint held fixed, or
/// another kind of equality is refused. Returns each follower with its leader and multiplier.
fn equalities(root: &Element, ctx: &Context, tree: &mut Tree) -> Result<Vec<(String, String, f64)>> {
    let mut followers = Vec::new();
    for section in root.all("equality") {
        for element in &section.children {
            let class = ctx.classes.class_of(element, MAIN, ctx.file)?;
            let a = ctx.attrs(element, class);
            if a.flag("active")? == Some(false) {
                ctx.note("inactive equality", "left out, as MuJoCo leaves it", &a.label(), false);
                continue;
            }
            if element.name != "joint" {
                return Err(a.error(format!(
                    "an <equality {}> constraint is not simulated: faze4 reads <equality joint> (a mimic joint) only",
                    element.name
                )));
            }
            let (Some(j1), Some(j2)) = (a.text("joint1"), a.text("joint2")) else {
                return Err(a.error("holds joint1 at a constant: faze4 reads an equality of two joints (a mimic)"));
            };
            let c = a.vector("polycoef", [0.0, 1.0, 0.0, 0.0, 0.0])?;
            if c[2..].iter().any(|&x| x != 0.0) {
                return Err(a.error("polycoef has terms of degree 2 or more: faze4 reads a linear mimic only"));
            }
            let reference = |name: &str| {
                tree.reference(name).ok_or_else(|| {
                    a.error(format!(
                        "names joint '{name}', which is not a moving joint of the model"
                    ))
                })
            };
            let (ref1, ref2) = (reference(j1)?, reference(j2)?);
            let follower = tree.joints.iter_mut().find(|j| j.name == j1).expect("found above");
            follower.mimic = Some(MimicDesc {
                joint: j2.to_string(),
                multiplier: c[1],
                offset: c[0] + ref1 - c[1] * ref2,
            });
            ctx.note("equality joint", "mimic joint", j1, false);
            followers.push((j1.to_string(), j2.to_string(), c[1]));
        }
    }
    Ok(followers)
}

/// The `home` keyframe's `qpos` as each moving joint's position.
fn keyframe(root: &Element, ctx: &Context, tree: &Tree) -> Result<Option<Vec<(String, f64)>>> {
    let home = (root.all("keyframe"))
        .flat_map(|k| k.all("key"))
        .find(|k| k.get("name") == Some("home"));
    let Some(home) = home else { return Ok(None) };
    let a = ctx.attrs(home, MAIN);
    let Some(qpos) = a.list("qpos", None)? else {
        return Ok(None);
    };
    if qpos.len() != tree.moving.len() {
        return Err(a.error(format!(
            "qpos has {} numbers for the model's {} joint positions",
            qpos.len(),
            tree.moving.len()
        )));
    }
    ctx.note("keyframe home", "start pose (`center` home)", "home", false);
    Ok(Some(tree.moving.iter().cloned().zip(qpos).collect()))
}

/// Tendons: faze4 simulates none; one with stiffness, damping, friction, armature or a limited
/// length changes the dynamics and is listed as not simulated.
fn tendons(root: &Element, ctx: &Context) -> Result<()> {
    for section in root.all("tendon") {
        for element in &section.children {
            let class = ctx.classes.class_of(element, MAIN, ctx.file)?;
            let a = ctx.attrs(element, class);
            let mut acts = false;
            for key in ["stiffness", "damping", "frictionloss", "armature"] {
                acts |= a.number(key, 0.0)? != 0.0;
            }
            acts |= a
                .flag("limited")?
                .unwrap_or(ctx.compiler.autolimits && a.text("range").is_some());
            let name = element.get("name").unwrap_or(&element.name).to_string();
            match acts {
                true => ctx.note("tendon", "not simulated: faze4 has no tendons", &name, true),
                false => ctx.note("tendon", "left out: it exerts no force of its own", &name, false),
            }
        }
    }
    Ok(())
}

/// Each joint's `armature` as its motor's rotor inertia at gear ratio 1 (its reflected inertia,
/// on M's diagonal as MuJoCo adds it); a mimic follower's, m² times it, goes to its leader (the
/// follower moves m times as fast).
fn armature(ctx: &Context, tree: &mut Tree, followers: &[(String, String, f64)], out: &mut Vec<TransmissionDesc>) {
    let mut total: Vec<(String, f64)> = Vec::new();
    for (joint, a) in tree.armature.drain(..) {
        let (target, scale) = match followers.iter().find(|(f, ..)| *f == joint) {
            Some((_, leader, m)) => (leader.clone(), m * m),
            None => (joint.clone(), 1.0),
        };
        match total.iter_mut().find(|(j, _)| *j == target) {
            Some((_, sum)) => *sum += scale * a,
            None => total.push((target, scale * a)),
        }
        ctx.note("armature", "rotor inertia at gear ratio 1", &joint, false);
    }
    out.extend(
        total
            .into_iter()
            .filter(|(_, a)| *a > 0.0)
            .map(|(joint, a)| TransmissionDesc {
                name: format!("{joint} armature"),
                joint,
                rotor_inertia: Some(a),
                gear_ratio: None,
            }),
    );
}
