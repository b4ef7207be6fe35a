//! `xacro.load_yaml`: a YAML file as the values PyYAML's `safe_load` gives xacro. yaml-rust2
//! reads the events; each plain scalar is resolved by PyYAML's YAML 1.1 rules (`yes` and `on`
//! are booleans, `1e-3` without a dot or a signed exponent is a string, `010` is octal 8), a
//! quoted one is a string, anchors and aliases are copied, a later duplicate key wins, `<<`
//! merges, and xacro's unit tags (`!degrees 90`, `!radians pi/2`, `!millimeters`, `!meters`,
//! `!foot`, `!inches`) evaluate their text and scale it. A timestamp, a sexagesimal number or
//! another tag is refused naming it and its line.

use std::collections::HashMap;
use std::rc::Rc;

use yaml_rust2::parser::{Event, Parser, Tag};
use yaml_rust2::scanner::TScalarStyle;

use super::value::{Value, lookup};

/// Deepest nesting of YAML collections (64): the values are walked recursively later.
const MAX_DEPTH: usize = 64;

/// Parses YAML `text`; `unit` evaluates a unit tag's expression (`90`, `pi/2`) to a number;
/// `charge` counts each value made against the expansion's budget (an alias bomb stops there).
/// The error: what is wrong and its line.
pub fn parse(
    text: &str,
    unit: &mut dyn FnMut(&str) -> Result<f64, String>,
    charge: &mut dyn FnMut(usize) -> Result<(), String>,
) -> Result<Value, (usize, String)> {
    let mut parser = Parser::new_from_str(text);
    let mut anchors: HashMap<usize, Value> = HashMap::new();
    // open collections: (anchor, line, items or pairs)
    enum Open {
        Seq(usize, Vec<Value>),
        Map(usize, Vec<(Value, Value)>, Option<Value>),
    }
    let mut stack: Vec<Open> = Vec::new();
    let mut document: Option<Value> = None;
    loop {
        let (event, mark) = parser
            .next_token()
            .map_err(|e| (e.marker().line(), e.info().to_string()))?;
        let line = mark.line();
        let value = match event {
            Event::StreamEnd => break,
            Event::StreamStart | Event::DocumentEnd | Event::Nothing => continue,
            Event::DocumentStart => {
                if document.is_some() {
                    return Err((line, "more than one document (xacro.load_yaml reads one)".into()));
                }
                continue;
            }
            Event::Alias(id) => anchors
                .get(&id)
                .cloned()
                .ok_or((line, "an alias to an anchor not yet complete".into()))?,
            Event::Scalar(text, style, anchor, tag) => {
                let v = scalar(&text, style, tag.as_ref(), unit).map_err(|e| (line, e))?;
                if anchor > 0 {
                    anchors.insert(anchor, v.clone());
                }
                v
            }
            Event::SequenceStart(anchor, ref tag) | Event::MappingStart(anchor, ref tag) => {
                let sequence = matches!(event, Event::SequenceStart(..));
                if let Some(tag) = tag
                    .as_ref()
                    .filter(|t| !is_core(t, if sequence { "seq" } else { "map" }))
                {
                    return Err((
                        line,
                        format!("the YAML tag {}{} is not supported", tag.handle, tag.suffix),
                    ));
                }
                if stack.len() >= MAX_DEPTH {
                    return Err((line, format!("collections nest more than {MAX_DEPTH} deep")));
                }
                stack.push(match sequence {
                    true => Open::Seq(anchor, Vec::new()),
                    false => Open::Map(anchor, Vec::new(), None),
                });
                continue;
            }
            Event::SequenceEnd | Event::MappingEnd => {
                let (anchor, v) = match stack.pop() {
                    Some(Open::Seq(anchor, items)) => (anchor, Value::List(Rc::new(items))),
                    Some(Open::Map(anchor, pairs, _)) => (anchor, Value::Dict(Rc::new(pairs))),
                    None => return Err((line, "an end without a start".into())),
                };
                if anchor > 0 {
                    anchors.insert(anchor, v.clone());
                }
                v
            }
        };
        charge(1 + size(&value)).map_err(|e| (line, e))?;
        match stack.last_mut() {
            None => document = Some(value),
            Some(Open::Seq(_, items)) => items.push(value),
            Some(Open::Map(_, pairs, key)) => match key.take() {
                None => *key = Some(value),
                Some(k) => insert(pairs, k, value).map_err(|e| (line, e))?,
            },
        }
    }
    Ok(document.unwrap_or(Value::None))
}

/// How much a value copies when an alias repeats it: its items, counted one level down.
fn size(v: &Value) -> usize {
    match v {
        Value::List(items) => items.len(),
        Value::Dict(pairs) => pairs.len(),
        Value::Str(s) => s.len() / 64,
        _ => 0,
    }
}

/// `key: value` into a mapping: a later duplicate wins (PyYAML's rule); `<<` merges a mapping
/// or a list of mappings, keys already there winning.
fn insert(pairs: &mut Vec<(Value, Value)>, key: Value, value: Value) -> Result<(), String> {
    if matches!(&key, Value::Str(k) if &**k == MERGE) {
        let sources = match value {
            Value::Dict(d) => vec![d],
            Value::List(items) => (items.iter())
                .map(|i| match i {
                    Value::Dict(d) => Ok(d.clone()),
                    _ => Err("'<<' merges mappings only".to_string()),
                })
                .collect::<Result<_, _>>()?,
            _ => return Err("'<<' merges mappings only".into()),
        };
        for source in sources {
            for (k, v) in source.iter() {
                if lookup(pairs, k).is_none() {
                    pairs.push((k.clone(), v.clone()));
                }
            }
        }
        return Ok(());
    }
    match pairs.iter_mut().find(|(k, _)| k.equals(&key)) {
        Some(slot) => slot.1 = value,
        None => pairs.push((key, value)),
    }
    Ok(())
}

/// A plain `<<` key, marked so that a quoted `'<<'` stays a string.
const MERGE: &str = "\u{0}<<merge";

/// Whether `tag` is YAML's own tag `tag:yaml.org,2002:NAME`.
fn is_core(tag: &Tag, name: &str) -> bool {
    tag.handle == "tag:yaml.org,2002:" && tag.suffix == name
}

/// A scalar: tagged, quoted (a string), or plain (resolved by YAML 1.1).
fn scalar(
    text: &str,
    style: TScalarStyle,
    tag: Option<&Tag>,
    unit: &mut dyn FnMut(&str) -> Result<f64, String>,
) -> Result<Value, String> {
    if let Some(tag) = tag {
        let factor = match (tag.handle.as_str(), tag.suffix.as_str()) {
            ("!", "radians" | "meters") => Some(1.0),
            ("!", "degrees") => Some(std::f64::consts::PI / 180.0),
            ("!", "millimeters") => Some(0.001),
            ("!", "foot") => Some(0.3048),
            ("!", "inches") => Some(0.0254),
            _ => None,
        };
        if let Some(factor) = factor {
            return Ok(Value::Float(unit(text)? * factor));
        }
        return match (tag.handle.as_str(), tag.suffix.as_str()) {
            ("tag:yaml.org,2002:", "str") => Ok(Value::str(text)),
            ("tag:yaml.org,2002:", kind @ ("int" | "float" | "bool" | "null")) => plain(text)
                .filter(|v| v.type_name() == core_type(kind))
                .ok_or(format!("'{text}' is not a YAML {kind}")),
            (handle, suffix) => Err(format!("the YAML tag {handle}{suffix} is not supported")),
        };
    }
    if style != TScalarStyle::Plain {
        return Ok(Value::str(text));
    }
    if text == "<<" {
        return Ok(Value::str(MERGE));
    }
    if is_timestamp(text) {
        return Err(format!("the YAML timestamp '{text}' is not supported"));
    }
    if (text.contains(':') && text.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+'))
        && plain_number_shape(text)
    {
        return Err(format!("the sexagesimal YAML number '{text}' is not supported"));
    }
    Ok(plain(text).unwrap_or_else(|| Value::str(text)))
}

fn core_type(kind: &str) -> &'static str {
    match kind {
        "int" => "int",
        "float" => "float",
        "bool" => "bool",
        _ => "NoneType",
    }
}

/// A plain scalar's value by PyYAML's implicit resolvers (bool, float, int, null), or `None`
/// for a string.
fn plain(t: &str) -> Option<Value> {
    match t {
        "yes" | "Yes" | "YES" | "true" | "True" | "TRUE" | "on" | "On" | "ON" => return Some(Value::Bool(true)),
        "no" | "No" | "NO" | "false" | "False" | "FALSE" | "off" | "Off" | "OFF" => return Some(Value::Bool(false)),
        "" | "~" | "null" | "Null" | "NULL" => return Some(Value::None),
        _ => {}
    }
    if is_float(t) {
        let lower = t.replace('_', "").to_ascii_lowercase();
        let (sign, body) = match lower.strip_prefix('-') {
            Some(b) => (-1.0, b.to_string()),
            None => (1.0, lower.trim_start_matches('+').to_string()),
        };
        return Some(Value::Float(match body.as_str() {
            ".inf" => sign * f64::INFINITY,
            ".nan" => f64::NAN,
            b => sign * b.parse::<f64>().ok()?,
        }));
    }
    if is_int(t) {
        let clean = t.replace('_', "");
        let (sign, body) = match clean.strip_prefix('-') {
            Some(b) => (-1i64, b),
            None => (1, clean.trim_start_matches('+')),
        };
        let magnitude = if body == "0" {
            0
        } else if let Some(b) = body.strip_prefix("0b") {
            i64::from_str_radix(b, 2).ok()?
        } else if let Some(h) = body.strip_prefix("0x") {
            i64::from_str_radix(h, 16).ok()?
        } else if body.starts_with('0') {
            i64::from_str_radix(body, 8).ok()?
        } else {
            body.parse().ok()?
        };
        return Some(Value::Int(sign * magnitude));
    }
    None
}

fn digits_(s: &str, radix: u32) -> bool {
    s.chars().all(|c| c.is_digit(radix) || c == '_')
}

/// PyYAML's float pattern (sexagesimal refused separately).
fn is_float(t: &str) -> bool {
    let unsigned = t.strip_prefix(['-', '+']).unwrap_or(t);
    if matches!(unsigned, ".inf" | ".Inf" | ".INF") || matches!(t, ".nan" | ".NaN" | ".NAN") {
        return true;
    }
    // [-+]?[0-9][0-9_]*\.[0-9_]*([eE][-+][0-9]+)?   or   \.[0-9][0-9_]*([eE][-+][0-9]+)?
    let (body, exponent) = match unsigned.find(['e', 'E']) {
        Some(i) => (&unsigned[..i], Some(&unsigned[i + 1..])),
        None => (unsigned, None),
    };
    if let Some(e) = exponent
        && !(e.len() > 1 && e.starts_with(['-', '+']) && e[1..].chars().all(|c| c.is_ascii_digit()))
    {
        return false;
    }
    let Some((whole, fraction)) = body.split_once('.') else {
        return false;
    };
    let leading_dot = whole.is_empty() && t == unsigned;
    let whole_ok = !whole.is_empty() && whole.starts_with(|c: char| c.is_ascii_digit()) && digits_(whole, 10);
    let fraction_ok = digits_(fraction, 10) && (!leading_dot || fraction.starts_with(|c: char| c.is_ascii_digit()));
    (whole_ok || leading_dot) && fraction_ok
}

/// PyYAML's int pattern (sexagesimal refused separately).
fn is_int(t: &str) -> bool {
    let u = t.strip_prefix(['-', '+']).unwrap_or(t);
    if let Some(b) = u.strip_prefix("0b") {
        return !b.is_empty() && digits_(b, 2);
    }
    if let Some(h) = u.strip_prefix("0x") {
        return !h.is_empty() && digits_(h, 16);
    }
    if u == "0" {
        return true;
    }
    if let Some(o) = u.strip_prefix('0') {
        return !o.is_empty() && digits_(o, 8);
    }
    u.starts_with(|c: char| ('1'..='9').contains(&c)) && digits_(u, 10)
}

/// Whether a text with ':' looks like a sexagesimal number (`1:30`, `-1:30.5`).
fn plain_number_shape(t: &str) -> bool {
    let u = t.strip_prefix(['-', '+']).unwrap_or(t);
    !u.is_empty()
        && u.chars()
            .all(|c| c.is_ascii_digit() || c == ':' || c == '_' || c == '.')
}

/// PyYAML's timestamp pattern, roughly: `YYYY-MM-DD…`.
fn is_timestamp(t: &str) -> bool {
    let b = t.as_bytes();
    b.len() >= 8
        && b[..4].iter().all(u8::is_ascii_digit)
        && b[4] == b'-'
        && b[5].is_ascii_digit()
        && (b[6] == b'-' || (b[6].is_ascii_digit() && b.get(7) == Some(&b'-')))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(text: &str) -> Result<String, String> {
        let mut unit = |t: &str| t.trim().parse::<f64>().map_err(|e| e.to_string());
        let mut charge = |_: usize| Ok(());
        parse(text, &mut unit, &mut charge)
            .map(|v| v.to_text())
            .map_err(|(line, e)| format!("{line}: {e}"))
    }

    #[test]
    fn scalars_resolve_as_pyyaml_resolves_them() {
        let text = "a: 1e-3\nb: 1.0e-3\nc: 1.5e-05\nd: yes\ne: 010\nf: 0x1F\ng: '1.5'\nh: ~\ni: -.inf\nj: 1_000\nk: .5\nl: 0 0 0.1\nm: !degrees 180\nn: 7\no: 1.0e3\n";
        assert_eq!(
            load(text).unwrap(),
            "{'a': '1e-3', 'b': 0.001, 'c': 1.5e-05, 'd': True, 'e': 8, 'f': 31, 'g': '1.5', 'h': None, 'i': -inf, 'j': 1000, 'k': 0.5, 'l': '0 0 0.1', 'm': 3.141592653589793, 'n': 7, 'o': '1.0e3'}"
        );
    }

    #[test]
    fn anchors_duplicates_and_merges_are_pyyamls() {
        let text = "base: &b {x: 1, y: 2}\ncopy: *b\nmerged:\n  <<: *b\n  y: 5\ndup:\ndup: 3\nlist: [1, [2, 3]]\n";
        assert_eq!(
            load(text).unwrap(),
            "{'base': {'x': 1, 'y': 2}, 'copy': {'x': 1, 'y': 2}, 'merged': {'x': 1, 'y': 5}, 'dup': 3, 'list': [1, [2, 3]]}"
        );
    }

    #[test]
    fn what_pyyaml_reads_and_faze4_does_not_is_refused_with_its_line() {
        for (text, expect) in [
            ("a: 1\nb: 2001-12-14\n", "2: the YAML timestamp"),
            ("a: !custom 1\n", "1: the YAML tag !custom"),
            ("a: 1:30\n", "sexagesimal"),
            ("a: [1\n", ""),
            ("---\na: 1\n---\nb: 2\n", "more than one document"),
        ] {
            let err = load(text).unwrap_err();
            assert!(err.contains(expect), "{text}: {err}");
        }
        let deep = format!("{}{}", "[".repeat(100), "]".repeat(100));
        assert!(load(&deep).is_err());
    }
}
