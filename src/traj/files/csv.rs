//! `.csv`: a header row, then one row per point. One time column (`t`, `time` or
//! `time_from_start`, s); one position column per joint, named by the joint (any order; `qK`
//! for the model's K-th joint); optionally `NAME.velocity` and `NAME.acceleration` columns,
//! for every joint or for none. Lines starting with `#` are comments.

use std::path::Path;

use super::invalid;
use crate::error::{Result, quoted};
use crate::input::{MAX_MOVING_JOINTS, MAX_TRAJECTORY_POINTS};
use crate::traj::{TimedTrajectory, TrajectoryPoint};

/// The names a time column may have.
pub const TIME_COLUMNS: [&str; 3] = ["t", "time", "time_from_start"];
/// The suffix of a velocity column (`NAME.velocity`).
pub const VELOCITY: &str = ".velocity";
/// The suffix of an acceleration column (`NAME.acceleration`).
pub const ACCELERATION: &str = ".acceleration";

/// What a column holds.
#[derive(Clone, Copy, PartialEq)]
enum Column {
    Time,
    Position(usize),
    Velocity(usize),
    Acceleration(usize),
}

/// The trajectory of a CSV file's bytes, unchecked (beyond what reading needs).
pub fn parse(bytes: &[u8], path: &Path) -> Result<TimedTrajectory> {
    let mut reader = ::csv::ReaderBuilder::new()
        .trim(::csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(bytes);
    let header: Vec<String> = (reader.headers())
        .map_err(|e| invalid(path, format!("cannot read the header row: {e}")))?
        .iter()
        .map(String::from)
        .collect();
    // a time column, and a position, velocity and acceleration column per joint at most
    let most = 1 + 3 * MAX_MOVING_JOINTS;
    if header.len() > most {
        return Err(invalid(
            path,
            format!(
                "its header has {} columns; a model has at most {MAX_MOVING_JOINTS} moving joints, so at most {most} columns (docs/development.md, Caps)",
                header.len()
            ),
        ));
    }
    // a column given twice would have the last one win, unsaid
    if let Some((second, h)) = (header.iter().enumerate()).find(|(k, h)| header[..*k].contains(h)) {
        let first = header.iter().position(|x| x == h).unwrap_or(0);
        return Err(invalid(
            path,
            format!(
                "column {} is given twice (columns {} and {}): give each column once",
                quoted(h),
                first + 1,
                second + 1
            ),
        ));
    }
    let times: Vec<&String> = header.iter().filter(|h| TIME_COLUMNS.contains(&h.as_str())).collect();
    if times.len() != 1 {
        return Err(invalid(
            path,
            format!(
                "needs one time column named t, time or time_from_start (s); the header has {}",
                match times.is_empty() {
                    true => "none".to_string(),
                    false => times.iter().map(|h| h.as_str()).collect::<Vec<_>>().join(", "),
                }
            ),
        ));
    }
    let mut joint_names: Vec<String> = Vec::new();
    for h in &header {
        if !TIME_COLUMNS.contains(&h.as_str()) && !h.ends_with(VELOCITY) && !h.ends_with(ACCELERATION) {
            joint_names.push(h.clone());
        }
    }
    let mut columns = Vec::with_capacity(header.len());
    let (mut velocities, mut accelerations) = (vec![false; joint_names.len()], vec![false; joint_names.len()]);
    for h in &header {
        let joint = |base: &str| {
            joint_names.iter().position(|j| j == base).ok_or_else(|| {
                invalid(
                    path,
                    format!("column {} has no position column {}", quoted(h), quoted(base)),
                )
            })
        };
        columns.push(if TIME_COLUMNS.contains(&h.as_str()) {
            Column::Time
        } else if let Some(base) = h.strip_suffix(VELOCITY) {
            let j = joint(base)?;
            velocities[j] = true;
            Column::Velocity(j)
        } else if let Some(base) = h.strip_suffix(ACCELERATION) {
            let j = joint(base)?;
            accelerations[j] = true;
            Column::Acceleration(j)
        } else {
            Column::Position(joint(h)?)
        });
    }
    for (what, given) in [("velocity", &velocities), ("acceleration", &accelerations)] {
        if given.iter().any(|&g| g) && !given.iter().all(|&g| g) {
            let missing = (joint_names.iter().zip(given.iter()))
                .find(|(_, g)| !**g)
                .map_or(String::new(), |(j, _)| quoted(j));
            return Err(invalid(
                path,
                format!("has {what} columns for some joints but not {missing}: give one for every joint or for none"),
            ));
        }
    }
    let n = joint_names.len();
    let (with_v, with_a) = (velocities.first() == Some(&true), accelerations.first() == Some(&true));
    let mut points = Vec::new();
    for record in reader.records() {
        // a row of another length than the header is the reader's error (it is not flexible)
        let record = record.map_err(|e| match e.kind() {
            ::csv::ErrorKind::UnequalLengths { pos: Some(at), len, .. } => invalid(
                path,
                format!("line {} has {len} fields; the header has {}", at.line(), header.len()),
            ),
            _ => invalid(path, e.to_string()),
        })?;
        // the record's line in the file, comments and blank lines counted
        let row = record.position().map_or(0, |at| at.line());
        // counted as they come: a row of one short column costs 30 times its text once read
        if points.len() == MAX_TRAJECTORY_POINTS {
            return Err(invalid(
                path,
                format!(
                    "line {row}: more than {MAX_TRAJECTORY_POINTS} rows, the points a trajectory may have (docs/development.md, Caps)"
                ),
            ));
        }
        let mut p = TrajectoryPoint {
            time_from_start: 0.0,
            positions: vec![0.0; n],
            velocities: if with_v { vec![0.0; n] } else { Vec::new() },
            accelerations: if with_a { vec![0.0; n] } else { Vec::new() },
        };
        for ((field, column), h) in record.iter().zip(&columns).zip(&header) {
            let x: f64 = field.parse().map_err(|_| {
                invalid(
                    path,
                    format!("line {row}, column {}: {} is not a number", quoted(h), quoted(field)),
                )
            })?;
            match *column {
                Column::Time => p.time_from_start = x,
                Column::Position(j) => p.positions[j] = x,
                Column::Velocity(j) => p.velocities[j] = x,
                Column::Acceleration(j) => p.accelerations[j] = x,
            }
        }
        points.push(p);
    }
    Ok(TimedTrajectory { joint_names, points })
}

/// `trajectory` as CSV: `time_from_start`, the positions, then `NAME.velocity` and
/// `NAME.acceleration` columns where given; every number the shortest decimal that reads back
/// to the same `f64`.
pub fn to_string(trajectory: &TimedTrajectory) -> String {
    let mut writer = ::csv::Writer::from_writer(Vec::new());
    let first = trajectory.points.first();
    let with_v = first.is_some_and(|p| !p.velocities.is_empty());
    let with_a = first.is_some_and(|p| !p.accelerations.is_empty());
    let names = &trajectory.joint_names;
    let mut header = vec![TIME_COLUMNS[2].to_string()];
    header.extend(names.iter().cloned());
    if with_v {
        header.extend(names.iter().map(|j| format!("{j}{VELOCITY}")));
    }
    if with_a {
        header.extend(names.iter().map(|j| format!("{j}{ACCELERATION}")));
    }
    let mut buffer = ryu::Buffer::new();
    let mut fields: Vec<String> = Vec::new();
    // writing to memory cannot fail
    let _ = writer.write_record(&header);
    for p in &trajectory.points {
        fields.clear();
        let values = std::iter::once(&p.time_from_start)
            .chain(&p.positions)
            .chain(&p.velocities)
            .chain(&p.accelerations);
        fields.extend(values.map(|&x| buffer.format(x).to_string()));
        let _ = writer.write_record(&fields);
    }
    String::from_utf8(writer.into_inner().unwrap_or_default()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_in_any_order_with_velocities() {
        let text = "# planned by hand\nb, time, a, a.velocity, b.velocity\n1, 0, 2, 0.5, 0.25\n3, 0.5, 4, 0, 0\n";
        let t = parse(text.as_bytes(), Path::new("p.csv")).unwrap();
        assert_eq!(t.joint_names, ["b", "a"]);
        assert_eq!(t.points[1].time_from_start, 0.5);
        assert_eq!(t.points[0].positions, [1.0, 2.0]);
        assert_eq!(t.points[0].velocities, [0.25, 0.5]);
        assert!(t.points[0].accelerations.is_empty());
    }

    #[test]
    fn bad_files_say_where() {
        let e = |text: &str| parse(text.as_bytes(), Path::new("p.csv")).unwrap_err().to_string();
        assert!(
            e("a,b\n1,2\n").contains("needs one time column named t, time or time_from_start (s); the header has none")
        );
        assert!(e("t,a\n0,x\n").contains("line 2, column 'a': 'x' is not a number"));
        // lines counted as the file has them, comments and blank lines included
        assert!(e("# by hand\nt,a\n\n# next\n0,1\n1,x\n").contains("line 6, column 'a': 'x' is not a number"));
        assert!(
            e("t,a,a.velocity,a.velocity\n0,1,2,3\n").contains("column 'a.velocity' is given twice (columns 3 and 4)")
        );
        assert!(e("t,a,b,a.velocity\n0,1,2,3\n").contains("has velocity columns for some joints but not 'b'"));
        assert!(e("t,a,c.velocity\n0,1,2\n").contains("column 'c.velocity' has no position column 'c'"));
        assert!(e("# by hand\nt,a\n0,1,2\n").contains("line 3 has 3 fields; the header has 2"));
    }
}
