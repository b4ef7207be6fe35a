//! Arms as people have them (issue 21): meshes in STL, COLLADA and OBJ (tests/urdf/mesh_arm_*,
//! written by tools/make_mesh_arms.py).

mod common;

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
