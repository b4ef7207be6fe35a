//! Which pairs of collision objects are checked.

use super::GeometryObject;
use crate::model::Model;

/// Which pairs of collision objects on different bodies are checked. Objects on one body
/// (links merged by fixed joints, or all welded to the world) never move relative to each
/// other and are never checked.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PairFilter {
    /// Drake's MultibodyPlant default: every pair on different bodies except bodies joined
    /// by a joint (parent and child; the world counts as the parent of the first bodies).
    #[default]
    NonAdjacent,
    /// Every pair on different bodies, adjacent ones included.
    All,
}

/// The pairs `(a, b)`, `a < b`, of `collisions` (indices) that `filter` checks on `model`.
pub fn checked_pairs(model: &Model, collisions: &[GeometryObject], filter: PairFilter) -> Vec<(usize, usize)> {
    let body = |k: usize| model.frames[collisions[k].frame].body;
    // the body carrying body b (None: the world); the world has no parent
    let parent = |b: Option<usize>| b.map(|b| model.parent[b]);
    let mut pairs = Vec::new();
    for a in 0..collisions.len() {
        for b in a + 1..collisions.len() {
            let (ba, bb) = (body(a), body(b));
            if ba == bb {
                continue;
            }
            let adjacent = parent(ba) == Some(bb) || parent(bb) == Some(ba);
            if filter == PairFilter::All || !adjacent {
                pairs.push((a, b));
            }
        }
    }
    pairs
}
