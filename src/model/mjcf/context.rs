//! What the reading of one MJCF model shares: the compiler's settings, the assets, the list of
//! what was mapped or left out, and each element's attributes (its own, else its class's) read
//! as numbers, flags and placements.

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::classes::Classes;
use super::frames::{Angles, axis_angle_quat, euler_quat, numbers, quat_matrix, xyaxes_matrix, zaxis_quat};
use super::xml::Element;
use crate::error::{Error, Result};
use crate::model::Mapping;
use crate::spatial::{Mat3, Pose, Vec3};

/// When a body's inertia comes from its geoms (`<compiler inertiafromgeom>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum FromGeom {
    /// Only for a body without `<inertial>` (MuJoCo's default, `auto`).
    Auto,
    /// Always, an `<inertial>` ignored.
    Always,
    /// Never: a body without `<inertial>` has no mass.
    Never,
}

/// What `<compiler>` says that the reading uses.
#[derive(Clone, Debug)]
pub(super) struct Compiler {
    /// Angle unit and Euler sequence.
    pub angles: Angles,
    /// Where mesh files are, as written (relative to the model's folder).
    pub meshdir: Option<PathBuf>,
    /// Whether a `range` alone limits (`autolimits`, true by default).
    pub autolimits: bool,
    /// When a body's inertia comes from its geoms.
    pub from_geom: FromGeom,
    /// The geom groups whose geoms count for a body's inertia (`inertiagrouprange`, 0 to 5).
    pub groups: (i64, i64),
    /// Whether mesh file names lose their folders (`strippath`).
    pub strippath: bool,
}

/// A `<mesh>` asset with a file.
#[derive(Clone, Debug)]
pub(super) struct MeshAsset {
    /// The file as written.
    pub file: String,
    /// Its scale.
    pub scale: Vec3,
}

/// What the reading of one model shares: its file, classes, compiler settings, assets, and the
/// list of what it mapped or left out.
pub(super) struct Context<'a> {
    /// The model's file, for messages.
    pub file: &'a str,
    /// Its folder.
    pub base_dir: Option<&'a Path>,
    /// Its `<default>` classes.
    pub classes: Classes,
    /// Its `<compiler>` settings.
    pub compiler: Compiler,
    /// Its meshes by name.
    pub meshes: HashMap<String, Option<MeshAsset>>,
    /// Its materials' colours by name.
    pub materials: HashMap<String, [f64; 4]>,
    /// What was mapped or left out, in the order first met.
    pub mapped: RefCell<Vec<Mapping>>,
}

impl Context<'_> {
    /// Notes that `item` said `from`, which became `to`.
    pub fn note(&self, from: &str, to: &str, item: &str, changes_dynamics: bool) {
        let mut mapped = self.mapped.borrow_mut();
        match mapped.iter_mut().find(|m| m.from == from && m.to == to) {
            Some(m) => m.items.push(item.to_string()),
            None => mapped.push(Mapping {
                from: from.to_string(),
                to: to.to_string(),
                items: vec![item.to_string()],
                changes_dynamics,
            }),
        }
    }

    /// The attributes of `element` of class `class`.
    pub fn attrs<'e>(&'e self, element: &'e Element, class: &'e str) -> Attrs<'e> {
        Attrs {
            element,
            class,
            classes: &self.classes,
            file: self.file,
        }
    }

    /// Mesh `file` as the model refers to it (under `meshdir`, relative to the model's folder)
    /// and the file that is there (`None`: none is).
    pub fn mesh_path(&self, file: &str) -> (PathBuf, Option<PathBuf>) {
        let file = match self.compiler.strippath {
            true => Path::new(file).file_name().map_or(file.into(), PathBuf::from),
            false => PathBuf::from(file),
        };
        let reference = self.compiler.meshdir.clone().unwrap_or_default().join(file);
        let path = match (reference.is_absolute(), self.base_dir) {
            (false, Some(base)) => base.join(&reference),
            _ => reference.clone(),
        };
        let found = path.is_file().then_some(path);
        (reference, found)
    }
}

/// One element's attributes: its own, else its class's defaults.
pub(super) struct Attrs<'a> {
    /// The element.
    pub element: &'a Element,
    /// Its class.
    pub class: &'a str,
    /// The model's classes.
    pub classes: &'a Classes,
    /// The model's file, for messages.
    pub file: &'a str,
}

impl<'a> Attrs<'a> {
    /// The element as messages name it: `<joint name="elbow"> (arm.xml:12)`.
    pub fn label(&self) -> String {
        label(self.element, self.file)
    }

    /// An error about this element.
    pub fn error(&self, message: impl Into<String>) -> Error {
        Error::model(self.file, self.label(), message)
    }

    /// Attribute `key` as written, or its default.
    pub fn text(&self, key: &str) -> Option<&'a str> {
        self.classes.attribute(self.element, self.class, key)
    }

    /// Attribute `key`'s numbers, if given: exactly `n` of them when `n` is given.
    pub fn list(&self, key: &str, n: Option<usize>) -> Result<Option<Vec<f64>>> {
        let Some(text) = self.text(key) else { return Ok(None) };
        let values = numbers(text).map_err(|e| self.error(format!("{key}=\"{text}\": {e}")))?;
        if let Some(n) = n.filter(|&n| values.len() != n) {
            return Err(self.error(format!("{key}=\"{text}\" has {} numbers, not {n}", values.len())));
        }
        if let Some(x) = values.iter().find(|x| !x.is_finite()) {
            return Err(self.error(format!("{key}=\"{text}\" has a non-finite value ({x})")));
        }
        Ok(Some(values))
    }

    /// Attribute `key` as `N` numbers, `default` when not given.
    pub fn vector<const N: usize>(&self, key: &str, default: [f64; N]) -> Result<[f64; N]> {
        Ok(match self.list(key, Some(N))? {
            Some(v) => std::array::from_fn(|i| v[i]),
            None => default,
        })
    }

    /// Attribute `key` as one number, `default` when not given.
    pub fn number(&self, key: &str, default: f64) -> Result<f64> {
        Ok(self.vector(key, [default])?[0])
    }

    /// Attribute `key` as `true`/`false`, `auto` or absent as `None`.
    pub fn flag(&self, key: &str) -> Result<Option<bool>> {
        match self.text(key) {
            None | Some("auto") => Ok(None),
            Some("true") => Ok(Some(true)),
            Some("false") => Ok(Some(false)),
            Some(other) => Err(self.error(format!("{key}=\"{other}\" is not true, false or auto"))),
        }
    }

    /// The element's placement in its parent's frame: `pos` and one orientation, its own or else
    /// its class's.
    pub fn pose(&self, angles: &Angles) -> Result<Pose> {
        let pos = self.vector("pos", [0.0; 3])?;
        let own = ORIENTATIONS.iter().any(|k| self.element.get(k).is_some());
        let given: Vec<&str> = (ORIENTATIONS.iter().copied())
            .filter(|k| match own {
                true => self.element.get(k).is_some(),
                false => self.text(k).is_some(),
            })
            .collect();
        let rot = match given.as_slice() {
            [] => Mat3::identity(),
            [one] => self.orientation(one, angles)?,
            many => {
                return Err(self.error(format!(
                    "gives {} orientations ({}): give one",
                    many.len(),
                    many.join(", ")
                )));
            }
        };
        Ok(Pose::new(rot, Vec3::from(pos)))
    }

    /// The rotation orientation attribute `key` gives.
    fn orientation(&self, key: &str, angles: &Angles) -> Result<Mat3> {
        Ok(match key {
            "quat" => quat_matrix(self.vector(key, [1.0, 0.0, 0.0, 0.0])?),
            "axisangle" => {
                let [x, y, z, a] = self.vector(key, [0.0; 4])?;
                quat_matrix(axis_angle_quat([x, y, z], angles.radians(a)))
            }
            "xyaxes" => {
                let v = self.vector(key, [0.0; 6])?;
                xyaxes_matrix([v[0], v[1], v[2]], [v[3], v[4], v[5]])
            }
            "zaxis" => quat_matrix(zaxis_quat(self.vector(key, [0.0, 0.0, 1.0])?)),
            _ => quat_matrix(euler_quat(
                self.vector(key, [0.0; 3])?.map(|a| angles.radians(a)),
                angles.eulerseq,
            )),
        })
    }
}

/// The five ways to write an orientation.
const ORIENTATIONS: [&str; 5] = ["quat", "axisangle", "xyaxes", "zaxis", "euler"];

/// An element as messages about `file` name it: `<joint name="elbow"> (line 12)`, the file
/// named too when it is an included one.
pub(super) fn label(element: &Element, file: &str) -> String {
    let at = match element.at.strip_prefix(file).and_then(|l| l.strip_prefix(':')) {
        Some(line) => format!("line {line}"),
        None => element.at.clone(),
    };
    match element.get("name") {
        Some(name) => format!("<{} name=\"{name}\"> ({at})", element.name),
        None => format!("<{}> ({at})", element.name),
    }
}
