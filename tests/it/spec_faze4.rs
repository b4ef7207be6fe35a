//! The bundled Faze4 against the check table of docs/model.md, and the official description file.

use crate::common;

use common::*;
use faze4::algo::{Data, crba, forward_kinematics, gravity};
use faze4::model::{JointKind, PackagePaths};
use faze4::spatial::{Inertia, Mat3, Vec3};

/// docs/model.md: tool_link origin in world at three configurations, to the printed digits.
#[test]
fn tool_positions_match_the_spec_table() {
    let model = load("urdf/faze4_arm.urdf");
    let mut data = Data::new(&model);
    let tool = model.frame_index("tool_link").unwrap();
    let table: [([f64; 6], [f64; 3], f64); 3] = [
        ([0.0, 0.378, 0.378, 0.0, -0.378, -0.378], [0.079, -0.521, 0.395], 5e-4),
        (
            [0.435, 0.244, -0.191, -0.435, -0.244, 0.191],
            [0.220, -0.495, 0.600],
            5e-4,
        ),
        (
            [0.0104, 0.1795, -0.5049, 0.0, -0.0938, 0.0],
            [0.0800, -0.4799, 0.7099],
            5e-5,
        ),
    ];
    for (q, expected, tol) in table {
        forward_kinematics(&model, &mut data, &q);
        let p = data.frame_pose[tool.0].pos;
        for a in 0..3 {
            assert!(
                (p[a] - expected[a]).abs() <= tol,
                "q = {q:?}: tool at {p:?}, published {expected:?}"
            );
        }
    }
}

/// docs/model.md: diag M(q0) at the wave start, to the printed five digits (±1 in the last; Drake
/// gives 1.39996e-03 for the fourth, which is published as 1.3999e-03), and exactly as the
/// Drake fixture records it.
#[test]
fn mass_matrix_diagonal_at_the_wave_start_matches_the_spec() {
    let model = load("urdf/faze4_arm.urdf");
    let mut data = Data::new(&model);
    let q0: Vec<f64> = (0..6)
        .map(|i| 25f64.to_radians() * (i as f64 * std::f64::consts::PI / 3.0).sin())
        .collect();
    let spec = [7.4957e-02, 3.5653e-01, 4.3554e-02, 1.3999e-03, 2.5971e-04, 6.4520e-06];
    let m = crba(&model, &mut data, &q0);
    for i in 0..6 {
        let rel = (m[(i, i)] - spec[i]).abs() / spec[i];
        assert!(rel < 1e-4, "M[{i}][{i}] = {:e}, published {:e}", m[(i, i)], spec[i]);
    }
    let drake = vec_f64(&fixture("core_faze4_arm.json")["spec_checks"]["diag_M_q0"]);
    for i in 0..6 {
        assert!((m[(i, i)] - drake[i]).abs() / drake[i] < 1e-12);
    }
}

/// The official SolidWorks export: continuous joints without limits, meshes under another
/// package name, no world link. It loads with its root fixed to the world and has the same
/// dynamics as faze4_arm.urdf once the 1 g tool_link is welded on.
#[test]
fn official_description_loads_and_matches_the_bundled_arm() {
    let dir = shared_description();
    let faze4::geometry::Robot {
        model: official,
        geometry,
        ..
    } = faze4::geometry::Robot::from_urdf_file(
        &dir.join("urdf/Final_light_assembly_URDF.urdf"),
        &PackagePaths::new(vec![dir.clone()]),
    )
    .unwrap();
    assert_eq!(official.dof(), 6);
    assert!(
        official
            .joints
            .iter()
            .all(|j| j.kind == JointKind::Continuous && j.lower == f64::NEG_INFINITY)
    );
    assert_eq!(official.frames[0].name, "base_link");
    assert_eq!(official.frames[0].body, None, "root fixed to the world");
    // the meshes resolved through the search path (base_link.STL is missing upstream)
    for shapes in [&geometry.visuals, &geometry.collisions] {
        let resolved = (shapes.iter())
            .filter(|v| matches!(&v.geometry, faze4::model::Geometry::Mesh { path: Some(_), .. }))
            .count();
        assert_eq!((shapes.len(), resolved), (7, 6));
    }

    let bundled = load("urdf/faze4_arm.urdf");
    let hand = official.frame_index("hvataljka").unwrap();
    let tool = Inertia::from_com(0.001, Vec3::new(0.0, 0.0, 0.0147), Mat3::identity() * 1e-7);
    let with_tool = official.with_added_inertia(hand, tool);
    let without_tool_differs = {
        let mut a = Data::new(&official);
        let mut b = Data::new(&bundled);
        let q = [0.3, -0.4, 0.9, 0.2, -0.7, 1.1];
        (gravity(&official, &mut a, &q) - gravity(&bundled, &mut b, &q)).amax()
    };
    assert!(
        without_tool_differs > 1e-6,
        "the tool link should matter: {without_tool_differs:e}"
    );

    let mut a = Data::new(&with_tool);
    let mut b = Data::new(&bundled);
    let mut rng = Rng::new(11);
    for _ in 0..20 {
        let q = rng.configuration(&bundled);
        let dm = (crba(&with_tool, &mut a, &q) - crba(&bundled, &mut b, &q)).amax();
        let dg = (gravity(&with_tool, &mut a, &q) - gravity(&bundled, &mut b, &q)).amax();
        assert!(
            dm < 1e-15 && dg < 1e-13,
            "official + tool vs bundled: M {dm:e}, g {dg:e}"
        );
        forward_kinematics(&with_tool, &mut a, &q);
        forward_kinematics(&bundled, &mut b, &q);
        let d = (a.frame_pose[hand.0].pos - b.frame_pose[bundled.frame_index("hvataljka").unwrap().0].pos).norm();
        assert!(d < 1e-15);
    }
}

/// A URDF whose meshes cannot be found still loads for dynamics.
#[test]
fn missing_meshes_do_not_stop_dynamics() {
    let dir = shared_description();
    let faze4::geometry::Robot { model, geometry, .. } = faze4::geometry::Robot::from_urdf_file(
        &dir.join("urdf/Final_light_assembly_URDF.urdf"),
        &PackagePaths::default(),
    )
    .unwrap();
    assert!(
        (geometry.visuals.iter().chain(&geometry.collisions))
            .all(|v| matches!(&v.geometry, faze4::model::Geometry::Mesh { path: None, .. }))
    );
    assert_eq!(model.dof(), 6);
}

/// `package://` references resolve through the search path, under any package name.
#[test]
fn package_paths_find_meshes_in_a_description_folder() {
    let shared = shared_description();
    let paths = PackagePaths::new(vec![shared.clone()]);
    let found = paths
        .resolve("package://Final_light_assembly_URDF/meshes/saka.STL", None)
        .unwrap();
    assert_eq!(found, Some(shared.join("meshes/saka.STL")));
    // the parent of a package directory works as a ROS path entry
    let paths = PackagePaths::new(vec![shared.parent().unwrap().to_path_buf()]);
    let found = paths
        .resolve(
            &format!(
                "package://{}/meshes/saka.STL",
                shared.file_name().unwrap().to_string_lossy()
            ),
            None,
        )
        .unwrap();
    assert_eq!(found, Some(shared.join("meshes/saka.STL")));
    assert_eq!(
        paths.resolve("package://faze4_description/meshes/base_link.STL", None),
        Ok(None),
        "missing upstream"
    );
    // relative to the URDF's directory
    let rel = PackagePaths::default()
        .resolve("../meshes/lakat.STL", Some(&shared.join("urdf")))
        .unwrap();
    assert_eq!(rel, Some(shared.join("urdf/../meshes/lakat.STL")));
}
