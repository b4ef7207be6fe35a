//! Commanded trajectories: what the joints are asked to do at each instant.

pub mod shape;
