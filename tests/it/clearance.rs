//! Self-clearance (`faze4::geometry`) against the oracle (`tools/oracle/clearance_fixtures.py`):
//! Drake's signed distances between convex hulls, coal's exact mesh distances, and Drake's
//! default pair filtering, on the Faze4's official meshes and on a primitive arm of our own;
//! and the answers to bad geometry.

use crate::common;

use common::*;
use faze4::Error;
use faze4::algo::{Data, forward_kinematics};
use std::sync::Arc;

use faze4::geometry::{
    Clearance, ClearanceGeometry, CollisionSet, GeometryData, PairFilter, PathClearance, Robot, Warning,
};
use faze4::model::{Geometry, PackagePaths};
use serde_json::Value;

/// Distances agree with the oracle within this (m).
const TOLERANCE: f64 = 1e-6;
/// Distances to a cylinder agree within this (m): GJK converges slowly on a curved support
/// function, and parry, coal (run to round-off) and Drake disagree among themselves by up to
/// 2e-6 m there (Drake, whose GJK stops at 1e-6, by up to 1e-4 m: see the oracle's printout).
const CYLINDER_TOLERANCE: f64 = 5e-6;
/// Penetration depths involving a cylinder agree within this (m): EPA on a curved shape stops
/// on a polytope inside it, in parry as in coal.
const CYLINDER_DEPTH_TOLERANCE: f64 = 5e-5;

/// How far above a pair's distance the parts that prove it by its hulls may be (m): the
/// documented certificate of `geometry::collision_set` (docs/clearance.md).
const HULL_CERTIFICATE: f64 = 1e-9;

fn real() -> Robot {
    Robot::from_urdf_file(
        &repo_path("urdf/faze4_real.urdf"),
        &PackagePaths::new(vec![shared_description()]),
    )
    .unwrap()
}

fn collision_arm() -> Robot {
    Robot::from_urdf_file(&repo_path("tests/urdf/collision_arm.urdf"), &PackagePaths::default()).unwrap()
}

/// The fixture's pairs as indices into `robot.geometry.collisions` (objects named by link and
/// index within the link), in fixture order.
fn fixture_pairs(robot: &Robot, fixture: &Value) -> Vec<(usize, usize)> {
    let object = |k: &Value| {
        let o = &fixture["objects"][k.as_u64().unwrap() as usize];
        let (link, index) = (o["link"].as_str().unwrap(), o["index"].as_u64().unwrap() as usize);
        (robot.geometry.collisions.iter().enumerate())
            .filter(|(_, g)| g.link == link)
            .nth(index)
            .unwrap_or_else(|| panic!("no collision {index} on {link}"))
            .0
    };
    (fixture["pairs"].as_array().unwrap().iter())
        .map(|p| {
            let (a, b) = (object(&p[0]), object(&p[1]));
            (a.min(b), a.max(b))
        })
        .collect()
}

/// Checks `kind`'s distances of `robot` at the fixture's poses selected by `keep` (index, label)
/// against the fixture's field (`hull` or `mesh`); returns how many were compared.
fn compare(robot: &Robot, fixture: &Value, kind: ClearanceGeometry, keep: impl Fn(usize, &str) -> bool) -> usize {
    let (set, warnings) = CollisionSet::new(&robot.model, &robot.geometry, kind, PairFilter::NonAdjacent).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    // the same pairs as Drake's default filtering
    let expected = fixture_pairs(robot, fixture);
    let ours: Vec<(usize, usize)> = set.pairs().collect();
    let mut sorted = (ours.clone(), expected.clone());
    sorted.0.sort();
    sorted.1.sort();
    assert_eq!(sorted.0, sorted.1, "checked pairs");
    let field = match kind {
        ClearanceGeometry::Hull => "hull",
        ClearanceGeometry::Mesh => "mesh",
    };
    let mut data = Data::new(&robot.model);
    let mut geometry_data = GeometryData::new(&set);
    let mut compared = 0;
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for (i, pose) in fixture["poses"].as_array().unwrap().iter().enumerate() {
        let label = pose["label"].as_str().unwrap();
        if !keep(i, label) {
            continue;
        }
        let q = vec_f64(&pose["q"]);
        forward_kinematics(&robot.model, &mut data, &q);
        set.distances(&data.frame_pose, &mut geometry_data);
        for (k, pair) in expected.iter().enumerate() {
            let ours_k = ours.iter().position(|p| p == pair).unwrap();
            let d = geometry_data.distances[ours_k];
            let links = [
                &robot.geometry.collisions[pair.0].link,
                &robot.geometry.collisions[pair.1].link,
            ];
            let Some(want) = pose[field][k].as_f64() else {
                // a mesh against a primitive: no oracle value (see the script); the hulls' signed
                // distance bounds the exact one from below
                let hull = pose["hull"][k].as_f64().unwrap();
                assert!(
                    d.distance >= hull - TOLERANCE,
                    "{label}, {links:?}: {} below the hulls' {hull}",
                    d.distance
                );
                continue;
            };
            let cylinder = [pair.0, pair.1]
                .iter()
                .any(|&g| matches!(robot.geometry.collisions[g].geometry, Geometry::Cylinder { .. }));
            let error = (d.distance - want).abs();
            let (worst, bound) = match (cylinder, want < 0.0) {
                (false, _) => (&mut worst.0, TOLERANCE),
                (true, false) => (&mut worst.1, CYLINDER_TOLERANCE),
                (true, true) => (&mut worst.2, CYLINDER_DEPTH_TOLERANCE),
            };
            *worst = worst.max(error);
            assert!(
                error <= bound,
                "{label}, {links:?} ({field}): {} vs oracle {want}",
                d.distance
            );
            if kind == ClearanceGeometry::Mesh {
                assert_eq!(
                    d.intersecting,
                    pose["intersecting"][k].as_bool().unwrap(),
                    "{label}, {links:?}"
                );
            }
            compared += 1;
        }
    }
    println!(
        "{} ({field}): {compared} distances, largest difference from the oracle {:.1e} m; pairs with a cylinder {:.1e} m apart, {:.1e} m penetrating",
        robot.model.name, worst.0, worst.1, worst.2
    );
    compared
}

#[test]
fn primitive_arm_signed_distances_match_the_oracle() {
    let arm = collision_arm();
    let fixture = fixture("clearance_collision_arm.json");
    // primitives are exact in both readings
    for kind in [ClearanceGeometry::Hull, ClearanceGeometry::Mesh] {
        let n = compare(&arm, &fixture, kind, |_, _| true);
        assert_eq!(n, 24 * 40);
    }
    let penetrating = (fixture["poses"].as_array().unwrap().iter())
        .filter(|p| p["hull"].as_array().unwrap().iter().any(|d| d.as_f64().unwrap() < 0.0))
        .count();
    assert!(
        penetrating >= 5,
        "the fixture exercises penetration ({penetrating} poses)"
    );
}

#[test]
fn faze4_hull_signed_distances_match_the_oracle() {
    let n = compare(
        &real(),
        &fixture("clearance_faze4_real.json"),
        ClearanceGeometry::Hull,
        |_, _| true,
    );
    assert_eq!(n, 15 * 252);
}

#[test]
fn faze4_exact_mesh_distances_match_coal() {
    let fixture = fixture("clearance_faze4_real.json");
    // exact queries are slow in a debug build: every 30th circle sample and the random poses
    let n = compare(&real(), &fixture, ClearanceGeometry::Mesh, |i, label| {
        i % 30 == 0 || label.starts_with("random")
    });
    // 5 of the 15 pairs are base_link's cylinder against a mesh, bounded only (see compare)
    assert_eq!(n, 10 * (8 + 12));
}

/// The issue's two figures along the circle: the convex hulls of nadlaktica and podlaktica
/// overlap at every sample, the meshes stay more than 2 cm apart; the report names the pair.
#[test]
fn circle_clearance_report_names_the_closest_pair() {
    let robot = real();
    let fixture = fixture("clearance_faze4_real.json");
    let circle: Vec<&Value> = (fixture["poses"].as_array().unwrap().iter())
        .filter(|p| p["label"].as_str().unwrap().starts_with("circle"))
        .collect();
    let mut data = Data::new(&robot.model);
    let (set, _) = CollisionSet::new(
        &robot.model,
        &robot.geometry,
        ClearanceGeometry::Hull,
        PairFilter::NonAdjacent,
    )
    .unwrap();
    let mut clearance = Clearance::new(&set);
    for (k, pose) in circle.iter().enumerate() {
        forward_kinematics(&robot.model, &mut data, &vec_f64(&pose["q"]));
        clearance.add(&data.frame_pose, k as f64 * 0.02);
    }
    clearance.finish();
    let report = clearance.into_report();
    let pair = fixture_pairs(&robot, &fixture)
        .iter()
        .position(|&(a, b)| {
            let links = [&robot.geometry.collisions[a].link, &robot.geometry.collisions[b].link];
            links == ["nadlaktica", "podlaktica"]
        })
        .unwrap();
    let drake: Vec<f64> = circle.iter().map(|p| p["hull"][pair].as_f64().unwrap()).collect();
    let (k_min, drake_min) =
        (drake.iter().copied().enumerate()).fold((0, f64::INFINITY), |b, (k, d)| if d < b.1 { (k, d) } else { b });
    assert!(drake.iter().all(|&d| d < 0.0), "the hulls overlap at every sample");
    assert_eq!(
        report.links.as_ref().unwrap(),
        &["nadlaktica".to_string(), "podlaktica".to_string()]
    );
    assert!((report.min_m.unwrap() - drake_min).abs() <= TOLERANCE);
    assert!((report.t.unwrap() - k_min as f64 * 0.02).abs() < 1e-12);
    assert!(report.any_intersecting());
    let json = serde_json::to_value(&report).unwrap();
    assert_eq!(json["geometry"], "hull");
    assert_eq!(json["links"], serde_json::json!(["nadlaktica", "podlaktica"]));
    assert_eq!(json["pairs"].as_array().unwrap().len(), 15);
    assert!(report.line().contains("'nadlaktica'–'podlaktica'"), "{}", report.line());

    // exact meshes, on the samples where the mesh pair is closest per the oracle
    let mesh: Vec<f64> = circle.iter().map(|p| p["mesh"][pair].as_f64().unwrap()).collect();
    assert!(mesh.iter().all(|&d| d > 0.02), "the meshes never come within 2 cm");
    let (set, _) = CollisionSet::new(
        &robot.model,
        &robot.geometry,
        ClearanceGeometry::Mesh,
        PairFilter::NonAdjacent,
    )
    .unwrap();
    let mut clearance = Clearance::new(&set);
    let k_mesh =
        (mesh.iter().copied().enumerate()).fold((0, f64::INFINITY), |b, (k, d)| if d < b.1 { (k, d) } else { b });
    for k in [k_mesh.0.saturating_sub(1), k_mesh.0, (k_mesh.0 + 1) % circle.len()] {
        forward_kinematics(&robot.model, &mut data, &vec_f64(&circle[k]["q"]));
        clearance.add(&data.frame_pose, k as f64 * 0.02);
    }
    clearance.finish();
    let report = clearance.into_report();
    let ours = &report.pairs[set
        .pair_links()
        .position(|l| l == ["nadlaktica", "podlaktica"])
        .unwrap()];
    assert!(
        (ours.min_m - k_mesh.1).abs() <= TOLERANCE,
        "{} vs {}",
        ours.min_m,
        k_mesh.1
    );
    assert!(!ours.intersecting);
}

#[test]
fn adjacent_pairs_are_checked_on_request() {
    let arm = collision_arm();
    let count = |filter| {
        let (set, _) = CollisionSet::new(&arm.model, &arm.geometry, ClearanceGeometry::Hull, filter).unwrap();
        set.pairs().count()
    };
    // 9 objects on 5 bodies; the welded forearm_tip is never checked against forearm
    assert_eq!(count(PairFilter::NonAdjacent), 24);
    // + base–turret 2, turret–upper 2, upper–forearm 2, forearm_tip–hand 2
    assert_eq!(count(PairFilter::All), 32);
}

fn write_temp(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("faze4-clearance-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn one_link_arm(collision: &str) -> String {
    format!(
        r#"<robot name="one"><link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
<joint name="j" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
<link name="a"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
<collision><origin xyz="0 0 0.5"/><geometry>{collision}</geometry></collision></link></robot>"#
    )
}

#[test]
fn a_missing_mesh_is_one_warning_and_unchecked() {
    let path = write_temp(
        "missing.urdf",
        &one_link_arm(r#"<mesh filename="package://nowhere/meshes/gone.STL"/>"#),
    );
    let robot = Robot::from_urdf_file(&path, &PackagePaths::default()).unwrap();
    let (set, warnings) =
        CollisionSet::new(&robot.model, &robot.geometry, ClearanceGeometry::Mesh, PairFilter::All).unwrap();
    assert_eq!(warnings.len(), 1);
    assert!(matches!(&warnings[0], Warning::MeshNotFound { link, .. } if link == "a"));
    let line = warnings[0].to_string();
    assert!(
        line.contains("missing.urdf") && line.contains("gone.STL") && line.contains("`package_path`"),
        "{line}"
    );
    assert!(!line.contains('\n'));
    assert_eq!(set.pairs().count(), 0);
    let report = set.new_report();
    assert_eq!(report.unchecked, ["a"]);
    assert_eq!(
        serde_json::to_value(&report).unwrap()["unchecked"],
        serde_json::json!(["a"])
    );
    // skipping collision geometry altogether: no warning, nothing checked
    let (set, warnings) = CollisionSet::new(
        &robot.model,
        &robot.geometry.without_collisions(),
        ClearanceGeometry::Mesh,
        PairFilter::All,
    )
    .unwrap();
    assert!(warnings.is_empty() && set.unchecked().is_empty() && set.pairs().count() == 0);
}

#[test]
fn an_unreadable_or_degenerate_mesh_is_an_error_naming_the_file() {
    let stl = write_temp("bad.stl", "solid nothing\nendsolid nothing\n");
    let urdf_text = one_link_arm(&format!(r#"<mesh filename="{}"/>"#, stl.display()));
    let path = write_temp("bad_mesh.urdf", &urdf_text);
    let robot = Robot::from_urdf_file(&path, &PackagePaths::default()).unwrap();
    let e = CollisionSet::new(&robot.model, &robot.geometry, ClearanceGeometry::Hull, PairFilter::All)
        .err()
        .unwrap();
    assert!(matches!(e, Error::MeshEmpty { .. }));
    assert!(e.to_string().starts_with(&stl.display().to_string()), "{e}");
    std::fs::write(&stl, b"not an stl at all").unwrap();
    let e = CollisionSet::new(&robot.model, &robot.geometry, ClearanceGeometry::Hull, PairFilter::All)
        .err()
        .unwrap();
    assert!(matches!(e, Error::InvalidData { .. }), "{e}");
    // NaN vertices
    let nan = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 NaN\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
    std::fs::write(&stl, nan).unwrap();
    let e = CollisionSet::new(&robot.model, &robot.geometry, ClearanceGeometry::Hull, PairFilter::All)
        .err()
        .unwrap();
    assert!(matches!(e, Error::MeshNotFinite { triangle: 0, .. }), "{e}");
}

#[test]
fn zero_size_primitives_are_refused() {
    for (shape, what) in [
        (r#"<box size="0.1 0 0.1"/>"#, "box size"),
        (r#"<cylinder radius="0" length="0.2"/>"#, "cylinder"),
        (r#"<sphere radius="0"/>"#, "sphere radius"),
        (r#"<sphere radius="-0.1"/>"#, "sphere radius"),
    ] {
        let e = Robot::from_urdf_str(&one_link_arm(shape), "zero.urdf", None, &PackagePaths::default())
            .err()
            .unwrap();
        assert!(matches!(e, Error::DegenerateShape { .. }), "{shape}: {e}");
        let line = e.to_string();
        assert!(
            line.starts_with("zero.urdf: link 'a' <collision>: ") && line.contains(what),
            "{line}"
        );
    }
}

/// Over consecutive circle samples, the pruned accumulation (lower bounds carried from sample
/// to sample, hull pre-checks, bounded exact searches) gives each pair exactly the smallest of
/// its per-sample distances, and when.
#[test]
fn pruned_accumulation_equals_the_minimum_of_every_sample_and_finds_each_intersection() {
    let robot = real();
    let fixture = fixture("clearance_faze4_real.json");
    // 60 consecutive samples of the circle: enough for finish to prune most of them
    let poses = &fixture["poses"].as_array().unwrap()[90..150];
    let mut data = Data::new(&robot.model);
    for kind in [ClearanceGeometry::Hull, ClearanceGeometry::Mesh] {
        let (set, _) = CollisionSet::new(&robot.model, &robot.geometry, kind, PairFilter::NonAdjacent).unwrap();
        let (mut every, mut pruned) = (GeometryData::new(&set), Clearance::new(&set));
        // every pair's distance at every sample, by the full query
        let mut every_sample: Vec<Vec<f64>> = Vec::new();
        for (k, pose) in poses.iter().enumerate() {
            let t = k as f64 * 0.02;
            forward_kinematics(&robot.model, &mut data, &vec_f64(&pose["q"]));
            set.distances(&data.frame_pose, &mut every);
            every_sample.push(every.distances.iter().map(|d| d.distance).collect());
            pruned.add(&data.frame_pose, t);
            let intersecting: Vec<bool> = every.distances.iter().map(|d| d.intersecting).collect();
            assert_eq!(pruned.intersecting(), intersecting, "{kind:?} at sample {k}");
            assert_eq!(intersecting.iter().any(|&i| i), kind == ClearanceGeometry::Hull);
        }
        pruned.finish();
        let report = pruned.into_report();
        // the report's minimum is the smallest of every sample, and its time a sample at which
        // the pair is that close: within GJK's accuracy on the hulls (the accumulation's
        // hill-climbing support maps stop GJK at other points than the full query's scans),
        // for the meshes within the hull certificate's 1 nm (a pair proven by its hulls is
        // answered by whichever parts within 1 nm of the hulls' distance it tries first, and
        // the run and the full query are seeded by different samples)
        let tolerance = if kind == ClearanceGeometry::Hull {
            TOLERANCE
        } else {
            HULL_CERTIFICATE
        };
        for (p, pair) in report.pairs.iter().enumerate() {
            let least = every_sample.iter().map(|d| d[p]).fold(f64::INFINITY, f64::min);
            let at_t = every_sample[(pair.t / 0.02).round() as usize][p];
            assert!(
                (pair.min_m - least).abs() <= tolerance && (at_t - least).abs() <= tolerance,
                "{kind:?} {:?}: {} at t = {} (full query there {at_t}) vs {least}",
                pair.links,
                pair.min_m,
                pair.t
            );
        }
    }
}

#[test]
fn the_bundled_arm_checks_its_built_in_meshes_as_the_files_do() {
    // Robot::faze4() resolves no mesh file: the official meshes come from the binary, and
    // give the same distances as the files (identical vertices).
    let (bundled, files) = (Robot::faze4(), real());
    let (set, warnings) = CollisionSet::new(
        &bundled.model,
        &bundled.geometry,
        ClearanceGeometry::Mesh,
        PairFilter::NonAdjacent,
    )
    .unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(set.unchecked().is_empty());
    assert_eq!(set.pairs().count(), 15);
    let (file_set, _) = CollisionSet::new(
        &files.model,
        &files.geometry,
        ClearanceGeometry::Mesh,
        PairFilter::NonAdjacent,
    )
    .unwrap();
    let q = faze4::faze4::Q_SEED;
    let mut data = Data::new(&bundled.model);
    forward_kinematics(&bundled.model, &mut data, &q);
    let (mut a, mut b) = (GeometryData::new(&set), GeometryData::new(&file_set));
    set.distances(&data.frame_pose, &mut a);
    file_set.distances(&data.frame_pose, &mut b);
    assert_eq!(a.distances, b.distances);
}

/// Runs `kind` clearance over the joint samples `qs` (one every 0.02 s) both ways: the pruned
/// accumulation, and the full query at every sample. Checks that the accumulation marks as
/// intersecting exactly the pairs the full query does at every sample, and that its report
/// gives each pair the smallest of its per-sample distances (exactly, meshes being read) at
/// a sample where the pair is that close. Returns how many (sample, pair) intersections
/// there were.
fn accumulation_matches_every_sample(robot: &Robot, filter: PairFilter, qs: &[Vec<f64>]) -> usize {
    let (set, _) = CollisionSet::new(&robot.model, &robot.geometry, ClearanceGeometry::Mesh, filter).unwrap();
    let mut data = Data::new(&robot.model);
    let (mut every, mut pruned) = (GeometryData::new(&set), Clearance::new(&set));
    let (mut every_sample, mut crossings) = (Vec::new(), 0);
    for (k, q) in qs.iter().enumerate() {
        forward_kinematics(&robot.model, &mut data, q);
        set.distances(&data.frame_pose, &mut every);
        every_sample.push(every.distances.iter().map(|d| d.distance).collect::<Vec<f64>>());
        pruned.add(&data.frame_pose, k as f64 * 0.02);
        let intersecting: Vec<bool> = every.distances.iter().map(|d| d.intersecting).collect();
        assert_eq!(pruned.intersecting(), intersecting, "sample {k}");
        crossings += intersecting.iter().filter(|&&i| i).count();
    }
    pruned.finish();
    let report = pruned.into_report();
    for (p, pair) in report.pairs.iter().enumerate() {
        let least = every_sample.iter().map(|d| d[p]).fold(f64::INFINITY, f64::min);
        let at_t = every_sample[(pair.t / 0.02).round() as usize][p];
        assert!(
            (pair.min_m - least).abs() <= 1e-12 && (at_t - least).abs() <= 1e-12,
            "{:?}: {} at t = {} (full query there {at_t}) vs {least}",
            pair.links,
            pair.min_m,
            pair.t
        );
        assert_eq!(pair.intersecting, least <= 0.0, "{:?}", pair.links);
    }
    crossings
}

/// `n` joint samples of the Faze4 folding into itself: every joint `90° sin(t + i π/3)`, one
/// every 0.04 s.
fn folding(n: usize) -> Vec<Vec<f64>> {
    (0..n)
        .map(|k| {
            let t = k as f64 * 0.04;
            (0..6)
                .map(|i| 90f64.to_radians() * (t + i as f64 * std::f64::consts::FRAC_PI_3).sin())
                .collect()
        })
        .collect()
}

/// The Faze4's meshes through a wave of 90° amplitude (every joint `A sin(t + i π/3)`), which
/// folds links into one another for many samples in a row, the crossing triangles changing
/// from sample to sample; with the default pairs, and with every pair.
#[test]
fn pruned_accumulation_sees_every_intersection_of_the_faze4_meshes() {
    let qs = folding(150);
    let crossings = accumulation_matches_every_sample(&real(), PairFilter::NonAdjacent, &qs);
    assert!(crossings > 50, "{crossings} intersections");
    // the arm's own motion in `faze4 wave --amp-deg 60` (J2 cannot hold it and it falls),
    // from 2 s to 6 s: rotary_base–lakat's minimum (5.24 s) was once skipped there by its
    // hulls' gap along their last GJK axis, the climbs on lakat's hull stopping short
    let dir = temp_dir("clearance-wave-60");
    let run = faze4(
        &dir,
        &[
            "wave",
            "--amp-deg",
            "60",
            "--no-collisions",
            "--trail",
            "t.csv",
            "--quiet",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    let (header, rows) = read_csv(&dir.join("t.csv"));
    let q_at = |row: &Vec<f64>| {
        (1..=6)
            .map(|i| row[header.iter().position(|h| *h == format!("q{i}")).unwrap()])
            .collect()
    };
    let fall: Vec<Vec<f64>> = rows[100..=300].iter().map(q_at).collect();
    accumulation_matches_every_sample(&real(), PairFilter::NonAdjacent, &fall);
    std::fs::remove_dir_all(&dir).unwrap();
    // with the pairs a joint connects, whose meshes come within a fraction of a millimetre
    // all along a joint's parts (too close for the crossing test: searched at each sample)
    let crossings = accumulation_matches_every_sample(&real(), PairFilter::All, &qs[..40]);
    assert!(crossings > 20, "{crossings} intersections");
}

/// An ASCII STL of the boxes `[lo, hi]`, each face cut into `n` × `n` squares of two triangles.
fn boxes_stl(boxes: &[([f64; 3], [f64; 3])], n: usize) -> String {
    let mut text = String::from("solid boxes\n");
    for (lo, hi) in boxes {
        for axis in 0..3 {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for side in [lo[axis], hi[axis]] {
                let corner = |i: usize, j: usize| {
                    let mut p = [0.0; 3];
                    p[axis] = side;
                    p[u] = lo[u] + (hi[u] - lo[u]) * i as f64 / n as f64;
                    p[v] = lo[v] + (hi[v] - lo[v]) * j as f64 / n as f64;
                    p
                };
                for (i, j) in (0..n).flat_map(|i| (0..n).map(move |j| (i, j))) {
                    let (a, b, c, d) = (corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1));
                    for [p, q, r] in [[a, b, c], [a, c, d]] {
                        text += " facet normal 0 0 0\n  outer loop\n";
                        for x in [p, q, r] {
                            text += &format!("   vertex {} {} {}\n", x[0], x[1], x[2]);
                        }
                        text += "  endloop\n endfacet\n";
                    }
                }
            }
        }
    }
    text + "endsolid boxes\n"
}

/// An arm of our own, of meshes: a base plate carrying a thin upright fin, and a two-pronged
/// fork on a joint about y that folds down around the fin (the fork's hull swallows the fin
/// while its prongs pass on either side of it) and then drives its prongs into the plate.
#[test]
fn pruned_accumulation_sees_every_intersection_of_a_folding_fork() {
    let base = boxes_stl(
        &[
            ([-0.5, -0.5, -0.1], [0.5, 0.5, 0.0]),
            ([0.1, -0.005, 0.0], [0.6, 0.005, 0.25]),
        ],
        8,
    );
    let fork = boxes_stl(
        &[
            ([0.0, 0.03, -0.01], [0.5, 0.05, 0.01]),
            ([0.0, -0.05, -0.01], [0.5, -0.03, 0.01]),
        ],
        6,
    );
    let (base, fork) = (write_temp("fork_base.stl", &base), write_temp("fork.stl", &fork));
    let urdf = format!(
        r#"<robot name="fork"><link name="base"><collision><geometry><mesh filename="{}"/></geometry></collision></link>
<joint name="j" type="revolute"><parent link="base"/><child link="fork"/><origin xyz="0 0 0.35"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
<link name="fork"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
<collision><geometry><mesh filename="{}"/></geometry></collision></link></robot>"#,
        base.display(),
        fork.display()
    );
    let path = write_temp("fork.urdf", &urdf);
    let robot = Robot::from_urdf_file(&path, &PackagePaths::default()).unwrap();
    // down to 1.2 rad and back up: the prongs reach the plate past about 0.75 rad
    let qs: Vec<Vec<f64>> = (0..=80)
        .map(|k| vec![1.2 * (std::f64::consts::PI * k as f64 / 80.0).sin()])
        .collect();
    let crossings = accumulation_matches_every_sample(&robot, PairFilter::All, &qs);
    assert!(crossings > 10, "{crossings} intersections");
}

/// Runs the clearance of `kind` over the joint samples `qs` (one every 0.02 s) exactly, to
/// within `tolerance` (searching the waiting samples every `batch` samples), and by the full
/// query at every sample. At every sample the tolerance's intersecting pairs are the exact
/// run's and the full query's; each pair's reported minimum is the distance of two actual
/// parts (not below the full query's distance at its sample), at most `tolerance` above the
/// smallest of every sample, and its `intersecting` the exact run's. Returns how many (sample,
/// pair) intersections there were.
fn tolerance_matches_exact(
    robot: &Robot,
    kind: ClearanceGeometry,
    filter: PairFilter,
    qs: &[Vec<f64>],
    tolerance: f64,
    batch: usize,
) -> usize {
    let (set, _) = CollisionSet::new(&robot.model, &robot.geometry, kind, filter).unwrap();
    let mut data = Data::new(&robot.model);
    let mut every = GeometryData::new(&set);
    let (mut exact, mut approx) = (
        Clearance::new(&set),
        Clearance::with_tolerance(&set, tolerance).batch(batch),
    );
    let (mut every_sample, mut crossings) = (Vec::new(), 0);
    for (k, q) in qs.iter().enumerate() {
        let t = k as f64 * 0.02;
        forward_kinematics(&robot.model, &mut data, q);
        set.distances(&data.frame_pose, &mut every);
        every_sample.push(every.distances.iter().map(|d| d.distance).collect::<Vec<f64>>());
        exact.add(&data.frame_pose, t);
        approx.add(&data.frame_pose, t);
        let intersecting: Vec<bool> = every.distances.iter().map(|d| d.intersecting).collect();
        assert_eq!(approx.intersecting(), intersecting, "{kind:?} sample {k}");
        assert_eq!(exact.intersecting(), intersecting, "{kind:?} sample {k}");
        crossings += intersecting.iter().filter(|&&i| i).count();
    }
    exact.finish();
    approx.finish();
    let (exact, approx) = (exact.into_report(), approx.into_report());
    assert_eq!(approx.tolerance_m, tolerance);
    // GJK's accuracy on hulls and cylinders (the full query scans, the run climbs); the hull
    // certificate's 1 nm on meshes (the parts tried first depend on the seeds)
    let slack = if kind == ClearanceGeometry::Hull {
        TOLERANCE
    } else {
        HULL_CERTIFICATE
    };
    for (p, (pair, exact)) in approx.pairs.iter().zip(&exact.pairs).enumerate() {
        let least = every_sample.iter().map(|d| d[p]).fold(f64::INFINITY, f64::min);
        let at_t = every_sample[(pair.t / 0.02).round() as usize][p];
        assert!(
            at_t <= pair.min_m + slack && pair.min_m <= least + tolerance + slack,
            "{kind:?} {:?}: {} at t = {} (full query there {at_t}), smallest {least}, tolerance {tolerance}",
            pair.links,
            pair.min_m,
            pair.t
        );
        assert!((exact.min_m - least).abs() <= slack, "{:?}", pair.links);
        assert_eq!(pair.intersecting, exact.intersecting, "{:?}", pair.links);
    }
    crossings
}

/// The tolerance on mesh pairs (the Faze4 circle, whose closest pairs are nearly concentric
/// surfaces), on primitive pairs (our box/cylinder/sphere arm, every pair) and on pairs that
/// intersect (the Faze4 folding into itself, exact meshes and hulls): intersections exactly
/// the exact run's at every sample, minima actual distances within the tolerance.
#[test]
fn a_tolerance_reports_actual_distances_within_it_and_the_exact_intersections() {
    let fixture = fixture("clearance_faze4_real.json");
    let circle: Vec<Vec<f64>> = fixture["poses"].as_array().unwrap()[90..150]
        .iter()
        .map(|p| vec_f64(&p["q"]))
        .collect();
    let folding = folding(60);
    let robot = real();
    for (tolerance, batch) in [(1e-3, 1024), (1e-4, 7)] {
        // mesh pairs
        let crossings = tolerance_matches_exact(
            &robot,
            ClearanceGeometry::Mesh,
            PairFilter::NonAdjacent,
            &circle,
            tolerance,
            batch,
        );
        assert_eq!(crossings, 0);
        // primitive pairs
        let arm = collision_arm();
        let wave: Vec<Vec<f64>> = (0..80)
            .map(|k| {
                let t = k as f64 * 0.05;
                (0..arm.model.dof()).map(|i| 1.2 * (t + i as f64).sin()).collect()
            })
            .collect();
        tolerance_matches_exact(&arm, ClearanceGeometry::Hull, PairFilter::All, &wave, tolerance, batch);
        // intersecting pairs
        let crossings = tolerance_matches_exact(
            &robot,
            ClearanceGeometry::Mesh,
            PairFilter::NonAdjacent,
            &folding,
            tolerance,
            batch,
        );
        assert!(crossings > 20, "{crossings} intersections");
        let crossings = tolerance_matches_exact(
            &robot,
            ClearanceGeometry::Hull,
            PairFilter::NonAdjacent,
            &circle,
            tolerance,
            batch,
        );
        assert!(crossings >= 60, "{crossings} intersections");
    }
}

/// The waiting samples' searches take a looser share of the tolerance where no later waiting
/// sample is near enough to gain from a tighter one, and a tighter share where one is: on the
/// Faze4's real meshes (whose closest pairs are nearly concentric shells), over samples in an
/// odd order, a sample repeated (the same pose twice and thrice: no motion between them), jumps
/// of tens of samples along the circle both ways (motions far above the tolerance) and a stretch
/// a tenth of a circle sample apart (motions below it), every pair's minimum is still an actual
/// distance within the tolerance of the smallest of the full query at every sample, exactly it
/// at 0, and no sample's intersections change; with the waiting samples searched all at the end
/// and in batches of 3.
#[test]
fn waiting_samples_in_any_order_keep_the_tolerance() {
    let fixture = fixture("clearance_faze4_real.json");
    let circle: Vec<Vec<f64>> = fixture["poses"].as_array().unwrap()[..]
        .iter()
        .map(|p| vec_f64(&p["q"]))
        .collect();
    let n = circle.len();
    assert!(n > 200, "{n} circle samples");
    let mut qs: Vec<Vec<f64>> = Vec::new();
    for &k in &[100, 100, 101, 160, 102, 102, 102, 40, 103, 200, 104, 10, 105] {
        qs.push(circle[k].clone());
    }
    // a tenth of a sample apart: the pair moves less than the tolerance from one to the next
    for step in 0..=20 {
        let f = step as f64 / 10.0;
        let (k, f) = (120 + f.floor() as usize, f.fract());
        qs.push(
            (circle[k].iter().zip(&circle[k + 1]))
                .map(|(a, b)| a + (b - a) * f)
                .collect(),
        );
    }
    for &k in &[0, n - 1, 0, 150, 149, 151, 150] {
        qs.push(circle[k].clone());
    }
    let robot = real();
    for (tolerance, batch) in [(1e-3, 1024), (1e-3, 3), (3e-4, 1024), (0.0, 1024)] {
        let crossings = tolerance_matches_exact(
            &robot,
            ClearanceGeometry::Mesh,
            PairFilter::NonAdjacent,
            &qs,
            tolerance,
            batch,
        );
        // the circle's first and last fixture poses (the arm folding into its start) intersect
        assert!(crossings <= 2, "{crossings} intersections");
    }
}

/// Samples queued and folded in together (the pairs in parallel, as a run's clearance worker
/// does when samples wait for it) give the report of the same samples added one by one, bit
/// for bit: each pair's minimum and time, and the closest pair overall when several pairs tie
/// (the Faze4 folding into itself, where pairs touch at the same samples), at the default
/// tolerance and exactly, with batches of waiting samples searched during the run.
#[test]
fn queued_samples_fold_in_as_one_by_one() {
    let robot = real();
    let (set, _) = CollisionSet::new(&robot.model, &robot.geometry, ClearanceGeometry::Mesh, PairFilter::All).unwrap();
    let qs = folding(40);
    let mut data = Data::new(&robot.model);
    for (tolerance, batch) in [(1e-3, 1024), (0.0, 5)] {
        let mut one_by_one = Clearance::with_tolerance(&set, tolerance).batch(batch);
        let mut queued = Clearance::with_tolerance(&set, tolerance).batch(batch);
        // queues of 1, 2, …, 9 samples (folded with the pairs in parallel from 8 on)
        let mut due = 1;
        for (k, q) in qs.iter().enumerate() {
            forward_kinematics(&robot.model, &mut data, q);
            one_by_one.add(&data.frame_pose, k as f64 * 0.04);
            queued.queue(&data.frame_pose, k as f64 * 0.04);
            if queued.queued() == due || k + 1 == qs.len() {
                queued.fold_queued();
                assert_eq!(queued.intersecting(), one_by_one.intersecting(), "sample {k}");
                due = due % 9 + 1;
            }
        }
        one_by_one.finish();
        queued.finish();
        let firsts: Vec<Option<f64>> = queued.first_intersections().collect();
        assert_eq!(firsts, one_by_one.first_intersections().collect::<Vec<_>>());
        assert!(firsts.iter().flatten().count() > 3, "{firsts:?}");
        assert_eq!(queued.into_report(), one_by_one.into_report());
    }
}

/// Runs that follow a path computed once (the commanded poses, as a sweep's rows share them),
/// each at its own poses, near the path or far from it: at every sample the intersecting
/// pairs are the full query's; each pair's minimum is the distance of two actual parts (not
/// below the full query at its time), at most `tolerance` above the smallest over the samples
/// (exactly that smallest at tolerance 0). `deviation` (rad) turns each joint by
/// `deviation · sin(0.3 k + i)` at sample k (a tracking error).
fn follower_matches_every_sample(
    robot: &Robot,
    set: &Arc<CollisionSet>,
    path: &PathClearance,
    qs: &[Vec<f64>],
    deviation: f64,
) {
    let tolerance = path.tolerance();
    let mut data = Data::new(&robot.model);
    let mut every = GeometryData::new(set);
    let mut run = Clearance::with_tolerance(set, tolerance).following(path);
    let mut every_sample = Vec::new();
    for (k, q) in qs.iter().enumerate() {
        let q: Vec<f64> = (q.iter().enumerate())
            .map(|(i, x)| x + deviation * (0.3 * k as f64 + i as f64).sin())
            .collect();
        forward_kinematics(&robot.model, &mut data, &q);
        set.distances(&data.frame_pose, &mut every);
        every_sample.push(every.distances.iter().map(|d| d.distance).collect::<Vec<f64>>());
        run.add(&data.frame_pose, path.times()[k]);
        let intersecting: Vec<bool> = every.distances.iter().map(|d| d.intersecting).collect();
        assert_eq!(run.intersecting(), intersecting, "deviation {deviation}, sample {k}");
    }
    run.finish();
    let report = run.into_report();
    for (p, pair) in report.pairs.iter().enumerate() {
        let least = every_sample.iter().map(|d| d[p]).fold(f64::INFINITY, f64::min);
        let k = path.times().iter().position(|&t| t == pair.t).unwrap();
        let at_t = every_sample[k][p];
        assert!(
            at_t <= pair.min_m + HULL_CERTIFICATE && pair.min_m <= least + tolerance + HULL_CERTIFICATE,
            "deviation {deviation} {:?}: {} at t = {} (full query there {at_t}), smallest {least}, tolerance {tolerance}",
            pair.links,
            pair.min_m,
            pair.t
        );
        if tolerance == 0.0 {
            assert!((pair.min_m - least).abs() <= 1e-12, "{:?}", pair.links);
        }
        assert_eq!(pair.intersecting, least <= 0.0, "{:?}", pair.links);
    }
}

/// A path's clearance computed once ([`PathClearance`]) and shared by runs that follow it:
/// on the Faze4 circle (mesh pairs whose hulls overlap, nearly concentric surfaces) and on the
/// arm folding into itself (intersections), at the default tolerance and exactly, for a run at
/// the path's own poses, runs a few milliradians off (a tracking error) and a run 0.2 rad off
/// (one that cannot follow, folded as without the path).
#[test]
fn runs_following_a_shared_path_keep_the_tolerance_and_the_exact_intersections() {
    let fixture = fixture("clearance_faze4_real.json");
    let circle: Vec<Vec<f64>> = fixture["poses"].as_array().unwrap()[90..150]
        .iter()
        .map(|p| vec_f64(&p["q"]))
        .collect();
    let robot = real();
    let (set, _) = CollisionSet::new(
        &robot.model,
        &robot.geometry,
        ClearanceGeometry::Mesh,
        PairFilter::NonAdjacent,
    )
    .unwrap();
    let set = Arc::new(set);
    let mut data = Data::new(&robot.model);
    for (qs, tolerance) in [(&circle, 1e-3), (&folding(60), 1e-3), (&circle, 0.0)] {
        let mut path = PathClearance::builder(set.clone(), tolerance);
        for (k, q) in qs.iter().enumerate() {
            forward_kinematics(&robot.model, &mut data, q);
            assert!(path.add(&data.frame_pose, k as f64 * 0.02));
        }
        let path = path.build();
        assert_eq!(path.len(), qs.len());
        assert!(path.bytes() <= faze4::geometry::MAX_PATH_BYTES);
        for deviation in [0.0, 1e-3, 4e-3, 0.2] {
            follower_matches_every_sample(&robot, &set, &path, qs, deviation);
        }
    }
}
