//! `urdf/faze4_real.urdf` (the official meshes as visuals and collision geometry) is the same
//! arm as `urdf/faze4_arm.urdf`: identical joints, limits, damping, frames and dynamics. The
//! bundled Faze4 is `faze4_arm.urdf` with `faze4_real.urdf`'s geometry, drawn from the built-in
//! meshes.

use crate::common;

use common::*;
use faze4::algo::{Data, bias, crba, forward_kinematics, gravity};
use faze4::geometry::Robot;
use faze4::model::{Geometry, Model, PackagePaths};

fn load_real(packages: &PackagePaths) -> Robot {
    let path = repo_path("urdf/faze4_real.urdf");
    Robot::from_urdf_file(&path, packages).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn real_model_has_the_same_kinematics_and_dynamics_exactly() {
    let boxes = load("urdf/faze4_arm.urdf");
    let real = load_real(&PackagePaths::default()).model;
    assert_eq!(boxes.dof(), real.dof());
    for (a, b) in boxes.joints.iter().zip(&real.joints) {
        assert_eq!(
            (&a.name, a.kind, a.axis, a.lower, a.upper, a.effort, a.damping),
            (&b.name, b.kind, b.axis, b.lower, b.upper, b.effort, b.damping)
        );
    }
    assert_eq!(boxes.parent, real.parent);
    assert_eq!(boxes.tree_pose, real.tree_pose);
    assert_eq!(boxes.inertia, real.inertia);
    let names = |m: &Model| m.frames.iter().map(|f| f.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&boxes), names(&real));

    let (mut da, mut db) = (Data::new(&boxes), Data::new(&real));
    let configurations = [
        [0.0; 6],
        [0.0104, 0.1795, -0.5049, 0.0, -0.0938, 0.0],
        [0.435, 0.244, -0.191, -0.435, -0.244, 0.191],
        [-2.5, 1.9, 2.4, 3.0, -2.0, -3.1],
    ];
    let v = [0.3, -0.2, 0.5, 1.0, -0.7, 2.0];
    for q in configurations {
        assert_eq!(crba(&boxes, &mut da, &q), crba(&real, &mut db, &q), "M at {q:?}");
        assert_eq!(gravity(&boxes, &mut da, &q), gravity(&real, &mut db, &q), "g at {q:?}");
        assert_eq!(
            bias(&boxes, &mut da, &q, &v),
            bias(&real, &mut db, &q, &v),
            "Cv + g at {q:?}"
        );
        forward_kinematics(&boxes, &mut da, &q);
        forward_kinematics(&real, &mut db, &q);
        assert_eq!(da.frame_pose, db.frame_pose, "frames at {q:?}");
    }
}

#[test]
fn real_model_visuals_and_collisions_are_the_official_meshes() {
    let description = shared_description();
    let real = load_real(&PackagePaths::new(vec![description.clone()]));
    let mut meshes = Vec::new();
    for visual in &real.geometry.visuals {
        let link = &visual.link;
        assert_eq!(&real.model.frame(visual.frame).name, link);
        assert!(visual.rgba.is_some(), "{link} has a colour");
        match &visual.geometry {
            Geometry::Mesh { uri, path, scale } => {
                assert_eq!(uri, &format!("package://faze4_description/meshes/{link}.STL"));
                assert_eq!(
                    path.as_deref(),
                    Some(description.join(format!("meshes/{link}.STL")).as_path())
                );
                assert_eq!(scale.as_slice(), [1.0, 1.0, 1.0]);
                assert_eq!(
                    visual.placement,
                    faze4::spatial::Pose::IDENTITY,
                    "{link}: identity origin"
                );
                meshes.push(link.clone());
            }
            Geometry::Cylinder { .. } => assert_eq!(link, "base_link"),
            other => panic!("{link}: unexpected visual {other:?}"),
        }
    }
    assert_eq!(
        meshes,
        ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"]
    );
    // the collision geometry is the visual geometry, as in the official URDF
    let shape = |g: &faze4::geometry::GeometryObject| (g.link.clone(), g.frame, g.placement, g.geometry.clone());
    assert_eq!(
        real.geometry.collisions.iter().map(shape).collect::<Vec<_>>(),
        real.geometry.visuals.iter().map(shape).collect::<Vec<_>>()
    );
    // without the package path the model loads all the same, meshes unresolved on disk (the built-in copies
    // stand in for them)
    let bare = load_real(&PackagePaths::default());
    let shapes = || bare.geometry.visuals.iter().chain(&bare.geometry.collisions);
    assert_eq!(shapes().count(), 14);
    assert!(shapes().all(|v| match &v.geometry {
        Geometry::Mesh { path, .. } => path.is_none(),
        _ => true,
    }));
}

/// The default model (no `--urdf`): the dynamics of `faze4_arm.urdf` exactly, the visuals of
/// `faze4_real.urdf`, every mesh drawn with no file and no search path.
#[test]
fn bundled_model_is_the_box_arm_with_the_real_geometry() {
    let Robot {
        model: bundled,
        geometry,
        ..
    } = Robot::faze4();
    let boxes = load("urdf/faze4_arm.urdf");
    let real = load_real(&PackagePaths::default());
    assert_eq!(
        (bundled.name.as_str(), bundled.source.as_str()),
        ("faze4_arm", "bundled urdf/faze4_arm.urdf")
    );
    assert_eq!(bundled.gravity, boxes.gravity);
    assert_eq!(bundled.parent, boxes.parent);
    assert_eq!(bundled.tree_pose, boxes.tree_pose);
    assert_eq!(bundled.inertia, boxes.inertia);
    assert_eq!(format!("{:?}", bundled.joints), format!("{:?}", boxes.joints));
    assert_eq!(format!("{:?}", bundled.frames), format!("{:?}", boxes.frames));
    assert_eq!(geometry, real.geometry);
    let box_geometry = Robot::from_urdf_file(&repo_path("urdf/faze4_arm.urdf"), &PackagePaths::default())
        .unwrap()
        .geometry;
    assert_ne!(geometry.visuals, box_geometry.visuals);

    let scene = faze4::viz::scene::Scene::from_model(&bundled, &geometry);
    assert!(scene.missing.is_empty() && scene.unreadable.is_empty());
    let description = shared_description();
    let mut drawn = Vec::new();
    for v in scene.visuals.iter().filter(|v| v.name != "base_link") {
        let stl = faze4::viz::mesh::read_trimesh(&description.join(format!("meshes/{}.STL", v.name))).unwrap();
        assert_eq!(
            scene.meshes[v.mesh].expand().indices,
            stl.indices,
            "{}: the STL's triangles",
            v.name
        );
        drawn.push(v.name.clone());
    }
    assert_eq!(
        drawn,
        ["rotary_base", "nadlaktica", "lakat", "podlaktica", "saka", "hvataljka"]
    );
}
