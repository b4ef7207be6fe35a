//! The clearance of a whole run: per checked pair, its smallest distance and when.

use serde::Serialize;

use crate::error::quoted;

/// How meshes are read for distances (primitives are exact either way).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ClearanceGeometry {
    /// Each mesh replaced by its convex hull; signed distances (negative: penetration depth).
    Hull,
    /// The exact triangles; distances ≥ 0, 0 when they intersect.
    #[default]
    Mesh,
}

crate::choice::choice_words!(ClearanceGeometry { Mesh => "mesh", Hull => "hull" });

/// The distance of one checked pair at one pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairDistance {
    /// Distance (m): signed for hulls (negative: penetration depth), ≥ 0 for meshes.
    pub distance: f64,
    /// Whether the two shapes overlap (hulls: `distance < 0`; meshes: triangles cross).
    pub intersecting: bool,
}

/// One checked pair over a run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PairReport {
    /// The two URDF link names.
    pub links: [String; 2],
    /// Smallest distance seen (m; see [`ClearanceGeometry`]); `+∞` (serialised as `null`)
    /// before the first sample.
    pub min_m: f64,
    /// Simulated time of that smallest distance (s).
    pub t: f64,
    /// Whether the pair intersected at any sample (only written when true).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub intersecting: bool,
}

impl PairReport {
    /// Folds the pair's distance `d` at time `t` in; whether it lowered the pair's minimum.
    pub(crate) fn record(&mut self, d: PairDistance, t: f64) -> bool {
        self.intersecting |= d.intersecting;
        let lower = d.distance < self.min_m;
        if lower {
            self.min_m = d.distance;
            self.t = t;
        }
        lower
    }
}

/// The clearance of a run, the summary's `"clearance"` object:
/// `{"geometry", "min_m", "links", "t", "pairs": [{"links", "min_m", "t", "intersecting"?}],
/// "unchecked"}`; the top-level `min_m`, `links` and `t` are those of the closest pair
/// (absent when no pair is checked).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClearanceReport {
    /// How meshes were read.
    pub geometry: ClearanceGeometry,
    /// Smallest distance over all pairs (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_m: Option<f64>,
    /// The closest pair's links.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub links: Option<[String; 2]>,
    /// When the closest pair was closest (s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t: Option<f64>,
    /// How far (m) each minimum may be above the true one over the samples (0: exact); each
    /// is the distance of two actual parts at one sample (see [`super::Clearance`]).
    pub tolerance_m: f64,
    /// Every checked pair, in [`super::CollisionSet::pair_links`] order.
    pub pairs: Vec<PairReport>,
    /// Links whose collision mesh was not found, so not checked.
    pub unchecked: Vec<String>,
}

impl ClearanceReport {
    /// An empty report for pairs of links `pair_links` measured with `geometry`; `unchecked`
    /// lists the links left out (see [`super::CollisionSet::new_report`]).
    pub fn new<'a>(
        geometry: ClearanceGeometry,
        pair_links: impl Iterator<Item = [&'a str; 2]>,
        unchecked: Vec<String>,
    ) -> ClearanceReport {
        ClearanceReport {
            geometry,
            min_m: None,
            links: None,
            t: None,
            tolerance_m: 0.0,
            pairs: pair_links
                .map(|[a, b]| PairReport {
                    links: [a.to_string(), b.to_string()],
                    min_m: f64::INFINITY,
                    t: 0.0,
                    intersecting: false,
                })
                .collect(),
            unchecked,
        }
    }

    /// Folds pair `k`'s distance `d` at time `t` in.
    pub(crate) fn record(&mut self, k: usize, d: PairDistance, t: f64) {
        if self.pairs[k].record(d, t) {
            self.lowered(k, d.distance, t);
        }
    }

    /// After pair `k`'s minimum was lowered to `distance` at time `t` ([`PairReport::record`]):
    /// the closest pair overall, the first pair to reach the smallest distance. Told the
    /// lowerings of every pair in the order they happened, it is what [`ClearanceReport::record`]
    /// would have made of them.
    pub(crate) fn lowered(&mut self, k: usize, distance: f64, t: f64) {
        if self.min_m.is_none_or(|m| distance < m) {
            self.min_m = Some(distance);
            self.links = Some(self.pairs[k].links.clone());
            self.t = Some(t);
        }
    }

    /// Whether any pair intersected.
    pub fn any_intersecting(&self) -> bool {
        self.pairs.iter().any(|p| p.intersecting)
    }

    /// One line for people: the closest pair, its distance in mm and when.
    pub fn line(&self) -> String {
        let what = match self.geometry {
            ClearanceGeometry::Hull => "convex hulls",
            ClearanceGeometry::Mesh => "meshes",
        };
        let unchecked = if self.unchecked.is_empty() {
            String::new()
        } else {
            format!("; not checked: {}", self.unchecked.join(", "))
        };
        match (&self.links, self.min_m, self.t) {
            (Some([a, b]), Some(m), Some(t)) => format!(
                "self-clearance ({what}): {}–{} {:.2} mm at t = {t:.2} s{}{unchecked}",
                quoted(a),
                quoted(b),
                m * 1e3,
                if self.any_intersecting() { ", intersecting" } else { "" },
            ),
            _ => format!("self-clearance ({what}): no pair checked{unchecked}"),
        }
    }
}
