//! Mimic joints (`<mimic joint multiplier offset>`) against Pinocchio 4 in reduced coordinates
//! (fixture by tools/oracle/mimic_fixtures.py, `buildModelFromUrdf(path, mimic=True)`): the
//! model's coordinates, limits and damping; M, g, C v + g, RNEA, every link's pose and the tool
//! Jacobian at random states (1e-12); the closed-loop wave run as the real binary (trail 1e-9);
//! the followers moving with their leaders; limits through the map.

use crate::common;

use common::*;
use faze4::algo::{Data, compute_all_terms, crba, forward_kinematics, frame_jacobian, gravity, rnea};
use faze4::spatial::Vec3;
use serde_json::Value;

const URDF: &str = "tests/urdf/mimic_gripper_arm.urdf";
const FIXTURE: &str = "mimic_gripper_arm.json";
const TOL: f64 = 1e-12;

fn matrix_diff(ours: &nalgebra::DMatrix<f64>, theirs: &[Vec<f64>]) -> f64 {
    let mut worst = 0.0f64;
    for (r, row) in theirs.iter().enumerate() {
        for (c, x) in row.iter().enumerate() {
            worst = worst.max((ours[(r, c)] - x).abs());
        }
    }
    worst
}

#[test]
fn followers_are_not_coordinates_and_constrain_their_leaders() {
    let model = load(URDF);
    let fx = fixture(FIXTURE);
    let names: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
    let theirs: Vec<&str> = fx["coordinates"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap())
        .collect();
    assert_eq!(names, theirs);
    assert_eq!((model.dof(), model.num_bodies()), (4, 6));
    let lower: Vec<f64> = model.joints.iter().map(|j| j.lower).collect();
    let upper: Vec<f64> = model.joints.iter().map(|j| j.upper).collect();
    let damping: Vec<f64> = model.damping().collect();
    assert!(max_abs_diff(&lower, &vec_f64(&fx["lower"])) <= TOL, "{lower:?}");
    assert!(max_abs_diff(&upper, &vec_f64(&fx["upper"])) <= TOL, "{upper:?}");
    assert!(max_abs_diff(&damping, &vec_f64(&fx["damping"])) <= TOL, "{damping:?}");
    // the elbow is capped by wrist_follow ((1 − 0.1)/0.5), the left finger by the right's
    assert!((upper[2] - 1.8).abs() < 1e-15 && (lower[3] - 0.002).abs() < 1e-15);
    let follower = &model.bodies[model.bodies.iter().position(|b| b.joint == "finger_right").unwrap()];
    assert!(follower.follower && follower.coordinate == 3);
    assert_eq!((follower.multiplier, follower.offset), (-1.0, 0.002));
}

#[test]
fn dynamics_kinematics_and_jacobian_match_pinocchio() {
    let model = load(URDF);
    let fx = fixture(FIXTURE);
    let mut data = Data::new(&model);
    let tool = model.frame_index("tool_link").unwrap();
    let mut worst = [0.0f64; 7];
    for s in fx["states"].as_array().unwrap() {
        let (q, v, a) = (vec_f64(&s["q"]), vec_f64(&s["v"]), vec_f64(&s["a"]));
        compute_all_terms(&model, &mut data, &q, &v);
        worst[0] = worst[0].max(matrix_diff(&data.m, &mat_f64(&s["m"])));
        worst[1] = worst[1].max(max_abs_diff(data.g.as_slice(), &vec_f64(&s["g"])));
        worst[2] = worst[2].max(max_abs_diff(data.bias.as_slice(), &vec_f64(&s["bias"])));
        let m = crba(&model, &mut data, &q).clone();
        worst[0] = worst[0].max(matrix_diff(&m, &mat_f64(&s["m"])));
        let g = gravity(&model, &mut data, &q).clone();
        worst[1] = worst[1].max(max_abs_diff(g.as_slice(), &vec_f64(&s["g"])));
        let tau = rnea(&model, &mut data, &q, &v, &a);
        worst[3] = worst[3].max(max_abs_diff(tau.as_slice(), &vec_f64(&s["tau"])));
        forward_kinematics(&model, &mut data, &q);
        for (name, pose) in s["frames"].as_object().unwrap() {
            let ours = &data.frame_pose[model.frame_index(name).unwrap().0];
            let theirs = mat_f64(pose);
            for r in 0..3 {
                worst[4] = worst[4].max((ours.pos[r] - theirs[r][3]).abs());
                for c in 0..3 {
                    worst[5] = worst[5].max((ours.rot[(r, c)] - theirs[r][c]).abs());
                }
            }
        }
        let j = frame_jacobian(&model, &mut data, tool);
        worst[6] = worst[6].max(matrix_diff(j, &mat_f64(&s["tool_jacobian"])));
    }
    eprintln!("M, g, bias, rnea, frame positions, rotations, Jacobian: {worst:?}");
    for (what, w) in [
        "M",
        "g",
        "C v + g",
        "rnea",
        "frame positions",
        "frame rotations",
        "Jacobian",
    ]
    .iter()
    .zip(worst)
    {
        assert!(w <= TOL, "{what} differs from Pinocchio by {w:e}");
    }
}

/// The fixture's wave run as the binary: the whole trail within 1e-9 and the summary.
#[test]
fn closed_loop_wave_matches_pinocchio() {
    let fx = fixture(FIXTURE);
    let cl = &fx["closed_loop"];
    let a = &cl["args"];
    let num = |k: &str| a[k].as_f64().unwrap().to_string();
    let dir = temp_dir("mimic-wave");
    // the fixture waves the prismatic fingers by the revolute amplitude in radians, as metres
    let amp_m = a["amp_deg"].as_f64().unwrap().to_radians().to_string();
    let urdf = repo_path(URDF).display().to_string();
    let run = faze4(
        &dir,
        &[
            "wave",
            "--urdf",
            &urdf,
            "--center",
            "mid",
            "--amp-deg",
            &num("amp_deg"),
            "--amp-m",
            &amp_m,
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
    let rows = fixture_trail(&dir, cl);
    let ours: Value = summary(&dir, "summary.json");
    std::fs::remove_dir_all(&dir).unwrap();
    let theirs = mat_f64(&cl["trail"]["rows"]);
    assert_eq!(rows.len(), theirs.len());
    let mut worst = 0.0f64;
    for (r, p) in rows.iter().zip(&theirs) {
        assert_eq!(r[0], p[0], "sample times");
        worst = worst.max(max_abs_diff(&r[1..], &p[1..]));
    }
    eprintln!("mimic wave: trail worst difference {worst:.1e}");
    assert!(worst <= 1e-9, "trail differs from Pinocchio's by {worst:e}");
    let pin = &cl["summary"];
    assert_eq!(ours["dof"], pin["dof"]);
    assert_eq!(ours["steps"], pin["steps"]);
    for key in ["effective_inertia", "kp", "kd", "effort"] {
        let e = max_abs_diff(&vec_f64(&ours[key]), &vec_f64(&pin[key])) / max_abs(&vec_f64(&pin[key]));
        assert!(e < 1e-12, "{key} differs (relative {e:e})");
    }
    let e = max_abs_diff(
        &vec_f64(&ours["max_tracking_error_rad"]),
        &vec_f64(&pin["max_tracking_error_rad"]),
    );
    assert!(e < 1e-9, "max tracking error differs by {e:e}");
    assert_eq!(ours["saturation_pct"], pin["saturation_pct"]);
}

/// Along the trail each follower sits where its map puts it: the two fingers open and close
/// together (finger_right at 0.002 − q_left), the wrist at 0.1 + q_elbow/2. Read from the poses
/// forward kinematics gives every frame (what the 3D views draw).
#[test]
fn followers_move_with_their_leaders() {
    let model = load(URDF);
    let fx = fixture(FIXTURE);
    let mut data = Data::new(&model);
    let [hand, left, right, forearm, wrist] =
        ["hand", "finger_left_link", "finger_right_link", "forearm", "wrist"].map(|f| model.frame_index(f).unwrap().0);
    let mut spread = (f64::INFINITY, f64::NEG_INFINITY);
    for row in mat_f64(&fx["closed_loop"]["trail"]["rows"]) {
        let q = &row[4..];
        forward_kinematics(&model, &mut data, q);
        let in_hand = |f: usize| data.frame_pose[hand].inverse().compose(&data.frame_pose[f]).pos;
        let (l, r) = (in_hand(left), in_hand(right));
        assert!(
            (l - Vec3::new(0.0, 0.01 + q[3], 0.05)).norm() < 1e-12,
            "left finger {l:?}"
        );
        assert!(
            (r - Vec3::new(0.0, -0.01 + 0.002 - q[3], 0.05)).norm() < 1e-12,
            "right finger {r:?}"
        );
        // the wrist turns by 0.1 + q_elbow/2 about its axis relative to the forearm
        let rel = data.frame_pose[forearm].inverse().compose(&data.frame_pose[wrist]);
        let turn = nalgebra::Rotation3::from_matrix_unchecked(rel.rot).angle();
        let expected = 0.1 + 0.5 * q[2];
        // the joint origin's rpy (0, 0, 0.3) turns about z, the joint about (0.2, 1, 0): compare
        // against the same composition
        let axis = nalgebra::Unit::new_normalize(nalgebra::Vector3::new(0.2, 1.0, 0.0));
        let want = nalgebra::Rotation3::from_euler_angles(0.0, 0.0, 0.3)
            * nalgebra::Rotation3::from_axis_angle(&axis, expected);
        assert!((rel.rot - want.matrix()).abs().max() < 1e-12, "wrist turned {turn}");
        spread = (spread.0.min(l.y - r.y), spread.1.max(l.y - r.y));
    }
    // the fingers really moved apart and together: in 4 s the finger's phase runs from π to
    // π + 2 rad, through sin = −1, so q_left spans A = 1° (0.01745 m) and the gap 2A
    let amplitude = 1f64.to_radians();
    assert!(
        (spread.1 - spread.0 - 2.0 * amplitude).abs() < 1e-4,
        "finger gap range {spread:?}"
    );
}

#[test]
fn a_wave_that_takes_a_follower_beyond_its_limits_is_refused() {
    let dir = temp_dir("mimic-limits");
    let urdf = repo_path(URDF).display().to_string();
    // the elbow at 1.7 ± 0.17 rad: within its own [-2, 2], but wrist_follow = 0.1 + q/2 would
    // pass its upper limit 1 at q = 1.8
    refuses(
        &dir,
        &[
            "wave",
            "--urdf",
            &urdf,
            "--center",
            "0,0,1.7,0.02",
            "--amp-deg",
            "10",
            "--no-collisions",
        ],
        &["--amp-deg", "J3 (elbow)", "mimic followers: wrist_follow"],
    );
    refuses(
        &dir,
        &["wave", "--urdf", &urdf, "--center", "0,0,1.9,0.02", "--no-collisions"],
        &["--center", "J3 (elbow)", "1.9", "wrist_follow"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
