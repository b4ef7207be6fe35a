//! Time-stamped trajectories (issue 31, docs/trajectories.md): `faze4 replay --q-traj` on the
//! YAML, JSON, MCAP and CSV files of `tools/oracle/trajectory_fixtures.py` (TOPP-RA on the UR5,
//! Ruckig on the SO-101) equals Pinocchio's closed loop with joint_trajectory_controller's
//! interpolation, linear, cubic and quintic, under both feed-forwards; what faze4 writes is what
//! ROS 2's readers read; and bad inputs are one line, exit 2, nothing written.

use crate::common;

use std::path::{Path, PathBuf};

use common::*;
use faze4::traj::files::{self, Selection};
use faze4::traj::{TimedTrajectory, TrajectoryPoint};

/// The worst |faze4 − Pinocchio| over the trail of fixture `trajectory_<name>.json` (rad, m),
/// after checking the summary's feed-forward and interpolation.
fn against_pinocchio(name: &str) -> f64 {
    let fixture = fixture(&format!("trajectory_{name}.json"));
    let dir = temp_dir(&format!("trajectory-{name}"));
    let mut args: Vec<String> = (fixture["faze4_args"].as_array().unwrap().iter())
        .map(|a| a.as_str().unwrap())
        .map(|a| match a.starts_with("tests/") {
            true => repo_path(a).to_string_lossy().into_owned(),
            false => a.to_string(),
        })
        .collect();
    args.extend(["-q", "--trail", "trail.csv", "--summary", "s.json"].map(String::from));
    let run = faze4(&dir, &words(&args));
    assert!(run.status.success(), "{name}: {}", run.stderr);
    let summary = summary(&dir, "s.json");
    assert_eq!(summary["feed_forward"], fixture["feed_forward"], "{name}");
    assert_eq!(summary["interpolation"], fixture["interpolation"], "{name}");
    let ours = fixture_trail(&dir, &fixture);
    let theirs = mat_f64(&fixture["trail"]["rows"]);
    assert_eq!(ours.len(), theirs.len(), "{name}: trail rows");
    let worst = (ours.iter().zip(&theirs))
        .map(|(a, b)| max_abs_diff(a, b))
        .fold(0.0, f64::max);
    // the run moves: a comparison of two standing arms would prove nothing
    let moves = (4..theirs[0].len())
        .map(|c| theirs.iter().fold(0.0f64, |m, r| m.max((r[c] - theirs[0][c]).abs())))
        .fold(0.0, f64::max);
    assert!(moves > 0.2, "{name}: the arm barely moves ({moves} rad)");
    std::fs::remove_dir_all(&dir).unwrap();
    worst
}

fn equals_pinocchio(name: &str) {
    let worst = against_pinocchio(name);
    assert!(worst <= 1e-9, "{name}: faze4 vs Pinocchio {worst:e}");
    eprintln!("{name}: faze4 vs Pinocchio {worst:.1e}");
}

#[test]
fn yaml_linear_full_feed_forward() {
    equals_pinocchio("ur5_yaml_linear_full");
}

#[test]
fn yaml_second_message_quintic() {
    equals_pinocchio("ur5_yaml_quintic_gravity");
}

#[test]
fn json_cubic_joints_in_another_order() {
    equals_pinocchio("ur5_json_cubic_gravity");
}

#[test]
fn mcap_quintic_full_feed_forward() {
    equals_pinocchio("ur5_mcap_quintic_full");
}

#[test]
fn csv_linear_columns_in_another_order() {
    equals_pinocchio("ur5_csv_linear_gravity");
}

#[test]
fn csv_cubic_with_a_held_gripper() {
    equals_pinocchio("so101_csv_cubic_full");
}

#[test]
fn mcap_joint_trajectory_topic_beside_joint_states() {
    equals_pinocchio("so101_mcap_quintic_gravity");
}

#[test]
fn mcap_recorded_joint_states() {
    equals_pinocchio("so101_mcap_joint_states_cubic_full");
}

/// UR's own example as a FollowJointTrajectory goal (`ros2 action send_goal`'s flow YAML): the
/// first point at 4 s is kept, the arm held at its positions until then.
#[test]
fn goal_first_point_at_4_s_held() {
    equals_pinocchio("ur5_goal_held_cubic_gravity");
}

/// The same goal from `--start`: 4 s to reach the first point, cubic from rest.
#[test]
fn goal_from_a_start() {
    equals_pinocchio("ur5_goal_from_start_cubic_full");
}

/// One point, positions only, reached in 4 s from `--start` (linear, as the controller).
#[test]
fn one_point_goal_from_a_start() {
    equals_pinocchio("ur5_one_point_linear_gravity");
}

/// A MoveIt DisplayTrajectory as `ros2 topic echo` prints it: `--message 2` its second
/// RobotTrajectory.
#[test]
fn moveit_display_trajectory_second_segment() {
    equals_pinocchio("ur5_display_trajectory_quintic_full");
}

/// ROS 1's layout (`secs`/`nsecs`, `header.seq`): a RobotTrajectory echo in YAML.
#[test]
fn ros1_robot_trajectory_echo() {
    equals_pinocchio("ur5_ros1_robot_trajectory_cubic_gravity");
}

/// A ROS 1 FollowJointTrajectoryGoal as JSON, positions only, `--interpolation cubic`: the
/// velocities of joint_trajectory_controller's positions_upsampling spline.
#[test]
fn ros1_goal_json_upsampled_cubic() {
    equals_pinocchio("ur5_ros1_goal_upsampled_cubic_full");
}

/// An FR3's JointTrajectory as `ros2 topic echo` printed it (franka_ros2 issue 172) on
/// example-robot-data's Panda, `--rename fr3_joint=panda_joint`.
#[test]
fn fr3_echo_renamed_onto_the_panda() {
    equals_pinocchio("panda_fr3_echo_renamed_linear_gravity");
}

/// A `/joint_states` echo whose velocities are all 0 (not measured), the gripper published
/// apart, a camera's joints the model lacks: merged by time, played linear.
#[test]
fn joint_states_echo_with_zero_velocities() {
    equals_pinocchio("so101_echo_zero_velocities_linear_gravity");
}

/// The arm and the gripper as two publishers on one MCAP topic with their true velocities:
/// merged, played cubic through them.
#[test]
fn joint_states_from_two_publishers_cubic() {
    equals_pinocchio("so101_mcap_publishers_cubic_full");
}

/// ROS 1 JointStates as JSON with measured noise in the velocities: left out, linear; and the
/// same under `--interpolation cubic`.
#[test]
fn joint_states_with_noisy_velocities() {
    equals_pinocchio("so101_ros1_noisy_velocities_linear_gravity");
    equals_pinocchio("so101_ros1_noisy_upsampled_cubic_gravity");
}

// Bags as `rosbags` writes them (tests/fixtures/trajectories/bags/; tests/it/bags.rs has the rest)

#[test]
fn rosbag2_folder_sqlite_recorded_joint_states() {
    equals_pinocchio("so101_db3_joint_states_cubic_full");
}

#[test]
fn rosbag2_folder_mcap_zstd_per_message() {
    equals_pinocchio("so101_mcap_zstd_per_message_quintic_gravity");
}

#[test]
fn rosbag2_folder_sqlite_zstd_per_file() {
    equals_pinocchio("ur5_db3_zstd_per_file_linear_gravity");
}

#[test]
fn rosbag2_folder_mcap_zstd_per_file() {
    equals_pinocchio("ur5_mcap_zstd_per_file_cubic_full");
}

#[test]
fn ros1_bag_bz2_recorded_joint_states() {
    equals_pinocchio("so101_ros1_bz2_joint_states_cubic_gravity");
}

#[test]
fn ros1_bag_lz4_joint_trajectory() {
    equals_pinocchio("ur5_ros1_lz4_quintic_full");
}

// LeRobot datasets (tests/fixtures/trajectories/lerobot/)

#[test]
fn lerobot_v3_normalised_with_calibration() {
    equals_pinocchio("so101_lerobot_v3_calibrated_linear_gravity");
}

#[test]
fn lerobot_v21_in_degrees() {
    equals_pinocchio("so101_lerobot_v21_degrees_linear_full");
}

/// The model joint a trajectory does not name is said once, and the default duration is the
/// last time.
#[test]
fn held_joints_are_said_and_the_duration_is_the_last_time() {
    let dir = temp_dir("trajectory-held");
    let input = repo_path("tests/fixtures/trajectories/so101_ruckig.csv");
    let args = replay_args("so101.urdf", &input, &["--trail", "none", "--summary", "s.json"]);
    let run = faze4(&dir, &words(&args));
    assert!(run.status.success(), "{}", run.stderr);
    let warnings: Vec<&str> = run.stderr.lines().filter(|l| l.contains("gives no values")).collect();
    assert_eq!(warnings.len(), 1, "{}", run.stderr);
    assert!(
        warnings[0].ends_with("gives no values for 'gripper' (0): it holds its start position with zero velocity"),
        "{}",
        warnings[0]
    );
    let read = files::read(&input, &Selection::default()).unwrap();
    let s = summary(&dir, "s.json");
    let steps = (read.duration() / 2e-4).round() as u64;
    assert_eq!(s["steps"].as_u64(), Some(steps));
    // the JointState topic names the gripper: no warning
    let mcap = repo_path("tests/fixtures/trajectories/so101_ruckig.mcap");
    let with_topic = replay_args("so101.urdf", &mcap, &["--trail", "none", "--topic", "/joint_states"]);
    let run = faze4(&dir, &words(&with_topic));
    assert!(
        run.status.success() && !run.stderr.contains("gives no values"),
        "{}",
        run.stderr
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// tools/oracle/trajectory_fixtures.py read faze4's conversion of the UR5's MCAP into every
/// format with PyYAML, json, csv and mcap_ros2's reader, and found the trajectory to the last
/// bit: faze4 still writes those files (the text formats byte for byte; the MCAP's schema,
/// channel and CDR message byte for byte, the container's compression being zstd's), and reads
/// each back as the MCAP it came from.
#[test]
fn what_faze4_writes_is_what_ros_readers_read() {
    let source = files::read(
        &repo_path("tests/fixtures/trajectories/ur5_toppra.mcap"),
        &Selection::default(),
    )
    .unwrap();
    let dir = temp_dir("trajectory-written");
    for ext in ["yaml", "json", "csv", "mcap"] {
        let checked = repo_path(&format!("tests/fixtures/trajectories/written/ur5_toppra.{ext}"));
        let ours = dir.join(format!("ur5_toppra.{ext}"));
        files::write(&ours, &source).unwrap();
        let (a, b) = (std::fs::read(&ours).unwrap(), std::fs::read(&checked).unwrap());
        match ext {
            "mcap" => assert_eq!(mcap_records(&a), mcap_records(&b)),
            _ => assert!(a == b, "{ext}: faze4 no longer writes what ROS's readers checked"),
        }
        assert_eq!(files::read(&checked, &Selection::default()).unwrap(), source, "{ext}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An MCAP file's header profile, schemas, channels and messages.
fn mcap_records(bytes: &[u8]) -> Vec<String> {
    let mut out = Vec::new();
    for message in mcap::MessageStream::new(bytes).unwrap() {
        let m = message.unwrap();
        let schema = m.channel.schema.as_ref().unwrap();
        out.push(format!(
            "{} {} {} {:?} {} {:?} {} {:?}",
            m.channel.topic,
            m.channel.message_encoding,
            schema.name,
            std::str::from_utf8(&schema.data).unwrap(),
            schema.encoding,
            m.data,
            m.log_time,
            m.channel.metadata
        ));
    }
    out
}

/// A small valid trajectory for the UR5, to break one way or another.
fn ur5_trajectory() -> TimedTrajectory {
    let point = |t: f64, q: f64| TrajectoryPoint {
        time_from_start: t,
        positions: vec![q, -1.0, 1.0, -1.0, -1.5, 0.0],
        ..Default::default()
    };
    TimedTrajectory {
        joint_names: [
            "shoulder_pan_joint",
            "shoulder_lift_joint",
            "elbow_joint",
            "wrist_1_joint",
            "wrist_2_joint",
            "wrist_3_joint",
        ]
        .map(String::from)
        .to_vec(),
        points: vec![point(0.0, 0.0), point(0.5, 0.2), point(1.0, 0.1)],
    }
}

/// Runs `replay` of `input` on the UR5 with `extra` options in an empty directory and expects
/// the refusal `parts`.
fn refused(input: &Path, extra: &[&str], parts: &[&str]) {
    let dir = temp_dir("trajectory-refused");
    let outputs = ["--trail", "trail.csv", "--summary", "s.json", "--html", "run.html"];
    let mut args = replay_args("ur5_robot.urdf", input, &outputs);
    args.extend(extra.iter().map(|a| a.to_string()));
    refuses(&dir, &words(&args), parts);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `replay --urdf tests/urdf/example_robot_data/<urdf> --q-traj <input> --no-collisions`, then
/// `extra`.
fn replay_args(urdf: &str, input: &Path, extra: &[&str]) -> Vec<String> {
    let urdf = repo_path(&format!("tests/urdf/example_robot_data/{urdf}"));
    let mut args: Vec<String> = [
        "replay",
        "--urdf",
        urdf.to_str().unwrap(),
        "--q-traj",
        input.to_str().unwrap(),
    ]
    .map(String::from)
    .to_vec();
    args.push("--no-collisions".into());
    args.extend(extra.iter().map(|a| a.to_string()));
    args
}

fn words(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

/// `text` as the file `name` in a directory of inputs.
fn input(inputs: &Path, name: &str, text: &str) -> PathBuf {
    let path = inputs.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// What a replay of a message says: the banner's start and approach, the summary's
/// `playback`, and the warnings of a recorded stream (joints and velocities left out are said
/// under `-q` too).
#[test]
fn the_start_the_approach_and_the_stream_are_said() {
    let dir = temp_dir("trajectory-said");
    let goal = repo_path("tests/fixtures/messages/ur5_example_goal.yaml");
    let run = faze4(
        &dir,
        &words(&replay_args(
            "ur5_robot.urdf",
            &goal,
            &["--trail", "none", "--summary", "s.json"],
        )),
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(
        run.stdout.lines().any(|l| l
            == "[faze4] trajectory: 2 points, cubic (its points give velocities) · from the first point's positions, held 4 s until its time"),
        "{}",
        run.stdout
    );
    let s = summary(&dir, "s.json");
    assert_eq!(s["playback"]["approach_s"], 4.0);
    assert_eq!(s["playback"]["start_given"], false);
    assert_eq!(s["playback"]["points"], 2);
    assert_eq!(s["steps"], 40000, "8 s: the approach included");
    let start = ["--start", "0,-1.57,1.57,-1.57,-1.57,0", "--interpolation", "linear"];
    let run = faze4(
        &dir,
        &words(&replay_args(
            "ur5_robot.urdf",
            &goal,
            &[&["--trail", "none"][..], &start[..]].concat(),
        )),
    );
    assert!(
        run.stdout.contains(
            "[faze4] trajectory: 2 points, linear (--interpolation) · from --start, reaching the first point at 4 s"
        ),
        "{}",
        run.stdout
    );
    // the stream: the camera's joints and the zero velocities left out, said under -q
    let echo = repo_path("tests/fixtures/messages/so101_joint_states_echo.yaml");
    let run = faze4(
        &dir,
        &words(&replay_args("so101.urdf", &echo, &["--trail", "none", "-q"])),
    );
    assert!(run.status.success(), "{}", run.stderr);
    let warnings: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(warnings.len(), 2, "{}", run.stderr);
    assert!(
        warnings[0].ends_with("so101_joint_states_echo.yaml: its JointState messages also name 'camera_pan', 'camera_tilt', not degrees of freedom of the model: left out"),
        "{}",
        warnings[0]
    );
    assert!(
        warnings[1].contains("give velocities that are all 0 while the positions move (not measured): left out"),
        "{}",
        warnings[1]
    );
    let run = faze4(&dir, &words(&replay_args("so101.urdf", &echo, &["--trail", "none"])));
    assert!(run.stderr.contains("come from 2 publishers (['shoulder_pan', 'shoulder_lift', 'elbow_flex', 'wrist_flex', 'wrist_roll'], ['gripper']): merged by time"), "{}", run.stderr);
    let mcap = repo_path("tests/fixtures/messages/so101_publishers.mcap");
    let run = faze4(&dir, &words(&replay_args("so101.urdf", &mcap, &["--trail", "none"])));
    assert!(run.stderr.contains("topic /joint_states's JointState messages give velocities that agree with their positions: played cubic through them"), "{}", run.stderr);
    let json = repo_path("tests/fixtures/messages/so101_ros1_joint_states.json");
    let run = faze4(
        &dir,
        &words(&replay_args("so101.urdf", &json, &["--trail", "none", "-q"])),
    );
    assert!(
        run.stderr
            .contains("give velocities that disagree with their positions (outside the positions' slopes by "),
        "{}",
        run.stderr
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Files people published that are not what `replay` plays, or need an option, refused for
/// their real cause (tests/fixtures/messages/README.md says where each comes from).
#[test]
fn published_files_are_refused_for_their_cause() {
    let file = |name: &str| repo_path(&format!("tests/fixtures/messages/{name}"));
    // UR's driver: the goal publisher's parameters
    refused(
        &file("ur_test_goal_publishers_config.yaml"),
        &[],
        &[
            "document 1 is a ROS 2 parameter file (the parameters of 'publisher_joint_trajectory_controller'), not a message; faze4 reads",
        ],
    );
    let dir = temp_dir("trajectory-published");
    let panda =
        |input: &Path, extra: &[&str]| replay_args("panda.urdf", input, &[&["--trail", "none"][..], extra].concat());
    // an FR3's joints on the Panda, before and after --rename
    refuses(
        &dir,
        &words(&panda(&file("fr3_joint_trajectory_echo.yaml"), &[])),
        &[
            "names joint 'fr3_joint1', which the model does not have",
            "--rename FROM=TO maps a prefix",
        ],
    );
    refuses(
        &dir,
        &words(&panda(
            &file("fr3_joint_trajectory_echo.yaml"),
            &["--rename", "franka_=panda_"],
        )),
        &["--rename: franka_=panda_: no joint of", "starts with 'franka_'"],
    );
    // one state: a hold of no length, unless --duration; the mimic finger left out
    refuses(
        &dir,
        &words(&panda(&file("panda_joint_states_echo.yaml"), &[])),
        &[
            "--duration:",
            "lasts 0 s (one point at t = 0): give how long to hold it",
        ],
    );
    let run = faze4(
        &dir,
        &words(&panda(
            &file("panda_joint_states_echo.yaml"),
            &["--duration", "0.5", "-q"],
        )),
    );
    assert!(
        run.status.success()
            && run
                .stderr
                .contains("'panda_finger_joint2', not degrees of freedom of the model"),
        "{}",
        run.stderr
    );
    // two publishers of the same wheels at one stamp (a joint_state_publisher beside the broadcaster)
    refuses(
        &dir,
        &words(&panda(&file("two_publishers_joint_states.yaml"), &[])),
        &[
            "all have the header stamp 22.6 s and give joint 'front_left_wheel_joint' different positions",
            "two publishers of the same joints",
        ],
    );
    // a ROS 1 echo of another robot's joints
    refuses(
        &dir,
        &words(&panda(&file("ros1_gimbal_joint_states_echo.yaml"), &[])),
        &["name none of the model's joints (they name 'pan_gimbal_joint', 'tilt_gimbal_joint'"],
    );
    // quintic from velocities; a start beyond a limit; --start on a .npy
    refuses(
        &dir,
        &words(&replay_args(
            "ur5_robot.urdf",
            &file("ur5_example_goal.yaml"),
            &["--interpolation", "quintic"],
        )),
        &["--interpolation quintic needs accelerations at every point; its points give positions and velocities"],
    );
    refuses(
        &dir,
        &words(&replay_args(
            "ur5_robot.urdf",
            &file("ur5_example_goal.yaml"),
            &["--start", "0,0,0,0,0"],
        )),
        &["--start: gives 5 values; ur5 has 6 degrees of freedom"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_inputs_are_one_line_exit_2_and_nothing_written() {
    let inputs = temp_dir("trajectory-bad-inputs");
    // written by faze4 (valid), then broken by hand in the text
    let good = inputs.join("good.yaml");
    files::write(&good, &ur5_trajectory()).unwrap();
    let yaml = std::fs::read_to_string(&good).unwrap();
    let csv = "t,shoulder_pan_joint,shoulder_lift_joint,elbow_joint,wrist_1_joint,wrist_2_joint,wrist_3_joint\n";
    // times not increasing
    let stalled = yaml.replacen("nanosec: 500000000", "nanosec: 0", 1);
    refused(
        &input(&inputs, "stalled.yaml", &stalled),
        &[],
        &[
            "stalled.yaml",
            "point 1: time_from_start 0 s is not after point 0's 0 s",
        ],
    );
    refused(
        &input(
            &inputs,
            "back.csv",
            &format!("{csv}0,0,-1,1,-1,-1.5,0\n0.5,0,-1,1,-1,-1.5,0\n0.25,0,-1,1,-1,-1.5,0\n"),
        ),
        &[],
        &["point 2: time_from_start 0.25 s is not after point 1's 0.5 s"],
    );
    // NaN
    refused(
        &input(&inputs, "nan.yaml", &yaml.replacen("- 0.2\n", "- .nan\n", 1)),
        &[],
        &["point 1: positions of joint 'shoulder_pan_joint' is NaN"],
    );
    refused(
        &input(
            &inputs,
            "nan.csv",
            &format!("{csv}0,0,-1,1,-1,-1.5,0\n0.5,NaN,-1,1,-1,-1.5,0\n"),
        ),
        &[],
        &["point 1: positions of joint 'shoulder_pan_joint' is NaN"],
    );
    // a joint the model lacks
    refused(
        &input(
            &inputs,
            "unknown.yaml",
            &yaml.replace("- wrist_3_joint", "- wrist_4_joint"),
        ),
        &[],
        &[
            "names joint 'wrist_4_joint', which the model does not have",
            "'shoulder_pan_joint', 'shoulder_lift_joint'",
        ],
    );
    // a point of the wrong length
    let short = yaml.replacen("  - -1.5\n  - 0.0\n", "  - -1.5\n", 1);
    refused(
        &input(&inputs, "short.yaml", &short),
        &[],
        &["point 0 has 5 positions; joint_names names 6 joints"],
    );
    // beyond a joint limit
    let far = yaml.replacen("- 0.2\n", "- 7.0\n", 1);
    refused(
        &input(&inputs, "far.yaml", &far),
        &[],
        &["point 1: joint J1 (shoulder_pan_joint) is commanded to 7 rad, beyond its limits"],
    );
    // a message the file does not hold; --topic on a YAML
    refused(
        &good,
        &["--message", "2"],
        &["--message: 2:", "holds 1 JointTrajectory messages"],
    );
    refused(
        &good,
        &["--topic", "/x"],
        &["--topic: picks a topic of a bag (.mcap, .db3, .bag, a rosbag2 folder)"],
    );
    // MCAP: several candidate topics, no such topic, a topic of another type
    let bad_topics = repo_path("tests/fixtures/trajectories/bad_topics.mcap");
    refused(
        &bad_topics,
        &[],
        &[
            "has 2 candidate topics: /left_arm/joint_states (sensor_msgs/msg/JointState, 3 messages), /right_arm/joint_states (sensor_msgs/msg/JointState, 3 messages); pick one with --topic",
        ],
    );
    refused(
        &bad_topics,
        &["--topic", "/joint_trajectory"],
        &[
            "--topic: /joint_trajectory:",
            "has no such topic (its topics: /chatter (std_msgs/msg/String, 1 message)",
        ],
    );
    refused(
        &bad_topics,
        &["--topic", "/chatter"],
        &["--topic: /chatter in", "is of type std_msgs/msg/String"],
    );
    // a JointState topic whose joints the model does not have (the SO-101's, on the UR5)
    refused(
        &bad_topics,
        &["--topic", "/left_arm/joint_states"],
        &[
            "topic /left_arm/joint_states's JointState messages name none of the model's joints (they name 'gripper', 'wrist_roll'",
            "--rename maps a prefix to the model's",
        ],
    );
    // --ff full and --no-ff together; --message on a .npy
    refused(&good, &["--ff", "full", "--no-ff"], &["--no-ff"]);
    let npy = inputs.join("frames.npy");
    faze4::traj::npy::write_samples(&npy, &[vec![0.0; 6], vec![0.1; 6]]).unwrap();
    refused(
        &npy,
        &["--message", "1"],
        &["--message: picks from a .yaml, .json or bag file, not a .npy"],
    );
    // not an MCAP at all
    refused(
        &input(&inputs, "text.mcap", "hello"),
        &[],
        &[
            "text.mcap: not a bag (MCAP, rosbag2 SQLite, ROS 1 or one of them compressed with zstd): it starts with hello",
        ],
    );
    std::fs::remove_dir_all(&inputs).unwrap();
}
