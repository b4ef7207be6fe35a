//! The README and docs/*.md, run: what they show the binary printing is what it prints, and the
//! README names every option and preset `--help` lists.
//!
//! # Which blocks are checked
//!
//! A fenced block whose info string is `console faze4-test` is checked:
//!
//! ````text
//! ```console faze4-test
//! $ faze4 sweep --find payload-kg=0:3 --resolution 0.01 -- wave --duration 1 --no-collisions
//! largest payload-kg that follows: …
//! ```
//! ````
//!
//! A line starting with `$ ` is a command; the lines after it, up to the next command, are its
//! output (but for empty lines at its end, which part it from the next command). The block's commands run in order, each by `sh -c`, in one fresh temporary directory
//! that holds links to the repository's folders (`urdf`, `tests`, `assets`, `examples`), so a
//! command names the shipped files by the paths a reader of a clone uses and writes into the
//! temporary directory; the built binary is first on `PATH`. stdout and stderr go to one pipe, as
//! a terminal shows them. A command that ends with a status other than 0 fails the test, unless
//! it shows its status itself (`…; echo "exit status $?"`).
//!
//! A block that shows a `$ faze4` command and its output but is not run says why in its info
//! string: ```` ```console unchecked: <why> ````. A `$ faze4` line anywhere else (an indented
//! block, another fence) fails [`every_shown_run_is_checked_or_says_why`].
//!
//! # What is masked
//!
//! Two things, and nothing else:
//! - **Elided lines.** A line that is `…` alone stands for any number of lines, at most once
//!   per command: the lines shown before it are the first lines of the output, those after it
//!   the last ones.
//! - **Times.** The figures that depend on the machine (the wall time of a run and of its
//!   self-clearance, µs per step) are printed as `…` in the docs: before comparing, the test
//!   replaces each number that [`MASKS`] describes (a number between two given texts) by `…` in
//!   the binary's output.
//!
//! # Regenerating
//!
//! The outputs shown are the binary's, never edited by hand: `FAZE4_BLESS=1 cargo test --test
//! docs` rewrites every checked block's output from the binary (masked as above, keeping as many
//! first and last lines as the block shows around its `…`). Review the diff, then commit.

use crate::common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use common::{repo, repo_path, temp_dir};

/// The info string of a checked block.
const CHECKED: &str = "console faze4-test";
/// The info string of a block shown but not run, followed by the reason.
const UNCHECKED: &str = "console unchecked:";
/// The line that stands for any number of output lines.
const ELISION: &str = "…";

/// The machine-dependent figures: a number directly between the first and the second text is
/// replaced by `…`. E.g. `[done] trail -> faze4_trail.csv (401 rows) · 40000 steps in 1.339 s
/// (dynamics 7.70 µs/step; self-clearance 1.031 s, 77 % of the time)` reads `… steps in … s
/// (dynamics … µs/step; self-clearance … s, … % of the time)`.
const MASKS: [(&str, &str); 5] = [
    (" steps in ", " s ("),
    ("(", " µs/step"),
    ("(dynamics ", " µs/step"),
    ("; self-clearance ", " s, "),
    (" s, ", " % of the time)"),
];

/// The repository's folders a checked command sees from its temporary directory.
const LINKED: [&str; 4] = ["urdf", "tests", "assets", "examples"];

/// One `$ ` command of a checked block and the output shown after it.
struct Shown {
    /// The command after `$ `.
    command: String,
    /// The output lines shown, the block's indentation removed.
    output: Vec<String>,
    /// The empty lines after the output, which part it from the next command.
    gap: usize,
}

/// A checked block: where it is and what it shows.
struct Block {
    /// The file's line (0-based) of the opening fence.
    fence: usize,
    /// The file's line (0-based) of the closing fence.
    end: usize,
    /// The indentation of the fence (inside a list item), which every line of the block has.
    indent: String,
    commands: Vec<Shown>,
}

/// The fenced blocks of `text` whose info string starts with `info`: (opening line, closing
/// line, indentation, the lines between without the indentation).
fn fenced(text: &str, info: &str) -> Vec<(usize, usize, String, Vec<String>)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut blocks = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let trimmed = lines[i].trim_start();
        let indent = &lines[i][..lines[i].len() - trimmed.len()];
        if let Some(rest) = trimmed.strip_prefix("```") {
            let end = (i + 1..lines.len())
                .find(|&j| lines[j].trim() == "```")
                .unwrap_or_else(|| panic!("line {}: a fence that is not closed", i + 1));
            if rest.trim_start().starts_with(info) {
                let body = (lines[i + 1..end].iter())
                    .map(|l| l.strip_prefix(indent).unwrap_or(l.trim_start()).to_string())
                    .collect();
                blocks.push((i, end, indent.to_string(), body));
            }
            i = end + 1;
        } else {
            i += 1;
        }
    }
    blocks
}

/// The checked blocks of `text`.
fn checked_blocks(text: &str) -> Vec<Block> {
    (fenced(text, CHECKED).into_iter())
        .map(|(fence, end, indent, body)| {
            let mut commands: Vec<Shown> = Vec::new();
            for line in body {
                match (line.strip_prefix("$ "), commands.last_mut()) {
                    (Some(command), _) => commands.push(Shown {
                        command: command.to_string(),
                        output: Vec::new(),
                        gap: 0,
                    }),
                    (None, Some(last)) => last.output.push(line),
                    (None, None) => panic!("line {}: a checked block starts with a command (`$ `)", fence + 2),
                }
            }
            assert!(
                !commands.is_empty(),
                "line {}: a checked block without a command",
                fence + 1
            );
            for shown in &mut commands {
                while shown.output.last().is_some_and(|l| l.is_empty()) {
                    shown.output.pop();
                    shown.gap += 1;
                }
            }
            Block {
                fence,
                end,
                indent,
                commands,
            }
        })
        .collect()
}

/// `line` with the numbers [`MASKS`] describes replaced by `…`.
fn masked(line: &str) -> String {
    let mut line = line.to_string();
    for (before, after) in MASKS {
        let mut from = 0;
        while let Some(start) = line[from..].find(before).map(|k| from + k + before.len()) {
            let rest = &line[start..];
            let len = rest
                .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | 'e' | '-' | '+')))
                .unwrap_or(rest.len());
            if len > 0 && rest[len..].starts_with(after) {
                line.replace_range(start..start + len, ELISION);
            }
            from = start;
        }
    }
    line
}

/// A clean temporary directory that sees the repository's [`LINKED`] folders.
fn sandbox(name: &str) -> PathBuf {
    let dir = temp_dir(name);
    for folder in LINKED {
        std::os::unix::fs::symlink(repo_path(folder), dir.join(folder)).unwrap();
    }
    dir
}

/// Runs `command` by `sh -c` in `dir` with the built binary first on `PATH`: its output lines
/// (stdout and stderr as one terminal shows them), masked; an error when its status is not 0.
fn run(dir: &Path, command: &str) -> Result<Vec<String>, String> {
    let bin = Path::new(env!("CARGO_BIN_EXE_faze4")).parent().unwrap();
    let path = std::env::join_paths(
        std::iter::once(bin.to_path_buf()).chain(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())),
    )
    .unwrap();
    let (reader, writer) = std::io::pipe().unwrap();
    let mut child = Command::new("sh")
        .args(["-c", command])
        .current_dir(dir)
        .env("PATH", path)
        .stdin(Stdio::null())
        .stdout(writer.try_clone().unwrap())
        .stderr(writer)
        .spawn()
        .expect("sh");
    let mut text = String::new();
    std::io::Read::read_to_string(&mut &reader, &mut text).unwrap();
    let status = child.wait().unwrap();
    if !status.success() {
        return Err(format!("`{command}` ended with {status}:\n{text}"));
    }
    Ok(text.lines().map(masked).collect())
}

/// Whether `actual` is what `shown` shows (with its one `…` line, if any).
fn agrees(shown: &[String], actual: &[String]) -> bool {
    match shown.iter().position(|l| l == ELISION) {
        None => shown == actual,
        Some(k) => {
            let (head, tail) = (&shown[..k], &shown[k + 1..]);
            actual.len() >= head.len() + tail.len()
                && actual.starts_with(head)
                && actual.ends_with(tail)
                && !tail.iter().any(|l| l == ELISION)
        }
    }
}

/// What `shown` becomes from `actual`: as many first and last lines as it shows around its `…`.
fn regenerated(shown: &[String], actual: &[String]) -> Vec<String> {
    match shown.iter().position(|l| l == ELISION) {
        Some(k) if actual.len() > shown.len() - 1 => {
            let tail = shown.len() - 1 - k;
            let mut lines = actual[..k].to_vec();
            lines.push(ELISION.to_string());
            lines.extend_from_slice(&actual[actual.len() - tail..]);
            lines
        }
        _ => actual.to_vec(),
    }
}

/// Runs every checked block of the document `rel` (repository-relative). Under `FAZE4_BLESS=1`
/// rewrites the shown outputs; otherwise fails naming every command whose output differs.
fn check_document(rel: &str) -> usize {
    let path = repo_path(rel);
    let text = std::fs::read_to_string(&path).unwrap();
    let blocks = checked_blocks(&text);
    let bless = std::env::var_os("FAZE4_BLESS").is_some_and(|v| v == "1");
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut failures = Vec::new();
    // from the last block up, so that a rewritten block does not move the ones before it
    for block in blocks.iter().rev() {
        let dir = sandbox(&format!("docs-{}-{}", rel.replace('/', "-"), block.fence + 1));
        let mut body = Vec::new();
        for shown in &block.commands {
            body.push(format!("$ {}", shown.command));
            match run(&dir, &shown.command) {
                Err(e) => failures.push(format!("{rel}:{}: {e}", block.fence + 1)),
                Ok(actual) if bless => body.extend(regenerated(&shown.output, &actual)),
                Ok(actual) if !agrees(&shown.output, &actual) => failures.push(format!(
                    "{rel}:{}: `{}` shows\n{}\nbut prints (masked)\n{}",
                    block.fence + 1,
                    shown.command,
                    shown.output.join("\n"),
                    actual.join("\n")
                )),
                Ok(_) => {}
            }
            body.extend(std::iter::repeat_n(String::new(), shown.gap));
        }
        std::fs::remove_dir_all(&dir).unwrap();
        let indented = body.iter().map(|l| match l.is_empty() {
            true => String::new(),
            false => format!("{}{l}", block.indent),
        });
        lines.splice(block.fence + 1..block.end, indented);
    }
    assert!(
        failures.is_empty(),
        "{} shown output(s) differ from the binary's; regenerate them with `FAZE4_BLESS=1 cargo test --test it docs::` (and review the diff):\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
    if bless {
        let mut new = lines.join("\n");
        new.push('\n');
        if new != text {
            std::fs::write(&path, new).unwrap();
        }
    }
    blocks.len()
}

/// The documents: README.md and docs/*.md.
fn documents() -> Vec<String> {
    let mut docs: Vec<String> = (std::fs::read_dir(repo_path("docs")).unwrap())
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    docs.sort();
    docs.insert(0, "README.md".into());
    docs
}

#[test]
fn the_readmes_shown_runs_print_what_it_shows() {
    let checked = check_document("README.md");
    assert!(checked >= 5, "README.md: only {checked} checked blocks");
}

#[test]
fn the_docs_shown_runs_print_what_they_show() {
    let checked: usize = (documents().iter().skip(1)).map(|d| check_document(d)).sum();
    assert!(checked >= 1, "docs/*.md: no checked block");
}

/// Every `$ faze4` line the documents show is in a checked block, or in a block that says why
/// it is not run.
#[test]
fn every_shown_run_is_checked_or_says_why() {
    let mut stray = Vec::new();
    for doc in documents() {
        let text = std::fs::read_to_string(repo_path(&doc)).unwrap();
        let mut allowed = BTreeSet::new();
        for (fence, end, ..) in fenced(&text, CHECKED).into_iter().chain(fenced(&text, UNCHECKED)) {
            allowed.extend(fence..=end);
        }
        for (fence, _, _, body) in fenced(&text, UNCHECKED) {
            let info = text.lines().nth(fence).unwrap().trim_start();
            assert!(
                info.len() > "```".len() + UNCHECKED.len() + 3,
                "{doc}:{}: an unchecked block says why",
                fence + 1
            );
            assert!(
                body.iter().any(|l| l.starts_with("$ ")),
                "{doc}:{}: no `$ ` command",
                fence + 1
            );
        }
        for (k, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("$ faze4") && !allowed.contains(&k) {
                stray.push(format!("{doc}:{}: {}", k + 1, line.trim()));
            }
        }
    }
    assert!(
        stray.is_empty(),
        "runs shown outside a ```{CHECKED} block (or ```{UNCHECKED} <why>):\n{}",
        stray.join("\n")
    );
}

/// The long options `help` lists (`--name` at the start of an option line), and their aliases
/// (`[alias: --urdf]`).
fn options_in_help(help: &str) -> BTreeSet<String> {
    let aliases = (help.match_indices("[alias: ").chain(help.match_indices("[aliases: ")))
        .flat_map(|(k, _)| options_in_line(help[k..].split(']').next().unwrap_or_default()));
    (help.lines())
        .filter_map(|l| {
            let l = l.trim_start();
            let l = l
                .strip_prefix("-")
                .filter(|r| r.len() > 3 && &r[1..3] == ", ")
                .map_or(l, |r| &r[3..]);
            l.strip_prefix("--").map(|r| {
                format!(
                    "--{}",
                    r.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
                        .next()
                        .unwrap()
                )
            })
        })
        .chain(aliases)
        .collect()
}

/// The `--name` words of `text`, but for those after `cargo ` on their line (cargo's own).
fn options_in_text(text: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for line in text.lines() {
        found.extend(options_in_line(line));
    }
    found
}

fn options_in_line(text: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for (k, _) in text.match_indices("--") {
        let before = text[..k].chars().next_back();
        if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '-') || text[..k].contains("cargo ") {
            continue;
        }
        let name: String = text[k + 2..]
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
            .collect();
        if name.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
            found.insert(format!("--{name}"));
        }
    }
    found
}

fn help(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_faze4")).args(args).output().unwrap();
    assert!(out.status.success(), "{args:?}");
    String::from_utf8(out.stdout).unwrap()
}

/// The README and `--help` name the same options: every option of `faze4 --help` and `faze4
/// CMD --help` (every command, `sweep merge` too) is in the README, and every option the README
/// names is one of them. Every `--motors` preset is in both.
#[test]
fn the_readme_and_help_name_the_same_options_and_presets() {
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let commands: [&[&str]; 7] = [
        &[],
        &["wave"],
        &["replay"],
        &["shape"],
        &["retime"],
        &["sweep"],
        &["sweep", "merge"],
    ];
    let mut listed = BTreeSet::new();
    let mut helps = String::new();
    for command in commands {
        let text = help(&[command, &["--help"]].concat());
        listed.extend(options_in_help(&text));
        helps += &text;
    }
    // every command's --help, not named in the README's option tables
    let generic: BTreeSet<String> = ["--help", "--version"].map(String::from).into();
    let named = options_in_text(&readme);
    let missing: Vec<_> = listed.difference(&named).filter(|o| !generic.contains(*o)).collect();
    assert!(
        missing.is_empty(),
        "options --help lists that the README does not name: {missing:?}"
    );
    let unknown: Vec<_> = named.difference(&listed).collect();
    assert!(
        unknown.is_empty(),
        "options the README names that --help does not list: {unknown:?}"
    );
    assert!(listed.len() > 50, "only {} options found in --help", listed.len());
    for preset in faze4::config::motors::PRESETS {
        assert!(
            helps.contains(&format!("{preset}:")),
            "--help does not describe the preset {preset}"
        );
        assert!(
            readme.contains(&format!("`--motors {preset}`")),
            "the README does not name the preset `--motors {preset}`"
        );
    }
}

/// The masks and the elision do what the module's documentation says.
#[test]
fn masks_and_elision() {
    assert_eq!(
        masked(
            "[done] trail -> t.csv (401 rows) · 40000 steps in 1.339 s (dynamics 7.70 µs/step; self-clearance 1.031 s, 77 % of the time)"
        ),
        "[done] trail -> t.csv (401 rows) · 40000 steps in … s (dynamics … µs/step; self-clearance … s, … % of the time)"
    );
    // only numbers between the texts: the rest of the line is compared as it is
    assert_eq!(masked("t=  8.00s (401 rows) in 1.3 s"), "t=  8.00s (401 rows) in 1.3 s");
    let lines = |s: &str| s.split('/').map(String::from).collect::<Vec<_>>();
    assert!(agrees(&lines("a/…/z"), &lines("a/b/c/z")));
    assert!(agrees(&lines("a/…/z"), &lines("a/z")));
    assert!(!agrees(&lines("a/…/z"), &lines("a/b/y")));
    assert!(!agrees(&lines("a/z"), &lines("a/b/z")));
    assert_eq!(regenerated(&lines("a/…/z"), &lines("A/b/c/Z")), lines("A/…/Z"));
    assert_eq!(regenerated(&lines("a/…/z"), &lines("A/Z")), lines("A/Z"));
}

/// The README says how to install what the optional tests need, in the words their `NOTICE:`
/// line prints: every `` `apt-get install …` `` of tests/browser.rs and tests/slurm.rs.
#[test]
fn the_readme_names_the_installs_the_optional_tests_ask_for() {
    let readme = std::fs::read_to_string(repo_path("README.md"))
        .unwrap()
        .replace('\n', " ");
    for harness in ["tests/browser.rs", "tests/slurm.rs"] {
        let source = std::fs::read_to_string(repo_path(harness)).unwrap();
        let installs: Vec<&str> = (source.match_indices("`apt-get install "))
            .map(|(k, _)| &source[k..k + 1 + source[k + 1..].find('`').unwrap() + 1])
            .collect();
        assert!(!installs.is_empty(), "{harness} names no `apt-get install`");
        for install in installs {
            assert!(
                readme.contains(install),
                "the README does not say {install} ({harness}'s notice)"
            );
        }
        assert!(readme.contains(harness), "the README does not name {harness}");
    }
}
