//! The expansion itself, following ROS xacro's `eval_all` (xacro 2.1, in-order processing):
//! properties in scoped tables with lazy evaluation, macros with their parameters, defaults,
//! forwarded (`^`) and block (`*`, `**`) parameters, includes, conditionals, arguments and the
//! `${…}` and `$(…)` substitutions.

use std::cell::RefCell;
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::dom::{self, Element, Node};
use super::expr::{self, Names, parse_float};
use super::value::Value;
use super::{MAX_BUDGET, MAX_DEPTH, MAX_INCLUDE_DEPTH, MAX_MACRO_DEPTH, MAX_TEXT_BYTES};
use crate::input::{MAX_URDF_BYTES, read_capped};
use crate::model::PackagePaths;

/// A failure, where it happened (the innermost element with a line) and what it is.
#[derive(Debug)]
pub struct Fail {
    /// The file.
    pub file: Rc<str>,
    /// The line.
    pub line: usize,
    /// What went wrong, the construct named.
    pub message: String,
}

type Result<T> = std::result::Result<T, Fail>;

/// A property as a table holds it.
#[derive(Clone, Debug)]
enum Prop {
    Value(Value),
    /// Text evaluated on first use, in the table that holds it.
    Lazy(String),
    /// Being evaluated (a use now is a circular definition).
    Resolving,
}

/// A scope of properties: the document's, a macro call's.
#[derive(Debug, Default)]
struct Table {
    vars: HashMap<String, Prop>,
    parent: Option<Scope>,
}

type Scope = Rc<RefCell<Table>>;

/// A macro: its parameters in order, their defaults, and its body.
#[derive(Debug)]
struct Macro {
    name: String,
    params: Vec<String>,
    /// param → (forwarded from the caller's property of that name, default text)
    defaults: HashMap<String, (bool, Option<String>)>,
    body: Rc<Element>,
}

/// The macros in scope: the document's, a macro call's (a macro defined in a macro's body is
/// that call's).
#[derive(Debug, Default)]
struct Macros {
    table: HashMap<String, Rc<Macro>>,
    parent: Option<Rc<RefCell<Macros>>>,
}

type MacroScope = Rc<RefCell<Macros>>;

/// The state of one expansion.
pub struct Expander<'a> {
    /// `$(arg …)` values: those given, then `<xacro:arg>` defaults.
    args: HashMap<String, String>,
    /// The arguments the document declares (`<xacro:arg>`) or reads (`$(arg)`, `xacro.arg`,
    /// `$(eval)`'s names), for [`Expander::unknown_args`].
    known_args: BTreeSet<String>,
    packages: &'a PackagePaths,
    /// The files being read, the current one last (relative names are taken from its folder).
    files: Vec<(PathBuf, Rc<str>)>,
    budget: usize,
    depth: usize,
    macro_depth: usize,
}

fn child_scope(parent: &Scope) -> Scope {
    Rc::new(RefCell::new(Table {
        vars: HashMap::new(),
        parent: Some(parent.clone()),
    }))
}

/// Python's `_eval_literal`: a property's text as the value it reads as: `'quoted'` without
/// its quotes; a number (`int`, then `float`); `true`/`false`; else the text (and text holding
/// `_` stays text).
fn literal(value: Value) -> Value {
    let Value::Str(s) = &value else {
        return value;
    };
    if s.len() >= 2 && s.starts_with('\'') && s.ends_with('\'') {
        return Value::str(&s[1..s.len() - 1]);
    }
    if s.contains('_') {
        return value;
    }
    let t = s.trim();
    let digits = t.strip_prefix(['+', '-']).unwrap_or(t);
    if !digits.is_empty()
        && digits.chars().all(|c| c.is_ascii_digit())
        && let Ok(i) = t.parse::<i64>()
    {
        return Value::Int(i);
    }
    if let Some(x) = parse_float(t) {
        return Value::Float(x);
    }
    match &**s {
        "true" | "True" => Value::Bool(true),
        "false" | "False" => Value::Bool(false),
        _ => value,
    }
}

/// xacro's `get_boolean_value`: `true`/`True`/`false`/`False`, an integer's text, or a typed
/// value's truth; anything else is refused naming the condition.
fn boolean(value: &Value, condition: &str) -> std::result::Result<bool, String> {
    match value {
        Value::Str(s) => match &**s {
            "true" | "True" => Ok(true),
            "false" | "False" => Ok(false),
            t => t.trim().parse::<i64>().map(|i| i != 0).map_err(|_| {
                format!("the condition \"{condition}\" evaluated to \"{t}\", which is not a boolean expression")
            }),
        },
        v => Ok(v.truthy()),
    }
}

/// Whether `name` is a Python identifier (a property's name must be one).
fn is_identifier(name: &str) -> bool {
    const KEYWORDS: [&str; 35] = [
        "False", "None", "True", "and", "as", "assert", "async", "await", "break", "class", "continue", "def", "del",
        "elif", "else", "except", "finally", "for", "from", "global", "if", "import", "in", "is", "lambda", "nonlocal",
        "not", "or", "pass", "raise", "return", "try", "while", "with", "yield",
    ];
    name.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_alphanumeric() || c == '_')
        && !KEYWORDS.contains(&name)
}

/// The next parameter of a macro's `params` text, as xacro's `parse_macro_arg` reads it:
/// `name`, `name:=default`, `name:=^`, `name:=^|default`, `*block`, `**block`. Returns the name,
/// the default (forwarded, text), and the rest.
fn macro_param(s: &str) -> (String, Option<(bool, Option<String>)>, &str) {
    let t = s.trim_start();
    let name_end = t
        .find(|c: char| c.is_whitespace() || c == ':' || c == '=')
        .unwrap_or(t.len());
    let (name, after) = t.split_at(name_end);
    let after_ws = after.trim_start();
    let assign = after_ws.strip_prefix(":=").or_else(|| after_ws.strip_prefix('='));
    if let (false, Some(rest)) = (name.is_empty(), assign) {
        let rest = rest.trim_start();
        let (forward, rest) = match rest.strip_prefix('^') {
            Some(r) => (true, r.strip_prefix('|').unwrap_or(r)),
            None => (false, rest),
        };
        if let Some((default, tail)) = default_value(rest) {
            let default = (!default.is_empty()).then(|| default.to_string());
            return (name.to_string(), Some((forward, default)), tail);
        }
    }
    let mut words = t.splitn(2, char::is_whitespace);
    let name = words.next().unwrap_or_default().to_string();
    (name, None, words.next().unwrap_or_default())
}

/// A default value at the start of `s` (`${…}`, `$(…)`, quoted or plain text, or nothing),
/// which must be followed by whitespace or the end; and what follows.
fn default_value(s: &str) -> Option<(&str, &str)> {
    let ends = |end: usize| {
        let tail = &s[end..];
        match tail.is_empty() || tail.starts_with(char::is_whitespace) {
            true => Some((&s[..end], tail.trim_start())),
            false => None,
        }
    };
    for (open, close) in [("${", '}'), ("$(", ')')] {
        if s.starts_with(open)
            && let Some(k) = s[2..].find(close)
            && let Some(found) = ends(k + 3)
        {
            return Some(found);
        }
    }
    let mut i = 0;
    let bytes = s.as_bytes();
    while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
        if bytes[i] == b'\'' || bytes[i] == b'"' {
            match s[i + 1..].find(bytes[i] as char) {
                Some(k) => i += k + 2,
                None => break,
            }
        } else {
            i += s[i..].chars().next().map_or(1, char::len_utf8);
        }
    }
    ends(i)
}

impl<'a> Expander<'a> {
    /// An expansion of the file `path` (named `file` in messages) with the arguments `args`.
    pub fn new(path: &Path, file: Rc<str>, args: HashMap<String, String>, packages: &'a PackagePaths) -> Self {
        Expander {
            args,
            known_args: BTreeSet::new(),
            packages,
            files: vec![(path.to_path_buf(), file)],
            budget: 0,
            depth: 0,
            macro_depth: 0,
        }
    }

    /// The document `root` expanded: its attributes evaluated, its content expanded.
    pub fn document(&mut self, root: &Element) -> Result<Element> {
        let scope = Rc::new(RefCell::new(Table::default()));
        let macros = Rc::new(RefCell::new(Macros::default()));
        let mut attrs = self.attributes(root, &scope)?;
        let mut children = Vec::new();
        self.nodes(&root.children, &scope, &macros, &mut children, &mut attrs)?;
        Ok(Element {
            name: root.name.clone(),
            attrs,
            children,
            file: root.file.clone(),
            line: root.line,
        })
    }

    fn fail(&self, e: &Element, message: impl Into<String>) -> Fail {
        Fail {
            file: e.file.clone(),
            line: e.line,
            message: format!("<{}>: {}", e.name, message.into()),
        }
    }

    fn charge(&mut self, units: usize) -> std::result::Result<(), String> {
        self.budget = self.budget.saturating_add(units);
        match self.budget > MAX_BUDGET {
            true => Err(format!(
                "the expansion grows past {} MiB of text and elements (docs/development.md, Caps)",
                MAX_BUDGET >> 20
            )),
            false => Ok(()),
        }
    }

    /// The directory of the file being read.
    fn base_dir(&self) -> PathBuf {
        (self.files.last())
            .and_then(|(p, _)| p.parent().map(Path::to_path_buf))
            .unwrap_or_else(|| PathBuf::from("."))
    }

    /// `name` relative to the file being read, unless absolute.
    fn relative(&self, name: &str) -> PathBuf {
        match Path::new(name).is_absolute() {
            true => PathBuf::from(name),
            false => self.base_dir().join(name),
        }
    }

    /// An element's attributes evaluated, `xacro:*` attributes and the xacro namespace left out.
    fn attributes(&mut self, e: &Element, scope: &Scope) -> Result<Vec<(String, String)>> {
        let mut attrs = Vec::with_capacity(e.attrs.len());
        for (k, v) in &e.attrs {
            if k.starts_with("xacro:") || k == "xmlns:xacro" {
                continue;
            }
            let value = self
                .text(v, scope)
                .map_err(|m| self.fail(e, format!("{k}=\"{v}\": {m}")))?;
            self.charge(value.len() + k.len()).map_err(|m| self.fail(e, m))?;
            attrs.push((k.clone(), value));
        }
        Ok(attrs)
    }

    /// `str(eval_text(text))`.
    fn text(&mut self, text: &str, scope: &Scope) -> std::result::Result<String, String> {
        self.eval_text(text, scope)?.text_within(MAX_TEXT_BYTES)
    }

    /// xacro's `eval_text`: `${…}` expressions, `$(…)` substitutions, `$${` and `$$(` escapes;
    /// one piece keeps its type, several are joined as text.
    fn eval_text(&mut self, text: &str, scope: &Scope) -> std::result::Result<Value, String> {
        if !text.contains('$') {
            return Ok(Value::str(text));
        }
        let mut pieces: Vec<Value> = Vec::new();
        let mut rest = text;
        while !rest.is_empty() {
            let dollars = rest.bytes().take_while(|b| *b == b'$').count();
            let after = rest.as_bytes().get(dollars).copied();
            if dollars >= 2 && matches!(after, Some(b'{' | b'(')) {
                // `$${` → `${` as text (the lexer goes on after the brace)
                pieces.push(Value::str(&rest[1..=dollars]));
                rest = &rest[dollars + 1..];
            } else if dollars == 1 && after == Some(b'{') {
                let end = rest.find('}').ok_or_else(|| format!("invalid expression: {rest}"))?;
                let inner = self.text(&rest[2..end], scope)?;
                let value = expr::eval(
                    &inner,
                    &mut Env {
                        x: self,
                        scope: scope.clone(),
                    },
                )
                // the innermost expression and property are named, once
                .map_err(|e| match e.contains(" (in ") {
                    true => e,
                    false => format!("{e} (in the expression '{}')", inner.trim()),
                })?;
                pieces.push(value);
                rest = &rest[end + 1..];
            } else if dollars == 1 && after == Some(b'(') {
                let end = rest.find(')').ok_or_else(|| format!("invalid expression: {rest}"))?;
                let inner = self.text(&rest[2..end], scope)?;
                pieces.push(Value::str(self.substitution(&inner)?));
                rest = &rest[end + 1..];
            } else if dollars == 0 {
                let end = rest.find('$').unwrap_or(rest.len());
                pieces.push(Value::str(&rest[..end]));
                rest = &rest[end..];
            } else if dollars == 1 && rest.len() == 1 {
                pieces.push(Value::str("$"));
                rest = "";
            } else if dollars == 1 {
                let end = rest[1..].find(['$', '{', '(']).map_or(rest.len(), |k| k + 1);
                if end == 1 {
                    return Err(format!("invalid expression: {rest}"));
                }
                pieces.push(Value::str(&rest[..end]));
                rest = &rest[end..];
            } else {
                return Err(format!("invalid expression: {rest}"));
            }
        }
        Ok(match pieces.len() {
            1 => pieces.pop().unwrap_or(Value::None),
            _ => {
                let joined = (pieces.iter())
                    .map(|p| p.text_within(MAX_TEXT_BYTES))
                    .collect::<std::result::Result<String, String>>()?;
                if joined.len() > MAX_TEXT_BYTES {
                    return Err(format!("a text of more than {MAX_TEXT_BYTES} bytes"));
                }
                Value::str(joined)
            }
        })
    }

    /// `$(inner)`: `arg`, `find`, `env`, `optenv`, `dirname`, `cwd`, or a whole `$(eval …)`.
    fn substitution(&mut self, inner: &str) -> std::result::Result<String, String> {
        if let Some(code) = inner.strip_prefix("eval ") {
            if code.contains("__") {
                return Err("$(eval ...) may not contain double underscore expressions".into());
            }
            let value = expr::eval(code, &mut EvalEnv { x: self })?;
            return Ok(value.to_text());
        }
        if inner == "cwd" {
            return std::env::current_dir()
                .map(|d| d.display().to_string())
                .map_err(|e| e.to_string());
        }
        if inner.contains('$') {
            return Err(format!(
                "Dollar signs \"$\" cannot be inside of substitution args [{inner}]"
            ));
        }
        let words: Vec<&str> = inner.split(' ').filter(|w| !w.is_empty()).collect();
        let one = |what: &str| match words.len() {
            2 => Ok(words[1].to_string()),
            _ => Err(format!("$({what} …) takes exactly one argument [{inner}]")),
        };
        match words.first().copied() {
            Some("arg") => {
                let name = one("arg")?;
                self.arg_value(&name)
                    .cloned()
                    .ok_or_else(|| format!("Undefined substitution argument {name}"))
            }
            Some("find") => {
                let name = one("find")?;
                self.packages.find_package(&name).map(|p| absolute(&p)).ok_or_else(|| {
                    format!(
                        "$(find {name}): no package '{name}' (a folder whose package.xml names it) under `package_path` or ROS_PACKAGE_PATH"
                    )
                })
            }
            Some("env") => {
                let name = one("env")?;
                std::env::var(&name).map_err(|_| format!("environment variable {name} is not set"))
            }
            Some("optenv") if words.len() >= 2 => Ok(std::env::var(words[1]).unwrap_or_else(|_| words[2..].join(" "))),
            Some("dirname") => Ok(absolute(&self.base_dir())),
            _ => Err(format!(
                "Unknown substitution command [{inner}]. Valid commands are ['find', 'env', 'optenv', 'dirname', 'arg', 'eval']"
            )),
        }
    }

    /// Expands `nodes` in `scope` with `macros` into `out`; `xacro:attribute` sets one of
    /// `attrs`, the enclosing element's.
    fn nodes(
        &mut self,
        nodes: &[Node],
        scope: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
        attrs: &mut Vec<(String, String)>,
    ) -> Result<()> {
        self.depth += 1;
        let result = self.nodes_inner(nodes, scope, macros, out, attrs);
        self.depth -= 1;
        result
    }

    fn nodes_inner(
        &mut self,
        nodes: &[Node],
        scope: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
        attrs: &mut Vec<(String, String)>,
    ) -> Result<()> {
        for node in nodes {
            match node {
                Node::Text(t) => {
                    let text = match t.contains('$') {
                        true => self.text(t, scope).map_err(|m| self.text_fail(nodes, m))?,
                        false => t.clone(),
                    };
                    self.charge(text.len()).map_err(|m| self.text_fail(nodes, m))?;
                    out.push(Node::Text(text));
                }
                Node::CData(t) => out.push(Node::CData(t.clone())),
                Node::Element(e) => {
                    if self.depth > MAX_DEPTH {
                        return Err(self.fail(
                            e,
                            format!("the expansion nests more than {MAX_DEPTH} deep (elements, macros and includes; docs/development.md, Caps)"),
                        ));
                    }
                    self.charge(64).map_err(|m| self.fail(e, m))?;
                    self.element(e, scope, macros, out, attrs)?;
                }
            }
        }
        Ok(())
    }

    /// A failure in a text node: named by the first element among its siblings.
    fn text_fail(&self, nodes: &[Node], message: String) -> Fail {
        let near = nodes.iter().find_map(|n| match n {
            Node::Element(e) => Some(e),
            _ => None,
        });
        match near {
            Some(e) => self.fail(e, format!("text beside it: {message}")),
            None => {
                let (_, file) = self.files.last().cloned().unwrap_or_default();
                Fail {
                    file,
                    line: 0,
                    message: format!("text: {message}"),
                }
            }
        }
    }

    fn element(
        &mut self,
        e: &Element,
        scope: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
        attrs: &mut Vec<(String, String)>,
    ) -> Result<()> {
        match e.name.as_str() {
            "xacro:insert_block" => self.insert_block(e, scope, macros, out, attrs),
            "xacro:include" => self.include(e, scope, macros, out, attrs),
            "xacro:property" => self.property(e, scope),
            "xacro:macro" => self.define(e, macros),
            "xacro:arg" => self.argument(e, scope),
            "xacro:if" | "xacro:unless" => {
                let condition = e.attr("value").ok_or_else(|| self.fail(e, "needs a value"))?;
                let value = self.eval_text(condition, scope).map_err(|m| self.fail(e, m))?;
                let keep = boolean(&value, condition).map_err(|m| self.fail(e, m))? == (e.name == "xacro:if");
                match keep {
                    true => self.nodes(&e.children, scope, macros, out, attrs),
                    false => Ok(()),
                }
            }
            "xacro:element" => {
                let renamed = self.renamed(e, scope, "xacro:name", "")?;
                self.element(&renamed, scope, macros, out, attrs)
            }
            "xacro:attribute" => self.attribute(e, scope, attrs),
            "xacro:call" => {
                let call = self.renamed(e, scope, "macro", "xacro:")?;
                self.call(&call, scope, macros, out)
            }
            name if name.starts_with("xacro:") => self.call(e, scope, macros, out),
            _ => {
                let mut own = self.attributes(e, scope)?;
                let mut children = Vec::new();
                self.nodes(&e.children, scope, macros, &mut children, &mut own)?;
                out.push(Node::Element(Element {
                    name: e.name.clone(),
                    attrs: own,
                    children,
                    file: e.file.clone(),
                    line: e.line,
                }));
                Ok(())
            }
        }
    }

    /// `<xacro:insert_block name>`: a `**` block's content, or a `*` block itself, expanded here.
    fn insert_block(
        &mut self,
        e: &Element,
        scope: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
        attrs: &mut Vec<(String, String)>,
    ) -> Result<()> {
        let name = e.attr("name").ok_or_else(|| self.fail(e, "needs a name"))?;
        let find = |key: String| Env::find(scope, &key);
        match (find(format!("**{name}")), find(format!("*{name}"))) {
            (Some(Prop::Value(Value::Block(b))), _) => self.nodes(&b.children, scope, macros, out, attrs),
            (_, Some(Prop::Value(Value::Block(b)))) => self.element(&b, scope, macros, out, attrs),
            _ => Err(self.fail(e, format!("Undefined block \"{name}\""))),
        }
    }

    /// Argument `name`'s value (given, else its declared default), the name noted as one the
    /// document knows.
    fn arg_value(&mut self, name: &str) -> Option<&String> {
        self.known_args.insert(name.to_string());
        self.args.get(name)
    }

    /// Of the arguments `given`, those the expanded document neither declared nor read (in
    /// their order), and the arguments it knows: a misspelled `ur_tpye:=ur10e` would otherwise
    /// leave `ur_type` at its default unsaid.
    pub fn unknown_args<'g>(&self, given: &'g [(String, String)]) -> (Vec<&'g str>, Vec<&str>) {
        let unknown = (given.iter())
            .map(|(name, _)| name.as_str())
            .filter(|name| !self.known_args.contains(*name))
            .collect();
        (unknown, self.known_args.iter().map(String::as_str).collect())
    }

    /// `<xacro:arg name default>`: the argument's default, unless it was given.
    fn argument(&mut self, e: &Element, scope: &Scope) -> Result<()> {
        let name = e.attr("name").ok_or_else(|| self.fail(e, "needs a name"))?;
        let default = e.attr("default").ok_or_else(|| self.fail(e, "needs a default"))?;
        self.known_args.insert(name.to_string());
        if !self.args.contains_key(name) {
            let value = self.text(default, scope).map_err(|m| self.fail(e, m))?;
            self.args.insert(name.to_string(), value);
        }
        Ok(())
    }

    /// `e` named by its attribute `key` (evaluated, after `prefix`), without that attribute:
    /// `<xacro:element xacro:name>`, `<xacro:call macro>`.
    fn renamed(&mut self, e: &Element, scope: &Scope, key: &str, prefix: &str) -> Result<Element> {
        let name = e
            .attr(key)
            .ok_or_else(|| self.fail(e, format!("needs the attribute {key}")))?;
        let name = self.text(name, scope).map_err(|m| self.fail(e, m))?;
        if name.is_empty() {
            return Err(self.fail(e, "empty name"));
        }
        let mut renamed = e.clone();
        renamed.name = format!("{prefix}{name}");
        renamed.attrs.retain(|(k, _)| k != key);
        Ok(renamed)
    }

    /// `<xacro:attribute name value>`: an attribute of the enclosing element (`attrs`).
    fn attribute(&mut self, e: &Element, scope: &Scope, attrs: &mut Vec<(String, String)>) -> Result<()> {
        let (Some(name), Some(value)) = (e.attr("name"), e.attr("value")) else {
            return Err(self.fail(e, "needs a name and a value"));
        };
        let name = self.text(name, scope).map_err(|m| self.fail(e, m))?;
        let value = self.text(value, scope).map_err(|m| self.fail(e, m))?;
        if name.is_empty() {
            return Err(self.fail(e, "empty name"));
        }
        match attrs.iter_mut().find(|(k, _)| *k == name) {
            Some(slot) => slot.1 = value,
            None => attrs.push((name, value)),
        }
        Ok(())
    }

    /// `<xacro:include filename=… [optional=…]>`: the file's content, expanded in this scope.
    fn include(
        &mut self,
        e: &Element,
        scope: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
        attrs: &mut Vec<(String, String)>,
    ) -> Result<()> {
        if e.attr("ns").is_some() {
            return Err(self.fail(e, "the ns attribute (an include's namespace) is not supported"));
        }
        let spec = e.attr("filename").ok_or_else(|| self.fail(e, "needs a filename"))?;
        let optional = match e.attr("optional") {
            Some(o) => boolean(&Value::str(o), o).map_err(|m| self.fail(e, m))?,
            None => false,
        };
        let name = self.text(spec, scope).map_err(|m| self.fail(e, m))?;
        if name.contains(['*', '[', '?']) {
            return Err(self.fail(
                e,
                format!("'{name}': an include of several files by a pattern is not supported"),
            ));
        }
        if self.files.len() > MAX_INCLUDE_DEPTH {
            return Err(self.fail(
                e,
                format!("includes nest more than {MAX_INCLUDE_DEPTH} deep (docs/development.md, Caps)"),
            ));
        }
        let path = self.relative(&name);
        let bytes = match read_capped(&path, MAX_URDF_BYTES, "a xacro file") {
            Ok(b) => b,
            Err(_) if optional && !path.exists() => return Ok(()),
            Err(err) => return Err(self.fail(e, err.to_string())),
        };
        let text = String::from_utf8(bytes)
            .map_err(|_| self.fail(e, format!("{}: the file is not UTF-8 text", path.display())))?;
        let file: Rc<str> = path.display().to_string().into();
        let root = dom::parse(&text, &file).map_err(|(line, message)| Fail {
            file: file.clone(),
            line,
            message,
        })?;
        self.files.push((path, file));
        let result = (|| {
            self.attributes(&root, scope)?;
            self.nodes(&root.children, scope, macros, out, attrs)
        })();
        self.files.pop();
        result
    }

    /// `<xacro:property>`: a value, a default, a block, a removal; lazy unless told otherwise;
    /// in this scope, the parent's or the global one.
    fn property(&mut self, e: &Element, scope: &Scope) -> Result<()> {
        let raw = e.attr("name").ok_or_else(|| self.fail(e, "needs a name"))?;
        let name = self.text(raw, scope).map_err(|m| self.fail(e, m))?;
        if !is_identifier(&name) || name.starts_with("__") {
            return Err(self.fail(e, format!("Property names must be valid python identifiers: {name}")));
        }
        let remove = match e.attr("remove") {
            Some(r) => {
                let v = self.eval_text(r, scope).map_err(|m| self.fail(e, m))?;
                boolean(&v, r).map_err(|m| self.fail(e, m))?
            }
            None => false,
        };
        let (value, default) = (e.attr("value"), e.attr("default"));
        if usize::from(value.is_some()) + usize::from(default.is_some()) + usize::from(remove) > 1 {
            return Err(self.fail(e, format!("default, value and remove are mutually exclusive: {name}")));
        }
        if remove {
            let mut table = Some(scope.clone());
            while let Some(t) = table {
                t.borrow_mut().vars.remove(&name);
                table = t.borrow().parent.clone();
            }
            return Ok(());
        }
        let mut value = value.map(|v| Value::str(v.to_string()));
        if let Some(default) = default {
            if Env::find(scope, &name).is_some() {
                return Ok(());
            }
            value = Some(Value::str(default.to_string()));
        }
        let (key, value) = match value {
            Some(v) => (name.clone(), v),
            None => (format!("**{name}"), Value::Block(Rc::new(e.clone()))),
        };
        let mut lazy = match e.attr("lazy_eval") {
            Some(l) => {
                let v = self.eval_text(l, scope).map_err(|m| self.fail(e, m))?;
                boolean(&v, l).map_err(|m| self.fail(e, m))?
            }
            None => true,
        };
        let target = match e.attr("scope") {
            Some("global") => {
                lazy = false;
                let mut t = scope.clone();
                loop {
                    let parent = t.borrow().parent.clone();
                    match parent {
                        Some(p) => t = p,
                        None => break t,
                    }
                }
            }
            Some("parent") => {
                lazy = false;
                let parent = scope.borrow().parent.clone();
                parent.ok_or_else(|| {
                    self.fail(
                        e,
                        format!("{name}: scope=\"parent\" at the top level has no parent scope"),
                    )
                })?
            }
            Some("local") | None => scope.clone(),
            Some(other) => return Err(self.fail(e, format!("scope=\"{other}\" is not local, parent or global"))),
        };
        let value = match (&value, lazy) {
            (Value::Str(text), false) => self.eval_text(text, scope).map_err(|m| self.fail(e, m))?,
            _ => value,
        };
        set(&target, key, value, lazy);
        Ok(())
    }

    /// `<xacro:macro name params>`: defined in `macros`.
    fn define(&mut self, e: &Element, macros: &MacroScope) -> Result<()> {
        let name = e.attr("name").ok_or_else(|| self.fail(e, "needs a name"))?;
        if name == "call" || name.contains('.') {
            return Err(self.fail(e, format!("'{name}' is not a macro name xacro allows")));
        }
        let name = name.strip_prefix("xacro:").unwrap_or(name).to_string();
        let mut params = Vec::new();
        let mut defaults = HashMap::new();
        let mut rest = e.attr("params").unwrap_or_default();
        while !rest.trim().is_empty() {
            let (param, default, tail) = macro_param(rest);
            if let Some(d) = default {
                defaults.insert(param.clone(), d);
            }
            params.push(param);
            rest = tail;
        }
        let m = Macro {
            name: name.clone(),
            params,
            defaults,
            body: Rc::new(e.clone()),
        };
        macros.borrow_mut().table.insert(name, Rc::new(m));
        Ok(())
    }

    /// `<xacro:NAME …>`: the macro NAME expanded with these arguments and blocks.
    fn call(&mut self, e: &Element, scope: &Scope, macros: &MacroScope, out: &mut Vec<Node>) -> Result<()> {
        let name = &e.name["xacro:".len()..];
        let m = find_macro(macros, name).ok_or_else(|| {
            self.fail(
                e,
                match KNOWN_UNSUPPORTED.contains(&name) {
                    true => format!("xacro:{name} is not supported"),
                    false => format!("unknown macro name: xacro:{name}"),
                },
            )
        })?;
        if self.macro_depth >= MAX_MACRO_DEPTH {
            return Err(self.fail(
                e,
                format!("macros call each other more than {MAX_MACRO_DEPTH} deep (docs/development.md, Caps)"),
            ));
        }
        let local = self.bind(&m, e, scope, macros)?;
        let local_macros = Rc::new(RefCell::new(Macros {
            table: HashMap::new(),
            parent: Some(macros.clone()),
        }));
        self.macro_depth += 1;
        let result = (|| {
            self.attributes(&m.body, &local)?;
            let mut ignored = Vec::new();
            self.nodes(&m.body.children, &local, &local_macros, out, &mut ignored)
        })();
        self.macro_depth -= 1;
        result.map_err(|mut f| {
            if f.message.matches(" (in macro ").count() < 3 {
                f.message += &format!(" (in macro {} called at {} line {})", m.name, e.file, e.line);
            }
            f
        })
    }

    /// The scope of a call `e` of macro `m`: its attributes evaluated where the call is, its
    /// blocks (expanded there) handed in order to the `*` parameters, the defaults of the rest
    /// (a forwarded one taken from the caller's property of that name).
    fn bind(&mut self, m: &Macro, e: &Element, scope: &Scope, macros: &MacroScope) -> Result<Scope> {
        let local = child_scope(scope);
        let mut params = m.params.clone();
        for (k, v) in &e.attrs {
            let Some(at) = params.iter().position(|p| p == k) else {
                return Err(self.fail(e, format!("Invalid parameter \"{k}\" of macro {}", m.name)));
            };
            params.remove(at);
            let value = self
                .eval_text(v, scope)
                .map_err(|msg| self.fail(e, format!("{k}=\"{v}\": {msg}")))?;
            set(&local, k.clone(), value, false);
        }
        let mut blocks = Vec::new();
        let mut ignored = Vec::new();
        self.nodes(&e.children, scope, macros, &mut blocks, &mut ignored)?;
        let mut blocks = blocks.into_iter().filter_map(|n| match n {
            Node::Element(b) => Some(b),
            _ => None,
        });
        for param in params.clone().iter().filter(|p| p.starts_with('*')) {
            let block = blocks
                .next()
                .ok_or_else(|| self.fail(e, format!("Not enough blocks for macro {}", m.name)))?;
            set(&local, param.clone(), Value::Block(Rc::new(block)), false);
            params.retain(|p| p != param);
        }
        if let Some(extra) = blocks.next() {
            return Err(self.fail(e, format!("Unused block \"{}\" for macro {}", extra.name, m.name)));
        }
        for param in params.clone() {
            let Some((forward, default)) = m.defaults.get(&param) else {
                continue;
            };
            let value = match (forward, default) {
                (true, _) if Env::find(scope, &param).is_some() => {
                    let mut env = Env {
                        x: self,
                        scope: scope.clone(),
                    };
                    env.lookup(&param)
                        .map_err(|msg| self.fail(e, msg))?
                        .unwrap_or(Value::None)
                }
                (_, Some(d)) => self
                    .eval_text(d, scope)
                    .map_err(|msg| self.fail(e, format!("{param}'s default: {msg}")))?,
                (true, None) => return Err(self.fail(e, format!("Undefined property to forward: {param}"))),
                (false, None) => continue,
            };
            set(&local, param.clone(), value, false);
            params.retain(|p| *p != param);
        }
        if !params.is_empty() {
            return Err(self.fail(
                e,
                format!("Undefined parameters [{}] of macro {}", params.join(","), m.name),
            ));
        }
        Ok(local)
    }

    /// `xacro.load_yaml(name)`: the YAML file relative to the file being read.
    fn load_yaml(&mut self, name: &str) -> std::result::Result<Value, String> {
        let path = self.relative(name);
        let bytes = read_capped(&path, MAX_URDF_BYTES, "a YAML file").map_err(|e| e.to_string())?;
        let text = String::from_utf8(bytes).map_err(|_| format!("{}: the file is not UTF-8 text", path.display()))?;
        let mut unit = |t: &str| -> std::result::Result<f64, String> {
            let v = expr::eval(t, &mut NoNames)?;
            v.number()
                .ok_or_else(|| format!("the unit value '{t}' is not a number"))
        };
        let budget = &mut self.budget;
        let mut charge = |units: usize| -> std::result::Result<(), String> {
            *budget = budget.saturating_add(units);
            match *budget > MAX_BUDGET {
                true => Err(format!(
                    "the YAML grows past {} MiB (docs/development.md, Caps)",
                    MAX_BUDGET >> 20
                )),
                false => Ok(()),
            }
        };
        super::yaml::parse(&text, &mut unit, &mut charge)
            .map_err(|(line, e)| format!("{} line {line}: {e}", path.display()))
    }
}

/// xacro elements faze4 names when refusing them (ROS 1's and other tools' extensions).
const KNOWN_UNSUPPORTED: [&str; 2] = ["loop", "for"];

/// The macro `name` in `macros` or a scope above.
fn find_macro(macros: &MacroScope, name: &str) -> Option<Rc<Macro>> {
    let mut table = Some(macros.clone());
    while let Some(t) = table {
        if let Some(m) = t.borrow().table.get(name) {
            return Some(m.clone());
        }
        table = t.borrow().parent.clone();
    }
    None
}

/// `table[name] = value` (xacro's `_setitem`): a text is read as a literal; a text left
/// unevaluated (`lazy`) is evaluated on first use.
fn set(table: &Scope, name: String, value: Value, lazy: bool) {
    let value = literal(value);
    let prop = match (&value, lazy) {
        // xacro evaluates a lazy text on first use even without `${`: a quoted `''x''` loses
        // one pair of quotes when set and the other when used
        (Value::Str(s), true) => Prop::Lazy(s.to_string()),
        _ => Prop::Value(value),
    };
    table.borrow_mut().vars.insert(name, prop);
}

fn absolute(p: &Path) -> String {
    std::path::absolute(p)
        .unwrap_or_else(|_| p.to_path_buf())
        .display()
        .to_string()
}

/// The names a `${…}` expression sees: the properties of `scope` and the scopes above.
struct Env<'x, 'a> {
    x: &'x mut Expander<'a>,
    scope: Scope,
}

impl Env<'_, '_> {
    /// The property `name` as a table above `scope` holds it.
    fn find(scope: &Scope, name: &str) -> Option<Prop> {
        let mut table = Some(scope.clone());
        while let Some(t) = table {
            if let Some(p) = t.borrow().vars.get(name) {
                return Some(p.clone());
            }
            table = t.borrow().parent.clone();
        }
        None
    }
}

impl Names for Env<'_, '_> {
    fn lookup(&mut self, name: &str) -> std::result::Result<Option<Value>, String> {
        if name.starts_with("__") {
            return Err(format!("Use of invalid name(s): {name}"));
        }
        let mut table = Some(self.scope.clone());
        while let Some(t) = table {
            let found = t.borrow().vars.get(name).cloned();
            match found {
                Some(Prop::Value(v)) => return Ok(Some(v)),
                Some(Prop::Resolving) => return Err(format!("circular variable definition: {name}")),
                Some(Prop::Lazy(text)) => {
                    if self.x.depth > MAX_DEPTH {
                        return Err(format!(
                            "properties refer to each other more than {MAX_DEPTH} deep (docs/development.md, Caps)"
                        ));
                    }
                    t.borrow_mut().vars.insert(name.to_string(), Prop::Resolving);
                    self.x.depth += 1;
                    let value = self.x.eval_text(&text, &t).map(literal);
                    self.x.depth -= 1;
                    let value = match value {
                        Ok(v) => v,
                        Err(e) => {
                            t.borrow_mut().vars.insert(name.to_string(), Prop::Lazy(text));
                            return Err(match e.contains(" (in property ") {
                                true => e,
                                false => format!("{e} (in property {name})"),
                            });
                        }
                    };
                    t.borrow_mut().vars.insert(name.to_string(), Prop::Value(value.clone()));
                    return Ok(Some(value));
                }
                None => table = t.borrow().parent.clone(),
            }
        }
        Ok(None)
    }

    fn load_yaml(&mut self, file: &str) -> std::result::Result<Value, String> {
        self.x.load_yaml(file)
    }

    fn arg(&mut self, name: &str) -> std::result::Result<Value, String> {
        self.x
            .arg_value(name)
            .map(|v| Value::str(v.as_str()))
            .ok_or_else(|| format!("KeyError: '{name}' (no such xacro argument)"))
    }

    fn abs_filename(&mut self, file: &str) -> String {
        self.x.relative(file).display().to_string()
    }

    fn charge(&mut self, units: usize) -> std::result::Result<(), String> {
        self.x.charge(units)
    }
}

/// The names of `$(eval …)`: the arguments (numbers and booleans read as such) and the
/// built-ins.
struct EvalEnv<'x, 'a> {
    x: &'x mut Expander<'a>,
}

impl Names for EvalEnv<'_, '_> {
    fn lookup(&mut self, name: &str) -> std::result::Result<Option<Value>, String> {
        if matches!(name, "true" | "True") {
            return Ok(Some(Value::Bool(true)));
        }
        if matches!(name, "false" | "False") {
            return Ok(Some(Value::Bool(false)));
        }
        Ok(self.x.arg_value(name).map(|v| auto(v)))
    }

    fn load_yaml(&mut self, _: &str) -> std::result::Result<Value, String> {
        Err("load_yaml is not available in $(eval …)".into())
    }

    fn arg(&mut self, name: &str) -> std::result::Result<Value, String> {
        self.x
            .arg_value(name)
            .map(|v| auto(v))
            .ok_or_else(|| format!("Undefined substitution argument {name}"))
    }

    fn abs_filename(&mut self, file: &str) -> String {
        self.x.relative(file).display().to_string()
    }

    fn charge(&mut self, units: usize) -> std::result::Result<(), String> {
        self.x.charge(units)
    }
}

/// roslaunch's `convert_value(value, 'auto')`: a number (float with a dot), a boolean, or text.
fn auto(v: &str) -> Value {
    let number = match v.contains('.') {
        true => parse_float(v).map(Value::Float),
        false => v.trim().parse::<i64>().ok().map(Value::Int),
    };
    number.unwrap_or_else(|| match v.to_ascii_lowercase().as_str() {
        "true" => Value::Bool(true),
        "false" => Value::Bool(false),
        _ => Value::str(v),
    })
}

/// The names of a YAML unit tag's expression: the built-ins only.
struct NoNames;

impl Names for NoNames {
    fn lookup(&mut self, _: &str) -> std::result::Result<Option<Value>, String> {
        Ok(None)
    }
    fn load_yaml(&mut self, _: &str) -> std::result::Result<Value, String> {
        Err("load_yaml is not available here".into())
    }
    fn arg(&mut self, _: &str) -> std::result::Result<Value, String> {
        Err("xacro.arg is not available here".into())
    }
    fn abs_filename(&mut self, file: &str) -> String {
        file.to_string()
    }
    fn charge(&mut self, _: usize) -> std::result::Result<(), String> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn macro_parameters_read_as_xacro_reads_them() {
        let mut rest = "name *origin parent:='world' xyz:='0 0 0' type:=^ t2:=^|x d=${a + b} e:=$(arg x) **blocks last";
        let mut got = Vec::new();
        while !rest.trim().is_empty() {
            let (p, d, tail) = macro_param(rest);
            got.push((p, d));
            rest = tail;
        }
        let s = |t: &str| Some(t.to_string());
        assert_eq!(
            got,
            vec![
                ("name".into(), None),
                ("*origin".into(), None),
                ("parent".into(), Some((false, s("'world'")))),
                ("xyz".into(), Some((false, s("'0 0 0'")))),
                ("type".into(), Some((true, None))),
                ("t2".into(), Some((true, s("x")))),
                ("d".into(), Some((false, s("${a + b}")))),
                ("e".into(), Some((false, s("$(arg x)")))),
                ("**blocks".into(), None),
                ("last".into(), None),
            ]
        );
    }

    #[test]
    fn literals_read_as_xacro_reads_them() {
        let text = |v: Value| (v.type_name(), v.to_text());
        assert_eq!(text(literal(Value::str("1"))), ("int", "1".into()));
        assert_eq!(text(literal(Value::str(" 010 "))), ("int", "10".into()));
        assert_eq!(text(literal(Value::str("1.50"))), ("float", "1.5".into()));
        assert_eq!(text(literal(Value::str("1e-3"))), ("float", "0.001".into()));
        assert_eq!(text(literal(Value::str("'0 0 1'"))), ("str", "0 0 1".into()));
        assert_eq!(text(literal(Value::str("True"))), ("bool", "True".into()));
        assert_eq!(text(literal(Value::str("1_0"))), ("str", "1_0".into()));
        assert_eq!(text(literal(Value::str("0 0 1"))), ("str", "0 0 1".into()));
        assert_eq!(boolean(&Value::str("1"), "c"), Ok(true));
        assert!(boolean(&Value::str("1.0"), "c").is_err());
        assert_eq!(boolean(&Value::Float(1.0), "c"), Ok(true));
    }
}
