//! Every way a URDF can be wrong gives an error naming the file, the element and the problem.

use faze4::model::{Model, PackagePaths, urdf};

/// A valid two-joint arm; each test breaks one thing in it.
const GOOD: &str = r#"<robot name="two">
  <link name="world"/>
  <joint name="base_joint" type="fixed"><parent link="world"/><child link="base"/></joint>
  <link name="base"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="5" velocity="1"/><dynamics damping="0.1"/>
  </joint>
  <link name="upper">
    <inertial><origin xyz="0.1 0 0" rpy="0 0 0"/><mass value="1.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>
  </link>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="fore"/>
    <origin xyz="0.2 0 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="3" velocity="1"/>
  </joint>
  <link name="fore">
    <inertial><origin xyz="0.1 0 0" rpy="0 0 0"/><mass value="0.5"/>
      <inertia ixx="0.005" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
</robot>"#;

fn load(text: &str) -> Result<Model, String> {
    urdf::read_str(text, "arm.urdf", None, &PackagePaths::default()).map_err(|e| e.to_string())
}

/// Loads `GOOD` with `from` replaced by `to` and returns the error message.
fn error_with(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "test setup: {from:?} not in the template");
    match load(&GOOD.replacen(from, to, 1)) {
        Ok(_) => panic!("replacing {from:?} with {to:?} should fail"),
        Err(e) => e,
    }
}

fn assert_mentions(message: &str, parts: &[&str]) {
    assert!(
        message.starts_with("arm.urdf: "),
        "the file is not named first: {message}"
    );
    for p in parts {
        assert!(message.contains(p), "{message:?} should mention {p:?}");
    }
    assert!(!message.contains('\n'), "one line: {message:?}");
}

#[test]
fn the_template_is_valid() {
    let model = load(GOOD).unwrap();
    assert_eq!(model.dof(), 2);
    assert_eq!(model.joints[0].name, "shoulder");
}

#[test]
fn malformed_and_truncated_xml() {
    assert_mentions(&load(&GOOD[..GOOD.len() / 2]).unwrap_err(), &["malformed URDF"]);
    assert_mentions(&load("this is not xml").unwrap_err(), &["malformed URDF"]);
    assert_mentions(&load("").unwrap_err(), &["empty"]);
    assert_mentions(
        &error_with("<limit lower=\"-1\"", "<limit lower=\"-1\" upper=\"x\""),
        &["malformed URDF"],
    );
}

#[test]
fn missing_file_names_the_path() {
    let e = Model::from_urdf_file(std::path::Path::new("/nonexistent/arm.urdf"), &PackagePaths::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/nonexistent/arm.urdf: "), "{e}");
}

#[test]
fn joint_with_a_missing_link() {
    let e = error_with("<child link=\"fore\"/>", "<child link=\"forearm\"/>");
    assert_mentions(&e, &["joint 'elbow'", "child link 'forearm' does not exist"]);
    let e = error_with("<parent link=\"upper\"/>", "<parent link=\"uper\"/>");
    assert_mentions(&e, &["joint 'elbow'", "parent link 'uper' does not exist"]);
}

#[test]
fn kinematic_loops_and_two_roots() {
    // a second parent for 'upper'
    let looped = GOOD.replace(
        "</robot>",
        r#"<joint name="back" type="fixed"><parent link="fore"/><child link="upper"/></joint></robot>"#,
    );
    assert_mentions(
        &load(&looped).unwrap_err(),
        &["joint 'back'", "already has parent joint 'shoulder'", "loop"],
    );
    // a cycle detached from the root
    let cycle = GOOD.replace(
        "</robot>",
        r#"<link name="a"/><link name="b"/>
           <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
           <joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint></robot>"#,
    );
    assert_mentions(&load(&cycle).unwrap_err(), &["not connected to the root", "loop"]);
    // a second tree
    let two_roots = GOOD.replace("</robot>", r#"<link name="stray"/></robot>"#);
    assert_mentions(&load(&two_roots).unwrap_err(), &["2 root links", "world", "stray"]);
    let itself = error_with("<child link=\"fore\"/>", "<child link=\"upper\"/>");
    assert_mentions(&itself, &["joint 'elbow'", "itself"]);
}

#[test]
fn bad_masses() {
    let e = error_with("<mass value=\"0.5\"/>", "<mass value=\"-0.5\"/>");
    assert_mentions(&e, &["link 'fore' <inertial>", "negative"]);
    let e = error_with(
        r#"<mass value="0.5"/>
      <inertia ixx="0.005" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>"#,
        r#"<mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>"#,
    );
    assert_mentions(&e, &["link 'fore'", "moved by joint 'elbow'", "no mass"]);
}

#[test]
fn bad_inertias() {
    let e = error_with("ixx=\"0.005\"", "ixx=\"-0.005\"");
    assert_mentions(&e, &["link 'fore' <inertial>", "not positive definite"]);
    let e = error_with("izz=\"0.01\"", "izz=\"0.03\"");
    assert_mentions(&e, &["link 'fore' <inertial>", "triangle inequality"]);
}

#[test]
fn non_finite_numbers() {
    let e = error_with("<origin xyz=\"0.2 0 0\"", "<origin xyz=\"0.2 NaN 0\"");
    assert_mentions(&e, &["joint 'elbow'", "origin xyz", "non-finite"]);
    let e = error_with("<mass value=\"1.0\"/>", "<mass value=\"inf\"/>");
    assert_mentions(&e, &["link 'upper' <inertial>", "mass", "non-finite"]);
    let e = error_with("<dynamics damping=\"0.1\"/>", "<dynamics damping=\"nan\"/>");
    assert_mentions(&e, &["joint 'shoulder'", "damping"]);
}

#[test]
fn zero_axis_and_bad_limits() {
    let e = error_with("<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 0 0\"/>");
    assert_mentions(&e, &["joint 'elbow' <axis>", "zero"]);
    let e = error_with("lower=\"-2\" upper=\"2\"", "lower=\"2\" upper=\"-2\"");
    assert_mentions(&e, &["joint 'elbow' <limit>", "above upper"]);
    let e = error_with("<dynamics damping=\"0.1\"/>", "<dynamics damping=\"-0.1\"/>");
    assert_mentions(&e, &["joint 'shoulder' <dynamics>", "negative"]);
}

#[test]
fn unsupported_joint_types_are_named() {
    for kind in ["floating", "planar"] {
        let e = error_with(
            "name=\"elbow\" type=\"revolute\"",
            &format!("name=\"elbow\" type=\"{kind}\""),
        );
        assert_mentions(&e, &["joint 'elbow'", &format!("'{kind}' is not supported")]);
    }
}

#[test]
fn duplicate_names() {
    let e = load(&GOOD.replace("</robot>", "<link name=\"fore\"/></robot>")).unwrap_err();
    assert_mentions(&e, &["link 'fore'", "defined twice"]);
}

#[test]
fn non_unit_axes_are_normalised() {
    let model = load(&GOOD.replace("<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 3 4\"/>")).unwrap();
    let a = model.joints[1].axis;
    assert!((a.norm() - 1.0).abs() < 1e-15 && (a.y - 0.6).abs() < 1e-15 && (a.z - 0.8).abs() < 1e-15);
}

/// `GOOD` with the elbow following `leader` through `<mimic>` (`extra` attributes), and the
/// error that gives.
fn mimic_error(leader: &str, extra: &str) -> String {
    error_with(
        r#"<axis xyz="0 1 0"/>"#,
        &format!(r#"<axis xyz="0 1 0"/><mimic joint="{leader}"{extra}/>"#),
    )
}

#[test]
fn a_mimic_of_a_missing_fixed_or_same_joint_is_refused() {
    assert_mentions(
        &mimic_error("nope", ""),
        &["joint 'elbow' <mimic>", "'nope'", "does not exist"],
    );
    assert_mentions(
        &mimic_error("base_joint", ""),
        &["joint 'elbow' <mimic>", "'base_joint'", "fixed"],
    );
    assert_mentions(&mimic_error("elbow", ""), &["joint 'elbow' <mimic>", "itself"]);
    // a fixed joint cannot follow
    assert_mentions(
        &error_with(
            r#"<child link="base"/></joint>"#,
            r#"<child link="base"/><mimic joint="shoulder"/></joint>"#,
        ),
        &["joint 'base_joint' <mimic>", "fixed joint"],
    );
}

#[test]
fn a_mimic_chain_is_refused() {
    // the shoulder follows the elbow, which follows the shoulder
    let text = GOOD
        .replacen(
            r#"<axis xyz="0 0 1"/>"#,
            r#"<axis xyz="0 0 1"/><mimic joint="elbow"/>"#,
            1,
        )
        .replacen(
            r#"<axis xyz="0 1 0"/>"#,
            r#"<axis xyz="0 1 0"/><mimic joint="shoulder"/>"#,
            1,
        );
    assert_mentions(
        &load(&text).unwrap_err(),
        &[
            "joint 'shoulder' <mimic>",
            "'elbow'",
            "itself mimics 'shoulder'",
            "chains",
        ],
    );
}

#[test]
fn a_follower_whose_limits_leave_its_leader_no_position_is_refused() {
    // elbow = shoulder + 5 within [-2, 2] needs shoulder in [-7, -3], outside its [-1, 1]
    assert_mentions(
        &mimic_error("shoulder", r#" offset="5""#),
        &["joint 'elbow' <mimic>", "'shoulder' no position"],
    );
    // a multiplier that is not a number
    assert_mentions(&mimic_error("shoulder", r#" multiplier="x""#), &["malformed URDF"]);
}

#[test]
fn a_motor_on_a_follower_is_refused() {
    let text = GOOD
        .replacen(
            r#"<axis xyz="0 1 0"/>"#,
            r#"<axis xyz="0 1 0"/><mimic joint="shoulder" multiplier="0.5"/>"#,
            1,
        )
        .replacen(
            "</robot>",
            r#"<transmission name="t"><joint name="elbow"/>
                 <actuator name="m"><drake:rotor_inertia value="1e-5"/><drake:gear_ratio value="10"/></actuator>
               </transmission></robot>"#,
            1,
        )
        .replacen(
            "<robot name=\"two\">",
            "<robot name=\"two\" xmlns:drake=\"http://drake.mit.edu\">",
            1,
        );
    assert_mentions(
        &load(&text).unwrap_err(),
        &["joint 'elbow' <mimic>", "<transmission>", "put the motor on 'shoulder'"],
    );
}

#[test]
fn a_follower_leaves_its_leader_the_only_coordinate() {
    let text = GOOD.replacen(
        r#"<axis xyz="0 1 0"/>"#,
        r#"<axis xyz="0 1 0"/><mimic joint="shoulder" multiplier="-2" offset="0.5"/>"#,
        1,
    );
    let model = load(&text).unwrap();
    assert_eq!((model.dof(), model.num_bodies()), (1, 2));
    assert_eq!(model.joints[0].name, "shoulder");
    // elbow = 0.5 − 2·shoulder within [-2, 2]: shoulder in [-0.75, 1.25], and its own [-1, 1]
    assert_eq!((model.joints[0].lower, model.joints[0].upper), (-0.75, 1.0));
    // its damping 0.1, the elbow's none
    assert_eq!(model.joints[0].damping, 0.1);
}

/// Issue 35: a huge mass names its overflow (it said the moments were "NaN ≤ 0"); an empty
/// `<geometry>` names its element (it printed urdf-rs's `XmlEvent` debug text); a model beyond
/// the caps on links and moving joints is refused from its size.
#[test]
fn overflowing_masses_empty_geometry_and_sizes_are_named() {
    let e = error_with("<mass value=\"0.5\"/>", "<mass value=\"1e308\"/>");
    assert_mentions(
        &e,
        &[
            "link 'fore' <inertial>",
            "mass 1e308 kg",
            "overflows floating-point numbers",
        ],
    );
    assert!(!e.contains("NaN"), "{e}");
    // a number read from the file is said in its shortest digits, not 309 of them
    let e = error_with("<mass value=\"0.5\"/>", "<mass value=\"-1e308\"/>");
    assert_mentions(&e, &["mass -1e308 kg is negative"]);
    let e = error_with("lower=\"-2\"", "lower=\"1e300\"");
    assert_mentions(&e, &["lower limit 1e300 is above upper limit 2"]);
    for empty in [
        "<geometry/>",
        "<geometry>\n </geometry>",
        "<geometry><!-- none --></geometry>",
    ] {
        let e = error_with(
            "<link name=\"fore\">",
            &format!("<link name=\"fore\"><collision>{empty}</collision>"),
        );
        assert_mentions(&e, &["link 'fore' <collision>", "<geometry> is empty"]);
    }
    let links = format!(
        "<robot name=\"r\">{}</robot>",
        "<link name=\"x\"/>".repeat(faze4::input::MAX_LINKS + 1)
    );
    let e = load(&links).unwrap_err();
    assert_mentions(&e, &["<robot>: has 4097 <link> elements, more than the 4096"]);
    let mut chain = String::from("<robot name=\"c\"><link name=\"l0\"/>");
    for i in 1..=faze4::input::MAX_MOVING_JOINTS + 1 {
        chain += &format!(
            "<joint name=\"j{i}\" type=\"continuous\"><parent link=\"l{}\"/><child link=\"l{i}\"/></joint><link name=\"l{i}\"/>",
            i - 1
        );
    }
    let e = load(&(chain + "</robot>")).unwrap_err();
    let most = faze4::input::MAX_MOVING_JOINTS;
    let cap = format!("robot 'c': has {} moving joints, more than the {most}", most + 1);
    assert_mentions(&e, &[cap.as_str()]);
}
