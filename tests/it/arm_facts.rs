//! Where an arm's facts come from (issue 50, item 4): the Faze4's torque limits, shapes' IK,
//! board and built-in meshes belong to the descriptions faze4 bundles, so the bundled arm and a
//! byte-for-byte copy of its files have them and nothing else does, whatever its name; any other
//! arm draws its shapes on a board from its own reach.

use crate::common;

use common::{faze4, repo_path, temp_dir};
use faze4::faze4::{BOARD, defaults};
use faze4::geometry::Robot;
use faze4::model::{ArmDefaults, FrameId, LoadWarning, PackagePaths};
use faze4::sim::MeshSource;
use faze4::spatial::Vec3;
use faze4::traj::ShapeRun;
use faze4::traj::shape::{self, Shape};
use std::path::Path;

/// A six-joint chain of our own making named `name`: joints `j1`..`j6` about z, y, y, z, y, z,
/// each `link` m above the last (the tool `tool` 0.1 m beyond the sixth), 1 kg boxes, and on
/// the last link a visual and collision mesh `package://faze4_description/meshes/saka.STL`
/// (one of the Faze4's built-in meshes, found on no disk here).
fn chain(name: &str, joint_names: [&str; 6], link: f64) -> String {
    let axes = ["0 0 1", "0 1 0", "0 1 0", "0 0 1", "0 1 0", "0 0 1"];
    let inertial =
        r#"<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>"#;
    let mut text = format!(r#"<robot name="{name}"><link name="base"/>"#);
    let mut parent = "base".to_string();
    for (i, (joint, axis)) in joint_names.iter().zip(axes).enumerate() {
        let child = format!("l{}", i + 1);
        let z = if i == 0 { 0.05 } else { link };
        text += &format!(
            r#"<joint name="{joint}" type="revolute"><parent link="{parent}"/><child link="{child}"/><origin xyz="0 0 {z}"/><axis xyz="{axis}"/><limit lower="-3" upper="3" effort="40" velocity="2"/></joint>"#
        );
        let mesh = match i {
            5 => {
                r#"<visual><geometry><mesh filename="package://faze4_description/meshes/saka.STL"/></geometry></visual><collision><geometry><mesh filename="package://faze4_description/meshes/saka.STL"/></geometry></collision>"#
            }
            _ => "",
        };
        text += &format!(r#"<link name="{child}">{inertial}{mesh}</link>"#);
        parent = child;
    }
    text += r#"<joint name="tool_joint" type="fixed"><parent link="l6"/><child link="tool"/><origin xyz="0 0 0.1"/></joint><link name="tool"/></robot>"#;
    text
}

const FAZE4_JOINTS: [&str; 6] = ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"];
const OWN_JOINTS: [&str; 6] = ["j1", "j2", "j3", "j4", "j5", "j6"];

fn write(dir: &Path, file: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(file);
    std::fs::write(&path, text).unwrap();
    path
}

fn read(path: &Path) -> Robot {
    Robot::from_urdf_file(path, &PackagePaths::default()).unwrap()
}

fn not_bundled(robot: &Robot) -> Vec<String> {
    (robot.warnings.iter())
        .filter(|w| matches!(w, LoadWarning::NotBundled { .. }))
        .map(ToString::to_string)
        .collect()
}

/// An arm of our own making named like the Faze4 (or with its joint names) gets none of its
/// facts, and a warning says so and what it gets; the Faze4's own files copied byte for byte
/// under another name keep them; one byte changed loses them.
#[test]
fn facts_follow_the_bundled_description_not_the_name() {
    let dir = temp_dir("arm-facts");
    for (name, joints, like) in [
        ("faze4_arm", OWN_JOINTS, "robot 'faze4_arm' is named like the Faze4"),
        ("faze4_real", FAZE4_JOINTS, "robot 'faze4_real' is named like the Faze4"),
        ("my_arm", FAZE4_JOINTS, "robot 'my_arm' has the Faze4's joint names"),
    ] {
        let robot = read(&write(&dir, &format!("{name}.urdf"), &chain(name, joints, 0.2)));
        assert_eq!(robot.model.defaults, ArmDefaults::default(), "{name}");
        assert!(!robot.geometry.built_in_meshes, "{name}");
        let said = not_bundled(&robot);
        assert_eq!(said.len(), 1, "{name}: {said:?}");
        assert!(
            said[0].contains(like) && said[0].contains("a board from its reach"),
            "{}",
            said[0]
        );
        // its torque limits are its own file's (40 N·m), not the Faze4's 7.9 … 6 N·m
        assert!(robot.model.joints.iter().all(|j| j.effort == Some(40.0)), "{name}");
    }
    let own = read(&write(&dir, "own.urdf", &chain("own", OWN_JOINTS, 0.2)));
    assert!(not_bundled(&own).is_empty(), "an arm like no other is told nothing");

    for file in ["urdf/faze4_arm.urdf", "urdf/faze4_real.urdf"] {
        let bytes = std::fs::read(repo_path(file)).unwrap();
        let copy = write(&dir, "renamed copy.urdf", std::str::from_utf8(&bytes).unwrap());
        let robot = read(&copy);
        assert_eq!(robot.model.defaults, defaults(), "{file}");
        assert!(
            robot.geometry.built_in_meshes && not_bundled(&robot).is_empty(),
            "{file}"
        );
        // the same file with one space more is another arm that happens to share the name
        let edited = String::from_utf8(bytes).unwrap().replacen("<robot ", "<robot  ", 1);
        let robot = read(&write(&dir, "edited.urdf", &edited));
        assert_eq!(robot.model.defaults, ArmDefaults::default(), "{file}");
        assert!(!robot.geometry.built_in_meshes, "{file}");
        assert_eq!(not_bundled(&robot).len(), 1, "{file}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The built-in Faze4 meshes stand in only for a bundled description's: another arm naming the
/// same `package://faze4_description/meshes/saka.STL` (found on no disk) has it found nowhere.
#[test]
fn built_in_meshes_belong_to_the_bundled_arm() {
    let dir = temp_dir("arm-facts-meshes");
    let robot = read(&write(&dir, "faze4_arm.urdf", &chain("faze4_arm", OWN_JOINTS, 0.2)));
    let sources = MeshSource::of(&robot.geometry);
    assert_eq!(sources.len(), 1);
    assert_eq!(sources[0].source, None, "{:?}", sources[0]);
    // the bundled arm's meshes are built in (no file on disk in the bundled robot)
    let bundled = MeshSource::of(&Robot::faze4().geometry);
    assert!(!bundled.is_empty() && bundled.iter().all(|m| m.source.as_deref() == Some("built-in")));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A board from an arm's reach: the chain's length R from its first joint (at its base) to the
/// tool, the board R·(0, −0.5, 0.45) from the base, 0.35·R wide, 0.88 times as tall; twice the
/// arm, twice the board about its base. The Faze4 keeps the original's board.
#[test]
fn a_board_follows_the_arms_reach() {
    let dir = temp_dir("arm-facts-board");
    for link in [0.2, 0.4] {
        let robot = read(&write(&dir, "own.urdf", &chain("own", OWN_JOINTS, link)));
        let tool = robot.model.frame_index("tool").unwrap();
        let (base, r) = shape::reach(&robot.model, tool);
        assert_eq!(base, Vec3::new(0.0, 0.0, 0.05));
        assert!((r - (5.0 * link + 0.1)).abs() < 1e-15, "{r}");
        let board = shape::board(&robot.model, tool);
        assert!((board.center - (base + Vec3::new(0.0, -0.5 * r, 0.45 * r))).norm() < 1e-15);
        assert!((board.width - 0.35 * r).abs() < 1e-15 && (board.height - 0.88 * board.width).abs() < 1e-15);
        // the shapes scale with the board: the circle's radius is 0.32 of its width
        let circle = Shape::Circle.targets(4, &board);
        assert!(((circle[0] - board.center).norm() - 0.32 * board.width).abs() < 1e-12);
    }
    let faze4 = Robot::faze4();
    assert_eq!(shape::board(&faze4.model, faze4.model.default_tool_frame()), BOARD);
    // the rule on the Faze4 (docs/model.md 4.3): R = 0.903 m, the board at (0.076, −0.664,
    // 0.457) m, 0.32 m wide; the Faze4 keeps the original's
    let mut bare = faze4.model.clone();
    bare.defaults = ArmDefaults::default();
    let tool = bare.default_tool_frame();
    let round = |x: f64, digits: i32| (x * 10f64.powi(digits)).round() / 10f64.powi(digits);
    assert_eq!(round(shape::reach(&bare, tool).1, 3), 0.903);
    let rule = shape::board(&bare, tool);
    let c = rule.center;
    assert_eq!((round(c.x, 3), round(c.y, 3), round(c.z, 3)), (0.076, -0.664, 0.457));
    assert_eq!(round(rule.width, 2), 0.32);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// On public arms (example-robot-data's UR5, Panda and SO-101, MuJoCo Menagerie's UR5e and
/// Panda, the SO-101's MJCF), each with its default tool frame, the three shapes are drawn on
/// the arm's own board at the default 240 samples: every target on the board's plane, inside it,
/// and reached by the IK (docs/model.md 4.3).
#[test]
fn public_arms_draw_their_shapes_on_their_own_boards() {
    for arm in [
        "tests/urdf/example_robot_data/ur5_robot.urdf",
        "tests/urdf/example_robot_data/panda.urdf",
        "tests/urdf/example_robot_data/so101.urdf",
        "tests/mjcf/menagerie/ur5e.xml",
        "tests/mjcf/menagerie/panda.xml",
        "tests/mjcf/so101/scene.xml",
    ] {
        let robot = read(&repo_path(arm));
        let tool: FrameId = robot.model.default_tool_frame();
        let board = shape::board(&robot.model, tool);
        assert_ne!(board, BOARD);
        for which in Shape::ALL {
            let planned = ShapeRun::plan(&robot.model, tool, which, 240, board, shape::PERIOD);
            let (_, run) = planned.unwrap_or_else(|e| panic!("{arm} {which:?}: {e}"));
            assert_eq!(run.board, board);
            assert!(
                run.ik_max_residual_m < 1e-9,
                "{arm} {which:?}: {}",
                run.ik_max_residual_m
            );
            for p in &run.reference {
                assert_eq!(p.y, board.center.y);
                assert!(
                    (p.x - board.center.x).abs() <= board.width / 2.0,
                    "{arm} {which:?} {p:?}"
                );
                assert!(
                    (p.z - board.center.z).abs() <= board.height / 2.0,
                    "{arm} {which:?} {p:?}"
                );
            }
        }
    }
}

/// Through the binary: a six-joint arm of our own making named `faze4_arm` runs with its own
/// file's torque limits, and says why on stderr.
#[test]
fn the_binary_says_what_an_arm_named_like_the_faze4_gets() {
    let dir = temp_dir("arm-facts-cli");
    write(&dir, "faze4_arm.urdf", &chain("faze4_arm", OWN_JOINTS, 0.2));
    let run = faze4(
        &dir,
        &[
            "wave",
            "--robot",
            "faze4_arm.urdf",
            "--duration",
            "0.05",
            "--no-collisions",
            "--summary",
            "s.json",
            "-q",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(
        run.stderr
            .contains("faze4_arm.urdf: robot 'faze4_arm' is named like the Faze4 but is not a byte-for-byte copy"),
        "{}",
        run.stderr
    );
    let summary = common::summary(&dir, "s.json");
    assert_eq!(common::vec_f64(&summary["effort"]), vec![40.0; 6]);
    std::fs::remove_dir_all(&dir).unwrap();
}
