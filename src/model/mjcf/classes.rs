//! MJCF's `<default>` classes: each class gives default attributes per element kind, a nested
//! class inherits its parent's and overrides them; the top `<default>` is the class `main`. An
//! element takes its own `class`, else the `childclass` of the nearest body (or frame) around
//! it that has one, else `main`.

use std::collections::HashMap;

use super::xml::Element;
use crate::error::{Error, Result};

/// The class every model has: the top `<default>`, or none.
pub(super) const MAIN: &str = "main";

/// MuJoCo's actuator elements: a default of any of them is the one actuator default of its
/// class (MuJoCo keeps one `general` default that each shortcut writes).
pub(super) const ACTUATORS: [&str; 9] = [
    "general",
    "motor",
    "position",
    "velocity",
    "intvelocity",
    "damper",
    "cylinder",
    "muscle",
    "adhesion",
];

/// One class: its parent and its default elements by kind (actuators under `actuator`).
#[derive(Debug, Default)]
struct Class {
    parent: Option<String>,
    defaults: HashMap<String, Element>,
}

/// Every `<default>` class of a model.
#[derive(Debug)]
pub(super) struct Classes {
    by_name: HashMap<String, Class>,
}

/// The kind an element's default is stored under: every actuator shortcut is `actuator`.
pub(super) fn kind(name: &str) -> &str {
    match ACTUATORS.contains(&name) {
        true => "actuator",
        false => name,
    }
}

impl Classes {
    /// The classes of the model's `<default>` sections (`root` is `<mujoco>`).
    pub fn of(root: &Element, file: &str) -> Result<Classes> {
        let mut classes = Classes {
            by_name: HashMap::from([(MAIN.to_string(), Class::default())]),
        };
        for top in root.all("default") {
            // a top <default> is `main`, whatever class it names
            classes.add(top, MAIN, None, file)?;
        }
        Ok(classes)
    }

    /// Adds the class `<default>` `element` holds, named `name`, under `parent`.
    fn add(&mut self, element: &Element, name: &str, parent: Option<&str>, file: &str) -> Result<()> {
        if parent.is_some() && self.by_name.contains_key(name) {
            return Err(Error::model(
                file,
                format!("<default class=\"{name}\"> ({})", element.at),
                "is defined twice",
            ));
        }
        let class = self.by_name.entry(name.to_string()).or_default();
        if let Some(p) = parent {
            class.parent = Some(p.to_string());
        }
        for child in element.children.iter().filter(|c| c.name != "default") {
            class.defaults.insert(kind(&child.name).to_string(), child.clone());
        }
        for nested in element.all("default") {
            let Some(child) = nested.get("class") else {
                return Err(Error::model(
                    file,
                    format!("<default> ({})", nested.at),
                    "a nested <default> needs a class name",
                ));
            };
            self.add(nested, child, Some(name), file)?;
        }
        Ok(())
    }

    /// Whether class `name` exists.
    pub fn has(&self, name: &str) -> bool {
        self.by_name.contains_key(name)
    }

    /// The value of attribute `key` for `element` of class `class`: its own, else the nearest
    /// class's default (the class, then its parents up to `main`).
    pub fn attribute<'a>(&'a self, element: &'a Element, class: &str, key: &str) -> Option<&'a str> {
        element
            .get(key)
            .or_else(|| self.default(kind(&element.name), class, key))
    }

    /// The default of attribute `key` for elements of kind `kind` in class `class`.
    pub fn default(&self, kind: &str, class: &str, key: &str) -> Option<&str> {
        self.default_element(kind, class, key).and_then(|d| d.get(key))
    }

    /// The default element of kind `kind` that gives `key` for class `class`, if one does.
    pub fn default_element(&self, kind: &str, class: &str, key: &str) -> Option<&Element> {
        // classes form a tree (each added under an existing one), so the walk ends
        self.chain(kind, class).find(|d| d.get(key).is_some())
    }

    /// The default elements of kind `kind` from class `class` up to `main`, nearest first.
    pub fn chain<'a, 'b>(&'a self, kind: &'b str, class: &'b str) -> impl Iterator<Item = &'a Element> + 'b
    where
        'a: 'b,
    {
        let mut at = Some(class);
        std::iter::from_fn(move || {
            loop {
                let c = self.by_name.get(at?)?;
                at = c.parent.as_deref();
                if let Some(d) = c.defaults.get(kind) {
                    return Some(d);
                }
            }
        })
    }

    /// The class of `element` inside a body (or frame) whose class for its children is
    /// `childclass`: its own `class`, else `childclass`; an unknown class is refused.
    pub fn class_of<'a>(&self, element: &'a Element, childclass: &'a str, file: &str) -> Result<&'a str> {
        let class = element.get("class").unwrap_or(childclass);
        match self.has(class) {
            true => Ok(class),
            false => Err(Error::model(
                file,
                format!("<{}> ({})", element.name, element.at),
                format!("names class '{class}', which no <default> defines"),
            )),
        }
    }
}
