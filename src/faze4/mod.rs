//! The Faze4 arm's own data, built into the library.

pub mod meshes;
