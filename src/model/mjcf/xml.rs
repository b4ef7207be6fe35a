//! An MJCF file's XML as an owned element tree, every `<include>` replaced by the children of
//! the included file's `<mujoco>` (MuJoCo's rule: an included file is a model of its own whose
//! root's children are pasted in place of the `<include>`, its path relative to the main
//! file's folder).

use std::path::Path;

use crate::error::{Error, Result, one_line};
use crate::input::{MAX_LINKS, MAX_URDF_BYTES, into_text, read_capped, xml_nested_deeper_than};

/// The deepest element nesting read: a body per moving joint nests at most
/// [`crate::input::MAX_MOVING_JOINTS`] deep, with room for the sections around them.
const MAX_NESTING: usize = 400;

/// The deepest chain of `<include>`s followed (a file that includes itself stops here).
const MAX_INCLUDE_DEPTH: usize = 8;

/// The most elements read from a model and the files it includes: each body is a link, and a
/// body holds a few joints, geoms and sites.
const MAX_ELEMENTS: usize = 16 * MAX_LINKS;

/// One element: its tag, attributes in document order, children, and where it was written.
#[derive(Clone, Debug)]
pub(super) struct Element {
    /// The tag name (`body`, `joint`, …).
    pub name: String,
    /// The attributes as written, in document order.
    pub attributes: Vec<(String, String)>,
    /// The child elements in document order, includes expanded.
    pub children: Vec<Element>,
    /// Where it is written: `FILE:LINE`, for messages.
    pub at: String,
}

impl Element {
    /// The value of attribute `key`, if given.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.attributes.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }

    /// The children named `name`.
    pub fn all<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Element> + 'a {
        self.children.iter().filter(move |c| c.name == name)
    }
}

/// Reads the model at `path` (at most [`MAX_URDF_BYTES`], UTF-8) and the files it includes.
pub(super) fn read_model(path: &Path) -> Result<Element> {
    let text = into_text(path, read_capped(path, MAX_URDF_BYTES, "an MJCF model")?)?;
    parse_model(&text, &path.display().to_string(), path.parent())
}

/// The `<mujoco>` element of model `text`, read from `file` (named in messages), its includes
/// found relative to `base_dir`.
pub(super) fn parse_model(text: &str, file: &str, base_dir: Option<&Path>) -> Result<Element> {
    let mut reader = Reader { base_dir, elements: 0 };
    reader.parse(text, file, 0)
}

/// One file being read: its name, how many includes down it is, where its lines end.
struct Source<'a> {
    file: &'a str,
    depth: usize,
    newlines: Vec<usize>,
}

impl Source<'_> {
    /// The line (from 1) on which `node` starts.
    fn line(&self, node: roxmltree::Node) -> usize {
        self.newlines.partition_point(|&i| i < node.range().start) + 1
    }
}

/// The state of one model's reading: where includes are found, how many elements were read.
struct Reader<'a> {
    base_dir: Option<&'a Path>,
    elements: usize,
}

impl Reader<'_> {
    /// The root `<mujoco>` of `text` (from `file`, `depth` includes down), converted.
    fn parse(&mut self, text: &str, file: &str, depth: usize) -> Result<Element> {
        let syntax = |message: String| Error::UrdfSyntax {
            file: file.to_string(),
            message: one_line(&message),
        };
        if text.trim().is_empty() {
            return Err(syntax("the file is empty".into()));
        }
        if let Some(line) = xml_nested_deeper_than(text.as_bytes(), MAX_NESTING) {
            return Err(syntax(format!(
                "elements nest more than {MAX_NESTING} deep (line {line})"
            )));
        }
        let options = roxmltree::ParsingOptions {
            allow_dtd: false,
            nodes_limit: u32::try_from(4 * MAX_ELEMENTS).unwrap_or(u32::MAX),
        };
        let doc = roxmltree::Document::parse_with_options(text, options).map_err(|e| syntax(e.to_string()))?;
        let root = doc.root_element();
        if root.tag_name().name() != "mujoco" {
            return Err(syntax(format!(
                "the root element is <{}>, not <mujoco>: this is no MJCF model",
                root.tag_name().name()
            )));
        }
        let source = Source {
            file,
            depth,
            newlines: text.match_indices('\n').map(|(i, _)| i).collect(),
        };
        self.convert(&source, root)
    }

    /// `node` and its children as [`Element`]s, each `<include>` replaced by its file's
    /// children.
    fn convert(&mut self, source: &Source, node: roxmltree::Node) -> Result<Element> {
        self.elements += 1;
        if self.elements > MAX_ELEMENTS {
            return Err(Error::model(
                source.file,
                "<mujoco>",
                format!("has more than {MAX_ELEMENTS} elements, more than faze4 reads (docs/development.md, Caps)"),
            ));
        }
        let mut element = Element {
            name: node.tag_name().name().to_string(),
            attributes: (node.attributes())
                .map(|a| (a.name().to_string(), a.value().to_string()))
                .collect(),
            children: Vec::new(),
            at: format!("{}:{}", source.file, source.line(node)),
        };
        for child in node.children().filter(|n| n.is_element()) {
            if child.tag_name().name() == "include" {
                let included = self.include(source, child)?;
                element.children.extend(included.children);
            } else {
                element.children.push(self.convert(source, child)?);
            }
        }
        Ok(element)
    }

    /// The `<mujoco>` of the file an `<include file>` names.
    fn include(&mut self, source: &Source, node: roxmltree::Node) -> Result<Element> {
        let element = format!("<include> (line {})", source.line(node));
        let file = source.file;
        let Some(name) = node.attribute("file") else {
            return Err(Error::model(file, element, "has no file attribute"));
        };
        if source.depth >= MAX_INCLUDE_DEPTH {
            return Err(Error::model(
                file,
                element,
                format!("includes nest more than {MAX_INCLUDE_DEPTH} deep (does '{name}' include itself?)"),
            ));
        }
        let path = match self.base_dir {
            Some(dir) => dir.join(name),
            None => Path::new(name).to_path_buf(),
        };
        let text = into_text(&path, read_capped(&path, MAX_URDF_BYTES, "an MJCF file")?)?;
        self.parse(&text, &path.display().to_string(), source.depth + 1)
    }
}
