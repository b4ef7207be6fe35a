//! docs/sweep.md's Slurm scripts, run as the page writes them on a real one-node Slurm cluster:
//! munged, slurmctld and slurmd (Debian's `slurm-wlm` and `munge`) started under a temporary
//! directory with their own configuration and ports, the three files extracted from the page
//! with the sweep made small (each replacement must match exactly once), `bash submit.sh`, a
//! wait for the merge job (with a timeout, failing as soon as it can never run), and the merged
//! table compared cell for cell with the same sweep run unsharded, the wall times left out.
//!
//! Its own harness (`harness = false`), as tests/browser.rs: without Slurm (or not as root, which
//! slurmd needs) the test prints ONE notice line; with `FAZE4_REQUIRE_SLURM=1` (`.ci/run` sets
//! it) that is a failure. Every daemon it started is stopped by its pid, on failure too.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use common::{repo_path, temp_dir};

const NAME: &str = "the_docs_slurm_scripts_run_as_written";

/// How long the jobs may take, queueing included.
const TIMEOUT: Duration = Duration::from_secs(240);

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--list") {
        println!("{NAME}: test");
        return ExitCode::SUCCESS;
    }
    let exact = args.iter().any(|a| a == "--exact");
    let mut filters = args.iter().filter(|a| !a.starts_with('-')).peekable();
    let skipped = args.windows(2).any(|w| w[0] == "--skip" && NAME.contains(&w[1]));
    let selected =
        filters.peek().is_none() || filters.any(|f| if exact { f == NAME } else { NAME.contains(f.as_str()) });
    if !selected || skipped {
        return ExitCode::SUCCESS;
    }
    let required = std::env::var("FAZE4_REQUIRE_SLURM").is_ok_and(|v| v == "1");
    let dir = temp_dir("slurm");
    let cluster = match Cluster::start(&dir) {
        Ok(cluster) => cluster,
        Err(why) => {
            println!(
                "{}: the Slurm test (tests/slurm.rs) did not run: {why}; install Slurm as root with \
                 `apt-get install slurm-wlm munge`{}",
                if required { "FAILED" } else { "NOTICE" },
                if required {
                    "; FAZE4_REQUIRE_SLURM=1 requires it"
                } else {
                    ""
                }
            );
            let _ = std::fs::remove_dir_all(&dir);
            return if required { ExitCode::FAILURE } else { ExitCode::SUCCESS };
        }
    };
    println!("\nrunning 1 Slurm test");
    let outcome = std::panic::catch_unwind(|| the_docs_slurm_scripts_run_as_written(&cluster));
    if outcome.is_err() {
        cluster.print_logs();
    }
    drop(cluster);
    println!("test {NAME} ... {}", if outcome.is_ok() { "ok" } else { "FAILED" });
    if outcome.is_ok() {
        let _ = std::fs::remove_dir_all(&dir);
        println!("\nslurm test result: ok");
        ExitCode::SUCCESS
    } else {
        println!("\nslurm test result: FAILED (files kept in {})", dir.display());
        ExitCode::FAILURE
    }
}

/// A program of the Slurm or munge packages: on PATH, or in /usr/sbin (not on a user's PATH).
fn program(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    (std::env::split_paths(&path).chain([PathBuf::from("/usr/sbin"), PathBuf::from("/sbin")]))
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// A one-node cluster under a directory: its daemons, stopped (by pid) when dropped.
struct Cluster {
    dir: PathBuf,
    conf: PathBuf,
    daemons: Vec<(&'static str, Child)>,
}

impl Cluster {
    fn start(dir: &Path) -> Result<Cluster, String> {
        let mut missing = Vec::new();
        for name in [
            "munged",
            "slurmctld",
            "slurmd",
            "sbatch",
            "squeue",
            "scontrol",
            "sinfo",
            "scancel",
        ] {
            if program(name).is_none() {
                missing.push(name);
            }
        }
        if !missing.is_empty() {
            return Err(format!("{} not found", missing.join(", ")));
        }
        // SAFETY: geteuid has no arguments and cannot fail
        if unsafe { libc::geteuid() } != 0 {
            return Err("slurmd must run as root".into());
        }
        let mut cluster = Cluster {
            dir: dir.to_path_buf(),
            conf: dir.join("slurm.conf"),
            daemons: Vec::new(),
        };
        cluster.start_daemons()?;
        Ok(cluster)
    }

    fn start_daemons(&mut self) -> Result<(), String> {
        use std::os::unix::fs::PermissionsExt;
        let dir = self.dir.clone();
        let io = |e: std::io::Error| e.to_string();
        // munged checks that every directory up to its socket is searchable by all
        for d in [
            dir.clone(),
            dir.join("munge"),
            dir.join("state"),
            dir.join("spool"),
            dir.join("log"),
        ] {
            std::fs::create_dir_all(&d).map_err(io)?;
            std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o755)).map_err(io)?;
        }
        let mut key = vec![0u8; 1024];
        std::io::Read::read_exact(&mut std::fs::File::open("/dev/urandom").map_err(io)?, &mut key).map_err(io)?;
        let key_file = dir.join("munge/munge.key");
        std::fs::write(&key_file, &key).map_err(io)?;
        std::fs::set_permissions(&key_file, std::fs::Permissions::from_mode(0o400)).map_err(io)?;
        let socket = dir.join("munge/munge.socket");
        let munge = |f: &str| format!("--{f}={}", dir.join("munge").join(f.replace("-file", "")).display());
        self.spawn(
            "munged",
            Command::new(program("munged").unwrap()).args([
                "--foreground".to_string(),
                format!("--key-file={}", key_file.display()),
                format!("--socket={}", socket.display()),
                munge("pid-file"),
                munge("log-file"),
                munge("seed-file"),
            ]),
        )?;
        self.wait_until("munged's socket", Duration::from_secs(10), || {
            Ok(socket.exists().then_some(()))
        })?;

        // two free ports for slurmctld and slurmd
        let listeners: Vec<std::net::TcpListener> = (0..2)
            .map(|_| std::net::TcpListener::bind("127.0.0.1:0").map_err(io))
            .collect::<Result<_, _>>()?;
        let ports: Vec<u16> = listeners.iter().map(|l| l.local_addr().unwrap().port()).collect();
        drop(listeners);
        let host = Command::new("hostname").arg("-s").output().map_err(io)?;
        let host = String::from_utf8_lossy(&host.stdout).trim().to_string();
        let d = dir.display();
        let conf = format!(
            "ClusterName=faze4test\n\
             SlurmctldHost={host}(127.0.0.1)\n\
             SlurmctldPort={}\n\
             SlurmdPort={}\n\
             AuthType=auth/munge\n\
             AuthInfo=socket={}\n\
             CredType=cred/munge\n\
             SlurmUser=root\n\
             SlurmdUser=root\n\
             StateSaveLocation={d}/state\n\
             SlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/slurmctld.pid\n\
             SlurmdPidFile={d}/slurmd.pid\n\
             SlurmctldLogFile={d}/log/slurmctld.log\n\
             SlurmdLogFile={d}/log/slurmd.log\n\
             ProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\n\
             JobAcctGatherType=jobacct_gather/none\n\
             AccountingStorageType=accounting_storage/none\n\
             JobCompType=jobcomp/none\n\
             MpiDefault=none\n\
             SchedulerType=sched/backfill\n\
             SelectType=select/cons_tres\n\
             SelectTypeParameters=CR_CPU\n\
             ReturnToService=2\n\
             SlurmdParameters=config_overrides\n\
             NodeName=faze4node NodeHostname={host} NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN\n\
             PartitionName=debug Nodes=faze4node Default=YES MaxTime=INFINITE State=UP\n",
            ports[0],
            ports[1],
            socket.display()
        );
        std::fs::write(&self.conf, conf).map_err(io)?;
        let conf = self.conf.display().to_string();
        self.spawn(
            "slurmctld",
            Command::new(program("slurmctld").unwrap()).args(["-D", "-f", &conf]),
        )?;
        self.spawn(
            "slurmd",
            Command::new(program("slurmd").unwrap()).args(["-D", "-N", "faze4node", "-f", &conf]),
        )?;
        let conf = self.conf.clone();
        self.wait_until("the node to be idle", Duration::from_secs(60), || {
            let state = client(&conf, "sinfo", &["-h", "-o", "%T"]).unwrap_or_default();
            Ok((state.trim() == "idle").then_some(()))
        })
    }

    /// Starts `command` (a daemon in the foreground), its output into log/NAME.out.
    fn spawn(&mut self, name: &'static str, command: &mut Command) -> Result<(), String> {
        let log = std::fs::File::create(self.dir.join(format!("log/{name}.out"))).map_err(|e| e.to_string())?;
        let child = command
            .env("SLURM_CONF", &self.conf)
            .stdin(Stdio::null())
            .stdout(log.try_clone().map_err(|e| e.to_string())?)
            .stderr(log)
            .spawn()
            .map_err(|e| format!("{name} did not start: {e}"))?;
        self.daemons.push((name, child));
        Ok(())
    }

    /// Polls `ready` until it gives a value; an error when a daemon has exited or after `limit`.
    fn wait_until<T>(
        &mut self,
        what: &str,
        limit: Duration,
        mut ready: impl FnMut() -> Result<Option<T>, String>,
    ) -> Result<T, String> {
        let started = Instant::now();
        loop {
            if let Some(value) = ready()? {
                return Ok(value);
            }
            for (name, child) in &mut self.daemons {
                if let Ok(Some(status)) = child.try_wait() {
                    let log = std::fs::read_to_string(self.dir.join(format!("log/{name}.out"))).unwrap_or_default();
                    let last = log.lines().rev().find(|l| l.contains("rror")).unwrap_or("");
                    return Err(format!("{name} exited ({status}) waiting for {what}: {last}"));
                }
            }
            if started.elapsed() > limit {
                return Err(format!("no {what} after {} s", limit.as_secs()));
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// A client command of this cluster: its stdout, or why it failed.
    fn client(&self, name: &str, args: &[&str]) -> Result<String, String> {
        client(&self.conf, name, args)
    }

    fn print_logs(&self) {
        for name in ["log/slurmctld.log", "log/slurmd.log", "log/munged.out"] {
            let text = std::fs::read_to_string(self.dir.join(name)).unwrap_or_default();
            let lines: Vec<&str> = text.lines().collect();
            println!("--- {name} (last 15 lines)");
            for line in &lines[lines.len().saturating_sub(15)..] {
                println!("{line}");
            }
        }
    }
}

impl Drop for Cluster {
    /// Cancels the jobs left, then stops each daemon by its pid (SIGTERM, SIGKILL after 10 s).
    fn drop(&mut self) {
        if self.daemons.iter().any(|(n, _)| *n == "slurmctld") {
            let _ = self.client("scancel", &["--user=root"]);
            std::thread::sleep(Duration::from_millis(500));
        }
        for (_, child) in self.daemons.iter_mut().rev() {
            // SAFETY: kill(2) only reads its arguments; the pid is our child's, not yet waited for
            unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
            let started = Instant::now();
            while child.try_wait().ok().flatten().is_none() && started.elapsed() < Duration::from_secs(10) {
                std::thread::sleep(Duration::from_millis(50));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// A client command of the cluster configured by `conf`: its stdout, or why it failed.
fn client(conf: &Path, name: &str, args: &[&str]) -> Result<String, String> {
    let out = Command::new(program(name).ok_or(format!("{name} not found"))?)
        .args(args)
        .env("SLURM_CONF", conf)
        .output()
        .map_err(|e| e.to_string())?;
    match out.status.success() {
        true => Ok(String::from_utf8_lossy(&out.stdout).into_owned()),
        false => Err(String::from_utf8_lossy(&out.stderr).trim().to_string()),
    }
}

/// The fenced blocks of `markdown` whose info string is `bash file=NAME`: (NAME, text).
fn files_of(markdown: &str) -> Vec<(String, String)> {
    let mut files = Vec::new();
    let mut lines = markdown.lines();
    while let Some(line) = lines.next() {
        if let Some(name) = line.strip_prefix("```bash file=") {
            let body: Vec<&str> = lines.by_ref().take_while(|l| *l != "```").collect();
            files.push((name.trim().to_string(), body.join("\n") + "\n"));
        }
    }
    files
}

/// `text` with `from` replaced by `to`, where `from` must occur exactly once.
fn replace_once(text: &str, from: &str, to: &str) -> String {
    assert_eq!(
        text.matches(from).count(),
        1,
        "docs/sweep.md's sweep.sbatch should hold {from:?} once"
    );
    text.replacen(from, to, 1)
}

/// A CSV table as header and rows of text cells.
fn read_table(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = reader.headers().unwrap().iter().map(str::to_string).collect();
    let rows = (reader.records())
        .map(|r| r.unwrap().iter().map(str::to_string).collect())
        .collect();
    (header, rows)
}

fn the_docs_slurm_scripts_run_as_written(cluster: &Cluster) {
    let docs = std::fs::read_to_string(repo_path("docs/sweep.md")).unwrap();
    let files = files_of(&docs);
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["sweep.sbatch", "merge.sbatch", "submit.sh"]);
    let work = cluster.dir.join("work");
    std::fs::create_dir_all(&work).unwrap();
    // the sweep made small: 3 parts of 12 runs of a 0.5 s circle, one CPU each
    let small = [
        ("--array=1-100", "--array=1-3"),
        ("--cpus-per-task=32", "--cpus-per-task=1"),
        ("payload-kg=0:2:0.001", "payload-kg=0:1:0.5"),
        ("mass-scale=0.8:1.2:0.01", "mass-scale=0.9,1.1"),
        ("kp-scale=0.5:1.5:0.1", "kp-scale=1"),
        ("dt=2e-4,5e-4,1e-3", "dt=2e-4,5e-4"),
        (
            "-- shape --shape circle\n",
            "-- shape --shape circle --duration 0.5 --no-collisions\n",
        ),
    ];
    for (name, text) in &files {
        let text = match name.as_str() {
            "sweep.sbatch" => small
                .iter()
                .fold(text.clone(), |t, (from, to)| replace_once(&t, from, to)),
            _ => text.clone(),
        };
        std::fs::write(work.join(name), text).unwrap();
    }

    // faze4 on the PATH the tasks inherit, as the page says
    let faze4 = Path::new(env!("CARGO_BIN_EXE_faze4"));
    let path = std::env::join_paths(
        std::iter::once(faze4.parent().unwrap().to_path_buf())
            .chain(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())),
    )
    .unwrap();
    let submit = Command::new("bash")
        .arg("submit.sh")
        .current_dir(&work)
        .env("PATH", &path)
        .env("SLURM_CONF", &cluster.conf)
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&submit.stdout).into_owned();
    assert!(
        submit.status.success(),
        "bash submit.sh: {said}{}",
        String::from_utf8_lossy(&submit.stderr)
    );
    let job = |label: &str| -> String {
        let rest = &said[said.find(label).unwrap_or_else(|| panic!("{label} in {said}")) + label.len()..];
        rest.chars().take_while(char::is_ascii_digit).collect()
    };
    let (parts, merge) = (job("parts: job "), job("merge: job "));
    assert!(!parts.is_empty() && !merge.is_empty(), "{said}");

    // wait for the merge job: done, or never to run (a part failed), or too slow
    let started = Instant::now();
    let state = loop {
        let text = cluster
            .client("scontrol", &["show", "job", "-o", &merge])
            .unwrap_or_default();
        let field = |key: &str| {
            (text.split_whitespace())
                .find_map(|w| w.strip_prefix(key))
                .unwrap_or("")
                .to_string()
        };
        let (state, reason) = (field("JobState="), field("Reason="));
        if reason == "DependencyNeverSatisfied" {
            let tasks = cluster
                .client("scontrol", &["show", "job", "-o", &parts])
                .unwrap_or_default();
            let logs: Vec<String> = (std::fs::read_dir(work.join("logs")).unwrap())
                .map(|e| std::fs::read_to_string(e.unwrap().path()).unwrap_or_default())
                .collect();
            panic!(
                "a part failed, so the merge can never run:\n{tasks}\n{}",
                logs.join("\n")
            );
        }
        if !state.is_empty() && !["PENDING", "CONFIGURING", "RUNNING", "COMPLETING"].contains(&state.as_str()) {
            break state;
        }
        assert!(
            started.elapsed() < TIMEOUT,
            "the merge job is still {state} ({reason}) after {} s",
            TIMEOUT.as_secs()
        );
        std::thread::sleep(Duration::from_millis(500));
    };
    let merge_log = std::fs::read_to_string(work.join(format!("logs/faze4-merge_{merge}.out"))).unwrap_or_default();
    assert_eq!(state, "COMPLETED", "merge job: {merge_log}");
    assert!(
        merge_log.contains("[done] 12 runs from 3 tables -> all.csv"),
        "{merge_log}"
    );
    println!("the jobs took {:.0} s", started.elapsed().as_secs_f64());

    // each task was part K of 3, with its log
    for k in 1..=3 {
        let meta: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(work.join(format!("parts/part_{k}.csv.meta"))).unwrap())
                .unwrap();
        assert_eq!(meta["shard"], serde_json::json!([k, 3]));
        assert_eq!(meta["complete"], true);
        assert!(work.join(format!("logs/faze4-sweep_{parts}_{k}.out")).exists());
    }

    // the merged table is the unsharded sweep, cell for cell but the wall times
    let whole = Command::new(faze4)
        .args([
            "sweep",
            "--vary",
            "payload-kg=0:1:0.5",
            "--vary",
            "mass-scale=0.9,1.1",
            "--vary",
            "kp-scale=1",
            "--vary",
            "dt=2e-4,5e-4",
            "--out",
            "whole.csv",
            "-q",
            "--",
            "shape",
            "--shape",
            "circle",
            "--duration",
            "0.5",
            "--no-collisions",
        ])
        .current_dir(&work)
        .output()
        .unwrap();
    assert!(whole.status.success(), "{}", String::from_utf8_lossy(&whole.stderr));
    let (header, rows) = read_table(&work.join("whole.csv"));
    let (merged_header, merged) = read_table(&work.join("all.csv"));
    assert_eq!(merged_header, header);
    assert_eq!(rows.len(), 12);
    assert_eq!(merged.len(), rows.len());
    let mut compared = 0;
    for (a, b) in rows.iter().zip(&merged) {
        for ((x, y), name) in a.iter().zip(b).zip(&header) {
            if !name.ends_with("wall_time_s") {
                assert_eq!(x, y, "run {}: {name}", a[0]);
                compared += 1;
            }
        }
    }
    println!("all.csv = the unsharded sweep: {compared} cells equal (12 runs, the wall times left out)");
}
