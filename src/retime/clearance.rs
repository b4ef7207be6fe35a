//! The path's own self-clearance, before it is timed: slowing cannot fix a collision, so a
//! path whose collision geometry intersects itself anywhere is refused before any timing or
//! check (docs/retime.md, "A colliding path").

use super::grid::PathGrid;
use super::spline::PathSpline;
use crate::algo::{Data, forward_kinematics};
use crate::error::{Error, Result};
use crate::geometry::{Clearance, CollisionSet};
use crate::model::Model;
use crate::sim::StopFlag;

/// The most any joint moves between two samples of the path whose clearance is checked (rad,
/// or m for a prismatic joint): a point 1 m from a joint's axis moves at most 1 mm for it.
pub const CLEARANCE_STEP: f64 = 1e-3;

/// The path positions s at which the clearance is checked: every grid point, and between two,
/// as many evenly spaced samples as keep each joint's change from one to the next within
/// [`CLEARANCE_STEP`] (measured on the chord between the grid points; the grid's intervals
/// are short enough that the spline between them is nearly straight).
pub(super) fn samples(grid: &PathGrid) -> Vec<f64> {
    let dof = grid.dof;
    let mut s = vec![grid.s[0]];
    for i in 0..grid.points() - 1 {
        let chord = (0..dof)
            .map(|j| (grid.q[(i + 1) * dof + j] - grid.q[i * dof + j]).abs())
            .fold(0.0, f64::max);
        let pieces = (chord / CLEARANCE_STEP).ceil().max(1.0) as usize;
        let (a, b) = (grid.s[i], grid.s[i + 1]);
        s.extend((1..=pieces).map(|k| a + (b - a) * k as f64 / pieces as f64));
    }
    s
}

/// Samples between two looks at the stop flag (each costs about what a sample's forward
/// kinematics does, in Python the interpreter's signal check).
const STOP_POLL_SAMPLES: usize = 64;

/// Refuses `path` ([`Error::PathCollides`], naming the pair, the path position and the
/// nearest input point) where its collision geometry intersects itself at one of the
/// [`samples`]; intersections are decided exactly (the `tolerance` only loosens distances).
/// A stop asked for ends it ([`Error::Stopped`]).
pub(super) fn check_path(
    model: &Model,
    set: &CollisionSet,
    tolerance: f64,
    path: &PathSpline,
    grid: &PathGrid,
    stop: &StopFlag,
) -> Result<()> {
    let mut clearance = Clearance::with_tolerance(set, tolerance);
    let mut data = Data::new(model);
    let mut q = vec![0.0; path.dof()];
    let samples = samples(grid);
    for (k, &s) in samples.iter().enumerate() {
        if k % STOP_POLL_SAMPLES == 0 {
            super::not_stopped(stop)?;
        }
        path.position(s, &mut q);
        forward_kinematics(model, &mut data, &q);
        clearance.add(&data.frame_pose, s);
        if let Some(k) = clearance.intersecting().iter().position(|&i| i) {
            let [a, b] = set.pair_links().nth(k).expect("a pair per intersection");
            return Err(Error::PathCollides {
                links: [a.to_string(), b.to_string()],
                s,
                length: path.length(),
                point: path.nearest_point(s),
                samples: samples.len(),
                step: CLEARANCE_STEP,
            });
        }
    }
    Ok(())
}
