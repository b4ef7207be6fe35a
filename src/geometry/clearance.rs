//! A run's self-clearance, sample by sample: [`Clearance`] folds each trail sample's pose into
//! a [`ClearanceReport`] using the single-pose queries of a [`CollisionSet`], and carries bounds
//! from one sample to the next so that most pairs need no query at most samples.
//!
//! Pruning uses lower bounds of a pair's distance: the last lower bound found for the pair
//! less how far its shapes can have moved relative to each other since (see [`super::motion_bound::relative_motion`]), the
//! bounding spheres' gap `|c₁ − c₂| − r₁ − r₂`, the gap between the convex shapes' projections
//! on the axis that separated them at the pair's last GJK (see
//! [`CollisionSet::separation_along`]: two support points, and tight when the pair moves
//! little), and (for meshes) the hulls' signed distance, since a mesh lies inside its hull. A
//! pair whose bound is not below its smallest distance so far cannot lower it and needs no
//! exact query. A pair whose hulls are apart may be proven by them
//! ([`CollisionSet::proven_by_hulls`]); one whose hulls overlap is only tested for crossing
//! triangles at the sample ([`CollisionSet::touch`]: the same traversal, opening just the
//! boxes that touch, which stops at the first crossing pair), unless that test runs over a
//! budget (meshes a fraction of a millimetre apart all along a joint's parts, whose boxes touch
//! all the way down): such a pair is searched at each sample, bounded by its smallest distance
//! so far. The samples whose distance is left open wait for [`Clearance::finish`], which
//! searches them in order of their upper bound, each search raising the other samples' lower
//! bounds by its distance less the relative motion between the two samples.

use parry3d_f64::math::{Pose as PPose, Vector as PVector};
use rayon::prelude::*;

use super::collision_set::{CollisionSet, TOUCH_BUDGET};
use super::motion_bound::{BATCH, SEARCH_SHARE, relative_motion};
use super::path::{PathClearance, PathSample};
use super::report::{ClearanceReport, PairDistance, PairReport};
use super::search::ROUND_OFF;
use super::search::Touch;
use crate::spatial::Pose;

/// A run's self-clearance over its samples (the accumulator): [`Clearance::add`] each sample
/// (or [`Clearance::queue`] several, then [`Clearance::fold_queued`]), then
/// [`Clearance::finish`] for the report. Holds the set's pairs' bounds between samples and
/// the samples whose distance is left for `finish`.
///
/// Each pair is folded over the samples on its own: the pairs of queued samples are folded
/// in parallel (rayon), and the report is the same as sample by sample, bit for bit (each
/// pair's minimum depends on its own samples alone, and the closest pair overall is decided
/// by replaying the pairs' lowerings in the order sample by sample would have made them).
pub struct Clearance<'a> {
    set: &'a CollisionSet,
    /// How far (m) the reported minimum may be above the true one (0: exact).
    tolerance: f64,
    /// How many samples a pair may leave for [`Clearance::finish`] before they are searched
    /// at once (memory stays bounded over a run of any length).
    batch: usize,
    /// The samples queued for [`Clearance::fold_queued`]: each one's time (s), the world
    /// pose of each object's shape then, and the sample of the path it follows there.
    queued: Vec<(f64, Vec<PPose>, Option<usize>)>,
    /// Pose buffers of samples already folded in, for the next ones.
    spare: Vec<Vec<PPose>>,
    /// How many samples were folded in before the queued ones.
    folded: usize,
    /// What each pair carries from one sample to the next.
    memory: Vec<PairMemory>,
    /// Whether each pair intersects at the last sample.
    intersecting: Vec<bool>,
    report: ClearanceReport,
    /// The path the run follows ([`Clearance::following`]), and the sample of it the next
    /// sample is likely to be at.
    path: Option<(&'a PathClearance, usize)>,
}

/// How many queued samples [`Clearance::fold_queued`] folds with the pairs in parallel (below,
/// waking rayon's threads costs more than the work).
const PARALLEL_SAMPLES: usize = 8;

/// A lowering of a pair's minimum while queued samples are folded in: the sample's index
/// among them, whether it came from a batch of waiting samples searched at once (after the
/// sample's own fold), the distance and its time (s).
type Lowering = (usize, bool, f64, f64);

/// One pair's state between queries.
#[derive(Clone)]
struct PairMemory {
    /// The two triangles found closest at its last exact mesh query.
    closest: (u32, u32),
    /// The two hull vertices last found furthest along GJK's directions (hill climbing starts).
    support: (u32, u32),
    /// The unit direction from a to b along the convex shapes' closest points at their last
    /// GJK, in a's shape frame (zero: none, or they touched).
    axis: PVector,
    /// A lower bound of its distance and the relative pose `a_T_b` it holds at.
    reference: (f64, PPose),
    /// An actual distance of the pair at some sample so far (m): the run's smallest is no
    /// larger.
    upper: f64,
    /// Samples left for [`Clearance::finish`]: apart, but not proven by the hulls.
    pending: Vec<Pending>,
    /// Whether a crossing test of the pair ran out of [`TOUCH_BUDGET`]: its hulls overlapping,
    /// its distance is then searched at each sample rather than tested and left for
    /// [`Clearance::finish`].
    search_now: bool,
    /// Whether it intersects at the last sample folded in.
    intersecting: bool,
    /// The time (s) of the first sample at which it intersected.
    first_intersection: Option<f64>,
}

/// A pair's sample as [`PairMemory::fold`] judges it: its time `t` (s), the pair's smallest
/// distance so far `best`, the smallest distance the sample could lower (`least`: `best` or an
/// actual distance seen, whichever is smaller) and the tolerance (m).
#[derive(Clone, Copy)]
struct Bounds {
    t: f64,
    best: f64,
    least: f64,
    tolerance: f64,
}

impl Bounds {
    /// Whether a sample whose distance is at least `lower` is passed over: it cannot intersect
    /// and cannot be closer than the smallest so far by more than the tolerance.
    fn skip(self, lower: f64) -> bool {
        lower > 0.0 && lower >= self.least - self.tolerance
    }

    /// With a tolerance, each actual distance found (an upper bound of the sample's) is
    /// recorded at once: the report's minimum is then never above it.
    fn upper_bound(self, distance: f64) -> Option<PairDistance> {
        (self.tolerance > 0.0).then_some(PairDistance {
            distance,
            intersecting: false,
        })
    }
}

/// What [`PairMemory::mesh_pair`] made of a sample.
enum Folded {
    /// The sample's distance, which becomes the pair's carried lower bound.
    Distance(PairDistance),
    /// Decided without one, the result [`PairMemory::fold`] gives as it is: passed over
    /// (`None`), an upper bound recorded at once, or a search's result (which set the carried
    /// bound itself).
    Decided(Option<PairDistance>),
}

/// A sample whose exact distance is left for [`Clearance::finish`].
#[derive(Clone, Copy)]
struct Pending {
    /// Its time (s).
    t: f64,
    /// The pair's relative pose `a_T_b` then.
    pose_ab: PPose,
    /// The hulls' distance then (m), a lower bound of the pair's.
    lower: f64,
    /// An actual distance of two of its parts then (m), an upper bound of the pair's.
    upper: f64,
    /// Whether its hulls were apart. Its lower bound then serves
    /// [`CollisionSet::proven_by_hulls`] as the hulls' distance would (any lower bound proves
    /// an actual pair no further apart than it plus [`HULL_CERTIFICATE`]); a sample whose
    /// hulls overlapped is searched triangle by triangle.
    hulls_apart: bool,
}

/// The share of the `tolerance` (m, > 0) a search of a waiting sample in
/// [`PairMemory::finish`] may use. The search's result bounds its own sample within the share
/// `s` (which needs only `s ≤ tolerance`), and each later waiting sample (`others`, whose
/// relative motions from it are `moves`) by that bound less the motion, which passes one over
/// only when it reaches `reach` (the smallest distance so far less the tolerance), so only when
/// `s + moved ≤ tolerance`. The share is [`SEARCH_SHARE`] of the tolerance while a later
/// sample still below `reach` is near enough to be passed over so, else the whole tolerance: a
/// looser search opens fewer nodes on nearly concentric shells, and when the pair moves more
/// than the rest of the tolerance from this sample to every other one still to be settled, a
/// tighter search settles no other.
fn search_share(tolerance: f64, others: &[Pending], moves: &[f64], reach: f64) -> f64 {
    let share = tolerance * SEARCH_SHARE;
    let near = (others.iter().zip(moves)).any(|(other, &moved)| other.lower < reach && share + moved <= tolerance);
    if near { share } else { tolerance }
}

impl<'a> Clearance<'a> {
    /// An empty accumulator for a run measured with `set`, exactly.
    pub fn new(set: &'a CollisionSet) -> Clearance<'a> {
        Clearance::with_tolerance(set, 0.0)
    }

    /// An empty accumulator for a run measured with `set` to within `tolerance` (m, ≥ 0; 0 is
    /// exact): each pair's reported minimum is the distance of two actual parts at one of the
    /// samples, and the pair's smallest distance over the samples is at most `tolerance` below
    /// it. Intersections are decided exactly whatever the tolerance.
    pub fn with_tolerance(set: &'a CollisionSet, tolerance: f64) -> Clearance<'a> {
        let pairs = set.object_pairs().len();
        let mut report = set.new_report();
        report.tolerance_m = tolerance;
        Clearance {
            set,
            tolerance,
            batch: BATCH,
            queued: Vec::new(),
            spare: Vec::new(),
            folded: 0,
            memory: vec![
                PairMemory {
                    closest: (0, 0),
                    support: (0, 0),
                    axis: PVector::ZERO,
                    reference: (f64::NEG_INFINITY, PPose::IDENTITY),
                    upper: f64::INFINITY,
                    pending: Vec::new(),
                    search_now: false,
                    intersecting: false,
                    first_intersection: None,
                };
                pairs
            ],
            intersecting: vec![false; pairs],
            report,
            path: None,
        }
    }

    /// The same accumulator for a run that follows `path` (a [`PathClearance`] of the same
    /// set, e.g. the commanded poses at the run's samples): each pair's sample at a pose
    /// near one of the path's is bounded below by the path's bound less the pair's relative
    /// motion between the two poses, and above by the distance of the path's parts at the
    /// run's pose, and is searched only when those leave it looser than the tolerance (see
    /// [`PathClearance`]). The report keeps the tolerance's guarantee and the exact
    /// intersections; at tolerance 0 it is the exact minimum, as without the path (to
    /// round-off ties). A path of another set is not used.
    pub fn following(mut self, path: &'a PathClearance) -> Self {
        if std::ptr::eq(&**path.set(), self.set) {
            self.path = Some((path, 0));
        }
        self
    }

    /// At most `samples` (≥ 1) waiting samples per pair before they are searched during the
    /// run (default 1024: about 0.1 MB a pair); the report is the same whatever the batch, to
    /// within the tolerance (exactly at tolerance 0, ties aside).
    pub fn batch(mut self, samples: usize) -> Self {
        self.batch = samples.max(1);
        self
    }

    /// Whether each checked pair intersects at the last sample folded in, in
    /// [`CollisionSet::pair_links`] order.
    pub fn intersecting(&self) -> &[bool] {
        &self.intersecting
    }

    /// Per checked pair, the time (s) of the first sample folded in at which it intersects.
    pub fn first_intersections(&self) -> impl Iterator<Item = Option<f64>> + '_ {
        self.memory.iter().map(|m| m.first_intersection)
    }

    /// The report so far (complete after [`Clearance::finish`]; before, the samples left for
    /// it are not in it).
    pub fn report(&self) -> &ClearanceReport {
        &self.report
    }

    /// Folds the sample at time `t` (s), whose model frames are at `frame_pose` (e.g.
    /// `algo::Data::frame_pose` after `forward_kinematics`), in, and sets
    /// [`Clearance::intersecting`] to its intersecting pairs: each pair's distance is computed
    /// only when a lower bound (the pair's last bound less its relative motion since, bounding
    /// spheres, then hulls) says it could be below the pair's smallest so far or could be an
    /// intersection. A mesh pair whose hulls are apart but do not prove its distance, or whose
    /// hulls overlap but whose triangles do not cross, is not searched now: the sample waits for
    /// [`Clearance::finish`], which searches only those that can still hold the minimum.
    /// A pair whose waiting samples fill a batch has them searched at once, as `finish` would.
    pub fn add(&mut self, frame_pose: &[Pose], t: f64) {
        self.queue(frame_pose, t);
        self.fold_queued();
    }

    /// Queues the sample at time `t` (s), whose model frames are at `frame_pose`, for
    /// [`Clearance::fold_queued`] (the objects are placed now: `frame_pose` may change after).
    /// Following a path, the sample is compared with the path's sample at the same time, if
    /// it has one.
    pub fn queue(&mut self, frame_pose: &[Pose], t: f64) {
        let near = self.path.and_then(|(path, next)| path.sample_at(t, next));
        self.queue_near(frame_pose, t, near);
    }

    /// [`Clearance::queue`], the sample compared with the followed path's sample `near`
    /// (when it has one; e.g. the path's sample nearest in the path's parameter, for a run
    /// along the same geometric path with another timing). Any sample of the path gives
    /// valid bounds; the nearer, the tighter.
    pub fn queue_near(&mut self, frame_pose: &[Pose], t: f64, near: Option<usize>) {
        let mut poses = self.spare.pop().unwrap_or_default();
        poses.resize(self.set.objects().count(), PPose::IDENTITY);
        self.set.place(frame_pose, &mut poses);
        let near = self
            .path
            .zip(near)
            .and_then(|((path, _), j)| (j < path.len()).then_some(j));
        if let (Some((_, next)), Some(j)) = (self.path.as_mut(), near) {
            *next = j + 1;
        }
        self.queued.push((t, poses, near));
    }

    /// How many samples are queued.
    pub fn queued(&self) -> usize {
        self.queued.len()
    }

    /// Folds the queued samples in, in order, as [`Clearance::add`] would one by one (the
    /// same report, bit for bit), with the pairs in parallel when several samples are queued;
    /// [`Clearance::intersecting`] is then the last one's.
    pub fn fold_queued(&mut self) {
        let (set, tolerance, batch, samples) = (self.set, self.tolerance, self.batch, &self.queued);
        let path = self.path.map(|(path, _)| path);
        let fold = |(k, (memory, pair)): (usize, (&mut PairMemory, &mut PairReport))| {
            let mut lowerings: Vec<Lowering> = Vec::new();
            for (i, (t, poses, near)) in samples.iter().enumerate() {
                let near = path.zip(*near).and_then(|(path, j)| path.sample(k, j));
                memory.step(set, k, (poses, near), *t, pair, tolerance, batch, |from_batch, d, t| {
                    lowerings.push((i, from_batch, d, t))
                });
            }
            lowerings
        };
        let pairs = self.memory.iter_mut().zip(self.report.pairs.iter_mut()).enumerate();
        let lowerings: Vec<Vec<Lowering>> = match samples.len() >= PARALLEL_SAMPLES {
            true => (self
                .memory
                .par_iter_mut()
                .zip(self.report.pairs.par_iter_mut())
                .enumerate())
            .map(fold)
            .collect(),
            false => pairs.map(fold).collect(),
        };
        // the closest pair overall, as sample by sample: lowerings by sample, then pair, then
        // a batch's after the sample's own
        let mut all: Vec<(usize, usize, bool, f64, f64)> = (lowerings.into_iter().enumerate())
            .flat_map(|(k, l)| l.into_iter().map(move |(i, from_batch, d, t)| (i, k, from_batch, d, t)))
            .collect();
        all.sort_by_key(|&(i, k, from_batch, _, _)| (i, k, from_batch));
        for (_, k, _, d, t) in all {
            self.report.lowered(k, d, t);
        }
        for (now, memory) in self.intersecting.iter_mut().zip(&self.memory) {
            *now = memory.intersecting;
        }
        self.folded += self.queued.len();
        self.spare.extend(self.queued.drain(..).map(|(_, poses, _)| poses));
    }

    /// Completes the report after the last [`Clearance::add`]: each pair's waiting samples
    /// whose lower bound is below the pair's smallest distance so far plus `ROUND_OFF` (with
    /// a tolerance: less the tolerance) are searched, the smallest upper bound first (none of
    /// them intersects: their hulls were apart, or their triangles were tested apart). The
    /// pairs are searched in parallel.
    pub fn finish(&mut self) {
        self.fold_queued();
        let (set, smallest, tolerance) = (self.set, &self.report.pairs, self.tolerance);
        let found: Vec<Option<(PairDistance, f64)>> = (self.memory.par_iter_mut().enumerate())
            .map(|(k, memory)| memory.finish(set, k, smallest[k].min_m, tolerance))
            .collect();
        for (k, found) in found.into_iter().enumerate() {
            if let Some((d, t)) = found {
                self.report.record(k, d, t);
            }
        }
    }

    /// The report (complete after [`Clearance::finish`]).
    pub fn into_report(self) -> ClearanceReport {
        self.report
    }
}

impl PairMemory {
    /// Folds pair `k`'s sample at time `t` (s), its objects at world `poses` (near the
    /// followed path's sample, if any), into `pair`, as [`Clearance::add`] does: `lowered` is
    /// told each lowering of the pair's minimum (whether it came from the batch of waiting
    /// samples searched at once, the distance, its time).
    #[allow(clippy::too_many_arguments)]
    fn step(
        &mut self,
        set: &CollisionSet,
        k: usize,
        (poses, near): (&[PPose], Option<PathSample>),
        t: f64,
        pair: &mut PairReport,
        tolerance: f64,
        batch: usize,
        mut lowered: impl FnMut(bool, f64, f64),
    ) {
        let found = self.fold(set, k, (poses, near), t, pair.min_m, tolerance);
        self.intersecting = found.is_some_and(|d| d.intersecting);
        if self.intersecting && self.first_intersection.is_none() {
            self.first_intersection = Some(t);
        }
        if let Some(d) = found
            && pair.record(d, t)
        {
            lowered(false, d.distance, t);
        }
        if self.pending.len() >= batch
            && let Some((d, t)) = self.finish(set, k, pair.min_m, tolerance)
            && pair.record(d, t)
        {
            lowered(true, d.distance, t);
        }
    }

    /// Pair `k`'s waiting samples for [`Clearance::finish`]: the smallest distance among
    /// them and its time, if below `best` (the pair's smallest so far); with a `tolerance`, an
    /// actual distance at most that far above the smallest, if below `best`, and none when no
    /// sample is closer than `best − tolerance`.
    fn finish(&mut self, set: &CollisionSet, k: usize, mut best: f64, tolerance: f64) -> Option<(PairDistance, f64)> {
        let (a, b) = set.object_pairs()[k];
        let mut pending = std::mem::take(&mut self.pending);
        // the likeliest minimum first (the smallest actual distance seen); each search finds
        // its sample's distance d_j, which bounds every other waiting sample i from below by
        // d_j − moved(j, i) (the pair's relative motion between them)
        pending.sort_by(|x, y| x.upper.total_cmp(&y.upper).then(x.t.total_cmp(&y.t)));
        let spheres = (set.object(a).sphere, set.object(b).sphere);
        let mut found = None;
        // the pair's relative motion from the sample searched to each one after it
        let mut moves: Vec<f64> = Vec::new();
        for j in 0..pending.len() {
            let p = pending[j];
            if best <= 0.0 {
                // an intersection: no waiting sample (all apart) can be closer
                break;
            }
            let reach = if tolerance > 0.0 {
                best - tolerance
            } else {
                best + ROUND_OFF
            };
            if p.lower >= reach {
                continue;
            }
            moves.clear();
            moves.extend((pending[j + 1..].iter()).map(|other| relative_motion(&p.pose_ab, &other.pose_ab, spheres)));
            // distances depend on the relative pose alone; overlapping hulls (0 stands for
            // their distance) prove nothing
            let hull = if p.hulls_apart { p.lower } else { 0.0 };
            let pose = (&PPose::IDENTITY, &p.pose_ab);
            // a lower bound of the sample's distance, from its search
            let lower = if tolerance > 0.0 {
                // an actual distance within the share of the tolerance of the sample's, or
                // none closer than best − share
                let search = search_share(tolerance, &pending[j + 1..], &moves, reach);
                match set.pair_distance(k, pose, &mut self.closest, best, Some(hull), search) {
                    Some(d) => {
                        (best, found) = (d.distance, Some((d, p.t)));
                        d.distance - search
                    }
                    None => best - search,
                }
            } else {
                let d = (set.pair_distance(k, pose, &mut self.closest, f64::INFINITY, Some(hull), 0.0))
                    .expect("an unbounded search finds the distance");
                if d.distance < best {
                    (best, found) = (d.distance, Some((d, p.t)));
                }
                d.distance
            };
            for (other, moved) in pending[j + 1..].iter_mut().zip(&moves) {
                other.lower = other.lower.max(lower - moved);
            }
        }
        pending.clear();
        self.pending = pending;
        found
    }

    /// Pair `k` at `poses` (time `t`) for [`Clearance::add`]: its distance, unless a
    /// lower bound shows that it is positive (no intersection) and not below the pair's
    /// smallest so far (`best`, or an actual distance seen: no new minimum), or the sample is
    /// left for [`Clearance::finish`]. The cheap bounds first ([`PairMemory::bounded`]), then
    /// two convex shapes' distance, or a pair with a mesh's ([`PairMemory::mesh_pair`]).
    fn fold(
        &mut self,
        set: &CollisionSet,
        k: usize,
        (poses, near): (&[PPose], Option<PathSample>),
        t: f64,
        best: f64,
        tolerance: f64,
    ) -> Option<PairDistance> {
        let (a, b) = set.object_pairs()[k];
        let bounds = Bounds {
            t,
            best,
            least: best.min(self.upper),
            tolerance,
        };
        let (pa, pb) = (&poses[a], &poses[b]);
        let pose_ab = pa.inv_mul(pb);
        if let Some(decided) = self.bounded(set, (a, b), (pa, pb), pose_ab, near, bounds) {
            return decided;
        }
        let d = match (set.object(a).exact_mesh, set.object(b).exact_mesh) {
            (false, false) => set.convex_distance(a, b, (pa, pb), Some(&mut self.support), Some(&mut self.axis)),
            _ => match self.mesh_pair(set, k, (pa, pb), pose_ab, bounds) {
                Folded::Distance(d) => d,
                Folded::Decided(result) => return result,
            },
        };
        self.reference = (d.distance, pose_ab);
        Some(d)
    }

    /// For [`PairMemory::fold`], the bounds that need no distance of pair `(a, b)` at world
    /// poses `(pa, pb)` (relative `pose_ab`): the lower bound carried from an earlier sample,
    /// the followed path's (`near`), the bounding spheres' gap and the convex shapes'
    /// separation along their last axis. `Some(result)` when one decides the sample (passed
    /// over, or apart on the path and recorded or left for finish), `None` when none does.
    fn bounded(
        &mut self,
        set: &CollisionSet,
        (a, b): (usize, usize),
        (pa, pb): (&PPose, &PPose),
        pose_ab: PPose,
        near: Option<PathSample>,
        bounds: Bounds,
    ) -> Option<Option<PairDistance>> {
        let (oa, ob) = (set.object(a), set.object(b));
        // the lower bound found at an earlier sample, less how far any point of b can have
        // moved relative to a since (or a relative to b, whichever bound is smaller)
        let (lower, then) = &self.reference;
        if bounds.skip(*lower - relative_motion(then, &pose_ab, (oa.sphere, ob.sphere))) {
            return Some(None);
        }
        // the followed path's bound less the pair's motion between the path's pose and this
        if let Some(path) = near {
            let lower = path.bound.lower - relative_motion(&path.pose_ab, &pose_ab, (oa.sphere, ob.sphere));
            if lower > 0.0 && (oa.exact_mesh || ob.exact_mesh) {
                // apart. Where the sample could lower the minimum at all, an actual distance
                // at this pose: the path's parts here (with a tolerance, recorded at once).
                // The sample waits for finish unless the bound proves it within the
                // tolerance of the smallest so far (exactly, a distance found here must be
                // found again by a search: it is this sample's only if the bound meets it)
                self.reference = (lower, pose_ab);
                let Some(upper) = (lower < bounds.least).then(|| set.part_distance(a, b, (pa, pb), path.bound.parts))
                else {
                    return Some(None);
                };
                self.upper = self.upper.min(upper);
                if !(bounds.tolerance > 0.0 && lower >= bounds.best.min(self.upper) - bounds.tolerance) {
                    self.closest = path.bound.parts;
                    self.pending.push(Pending {
                        t: bounds.t,
                        pose_ab,
                        lower,
                        upper,
                        hulls_apart: true,
                    });
                }
                return Some(bounds.upper_bound(upper));
            }
            if bounds.skip(lower) {
                self.reference = (lower, pose_ab);
                return Some(None);
            }
        }
        let gap = (*pa * oa.sphere.0 - *pb * ob.sphere.0).length() - oa.sphere.1 - ob.sphere.1;
        if bounds.skip(gap) {
            self.reference = (gap, pose_ab);
            return Some(None);
        }
        // the convex shapes' separation along the axis that separated them last time
        if self.axis != PVector::ZERO {
            let gap = set.separation_along(a, b, &pose_ab, self.axis, &mut self.support);
            if bounds.skip(gap) {
                self.reference = (gap, pose_ab);
                return Some(None);
            }
        }
        None
    }

    /// For [`PairMemory::fold`], pair `k` with a mesh, at world poses `(pa, pb)`: its hulls'
    /// distance, then where they are apart the distance they prove (or the sample left for
    /// finish), where they overlap the crossing test ([`PairMemory::hulls_overlap`]).
    fn mesh_pair(
        &mut self,
        set: &CollisionSet,
        k: usize,
        (pa, pb): (&PPose, &PPose),
        pose_ab: PPose,
        bounds: Bounds,
    ) -> Folded {
        let (a, b) = set.object_pairs()[k];
        let hull = (set.convex_distance(a, b, (pa, pb), Some(&mut self.support), Some(&mut self.axis))).distance;
        self.reference = (hull, pose_ab);
        if bounds.skip(hull) {
            return Folded::Decided(None);
        }
        if hull <= 0.0 {
            return self.hulls_overlap(set, k, (pa, pb), pose_ab, hull, bounds);
        }
        match set.proven_by_hulls(
            a,
            b,
            (pa, pb),
            hull,
            (&mut self.closest, self.support),
            bounds.tolerance,
        ) {
            Ok(distance) if bounds.tolerance > 0.0 => {
                // within the tolerance of the hulls' distance, which stays the lower bound
                // carried on
                self.upper = self.upper.min(distance);
                Folded::Decided(bounds.upper_bound(distance))
            }
            Ok(distance) => {
                self.upper = self.upper.min(distance);
                Folded::Distance(PairDistance {
                    distance,
                    intersecting: false,
                })
            }
            Err(upper) => {
                self.upper = self.upper.min(upper);
                self.pending.push(Pending {
                    t: bounds.t,
                    pose_ab,
                    lower: hull,
                    upper,
                    hulls_apart: true,
                });
                Folded::Decided(bounds.upper_bound(upper))
            }
        }
    }

    /// For [`PairMemory::mesh_pair`], pair `k` whose hulls overlap (signed distance `hull`):
    /// whether two triangles cross (or a triangle and a primitive) is tested now (an
    /// intersection must be seen at its sample); the distance of a sample whose parts are
    /// apart waits for finish like the others, its hulls bounding it below by 0 (none can lower
    /// a smallest distance of 0, and then the test goes on whatever it costs). A pair too
    /// close for a crossing test is searched now ([`PairMemory::search_now`]).
    fn hulls_overlap(
        &mut self,
        set: &CollisionSet,
        k: usize,
        (pa, pb): (&PPose, &PPose),
        pose_ab: PPose,
        hull: f64,
        bounds: Bounds,
    ) -> Folded {
        if self.search_now && bounds.best > 0.0 {
            return Folded::Decided(self.search_now(set, k, (pa, pb), bounds.best, hull, bounds.tolerance));
        }
        let (a, b) = set.object_pairs()[k];
        let budget = if bounds.best > 0.0 { TOUCH_BUDGET } else { usize::MAX };
        match (set.touch(a, b, &pose_ab, &mut self.closest, budget)).expect("a mesh") {
            Touch::Crossing => Folded::Distance(PairDistance {
                distance: 0.0,
                intersecting: true,
            }),
            Touch::Apart(upper) => {
                self.upper = self.upper.min(upper);
                if bounds.least > 0.0 {
                    self.pending.push(Pending {
                        t: bounds.t,
                        pose_ab,
                        lower: 0.0,
                        upper,
                        hulls_apart: false,
                    });
                }
                Folded::Decided(bounds.upper_bound(upper))
            }
            Touch::Undecided => {
                self.search_now = true;
                Folded::Decided(self.search_now(set, k, (pa, pb), bounds.best, hull, bounds.tolerance))
            }
        }
    }

    /// For [`PairMemory::fold`]: the distance of pair `k`, whose hulls overlap (signed
    /// distance `hull`), at the world poses `(pa, pb)` of its objects, searched now, bounded by
    /// the smallest distance so far `best`, or (once the pair has intersected) by the least
    /// positive distance, which still finds an intersection (a pair of meshes is then given
    /// the crossing test, whose budget is lifted). Sets the pair's carried lower bound.
    ///
    /// The pair may touch, yet a search to within a share `s` of the `tolerance` is safe while
    /// `best > s`: it passes over only boxes and parts whose lower bound is at least the best
    /// distance found less `s`, which is positive until it finds parts within `s` of each
    /// other, and two parts that touch have a lower bound of 0. When it finds parts that
    /// close, the sample is searched again exactly, so an intersection is never passed over.
    fn search_now(
        &mut self,
        set: &CollisionSet,
        k: usize,
        (pa, pb): (&PPose, &PPose),
        best: f64,
        hull: f64,
        tolerance: f64,
    ) -> Option<PairDistance> {
        let bound = best.max(f64::MIN_POSITIVE);
        let share = tolerance * SEARCH_SHARE;
        let mut search = |tolerance| set.pair_distance(k, (pa, pb), &mut self.closest, bound, Some(hull), tolerance);
        let (found, slack) = if share > 0.0 && bound > share {
            match search(share) {
                Some(d) if d.distance <= share => (search(0.0), 0.0),
                found => (found, share),
            }
        } else {
            (search(0.0), 0.0)
        };
        let lower = found.map_or(bound, |d| d.distance) - slack;
        self.reference = (lower, pa.inv_mul(pb));
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn waiting(lower: f64) -> Pending {
        Pending {
            t: 0.0,
            pose_ab: PPose::IDENTITY,
            lower,
            upper: 1.0,
            hulls_apart: true,
        }
    }

    /// The least share while a later sample still to be settled is near enough for it to
    /// settle it; else (none waiting, all settled already, or all moved further than the
    /// tolerance less the least share) the whole tolerance.
    #[test]
    fn a_search_takes_the_whole_tolerance_when_no_later_sample_can_gain() {
        let (tolerance, reach) = (1e-3, 0.02);
        let least = tolerance * SEARCH_SHARE;
        let share = |others: &[Pending], moves: &[f64]| search_share(tolerance, others, moves, reach);
        assert_eq!(share(&[], &[]), tolerance);
        // settled already (its bound reaches `reach`): it does not count
        assert_eq!(share(&[waiting(reach), waiting(0.0)], &[0.0, 5e-3]), tolerance);
        // one of those below `reach` near enough, or a repeated pose (no motion)
        assert_eq!(share(&[waiting(0.0), waiting(0.0)], &[4e-3, 1e-4]), least);
        assert_eq!(share(&[waiting(0.0)], &[0.0]), least);
        // just within the least share's reach, and just beyond it
        assert_eq!(share(&[waiting(0.0)], &[tolerance - least]), least);
        assert_eq!(share(&[waiting(0.0)], &[tolerance - least + 1e-9]), tolerance);
    }
}
