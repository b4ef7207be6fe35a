//! Self-clearance on runs of the real binary: the summary's `"clearance"` equals the library's
//! [`ClearanceReport`] over the same trail samples (read back from the trail CSV), the terminal
//! line, the verdict "collides" and `--strict`, the options (`--collision-geometry`,
//! `--collision-pairs all`, `--no-collisions`), and the answers to missing and unreadable
//! meshes; on the Faze4 and on arms of our own (`tests/urdf/collision_arm.urdf`,
//! `tests/urdf/clashing_arm.urdf`).

use crate::common;

use std::path::Path;

use common::*;
use faze4::algo::{Data, forward_kinematics};
use faze4::geometry::{Clearance, ClearanceGeometry, ClearanceReport, CollisionSet, PairFilter, Robot};
use faze4::model::PackagePaths;
use serde_json::Value;

/// The library's report for `robot` over the samples of a trail CSV (t and the joint
/// positions q1…qn of every row, exact decimals), as `kind` and `filter` measure it, and the
/// time of the first sample at which any pair intersects.
fn library_run(
    robot: &Robot,
    kind: ClearanceGeometry,
    filter: PairFilter,
    tolerance: f64,
    trail: &Path,
) -> (ClearanceReport, Option<f64>) {
    let (set, _) = CollisionSet::new(&robot.model, &robot.geometry, kind, filter).unwrap();
    let (header, rows) = read_csv(trail);
    let q_columns: Vec<usize> = (1..=robot.model.dof())
        .map(|i| header.iter().position(|h| *h == format!("q{i}")).unwrap())
        .collect();
    let mut data = Data::new(&robot.model);
    let mut clearance = Clearance::with_tolerance(&set, tolerance);
    let mut first = None;
    for row in &rows {
        let q: Vec<f64> = q_columns.iter().map(|&c| row[c]).collect();
        forward_kinematics(&robot.model, &mut data, &q);
        clearance.add(&data.frame_pose, row[0]);
        if first.is_none() && clearance.intersecting().contains(&true) {
            first = Some(row[0]);
        }
    }
    clearance.finish();
    let report = clearance.into_report();
    (report, first)
}

/// A run of the binary whose clearance was checked against the library's.
struct Checked {
    run: Run,
    /// Its summary.
    summary: Value,
    /// The library's report over its trail.
    report: ClearanceReport,
    /// The library's first sample with an intersecting pair.
    first: Option<f64>,
}

/// Runs faze4 with `args` in `dir` (they write the trail to t.csv and the summary to s.json),
/// checks that it succeeded and that the summary's `"clearance"` equals the library's report
/// for `robot` over the run's trail samples, as `kind` and `filter` measure them.
fn run_as_library(dir: &Path, args: &[&str], robot: &Robot, kind: ClearanceGeometry, filter: PairFilter) -> Checked {
    let run = faze4(dir, args);
    assert!(run.status.success(), "{}", run.stderr);
    let summary = summary(dir, "s.json");
    let tolerance = summary["clearance"]["tolerance_m"].as_f64().unwrap();
    let (report, first) = library_run(robot, kind, filter, tolerance, &dir.join("t.csv"));
    assert_eq!(summary["clearance"], serde_json::to_value(&report).unwrap());
    Checked {
        run,
        summary,
        report,
        first,
    }
}

/// The closest pair of shapes of links `a`, `b` (either order; a link may have several) in a
/// summary's clearance.
fn pair<'a>(clearance: &'a Value, a: &str, b: &str) -> &'a Value {
    (clearance["pairs"].as_array().unwrap().iter())
        .filter(|p| {
            let links = [p["links"][0].as_str().unwrap(), p["links"][1].as_str().unwrap()];
            links == [a, b] || links == [b, a]
        })
        .min_by(|p, q| p["min_m"].as_f64().unwrap().total_cmp(&q["min_m"].as_f64().unwrap()))
        .unwrap_or_else(|| panic!("no pair {a}–{b} in {clearance}"))
}

/// The one stdout line starting with `prefix`.
fn line<'a>(stdout: &'a str, prefix: &str) -> &'a str {
    let lines: Vec<&str> = stdout.lines().filter(|l| l.starts_with(prefix)).collect();
    assert_eq!(lines.len(), 1, "one '{prefix}' line in:\n{stdout}");
    lines[0]
}

fn collision_arm() -> String {
    repo_path("tests/urdf/collision_arm.urdf").display().to_string()
}

/// The Faze4 circle with the exact meshes (the default): the real meshes never touch, the
/// closest pair is podlaktica–hvataljka at about 18.85 mm, nadlaktica–podlaktica stay at
/// least 21.36 mm apart (the issue's figures, Drake/coal); the summary is the library's report
/// over the trail's samples, bit for bit.
#[test]
fn the_faze4_circle_with_exact_meshes_clears_itself() {
    let dir = temp_dir("clearance-exact");
    let args = [
        "shape",
        "--shape",
        "circle",
        "--duration",
        "5",
        "--trail",
        "t.csv",
        "--summary",
        "s.json",
    ];
    let Checked { run, summary: s, .. } = run_as_library(
        &dir,
        &args,
        &Robot::faze4(),
        ClearanceGeometry::Mesh,
        PairFilter::NonAdjacent,
    );
    let c = &s["clearance"];
    assert_eq!(c["geometry"], "mesh");
    assert_eq!(c["links"], serde_json::json!(["podlaktica", "hvataljka"]));
    let min = c["min_m"].as_f64().unwrap();
    assert!((min - 0.01885).abs() < 5e-5, "closest {min} m");
    assert!(pair(c, "nadlaktica", "podlaktica")["min_m"].as_f64().unwrap() >= 0.02136 - 5e-5);
    assert!(
        c["pairs"]
            .as_array()
            .unwrap()
            .iter()
            .all(|p| p.get("intersecting").is_none())
    );
    assert_eq!(c["unchecked"], serde_json::json!([]));
    assert_eq!(s["verdict"]["collides"], false);
    let t = c["t"].as_f64().unwrap();
    // the default tolerance, stated with the bound it gives the true minimum
    let tolerance = c["tolerance_m"].as_f64().unwrap();
    assert_eq!(tolerance, faze4::sim::DEFAULT_CLEARANCE_TOLERANCE_M);
    assert_eq!(
        line(&run.stdout, "self-clearance"),
        format!(
            "self-clearance (meshes, tolerance {:.2} mm): 'podlaktica'–'hvataljka' {:.2} mm at t = {t:.2} s (true minimum ≥ {:.2} mm)",
            tolerance * 1e3,
            min * 1e3,
            (min - tolerance) * 1e3
        )
    );
    assert_eq!(run.stdout.lines().last(), Some("verdict: follows"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The same circle with convex hulls: the hulls of nadlaktica and podlaktica overlap by
/// 3.08–3.24 mm at every sample, so the run collides from t = 0 (and `--strict` exits 3);
/// `--quiet` keeps only the verdict.
#[test]
fn the_faze4_circle_with_hulls_collides() {
    let dir = temp_dir("clearance-hull");
    let args = [
        "shape",
        "--shape",
        "circle",
        "--duration",
        "5",
        "--collision-geometry",
        "hull",
        "--trail",
        "t.csv",
        "--summary",
        "s.json",
    ];
    let Checked { run, summary: s, .. } = run_as_library(
        &dir,
        &args,
        &Robot::faze4(),
        ClearanceGeometry::Hull,
        PairFilter::NonAdjacent,
    );
    let c = &s["clearance"];
    assert_eq!(c["geometry"], "hull");
    assert_eq!(c["links"], serde_json::json!(["nadlaktica", "podlaktica"]));
    let overlap = pair(c, "nadlaktica", "podlaktica");
    let min = overlap["min_m"].as_f64().unwrap();
    assert!((-0.00324 - 5e-6..=-0.00308 + 5e-6).contains(&min), "{min}");
    assert_eq!(overlap["intersecting"], true);
    let intersecting: Vec<&Value> = (c["pairs"].as_array().unwrap().iter())
        .filter(|p| p.get("intersecting").is_some())
        .collect();
    assert_eq!(intersecting.len(), 1, "{c}");
    assert_eq!(s["verdict"]["follows"], false);
    assert_eq!(s["verdict"]["collides"], true);
    let verdict = "verdict: collides — 'nadlaktica'–'podlaktica' intersect from t = 0.00 s";
    assert_eq!(s["verdict"]["reasons"][0], verdict["verdict: collides — ".len()..]);
    assert_eq!(run.stdout.lines().last(), Some(verdict));
    assert!(
        line(&run.stdout, "self-clearance").starts_with(&format!(
            "self-clearance (convex hulls, tolerance 1.00 mm): 'nadlaktica'–'podlaktica' {:.2} mm at t = ",
            min * 1e3
        )),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("· intersecting: 'nadlaktica'–'podlaktica' from t = 0.00 s")
    );

    let quiet = faze4(&dir, &[&args[..], &["--quiet", "--strict"]].concat());
    assert_eq!(quiet.status.code(), Some(3), "{}", quiet.stderr);
    assert_eq!(quiet.stdout.trim_end(), verdict);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Our own arm of boxes, cylinders and spheres: the turret's cylinder dips into the base's
/// column, a pair a joint connects: checked only with `--collision-pairs all`, which then
/// collides; `--no-collisions` has no clearance at all.
#[test]
fn collision_pairs_all_checks_the_pairs_a_joint_connects() {
    let dir = temp_dir("clearance-pairs");
    let urdf = collision_arm();
    let base = [
        "wave",
        "--urdf",
        urdf.as_str(),
        "--duration",
        "2",
        "--trail",
        "t.csv",
        "--summary",
        "s.json",
    ];
    let robot = Robot::from_urdf_file(Path::new(&urdf), &PackagePaths::default()).unwrap();

    let Checked {
        summary: s,
        report: expected,
        ..
    } = run_as_library(&dir, &base, &robot, ClearanceGeometry::Mesh, PairFilter::NonAdjacent);
    let default_pairs = s["clearance"]["pairs"].as_array().unwrap().len();
    assert!(!expected.any_intersecting(), "{}", s["clearance"]);
    assert_eq!(s["verdict"]["collides"], false);

    let all = [&base[..], &["--collision-pairs", "all"]].concat();
    let Checked { run, summary: s, .. } = run_as_library(&dir, &all, &robot, ClearanceGeometry::Mesh, PairFilter::All);
    assert!(s["clearance"]["pairs"].as_array().unwrap().len() > default_pairs);
    assert_eq!(pair(&s["clearance"], "base", "turret")["intersecting"], true);
    assert_eq!(s["verdict"]["collides"], true);
    let verdict = run.stdout.lines().last().unwrap();
    assert!(
        verdict.starts_with("verdict: collides — 'base'–'turret' intersect from t = 0.00 s"),
        "{verdict}"
    );
    // upper and forearm intersect with two pairs of shapes: named once
    assert_eq!(verdict.matches("'upper'–'forearm'").count(), 1, "{verdict}");

    let run = faze4(&dir, &[&base[..], &["--no-collisions"]].concat());
    assert!(run.status.success(), "{}", run.stderr);
    let s = summary(&dir, "s.json");
    assert!(s.get("clearance").is_none(), "{s}");
    assert_eq!(s["verdict"]["collides"], false);
    assert!(!run.stdout.contains("self-clearance"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An arm of our own whose forearm folds down into its base plate in the middle of a replay:
/// the pair intersects from the first sample that crosses, which the verdict names; exact
/// and hull runs agree (primitives are exact in both readings).
#[test]
fn a_motion_that_folds_the_arm_into_itself_collides_from_when_it_does() {
    let dir = temp_dir("clearance-fold");
    let urdf = repo_path("tests/urdf/clashing_arm.urdf").display().to_string();
    // j1 still, j2 from 0 to 1.6 rad and back over 4 s: past about 0.73 rad the forearm
    // reaches the base plate
    let frames: Vec<Vec<f64>> = (0..=40)
        .map(|k| {
            let x = k as f64 / 40.0;
            vec![0.0, 1.6 * (std::f64::consts::PI * x).sin()]
        })
        .collect();
    let npy = dir.join("fold.npy");
    faze4::traj::npy::write_samples(&npy, &frames).unwrap();
    let args = [
        "replay",
        "--urdf",
        urdf.as_str(),
        "--q-traj",
        "fold.npy",
        "--traj-period",
        "4",
        "--duration",
        "4",
        "--no-gravity",
        "--trail",
        "t.csv",
        "--summary",
        "s.json",
    ];
    let robot = Robot::from_urdf_file(Path::new(&urdf), &PackagePaths::default()).unwrap();
    let Checked {
        run, summary: s, first, ..
    } = run_as_library(&dir, &args, &robot, ClearanceGeometry::Mesh, PairFilter::NonAdjacent);
    let clash = pair(&s["clearance"], "base", "forearm");
    assert_eq!(clash["intersecting"], true, "{}", s["clearance"]);
    assert!(clash["min_m"].as_f64().unwrap() < 0.0, "primitives: signed distances");
    let (header, rows) = read_csv(&dir.join("t.csv"));
    let q2 = header.iter().position(|h| h == "q2").unwrap();
    assert!(rows[0][q2].abs() < 1e-3, "the run starts folded out");
    let reason = s["verdict"]["reasons"][0].as_str().unwrap();
    assert!(reason.starts_with("'base'–'forearm' intersect from t = "), "{reason}");
    let from: f64 = reason["'base'–'forearm' intersect from t = ".len()..]
        .trim_end_matches(" s")
        .parse()
        .unwrap();
    assert!(from > 0.2 && from < 2.0, "{reason}");
    // the first trail sample at which the library sees the pair intersect
    assert_eq!(format!("{:.2}", first.unwrap()), format!("{from:.2}"), "{reason}");
    assert_eq!(line(&run.stdout, "verdict"), format!("verdict: collides — {reason}"));

    let hull = faze4(&dir, &[&args[..], &["--collision-geometry", "hull"]].concat());
    assert!(hull.status.success(), "{}", hull.stderr);
    let h = summary(&dir, "s.json");
    assert_eq!(
        h["clearance"]["pairs"], s["clearance"]["pairs"],
        "primitives read the same either way"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `collision_arm` with a mesh collision added on `hand` (`uri`), written into `dir`.
fn arm_with_mesh(dir: &Path, uri: &str) -> String {
    let text = std::fs::read_to_string(repo_path("tests/urdf/collision_arm.urdf")).unwrap();
    let claw = format!(
        r#"<collision><origin xyz="0.15 0 0"/><geometry><mesh filename="{uri}" scale="0.001 0.001 0.001"/></geometry></collision>
  </link>
</robot>"#
    );
    let at = text.rfind("</link>").unwrap();
    let path = dir.join("arm_with_mesh.urdf");
    std::fs::write(&path, format!("{}{claw}\n", &text[..at])).unwrap();
    path.display().to_string()
}

/// A collision mesh not found: one warning line naming it and `--package-path`, the run goes
/// on without it, the summary lists its link under `"unchecked"`; `--no-collisions` does not
/// even look for it.
#[test]
fn a_missing_mesh_is_one_warning_and_an_unchecked_link() {
    let models = temp_dir("clearance-missing-models");
    let urdf = arm_with_mesh(&models, "package://no_such_package/meshes/claw.STL");
    let dir = temp_dir("clearance-missing");
    let args = [
        "wave",
        "--urdf",
        urdf.as_str(),
        "--duration",
        "0.5",
        "--trail",
        "none",
        "--summary",
        "s.json",
    ];
    let run = faze4(&dir, &args);
    assert!(run.status.success(), "{}", run.stderr);
    let warnings: Vec<&str> = run.stderr.lines().filter(|l| l.contains("claw.STL")).collect();
    assert_eq!(warnings.len(), 1, "{}", run.stderr);
    assert!(warnings[0].starts_with("faze4: warning: "), "{}", warnings[0]);
    for part in ["package://no_such_package/meshes/claw.STL", "--package-path", "hand"] {
        assert!(warnings[0].contains(part), "{} should name {part}", warnings[0]);
    }
    let s = summary(&dir, "s.json");
    assert_eq!(s["clearance"]["unchecked"], serde_json::json!(["hand"]));
    assert!(
        line(&run.stdout, "self-clearance").ends_with(" · not checked: hand"),
        "{}",
        run.stdout
    );
    // the hand's primitives are checked still: the pairs are those of the arm without the mesh
    let plain = faze4(
        &dir,
        &[
            "wave",
            "--urdf",
            &collision_arm(),
            "--duration",
            "0.5",
            "--trail",
            "none",
            "--summary",
            "s.json",
        ],
    );
    assert!(plain.status.success());
    assert_eq!(summary(&dir, "s.json")["clearance"]["pairs"], s["clearance"]["pairs"]);

    let off = faze4(&dir, &[&args[..], &["--no-collisions"]].concat());
    assert!(off.status.success(), "{}", off.stderr);
    assert!(!off.stderr.contains("claw"), "{}", off.stderr);
    assert!(summary(&dir, "s.json").get("clearance").is_none());

    // a sweep reads the meshes once and says so once, whatever its number of runs; a warning
    // that changes the result (a link left unchecked) is printed under --quiet too (issue 21)
    let base = ["wave", "--urdf", urdf.as_str(), "--duration", "0.2", "--trail", "none"];
    let sweep = |extra: &[&str]| {
        let words = [
            &["sweep", "--vary", "payload-kg=0,0.5,1", "--out", "table.csv"],
            extra,
            &["--"],
            &base[..],
        ];
        let run = faze4(&dir, &words.concat());
        assert!(run.status.success(), "{}", run.stderr);
        run.stderr.lines().filter(|l| l.contains("claw.STL")).count()
    };
    assert_eq!(sweep(&[]), 1);
    assert_eq!(sweep(&["--quiet"]), 1);
    let mut table = csv::Reader::from_path(dir.join("table.csv")).unwrap();
    let column = table
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == "clearance_unchecked_1");
    let column = column.expect("an unchecked column");
    let unchecked: Vec<String> = (table.records()).map(|r| r.unwrap()[column].to_string()).collect();
    assert_eq!(unchecked, ["hand"; 3]);
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_dir_all(&models).unwrap();
}

/// A collision mesh that is found but cannot be read: one error line naming the file, exit
/// 2, nothing written; `--no-collisions` runs without reading it.
#[test]
fn an_unreadable_mesh_is_an_error_naming_it() {
    let models = temp_dir("clearance-unreadable-models");
    std::fs::write(
        models.join("claw.stl"),
        b"solid claw\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0",
    )
    .unwrap();
    let urdf = arm_with_mesh(&models, "claw.stl");
    let dir = temp_dir("clearance-unreadable");
    let claw = models.join("claw.stl").display().to_string();
    refuses(
        &dir,
        &["wave", "--urdf", &urdf, "--summary", "s.json", "--duration", "0.5"],
        &[&claw],
    );
    let off = faze4(
        &dir,
        &[
            "wave",
            "--urdf",
            &urdf,
            "--duration",
            "0.5",
            "--trail",
            "none",
            "--no-collisions",
        ],
    );
    assert!(off.status.success(), "{}", off.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_dir_all(&models).unwrap();
}

/// `--no-collisions` refuses the options it makes meaningless.
#[test]
fn no_collisions_refuses_collision_options() {
    let dir = temp_dir("clearance-conflict");
    refuses(
        &dir,
        &[
            "wave",
            "--no-collisions",
            "--collision-geometry",
            "hull",
            "--duration",
            "0.1",
        ],
        &["--no-collisions", "--collision-geometry"],
    );
    refuses(&dir, &["wave", "--collision-pairs", "some"], &["--collision-pairs"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
