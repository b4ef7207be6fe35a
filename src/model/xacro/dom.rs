//! A xacro document as a tree of elements, each with its file and line, read with quick-xml
//! without namespace processing (as xacro's minidom reads it: `xacro:macro` is the element's
//! name), and written back as XML text.

use std::rc::Rc;

/// Deepest element nesting of one xacro file (100, as a URDF's): the expansion walks the tree
/// recursively.
pub const MAX_NESTING: usize = 100;

/// An element: its qualified name (`xacro:if`, `link`), attributes in document order, children,
/// and where it is.
#[derive(Clone, Debug)]
pub struct Element {
    /// The name as written, prefix included.
    pub name: String,
    /// The attributes as written (values unescaped, whitespace normalised as XML does).
    pub attrs: Vec<(String, String)>,
    /// Its content.
    pub children: Vec<Node>,
    /// The file it is in, as messages name it.
    pub file: Rc<str>,
    /// Its line in that file (1-based).
    pub line: usize,
}

/// What an element holds.
#[derive(Clone, Debug)]
pub enum Node {
    /// An element.
    Element(Element),
    /// Text (evaluated by xacro).
    Text(String),
    /// A CDATA section (left as it is, as xacro does).
    CData(String),
}

impl Element {
    /// The value of attribute `name`.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str())
    }

    /// The child elements, in order.
    #[cfg(test)]
    pub fn elements(&self) -> impl Iterator<Item = &Element> {
        self.children.iter().filter_map(|n| match n {
            Node::Element(e) => Some(e),
            _ => None,
        })
    }
}

/// Parses `text` (the file `file`) into its root element. The error: what is malformed, with its
/// line.
pub fn parse(text: &str, file: &Rc<str>) -> Result<Element, (usize, String)> {
    use quick_xml::events::Event;
    let lines = LineIndex::new(text);
    let mut reader = quick_xml::Reader::from_str(text);
    let mut stack: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    loop {
        let at = lines.line(reader.buffer_position() as usize);
        let event = reader
            .read_event()
            .map_err(|e| (lines.line(reader.error_position() as usize), e.to_string()))?;
        let add = |stack: &mut Vec<Element>, node: Node| -> Result<(), (usize, String)> {
            match stack.last_mut() {
                Some(parent) => parent.children.push(node),
                None if matches!(&node, Node::Text(t) if t.trim().is_empty()) => {}
                None => return Err((at, "text outside the root element".into())),
            }
            Ok(())
        };
        match event {
            Event::Start(e) | Event::Empty(e) if root.is_some() => {
                let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
                return Err((at, format!("<{name}> after the root element")));
            }
            Event::Start(ref e) | Event::Empty(ref e) => {
                if stack.len() >= MAX_NESTING {
                    return Err((
                        at,
                        format!("elements nest more than {MAX_NESTING} deep; a description needs about 10"),
                    ));
                }
                let element = start(e, file, at)?;
                match event {
                    Event::Start(_) => stack.push(element),
                    _ => close(&mut stack, &mut root, element),
                }
            }
            Event::End(_) => {
                if let Some(element) = stack.pop() {
                    close(&mut stack, &mut root, element);
                }
            }
            Event::Text(t) => {
                let text = t.decode().map_err(|e| (at, e.to_string()))?;
                add(&mut stack, Node::Text(text.into_owned()))?;
            }
            Event::GeneralRef(r) => {
                let text = match r.resolve_char_ref().map_err(|e| (at, e.to_string()))? {
                    Some(c) => c.to_string(),
                    None => match r.decode().map_err(|e| (at, e.to_string()))?.as_ref() {
                        "amp" => "&".into(),
                        "lt" => "<".into(),
                        "gt" => ">".into(),
                        "quot" => "\"".into(),
                        "apos" => "'".into(),
                        other => return Err((at, format!("the entity &{other}; is not one of XML's five"))),
                    },
                };
                add(&mut stack, Node::Text(text))?;
            }
            Event::CData(c) => {
                let text = String::from_utf8_lossy(&c).into_owned();
                add(&mut stack, Node::CData(text))?;
            }
            Event::DocType(d) => {
                if String::from_utf8_lossy(&d).contains("<!ENTITY") {
                    return Err((
                        at,
                        "a DOCTYPE declaring entities: xacro descriptions declare none".into(),
                    ));
                }
            }
            Event::Eof => break,
            Event::Comment(_) | Event::Decl(_) | Event::PI(_) => {}
        }
    }
    if let Some(open) = stack.first() {
        return Err((open.line, format!("<{}> is not closed", open.name)));
    }
    root.ok_or((1, "the file has no root element".into()))
}

/// `element` ended: a child of the element above it, or the root.
fn close(stack: &mut [Element], root: &mut Option<Element>, element: Element) {
    match stack.last_mut() {
        Some(parent) => parent.children.push(Node::Element(element)),
        None => *root = Some(element),
    }
}

/// The element a start tag opens.
fn start(e: &quick_xml::events::BytesStart, file: &Rc<str>, line: usize) -> Result<Element, (usize, String)> {
    let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
    let mut attrs = Vec::new();
    for attr in e.attributes() {
        let attr = attr.map_err(|err| (line, format!("<{name}>: {err}")))?;
        let key = String::from_utf8_lossy(attr.key.as_ref()).into_owned();
        // XML normalises a literal tab, newline or carriage return in a value to a space
        let raw: Vec<u8> = attr
            .value
            .iter()
            .map(|&b| if matches!(b, b'\t' | b'\n' | b'\r') { b' ' } else { b })
            .collect();
        let raw = String::from_utf8_lossy(&raw).into_owned();
        let value = quick_xml::escape::unescape(&raw)
            .map_err(|err| (line, format!("<{name} {key}>: {err}")))?
            .into_owned();
        attrs.push((key, value));
    }
    Ok(Element {
        name,
        attrs,
        children: Vec::new(),
        file: file.clone(),
        line,
    })
}

/// Byte offsets → line numbers.
struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    fn new(text: &str) -> Self {
        let starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        LineIndex { starts }
    }

    fn line(&self, offset: usize) -> usize {
        // the first non-whitespace byte at or after the offset is the event's start
        self.starts.partition_point(|&s| s <= offset)
    }
}

/// `element` as XML text, after an XML declaration.
pub fn write(element: &Element) -> String {
    let mut out = String::from("<?xml version=\"1.0\"?>\n");
    write_element(element, &mut out);
    out.push('\n');
    out
}

fn write_element(element: &Element, out: &mut String) {
    out.push('<');
    out.push_str(&element.name);
    for (k, v) in &element.attrs {
        out.push(' ');
        out.push_str(k);
        out.push_str("=\"");
        escape(v, true, out);
        out.push('"');
    }
    if element.children.is_empty() {
        out.push_str("/>");
        return;
    }
    out.push('>');
    for child in &element.children {
        match child {
            Node::Element(e) => write_element(e, out),
            Node::Text(t) | Node::CData(t) => escape(t, false, out),
        }
    }
    out.push_str("</");
    out.push_str(&element.name);
    out.push('>');
}

fn escape(text: &str, attribute: bool, out: &mut String) {
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' if attribute => out.push_str("&quot;"),
            '\n' if attribute => out.push_str("&#10;"),
            '\t' if attribute => out.push_str("&#9;"),
            '\r' => out.push_str("&#13;"),
            c => out.push(c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_document_reads_with_its_lines_and_writes_back() {
        let file: Rc<str> = "t.xacro".into();
        let text = "<?xml version=\"1.0\"?>\n<!-- c -->\n<robot name=\"r\" xmlns:xacro=\"x\">\n  <xacro:if value=\"a&amp;b\n c\">t &lt; &#65;<![CDATA[${x}]]></xacro:if>\n  <link name='l'/>\n</robot>\n";
        let root = parse(text, &file).unwrap();
        assert_eq!((root.name.as_str(), root.line), ("robot", 3));
        let first = root.elements().next().unwrap();
        assert_eq!(
            (first.name.as_str(), first.line, first.attr("value")),
            ("xacro:if", 4, Some("a&b  c"))
        );
        assert_eq!(root.elements().nth(1).unwrap().line, 6);
        let written = write(&root);
        assert!(
            written.contains("<xacro:if value=\"a&amp;b  c\">t &lt; A${x}</xacro:if>"),
            "{written}"
        );
        for (bad, line) in [
            ("<robot>\n<a>\n</robot>", 3),
            ("<robot/>\n<robot/>", 2),
            ("", 1),
            ("<robot>&foo;</robot>", 1),
            ("<!DOCTYPE r [<!ENTITY a \"b\">]><robot/>", 1),
            ("<robot>\n<a b='1' b='2'/></robot>", 2),
        ] {
            let (at, message) = parse(bad, &file).unwrap_err();
            assert_eq!(at, line, "{bad}: {message}");
        }
        let deep = format!("{}{}", "<a>".repeat(MAX_NESTING + 1), "</a>".repeat(MAX_NESTING + 1));
        assert!(parse(&deep, &file).unwrap_err().1.contains("nest more than"));
    }
}
