//! Self-clearance over a whole run of the real binary against coal's exact minimum over the same
//! samples: `tests/fixtures/clearance_run_*.json`, written by
//! `tools/oracle/clearance_run_oracle.py` (coal 3.0.3 on the exact triangles, Pinocchio for the
//! poses), hold a run's arguments, its trail samples (the poses the clearance is measured at)
//! and per checked pair coal's exact minimum over them and whether it ever intersects.
//!
//! Each test reruns the binary with the fixture's arguments, at the default tolerance (1 mm) and
//! at `--clearance-tolerance 0`, and checks per pair, with R the summary's `min_m`, τ its
//! `tolerance_m` and E coal's minimum: `E ≤ R + slack` (R is the distance of two actual parts at
//! a sample), `R − τ ≤ E + slack` (the true minimum is at most τ below R), and that the pair
//! intersected exactly when coal finds it intersecting at some sample. At τ = 0 the two give
//! `|R − E| ≤ slack`. slack is the fixture's: 1e-9 m for meshes, boxes and spheres (coal's
//! triangle distances are closed-form, GJK is exact on polytopes), 1e-5 m for a pair with a
//! cylinder (GJK and EPA on curved shapes; docs/clearance.md). Two primitives with a cylinder
//! that intersect are checked for the intersection only (coal's depth there is not trusted).

use crate::common;

use common::*;
use serde_json::Value;

/// What one run was checked against: pairs, intersecting pairs, and the kinds of pair.
struct Checked {
    pairs: usize,
    intersecting: usize,
    kinds: Vec<String>,
}

/// Runs fixture `name`'s arguments with `--clearance-tolerance tolerance_mm` (`None`: the
/// default, 1 mm) and checks the summary's pairs against coal's exact minima.
fn check_run(name: &str, tolerance_mm: Option<&str>, expect_tolerance_m: f64) -> Checked {
    let fixture = fixture(&format!("clearance_run_{name}.json"));
    let dir = temp_dir(&format!(
        "clearance-run-oracle-{name}-{}",
        tolerance_mm.unwrap_or("default")
    ));
    // the fixture's paths are relative to the repository
    let mut args: Vec<String> = (fixture["args"].as_array().unwrap().iter())
        .map(|a| {
            let a = a.as_str().unwrap();
            let path = repo_path(a);
            if a.contains('/') && path.exists() {
                path.display().to_string()
            } else {
                a.to_string()
            }
        })
        .collect();
    args.extend(["--quiet", "--trail", "t.csv", "--summary", "s.json"].map(String::from));
    if let Some(t) = tolerance_mm {
        args.extend(["--clearance-tolerance".to_string(), t.to_string()]);
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let run = faze4(&dir, &args);
    assert!(run.status.success(), "faze4 {args:?}: {}", run.stderr);

    // the samples: the trail's rows are the poses the clearance was measured at
    let (header, rows) = read_csv(&dir.join("t.csv"));
    let q_cols: Vec<usize> = (header.iter().enumerate())
        .filter(|(_, h)| h.starts_with('q') && h[1..].parse::<usize>().is_ok())
        .map(|(i, _)| i)
        .collect();
    let (fixture_t, fixture_q) = (vec_f64(&fixture["t"]), mat_f64(&fixture["q"]));
    assert_eq!(rows.len(), fixture_q.len(), "{name}: trail rows");
    for ((row, t), q) in rows.iter().zip(&fixture_t).zip(&fixture_q) {
        let ours: Vec<f64> = q_cols.iter().map(|&i| row[i]).collect();
        assert!(
            (row[0] - t).abs() < 1e-12 && max_abs_diff(&ours, q) <= 1e-9,
            "{name}: the run's samples are not the fixture's at t = {t} (regenerate with clearance_run_oracle.py --fixtures)"
        );
    }

    let text = std::fs::read_to_string(dir.join("s.json")).unwrap();
    let summary: Value = serde_json::from_str(&text).unwrap();
    let clearance = &summary["clearance"];
    let tau = clearance["tolerance_m"].as_f64().unwrap();
    assert_eq!(tau, expect_tolerance_m, "{name}: tolerance_m");
    let ours = clearance["pairs"].as_array().unwrap();
    let exact = fixture["pairs"].as_array().unwrap();
    assert_eq!(ours.len(), exact.len(), "{name}: the checked pairs");
    let (mut intersecting, mut kinds) = (0, Vec::new());
    for (p, e) in ours.iter().zip(exact) {
        assert_eq!(p["links"], e["links"], "{name}: the checked pairs, in order");
        let r = p["min_m"].as_f64().unwrap();
        let slack = e["slack_m"].as_f64().unwrap();
        let faze4_hits = p.get("intersecting").and_then(Value::as_bool).unwrap_or(false);
        let coal_hits = e["intersecting"].as_bool().unwrap();
        let what = format!(
            "{name}, tolerance {tau} m, {} {} ({}): faze4 {r}, coal {} at t = {}",
            e["links"], e["shapes"], e["kind"], e["exact_min_m"], e["exact_t"]
        );
        assert_eq!(faze4_hits, coal_hits, "{what}: intersecting");
        match e["exact_min_m"].as_f64() {
            Some(min) => {
                assert!(
                    min <= r + slack,
                    "{what}: below coal's exact minimum, not an actual distance"
                );
                assert!(
                    r - tau <= min + slack,
                    "{what}: more than the tolerance above the exact minimum"
                );
            }
            // two primitives with a cylinder that intersect: coal's penetration depth is not
            // trusted (the script's docstring), only that they intersect
            None => assert!(coal_hits && r <= 0.0, "{what}"),
        }
        intersecting += usize::from(coal_hits);
        let kind = e["kind"].as_str().unwrap().to_string();
        if !kinds.contains(&kind) {
            kinds.push(kind);
        }
    }
    Checked {
        pairs: ours.len(),
        intersecting,
        kinds,
    }
}

/// Both tolerances of one fixture; the kinds of pair it covers and its intersecting pairs.
fn check_both(name: &str) -> Checked {
    let default = check_run(name, None, 1e-3);
    let exact = check_run(name, Some("0"), 0.0);
    assert_eq!((default.pairs, default.intersecting), (exact.pairs, exact.intersecting));
    exact
}

/// Mesh pairs: the Faze4's official meshes through a 2 s `faze4 wave` (and its base cylinder
/// against them), none intersecting.
#[test]
fn mesh_pairs_are_within_the_tolerance_of_coals_exact_minimum_over_the_run() {
    let c = check_both("faze4_wave");
    assert!(c.kinds.contains(&"mesh-mesh".to_string()), "{:?}", c.kinds);
    assert_eq!(c.intersecting, 0);
    assert!(c.pairs >= 10, "{} pairs", c.pairs);
}

/// Primitive pairs: our box/cylinder/sphere arm (`tests/urdf/collision_arm.urdf`, every pair)
/// through a 60° wave; some pairs overlap (signed distances, penetration depths).
#[test]
fn primitive_pairs_are_within_the_tolerance_of_coals_exact_minimum_over_the_run() {
    let c = check_both("collision_arm");
    assert_eq!(c.kinds, ["primitive-primitive"]);
    assert!(c.intersecting > 0);
}

/// Intersecting pairs: the Faze4 folding into itself (a 90° wave at 2 rad/s): meshes that cross
/// and the base cylinder inside meshes; faze4's intersecting pairs are coal's.
#[test]
fn intersecting_pairs_are_coals_over_the_run() {
    let c = check_both("faze4_fold");
    assert!(c.intersecting >= 5, "{} intersecting pairs", c.intersecting);
    assert!(c.kinds.contains(&"mesh-mesh".to_string()) && c.kinds.contains(&"mesh-primitive".to_string()));
}
