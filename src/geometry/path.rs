//! A path's self-clearance, computed once and shared by the runs that follow it: a sweep's
//! rows, a `--find`'s steps and retime's checks command the same poses and differ from them
//! only by their tracking error.
//!
//! [`PathClearance`] holds, for a sequence of poses of the arm (the commanded poses at a run's
//! trail samples, or any sampling of a geometric path), each object's world pose and, per
//! checked pair and sample, a proven lower bound `L` of the pair's distance and the two parts
//! (triangles, or a primitive whole) of an actual distance. A run at a pose near sample `j`
//! ([`super::Clearance::following`]) then has, for each pair,
//!
//! * the lower bound `L_j − moved`, with `moved` the relative motion of the pair's two bodies
//!   between the path's pose and the run's ([`super::motion_bound::relative_motion`]: how far any point of one
//!   body's bounding sphere can have moved relative to the other; distances are 1-Lipschitz
//!   in such a displacement), and
//! * the upper bound `u`, the distance of the path's two parts at the run's own pose (an
//!   actual distance, one triangle pair),
//!
//! and needs no search of that sample when the lower bound already proves it cannot beat the
//! run's minimum by more than the tolerance (the same test as its own bounds; see
//! [`super::Clearance`]). A run that strays far from the path loses the bound and folds the
//! sample as without a path: the result keeps the tolerance's guarantee and the exact
//! intersections either way (a sample is passed over only on a positive lower bound).
//!
//! How `L` is found: as a run's clearance folds its samples (bounds carried between samples,
//! bounding spheres, the hulls' gap along their last axis, the hulls' distance and their
//! certificate, and searches of the samples left waiting, each raising the others' bounds by
//! its distance less the motion between them): a sample is left as soon as its lower bound
//! reaches the pair's smallest distance so far less `τ/2` (the margin, half the runs'
//! tolerance `τ`), and the waiting samples below that are searched to within `τ/4` while a
//! later waiting sample below it is within `τ/4` of relative motion (near enough for the
//! search's bound less the motion to leave it), else to within the margin `τ/2` (exactly at
//! tolerance 0). A search to within `s` bounds its sample by its result less `s`, or, finding
//! nothing closer than the smallest so far less `s`, by that; so with `s ≤ τ/2` at every
//! sample `L ≥ D − τ/2`, with `D` the smallest actual distance found along the path, as for a
//! sample left unsearched. A run with minimum `R` settles a sample when `L − moved ≥ R − τ`;
//! as `R ≤ D + moved*` (the path's parts at the path's minimum, at the run's pose there), a
//! run whose pair moves relative to the path by `moved` at the sample and `moved*` at the
//! path's minimum settles every sample when `moved + moved* ≤ τ/2` (the Faze4 circle's runs:
//! about 0.1 to 0.3 mm each at 1 mm).
//! Beyond, it searches those samples itself; at tolerance 0, those near its minimum.
//!
//! Memory: 8 bytes a sample for its time, 56 per object for its pose and 16 per pair for its
//! bound and parts; a path keeps at most [`MAX_PATH_BYTES`] of them (on the Faze4, 7 objects
//! and 15 pairs: 640 bytes a sample, 26,214 samples, 524 s at the default 0.02 s), and a run's
//! samples beyond its end are folded as without a path. While it is computed, each pair's
//! waiting samples are resolved in batches, as a run's are.

use std::sync::{Arc, Mutex, OnceLock};

use parry3d_f64::math::{Pose as PPose, Vector as PVector};

use super::collision_set::CollisionSet;
use super::motion_bound::{BATCH, SEARCH_SHARE, relative_motion};
use crate::spatial::Pose;

/// The share of the runs' tolerance within which a sample's bound must come of the path's
/// smallest distance so far for the sample to be left at it (unsearched).
const MARGIN_SHARE: f64 = 0.5;

/// Most memory (bytes) a [`PathClearance`] keeps once computed: the samples beyond are left
/// out.
pub const MAX_PATH_BYTES: usize = 16 << 20;

/// One pair at one sample of the path.
#[derive(Clone, Copy, Debug)]
pub(super) struct Bound {
    /// A lower bound of the pair's distance at the path's pose (m).
    pub lower: f64,
    /// The two parts of an actual distance there (a mesh's triangles; 0 for a primitive).
    pub parts: (u32, u32),
}

/// What a run's fold needs of the path at one sample for one pair.
#[derive(Clone, Copy, Debug)]
pub(super) struct PathSample {
    /// The pair's relative pose `a_T_b` on the path.
    pub pose_ab: PPose,
    /// Its bound there.
    pub bound: Bound,
}

/// A path's self-clearance, computed once for the runs that follow it (see the module doc):
/// per sample, each object's world pose; per checked pair and sample, a proven lower bound of
/// its distance and the parts of an actual distance. Built by [`PathBuilder::build`], which
/// returns at once and computes the pairs' bounds on threads of its own: a pair's bounds are
/// waited for when first needed, so a sweep's runs start their dynamics meanwhile.
pub struct PathClearance {
    set: Arc<CollisionSet>,
    /// The tolerance (m) of the runs it serves: its bounds are at most half of it below the
    /// path's smallest distance.
    tolerance: f64,
    /// Each sample's time (s).
    times: Vec<f64>,
    /// Each sample's objects' world poses, sample after sample.
    poses: Vec<PPose>,
    /// Each pair's bound at each sample, once computed.
    bounds: Vec<OnceLock<Vec<Bound>>>,
}

/// Gathers a path's samples for [`PathClearance`].
pub struct PathBuilder {
    set: Arc<CollisionSet>,
    tolerance: f64,
    times: Vec<f64>,
    poses: Vec<PPose>,
    /// Most samples kept ([`MAX_PATH_BYTES`]).
    capacity: usize,
}

impl PathClearance {
    /// A path of the objects of `set` for runs measured to within `tolerance` (m, ≥ 0): give it
    /// its samples with [`PathBuilder::add`], then [`PathBuilder::build`].
    pub fn builder(set: Arc<CollisionSet>, tolerance: f64) -> PathBuilder {
        let bytes = 8 + 56 * set.objects().count() + 16 * set.object_pairs().len();
        PathBuilder {
            capacity: MAX_PATH_BYTES / bytes,
            set,
            tolerance,
            times: Vec::new(),
            poses: Vec::new(),
        }
    }

    /// The collision set it was computed with.
    pub fn set(&self) -> &Arc<CollisionSet> {
        &self.set
    }

    /// The tolerance (m) of the runs it was computed for.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// Its samples' times (s).
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// How many samples it holds.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether it holds no sample.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// The memory it holds once computed (bytes), at most [`MAX_PATH_BYTES`].
    pub fn bytes(&self) -> usize {
        8 * self.times.len() + 56 * self.poses.len() + 16 * self.bounds.len() * self.times.len()
    }

    /// Waits until every pair's bounds are computed.
    pub fn wait(&self) {
        self.bounds.iter().for_each(|b| {
            b.wait();
        });
    }

    /// The sample at time `t` (s): `guess` when it is at `t` (the next sample of a run that
    /// follows the path sample by sample), else the one at exactly `t`, if any.
    pub(super) fn sample_at(&self, t: f64, guess: usize) -> Option<usize> {
        match self.times.get(guess) {
            Some(&at) if at == t => Some(guess),
            _ => self.times.binary_search_by(|x| x.total_cmp(&t)).ok(),
        }
    }

    /// Pair `k` at sample `j` (`None` past the end), once the pair's bounds are computed
    /// (waits for them).
    pub(super) fn sample(&self, k: usize, j: usize) -> Option<PathSample> {
        if j >= self.times.len() {
            return None;
        }
        let (a, b) = self.set.object_pairs()[k];
        let objects = self.set.objects().count();
        let poses = &self.poses[j * objects..(j + 1) * objects];
        Some(PathSample {
            pose_ab: poses[a].inv_mul(&poses[b]),
            bound: self.bounds[k].wait()[j],
        })
    }
}

impl std::fmt::Debug for PathClearance {
    /// Its samples, the tolerance it serves and its memory.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PathClearance")
            .field("samples", &self.len())
            .field("tolerance", &self.tolerance)
            .field("bytes", &self.bytes())
            .finish()
    }
}

impl PathBuilder {
    /// Adds the sample at time `t` (s), the model's frames at `frame_pose` (e.g.
    /// `algo::Data::frame_pose` after `forward_kinematics` at the commanded q); `false` (and
    /// nothing kept) once the path holds [`MAX_PATH_BYTES`].
    pub fn add(&mut self, frame_pose: &[Pose], t: f64) -> bool {
        if self.times.len() >= self.capacity {
            return false;
        }
        let objects = self.set.objects().count();
        let start = self.poses.len();
        self.poses.resize(start + objects, PPose::IDENTITY);
        self.set.place(frame_pose, &mut self.poses[start..]);
        self.times.push(t);
        true
    }

    /// The path, its pairs' bounds computed on as many threads of its own as there are cores
    /// (none of them rayon's: a run waiting for a pair on rayon's pool must not hold up the
    /// thread that computes it), the pairs of the biggest meshes first. Returns at once.
    pub fn build(self) -> Arc<PathClearance> {
        let PathBuilder {
            set,
            tolerance,
            times,
            poses,
            ..
        } = self;
        let pairs = set.object_pairs().len();
        let path = Arc::new(PathClearance {
            bounds: (0..pairs).map(|_| OnceLock::new()).collect(),
            set,
            tolerance,
            times,
            poses,
        });
        // the costliest searches are of the pairs of the most triangles
        let mut order: Vec<usize> = (0..pairs).collect();
        order.sort_by_key(|&k| std::cmp::Reverse(path.set.pair_triangles(k)));
        let queue = Arc::new(Mutex::new(order));
        let threads = std::thread::available_parallelism().map_or(1, usize::from).min(pairs);
        for _ in 0..threads {
            let (path, queue) = (path.clone(), queue.clone());
            std::thread::spawn(move || {
                while let Some(k) = queue.lock().ok().and_then(|mut q| (!q.is_empty()).then(|| q.remove(0))) {
                    let objects = path.set.objects().count();
                    let bounds = pair_bounds(&path.set, k, &path.poses, objects, path.times.len(), path.tolerance);
                    let _ = path.bounds[k].set(bounds);
                }
            });
        }
        path
    }
}

/// A sample of pair `k` left for the searches, while its path is computed.
#[derive(Clone, Copy)]
struct Waiting {
    /// The sample's index.
    j: usize,
    pose_ab: PPose,
    /// A lower bound of its distance (m).
    lower: f64,
    /// An actual distance there (m), an upper bound.
    upper: f64,
    /// Whether its lower bound is the hulls' distance, apart (else 0 stands for it: the
    /// hulls overlap).
    hulls_apart: bool,
}

/// Pair `k`'s bound at each of the `samples` samples whose objects' poses are `poses`
/// (`objects` a sample), for runs at `tolerance` (see the module doc).
fn pair_bounds(
    set: &CollisionSet,
    k: usize,
    poses: &[PPose],
    objects: usize,
    samples: usize,
    tolerance: f64,
) -> Vec<Bound> {
    let (a, b) = set.object_pairs()[k];
    let (oa, ob) = (set.object(a), set.object(b));
    let spheres = (oa.sphere, ob.sphere);
    let mesh = oa.exact_mesh || ob.exact_mesh;
    let (share, margin) = (tolerance * SEARCH_SHARE, tolerance * MARGIN_SHARE);
    let mut bounds = vec![
        Bound {
            lower: f64::NEG_INFINITY,
            parts: (0, 0),
        };
        samples
    ];
    let (mut closest, mut support, mut axis) = ((0, 0), (0, 0), PVector::ZERO);
    let mut reference = (f64::NEG_INFINITY, PPose::IDENTITY);
    // the smallest actual distance found so far (m)
    let mut least = f64::INFINITY;
    let mut waiting: Vec<Waiting> = Vec::new();
    for j in 0..samples {
        let (pa, pb) = (&poses[j * objects + a], &poses[j * objects + b]);
        let pose_ab = pa.inv_mul(pb);
        // a sample whose bound is within the margin of the smallest so far is left at that
        let tight = |lower: f64, least: f64| lower >= least - margin;
        let mut lower = reference.0 - relative_motion(&reference.1, &pose_ab, spheres);
        let gap = (*pa * oa.sphere.0 - *pb * ob.sphere.0).length() - oa.sphere.1 - ob.sphere.1;
        if gap > lower {
            (lower, reference) = (gap, (gap, pose_ab));
        }
        if !tight(lower, least) && axis != PVector::ZERO {
            let gap = set.separation_along(a, b, &pose_ab, axis, &mut support);
            if gap > lower {
                (lower, reference) = (gap, (gap, pose_ab));
            }
        }
        bounds[j] = Bound { lower, parts: closest };
        if tight(lower, least) {
            continue;
        }
        let convex = set.convex_distance(a, b, (pa, pb), Some(&mut support), Some(&mut axis));
        if !mesh {
            // two primitives: the distance itself
            least = least.min(convex.distance);
            reference = (convex.distance, pose_ab);
            bounds[j].lower = convex.distance;
            continue;
        }
        let hull = convex.distance;
        if hull > lower {
            (lower, reference) = (hull, (hull, pose_ab));
            bounds[j].lower = lower;
        }
        if tight(lower, least) {
            continue;
        }
        if hull > 0.0 {
            match set.proven_by_hulls(a, b, (pa, pb), hull, (&mut closest, support), share) {
                Ok(distance) => {
                    least = least.min(distance);
                    bounds[j].parts = closest;
                }
                Err(upper) => {
                    least = least.min(upper);
                    waiting.push(Waiting {
                        j,
                        pose_ab,
                        lower,
                        upper,
                        hulls_apart: true,
                    });
                }
            }
        } else {
            let upper = set.part_distance(a, b, (pa, pb), closest);
            least = least.min(upper);
            waiting.push(Waiting {
                j,
                pose_ab,
                lower,
                upper,
                hulls_apart: false,
            });
        }
        if waiting.len() >= BATCH {
            least = search_waiting(set, k, &mut waiting, &mut bounds, &mut closest, least, (share, margin));
        }
    }
    search_waiting(set, k, &mut waiting, &mut bounds, &mut closest, least, (share, margin));
    bounds
}

/// Pair `k`'s `waiting` samples searched, the smallest upper bound first, each only while its
/// lower bound is below `least` (the smallest actual distance so far) less `margin`, to
/// within `share` or `margin` ([`search_share`]; m, 0: exactly) and bounded by `least`; each search raises the other
/// samples' bounds by its own less the motion between them. Their bounds go into `bounds`;
/// returns the smallest actual distance found.
fn search_waiting(
    set: &CollisionSet,
    k: usize,
    waiting: &mut Vec<Waiting>,
    bounds: &mut [Bound],
    closest: &mut (u32, u32),
    mut least: f64,
    (share, margin): (f64, f64),
) -> f64 {
    let (a, b) = set.object_pairs()[k];
    let spheres = (set.object(a).sphere, set.object(b).sphere);
    waiting.sort_by(|x, y| x.upper.total_cmp(&y.upper).then(x.j.cmp(&y.j)));
    // the pair's relative motion from the sample searched to each one after it
    let mut moves: Vec<f64> = Vec::new();
    for i in 0..waiting.len() {
        let w = waiting[i];
        if w.lower >= least - margin {
            bounds[w.j].lower = bounds[w.j].lower.max(w.lower);
            continue;
        }
        moves.clear();
        moves.extend((waiting[i + 1..].iter()).map(|other| relative_motion(&w.pose_ab, &other.pose_ab, spheres)));
        let share = search_share((share, margin), &waiting[i + 1..], &moves, least - margin);
        let hull = if w.hulls_apart { w.lower } else { 0.0 };
        let pose = (&PPose::IDENTITY, &w.pose_ab);
        let lower = match set.pair_distance(k, pose, closest, least, Some(hull), share) {
            Some(d) => {
                least = least.min(d.distance);
                bounds[w.j].parts = *closest;
                d.distance - share
            }
            // nothing closer than the smallest so far less the share
            None => least - share,
        };
        let lower = lower.max(w.lower);
        bounds[w.j].lower = bounds[w.j].lower.max(lower);
        for (other, moved) in waiting[i + 1..].iter_mut().zip(&moves) {
            other.lower = other.lower.max(lower - moved);
        }
    }
    waiting.clear();
    least
}

/// The share (m) of the runs' tolerance a search of a waiting sample in [`search_waiting`] may
/// use: `share` (a quarter of the tolerance) while a later waiting sample (`others`, whose
/// relative motions from it are `moves`) still below `reach` (the smallest distance so far
/// less the `margin`) is near enough for the search's bound, less the motion, to reach it
/// (`share + moved ≤ margin`), else the whole `margin` (half the tolerance). Either keeps the
/// path's bound at every sample at least its smallest distance less the margin, as a sample
/// left unsearched has it (see the module doc); the looser search opens fewer nodes, and when
/// no other waiting sample can be settled by a tighter one, the tighter one settles none.
fn search_share((share, margin): (f64, f64), others: &[Waiting], moves: &[f64], reach: f64) -> f64 {
    let near = (others.iter().zip(moves)).any(|(other, &moved)| other.lower < reach && share + moved <= margin);
    if near { share } else { margin }
}
