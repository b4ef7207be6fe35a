//! What the self-clearance's searches share: how far a pair's distance can have changed
//! between two of its relative poses ([`relative_motion`]), and the search budget (the share of
//! the tolerance a search may use, how many samples wait before a batch). A run's accumulator
//! (`clearance.rs`) and a path's clearance (`path.rs`) both bound a sample by a nearby one's
//! lower bound less this motion.

use parry3d_f64::math::{Pose as PPose, Vector as PVector};

/// The share of the tolerance a search of a waiting sample may use (the rest raises the other waiting samples' lower bounds)
pub(super) const SEARCH_SHARE: f64 = 0.25;

/// How many samples a pair may leave for [`super::Clearance::finish`] before they are searched at
/// once: about 0.1 MB a pair (a relative pose and three numbers a sample).
pub(super) const BATCH: usize = 1024;

/// An upper bound of how far a point of b's bounding sphere (`centre`, `radius`, in b's frame)
/// has moved relative to a between the relative poses `then` and `now` (`a_T_b`): a point
/// `c + u` (`|u| ≤ radius`) moves by `(now·c − then·c) + (R_now − R_then) u`, at most
/// `|now·c − then·c| + 2 sin(θ/2) · radius`, with `θ` the angle of the rotation between them
/// (`2 sin(θ/2)` is the spectral norm of `R_now − R_then`, and `sin(θ/2)` the length of the
/// vector part of the unit quaternion `q_then⁻¹ q_now`). Distances are 1-Lipschitz in such a
/// displacement, so a lower bound `L` at `then` gives `L − moved` at `now`.
fn moved(then: &PPose, now: &PPose, centre: PVector, radius: f64) -> f64 {
    let turn = then.rotation.inverse() * now.rotation;
    let half_sine = PVector::new(turn.x, turn.y, turn.z).length();
    (*now * centre - *then * centre).length() + 2.0 * half_sine * radius
}

/// How far the distance of a pair can have changed between its relative poses `then` and
/// `now` (`a_T_b`), given the bounding spheres (centre, radius; each in its own shape's frame)
/// of a and of b: the smaller of how far b moved relative to a ([`moved`]) and how far a moved
/// relative to b (the same bound on the inverse poses, `b_T_a`), since the distance is the
/// same seen from either. Its smaller shape gives the tighter bound when the pair turns.
pub(super) fn relative_motion(
    then: &PPose,
    now: &PPose,
    ((ca, ra), (cb, rb)): ((PVector, f64), (PVector, f64)),
) -> f64 {
    let b_moved = moved(then, now, cb, rb);
    let a_moved = moved(&then.inverse(), &now.inverse(), ca, ra);
    b_moved.min(a_moved)
}
