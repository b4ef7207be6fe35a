//! Arms as people have them (issue 21): meshes in STL, COLLADA and OBJ (tests/urdf/mesh_arm_*,
//! written by tools/make_mesh_arms.py).

use crate::common;

use common::*;
use faze4::algo::{Data, forward_kinematics};
use faze4::geometry::{ClearanceGeometry, CollisionSet, GeometryData, PairFilter, Robot};
use faze4::model::PackagePaths;
use faze4::viz::scene::Scene;

fn mesh_arm(ext: &str) -> Robot {
    let packages = PackagePaths::new(vec![repo_path("tests/urdf")]);
    Robot::from_urdf_file(&repo_path(&format!("tests/urdf/mesh_arm_{ext}.urdf")), &packages).unwrap()
}

/// Per pair of links, the mesh distance at a few poses.
fn distances(robot: &Robot) -> Vec<f64> {
    let (set, warnings) = CollisionSet::new(
        &robot.model,
        &robot.geometry,
        ClearanceGeometry::Mesh,
        PairFilter::NonAdjacent,
    )
    .unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(set.unchecked().is_empty());
    let mut data = Data::new(&robot.model);
    let mut gdata = GeometryData::new(&set);
    let mut rng = Rng::new(21);
    let mut out = Vec::new();
    for _ in 0..6 {
        let q = rng.configuration(&robot.model);
        forward_kinematics(&robot.model, &mut data, &q);
        set.distances(&data.frame_pose, &mut gdata);
        out.extend(gdata.distances.iter().map(|d| d.distance));
    }
    out
}

#[test]
fn collada_and_obj_arms_are_the_stl_arm() {
    let stl = distances(&mesh_arm("stl"));
    assert_eq!(stl.len(), 6 * 3, "six poses, three pairs");
    // OBJ: the same f32 vertices as the STL, so the same distances bit for bit
    assert_eq!(distances(&mesh_arm("obj")), stl);
    // COLLADA: millimetres × <unit meter="0.001"> in f32 (and a Y_UP that ROS tools ignore)
    let dae = distances(&mesh_arm("dae"));
    let worst = max_abs_diff(&dae, &stl);
    assert!(worst < 1e-6, "COLLADA vs STL: {worst} m");
}

#[test]
fn the_views_use_the_files_colours_where_the_urdf_gives_none() {
    let colour = |ext: &str| {
        let robot = mesh_arm(ext);
        let scene = Scene::from_model(&robot.model, &robot.geometry);
        assert!(
            scene.missing.is_empty() && scene.unreadable.is_empty(),
            "{:?}",
            scene.unreadable
        );
        let upper = scene.visuals.iter().find(|v| v.name == "upper").unwrap();
        upper.color
    };
    // the generator's colour of 'upper' (COLLADA <diffuse>, OBJ .mtl Kd and d)
    assert_eq!(colour("dae"), [0.9, 0.5, 0.1, 1.0]);
    assert_eq!(colour("obj"), [0.9, 0.5, 0.1, 1.0]);
    // an STL has no material: the default colour
    assert_ne!(colour("stl"), [0.9, 0.5, 0.1, 1.0]);
}

/// Runs `faze4 wave` on `tests/urdf/<arm>.urdf` for 0.2 s, quiet, with `extra` options.
fn wave_quiet(arm: &str, extra: &[&str]) -> Run {
    let dir = temp_dir(&format!("any-arm-{arm}-{}", extra.len()));
    let urdf = repo_path(&format!("tests/urdf/{arm}.urdf"));
    let mut args = vec![
        "wave",
        "--urdf",
        urdf.to_str().unwrap(),
        "--duration",
        "0.2",
        "-q",
        "--trail",
        "none",
    ];
    args.extend(extra);
    let run = faze4(&dir, &args);
    std::fs::remove_dir_all(&dir).unwrap();
    run
}

#[test]
fn zero_mass_links_load_as_drake_and_pinocchio_load_them() {
    // a zero-mass base with rotational inertia welded to the world, a zero-mass link with
    // rotational inertia welded to a moving body, a 1e-9 kg dummy with zero inertia
    for arm in ["zero_mass_welded_arm", "dummy_leaf_arm"] {
        let run = wave_quiet(arm, &[]);
        assert!(run.status.success(), "{arm}: {}", run.stderr);
        assert_eq!(run.stderr, "", "{arm}: nothing to warn about");
    }
}

#[test]
fn a_transmission_on_a_fixed_joint_is_skipped_with_a_warning_even_when_quiet() {
    let run = wave_quiet("fixed_transmission_arm", &[]);
    assert!(run.status.success(), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    for part in [
        "warning",
        "transmission 'tool_trans' skipped",
        "joint 'tool_weld' is fixed",
    ] {
        assert!(lines[0].contains(part), "{part:?} in {}", lines[0]);
    }
}

#[test]
fn an_impossible_inertia_is_refused_or_balanced() {
    let dir = temp_dir("any-arm-inertia");
    let urdf = repo_path("tests/urdf/invalid_inertia_arm.urdf");
    refuses(
        &dir,
        &[
            "wave",
            "--urdf",
            urdf.to_str().unwrap(),
            "--duration",
            "0.2",
            "--trail",
            "none",
        ],
        &[
            "link 'hand' <inertial>",
            "triangle inequality",
            "5e-4",
            "--balance-inertia",
        ],
    );
    let run = wave_quiet("invalid_inertia_arm", &["--balance-inertia"]);
    assert!(run.status.success(), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    // (1e-4 + 1e-4 + 5e-4) / 3
    for part in [
        "warning",
        "link 'hand'",
        "set to their mean 2.333333333333333",
        "--balance-inertia",
    ] {
        assert!(lines[0].contains(part), "{part:?} in {}", lines[0]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_mesh_not_found_is_said_even_when_quiet_with_ros_advice() {
    // no --package-path: package://mesh_arms/... is found nowhere
    let run = wave_quiet("mesh_arm_stl", &[]);
    assert!(run.status.success(), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 4, "one per collision mesh: {}", run.stderr);
    for part in [
        "mesh 'package://mesh_arms/meshes/",
        "not found",
        "package 'mesh_arms'",
        "the folder that contains the package folder 'mesh_arms'",
    ] {
        assert!(lines[0].contains(part), "{part:?} in {}", lines[0]);
    }
}

#[test]
fn prismatic_joints_wave_in_metres_and_say_so() {
    // arm_prismatic's J2 'reach' slides in [-0.1, 0.2] m: by default a quarter of that, 0.075 m
    let dir = temp_dir("any-arm-prismatic");
    let urdf = repo_path("tests/urdf/arm_prismatic.urdf");
    let trail = dir.join("trail.csv");
    let run = faze4(
        &dir,
        &[
            "wave",
            "--urdf",
            urdf.to_str().unwrap(),
            "--duration",
            "0.2",
            "--trail",
            trail.to_str().unwrap(),
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(run.stdout.contains("start pose (deg | mm)"), "{}", run.stdout);
    let units = run.stdout.lines().find(|l| l.starts_with("unit of rad rows")).unwrap();
    assert_eq!(
        units.split_whitespace().skip(4).collect::<Vec<_>>(),
        ["rad", "m", "rad", "rad", "rad", "rad"]
    );
    // q2(0) = 0.075 sin(π/3)
    let (_, rows) = read_csv(&trail);
    let expected = 0.075 * std::f64::consts::FRAC_PI_3.sin();
    assert!((rows[0][5] - expected).abs() < 1e-12, "{} vs {expected}", rows[0][5]);
    std::fs::remove_file(&trail).unwrap();
    // too much: the error names the joint, its unit, what fits and the option
    refuses(
        &dir,
        &["wave", "--urdf", urdf.to_str().unwrap(), "--amp-m", "1"],
        &[
            "--amp-m",
            "J2 (reach)",
            " m at t = ",
            "[-0.1, 0.2] m",
            "at most 0.1 m fits",
        ],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_wave_about_an_illegal_zero_pose_points_to_center_mid() {
    let dir = temp_dir("any-arm-mid");
    let text = std::fs::read_to_string(repo_path("tests/urdf/dummy_leaf_arm.urdf")).unwrap();
    // j2 limited to [0.2, 1.8] rad: the zero pose is outside
    let urdf = dir.join("offset.urdf");
    std::fs::write(
        &urdf,
        text.replace(
            r#"lower="-2" upper="2" effort="20""#,
            r#"lower="0.2" upper="1.8" effort="20""#,
        ),
    )
    .unwrap();
    refuses(
        &dir,
        &["wave", "--urdf", urdf.to_str().unwrap(), "--amp-deg", "10"],
        &[
            "--amp-deg",
            "J2 (j2)",
            "rad",
            "[0.2, 1.8] rad",
            "centre 0 rad is itself outside them",
            "--center mid",
        ],
    );
    let run = faze4(
        &dir,
        &[
            "wave",
            "--urdf",
            urdf.to_str().unwrap(),
            "--amp-deg",
            "10",
            "--center",
            "mid",
            "--duration",
            "0.2",
            "--trail",
            "none",
            "-q",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Each arm of tools/oracle/any_arm_fixtures.py: faze4's closed loop equals Pinocchio's run
/// with faze4's gains (pin_closed_loop.py) to 1e-9 (m for the tool, rad or m for the joints).
#[test]
fn the_arms_agree_with_pinocchio_closed_loop() {
    let dir = temp_dir("any-arm-pin");
    for arm in [
        "zero_mass_welded_arm",
        "dummy_leaf_arm",
        "fixed_transmission_arm",
        "invalid_inertia_arm",
        "mesh_arm_dae",
        "mesh_arm_obj",
        "arm_prismatic",
    ] {
        let fx = fixture(&format!("any_arm_{arm}.json"));
        let mut args: Vec<String> = (fx["faze4_args"].as_array().unwrap().iter())
            .map(|a| a.as_str().unwrap().to_string())
            .collect();
        // paths in the fixture are relative to the repository
        for a in args.iter_mut() {
            if a.starts_with("tests/urdf") {
                *a = repo_path(a).to_str().unwrap().to_string();
            }
        }
        let trail = dir.join(format!("{arm}.csv"));
        args.extend(["-q", "--trail", trail.to_str().unwrap()].map(String::from));
        let run = faze4(&dir, &args.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(run.status.success(), "{arm}: {}", run.stderr);
        let (header, rows) = read_csv(&trail);
        let expected = mat_f64(&fx["trail"]["rows"]);
        assert_eq!(rows.len(), expected.len(), "{arm}: rows");
        assert_eq!(header.len(), expected[0].len(), "{arm}: columns");
        let worst = rows
            .iter()
            .zip(&expected)
            .map(|(a, b)| max_abs_diff(a, b))
            .fold(0.0, f64::max);
        assert!(worst <= 1e-9, "{arm}: faze4 vs Pinocchio {worst:e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The `--summary` JSON of `faze4 ARGS --duration 0.05 -q --trail none` (it must succeed).
fn summary_of(name: &str, args: &[&str]) -> serde_json::Value {
    let dir = temp_dir(&format!("any-arm-summary-{name}"));
    let summary = dir.join("s.json");
    let mut all = args.to_vec();
    all.extend([
        "--duration",
        "0.05",
        "-q",
        "--trail",
        "none",
        "--summary",
        summary.to_str().unwrap(),
    ]);
    let run = faze4(&dir, &all);
    assert!(run.status.success(), "{name}: {}", run.stderr);
    let value = serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    value
}

/// The summary's `joints` as (name, unit) pairs.
fn joints_of(summary: &serde_json::Value) -> Vec<(String, String)> {
    (summary["joints"].as_array().unwrap().iter())
        .map(|j| (j["name"].as_str().unwrap().into(), j["unit"].as_str().unwrap().into()))
        .collect()
}

/// The summary's `meshes` as (link, uri, source) triples.
fn meshes_of(summary: &serde_json::Value) -> Vec<(String, String, Option<String>)> {
    (summary["meshes"].as_array().unwrap().iter())
        .map(|m| {
            (
                m["link"].as_str().unwrap().into(),
                m["uri"].as_str().unwrap().into(),
                m["source"].as_str().map(String::from),
            )
        })
        .collect()
}

#[test]
fn the_summary_says_what_was_simulated_on_the_default_arm() {
    let s = summary_of("faze4", &["wave"]);
    // urdf/faze4_arm.urdf's <robot name> and its six revolute joints in DOF order
    assert_eq!(s["robot"], "faze4_arm");
    let names = ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"];
    let expected: Vec<(String, String)> = names.iter().map(|n| (n.to_string(), "rad".into())).collect();
    assert_eq!(joints_of(&s), expected);
    assert_eq!(
        s["joints"].as_array().unwrap().len(),
        s["dof"].as_u64().unwrap() as usize
    );
    assert_eq!(
        (&s["tool_link"], &s["tool_choice"]),
        (&"tool_link".into(), &"named_tool_link".into())
    );
    // the real arm's collision meshes, one per moving link, from the copies built into the binary
    let meshes = meshes_of(&s);
    let expected: Vec<_> = (names.iter())
        .map(|n| {
            let uri = format!("package://faze4_description/meshes/{n}.STL");
            (n.to_string(), uri, Some("built-in".to_string()))
        })
        .collect();
    assert_eq!(meshes, expected);
    assert!(s["clearance"].is_object());

    // another tool is `given`; without clearance the meshes are still listed, and no clearance
    let s = summary_of("faze4-saka", &["wave", "--tool-link", "saka", "--no-collisions"]);
    assert_eq!((&s["tool_link"], &s["tool_choice"]), (&"saka".into(), &"given".into()));
    assert_eq!(meshes_of(&s), expected);
    assert!(s.get("clearance").is_none(), "{s}");
}

#[test]
fn the_summary_names_the_leading_joints_with_their_units_and_the_default_tool_rule() {
    // mimic_gripper_arm: the revolute `wrist_follow` and the prismatic `finger_right` follow
    let urdf = repo_path("tests/urdf/mimic_gripper_arm.urdf");
    let s = summary_of("mimic", &["wave", "--urdf", urdf.to_str().unwrap(), "--center", "mid"]);
    assert_eq!(s["robot"], "mimic_gripper_arm");
    let joints = joints_of(&s);
    let pairs: Vec<(&str, &str)> = joints.iter().map(|(n, u)| (n.as_str(), u.as_str())).collect();
    assert_eq!(
        pairs,
        [
            ("shoulder_yaw", "rad"),
            ("shoulder_pitch", "rad"),
            ("elbow", "rad"),
            ("finger_left", "m")
        ]
    );
    assert_eq!(s["max_speed"].as_array().unwrap().len(), joints.len());
    assert_eq!(
        (&s["tool_link"], &s["tool_choice"]),
        (&"tool_link".into(), &"named_tool_link".into())
    );
    assert_eq!(s["meshes"], serde_json::json!([]), "no collision mesh");

    // a chain without tool_link: its last link; a branched tree: the deepest common ancestor
    let urdf = repo_path("tests/urdf/arm_prismatic.urdf");
    let s = summary_of("prismatic", &["wave", "--urdf", urdf.to_str().unwrap()]);
    let units: Vec<String> = joints_of(&s).into_iter().map(|(_, u)| u).collect();
    assert_eq!(units, ["rad", "m", "rad", "rad", "rad", "rad"]);
    assert_eq!(s["tool_choice"], "last_link");
    let urdf = repo_path("tests/urdf/tree_arm.urdf");
    let s = summary_of("tree", &["wave", "--urdf", urdf.to_str().unwrap(), "--center", "mid"]);
    assert_eq!(
        (&s["tool_link"], &s["tool_choice"]),
        (&"chest".into(), &"deepest_common_ancestor".into())
    );
}

#[test]
fn the_summary_says_where_each_mesh_came_from() {
    // mesh_arm_stl with the upper arm's collision mesh renamed to a file that does not exist
    let dir = temp_dir("any-arm-mesh-sources");
    let text = std::fs::read_to_string(repo_path("tests/urdf/mesh_arm_stl.urdf")).unwrap();
    let collision = r#"<collision><geometry><mesh filename="package://mesh_arms/meshes/upper.stl"/>"#;
    assert!(text.contains(collision));
    let text = text.replace(collision, &collision.replace("upper.stl", "missing.stl"));
    let urdf = dir.join("arm.urdf");
    std::fs::write(&urdf, text).unwrap();
    let packages = repo_path("tests/urdf");
    let s = summary_of(
        "mesh-sources",
        &[
            "wave",
            "--urdf",
            urdf.to_str().unwrap(),
            "--package-path",
            packages.to_str().unwrap(),
        ],
    );
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(s["robot"], "mesh_arm_stl");
    let file = |name: &str| {
        Some(
            packages
                .join("mesh_arms/meshes")
                .join(name)
                .to_str()
                .unwrap()
                .to_string(),
        )
    };
    let uri = |name: &str| format!("package://mesh_arms/meshes/{name}");
    let expected = vec![
        ("base".to_string(), uri("base.stl"), file("base.stl")),
        ("upper".to_string(), uri("missing.stl"), None),
        ("forearm".to_string(), uri("forearm.stl"), file("forearm.stl")),
        ("hand".to_string(), uri("base.stl"), file("base.stl")),
    ];
    assert_eq!(meshes_of(&s), expected);
    // the files exist, and the missing mesh's link is the one the clearance left out
    for (_, _, source) in &expected {
        if let Some(path) = source {
            assert!(std::path::Path::new(path).is_file(), "{path}");
        }
    }
    assert_eq!(s["clearance"]["unchecked"], serde_json::json!(["upper"]));
}
