//! `--self-collisions` (docs/contact.md): the real binary against Drake's contact closed loop
//! (fixtures by tools/oracle/drake_contact_loop.py), the exact meshes' truth, the contact solver
//! on a slider pressed into a wall, and the options' answers to bad input.

use crate::common;

use common::*;
use faze4::algo::{
    ContactPoint, ContactSolver, Data, STICTION_TOLERANCE, State, compute_all_terms, forward_kinematics,
    forward_kinematics_from_transforms, integrate_discrete_with_contacts,
};
use faze4::geometry::{ClearanceGeometry, CollisionSet, ContactGeometry, GeometryData, PairFilter, Robot};
use faze4::model::{Model, PackagePaths};
use faze4::sim::{Collisions, Scenario, SelfContact, StopFlag, run};
use faze4::traj::ShapeRun;
use faze4::traj::shape::Shape;
use serde_json::Value;

/// Runs `faze4 shape --shape circle` on the real Faze4 (official meshes) with `extra`; returns
/// the summary and the trail.
fn circle(name: &str, extra: &[&str]) -> (Value, Vec<Vec<f64>>) {
    let dir = temp_dir(name);
    let urdf = repo_path("urdf/faze4_real.urdf").display().to_string();
    let assets = repo_path("assets").display().to_string();
    let mut args = vec![
        "shape",
        "--shape",
        "circle",
        "--urdf",
        &urdf,
        "--package-path",
        &assets,
        "--trail",
        "trail.csv",
        "--summary",
        "summary.json",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let run = faze4(&dir, &args);
    assert!(matches!(run.status.code(), Some(0 | 3)), "{args:?}: {}", run.stderr);
    let summary: Value = summary(&dir, "summary.json");
    let (_, trail) = read_csv(&dir.join("trail.csv"));
    (summary, trail)
}

/// Saturation per joint within 5 percentage points of Drake's, path deviation max and mean
/// within 15 %.
fn matches_drake(name: &str, fixture_name: &str, friction: &str) -> Value {
    let fx = fixture(fixture_name);
    let (ours, _) = circle(
        name,
        &[
            "--collision-geometry",
            "hull",
            "--self-collisions",
            "--friction",
            friction,
        ],
    );
    let (sat, drake_sat) = (
        vec_f64(&ours["saturation_pct"]),
        vec_f64(&fx["summary"]["saturation_pct"]),
    );
    for (j, (a, b)) in sat.iter().zip(&drake_sat).enumerate() {
        assert!((a - b).abs() <= 5.0, "J{} saturation {a} % vs Drake {b} %", j + 1);
    }
    for key in ["max", "mean"] {
        let (a, b) = (
            ours["path_deviation_mm"][key].as_f64().unwrap(),
            fx["summary"]["path_deviation_mm"][key].as_f64().unwrap(),
        );
        assert!((a - b).abs() <= 0.15 * b, "deviation {key} {a} mm vs Drake {b} mm");
    }
    let contact = &ours["self_contact"];
    assert_eq!(contact["geometry"], "hull");
    assert_eq!(contact["friction"].as_f64().unwrap(), friction.parse::<f64>().unwrap());
    // Drake's hulls of nadlaktica and podlaktica overlap along the whole circle
    assert!(contact["steps_in_contact_pct"].as_f64().unwrap() > 99.0, "{contact}");
    ours
}

/// A saturation share as the README's `--self-collisions` table writes it: `93.9 %`, `0 %`.
fn share(pct: f64) -> String {
    match pct == 0.0 {
        true => "0 %".into(),
        false => format!("{pct:.1} %"),
    }
}

/// A summary's path deviation as the table writes it, max / mean (mm): one decimal from 10 mm
/// up, else two.
fn deviation(summary: &Value) -> String {
    let (max, mean) = (
        summary["path_deviation_mm"]["max"].as_f64().unwrap(),
        summary["path_deviation_mm"]["mean"].as_f64().unwrap(),
    );
    match max >= 10.0 {
        true => format!("{max:.1} / {mean:.1}"),
        false => format!("{max:.2} / {mean:.2}"),
    }
}

/// The README's `--self-collisions` table has `row` as one of its lines: its figures, ours and
/// Drake's fixture's, are what the runs give (a figure edited there, or a run that changes,
/// fails here).
fn readme_has_row(row: &str) {
    let readme = std::fs::read_to_string(repo_path("README.md")).unwrap();
    let label = row.split(" | ").next().unwrap();
    let shown = readme
        .lines()
        .find(|l| l.starts_with(&format!("{label} | ")))
        .unwrap_or("(none)");
    assert_eq!(shown, row, "README.md's --self-collisions table");
}

#[test]
fn circle_on_hulls_pins_j3_as_drake_does() {
    let ours = matches_drake("hull_mu1", "contact_circle_mu1.json", "1");
    let sat = vec_f64(&ours["saturation_pct"]);
    assert!(sat[2] > 90.0 && sat[3] == 0.0, "J3 pinned, J4 free: {sat:?}");
    let drake = &fixture("contact_circle_mu1.json")["summary"];
    let (err, drake_sat, drake_err) = (
        vec_f64(&ours["max_tracking_error_rad"]),
        vec_f64(&drake["saturation_pct"]),
        vec_f64(&drake["max_tracking_error_rad"]),
    );
    readme_has_row(&format!(
        "| hull | `… --collision-geometry hull --self-collisions` | J3 {} (error {:.3} rad), J4 {} | {} | J3 {} ({:.3} rad), {} |",
        share(sat[2]),
        err[2],
        share(sat[3]),
        deviation(&ours),
        share(drake_sat[2]),
        drake_err[2],
        deviation(drake)
    ));
}

#[test]
fn circle_on_hulls_without_friction_lets_j4_roll_as_drake_does() {
    let ours = matches_drake("hull_mu0", "contact_circle_mu0.json", "0");
    let sat = vec_f64(&ours["saturation_pct"]);
    assert!(sat[3] > 90.0 && sat[2] == 0.0, "J4 saturated, J3 free: {sat:?}");
    let drake = &fixture("contact_circle_mu0.json")["summary"];
    let drake_sat = vec_f64(&drake["saturation_pct"]);
    readme_has_row(&format!(
        "| hull without friction | `… --collision-geometry hull --self-collisions --friction 0` | J4 {}, J3 {} | {} | J4 {}, {} |",
        share(sat[3]),
        share(sat[2]),
        deviation(&ours),
        share(drake_sat[3]),
        deviation(drake)
    ));
}

#[test]
fn exact_meshes_never_touch_on_the_circle() {
    let (free, free_trail) = circle("mesh_off", &[]);
    let (ours, trail) = circle("mesh_on", &["--self-collisions"]);
    assert_eq!(ours["self_contact"]["geometry"], "mesh");
    assert_eq!(ours["self_contact"]["steps_in_contact_pct"].as_f64(), Some(0.0));
    for key in [
        "saturation_pct",
        "max_tracking_error_rad",
        "path_deviation_mm",
        "tool_range_m",
    ] {
        assert_eq!(ours[key], free[key], "{key}");
    }
    assert_eq!(trail, free_trail);
    // the README's rows of the run without collisions (Drake's: its closed loop on the circle,
    // the fixture tests/it/closed_loop_vs_drake.rs compares with) and of the exact meshes
    let drake = &fixture("closed_loop_shape_circle.json")["summary"];
    let sat = vec_f64(&free["saturation_pct"]);
    assert!(sat.iter().chain(&vec_f64(&drake["saturation_pct"])).all(|&s| s == 0.0));
    let free_dev = deviation(&free);
    readme_has_row(&format!(
        "| no collisions | `faze4 shape --shape circle --robot urdf/faze4_real.urdf` | 0 % | {free_dev} | 0 %, {} |",
        deviation(drake)
    ));
    readme_has_row(&format!(
        "| exact mesh | `… --self-collisions` | 0 % (no contact) | {free_dev} | (Drake contacts hulls only) |"
    ));
}

/// Runs `faze4 wave` with the self-contact on the arm, command and friction of a
/// drake_contact_loop.py arm fixture (`fx`); returns our summary and trail (rows as Drake's).
fn arm_run(name: &str, fx: &Value) -> (Value, Vec<Vec<f64>>) {
    let dir = temp_dir(name);
    let a = &fx["args"];
    let num = |k: &str| a[k].as_f64().unwrap().to_string();
    let urdf = repo_path(fx["urdf"].as_str().unwrap()).display().to_string();
    let effort: Vec<String> = vec_f64(&a["effort"]).iter().map(f64::to_string).collect();
    let args = [
        "wave",
        "--urdf",
        &urdf,
        "--effort",
        &effort.join(","),
        "--tool-link",
        a["tool_link"].as_str().unwrap(),
        "--freq",
        &num("freq"),
        "--amp-deg",
        &num("amp_deg"),
        "--duration",
        &num("duration"),
        "--dt",
        &num("dt"),
        "--record-period",
        &num("record_period"),
        "--self-collisions",
        "--friction",
        &num("friction"),
        "--collision-geometry",
        "hull",
        "--trail",
        "trail.csv",
        "--summary",
        "summary.json",
        "--quiet",
    ];
    let run = faze4(&dir, &args);
    assert!(matches!(run.status.code(), Some(0 | 3)), "{}", run.stderr);
    let (_, trail) = read_csv(&dir.join("trail.csv"));
    let summary: Value = summary(&dir, "summary.json");
    (summary, trail)
}

/// The largest difference between two trails of equal length, and the time of its row.
fn worst_row(trail: &[Vec<f64>], drake: &[Vec<f64>]) -> (f64, f64) {
    assert_eq!(trail.len(), drake.len());
    trail
        .iter()
        .zip(drake)
        .map(|(a, b)| (max_abs_diff(a, b), b[0]))
        .fold((0.0, 0.0), |w, x| if x.0 > w.0 { x } else { w })
}

#[test]
fn contact_arm_follows_drake_closely() {
    let fx = fixture("contact_arm.json");
    let (summary, trail) = arm_run("contact_arm", &fx);
    let (worst, _) = worst_row(&trail, &mat_f64(&fx["trail"]["rows"]));
    assert!(worst < 2e-5, "trail differs from Drake's by {worst}");
    let (sat, drake_sat) = (
        vec_f64(&summary["saturation_pct"]),
        vec_f64(&fx["summary"]["saturation_pct"]),
    );
    assert!(max_abs_diff(&sat, &drake_sat) < 0.1, "{sat:?} vs {drake_sat:?}");
    // the tip is pressed into the wall for a good part of the run
    assert!(fx["contacts"]["rows_in_contact"].as_u64().unwrap() > 20);
    assert!(summary["self_contact"]["steps_in_contact_pct"].as_f64().unwrap() > 15.0);
}

/// Per trail row (q in columns 4..): whether a checked pair penetrates and whether a joint
/// sits on one of its limits (within `tolerance`), from the trail's q and the URDF.
fn contact_and_limit_rows(urdf: &str, trail: &[Vec<f64>], tolerance: f64) -> Vec<(bool, bool)> {
    let robot = Robot::from_urdf_file(&repo_path(urdf), &PackagePaths::default()).unwrap();
    let (set, _) = CollisionSet::new(
        &robot.model,
        &robot.geometry,
        ClearanceGeometry::Hull,
        PairFilter::NonAdjacent,
    )
    .unwrap();
    let (mut data, mut distances) = (Data::new(&robot.model), GeometryData::new(&set));
    trail
        .iter()
        .map(|row| {
            let q = &row[4..4 + robot.model.dof()];
            forward_kinematics(&robot.model, &mut data, q);
            set.distances(&data.frame_pose, &mut distances);
            let contact = distances.distances.iter().any(|d| d.intersecting);
            let at_limit = robot
                .model
                .joints
                .iter()
                .zip(q)
                .any(|(j, &x)| (x - j.lower).abs() <= tolerance || (x - j.upper).abs() <= tolerance);
            (contact, at_limit)
        })
        .collect()
}

#[test]
fn contact_pushing_a_joint_onto_its_limit_follows_drake() {
    let fx = fixture("contact_limit_arm.json");
    let urdf = fx["urdf"].as_str().unwrap();
    let (summary, trail) = arm_run("contact_limit_arm", &fx);
    let drake = mat_f64(&fx["trail"]["rows"]);
    // the scenario: the tip on the wall and j2 on its upper limit together in a third of the
    // rows, on our side (the limit held exactly) and on Drake's (its limit constraint is
    // compliant: j2 sits about 1e-9 rad beyond)
    let mut last_both = 0;
    for (who, rows, tolerance) in [("faze4", &trail, 0.0), ("Drake", &drake, 1e-8)] {
        let flags = contact_and_limit_rows(urdf, rows, tolerance);
        let both = flags.iter().filter(|&&(c, l)| c && l).count();
        assert!(
            both * 4 > rows.len(),
            "{who}: contact and limit in {both} of {} rows",
            rows.len()
        );
        last_both = last_both.max(flags.iter().rposition(|&(c, l)| c && l).unwrap());
    }
    // up to the last row with both: the contact and the limit solved together, as Drake does
    // (solved one after the other the trail was 5.7e-4 away at the impact, 2.5e-5 in the hold)
    let (held, at) = worst_row(&trail[..=last_both], &drake[..=last_both]);
    assert!(
        held < 1e-5,
        "while held: trail differs from Drake's by {held} at t = {at} s"
    );
    // Drake's compliant limit lets j2 go one step (0.2 ms) earlier; the swing that follows
    // carries that step's difference
    let (worst, at) = worst_row(&trail, &drake);
    assert!(worst < 3e-4, "trail differs from Drake's by {worst} at t = {at} s");
    let (sat, drake_sat) = (
        vec_f64(&summary["saturation_pct"]),
        vec_f64(&fx["summary"]["saturation_pct"]),
    );
    assert!(max_abs_diff(&sat, &drake_sat) < 0.1, "{sat:?} vs {drake_sat:?}");
    let (err, drake_err) = (
        vec_f64(&summary["max_tracking_error_rad"]),
        vec_f64(&fx["summary"]["max_tracking_error_rad"]),
    );
    assert!(max_abs_diff(&err, &drake_err) < 3e-4, "{err:?} vs {drake_err:?}");
}

/// A point mass on two prismatic joints (x, then y), no gravity, no damping: the wall is the
/// plane x = 0, the mass penetrates it when x < 0.
const SLIDER: &str = r#"<robot name="slider">
  <link name="world"/>
  <joint name="x" type="prismatic"><parent link="world"/><child link="carriage"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="100" velocity="1"/></joint>
  <link name="carriage"><inertial><mass value="0.5"/>
    <inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>
  <joint name="y" type="prismatic"><parent link="carriage"/><child link="block"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="100" velocity="1"/></joint>
  <link name="block"><inertial><mass value="2"/>
    <inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>
</robot>"#;

/// The slider without gravity, its x joint's lower limit at `lower_x` (m).
fn slider(lower_x: f64) -> Model {
    let text = SLIDER.replacen(r#"lower="-1""#, &format!(r#"lower="{lower_x}""#), 1);
    let mut model = Robot::from_urdf_str(&text, "slider", None, &PackagePaths::default())
        .unwrap()
        .model;
    model.gravity = Default::default();
    model
}

/// Pushes the slider into the wall with force `push` (N) and along it with `drag` (N) for
/// `steps`; returns (x, y velocity, normal force n/Δt, friction force) after the last step.
fn slide(push: f64, drag: f64, friction: f64, steps: usize) -> (f64, f64, f64, f64) {
    slide_on(&slider(-1.0), push, drag, friction, steps)
}

/// [`slide`] on a given slider model.
fn slide_on(model: &Model, push: f64, drag: f64, friction: f64, steps: usize) -> (f64, f64, f64, f64) {
    let (dt, k) = (2e-4, 5e5);
    let mut data = Data::new(model);
    let mut solver = ContactSolver::new(model);
    let mut state = State::at(&[0.0, 0.0], &[0.0, 0.0], &[-push, drag], dt);
    for _ in 0..steps {
        let q = &state.q;
        compute_all_terms(model, &mut data, q, &state.v);
        solver.clear();
        if q[0] < 0.0 {
            let point = ContactPoint {
                phi: q[0],
                stiffness: k,
                dissipation: 50.0,
                friction,
            };
            // rows: tangent y, tangent z, normal x (wall → block)
            solver.push(point).copy_from_slice(&[0.0, 1.0, 0.0, 0.0, 1.0, 0.0]);
        }
        integrate_discrete_with_contacts(model, &mut data, &mut state, &mut solver).unwrap();
    }
    let gamma = if solver.is_empty() { [0.0; 3] } else { solver.impulse(0) };
    (state.q[0], state.v[1], gamma[2] / dt, gamma[0] / dt)
}

#[test]
fn a_pressed_slider_settles_at_force_over_stiffness() {
    let (x, _, normal, _) = slide(20.0, 0.0, 1.0, 20_000);
    assert!((normal - 20.0).abs() < 1e-4, "normal force {normal} N");
    assert!((x + 20.0 / 5e5).abs() < 1e-9, "penetration {x} m");
}

#[test]
fn friction_holds_below_mu_n_and_slides_above() {
    // μ N = 10 N: a 6 N drag is held (slip within the stiction tolerance), the friction
    // force balancing it
    let (_, slip, normal, friction) = slide(20.0, 6.0, 0.5, 20_000);
    assert!((normal - 20.0).abs() < 1e-4, "{normal}");
    assert!(slip.abs() < STICTION_TOLERANCE, "slip {slip} m/s");
    assert!((friction + 6.0).abs() < 1e-4, "friction {friction} N");
    // a 14 N drag slides: friction μ N against it, the other 4 N accelerate the 2 kg block
    let (_, v1, _, friction) = slide(20.0, 14.0, 0.5, 2_000);
    let (_, v2, _, _) = slide(20.0, 14.0, 0.5, 4_000);
    assert!((friction + 10.0).abs() < 1e-3, "friction {friction} N");
    let acceleration = (v2 - v1) / (2_000.0 * 2e-4);
    assert!(
        (acceleration - 4.0 / 2.0).abs() < 1e-3,
        "acceleration {acceleration} m/s²"
    );
}

#[test]
fn a_limit_inside_the_wall_takes_the_rest_of_the_push() {
    // 20 N would press the slider 40 µm into the wall; its limit stops it at 10 µm, so the
    // contact carries k·10 µm = 5 N and the limit the other 15 N. Solved together, the contact's
    // impulse is that of the penetration held (v_n = 0); a contact solved before the limit
    // would see the slider still moving in and push harder.
    let (x, _, normal, _) = slide_on(&slider(-1e-5), 20.0, 0.0, 1.0, 2_000);
    assert!((x + 1e-5).abs() < 1e-15, "x = {x} m");
    assert!((normal - 5.0).abs() < 1e-9, "normal force {normal} N");
}

#[test]
fn self_collision_options_refuse_bad_input() {
    let dir = temp_dir("contact_refuses");
    refuses(
        &dir,
        &["wave", "--self-collisions", "--friction", "-1"],
        &["--friction", "-1"],
    );
    let run = faze4(&dir, &["wave", "--friction", "0.5"]);
    assert_eq!(run.status.code(), Some(2));
    assert!(run.stderr.contains("--self-collisions"), "{}", run.stderr);
    let run = faze4(&dir, &["wave", "--self-collisions", "--no-collisions"]);
    assert_eq!(run.status.code(), Some(2));
    assert!(run.stderr.contains("--no-collisions"), "{}", run.stderr);
}

/// An ASCII STL of an axis-aligned box of `size` (m) centred on the origin: 12 triangles.
fn box_stl(size: [f64; 3]) -> String {
    let h = size.map(|x| x / 2.0);
    let corner = |i: usize| [0, 1, 2].map(|k| if i >> k & 1 == 1 { h[k] } else { -h[k] });
    // each face as two triangles of corner indices (bit k set: +h on axis k)
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut text = String::from("solid box\n");
    for f in faces {
        for t in [[f[0], f[1], f[2]], [f[0], f[2], f[3]]] {
            text += "facet normal 0 0 0\nouter loop\n";
            for v in t {
                let [x, y, z] = corner(v);
                text += &format!("vertex {x} {y} {z}\n");
            }
            text += "endloop\nendfacet\n";
        }
    }
    text + "endsolid box\n"
}

#[test]
fn exact_meshes_that_intersect_stop_the_run_with_one_line_naming_them() {
    // contact_arm with its wall and its tip sphere as box meshes: the tip's path crosses the
    // wall's face, so the exact meshes intersect; contact between two triangle meshes is not
    // modelled, and the run says so instead of going on without it
    let dir = temp_dir("contact_mesh_clash");
    let urdf = std::fs::read_to_string(repo_path("tests/urdf/contact_arm.urdf"))
        .unwrap()
        .replace(
            r#"<geometry><box size="0.4 0.1 0.1"/></geometry>"#,
            r#"<geometry><mesh filename="wall.stl"/></geometry>"#,
        )
        .replace(
            r#"<geometry><sphere radius="0.03"/></geometry>"#,
            r#"<geometry><mesh filename="tip.stl"/></geometry>"#,
        );
    std::fs::write(dir.join("wall.stl"), box_stl([0.4, 0.1, 0.1])).unwrap();
    std::fs::write(dir.join("tip.stl"), box_stl([0.06, 0.06, 0.06])).unwrap();
    std::fs::write(dir.join("mesh_arm.urdf"), urdf).unwrap();
    let fx = fixture("contact_arm.json");
    let a = &fx["args"];
    let num = |k: &str| a[k].as_f64().unwrap().to_string();
    let effort: Vec<String> = vec_f64(&a["effort"]).iter().map(f64::to_string).collect();
    let (effort, freq, amp, duration) = (effort.join(","), num("freq"), num("amp_deg"), num("duration"));
    let args = |geometry: &'static str| {
        let mut args = vec![
            "wave",
            "--urdf",
            "mesh_arm.urdf",
            "--effort",
            &effort,
            "--tool-link",
            "tip_link",
        ];
        args.extend([
            "--freq",
            &freq,
            "--amp-deg",
            &amp,
            "--duration",
            &duration,
            "--self-collisions",
        ]);
        args.extend(["--collision-geometry", geometry, "--trail", "trail.csv", "--quiet"]);
        args
    };
    let run = faze4(&dir, &args("mesh"));
    assert_eq!(run.status.code(), Some(2), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    for part in [
        "faze4: error: ",
        "'wall'",
        "'forearm'",
        "intersect at t = ",
        "--collision-geometry hull",
    ] {
        assert!(lines[0].contains(part), "{:?} should mention {part:?}", lines[0]);
    }
    assert!(!dir.join("trail.csv").exists(), "a run that stopped left its trail");
    // the same arm on the hulls (boxes: their own hulls) is contact the solver models
    let mut hull = args("hull");
    hull.extend(["--summary", "summary.json"]);
    let run = faze4(&dir, &hull);
    assert!(matches!(run.status.code(), Some(0 | 3)), "{}", run.stderr);
    let summary: Value = summary(&dir, "summary.json");
    let in_contact = summary["self_contact"]["steps_in_contact_pct"].as_f64().unwrap();
    assert!(in_contact > 1.0, "the hulls touch in {in_contact} % of the steps");
}

/// The circle on the hulls through the library, with `settings`.
fn circle_summary(settings: SelfContact) -> faze4::sim::Summary {
    let packages = PackagePaths::new(vec![repo_path("assets")]);
    let Robot { model, geometry, .. } = Robot::from_urdf_file(&repo_path("urdf/faze4_real.urdf"), &packages).unwrap();
    let tool = model.default_tool_frame();
    let (trajectory, shape) = ShapeRun::plan(
        &model,
        tool,
        Shape::Circle,
        240,
        faze4::faze4::BOARD,
        faze4::faze4::SHAPE_PERIOD,
    )
    .unwrap();
    let scenario = Scenario::builder(model, trajectory)
        .geometry(geometry)
        .collisions(Some(Collisions {
            geometry: ClearanceGeometry::Hull,
            pairs: PairFilter::NonAdjacent,
        }))
        .self_contact(settings)
        .duration(12.0)
        .shape(shape)
        .build()
        .unwrap();
    run(&scenario, &mut [], &StopFlag::new()).unwrap()
}

#[test]
fn following_contacts_between_queries_changes_the_figures_little() {
    for friction in [1.0, 0.0] {
        let every_step = circle_summary(SelfContact {
            friction,
            refresh_every: 1,
            refresh_motion: 0.0,
            ..SelfContact::default()
        });
        let followed = circle_summary(SelfContact {
            friction,
            ..SelfContact::default()
        });
        let (a, b) = (
            every_step.self_contact.unwrap(),
            followed.self_contact.as_ref().unwrap(),
        );
        assert!(
            b.geometry_queries * 2 < a.geometry_queries,
            "{} vs {}",
            b.geometry_queries,
            a.geometry_queries
        );
        let sat = max_abs_diff(&every_step.saturation_pct, &followed.saturation_pct);
        assert!(sat < 0.5, "μ {friction}: saturation differs by {sat} points");
        let (x, y) = (
            every_step.path_deviation_mm.unwrap(),
            followed.path_deviation_mm.unwrap(),
        );
        // at most half the tolerance against Drake (15 %)
        assert!((x.max - y.max).abs() < 0.075 * x.max, "μ {friction}: {x:?} vs {y:?}");
        assert!((x.mean - y.mean).abs() < 0.075 * x.mean, "μ {friction}: {x:?} vs {y:?}");
    }
}

#[test]
fn world_poses_from_the_joint_transforms_are_forward_kinematics() {
    for file in [
        "urdf/faze4_arm.urdf",
        "tests/urdf/arm_prismatic.urdf",
        "tests/urdf/contact_arm.urdf",
    ] {
        let model = load(file);
        let mut rng = Rng::new(7);
        let (mut from_xup, mut direct) = (Data::new(&model), Data::new(&model));
        for _ in 0..20 {
            let q = rng.configuration(&model);
            let v = rng.vector(model.dof(), -1.0, 1.0);
            compute_all_terms(&model, &mut from_xup, &q, &v);
            forward_kinematics_from_transforms(&model, &mut from_xup);
            forward_kinematics(&model, &mut direct, &q);
            for (a, b) in from_xup.frame_pose.iter().zip(&direct.frame_pose) {
                assert!(
                    (a.rot - b.rot).abs().max() < 1e-12 && (a.pos - b.pos).norm() < 1e-12,
                    "{file}"
                );
            }
        }
    }
}

#[test]
fn contact_geometry_reads_the_faze4_hulls_and_drakes_pairs() {
    let packages = PackagePaths::new(vec![repo_path("assets")]);
    let Robot { model, geometry, .. } = Robot::from_urdf_file(&repo_path("urdf/faze4_real.urdf"), &packages).unwrap();
    let (set, missing) =
        CollisionSet::new(&model, &geometry, ClearanceGeometry::Hull, PairFilter::NonAdjacent).unwrap();
    assert!(missing.is_empty());
    let pairs = set.pair_links().count();
    let contact = ContactGeometry::new(&model, std::sync::Arc::new(set));
    assert_eq!(contact.pair_links().count(), pairs);
    for (link, vertices) in contact.hull_vertices() {
        // the base's cylinder is a primitive; every mesh is a hull of a few hundred vertices
        if link == "base_link" {
            assert_eq!(vertices, 0);
        } else {
            assert!((100..2000).contains(&vertices), "{link}: {vertices}");
        }
    }
}
