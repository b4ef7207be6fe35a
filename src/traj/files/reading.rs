//! What reading a trajectory file gives besides its points: what the reader noticed
//! ([`Note`], said as warnings), and the joint names the file's are renamed to ([`Rename`],
//! `--rename FROM=TO`).

use std::borrow::Cow;
use std::fmt;
use std::path::Path;

use super::invalid;
use crate::error::{Error, Result, quoted};
use crate::traj::TimedTrajectory;

/// A trajectory file as read: the trajectory (checked), and what reading it noticed.
#[derive(Clone, Debug, PartialEq)]
pub struct Read {
    /// The trajectory, its names renamed.
    pub trajectory: TimedTrajectory,
    /// What the user should know about how it was read, in order.
    pub notes: Vec<Note>,
}

impl From<TimedTrajectory> for Read {
    fn from(trajectory: TimedTrajectory) -> Read {
        Read {
            trajectory,
            notes: Vec::new(),
        }
    }
}

/// Something reading a file decided that the user should know (a warning line).
#[derive(Clone, Debug, PartialEq)]
pub enum Note {
    /// A recorded stream names joints the model does not have: they are left out.
    IgnoredJoints {
        /// The stream (`topic /joint_states`, or `its JointState messages`).
        stream: String,
        /// The joints left out, as the file names them.
        joints: Vec<String>,
    },
    /// Messages with different joints (several publishers on one topic) were merged by time.
    Merged {
        /// The stream.
        stream: String,
        /// The joints of each publisher, as the file names them.
        groups: Vec<Vec<String>>,
    },
    /// The messages' header stamps are all the same: the container's log times are the times.
    LogTimes {
        /// The stream.
        stream: String,
    },
    /// The recorded velocities agree with the positions: joint_trajectory_controller's rule
    /// then plays the points cubic.
    VelocitiesChoseCubic {
        /// The stream.
        stream: String,
    },
    /// The recorded velocities are left out (as if not recorded): the points are joined by
    /// their positions.
    VelocitiesIgnored {
        /// The stream.
        stream: String,
        /// Why.
        why: Unused,
    },
    /// A MoveIt `RobotTrajectory`'s `multi_dof_joint_trajectory` with points (a mobile
    /// base's or a floating frame's poses) beside its joint trajectory: left out, the arm
    /// played fixed to the world as its model is.
    MultiDofLeftOut {
        /// The document (`document 1`).
        label: String,
        /// The multi-DOF joints it moves, as the file names them.
        joints: Vec<String>,
        /// Its points.
        points: usize,
    },
}

/// Why a stream's recorded velocities are left out.
#[derive(Clone, Debug, PartialEq)]
pub enum Unused {
    /// Every velocity is 0 while the positions move (a driver that does not measure them).
    Zero,
    /// Some messages give velocities and others none (this joint has none somewhere).
    Partial {
        /// A joint without velocities in some message.
        joint: String,
    },
    /// They disagree with the positions (measured noise): they fall outside the positions'
    /// slopes by `share` of the positions' motion.
    Disagree {
        /// The joint they miss most on.
        joint: String,
        /// Σᵢ dist(vᵢ, [sᵢ₋, sᵢ₊])·Δtᵢ / Σ|Δq| over every joint
        /// ([`super::joint_states::VELOCITY_AGREEMENT`]).
        share: f64,
    },
}

impl Note {
    /// Whether what is played differs from what the file gives (joints, velocities or a
    /// multi-DOF part left out): such a note is said even under `quiet`.
    pub fn changes_result(&self) -> bool {
        matches!(
            self,
            Note::IgnoredJoints { .. } | Note::VelocitiesIgnored { .. } | Note::MultiDofLeftOut { .. }
        )
    }
}

impl fmt::Display for Note {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = |joints: &[String]| joints.iter().map(|j| quoted(j)).collect::<Vec<_>>().join(", ");
        match self {
            Note::IgnoredJoints { stream, joints } => write!(
                f,
                "{stream} also name {}, not degrees of freedom of the model: left out",
                names(joints)
            ),
            Note::Merged { stream, groups } => write!(
                f,
                "{stream} come from {} publishers ({}): merged by time, each joint between its own messages joined as the points are",
                groups.len(),
                groups
                    .iter()
                    .map(|g| format!("[{}]", names(g)))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Note::MultiDofLeftOut { label, joints, points } => write!(
                f,
                "{label}'s multi_dof_joint_trajectory moves {} over {points} point{} (poses of frames: a mobile base, a floating joint): left out, the arm played fixed to the world as its model is",
                match joints.is_empty() {
                    true => "unnamed joints".to_string(),
                    false => names(joints),
                },
                if *points == 1 { "" } else { "s" }
            ),
            Note::LogTimes { stream } => write!(
                f,
                "{stream} all have the same header stamp: the times are when the bag logged them"
            ),
            Note::VelocitiesChoseCubic { stream } => write!(
                f,
                "{stream} give velocities that agree with their positions: played cubic through them, as joint_trajectory_controller plays points with velocities (`interpolation` linear leaves them out)"
            ),
            Note::VelocitiesIgnored { stream, why } => {
                write!(f, "{stream} give velocities that ")?;
                match why {
                    Unused::Zero => write!(f, "are all 0 while the positions move (not measured)")?,
                    Unused::Partial { joint } => {
                        write!(f, "some messages leave out ({} has none in some)", quoted(joint))?
                    }
                    Unused::Disagree { joint, share } if share.is_finite() => write!(
                        f,
                        "disagree with their positions (outside the positions' slopes by {:.0} % of the motion, most on {}: measured noise)",
                        share * 100.0,
                        quoted(joint)
                    )?,
                    Unused::Disagree { joint, .. } => write!(
                        f,
                        "disagree with their positions (not 0 while the positions stand still, most on {}: measured noise)",
                        quoted(joint)
                    )?,
                }
                write!(
                    f,
                    ": left out, the points joined by their positions (cubic through zero or noisy velocities would stop and go at every message)"
                )
            }
        }
    }
}

/// A joint-name prefix of the file renamed (`--rename FROM=TO`): a name starting with `from`
/// has it replaced by `to` (`fr3_joint1` → `panda_joint1` for `fr3_joint=panda_joint`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rename {
    /// The prefix the file's names have (may be empty: `to` is put before every name).
    pub from: String,
    /// What it becomes (may be empty: the prefix is taken off).
    pub to: String,
}

impl Rename {
    /// `FROM=TO`, or several separated by commas; the error names `rename`.
    pub fn parse_list(text: &str) -> Result<Vec<Rename>> {
        text.split(',')
            .map(|rule| {
                let (from, to) = rule.split_once('=').ok_or_else(|| {
                    Error::option(
                        "rename",
                        format!(
                            "{}: expected FROM=TO (a joint-name prefix of the file, and what it becomes)",
                            quoted(rule)
                        ),
                    )
                })?;
                if from == to {
                    return Err(Error::option("rename", format!("{}: renames nothing", quoted(rule))));
                }
                Ok(Rename {
                    from: from.to_string(),
                    to: to.to_string(),
                })
            })
            .collect()
    }

    /// `name` with the first rule of `rules` whose prefix it has applied.
    pub fn apply<'a>(rules: &[Rename], name: &'a str) -> Cow<'a, str> {
        match rules
            .iter()
            .find_map(|r| name.strip_prefix(r.from.as_str()).map(|rest| (r, rest)))
        {
            Some((rule, rest)) => Cow::Owned(format!("{}{rest}", rule.to)),
            None => Cow::Borrowed(name),
        }
    }
}

/// Renames `trajectory`'s joints by `rules` ([`Rename::apply`]). Each rule must rename some
/// joint, and no two joints may end with one name (each an error naming `rename` and `path`).
pub fn rename(trajectory: &mut TimedTrajectory, rules: &[Rename], path: &Path) -> Result<()> {
    if rules.is_empty() {
        return Ok(());
    }
    let names = &trajectory.joint_names;
    for rule in rules {
        if !names.iter().any(|n| n.starts_with(rule.from.as_str())) {
            return Err(Error::option(
                "rename",
                format!(
                    "{}={}: no joint of {} starts with {} (its joints: {})",
                    rule.from,
                    rule.to,
                    path.display(),
                    quoted(&rule.from),
                    names.iter().map(|n| quoted(n)).collect::<Vec<_>>().join(", ")
                ),
            ));
        }
    }
    let renamed: Vec<String> = names.iter().map(|n| Rename::apply(rules, n).into_owned()).collect();
    for (i, name) in renamed.iter().enumerate() {
        if let Some(j) = renamed[..i].iter().position(|m| m == name) {
            return Err(invalid(
                path,
                format!(
                    "`rename` makes {} and {} one joint, {}",
                    quoted(&names[j]),
                    quoted(&names[i]),
                    quoted(name)
                ),
            ));
        }
    }
    trajectory.joint_names = renamed;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_rename_prefixes_first_match_first() {
        let rules = Rename::parse_list("fr3_joint=panda_joint,fr3_=panda_,=robot_").unwrap();
        assert_eq!(Rename::apply(&rules, "fr3_joint1"), "panda_joint1");
        assert_eq!(Rename::apply(&rules, "fr3_finger_joint1"), "panda_finger_joint1");
        assert_eq!(Rename::apply(&rules, "gripper"), "robot_gripper");
        let strip = Rename::parse_list("robot_arm_=").unwrap();
        assert_eq!(Rename::apply(&strip, "robot_arm_elbow"), "elbow");
        let e = Rename::parse_list("a=b,c").unwrap_err().to_string();
        assert_eq!(
            e,
            "`rename`: 'c': expected FROM=TO (a joint-name prefix of the file, and what it becomes)"
        );
        assert!(
            Rename::parse_list("a=a")
                .unwrap_err()
                .to_string()
                .contains("renames nothing")
        );
    }

    #[test]
    fn a_rule_that_renames_nothing_or_merges_two_joints_is_refused() {
        let mut t = TimedTrajectory {
            joint_names: vec!["fr3_joint1".into(), "panda_joint1".into()],
            points: Vec::new(),
        };
        let path = Path::new("f.yaml");
        let e = rename(&mut t.clone(), &Rename::parse_list("ur_=x_").unwrap(), path).unwrap_err();
        assert_eq!(
            e.to_string(),
            "`rename`: ur_=x_: no joint of f.yaml starts with 'ur_' (its joints: 'fr3_joint1', 'panda_joint1')"
        );
        let e = rename(&mut t.clone(), &Rename::parse_list("fr3_=panda_").unwrap(), path).unwrap_err();
        assert!(
            e.to_string()
                .contains("makes 'fr3_joint1' and 'panda_joint1' one joint, 'panda_joint1'"),
            "{e}"
        );
        rename(&mut t, &Rename::parse_list("fr3_joint=j").unwrap(), path).unwrap();
        assert_eq!(t.joint_names, ["j1", "panda_joint1"]);
    }
}
