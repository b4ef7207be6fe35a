//! URDF files → [`RobotDescription`] (links, joints, visuals, collision elements, transmissions)
//! → [`Model`]. The only place that knows urdf-rs.
//!
//! urdf-rs parses the XML; everything it lets through unchecked is checked by the model
//! builder (missing links, loops, non-finite numbers, zero axes, bad inertias). Known urdf-rs
//! behaviours this module works around: `package://` paths are resolved here (urdf-rs's own
//! expansion needs ROS), a missing `<limit>` reads as all zeros (taken as "no limits"), and
//! `<transmission>` is dropped, so [`transmissions`] reads it beside urdf-rs.

use std::cell::Cell;
use std::path::Path;
use std::sync::Once;

use super::description::{
    Collision, Geometry, InertialDesc, JointDesc, JointType, LinkDesc, MimicDesc, RobotDescription, TransmissionDesc,
    Visual,
};
use super::{Model, PackagePaths};
use crate::error::{Error, Result, one_line};
use crate::spatial::{Pose, Vec3};

/// Reads and validates the URDF file at `path`: its dynamics model. Mesh files are only
/// located (`packages` resolves `package://`), not read.
pub fn read_file(path: &Path, packages: &PackagePaths) -> Result<Model> {
    read_str(&read_text(path)?, &path.display().to_string(), path.parent(), packages)
}

/// The text of the URDF file at `path` (UTF-8).
pub fn read_text(path: &Path) -> Result<String> {
    let text = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let text = String::from_utf8(text).map_err(|_| Error::UrdfSyntax {
        file: path.display().to_string(),
        message: "the file is not UTF-8 text".into(),
    })?;
    Ok(text)
}

/// Reads and validates URDF `text`; `file` names it in errors, `base_dir` anchors relative
/// mesh paths.
pub fn read_str(text: &str, file: &str, base_dir: Option<&Path>, packages: &PackagePaths) -> Result<Model> {
    Model::from_description(&describe(text, file, base_dir, packages)?)
}

/// Parses URDF `text` into a description, resolving mesh references. No validation beyond
/// the XML structure.
pub fn describe(text: &str, file: &str, base_dir: Option<&Path>, packages: &PackagePaths) -> Result<RobotDescription> {
    let syntax = |message: String| Error::UrdfSyntax {
        file: file.to_string(),
        message: one_line(&message),
    };
    if text.trim().is_empty() {
        return Err(syntax("the file is empty".into()));
    }
    // urdf-rs walks the element tree recursively, so deep nesting overflows the stack (a
    // crash, not a panic: catch_unwind cannot help). A URDF nests about 5 deep.
    if let Some(line) = nested_deeper_than(text, MAX_NESTING) {
        return Err(syntax(format!(
            "elements nest more than {MAX_NESTING} deep (line {line}); a URDF needs about 5 levels"
        )));
    }
    // urdf-rs panics on a few malformed inputs instead of returning an error (RustyXML's "No
    // namespace prefix bound" on `<" xmlns="N":=""/>`): catch it, quietly, and report it.
    let parsed = parse_quietly(text)
        .map_err(|panic| {
            syntax(format!(
                "the XML parser failed on this input (urdf-rs panicked: {panic})"
            ))
        })?
        .map_err(|e| syntax(e.to_string()))?;

    let links = parsed
        .links
        .iter()
        .map(|link| LinkDesc {
            name: link.name.clone(),
            inertial: Some(InertialDesc {
                xyz: link.inertial.origin.xyz.0,
                rpy: link.inertial.origin.rpy.0,
                mass: link.inertial.mass.value,
                inertia: {
                    let i = &link.inertial.inertia;
                    [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz]
                },
            }),
            visuals: link
                .visual
                .iter()
                .map(|v| visual(v, &parsed.materials, base_dir, packages))
                .collect(),
            collisions: (link.collision.iter())
                .map(|c| Collision {
                    origin: Pose::from_xyz_rpy(c.origin.xyz.0, c.origin.rpy.0),
                    geometry: geometry(&c.geometry, base_dir, packages),
                })
                .collect(),
        })
        .collect();

    let joints = parsed
        .joints
        .iter()
        .map(|j| {
            let kind = match j.joint_type {
                urdf_rs::JointType::Revolute => JointType::Revolute,
                urdf_rs::JointType::Continuous => JointType::Continuous,
                urdf_rs::JointType::Prismatic => JointType::Prismatic,
                urdf_rs::JointType::Fixed => JointType::Fixed,
                ref other => JointType::Unsupported(format!("{other:?}").to_lowercase()),
            };
            let lim = &j.limit;
            let no_limit_element = lim.lower == 0.0 && lim.upper == 0.0 && lim.effort == 0.0 && lim.velocity == 0.0;
            JointDesc {
                name: j.name.clone(),
                kind,
                parent: j.parent.link.clone(),
                child: j.child.link.clone(),
                xyz: j.origin.xyz.0,
                rpy: j.origin.rpy.0,
                axis: j.axis.xyz.0,
                limits: (!no_limit_element).then_some((lim.lower, lim.upper)),
                // 0 is urdf-rs's value for an absent attribute: no limit; a negative one is
                // refused by the model's checks, not read as none
                effort: (lim.effort != 0.0).then_some(lim.effort),
                velocity: (lim.velocity != 0.0).then_some(lim.velocity),
                damping: j.dynamics.as_ref().map_or(0.0, |d| d.damping),
                mimic: j.mimic.as_ref().map(|m| MimicDesc {
                    joint: m.joint.clone(),
                    multiplier: m.multiplier.unwrap_or(1.0),
                    offset: m.offset.unwrap_or(0.0),
                }),
            }
        })
        .collect();

    Ok(RobotDescription {
        name: parsed.name.clone(),
        file: file.to_string(),
        links,
        joints,
        transmissions: transmissions(text).map_err(syntax)?,
    })
}

/// The `<transmission>` elements of URDF `text`, as Drake reads a motor from them:
///
/// ```xml
/// <transmission name="t1">
///   <type>transmission_interface/SimpleTransmission</type>
///   <joint name="j1"/>
///   <actuator name="m1">
///     <drake:rotor_inertia value="5.4e-6"/>  <!-- kg·m², at the motor shaft -->
///     <drake:gear_ratio value="25"/>         <!-- motor turns per joint turn -->
///   </actuator>
/// </transmission>
/// ```
///
/// A transmission without a `<joint name>` is skipped; the values are checked by the model
/// builder. Fails on malformed XML or a value that is not a number.
pub fn transmissions(text: &str) -> std::result::Result<Vec<TransmissionDesc>, String> {
    use quick_xml::events::{BytesStart, Event};
    if !text.contains("<transmission") {
        return Ok(Vec::new());
    }
    let attribute = |e: &BytesStart, key: &str| -> std::result::Result<Option<String>, String> {
        let attr = e.try_get_attribute(key).map_err(|err| err.to_string())?;
        attr.map(|a| {
            a.unescape_value()
                .map(|v| v.trim().to_string())
                .map_err(|err| err.to_string())
        })
        .transpose()
    };
    let mut reader = quick_xml::Reader::from_str(text);
    let mut found = Vec::new();
    let mut current: Option<(TransmissionDesc, bool)> = None;
    loop {
        let event = reader
            .read_event()
            .map_err(|e| format!("<transmission>: {e} (at byte {})", reader.error_position()))?;
        let (element, closes) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(e) if e.name().as_ref() == b"transmission" => {
                if let Some((t, true)) = current.take() {
                    found.push(t);
                }
                continue;
            }
            Event::Eof => return Ok(found),
            _ => continue,
        };
        match element.name().as_ref() {
            b"transmission" if !closes => {
                let name = attribute(element, "name")?.unwrap_or_default();
                let t = TransmissionDesc {
                    name,
                    joint: String::new(),
                    rotor_inertia: None,
                    gear_ratio: None,
                };
                current = Some((t, false));
            }
            b"joint" => {
                if let (Some((t, has_joint)), Some(name)) = (current.as_mut(), attribute(element, "name")?) {
                    t.joint = name;
                    *has_joint = true;
                }
            }
            tag @ (b"drake:rotor_inertia" | b"drake:gear_ratio") => {
                let Some((t, _)) = current.as_mut() else { continue };
                let tag = String::from_utf8_lossy(tag).into_owned();
                let value = attribute(element, "value")?
                    .ok_or_else(|| format!("transmission '{}' <{tag}> has no value", t.name))?;
                let value: f64 = value
                    .parse()
                    .map_err(|_| format!("transmission '{}' <{tag}> value '{value}' is not a number", t.name))?;
                if tag == "drake:rotor_inertia" {
                    t.rotor_inertia = Some(value);
                } else {
                    t.gear_ratio = Some(value);
                }
            }
            _ => {}
        }
    }
}

thread_local! {
    /// Whether this thread is inside urdf-rs, under [`parse_quietly`]'s `catch_unwind`.
    static IN_PARSER: Cell<bool> = const { Cell::new(false) };
}

/// `urdf_rs::read_from_string(text)`, with a panic inside it caught and returned as its
/// message. The panic is not printed: a process-wide panic hook, installed on the first call,
/// stays silent for panics on a thread that is inside urdf-rs and hands every other panic to
/// the hook that was there before (by default the one that prints message and backtrace; under
/// the fuzzer, libFuzzer's, which aborts). A hook set after the first call replaces it, which
/// only makes a caught parser panic visible again.
fn parse_quietly(text: &str) -> std::result::Result<urdf_rs::Result<urdf_rs::Robot>, String> {
    quietly(|| urdf_rs::read_from_string(text))
}

/// `f()`, with a panic inside it caught and returned as its message, unprinted, as
/// [`parse_quietly`] does for urdf-rs (the mesh reader uses it for mesh-loader, which panics on
/// some malformed COLLADA files).
pub(crate) fn quietly<T>(f: impl FnOnce() -> T + std::panic::UnwindSafe) -> std::result::Result<T, String> {
    static QUIET_HOOK: Once = Once::new();
    QUIET_HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !IN_PARSER.get() {
                previous(info);
            }
        }));
    });
    IN_PARSER.set(true);
    let result = std::panic::catch_unwind(f);
    IN_PARSER.set(false);
    result.map_err(|payload| {
        (payload.downcast_ref::<&str>().map(|s| s.to_string()))
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into())
    })
}

/// The deepest element nesting [`describe`] hands to urdf-rs.
const MAX_NESTING: usize = 100;

/// The line on which XML `text` first has more than `limit` elements open, if it does. A
/// lexical scan (comments, CDATA, processing instructions, declarations and quoted attribute
/// values skipped), linear in the length of the text; malformed XML is left to the parser.
fn nested_deeper_than(text: &str, limit: usize) -> Option<usize> {
    let b = text.as_bytes();
    let find = |from: usize, pat: &[u8]| -> usize {
        (b.get(from..).unwrap_or_default().windows(pat.len()))
            .position(|w| w == pat)
            .map_or(b.len(), |p| from + p + pat.len())
    };
    let (mut depth, mut i) = (0usize, 0usize);
    while let Some(p) = b.get(i..).and_then(|rest| rest.iter().position(|&c| c == b'<')) {
        let at = i + p;
        let rest = &b[at..];
        i = if rest.starts_with(b"<!--") {
            find(at + 4, b"-->")
        } else if rest.starts_with(b"<![CDATA[") {
            find(at + 9, b"]]>")
        } else if rest.starts_with(b"<?") {
            find(at + 2, b"?>")
        } else if rest.starts_with(b"<!") || rest.starts_with(b"</") {
            depth = depth.saturating_sub(usize::from(rest.starts_with(b"</")));
            find(at + 1, b">")
        } else {
            // a start tag: find its '>' outside quotes; "/>" closes it at once
            let (mut j, mut quote) = (at + 1, None);
            while j < b.len() {
                match (quote, b[j]) {
                    (None, b'"' | b'\'') => quote = Some(b[j]),
                    (Some(q), c) if c == q => quote = None,
                    (None, b'>') => break,
                    _ => {}
                }
                j += 1;
            }
            if b.get(j.wrapping_sub(1)) != Some(&b'/') {
                depth += 1;
                if depth > limit {
                    return Some(1 + b[..at].iter().filter(|&&c| c == b'\n').count());
                }
            }
            j + 1
        };
    }
    None
}

fn visual(
    v: &urdf_rs::Visual,
    materials: &[urdf_rs::Material],
    base_dir: Option<&Path>,
    packages: &PackagePaths,
) -> Visual {
    let geometry = geometry(&v.geometry, base_dir, packages);
    // A colour inline, or by name from the robot's top-level <material> list.
    let rgba = v.material.as_ref().and_then(|m| {
        m.color
            .as_ref()
            .or_else(|| {
                materials
                    .iter()
                    .find(|g| g.name == m.name)
                    .and_then(|g| g.color.as_ref())
            })
            .map(|c| c.rgba.0)
    });
    Visual {
        origin: Pose::from_xyz_rpy(v.origin.xyz.0, v.origin.rpy.0),
        geometry,
        rgba,
    }
}

/// A `<geometry>` element; mesh references are resolved (the file is not read).
fn geometry(g: &urdf_rs::Geometry, base_dir: Option<&Path>, packages: &PackagePaths) -> Geometry {
    match g {
        urdf_rs::Geometry::Box { size } => Geometry::Box {
            size: Vec3::from(size.0),
        },
        urdf_rs::Geometry::Cylinder { radius, length } | urdf_rs::Geometry::Capsule { radius, length } => {
            Geometry::Cylinder {
                radius: *radius,
                length: *length,
            }
        }
        urdf_rs::Geometry::Sphere { radius } => Geometry::Sphere { radius: *radius },
        urdf_rs::Geometry::Mesh { filename, scale } => Geometry::Mesh {
            uri: filename.clone(),
            path: packages.resolve(filename, base_dir),
            scale: scale.map_or(Vec3::new(1.0, 1.0, 1.0), |s| Vec3::from(s.0)),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_depth_counts_elements_only() {
        let nested = |n: usize| format!("<robot>\n{}{}</robot>", "<a>".repeat(n), "</a>".repeat(n));
        assert_eq!(nested_deeper_than(&nested(99), 100), None);
        assert_eq!(nested_deeper_than(&nested(100), 100), Some(2));
        // siblings, empty elements, comments, CDATA, declarations and quoted '>' do not nest
        let flat = format!(
            "<?xml version=\"1.0\"?><!DOCTYPE robot><robot>{}<!-- {} --><![CDATA[{}]]><a b=\"/>\" c='>'>x</a></robot>",
            "<link name=\"x\"/><joint></joint>".repeat(500),
            "<a>".repeat(500),
            "<a>".repeat(500)
        );
        assert_eq!(nested_deeper_than(&flat, 3), None);
        assert_eq!(nested_deeper_than("<a><b><c><d>", 3), Some(1));
        assert_eq!(nested_deeper_than("<a", 0), Some(1));
        assert_eq!(nested_deeper_than("", 0), None);
    }
}
