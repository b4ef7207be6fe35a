//! A robot file of any format faze4 reads → a [`RobotDescription`]. The one place that picks
//! a file's format and hands its text to the file that owns the format:
//!
//! | format | how it is known | read by |
//! |---|---|---|
//! | URDF | root `<robot>`, no `<xacro:…>` element; or `.urdf`, or anything unknown | [`super::urdf`] (the only file that knows urdf-rs) |
//! | xacro | root `<robot>` with `<xacro:…>` elements, or a `.xacro` file (`.urdf.xacro`) | [`super::xacro`]: expanded to URDF text, then read by `urdf` |
//! | MJCF | root `<mujoco>` | [`super::mjcf`] |
//!
//! The root element decides; the extension only where the text has no root element (an empty
//! or malformed file, which its owner then names).

use std::path::Path;

use super::{PackagePaths, RobotDescription, mjcf, urdf, xacro};
use crate::error::{Error, Result};

/// The formats of robot files.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RobotFormat {
    /// A URDF.
    Urdf,
    /// A xacro file that expands to a URDF.
    Xacro,
    /// A MuJoCo MJCF model.
    Mjcf,
}

impl RobotFormat {
    /// Every format `robot` reads.
    pub const ALL: [RobotFormat; 3] = [RobotFormat::Urdf, RobotFormat::Xacro, RobotFormat::Mjcf];

    /// How a file of the format is told apart, for people (`faze4 list robots`; [`RobotFormat::detect`]).
    pub fn told_by(self) -> &'static str {
        match self {
            RobotFormat::Urdf => "a <robot> root element without <xacro:…> elements (.urdf)",
            RobotFormat::Xacro => "a <robot> root element with <xacro:…> elements, or a name ending in .xacro",
            RobotFormat::Mjcf => "a <mujoco> root element (.xml)",
        }
    }

    /// The format's name as messages and the banner write it.
    pub fn name(self) -> &'static str {
        match self {
            RobotFormat::Urdf => "urdf",
            RobotFormat::Xacro => "xacro",
            RobotFormat::Mjcf => "mjcf",
        }
    }

    /// The format of the file `path` holding `text`: by its root element (`<mujoco>` is MJCF;
    /// `<robot>` is xacro when the file has a `<xacro:…>` element or ends in `.xacro`, else
    /// URDF), and by its extension when the text has no root element.
    pub fn detect(path: &Path, text: &str) -> RobotFormat {
        let xacro_name = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("xacro"));
        match root_element(text).as_deref() {
            Some("mujoco") => RobotFormat::Mjcf,
            Some("robot") if xacro_name || text.contains("<xacro:") => RobotFormat::Xacro,
            Some(_) => RobotFormat::Urdf,
            None if xacro_name => RobotFormat::Xacro,
            None => RobotFormat::Urdf,
        }
    }
}

/// How a robot file is read: where `package://` and `$(find …)` packages are looked for, and
/// a xacro file's arguments.
#[derive(Clone, Debug, Default)]
pub struct ReadOptions {
    /// Where packages are looked for (`--package-path`, then `ROS_PACKAGE_PATH`).
    pub packages: PackagePaths,
    /// A xacro file's `<xacro:arg>` values, `NAME:=VALUE` as the command line gives them
    /// (`xacro_arg`), in order; a later one of the same name wins.
    pub xacro_args: Vec<String>,
}

/// The description in the robot file `path`, of whichever format it is ([`RobotFormat::detect`]),
/// mesh references resolved (not read). Its `format` is the format's name, its `file` names
/// where it came from for the banner, the summary and messages: the path, and for a xacro file
/// the arguments given (`PATH, NAME:=VALUE, …`). Arguments for a file that is not xacro are
/// refused naming `xacro_arg`.
pub fn describe_file(path: &Path, options: &ReadOptions) -> Result<RobotDescription> {
    let text = urdf::read_text(path)?;
    let format = RobotFormat::detect(path, &text);
    if format != RobotFormat::Xacro && !options.xacro_args.is_empty() {
        let article = match format {
            RobotFormat::Mjcf => "an MJCF",
            _ => "a URDF",
        };
        return Err(Error::option(
            "xacro_arg",
            format!(
                "{} is {article} file, not a xacro file: it takes no xacro arguments",
                path.display()
            ),
        ));
    }
    let file = path.display().to_string();
    let mut desc = match format {
        RobotFormat::Urdf => urdf::describe(&text, &file, path.parent(), &options.packages)?,
        RobotFormat::Xacro => {
            let expanded = xacro::expand(&text, path, &options.xacro_args, &options.packages)?;
            urdf::describe(&expanded.urdf, &expanded.label(), path.parent(), &options.packages)?
        }
        RobotFormat::Mjcf => mjcf::describe_str(&text, &file, path.parent())?,
    };
    desc.format = format.name().to_string();
    Ok(desc)
}

/// The name of the document's root element, if the text has one before any malformed markup.
fn root_element(text: &str) -> Option<String> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(text);
    loop {
        match reader.read_event() {
            Ok(Event::Start(e) | Event::Empty(e)) => {
                return Some(String::from_utf8_lossy(e.name().as_ref()).into_owned());
            }
            Ok(Event::Eof) | Err(_) => return None,
            Ok(_) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_root_element_decides_and_the_extension_only_without_one() {
        let urdf = "<?xml version=\"1.0\"?>\n<!-- c --><robot name=\"r\"><link name=\"a\"/></robot>";
        let xacro =
            "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\"><xacro:property name=\"x\" value=\"1\"/></robot>";
        let mjcf = "<mujoco model=\"m\"><worldbody/></mujoco>";
        let detect = |name: &str, text: &str| RobotFormat::detect(Path::new(name), text);
        assert_eq!(detect("a.urdf", urdf), RobotFormat::Urdf);
        assert_eq!(detect("a.xml", urdf), RobotFormat::Urdf);
        assert_eq!(detect("/dev/stdin", urdf), RobotFormat::Urdf);
        assert_eq!(detect("a.urdf.xacro", urdf), RobotFormat::Xacro);
        assert_eq!(detect("a.urdf", xacro), RobotFormat::Xacro);
        assert_eq!(detect("a.xml", mjcf), RobotFormat::Mjcf);
        assert_eq!(detect("a.urdf", mjcf), RobotFormat::Mjcf);
        assert_eq!(detect("a.xacro", ""), RobotFormat::Xacro);
        assert_eq!(detect("a.xml", "not xml"), RobotFormat::Urdf);
        assert_eq!(detect("a.URDF.XACRO", "<robot"), RobotFormat::Xacro);
    }
}
