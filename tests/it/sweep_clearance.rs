//! A sweep's self-clearance columns against each row's exact run: the rows of a sweep that
//! varies the payload follow one commanded path's clearance, computed once
//! (`geometry::PathClearance`, docs/clearance.md "Sweeps"), and each row keeps the tolerance's
//! guarantee and its exact intersections.

use crate::common;

use common::*;
use serde_json::Value;

/// The rows of `faze4 sweep --vary payload-kg=VALUES --out t.json -- BASE…`, each beside the
/// summary of the same run alone (`BASE --payload-kg x`) at tolerance 0: the row's
/// `clearance_min_m` is not below the exact minimum (it is an actual distance) and at most
/// the row's tolerance above it; the closest pair's links are a pair as close; the verdict
/// and its reasons (the intersecting pairs, from when) are the exact run's. Returns how many
/// rows collide.
fn rows_match_their_exact_runs(dir: &std::path::Path, values: &str, base: &[&str]) -> usize {
    let vary = format!("payload-kg={values}");
    let sweep = faze4(
        dir,
        &[&["sweep", "--vary", &vary, "--out", "t.json", "-q", "--"], base].concat(),
    );
    assert!(sweep.status.success(), "{}", sweep.stderr);
    let rows: Vec<Value> = serde_json::from_str(&std::fs::read_to_string(dir.join("t.json")).unwrap()).unwrap();
    assert_eq!(rows.len(), values.split(',').count());
    let mut colliding = 0;
    for row in &rows {
        let payload = row["payload-kg"].as_f64().unwrap().to_string();
        let alone = faze4(
            dir,
            &[
                base,
                &[
                    "--payload-kg",
                    &payload,
                    "--clearance-tolerance",
                    "0",
                    "--summary",
                    "s.json",
                    "--trail",
                    "none",
                    "-q",
                ],
            ]
            .concat(),
        );
        assert!(
            alone.status.code().is_some_and(|c| c == 0 || c == 3),
            "{}",
            alone.stderr
        );
        let exact = summary(dir, "s.json");
        let (r, e) = (
            row["clearance_min_m"].as_f64().unwrap(),
            exact["clearance"]["min_m"].as_f64().unwrap(),
        );
        let tolerance = row["clearance_tolerance_m"].as_f64().unwrap();
        assert_eq!(tolerance, 1e-3, "the default");
        assert!(
            e <= r + 1e-9 && r <= e + tolerance + 1e-9,
            "payload {payload}: row {r}, exact {e}"
        );
        let reasons: Vec<&str> = (exact["verdict"]["reasons"].as_array().unwrap().iter())
            .map(|r| r.as_str().unwrap())
            .collect();
        assert_eq!(
            row["reasons"].as_str().unwrap(),
            reasons.join("; "),
            "payload {payload}"
        );
        assert_eq!(row["follows"], exact["verdict"]["follows"]);
        colliding += usize::from(exact["verdict"]["collides"] == true);
    }
    colliding
}

/// `faze4 sweep --own-clearance`: each row's clearance is the same run's alone at the same
/// (default) tolerance, to the bit.
#[test]
fn with_its_own_clearance_a_row_is_the_run_alone() {
    let dir = temp_dir("sweep-own-clearance");
    let base = ["shape", "--shape", "circle", "--duration", "2"];
    let sweep = faze4(
        &dir,
        &[
            &[
                "sweep",
                "--own-clearance",
                "--vary",
                "payload-kg=0,0.7",
                "--out",
                "t.json",
                "-q",
                "--",
            ],
            &base[..],
        ]
        .concat(),
    );
    assert!(sweep.status.success(), "{}", sweep.stderr);
    let rows: Vec<Value> = serde_json::from_str(&std::fs::read_to_string(dir.join("t.json")).unwrap()).unwrap();
    for row in &rows {
        let payload = row["payload-kg"].as_f64().unwrap().to_string();
        let extra = ["--payload-kg", &payload, "--summary", "s.json", "--trail", "none", "-q"];
        let alone = faze4(&dir, &[&base[..], &extra].concat());
        assert!(alone.status.success(), "{}", alone.stderr);
        let clearance = &summary(&dir, "s.json")["clearance"];
        assert_eq!(row["clearance_min_m"], clearance["min_m"], "payload {payload}");
        assert_eq!(row["clearance_t"], clearance["t"], "payload {payload}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The circle with payloads up to 0.9 kg (the runs follow: mesh pairs whose hulls overlap,
/// derived from the shared path), and the arm folding into itself (`wave --amp-deg 90`: the
/// runs cannot follow and their links intersect from the first sample).
#[test]
fn a_sweeps_clearance_is_within_the_tolerance_of_each_rows_exact_run_with_its_intersections() {
    let dir = temp_dir("sweep-clearance");
    let circle = ["shape", "--shape", "circle", "--duration", "3"];
    assert_eq!(rows_match_their_exact_runs(&dir, "0,0.5,0.9", &circle), 0);
    let folding = ["wave", "--amp-deg", "90", "--duration", "1"];
    assert_eq!(rows_match_their_exact_runs(&dir, "0,1.5", &folding), 2);
    std::fs::remove_dir_all(&dir).unwrap();
}
