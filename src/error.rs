//! The library's one error type.

use std::path::PathBuf;

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

    /// The URDF is not well-formed XML or not a URDF document.
    #[error("{file}: malformed URDF: {message}")]
    UrdfSyntax {
        /// The URDF file.
        file: String,
        /// The parser's message.
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
        /// The option, e.g. `--dt`.
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

    /// The simulation went unstable and was stopped.
    #[error("{0}")]
    Diverged(String),

    /// Inverse kinematics could not reach a target.
    #[error("{0}")]
    Unreachable(String),
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

    /// An [`Error::InvalidArgument`] for `option`.
    pub fn argument(option: impl Into<String>, message: impl Into<String>) -> Self {
        Error::InvalidArgument {
            option: option.into(),
            message: message.into(),
        }
    }
}

/// `text` on one line (errors are one line on stderr): every run of whitespace, line breaks
/// included, becomes one space. For messages quoting the input (names, parser reports).
pub(crate) fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// `Result` with faze4's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
