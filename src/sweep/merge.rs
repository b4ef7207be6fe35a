//! The merge of a sweep's parts (see `part.rs`): [`merge`] reads the parts (CSV or JSON, by
//! extension) and refuses, with one line, a set that is not the whole sweep: a missing,
//! duplicate, partial or truncated part, a part of another sweep, different columns.

use std::ops::Range;
use std::path::Path;

use serde_json::Value;

use super::Shard;
use super::part::{MERGE, PartMeta, VERSION, hash_file, meta_path, runs_text};
use super::table::{Cell, Cells, Format, TableWriter};
use crate::atomic::Inputs;
use crate::error::{Error, Result};
use crate::input::{MAX_META_BYTES, into_text, read_file_capped, regular_file};

/// A part given to [`merge`].
struct Part<'a> {
    path: &'a Path,
    format: Format,
    meta: PartMeta,
}

fn invalid(path: &Path, message: impl Into<String>) -> Error {
    Error::InvalidData {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

impl<'a> Part<'a> {
    /// The table at `path` and its metadata, checked to be whole (its size).
    fn open(path: &'a Path) -> Result<Self> {
        let format = Format::of(path, MERGE)?;
        let meta_file = meta_path(path);
        let read = read_file_capped(&meta_file, MAX_META_BYTES, "a sweep part's metadata");
        let text = match read.and_then(|bytes| into_text(&meta_file, bytes)) {
            Ok(text) => text,
            Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {
                let why = match path.exists() {
                    true => "an unfinished part (its task stopped before the end) or not a `shard` table",
                    false => "no such table",
                };
                return Err(invalid(
                    path,
                    format!("no part metadata beside it ({}): {why}", meta_file.display()),
                ));
            }
            Err(e) => return Err(e),
        };
        let meta: PartMeta = serde_json::from_str(&text).map_err(|e| {
            invalid(
                &meta_file,
                format!(
                    "not the metadata of a sweep's part: {}",
                    crate::error::one_line(&e.to_string())
                ),
            )
        })?;
        if meta.faze4_sweep_part != VERSION {
            return Err(invalid(
                &meta_file,
                format!(
                    "metadata version {} (this faze4 reads {VERSION})",
                    meta.faze4_sweep_part
                ),
            ));
        }
        // its size and hash are checked: a stream has neither
        let size = regular_file(path, "a sweep part's table")?.len();
        let rerun = match meta.shard {
            Some([k, n]) => format!("; rerun its task (`shard` {k}/{n})"),
            None => String::new(),
        };
        if size != meta.bytes {
            let what = if size < meta.bytes {
                "truncated"
            } else {
                "changed since it was written"
            };
            return Err(invalid(
                path,
                format!("{what}: {size} bytes where its metadata says {}{rerun}", meta.bytes),
            ));
        }
        let io = |e| Error::Io {
            path: path.to_path_buf(),
            source: e,
        };
        if hash_file(path).map_err(io)? != meta.table_fnv1a {
            return Err(invalid(
                path,
                format!(
                    "not the table its metadata describes (the hash of its bytes differs: changed, or its task stopped between the two){rerun}"
                ),
            ));
        }
        Ok(Part { path, format, meta })
    }

    /// Reads the rows (cells in column order), checking that they are the runs and columns the
    /// metadata says.
    fn rows(&self) -> Result<Vec<Vec<Cell>>> {
        let path = self.path;
        let columns = &self.meta.columns;
        let rows: Vec<Vec<Cell>> = match self.format {
            Format::Csv => {
                let io = |e: csv::Error| invalid(path, crate::error::one_line(&e.to_string()));
                let mut reader = csv::ReaderBuilder::new().flexible(false).from_path(path).map_err(io)?;
                let header: Vec<&str> = reader.headers().map_err(io)?.iter().collect();
                if header != *columns {
                    return Err(invalid(path, "its header is not the columns its metadata lists"));
                }
                reader
                    .records()
                    .map(|r| {
                        r.map(|r| r.iter().map(|t| Cell::Text(t.to_string())).collect())
                            .map_err(io)
                    })
                    .collect::<Result<_>>()?
            }
            Format::Json => {
                let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
                    path: path.to_path_buf(),
                    source: e,
                })?;
                let value: Value = serde_json::from_str(&text)
                    .map_err(|e| invalid(path, format!("not JSON: {}", crate::error::one_line(&e.to_string()))))?;
                let items = value.as_array().ok_or_else(|| invalid(path, "not an array of rows"))?;
                items
                    .iter()
                    .map(|item| {
                        let object = item.as_object().filter(|o| o.len() == columns.len());
                        let object = object.ok_or_else(|| invalid(path, "a row whose keys are not its columns"))?;
                        columns
                            .iter()
                            .map(|c| object.get(c).map(cell_of_json))
                            .collect::<Option<Vec<Cell>>>()
                            .ok_or_else(|| invalid(path, "a row whose keys are not its columns"))
                    })
                    .collect::<Result<_>>()?
            }
        };
        let expected = self.meta.held().flatten();
        let runs = rows.iter().map(|r| run_of(&r[0]));
        if rows.len() != self.meta.rows || !runs.eq(expected.map(Some)) {
            return Err(invalid(
                path,
                format!(
                    "holds {} rows, not the {} of its metadata ({})",
                    rows.len(),
                    self.meta.rows,
                    runs_text(&self.meta.held().collect::<Vec<_>>())
                ),
            ));
        }
        Ok(rows)
    }
}

fn cell_of_json(value: &Value) -> Cell {
    match value {
        Value::Null => Cell::Empty,
        Value::Bool(b) => Cell::Bool(*b),
        Value::Number(n) => match n.as_u64() {
            Some(k) => Cell::Integer(k),
            None => n.as_f64().map_or(Cell::Empty, Cell::Number),
        },
        Value::String(s) => Cell::Text(s.clone()),
        other => Cell::Text(other.to_string()),
    }
}

fn run_of(cell: &Cell) -> Option<usize> {
    match cell {
        Cell::Integer(k) => usize::try_from(*k).ok(),
        Cell::Text(t) => t.parse().ok(),
        _ => None,
    }
}

/// What a text cell read from CSV is: the writer's empty, boolean or number, or text.
fn typed(text: &str) -> Option<Cell> {
    match text {
        "" => Some(Cell::Empty),
        "true" => Some(Cell::Bool(true)),
        "false" => Some(Cell::Bool(false)),
        _ => text.parse::<u64>().map(Cell::Integer).ok().or_else(|| {
            text.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() || text.contains(['i', 'n', 'I', 'N']))
                .map(Cell::Number)
        }),
    }
}

/// What [`merge`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Merged {
    /// Rows written.
    pub rows: usize,
    /// Runs of the whole sweep.
    pub total: usize,
    /// The runs no part held (empty unless `--allow-partial`), and which parts they are
    /// (`runs 4–6 (part 3 of 5)`), for people.
    pub absent: Option<String>,
}

/// Joins the parts `tables` (CSV or JSON) of one sweep into `out` (CSV or JSON by its
/// extension) with its metadata, rows ordered by run. Refuses (one line) a part without
/// metadata, truncated or changed since written, of another sweep, with other columns, runs held
/// twice, and — unless `allow_partial` — a partial part or runs no part holds.
pub fn merge(tables: &[&Path], out: &Path, allow_partial: bool) -> Result<Merged> {
    let out_format = Format::of(out, "`out`")?;
    if tables.is_empty() {
        return Err(Error::argument(MERGE, "no table to merge"));
    }
    // the merged table and its metadata replace none of the parts or theirs
    let mut inputs = Inputs::new();
    for table in tables {
        inputs.add(table, "a part being merged");
        inputs.add(&meta_path(table), "a part's metadata");
    }
    inputs.check(out, "`out`")?;
    inputs.check(&meta_path(out), "`out`")?;
    let parts: Vec<Part> = tables.iter().map(|p| Part::open(p)).collect::<Result<_>>()?;
    let first = &parts[0];
    same_sweep(&parts)?;
    let held = held_once(&parts)?;
    let total = first.meta.runs_total;
    let absent = gaps(0..total, held.iter().map(|(r, _)| r.clone()));
    let absent_text = check_absent(&parts, &absent, allow_partial)?;
    let columns = first.meta.columns.clone();
    let textual = textual_columns(&parts, columns.len())?;
    let mut table = TableWriter::create(out, out_format)?;
    table.set_columns(columns.clone())?;
    write_rows(&mut table, &parts, &held, &columns, &textual, out_format)?;
    let rows = table.rows();
    let mut meta = PartMeta {
        shard: None,
        complete: absent.is_empty(),
        runs: coalesce(held.iter().map(|(r, _)| r.clone())),
        ..first.meta.clone()
    };
    table.finish(Some(&mut meta))?;
    Ok(Merged {
        rows,
        total,
        absent: absent_text,
    })
}

/// Refuses parts of different sweeps, or with different columns (a model or option changed
/// between their tasks), naming the first that differs from the first part.
fn same_sweep(parts: &[Part]) -> Result<()> {
    let first = &parts[0];
    for part in &parts[1..] {
        if part.meta.sweep != first.meta.sweep || part.meta.runs_total != first.meta.runs_total {
            return Err(Error::argument(
                MERGE,
                format!(
                    "{} is a part of another sweep than {}: {} vs {}",
                    part.path.display(),
                    first.path.display(),
                    part.meta.describe(),
                    first.meta.describe()
                ),
            ));
        }
    }
    for part in &parts[1..] {
        if part.meta.columns != first.meta.columns {
            let (a, b) = (&first.meta.columns, &part.meta.columns);
            let at = a
                .iter()
                .zip(b)
                .position(|(x, y)| x != y)
                .unwrap_or(a.len().min(b.len()));
            let name = |c: &[String]| c.get(at).map_or("none".to_string(), |n| format!("'{n}'"));
            return Err(Error::argument(
                MERGE,
                format!(
                    "{} and {} have different columns ({} and {} columns; column {} is {} and {}): a model or option changed between their tasks",
                    first.path.display(),
                    part.path.display(),
                    a.len(),
                    b.len(),
                    at + 1,
                    name(a),
                    name(b)
                ),
            ));
        }
    }
    Ok(())
}

/// Every part's held run ranges, each with its part's index, in run order; refused when two
/// ranges overlap (one part given twice, or two parts holding the same runs).
fn held_once(parts: &[Part]) -> Result<Vec<(Range<usize>, usize)>> {
    let mut held: Vec<(Range<usize>, usize)> = (parts.iter().enumerate())
        .flat_map(|(i, p)| p.meta.held().map(move |r| (r, i)))
        .collect();
    held.sort_by_key(|(r, _)| (r.start, r.end));
    for w in held.windows(2) {
        let ((a, i), (b, j)) = (&w[0], &w[1]);
        if b.start < a.end {
            let (p, q) = (&parts[*i], &parts[*j]);
            let both = b.start..a.end.min(b.end);
            let message = if std::fs::canonicalize(p.path).ok() == std::fs::canonicalize(q.path).ok() {
                format!("{} is given twice", p.path.display())
            } else {
                format!(
                    "{} and {} both hold {} ({} and {}): one part twice",
                    p.path.display(),
                    q.path.display(),
                    runs_text(std::slice::from_ref(&both)),
                    p.meta.what(),
                    q.meta.what()
                )
            };
            return Err(Error::argument(MERGE, message));
        }
    }
    Ok(held)
}

/// Refuses runs no part holds (`absent`, out of the sweep's total) unless `allow_partial`, and a
/// part stopped early whose absent runs no other part holds; the absent runs in words (with the
/// parts they belong to) when they are allowed, `None` when none are.
fn check_absent(parts: &[Part], absent: &[Range<usize>], allow_partial: bool) -> Result<Option<String>> {
    let total = parts[0].meta.runs_total;
    let overlaps = |runs: &[Range<usize>]| {
        runs.iter()
            .any(|r| absent.iter().any(|a| a.start < r.end && r.start < a.end))
    };
    // a part stopped early whose absent runs no other part holds
    let partial = parts
        .iter()
        .find(|p| !p.meta.complete && overlaps(&gaps(p.meta.meant(), p.meta.held())));
    if !allow_partial && let Some(p) = partial {
        let absent = gaps(p.meta.meant(), p.meta.held());
        return Err(Error::argument(
            MERGE,
            format!(
                "{} is partial ({} stopped after {} runs; {} absent): rerun it, or merge with `allow_partial`",
                p.path.display(),
                p.meta.what(),
                p.meta.rows,
                runs_text(&absent)
            ),
        ));
    }
    let which = describe_absent(absent, parts, total);
    if !allow_partial && !absent.is_empty() {
        let message = match &which {
            Some(parts) => format!("{parts} missing: {}", runs_text(absent)),
            None => format!("{} missing", runs_text(absent)),
        };
        return Err(Error::argument(
            MERGE,
            format!("{message} (`allow_partial` merges without them)"),
        ));
    }
    Ok((!absent.is_empty()).then(|| match &which {
        Some(parts) => format!("{} ({parts})", runs_text(absent)),
        None => runs_text(absent),
    }))
}

/// Which of the `n_columns` columns hold text in some row of some part (the others' text cells
/// are numbers or booleans, typed again in a JSON table); every part's rows are read, so a
/// truncated part is refused before anything is written.
fn textual_columns(parts: &[Part], n_columns: usize) -> Result<Vec<bool>> {
    let mut textual = vec![false; n_columns];
    for part in parts {
        for row in part.rows()? {
            for (c, cell) in row.iter().enumerate() {
                if let Cell::Text(t) = cell {
                    textual[c] |= typed(t).is_none();
                }
            }
        }
    }
    Ok(textual)
}

/// The held ranges' rows into `table`, in run order.
fn write_rows(
    table: &mut TableWriter,
    parts: &[Part],
    held: &[(Range<usize>, usize)],
    columns: &[String],
    textual: &[bool],
    out_format: Format,
) -> Result<()> {
    // the held ranges in run order, each a slice of its part's rows (a merged table may hold
    // several ranges, with another part's between them)
    let mut loaded: Option<(usize, Vec<Vec<Cell>>)> = None;
    for (range, i) in held {
        if loaded.as_ref().is_none_or(|(j, _)| j != i) {
            loaded = Some((*i, parts[*i].rows()?));
        }
        let Some((_, rows)) = &loaded else {
            unreachable!("loaded above")
        };
        let offset: usize = (parts[*i].meta.held())
            .take_while(|r| r.start < range.start)
            .map(|r| r.len())
            .sum();
        for row in &rows[offset..offset + range.len()] {
            let cells: Cells = (columns.iter().cloned())
                .zip(row.iter().cloned())
                .enumerate()
                .map(|(c, (name, cell))| match (cell, out_format) {
                    (Cell::Text(t), Format::Json) if !textual[c] => (name, typed(&t).unwrap_or(Cell::Text(t))),
                    (cell, _) => (name, cell),
                })
                .collect();
            table.push_cells(&cells)?;
        }
    }
    Ok(())
}

/// The ranges of `within` that `held` (sorted, disjoint) leave out.
fn gaps(within: Range<usize>, held: impl Iterator<Item = Range<usize>>) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut at = within.start;
    for r in held {
        if r.start > at {
            out.push(at..r.start.min(within.end));
        }
        at = at.max(r.end);
    }
    if at < within.end {
        out.push(at..within.end);
    }
    out.retain(|r| !r.is_empty());
    out
}

fn coalesce(ranges: impl Iterator<Item = Range<usize>>) -> Vec<[usize; 2]> {
    let mut out: Vec<[usize; 2]> = Vec::new();
    for r in ranges {
        match out.last_mut() {
            Some(last) if last[1] == r.start => last[1] = r.end,
            _ => out.push([r.start, r.end]),
        }
    }
    out
}

/// The parts that hold the `absent` runs: `part 3 of 5`, `parts 2, 4 of 5`; `None` when the
/// parts given are not all of one split (or none is absent).
fn describe_absent(absent: &[Range<usize>], parts: &[Part], total: usize) -> Option<String> {
    let n = parts[0].meta.shard.map(|[_, n]| n)?;
    if absent.is_empty() || parts.iter().any(|p| p.meta.shard.map(|[_, n]| n) != Some(n)) {
        return None;
    }
    let which: Vec<usize> = (1..=n)
        .filter(|&k| {
            let r = Shard { k, n }.range(total);
            absent.iter().any(|a| a.start < r.end && r.start < a.end)
        })
        .collect();
    let listed: Vec<String> = which.iter().take(20).map(ToString::to_string).collect();
    let more = if which.len() > 20 { ", …" } else { "" };
    let word = if which.len() == 1 { "part" } else { "parts" };
    Some(format!("{word} {}{more} of {n}", listed.join(", ")))
}

/// Writes `text` into `out` (a helper for tests of damaged parts).
#[cfg(test)]
fn write(out: &Path, text: &str) {
    std::fs::write(out, text).unwrap();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaps_and_runs_for_people() {
        assert_eq!(gaps(0..10, [0..4, 7..10].into_iter()), vec![4..7]);
        assert_eq!(gaps(0..10, std::iter::empty()), vec![0..10]);
        assert_eq!(gaps(2..6, std::iter::once(2..3)), vec![3..6]);
        assert_eq!(runs_text(&[4..7, 9..10]), "runs 4–6, 9");
        assert_eq!(runs_text(std::slice::from_ref(&(4..5))), "run 4");
        assert_eq!(coalesce([0..3, 3..5, 7..8].into_iter()), vec![[0, 5], [7, 8]]);
    }

    #[test]
    fn csv_text_reads_back_as_the_writer_wrote_it() {
        assert_eq!(typed(""), Some(Cell::Empty));
        assert_eq!(typed("12"), Some(Cell::Integer(12)));
        assert_eq!(typed("0.25"), Some(Cell::Number(0.25)));
        assert_eq!(typed("true"), Some(Cell::Bool(true)));
        assert_eq!(typed("J3 saturates"), None);
        let dir = std::env::temp_dir().join(format!("faze4_part_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let table = dir.join("p.csv");
        write(&table, "run,x\n0,1\n");
        assert_eq!(meta_path(&table), dir.join("p.csv.meta"));
        let e = Part::open(&table).err().unwrap().to_string();
        assert!(e.contains("no part metadata"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
