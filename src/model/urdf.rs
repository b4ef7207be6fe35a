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
use crate::input::{MAX_LINKS, MAX_URDF_BYTES, read_capped, xml_nested_deeper_than};
use crate::spatial::{Pose, Vec3};

/// Reads and validates the URDF file at `path`: its dynamics model. Mesh files are only
/// located (`packages` resolves `package://`), not read.
pub fn read_file(path: &Path, packages: &PackagePaths) -> Result<Model> {
    read_str(&read_text(path)?, &path.display().to_string(), path.parent(), packages)
}

/// The text of the URDF file at `path` (UTF-8, at most [`MAX_URDF_BYTES`]; a stream such as
/// `/dev/stdin` is read up to that cap).
pub fn read_text(path: &Path) -> Result<String> {
    let text = read_capped(path, MAX_URDF_BYTES, "a URDF")?;
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
    if let Some(line) = xml_nested_deeper_than(text.as_bytes(), MAX_NESTING) {
        return Err(syntax(format!(
            "elements nest more than {MAX_NESTING} deep (line {line}); a URDF needs about 5 levels"
        )));
    }
    // every link is a frame: a count bounds what urdf-rs and the model builder take
    let links = count_elements(text, "link");
    if links > MAX_LINKS {
        return Err(Error::model(
            file,
            "<robot>",
            format!("has {links} <link> elements, more than the {MAX_LINKS} faze4 reads (docs/development.md, Caps)"),
        ));
    }
    // urdf-rs's message for an empty <geometry> is its XML layer's debug text
    if let Some(element) = empty_geometry(text) {
        return Err(Error::model(
            file,
            element,
            "<geometry> is empty: give it a <box>, <cylinder>, <sphere> or <mesh>",
        ));
    }
    // urdf-rs panics on a few malformed inputs instead of returning an error (RustyXML's "No
    // namespace prefix bound" on `<" xmlns="N":=""/>`): catch it, quietly, and report it.
    let parsed = parse_quietly(text)
        .map_err(|panic| {
            syntax(format!(
                "the XML parser failed on this input (urdf-rs panicked: {panic})"
            ))
        })?
        .map_err(|e| syntax(readable(&e.to_string())))?;

    let links = (parsed.links.iter())
        .map(|link| {
            // a mesh reference that leaves its package is refused, naming the element
            let refused = |what: &str| {
                let element = format!("link '{}' <{what}>", link.name);
                move |message: String| Error::model(file, element.clone(), message)
            };
            Ok(LinkDesc {
                name: link.name.clone(),
                inertial: Some(InertialDesc {
                    origin: Pose::from_xyz_rpy(link.inertial.origin.xyz.0, link.inertial.origin.rpy.0),
                    mass: link.inertial.mass.value,
                    inertia: {
                        let i = &link.inertial.inertia;
                        [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz]
                    },
                }),
                visuals: (link.visual.iter())
                    .map(|v| visual(v, &parsed.materials, base_dir, packages).map_err(refused("visual")))
                    .collect::<Result<_>>()?,
                collisions: (link.collision.iter())
                    .map(|c| {
                        Ok(Collision {
                            origin: Pose::from_xyz_rpy(c.origin.xyz.0, c.origin.rpy.0),
                            geometry: geometry(&c.geometry, base_dir, packages).map_err(refused("collision"))?,
                        })
                    })
                    .collect::<Result<_>>()?,
            })
        })
        .collect::<Result<_>>()?;

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
                origin: Pose::from_xyz_rpy(j.origin.xyz.0, j.origin.rpy.0),
                axis: j.axis.xyz.0,
                limits: (!no_limit_element).then_some((lim.lower, lim.upper)),
                // 0 is urdf-rs's value for an absent attribute: no limit; a negative one is
                // refused by the model's checks, not read as none
                effort: (lim.effort != 0.0).then_some(lim.effort),
                velocity: (lim.velocity != 0.0).then_some(lim.velocity),
                damping: j.dynamics.as_ref().map_or(0.0, |d| d.damping),
                friction: j.dynamics.as_ref().map_or(0.0, |d| d.friction),
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
        format: "urdf".into(),
        ..RobotDescription::default()
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

/// The first `<visual>` or `<collision>` whose `<geometry>` holds no element, as
/// `link 'NAME' <visual>`, if any. Malformed XML is left to urdf-rs.
fn empty_geometry(text: &str) -> Option<String> {
    use quick_xml::events::Event;
    if !text.contains("<geometry") {
        return None;
    }
    let mut reader = quick_xml::Reader::from_str(text);
    let (mut link, mut shape, mut open) = (String::new(), "visual", false);
    loop {
        let (element, empty) = match reader.read_event().ok()? {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(e) if e.name().as_ref() == b"geometry" && open => {
                return Some(format!("link '{link}' <{shape}>"));
            }
            Event::Eof => return None,
            _ => continue,
        };
        // an element inside <geometry>: it is not empty
        open = false;
        match element.name().as_ref() {
            b"link" => {
                let name = element.try_get_attribute("name").ok().flatten();
                link = name
                    .and_then(|a| a.unescape_value().ok())
                    .unwrap_or_default()
                    .into_owned();
            }
            b"visual" => shape = "visual",
            b"collision" => shape = "collision",
            b"geometry" if empty => return Some(format!("link '{link}' <{shape}>")),
            b"geometry" => open = true,
            _ => {}
        }
    }
}

/// How many `<NAME` start tags (`<NAME>`, `<NAME …`, `<NAME/>`) XML `text` holds: a lexical
/// count, linear, before any parser.
fn count_elements(text: &str, name: &str) -> usize {
    let tag = format!("<{name}");
    text.match_indices(&tag)
        .filter(|(at, _)| {
            let next = text.as_bytes().get(at + tag.len());
            next.is_none_or(|c| c.is_ascii_whitespace() || *c == b'>' || *c == b'/')
        })
        .count()
}

/// A message of urdf-rs's XML layer (serde-xml-rs) without its debug text: `Expected token
/// &XmlEvent::Characters(ref name) | …, found EndElement(geometry)` becomes `an element or
/// text was expected, found </geometry>`.
fn readable(message: &str) -> String {
    let Some(found) = message
        .strip_prefix("Expected token ")
        .and_then(|m| m.split(", found ").nth(1))
    else {
        return message.to_string();
    };
    let tag = |s: &str, open: &str| {
        let name = s.split(['(', ')', ' ', ',', '"']).find(|w| !w.is_empty()).unwrap_or("");
        format!("<{open}{name}>")
    };
    let found = if let Some(rest) = found.strip_prefix("EndElement(") {
        tag(rest, "/")
    } else if let Some(rest) = found.strip_prefix("StartElement(") {
        tag(rest, "")
    } else if found.starts_with("EndDocument") {
        "the end of the file".to_string()
    } else if found.starts_with("Characters") {
        "text".to_string()
    } else {
        found.to_string()
    };
    format!("an element or text was expected, found {found}")
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

fn visual(
    v: &urdf_rs::Visual,
    materials: &[urdf_rs::Material],
    base_dir: Option<&Path>,
    packages: &PackagePaths,
) -> std::result::Result<Visual, String> {
    let geometry = geometry(&v.geometry, base_dir, packages)?;
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
    Ok(Visual {
        origin: Pose::from_xyz_rpy(v.origin.xyz.0, v.origin.rpy.0),
        geometry,
        rgba,
    })
}

/// A `<geometry>` element; mesh references are resolved (the file is not read). The error: a
/// `package://` reference that leaves its package ([`PackagePaths::resolve`]).
fn geometry(
    g: &urdf_rs::Geometry,
    base_dir: Option<&Path>,
    packages: &PackagePaths,
) -> std::result::Result<Geometry, String> {
    Ok(match g {
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
            path: (packages.resolve(filename, base_dir)).map_err(|e| format!("mesh '{filename}': {e}"))?,
            scale: scale.map_or(Vec3::new(1.0, 1.0, 1.0), |s| Vec3::from(s.0)),
        },
    })
}
