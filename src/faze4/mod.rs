//! Facts about the Faze4 arm itself (its motors), as opposed to any arm faze4 can simulate.
pub mod motors;
