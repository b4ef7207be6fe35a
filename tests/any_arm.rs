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
