//! The values of xacro's Python expressions, and how Python writes them (`str()`, `repr()`).

use std::rc::Rc;

use super::dom::Element;

/// A Python value as xacro's expressions and properties hold it.
#[derive(Clone, Debug)]
pub enum Value {
    /// `None`.
    None,
    /// `True`, `False`.
    Bool(bool),
    /// An `int` (64 bits here; Python's are unbounded, an overflow is refused).
    Int(i64),
    /// A `float`.
    Float(f64),
    /// A `str`.
    Str(Rc<str>),
    /// A `list` (a YAML sequence, `str.split()`'s result, a list literal) or a `tuple`.
    List(Rc<Vec<Value>>),
    /// A `dict` (a YAML mapping), in insertion order.
    Dict(Rc<Vec<(Value, Value)>>),
    /// A block: a macro's `*param` or a property block, inserted by `xacro:insert_block`.
    Block(Rc<Element>),
    /// A built-in function or method, by name (`radians`, `xacro.load_yaml`, `str.split`).
    Function(Function),
    /// A namespace of built-ins (`math`, `xacro`, `python`).
    Namespace(&'static str),
}

/// A callable: a built-in by name, or a method bound to its object.
#[derive(Clone, Debug)]
pub struct Function {
    /// Its name (`radians`, `xacro.load_yaml`, `split`).
    pub name: &'static str,
    /// The object a method is bound to.
    pub this: Option<Box<Value>>,
}

impl Value {
    /// A `str` value.
    pub fn str(text: impl Into<Rc<str>>) -> Value {
        Value::Str(text.into())
    }

    /// Python's type name of the value, for messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::None => "NoneType",
            Value::Bool(_) => "bool",
            Value::Int(_) => "int",
            Value::Float(_) => "float",
            Value::Str(_) => "str",
            Value::List(_) => "list",
            Value::Dict(_) => "dict",
            Value::Block(_) => "block",
            Value::Function(_) => "function",
            Value::Namespace(_) => "namespace",
        }
    }

    /// Python's truth value.
    pub fn truthy(&self) -> bool {
        match self {
            Value::None => false,
            Value::Bool(b) => *b,
            Value::Int(i) => *i != 0,
            Value::Float(x) => *x != 0.0,
            Value::Str(s) => !s.is_empty(),
            Value::List(l) => !l.is_empty(),
            Value::Dict(d) => !d.is_empty(),
            Value::Block(_) | Value::Function(_) | Value::Namespace(_) => true,
        }
    }

    /// The value as a number, if it is one (`bool` is an `int` in Python).
    pub fn number(&self) -> Option<f64> {
        match self {
            Value::Bool(b) => Some(f64::from(u8::from(*b))),
            Value::Int(i) => Some(*i as f64),
            Value::Float(x) => Some(*x),
            _ => None,
        }
    }

    /// The value as an integer, if it is one (`bool` included).
    pub fn int(&self) -> Option<i64> {
        match self {
            Value::Bool(b) => Some(i64::from(*b)),
            Value::Int(i) => Some(*i),
            _ => None,
        }
    }

    /// Python's `str(value)`.
    pub fn to_text(&self) -> String {
        match self {
            Value::Str(s) => s.to_string(),
            other => other.repr(),
        }
    }

    /// Python's `str(value)`, refused when it would be longer than `limit` bytes (a list of
    /// YAML aliases shares its items and may stand for billions of them).
    pub fn text_within(&self, limit: usize) -> Result<String, String> {
        let mut left = limit;
        match matches!(self, Value::Str(_)) || self.fits(&mut left) {
            true => Ok(self.to_text()),
            false => Err(format!("a text of more than {limit} bytes")),
        }
    }

    /// Whether the value's `repr` fits in `left` bytes (about: numbers count 24), taking them.
    fn fits(&self, left: &mut usize) -> bool {
        let own = match self {
            Value::List(items) => {
                if !items.iter().all(|i| i.fits(left)) {
                    return false;
                }
                2 + 2 * items.len()
            }
            Value::Dict(pairs) => {
                if !pairs.iter().all(|(k, v)| k.fits(left) && v.fits(left)) {
                    return false;
                }
                2 + 4 * pairs.len()
            }
            Value::Str(s) => s.len() + 2,
            _ => 24,
        };
        match own <= *left {
            true => {
                *left -= own;
                true
            }
            false => false,
        }
    }

    /// Python's `repr(value)`.
    pub fn repr(&self) -> String {
        match self {
            Value::None => "None".into(),
            Value::Bool(true) => "True".into(),
            Value::Bool(false) => "False".into(),
            Value::Int(i) => i.to_string(),
            Value::Float(x) => float_repr(*x),
            Value::Str(s) => string_repr(s),
            Value::List(items) => {
                let items: Vec<String> = items.iter().map(Value::repr).collect();
                format!("[{}]", items.join(", "))
            }
            Value::Dict(pairs) => {
                let pairs: Vec<String> = pairs
                    .iter()
                    .map(|(k, v)| format!("{}: {}", k.repr(), v.repr()))
                    .collect();
                format!("{{{}}}", pairs.join(", "))
            }
            Value::Block(e) => format!("<Element {}>", e.name),
            Value::Function(f) => format!("<function {}>", f.name),
            Value::Namespace(n) => format!("<namespace {n}>"),
        }
    }

    /// Python's `==` (numbers compare by value across int, float and bool).
    pub fn equals(&self, other: &Value) -> bool {
        match (self, other) {
            (Value::None, Value::None) => true,
            (Value::Str(a), Value::Str(b)) => a == b,
            (Value::List(a), Value::List(b)) => a.len() == b.len() && a.iter().zip(b.iter()).all(|(x, y)| x.equals(y)),
            (Value::Dict(a), Value::Dict(b)) => {
                a.len() == b.len() && a.iter().all(|(k, v)| lookup(b, k).is_some_and(|w| v.equals(w)))
            }
            (a, b) => match (a.int(), b.int()) {
                (Some(x), Some(y)) => x == y,
                _ => match (a.number(), b.number()) {
                    (Some(x), Some(y)) => x == y,
                    _ => false,
                },
            },
        }
    }
}

/// The value of `key` in the pairs of a dict.
pub fn lookup<'a>(pairs: &'a [(Value, Value)], key: &Value) -> Option<&'a Value> {
    pairs.iter().rev().find(|(k, _)| k.equals(key)).map(|(_, v)| v)
}

/// Python's `repr(float)`: the shortest digits that read back to `x`, in fixed notation when
/// the decimal point falls within 16 digits of them (`0.0001`, `1000000000000000.0`), else in
/// exponent notation (`1e-05`, `1e+16`).
pub fn float_repr(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    // Rust's `{:e}` gives the shortest round-trip digits, as Python's repr
    let e = format!("{x:e}");
    let (mantissa, exponent) = e.split_once('e').unwrap_or((&e, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let (sign, mantissa) = match mantissa.strip_prefix('-') {
        Some(m) => ("-", m),
        None => ("", mantissa),
    };
    let digits: String = mantissa.chars().filter(|c| *c != '.').collect();
    let n = digits.len() as i32;
    let point = exponent + 1; // digits before the decimal point
    let body = if !(-4 < point && point <= 16) {
        let rest = &digits[1..];
        let sign_e = if exponent < 0 { '-' } else { '+' };
        match rest.is_empty() {
            true => format!("{}e{sign_e}{:02}", &digits[..1], exponent.abs()),
            false => format!("{}.{rest}e{sign_e}{:02}", &digits[..1], exponent.abs()),
        }
    } else if point <= 0 {
        format!("0.{}{digits}", "0".repeat((-point) as usize))
    } else if point >= n {
        format!("{digits}{}.0", "0".repeat((point - n) as usize))
    } else {
        format!("{}.{}", &digits[..point as usize], &digits[point as usize..])
    };
    format!("{sign}{body}")
}

/// Python's `repr(str)`: single quotes unless the text holds one and no double quote.
fn string_repr(s: &str) -> String {
    let quote = if s.contains('\'') && !s.contains('"') {
        '"'
    } else {
        '\''
    };
    let mut out = String::with_capacity(s.len() + 2);
    out.push(quote);
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c == quote => {
                out.push('\\');
                out.push(c);
            }
            c if (c as u32) < 0x20 || c as u32 == 0x7f => out.push_str(&format!("\\x{:02x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push(quote);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_are_written_as_python_writes_them() {
        let cases = [
            (0.0, "0.0"),
            (-0.0, "-0.0"),
            (1.0, "1.0"),
            (std::f64::consts::PI, "3.141592653589793"),
            (-std::f64::consts::FRAC_PI_2, "-1.5707963267948966"),
            (0.1 + 0.2, "0.30000000000000004"),
            (1e-4, "0.0001"),
            (1e-5, "1e-05"),
            (1.5e-7, "1.5e-07"),
            (9.890414008333333e-05, "9.890414008333333e-05"),
            (1e15, "1000000000000000.0"),
            (1e16, "1e+16"),
            (1.25e22, "1.25e+22"),
            (123456.789, "123456.789"),
            (f64::INFINITY, "inf"),
            (f64::NAN, "nan"),
            (1e300 * 10.0, "1e+301"),
        ];
        for (x, text) in cases {
            assert_eq!(float_repr(x), text, "{x:e}");
        }
    }

    #[test]
    fn containers_and_strings_are_written_as_python_writes_them() {
        let list = Value::List(Rc::new(vec![
            Value::Int(1),
            Value::str("a'b"),
            Value::Float(0.5),
            Value::None,
        ]));
        assert_eq!(list.to_text(), "[1, \"a'b\", 0.5, None]");
        let dict = Value::Dict(Rc::new(vec![(Value::str("x"), Value::Bool(true))]));
        assert_eq!(dict.to_text(), "{'x': True}");
        assert_eq!(Value::str("it's \"q\"").repr(), "'it\\'s \"q\"'");
        assert!(Value::Int(1).equals(&Value::Float(1.0)) && Value::Bool(true).equals(&Value::Int(1)));
        assert!(!Value::str("1").equals(&Value::Int(1)));
    }
}
