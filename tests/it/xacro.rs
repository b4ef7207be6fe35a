//! xacro files (docs/robots.md, "xacro"): the official UR and Franka descriptions expand to the
//! model ROS's `xacro` expands them to (fixtures by `tools/oracle/xacro_fixtures.py`: every link,
//! joint, inertia, limit and mesh reference), and run to the same trail bit for bit; odd and
//! hostile xacro is refused naming the construct and its line, within the caps.

use crate::common;

use std::path::{Path, PathBuf};

use common::{faze4, repo_path, temp_dir};
use faze4::model::{PackagePaths, ReadOptions, RobotDescription, describe_file, urdf};

/// The fixtures: (name, the xacro file, its arguments), from each fixture's first comment.
fn cases() -> Vec<(String, PathBuf, Vec<String>)> {
    let mut cases: Vec<_> = std::fs::read_dir(repo_path("tests/fixtures/xacro"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "urdf"))
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            let line = text.lines().nth(1).unwrap();
            let spec = line.split(" on ").nth(1).unwrap().trim_end_matches("-->").trim();
            let mut words = spec.split_whitespace();
            let source = repo_path(words.next().unwrap());
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            (name, source, words.map(str::to_string).collect())
        })
        .collect();
    cases.sort();
    cases
}

fn read(path: &Path, args: &[String]) -> faze4::Result<RobotDescription> {
    describe_file(
        path,
        &ReadOptions {
            packages: PackagePaths::new(vec![repo_path("tests/xacro")]),
            xacro_args: args.to_vec(),
        },
    )
}

/// An XML document as a canonical text: each element's name, its attributes sorted, its text
/// (trimmed, whitespace-only text left out) and its children, comments left out.
fn canonical(text: &str) -> String {
    fn walk(node: roxmltree::Node, depth: usize, out: &mut String) {
        let mut attrs: Vec<String> = node
            .attributes()
            .map(|a| format!("{}={:?}", a.name(), a.value()))
            .collect();
        attrs.sort();
        out.push_str(&format!(
            "{}<{} {}>\n",
            " ".repeat(depth),
            node.tag_name().name(),
            attrs.join(" ")
        ));
        for child in node.children() {
            if child.is_element() {
                walk(child, depth + 1, out);
            } else if let Some(t) = child
                .text()
                .filter(|_| child.is_text())
                .map(str::trim)
                .filter(|t| !t.is_empty())
            {
                out.push_str(&format!("{}{t:?}\n", " ".repeat(depth + 1)));
            }
        }
    }
    let doc = roxmltree::Document::parse(text).unwrap();
    let mut out = String::new();
    walk(doc.root_element(), 0, &mut out);
    out
}

#[test]
fn every_fixture_expands_to_xacros_document_element_for_element() {
    for (name, source, args) in cases() {
        let text = std::fs::read_to_string(&source).unwrap();
        let packages = PackagePaths::new(vec![repo_path("tests/xacro")]);
        let ours =
            faze4::model::xacro::expand(&text, &source, &args, &packages).unwrap_or_else(|e| panic!("{name}: {e}"));
        let oracle = std::fs::read_to_string(repo_path(&format!("tests/fixtures/xacro/{name}.urdf"))).unwrap();
        let (ours, oracle) = (canonical(&ours.urdf), canonical(&oracle));
        assert!(oracle.lines().count() > 40, "{name}");
        assert_eq!(ours, oracle, "{name}");
    }
}

/// The description without where it came from: its name, links, joints and transmissions.
fn facts(d: &RobotDescription) -> String {
    format!("{}\n{:#?}\n{:#?}\n{:#?}", d.name, d.links, d.joints, d.transmissions)
}

#[test]
fn the_official_descriptions_expand_to_the_model_xacro_expands_them_to() {
    let cases = cases();
    assert_eq!(
        cases.len(),
        14,
        "every ur_type, a prefixed UR, fr3 with and without its hand, odd"
    );
    for (name, source, args) in cases.into_iter().filter(|(n, ..)| !n.starts_with("odd")) {
        let ours = read(&source, &args).unwrap_or_else(|e| panic!("{name}: {e}"));
        let fixture = repo_path(&format!("tests/fixtures/xacro/{name}.urdf"));
        let text = std::fs::read_to_string(&fixture).unwrap();
        let oracle = urdf::describe(&text, "oracle", fixture.parent(), &PackagePaths::default()).unwrap();
        assert_eq!(facts(&ours), facts(&oracle), "{name}");
        // the arms are arms: joints, inertias and meshes were there to compare
        assert!(
            oracle.joints.iter().filter(|j| j.limits.is_some()).count() >= 6,
            "{name}"
        );
        assert!(
            oracle
                .links
                .iter()
                .filter(|l| l
                    .visuals
                    .iter()
                    .any(|v| matches!(v.geometry, faze4::model::Geometry::Mesh { .. })))
                .count()
                >= 6,
            "{name}"
        );
        assert!(
            ours.format == "xacro"
                && ours.file.starts_with(&source.display().to_string())
                && ours
                    .file
                    .ends_with(&args.iter().map(|a| format!(", {a}")).collect::<String>()),
            "{}",
            ours.file
        );
    }
}

/// The trail and summary of `faze4 wave` on `robot` for 1 s, no meshes (the fixtures have none).
fn wave(dir: &Path, robot: &str, extra: &[&str]) -> (Vec<u8>, serde_json::Value, String) {
    let package = repo_path("tests/xacro");
    let mut args = vec![
        "wave",
        "--robot",
        robot,
        "--package-path",
        package.to_str().unwrap(),
        "--duration",
        "1",
        "--center",
        "mid",
        "--no-collisions",
        "--summary",
        "s.json",
        "--trail",
        "t.csv",
    ];
    args.extend(extra);
    let run = faze4(dir, &args);
    assert!(run.status.success(), "{robot}: {}", run.stderr);
    let trail = std::fs::read(dir.join("t.csv")).unwrap();
    (trail, common::summary(dir, "s.json"), run.stdout)
}

#[test]
fn a_xacro_runs_to_the_same_trail_as_xacros_expansion_bit_for_bit() {
    let dir = temp_dir("xacro-runs");
    for (name, source, args) in cases()
        .into_iter()
        .filter(|(n, ..)| ["ur5e", "ur3", "fr3", "ur5e_prefixed_safety"].contains(&n.as_str()))
    {
        let mut given = Vec::new();
        for a in &args {
            given.extend(["--xacro-arg", a.as_str()]);
        }
        let (trail, mut summary, stdout) = wave(&dir, source.to_str().unwrap(), &given);
        let fixture = repo_path(&format!("tests/fixtures/xacro/{name}.urdf"));
        let (oracle_trail, mut oracle_summary, _) = wave(&dir, fixture.to_str().unwrap(), &[]);
        assert!(trail.len() > 1000 && trail == oracle_trail, "{name}: the trails differ");
        // the banner and summary say the format and the arguments given, once each
        let label = format!(
            "{}{}",
            source.display(),
            args.iter().map(|a| format!(", {a}")).collect::<String>()
        );
        assert!(
            stdout.lines().next().unwrap().contains(&format!("(xacro {label})")),
            "{name}: {stdout}"
        );
        assert_eq!(summary["robot_source"], label.as_str());
        assert_eq!(summary["format"], "xacro");
        assert_eq!(oracle_summary["format"], "urdf");
        for s in [&mut summary, &mut oracle_summary] {
            s.as_object_mut().unwrap().remove("robot_source");
            s.as_object_mut().unwrap().remove("format");
            s.as_object_mut().unwrap().remove("wall_time_s");
            s.as_object_mut().unwrap().remove("dynamics_wall_time_s");
        }
        assert_eq!(summary, oracle_summary, "{name}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Expands `text` written as `main.urdf.xacro` in a fresh folder beside `files`; the error.
fn refused(name: &str, text: &str, files: &[(&str, &str)], args: &[&str]) -> String {
    let dir = temp_dir(&format!("xacro-{name}"));
    std::fs::write(dir.join("main.urdf.xacro"), text).unwrap();
    for (file, body) in files {
        std::fs::write(dir.join(file), body).unwrap();
    }
    let args: Vec<String> = args.iter().map(|a| a.to_string()).collect();
    let result = read(&dir.join("main.urdf.xacro"), &args);
    std::fs::remove_dir_all(&dir).unwrap();
    match result {
        Ok(d) => panic!("{name}: expanded to {} links", d.links.len()),
        Err(e) => e.to_string(),
    }
}

const HEAD: &str = "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n";

#[test]
fn hostile_xacro_is_refused_within_its_caps_naming_the_construct_and_its_line() {
    let bomb = "a: &a [x, x, x, x, x, x, x, x, x, x]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a, *a]\nc: &c [*b, *b, *b, *b, *b, *b, *b, *b, *b, *b]\nd: &d [*c, *c, *c, *c, *c, *c, *c, *c, *c, *c]\ne: &e [*d, *d, *d, *d, *d, *d, *d, *d, *d, *d]\nf: &f [*e, *e, *e, *e, *e, *e, *e, *e, *e, *e]\ng: &g [*f, *f, *f, *f, *f, *f, *f, *f, *f, *f]\nh: &h [*g, *g, *g, *g, *g, *g, *g, *g, *g, *g]\ni: &i [*h, *h, *h, *h, *h, *h, *h, *h, *h, *h]\n";
    // (name, main.urdf.xacro, files beside it, arguments, what the message says)
    type Case<'a> = (&'a str, String, Vec<(&'a str, &'a str)>, Vec<&'a str>, Vec<&'a str>);
    let cases: Vec<Case> = vec![
        (
            "self-include",
            format!("{HEAD}<xacro:include filename=\"main.urdf.xacro\"/>\n</robot>"),
            vec![],
            vec![],
            vec!["line 2", "<xacro:include>", "includes nest more than 32 deep"],
        ),
        (
            "recursion",
            format!("{HEAD}<xacro:macro name=\"m\"><xacro:m/></xacro:macro>\n<xacro:m/>\n</robot>"),
            vec![],
            vec![],
            vec!["<xacro:m>", "macros call each other more than 100 deep"],
        ),
        (
            "exponential",
            {
                // each level calls the one below twice: 2^40 links
                let mut t = HEAD.to_string();
                t += "<xacro:macro name=\"l0\"><link name=\"${'x' * 1000}\"/></xacro:macro>\n";
                for i in 1..40 {
                    t += &format!(
                        "<xacro:macro name=\"l{i}\"><xacro:l{}/><xacro:l{}/></xacro:macro>\n",
                        i - 1,
                        i - 1
                    );
                }
                t + "<xacro:l39/>\n</robot>"
            },
            vec![],
            vec![],
            vec!["the expansion grows past 64 MiB"],
        ),
        (
            "circular",
            format!(
                "{HEAD}<xacro:property name=\"a\" value=\"${{b}}\"/>\n<xacro:property name=\"b\" value=\"${{a}}\"/>\n<link name=\"${{a}}\"/>\n</robot>"
            ),
            vec![],
            vec![],
            vec!["line 4", "circular variable definition"],
        ),
        (
            "unknown",
            format!("{HEAD}\n\n<xacro:loop items=\"3\"/>\n</robot>"),
            vec![],
            vec![],
            vec!["line 4", "xacro:loop is not supported"],
        ),
        (
            "unknown-macro",
            format!("{HEAD}<xacro:wheel/>\n</robot>"),
            vec![],
            vec![],
            vec!["line 2", "unknown macro name: xacro:wheel"],
        ),
        (
            "lambda",
            format!("{HEAD}<link name=\"${{(lambda x: x)(1)}}\"/>\n</robot>"),
            vec![],
            vec![],
            vec!["line 2", "<link>", "lambda is not supported"],
        ),
        (
            "include-ns",
            format!("{HEAD}<xacro:include filename=\"b.xacro\" ns=\"b\"/>\n</robot>"),
            vec![("b.xacro", "<robot/>")],
            vec![],
            vec!["the ns attribute", "not supported"],
        ),
        (
            // aliases share their values (as PyYAML's do), so 10^9 items cost nothing until
            // written out: str() of them is refused at the text cap
            "alias-bomb",
            format!(
                "{HEAD}<xacro:property name=\"y\" value=\"${{xacro.load_yaml('bomb.yaml')}}\"/>\n<link name=\"${{len(y['i'])}}\"/>\n<link name=\"${{str(y)}}\"/>\n</robot>"
            ),
            vec![("bomb.yaml", bomb)],
            vec![],
            vec!["line 4", "more than 16777216 bytes"],
        ),
        (
            "yaml-date",
            format!(
                "{HEAD}<xacro:property name=\"y\" value=\"${{xacro.load_yaml('d.yaml')}}\"/>\n<link name=\"${{y['when']}}\"/>\n</robot>"
            ),
            vec![("d.yaml", "# made\nwhen: 2024-01-02\n")],
            vec![],
            vec!["d.yaml line 2", "the YAML timestamp '2024-01-02' is not supported"],
        ),
        (
            "missing-arg",
            "<robot name=\"$(arg who)\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\"/>".to_string(),
            vec![],
            vec![],
            vec!["line 1", "Undefined substitution argument who"],
        ),
        (
            "bad-condition",
            format!("{HEAD}<xacro:if value=\"maybe\"><link name=\"a\"/></xacro:if>\n</robot>"),
            vec![],
            vec![],
            vec!["line 2", "<xacro:if>", "\"maybe\", which is not a boolean expression"],
        ),
        (
            "missing-param",
            format!(
                "{HEAD}<xacro:macro name=\"m\" params=\"a b:=1\"><link name=\"${{a}}\"/></xacro:macro>\n\n<xacro:m/>\n</robot>"
            ),
            vec![],
            vec![],
            vec!["line 4", "Undefined parameters [a] of macro m"],
        ),
        (
            "find",
            format!("{HEAD}<xacro:include filename=\"$(find nowhere_description)/x.xacro\"/>\n</robot>"),
            vec![],
            vec![],
            vec!["line 2", "no package 'nowhere_description'"],
        ),
        (
            "malformed",
            format!("{HEAD}<link name=\"a\">\n</robot>"),
            vec![],
            vec![],
            vec!["line 3"],
        ),
        (
            "lazy-chain",
            {
                // each property refers to the one before: evaluated on first use, recursively
                let mut t = HEAD.to_string() + "<xacro:property name=\"p0\" value=\"1\"/>\n";
                for i in 1..2000 {
                    t += &format!("<xacro:property name=\"p{i}\" value=\"${{p{} + 1}}\"/>\n", i - 1);
                }
                t + "<link name=\"${p1999}\"/>\n</robot>"
            },
            vec![],
            vec![],
            vec!["line 2002", "properties refer to each other more than 250 deep"],
        ),
        (
            "wrapped-lists",
            {
                // a global property wrapped in a list by each of 2^12 calls
                let mut t = HEAD.to_string();
                t += "<xacro:property name=\"x\" value=\"${[]}\" lazy_eval=\"false\"/>\n";
                t += "<xacro:macro name=\"w0\"><xacro:property name=\"x\" value=\"${[x]}\" scope=\"global\"/></xacro:macro>\n";
                for i in 1..13 {
                    t += &format!(
                        "<xacro:macro name=\"w{i}\"><xacro:w{}/><xacro:w{}/></xacro:macro>\n",
                        i - 1,
                        i - 1
                    );
                }
                t + "<xacro:w12/>\n</robot>"
            },
            vec![],
            vec![],
            vec!["lists and dicts nested more than 100 deep"],
        ),
        (
            "deep-nesting",
            format!("{HEAD}{}{}</robot>", "<a>".repeat(150), "</a>".repeat(150)),
            vec![],
            vec![],
            vec!["nest more than 100 deep"],
        ),
    ];
    for (name, text, files, args, expect) in cases {
        let message = refused(name, &text, &files, &args);
        assert!(
            message.contains("main.urdf.xacro") || message.contains(".yaml"),
            "{name}: {message}"
        );
        for part in expect {
            assert!(message.contains(part), "{name}: {message:?} lacks {part:?}");
        }
        assert!(!message.contains('\n') && message.len() < 600, "{name}: {message}");
    }
}

#[test]
fn odd_but_valid_xacro_expands_as_xacro_does() {
    // properties (lazy, a block, default, scope parent and global), forwarded and block
    // parameters, a property block inserted, $(eval), xacro:element and xacro:attribute,
    // escapes, an argument overriding its default, conditionals typed and as text
    let dir = temp_dir("xacro-odd");
    let text = format!(
        r#"{HEAD}  <xacro:arg name="len" default="0.5"/>
  <xacro:property name="half" value="${{length / 2}}"/>
  <xacro:property name="length" value="$(arg len)"/>
  <xacro:property name="inertia_block">
    <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>
  </xacro:property>
  <xacro:macro name="set_name" params="n">
    <xacro:property name="link_name" value="${{n}}_link" scope="parent"/>
    <xacro:property name="seen" value="yes" scope="global"/>
  </xacro:macro>
  <xacro:macro name="body" params="n mass:=2 length:=^ *origin **extra">
    <xacro:set_name n="${{n}}"/>
    <link name="${{link_name}}">
      <inertial>
        <mass value="${{mass}}"/>
        <xacro:insert_block name="origin"/>
        <xacro:insert_block name="inertia_block"/>
      </inertial>
      <xacro:insert_block name="extra"/>
    </link>
  </xacro:macro>
  <link name="base"/>
  <xacro:body n="arm" mass="${{3 * half}}">
    <origin xyz="0 0 ${{half}}" rpy="0 0 0"/>
    <extra><visual><geometry><box size="$(eval 2 * len) 1 1"/></geometry></visual></extra>
  </xacro:body>
  <xacro:element xacro:name="joint" name="j$${{x}}">
    <xacro:attribute name="type" value="${{'revolute' if seen == 'yes' else 'fixed'}}"/>
    <parent link="base"/><child link="arm_link"/>
    <axis xyz="0 0 1"/>
    <limit lower="${{-pi}}" upper="${{radians(180)}}" effort="${{round(2.5)}}" velocity="1"/>
  </xacro:element>
  <xacro:unless value="${{length > 1}}"><link name="short"/></xacro:unless>
  <xacro:if value="0"><link name="never"/></xacro:if>
</robot>"#
    );
    std::fs::write(dir.join("odd.xacro"), text).unwrap();
    let desc = read(&dir.join("odd.xacro"), &["len:=0.8".into()]).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let names: Vec<&str> = desc.links.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["base", "arm_link", "short"]);
    let arm = &desc.links[1];
    let inertial = arm.inertial.as_ref().unwrap();
    assert_eq!(
        (
            inertial.mass,
            <[f64; 3]>::from(inertial.origin.pos),
            inertial.inertia[0]
        ),
        (3.0 * 0.4, [0.0, 0.0, 0.4], 1.0)
    );
    let faze4::model::Geometry::Box { size } = &arm.visuals[0].geometry else {
        panic!()
    };
    assert_eq!(size.x, 1.6);
    let joint = &desc.joints[0];
    assert_eq!(joint.name, "j${x}");
    assert_eq!(joint.kind, faze4::model::JointType::Revolute);
    assert_eq!(
        (joint.limits, joint.effort),
        (Some((-std::f64::consts::PI, std::f64::consts::PI)), Some(2.0))
    );
}

#[test]
fn the_command_line_names_the_format_and_refuses_arguments_it_cannot_use() {
    let dir = temp_dir("xacro-cli");
    let ur = repo_path("tests/xacro/ur_description/urdf/ur.urdf.xacro");
    let package = repo_path("tests/xacro");
    let base = [
        "wave",
        "--duration",
        "0.01",
        "--trail",
        "none",
        "--package-path",
        package.to_str().unwrap(),
    ];
    // meshes that are not there are a warning, not an error: the dynamics need none
    let run = faze4(
        &dir,
        &[
            &base[..],
            &[
                "--robot",
                ur.to_str().unwrap(),
                "--xacro-arg",
                "name:=ur10e",
                "--xacro-arg",
                "ur_type:=ur10e",
            ],
        ]
        .concat(),
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(
        run.stdout.starts_with(&format!(
            "[faze4] wave · ur10e (xacro {}, name:=ur10e, ur_type:=ur10e) · 6 dof",
            ur.display()
        )),
        "{}",
        run.stdout
    );
    assert!(
        run.stderr
            .contains("package://ur_description/meshes/ur10e/collision/base.stl"),
        "{}",
        run.stderr
    );
    // $(find) through ROS_PACKAGE_PATH, as ROS users have it, without --package-path
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_faze4"))
        .args([
            "wave",
            "--duration",
            "0.01",
            "--trail",
            "none",
            "--no-collisions",
            "-q",
            "--robot",
        ])
        .args([
            ur.to_str().unwrap(),
            "--xacro-arg",
            "name:=ur3",
            "--xacro-arg",
            "ur_type:=ur3",
        ])
        .env("ROS_PACKAGE_PATH", format!("/nonexistent:{}", package.display()))
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // the old name of --robot
    let urdf = repo_path("tests/urdf/arm_prismatic.urdf");
    let run = faze4(
        &dir,
        &[&base[..], &["--urdf", urdf.to_str().unwrap(), "--no-collisions"]].concat(),
    );
    assert!(run.status.success(), "{}", run.stderr);
    for (args, expect) in [
        (
            vec!["--robot", urdf.to_str().unwrap(), "--xacro-arg", "a:=1"],
            "--xacro-arg: ",
        ),
        (
            vec!["--xacro-arg", "a:=1"],
            "--xacro-arg: is for a xacro file given as --robot",
        ),
        (
            vec!["--robot", ur.to_str().unwrap(), "--xacro-arg", "ur_type=ur5e"],
            "'ur_type=ur5e' is not NAME:=VALUE",
        ),
        (
            vec!["--robot", ur.to_str().unwrap(), "--xacro-arg", "name:=x"],
            "config/ur5x/visual_parameters.yaml",
        ),
    ] {
        let run = faze4(&dir, &[&base[..], &args[..]].concat());
        assert_eq!(run.status.code(), Some(2), "{args:?}: {}", run.stderr);
        assert!(
            run.stderr.contains(expect) && run.stderr.lines().count() == 1,
            "{args:?}: {}",
            run.stderr
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Mutations of the odd xacro of our own making (ranges deleted and repeated, the characters
/// xacro gives a meaning inserted), each expanded: an error or a URDF, never a panic, and an
/// error is one line naming its file. A cheap stand-in for a fuzzer, seeded.
#[test]
fn mutated_xacro_is_expanded_or_refused_in_one_line_never_a_panic() {
    let source = repo_path("tests/xacro/odd/odd.urdf.xacro");
    let original = std::fs::read_to_string(&source).unwrap();
    let packages = PackagePaths::new(vec![repo_path("tests/xacro")]);
    let args = vec!["name:=m".to_string()];
    let mut random = common::Rng::new(44);
    const SPECIAL: [&str; 16] = [
        "$", "{", "}", "(", ")", "'", "\"", "<", ">", "/", ":=", "*", "^", "|", "[", "**",
    ];
    let (mut expanded, mut refused) = (0, 0);
    for _ in 0..1500 {
        let mut text: Vec<char> = original.chars().collect();
        for _ in 0..1 + random.next_u64() % 3 {
            let at = (random.next_u64() as usize) % text.len();
            let len = 1 + (random.next_u64() as usize) % 40;
            let end = (at + len).min(text.len());
            match random.next_u64() % 3 {
                0 => drop(text.drain(at..end)),
                1 => {
                    let piece: Vec<char> = text[at..end].to_vec();
                    text.splice(at..at, piece);
                }
                _ => {
                    let special = SPECIAL[(random.next_u64() as usize) % SPECIAL.len()];
                    text.splice(at..at, special.chars());
                }
            }
        }
        let text: String = text.into_iter().collect();
        let result = std::panic::catch_unwind(|| faze4::model::xacro::expand(&text, &source, &args, &packages));
        match result.unwrap_or_else(|_| panic!("a panic on:\n{text}")) {
            Ok(_) => expanded += 1,
            Err(e) => {
                let message = e.to_string();
                assert!(!message.contains('\n') && message.contains("odd"), "{message}");
                refused += 1;
            }
        }
    }
    assert!(
        expanded > 100 && refused > 100,
        "{expanded} expanded, {refused} refused"
    );
}

/// Mesh references in a xacro file resolve as in a URDF: relative to the xacro file's folder,
/// `package://` through the package path, `file://$(find PKG)/…` to the package's folder.
#[test]
fn mesh_references_of_a_xacro_resolve_as_a_urdfs() {
    let dir = temp_dir("xacro-meshes");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    let stl = repo_path("tests/urdf/mesh_arms/meshes/base.stl");
    std::fs::copy(&stl, dir.join("meshes/base.stl")).unwrap();
    let text = format!(
        r#"{HEAD}<xacro:property name="m" value="meshes/base.stl"/>
  <link name="a"><visual><geometry><mesh filename="${{m}}"/></geometry></visual>
    <collision><geometry><mesh filename="package://mesh_arms/meshes/base.stl"/></geometry></collision>
    <collision><geometry><mesh filename="file://$(find mesh_arms)/meshes/base.stl"/></geometry></collision>
  </link>
</robot>"#
    );
    std::fs::write(dir.join("m.urdf.xacro"), text).unwrap();
    std::fs::write(dir.join("package.xml"), "<package><name>mesh_arms</name></package>").unwrap();
    let desc = describe_file(
        &dir.join("m.urdf.xacro"),
        &ReadOptions {
            packages: PackagePaths::new(vec![dir.clone()]),
            xacro_args: Vec::new(),
        },
    )
    .unwrap();
    let link = &desc.links[0];
    let paths: Vec<PathBuf> = (link.visuals.iter().map(|v| &v.geometry))
        .chain(link.collisions.iter().map(|c| &c.geometry))
        .map(|g| match g {
            faze4::model::Geometry::Mesh { path: Some(p), .. } => std::fs::canonicalize(p).unwrap(),
            other => panic!("{other:?}"),
        })
        .collect();
    let expected = std::fs::canonicalize(dir.join("meshes/base.stl")).unwrap();
    assert_eq!(paths, vec![expected.clone(), expected.clone(), expected]);
    std::fs::remove_dir_all(&dir).unwrap();
}
