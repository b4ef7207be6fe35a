//! Which pairs of collision objects are checked.

use super::GeometryObject;
use crate::model::{FrameId, Model};

/// Which pairs of collision objects on different bodies are checked. Objects on one body
/// (links merged by fixed joints, or all welded to the world) never move relative to each
/// other and are never checked.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PairFilter {
    /// Drake's MultibodyPlant default: every pair on different bodies except the two links a
    /// moving joint connects (its parent and child link). Adjacency is by link, as Drake has
    /// it: a link welded to the parent link is still checked against the child.
    #[default]
    NonAdjacent,
    /// Every pair on different bodies, adjacent ones included.
    All,
}

crate::choice::choice_words!(PairFilter { All => "all" });

/// The pairs `(a, b)`, `a < b`, of `collisions` (indices) that `filter` checks on `model`;
/// `joined` lists the `[parent, child]` link frames of the moving joints
/// ([`super::GeometryModel::joined`]).
pub fn checked_pairs(
    model: &Model,
    collisions: &[GeometryObject],
    joined: &[[FrameId; 2]],
    filter: PairFilter,
) -> Vec<(usize, usize)> {
    let body = |k: usize| model.frame(collisions[k].frame).body;
    let mut pairs = Vec::new();
    for a in 0..collisions.len() {
        for b in a + 1..collisions.len() {
            if body(a) == body(b) {
                continue;
            }
            let (fa, fb) = (collisions[a].frame, collisions[b].frame);
            let adjacent = joined.contains(&[fa, fb]) || joined.contains(&[fb, fa]);
            if filter == PairFilter::All || !adjacent {
                pairs.push((a, b));
            }
        }
    }
    pairs
}
