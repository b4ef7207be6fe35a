//! MJCF models against MuJoCo (fixtures by tools/oracle/mjcf_fixtures.py, the `mujoco` package):
//! TheRobotStudio's SO-101, Menagerie's UR5e and Panda, and tests/mjcf/feature_arm.xml (ours,
//! every construct faze4 reads). The coordinates, limits, damping, effort limits, armature and
//! home pose; M (armature included) and C v + g at random states to 1e-12 relative; what the
//! reading mapped and left out; the models and constructs it refuses.

use crate::common;

use common::*;
use faze4::algo::{Data, compute_all_terms};
use faze4::model::{Model, RobotFormat, mjcf};
use serde_json::Value;
use std::path::Path;

const MODELS: [&str; 4] = ["so101", "ur5e", "panda", "feature_arm"];
const TOL: f64 = 1e-12;

fn model_of(fx: &Value) -> Model {
    mjcf::read_file(&repo_path(fx["model"].as_str().unwrap())).unwrap()
}

/// A fixture's list of numbers, `null` as `none`.
fn or_inf(v: &Value, none: f64) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap_or(none))
        .collect()
}

fn relative(ours: &[f64], theirs: &[f64]) -> f64 {
    max_abs_diff(ours, theirs) / max_abs(theirs).max(f64::MIN_POSITIVE)
}

#[test]
fn coordinates_limits_damping_effort_armature_and_home_are_mujocos() {
    for name in MODELS {
        let fx = fixture(&format!("mjcf_{name}.json"));
        let model = model_of(&fx);
        let names: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
        let theirs: Vec<&str> = fx["coordinates"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect();
        assert_eq!(names, theirs, "{name}: coordinates");
        let lower: Vec<f64> = model.joints.iter().map(|j| j.lower).collect();
        let upper: Vec<f64> = model.joints.iter().map(|j| j.upper).collect();
        let n = names.len();
        for (what, ours, theirs) in [
            ("lower", lower, or_inf(&fx["lower"], f64::NEG_INFINITY)),
            ("upper", upper, or_inf(&fx["upper"], f64::INFINITY)),
        ] {
            for (a, b) in ours.iter().zip(&theirs) {
                assert!(
                    a == b || (a - b).abs() <= 1e-15 * b.abs(),
                    "{name}: {what} {ours:?} vs {theirs:?}"
                );
            }
        }
        let diag = |key: &str| (0..n).map(|i| fx[key][i][i].as_f64().unwrap()).collect::<Vec<_>>();
        let damping: Vec<f64> = model.damping().collect();
        assert!(
            relative(&damping, &diag("damping")) <= TOL,
            "{name}: damping {damping:?}"
        );
        let armature: Vec<f64> = model.joints.iter().map(|j| j.reflected_inertia()).collect();
        assert!(
            relative(&armature, &diag("armature")) <= TOL,
            "{name}: armature {armature:?}"
        );
        let effort: Vec<f64> = model.joints.iter().map(|j| j.effort.unwrap_or(f64::INFINITY)).collect();
        assert_eq!(effort, or_inf(&fx["effort"], f64::INFINITY), "{name}: effort");
        match &fx["home"] {
            Value::Null => assert_eq!(model.home, None, "{name}: home"),
            home => assert_eq!(model.home.as_deref(), Some(&vec_f64(home)[..]), "{name}: home"),
        }
    }
}

#[test]
fn mass_matrix_and_bias_equal_mujocos_at_random_states() {
    for name in MODELS {
        let fx = fixture(&format!("mjcf_{name}.json"));
        let model = model_of(&fx);
        let mut data = Data::new(&model);
        let (mut worst_m, mut worst_b) = (0.0f64, 0.0f64);
        for state in fx["states"].as_array().unwrap() {
            compute_all_terms(&model, &mut data, &vec_f64(&state["q"]), &vec_f64(&state["v"]));
            let theirs: Vec<f64> = mat_f64(&state["m"]).concat();
            let ours: Vec<f64> = (0..model.dof())
                .flat_map(|r| (0..model.dof()).map(move |c| (r, c)))
                .map(|(r, c)| data.m[(r, c)])
                .collect();
            worst_m = worst_m.max(relative(&ours, &theirs));
            worst_b = worst_b.max(relative(data.bias.as_slice(), &vec_f64(&state["bias"])));
        }
        eprintln!("{name}: M {worst_m:.1e}, C v + g {worst_b:.1e} (relative, worst of 8 states)");
        assert!(
            worst_m <= TOL,
            "{name}: M differs from MuJoCo's by {worst_m:e} relative"
        );
        assert!(
            worst_b <= TOL,
            "{name}: C v + g differs from MuJoCo's by {worst_b:e} relative"
        );
    }
}

/// Runs the fixture's closed-loop wave (`cl`: its `args`) on MJCF model `model` as the binary,
/// in `dir`: the run, its trail's rows in the fixture's columns, its summary.
fn wave(dir: &Path, model: &str, cl: &Value) -> (Run, Vec<Vec<f64>>, Value) {
    let a = &cl["args"];
    let num = |k: &str| a[k].as_f64().unwrap().to_string();
    let run = faze4(
        dir,
        &[
            "wave",
            "--robot",
            model,
            "--center",
            "mid",
            "--amp-deg",
            &num("amp_deg"),
            "--amp-m",
            &num("amp_m"),
            "--freq",
            &num("freq"),
            "--duration",
            &num("duration"),
            "--dt",
            &num("dt"),
            "--record-period",
            &num("record_period"),
            "--tool-link",
            a["tool_link"].as_str().unwrap(),
            "--no-collisions",
            "--trail",
            "trail.csv",
            "--summary",
            "summary.json",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    let rows = fixture_trail(dir, cl);
    let ours = summary(dir, "summary.json");
    (run, rows, ours)
}

/// The largest difference between a trail and a fixture's (tool xyz in m, q in rad or m), the
/// sample times equal.
fn trail_difference(rows: &[Vec<f64>], cl: &Value) -> f64 {
    let theirs = mat_f64(&cl["trail"]["rows"]);
    assert_eq!(rows.len(), theirs.len());
    let mut worst = 0.0f64;
    for (r, p) in rows.iter().zip(&theirs) {
        assert_eq!(r[0], p[0], "sample times");
        worst = worst.max(max_abs_diff(&r[1..], &p[1..]));
    }
    worst
}

/// The fixture's wave on an MJCF model, run as the binary: the trail within 1e-9 of MuJoCo's
/// dynamics stepped as docs/model.md steps (frictionloss as faze4's joint Coulomb friction on
/// both sides), the gains tuned from the same inertia and effort limits, the same errors and
/// saturation. Where two coupled joints stick together, faze4's joint-alone stopping torque
/// chatters and amplifies rounding (docs/model.md §2.3): there the tolerance is ten times the
/// trail's change the oracle measured when M changes by one rounding (`rounding_sensitivity`:
/// 6e-17 on the SO-101, 5.0e-8 on the feature arm, 2.0e-5 on the friction arm).
#[test]
fn closed_loop_wave_matches_mujocos_dynamics() {
    for name in ["so101", "feature_arm", "friction_arm"] {
        let fx = fixture(&format!("mjcf_{name}.json"));
        let cl = &fx["closed_loop"];
        let dir = temp_dir(&format!("mjcf-wave-{name}"));
        let model = repo_path(fx["model"].as_str().unwrap()).display().to_string();
        let (run, rows, ours) = wave(&dir, &model, cl);
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(
            run.stdout.contains("frictionloss → joint Coulomb friction") && !run.stderr.contains("frictionloss"),
            "{name}: the friction is mapped, not warned: {}{}",
            run.stdout,
            run.stderr
        );
        let tol = (10.0 * cl["rounding_sensitivity"].as_f64().unwrap()).max(1e-9);
        let worst = trail_difference(&rows, cl);
        eprintln!("{name} wave: trail worst difference {worst:.1e} (tolerance {tol:.0e})");
        assert!(worst <= tol, "{name}: trail differs from MuJoCo's by {worst:e}");
        let mj = &cl["summary"];
        assert_eq!(ours["steps"], mj["steps"]);
        for key in ["effective_inertia", "kp", "kd", "effort"] {
            let e = relative(&vec_f64(&ours[key]), &vec_f64(&mj[key]));
            assert!(e < 1e-12, "{name}: {key} differs (relative {e:e})");
        }
        let e = max_abs_diff(
            &vec_f64(&ours["max_tracking_error_rad"]),
            &vec_f64(&mj["max_tracking_error_rad"]),
        );
        assert!(e < tol, "{name}: max tracking error differs by {e:e}");
        assert_eq!(ours["saturation_pct"], mj["saturation_pct"]);
        // the format and the source once each, in the summary and the banner
        assert_eq!(ours["format"], "mjcf");
        assert_eq!(ours["robot_source"], model.as_str());
        assert!(
            run.stdout.contains(&format!("(mjcf {model})")),
            "{name}: {}",
            run.stdout
        );
        assert!(
            run.stdout.contains("\n[faze4] mapped from mjcf: "),
            "{name}: {}",
            run.stdout
        );
    }
}

/// The trail's tolerance against MuJoCo's own step (`mj_step`, its constraint solver) with
/// frictionloss, per model: (as the file writes it, MuJoCo's soft defaults; with MuJoCo's
/// friction made as hard as it goes). faze4's friction is the clamped torque that stops the joint
/// within one step; MuJoCo's a soft constraint that, while a joint sticks, lets 1 − d = 10 % of
/// its unconstrained acceleration through and pulls its speed to 0 over solref's 0.02 s. Measured
/// by the oracle on its own (the fixture's `friction_models_difference`, MuJoCo's step against
/// docs/model.md's step with faze4's friction; 3.8e-4 and 7.8e-8 on the SO-101, 5.9e-3 and
/// 4.5e-4 on the friction arm) and rounded up; hard, the friction arm keeps 4.5e-4: faze4 stops
/// each joint alone, MuJoCo solves the joints' frictions together through M. Without friction
/// MuJoCo's step and faze4's agree to 6e-17 (`integrators_difference`). docs/robots.md.
const FRICTION_TOL: [(&str, f64, f64); 2] = [("so101", 5e-4, 1e-6), ("friction_arm", 8e-3, 1e-3)];

/// MJCF's frictionloss against MuJoCo's own step: the SO-101's (TheRobotStudio's values) and
/// our friction arm's (a yaw that sticks and slips) closed loops within [`FRICTION_TOL`] of
/// MuJoCo's, as written and hard; with the frictionloss removed from the file, the same run
/// differs from MuJoCo's by more than the tolerance as written and by ten times it hard.
#[test]
fn frictionloss_follows_mujocos_own_step_within_the_friction_models_difference() {
    for (name, as_written, hard) in FRICTION_TOL {
        let fx = fixture(&format!("mjcf_{name}.json"));
        let mj = &fx["mujoco_step"];
        let integrators = mj["integrators_difference"].as_f64().unwrap();
        assert!(integrators < 1e-12, "{name}: without friction {integrators:e}");
        let path = repo_path(fx["model"].as_str().unwrap());
        let dir = temp_dir(&format!("mjcf-friction-{name}"));
        let (_, rows, _) = wave(&dir, &path.display().to_string(), &mj["as_written"]);
        // the same file without its frictionloss, beside it in the temporary folder
        let text = std::fs::read_to_string(&path).unwrap();
        let stripped = text.replace("frictionloss=\"", "frictionloss=\"0\" was=\"");
        assert_ne!(stripped, text);
        std::fs::write(dir.join("no_friction.xml"), stripped).unwrap();
        let (free_run, free_rows, _) = wave(&dir, "no_friction.xml", &mj["as_written"]);
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(!free_run.stdout.contains("frictionloss"), "{}", free_run.stdout);
        for (key, tol, margin) in [("as_written", as_written, 1.0), ("hard", hard, 10.0)] {
            let cl = &mj[key];
            let measured = cl["friction_models_difference"].as_f64().unwrap();
            let ours = trail_difference(&rows, cl);
            let without = trail_difference(&free_rows, cl);
            eprintln!(
                "{name} frictionloss, MuJoCo {key}: faze4 {ours:.1e} (the oracle's {measured:.1e}, tolerance {tol:.0e}); without friction {without:.1e}"
            );
            assert!(measured <= tol, "{name} {key}: the models differ by {measured:e} now");
            assert!(
                ours <= tol,
                "{name} {key}: faze4 differs from MuJoCo by {ours:e} > {tol:e}"
            );
            assert!(
                without > margin * tol,
                "{name} {key}: without friction only {without:e} from MuJoCo: the test could not fail"
            );
        }
    }
}

/// `--xacro-arg` is for a xacro file: given with an MJCF model it is refused naming the flag
/// (not silently dropped), and the old name `--urdf` reads an MJCF model as `--robot` does.
#[test]
fn an_mjcf_model_takes_no_xacro_arguments() {
    let dir = temp_dir("mjcf-xacro-arg");
    let model = repo_path("tests/mjcf/feature_arm.xml").display().to_string();
    let refused = faze4(
        &dir,
        &["wave", "--robot", &model, "--xacro-arg", "a:=1", "--trail", "none"],
    );
    assert_eq!(refused.status.code(), Some(2), "{}", refused.stderr);
    assert!(
        refused.stderr.contains(&format!(
            "--xacro-arg: {model} is an MJCF file, not a xacro file: it takes no xacro arguments"
        )),
        "{}",
        refused.stderr
    );
    let old_name = faze4(
        &dir,
        &[
            "wave",
            "--urdf",
            &model,
            "--center",
            "mid",
            "--duration",
            "0.01",
            "--trail",
            "none",
        ],
    );
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(old_name.status.success(), "{}", old_name.stderr);
    assert!(
        old_name.stdout.contains(&format!("(mjcf {model})")),
        "{}",
        old_name.stdout
    );
}

/// The feature arm as faze4 reads it beyond its dynamics: what was mapped and left out, its
/// shapes (meshes found under `meshdir`, a capsule as the cylinder around it, the visual class
/// drawn and not checked), its site and hinge-axis frames.
#[test]
fn the_feature_arm_maps_and_leaves_out_what_it_says() {
    use faze4::geometry::Robot;
    use faze4::model::{Geometry, PackagePaths};
    let path = repo_path("tests/mjcf/feature_arm.xml");
    let robot = Robot::from_urdf_file(&path, &PackagePaths::default()).unwrap();
    let mapped = |from: &str| {
        let m = robot.model.mapped.iter().find(|m| m.from == from);
        m.unwrap_or_else(|| panic!("{from} not in {:?}", robot.model.mapped))
    };
    assert_eq!(mapped("world geom").items, ["floor"]);
    let friction = mapped("frictionloss");
    assert!(!friction.changes_dynamics && friction.items.len() == 6, "{friction:?}");
    assert_eq!(friction.to, "joint Coulomb friction");
    // the big class's 0.2 on every joint; finger_b's reaches finger_a through the mimic, |1|·0.2
    let f: Vec<f64> = robot.model.joints.iter().map(|j| j.friction).collect();
    assert_eq!(f, [0.2, 0.2, 0.2, 0.2, 0.4]);
    assert_eq!(mapped("armature").items.len(), 6);
    assert_eq!(mapped("equality joint").items, ["finger_b"]);
    assert_eq!(mapped("motor ctrlrange").items, ["yaw", "extend"]);
    assert!(!mapped("armature").changes_dynamics);
    assert_eq!(robot.model.format, "mjcf");
    assert!(
        !robot.warnings.iter().any(|w| w.to_string().contains("frictionloss")),
        "{:?}",
        robot.warnings
    );
    // the site and the hinge away from its body's origin are frames
    for frame in ["world", "base", "tool", "upper", "upper:shoulder"] {
        assert!(robot.model.frame_index(frame).is_some(), "frame {frame}");
    }
    let g = &robot.geometry;
    let meshes: Vec<(&str, &Geometry)> = g.visuals.iter().map(|v| (v.link.as_str(), &v.geometry)).collect();
    let Some((_, Geometry::Mesh { uri, path, .. })) = meshes.iter().find(|(l, _)| *l == "base") else {
        panic!("no base mesh in {meshes:?}")
    };
    assert_eq!(uri, "../urdf/mesh_arms/meshes/base.stl");
    assert!(path.as_ref().is_some_and(|p| p.is_file()), "{path:?}");
    // the class's rgba, not MuJoCo's grey, takes precedence over the material (as MuJoCo says)
    let colour = g.visuals.iter().find(|v| v.link == "base").unwrap().rgba;
    assert_eq!(colour, Some([0.7, 0.7, 0.7, 1.0]));
    // without an rgba of its own or its class's, a geom takes its material's (the SO-101's yellow)
    let so101 = Robot::from_urdf_file(&repo_path("tests/mjcf/so101/scene.xml"), &PackagePaths::default()).unwrap();
    assert_eq!(so101.geometry.visuals[0].rgba, Some([1.0, 0.82, 0.12, 1.0]));
    let capsule = Geometry::Capsule {
        radius: 0.03,
        length: (0.01f64.powi(2) + 0.09).sqrt(),
    };
    assert!(g.collisions.iter().any(|c| c.geometry == capsule), "the fromto capsule");
    // visual-class meshes are drawn, not checked; the collision class is checked, not drawn
    assert!(!g.collisions.iter().any(|c| matches!(c.geometry, Geometry::Mesh { .. })));
    assert_eq!(g.visuals.iter().filter(|v| v.link == "slider").count(), 0);
    assert_eq!(g.collisions.iter().filter(|c| c.link == "slider").count(), 1);
}

/// Each construct faze4 does not simulate, and each malformed one, is refused naming it.
#[test]
fn what_faze4_cannot_simulate_is_refused_naming_it() {
    let body = |inside: &str| {
        format!(
            "<mujoco><worldbody><body name=\"b\"><inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"1 1 1\"/>{inside}</body></worldbody></mujoco>"
        )
    };
    let cases: Vec<(String, Vec<&str>)> = vec![
        (body("<freejoint/>"), vec!["<freejoint>", "body 'b'", "floating base"]),
        (body("<joint type=\"free\"/>"), vec!["body 'b'", "floating base"]),
        (body("<joint type=\"ball\"/>"), vec!["type=\"ball\"", "hinge and slide"]),
        (body("<joint name=\"a\"/><joint name=\"c\"/>"), vec!["<body name=\"b\">", "has 2 joints"]),
        (body("<joint class=\"nope\"/>"), vec!["names class 'nope'"]),
        (body("<joint range=\"0 1\" limited=\"true\" axis=\"0 0 x\"/>"), vec!["axis=\"0 0 x\"", "'x' is not a number"]),
        (body("<joint limited=\"true\"/>"), vec!["limited but gives no range"]),
        (body("<geom size=\"0.1\" quat=\"1 0 0 0\" euler=\"0 0 1\"/>"), vec!["gives 2 orientations"]),
        (
            "<mujoco><asset><mesh file=\"m.stl\"/></asset><worldbody><body name=\"b\"><joint/><geom type=\"mesh\" mesh=\"m\"/></body></worldbody></mujoco>".into(),
            vec!["body 'b' has no <inertial>", "mesh"],
        ),
        (
            "<mujoco><worldbody><body name=\"b\"><joint/></body></worldbody></mujoco>".into(),
            vec!["link 'b'", "has no mass"],
        ),
        (
            format!("{}<equality><connect body1=\"b\" anchor=\"0 0 0\"/></equality></mujoco>", body("<joint/>").trim_end_matches("</mujoco>")),
            vec!["<equality connect>", "not simulated"],
        ),
        (
            format!(
                "{}<equality><joint joint1=\"j\" joint2=\"k\" polycoef=\"0 1 0.5 0 0\"/></equality></mujoco>",
                body("<joint name=\"j\"/><body name=\"c\"><inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"1 1 1\"/><joint name=\"k\"/></body>").trim_end_matches("</mujoco>")
            ),
            vec!["degree 2"],
        ),
        (
            format!("{}<keyframe><key name=\"home\" qpos=\"0 1\"/></keyframe></mujoco>", body("<joint/>").trim_end_matches("</mujoco>")),
            vec!["<key name=\"home\">", "qpos has 2 numbers for the model's 1"],
        ),
        (
            format!("{}<actuator><motor joint=\"nowhere\"/></actuator></mujoco>", body("<joint/>").trim_end_matches("</mujoco>")),
            vec!["joint 'nowhere'", "not a moving joint"],
        ),
        ("<mujoco><compiler boundmass=\"0.1\"/></mujoco>".into(), vec!["<compiler>", "boundmass"]),
        ("<mujoco><compiler angle=\"grad\"/></mujoco>".into(), vec!["angle=\"grad\""]),
        ("<robot name=\"r\"/>".into(), vec!["root element is <robot>", "no MJCF model"]),
        ("<mujoco><worldbody>".into(), vec!["t.xml"]),
        ("".into(), vec!["t.xml", "empty"]),
    ];
    for (xml, parts) in cases {
        let e = mjcf::describe_str(&xml, "t.xml", None)
            .and_then(|d| Model::from_description(&d))
            .expect_err(&xml)
            .to_string();
        assert!(e.starts_with("t.xml"), "{e}");
        for part in parts {
            assert!(e.contains(part), "{xml}\n  gave: {e}\n  without: {part}");
        }
        assert!(!e.contains('\n'), "one line: {e}");
    }
}

/// `<include>`: files are found beside the main file, a missing one is named, a file that
/// includes itself stops.
#[test]
fn includes_are_read_beside_the_model_and_a_cycle_stops() {
    let dir = temp_dir("mjcf-include");
    let write = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
    write("arm.xml", "<mujoco model=\"a\"><include file=\"parts.xml\"/></mujoco>");
    write(
        "parts.xml",
        "<mujoco><worldbody><body name=\"b\"><joint/><geom size=\"0.1\"/></body></worldbody></mujoco>",
    );
    write("loop.xml", "<mujoco><include file=\"loop.xml\"/></mujoco>");
    write("missing.xml", "<mujoco><include file=\"nowhere.xml\"/></mujoco>");
    let model = mjcf::read_file(&dir.join("arm.xml")).unwrap();
    assert_eq!(
        model.joints[0].name, "joint0",
        "an unnamed joint is named by its MuJoCo id"
    );
    // a 0.1 m sphere of water: 4.19 kg, as MuJoCo weighs it
    assert!((model.inertia[0].mass - 4.0 / 3.0 * std::f64::consts::PI * 1e-3 * 1000.0).abs() < 1e-12);
    let e = mjcf::read_file(&dir.join("loop.xml")).unwrap_err().to_string();
    assert!(e.contains("includes nest more than 8 deep"), "{e}");
    let e = mjcf::read_file(&dir.join("missing.xml")).unwrap_err().to_string();
    assert!(e.contains("nowhere.xml"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_root_element_tells_mjcf() {
    let mjcf = |text: &str| RobotFormat::detect(Path::new("a.urdf"), text) == RobotFormat::Mjcf;
    assert!(mjcf("<?xml version=\"1.0\"?>\n<!-- an arm -->\n<mujoco model=\"m\">"));
    assert!(mjcf("\u{feff}<mujoco>"));
    assert!(mjcf("<!DOCTYPE mujoco>\n<mujoco/>"));
    assert!(!mjcf("<robot name=\"r\"><!-- <mujoco> --></robot>"));
    assert!(!mjcf("<mujocoo/>"));
    assert!(!mjcf(""));
}

/// A capsule is a capsule in the clearance, not the cylinder around it: two capsules whose
/// distance is the same in every pose (tests/mjcf/capsule_pair.xml) measured by a run.
#[test]
fn capsules_are_measured_as_capsules() {
    let dir = temp_dir("mjcf-capsules");
    let model = repo_path("tests/mjcf/capsule_pair.xml").display().to_string();
    let run = faze4(
        &dir,
        &[
            "wave",
            "--urdf",
            &model,
            "--duration",
            "0.2",
            "--trail",
            "none",
            "--summary",
            "s.json",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    let s = summary(&dir, "s.json");
    std::fs::remove_dir_all(&dir).unwrap();
    let pairs = s["clearance"]["pairs"].as_array().unwrap();
    assert_eq!(pairs.len(), 1, "{pairs:?}");
    let expected = (0.03f64.powi(2) + 0.1f64.powi(2)).sqrt() - 0.04;
    let d = pairs[0]["min_m"].as_f64().unwrap();
    // GJK's distance to within 0.01 mm; the cylinders around the capsules would be 4.4 mm nearer
    assert!(
        (d - expected).abs() < 1e-5,
        "capsule distance {d} m, expected {expected} m"
    );
}

/// The caps of docs/development.md hold for MJCF: nesting is refused before the parser, and so
/// are more bodies than faze4 reads.
#[test]
fn nesting_and_body_counts_are_capped() {
    let deep = format!(
        "<mujoco><worldbody>{}{}</worldbody></mujoco>",
        "<body>".repeat(20_000),
        "</body>".repeat(20_000)
    );
    let e = mjcf::describe_str(&deep, "deep.xml", None).unwrap_err().to_string();
    assert!(e.contains("nest more than 400 deep"), "{e}");
    let body = "<body><inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"1 1 1\"/></body>";
    let wide = format!("<mujoco><worldbody>{}</worldbody></mujoco>", body.repeat(5000));
    let e = mjcf::describe_str(&wide, "wide.xml", None).unwrap_err().to_string();
    assert!(e.contains("more than the 4096 faze4 reads"), "{e}");
}

/// The notes that name an option (`<option gravity>` not simulated, the `home` keyframe as the
/// start pose) name it in each front end's words: the command line's banner `--no-gravity` and
/// `--center home`, the summary (every front end's) the fields `no_gravity` and `center`; no
/// flag reaches the summary.
#[test]
fn mapped_notes_name_options_in_each_front_ends_words() {
    let dir = temp_dir("mjcf-mapped-words");
    let body = "<inertial pos=\"0 0 -0.1\" mass=\"1\" diaginertia=\"0.01 0.01 0.01\"/>";
    let xml = format!(
        "<mujoco><option gravity=\"0 0 -3\"/><worldbody><body name=\"b\">{body}<joint name=\"j\" \
         range=\"-60 60\" limited=\"true\"/></body></worldbody><keyframe><key name=\"home\" \
         qpos=\"0.2\"/></keyframe></mujoco>"
    );
    std::fs::write(dir.join("arm.xml"), xml).unwrap();
    let run = faze4(
        &dir,
        &[
            "wave",
            "--robot",
            "arm.xml",
            "--center",
            "home",
            "--duration",
            "0.01",
            "--summary",
            "s.json",
        ],
    );
    assert!(run.status.success(), "{}", run.stderr);
    let banner = run.stdout.lines().find(|l| l.starts_with("[faze4] mapped from mjcf: "));
    let banner = banner.unwrap_or_else(|| panic!("no mapped line: {}", run.stdout));
    assert!(
        banner.contains("keyframe home → start pose (--center home) (1)"),
        "{banner}"
    );
    assert!(banner.contains("9.81 m/s² down (--no-gravity: none) (1)"), "{banner}");
    let s = summary(&dir, "s.json");
    std::fs::remove_dir_all(&dir).unwrap();
    let to = |from: &str| {
        let m = s["mapped"].as_array().unwrap().iter().find(|m| m["from"] == from);
        m.unwrap_or_else(|| panic!("{from} not in {}", s["mapped"]))["to"]
            .as_str()
            .unwrap()
            .to_string()
    };
    assert_eq!(to("keyframe home"), "start pose (center home)");
    assert_eq!(
        to("option gravity"),
        "not simulated: faze4's gravity is 9.81 m/s² down (no_gravity: none)"
    );
    assert!(!s["mapped"].to_string().contains("--"), "{}", s["mapped"]);
}
