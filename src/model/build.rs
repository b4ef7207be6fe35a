//! Description → [`Model`]: validation, topology, and merging of fixed joints.

use std::collections::HashMap;

use nalgebra::SymmetricEigen;

use super::description::{Geometry, InertialDesc, JointDesc, JointType, RobotDescription};
use super::{ArmDefaults, AxisSplit, Body, Frame, Joint, JointId, JointKind, Model, STANDARD_GRAVITY};
use crate::error::{Error, Result, one_line, shortest};
use crate::id::FrameId;
use crate::input::MAX_MOVING_JOINTS;
use crate::spatial::{Inertia, Mat3, Pose, Vec3};

/// Relative tolerance on the triangle inequality of principal moments (rounding in exported
/// CAD inertias; a real violation is orders of magnitude larger).
const TRIANGLE_TOLERANCE: f64 = 1e-9;

/// How a model is read: what may be changed to make a URDF usable.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// A moving body whose inertia no rigid body has gets its principal moments set to their
    /// mean (MuJoCo's `balanceinertia`; `--balance-inertia`), with a [`LoadWarning`].
    pub balance_inertia: bool,
}

/// Something the reading of a model skipped or changed, which changes the result: returned as
/// a value for the caller to print (the CLI prints it even under `-q`).
#[derive(Clone, Debug, PartialEq)]
pub enum LoadWarning {
    /// A `<transmission>` on a fixed joint: skipped, as Drake skips it.
    TransmissionSkipped {
        /// The URDF file.
        file: String,
        /// The transmission's name.
        transmission: String,
        /// The fixed joint it names.
        joint: String,
    },
    /// A moving body's rotational inertia balanced (`--balance-inertia`).
    InertiaBalanced {
        /// The URDF file.
        file: String,
        /// The link that heads the body.
        link: String,
        /// Its principal moments about its centre of mass as read, ascending (kg·m²).
        moments: [f64; 3],
        /// The moment all three were set to (their mean).
        balanced: f64,
    },
    /// Something the file describes that faze4 does not simulate (MJCF's `stiffness`).
    NotSimulated {
        /// The robot file.
        file: String,
        /// What the file says, in its own words.
        what: String,
        /// What faze4 made of it instead, and why.
        why: String,
        /// The elements that say it (joint names).
        items: Vec<String>,
    },
    /// A model that looks like an arm faze4 bundles (its name, its joint names) but is not a
    /// byte-for-byte copy of its description: it gets none of that arm's facts (`defaults`).
    NotBundled {
        /// The robot file.
        file: String,
        /// What it has of the bundled arm (`robot 'faze4_arm' is named like the Faze4`).
        like: String,
        /// What it gets instead.
        gets: String,
    },
}

impl std::fmt::Display for LoadWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadWarning::TransmissionSkipped {
                file,
                transmission,
                joint,
            } => write!(
                f,
                "{file}: transmission '{transmission}' skipped: joint '{joint}' is fixed (Drake skips it too)"
            ),
            LoadWarning::InertiaBalanced {
                file,
                link,
                moments: [a, b, c],
                balanced,
            } => write!(
                f,
                "{file}: link '{link}' <inertial>: principal moments {a:e}, {b:e}, {c:e} kg·m² (about the centre of mass of the body it heads) set to their mean {balanced:e} kg·m² (`balance_inertia`)"
            ),
            LoadWarning::NotSimulated { file, what, why, items } => {
                write!(f, "{file}: {what} of {}: {why}", items.join(", "))
            }
            LoadWarning::NotBundled { file, like, gets } => write!(
                f,
                "{file}: {like} but is not a byte-for-byte copy of a description faze4 bundles, so it gets none of its facts: {gets}"
            ),
        }
    }
}

/// Validates `desc` and builds its model: the links as one tree, walked depth-first into
/// bodies and frames; the motors of its transmissions; every moving body checked for mass and
/// a physical inertia (after the links welded to it are merged in).
pub(super) fn build(desc: &RobotDescription, options: &LoadOptions) -> Result<(Model, Vec<LoadWarning>)> {
    // each moving joint is a body: the matrices and the step grow as their number squared and cubed
    let moving = desc.joints.iter().filter(|j| j.kind != JointType::Fixed).count();
    if moving > MAX_MOVING_JOINTS {
        return Err(Error::model(
            &desc.file,
            format!("robot '{}'", desc.name),
            format!(
                "has {moving} moving joints, more than the {MAX_MOVING_JOINTS} faze4 simulates: a step costs their number cubed (docs/development.md, Caps)"
            ),
        ));
    }
    check_finite(desc)?;
    let tree = Tree::of(desc)?;
    let mut model = walk(desc, &tree)?;
    let mut warnings = apply_transmissions(desc, &mut model)?;
    check_masses(desc, &model)?;
    check_inertias(desc, &mut model, options, &mut warnings)?;
    apply_mimics(desc, &mut model)?;
    model.home = (desc.home.as_ref()).map(|home| {
        let at = |name: &str| home.iter().find(|(j, _)| j == name).map_or(0.0, |&(_, q)| q);
        model.joints.iter().map(|j| at(&j.name)).collect()
    });
    warnings.extend(
        (desc.mapped.iter().filter(|m| m.changes_dynamics)).map(|m| LoadWarning::NotSimulated {
            file: desc.file.clone(),
            what: m.from.clone(),
            why: m.to.clone(),
            items: m.items.clone(),
        }),
    );
    Ok((model, warnings))
}

/// The links as one tree: each link's index by name, each link's child joints (document
/// order), and the root link.
struct Tree<'a> {
    link_index: HashMap<&'a str, usize>,
    children: Vec<Vec<usize>>,
    root: usize,
}

impl<'a> Tree<'a> {
    /// Names are unique, every joint joins two existing links, a link has at most one parent
    /// joint, and exactly one link has none.
    fn of(desc: &'a RobotDescription) -> Result<Tree<'a>> {
        let file = desc.file.as_str();
        // Link and joint names are unique.
        let mut link_index = HashMap::with_capacity(desc.links.len());
        for (i, link) in desc.links.iter().enumerate() {
            if link_index.insert(link.name.as_str(), i).is_some() {
                return Err(Error::model(file, format!("link '{}'", link.name), "is defined twice"));
            }
        }
        if desc.links.is_empty() {
            return Err(Error::model(file, "<robot>", "has no links"));
        }
        let mut joint_names = HashMap::with_capacity(desc.joints.len());
        for joint in &desc.joints {
            if joint_names.insert(joint.name.as_str(), ()).is_some() {
                return Err(Error::model(file, joint_element(joint), "is defined twice"));
            }
        }

        // Every joint joins two existing links; a link has at most one parent joint.
        let mut parent_joint: Vec<Option<usize>> = vec![None; desc.links.len()];
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); desc.links.len()];
        for (j, joint) in desc.joints.iter().enumerate() {
            if let JointType::Unsupported(kind) = &joint.kind {
                return Err(Error::model(
                    file,
                    joint_element(joint),
                    format!("joint type '{kind}' is not supported (revolute, continuous, prismatic and fixed are)"),
                ));
            }
            let parent = *link_index.get(joint.parent.as_str()).ok_or_else(|| {
                Error::model(
                    file,
                    joint_element(joint),
                    format!("parent link '{}' does not exist", joint.parent),
                )
            })?;
            let child = *link_index.get(joint.child.as_str()).ok_or_else(|| {
                Error::model(
                    file,
                    joint_element(joint),
                    format!("child link '{}' does not exist", joint.child),
                )
            })?;
            if parent == child {
                return Err(Error::model(
                    file,
                    joint_element(joint),
                    format!("joins link '{}' to itself (a kinematic loop)", joint.child),
                ));
            }
            if let Some(other) = parent_joint[child] {
                return Err(Error::model(
                    file,
                    joint_element(joint),
                    format!(
                        "link '{}' already has parent joint '{}': a link with two parents closes a kinematic loop",
                        joint.child, desc.joints[other].name
                    ),
                ));
            }
            parent_joint[child] = Some(j);
            children[parent].push(j);
        }

        // Exactly one root, from which every link is reached.
        let roots: Vec<usize> = (0..desc.links.len()).filter(|&l| parent_joint[l].is_none()).collect();
        let root = match roots.as_slice() {
            [root] => *root,
            [] => {
                return Err(Error::model(
                    file,
                    "<robot>",
                    "every link has a parent: the joints form a kinematic loop",
                ));
            }
            many => {
                let names: Vec<&str> = many.iter().map(|&l| desc.links[l].name.as_str()).collect();
                return Err(Error::model(
                    file,
                    "<robot>",
                    format!(
                        "{} root links ({}): the links must form one tree",
                        names.len(),
                        names.join(", ")
                    ),
                ));
            }
        };
        Ok(Tree {
            link_index,
            children,
            root,
        })
    }
}

/// Depth-first from the root, children in document order. Each link gets the body it is fixed
/// to and its placement in that body; each moving joint opens a new body.
fn walk(desc: &RobotDescription, tree: &Tree) -> Result<Model> {
    let file = desc.file.as_str();
    let Tree {
        link_index,
        children,
        root,
    } = tree;
    let root = *root;
    let mut model = Model {
        name: desc.name.clone(),
        source: desc.file.clone(),
        joints: Vec::new(),
        bodies: Vec::new(),
        parent: Vec::new(),
        tree_pose: Vec::new(),
        axis_split: Vec::new(),
        s: Vec::new(),
        inertia: Vec::new(),
        gravity: Vec3::new(0.0, 0.0, -STANDARD_GRAVITY),
        frames: Vec::with_capacity(desc.links.len()),
        defaults: ArmDefaults::default(),
        format: desc.format.clone(),
        mapped: desc.mapped.clone(),
        home: None,
    };
    let mut frame_of_link = vec![usize::MAX; desc.links.len()];
    let mut stack = vec![(root, None::<usize>)];
    while let Some((link, via)) = stack.pop() {
        let frame = match via {
            None => Frame {
                name: desc.links[link].name.clone(),
                body: None,
                placement: Pose::IDENTITY,
                parent: None,
            },
            Some(j) => {
                let joint = &desc.joints[j];
                let parent_id = frame_of_link[link_index[joint.parent.as_str()]];
                let parent = model.frames[parent_id].clone();
                let mut frame = joint_frame(file, joint, &parent, &mut model)?;
                frame.parent = Some(FrameId(parent_id));
                frame
            }
        };
        frame_of_link[link] = model.frames.len();
        let link_desc = &desc.links[link];
        if let Some(inertial) = &link_desc.inertial {
            let inertia = link_inertia(file, &link_desc.name, inertial)?;
            if let Some(JointId(body)) = frame.body {
                // Express the link's inertia in its body's frame: Xᵀ I X with X = link_X_body.
                model.inertia[body] += inertia.transform_to_source(&frame.placement.to_xform());
                if !model.inertia[body].is_finite() {
                    return Err(Error::model(
                        file,
                        format!("link '{}' <inertial>", link_desc.name),
                        "mass, centre of mass and inertia overflow the range of floating-point numbers once expressed in its body's frame",
                    ));
                }
            }
        }
        model.frames.push(frame);
        for &j in children[link].iter().rev() {
            stack.push((link_index[desc.joints[j].child.as_str()], Some(j)));
        }
    }
    if let Some(lost) = frame_of_link.iter().position(|&f| f == usize::MAX) {
        return Err(Error::model(
            file,
            format!("link '{}'", desc.links[lost].name),
            format!(
                "is not connected to the root link '{}': its joints form a kinematic loop",
                desc.links[root].name
            ),
        ));
    }

    Ok(model)
}

/// The frame of the link that `joint` attaches to `parent`'s link: welded into the parent's
/// body by a fixed joint, or, for a moving joint, the origin of a new body added to `model`.
fn joint_frame(file: &str, joint: &JointDesc, parent: &Frame, model: &mut Model) -> Result<Frame> {
    let parent_body = parent.body;
    let origin = parent.placement.compose(&joint.origin);
    if !origin.is_finite() {
        return Err(Error::model(
            file,
            format!("{} <origin>", joint_element(joint)),
            format!(
                "places link '{}' beyond the range of floating-point numbers (the offsets on its path from the root add up to infinity)",
                joint.child
            ),
        ));
    }
    Ok(match moving_joint(file, joint)? {
        None => Frame {
            name: joint.child.clone(),
            body: parent_body,
            placement: origin,
            parent: None,
        },
        Some(moving) => {
            let body = model.joints.len();
            model.parent.push(parent_body.map(|b| b.0));
            model
                .axis_split
                .push(AxisSplit::new(&moving.axis, &origin.to_xform().e));
            model.tree_pose.push(origin);
            model.s.push(moving.motion_subspace());
            model.inertia.push(Inertia::ZERO);
            model.bodies.push(Body {
                joint: moving.name.clone(),
                kind: moving.kind,
                axis: moving.axis,
                coordinate: body,
                multiplier: 1.0,
                offset: 0.0,
                follower: false,
            });
            model.joints.push(moving);
            Frame {
                name: joint.child.clone(),
                body: Some(JointId(body)),
                placement: Pose::IDENTITY,
                parent: None,
            }
        }
    })
}

/// Each `<transmission>`'s motor (rotor inertia, gear ratio) on the joint it names; one on a
/// fixed joint is skipped with a warning, one on a joint the URDF does not have is refused
/// (both as Drake's URDF parser does).
fn apply_transmissions(desc: &RobotDescription, model: &mut Model) -> Result<Vec<LoadWarning>> {
    let file = desc.file.as_str();
    let mut warnings = Vec::new();
    for t in &desc.transmissions {
        let element = || format!("transmission '{}'", t.name);
        let Some(i) = model.joint_index(&t.joint) else {
            if desc
                .joints
                .iter()
                .any(|j| j.name == t.joint && j.kind == JointType::Fixed)
            {
                warnings.push(LoadWarning::TransmissionSkipped {
                    file: file.to_string(),
                    transmission: t.name.clone(),
                    joint: t.joint.clone(),
                });
                continue;
            }
            return Err(Error::model(
                file,
                element(),
                format!("names joint '{}', which is not a moving joint of the robot", t.joint),
            ));
        };
        let (rotor_inertia, gear_ratio) = (t.rotor_inertia.unwrap_or(0.0), t.gear_ratio.unwrap_or(1.0));
        if !(gear_ratio.is_finite() && gear_ratio > 0.0) {
            return Err(Error::model(
                file,
                element(),
                format!("gear ratio {} must be > 0", shortest(gear_ratio)),
            ));
        }
        if t.rotor_inertia.is_some() && !(rotor_inertia.is_finite() && rotor_inertia > 0.0) {
            return Err(Error::model(
                file,
                element(),
                format!("rotor inertia {} kg·m² must be > 0", shortest(rotor_inertia)),
            ));
        }
        model.joints[i.0].rotor_inertia = rotor_inertia;
        model.joints[i.0].gear_ratio = gear_ratio;
    }

    Ok(warnings)
}

/// Every moving body's rotational inertia about its centre of mass (its links merged) must be
/// one a rigid body can have: principal moments a ≤ b ≤ c with a > 0 and a + b ≥ c (to a
/// relative [`TRIANGLE_TOLERANCE`]). Else, with `balance_inertia`, all three become their mean
/// (MuJoCo's `balanceinertia`), with a warning; without, the model is refused.
fn check_inertias(
    desc: &RobotDescription,
    model: &mut Model,
    options: &LoadOptions,
    warnings: &mut Vec<LoadWarning>,
) -> Result<()> {
    let file = desc.file.as_str();
    for i in 0..model.dof() {
        let inertia = model.inertia[i];
        let i_com = inertia.rot_about_com();
        // I_com = I_o − m c×ᵀc×: with a huge mass the product overflows, and the moments are NaN
        if !i_com.iter().all(|x| x.is_finite()) {
            let c = inertia.com();
            return Err(Error::model(
                file,
                format!("link '{}' <inertial>", model.joints[i].child_link),
                format!(
                    "mass {} kg with its centre of mass {} m from its body's joint: its rotational inertia about the centre of mass is not a number, as the square of its first moment m·|c| overflows floating-point numbers",
                    shortest(inertia.mass),
                    shortest(c.norm())
                ),
            ));
        }
        let mut moments = SymmetricEigen::new(i_com).eigenvalues;
        moments.as_mut_slice().sort_by(f64::total_cmp);
        let [a, b, c] = [moments[0], moments[1], moments[2]];
        let definite = a > 0.0;
        let triangle = a + b >= c * (1.0 - TRIANGLE_TOLERANCE);
        if definite && triangle {
            continue;
        }
        let link = model.joints[i].child_link.clone();
        let mean = (a + b + c) / 3.0;
        if options.balance_inertia && mean > 0.0 {
            model.inertia[i] = Inertia::from_com(inertia.mass, inertia.com(), Mat3::identity() * mean);
            warnings.push(LoadWarning::InertiaBalanced {
                file: file.to_string(),
                link,
                moments: [a, b, c],
                balanced: mean,
            });
            continue;
        }
        let what = if !definite {
            format!("are not positive definite ({a:e} ≤ 0)")
        } else {
            format!("violate the triangle inequality ({a:e} + {b:e} < {c:e})")
        };
        let fix = if mean > 0.0 {
            " (`balance_inertia` sets them to their mean, as MuJoCo's balanceinertia does)"
        } else {
            ""
        };
        return Err(Error::model(
            file,
            format!("link '{link}' <inertial>"),
            format!(
                "the principal moments {a:e}, {b:e}, {c:e} kg·m² of its body (it and the links welded to it, about their centre of mass) {what}: no rigid body has them{fix}"
            ),
        ));
    }
    Ok(())
}

/// Every moving body needs mass (else M is singular).
fn check_masses(desc: &RobotDescription, model: &Model) -> Result<()> {
    let file = desc.file.as_str();
    for (i, joint) in model.joints.iter().enumerate() {
        if model.inertia[i].mass <= 0.0 {
            return Err(Error::model(
                file,
                format!("link '{}'", joint.child_link),
                format!(
                    "is moved by joint '{}' but has no mass (it and the links welded to it weigh {} kg); a moving body needs mass > 0",
                    joint.name,
                    shortest(model.inertia[i].mass)
                ),
            ));
        }
    }
    Ok(())
}

/// Each `<mimic>`: the follower's body is driven by its leader's coordinate
/// (`q_f = m·q_l + o`) and the follower stops being a degree of freedom. Its limits constrain
/// the leader through the map, its damping adds m²·d to the leader's (`Gᵀ D G`), its Coulomb
/// friction |m|·f (the range of m·τ_f for τ_f within ±f), its velocity
/// limit bounds the leader's by v/|m|. Refused: a mimic of a missing, fixed or following joint
/// (no chains), of itself, a fixed joint with `<mimic>`, a motor on a follower, limits that
/// leave the leader no position.
fn apply_mimics(desc: &RobotDescription, model: &mut Model) -> Result<()> {
    let file = desc.file.as_str();
    let body_of = |name: &str| model.bodies.iter().position(|b| b.joint == name);
    // (follower body, leader body, multiplier, offset)
    let mut follows = Vec::new();
    for joint in &desc.joints {
        let Some(mimic) = &joint.mimic else { continue };
        let element = || format!("joint '{}' <mimic>", joint.name);
        let Some(follower) = body_of(&joint.name) else {
            return Err(Error::model(
                file,
                element(),
                "is on a fixed joint: only a moving joint can mimic another",
            ));
        };
        if mimic.joint == joint.name {
            return Err(Error::model(file, element(), "names the joint itself"));
        }
        let Some(leader_desc) = desc.joints.iter().find(|j| j.name == mimic.joint) else {
            return Err(Error::model(
                file,
                element(),
                format!("names joint '{}', which does not exist", mimic.joint),
            ));
        };
        let Some(leader) = body_of(&mimic.joint) else {
            return Err(Error::model(
                file,
                element(),
                format!(
                    "names joint '{}', which is fixed: a mimic needs a moving leader",
                    mimic.joint
                ),
            ));
        };
        if let Some(next) = &leader_desc.mimic {
            return Err(Error::model(
                file,
                element(),
                format!(
                    "names joint '{}', which itself mimics '{}': mimic chains are not supported (make '{}' mimic '{}' directly)",
                    mimic.joint, next.joint, joint.name, next.joint
                ),
            ));
        }
        if !(mimic.multiplier.is_finite() && mimic.offset.is_finite()) {
            return Err(Error::model(
                file,
                element(),
                format!(
                    "multiplier {} and offset {} must be finite",
                    shortest(mimic.multiplier),
                    shortest(mimic.offset)
                ),
            ));
        }
        let f = &model.joints[follower];
        if f.rotor_inertia != 0.0 || f.gear_ratio != 1.0 {
            return Err(Error::model(
                file,
                element(),
                format!(
                    "joint '{}' has a <transmission>, but a follower is driven by its leader: put the motor on '{}'",
                    joint.name, mimic.joint
                ),
            ));
        }
        follows.push((follower, leader, mimic.multiplier, mimic.offset));
    }
    if follows.is_empty() {
        return Ok(());
    }
    // the leaders take their followers' limits, damping, friction and speed limits
    for &(f, l, m, o) in &follows {
        let follower = model.joints[f].clone();
        let leader = &mut model.joints[l];
        if m != 0.0 {
            let (a, b) = ((follower.lower - o) / m, (follower.upper - o) / m);
            leader.lower = leader.lower.max(a.min(b));
            leader.upper = leader.upper.min(a.max(b));
            if let Some(v) = follower.velocity {
                leader.velocity = Some(leader.velocity.map_or(v / m.abs(), |u| u.min(v / m.abs())));
            }
        }
        leader.damping += m * m * follower.damping;
        leader.friction += m.abs() * follower.friction;
        if leader.lower > leader.upper {
            return Err(Error::model(
                file,
                format!("joint '{}' <mimic>", follower.name),
                format!(
                    "its limits [{}, {}] through q = {}·q_{} + {} leave joint '{}' no position within its own",
                    shortest(follower.lower),
                    shortest(follower.upper),
                    shortest(m),
                    leader.name,
                    shortest(o),
                    leader.name
                ),
            ));
        }
    }
    // coordinates: the bodies that follow nobody, in body order
    let mut coordinate = vec![usize::MAX; model.bodies.len()];
    let mut n = 0;
    for (i, c) in coordinate.iter_mut().enumerate() {
        if !follows.iter().any(|&(f, ..)| f == i) {
            *c = n;
            n += 1;
        }
    }
    for (i, body) in model.bodies.iter_mut().enumerate() {
        body.coordinate = coordinate[i];
    }
    for &(f, l, m, o) in &follows {
        let body = &mut model.bodies[f];
        (body.coordinate, body.multiplier, body.offset, body.follower) = (coordinate[l], m, o, true);
    }
    let mut i = 0;
    model.joints.retain(|_| {
        i += 1;
        coordinate[i - 1] != usize::MAX
    });
    Ok(())
}

fn joint_element(joint: &JointDesc) -> String {
    format!("joint '{}'", joint.name)
}

/// The [`Joint`] of a moving joint description, or `None` for a fixed joint.
fn moving_joint(file: &str, joint: &JointDesc) -> Result<Option<Joint>> {
    let kind = match joint.kind {
        JointType::Fixed => return Ok(None),
        JointType::Revolute => JointKind::Revolute,
        JointType::Continuous => JointKind::Continuous,
        JointType::Prismatic => JointKind::Prismatic,
        JointType::Unsupported(_) => unreachable!("rejected before the tree is built"),
    };
    let axis = Vec3::from(joint.axis);
    // |axis| overflows for components near f64::MAX; the direction does not
    let norm = axis.norm();
    let unit = match norm.is_finite() {
        true => axis / norm,
        false => (axis / axis.amax()).normalize(),
    };
    if norm < 1e-12 {
        return Err(Error::model(
            file,
            format!("joint '{}' <axis>", joint.name),
            "is zero: a moving joint needs a direction",
        ));
    }
    let (lower, upper) = match (kind, joint.limits) {
        (JointKind::Continuous, _) | (_, None) => (f64::NEG_INFINITY, f64::INFINITY),
        (_, Some((lo, hi))) => (lo, hi),
    };
    if lower > upper {
        return Err(Error::model(
            file,
            format!("joint '{}' <limit>", joint.name),
            format!(
                "lower limit {} is above upper limit {}",
                shortest(lower),
                shortest(upper)
            ),
        ));
    }
    for (what, value) in [("damping", joint.damping), ("friction", joint.friction)] {
        if value < 0.0 {
            return Err(Error::model(
                file,
                format!("joint '{}' <dynamics>", joint.name),
                format!("{what} {} is negative", shortest(value)),
            ));
        }
    }
    Ok(Some(Joint {
        name: joint.name.clone(),
        kind,
        axis: unit,
        lower,
        upper,
        effort: joint.effort.filter(|&e| e > 0.0),
        velocity: joint.velocity.filter(|&v| v > 0.0),
        damping: joint.damping,
        friction: joint.friction,
        child_link: joint.child.clone(),
        rotor_inertia: 0.0,
        gear_ratio: 1.0,
    }))
}

/// A link's spatial inertia about the link origin (its mass must not be negative).
fn link_inertia(file: &str, link: &str, inertial: &InertialDesc) -> Result<Inertia> {
    let element = || format!("link '{link}' <inertial>");
    let m = inertial.mass;
    if m < 0.0 {
        return Err(Error::model(
            file,
            element(),
            format!("mass {} kg is negative", shortest(m)),
        ));
    }
    let [ixx, ixy, ixz, iyy, iyz, izz] = inertial.inertia;
    let i_frame = Mat3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
    if m == 0.0 && i_frame.abs().max() == 0.0 {
        return Ok(Inertia::ZERO);
    }
    // a link's inertia may be anything a body's part can add (a zero-mass link with rotational
    // inertia, a point mass); its body is checked once its links are merged (check_inertias)
    let frame = inertial.origin;
    let i_com = frame.rot * i_frame * frame.rot.transpose();
    Ok(Inertia::from_com(m, frame.pos, i_com))
}

/// Rejects NaN and infinite numbers anywhere they are not meaningful (limits may be infinite).
fn check_finite(desc: &RobotDescription) -> Result<()> {
    let file = desc.file.as_str();
    let bad = |element: String, field: &str, values: &[f64]| -> Result<()> {
        match values.iter().find(|v| !v.is_finite()) {
            Some(v) => Err(Error::model(
                file,
                element,
                format!("{field} has a non-finite value ({})", shortest(*v)),
            )),
            None => Ok(()),
        }
    };
    for link in &desc.links {
        if let Some(i) = &link.inertial {
            let e = || format!("link '{}' <inertial>", link.name);
            bad(e(), "origin xyz", i.origin.pos.as_slice())?;
            bad(e(), "origin rotation", i.origin.rot.as_slice())?;
            bad(e(), "mass", &[i.mass])?;
            bad(e(), "inertia", &i.inertia)?;
        }
        for v in &link.visuals {
            let e = || format!("link '{}' <visual>", link.name);
            if !v.origin.is_finite() {
                return Err(Error::model(file, e(), "origin has a non-finite value"));
            }
            match &v.geometry {
                Geometry::Box { size } => bad(e(), "box size", size.as_slice())?,
                Geometry::Cylinder { radius, length } => bad(e(), "cylinder", &[*radius, *length])?,
                Geometry::Capsule { radius, length } => bad(e(), "capsule", &[*radius, *length])?,
                Geometry::Sphere { radius } => bad(e(), "sphere radius", &[*radius])?,
                Geometry::Mesh { scale, .. } => bad(e(), "mesh scale", scale.as_slice())?,
            }
        }
        for c in &link.collisions {
            let element = format!("link '{}' <collision>", link.name);
            if !c.origin.is_finite() {
                return Err(Error::model(file, element, "origin has a non-finite value"));
            }
            let (field, sizes): (&str, &[f64]) = match &c.geometry {
                Geometry::Box { size } => ("box size", size.as_slice()),
                Geometry::Cylinder { radius, length } => ("cylinder radius and length", &[*radius, *length]),
                Geometry::Capsule { radius, length } => ("capsule radius and length", &[*radius, *length]),
                Geometry::Sphere { radius } => ("sphere radius", &[*radius]),
                Geometry::Mesh { scale, .. } => ("mesh scale", scale.as_slice()),
            };
            bad(element.clone(), field, sizes)?;
            // a mirroring mesh scale (negative) is a shape; a zero extent is none
            let positive = match &c.geometry {
                Geometry::Mesh { .. } => sizes.iter().all(|&v| v != 0.0),
                _ => sizes.iter().all(|&v| v > 0.0),
            };
            if !positive {
                return Err(Error::DegenerateShape {
                    file: file.to_string(),
                    element: one_line(&element),
                    message: format!("{field} {sizes:?} is not positive: the shape has no extent"),
                });
            }
        }
    }
    for j in &desc.joints {
        let e = || joint_element(j);
        bad(e(), "origin xyz", j.origin.pos.as_slice())?;
        bad(e(), "origin rotation", j.origin.rot.as_slice())?;
        bad(e(), "axis", &j.axis)?;
        bad(e(), "damping", &[j.damping])?;
        bad(e(), "friction", &[j.friction])?;
        let (lo, hi) = j.limits.unwrap_or((0.0, 0.0));
        if lo.is_nan() || hi.is_nan() || j.effort.is_some_and(f64::is_nan) || j.velocity.is_some_and(f64::is_nan) {
            return Err(Error::model(
                file,
                format!("joint '{}' <limit>", j.name),
                "has a NaN value",
            ));
        }
        for (attribute, value) in [("effort", j.effort), ("velocity", j.velocity)] {
            if let Some(x) = value.filter(|&x| x < 0.0) {
                return Err(Error::model(
                    file,
                    format!("joint '{}' <limit>", j.name.escape_debug()),
                    format!("{attribute}=\"{}\" must be > 0 (or left out: no limit)", shortest(x)),
                ));
            }
        }
    }
    Ok(())
}
