//! The 3D views of the real `faze4` binary in a real browser: headless Chromium (Debian's
//! `chromium`, software WebGL through SwiftShader) opens the file `--html` wrote and the page
//! `--view` serves, takes screenshots,
//! and the test reads their pixels: the arm is drawn where it should be, and it moves between
//! two times.
//!
//! Its own harness (`harness = false` in Cargo.toml), so that a missing Chromium is ONE line in
//! `cargo test`'s output (libtest would hide it): the browser tests did not run, and how to
//! install Chromium. With `FAZE4_REQUIRE_CHROMIUM=1` (`.ci/run` sets it) a missing Chromium is a
//! failure. `FAZE4_CHROMIUM` names the browser to use (default `chromium`). Arguments as
//! libtest's: name filters, `--exact`, `--skip`, `--list`.
//!
//! `FAZE4_INSTALLED_HTML=F`: the default-arm test checks F (`.ci/run` writes it with an installed
//! binary, its source removed) instead of a file from the binary under test.
//!
//! With `FAZE4_UPDATE_DOCS=1` the screenshots at the known poses are also copied to
//! `docs/html_export.png`, `docs/live_view.png` and `docs/self_collision.png`.

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::sync::mpsc;
use std::time::Duration;

use common::{interrupt, repo, shared_description};

const WIDTH: usize = 1000;
const HEIGHT: usize = 700;

/// The browser, found once by `main`.
static CHROMIUM: OnceLock<PathBuf> = OnceLock::new();

/// `$FAZE4_CHROMIUM` if set, else `chromium`, if it runs.
fn find_chromium() -> Option<PathBuf> {
    let candidate = std::env::var("FAZE4_CHROMIUM").unwrap_or_else(|_| "chromium".into());
    Command::new(&candidate)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
        .then(|| PathBuf::from(candidate))
}

fn chromium() -> &'static Path {
    CHROMIUM.get().expect("main finds Chromium first")
}

/// The tests, in the order they run (one at a time: two software-rendering Chromiums at once
/// starve a 2-core machine).
const TESTS: [(&str, fn()); 4] = [
    (
        "exported_html_draws_the_arm_and_plays_the_motion",
        exported_html_draws_the_arm_and_plays_the_motion,
    ),
    (
        "live_page_draws_the_arm_and_follows_the_run",
        live_page_draws_the_arm_and_follows_the_run,
    ),
    (
        "default_arm_is_drawn_with_the_real_meshes",
        default_arm_is_drawn_with_the_real_meshes,
    ),
    ("colliding_links_are_drawn_red", colliding_links_are_drawn_red),
];

/// What `cargo test … -- ARGS` asks of these tests, with libtest's meaning: names to run
/// (substrings, or whole names with `--exact`), `--skip NAME`, `--ignored` (none is), `--list`.
struct Selection {
    filters: Vec<String>,
    skip: Vec<String>,
    exact: bool,
    ignored_only: bool,
    list: bool,
}

impl Selection {
    fn from_args(mut args: impl Iterator<Item = String>) -> Selection {
        let mut selection = Selection {
            filters: Vec::new(),
            skip: Vec::new(),
            exact: false,
            ignored_only: false,
            list: false,
        };
        while let Some(arg) = args.next() {
            match arg.as_str() {
                "--skip" => selection.skip.extend(args.next()),
                "--exact" => selection.exact = true,
                "--ignored" => selection.ignored_only = true,
                "--list" => selection.list = true,
                // libtest options with a value, which is no test name
                "--test-threads" | "--color" | "--format" | "--logfile" | "--shuffle-seed" | "-Z" => {
                    args.next();
                }
                flag if flag.starts_with('-') => {}
                _ => selection.filters.push(arg),
            }
        }
        selection
    }

    fn wants(&self, name: &str) -> bool {
        let matches = |pattern: &String| match self.exact {
            true => name == pattern,
            false => name.contains(pattern.as_str()),
        };
        !self.ignored_only
            && (self.filters.is_empty() || self.filters.iter().any(matches))
            && !self.skip.iter().any(matches)
    }
}

fn main() -> ExitCode {
    let selection = Selection::from_args(std::env::args().skip(1));
    let selected: Vec<_> = TESTS.iter().filter(|(name, _)| selection.wants(name)).collect();
    if selection.list {
        for (name, _) in &selected {
            println!("{name}: test");
        }
        return ExitCode::SUCCESS;
    }
    if selected.is_empty() {
        return ExitCode::SUCCESS;
    }
    let Some(found) = find_chromium() else {
        let required = std::env::var("FAZE4_REQUIRE_CHROMIUM").is_ok_and(|v| v == "1");
        println!(
            "{}: the {} browser tests (tests/browser.rs) did not run: Chromium was not found; install it \
             with `apt-get install chromium` (or set FAZE4_CHROMIUM to its path){}",
            if required { "FAILED" } else { "NOTICE" },
            selected.len(),
            if required {
                "; FAZE4_REQUIRE_CHROMIUM=1 requires it"
            } else {
                ""
            }
        );
        return if required { ExitCode::FAILURE } else { ExitCode::SUCCESS };
    };
    CHROMIUM.set(found).unwrap();
    println!("\nrunning {} browser tests", selected.len());
    let mut failed = Vec::new();
    for (name, test) in selected {
        let outcome = std::panic::catch_unwind(test);
        println!("test {name} ... {}", if outcome.is_ok() { "ok" } else { "FAILED" });
        if outcome.is_err() {
            failed.push(*name);
        }
    }
    if failed.is_empty() {
        println!("\nbrowser test result: ok");
        ExitCode::SUCCESS
    } else {
        println!("\nbrowser test result: FAILED ({})", failed.join(", "));
        ExitCode::FAILURE
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("faze4-browser-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Screenshot of `url` after `wait` of wall-clock time (the page is then stopped and drawn).
fn screenshot(url: &str, out: &Path, wait: Duration) -> Image {
    let profile = out.with_extension("profile");
    std::fs::create_dir_all(&profile).unwrap();
    let output = Command::new(chromium())
        .args([
            "--headless",
            "--no-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
            "--mute-audio",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size={WIDTH},{HEIGHT}"))
        .arg(format!("--timeout={}", wait.as_millis()))
        .arg(format!("--screenshot={}", out.display()))
        .args(["--enable-logging=stderr", "--v=0"])
        .arg(url)
        .output()
        .expect("chromium runs");
    // the page's console (errors of the viewer) goes to the test's output
    for line in String::from_utf8_lossy(&output.stderr).lines() {
        if line.contains("CONSOLE") {
            eprintln!("chromium: {line}");
        }
    }
    let _ = std::fs::remove_dir_all(&profile);
    assert!(
        out.is_file(),
        "no screenshot of {url}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    Image::read(out)
}

struct Image {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
}

impl Image {
    fn read(path: &Path) -> Image {
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        let channels = info.color_type.samples();
        let rgb = buf[..info.buffer_size()]
            .chunks(channels)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        Image {
            width: info.width as usize,
            height: info.height as usize,
            rgb,
        }
    }

    fn pixel(&self, x: usize, y: usize) -> [u8; 3] {
        let o = 3 * (y * self.width + x);
        [self.rgb[o], self.rgb[o + 1], self.rgb[o + 2]]
    }

    /// Pixels of the arm's colours (the lit grey-blue of the Faze4 parts) in the rectangle
    /// x0..x1, y0..y1: bright, bluish, unsaturated. The background, the ground, the board
    /// (warm white), the trails (yellow, saturated blue) and the red target are not.
    fn arm_pixels(&self, x0: usize, y0: usize, x1: usize, y1: usize) -> usize {
        let mut n = 0;
        for y in y0..y1.min(self.height) {
            for x in x0..x1.min(self.width) {
                let [r, g, b] = self.pixel(x, y).map(|c| c as i32);
                if (r + g + b) / 3 > 110 && b > r + 8 && b >= g && b - r < 80 {
                    n += 1;
                }
            }
        }
        n
    }

    /// Pixels whose colour differs from `other`'s by more than 60 (sum over channels).
    fn changed(&self, other: &Image) -> usize {
        self.rgb
            .chunks(3)
            .zip(other.rgb.chunks(3))
            .filter(|(a, b)| {
                a.iter()
                    .zip(*b)
                    .map(|(x, y)| (*x as i32 - *y as i32).abs())
                    .sum::<i32>()
                    > 60
            })
            .count()
    }
}

/// The region of the 1000×700 window where the arm stands (the default camera frames it).
const ARM_REGION: (usize, usize, usize, usize) = (250, 130, 780, 640);
/// Regions left and right of it where nothing arm-coloured is (below the text overlays).
const EMPTY_REGIONS: [(usize, usize, usize, usize); 2] = [(0, 150, 230, 620), (800, 150, 1000, 620)];
/// At least this many arm-coloured pixels in the arm's region (the real arm covers about
/// 40,000 at the default view).
const MIN_ARM_PIXELS: usize = 15_000;

fn check_arm_drawn(image: &Image, what: &str) {
    assert_eq!((image.width, image.height), (WIDTH, HEIGHT), "{what}");
    let (x0, y0, x1, y1) = ARM_REGION;
    let inside = image.arm_pixels(x0, y0, x1, y1);
    assert!(
        inside >= MIN_ARM_PIXELS,
        "{what}: {inside} arm pixels in the arm's region"
    );
    for (x0, y0, x1, y1) in EMPTY_REGIONS {
        let stray = image.arm_pixels(x0, y0, x1, y1);
        assert!(
            stray < 300,
            "{what}: {stray} arm-coloured pixels in {x0}..{x1} × {y0}..{y1}"
        );
    }
}

/// A screenshot of `url`; on a slow machine (the arm not drawn yet when the page is
/// stopped) taken again with more time, twice.
fn screenshot_drawn(url: &str, out: &Path, wait: Duration) -> Image {
    let (x0, y0, x1, y1) = ARM_REGION;
    let mut image = screenshot(url, out, wait);
    for more in [3, 8] {
        if image.arm_pixels(x0, y0, x1, y1) >= MIN_ARM_PIXELS {
            break;
        }
        eprintln!("{url}: not drawn yet, trying again with {more}× the time");
        image = screenshot(url, out, wait * more);
    }
    image
}

fn docs(image: &Path, name: &str) {
    if std::env::var("FAZE4_UPDATE_DOCS").is_ok_and(|v| v == "1") {
        let to = repo().join("docs").join(name);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(image, &to).unwrap();
        eprintln!("updated {}", to.display());
    }
}

/// The real Faze4 (urdf/faze4_real.urdf: the official meshes, found with no search path) for
/// the binary.
fn real_arm_args() -> Vec<String> {
    vec![
        "--urdf".into(),
        repo().join("urdf/faze4_real.urdf").display().to_string(),
        "--trail".into(),
        "none".into(),
    ]
}

/// `faze4 shape --html`: the exported file, opened from the file system.
fn exported_html_draws_the_arm_and_plays_the_motion() {
    let dir = temp_dir("html");
    let html = dir.join("circle.html");
    let mut args: Vec<String> = ["shape", "--shape", "circle", "--duration", "6", "--html"]
        .map(String::from)
        .into();
    args.push(html.display().to_string());
    args.extend(real_arm_args());
    let run = Command::new(env!("CARGO_BIN_EXE_faze4")).args(&args).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(
        run.stderr.is_empty(),
        "the meshes are found: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let url = format!("file://{}", html.display());

    // the page honours #t=…&paused
    let shot = |t: f64, name: &str| {
        let out = dir.join(name);
        (
            screenshot_drawn(&format!("{url}#t={t}&paused"), &out, Duration::from_secs(6)),
            out,
        )
    };
    let (at1, path1) = shot(1.0, "t1.png");
    let (at3, _) = shot(3.0, "t3.png");
    check_arm_drawn(&at1, "export at t = 1 s");
    check_arm_drawn(&at3, "export at t = 3 s");
    let changed = at1.changed(&at3);
    assert!(
        changed > 3_000,
        "the arm moved between t = 1 s and 3 s: {changed} pixels changed"
    );
    // the trail: yellow pixels, more at 3 s than at 1 s
    let yellow = |im: &Image| {
        im.rgb
            .chunks(3)
            .filter(|p| p[0] > 150 && p[1] > 120 && (p[2] as i32) < p[1] as i32 - 60)
            .count()
    };
    assert!(yellow(&at3) > yellow(&at1) + 300, "{} → {}", yellow(&at1), yellow(&at3));
    docs(&path1, "html_export.png");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `faze4 wave --view --port 0 --hold`: the live page follows the run (paced to the wall
/// clock), a browser that comes after the run's end gets all of it, and Ctrl-C ends the
/// holding cleanly (status 0: the run was complete).
fn live_page_draws_the_arm_and_follows_the_run() {
    let dir = temp_dir("live");
    let mut args: Vec<String> = [
        "wave",
        "--duration",
        "8",
        "--freq",
        "2",
        "--view",
        "--port",
        "0",
        "--hold",
        "--summary",
    ]
    .map(String::from)
    .into();
    args.push(dir.join("s.json").display().to_string());
    args.extend(real_arm_args());
    let mut child = Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(&args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // the address is printed on stderr; keep reading it all in the background
    let (lines, stderr_lines) = mpsc::channel::<String>();
    let stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            let _ = lines.send(line);
        }
    });
    let mut seen = Vec::new();
    let url = loop {
        let line = stderr_lines
            .recv_timeout(Duration::from_secs(30))
            .unwrap_or_else(|_| panic!("no live view address on stderr: {seen:?}"));
        if let Some(at) = line.strip_prefix("viz: live view at ") {
            break at.to_string();
        }
        seen.push(line);
    };
    assert!(url.starts_with("http://127.0.0.1:"), "{url}");
    let shot = |fragment: &str, name: &str, wait: u64| {
        let out = dir.join(name);
        (
            screenshot_drawn(&format!("{url}/{fragment}"), &out, Duration::from_secs(wait)),
            out,
        )
    };
    // following the run as it goes
    let (following, _) = shot("", "follow.png", 5);
    check_arm_drawn(&following, "live page following the run");
    // two fixed times: the page waits for their samples to arrive; the second browser may come
    // after the run's end (8 s) and gets the whole run from the server's history
    let (at1, path1) = shot("#t=1.0&paused", "t1.png", 6);
    let (at2, _) = shot("#t=2.2&paused", "t2.png", 6);
    check_arm_drawn(&at1, "live page at t = 1 s");
    check_arm_drawn(&at2, "live page at t = 2.2 s");
    let changed = at1.changed(&at2);
    assert!(
        changed > 3_000,
        "the arm moved between t = 1 s and 2.2 s: {changed} pixels changed"
    );
    // the run ends, its summary is written, and the view keeps serving until Ctrl-C
    let serving = std::iter::from_fn(|| stderr_lines.recv_timeout(Duration::from_secs(30)).ok())
        .any(|l| l.starts_with("viz: serving "));
    assert!(serving, "no 'serving … until Ctrl-C' line after the run");
    assert!(dir.join("s.json").is_file(), "the summary is written before holding");
    assert!(child.try_wait().unwrap().is_none(), "--hold keeps serving");
    interrupt(child.id());
    let status = child.wait().unwrap();
    reader.join().unwrap();
    assert_eq!(status.code(), Some(0), "Ctrl-C while holding ends cleanly");
    docs(&path1, "live_view.png");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The issue's case: `faze4 shape --shape circle --html c.html`, the default arm, run in an
/// empty folder, draws the real arm: the scene carries the six official meshes (each with its
/// STL's triangle count) and the screenshot shows the arm. The file is `$FAZE4_INSTALLED_HTML`
/// when set (`.ci/run`: written by `cargo install`'s binary, its source removed), else written
/// here by the binary under test.
fn default_arm_is_drawn_with_the_real_meshes() {
    let dir = temp_dir("default");
    let html = match std::env::var_os("FAZE4_INSTALLED_HTML") {
        Some(path) => PathBuf::from(path),
        None => {
            let run = Command::new(env!("CARGO_BIN_EXE_faze4"))
                .args(["shape", "--shape", "circle", "--html", "c.html"])
                .current_dir(&dir)
                .output()
                .unwrap();
            assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
            assert!(
                run.stderr.is_empty(),
                "no mesh is missing: {}",
                String::from_utf8_lossy(&run.stderr)
            );
            dir.join("c.html")
        }
    };
    let page = std::fs::read_to_string(&html).unwrap_or_else(|e| panic!("{}: {e}", html.display()));
    let header = scene_header(&page);
    assert_eq!(header["name"], "faze4_arm");
    let triangles: Vec<u64> = header["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["indices"].as_u64().unwrap() / 3)
        .collect();
    for link in ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"] {
        let stl = faze4::viz::mesh::read_trimesh(&shared_description().join(format!("meshes/{link}.STL"))).unwrap();
        assert!(
            triangles.contains(&(stl.triangles() as u64)),
            "{link}: no mesh of {} triangles in the scene ({triangles:?})",
            stl.triangles()
        );
    }
    let url = format!("file://{}#t=1&paused", html.display());
    let shot = screenshot_drawn(&url, &dir.join("t1.png"), Duration::from_secs(6));
    check_arm_drawn(&shot, "default arm at t = 1 s");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Pixels of the colliding links' red (strongly red, little green or blue; not the pink
/// target sphere) in the arm's region.
fn red_pixels(image: &Image) -> usize {
    let (x0, y0, x1, y1) = ARM_REGION;
    let mut n = 0;
    for y in y0..y1.min(image.height) {
        for x in x0..x1.min(image.width) {
            let [r, g, b] = image.pixel(x, y).map(|c| c as i32);
            if r > 90 && 3 * g < r && 3 * b < r {
                n += 1;
            }
        }
    }
    n
}

/// `faze4 shape --shape circle --collision-geometry hull --html`: the hulls of nadlaktica and
/// podlaktica overlap at every sample, so both links are drawn red; with the exact meshes
/// (which never touch) nothing is.
fn colliding_links_are_drawn_red() {
    let dir = temp_dir("red");
    let shot = |name: &str, extra: &[&str]| {
        let html = dir.join(format!("{name}.html"));
        let run = Command::new(env!("CARGO_BIN_EXE_faze4"))
            .args([
                "shape",
                "--shape",
                "circle",
                "--duration",
                "2",
                "--trail",
                "none",
                "--html",
            ])
            .arg(&html)
            .args(extra)
            .output()
            .unwrap();
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let url = format!("file://{}#t=1&paused", html.display());
        let out = dir.join(format!("{name}.png"));
        // drawn: the arm's pixels, grey-blue or red (on a slow machine, again with more time)
        let (x0, y0, x1, y1) = ARM_REGION;
        let drawn = |image: &Image| image.arm_pixels(x0, y0, x1, y1) + red_pixels(image) >= MIN_ARM_PIXELS;
        // the hulls' shot is ready once its colliding links are red too (a loaded machine has
        // given a shot of the arm drawn before its colours were)
        let ready = |image: &Image| drawn(image) && (name != "hull" || red_pixels(image) > 3_000);
        let mut image = screenshot(&url, &out, Duration::from_secs(6));
        for more in [3, 8] {
            if ready(&image) {
                break;
            }
            image = screenshot(&url, &out, Duration::from_secs(6) * more);
        }
        assert!(drawn(&image), "{name}: the arm is not drawn");
        image
    };
    let hull = shot("hull", &["--collision-geometry", "hull"]);
    let red = red_pixels(&hull);
    assert!(red > 3_000, "the two colliding links are red: {red} red pixels");
    docs(&dir.join("hull.png"), "self_collision.png");
    let exact = shot("exact", &[]);
    check_arm_drawn(&exact, "exact meshes");
    let red = red_pixels(&exact);
    assert!(red < 50, "nothing collides with the exact meshes: {red} red pixels");

    // the live view draws the same records: the hull run served with --view --hold
    let mut child = Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args(["shape", "--shape", "circle", "--duration", "2", "--trail", "none"])
        .args(["--collision-geometry", "hull", "--view", "--port", "0", "--hold"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap())
        .lines()
        .map_while(Result::ok);
    let url = stderr
        .find_map(|line| line.strip_prefix("viz: live view at ").map(str::to_string))
        .expect("the live view's address on stderr");
    // the run over and the view holding (the run is paced to the wall clock): every record is
    // served, so the page at t = 1 s has its sample whenever Chromium loads it (a screenshot
    // taken during the run could come back before the run reached t = 1 s)
    assert!(
        stderr.any(|line| line.starts_with("viz: serving ")),
        "no 'serving … until Ctrl-C' line after the run"
    );
    let mut red = 0;
    for wait in [8, 24] {
        // on a slow machine, again with more time
        red = red_pixels(&screenshot(
            &format!("{url}/#t=1&paused"),
            &dir.join("live.png"),
            Duration::from_secs(wait),
        ));
        if red > 3_000 {
            break;
        }
    }
    interrupt(child.id());
    assert_eq!(
        child.wait().unwrap().code(),
        Some(0),
        "Ctrl-C while holding ends cleanly"
    );
    assert!(
        red > 3_000,
        "the live view draws the colliding links red: {red} red pixels"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The JSON header of the scene blob an exported page carries (base64 in `faze4-scene`).
fn scene_header(page: &str) -> serde_json::Value {
    let b64 = page
        .split(r#"<script id="faze4-scene" type="application/octet-stream">"#)
        .nth(1)
        .and_then(|rest| rest.split("</script>").next())
        .expect("a scene in the page");
    let blob = base64_decode(b64.trim());
    assert_eq!(&blob[..4], b"F4VZ");
    let len = u32::from_le_bytes(blob[8..12].try_into().unwrap()) as usize;
    serde_json::from_slice(&blob[12..12 + len]).unwrap()
}

/// Standard base64 (RFC 4648, with padding) to bytes.
fn base64_decode(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    for quad in text.as_bytes().chunks(4) {
        let data: Vec<u8> = quad.iter().copied().filter(|&c| c != b'=').map(value).collect();
        let n = data.iter().fold(0u32, |n, &v| n << 6 | v as u32) << (6 * (4 - data.len()));
        out.extend(&n.to_be_bytes()[1..data.len()]);
    }
    out
}
