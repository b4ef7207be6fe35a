//! `faze4 sweep` through the real binary: rows equal single runs bit for bit, shards merge to
//! the whole sweep, the search's answer agrees with single runs, and bad input is one line and
//! exit 2. Only the tests of rows against single runs measure self-clearance (its cost on the
//! Faze4's exact meshes is seconds per run in a debug build); the others pass `--no-collisions`.

use crate::common;

use std::collections::HashMap;
use std::path::Path;

use common::*;
use serde_json::Value;

/// A table as its header and rows of text cells (the `csv` crate: reasons may be quoted).
fn read_table(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = reader.headers().unwrap().iter().map(str::to_string).collect();
    let rows = reader
        .records()
        .map(|r| r.unwrap().iter().map(str::to_string).collect())
        .collect();
    (header, rows)
}

/// Row `row` of a table as column → cell.
fn named<'a>(header: &'a [String], row: &'a [String]) -> HashMap<&'a str, &'a str> {
    header
        .iter()
        .map(String::as_str)
        .zip(row.iter().map(String::as_str))
        .collect()
}

fn ok(run: &Run) {
    assert!(
        run.status.success(),
        "status {:?}\nstdout: {}\nstderr: {}",
        run.status,
        run.stdout,
        run.stderr
    );
}

/// Runs `base` once per row of a sweep over it with `vary`, each as a single run with the
/// row's values as options and `--summary`, and checks that every figure of the row is the
/// summary's, bit for bit.
fn rows_equal_single_runs(name: &str, vary: &[&str], base: &[&str]) {
    let dir = temp_dir(name);
    let mut args = vec!["sweep", "--out", "table.csv"];
    for v in vary {
        args.extend(["--vary", v]);
    }
    args.push("--");
    args.extend(base);
    ok(&faze4(&dir, &args));
    let (header, rows) = read_table(&dir.join("table.csv"));
    let axes: Vec<&str> = vary.iter().map(|v| v.split('=').next().unwrap()).collect();
    assert!(rows.len() >= 2, "{name}: {} rows", rows.len());
    let mut compared = 0;
    for row in &rows {
        let cells = named(&header, row);
        let mut single: Vec<String> = base.iter().map(|s| s.to_string()).collect();
        for axis in &axes {
            single.extend([format!("--{axis}"), cells[axis].to_string()]);
        }
        single.extend([
            "--summary".into(),
            "s.json".into(),
            "--trail".into(),
            "none".into(),
            "-q".into(),
        ]);
        let run = faze4(&dir, &single.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(
            run.status.code() == Some(0) || run.status.code() == Some(1),
            "{single:?}: {}",
            run.stderr
        );
        let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
        assert_eq!(
            cells["follows"],
            summary["verdict"]["follows"].to_string(),
            "{single:?}"
        );
        assert_eq!(
            cells["diverged"],
            (!summary["diverged"].is_null()).to_string(),
            "{single:?}"
        );
        let reasons: Vec<&str> = summary["verdict"]["reasons"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r.as_str().unwrap())
            .collect();
        assert_eq!(cells["reasons"], reasons.join("; "));
        let mut figures = vec!["steps".to_string()];
        for field in [
            "max_tracking_error_rad",
            "saturation_pct",
            "kp",
            "kd",
            "effort",
            "effective_inertia",
        ] {
            let n = summary[field].as_array().unwrap().len();
            figures.extend((1..=n).map(|j| format!("{field}_{j}")));
        }
        if summary.get("path_deviation_mm").is_some() {
            figures.extend(["path_deviation_mm_max".into(), "path_deviation_mm_mean".into()]);
        }
        for figure in &figures {
            let (field, index) = match figure.rsplit_once('_') {
                Some((f, j)) if j.parse::<usize>().is_ok() && summary.get(f).is_some() => {
                    (f, Some(j.parse::<usize>().unwrap() - 1))
                }
                _ => (figure.as_str(), None),
            };
            let expected = match (field, index) {
                ("path_deviation_mm_max", _) => &summary["path_deviation_mm"]["max"],
                ("path_deviation_mm_mean", _) => &summary["path_deviation_mm"]["mean"],
                (f, Some(j)) => &summary[f][j],
                (f, None) => &summary[f],
            };
            let cell = cells
                .get(figure.as_str())
                .unwrap_or_else(|| panic!("{name}: no column {figure}"));
            match expected.as_f64() {
                Some(x) => assert_eq!(
                    cell.parse::<f64>().unwrap().to_bits(),
                    x.to_bits(),
                    "{single:?}: {figure} {cell} vs {x}"
                ),
                None => assert_eq!(*cell, "", "{single:?}: {figure} (unlimited)"),
            }
            compared += 1;
        }
        // the self-clearance: the closest pair, its distance and time; the per-pair list
        // stays in the summary
        assert!(!header.iter().any(|h| h.starts_with("clearance_pairs")), "{header:?}");
        if let Some(c) = summary.get("clearance") {
            for key in ["min_m", "t"] {
                let cell = cells[format!("clearance_{key}").as_str()];
                assert_eq!(
                    cell.parse::<f64>().unwrap().to_bits(),
                    c[key].as_f64().unwrap().to_bits(),
                    "{single:?}: clearance_{key}"
                );
            }
            assert_eq!(cells["clearance_geometry"], c["geometry"].as_str().unwrap());
            assert_eq!(cells["clearance_links_1"], c["links"][0].as_str().unwrap());
            assert_eq!(cells["clearance_links_2"], c["links"][1].as_str().unwrap());
            compared += 1;
        }
    }
    assert!(compared > 20 * rows.len(), "{name}: compared {compared} figures");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_wave_sweeps_rows_equal_its_single_runs() {
    rows_equal_single_runs(
        "wave",
        &["payload-kg=0:1.5:0.75", "freq=0.5,2"],
        &["wave", "--duration", "1"],
    );
}

#[test]
fn a_shape_sweeps_rows_equal_its_single_runs() {
    rows_equal_single_runs(
        "shape",
        &["payload-kg=0,1.2", "dt=2e-4,5e-4"],
        &["shape", "--shape", "circle", "--duration", "1"],
    );
}

/// With the convex hulls every run collides (nadlaktica and podlaktica): `follows` false, the
/// reasons and the clearance columns those of the single runs.
#[test]
fn a_hull_sweeps_clearance_equals_its_single_runs() {
    rows_equal_single_runs(
        "hull",
        &["payload-kg=0,1.2"],
        &[
            "shape",
            "--shape",
            "circle",
            "--duration",
            "1",
            "--collision-geometry",
            "hull",
        ],
    );
}

/// `--self-collisions` in a sweep: the runs share the sweep's collision set (loaded once)
/// and their rows are the single runs', contact included (the hulls touch, so the contact
/// forces change the motion).
#[test]
fn a_sweep_with_self_collisions_equals_its_single_runs() {
    rows_equal_single_runs(
        "self_collisions",
        &["payload-kg=0:0.2:0.1"],
        &[
            "shape",
            "--shape",
            "circle",
            "--duration",
            "2",
            "--collision-geometry",
            "hull",
            "--self-collisions",
        ],
    );
}

#[test]
fn a_sweep_of_an_arm_of_our_own_equals_its_single_runs() {
    let urdf = repo_path("tests/urdf/arm_prismatic.urdf");
    rows_equal_single_runs(
        "own_arm",
        &["amp-deg=2:8:3", "dt=1e-3,2e-4"],
        &["wave", "--urdf", urdf.to_str().unwrap(), "--duration", "1"],
    );
}

#[test]
fn merged_shards_equal_the_whole_sweep() {
    let dir = temp_dir("shards");
    let sweep = |extra: &[&str]| {
        let mut args = vec!["sweep", "--vary", "payload-kg=0:2:0.25", "--vary", "freq=0.5,1.5", "-q"];
        args.extend(extra);
        args.extend(["--", "wave", "--duration", "0.5", "--no-collisions"]);
        ok(&faze4(&dir, &args));
    };
    sweep(&["--out", "whole.csv"]);
    for k in 1..=4 {
        sweep(&["--shard", &format!("{k}/4"), "--out", &format!("part{k}.csv")]);
    }
    // the parts in any order
    ok(&faze4(
        &dir,
        &[
            "sweep",
            "merge",
            "part3.csv",
            "part1.csv",
            "part4.csv",
            "part2.csv",
            "--out",
            "all.csv",
        ],
    ));
    let (whole_header, whole) = read_table(&dir.join("whole.csv"));
    let (merged_header, merged) = read_table(&dir.join("all.csv"));
    assert_eq!(whole_header, merged_header);
    assert_eq!(whole.len(), 18);
    assert_eq!(merged.len(), whole.len());
    // wall-clock times (wall_time_s, clearance_wall_time_s) differ from run to run
    let wall: Vec<usize> = (whole_header.iter().enumerate())
        .filter(|(_, h)| h.ends_with("wall_time_s"))
        .map(|(i, _)| i)
        .collect();
    assert!(!wall.is_empty(), "a wall_time_s column");
    let mut shard_sizes: Vec<usize> = (1..=4)
        .map(|k| read_table(&dir.join(format!("part{k}.csv"))).1.len())
        .collect();
    shard_sizes.sort();
    assert_eq!(shard_sizes, [4, 4, 5, 5]);
    for (a, b) in whole.iter().zip(&merged) {
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            if !wall.contains(&i) {
                assert_eq!(x, y, "column {}", whole_header[i]);
            }
        }
    }
    // the parts as JSON merge to the same table, written as JSON or CSV by --out's extension
    for k in 1..=4 {
        sweep(&["--shard", &format!("{k}/4"), "--out", &format!("part{k}.json")]);
    }
    ok(&faze4(
        &dir,
        &[
            "sweep",
            "merge",
            "part1.json",
            "part2.csv",
            "part3.json",
            "part4.json",
            "--out",
            "all.json",
        ],
    ));
    ok(&faze4(
        &dir,
        &[
            "sweep",
            "merge",
            "part1.json",
            "part2.json",
            "part3.json",
            "part4.json",
            "--out",
            "all2.csv",
        ],
    ));
    let (json_csv_header, json_csv) = read_table(&dir.join("all2.csv"));
    assert_eq!(json_csv_header, whole_header);
    ok(&faze4(
        &dir,
        &[
            "sweep",
            "--vary",
            "payload-kg=0:2:0.25",
            "--vary",
            "freq=0.5,1.5",
            "-q",
            "--out",
            "whole.json",
            "--",
            "wave",
            "--duration",
            "0.5",
            "--no-collisions",
        ],
    ));
    let whole_json: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("whole.json")).unwrap()).unwrap();
    let merged_json: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("all.json")).unwrap()).unwrap();
    let (whole_json, merged_json) = (whole_json.as_array().unwrap(), merged_json.as_array().unwrap());
    assert_eq!(merged_json.len(), 18);
    for (a, b) in whole_json.iter().zip(merged_json) {
        let (a, b) = (a.as_object().unwrap(), b.as_object().unwrap());
        assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
        for (key, x) in a {
            if !key.ends_with("wall_time_s") {
                assert_eq!(x, &b[key], "{key}");
            }
        }
    }
    for (a, b) in whole.iter().zip(&json_csv) {
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            if !wall.contains(&i) {
                assert_eq!(x, y, "column {}", whole_header[i]);
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `merge` with `args` refuses: exit 2, one line naming `expected`, no output written.
fn merge_refuses(dir: &Path, args: &[&str], expected: &[&str]) {
    let mut all = vec!["sweep", "merge"];
    all.extend(args);
    all.extend(["--out", "refused.csv"]);
    let run = faze4(dir, &all);
    assert_eq!(run.status.code(), Some(2), "{args:?}: {}{}", run.stdout, run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{args:?}: {}", run.stderr);
    for e in expected {
        assert!(run.stderr.contains(e), "{args:?}: {:?} should say {e:?}", run.stderr);
    }
    assert!(!dir.join("refused.csv").exists() && !dir.join("refused.csv.meta").exists());
}

/// The five parts of a 15-run sweep (and `--urdf arm.urdf`, an arm of our own).
fn five_parts(dir: &Path, vary: &str, out: &str, k: usize) {
    ok(&faze4(
        dir,
        &[
            "sweep",
            "--vary",
            vary,
            "--shard",
            &format!("{k}/5"),
            "--out",
            out,
            "-q",
            "--",
            "wave",
            "--urdf",
            "arm.urdf",
            "--duration",
            "0.2",
            "--no-collisions",
        ],
    ));
}

/// Each way a set of parts can fail to be the whole sweep is refused with one line naming it.
#[test]
fn merge_refuses_a_set_that_is_not_the_whole_sweep() {
    let dir = temp_dir("merge-refusals");
    std::fs::copy(repo_path("tests/urdf/arm_prismatic.urdf"), dir.join("arm.urdf")).unwrap();
    let vary = "amp-deg=1:15:1";
    for k in 1..=5 {
        five_parts(&dir, vary, &format!("part{k}.csv"), k);
    }
    let parts = |ks: &[usize]| ks.iter().map(|k| format!("part{k}.csv")).collect::<Vec<_>>();
    let with = |names: &[String], extra: &[&str]| {
        let mut v: Vec<String> = names.to_vec();
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let refuse = |names: Vec<String>, expected: &[&str]| {
        merge_refuses(&dir, &names.iter().map(String::as_str).collect::<Vec<_>>(), expected)
    };
    // the whole set merges
    let all = faze4(
        &dir,
        &with(
            &[vec!["sweep".to_string(), "merge".to_string()], parts(&[5, 4, 3, 2, 1])].concat(),
            &["--out", "all.csv"],
        )
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>(),
    );
    ok(&all);
    assert!(all.stdout.contains("15 runs from 5 tables"), "{}", all.stdout);
    // a part missing, two
    refuse(parts(&[1, 2, 4, 5]), &["part 3 of 5 missing: runs 6–8"]);
    refuse(parts(&[1, 3, 5]), &["parts 2, 4 of 5 missing: runs 3–5, 9–11"]);
    // a part twice: the same file, or a copy
    refuse(parts(&[1, 2, 3, 4, 5, 2]), &["part2.csv is given twice"]);
    std::fs::copy(dir.join("part2.csv"), dir.join("copy.csv")).unwrap();
    std::fs::copy(dir.join("part2.csv.meta"), dir.join("copy.csv.meta")).unwrap();
    refuse(
        with(&parts(&[1, 2, 3, 4, 5]), &["copy.csv"]),
        &["part2.csv and copy.csv both hold runs 3–5 (part 2 of 5 and part 2 of 5)"],
    );
    // a part of another sweep
    five_parts(&dir, "amp-deg=1:15:2", "other.csv", 3);
    refuse(
        with(&parts(&[1, 2, 4, 5]), &["other.csv"]),
        &[
            "other.csv is a part of another sweep than part1.csv",
            "amp-deg (8 values 1…15)",
        ],
    );
    // a truncated part (a copy cut short, with its metadata)
    let text = std::fs::read(dir.join("part4.csv")).unwrap();
    std::fs::write(dir.join("cut.csv"), &text[..text.len() - 40]).unwrap();
    std::fs::copy(dir.join("part4.csv.meta"), dir.join("cut.csv.meta")).unwrap();
    refuse(
        with(&parts(&[1, 2, 3, 5]), &["cut.csv"]),
        &["cut.csv: truncated", "rerun its task (--shard 4/5)"],
    );
    // a table beside the metadata of another (same size, one digit changed)
    let mut text = std::fs::read(dir.join("part5.csv")).unwrap();
    let at = text.len() - 2;
    text[at] = if text[at] == b'1' { b'2' } else { b'1' };
    std::fs::write(dir.join("edited.csv"), &text).unwrap();
    std::fs::copy(dir.join("part5.csv.meta"), dir.join("edited.csv.meta")).unwrap();
    refuse(
        with(&parts(&[1, 2, 3, 4]), &["edited.csv"]),
        &["edited.csv: not the table its metadata describes", "(--shard 5/5)"],
    );
    // a part without its metadata (its task stopped between the two, or not a --shard table)
    std::fs::copy(dir.join("part5.csv"), dir.join("bare.csv")).unwrap();
    refuse(
        with(&parts(&[1, 2, 3, 4]), &["bare.csv"]),
        &["bare.csv: no part metadata beside it (bare.csv.meta)"],
    );
    // different columns: the model file changed between two tasks (7 joints instead of 6)
    std::fs::copy(repo_path("tests/urdf/tree_arm.urdf"), dir.join("arm.urdf")).unwrap();
    five_parts(&dir, vary, "part3.csv", 3);
    refuse(
        parts(&[1, 2, 3, 4, 5]),
        &["part1.csv and part3.csv have different columns"],
    );

    // --allow-partial merges what there is and says what is absent, in its line and the
    // merged table's metadata
    let run = faze4(
        &dir,
        &[
            "sweep",
            "merge",
            "part1.csv",
            "part2.csv",
            "part4.csv",
            "part5.csv",
            "--allow-partial",
            "--out",
            "some.json",
        ],
    );
    ok(&run);
    assert!(
        run.stdout.contains("12 of 15 runs (absent: runs 6–8 (part 3 of 5))"),
        "{}",
        run.stdout
    );
    let rows: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("some.json")).unwrap()).unwrap();
    let runs: Vec<u64> = rows
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["run"].as_u64().unwrap())
        .collect();
    assert_eq!(runs, [0, 1, 2, 3, 4, 5, 9, 10, 11, 12, 13, 14]);
    let meta: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("some.json.meta")).unwrap()).unwrap();
    assert_eq!(meta["complete"], false);
    assert_eq!(meta["runs"], serde_json::json!([[0, 6], [9, 15]]));
    // a merged table is a part too: with the missing part, it is the whole sweep
    std::fs::copy(repo_path("tests/urdf/arm_prismatic.urdf"), dir.join("arm.urdf")).unwrap();
    five_parts(&dir, vary, "part3.csv", 3);
    ok(&faze4(
        &dir,
        &["sweep", "merge", "some.json", "part3.csv", "--out", "again.csv"],
    ));
    let (h1, r1) = read_table(&dir.join("all.csv"));
    let (h2, r2) = read_table(&dir.join("again.csv"));
    assert_eq!(h1, h2);
    let cells = |rows: &[Vec<String>]| -> Vec<Vec<String>> {
        rows.iter()
            .map(|r| {
                r.iter()
                    .zip(&h1)
                    .filter(|(_, h)| !h.ends_with("wall_time_s"))
                    .map(|(c, _)| c.clone())
                    .collect()
            })
            .collect()
    };
    assert_eq!(cells(&r1), cells(&r2));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A part none of whose runs ran (all failed, or none in it) has the sweep's columns, and
/// merges with the others.
#[test]
fn empty_and_all_failed_parts_have_the_sweeps_columns() {
    let dir = temp_dir("well-formed-parts");
    let sweep = |extra: &[&str]| {
        let mut args = vec!["sweep", "--vary", "dt=-1,-1,2e-4", "-q"];
        args.extend(extra);
        args.extend(["--", "wave", "--duration", "0.2", "--no-collisions"]);
        ok(&faze4(&dir, &args));
    };
    sweep(&["--out", "whole.csv"]);
    // 3 runs in 5 parts: parts 1, 3 and 5 are empty, part 2 holds a failed run
    for k in 1..=5 {
        sweep(&["--shard", &format!("{k}/5"), "--out", &format!("p{k}.csv")]);
    }
    let (whole_header, whole) = read_table(&dir.join("whole.csv"));
    assert!(whole_header.contains(&"max_tracking_error_rad_6".to_string()));
    let mut sizes = Vec::new();
    for k in 1..=5 {
        let (header, rows) = read_table(&dir.join(format!("p{k}.csv")));
        assert_eq!(header, whole_header, "part {k}");
        sizes.push(rows.len());
    }
    assert_eq!(sizes, [0, 1, 0, 1, 1]);
    let (_, failed) = read_table(&dir.join("p2.csv"));
    assert!(failed[0][4].starts_with("failed: --dt: -1"), "{:?}", failed[0]);
    ok(&faze4(
        &dir,
        &[
            "sweep", "merge", "p1.csv", "p2.csv", "p3.csv", "p4.csv", "p5.csv", "--out", "all.csv",
        ],
    ));
    let (header, merged) = read_table(&dir.join("all.csv"));
    assert_eq!(header, whole_header);
    assert_eq!(merged.len(), whole.len());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A task killed (SIGKILL: no handler runs) leaves nothing a merge takes for its part; the
/// rerun of the same part merges. A task stopped (SIGTERM, as Ctrl-C) writes a part marked partial.
#[test]
fn killed_and_stopped_tasks_leave_no_part_a_merge_takes_whole() {
    use std::os::unix::process::ExitStatusExt;
    let dir = temp_dir("killed-task");
    let args = |k: usize| -> Vec<String> {
        let mut v: Vec<String> = ["sweep", "--vary", "payload-kg=0:1.19:0.01", "-q", "--shard"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        v.extend([format!("{k}/3"), "--out".into(), format!("part{k}.csv"), "--".into()]);
        v.extend(["wave", "--duration", "1", "--no-collisions"].map(String::from));
        v
    };
    let run = |k: usize| ok(&faze4(&dir, &args(k).iter().map(String::as_str).collect::<Vec<_>>()));
    run(1);
    run(3);
    // part 2 killed while it runs: once its table's temporary file exists
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(args(2))
        .current_dir(&dir)
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    let temp = loop {
        let found = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .find(|n| n.starts_with(".part2.csv"));
        if let Some(name) = found {
            break name;
        }
        assert!(child.try_wait().unwrap().is_none(), "part 2 ended before it was killed");
        assert!(started.elapsed().as_secs() < 60, "no temporary file");
        std::thread::sleep(std::time::Duration::from_millis(2));
    };
    child.kill().unwrap();
    assert_eq!(child.wait().unwrap().signal(), Some(9));
    assert!(temp.ends_with(".tmp"), "{temp}");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            temp.clone(),
            "part1.csv".into(),
            "part1.csv.meta".into(),
            "part3.csv".into(),
            "part3.csv.meta".into()
        ]
    );
    merge_refuses(&dir, &["part1.csv", "part3.csv"], &["part 2 of 3 missing: runs 40–79"]);
    merge_refuses(&dir, &["part1.csv", &temp, "part3.csv"], &[".csv or .json"]);
    // the rerun
    run(2);
    let merged = faze4(
        &dir,
        &[
            "sweep",
            "merge",
            "part1.csv",
            "part2.csv",
            "part3.csv",
            "--out",
            "all.csv",
        ],
    );
    ok(&merged);
    let (_, rows) = read_table(&dir.join("all.csv"));
    assert_eq!(
        rows.iter().map(|r| r[0].parse::<usize>().unwrap()).collect::<Vec<_>>(),
        (0..120).collect::<Vec<_>>()
    );

    // part 2 of a sweep of hours, stopped by a signal: a partial part, refused as a whole one
    let long = [
        "sweep",
        "--vary",
        "payload-kg=0:9.9999:0.0001",
        "-q",
        "--shard",
        "2/2",
        "--out",
        "long2.csv",
        "--",
        "wave",
        "--duration",
        "1",
        "--no-collisions",
    ];
    // SIGTERM, what Slurm sends at the time limit (and Kubernetes when it stops a pod), once
    // the part's temporary exists: its runs have begun
    let out = signalled_once_begun(
        &dir,
        &long,
        libc::SIGTERM,
        |dir, _| has_temporary(dir),
        std::time::Duration::from_millis(500),
    );
    assert_eq!(out.status.code(), Some(143), "{}", String::from_utf8_lossy(&out.stderr));
    let meta: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("long2.csv.meta")).unwrap()).unwrap();
    assert_eq!(meta["complete"], false);
    let held = meta["rows"].as_u64().unwrap();
    assert!(held < 50_000);
    assert_eq!(meta["runs"], serde_json::json!([[50_000, 50_000 + held]]));
    merge_refuses(
        &dir,
        &["long2.csv"],
        &[&format!(
            "long2.csv is partial (part 2 of 2 stopped after {held} runs; runs {}–99999 absent)",
            50_000 + held
        )],
    );
    let some = faze4(
        &dir,
        &["sweep", "merge", "long2.csv", "--allow-partial", "--out", "some.csv"],
    );
    ok(&some);
    assert!(
        some.stdout
            .contains(&format!("runs 0–49999, {}–99999 (parts 1, 2 of 2)", 50_000 + held)),
        "{}",
        some.stdout
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The number in `line` after `label`.
fn number_after(line: &str, label: &str) -> f64 {
    let rest = &line[line.find(label).unwrap_or_else(|| panic!("'{label}' in {line}")) + label.len()..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .unwrap_or(rest.len());
    rest[..end]
        .parse()
        .unwrap_or_else(|_| panic!("a number after '{label}' in {line}"))
}

#[test]
fn find_answers_with_values_that_single_runs_confirm() {
    let dir = temp_dir("find");
    let base = ["wave", "--duration", "1", "--no-collisions"];
    let mut args = vec!["sweep", "--find", "payload-kg=0:3", "--resolution", "0.01", "--"];
    args.extend(base);
    let run = faze4(&dir, &args);
    ok(&run);
    let line = run.stdout.trim();
    assert!(line.starts_with("largest payload-kg that follows: "), "{line}");
    let (follows, fails) = (number_after(line, "follows: "), number_after(line, "(at "));
    // the values printed are the values run (shortest round-trip decimals, issue 21): printed
    // with more digits they would read back the same
    for (label, x) in [("follows: ", follows), ("(at ", fails)] {
        assert!(line.contains(&format!("{label}{x}")), "{label}{x} in {line}");
    }
    assert!(fails > follows && fails - follows <= 0.01 + 1e-9, "{line}");
    assert!(line.contains("saturates") || line.contains("tracking error"), "{line}");
    let verdict = |value: f64| {
        let payload = value.to_string(); // Rust's shortest round-trip, as the line
        let mut single: Vec<&str> = base.to_vec();
        single.extend(["--payload-kg", &payload, "--trail", "none", "-q"]);
        faze4(&dir, &single).stdout.trim().to_string()
    };
    assert_eq!(verdict(follows), "verdict: follows");
    assert!(verdict(fails).starts_with("verdict: cannot follow"));

    // the smallest: a stiffer loop (kp-scale) follows above some value
    let mut args = vec!["sweep", "--find-min", "kp-scale=0.001:1", "--"];
    args.extend(base);
    let run = faze4(&dir, &args);
    ok(&run);
    assert!(
        run.stdout.starts_with("smallest kp-scale that follows: "),
        "{}",
        run.stdout
    );

    // the ends, said plainly
    let mut args = vec!["sweep", "--find", "payload-kg=5:6", "--"];
    args.extend(base);
    let run = faze4(&dir, &args);
    ok(&run);
    assert!(
        run.stdout.starts_with("no payload-kg in [5, 6] follows: already at 5"),
        "{}",
        run.stdout
    );
    let mut args = vec!["sweep", "--find", "payload-kg=0:0.05", "--"];
    args.extend(base);
    let run = faze4(&dir, &args);
    ok(&run);
    assert!(run.stdout.contains("beyond the range (raise HI)"), "{}", run.stdout);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn failed_runs_are_rows_and_the_scales_multiply_the_tuned_values() {
    let dir = temp_dir("rows");
    ok(&faze4(
        &dir,
        &[
            "sweep",
            "--vary",
            "dt=-1,2e-4",
            "--vary",
            "kp-scale=1,0.5",
            "--out",
            "t.json",
            "--",
            "wave",
            "--no-collisions",
            "--duration",
            "0.5",
        ],
    ));
    let rows: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("t.json")).unwrap()).unwrap();
    let rows = rows.as_array().unwrap();
    assert_eq!(rows.len(), 4);
    for failed in &rows[..2] {
        assert_eq!(failed["follows"], false);
        assert!(
            failed["reasons"].as_str().unwrap().starts_with("failed: --dt: -1"),
            "{failed}"
        );
        assert!(failed["kp_1"].is_null());
    }
    for j in 1..=6 {
        let (full, half) = (
            rows[2][format!("kp_{j}")].as_f64().unwrap(),
            rows[3][format!("kp_{j}")].as_f64().unwrap(),
        );
        assert_eq!(half, full * 0.5);
        assert_eq!(rows[2][format!("kd_{j}")], rows[3][format!("kd_{j}")]);
    }

    // mass-scale changes the arm, not the gains tuned for it; trails only when asked
    std::fs::create_dir(dir.join("trails")).unwrap();
    ok(&faze4(
        &dir,
        &[
            "sweep",
            "--vary",
            "mass-scale=1,1.3",
            "--out",
            "m.csv",
            "--trails",
            "trails",
            "--",
            "wave",
            "--no-collisions",
            "--duration",
            "0.5",
        ],
    ));
    let (header, rows) = read_table(&dir.join("m.csv"));
    let (a, b) = (named(&header, &rows[0]), named(&header, &rows[1]));
    assert_eq!(a["kp_2"], b["kp_2"]);
    assert_eq!(a["effective_inertia_2"], b["effective_inertia_2"]);
    assert_ne!(a["max_tracking_error_rad_2"], b["max_tracking_error_rad_2"]);
    let trails: Vec<_> = std::fs::read_dir(dir.join("trails"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(trails.len(), 2, "{trails:?}");
    assert!(dir.join("trails/run_0000001.csv").exists());
    assert!(!dir.join("faze4_trail.csv").exists());

    // rotor-inertia-scale changes the motors' reflected inertia, not the gains tuned for it
    ok(&faze4(
        &dir,
        &[
            "sweep",
            "--vary",
            "rotor-inertia-scale=1,4",
            "--out",
            "r.csv",
            "--",
            "wave",
            "--no-collisions",
            "--motors",
            "faze4",
            "--duration",
            "0.5",
        ],
    ));
    let (header, rows) = read_table(&dir.join("r.csv"));
    let (a, b) = (named(&header, &rows[0]), named(&header, &rows[1]));
    assert_eq!(a["kp_6"], b["kp_6"]);
    assert_ne!(a["max_tracking_error_rad_6"], b["max_tracking_error_rad_6"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_plot_draws_one_option_as_lines_and_two_as_heatmaps() {
    let dir = temp_dir("plot");
    ok(&faze4(
        &dir,
        &[
            "sweep",
            "--vary",
            "payload-kg=0:1:0.5",
            "--plot",
            "one.svg",
            "-q",
            "--",
            "shape",
            "--no-collisions",
            "--shape",
            "tri",
            "--duration",
            "0.5",
        ],
    ));
    ok(&faze4(
        &dir,
        &[
            "sweep",
            "--vary",
            "payload-kg=0:1:0.5",
            "--vary",
            "freq=0.5,1",
            "--plot",
            "two.png",
            "-q",
            "--",
            "wave",
            "--no-collisions",
            "--duration",
            "0.5",
        ],
    ));
    let svg = std::fs::read_to_string(dir.join("one.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("path deviation") && svg.contains("payload-kg"));
    let png = std::fs::read(dir.join("two.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A heatmap whose figures span decades (the tracking error of a light and of a crushing payload)
/// says in its caption that its colours are logarithmic; one whose figures do not, does not.
#[test]
fn a_heatmap_spanning_decades_has_a_log_colour_scale() {
    let dir = temp_dir("plot-log");
    let sweep = |payloads: &str, plot: &str| {
        ok(&faze4(
            &dir,
            &[
                "sweep",
                "--vary",
                payloads,
                "--vary",
                "freq=0.5,1",
                "--plot",
                plot,
                "-q",
                "--",
                "wave",
                "--no-collisions",
                "--duration",
                "0.5",
            ],
        ));
        std::fs::read_to_string(dir.join(plot)).unwrap()
    };
    let decades = sweep("payload-kg=0,4", "decades.svg");
    assert!(
        decades.contains("tracking error (mrad): log colour scale: "),
        "no log scale"
    );
    let narrow = sweep("payload-kg=0,0.1", "narrow.svg");
    assert!(narrow.contains("tracking error (mrad): ") && !narrow.contains("log colour scale"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_input_is_one_line_and_exit_2() {
    let dir = temp_dir("bad");
    std::fs::write(dir.join("a.csv"), "run,x\n0,1\n").unwrap();
    let cases: &[(&[&str], &str)] = &[
        (
            &["sweep", "--vary", "bogus=1,2", "--", "wave"],
            "'bogus' is not a numeric option",
        ),
        (
            &["sweep", "--vary", "urdf=1", "--", "wave"],
            "'urdf' is not a numeric option",
        ),
        (
            &["sweep", "--vary", "freq=1,2", "--", "shape", "--shape", "circle"],
            "freq is not an option of shape",
        ),
        (
            &[
                "sweep",
                "--vary",
                "shape-points=10.5",
                "--",
                "shape",
                "--shape",
                "circle",
            ],
            "whole numbers",
        ),
        (&["sweep", "--vary", "freq=a,b", "--", "wave"], "'a' is not a number"),
        (&["sweep", "--vary", "freq=1:0:0.1", "--", "wave"], "empty range"),
        (&["sweep", "--vary", "freq=0:1:0", "--", "wave"], "must be > 0"),
        (&["sweep", "--vary", "freq=0:1:1e-9", "--", "wave"], "at most"),
        (&["sweep", "--vary", "freq=0:1:-0.5", "--", "wave"], "must be > 0"),
        (
            &["sweep", "--vary", "freq=1", "--shard", "4/3", "--", "wave"],
            "--shard",
        ),
        (&["sweep", "--vary", "freq=1", "--shard", "x", "--", "wave"], "--shard"),
        (
            &[
                "sweep",
                "--vary",
                "payload-kg=0:1000:0.001",
                "--vary",
                "freq=1,2",
                "--",
                "wave",
            ],
            "--shard",
        ),
        (
            &["sweep", "--vary", "freq=1", "--out", "t.txt", "--", "wave"],
            ".csv or .json",
        ),
        (
            &[
                "sweep",
                "--vary",
                "freq=1",
                "--plot",
                "p.svg",
                "--vary",
                "dt=1e-4",
                "--vary",
                "duration=1",
                "--",
                "wave",
            ],
            "one or two",
        ),
        (&["sweep", "--vary", "freq=1", "--", "wave", "--bogus"], "--bogus"),
        (&["sweep", "--vary", "freq=1"], "no command to run"),
        (&["sweep", "--", "wave"], "nothing to vary"),
        (
            &["sweep", "--vary", "freq=1", "--", "wave", "--summary", "s.json"],
            "--summary",
        ),
        (
            &["sweep", "--vary", "freq=1", "--", "wave", "--html", "x.html"],
            "--html: is for single runs",
        ),
        (&["sweep", "--find", "payload-kg=2:1", "--", "wave"], "empty range"),
        (
            &[
                "sweep",
                "--find",
                "shape-points=10:100",
                "--",
                "shape",
                "--shape",
                "tri",
            ],
            "whole numbers",
        ),
        (
            &["sweep", "--find", "payload-kg=0:1", "--resolution", "0", "--", "wave"],
            "--resolution",
        ),
        (
            &["sweep", "merge", "a.csv", "--out", "m.csv"],
            "a.csv: no part metadata",
        ),
        (
            &["sweep", "merge", "a.csv", "--out", "m.txt"],
            "--out: m.txt: the table is written as .csv or .json",
        ),
    ];
    for (args, expected) in cases {
        let run = faze4(&dir, args);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {}", run.stderr);
        assert_eq!(run.stderr.lines().count(), 1, "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains(expected), "{args:?}: {}", run.stderr);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A stop does not wait for the runs in flight: they end where they are and are left out, with
/// their trails (a sweep of hour-long runs waited for a whole chunk of them, 32 per thread, and
/// wrote them as rows; Slurm kills a task 30 s after its SIGTERM by default).
#[test]
fn a_stop_ends_the_runs_in_flight_and_leaves_them_out() {
    let dir = temp_dir("stop-in-flight");
    std::fs::create_dir(dir.join("trails")).unwrap();
    // two runs of an hour each (minutes of work), stopped once their temporaries exist
    let out = signalled_once_begun(
        &dir,
        &[
            "sweep",
            "--vary",
            "payload-kg=0,0.1",
            "--jobs",
            "2",
            "--out",
            "t.csv",
            "--trails",
            "trails",
            "--",
            "wave",
            "--no-collisions",
            "--duration",
            "3600",
        ],
        libc::SIGTERM,
        |dir, _| has_temporary(&dir.join("trails")),
        std::time::Duration::from_millis(200),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(143), "{stderr}");
    assert!(
        stderr.contains("stopped by SIGTERM after 0 of 2 runs; the outputs hold those"),
        "{stderr}"
    );
    let (header, rows) = read_table(&dir.join("t.csv"));
    assert!(header.len() > 5, "the sweep's columns all the same: {header:?}");
    assert!(rows.is_empty(), "{rows:?}");
    let trails: Vec<_> = std::fs::read_dir(dir.join("trails")).unwrap().collect();
    assert!(trails.is_empty(), "{trails:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn ctrl_c_ends_a_sweep_with_the_rows_before_it() {
    let dir = temp_dir("ctrl-c");
    // 100 000 runs of 1 s: hours, so the signal always comes first; sent once the table's
    // temporary exists (the runs have begun)
    let out = signalled_once_begun(
        &dir,
        &[
            "sweep",
            "--vary",
            "payload-kg=0:9.9999:0.0001",
            "--out",
            "t.csv",
            "-q",
            "--",
            "wave",
            "--no-collisions",
            "--duration",
            "1",
        ],
        libc::SIGINT,
        |dir, _| has_temporary(dir),
        std::time::Duration::from_millis(500),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted after"), "{stderr}");
    let (header, rows) = read_table(&dir.join("t.csv"));
    assert!(rows.len() < 100_000);
    // whole rows, in order from the first run
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), header.len());
        assert_eq!(row[0], i.to_string());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
