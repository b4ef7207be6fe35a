//! Bags as recorded and LeRobot datasets (issue 43; docs/trajectories.md): what a container
//! holds, read whatever its name says, equals what its writer wrote; split bags are joined;
//! what is not played is said with its cause. The closed loops of these files against
//! Pinocchio are in tests/it/trajectories.rs.

use crate::common;

use std::path::{Path, PathBuf};

use common::*;
use faze4::traj::files::{self, Selection};

const BAGS: &str = "tests/fixtures/trajectories/bags";
const LEROBOT: &str = "tests/fixtures/trajectories/lerobot";

fn so101_replay(input: &Path, extra: &[&str]) -> Vec<String> {
    let urdf = repo_path("tests/urdf/example_robot_data/so101.urdf");
    let mut args: Vec<String> = [
        "replay",
        "--urdf",
        urdf.to_str().unwrap(),
        "--q-traj",
        input.to_str().unwrap(),
    ]
    .map(String::from)
    .to_vec();
    args.extend(["--no-collisions", "--trail", "none"].map(String::from));
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

fn run(dir: &Path, args: &[String]) -> Run {
    faze4(dir, &args.iter().map(String::as_str).collect::<Vec<_>>())
}

/// The topics and message counts a rosbag2 folder's metadata.yaml lists, as faze4 lists them.
fn listed_in_metadata(folder: &Path) -> String {
    let text = std::fs::read_to_string(folder.join("metadata.yaml")).unwrap();
    let yaml: serde_json::Value = serde_norway::from_str(&text).unwrap();
    let mut topics: Vec<(String, String, u64)> = (yaml["rosbag2_bagfile_information"]["topics_with_message_count"]
        .as_array()
        .unwrap()
        .iter())
    .map(|t| {
        let m = &t["topic_metadata"];
        (
            m["name"].as_str().unwrap().to_string(),
            m["type"].as_str().unwrap().to_string(),
            t["message_count"].as_u64().unwrap(),
        )
    })
    .collect();
    topics.sort();
    (topics.iter())
        .map(|(name, kind, n)| format!("{name} ({kind}, {n} messages)"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// rosbag2's own split test bags (ros2/rosbag2, 5 files each, MCAP and SQLite; no joint
/// topic): every file is read in order, so the topics listed carry the counts metadata.yaml
/// gives for the whole bag (6,074 messages); a file missing is named.
#[test]
fn split_bags_are_read_whole_and_a_bag_without_joints_lists_its_topics() {
    let dir = temp_dir("bags-split");
    for storage in ["mcap", "sqlite3"] {
        let folder = repo_path(&format!("{BAGS}/public/rosbag2_wbag_{storage}"));
        let listed = listed_in_metadata(&folder);
        assert!(
            listed.starts_with("AAA (std_msgs/msg/String, 804 messages), BBB"),
            "{listed}"
        );
        let args = so101_replay(&folder, &[]);
        refuses(
            &dir,
            &args.iter().map(String::as_str).collect::<Vec<_>>(),
            &[
                "has no trajectory_msgs/msg/JointTrajectory or sensor_msgs/msg/JointState topic",
                &format!("(its topics: {listed})"),
            ],
        );
        // one split file gone
        let partial = dir.join(format!("partial_{storage}"));
        std::fs::create_dir_all(&partial).unwrap();
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if !path.to_string_lossy().contains("wbag_2") {
                std::fs::copy(&path, partial.join(path.file_name().unwrap())).unwrap();
            }
        }
        let e = files::read(&partial, &Selection::default()).unwrap_err().to_string();
        assert!(e.contains("metadata.yaml: lists 'wbag_2."), "{e}");
        // without metadata.yaml, the files in split order: the same topics
        std::fs::remove_file(partial.join("metadata.yaml")).unwrap();
        let e = files::read(&partial, &Selection::default()).unwrap_err().to_string();
        assert!(e.contains("(its topics: AAA (std_msgs/msg/String, "), "{e}");
        std::fs::remove_dir_all(&partial).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A storage file read alone, or under another name (`.npy`, no extension), gives what its
/// folder gives: the file is told by its first bytes (a `.mcap.zstd` was "not a NumPy .npy
/// file").
#[test]
fn a_file_is_what_its_bytes_say() {
    let dir = temp_dir("bags-sniffed");
    let cases = [
        ("ur5_mcap_zstd_per_file", "ur5_mcap_zstd_per_file.mcap.zstd"),
        ("ur5_db3_zstd_per_file", "ur5_db3_zstd_per_file.db3.zstd"),
        ("so101_humble_db3", "so101_humble_db3.db3"),
        ("so101_mcap_zstd_per_message", "so101_mcap_zstd_per_message.mcap"),
    ];
    for (folder, file) in cases {
        let folder = repo_path(&format!("{BAGS}/{folder}"));
        let whole = files::read(&folder, &Selection::default()).unwrap();
        assert!(whole.points.len() > 10);
        let alone = folder.join(file);
        assert_eq!(files::read(&alone, &Selection::default()).unwrap(), whole, "{file}");
        for name in ["renamed.npy", "renamed"] {
            let copy = dir.join(name);
            std::fs::copy(&alone, &copy).unwrap();
            assert_eq!(
                files::read(&copy, &Selection::default()).unwrap(),
                whole,
                "{file} as {name}"
            );
        }
    }
    // a ROS 1 bag under an .mcap name
    let bag = repo_path(&format!("{BAGS}/ur5_noetic_lz4.bag"));
    std::fs::copy(&bag, dir.join("bag.mcap")).unwrap();
    assert_eq!(
        files::read(&dir.join("bag.mcap"), &Selection::default()).unwrap(),
        files::read(&bag, &Selection::default()).unwrap()
    );
    // the banner says what the file is and which topic was played
    let run = run(
        &dir,
        &so101_replay(
            &repo_path(&format!("{BAGS}/so101_noetic_bz2.bag")),
            &["--topic", "/joint_states", "--duration", "0.01"],
        ),
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(
        run.stdout
            .starts_with("[faze4] replay of a ROS 1 bag, topic /joint_states ·"),
        "{}",
        run.stdout
    );
    // a folder holding nothing faze4 reads
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let e = files::read(&empty, &Selection::default()).unwrap_err().to_string();
    assert!(e.ends_with("is a directory holding neither a rosbag2 bag (metadata.yaml, .mcap or .db3 files) nor a LeRobot dataset (meta/info.json)"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Broken containers are refused in one line naming the cause, before memory is taken for
/// what they claim.
#[test]
fn broken_containers_name_their_cause() {
    let dir = temp_dir("bags-broken");
    let write = |name: &str, bytes: &[u8]| -> PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    };
    let read = |path: &Path| files::read(path, &Selection::default()).unwrap_err().to_string();
    // a ROS 1 chunk claiming 4 GiB once decompressed
    let field = |name: &str, value: &[u8]| {
        let mut f = ((name.len() + 1 + value.len()) as u32).to_le_bytes().to_vec();
        f.extend(name.as_bytes());
        f.push(b'=');
        f.extend(value);
        f
    };
    let record = |header: Vec<u8>, data: &[u8]| {
        let mut r = (header.len() as u32).to_le_bytes().to_vec();
        r.extend(header);
        r.extend((data.len() as u32).to_le_bytes());
        r.extend(data);
        r
    };
    let mut bag = b"#ROSBAG V2.0\n".to_vec();
    bag.extend(record(
        [
            field("op", &[5]),
            field("compression", b"bz2"),
            field("size", &u32::MAX.to_le_bytes()),
        ]
        .concat(),
        b"BZh9",
    ));
    let e = read(&write("huge_chunk.bag", &bag));
    assert!(
        e.contains("a chunk claims 4.0 GiB once decompressed, more than the 256 MiB a record may hold"),
        "{e}"
    );
    // a record's length past the end
    let mut cut = b"#ROSBAG V2.0\n".to_vec();
    cut.extend(4096u32.to_le_bytes());
    cut.extend(b"op=");
    let e = read(&write("cut.bag", &cut));
    assert!(
        e.contains("not a readable ROS 1 bag: it ends inside a record's header (3 of 4096 bytes)"),
        "{e}"
    );
    // a truncated SQLite database
    let db3 = std::fs::read(repo_path(&format!("{BAGS}/so101_humble_db3/so101_humble_db3.db3"))).unwrap();
    let e = read(&write("cut.db3", &db3[..4096]));
    assert!(e.contains("cut.db3: not a readable rosbag2 SQLite bag"), "{e}");
    // zstd that is not a bag, and zstd that does not decompress
    let e = read(&write(
        "text.mcap.zstd",
        &zstd::encode_all(&b"hello, world"[..], 3).unwrap(),
    ));
    assert!(
        e.contains(
            "compressed with zstd, and what it holds is not a bag (MCAP, SQLite or ROS 1): it starts with hello, world"
        ),
        "{e}"
    );
    let e = read(&write("junk.mcap.zstd", &[0x28, 0xb5, 0x2f, 0xfd, 0, 0, 0, 0]));
    assert!(e.contains("junk.mcap.zstd:"), "{e}");
    // a Parquet file given alone
    let parquet = repo_path(&format!("{LEROBOT}/so101_v3/data/chunk-000/file-000.parquet"));
    let e = read(&parquet);
    assert!(
        e.contains("a Parquet file: a LeRobot dataset is read from its folder"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// LeRobot datasets: the gripper is held with a warning; normalised values taken as radians
/// say what to give; options that do not fit are refused naming them.
#[test]
fn lerobot_datasets_say_what_they_are_and_what_is_missing() {
    let dir = temp_dir("bags-lerobot");
    let v3 = repo_path(&format!("{LEROBOT}/so101_v3"));
    let calibration = repo_path(&format!("{LEROBOT}/so101_calibration.json"));
    let calibrated = so101_replay(
        &v3,
        &[
            "--episode",
            "1",
            "--calibration",
            calibration.to_str().unwrap(),
            "--duration",
            "0.01",
        ],
    );
    let ok = run(&dir, &calibrated);
    assert!(ok.status.success(), "{}", ok.stderr);
    assert!(
        ok.stdout.starts_with("[faze4] replay of a LeRobot v3.0 dataset, episode 1 of 3, action (60 frames, normalised, turned into rad by the calibration) ·"),
        "{}",
        ok.stdout
    );
    assert!(
        ok.stderr.contains("so101_v3: column 'gripper.pos' is the gripper's opening (LeRobot's 0–100 % of its range, not an angle): the gripper holds its start position"),
        "{}",
        ok.stderr
    );
    let args = |extra: &[&str]| so101_replay(&v3, extra);
    let refused = |extra: &[&str], parts: &[&str]| {
        let a = args(extra);
        refuses(&dir, &a.iter().map(String::as_str).collect::<Vec<_>>(), parts)
    };
    refused(
        &["--episode", "1"],
        &[
            "]; the values were taken as radians, but LeRobot stores a joint as −100…100 normalised by the arm's calibration unless the arm was recorded in degrees: give --calibration FILE.json",
        ],
    );
    refused(
        &["--episode", "3"],
        &["--episode: 3:", "holds 3 episodes, counted from 0"],
    );
    refused(
        &["--lerobot-key", "velocity"],
        &[
            "--lerobot-key: velocity:",
            "its features with names: action, observation.state",
        ],
    );
    refused(
        &["--units", "deg", "--calibration", calibration.to_str().unwrap()],
        &["--units: and --calibration both say what the values are"],
    );
    refused(
        &["--topic", "/x"],
        &["--topic: picks from a file or bag, not a LeRobot dataset"],
    );
    let bag = repo_path(&format!("{BAGS}/so101_noetic_bz2.bag"));
    let on_bag = so101_replay(&bag, &["--units", "deg"]);
    refuses(
        &dir,
        &on_bag.iter().map(String::as_str).collect::<Vec<_>>(),
        &["--units: applies to a LeRobot dataset (a folder holding meta/info.json)"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
