//! The 3D views in a real browser: headless Chromium (Debian's `chromium`, software WebGL
//! through SwiftShader) opens the exported HTML file and the live page, takes screenshots,
//! and the test reads their pixels: the arm is drawn where it should be, and it moves between
//! two times. Chromium missing is a failure, never a skip (`.ci/run` installs it).
//!
//! With `FAZE4_UPDATE_DOCS=1` the screenshots at the known poses are also copied to
//! `docs/html_export.png` and `docs/live_view.png`.

mod viz_support;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::mpsc;
use std::time::Duration;

use faze4::viz::{HtmlExport, LiveView};
use viz_support::*;

const WIDTH: usize = 1000;
const HEIGHT: usize = 700;

fn chromium() -> PathBuf {
    let candidates = [std::env::var("FAZE4_CHROMIUM").unwrap_or_default(), "chromium".into()];
    for c in candidates.iter().filter(|c| !c.is_empty()) {
        if Command::new(c)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
        {
            return PathBuf::from(c);
        }
    }
    panic!(
        "Chromium is needed for the browser tests and was not found: install it with \
         `apt-get install -y chromium` (.ci/run does), or set FAZE4_CHROMIUM to its path"
    );
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
/// stopped) taken again with more time.
fn screenshot_drawn(url: &str, out: &Path, wait: Duration) -> Image {
    let image = screenshot(url, out, wait);
    let (x0, y0, x1, y1) = ARM_REGION;
    if image.arm_pixels(x0, y0, x1, y1) >= MIN_ARM_PIXELS {
        return image;
    }
    eprintln!("{url}: not drawn after {wait:?}, trying again with more time");
    screenshot(url, out, wait * 4)
}

fn docs(image: &Path, name: &str) {
    if std::env::var("FAZE4_UPDATE_DOCS").is_ok_and(|v| v == "1") {
        let to = repo().join("docs").join(name);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(image, &to).unwrap();
        eprintln!("updated {}", to.display());
    }
}

/// A shape run exported to HTML with the real meshes, opened from the file system.
#[test]
fn exported_html_draws_the_arm_and_plays_the_motion() {
    let dir = temp_dir("html");
    let html = dir.join("circle.html");
    let mut export = HtmlExport::new(&html).unwrap();
    SyntheticRun::circle(real_model(), 6.0).drive(&mut [&mut export]);
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

/// The live page, following a run paced to the wall clock (a wave of the real arm) served by
/// a LiveView in this process.
#[test]
fn live_page_draws_the_arm_and_follows_the_run() {
    let dir = temp_dir("live");
    let live = LiveView::start(0).unwrap();
    let url = live.url();
    let (done, wait_done) = mpsc::channel::<()>();
    let runner = std::thread::spawn(move || {
        let mut live = live;
        SyntheticRun::wave(real_model(), 8.0, 25.0, 2.0).drive(&mut [&mut live]);
        // keep serving (as --hold does) until the test is done
        let _ = wait_done.recv_timeout(Duration::from_secs(120));
    });
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
    // two fixed times: the page waits for their samples to arrive; the second browser comes
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
    done.send(()).unwrap();
    runner.join().unwrap();
    docs(&path1, "live_view.png");
    std::fs::remove_dir_all(&dir).unwrap();
}
