//! The sweep's table: one row per run, written as CSV or JSON while the sweep runs (the merge
//! of a sweep's parts is [`super::part`]'s).
//!
//! Columns: `run` (the index in the whole sweep), the varied options (named as the options),
//! `follows`, `diverged`, `reasons` (the verdict's reasons, or `failed: …` for a run that could
//! not be built or run), then every figure of the run's summary (the `--summary` JSON; `dt`
//! only once when it is varied) flattened: a per-joint list `x` becomes `x_1` … `x_N`, a nested object `a: {b}` becomes
//! `a_b`; an unlimited torque limit is empty. A failed run has empty figures. Lists of objects
//! (the clearance's per-pair `pairs`) stay in the summary: the table keeps the closest pair,
//! `clearance_min_m`, `clearance_links_1`, `clearance_links_2`, `clearance_t` (and
//! `clearance_geometry`), the same columns in every row. What was simulated (`robot`, `robot_source`,
//! `format`, `mapped`, `joints`, `tool_link`, `tool_choice`, `meshes`) is the same in every run of a
//! sweep and has no column.

use std::io::Write;
use std::path::Path;

use serde_json::{Map, Value};

use super::part::{Fnv, PartMeta, meta_path, meta_text};
use super::{Outcome, Row};
use crate::atomic::{AtomicFile, Outputs};
use crate::error::{Error, Result, escape_controls};
use crate::output::format::push_exact;

/// The summary fields that are not figures of the run, or that have their own columns: the
/// description of what was simulated is the same in every row of a sweep and left out.
const NOT_FIGURES: [&str; 11] = [
    "verdict",
    "diverged",
    "interrupted_at_s",
    "robot",
    "robot_source",
    "format",
    "mapped",
    "joints",
    "tool_link",
    "tool_choice",
    "meshes",
];

/// One cell.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    /// Nothing (a failed run's figure, an unlimited limit).
    Empty,
    /// A count (the run index, steps, dof).
    Integer(u64),
    /// A number, written exactly (the shortest decimal that reads back to the same `f64`).
    Number(f64),
    /// True or false.
    Bool(bool),
    /// Text.
    Text(String),
}

/// A row as named cells, in column order.
pub type Cells = Vec<(String, Cell)>;

/// The cells of `row` whose varied options are `axes`.
pub fn cells(axes: &[String], row: &Row) -> Cells {
    let mut cells: Cells = vec![("run".into(), Cell::Integer(row.index as u64))];
    cells.extend(axes.iter().cloned().zip(row.values.iter().map(|&x| Cell::Number(x))));
    match &row.outcome {
        Outcome::Ran(summary) => {
            cells.push(("follows".into(), Cell::Bool(summary.verdict.follows)));
            cells.push(("diverged".into(), Cell::Bool(summary.diverged.is_some())));
            cells.push(("reasons".into(), Cell::Text(row.reasons())));
            if let Ok(Value::Object(fields)) = serde_json::to_value(summary) {
                let mut figures = Vec::new();
                flatten_into(&mut figures, "", &fields);
                // a varied option named as a figure (dt) keeps its one column
                figures.retain(|(name, _)| !axes.contains(name));
                cells.extend(figures);
            }
        }
        Outcome::Failed(_) => {
            cells.push(("follows".into(), Cell::Bool(false)));
            cells.push(("diverged".into(), Cell::Empty));
            cells.push(("reasons".into(), Cell::Text(row.reasons())));
        }
    }
    cells
}

fn flatten_into(cells: &mut Cells, prefix: &str, fields: &Map<String, Value>) {
    for (key, value) in fields {
        if prefix.is_empty() && NOT_FIGURES.contains(&key.as_str()) {
            continue;
        }
        let name = format!("{prefix}{key}");
        match value {
            Value::Object(inner) => flatten_into(cells, &format!("{name}_"), inner),
            // `--motors`: per joint the same figures in every row, `motors_<figure>_<joint>`
            Value::Array(items) if name == "motors" => {
                for (i, item) in items.iter().enumerate() {
                    for (figure, v) in item.as_object().into_iter().flatten() {
                        if !v.is_object() {
                            cells.push((format!("motors_{figure}_{}", i + 1), scalar(v)));
                        }
                    }
                }
            }
            // per-pair records: their fields vary from row to row (`intersecting`)
            Value::Array(items) if items.iter().any(Value::is_object) => {}
            Value::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    cells.push((format!("{name}_{}", i + 1), scalar(item)));
                }
            }
            other => cells.push((name, scalar(other))),
        }
    }
}

fn scalar(value: &Value) -> Cell {
    match value {
        Value::Number(n) => match n.as_u64() {
            Some(count) => Cell::Integer(count),
            None => n.as_f64().map_or(Cell::Empty, Cell::Number),
        },
        Value::Bool(b) => Cell::Bool(*b),
        Value::String(s) => Cell::Text(s.clone()),
        Value::Null => Cell::Empty,
        other => Cell::Text(other.to_string()),
    }
}

/// Table formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated, a header line first.
    Csv,
    /// A JSON array of objects (one per run, keys the column names in column order; empty
    /// cells are `null`).
    Json,
}

impl Format {
    /// The format of `path` by its extension, `.csv` or `.json`.
    pub fn of(path: &Path, option: &str) -> Result<Format> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("csv") => Ok(Format::Csv),
            Some("json") => Ok(Format::Json),
            _ => Err(Error::argument(
                option,
                format!("{}: the table is written as .csv or .json", path.display()),
            )),
        }
    }
}

/// A table being written, row by row, into a file that appears whole when [`TableWriter::finish`]
/// is called (and not at all otherwise). The columns are those of the first row that ran (or
/// those given with [`TableWriter::set_columns`]): later rows fill those columns, empty where
/// they have none.
pub struct TableWriter {
    file: AtomicFile,
    path: std::path::PathBuf,
    format: Format,
    header: Option<Vec<String>>,
    /// Rows waiting for a row that ran, which fixes the columns.
    waiting: Vec<Cells>,
    rows: usize,
    /// Bytes written.
    bytes: u64,
    /// Their hash.
    hash: Fnv,
    /// The set the table is a file of (its metadata too).
    outputs: Outputs,
}

impl TableWriter {
    /// A table to `path` in `format`.
    pub fn create(path: &Path, format: Format) -> Result<TableWriter> {
        Self::within(&Outputs::immediate(), path, format)
    }

    /// A table to `path` in `format`, a file of `outputs` (it appears when they are committed).
    pub fn within(outputs: &Outputs, path: &Path, format: Format) -> Result<TableWriter> {
        Ok(TableWriter {
            file: outputs.create(path)?,
            path: path.to_path_buf(),
            format,
            header: None,
            waiting: Vec::new(),
            rows: 0,
            bytes: 0,
            hash: Fnv::default(),
            outputs: outputs.clone(),
        })
    }

    /// Whether the columns are fixed (by a row that ran, or [`TableWriter::set_columns`]).
    pub fn has_columns(&self) -> bool {
        self.header.is_some()
    }

    /// Fixes the columns before any row that ran (an empty part, or one whose runs all
    /// failed, still has the sweep's columns); the rows waiting are written.
    pub fn set_columns(&mut self, columns: Vec<String>) -> Result<()> {
        if self.header.is_none() {
            self.start(columns)?;
            for waiting in std::mem::take(&mut self.waiting) {
                self.write(&waiting)?;
            }
        }
        Ok(())
    }

    /// Adds a row of named cells (the columns must be fixed).
    pub fn push_cells(&mut self, cells: &Cells) -> Result<()> {
        self.write(cells)
    }

    /// Adds `row`, whose varied options are `axes`.
    pub fn push(&mut self, axes: &[String], row: &Row) -> Result<()> {
        let cells = cells(axes, row);
        if self.header.is_none() {
            if matches!(row.outcome, Outcome::Failed(_)) {
                self.waiting.push(cells);
                return Ok(());
            }
            self.set_columns(cells.iter().map(|(name, _)| name.clone()).collect())?;
        }
        self.write(&cells)
    }

    /// Rows written.
    pub fn rows(&self) -> usize {
        self.rows + self.waiting.len()
    }

    /// Writes the rows still waiting, closes the table and moves it into place (or stages it,
    /// in a set of outputs). With `part`, the table is a part of a sweep: its metadata (filled
    /// here with the rows, bytes, hash and columns) follows it as `TABLE.meta`, renamed into
    /// place after it; the hash of the table's bytes binds the two, so a table beside another's
    /// metadata (a task killed between the two renames) is refused by `merge`.
    pub fn finish(mut self, part: Option<&mut PartMeta>) -> Result<()> {
        if self.header.is_none() {
            let header = match self.waiting.first() {
                Some(cells) => cells.iter().map(|(name, _)| name.clone()).collect(),
                None => vec!["run".to_string()],
            };
            self.set_columns(header)?;
        }
        let end = match (self.format, self.rows) {
            (Format::Csv, _) => "",
            (Format::Json, 0) => "[]\n",
            (Format::Json, _) => "\n]\n",
        };
        self.put(end)?;
        // a device or FIFO (`--out /dev/null`) has no metadata beside it
        let special = std::fs::metadata(&self.path).is_ok_and(|m| !m.is_file());
        let Some(meta) = part.filter(|_| !special) else {
            return self.file.commit();
        };
        meta.rows = self.rows;
        meta.bytes = self.bytes;
        meta.table_fnv1a = self.hash.hex();
        meta.columns = self.header.clone().unwrap_or_default();
        self.file.commit()?;
        self.outputs.write(&meta_path(&self.path), meta_text(meta).as_bytes())
    }

    fn put(&mut self, text: &str) -> Result<()> {
        self.file
            .writer()
            .write_all(text.as_bytes())
            .map_err(|e| self.file.error(e))?;
        self.bytes += text.len() as u64;
        self.hash.eat(text.as_bytes());
        Ok(())
    }

    fn start(&mut self, header: Vec<String>) -> Result<()> {
        if self.format == Format::Csv {
            let line = csv_line(header.iter().map(|h| Cell::Text(h.clone())));
            self.put(&line)?;
        }
        self.header = Some(header);
        Ok(())
    }

    fn write(&mut self, cells: &Cells) -> Result<()> {
        let header = self.header.as_ref().expect("started");
        let ordered = header.iter().map(|name| {
            cells
                .iter()
                .find(|(n, _)| n == name)
                .map_or(Cell::Empty, |(_, c)| c.clone())
        });
        let text = match self.format {
            Format::Csv => csv_line(ordered),
            Format::Json => {
                // the keys in column order (a serde_json map would sort them)
                let fields: Vec<String> = (header.iter())
                    .zip(ordered)
                    .map(|(name, cell)| format!("{}:{}", Value::from(name.as_str()), json_value(cell)))
                    .collect();
                let lead = if self.rows == 0 { "[\n" } else { ",\n" };
                format!("{lead}{{{}}}", fields.join(","))
            }
        };
        self.put(&text)?;
        self.rows += 1;
        Ok(())
    }
}

fn csv_line(cells: impl Iterator<Item = Cell>) -> String {
    let mut line = String::new();
    for (i, cell) in cells.enumerate() {
        if i > 0 {
            line.push(',');
        }
        match cell {
            Cell::Empty => {}
            Cell::Integer(k) => line.push_str(&k.to_string()),
            Cell::Number(x) => push_exact(&mut line, x),
            Cell::Bool(b) => line.push_str(if b { "true" } else { "false" }),
            // a text (a name read from a URDF) without control or bidirectional characters
            Cell::Text(t) => {
                let t = escape_controls(&t);
                match t.contains([',', '"']) {
                    true => {
                        line.push('"');
                        line.push_str(&t.replace('"', "\"\""));
                        line.push('"');
                    }
                    false => line.push_str(&t),
                }
            }
        }
    }
    line.push('\n');
    line
}

fn json_value(cell: Cell) -> Value {
    match cell {
        Cell::Empty => Value::Null,
        Cell::Integer(k) => Value::from(k),
        Cell::Number(x) => serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number),
        Cell::Bool(b) => Value::Bool(b),
        Cell::Text(t) => Value::String(t),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Diverged, Summary, Verdict};

    fn row(index: usize, diverged: bool) -> Row {
        let summary = Summary {
            dof: 2,
            max_tracking_error_rad: vec![0.1, 0.25],
            saturation_pct: vec![0.0, 12.5],
            diverged: diverged.then(|| Diverged {
                t: 0.5,
                joint: crate::model::JointId(1),
                stiffness_b: vec![0.4, 0.6],
            }),
            verdict: Verdict::default(),
            simulated: crate::sim::Simulated {
                robot: "two_link".into(),
                tool_link: "tip".into(),
                ..Default::default()
            },
            ..Summary::default()
        };
        Row {
            index,
            values: vec![0.5 * index as f64],
            outcome: Outcome::Ran(Box::new(summary)),
        }
    }

    #[test]
    fn per_joint_figures_become_numbered_columns() {
        let cells = cells(&["payload-kg".into()], &row(3, true));
        let get = |name: &str| cells.iter().find(|(n, _)| n == name).map(|(_, c)| c.clone());
        assert_eq!(get("run"), Some(Cell::Integer(3)));
        assert_eq!(get("payload-kg"), Some(Cell::Number(1.5)));
        assert_eq!(get("max_tracking_error_rad_2"), Some(Cell::Number(0.25)));
        assert_eq!(get("saturation_pct_2"), Some(Cell::Number(12.5)));
        assert_eq!(get("tool_range_m_z_2"), Some(Cell::Number(0.0)));
        assert_eq!(get("diverged"), Some(Cell::Bool(true)));
        assert_eq!(get("verdict"), None);
        assert_eq!(get("robot"), None, "what was simulated has no column");
        assert_eq!(get("tool_link"), None);
        assert_eq!(get("max_tracking_error_rad_3"), None);
    }

    #[test]
    fn failed_rows_before_the_first_run_wait_for_its_columns() {
        let dir = std::env::temp_dir().join(format!("faze4_table_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.csv");
        let mut table = TableWriter::create(&path, Format::Csv).unwrap();
        let axes = vec!["dt".to_string()];
        let failed = Row {
            index: 0,
            values: vec![-1.0],
            outcome: Outcome::Failed("--dt: -1 must be > 0, really".into()),
        };
        table.push(&axes, &failed).unwrap();
        table.push(&axes, &row(1, false)).unwrap();
        table.finish(None).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        let columns = lines[0].split(',').count();
        assert!(
            lines[0].starts_with("run,dt,follows,diverged,reasons,dof,"),
            "{}",
            lines[0]
        );
        assert!(
            lines[1].starts_with("0,-1.0,false,,\"failed: --dt: -1 must be > 0, really\","),
            "{}",
            lines[1]
        );
        let mut reader = csv::Reader::from_path(&path).unwrap();
        for record in reader.records() {
            assert_eq!(record.unwrap().len(), columns);
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
