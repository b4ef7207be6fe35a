//! The Python of xacro's `${…}` expressions: parsed into a tree, then evaluated against the
//! properties in scope ([`Names`]). What robot descriptions use: numbers and strings, arithmetic
//! (`+ - * / // % **`), comparisons (chained), `and`/`or`/`not`, `x if c else y`, `in`,
//! indexing and slicing, lists, tuples and dicts, attribute access on YAML dicts
//! (`link.origin.xyz`), `math`'s functions and constants, the built-ins xacro exposes (`abs`,
//! `min`, `max`, `round`, `int`, `float`, `str`, `bool`, `len`, `list`, `sum`, `sorted`,
//! `range`, …), `str` and `dict` methods, and `xacro.load_yaml`, `xacro.arg`, the message
//! functions and `xacro.fatal`. Anything else (`lambda`, comprehensions, bitwise operators,
//! f-strings…) is refused by name.

use std::rc::Rc;

use super::value::{Function, Value, float_repr, lookup};

/// Deepest nesting of an expression's parentheses, brackets and operators (64): the parser and
/// the evaluator recurse.
const MAX_DEPTH: usize = 64;

/// What an expression can reach beyond its own text: the properties in scope, and the
/// functions that read files or count the expansion's size.
pub trait Names {
    /// The value of `name` (a property, or `None` to fall back to the built-ins).
    fn lookup(&mut self, name: &str) -> Result<Option<Value>, String>;
    /// `xacro.load_yaml(file)`.
    fn load_yaml(&mut self, file: &str) -> Result<Value, String>;
    /// `xacro.arg(name)`.
    fn arg(&mut self, name: &str) -> Result<Value, String>;
    /// `xacro.abs_filename(file)`: the file relative to the file being read.
    fn abs_filename(&mut self, file: &str) -> String;
    /// Counts `units` of the expansion's budget (bytes of text made, elements expanded).
    fn charge(&mut self, units: usize) -> Result<(), String>;
}

/// A parsed expression.
#[derive(Clone, Debug)]
enum Expr {
    Const(Value),
    Name(String),
    Attr(Box<Expr>, String),
    Index(Box<Expr>, Box<Expr>),
    Slice(Box<Expr>, [Option<Box<Expr>>; 3]),
    Call(Box<Expr>, Vec<Expr>),
    Neg(Box<Expr>),
    Pos(Box<Expr>),
    Not(Box<Expr>),
    Binary(Op, Box<Expr>, Box<Expr>),
    Compare(Box<Expr>, Vec<(Cmp, Expr)>),
    And(Box<Expr>, Box<Expr>),
    Or(Box<Expr>, Box<Expr>),
    IfElse(Box<Expr>, Box<Expr>, Box<Expr>),
    List(Vec<Expr>),
    Dict(Vec<(Expr, Expr)>),
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Add,
    Sub,
    Mul,
    Div,
    FloorDiv,
    Mod,
    Pow,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Cmp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    In,
    NotIn,
    Is,
    IsNot,
}

#[derive(Clone, Debug)]
enum Token {
    Num(Value),
    Str(String),
    Name(String),
    Op(&'static str),
}

/// Evaluates the Python expression `text` with `names`.
pub fn eval(text: &str, names: &mut dyn Names) -> Result<Value, String> {
    let expr = parse(text)?;
    Evaluator { names, depth: 0 }.eval(&expr)
}

fn parse(text: &str) -> Result<Expr, String> {
    let tokens = tokenize(text)?;
    let mut parser = Parser {
        tokens,
        pos: 0,
        depth: 0,
    };
    let expr = parser.tuple_or_expr()?;
    match parser.peek() {
        None => Ok(expr),
        Some(t) => Err(format!("unexpected {} in '{}'", describe(t), text.trim())),
    }
}

fn describe(t: &Token) -> String {
    match t {
        Token::Num(v) => v.repr(),
        Token::Str(s) => format!("'{s}'"),
        Token::Name(n) => format!("'{n}'"),
        Token::Op(o) => format!("'{o}'"),
    }
}

const OPERATORS: [&str; 30] = [
    "**", "//", "==", "!=", "<=", ">=", ":=", "<<", ">>", "->", "+", "-", "*", "/", "%", "<", ">", "(", ")", "[", "]",
    "{", "}", ",", ".", ":", "&", "|", "^", "~",
];

fn tokenize(text: &str) -> Result<Vec<Token>, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit())) {
            let (value, next) = number(&chars, i)?;
            tokens.push(Token::Num(value));
            i = next;
        } else if c == '\'' || c == '"' {
            let (s, next) = string(&chars, i, false)?;
            tokens.push(Token::Str(s));
            i = next;
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let quote = chars.get(i).is_some_and(|q| *q == '\'' || *q == '"');
            match (word.as_str(), quote) {
                ("r" | "R", true) => {
                    let (s, next) = string(&chars, i, true)?;
                    tokens.push(Token::Str(s));
                    i = next;
                }
                (prefix, true) if prefix.len() <= 2 && prefix.chars().all(|p| "bBfFuU".contains(p)) => {
                    return Err(format!("the string prefix {prefix}'…' is not supported"));
                }
                _ => tokens.push(Token::Name(word)),
            }
        } else {
            let rest: String = chars[i..chars.len().min(i + 2)].iter().collect();
            let op = OPERATORS
                .iter()
                .find(|op| rest.starts_with(**op))
                .ok_or_else(|| format!("'{c}' is not Python"))?;
            if matches!(*op, ":=" | "<<" | ">>" | "->" | "&" | "|" | "^" | "~") {
                return Err(format!("the operator '{op}' is not supported"));
            }
            tokens.push(Token::Op(op));
            i += op.chars().count();
        }
    }
    Ok(tokens)
}

/// A number literal from `chars[i..]`: its value and the index after it.
fn number(chars: &[char], mut i: usize) -> Result<(Value, usize), String> {
    let start = i;
    let digits = |chars: &[char], mut i: usize, radix: u32| {
        while i < chars.len() && (chars[i].is_digit(radix) || chars[i] == '_') {
            i += 1;
        }
        i
    };
    if chars[i] == '0' && chars.get(i + 1).is_some_and(|c| "xXoObB".contains(*c)) {
        let radix = match chars[i + 1].to_ascii_lowercase() {
            'x' => 16,
            'o' => 8,
            _ => 2,
        };
        let end = digits(chars, i + 2, radix);
        let text: String = chars[i + 2..end].iter().filter(|c| **c != '_').collect();
        let value = i64::from_str_radix(&text, radix).map_err(|_| {
            format!(
                "'{}' is not a number faze4 reads",
                String::from_iter(&chars[start..end])
            )
        })?;
        return Ok((Value::Int(value), end));
    }
    i = digits(chars, i, 10);
    let mut float = false;
    if chars.get(i) == Some(&'.') {
        float = true;
        i = digits(chars, i + 1, 10);
    }
    if chars.get(i).is_some_and(|c| *c == 'e' || *c == 'E') {
        let mut j = i + 1;
        if chars.get(j).is_some_and(|c| *c == '+' || *c == '-') {
            j += 1;
        }
        if chars.get(j).is_some_and(|c| c.is_ascii_digit()) {
            float = true;
            i = digits(chars, j, 10);
        }
    }
    if chars.get(i).is_some_and(|c| *c == 'j' || *c == 'J') {
        return Err("complex numbers are not supported".into());
    }
    let text: String = chars[start..i].iter().filter(|c| **c != '_').collect();
    let value = match float {
        true => Value::Float(text.parse().map_err(|_| format!("'{text}' is not a number"))?),
        false => Value::Int(
            text.parse()
                .map_err(|_| format!("the integer {text} is larger than 64 bits"))?,
        ),
    };
    Ok((value, i))
}

/// A quoted string from `chars[i..]` (`raw`: no escapes): its text and the index after it.
fn string(chars: &[char], i: usize, raw: bool) -> Result<(String, usize), String> {
    let quote = chars[i];
    if chars.get(i + 1) == Some(&quote) && chars.get(i + 2) == Some(&quote) {
        return Err("triple-quoted strings are not supported".into());
    }
    let mut out = String::new();
    let mut j = i + 1;
    while j < chars.len() {
        let c = chars[j];
        if c == quote {
            return Ok((out, j + 1));
        }
        if c == '\\' && j + 1 < chars.len() {
            let e = chars[j + 1];
            if raw {
                out.push('\\');
                out.push(e);
            } else {
                match e {
                    'n' => out.push('\n'),
                    't' => out.push('\t'),
                    'r' => out.push('\r'),
                    '0' => out.push('\0'),
                    '\\' | '\'' | '"' => out.push(e),
                    other => {
                        out.push('\\');
                        out.push(other);
                    }
                }
            }
            j += 2;
            continue;
        }
        out.push(c);
        j += 1;
    }
    Err("a string is not closed".into())
}

struct Parser {
    tokens: Vec<Token>,
    pos: usize,
    depth: usize,
}

impl Parser {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    fn next(&mut self) -> Option<Token> {
        let t = self.tokens.get(self.pos).cloned();
        self.pos += 1;
        t
    }

    fn is_op(&self, op: &str) -> bool {
        matches!(self.peek(), Some(Token::Op(o)) if *o == op)
    }

    fn is_word(&self, word: &str) -> bool {
        matches!(self.peek(), Some(Token::Name(n)) if n == word)
    }

    fn eat_op(&mut self, op: &str) -> bool {
        let found = self.is_op(op);
        if found {
            self.pos += 1;
        }
        found
    }

    fn eat_word(&mut self, word: &str) -> bool {
        let found = self.is_word(word);
        if found {
            self.pos += 1;
        }
        found
    }

    fn expect(&mut self, op: &str) -> Result<(), String> {
        match self.eat_op(op) {
            true => Ok(()),
            false => Err(match self.peek() {
                Some(t) => format!("expected '{op}', found {}", describe(t)),
                None => format!("expected '{op}' at the end"),
            }),
        }
    }

    fn deeper(&mut self) -> Result<(), String> {
        self.depth += 1;
        match self.depth > MAX_DEPTH {
            true => Err(format!("the expression nests more than {MAX_DEPTH} deep")),
            false => Ok(()),
        }
    }

    /// `a, b` (a tuple, as a list) or one expression.
    fn tuple_or_expr(&mut self) -> Result<Expr, String> {
        let first = self.expr()?;
        if !self.is_op(",") {
            return Ok(first);
        }
        let mut items = vec![first];
        while self.eat_op(",") {
            if self.peek().is_none() || self.is_op(")") {
                break;
            }
            items.push(self.expr()?);
        }
        Ok(Expr::List(items))
    }

    fn expr(&mut self) -> Result<Expr, String> {
        self.deeper()?;
        if self.is_word("lambda") {
            return Err("lambda is not supported".into());
        }
        let body = self.or_test()?;
        let result = if self.eat_word("if") {
            let cond = self.or_test()?;
            if !self.eat_word("else") {
                return Err("'x if c' needs 'else'".into());
            }
            let other = self.expr()?;
            Expr::IfElse(Box::new(cond), Box::new(body), Box::new(other))
        } else {
            body
        };
        if self.is_word("for") {
            return Err("comprehensions ('for' in an expression) are not supported".into());
        }
        self.depth -= 1;
        Ok(result)
    }

    fn or_test(&mut self) -> Result<Expr, String> {
        let mut left = self.and_test()?;
        while self.eat_word("or") {
            left = Expr::Or(Box::new(left), Box::new(self.and_test()?));
        }
        Ok(left)
    }

    fn and_test(&mut self) -> Result<Expr, String> {
        let mut left = self.not_test()?;
        while self.eat_word("and") {
            left = Expr::And(Box::new(left), Box::new(self.not_test()?));
        }
        Ok(left)
    }

    fn not_test(&mut self) -> Result<Expr, String> {
        if self.eat_word("not") {
            self.deeper()?;
            let inner = self.not_test()?;
            self.depth -= 1;
            return Ok(Expr::Not(Box::new(inner)));
        }
        self.comparison()
    }

    fn comparison(&mut self) -> Result<Expr, String> {
        let first = self.arith()?;
        let mut rest = Vec::new();
        loop {
            let op = match self.peek() {
                Some(Token::Op("==")) => Cmp::Eq,
                Some(Token::Op("!=")) => Cmp::Ne,
                Some(Token::Op("<")) => Cmp::Lt,
                Some(Token::Op("<=")) => Cmp::Le,
                Some(Token::Op(">")) => Cmp::Gt,
                Some(Token::Op(">=")) => Cmp::Ge,
                Some(Token::Name(n)) if n == "in" => Cmp::In,
                Some(Token::Name(n)) if n == "is" => Cmp::Is,
                Some(Token::Name(n)) if n == "not" => Cmp::NotIn,
                _ => break,
            };
            self.pos += 1;
            let op = match op {
                Cmp::NotIn if !self.eat_word("in") => return Err("'not' here must be 'not in'".into()),
                Cmp::Is if self.eat_word("not") => Cmp::IsNot,
                op => op,
            };
            rest.push((op, self.arith()?));
        }
        Ok(match rest.is_empty() {
            true => first,
            false => Expr::Compare(Box::new(first), rest),
        })
    }

    fn arith(&mut self) -> Result<Expr, String> {
        let mut left = self.term()?;
        loop {
            let op = match self.peek() {
                Some(Token::Op("+")) => Op::Add,
                Some(Token::Op("-")) => Op::Sub,
                _ => break,
            };
            self.pos += 1;
            left = Expr::Binary(op, Box::new(left), Box::new(self.term()?));
        }
        Ok(left)
    }

    fn term(&mut self) -> Result<Expr, String> {
        let mut left = self.factor()?;
        loop {
            let op = match self.peek() {
                Some(Token::Op("*")) => Op::Mul,
                Some(Token::Op("/")) => Op::Div,
                Some(Token::Op("//")) => Op::FloorDiv,
                Some(Token::Op("%")) => Op::Mod,
                _ => break,
            };
            self.pos += 1;
            left = Expr::Binary(op, Box::new(left), Box::new(self.factor()?));
        }
        Ok(left)
    }

    fn factor(&mut self) -> Result<Expr, String> {
        if self.is_op("-") || self.is_op("+") {
            let negative = self.is_op("-");
            self.pos += 1;
            self.deeper()?;
            let inner = self.factor()?;
            self.depth -= 1;
            return Ok(match negative {
                true => Expr::Neg(Box::new(inner)),
                false => Expr::Pos(Box::new(inner)),
            });
        }
        self.power()
    }

    fn power(&mut self) -> Result<Expr, String> {
        let base = self.primary()?;
        if self.eat_op("**") {
            self.deeper()?;
            let exponent = self.factor()?;
            self.depth -= 1;
            return Ok(Expr::Binary(Op::Pow, Box::new(base), Box::new(exponent)));
        }
        Ok(base)
    }

    fn primary(&mut self) -> Result<Expr, String> {
        let mut e = self.atom()?;
        loop {
            if self.eat_op(".") {
                match self.next() {
                    Some(Token::Name(n)) => e = Expr::Attr(Box::new(e), n),
                    _ => return Err("a name must follow '.'".into()),
                }
            } else if self.eat_op("(") {
                let mut args = Vec::new();
                while !self.is_op(")") {
                    if matches!(self.peek(), Some(Token::Name(_)))
                        && matches!(self.tokens.get(self.pos + 1), Some(Token::Op(o)) if *o == "=")
                    {
                        return Err("keyword arguments are not supported".into());
                    }
                    if self.is_op("*") || self.is_op("**") {
                        return Err("argument unpacking is not supported".into());
                    }
                    args.push(self.expr()?);
                    if !self.eat_op(",") {
                        break;
                    }
                }
                self.expect(")")?;
                e = Expr::Call(Box::new(e), args);
            } else if self.eat_op("[") {
                e = self.subscript(e)?;
            } else {
                return Ok(e);
            }
        }
    }

    fn subscript(&mut self, target: Expr) -> Result<Expr, String> {
        let mut parts: [Option<Box<Expr>>; 3] = [None, None, None];
        let mut colons = 0;
        loop {
            if self.is_op("]") {
                break;
            }
            if self.eat_op(":") {
                colons += 1;
                if colons > 2 {
                    return Err("a slice takes at most two ':'".into());
                }
                continue;
            }
            if parts[colons].is_some() {
                return Err("expected ']' or ':'".into());
            }
            parts[colons] = Some(Box::new(self.expr()?));
        }
        self.expect("]")?;
        Ok(match (colons, parts) {
            (0, [Some(index), None, None]) => Expr::Index(Box::new(target), index),
            (0, _) => return Err("an empty subscript".into()),
            (_, parts) => Expr::Slice(Box::new(target), parts),
        })
    }

    fn atom(&mut self) -> Result<Expr, String> {
        match self.next() {
            Some(Token::Num(v)) => Ok(Expr::Const(v)),
            Some(Token::Str(mut s)) => {
                // adjacent literals concatenate
                while let Some(Token::Str(more)) = self.peek() {
                    s.push_str(more);
                    self.pos += 1;
                }
                Ok(Expr::Const(Value::str(s)))
            }
            Some(Token::Name(n)) => Ok(match n.as_str() {
                "True" => Expr::Const(Value::Bool(true)),
                "False" => Expr::Const(Value::Bool(false)),
                "None" => Expr::Const(Value::None),
                "and" | "or" | "not" | "in" | "is" | "if" | "else" | "for" | "lambda" | "yield" | "await"
                | "import" => return Err(format!("'{n}' cannot start an expression")),
                _ => Expr::Name(n),
            }),
            Some(Token::Op("(")) => {
                self.deeper()?;
                if self.eat_op(")") {
                    self.depth -= 1;
                    return Ok(Expr::List(Vec::new()));
                }
                let inner = self.tuple_or_expr()?;
                self.expect(")")?;
                self.depth -= 1;
                Ok(inner)
            }
            Some(Token::Op("[")) => {
                self.deeper()?;
                let mut items = Vec::new();
                while !self.is_op("]") {
                    items.push(self.expr()?);
                    if !self.eat_op(",") {
                        break;
                    }
                }
                self.expect("]")?;
                self.depth -= 1;
                Ok(Expr::List(items))
            }
            Some(Token::Op("{")) => {
                self.deeper()?;
                let mut pairs = Vec::new();
                while !self.is_op("}") {
                    let key = self.expr()?;
                    self.expect(":")?;
                    pairs.push((key, self.expr()?));
                    if !self.eat_op(",") {
                        break;
                    }
                }
                self.expect("}")?;
                self.depth -= 1;
                Ok(Expr::Dict(pairs))
            }
            Some(t) => Err(format!("unexpected {}", describe(&t))),
            None => Err("the expression ends too early".into()),
        }
    }
}

struct Evaluator<'a> {
    names: &'a mut dyn Names,
    depth: usize,
}

/// The functions and constants of Python's `math` that xacro exposes, as names.
const MATH_FUNCTIONS: [&str; 31] = [
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "sqrt",
    "exp", "log", "log10", "log2", "pow", "fabs", "floor", "ceil", "trunc", "degrees", "radians", "hypot", "fmod",
    "copysign", "isnan", "isinf", "isfinite",
];
/// The built-ins xacro exposes in `python.`.
const BUILTINS: [&str; 17] = [
    "abs", "min", "max", "round", "int", "float", "str", "bool", "len", "list", "sum", "sorted", "range", "any", "all",
    "repr", "tuple",
];
/// The built-ins xacro exposes as bare names too (`sorted` and `range` deprecated there).
const DIRECT_BUILTINS: [&str; 11] = [
    "min", "max", "round", "int", "float", "str", "bool", "len", "list", "sorted", "range",
];
/// xacro's own functions (`xacro.load_yaml`, …; `load_yaml` also bare, as xacro keeps it).
const XACRO_FUNCTIONS: [&str; 9] = [
    "load_yaml",
    "arg",
    "message",
    "warning",
    "error",
    "print_location",
    "fatal",
    "tokenize",
    "abs_filename",
];
/// The methods of `str` and `dict` that descriptions call.
const METHODS: [&str; 16] = [
    "split",
    "strip",
    "lstrip",
    "rstrip",
    "lower",
    "upper",
    "replace",
    "startswith",
    "endswith",
    "join",
    "find",
    "count",
    "get",
    "keys",
    "values",
    "items",
];

/// A built-in by its name in `namespace` (`""`: a bare name).
fn builtin(namespace: &str, name: &str) -> Option<Value> {
    let function = |name: &'static str| Value::Function(Function { name, this: None });
    let find = |list: &[&'static str]| list.iter().find(|f| **f == name).copied();
    let constant = match name {
        "pi" => Some(std::f64::consts::PI),
        "e" => Some(std::f64::consts::E),
        "tau" => Some(std::f64::consts::TAU),
        "inf" => Some(f64::INFINITY),
        "nan" => Some(f64::NAN),
        _ => None,
    };
    match namespace {
        "" => match name {
            "math" | "xacro" | "python" => Some(Value::Namespace(match name {
                "math" => "math",
                "xacro" => "xacro",
                _ => "python",
            })),
            _ => constant
                .map(Value::Float)
                .or_else(|| find(&MATH_FUNCTIONS).map(function))
                .or_else(|| find(&DIRECT_BUILTINS).map(function))
                .or_else(|| match name {
                    "load_yaml" => Some(function("load_yaml")),
                    "abs_filename" => Some(function("abs_filename")),
                    _ => None,
                }),
        },
        "math" => constant
            .map(Value::Float)
            .or_else(|| find(&MATH_FUNCTIONS).map(function)),
        "python" => find(&BUILTINS).map(function),
        "xacro" => find(&XACRO_FUNCTIONS).map(|n| {
            // `arg` and `load_yaml` are the same functions under xacro.
            function(n)
        }),
        _ => None,
    }
}

impl Evaluator<'_> {
    fn eval(&mut self, e: &Expr) -> Result<Value, String> {
        self.depth += 1;
        if self.depth > 4 * MAX_DEPTH {
            return Err("the expression nests too deep".into());
        }
        let value = self.eval_inner(e);
        self.depth -= 1;
        value
    }

    fn eval_inner(&mut self, e: &Expr) -> Result<Value, String> {
        Ok(match e {
            Expr::Const(v) => v.clone(),
            Expr::Name(n) => match self.names.lookup(n)? {
                Some(v) => v,
                None => builtin("", n).ok_or_else(|| format!("name '{n}' is not defined"))?,
            },
            Expr::Attr(target, name) => {
                let target = self.eval(target)?;
                attribute(target, name)?
            }
            Expr::Index(target, index) => {
                let target = self.eval(target)?;
                let index = self.eval(index)?;
                subscript(&target, &index)?
            }
            Expr::Slice(target, parts) => {
                let target = self.eval(target)?;
                let mut bounds = [None, None, None];
                for (bound, part) in bounds.iter_mut().zip(parts) {
                    if let Some(p) = part {
                        *bound = match self.eval(p)? {
                            Value::None => None,
                            v => Some(v.int().ok_or("slice indices must be integers")?),
                        };
                    }
                }
                slice(&target, bounds)?
            }
            Expr::Call(f, args) => {
                let f = self.eval(f)?;
                let args = args.iter().map(|a| self.eval(a)).collect::<Result<Vec<_>, _>>()?;
                self.call(f, args)?
            }
            Expr::Neg(x) => match self.eval(x)? {
                Value::Float(f) => Value::Float(-f),
                v => match v.int() {
                    Some(i) => Value::Int(i.checked_neg().ok_or("integer overflow")?),
                    None => return Err(format!("bad operand type for unary -: '{}'", v.type_name())),
                },
            },
            Expr::Pos(x) => match self.eval(x)? {
                Value::Float(f) => Value::Float(f),
                v => Value::Int(
                    v.int()
                        .ok_or(format!("bad operand type for unary +: '{}'", v.type_name()))?,
                ),
            },
            Expr::Not(x) => Value::Bool(!self.eval(x)?.truthy()),
            Expr::And(a, b) => {
                let a = self.eval(a)?;
                match a.truthy() {
                    true => self.eval(b)?,
                    false => a,
                }
            }
            Expr::Or(a, b) => {
                let a = self.eval(a)?;
                match a.truthy() {
                    true => a,
                    false => self.eval(b)?,
                }
            }
            Expr::IfElse(cond, then, other) => match self.eval(cond)?.truthy() {
                true => self.eval(then)?,
                false => self.eval(other)?,
            },
            Expr::Binary(op, a, b) => {
                let a = self.eval(a)?;
                let b = self.eval(b)?;
                let v = binary(*op, &a, &b)?;
                if let Value::Str(s) = &v {
                    self.names.charge(s.len())?;
                }
                if let Value::List(l) = &v {
                    self.names.charge(l.len())?;
                }
                v
            }
            Expr::Compare(first, rest) => {
                let mut left = self.eval(first)?;
                for (op, right) in rest {
                    let right = self.eval(right)?;
                    if !compare(*op, &left, &right)? {
                        return Ok(Value::Bool(false));
                    }
                    left = right;
                }
                Value::Bool(true)
            }
            Expr::List(items) => shallow(Value::List(Rc::new(
                items.iter().map(|i| self.eval(i)).collect::<Result<_, _>>()?,
            )))?,
            Expr::Dict(pairs) => shallow(Value::Dict(Rc::new(
                pairs
                    .iter()
                    .map(|(k, v)| Ok((self.eval(k)?, self.eval(v)?)))
                    .collect::<Result<_, String>>()?,
            )))?,
        })
    }

    fn call(&mut self, f: Value, args: Vec<Value>) -> Result<Value, String> {
        let Value::Function(f) = f else {
            return Err(format!("'{}' object is not callable", f.type_name()));
        };
        if let Some(this) = f.this {
            let v = method(f.name, &this, &args)?;
            if let Value::Str(s) = &v {
                self.names.charge(s.len())?;
            }
            return Ok(v);
        }
        let text = |i: usize| match args.get(i) {
            Some(Value::Str(s)) => Ok(s.to_string()),
            Some(v) => Err(format!("{}() takes a str, not {}", f.name, v.type_name())),
            None => Err(format!("{}() needs an argument", f.name)),
        };
        match f.name {
            "load_yaml" => self.names.load_yaml(&text(0)?),
            "arg" => self.names.arg(&text(0)?),
            "abs_filename" => Ok(Value::str(self.names.abs_filename(&text(0)?))),
            "message" | "warning" | "error" | "print_location" => Ok(Value::str("")),
            "fatal" => Err(args.iter().map(Value::to_text).collect::<Vec<_>>().join(" ")),
            "tokenize" => {
                let s = text(0)?;
                Ok(list(
                    s.split([',', ';', ' '])
                        .filter(|t| !t.is_empty())
                        .map(Value::str)
                        .collect(),
                ))
            }
            "range" => {
                let ints = args
                    .iter()
                    .map(|a| a.int().ok_or("range() takes integers"))
                    .collect::<Result<Vec<_>, _>>()?;
                let (start, stop, step) = match ints.as_slice() {
                    [stop] => (0, *stop, 1),
                    [start, stop] => (*start, *stop, 1),
                    [start, stop, step] if *step != 0 => (*start, *stop, *step),
                    _ => return Err("range() takes 1 to 3 integers, the step not 0".into()),
                };
                let n = match step > 0 {
                    true => (stop.saturating_sub(start).max(0) as u64).div_ceil(step as u64),
                    false => (start.saturating_sub(stop).max(0) as u64).div_ceil(step.unsigned_abs()),
                };
                self.names.charge(n as usize)?;
                Ok(list((0..n as i64).map(|k| Value::Int(start + k * step)).collect()))
            }
            name => call_builtin(name, &args),
        }
    }
}

fn list(items: Vec<Value>) -> Value {
    Value::List(Rc::new(items))
}

/// Deepest nesting of lists and dicts a value may have (100; a YAML file's nest at most 64):
/// values are dropped, compared and written recursively, and a property wrapping the one
/// before it a million times over would overflow the stack.
const MAX_VALUE_NESTING: usize = 100;

/// `v`, refused if its lists and dicts nest deeper than [`MAX_VALUE_NESTING`]. Each shared
/// list or dict is looked at once (a YAML alias bomb holds ten distinct lists).
fn shallow(v: Value) -> Result<Value, String> {
    fn deeper(v: &Value, left: usize, seen: &mut std::collections::HashSet<*const ()>) -> bool {
        let children: Box<dyn Iterator<Item = &Value>> = match v {
            Value::List(items) if seen.insert(Rc::as_ptr(items).cast()) => Box::new(items.iter()),
            Value::Dict(pairs) if seen.insert(Rc::as_ptr(pairs).cast()) => {
                Box::new(pairs.iter().flat_map(|(k, v)| [k, v]))
            }
            _ => return false,
        };
        match left {
            0 => true,
            _ => children.into_iter().any(|c| deeper(c, left - 1, seen)),
        }
    }
    match deeper(&v, MAX_VALUE_NESTING, &mut std::collections::HashSet::new()) {
        true => Err(format!("lists and dicts nested more than {MAX_VALUE_NESTING} deep")),
        false => Ok(v),
    }
}

/// `target.name`: a namespace's member, a method, or a YAML dict's key (`link.origin`).
fn attribute(target: Value, name: &str) -> Result<Value, String> {
    match &target {
        Value::Namespace(ns) => builtin(ns, name).ok_or_else(|| format!("{ns}.{name} is not supported")),
        Value::Dict(pairs) if !matches!(name, "get" | "keys" | "values" | "items") => lookup(pairs, &Value::str(name))
            .cloned()
            .ok_or_else(|| format!("The yaml dictionary has no key '{name}'")),
        Value::Str(_) | Value::Dict(_) => match METHODS.iter().find(|m| **m == name) {
            Some(m) => Ok(Value::Function(Function {
                name: m,
                this: Some(Box::new(target.clone())),
            })),
            None => Err(format!(
                "'{}' object has no attribute '{name}' faze4 supports",
                target.type_name()
            )),
        },
        other => Err(format!("'{}' object has no attribute '{name}'", other.type_name())),
    }
}

/// `target[index]`.
fn subscript(target: &Value, index: &Value) -> Result<Value, String> {
    match target {
        Value::Dict(pairs) => lookup(pairs, index)
            .cloned()
            .ok_or_else(|| format!("KeyError: {}", index.repr())),
        Value::List(items) => {
            let i = position(index, items.len())?;
            Ok(items[i].clone())
        }
        Value::Str(s) => {
            let chars: Vec<char> = s.chars().collect();
            let i = position(index, chars.len())?;
            Ok(Value::str(chars[i].to_string()))
        }
        other => Err(format!("'{}' object is not subscriptable", other.type_name())),
    }
}

/// A Python index (negative from the end) into a sequence of `len`.
fn position(index: &Value, len: usize) -> Result<usize, String> {
    let i = index
        .int()
        .ok_or_else(|| format!("indices must be integers, not {}", index.type_name()))?;
    let i = if i < 0 { i + len as i64 } else { i };
    match (0..len as i64).contains(&i) {
        true => Ok(i as usize),
        false => Err("IndexError: index out of range".into()),
    }
}

/// `target[a:b:c]`.
fn slice(target: &Value, [start, stop, step]: [Option<i64>; 3]) -> Result<Value, String> {
    let items: Vec<Value> = match target {
        Value::List(items) => items.to_vec(),
        Value::Str(s) => s.chars().map(|c| Value::str(c.to_string())).collect(),
        other => return Err(format!("'{}' object is not subscriptable", other.type_name())),
    };
    let n = items.len() as i64;
    let step = step.unwrap_or(1);
    if step == 0 {
        return Err("slice step cannot be zero".into());
    }
    let clamp = |i: i64, low: i64, high: i64| {
        let i = if i < 0 { i + n } else { i };
        i.clamp(low, high)
    };
    let picked: Vec<Value> = if step > 0 {
        let (a, b) = (clamp(start.unwrap_or(0), 0, n), clamp(stop.unwrap_or(n), 0, n));
        (a..b.max(a))
            .step_by(step as usize)
            .map(|i| items[i as usize].clone())
            .collect()
    } else {
        let a = start.map_or(n - 1, |s| clamp(s, -1, n - 1));
        let b = stop.map_or(-1, |s| clamp(s, -1, n - 1));
        let mut out = Vec::new();
        let mut i = a;
        while i > b {
            out.push(items[i as usize].clone());
            i += step;
        }
        out
    };
    Ok(match target {
        Value::Str(_) => Value::str(picked.iter().map(Value::to_text).collect::<String>()),
        _ => list(picked),
    })
}

/// `a op b` with Python's rules (int and float mixed, `str` and `list` joined and repeated).
fn binary(op: Op, a: &Value, b: &Value) -> Result<Value, String> {
    let unsupported = || {
        let symbol = match op {
            Op::Add => "+",
            Op::Sub => "-",
            Op::Mul => "*",
            Op::Div => "/",
            Op::FloorDiv => "//",
            Op::Mod => "%",
            Op::Pow => "**",
        };
        format!(
            "unsupported operand type(s) for {symbol}: '{}' and '{}'",
            a.type_name(),
            b.type_name()
        )
    };
    match (op, a, b) {
        (Op::Add, Value::Str(x), Value::Str(y)) => return Ok(Value::str(format!("{x}{y}"))),
        (Op::Add, Value::List(x), Value::List(y)) => return Ok(list(x.iter().chain(y.iter()).cloned().collect())),
        (Op::Mul, Value::Str(_) | Value::List(_), n) | (Op::Mul, n, Value::Str(_) | Value::List(_))
            if n.int().is_some() =>
        {
            let times = n.int().unwrap_or(0).max(0) as usize;
            let seq = if matches!(a, Value::Str(_) | Value::List(_)) {
                a
            } else {
                b
            };
            return match seq {
                Value::Str(s) => {
                    if s.len().saturating_mul(times) > super::MAX_TEXT_BYTES {
                        return Err(format!("a string of more than {} bytes", super::MAX_TEXT_BYTES));
                    }
                    Ok(Value::str(s.repeat(times)))
                }
                Value::List(l) => {
                    if l.len().saturating_mul(times) > super::MAX_TEXT_BYTES {
                        return Err(format!("a list of more than {} items", super::MAX_TEXT_BYTES));
                    }
                    Ok(list(l.iter().cloned().cycle().take(l.len() * times).collect()))
                }
                _ => unreachable!(),
            };
        }
        (Op::Mod, Value::Str(_), _) => return Err("string formatting with % is not supported".into()),
        _ => {}
    }
    if let (Some(x), Some(y)) = (a.int(), b.int()) {
        let overflow = || "integer overflow (faze4's xacro integers have 64 bits)".to_string();
        let zero = || "ZeroDivisionError: division by zero".to_string();
        return Ok(match op {
            Op::Add => Value::Int(x.checked_add(y).ok_or_else(overflow)?),
            Op::Sub => Value::Int(x.checked_sub(y).ok_or_else(overflow)?),
            Op::Mul => Value::Int(x.checked_mul(y).ok_or_else(overflow)?),
            Op::Div if y == 0 => return Err(zero()),
            Op::Div => Value::Float(x as f64 / y as f64),
            Op::FloorDiv | Op::Mod if y == 0 => return Err(zero()),
            Op::FloorDiv => {
                Value::Int(x.checked_div_euclid(y).ok_or_else(overflow)? - i64::from(y < 0 && x.rem_euclid(y) != 0))
            }
            Op::Mod => {
                let r = x.checked_rem(y).ok_or_else(overflow)?;
                Value::Int(if r != 0 && (r < 0) != (y < 0) { r + y } else { r })
            }
            Op::Pow if y >= 0 => Value::Int(
                x.checked_pow(u32::try_from(y).map_err(|_| overflow())?)
                    .ok_or_else(overflow)?,
            ),
            Op::Pow if x == 0 => return Err("ZeroDivisionError: 0 cannot be raised to a negative power".into()),
            Op::Pow => Value::Float((x as f64).powf(y as f64)),
        });
    }
    let (Some(x), Some(y)) = (a.number(), b.number()) else {
        return Err(unsupported());
    };
    let zero = || "ZeroDivisionError: float division by zero".to_string();
    Ok(Value::Float(match op {
        Op::Add => x + y,
        Op::Sub => x - y,
        Op::Mul => x * y,
        Op::Div if y == 0.0 => return Err(zero()),
        Op::Div => x / y,
        Op::FloorDiv if y == 0.0 => return Err(zero()),
        Op::FloorDiv => (x / y).floor(),
        Op::Mod if y == 0.0 => return Err(zero()),
        Op::Mod => {
            let r = x % y;
            if r != 0.0 && (r < 0.0) != (y < 0.0) { r + y } else { r }
        }
        Op::Pow if x == 0.0 && y < 0.0 => {
            return Err("ZeroDivisionError: 0.0 cannot be raised to a negative power".into());
        }
        Op::Pow if x < 0.0 && y.fract() != 0.0 => {
            return Err("a negative number to a fractional power is complex".into());
        }
        Op::Pow => x.powf(y),
    }))
}

/// `a op b` for a comparison.
fn compare(op: Cmp, a: &Value, b: &Value) -> Result<bool, String> {
    let order = || -> Result<std::cmp::Ordering, String> {
        match (a, b) {
            (Value::Str(x), Value::Str(y)) => Ok(x.cmp(y)),
            _ => match (a.number(), b.number()) {
                (Some(x), Some(y)) => x.partial_cmp(&y).ok_or_else(|| "a comparison with nan".to_string()),
                _ => Err(format!(
                    "'<' not supported between '{}' and '{}'",
                    a.type_name(),
                    b.type_name()
                )),
            },
        }
    };
    Ok(match op {
        Cmp::Eq => a.equals(b),
        Cmp::Ne => !a.equals(b),
        Cmp::Lt => order()?.is_lt(),
        Cmp::Le => order()?.is_le(),
        Cmp::Gt => order()?.is_gt(),
        Cmp::Ge => order()?.is_ge(),
        Cmp::In | Cmp::NotIn => {
            let found = match b {
                Value::Str(s) => match a {
                    Value::Str(needle) => s.contains(needle.as_ref()),
                    _ => return Err(format!("'in <string>' requires a string, not {}", a.type_name())),
                },
                Value::List(items) => items.iter().any(|i| i.equals(a)),
                Value::Dict(pairs) => lookup(pairs, a).is_some(),
                other => return Err(format!("argument of type '{}' is not iterable", other.type_name())),
            };
            found == (op == Cmp::In)
        }
        Cmp::Is | Cmp::IsNot => {
            let same = match (a, b) {
                (Value::None, Value::None) => true,
                (Value::Bool(x), Value::Bool(y)) => x == y,
                (Value::None | Value::Bool(_), _) | (_, Value::None | Value::Bool(_)) => false,
                _ => return Err("'is' is supported with None, True and False".into()),
            };
            same == (op == Cmp::Is)
        }
    })
}

/// The items of an iterable, as Python's `list(x)` gives them.
fn items(v: &Value) -> Result<Vec<Value>, String> {
    match v {
        Value::List(items) => Ok(items.to_vec()),
        Value::Dict(pairs) => Ok(pairs.iter().map(|(k, _)| k.clone()).collect()),
        Value::Str(s) => Ok(s.chars().map(|c| Value::str(c.to_string())).collect()),
        other => Err(format!("'{}' object is not iterable", other.type_name())),
    }
}

/// A function of Python's `math` ([`MATH_FUNCTIONS`]).
fn math_function(name: &str, args: &[Value]) -> Result<Value, String> {
    let count = |n: usize| match args.len() == n {
        true => Ok(()),
        false => Err(format!(
            "{name}() takes {n} argument{}, {} given",
            if n == 1 { "" } else { "s" },
            args.len()
        )),
    };
    let num = |i: usize| {
        args[i]
            .number()
            .ok_or_else(|| format!("{name}(): must be a real number, not {}", args[i].type_name()))
    };
    let float1 = |f: fn(f64) -> f64| -> Result<Value, String> {
        count(1)?;
        let y = f(num(0)?);
        match y.is_nan() && !num(0)?.is_nan() {
            true => Err(format!("ValueError: math domain error in {name}()")),
            false => Ok(Value::Float(y)),
        }
    };
    match name {
        "sin" => float1(f64::sin),
        "cos" => float1(f64::cos),
        "tan" => float1(f64::tan),
        "asin" => float1(f64::asin),
        "acos" => float1(f64::acos),
        "atan" => float1(f64::atan),
        "sinh" => float1(f64::sinh),
        "cosh" => float1(f64::cosh),
        "tanh" => float1(f64::tanh),
        "asinh" => float1(f64::asinh),
        "acosh" => float1(f64::acosh),
        "atanh" => float1(f64::atanh),
        "sqrt" => float1(f64::sqrt),
        "exp" => float1(f64::exp),
        "log10" => float1(f64::log10),
        "log2" => float1(f64::log2),
        "fabs" => float1(f64::abs),
        "degrees" => float1(f64::to_degrees),
        "radians" => float1(f64::to_radians),
        "log" => match args.len() {
            1 if num(0).is_ok_and(|x| x <= 0.0) => Err("ValueError: math domain error in log()".into()),
            1 => float1(f64::ln),
            _ => {
                count(2)?;
                Ok(Value::Float(num(0)?.ln() / num(1)?.ln()))
            }
        },
        "atan2" | "pow" | "hypot" | "fmod" | "copysign" => {
            count(2)?;
            let (x, y) = (num(0)?, num(1)?);
            Ok(Value::Float(match name {
                "atan2" => x.atan2(y),
                "pow" => x.powf(y),
                "hypot" => x.hypot(y),
                "fmod" => x % y,
                _ => x.copysign(y),
            }))
        }
        "floor" | "ceil" | "trunc" => {
            count(1)?;
            if let Value::Int(i) = args[0] {
                return Ok(Value::Int(i));
            }
            let x = num(0)?;
            let y = match name {
                "floor" => x.floor(),
                "ceil" => x.ceil(),
                _ => x.trunc(),
            };
            to_int(y).map(Value::Int)
        }
        "isnan" | "isinf" | "isfinite" => {
            count(1)?;
            let x = num(0)?;
            Ok(Value::Bool(match name {
                "isnan" => x.is_nan(),
                "isinf" => x.is_infinite(),
                _ => x.is_finite(),
            }))
        }
        other => Err(format!("{other}() is not supported")),
    }
}

/// A built-in function of numbers and sequences.
fn call_builtin(name: &str, args: &[Value]) -> Result<Value, String> {
    if MATH_FUNCTIONS.contains(&name) {
        return math_function(name, args);
    }
    let count = |n: usize| match args.len() == n {
        true => Ok(()),
        false => Err(format!(
            "{name}() takes {n} argument{}, {} given",
            if n == 1 { "" } else { "s" },
            args.len()
        )),
    };
    match name {
        "abs" => {
            count(1)?;
            Ok(match &args[0] {
                Value::Float(x) => Value::Float(x.abs()),
                v => Value::Int(
                    v.int()
                        .ok_or("abs() takes a number")?
                        .checked_abs()
                        .ok_or("integer overflow")?,
                ),
            })
        }
        "min" | "max" => {
            let pool = match args {
                [one] => items(one)?,
                many => many.to_vec(),
            };
            let mut best = pool.first().cloned().ok_or_else(|| format!("{name}() of nothing"))?;
            for v in &pool[1..] {
                let better = match name {
                    "min" => compare(Cmp::Lt, v, &best)?,
                    _ => compare(Cmp::Gt, v, &best)?,
                };
                if better {
                    best = v.clone();
                }
            }
            Ok(best)
        }
        "round" => match args {
            [x] => match x {
                Value::Float(f) => to_int(f.round_ties_even()).map(Value::Int),
                v => Ok(Value::Int(v.int().ok_or("round() takes a number")?)),
            },
            [x, digits] => {
                let n = digits.int().ok_or("round()'s digits must be an integer")?;
                match x {
                    Value::Float(f) if (0..=300).contains(&n) && f.is_finite() => {
                        Ok(Value::Float(format!("{f:.*}", n as usize).parse().unwrap_or(*f)))
                    }
                    Value::Float(f) => Ok(Value::Float(*f)),
                    v => Ok(Value::Int(v.int().ok_or("round() takes a number")?)),
                }
            }
            _ => Err("round() takes 1 or 2 arguments".into()),
        },
        "int" => {
            count(1)?;
            match &args[0] {
                Value::Float(f) => to_int(f.trunc()).map(Value::Int),
                Value::Str(s) => {
                    let t: String = s.trim().chars().filter(|c| *c != '_').collect();
                    t.parse::<i64>()
                        .map(Value::Int)
                        .map_err(|_| format!("ValueError: invalid literal for int(): '{s}'"))
                }
                v => Ok(Value::Int(
                    v.int().ok_or(format!("int() cannot take a {}", v.type_name()))?,
                )),
            }
        }
        "float" => {
            count(1)?;
            match &args[0] {
                Value::Str(s) => parse_float(s)
                    .map(Value::Float)
                    .ok_or_else(|| format!("ValueError: could not convert string to float: '{s}'")),
                v => Ok(Value::Float(
                    v.number().ok_or(format!("float() cannot take a {}", v.type_name()))?,
                )),
            }
        }
        "str" => {
            count(1)?;
            Ok(Value::str(args[0].text_within(super::MAX_TEXT_BYTES)?))
        }
        "repr" => {
            count(1)?;
            args[0].text_within(super::MAX_TEXT_BYTES)?;
            Ok(Value::str(args[0].repr()))
        }
        "bool" => {
            count(1)?;
            Ok(Value::Bool(args[0].truthy()))
        }
        "len" => {
            count(1)?;
            Ok(Value::Int(match &args[0] {
                Value::Str(s) => s.chars().count(),
                v => items(v)?.len(),
            } as i64))
        }
        "list" | "tuple" => match args {
            [] => Ok(list(Vec::new())),
            [v] => Ok(list(items(v)?)),
            _ => Err(format!("{name}() takes at most 1 argument")),
        },
        "sorted" => {
            count(1)?;
            let mut all = items(&args[0])?;
            let mut failed = None;
            all.sort_by(|a, b| {
                if compare(Cmp::Lt, a, b).unwrap_or_else(|e| {
                    failed = Some(e);
                    false
                }) {
                    std::cmp::Ordering::Less
                } else if compare(Cmp::Lt, b, a).unwrap_or(false) {
                    std::cmp::Ordering::Greater
                } else {
                    std::cmp::Ordering::Equal
                }
            });
            match failed {
                Some(e) => Err(e),
                None => Ok(list(all)),
            }
        }
        "sum" => {
            let mut total = Value::Int(0);
            for v in items(args.first().ok_or("sum() needs an iterable")?)? {
                total = binary(Op::Add, &total, &v)?;
            }
            Ok(total)
        }
        "any" | "all" => {
            count(1)?;
            let truths = items(&args[0])?.iter().map(Value::truthy).collect::<Vec<_>>();
            Ok(Value::Bool(match name {
                "any" => truths.iter().any(|t| *t),
                _ => truths.iter().all(|t| *t),
            }))
        }
        other => Err(format!("{other}() is not supported")),
    }
}

/// A float as an `int` (Python's floats convert exactly; infinity and nan cannot).
fn to_int(x: f64) -> Result<i64, String> {
    match x.is_finite() && x.abs() < 9.2e18 {
        true => Ok(x as i64),
        false => Err(format!("cannot convert float {} to integer", float_repr(x))),
    }
}

/// Python's `float(text)`: surrounding whitespace allowed, `inf`, `nan`, `1e3`.
pub fn parse_float(text: &str) -> Option<f64> {
    let t = text.trim();
    let lower = t.to_ascii_lowercase();
    let unsigned = lower.trim_start_matches(['+', '-']);
    if matches!(unsigned, "inf" | "infinity" | "nan") {
        return lower.parse().ok().or(match unsigned {
            "nan" => Some(f64::NAN),
            _ if lower.starts_with('-') => Some(f64::NEG_INFINITY),
            _ => Some(f64::INFINITY),
        });
    }
    if t.is_empty() || !t.chars().all(|c| c.is_ascii_digit() || "+-.eE_".contains(c)) {
        return None;
    }
    t.replace('_', "").parse().ok()
}

/// A method of `str` or `dict`.
fn method(name: &str, this: &Value, args: &[Value]) -> Result<Value, String> {
    match this {
        Value::Str(s) => str_method(name, s, args),
        Value::Dict(pairs) => dict_method(name, pairs, args),
        other => Err(format!("'{}' has no method {name}()", other.type_name())),
    }
}

/// A method of `str`.
fn str_method(name: &str, s: &str, args: &[Value]) -> Result<Value, String> {
    let text = |i: usize| match args.get(i) {
        Some(Value::Str(s)) => Ok(Some(s.to_string())),
        Some(Value::None) | None => Ok(None),
        Some(v) => Err(format!("{name}() takes a str, not {}", v.type_name())),
    };
    Ok(match name {
        "split" => match text(0)? {
            Some(sep) if sep.is_empty() => return Err("ValueError: empty separator".into()),
            Some(sep) => list(s.split(sep.as_str()).map(Value::str).collect()),
            None => list(s.split_whitespace().map(Value::str).collect()),
        },
        "strip" | "lstrip" | "rstrip" => {
            let chars = text(0)?;
            let pattern = |c: char| match &chars {
                Some(set) => set.contains(c),
                None => c.is_whitespace(),
            };
            Value::str(match name {
                "strip" => s.trim_matches(pattern),
                "lstrip" => s.trim_start_matches(pattern),
                _ => s.trim_end_matches(pattern),
            })
        }
        "lower" => Value::str(s.to_lowercase()),
        "upper" => Value::str(s.to_uppercase()),
        "replace" => match (text(0)?, text(1)?) {
            (Some(from), Some(to)) => {
                if from.is_empty() {
                    return Err("replace() of an empty string is not supported".into());
                }
                let grown = s.matches(from.as_str()).count().saturating_mul(to.len());
                if grown > super::MAX_TEXT_BYTES {
                    return Err(format!("a string of more than {} bytes", super::MAX_TEXT_BYTES));
                }
                Value::str(s.replace(from.as_str(), &to))
            }
            _ => return Err("replace() takes two strings".into()),
        },
        "startswith" => Value::Bool(s.starts_with(text(0)?.unwrap_or_default().as_str())),
        "endswith" => Value::Bool(s.ends_with(text(0)?.unwrap_or_default().as_str())),
        "find" => {
            let needle = text(0)?.unwrap_or_default();
            Value::Int(s.find(needle.as_str()).map_or(-1, |i| s[..i].chars().count() as i64))
        }
        "count" => Value::Int(s.matches(text(0)?.unwrap_or_default().as_str()).count() as i64),
        "join" => {
            let parts = items(args.first().ok_or("join() needs an iterable")?)?;
            let parts: Result<Vec<String>, String> = (parts.iter())
                .map(|p| match p {
                    Value::Str(t) => Ok(t.to_string()),
                    v => Err(format!("join() takes strings, not {}", v.type_name())),
                })
                .collect();
            Value::str(parts?.join(s))
        }
        other => return Err(format!("str.{other}() is not supported")),
    })
}

/// A method of `dict`.
fn dict_method(name: &str, pairs: &[(Value, Value)], args: &[Value]) -> Result<Value, String> {
    Ok(match name {
        "get" => {
            let key = args.first().ok_or("get() needs a key")?;
            lookup(pairs, key)
                .cloned()
                .unwrap_or_else(|| args.get(1).cloned().unwrap_or(Value::None))
        }
        "keys" => list(pairs.iter().map(|(k, _)| k.clone()).collect()),
        "values" => list(pairs.iter().map(|(_, v)| v.clone()).collect()),
        "items" => shallow(list(
            pairs.iter().map(|(k, v)| list(vec![k.clone(), v.clone()])).collect(),
        ))?,
        other => return Err(format!("dict.{other}() is not supported")),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Props(Vec<(&'static str, Value)>);

    impl Names for Props {
        fn lookup(&mut self, name: &str) -> Result<Option<Value>, String> {
            Ok(self.0.iter().find(|(n, _)| *n == name).map(|(_, v)| v.clone()))
        }
        fn load_yaml(&mut self, file: &str) -> Result<Value, String> {
            Err(format!("no file {file}"))
        }
        fn arg(&mut self, name: &str) -> Result<Value, String> {
            Ok(Value::str(format!("arg:{name}")))
        }
        fn abs_filename(&mut self, file: &str) -> String {
            format!("/d/{file}")
        }
        fn charge(&mut self, _: usize) -> Result<(), String> {
            Ok(())
        }
    }

    fn text(expr: &str) -> String {
        let yaml = Value::Dict(Rc::new(vec![
            (
                Value::str("origin"),
                Value::Dict(Rc::new(vec![(Value::str("xyz"), Value::str("0 0.5 1"))])),
            ),
            (Value::str("mass"), Value::Float(0.25)),
        ]));
        let mut props = Props(vec![
            ("x", Value::Int(3)),
            ("r", Value::Float(0.06)),
            ("name", Value::str("link1")),
            ("prefix", Value::str("")),
            ("link", yaml),
            ("direction", Value::str("-y")),
        ]);
        match eval(expr, &mut props) {
            Ok(v) => v.to_text(),
            Err(e) => format!("error: {e}"),
        }
    }

    #[test]
    fn expressions_evaluate_as_python_evaluates_them() {
        let cases = [
            ("pi/2", "1.5707963267948966"),
            ("-pi/4", "-0.7853981633974483"),
            ("1./12 * 2 * (3 * r**2 + 0.1**2)", "0.003466666666666667"),
            ("x / 2", "1.5"),
            ("x // 2", "1"),
            ("-7 // 2", "-4"),
            ("-7 % 3", "2"),
            ("7.5 % -2", "-0.5"),
            ("2 ** 10", "1024"),
            ("2 ** -1", "0.5"),
            ("radians(180)", "3.141592653589793"),
            ("math.degrees(pi)", "180.0"),
            ("round(2.5)", "2"),
            ("round(0.125, 2)", "0.12"),
            ("int('42') + float(' 1.5 ')", "43.5"),
            ("'' if prefix == '' else prefix + '_'", ""),
            ("name + '_' if name else ''", "link1_"),
            ("1 < x <= 3 and not False", "True"),
            ("'y' in direction", "True"),
            ("'inertia' in link", "False"),
            ("link.origin.xyz.split(' ')[1]", "0.5"),
            ("link['mass'] * 4", "1.0"),
            ("[1, 2, 3][-1]", "3"),
            ("'abcdef'[1:4]", "bcd"),
            ("'abc'[::-1]", "cba"),
            ("len(link)", "2"),
            ("max(1, 2.5, 2)", "2.5"),
            ("min([4, 3])", "3"),
            ("str(1.0) + 'x'", "1.0x"),
            ("python.abs(-2)", "2"),
            ("None is None", "True"),
            ("x if x > 5 else -x", "-3"),
            ("xacro.arg('t')", "arg:t"),
            ("True + 1", "2"),
            ("'a' 'b'", "ab"),
            ("python.sum([1, 2.5])", "3.5"),
            ("link.get('nope', 7)", "7"),
            ("sorted([3, 1, 2])", "[1, 2, 3]"),
            ("python.range(3)", "[0, 1, 2]"),
            ("1e-3 * 2", "0.002"),
            ("0x10 + 1_000", "1016"),
            ("(1, 2)", "[1, 2]"),
            ("{'a': 1}['a']", "1"),
            ("xacro.tokenize('a, b;c')", "['a', 'b', 'c']"),
        ];
        for (expr, expect) in cases {
            assert_eq!(text(expr), expect, "{expr}");
        }
    }

    #[test]
    fn what_python_refuses_or_faze4_does_not_support_is_an_error_naming_it() {
        let cases = [
            ("1/0", "division by zero"),
            ("undefined + 1", "name 'undefined' is not defined"),
            ("'a' + 1", "unsupported operand type(s) for +: 'str' and 'int'"),
            ("lambda x: x", "lambda is not supported"),
            ("[i for i in range(3)]", "comprehensions"),
            ("1 & 2", "the operator '&' is not supported"),
            ("f'{x}'", "string prefix"),
            ("link.nope", "no key 'nope'"),
            ("[1][5]", "IndexError"),
            ("2 ** 64", "integer overflow"),
            ("xacro.fatal('stop', 1)", "stop 1"),
            ("'%s' % 1", "formatting with %"),
            ("(1 + 2", "expected ')'"),
            ("'abc' * 100000000", "a string of more than"),
            ("sqrt(-1)", "math domain error"),
            ("max()", "of nothing"),
            ("abs(-1)", "name 'abs' is not defined"),
        ];
        for (expr, expect) in cases {
            let got = text(expr);
            assert!(got.starts_with("error:") && got.contains(expect), "{expr}: {got}");
        }
        let mut nested = Value::Int(1);
        for _ in 0..150 {
            nested = list(vec![nested]);
        }
        let mut props = Props(vec![("deep", nested)]);
        assert!(
            eval("[deep]", &mut props)
                .unwrap_err()
                .contains("nested more than 100 deep")
        );
        let deep = format!("{}1{}", "(".repeat(200), ")".repeat(200));
        assert!(text(&deep).contains("nests more than"));
        let unary = format!("{}1", "-".repeat(500));
        assert!(text(&unary).contains("nests more than"));
    }
}
