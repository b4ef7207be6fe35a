//! The library's one error type.

use std::path::PathBuf;

use crate::id::JointId;

/// Everything that can go wrong in faze4. Every message names the file (or argument), the
/// element and what is wrong, so that one line on stderr is enough to fix it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },

    /// An output an option names could not be written.
    #[error("{option}: {}: {source}", path.display())]
    Output {
        /// The option, named as a field in backticks (`` `trail` ``, [`Error::InvalidArgument`]).
        option: String,
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },

    /// The URDF is not well-formed XML or not a URDF document.
    #[error("{file}: malformed URDF: {message}")]
    UrdfSyntax {
        /// The URDF file.
        file: String,
        /// The parser's message.
        message: String,
    },

    /// A xacro file could not be expanded: what is wrong, the construct named, and where.
    #[error("{file} line {line}: xacro: {message}")]
    Xacro {
        /// The xacro, included or YAML file.
        file: String,
        /// The line of the element at fault (1-based).
        line: usize,
        /// What is wrong.
        message: String,
    },

    /// The URDF is well-formed but describes something faze4 cannot model.
    #[error("{file}: {element}: {message}")]
    InvalidModel {
        /// The URDF file.
        file: String,
        /// The element at fault, e.g. `joint 'lakat'` or `link 'saka' <inertial>`.
        element: String,
        /// What is wrong with it.
        message: String,
    },

    /// A command-line argument or option value is not acceptable.
    #[error("{option}: {message}")]
    InvalidArgument {
        /// The run option, named as a field in backticks (`` `dt` ``); each
        /// front end shows it in its own words ([`in_words`]).
        option: String,
        /// What is wrong with it.
        message: String,
    },

    /// An input data file (e.g. a `.npy` trajectory) is unusable.
    #[error("{}: {message}", path.display())]
    InvalidData {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },

    /// The equations of motion cannot be solved at a state: the mass matrix (in a step, plus
    /// Δt·D) is not positive definite. A physical state never does this; a run that has gone
    /// unstable can.
    #[error(
        "the mass matrix is not positive definite at joint {joint} (pivot {pivot:e}): the state is not physical, or the run has gone unstable"
    )]
    Diverged {
        /// The joint whose Cholesky pivot failed: the first that cannot be solved.
        joint: JointId,
        /// That pivot (≤ 0 or NaN).
        pivot: f64,
    },

    /// The contact problem of a step (`--self-collisions`) did not converge: the run has gone
    /// unstable, or the contacts are too stiff for the step.
    #[error(
        "the contact problem did not converge in {iterations} Newton iterations (scaled residual {residual:e}): the run has gone unstable, or the contacts are too stiff for the step"
    )]
    ContactNotConverged {
        /// Newton iterations made.
        iterations: usize,
        /// The scaled gradient norm left.
        residual: f64,
    },

    /// A mesh file holds a NaN or infinite coordinate.
    #[error("{}: triangle {triangle} has a non-finite coordinate", path.display())]
    MeshNotFinite {
        /// The mesh file.
        path: PathBuf,
        /// Index of the first triangle with a non-finite coordinate (0-based, file order).
        triangle: usize,
    },

    /// A mesh file holds no triangle of non-zero extent.
    #[error("{}: the mesh has no triangles", path.display())]
    MeshEmpty {
        /// The mesh file.
        path: PathBuf,
    },

    /// A collision shape of zero (or negative) size: it could touch nothing.
    #[error("{file}: {element}: {message}")]
    DegenerateShape {
        /// The URDF file.
        file: String,
        /// The element, e.g. `link 'saka' <collision>`.
        element: String,
        /// Which size is not positive.
        message: String,
    },

    /// Inverse kinematics could not reach a target.
    #[error(
        "IK{}: target ({:.6}, {:.6}, {:.6}) m of frame '{frame}' is out of reach: closest distance reached {} m",
        sample.map_or(String::new(), |(k, n)| format!(" sample {k} of {n}")),
        target[0], target[1], target[2],
        distance(*closest_m)
    )]
    Unreachable {
        /// For a path: the sample (0-based) and the number of samples.
        sample: Option<(usize, usize)>,
        /// The target (world, m).
        target: [f64; 3],
        /// The frame placed on it (URDF link name).
        frame: String,
        /// The closest distance reached (m).
        closest_m: f64,
    },

    /// An inverse-kinematics task or its input does not fit the model.
    #[error("IK {field}: {message}")]
    InvalidIk {
        /// What is wrong: `frame`, `free joints`, `weights`, `tolerance`, `q_prev`, `target`.
        field: &'static str,
        /// What is wrong with it.
        message: String,
    },

    /// A path given to retime cannot be timed as given: too few points, a value that is not a
    /// number, a point (or the spline between points) beyond a joint's limits.
    #[error("retime: path{}: {message}", point.map_or(String::new(), |k| format!(" point {k}")))]
    BadPath {
        /// The point at fault (0-based, in the input's order), if one is.
        point: Option<usize>,
        /// What is wrong.
        message: String,
    },

    /// No timing of the path keeps the limits, however slow: at path position `s` the torque
    /// limits (less the margin) leave no admissible path speed.
    #[error("retime: nothing follows at s = {s:.4} of {length:.4} (near point {point}): {message}")]
    NothingFollows {
        /// Path position (rad or m of path length).
        s: f64,
        /// The path's length.
        length: f64,
        /// The input point nearest to s (0-based).
        point: usize,
        /// The joint whose limit is at fault, if one is alone.
        joint: Option<JointId>,
        /// What it needs and what it has (naming the joint, if one is at fault).
        message: String,
    },

    /// A stop (Ctrl-C in Python, [`crate::sim::StopFlag::raise`]) came while `what` was under
    /// way, which has nothing to finish: nothing is returned or written.
    #[error("stopped while {what}: nothing is written")]
    Stopped {
        /// What was under way ("retime timed the path").
        what: &'static str,
    },

    /// The path retime is given makes the arm's collision geometry intersect itself: no timing
    /// follows it, since a timing changes when the poses come, not the poses (checked before
    /// any timing, at `samples` positions of the path).
    #[error(
        "retime: the path collides: '{}' and '{}' intersect at s = {s:.4} of {length:.4} (near point {point}); no timing follows it (a timing changes when the poses come, not the poses; checked at {samples} positions of the path, each joint moving at most {step} rad or m between two): change the path, or leave the self-clearance out with `no_collisions`",
        links[0].escape_debug(), links[1].escape_debug()
    )]
    PathCollides {
        /// The first pair to intersect along the path (URDF link names).
        links: [String; 2],
        /// Where it first does (rad or m of path length).
        s: f64,
        /// The path's length.
        length: f64,
        /// The input point nearest to s (0-based).
        point: usize,
        /// How many positions of the path are checked.
        samples: usize,
        /// The most any joint moves between two of them (rad or m).
        step: f64,
    },

    /// Under `--self-collisions` with exact meshes, two meshes intersect: contact between two
    /// triangle meshes is not modelled (only between convex shapes).
    #[error(
        "`self_collisions`: the exact meshes of '{}' and '{}' intersect at t = {t:.4} s; contact is modelled between convex shapes only: use `collision_geometry` hull",
        links[0].escape_debug(), links[1].escape_debug()
    )]
    MeshContact {
        /// The two URDF link names.
        links: [String; 2],
        /// Simulated time (s).
        t: f64,
    },
}

/// A distance in m for messages: µm resolution, or three significant digits below 1 mm.
fn distance(d: f64) -> String {
    if d >= 1e-3 {
        format!("{d:.6}")
    } else {
        format!("{d:.3e}")
    }
}

impl Error {
    /// An [`Error::InvalidModel`] for `element` of `file`.
    pub fn model(file: &str, element: impl Into<String>, message: impl Into<String>) -> Self {
        Error::InvalidModel {
            file: file.to_string(),
            element: one_line(&element.into()),
            message: one_line(&message.into()),
        }
    }

    /// An [`Error::InvalidIk`] for `field`.
    pub fn ik(field: &'static str, message: impl Into<String>) -> Self {
        Error::InvalidIk {
            field,
            message: message.into(),
        }
    }

    /// An [`Error::InvalidArgument`] for `option`, named as the front end writes it
    /// (`--vary`, `sweep`); a run option is [`Error::option`].
    pub fn argument(option: impl Into<String>, message: impl Into<String>) -> Self {
        Error::InvalidArgument {
            option: option.into(),
            message: message.into(),
        }
    }

    /// An [`Error::InvalidArgument`] for the run option `field` (a field of
    /// [`crate::config::RunConfig`], `dt`, `payload_kg`): the message names it `` `dt` ``, which
    /// each front end shows in its own words ([`in_words`]: `--dt` on the command line, `dt` in
    /// Python). `message` names other options the same way.
    pub fn option(field: &str, message: impl Into<String>) -> Self {
        Error::InvalidArgument {
            option: format!("`{field}`"),
            message: message.into(),
        }
    }
}

/// How a front end names the run options a message refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Words {
    /// The command line's: `--payload-kg`.
    Flags,
    /// Python's keywords, the fields' own names: `payload_kg`.
    Keywords,
}

/// `text` (a message of the library) with every run option it names as `` `field` `` (a
/// lower-case snake_case name between backticks) written in `words`. Anything else between
/// backticks is left as it is.
pub fn in_words(text: &str, words: Words) -> String {
    let mut out = String::with_capacity(text.len() + 8);
    let mut rest = text;
    while let Some(open) = rest.find('`') {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        let field = after.find('`').map(|close| &after[..close]).filter(|name| {
            name.starts_with(|c: char| c.is_ascii_lowercase())
                && name
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        });
        match field {
            Some(name) => {
                match words {
                    Words::Flags => {
                        out.push_str("--");
                        out.push_str(&name.replace('_', "-"));
                    }
                    Words::Keywords => out.push_str(name),
                }
                rest = &after[name.len() + 1..];
            }
            None => {
                out.push('`');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// A parser's message about a file (serde's `unknown field \`colour\``) with its names quoted
/// as `'colour'`, on one line: a name the file spells is not a field of a `RunConfig`, which
/// the front ends would show as a flag or keyword ([`in_words`]).
pub(crate) fn file_words(message: &str) -> String {
    one_line(&message.replace('`', "'"))
}

/// `x` as its shortest decimal that reads back to the same `f64` (Ryū): positional from 1e-5
/// to 1e16, scientific outside (`1e-300`, not 300 digits), `1` rather than `1.0`.
pub fn shortest(x: f64) -> String {
    let text = ryu::Buffer::new().format(x).to_string();
    match text.strip_suffix(".0") {
        Some(whole) => whole.to_string(),
        None => text,
    }
}

/// A computed figure for a message: six decimals (`6.538822`), or, from 10⁹ up, as short as
/// it reads back exactly (`1.3e154`, not 155 digits).
pub fn six_digits(x: f64) -> String {
    match x.abs() < 1e9 {
        true => format!("{x:.6}"),
        false => shortest(x),
    }
}

/// A link's or joint's `name` in quotes, its control and bidirectional characters escaped
/// (`'a\\nb'`): a name read from a URDF never breaks the one line it is printed on, nor
/// reorders what a reader sees.
pub fn quoted(name: &str) -> String {
    format!("'{}'", escape_controls(&name.escape_debug().to_string()))
}

/// Whether `c` must not reach a terminal or a text file as it is: a control character (C0,
/// DEL, or C1 such as U+009B, the one-byte start of a terminal escape sequence), a line or
/// paragraph separator (U+2028, U+2029), or a bidirectional formatting character (U+061C,
/// U+200E, U+200F, U+202A–U+202E, U+2066–U+2069), which reorders the text a reader sees.
pub fn is_unsafe_char(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{2028}' | '\u{2029}' | '\u{061C}' | '\u{200E}' | '\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}'
        )
}

/// `text` with its unsafe characters ([`is_unsafe_char`]) escaped as Rust writes them (`\n`,
/// `\u{202e}`): a message, a line on the terminal or a label in a file quoting a name read
/// from a file stays on its one line and reads in its order. Escaping twice changes nothing.
pub fn escape_controls(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match is_unsafe_char(c) {
            true => out.extend(c.escape_default()),
            false => out.push(c),
        }
    }
    out
}

/// [`escape_controls`] for lines: `text` with every unsafe character escaped but its line
/// breaks, which end its lines.
pub fn escape_lines(text: &str) -> String {
    text.split_inclusive('\n')
        .map(|line| match line.strip_suffix('\n') {
            Some(line) => escape_controls(line) + "\n",
            None => escape_controls(line),
        })
        .collect()
}

/// `path` as a line shows it: its unsafe characters escaped ([`escape_controls`], a line break
/// as `\n`), so that a path the user gave (`--trail $'e\nverdict: follows\ny.csv'`) never
/// starts a line of its own.
pub fn shown_path(path: &std::path::Path) -> String {
    escape_controls(&path.display().to_string())
}

/// Writes `line` and a line break on stderr, its unsafe characters escaped ([`escape_controls`],
/// a line break inside it too): a message is one line. A failed write (stderr closed, or full:
/// `2>/dev/full`) is ignored, where `eprintln!` would panic: the exit status still says what
/// happened.
pub fn to_stderr(line: &str) {
    use std::io::Write;
    let text = escape_controls(line) + "\n";
    let _ = std::io::stderr().lock().write_all(text.as_bytes());
}

/// `text` on one line (errors are one line on stderr): every run of whitespace, line breaks
/// included, becomes one space. For messages quoting the input (names, parser reports).
pub(crate) fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// `Result` with faze4's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_shown_in_each_front_ends_words() {
        let e = Error::option(
            "payload_kg",
            "-1 must be ≥ 0 (or lower `dt`; see `not an option` and `Dt`)",
        );
        let text = e.to_string();
        assert_eq!(
            in_words(&text, Words::Flags),
            "--payload-kg: -1 must be ≥ 0 (or lower --dt; see `not an option` and `Dt`)"
        );
        assert_eq!(
            in_words(&text, Words::Keywords),
            "payload_kg: -1 must be ≥ 0 (or lower dt; see `not an option` and `Dt`)"
        );
        assert_eq!(in_words("a ` lone backtick", Words::Flags), "a ` lone backtick");
    }
}
