//! The visual outputs without a browser: scenes of both models, the HTML export's size
//! budget, the live server's assets and refusals, the plot files.

use crate::viz_support;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::time::Duration;

use faze4::viz::mesh::{Indices, read_trimesh};
use faze4::viz::scene::{SampleEncoder, Scene};
use faze4::viz::{HtmlExport, LiveView, PlotRecorder};
use viz_support::*;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("faze4-viz-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn real_model_scene_uses_the_official_meshes() {
    let robot = real_model();
    let scene = Scene::from_model(&robot.model, &robot.geometry);
    assert!(scene.missing.is_empty() && scene.unreadable.is_empty());
    // base cylinder + six meshes, each visual on its link's frame
    assert_eq!(scene.visuals.len(), 7);
    assert_eq!(scene.visuals[0].name, "base_link");
    assert_eq!(scene.visuals[0].slot, None);
    for v in &scene.visuals[1..] {
        assert_eq!(scene.slot_names[v.slot.unwrap()], v.name);
        let mesh = &scene.meshes[v.mesh];
        let stl = read_trimesh(&description().join(format!("meshes/{}.STL", v.name))).unwrap();
        // the compact mesh is the indexed STL: same triangles, same vertices
        assert_eq!(mesh.vertices(), stl.positions.len(), "{}", v.name);
        assert!(matches!(mesh.indices, Indices::U16(_)), "{}: 16-bit indices", v.name);
        let (lo, hi) = stl.bounds();
        assert!(hi.iter().zip(lo).all(|(h, l)| h - l < 0.5), "{}: metres", v.name);
    }
    let bytes: usize = scene.meshes.iter().map(|m| m.byte_size()).sum();
    assert!(bytes < 3_000_000, "{bytes} bytes of geometry");
}

#[test]
fn box_model_scene_needs_no_files() {
    let robot = box_model();
    let scene = Scene::from_model(&robot.model, &robot.geometry);
    assert!(scene.missing.is_empty());
    assert_eq!(scene.visuals.len(), 7);
    let blob = scene.encode();
    assert_eq!(&blob[..4], b"F4VZ");
    let len = u32::from_le_bytes(blob[8..12].try_into().unwrap()) as usize;
    let header: serde_json::Value = serde_json::from_slice(&blob[12..12 + len]).unwrap();
    assert_eq!(header["stride"], SampleEncoder::stride_for(6, 6));
    assert_eq!(header["visuals"].as_array().unwrap().len(), 7);
}

/// The 3D view's budget: a 12 s shape run recorded every 0.02 s with the real meshes is under
/// 10 MB. (Its write time is measured by `cargo bench --bench viz`, not asserted here.)
#[test]
fn html_export_of_a_12_s_circle_with_real_meshes_is_under_10_mb() {
    let dir = temp_dir("html");
    let path = dir.join("circle.html");
    let run = SyntheticRun::circle(real_model(), 12.0);
    let mut export = HtmlExport::new(&path).unwrap();
    run.drive(&mut [&mut export]);
    let html = std::fs::read_to_string(&path).unwrap();
    assert!(html.len() < 10_000_000, "{} bytes", html.len());
    assert!(html.len() > 1_000_000, "the meshes are inside: {} bytes", html.len());
    assert!(!html.contains("{{"), "every placeholder filled");
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "nothing to fetch"
    );
    let samples = html
        .split("<script id=\"faze4-samples\" type=\"application/octet-stream\">")
        .nth(1)
        .unwrap()
        .split("</script>")
        .next()
        .unwrap();
    let records = 601; // t = 0, 0.02, …, 12
    assert_eq!(
        samples.len(),
        (records * 4 * SampleEncoder::stride_for(6, 6)).div_ceil(3) * 4
    );
    let entries: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(entries.len(), 1, "no temporary file left");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn html_export_refuses_a_missing_directory_before_the_run() {
    let err = HtmlExport::new("/nonexistent-dir/x.html").unwrap_err().to_string();
    assert!(err.starts_with("`html`: ") && err.contains("does not exist"), "{err}");
    let err = PlotRecorder::new("plot.pdf").unwrap_err().to_string();
    assert!(err.contains(".svg or .png"), "{err}");
}

#[test]
fn plots_are_written_as_svg_and_png() {
    let dir = temp_dir("plot");
    let run = SyntheticRun::circle(box_model(), 6.0);
    let mut svg = PlotRecorder::new(dir.join("run.svg")).unwrap();
    let mut png = PlotRecorder::new(dir.join("run.png")).unwrap();
    run.drive(&mut [&mut svg, &mut png]);
    let text = std::fs::read_to_string(dir.join("run.svg")).unwrap();
    assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
    for caption in [
        "J1 rotary_base",
        "tracking error",
        "tool distance to the reference path",
    ] {
        assert!(text.contains(caption), "{caption}");
    }
    let bytes = std::fs::read(dir.join("run.png")).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (1400, 44 + 7 * 220));
    // text and curves are drawn: plenty of dark pixels
    let dark = buf.chunks(3).filter(|p| p.iter().all(|&c| c < 100)).count();
    assert!(dark > 20_000, "{dark} dark pixels");
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------------- live view

/// A raw HTTP/1.1 request; returns (status code, headers, body).
fn http(port: u16, request: &str) -> (u16, String, Vec<u8>) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    s.write_all(request.as_bytes()).unwrap();
    let mut out = Vec::new();
    s.read_to_end(&mut out).unwrap();
    let split = out.windows(4).position(|w| w == b"\r\n\r\n").expect("a response head");
    let head = String::from_utf8(out[..split].to_vec()).unwrap();
    let code = head.split(' ').nth(1).unwrap().parse().unwrap();
    (code, head, out[split + 4..].to_vec())
}

fn get(port: u16, path: &str) -> (u16, String, Vec<u8>) {
    http(port, &format!("GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n"))
}

#[test]
fn live_view_serves_its_assets_and_nothing_else() {
    let mut live = LiveView::start(0).unwrap().with_realtime(false);
    let port = live.port();
    assert_eq!(live.url(), format!("http://127.0.0.1:{port}"));

    let (code, head, body) = get(port, "/");
    assert_eq!(code, 200);
    assert!(head.contains("text/html"));
    let page = String::from_utf8(body).unwrap();
    assert!(page.contains("\"mode\":\"live\"") && page.contains("EventSource"));
    assert_eq!(get(port, "/scene").0, 503, "no run yet");

    // a browser already connected sees the run from its start
    let mut early = TcpStream::connect(("127.0.0.1", port)).unwrap();
    early
        .write_all(format!("GET /events HTTP/1.1\r\nHost: localhost:{port}\r\n\r\n").as_bytes())
        .unwrap();
    early.set_read_timeout(Some(Duration::from_secs(10))).unwrap();

    SyntheticRun::wave(box_model(), 1.0, 25.0, 2.0).drive(&mut [&mut live]);

    let (code, _, scene) = get(port, "/scene?run=1");
    assert_eq!(code, 200);
    assert_eq!(&scene[..4], b"F4VZ");
    // a browser connecting after the run gets all of it: run, 51 records, end
    let late = events_until_end(TcpStream::connect(("127.0.0.1", port)).unwrap(), port, true);
    let early = events_until_end(early, port, false);
    for stream in [&late, &early] {
        assert!(
            stream.contains("event: run\ndata: {\"run\":1,\"stride\":91}"),
            "{stream}"
        );
        let b64: usize = stream
            .split("event: samples\ndata: ")
            .skip(1)
            .map(|s| s.split('\n').next().unwrap().len())
            .sum();
        let records = 51; // 0, 0.02, …, 1.0
        assert!(b64 >= records * 85 * 4 * 4 / 3, "{b64} base64 chars");
        // the summary, what was simulated first
        assert!(
            stream.contains("event: end\ndata: {\"robot\":\"faze4_arm\""),
            "{stream}"
        );
        assert!(stream.contains(",\"dof\":6,"));
    }

    // refusals
    for path in [
        "/../etc/passwd",
        "/etc/passwd",
        "/viewer.js",
        "/scene/../../x",
        "/%2e%2e/x",
    ] {
        assert_eq!(get(port, path).0, 404, "{path}");
    }
    assert_eq!(http(port, "GET / HTTP/1.1\r\nHost: evil.example:80\r\n\r\n").0, 403);
    assert_eq!(http(port, "POST / HTTP/1.1\r\nHost: localhost\r\n\r\n").0, 405);
    assert_eq!(http(port, "garbage\r\n\r\n").0, 400);
    // a client that connects and says nothing, or leaves mid-stream, harms no one
    let idle = TcpStream::connect(("127.0.0.1", port)).unwrap();
    let mut gone = TcpStream::connect(("127.0.0.1", port)).unwrap();
    gone.write_all(format!("GET /events HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n").as_bytes())
        .unwrap();
    drop(gone);
    assert_eq!(get(port, "/").0, 200);
    drop(idle);
}

/// Reads an event stream until its `end` event (sending the request first if `request`).
fn events_until_end(mut s: TcpStream, port: u16, request: bool) -> String {
    if request {
        s.write_all(format!("GET /events HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n").as_bytes())
            .unwrap();
    }
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let mut text = String::new();
    let mut buf = [0u8; 65536];
    while !text.contains("event: end\ndata: ") || !text.ends_with("\n\n") {
        let n = s.read(&mut buf).unwrap();
        assert!(n > 0, "stream closed early: {text}");
        text.push_str(std::str::from_utf8(&buf[..n]).unwrap());
    }
    assert!(text.starts_with("HTTP/1.1 200 OK\r\nContent-Type: text/event-stream"));
    text
}

/// 200 connections that send nothing (half-open, as a port scanner or a stalled client leaves
/// them) do not keep a browser out: a new request is answered at once, each idle connection
/// giving its place to a newer one, not after they time out (2 s); a client that sends its
/// request a byte at a time is closed once that time is up.
#[test]
fn idle_connections_do_not_keep_a_browser_out() {
    let live = LiveView::start(0).unwrap().with_realtime(false);
    let port = live.port();
    let idle: Vec<TcpStream> = (0..200)
        .map(|_| TcpStream::connect(("127.0.0.1", port)).unwrap())
        .collect();
    let start = std::time::Instant::now();
    let (code, _, page) = get(port, "/");
    assert_eq!(code, 200);
    assert!(String::from_utf8_lossy(&page).contains("EventSource"));
    assert!(
        start.elapsed() < Duration::from_millis(1500),
        "the page came after {:?}: it waited for idle connections to time out",
        start.elapsed()
    );
    drop(idle);
    // a byte every 300 ms: the connection is closed after the 2 s the head may take
    let mut slow = TcpStream::connect(("127.0.0.1", port)).unwrap();
    slow.set_read_timeout(Some(Duration::from_millis(300))).unwrap();
    let start = std::time::Instant::now();
    let mut byte = [0u8; 1];
    let closed_after = loop {
        let _ = slow.write_all(b"G");
        match slow.read(&mut byte) {
            Ok(0) => break start.elapsed(),
            Err(e) if !matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {
                break start.elapsed();
            }
            _ => assert!(
                start.elapsed() < Duration::from_secs(6),
                "a request sent a byte at a time is never cut off"
            ),
        }
    };
    assert!(
        closed_after >= Duration::from_millis(1900),
        "closed after {closed_after:?}"
    );
}

#[test]
fn a_port_in_use_is_a_clear_error() {
    let first = LiveView::start(0).unwrap();
    let err = LiveView::start(first.port()).err().expect("the port is taken");
    let message = err.to_string();
    assert!(
        matches!(err, faze4::Error::InvalidArgument { ref option, .. } if option == "`port`"),
        "{message}"
    );
    assert!(message.contains(&format!("port {} ", first.port())) && message.contains("already in use"));
    assert_eq!(message.lines().count(), 1);
}

#[test]
fn live_view_paces_samples_to_the_wall_clock() {
    let mut live = LiveView::start(0).unwrap();
    let started = std::time::Instant::now();
    SyntheticRun::wave(box_model(), 0.5, 25.0, 2.0).drive(&mut [&mut live]);
    let took = started.elapsed().as_secs_f64();
    // the last sample (t = 0.5 s) is published 0.5 s after the first
    assert!(took >= 0.5, "{took} s");
}

#[test]
fn hold_until_returns_when_asked_and_serves_meanwhile() {
    let live = LiveView::start(0).unwrap();
    let port = live.port();
    let polls = std::cell::Cell::new(0);
    live.hold_until(|| {
        polls.set(polls.get() + 1);
        if polls.get() == 2 {
            assert_eq!(get(port, "/").0, 200, "serving while held");
        }
        polls.get() >= 3
    });
    assert_eq!(polls.get(), 3);
}

/// The recorders behind the real closed loop (`sim::run`): a circle on the board, drawn by
/// the real arm under the 5 kHz PD controller for 2 s, into the HTML export, the plot and the
/// live view at once.
#[test]
fn the_real_closed_loop_feeds_every_visual_recorder() {
    let run = SyntheticRun::circle(real_model(), 2.0);
    let dir = temp_dir("closed-loop");
    let mut html = HtmlExport::new(dir.join("run.html")).unwrap();
    let mut plot = PlotRecorder::new(dir.join("run.svg")).unwrap();
    let mut live = LiveView::start(0).unwrap().with_realtime(false);
    let summary = run.drive(&mut [&mut html, &mut plot, &mut live]);
    assert!(summary.diverged.is_none());
    let deviation = summary.path_deviation_mm.unwrap();
    assert!(deviation.max < 1.0, "the tool follows the circle: {deviation:?}");
    let page = std::fs::read_to_string(dir.join("run.html")).unwrap();
    assert!(page.contains("\"path_deviation_mm\""), "the summary is in the page");
    let svg = std::fs::read_to_string(dir.join("run.svg")).unwrap();
    assert!(svg.contains("tool distance to the reference path"));
    let (code, _, scene) = get(live.port(), "/scene");
    assert_eq!((code, &scene[..4]), (200, &b"F4VZ"[..]));
    std::fs::remove_dir_all(&dir).unwrap();
}
