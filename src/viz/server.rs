//! The live view's HTTP server on 127.0.0.1 (std::net, one thread per connection). It serves
//! exactly three things: the page (`/`), the scene blob of the current run (`/scene`), and a
//! Server-Sent Events stream (`/events`): `run` (a new run: its id and record size), `samples`
//! (base64 of whole f32 records), `end` (the summary JSON). A browser that connects late or
//! reloads gets the run and every sample so far, then the new ones. The run only ever appends
//! to a shared buffer and wakes the stream threads ([`Server::publish_run`],
//! [`Server::publish_samples`], [`Server::publish_end`]), so a slow or dead browser cannot
//! block it.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpListener, TcpStream};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use serde_json::json;

use super::util::base64;
use crate::error::{Error, Result};

/// Connections served at once. A new one beyond them takes the place of the oldest that has not
/// sent its request yet (an idle or half-open connection); if every one is a browser's stream,
/// it is closed at once.
const MAX_CONNECTIONS: usize = 64;
/// A client has this long to send its whole request head (a browser sends it at once; a
/// connection that sends nothing, or a byte at a time, is closed then).
const HEAD_TIMEOUT: Duration = Duration::from_secs(2);
/// A stream with nothing new sends a comment this often (finds closed tabs).
const KEEPALIVE: Duration = Duration::from_secs(10);
/// A browser that takes longer than this to take a write is dropped.
const SOCKET_TIMEOUT: Duration = Duration::from_secs(10);
/// Longest request head read.
const MAX_REQUEST: usize = 16 * 1024;

/// The server: its address, the state its connections read, and the accepting thread. Stops
/// (and joins its acceptor) when dropped.
pub(super) struct Server {
    shared: Arc<Shared>,
    addr: SocketAddr,
    acceptor: Mutex<Option<JoinHandle<()>>>,
}

struct Shared {
    state: Mutex<State>,
    wake: Condvar,
    port: u16,
    page: String,
}

#[derive(Default)]
struct State {
    /// Id of the current run (0: none yet).
    run: u64,
    /// f32 per record.
    stride: usize,
    /// The current run's scene blob.
    scene: Option<Arc<Vec<u8>>>,
    /// Every record of the current run so far, little-endian f32.
    samples: Vec<u8>,
    /// The summary JSON, once the run finished.
    end: Option<String>,
    stopping: bool,
    /// Connections being served (threads alive, less those evicted).
    connections: usize,
    /// The connections still reading their request head, oldest first (id, a handle to close
    /// it): the ones a new connection may evict.
    idle: std::collections::VecDeque<(u64, TcpStream)>,
    /// The next connection's id.
    next_id: u64,
}

fn lock(shared: &Shared) -> MutexGuard<'_, State> {
    // a panicking connection thread must not take the view down
    shared.state.lock().unwrap_or_else(|e| e.into_inner())
}

impl Server {
    /// Starts serving `page` on `127.0.0.1:port` (0: any free port). A port already in use is an
    /// [`Error::InvalidArgument`] for `port`.
    pub(super) fn start(port: u16, page: String) -> Result<Server> {
        let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, port)).map_err(|e| {
            let message = if e.kind() == std::io::ErrorKind::AddrInUse {
                format!("port {port} on 127.0.0.1 is already in use (another live view?); choose another port")
            } else {
                format!("cannot listen on 127.0.0.1:{port}: {e}")
            };
            Error::option("port", message)
        })?;
        let addr = listener
            .local_addr()
            .map_err(|e| Error::option("port", format!("cannot listen on 127.0.0.1:{port}: {e}")))?;
        let shared = Arc::new(Shared {
            state: Mutex::new(State::default()),
            wake: Condvar::new(),
            port: addr.port(),
            page,
        });
        let acceptor = {
            let shared = shared.clone();
            std::thread::Builder::new()
                .name("faze4-live".into())
                .spawn(move || accept(listener, shared))
                .map_err(|e| Error::option("port", format!("cannot start the live view: {e}")))?
        };
        Ok(Server {
            shared,
            addr,
            acceptor: Mutex::new(Some(acceptor)),
        })
    }

    /// The address served.
    pub(super) fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Whether the accepting thread has ended (the server stopped by itself).
    pub(super) fn is_finished(&self) -> bool {
        (self.acceptor.lock().unwrap_or_else(|e| e.into_inner()))
            .as_ref()
            .is_none_or(|h| h.is_finished())
    }

    /// A new run: its scene blob and record size (f32 per record); earlier samples are dropped.
    pub(super) fn publish_run(&self, stride: usize, scene: Vec<u8>) {
        {
            let mut st = lock(&self.shared);
            st.run += 1;
            st.stride = stride;
            st.scene = Some(Arc::new(scene));
            st.samples.clear();
            st.end = None;
        }
        self.shared.wake.notify_all();
    }

    /// Whole records of the current run (little-endian f32).
    pub(super) fn publish_samples(&self, bytes: &[u8]) {
        lock(&self.shared).samples.extend_from_slice(bytes);
        self.shared.wake.notify_all();
    }

    /// The end of the current run, with its summary JSON.
    pub(super) fn publish_end(&self, summary_json: String) {
        lock(&self.shared).end = Some(summary_json);
        self.shared.wake.notify_all();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        lock(&self.shared).stopping = true;
        self.shared.wake.notify_all();
        // wake the acceptor blocked in accept()
        let _ = TcpStream::connect_timeout(&self.addr, Duration::from_secs(1));
        if let Some(h) = self.acceptor.lock().unwrap_or_else(|e| e.into_inner()).take() {
            let _ = h.join();
        }
    }
}

fn accept(listener: TcpListener, shared: Arc<Shared>) {
    for stream in listener.incoming() {
        if lock(&shared).stopping {
            return;
        }
        let Ok(stream) = stream else {
            // e.g. out of file descriptors: let it pass
            std::thread::sleep(Duration::from_millis(20));
            continue;
        };
        let id = {
            let mut st = lock(&shared);
            if st.connections >= MAX_CONNECTIONS {
                // the oldest connection that has not sent its request makes room
                let Some((_, oldest)) = st.idle.pop_front() else {
                    continue;
                };
                let _ = oldest.shutdown(std::net::Shutdown::Both);
                st.connections -= 1;
            }
            st.connections += 1;
            st.next_id += 1;
            if let Ok(handle) = stream.try_clone() {
                let id = st.next_id;
                st.idle.push_back((id, handle));
            }
            st.next_id
        };
        let spawned = std::thread::Builder::new().name("faze4-live-conn".into()).spawn({
            let shared = shared.clone();
            move || {
                let evicted = serve(stream, &shared, id).unwrap_or(false);
                if !evicted {
                    lock(&shared).connections -= 1;
                }
            }
        });
        if spawned.is_err() {
            let mut st = lock(&shared);
            st.connections -= 1;
            st.idle.retain(|(i, _)| *i != id);
        }
    }
}

/// One request (connection `id`): read its head within [`HEAD_TIMEOUT`], answer, close.
/// `Ok(true)` when a newer connection evicted it while it read its head (its place is counted
/// free already).
fn serve(stream: TcpStream, shared: &Shared, id: u64) -> std::io::Result<bool> {
    stream.set_write_timeout(Some(SOCKET_TIMEOUT))?;
    let _ = stream.set_nodelay(true);
    let head = read_head(&stream);
    // no longer idle; gone from the list already if evicted
    let evicted = {
        let mut st = lock(shared);
        let before = st.idle.len();
        st.idle.retain(|(i, _)| *i != id);
        st.idle.len() == before
    };
    if evicted {
        return Ok(true);
    }
    answer(stream, shared, head?).map(|()| false)
}

/// The answer to a request whose head was read (`None`: malformed).
fn answer(
    mut stream: TcpStream,
    shared: &Shared,
    head: Option<(String, String, Option<String>)>,
) -> std::io::Result<()> {
    let Some((method, target, host)) = head else {
        return respond(&mut stream, "400 Bad Request", "text/plain", b"bad request\n", false);
    };
    let head = method == "HEAD";
    if method != "GET" && !head {
        return respond(&mut stream, "405 Method Not Allowed", "text/plain", b"only GET\n", head);
    }
    // only this machine's names for the server (guards against DNS rebinding)
    if let Some(host) = host {
        let port = shared.port;
        let allowed = [format!("127.0.0.1:{port}"), format!("localhost:{port}")];
        if !allowed.iter().any(|a| a.eq_ignore_ascii_case(&host)) {
            return respond(&mut stream, "403 Forbidden", "text/plain", b"unknown host\n", head);
        }
    }
    let path = target.split(['?', '#']).next().unwrap_or("");
    match path {
        "/" | "/index.html" => respond(
            &mut stream,
            "200 OK",
            "text/html; charset=utf-8",
            shared.page.as_bytes(),
            head,
        ),
        "/scene" => {
            let scene = lock(shared).scene.clone();
            match scene {
                Some(s) => respond(&mut stream, "200 OK", "application/octet-stream", &s, head),
                None => respond(
                    &mut stream,
                    "503 Service Unavailable",
                    "text/plain",
                    b"no run yet\n",
                    head,
                ),
            }
        }
        "/events" if !head => events(stream, shared),
        _ => respond(&mut stream, "404 Not Found", "text/plain", b"not found\n", head),
    }
}

/// A stream read until a deadline: each read waits at most the time left, and fails with
/// `TimedOut` once it has passed, however slowly the bytes come.
struct Deadline<'a> {
    stream: &'a TcpStream,
    until: Instant,
}

impl Read for Deadline<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let left = self.until.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(std::io::ErrorKind::TimedOut.into());
        }
        self.stream.set_read_timeout(Some(left))?;
        (&mut &*self.stream).read(buf)
    }
}

/// The request line's method and target, and the Host header, read within [`HEAD_TIMEOUT`];
/// `None` if malformed.
fn read_head(stream: &TcpStream) -> std::io::Result<Option<(String, String, Option<String>)>> {
    let until = Instant::now() + HEAD_TIMEOUT;
    let mut reader = BufReader::new(Deadline { stream, until }.take(MAX_REQUEST as u64));
    let mut line = String::new();
    reader.read_line(&mut line)?;
    let mut parts = line.split_ascii_whitespace();
    let (Some(method), Some(target), Some(version)) = (parts.next(), parts.next(), parts.next()) else {
        return Ok(None);
    };
    if !version.starts_with("HTTP/1.") || !target.starts_with('/') {
        return Ok(None);
    }
    let (method, target) = (method.to_string(), target.to_string());
    let mut host = None;
    loop {
        line.clear();
        if reader.read_line(&mut line)? == 0 {
            return Ok(None); // the head did not end (too long, or the client went away)
        }
        let l = line.trim_end();
        if l.is_empty() {
            break;
        }
        if let Some((name, value)) = l.split_once(':')
            && name.eq_ignore_ascii_case("host")
        {
            host = Some(value.trim().to_string());
        }
    }
    Ok(Some((method, target, host)))
}

fn respond(stream: &mut TcpStream, status: &str, kind: &str, body: &[u8], head_only: bool) -> std::io::Result<()> {
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: no-store\r\n\
         X-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
        body.len()
    );
    stream.write_all(head.as_bytes())?;
    if !head_only {
        stream.write_all(body)?;
    }
    stream.flush()
}

/// The event stream of one browser, until it goes away or the server stops.
fn events(mut stream: TcpStream, shared: &Shared) -> std::io::Result<()> {
    stream.write_all(
        b"HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n\
          Connection: close\r\n\r\nretry: 1000\n\n",
    )?;
    let (mut run, mut sent, mut ended) = (0u64, 0usize, false);
    loop {
        let mut out = String::new();
        let fresh: Vec<u8>;
        {
            let mut st = lock(shared);
            loop {
                if st.stopping {
                    return Ok(());
                }
                if st.run != run || st.samples.len() > sent || (st.end.is_some() && !ended) {
                    break;
                }
                let (guard, wait) = shared
                    .wake
                    .wait_timeout(st, KEEPALIVE)
                    .unwrap_or_else(|e| e.into_inner());
                st = guard;
                if wait.timed_out() {
                    out.push_str(": keepalive\n\n");
                    break;
                }
            }
            if st.run != run {
                run = st.run;
                sent = 0;
                ended = false;
                out += &format!("event: run\ndata: {}\n\n", json!({"run": run, "stride": st.stride}));
            }
            fresh = st.samples[sent..].to_vec();
            sent = st.samples.len();
            let end = match (&st.end, ended) {
                (Some(summary), false) => Some(summary.clone()),
                _ => None,
            };
            drop(st);
            if !fresh.is_empty() {
                out += &format!("event: samples\ndata: {}\n\n", base64(&fresh));
            }
            if let Some(summary) = end {
                ended = true;
                out += &format!("event: end\ndata: {summary}\n\n");
            }
        }
        stream.write_all(out.as_bytes())?;
        stream.flush()?;
    }
}
