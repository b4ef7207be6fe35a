//! A part of a sweep and what it says of itself. A table written with `--shard K/N` is a part;
//! beside it, `TABLE.meta` (JSON, written after the table, so a part without it is unfinished)
//! says what it is: the sweep's fingerprint (a hash of the base command's words and every
//! varied value), K, N, the runs it holds, whether it holds all of its share (a sweep stopped
//! early writes a partial part), its rows, bytes and columns. `merge.rs` joins parts.

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{Grid, Shard};

/// The version of the metadata's layout.
pub(super) const VERSION: u32 = 1;

/// The option merge's refusals name.
pub(super) const MERGE: &str = "sweep merge";

/// One varied option, as the metadata shows it to people (the fingerprint has every value).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VaryMeta {
    /// The option (`payload-kg`).
    pub name: String,
    /// How many values.
    pub count: usize,
    /// The first value.
    pub first: f64,
    /// The last value.
    pub last: f64,
}

/// What a table of a sweep holds: the `TABLE.meta` beside it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartMeta {
    /// The layout's version (1).
    pub faze4_sweep_part: u32,
    /// The sweep's fingerprint: 16 hex digits of a 64-bit FNV-1a hash of the base command's
    /// words and each varied option's name and values (their bits).
    pub sweep: String,
    /// The base command (the words after `--`).
    pub command: Vec<String>,
    /// The varied options.
    pub vary: Vec<VaryMeta>,
    /// Runs in the whole sweep.
    pub runs_total: usize,
    /// `[K, N]` for part K of N; absent for a merged table.
    pub shard: Option<[usize; 2]>,
    /// The runs the table holds, as `[start, end)` ranges of run indices, in order.
    pub runs: Vec<[usize; 2]>,
    /// Whether it holds every run it was meant to (its part's, or the whole sweep's for a
    /// merged table); false for a sweep stopped early or a merge with `--allow-partial`.
    pub complete: bool,
    /// Rows in the table.
    pub rows: usize,
    /// Bytes of the table.
    pub bytes: u64,
    /// The FNV-1a hash of the table's bytes (16 hex digits): binds this metadata to its table.
    pub table_fnv1a: String,
    /// The table's columns, in order.
    pub columns: Vec<String>,
}

/// The metadata file of `table`: `TABLE.meta`.
pub fn meta_path(table: &Path) -> PathBuf {
    let mut name = table.as_os_str().to_owned();
    name.push(".meta");
    PathBuf::from(name)
}

/// A 64-bit FNV-1a hash, fed in pieces.
#[derive(Clone, Copy, Debug)]
pub struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    /// Feeds `bytes`.
    pub fn eat(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// The hash as 16 hex digits.
    pub fn hex(self) -> String {
        format!("{:016x}", self.0)
    }
}

/// The FNV-1a hash of the file at `path` (16 hex digits).
pub(super) fn hash_file(path: &Path) -> std::io::Result<String> {
    use std::io::Read;
    let mut file = std::fs::File::open(path)?;
    let mut hash = Fnv::default();
    let mut buffer = vec![0u8; 1 << 16];
    loop {
        match file.read(&mut buffer)? {
            0 => return Ok(hash.hex()),
            n => hash.eat(&buffer[..n]),
        }
    }
}

/// The fingerprint of the sweep of `command` (the words after `--`) over `grid`.
pub fn fingerprint(command: &[String], grid: &Grid) -> String {
    let mut hash = Fnv::default();
    let mut eat = |bytes: &[u8]| hash.eat(bytes);
    eat(b"faze4 sweep\0");
    for word in command {
        eat(word.as_bytes());
        eat(b"\0");
    }
    for axis in &grid.axes {
        eat(b"\x01");
        eat(axis.name.as_bytes());
        eat(b"\0");
        for x in &axis.values {
            eat(&x.to_bits().to_le_bytes());
        }
    }
    hash.hex()
}

impl PartMeta {
    /// The metadata of a table of the sweep of `command` over `grid` (`runs_total` runs),
    /// part `shard`, holding the runs `held` (rows, bytes and columns are filled when the table
    /// is finished).
    pub fn new(command: &[String], grid: &Grid, runs_total: usize, shard: Option<Shard>, held: Range<usize>) -> Self {
        let meant = shard.map_or(0..runs_total, |s| s.range(runs_total));
        PartMeta {
            faze4_sweep_part: VERSION,
            sweep: fingerprint(command, grid),
            command: command.to_vec(),
            vary: (grid.axes.iter())
                .map(|a| VaryMeta {
                    name: a.name.clone(),
                    count: a.values.len(),
                    first: a.values[0],
                    last: a.values[a.values.len() - 1],
                })
                .collect(),
            runs_total,
            shard: shard.map(|s| [s.k, s.n]),
            complete: held == meant,
            runs: if held.is_empty() {
                vec![]
            } else {
                vec![[held.start, held.end]]
            },
            rows: 0,
            bytes: 0,
            table_fnv1a: String::new(),
            columns: Vec::new(),
        }
    }

    /// The sweep for people: `` `-- wave --duration 0.5` varying payload-kg (9 values) ``.
    pub(super) fn describe(&self) -> String {
        let vary: Vec<String> = (self.vary.iter())
            .map(|v| format!("{} ({} values {}…{})", v.name, v.count, v.first, v.last))
            .collect();
        format!(
            "`-- {}` varying {}, {} runs (sweep {})",
            self.command.join(" "),
            vary.join(", "),
            self.runs_total,
            self.sweep
        )
    }

    /// `part 3 of 5`, or `a merged table`.
    pub(super) fn what(&self) -> String {
        match self.shard {
            Some([k, n]) => format!("part {k} of {n}"),
            None => "a merged table".into(),
        }
    }

    /// The runs it was meant to hold.
    pub(super) fn meant(&self) -> Range<usize> {
        match self.shard {
            Some([k, n]) if k >= 1 && k <= n => Shard { k, n }.range(self.runs_total),
            _ => 0..self.runs_total,
        }
    }

    pub(super) fn held(&self) -> impl Iterator<Item = Range<usize>> + '_ {
        self.runs.iter().map(|[a, b]| *a..*b)
    }
}

/// `meta` as the text of a `.meta` file.
pub fn meta_text(meta: &PartMeta) -> String {
    let mut text = serde_json::to_string_pretty(meta).unwrap_or_default();
    text.push('\n');
    text
}

/// `runs 4–6`, `run 4`, `runs 0–3, 8–9`: ranges of run indices for people (at most 8 listed).
pub fn runs_text(ranges: &[Range<usize>]) -> String {
    let count: usize = ranges.iter().map(|r| r.len()).sum();
    let mut parts: Vec<String> = (ranges.iter().take(8))
        .map(|r| match r.len() {
            1 => r.start.to_string(),
            _ => format!("{}–{}", r.start, r.end - 1),
        })
        .collect();
    if ranges.len() > 8 {
        parts.push(format!("… ({} ranges)", ranges.len()));
    }
    let word = if count == 1 { "run" } else { "runs" };
    format!("{word} {}", parts.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::Axis;

    #[test]
    fn the_fingerprint_is_the_command_and_the_values() {
        let grid = |spec: &str| Grid::new(vec![Axis::parse(spec).unwrap()]).unwrap();
        let words = |w: &[&str]| w.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let a = fingerprint(&words(&["wave"]), &grid("payload-kg=0:1:0.5"));
        assert_eq!(a.len(), 16);
        assert_eq!(a, fingerprint(&words(&["wave"]), &grid("payload-kg=0,0.5,1")));
        assert_ne!(a, fingerprint(&words(&["wave"]), &grid("payload-kg=0,0.5,1.5")));
        assert_ne!(a, fingerprint(&words(&["shape"]), &grid("payload-kg=0:1:0.5")));
        assert_ne!(a, fingerprint(&words(&["wave"]), &grid("mass-scale=0:1:0.5")));
    }
}
