//! The question every run answers — can the arm follow its command? — and the outputs that
//! respect the user: the verdict line, `--strict`, the thresholds, `--quiet`, the progress
//! lines of long runs, paths checked before the run, interrupted counts, suggestions.

use crate::common;

use common::*;

fn last_line(text: &str) -> &str {
    text.lines().last().unwrap_or("")
}

/// The original's runs follow: the default wave and the three shapes.
#[test]
fn the_originals_runs_follow() {
    let dir = temp_dir("verdict-follows");
    for args in [
        vec!["wave"],
        vec!["shape", "--shape", "sine"],
        vec!["shape", "--shape", "circle"],
        vec!["shape", "--shape", "tri"],
    ] {
        let mut all = args.clone();
        // the figures are the point; the circle's self-clearance is tests/it/self_clearance.rs's
        all.extend(["--trail", "none", "--summary", "s.json", "--strict", "--no-collisions"]);
        let run = faze4(&dir, &all);
        assert!(run.status.success(), "{args:?}: {}", run.stderr);
        assert_eq!(last_line(&run.stdout), "verdict: follows", "{args:?}");
        let s = summary(&dir, "s.json");
        assert_eq!(
            s["verdict"],
            serde_json::json!({"follows": true, "collides": false, "reasons": []}),
            "{args:?}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// 5 kg on the circle: J2 saturates nearly always and the path is lost; the verdict says so in
/// words, the summary lists the reasons, and --strict makes it a failure for CI.
#[test]
fn a_heavy_payload_cannot_follow_and_strict_fails() {
    let dir = temp_dir("verdict-heavy");
    let args = [
        "shape",
        "--shape",
        "circle",
        "--payload-kg",
        "5",
        "--trail",
        "none",
        "--summary",
        "s.json",
        // the figures are the point here; self-clearance has its own tests
        "--no-collisions",
    ];
    let run = faze4(&dir, &args);
    assert!(
        run.status.success(),
        "without --strict the run itself succeeded: {}",
        run.stderr
    );
    let verdict = last_line(&run.stdout);
    assert!(verdict.starts_with("verdict: cannot follow — "), "{verdict}");
    for part in [
        "J2 saturates",
        "% of the steps (limit 5 %)",
        "path deviation",
        "tracking error",
    ] {
        assert!(verdict.contains(part), "{verdict:?} lacks {part:?}");
    }
    let s = summary(&dir, "s.json");
    assert_eq!(s["verdict"]["follows"], false);
    let reasons: Vec<&str> = s["verdict"]["reasons"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r.as_str().unwrap())
        .collect();
    assert!(reasons.iter().any(|r| r.starts_with("J2 saturates")), "{reasons:?}");
    assert!(s["saturation_pct"][1].as_f64().unwrap() > 90.0);

    let mut strict = args.to_vec();
    strict.push("--strict");
    let run = faze4(&dir, &strict);
    assert_eq!(run.status.code(), Some(3), "--strict: cannot follow exits with 3");
    assert!(last_line(&run.stdout).starts_with("verdict: cannot follow"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Each threshold moves the verdict: the default wave's errors (≤ 3.4e-4 rad) fail a 1e-4 rad
/// limit; --no-ff's J2 error (0.041 rad) passes the default and fails 0.03; the sine's J2
/// saturation (0.52 %) fails a 0.1 % limit; the triangle's corners (3.95 mm) fail a 3 mm limit.
#[test]
fn the_thresholds_move_the_verdict() {
    let dir = temp_dir("verdict-thresholds");
    let verdict = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend(["--trail", "none", "--strict", "--no-collisions"]);
        let run = faze4(&dir, &all);
        (run.status.code(), last_line(&run.stdout).to_string())
    };
    let (code, v) = verdict(&["wave", "--duration", "2", "--max-error", "1e-4"]);
    assert_eq!(code, Some(3), "{v}");
    assert!(
        v.contains("J1 tracking error") && v.contains("(limit 0.0001 rad)"),
        "{v}"
    );
    assert_eq!(verdict(&["wave", "--no-ff"]).1, "verdict: follows");
    let (code, v) = verdict(&["wave", "--no-ff", "--max-error", "0.03"]);
    assert_eq!(code, Some(3));
    assert!(v.contains("J2 tracking error 0.041 rad") && !v.contains("J1 "), "{v}");
    let (_, v) = verdict(&["shape", "--shape", "sine", "--max-saturation-pct", "0.1"]);
    assert!(v.contains("J2 saturates 0.52 % of the steps (limit 0.1 %)"), "{v}");
    let (_, v) = verdict(&["shape", "--shape", "tri", "--max-deviation-mm", "3"]);
    assert!(
        v.contains("path deviation 3.9 mm (limit 3 mm)") || v.contains("path deviation 4.0 mm"),
        "{v}"
    );
    let run = faze4(&dir, &["wave", "--max-error", "-1"]);
    assert_eq!(run.status.code(), Some(2));
    assert!(run.stderr.contains("--max-error"), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A diverging run cannot follow, and says where.
#[test]
fn a_diverged_run_cannot_follow() {
    let dir = temp_dir("verdict-diverged");
    let run = faze4(
        &dir,
        &[
            "wave",
            "--kp",
            "auto,auto,auto,auto,auto,40000",
            "--effort",
            "7.9,8.5,4.7,3.7,3.5,1e9",
            "--trail",
            "none",
        ],
    );
    assert_eq!(run.status.code(), Some(1));
    let v = last_line(&run.stdout);
    assert!(
        v.starts_with("verdict: cannot follow — the loop diverged at t = ") && v.contains("on J6"),
        "{v}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// --quiet prints the verdict alone; errors still come.
#[test]
fn quiet_prints_only_the_verdict() {
    let dir = temp_dir("verdict-quiet");
    let run = faze4(&dir, &["wave", "--duration", "1", "--quiet"]);
    assert!(run.status.success());
    assert_eq!(run.stdout, "verdict: follows\n");
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    assert!(dir.join("faze4_trail.csv").is_file(), "the files are still written");
    let run = faze4(&dir, &["wave", "--quiet", "--dt", "0"]);
    assert_eq!(run.status.code(), Some(2));
    assert!(run.stderr.starts_with("faze4: error: --dt"), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A long run prints at most about 40 progress lines; --print-period chooses.
#[test]
fn long_runs_print_about_forty_lines() {
    let dir = temp_dir("verdict-lines");
    let lines = |args: &[&str]| {
        let run = faze4(&dir, args);
        assert!(run.status.success(), "{}", run.stderr);
        run.stdout.lines().filter(|l| l.starts_with("t=")).count()
    };
    assert_eq!(
        lines(&["wave", "--duration", "8", "--trail", "none", "--no-collisions"]),
        17,
        "0.5 s lines, t = 0 included"
    );
    let long = lines(&["wave", "--duration", "120", "--trail", "none", "--no-collisions"]);
    assert!((20..=41).contains(&long), "{long} lines for 120 s");
    assert_eq!(
        lines(&[
            "wave",
            "--duration",
            "120",
            "--trail",
            "none",
            "--print-period",
            "10",
            "--no-collisions"
        ]),
        13
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// --summary and --trail are checked before the run, the error names the option, and nothing
/// is left behind.
#[test]
fn output_paths_are_checked_before_the_run() {
    let dir = temp_dir("verdict-paths");
    for (option, args) in [
        ("--summary", vec!["wave", "--summary", "/missing-dir-faze4/s.json"]),
        ("--trail", vec!["wave", "--trail", "/missing-dir-faze4/t.csv"]),
        (
            "--save-q",
            vec!["shape", "--shape", "circle", "--save-q", "/missing-dir-faze4/q.npy"],
        ),
    ] {
        let started = std::time::Instant::now();
        let run = faze4(&dir, &args);
        assert_eq!(run.status.code(), Some(2), "{args:?}");
        assert!(
            run.stderr.starts_with(&format!("faze4: error: {option}:")),
            "{}",
            run.stderr
        );
        assert_eq!(run.stderr.lines().count(), 1);
        assert!(run.stdout.is_empty(), "nothing ran: {}", run.stdout);
        assert!(started.elapsed().as_secs_f64() < 5.0);
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert!(left.is_empty(), "{args:?} left {left:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A run stopped by a signal once it has begun says it stopped and when, and gives no verdict
/// on the part it did not run; the summary counts the steps it ran; the status is 128 + the
/// signal's number.
#[test]
fn a_run_stopped_midway_says_so_and_gives_no_verdict() {
    let dir = temp_dir("verdict-interrupted");
    for (signal, status, said) in [
        (libc::SIGTERM, 143, "stopped by SIGTERM"),
        (libc::SIGINT, 130, "interrupted"),
    ] {
        // begun: its first progress line on stdout, `t=  0.00s …`
        let run = signalled_once_begun(
            &dir,
            &["wave", "--duration", "3600", "--trail", "none", "--summary", "s.json"],
            signal,
            |_, printed| printed.lines().any(|l| l.starts_with("t=")),
            std::time::Duration::ZERO,
        );
        let (stdout, stderr) = (
            String::from_utf8_lossy(&run.stdout),
            String::from_utf8_lossy(&run.stderr),
        );
        assert_eq!(run.status.code(), Some(status), "{stderr}");
        let s = summary(&dir, "s.json");
        let t = s["interrupted_at_s"].as_f64().unwrap();
        let steps = s["steps"].as_u64().unwrap();
        assert_eq!(steps, (t / 2e-4).round() as u64, "steps = those run before t = {t}");
        assert!(steps < 18_000_000);
        assert!(stdout.contains(&format!(" {steps} steps in ")), "{stdout}");
        let line = format!("faze4: {said} at t = {t:.3} s of 3600 s: no verdict; the outputs are complete up to there");
        assert_eq!(stderr.lines().last(), Some(line.as_str()), "{stderr}");
        assert!(!stdout.lines().any(|l| l.contains("verdict")), "{stdout}");
        assert!(!last_line(&stdout).is_empty());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A mistyped subcommand, option or value gets the closest one.
#[test]
fn typos_get_a_suggestion() {
    let dir = temp_dir("verdict-typos");
    for (args, wanted) in [
        (vec!["wav"], "did you mean 'wave'?"),
        (vec!["wave", "--amp-dg", "3"], "did you mean '--amp-deg'?"),
        (vec!["shape", "--shape", "circl"], "did you mean 'circle'?"),
    ] {
        let run = faze4(&dir, &args);
        assert_eq!(run.status.code(), Some(2));
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
        assert!(run.stderr.contains(wanted), "{args:?}: {}", run.stderr);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
